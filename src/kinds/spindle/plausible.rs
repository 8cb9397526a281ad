//! What a spindle record's own readings say against its units and its preamble, as cautions
//! for the ISO 230-7 report:
//!
//! - a total error motion beyond [`LARGEST_MOTION`] (nm in the µm columns), or the largest
//!   below [`SMALLEST_MOTION`] (mm in them);
//! - one probe spanning less than [`SMALLEST_MOTION`] while another spans a hundred times more
//!   (mm in that column);
//! - a probe holding one value through a whole revolution or more
//!   ([`crate::io::plausible::stuck`]: saturated at its range's end, disconnected);
//! - an artefact's eccentricity that turns against the axis (more than twice as much as with
//!   it, and by over [`SMALLEST_COUNTER_ROTATION`]): a probe direction's sign, swapped columns
//!   or the angle's sense wrong;
//! - two probes carrying one signal (the same readings but for an offset, or negated): one
//!   probe on two inputs of the analyser;
//! - one probe whose once-per-revolution amplitude steps within a run while the others hold
//!   theirs: a range or gain switched mid-record.
//!
//! [`record_cautions`] are those the record shows without an evaluation (`discover` prints
//! them).

use super::analysis::motion::Direction;
use super::evaluate::Evaluation;
use super::record::{Sensing, SpindleRecord};
use crate::io::plausible::spread;
use crate::math::{Real, trimmed};

/// The largest total error motion of a machine tool's axis of rotation (m): 100 µm. A worn
/// rolling-bearing spindle shows tens of µm, a good one a few; nm written in the µm columns
/// read 1000 times larger.
pub const LARGEST_MOTION: Real = 100e-6;

/// The smallest total error motion the worst direction of an axis of rotation shows to a probe
/// (m): 5 nm. The best air-bearing spindles run at tens of nm, and a probe's noise alone over
/// the record gives a few; mm written in the µm columns read 1000 times smaller.
pub const SMALLEST_MOTION: Real = 5e-9;

/// The smallest once-per-revolution motion that turns against the axis which is read as a
/// probe's stated direction being wrong (m): 0.2 µm, above the counter-rotating part real
/// error motions show (0.1 µm in the twin's 12 000 min⁻¹ test) and below the few µm an
/// artefact is centred to.
pub const SMALLEST_COUNTER_ROTATION: Real = 0.2e-6;

/// The fewest samples of one value that read as a stuck probe: 50, a twentieth of a revolution
/// at 1024 samples (a capacitive probe's noise changes its reading every sample).
pub const STUCK_SAMPLES: usize = 50;

/// The smallest spike (m) of a probe's record that is named: 0.5 µm, beyond the asynchronous
/// error motion of a rolling-bearing spindle between two samples.
pub const SMALLEST_SPIKE: Real = 0.5e-6;

/// Every caution for the report of `evaluation` of `record`.
pub fn cautions(record: &SpindleRecord, evaluation: &Evaluation) -> Vec<String> {
    let mut found = Vec::new();
    let totals: Vec<(String, Real)> = evaluation
        .segments
        .iter()
        .flat_map(|s| &s.tests)
        .filter(|t| t.direction != Direction::Tilt)
        .filter_map(|t| t.values.first().map(|v| (t.name.clone(), v.total)))
        .collect();
    if let Some((name, largest)) = totals
        .iter()
        .filter(|(_, v)| *v > LARGEST_MOTION)
        .max_by(|a, b| a.1.total_cmp(&b.1))
    {
        found.push(format!(
            "{name}: a total error motion of {} µm, more than the {} µm of any machine tool's spindle or rotary axis: nm in the µm columns?",
            trimmed(largest * 1e6, 3),
            trimmed(LARGEST_MOTION * 1e6, 3)
        ));
    }
    if !totals.is_empty() && totals.iter().all(|(_, v)| *v < SMALLEST_MOTION) {
        found.push(format!(
            "every total error motion is below {} µm, less than the best air-bearing spindle shows (tens of nm): mm in the µm columns?",
            trimmed(SMALLEST_MOTION * 1e6, 4)
        ));
    } else {
        found.extend(flat_probes(record));
    }
    found.extend(record_cautions(record, evaluation.samples_per_revolution));
    found
}

/// The cautions `record` shows by itself (`per_revolution` samples a revolution): stuck
/// probes and spikes, an eccentricity turning against the axis, two probes on one signal.
pub fn record_cautions(record: &SpindleRecord, per_revolution: usize) -> Vec<String> {
    let mut found = stuck_probes(record, per_revolution);
    found.extend(counter_rotating(record));
    found.extend(copied_probes(record));
    found.extend(gain_steps(record));
    found
}

/// Pairs of probes whose readings differ by one constant at every sample, or sum to one (to
/// 1 pm), while they move by more than [`SMALLEST_MOTION`]: one signal on two inputs of the
/// analyser (a cable on the wrong input, a channel duplicated in the export). Probes read
/// their own noise and their own direction's motion, so no two real ones do that; the error
/// motions of both directions would be computed from one.
fn copied_probes(record: &SpindleRecord) -> Vec<String> {
    let mut found = Vec::new();
    for (i, (a, ra)) in record.probes.iter().zip(&record.readings).enumerate() {
        if spread(ra.iter().copied()) < SMALLEST_MOTION {
            continue;
        }
        for (b, rb) in record.probes.iter().zip(&record.readings).skip(i + 1) {
            let same = spread(ra.iter().zip(rb).map(|(x, y)| x - y)) < 1e-12;
            let negated = spread(ra.iter().zip(rb).map(|(x, y)| x + y)) < 1e-12;
            if same || negated {
                found.push(format!(
                    "columns `{}_um` and `{}_um` carry one signal ({} at every sample): one probe on two inputs of the analyser, or a channel duplicated in the export? The error motions along both directions come from one probe",
                    a.name,
                    b.name,
                    if same { "the same readings but for an offset" } else { "one the other negated" }
                ));
            }
        }
    }
    found
}

/// Probes that hold one value through [`STUCK_SAMPLES`] samples or more (and ten times their
/// longest other rest): a probe's noise and the artefact's form change every sample, so a held
/// value is a probe saturated at its range's end, disconnected, or a dropout filled with
/// zeros. Its error motions read as none there. Then a sample standing apart from both its
/// neighbours by more than [`SMALLEST_SPIKE`] ([`crate::io::plausible::spike`]).
fn stuck_probes(record: &SpindleRecord, per_revolution: usize) -> Vec<String> {
    let mut found = Vec::new();
    for (probe, values) in record.probes.iter().zip(&record.readings) {
        if let Some((first, count)) = crate::io::plausible::stuck(values, STUCK_SAMPLES) {
            let rpm = record
                .speed
                .get(first)
                .map_or(0.0, |w| w * 60.0 / std::f64::consts::TAU);
            found.push(format!(
                "column `{}_um` holds {} µm unchanged for {count} samples ({} revolutions) from revolution {} at {} rpm: a probe saturated at its range's end or disconnected? Its error motions there read as none",
                probe.name,
                trimmed(values[first] * 1e6, 4),
                trimmed(count as Real / per_revolution.max(1) as Real, 3),
                record.revolution.get(first).copied().unwrap_or(0),
                trimmed(rpm, 5)
            ));
        } else if let Some((k, size, scale)) = crate::io::plausible::spike(values, SMALLEST_SPIKE) {
            found.push(format!(
                "column `{}_um`: sample {} (revolution {}) stands {} µm from both its neighbours, more than {} times the probe's typical {} µm: an electrical glitch or a typo? It sets the asynchronous error motion",
                probe.name,
                k + 1,
                record.revolution.get(k).copied().unwrap_or(0),
                trimmed(size * 1e6, 4),
                crate::io::plausible::LONE_READING,
                trimmed(scale * 1e6, 3)
            ));
        }
    }
    found
}

/// Probes whose readings span less than [`SMALLEST_MOTION`] over the whole record while
/// another probe spans a hundred times more: below any probe's noise, mm in that column.
fn flat_probes(record: &SpindleRecord) -> Vec<String> {
    let spans: Vec<Real> = record
        .readings
        .iter()
        .map(|r| spread(r.iter().copied()))
        .collect();
    let widest = spans.iter().copied().fold(0.0, Real::max);
    record
        .probes
        .iter()
        .zip(&spans)
        .filter(|&(_, &span)| span < SMALLEST_MOTION && widest > 100.0 * SMALLEST_MOTION)
        .map(|(probe, span)| {
            format!(
                "column `{}_um` spans {} µm over the record, less than a probe's noise alone gives, while another probe spans {} µm: mm in that column?",
                probe.name,
                trimmed(span * 1e6, 6),
                trimmed(widest * 1e6, 4)
            )
        })
        .collect()
}

/// Two fixed radial probes at one height whose readings, taken along their stated directions,
/// put the once-per-revolution motion turning against the axis.
///
/// An artefact's eccentricity is a vector fixed in the rotor, so the centre it puts on the
/// probes turns with the axis angle: c(θ) = e·e^{iθ}, all co-rotating. Error motions add a
/// little counter-rotating first harmonic (unequal stiffness under unbalance), never more
/// than the centring itself. When the counter-rotating part is more than twice the
/// co-rotating one and above [`SMALLEST_COUNTER_ROTATION`], one probe's direction in the
/// preamble has the wrong sign, the x and y columns are swapped, or the angle runs against
/// the rotation: every radial and tilt value of that pair is then wrong.
fn counter_rotating(record: &SpindleRecord) -> Vec<String> {
    let mut found = Vec::new();
    let probes = &record.probes;
    for (i, a) in probes.iter().enumerate() {
        for (j, b) in probes.iter().enumerate().skip(i + 1) {
            let radial = |d: &[Real; 3]| d[2].abs() < 1e-6;
            if a.sensing != Sensing::Fixed
                || b.sensing != Sensing::Fixed
                || !radial(&a.direction)
                || !radial(&b.direction)
                || (a.position[2] - b.position[2]).abs() > 1e-3
            {
                continue;
            }
            let det = a.direction[0] * b.direction[1] - a.direction[1] * b.direction[0];
            if det.abs() < 0.5 {
                continue;
            }
            if let Some((co, counter)) = first_harmonics(record, i, j, det)
                && counter > 2.0 * co
                && counter > SMALLEST_COUNTER_ROTATION
            {
                found.push(format!(
                    "probes {} and {}: their once-per-revolution motion turns against the axis ({} µm) more than with it ({} µm), while an artefact's eccentricity always turns with it: a direction in the preamble with the wrong sign, the two columns swapped, or the angle running against the rotation? Their radial and tilt values are wrong if so",
                    a.name,
                    b.name,
                    trimmed(counter * 1e6, 4),
                    trimmed(co * 1e6, 4)
                ));
            }
        }
    }
    found
}

/// The co- and counter-rotating first harmonics (m) of the centre that probes `i` and `j`
/// (directions with determinant `det` in the plane) read, averaged over the whole record.
fn first_harmonics(record: &SpindleRecord, i: usize, j: usize, det: Real) -> Option<(Real, Real)> {
    let (da, db) = (record.probes[i].direction, record.probes[j].direction);
    let n = record.len();
    if n == 0 {
        return None;
    }
    let (mut co, mut counter) = ([0.0; 2], [0.0; 2]);
    for k in 0..n {
        let (ra, rb) = (record.readings[i][k], record.readings[j][k]);
        let x = (ra * db[1] - rb * da[1]) / det;
        let y = (da[0] * rb - db[0] * ra) / det;
        let (s, c) = record.angle[k].sin_cos();
        // (x + iy)·e^{−iθ} and (x + iy)·e^{+iθ}
        co[0] += x * c + y * s;
        co[1] += y * c - x * s;
        counter[0] += x * c - y * s;
        counter[1] += y * c + x * s;
    }
    let norm = |v: [Real; 2]| v[0].hypot(v[1]) / n as Real;
    Some((norm(co), norm(counter)))
}

/// The smallest once-per-revolution amplitude (m) of a probe whose step within a run is
/// judged: 0.2 µm, where a probe's noise moves the amplitude by a few percent at most.
pub const SMALLEST_GAIN_AMPLITUDE: Real = 0.2e-6;

/// The smallest change of a probe's once-per-revolution amplitude, as a ratio, named as a
/// gain or range switched within a run: 1.25. The artefact's eccentricity, which dominates
/// it, does not change within a run; each side of the step must hold within ±10 %.
pub const SMALLEST_GAIN_STEP: Real = 1.25;

/// Probes whose once-per-revolution amplitude (the artefact's eccentricity as they see it)
/// steps by [`SMALLEST_GAIN_STEP`] or more within a run, holding within ±10 % on each side of
/// the step, while every other probe of the run holds its own: an amplifier's range or gain
/// switched mid-record (the error motions then mix two scales, and the step reads as
/// asynchronous motion). A real change of the set-up (the artefact knocked) changes what
/// every probe sees.
fn gain_steps(record: &SpindleRecord) -> Vec<String> {
    let mut found = Vec::new();
    let n = record.angle.len();
    let mut start = 0;
    for end in 1..=n {
        let boundary = end == n
            || record.setup[end] != record.setup[start]
            || record.speed[end] != record.speed[start]
            || record.revolution[end] < record.revolution[end - 1];
        if !boundary {
            continue;
        }
        let steps: Vec<Option<(usize, Real)>> = record
            .readings
            .iter()
            .map(|values| amplitude_step(record, values, start, end))
            .collect();
        let stepped: Vec<usize> = (0..steps.len()).filter(|&p| steps[p].is_some()).collect();
        if let [p] = stepped.as_slice()
            && let Some((revolution, ratio)) = steps[*p]
        {
            found.push(format!(
                "column `{}_um`: its once-per-revolution amplitude changes {}-fold from revolution {revolution} of the run at {} rpm, steady on each side, while the other probes hold theirs: an amplifier's range or gain switched mid-record? The error motions mix two scales",
                record.probes[*p].name,
                trimmed(ratio, 3),
                trimmed(record.speed[start] * 60.0 / std::f64::consts::TAU, 5)
            ));
        }
        start = end;
    }
    found
}

/// The revolution (as numbered in the record) where the once-per-revolution amplitude of
/// `values` over samples `start..end` steps ([`gain_steps`]), with the ratio after/before.
fn amplitude_step(
    record: &SpindleRecord,
    values: &[Real],
    start: usize,
    end: usize,
) -> Option<(usize, Real)> {
    let mut amplitudes: Vec<(usize, Real)> = Vec::new();
    let mut first = start;
    for i in start + 1..=end {
        if i == end || record.revolution[i] != record.revolution[first] {
            let (mut c, mut s) = (0.0, 0.0);
            for (value, angle) in values[first..i].iter().zip(&record.angle[first..i]) {
                let (sin, cos) = angle.sin_cos();
                c += value * cos;
                s += value * sin;
            }
            let count = (i - first) as Real;
            amplitudes.push((record.revolution[first], 2.0 * c.hypot(s) / count));
            first = i;
        }
    }
    if amplitudes.len() < 8 {
        return None;
    }
    let median =
        |a: &[(usize, Real)]| crate::io::plausible::median(a.iter().map(|x| x.1).collect());
    let steady = |a: &[(usize, Real)], m: Real| a.iter().all(|x| (x.1 / m - 1.0).abs() <= 0.1);
    (2..amplitudes.len() - 1).find_map(|split| {
        let (before, after) = amplitudes.split_at(split);
        let (b, a) = (median(before)?, median(after)?);
        let ratio = a / b;
        (b.min(a) >= SMALLEST_GAIN_AMPLITUDE
            && (ratio >= SMALLEST_GAIN_STEP || ratio <= 1.0 / SMALLEST_GAIN_STEP)
            && steady(before, b)
            && steady(after, a))
        .then_some((after[0].0, ratio))
    })
}

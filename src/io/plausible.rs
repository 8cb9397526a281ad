//! What a table's data can say about themselves, beyond each value's range: a block of
//! readings (a run, a test, a sense, a feature) that is a copy of another, and a spread of
//! readings too small or too large for the instrument and the machine. The kinds turn these
//! into refusals (`identify`, whose outputs drive a machine) or into cautions (`analyze`).
//!
//! A copy is judged by bit-identical readings: an instrument's noise and a machine's drift
//! make two real blocks of [`MIN_COPY_READINGS`] or more readings differ somewhere, so
//! identical blocks are the same readings counted twice (a run pasted under a new label, a
//! test exported twice), and each would shrink every uncertainty by √2. Only a noise-free
//! simulation repeats itself exactly, and the messages say so.

use crate::math::Real;

/// The fewest readings two blocks must share for their being identical to count as a copy:
/// with a noise of even one resolution step, three equal readings in a row happen by chance
/// with a probability of order (1/ number of steps in the noise)³.
pub const MIN_COPY_READINGS: usize = 3;

/// A block of readings: its label (as the file names it) and its readings in file order, in
/// whatever unit the kind reads them (compared bit for bit, so only equal text gives equal
/// readings).
#[derive(Clone, Debug, PartialEq)]
pub struct Block {
    /// The block's name in the file (`run "3"`, `test "CK1 A0"`, `the ccw sense`).
    pub label: String,
    /// The readings that would be counted, in file order.
    pub readings: Vec<Real>,
}

/// The first two blocks (by index, the earlier first) that hold the same readings in the same
/// order, with at least [`MIN_COPY_READINGS`] of them and not all equal to one value (a
/// constant block, such as zeros at a reference, is not evidence of a copy).
pub fn copied_block(blocks: &[Block]) -> Option<(usize, usize)> {
    for (j, later) in blocks.iter().enumerate() {
        let r = &later.readings;
        if r.len() < MIN_COPY_READINGS || r.iter().all(|v| v.to_bits() == r[0].to_bits()) {
            continue;
        }
        if let Some(i) = blocks[..j].iter().position(|earlier| {
            earlier.readings.len() == r.len()
                && earlier
                    .readings
                    .iter()
                    .zip(r)
                    .all(|(a, b)| a.to_bits() == b.to_bits())
        }) {
            return Some((i, j));
        }
    }
    None
}

/// The block whose readings span `factor` times more or less than the median span of the
/// others (blocks of at least [`MIN_COPY_READINGS`]), with its span and that median: one run,
/// sense or test written in another unit than the rest (×1000 for mm or nm, ×10 for a count
/// of 0.1 µm). The most extreme one, if any.
pub fn odd_block(blocks: &[Block], factor: Real) -> Option<(usize, Real, Real)> {
    let spans: Vec<Option<Real>> = blocks
        .iter()
        .map(|b| {
            (b.readings.len() >= MIN_COPY_READINGS).then(|| spread(b.readings.iter().copied()))
        })
        .collect();
    let mut worst: Option<(usize, Real, Real, Real)> = None;
    for (j, span) in spans.iter().enumerate() {
        let Some(span) = *span else { continue };
        let others: Vec<Real> = spans
            .iter()
            .enumerate()
            .filter(|(i, _)| *i != j)
            .filter_map(|(_, s)| *s)
            .collect();
        let Some(middle) = median(others) else {
            continue;
        };
        if middle <= 0.0 || span <= 0.0 {
            continue;
        }
        let ratio = (span / middle).max(middle / span);
        if ratio > factor && worst.is_none_or(|w| ratio > w.3) {
            worst = Some((j, span, middle, ratio));
        }
    }
    worst.map(|(j, span, middle, _)| (j, span, middle))
}

/// The sentence for an [`odd_block`] (µm figures; the caller names the file). With two
/// blocks, either may be the odd one, and the sentence names both.
pub fn odd_sentence(
    column: &str,
    blocks: &[Block],
    (j, span, middle): (usize, Real, Real),
) -> String {
    let judged = blocks
        .iter()
        .filter(|b| b.readings.len() >= MIN_COPY_READINGS)
        .count();
    if judged == 2 {
        let other = blocks
            .iter()
            .enumerate()
            .find(|(i, b)| *i != j && b.readings.len() >= MIN_COPY_READINGS)
            .map_or("the other", |(_, b)| b.label.as_str());
        return format!(
            "column `{column}`: {} spans {} µm and {other} {} µm, {} times apart: one of them in another unit (mm, nm, a count of 0.1 µm)?",
            blocks[j].label,
            crate::math::trimmed(span * 1e6, 4),
            crate::math::trimmed(middle * 1e6, 4),
            crate::math::trimmed((span / middle).max(middle / span), 1),
        );
    }
    format!(
        "column `{column}`: {} spans {} µm where the others span {} µm (median), {} times {}: that one in another unit (mm, nm, a count of 0.1 µm)?",
        blocks[j].label,
        crate::math::trimmed(span * 1e6, 4),
        crate::math::trimmed(middle * 1e6, 4),
        crate::math::trimmed((span / middle).max(middle / span), 1),
        if span > middle { "more" } else { "less" }
    )
}

/// The sentence for a copy [`copied_block`] found (the caller names the file).
pub fn copy_sentence(blocks: &[Block], (i, j): (usize, usize)) -> String {
    format!(
        "{} holds the same {} readings as {}, reading for reading: a copy would count them twice (every uncertainty √2 too small); no instrument repeats its noise, only a noise-free simulation does",
        blocks[j].label,
        blocks[j].readings.len(),
        blocks[i].label
    )
}

/// The range of air temperatures a machine shop has (°C): 0 … 40 °C, from an unheated hall
/// in winter to a hot one in summer. Air read outside it is in another unit (°F: 20 °C reads
/// 68; kelvin are refused by the thermometer's range).
pub const SHOP_AIR_DEGC: (Real, Real) = (0.0, 40.0);

/// The caution for an air temperature column `column` whose median lies outside
/// [`SHOP_AIR_DEGC`].
pub fn air_caution(column: &str, values: &[Real]) -> Option<String> {
    let middle = median(values.to_vec())?;
    let (lo, hi) = SHOP_AIR_DEGC;
    (!(lo..=hi).contains(&middle)).then(|| {
        format!(
            "column `{column}`: the air reads {} °C (median), outside the {lo} … {hi} °C of any machine shop: °F in the °C column?",
            crate::math::trimmed(middle, 2)
        )
    })
}

/// The coarsest of the steps a metrology export is rounded to (m: 10 µm, 1 µm) that every
/// one of `values` is a whole multiple of, when there are at least 10 values and 3 distinct:
/// a column rounded that coarsely loses what an instrument reads (a laser 1 nm, a ball-bar or
/// a nest 0.1 µm) and its rounding does not average out along a smooth trace.
pub fn rounded_to(values: &[Real]) -> Option<Real> {
    if values.len() < 10 {
        return None;
    }
    let mut distinct: Vec<u64> = values.iter().take(1000).map(|v| v.to_bits()).collect();
    distinct.sort_unstable();
    distinct.dedup();
    if distinct.len() < 3 {
        return None;
    }
    coarsest_grid(values, &[1e-5, 1e-6], 1e-6)
}

/// The first of `steps` (coarsest first) that every one of `values` is a whole multiple of,
/// to within `tolerance` of the step.
pub fn coarsest_grid(values: &[Real], steps: &[Real], tolerance: Real) -> Option<Real> {
    steps.iter().copied().find(|step| {
        values.iter().all(|v| {
            let n = v / step;
            (n - n.round()).abs() < tolerance
        })
    })
}

/// The sentence for a column `column` rounded to `step` (m).
pub fn rounding_sentence(column: &str, step: Real, what: &str) -> String {
    format!(
        "column `{column}`: every reading is a whole multiple of {} µm, an export rounded that coarsely ({what}): the figures carry its rounding",
        crate::math::trimmed(step * 1e6, 3)
    )
}

/// The hottest a machine's structure runs where test sensors sit (°C): 60 °C. Spindle
/// housings and screw nuts run at 30 to 50 °C; 20 °C in °F reads 68.
pub const HOTTEST_STRUCTURE_DEGC: Real = 60.0;

/// The caution for a structure temperature column `column` whose median is above
/// [`HOTTEST_STRUCTURE_DEGC`].
pub fn structure_caution(column: &str, values: &[Real]) -> Option<String> {
    let middle = median(values.to_vec())?;
    (middle > HOTTEST_STRUCTURE_DEGC).then(|| {
        format!(
            "column `{column}`: the structure reads {} °C (median), hotter than the {HOTTEST_STRUCTURE_DEGC} °C any machine tool runs at where sensors sit: °F in the °C column?",
            crate::math::trimmed(middle, 2)
        )
    })
}

/// How many times the readings' typical scatter one reading must lie from the others of its
/// group to read as a glitch: 20 (the robust standard deviation, 1.4826 × the median absolute
/// deviation from each group's median, so that a Gaussian noise exceeds it with a
/// probability of about 1e-88).
pub const LONE_READING: Real = 20.0;

/// A reading that lies far from the others of its group: its group and index, how far from the
/// group's median (m, signed) and the readings' robust standard deviation (m).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Lone {
    /// The group (a target and direction, a test).
    pub group: usize,
    /// The reading, within its group.
    pub index: usize,
    /// Its distance from the group's median (signed, the reading's unit).
    pub off: Real,
    /// The readings' robust standard deviation about their groups' medians.
    pub scale: Real,
}

/// The reading farthest from its group's median, when it lies more than [`LONE_READING`]
/// times the readings' robust scatter and more than `floor` from it, and the other readings
/// of its source (its run) lie within a quarter of that from theirs: a glitch (a beam
/// interrupted, a chip, a typo), not a source offset or in another unit as a whole (which
/// other checks name). Each reading is `(value, source)`. Groups of fewer than 3 readings
/// have no median that one reading cannot move, and are passed over.
pub fn lone_reading(groups: &[Vec<(Real, usize)>], floor: Real) -> Option<Lone> {
    let mut offs: Vec<(usize, usize, Real, usize)> = Vec::new();
    for (g, values) in groups.iter().enumerate() {
        if values.len() < 3 {
            continue;
        }
        let middle = median(values.iter().map(|v| v.0).collect())?;
        offs.extend(
            values
                .iter()
                .enumerate()
                .map(|(i, v)| (g, i, v.0 - middle, v.1)),
        );
    }
    let scale = 1.4826 * median(offs.iter().map(|o| o.2.abs()).collect())?;
    let &(group, index, off, source) =
        offs.iter().max_by(|a, b| a.2.abs().total_cmp(&b.2.abs()))?;
    let others = median(
        offs.iter()
            .filter(|o| o.3 == source && (o.0, o.1) != (group, index))
            .map(|o| o.2.abs())
            .collect(),
    )
    .unwrap_or(0.0);
    (off.abs() > LONE_READING * scale && off.abs() > floor && others < 0.25 * off.abs()).then_some(
        Lone {
            group,
            index,
            off,
            scale,
        },
    )
}

/// The longest stretch of consecutive readings that hold one value bit for bit, as (first,
/// count), when it has at least `fewest` readings, is not the whole channel (a constant
/// channel is judged by its spread), and is at least ten times the channel's longest other
/// rest on one value (a channel whose resolution is coarse for its motion rests often and
/// long, and a long rest then says nothing). A sensor's noise, or the motion it follows,
/// changes its reading at a pace of its own; a value held ten times longer than ever before
/// is a sensor out of its range, disconnected, or a logger repeating its last value.
pub fn stuck(values: &[Real], fewest: usize) -> Option<(usize, usize)> {
    let mut rests: Vec<(usize, usize)> = Vec::new();
    let mut start = 0;
    for k in 1..=values.len() {
        if k == values.len() || values[k].to_bits() != values[start].to_bits() {
            rests.push((start, k - start));
            start = k;
        }
    }
    let &best = rests.iter().max_by_key(|r| r.1)?;
    let other = rests
        .iter()
        .filter(|r| r.0 != best.0)
        .map(|r| r.1)
        .max()
        .unwrap_or(0);
    (best.1 >= fewest.max(2) && best.1 < values.len() && best.1 >= 10 * other).then_some(best)
}

/// The robust scale of a series' steps (their magnitudes): 1.4826 × their median, and at least
/// the smallest step that is not zero (the series' resolution: a series that mostly rests on
/// one value has a median step of 0, and its every change is one resolution step, not a
/// glitch).
fn step_scale(magnitudes: &[Real]) -> Option<Real> {
    let robust = 1.4826 * median(magnitudes.to_vec())?;
    let finest = magnitudes
        .iter()
        .copied()
        .filter(|&d| d > 0.0)
        .fold(Real::INFINITY, Real::min);
    Some(if finest.is_finite() {
        robust.max(finest)
    } else {
        robust
    })
}

/// A reading that stands apart from both its neighbours the same way (a spike: a glitch, an
/// electrical pulse, a typo), as (index, its distance from its neighbours' mean, the robust
/// scale of that distance over the series): when it is more than [`LONE_READING`] times that
/// scale, and its smaller step to a neighbour more than `floor`. The distance from the
/// neighbours' mean (a second difference) is small on any smooth series, however fast it
/// moves (a spindle warming, an eccentricity sampled 32 times a turn); a step (re-zeroed)
/// moves one neighbour only and is not a spike.
pub fn spike(values: &[Real], floor: Real) -> Option<(usize, Real, Real)> {
    if values.len() < 5 {
        return None;
    }
    let off: Vec<Real> = (1..values.len() - 1)
        .map(|k| values[k] - 0.5 * (values[k - 1] + values[k + 1]))
        .collect();
    let scale = step_scale(&off.iter().map(|e| e.abs()).collect::<Vec<_>>())?;
    let (k, size) = (1..values.len() - 1)
        .filter(|&k| {
            let (before, after) = (values[k] - values[k - 1], values[k] - values[k + 1]);
            before * after > 0.0 && before.abs().min(after.abs()) > floor
        })
        .map(|k| (k, off[k - 1]))
        .max_by(|a, b| a.1.abs().total_cmp(&b.1.abs()))?;
    (size.abs() > LONE_READING * scale).then_some((k, size, scale))
}

/// A step between two readings with quiet steps on either side (a sensor re-zeroed or
/// knocked), as (index of the reading after the step, the step, the robust scale of the
/// steps): more than [`LONE_READING`] times that scale and `floor`, its neighbouring steps
/// within five times the scale. A fast but smooth change (a spindle starting) moves several
/// steps in a row and is not one.
pub fn lone_step(values: &[Real], floor: Real) -> Option<(usize, Real, Real)> {
    if values.len() < 5 {
        return None;
    }
    let steps: Vec<Real> = values.windows(2).map(|w| w[1] - w[0]).collect();
    let scale = step_scale(&steps.iter().map(|d| d.abs()).collect::<Vec<_>>())?;
    let (k, step) = (1..steps.len() - 1)
        .filter(|&k| steps[k - 1].abs() < 5.0 * scale && steps[k + 1].abs() < 5.0 * scale)
        .map(|k| (k, steps[k]))
        .max_by(|a, b| a.1.abs().total_cmp(&b.1.abs()))?;
    (step.abs() > LONE_READING * scale && step.abs() > floor).then_some((k + 1, step, scale))
}

/// The unit factors one channel can differ from its partner by: a count of 0.1 µm, nm, mm
/// (powers of ten), inches (25.4) and micro-inches in a µm column (39.37).
pub const UNIT_FACTORS: [Real; 5] = [10.0, 100.0, 1000.0, 25.4, 39.37];

/// How closely two channels must follow each other, reading for reading, for their ratio to
/// be read as a unit slip rather than a motion: a correlation of 0.99, and a slope within
/// [`UNIT_RATIO_TOLERANCE`] of a factor of [`UNIT_FACTORS`].
pub const UNIT_RATIO_CORRELATION: Real = 0.99;

/// How far (relative) a slope may be from a unit factor and still be read as it: 10 %. Two
/// sensors of one nest differ by the tilt between them, a few % of the drift on a spindle
/// head; the nearest factors (10 and 25.4) are 2.5 times apart, so no factor is mistaken for
/// another.
pub const UNIT_RATIO_TOLERANCE: Real = 0.1;

/// Whether `b` reads a unit factor times `a`, reading for reading: the factor (of
/// [`UNIT_FACTORS`], or its inverse when `a` is the larger) when the least-squares slope of `b`
/// on `a` is within [`UNIT_RATIO_TOLERANCE`] of it and the two correlate by [`UNIT_RATIO_CORRELATION`] or more.
/// At least ten readings; None for constant channels.
pub fn unit_ratio(a: &[Real], b: &[Real]) -> Option<Real> {
    let n = a.len().min(b.len());
    if n < 10 {
        return None;
    }
    let mean = |v: &[Real]| v[..n].iter().sum::<Real>() / n as Real;
    let (ma, mb) = (mean(a), mean(b));
    let (mut saa, mut sbb, mut sab) = (0.0, 0.0, 0.0);
    for (p, q) in a[..n].iter().zip(&b[..n]) {
        let (p, q) = (p - ma, q - mb);
        saa += p * p;
        sbb += q * q;
        sab += p * q;
    }
    if !(saa > 0.0 && sbb > 0.0) || sab / (saa * sbb).sqrt() < UNIT_RATIO_CORRELATION {
        return None;
    }
    let slope = sab / saa;
    UNIT_FACTORS
        .iter()
        .flat_map(|&f| [f, 1.0 / f])
        .find(|&f| (slope / f - 1.0).abs() < UNIT_RATIO_TOLERANCE)
}

/// Max − min of `values` (0 for none).
pub fn spread(values: impl IntoIterator<Item = Real>) -> Real {
    let (lo, hi) = values
        .into_iter()
        .fold((Real::INFINITY, Real::NEG_INFINITY), |(lo, hi), v| {
            (lo.min(v), hi.max(v))
        });
    if hi >= lo { hi - lo } else { 0.0 }
}

/// The median of `values` (None for none).
pub fn median(mut values: Vec<Real>) -> Option<Real> {
    if values.is_empty() {
        return None;
    }
    values.sort_by(Real::total_cmp);
    let n = values.len();
    Some(if n % 2 == 1 {
        values[n / 2]
    } else {
        0.5 * (values[n / 2 - 1] + values[n / 2])
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    fn block(label: &str, readings: &[Real]) -> Block {
        Block {
            label: label.into(),
            readings: readings.to_vec(),
        }
    }

    #[test]
    fn a_pasted_block_is_found_and_a_noisy_repeat_is_not() {
        let blocks = [
            block("run 1", &[0.1, 0.2, 0.3]),
            block("run 2", &[0.1, 0.2, 0.300_001]),
            block("run 3", &[0.1, 0.2, 0.3]),
        ];
        assert_eq!(copied_block(&blocks), Some((0, 2)));
        assert_eq!(copied_block(&blocks[..2]), None);
        let sentence = copy_sentence(&blocks, (0, 2));
        assert!(sentence.starts_with("run 3 holds the same 3 readings as run 1"));
    }

    #[test]
    fn short_or_constant_blocks_are_not_copies() {
        let short = [block("a", &[1.0, 2.0]), block("b", &[1.0, 2.0])];
        assert_eq!(copied_block(&short), None);
        let zeros = [block("a", &[0.0; 5]), block("b", &[0.0; 5])];
        assert_eq!(copied_block(&zeros), None);
    }

    #[test]
    fn one_block_in_another_unit_is_found() {
        let blocks = [
            block("run 1", &[0.0, 5e-6, 10e-6]),
            block("run 2", &[0.0, 5.2e-6, 10.1e-6]),
            block("run 3", &[0.0, 5e-9, 10e-9]),
            block("run 4", &[0.1e-6, 5e-6, 9.9e-6]),
        ];
        // Run 3 spans 10 nm against a median 10 µm of the others (10, 10.1, 9.8).
        let (j, span, middle) = odd_block(&blocks, 30.0).unwrap();
        assert_eq!(j, 2);
        assert!((span - 10e-9).abs() < 1e-15 && (middle - 10e-6).abs() < 1e-12);
        assert_eq!(odd_block(&blocks[..2], 30.0), None);
        assert!(
            odd_sentence("deviation_um", &blocks, (j, span, middle)).contains(
                "run 3 spans 0.01 µm where the others span 10 µm (median), 1000 times less"
            )
        );
    }

    #[test]
    fn rounding_is_found_at_the_coarsest_step_and_not_in_finer_data() {
        let whole: Vec<Real> = (0..20).map(|k| (k % 7) as Real * 1e-6).collect();
        assert_eq!(rounded_to(&whole), Some(1e-6));
        let tens: Vec<Real> = whole.iter().map(|v| v * 10.0).collect();
        assert_eq!(rounded_to(&tens), Some(1e-5));
        let tenths: Vec<Real> = (0..20).map(|k| k as Real * 0.1e-6).collect();
        assert_eq!(rounded_to(&tenths), None);
        assert_eq!(rounded_to(&whole[..9]), None);
    }

    #[test]
    fn air_and_structure_in_fahrenheit_are_named() {
        // 20.5 °C of air read in °F: 68.9; a screw nut at 24 °C: 75.2.
        let air = air_caution("temp_air_degc", &[68.9, 68.9, 69.0]).unwrap();
        assert!(air.contains("`temp_air_degc`") && air.contains("68.9 °C") && air.contains("°F"));
        assert_eq!(air_caution("temp_air_degc", &[20.5, 20.6]), None);
        let nut = structure_caution("temp_nut_degc", &[75.2, 75.3, 75.4]).unwrap();
        assert!(nut.contains("`temp_nut_degc`") && nut.contains("75.3 °C"));
        assert_eq!(structure_caution("temp_spindle_degc", &[45.0, 48.0]), None);
    }

    #[test]
    fn a_channel_ten_times_its_partner_is_a_unit_ratio_and_a_tilt_is_not() {
        // Two sensors of a nest drifting together with a little noise, then the second read in
        // counts of 0.1 µm (×10), or in mm (÷1000); and a real tilt: the partner drifts 1.8 times
        // as much, a factor of no unit (nor is 11.5, 15 % from 10).
        let x1: Vec<Real> = (0..40)
            .map(|k| 1e-6 * (k as Real / 10.0).tanh() + 1e-9 * ((k * 7 % 5) as Real))
            .collect();
        let tens: Vec<Real> = x1.iter().map(|v| 10.0 * v).collect();
        assert_eq!(unit_ratio(&x1, &tens), Some(10.0));
        let mm: Vec<Real> = x1.iter().map(|v| v / 1000.0).collect();
        assert_eq!(unit_ratio(&x1, &mm), Some(1e-3));
        let tilted: Vec<Real> = x1.iter().map(|v| 1.8 * v).collect();
        assert_eq!(unit_ratio(&x1, &tilted), None);
        let near: Vec<Real> = x1.iter().map(|v| 11.5 * v).collect();
        assert_eq!(unit_ratio(&x1, &near), None);
        let unrelated: Vec<Real> = (0..40).map(|k| 1e-5 * ((k * 13 % 7) as Real)).collect();
        assert_eq!(unit_ratio(&x1, &unrelated), None);
        assert_eq!(unit_ratio(&x1[..9], &tens[..9]), None);
    }

    #[test]
    fn one_reading_far_from_its_group_is_lone_and_a_drift_is_not() {
        // Eleven targets read in five runs (the source) with ±0.1 µm of scatter; then one
        // reading +150 µm.
        let mut groups: Vec<Vec<(Real, usize)>> = (0..11)
            .map(|t| {
                (0..5)
                    .map(|r| {
                        let noise = 0.1 * (((t * 5 + r) * 7 % 5) as Real - 2.0);
                        (1e-6 * (t as Real + noise), r)
                    })
                    .collect()
            })
            .collect();
        assert_eq!(lone_reading(&groups, 1e-6), None);
        groups[7][2].0 += 150e-6;
        let lone = lone_reading(&groups, 1e-6).unwrap();
        assert_eq!((lone.group, lone.index), (7, 2));
        assert!((lone.off - 150e-6).abs() < 0.21e-6, "{lone:?}");
        // Run 2 offset as a whole by 2 µm (re-zeroed): no reading is lone in it.
        let mut offset = groups.clone();
        offset[7][2].0 -= 150e-6;
        offset.iter_mut().for_each(|g| g[2].0 += 2e-6);
        assert_eq!(lone_reading(&offset, 1e-6), None);
        // Runs drifting apart by 2 µm a run (a warm-up) move every reading, not one.
        let drifting: Vec<Vec<(Real, usize)>> = (0..11)
            .map(|t| {
                (0..5)
                    .map(|r| (1e-6 * (t as Real + 2.0 * r as Real), r))
                    .collect()
            })
            .collect();
        assert_eq!(lone_reading(&drifting, 1e-6), None);
        // Two readings a group: no median to judge by.
        let pairs = [vec![(0.0, 0), (1.0, 1)], vec![(0.0, 0), (5.0, 1)]];
        assert_eq!(lone_reading(&pairs, 0.0), None);
    }

    #[test]
    fn a_value_held_through_a_stretch_is_stuck_and_noise_is_not() {
        let mut values: Vec<Real> = (0..100).map(|k| ((k * 37 % 11) as Real) * 1e-9).collect();
        assert_eq!(stuck(&values, 20), None);
        for v in &mut values[60..] {
            *v = 20e-9;
        }
        assert_eq!(stuck(&values, 20), Some((60, 40)));
        assert_eq!(stuck(&values, 41), None);
        assert_eq!(
            stuck(&[1.0; 30], 20),
            None,
            "a constant channel is not judged here"
        );
        // A slow ramp read at a coarse resolution rests 8 readings on each value: a rest of 40
        // is only five of those, no evidence; a ramp that rests 2 and then holds 40 is stuck.
        let slow: Vec<Real> = (0..100)
            .map(|k| if k < 60 { (k / 8) as Real } else { 7.0 })
            .collect();
        assert_eq!(stuck(&slow, 20), None);
        let fast: Vec<Real> = (0..100)
            .map(|k| if k < 60 { (k / 2) as Real } else { 30.0 })
            .collect();
        assert_eq!(stuck(&fast, 20), Some((60, 40)));
    }

    #[test]
    fn a_spike_and_a_lone_step_are_found_and_a_fast_smooth_rise_is_neither() {
        // A warming: 10 µm with a 20-reading time constant, ±0.01 µm of noise.
        let warm: Vec<Real> = (0..200)
            .map(|k| {
                10e-6 * (1.0 - (-(k as Real) / 20.0).exp()) + 1e-8 * ((k * 7 % 5) as Real - 2.0)
            })
            .collect();
        assert_eq!(spike(&warm, 1e-6), None);
        assert_eq!(lone_step(&warm, 1e-6), None);
        let mut spiked = warm.clone();
        spiked[120] += 15e-6;
        let (k, size, _) = spike(&spiked, 1e-6).unwrap();
        assert_eq!(k, 120);
        assert!((size - 15e-6).abs() < 0.1e-6, "{size}");
        // Re-zeroed at reading 150: every reading from it 4 µm lower.
        let stepped: Vec<Real> = warm
            .iter()
            .enumerate()
            .map(|(k, v)| if k >= 150 { v - 4e-6 } else { *v })
            .collect();
        assert_eq!(spike(&stepped, 1e-6), None);
        let (k, step, _) = lone_step(&stepped, 1e-6).unwrap();
        assert_eq!(k, 150);
        assert!((step + 4e-6).abs() < 0.1e-6, "{step}");
        // A channel rounded to 1 µm that rests and moves a step at a time: no spike, no step.
        let rounded: Vec<Real> = warm
            .iter()
            .map(|v| (v * 1e6 / 3.0).round() * 1e-6)
            .collect();
        assert_eq!(spike(&rounded, 0.5e-6), None);
        assert_eq!(lone_step(&rounded, 0.5e-6), None);
    }

    #[test]
    fn spread_and_median_by_hand() {
        assert_eq!(spread([3.0, -1.0, 2.0]), 4.0);
        assert_eq!(spread(std::iter::empty()), 0.0);
        assert_eq!(median(vec![5.0, 1.0, 3.0]), Some(3.0));
        assert_eq!(median(vec![4.0, 1.0, 3.0, 2.0]), Some(2.5));
        assert_eq!(median(vec![]), None);
    }
}

//! From a record to the ISO 230-7 tests its probes allow, evaluated set-up by set-up and speed
//! by speed: what `mtwin analyze spindle` reports.
//!
//! The probes decide the tests (directions and positions from the table, see
//! [`super::record`]):
//!
//! | probes | test | signal |
//! |---|---|---|
//! | one radial probe (direction across the axis), fixed | radial, fixed sensitive direction (§5.4.3, formula (3)) | its reading |
//! | two radial probes at one height, not parallel, fixed | radial, rotating sensitive direction (§5.3.2, formula (1)) | `E_X cos θ + E_Y sin θ`, with `E` solved from both readings |
//! | the same pair, a direction θ_f asked ([`Options::fixed_directions`]) | radial, fixed sensitive direction between the probes (§5.4.3.2, formula (4)) | `E_X cos θ_f + E_Y sin θ_f` |
//! | two parallel radial probes at two heights | tilt, fixed sensitive direction (§5.4.5 Method 2, formula (5)) | `(upper − lower) / L` |
//! | two such pairs at two heights | tilt, rotating sensitive direction (§5.3.3 Method 2) | formula (1) on the differences, `/ L` |
//! | a probe along the axis, on it | axial (§5.3.4) | its reading |
//! | a probe along the axis at a radius | face | its reading |
//! | a probe turning with the axis | the same tests, its sensitive direction rotating | its reading |
//!
//! Each test is scored about every centre asked (the preferred one of ISO 230-7 Tab 1 first),
//! with its spectrum. When the record holds the set-ups `normal` and `reversed` (Donaldson
//! reversal, Annex B) the radial probes' synchronous profiles are separated into artefact form
//! and error motion; three or more radial probes at one height are separated by the
//! multi-probe method, whose blind harmonics are listed.
//!
//! A rotary axis (not `S`) turned both ways at one speed also gets the two senses pooled into
//! one evaluation (`pool`, §6), after the per-direction segments.
//!
//! Samples must lie on the index grid `θ_m = 2πm/M` (within 1 µrad); a record sampled off
//! the grid is resampled first ([`motion::resample`]). A record of an axis turning backwards
//! (negative speed) is laid out on the angle travelled, `2π − θ`, so that its revolutions run
//! forward in time; its values are those of the mirrored plot, which are the same, and formula
//! (1) takes the axis angle. Separations use forward records of the normal set-up only: the
//! probe azimuths in the table describe that set-up.

use super::analysis::motion::{self, Direction, ErrorMotionValues, Grid, MotionError, Revolutions};
use super::analysis::polar::Centre;
use super::analysis::separation::{self, SeparationError};
use super::analysis::spectrum::{self, Line};
use super::record::{Sensing, SpindleProbe, SpindleRecord};
use crate::math::Real;
use std::f64::consts::TAU;

mod pool;
mod separated;
mod shift;
mod uncertainty;

pub use separated::{Separated, SeparatedMotion};
pub use shift::SpeedShift;
pub use uncertainty::{Budget, Contribution, TestUncertainty, rounding_step, student_t95};

/// How far a probe direction may lean and still count as radial or axial (1 mrad).
const ALIGNED: Real = 1e-3;

/// Spectral lines reported per test.
pub const LINES: usize = 8;

/// What to evaluate.
#[derive(Clone, Debug)]
pub struct Options {
    /// Centres to score about (the preferred one is always first).
    pub centres: Vec<Centre>,
    /// Condition number above which a multi-probe harmonic is blind.
    pub condition_limit: Real,
    /// Fixed sensitive directions (rad from X) to evaluate from each pair of radial probes at
    /// one height, by ISO 230-7 formula (4) `ΔX cos θ_f + ΔY sin θ_f` (§5.4.3.2, F(4)).
    pub fixed_directions: Vec<Real>,
    /// What the record cannot say about its uncertainty (Annex F).
    pub budget: Budget,
}

impl Default for Options {
    fn default() -> Options {
        Options {
            centres: vec![
                Centre::Pc,
                Centre::Lsc,
                Centre::Mrs,
                Centre::Mic,
                Centre::Mcc,
            ],
            condition_limit: separation::DEFAULT_CONDITION_LIMIT,
            fixed_directions: Vec::new(),
            budget: Budget::default(),
        }
    }
}

/// Why a record cannot be evaluated.
#[derive(Debug, thiserror::Error)]
pub enum EvaluateError {
    /// A test's signal could not be laid out or scored.
    #[error("{test}: {source}")]
    Motion {
        /// The test.
        test: String,
        /// Why.
        source: MotionError,
    },
    /// A separation failed.
    #[error("{what}: {source}")]
    Separation {
        /// Which separation.
        what: String,
        /// Why.
        source: SeparationError,
    },
    /// No probe gives any test.
    #[error("no probe gives an ISO 230-7 test (radial, axial, face or tilt)")]
    NoTest,
}

/// One evaluated test.
#[derive(Clone, Debug)]
pub struct Test {
    /// Its name: kind, probes and sensing (`radial x1`, `radial x1+y1 rotating`, `tilt x1-x2`).
    pub name: String,
    /// Radial, axial, tilt or face.
    pub direction: Direction,
    /// Whether the sensitive direction is fixed or rotating.
    pub sensing: Sensing,
    /// The probes it uses.
    pub probes: Vec<String>,
    /// Height along the axis (m) of a radial or face test; the lower station of a tilt.
    pub height: Real,
    /// The signal (m, or rad for tilt), revolution by revolution.
    pub signal: Revolutions,
    /// The values about each centre asked, the preferred centre first.
    pub values: Vec<ErrorMotionValues>,
    /// The largest spectral lines (synchronous and asynchronous).
    pub lines: Vec<Line>,
    /// The values' uncertainty (Annex F).
    pub uncertainty: TestUncertainty,
}

/// The tests of one set-up at one speed.
#[derive(Clone, Debug)]
pub struct Segment {
    /// The set-up's name (`""` for a record of one set-up).
    pub setup: String,
    /// Speed (rad/s, signed).
    pub speed: Real,
    /// Revolutions recorded.
    pub revolutions: usize,
    /// Whether it pools the forward and backward runs of a rotary axis at this speed
    /// (its set-up then ends in `(both senses)`, its speed is the forward one).
    pub pooled: bool,
    /// The tests.
    pub tests: Vec<Test>,
}

/// Everything `analyze spindle` reports on one record.
#[derive(Clone, Debug)]
pub struct Evaluation {
    /// Samples per revolution.
    pub samples_per_revolution: usize,
    /// Set-up by set-up, speed by speed, in file order.
    pub segments: Vec<Segment>,
    /// Form separations.
    pub separations: Vec<Separated>,
    /// Speed-induced axis shift of each test seen at several speeds.
    pub shifts: Vec<SpeedShift>,
    /// Things a reader should know (resampling, skipped separations).
    pub notes: Vec<String>,
}

/// The probe's kind from its geometry.
#[derive(Clone, Copy, Debug, PartialEq)]
enum ProbeKind {
    /// Across the axis at stator azimuth `azimuth` (the side it sits on).
    Radial { azimuth: Real },
    /// Along the axis, on it.
    Axial,
    /// Along the axis at a radius.
    Face,
}

fn kind(probe: &SpindleProbe) -> Option<ProbeKind> {
    let [dx, dy, dz] = probe.direction;
    let [px, py, _] = probe.position;
    if dz.abs() < ALIGNED {
        // The probe faces −d: it sits on the side −d points away from, at azimuth of −d.
        Some(ProbeKind::Radial {
            azimuth: (-dy).atan2(-dx).rem_euclid(TAU),
        })
    } else if dx.hypot(dy) < ALIGNED {
        if px.hypot(py) < 1e-6 {
            Some(ProbeKind::Axial)
        } else {
            Some(ProbeKind::Face)
        }
    } else {
        None
    }
}

/// Evaluates every test the record's probes allow.
pub fn evaluate(
    record: &SpindleRecord,
    samples_per_revolution: usize,
    options: &Options,
) -> Result<Evaluation, EvaluateError> {
    let m = samples_per_revolution;
    let mut notes = Vec::new();
    // The resolution: stated, or the step the readings are rounded to.
    let mut options = options.clone();
    if options.budget.resolution.is_none() {
        options.budget.resolution = rounding_step(&record.readings);
    }
    let options = &options;
    let mut segments = Vec::new();
    for (start, end) in segment_bounds(record) {
        let signals = probe_signals(record, start, end, m, &mut notes)?;
        let backwards = record.speed[start] < 0.0;
        if backwards {
            let note = "a backwards record is laid out on the angle travelled (360° − the axis \
                        angle): its polar plots are mirrored; its values are not changed by that";
            if !notes.iter().any(|n| n == note) {
                notes.push(note.to_string());
            }
        }
        let revolutions = signals.first().map_or(0, |s| s.count());
        let tests = tests(record, signals, options, backwards)?;
        if tests.is_empty() {
            return Err(EvaluateError::NoTest);
        }
        segments.push(Segment {
            setup: record.setup[start].clone(),
            speed: record.speed[start],
            revolutions,
            pooled: false,
            tests,
        });
    }
    let pooled = pool::pooled(record, &segments, options)?;
    let mut separations = separated::reversals(record, &segments, options)?;
    separations.extend(separated::multiprobe(
        record, &segments, options, &mut notes,
    )?);
    let shifts = shift::speed_shifts(&segments);
    segments.extend(pooled);
    Ok(Evaluation {
        samples_per_revolution: m,
        shifts,
        segments,
        separations,
        notes,
    })
}

/// Sample ranges of equal set-up and speed, in file order.
fn segment_bounds(record: &SpindleRecord) -> Vec<(usize, usize)> {
    let mut bounds = Vec::new();
    let mut start = 0;
    for i in 1..=record.len() {
        if i == record.len()
            || record.setup[i] != record.setup[start]
            || record.speed[i] != record.speed[start]
        {
            bounds.push((start, i));
            start = i;
        }
    }
    bounds
}

/// Each probe's readings in `start..end` as revolutions on the index grid (resampled when
/// the angles are off it).
fn probe_signals(
    record: &SpindleRecord,
    start: usize,
    end: usize,
    m: usize,
    notes: &mut Vec<String>,
) -> Result<Vec<Revolutions>, EvaluateError> {
    // The angle travelled since the index: the axis angle, or its complement for an axis
    // turning backwards, so that revolutions run forward in time either way.
    let backwards = record.speed[start] < 0.0;
    let travelled = |i: usize| {
        if backwards {
            (TAU - record.angle[i]).rem_euclid(TAU)
        } else {
            record.angle[i]
        }
    };
    let grid: Vec<Real> = (0..m).map(|k| TAU * k as Real / m as Real).collect();
    let on_grid = (start..end)
        .zip(grid.iter().cycle())
        .all(|(i, &nominal)| (travelled(i) - nominal).abs() < 1e-6)
        && (end - start).is_multiple_of(m);
    record
        .probes
        .iter()
        .zip(&record.readings)
        .map(|(probe, readings)| {
            let values = readings[start..end].to_vec();
            let laid_out = if on_grid {
                Revolutions::new(m, values)
            } else {
                let first = record.revolution[start];
                let unwrapped: Vec<Real> = (start..end)
                    .map(|i| TAU * (record.revolution[i] - first) as Real + travelled(i))
                    .collect();
                motion::resample(&unwrapped, &values, m)
            };
            laid_out.map_err(|source| EvaluateError::Motion {
                test: format!("probe {}", probe.name),
                source,
            })
        })
        .collect::<Result<Vec<_>, _>>()
        .inspect(|_| {
            if !on_grid {
                let note = format!(
                    "samples off the index grid: resampled linearly onto {m} per revolution"
                );
                if !notes.contains(&note) {
                    notes.push(note);
                }
            }
        })
}

/// A test's signal with what names it, before it is scored.
struct Candidate {
    name: String,
    direction: Direction,
    sensing: Sensing,
    /// Indices of the probes it uses.
    probes: Vec<usize>,
    height: Real,
    signal: Revolutions,
}

/// A test's values about each centre asked (the preferred one first) and its largest spectral
/// lines, on the record's grid.
fn score(
    candidate: Candidate,
    probes: &[SpindleProbe],
    centrings: &[Real],
    grid: &Grid,
    options: &Options,
) -> Result<Test, EvaluateError> {
    let Candidate {
        name,
        direction,
        sensing,
        probes: used,
        height,
        signal,
    } = candidate;
    let preferred = direction.preferred_centre();
    let centres = std::iter::once(preferred)
        .chain(options.centres.iter().copied().filter(|c| *c != preferred));
    let centres: Vec<Centre> = centres.collect();
    let values = motion::values_about_on(&signal, direction, &centres, grid).map_err(|source| {
        EvaluateError::Motion {
            test: name.clone(),
            source,
        }
    })?;
    let lines = spectrum::largest_lines(&signal, LINES, None);
    let mut test = Test {
        name,
        direction,
        sensing,
        probes: used.iter().map(|&i| probes[i].name.clone()).collect(),
        height,
        signal,
        values,
        lines,
        uncertainty: TestUncertainty::default(),
    };
    let centring = used.iter().map(|&i| centrings[i]).fold(0.0, Real::max);
    let used: Vec<&SpindleProbe> = used.iter().map(|&i| &probes[i]).collect();
    // A tilt's stations: its first and last probes are at the lower and upper heights.
    let length =
        (used.len() >= 2).then(|| (used[used.len() - 1].position[2] - used[0].position[2]).abs());
    test.uncertainty =
        uncertainty::test_uncertainty(&test, &used, length, centring, &options.budget);
    Ok(test)
}

/// The tests of one segment, in report order: single probes, pairs of radial probes at one
/// height (rotating sensitive direction), tilts between parallel probes (fixed sensitive
/// direction), tilts between pairs (rotating). Each signal is built once: the single tests
/// take the probes' signals over, the rotating tilts are built from the pairs' signals.
fn tests(
    record: &SpindleRecord,
    signals: Vec<Revolutions>,
    options: &Options,
    backwards: bool,
) -> Result<Vec<Test>, EvaluateError> {
    let probes = &record.probes;
    let kinds: Vec<Option<ProbeKind>> = probes.iter().map(kind).collect();
    let Some(first) = signals.first() else {
        return Ok(Vec::new());
    };
    let m = first.samples_per_revolution();
    // Fixed radial probes: pairs at one height (rotating sensitive direction), parallel pairs
    // at two heights (tilt).
    let radial: Vec<usize> = (0..probes.len())
        .filter(|&i| {
            matches!(kinds[i], Some(ProbeKind::Radial { .. }))
                && probes[i].sensing == Sensing::Fixed
        })
        .collect();
    // Formula (1) takes the axis angle: minus the angle travelled when turning backwards.
    let sign = if backwards { -1.0 } else { 1.0 };
    let directions: Vec<(Real, Real)> = (0..m)
        .map(|k| (sign * TAU * k as Real / m as Real).sin_cos())
        .collect();
    let pairs = xy_pairs(probes, &radial);
    // Each radial probe's 1-UPR amplitude, the artefact's centring it reads (for the budget).
    let centrings: Vec<Real> = signals
        .iter()
        .zip(&kinds)
        .map(|(signal, kind)| match kind {
            Some(ProbeKind::Radial { .. }) => uncertainty::centring(signal),
            _ => 0.0,
        })
        .collect();
    let pair_tests: Vec<Candidate> = pairs
        .iter()
        .map(|&(a, b)| Candidate {
            name: format!("radial {}+{} rotating", probes[a].name, probes[b].name),
            direction: Direction::Radial,
            sensing: Sensing::Rotating,
            probes: vec![a, b],
            height: probes[a].position[2],
            signal: rotating(
                &probes[a],
                &probes[b],
                &signals[a],
                &signals[b],
                &directions,
            ),
        })
        .collect();
    // The same pairs in each fixed direction asked (formula (4)): a constant direction.
    let fixed_tests: Vec<Candidate> = pairs
        .iter()
        .flat_map(|&(a, b)| {
            options
                .fixed_directions
                .iter()
                .map(move |&theta_f| (a, b, theta_f))
        })
        .map(|(a, b, theta_f)| {
            let along = vec![theta_f.sin_cos(); m];
            Candidate {
                name: format!(
                    "radial {}+{} fixed {}°",
                    probes[a].name,
                    probes[b].name,
                    degrees_label(theta_f)
                ),
                direction: Direction::Radial,
                sensing: Sensing::Fixed,
                probes: vec![a, b],
                height: probes[a].position[2],
                signal: rotating(&probes[a], &probes[b], &signals[a], &signals[b], &along),
            }
        })
        .collect();
    let mut tilts = Vec::new();
    for (n, &a) in radial.iter().enumerate() {
        for &b in &radial[n + 1..] {
            let (da, db) = (probes[a].direction, probes[b].direction);
            let parallel = (da[0] * db[0] + da[1] * db[1] - 1.0).abs() < ALIGNED;
            let (za, zb) = (probes[a].position[2], probes[b].position[2]);
            if !parallel || (za - zb).abs() < 1e-6 {
                continue;
            }
            let (lower, upper) = if za < zb { (a, b) } else { (b, a) };
            tilts.push(Candidate {
                name: format!("tilt {}-{}", probes[lower].name, probes[upper].name),
                direction: Direction::Tilt,
                sensing: Sensing::Fixed,
                probes: vec![lower, upper],
                height: probes[lower].position[2],
                signal: tilt(&signals[lower], &signals[upper], (za - zb).abs()),
            });
        }
    }
    // Two xy pairs at two heights: tilt in the rotating sensitive direction (Method 2), from
    // the pairs' formula-(1) signals.
    for (n, &(a1, b1)) in pairs.iter().enumerate() {
        for (n2, &(a2, b2)) in pairs.iter().enumerate().skip(n + 1) {
            let (z1, z2) = (probes[a1].position[2], probes[a2].position[2]);
            if (z1 - z2).abs() < 1e-6 {
                continue;
            }
            let (((la, lb), lower), ((ua, ub), upper)) = if z1 < z2 {
                (((a1, b1), n), ((a2, b2), n2))
            } else {
                (((a2, b2), n2), ((a1, b1), n))
            };
            tilts.push(Candidate {
                name: format!(
                    "tilt {}+{}-{}+{} rotating",
                    probes[la].name, probes[lb].name, probes[ua].name, probes[ub].name
                ),
                direction: Direction::Tilt,
                sensing: Sensing::Rotating,
                probes: vec![la, lb, ua, ub],
                height: probes[la].position[2],
                signal: tilt(
                    &pair_tests[lower].signal,
                    &pair_tests[upper].signal,
                    (z1 - z2).abs(),
                ),
            });
        }
    }
    // Single probes last to be built, first in the report: they take the signals over.
    let singles = signals
        .into_iter()
        .enumerate()
        .filter_map(|(i, signal)| {
            let probe = &probes[i];
            let (direction, label) = match kinds[i]? {
                ProbeKind::Radial { .. } => (Direction::Radial, "radial"),
                ProbeKind::Axial => (Direction::Axial, "axial"),
                ProbeKind::Face => (Direction::Face, "face"),
            };
            let suffix = match probe.sensing {
                Sensing::Fixed => "",
                Sensing::Rotating => " rotating",
            };
            Some(Candidate {
                name: format!("{label} {}{suffix}", probe.name),
                direction,
                sensing: probe.sensing,
                probes: vec![i],
                height: probe.position[2],
                signal,
            })
        })
        .collect::<Vec<_>>();
    // The grid's directions once for every test of the segment.
    let grid = Grid::new(m).expect("a laid-out signal has at least 3 samples per revolution");
    singles
        .into_iter()
        .chain(pair_tests)
        .chain(fixed_tests)
        .chain(tilts)
        .map(|candidate| score(candidate, probes, &centrings, &grid, options))
        .collect()
}

/// Formula (5): `(upper − lower) / length`, revolution by revolution.
fn tilt(lower: &Revolutions, upper: &Revolutions, length: Real) -> Revolutions {
    let mut values = vec![0.0; lower.values().len()];
    motion::tilt(lower.values(), upper.values(), length, &mut values);
    Revolutions::new(lower.samples_per_revolution(), values).expect("laid out like its probes")
}

/// Pairs of fixed radial probes at one height whose directions are at least 30° apart, each
/// probe in one pair at most (the first partner in column order).
fn xy_pairs(probes: &[SpindleProbe], radial: &[usize]) -> Vec<(usize, usize)> {
    let mut used = vec![false; probes.len()];
    let mut pairs = Vec::new();
    for (n, &a) in radial.iter().enumerate() {
        if used[a] {
            continue;
        }
        for &b in &radial[n + 1..] {
            let (da, db) = (probes[a].direction, probes[b].direction);
            let cross = (da[0] * db[1] - da[1] * db[0]).abs();
            let same_height = (probes[a].position[2] - probes[b].position[2]).abs() < 1e-6;
            if !used[b] && same_height && cross > 0.5 {
                used[a] = true;
                used[b] = true;
                pairs.push((a, b));
                break;
            }
        }
    }
    pairs
}

/// An angle in degrees as a test's name shows it: whole degrees without decimals, otherwise
/// to 0.001°.
fn degrees_label(theta: Real) -> String {
    let deg = theta.to_degrees();
    if (deg - deg.round()).abs() < 1e-9 {
        format!("{:.0}", deg.round())
    } else {
        format!("{deg:.3}")
    }
}

/// Formula (1) of ISO 230-7: `E_X cos θ + E_Y sin θ`, with `E` solved per sample from two
/// radial readings `r_i = d_i · E`; `directions` holds `(sin θ, cos θ)` of the `M` axis
/// angles of a revolution (all the same for a fixed direction, formula (4)).
fn rotating(
    pa: &SpindleProbe,
    pb: &SpindleProbe,
    a: &Revolutions,
    b: &Revolutions,
    directions: &[(Real, Real)],
) -> Revolutions {
    let (da, db) = (pa.direction, pb.direction);
    let det = da[0] * db[1] - da[1] * db[0];
    let m = directions.len();
    let mut values = Vec::with_capacity(a.values().len());
    for (ra, rb) in a.values().chunks_exact(m).zip(b.values().chunks_exact(m)) {
        values.extend(
            ra.iter()
                .zip(rb)
                .zip(directions)
                .map(|((&ra, &rb), &(sin, cos))| {
                    let ex = (ra * db[1] - rb * da[1]) / det;
                    let ey = (da[0] * rb - db[0] * ra) / det;
                    ex * cos + ey * sin
                }),
        );
    }
    Revolutions::new(m, values).expect("laid out like its probes")
}

/// `2, 4, 5, 7, …` shortened: at most 12 numbers, then the count of the rest.
pub fn compact_list(values: &[usize]) -> String {
    let shown: Vec<String> = values.iter().take(12).map(|v| v.to_string()).collect();
    if values.len() > 12 {
        format!("{}, … ({} in all)", shown.join(", "), values.len())
    } else {
        shown.join(", ")
    }
}

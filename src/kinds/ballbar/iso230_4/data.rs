//! A ball-bar table prepared for fitting ([`CircleData`]): the checks of the table and the
//! test, the readings as basis points (times, the reversals each sense crossed), the searched
//! parameters' ranges ([`SearchRanges`]), and the columns of terms over chosen readings.

use super::{BallbarError, CircularTest, MIN_READINGS, MIN_SPAN_DEG};
use super::{BasisPoint, Shape, Term, arc_since_reversal, diagnostic_column};
use crate::kinds::ballbar::table::BallbarTable;
use crate::math::{M_PER_MM, RAD_PER_DEG, Real};
use std::f64::consts::{FRAC_PI_2, TAU};

/// A reversal counts as crossed when the sense has readings this close before it (rad).
const CROSSING_WINDOW: Real = 3.0 * RAD_PER_DEG;

/// Decay search bounds (s) and the arc (rad) whose duration also bounds it.
const DECAY_MIN: Real = 1e-3;
const DECAY_MAX: Real = 0.2;
const DECAY_ARC: Real = 30.0 * RAD_PER_DEG;
/// Shortest cyclic period searched (m).
const PERIOD_MIN: Real = 1e-3;
/// The most lobes searched.
const LOBES_MAX: u32 = 60;

/// The searched parameters' ranges for a table.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct SearchRanges {
    /// Reversal lag (s): most negative (an axis that reverses before the trace's angles say
    /// it should: it lags less than the start the software detected) and longest.
    pub lag: (Real, Real),
    /// Spike decay (s): shortest and longest.
    pub decay: (Real, Real),
    /// Cyclic period (m): shortest and longest.
    pub period: (Real, Real),
    /// Lobes per turn: fewest and most.
    pub lobes: (u32, u32),
}

/// A table prepared for fitting: its readings as basis points and deviations.
#[derive(Clone, Debug, PartialEq)]
pub struct CircleData {
    /// The test conditions.
    pub test: CircularTest,
    /// Every reading's place on the circle, in file order.
    pub points: Vec<BasisPoint>,
    /// Every reading's deviation (m).
    pub deviation: Vec<Real>,
    /// The searched parameters' ranges.
    pub ranges: SearchRanges,
    /// Readings per sense (ccw, cw).
    pub counts: [usize; 2],
    /// Angular span per sense (rad), when present.
    pub spans: [Option<Real>; 2],
}

/// Index of a sense: ccw 0, cw 1.
pub(super) fn sense_index(sense: Real) -> usize {
    usize::from(sense < 0.0)
}

pub(super) const SENSE_NAMES: [&str; 2] = ["ccw", "cw"];

/// The arc that angles in [0, 2π) cover (rad): where it starts (the angle after the largest
/// gap, the wrap at 360° included) and its span (2π less that gap). Empty input: (0, 0).
pub fn covered_arc(angles: &[Real]) -> (Real, Real) {
    let mut sorted = angles.to_vec();
    sorted.sort_by(Real::total_cmp);
    let (Some(&first), Some(&last)) = (sorted.first(), sorted.last()) else {
        return (0.0, 0.0);
    };
    let (mut largest, mut start) = (first + TAU - last, first);
    for pair in sorted.windows(2) {
        if pair[1] - pair[0] > largest {
            largest = pair[1] - pair[0];
            start = pair[1];
        }
    }
    (start, TAU - largest)
}

impl CircleData {
    /// Checks `table` and `test` and prepares the readings.
    pub fn new(table: &BallbarTable, test: &CircularTest) -> Result<CircleData, BallbarError> {
        if !(test.radius.is_finite() && test.radius > 0.0) {
            return Err(BallbarError::Radius(test.radius / M_PER_MM));
        }
        if !(test.feed.is_finite() && test.feed > 0.0) {
            return Err(BallbarError::Feed(test.feed / M_PER_MM * 60.0));
        }
        if table.readings.is_empty() {
            return Err(BallbarError::Empty);
        }
        if let Some(k) = table.readings.iter().position(|r| {
            !(r.angle.is_finite()
                && r.deviation.is_finite()
                && r.time.is_none_or(|t| t.is_finite()))
        }) {
            return Err(BallbarError::NotFinite(k + 1));
        }
        let n = table.readings.len();
        let sense: Vec<Real> = table.readings.iter().map(|r| r.sense.sign()).collect();
        let angle: Vec<Real> = table
            .readings
            .iter()
            .map(|r| r.angle.rem_euclid(TAU) % TAU)
            .collect();
        let mut counts = [0; 2];
        let mut spans = [None; 2];
        let mut test_time = 0.0;
        for s in 0..2 {
            let angles: Vec<Real> = (0..n)
                .filter(|&i| sense_index(sense[i]) == s)
                .map(|i| angle[i])
                .collect();
            counts[s] = angles.len();
            if angles.is_empty() {
                continue;
            }
            if angles.len() < MIN_READINGS {
                return Err(BallbarError::TooFewReadings {
                    sense: SENSE_NAMES[s],
                    n: angles.len(),
                });
            }
            let (_, span) = covered_arc(&angles);
            if span < MIN_SPAN_DEG * RAD_PER_DEG {
                return Err(BallbarError::SpanTooSmall {
                    sense: SENSE_NAMES[s],
                    span_deg: span / RAD_PER_DEG,
                });
            }
            spans[s] = Some(span);
            test_time += span * test.radius / test.feed;
        }
        let timed = table.readings.iter().all(|r| r.time.is_some());
        let time: Vec<Real> = if timed {
            let start = table
                .readings
                .iter()
                .filter_map(|r| r.time)
                .fold(Real::INFINITY, Real::min);
            table
                .readings
                .iter()
                .map(|r| r.time.unwrap_or(start) - start)
                .collect()
        } else {
            (0..n).map(|i| test_time * i as Real / n as Real).collect()
        };
        // crossed[sense][reversal k at k·90°]: readings of the sense just before it.
        let mut crossed = [[false; 4]; 2];
        for i in 0..n {
            let s = sense_index(sense[i]);
            for (k, flag) in crossed[s].iter_mut().enumerate() {
                let before = (sense[i] * (k as Real * FRAC_PI_2 - angle[i])).rem_euclid(TAU);
                if before > 0.0 && before <= CROSSING_WINDOW {
                    *flag = true;
                }
            }
        }
        let unlagged = Shape::default();
        let points: Vec<BasisPoint> = (0..n)
            .map(|i| {
                let mut point = BasisPoint::new(angle[i], sense[i], time[i], [false; 2]);
                for axis in 0..2 {
                    let reversal = (angle[i]
                        - sense[i] * arc_since_reversal(axis, &point, test, &unlagged))
                    .rem_euclid(TAU);
                    let k = (reversal / FRAC_PI_2).round() as usize % 4;
                    // The next reversal of the axis in the sense of travel is half a turn on.
                    point.crossed[axis] = crossed[sense_index(sense[i])][k];
                    point.crossed_next[axis] = crossed[sense_index(sense[i])][(k + 2) % 4];
                }
                point
            })
            .collect();
        let ranges = Self::ranges(&points, test, n);
        Ok(CircleData {
            test: *test,
            points,
            deviation: exactly_centred(
                &angle,
                &table
                    .readings
                    .iter()
                    .map(|r| r.deviation)
                    .collect::<Vec<_>>(),
                test.radius,
            ),
            ranges,
            counts,
            spans,
        })
    }

    /// The searched parameters' ranges: reversal lags within ± min(200 ms, time for 30° of
    /// arc), decays from max(1 ms, two sampling intervals) to that; periods from max(1 mm,
    /// 4 sample spacings) to R/2; lobes from 3 to min(60, a quarter of the readings per turn).
    fn ranges(points: &[BasisPoint], test: &CircularTest, n: usize) -> SearchRanges {
        let mut steps: Vec<Real> = points
            .windows(2)
            .filter(|w| w[0].sense == w[1].sense)
            .map(|w| w[1].time - w[0].time)
            .filter(|dt| *dt > 0.0)
            .collect();
        steps.sort_by(Real::total_cmp);
        let interval = steps.get(steps.len() / 2).copied().unwrap_or(0.0);
        let spacing = interval * test.feed;
        let per_turn = (n as Real / 2.0).max(1.0);
        let longest = DECAY_MAX.min(DECAY_ARC * test.radius / test.feed);
        SearchRanges {
            lag: (-longest, longest),
            decay: (DECAY_MIN.max(2.0 * interval), longest),
            period: (PERIOD_MIN.max(4.0 * spacing), test.radius / 2.0),
            lobes: (3, LOBES_MAX.min((per_turn / 4.0) as u32)),
        }
    }

    /// The number of readings.
    pub fn len(&self) -> usize {
        self.points.len()
    }

    /// Whether there are no readings.
    pub fn is_empty(&self) -> bool {
        self.points.is_empty()
    }

    /// Whether both senses are present.
    pub fn both_senses(&self) -> bool {
        self.counts[0] > 0 && self.counts[1] > 0
    }

    /// Column `index` of `term` over `rows`.
    pub(super) fn column_on(
        &self,
        term: Term,
        index: usize,
        shape: &Shape,
        rows: &[usize],
    ) -> Vec<Real> {
        rows.iter()
            .map(|&i| diagnostic_column(term, index, &self.points[i], &self.test, shape))
            .collect()
    }

    /// Every column of `terms`, in order, over `rows`.
    pub(super) fn columns_on(
        &self,
        terms: &[Term],
        shape: &Shape,
        rows: &[usize],
    ) -> Vec<Vec<Real>> {
        terms
            .iter()
            .flat_map(|&t| (0..t.columns()).map(move |k| (t, k)))
            .map(|(t, k)| self.column_on(t, k, shape, rows))
            .collect()
    }
}

/// The readings `deviation` (at the programmed angles `angle`, radius `radius`) with the
/// second-order effect of the centre ball's offset taken out, so that the first-order circle
/// d ≈ r₀ + c_p·cos θ + c_q·sin θ the figures remove is exact.
///
/// With the tool ball at (R + e(θ))·u(θ) from the programmed centre and the centre ball at c
/// from it, the bar reads D = |(R + e)·u − c|, so D² = (R + e)² − 2(R + e)·u·c + |c|² and
/// R + e = u·c + √(D² − (u⊥·c)²) exactly (u⊥ the direction normal to u). Since
/// d = D − R, the reading d' = √((R + d)² − (u⊥·c)²) − R differs from the machine's radial
/// deviation e by −u·c alone, first order as the figures model it; without this the offset
/// leaves (u⊥·c)²/(2R) = |c|²/(4R)·(1 − cos 2(θ − φ)) in the trace (0.22 µm at 2θ for a
/// centre set 0.36 mm off on a 150 mm bar), which reads as squareness and ovality. c comes
/// from the first-order fit itself (c = −(c_p, c_q)), refitted on the corrected readings until
/// it settles (the correction is second order: two passes change it by less than 1 pm).
fn exactly_centred(angle: &[Real], deviation: &[Real], radius: Real) -> Vec<Real> {
    let mut centred = deviation.to_vec();
    for _ in 0..3 {
        let Some((c_p, c_q)) = first_order_centre(angle, &centred) else {
            return deviation.to_vec();
        };
        for ((out, &d), &theta) in centred.iter_mut().zip(deviation).zip(angle) {
            let (sin, cos) = theta.sin_cos();
            // u⊥·c with u⊥ = (−sin θ, cos θ) and c = −(c_p, c_q).
            let across = c_p * sin - c_q * cos;
            let reach = radius + d;
            let root = reach * reach - across * across;
            // √(X² − a²) − R = d − a²/(√(X² − a²) + X), without the cancellation.
            *out = if root > 0.0 && reach > 0.0 {
                d - across * across / (root.sqrt() + reach)
            } else {
                d
            };
        }
    }
    centred
}

/// The first-order circle's centre terms (c_p, c_q) of d ≈ r₀ + c_p·cos θ + c_q·sin θ, by least
/// squares; `None` when the angles do not determine them.
fn first_order_centre(angle: &[Real], deviation: &[Real]) -> Option<(Real, Real)> {
    let mut normal = nalgebra::Matrix3::<Real>::zeros();
    let mut right = nalgebra::Vector3::<Real>::zeros();
    for (&theta, &d) in angle.iter().zip(deviation) {
        let row = nalgebra::Vector3::new(1.0, theta.cos(), theta.sin());
        normal += row * row.transpose();
        right += row * d;
    }
    let solution = normal.try_inverse()? * right;
    Some((solution[1], solution[2]))
}

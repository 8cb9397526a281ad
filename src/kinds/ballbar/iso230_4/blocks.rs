//! The readings cut into blocks for fast fits of any union of blocks ([`Blocks`]): the angular
//! sectors of cross-validation, where nine fits (all data, then each sector held out) share
//! what depends on the data alone, or one block of training rows for a single fit.
//!
//! What depends on the data alone is computed once: the static columns (those that do not
//! depend on the searched shape) and the deviation at every reading, their cross products
//! summed per block, and per axis the readings ordered by their arc from the nearest
//! programmed reversal, where the reversal terms change with the searched lag, play and decay
//! (`reversal.rs`). Sums over other columns at chosen shapes (lobes, cyclic terms) are cached
//! here too when first needed (`spectral.rs`).

use super::spectral::{CentreMoments, LobeMoments, LobeSums, LobeTransform, Spectrum};
use super::{CircleData, CircularTest, Shape, Term, arc_since_reversal, diagnostic_column};
use crate::math::Real;
use std::collections::HashMap;
use std::f64::consts::{FRAC_PI_2, PI};
use std::sync::{Arc, Mutex, OnceLock};

/// The columns that do not depend on the searched shape (with no angle lag), the reversal
/// terms among them at no lag and no play: their change with a lag or a play is on the
/// readings near the reversals only.
pub(super) const STATICS: [Term; 14] = [
    Term::Radius,
    Term::CentreP,
    Term::CentreQ,
    Term::Squareness,
    Term::ScaleMismatch,
    Term::ServoMismatch,
    Term::StraightnessP,
    Term::StraightnessQ,
    Term::RadiusDrift,
    Term::SenseRadius,
    Term::BacklashP,
    Term::BacklashQ,
    Term::LateralPlayP,
    Term::LateralPlayQ,
];
/// Three more static columns, σ·sin θ, σ·cos θ and σ·(R/2)·cos 2θ: with them (and the servo
/// mismatch's σ·sin 2θ) the position-dependent columns at an angle lag, at θ − σ·φ, are
/// combinations of static ones.
const SIGMA_SIN: usize = STATICS.len();
const SIGMA_COS: usize = STATICS.len() + 1;
const SIGMA_COS_2: usize = STATICS.len() + 2;
/// The deviation's index after the static columns.
pub(super) const Y: usize = STATICS.len() + 3;
/// Values per reading in the table: the static columns, then the deviation.
pub(super) const WIDTH: usize = Y + 1;

/// The index of `term` among [`STATICS`] (position-dependent terms only without angle lag).
pub(super) fn static_index(term: Term, shape: &Shape) -> Option<usize> {
    let position = matches!(
        term,
        Term::CentreP | Term::CentreQ | Term::Squareness | Term::ScaleMismatch
    );
    if position && shape.angle_lag != 0.0 {
        return None;
    }
    STATICS.iter().position(|t| *t == term)
}

/// A position-dependent column at `shape`'s angle lag as a combination of static columns
/// (index, weight): with φ = v·ℓ/R, cos(θ − σφ) = cos φ·cos θ + sin φ·σ sin θ, and alike.
pub(super) fn lagged(term: Term, shape: &Shape, test: &CircularTest) -> Option<Vec<(usize, Real)>> {
    let phi = test.feed * shape.angle_lag / test.radius;
    let (s, c) = phi.sin_cos();
    let (s2, c2) = (2.0 * phi).sin_cos();
    let index = |t: Term| STATICS.iter().position(|x| *x == t).unwrap_or_default();
    Some(match term {
        Term::CentreP => vec![(index(Term::CentreP), c), (SIGMA_SIN, s)],
        Term::CentreQ => vec![(index(Term::CentreQ), c), (SIGMA_COS, -s)],
        // (R/2)·sin 2θ_a = cos 2φ·(R/2)·sin 2θ − sin 2φ·σ·(R/2)·cos 2θ.
        Term::Squareness => vec![(index(Term::Squareness), c2), (SIGMA_COS_2, -s2)],
        // (R/2)·cos 2θ_a = cos 2φ·(R/2)·cos 2θ + sin 2φ·σ·(R/2)·sin 2θ, the servo column
        // σ·(v/2)·sin 2θ times R/v.
        Term::ScaleMismatch => vec![
            (index(Term::ScaleMismatch), c2),
            (index(Term::ServoMismatch), s2 * test.radius / test.feed),
        ],
        _ => return None,
    })
}

/// The derivative in the angle lag ℓ of c_p·cos θ_a + c_q·sin θ_a at `shape`'s angle lag,
/// σ·(v/R)·(c_p·sin θ_a − c_q·cos θ_a), as a combination of static columns.
pub(super) fn angle_lag_derivative(
    centre: (Real, Real),
    shape: &Shape,
    test: &CircularTest,
) -> Vec<(usize, Real)> {
    let rate = test.feed / test.radius;
    let (s, c) = (rate * shape.angle_lag).sin_cos();
    let index = |t: Term| STATICS.iter().position(|x| *x == t).unwrap_or_default();
    let (cp, cq) = centre;
    // σ·sin θ_a = σ·sin θ·cos φ − cos θ·sin φ; σ·cos θ_a = σ·cos θ·cos φ + sin θ·sin φ.
    vec![
        (SIGMA_SIN, rate * cp * c),
        (index(Term::CentreP), -rate * cp * s),
        (SIGMA_COS, -rate * cq * c),
        (index(Term::CentreQ), -rate * cq * s),
    ]
}

/// Values made once when first needed, by key, shared between threads (the lock is held only
/// to find or make a key's cell; the value is made in the cell).
pub(super) type Cache<K, V> = Mutex<HashMap<K, Arc<OnceLock<V>>>>;

/// One axis's place of every reading relative to its reversals.
#[derive(Clone, Debug)]
pub(super) struct AxisRows {
    /// The arc (rad) from the nearest programmed reversal of the axis in the sense of travel,
    /// in [−π/2, π/2): negative before it, positive after it.
    pub(super) arc: Vec<Real>,
    /// The readings in increasing `arc`.
    pub(super) order: Vec<u32>,
    /// Their arcs, in that order.
    pub(super) sorted: Vec<Real>,
}

impl AxisRows {
    fn new(data: &CircleData, axis: usize) -> AxisRows {
        let unlagged = Shape::default();
        let arc: Vec<Real> = data
            .points
            .iter()
            .map(|p| {
                let since = arc_since_reversal(axis, p, &data.test, &unlagged);
                if since < FRAC_PI_2 { since } else { since - PI }
            })
            .collect();
        let mut order: Vec<u32> = (0..arc.len() as u32).collect();
        order.sort_by(|&a, &b| arc[a as usize].total_cmp(&arc[b as usize]));
        let sorted = order.iter().map(|&i| arc[i as usize]).collect();
        AxisRows { arc, order, sorted }
    }

    /// The readings whose arc lies in [`from`, `to`], in increasing arc.
    pub(super) fn within(&self, from: Real, to: Real) -> &[u32] {
        let start = self.sorted.partition_point(|&a| a < from);
        let end = self.sorted.partition_point(|&a| a <= to);
        &self.order[start..end.max(start)]
    }
}

/// A table's readings cut into blocks, with what fits of unions of blocks need from the data
/// alone: see the module documentation. Cloning it keeps the sums and starts its caches anew.
#[derive(Debug)]
pub struct Blocks {
    /// The number of blocks.
    pub(super) count: usize,
    /// The block of every reading.
    pub(super) block_of: Vec<u16>,
    /// Every reading's static columns and deviation, [`WIDTH`] values a reading.
    pub(super) table: Vec<Real>,
    /// Per block, the cross products of the table's columns (`WIDTH` × `WIDTH`, row-major).
    pub(super) sums: Vec<Real>,
    /// Per axis, the readings relative to the reversals.
    pub(super) axes: [AxisRows; 2],
    /// Per sense (ccw, cw), the readings' angles in increasing order with their blocks.
    angles: [Vec<(Real, u16)>; 2],
    /// The lobe columns' sums, when a lobe count has been searched.
    pub(super) lobes: OnceLock<LobeSums>,
    /// The transform over the angles that gives any column's products with every lobe count.
    pub(super) lobe_transform: OnceLock<LobeTransform>,
    /// The cyclic columns' Taylor moments about a grid frequency, per (axis, grid index).
    pub(super) centres: Cache<(usize, usize), CentreMoments>,
    /// The lobe columns' moments about a grid frequency of an axis's cyclic columns, per
    /// (axis, grid index, lobe count).
    pub(super) lobe_moments: Cache<(usize, usize, u32), LobeMoments>,
    /// Per axis, what the cyclic periodogram needs from the data alone.
    pub(super) spectra: [OnceLock<Spectrum>; 2],
}

impl Clone for Blocks {
    fn clone(&self) -> Blocks {
        Blocks {
            count: self.count,
            block_of: self.block_of.clone(),
            table: self.table.clone(),
            sums: self.sums.clone(),
            axes: self.axes.clone(),
            angles: self.angles.clone(),
            lobes: OnceLock::new(),
            lobe_transform: OnceLock::new(),
            centres: Mutex::new(HashMap::new()),
            lobe_moments: Mutex::new(HashMap::new()),
            spectra: [OnceLock::new(), OnceLock::new()],
        }
    }
}

impl Blocks {
    /// Cuts the readings of `data` into `count` blocks, `block_of[i]` the block of reading i
    /// (each below `count`).
    pub fn new(data: &CircleData, block_of: &[usize], count: usize) -> Blocks {
        assert_eq!(block_of.len(), data.len(), "a block for every reading");
        assert!(
            count <= usize::from(u16::MAX) && block_of.iter().all(|&b| b < count),
            "blocks below their count"
        );
        let n = data.len();
        let unlagged = Shape::default();
        let mut table = vec![0.0; n * WIDTH];
        for (i, point) in data.points.iter().enumerate() {
            let row = &mut table[i * WIDTH..(i + 1) * WIDTH];
            for (j, &term) in STATICS.iter().enumerate() {
                row[j] = diagnostic_column(term, 0, point, &data.test, &unlagged);
            }
            let (sin, cos) = point.sin_cos;
            row[SIGMA_SIN] = point.sense * sin;
            row[SIGMA_COS] = point.sense * cos;
            row[SIGMA_COS_2] = point.sense * data.test.radius / 2.0 * (cos * cos - sin * sin);
            row[Y] = data.deviation[i];
        }
        let mut sums = vec![0.0; count * WIDTH * WIDTH];
        for i in 0..n {
            let row = &table[i * WIDTH..(i + 1) * WIDTH];
            let block = &mut sums[block_of[i] * WIDTH * WIDTH..(block_of[i] + 1) * WIDTH * WIDTH];
            for a in 0..WIDTH {
                let va = row[a];
                for b in a..WIDTH {
                    block[a * WIDTH + b] += va * row[b];
                }
            }
        }
        for block in sums.chunks_mut(WIDTH * WIDTH) {
            for a in 0..WIDTH {
                for b in 0..a {
                    block[a * WIDTH + b] = block[b * WIDTH + a];
                }
            }
        }
        let mut angles: [Vec<(Real, u16)>; 2] = [Vec::new(), Vec::new()];
        for (i, point) in data.points.iter().enumerate() {
            angles[usize::from(point.sense < 0.0)].push((point.angle, block_of[i] as u16));
        }
        for list in &mut angles {
            list.sort_by(|a, b| a.0.total_cmp(&b.0));
        }
        Blocks {
            count,
            block_of: block_of.iter().map(|&b| b as u16).collect(),
            table,
            sums,
            axes: [AxisRows::new(data, 0), AxisRows::new(data, 1)],
            angles,
            lobes: OnceLock::new(),
            lobe_transform: OnceLock::new(),
            centres: Mutex::new(HashMap::new()),
            lobe_moments: Mutex::new(HashMap::new()),
            spectra: [OnceLock::new(), OnceLock::new()],
        }
    }

    /// One block of the readings where `train` is true and one of the others.
    pub fn training(data: &CircleData, train: &[bool]) -> Blocks {
        let block_of: Vec<usize> = train.iter().map(|&t| usize::from(!t)).collect();
        Blocks::new(data, &block_of, 2)
    }

    /// The blocks whose readings are exactly those where `train` is true, if `train` takes
    /// whole blocks.
    pub fn included(&self, train: &[bool]) -> Option<Vec<bool>> {
        if train.len() != self.block_of.len() {
            return None;
        }
        let mut state: Vec<Option<bool>> = vec![None; self.count];
        for (&b, &t) in self.block_of.iter().zip(train) {
            match state[usize::from(b)] {
                None => state[usize::from(b)] = Some(t),
                Some(s) if s != t => return None,
                _ => {}
            }
        }
        Some(state.into_iter().map(|s| s.unwrap_or(false)).collect())
    }

    /// Reading `i`'s static columns and deviation.
    pub(super) fn row(&self, i: usize) -> &[Real] {
        &self.table[i * WIDTH..(i + 1) * WIDTH]
    }

    /// The largest gap (rad) between the angles of a sense among the `included` blocks'
    /// readings, the wrap at 360° included; 2π without readings (see
    /// [`super::covered_arc`]: the covered span is 2π less this gap).
    pub(super) fn largest_gap(&self, sense: usize, included: &[bool]) -> Real {
        let mut angles = self.angles[sense]
            .iter()
            .filter(|(_, b)| included[usize::from(*b)])
            .map(|(a, _)| *a);
        let Some(first) = angles.next() else {
            return std::f64::consts::TAU;
        };
        let (mut last, mut largest) = (first, 0.0);
        for angle in angles {
            largest = Real::max(largest, angle - last);
            last = angle;
        }
        Real::max(largest, first + std::f64::consts::TAU - last)
    }
}

//! The readings cut into blocks for fast fits of any union of blocks ([`Blocks`]): the angular
//! sectors of cross-validation, where nine fits (all data, then each sector held out) share
//! what depends on the data alone, or one block of training rows for a single fit.
//!
//! What depends on the data alone is computed once: the static columns (those that do not
//! depend on the searched shape) and the deviation at every reading, their cross products
//! summed per block, and per axis the readings ordered by their arc from the nearest
//! programmed reversal, where the reversal terms change with the searched lag, play and decay
//! (`reversal.rs`). Sums over other columns at chosen shapes (lobes, cyclic terms) are made
//! here too when first needed, and kept (their kinds in `moments.rs`, read in `spectral.rs`).
use super::moments::{
    CentreMoments, DOUBLE_ORDER, LOBE_WIDTH, LobeMoments, LobeSums, LobeTransform, ORDER, Spectrum,
};
use super::statics::{SIGMA_COS, SIGMA_COS_2, SIGMA_SIN, STATICS, WIDTH, Y};
use super::{CircleData, Shape, arc_since_reversal, diagnostic_column};
use crate::discovery::nufft::Nufft;
use crate::math::Real;
use rustfft::num_complex::Complex;
use std::collections::HashMap;
use std::f64::consts::{FRAC_PI_2, PI, TAU};
use std::sync::{Arc, Mutex, OnceLock};

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

    /// Whether reading `i` is in the `included` blocks.
    pub(super) fn fitted(&self, included: &[bool], i: usize) -> bool {
        included[usize::from(self.block_of[i])]
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

/// The sums over other columns, made per block when a fit first needs them.
impl Blocks {
    /// The moments of `axis`'s cyclic columns about grid frequency `frequency` (1/m), per
    /// block.
    pub(super) fn centre_moments(
        &self,
        data: &CircleData,
        axis: usize,
        frequency: Real,
    ) -> CentreMoments {
        let mut linear = vec![vec![Complex::new(0.0, 0.0); WIDTH * ORDER]; self.count];
        let mut double = vec![vec![Complex::new(0.0, 0.0); DOUBLE_ORDER]; self.count];
        let mut squares = vec![0.0; self.count];
        let mut powers = [Complex::new(0.0, 0.0); DOUBLE_ORDER];
        let mut phasors = Vec::with_capacity(data.len());
        for i in 0..data.len() {
            let b = usize::from(self.block_of[i]);
            let c = data.cyclic_c(axis, i);
            let phase = TAU * frequency * data.test.radius * c;
            let (s, k) = phase.sin_cos();
            let mut term = Complex::new(c * k, c * s);
            phasors.push(term);
            for power in powers.iter_mut().take(ORDER) {
                *power = term;
                term *= c;
            }
            let row = self.row(i);
            let sums = &mut linear[b];
            for (j, &w) in row.iter().enumerate() {
                for (sum, power) in sums[j * ORDER..(j + 1) * ORDER].iter_mut().zip(&powers) {
                    *sum += power * w;
                }
            }
            let (s2, k2) = (2.0 * phase).sin_cos();
            let mut term = Complex::new(c * c * k2, c * c * s2);
            for sum in double[b].iter_mut() {
                *sum += term;
                term *= c;
            }
            squares[b] += c * c;
        }
        CentreMoments {
            linear,
            double,
            squares,
            phasors,
        }
    }

    /// The lobe columns' sums per block, for every lobe count searched.
    pub(super) fn lobe_sums(&self, data: &CircleData) -> LobeSums {
        let (low, high) = data.ranges.lobes;
        let counts = (high + 1).saturating_sub(low) as usize;
        let mut sums = vec![vec![0.0; counts * LOBE_WIDTH]; self.count];
        for (i, point) in data.points.iter().enumerate() {
            let block = &mut sums[usize::from(self.block_of[i])];
            let row = self.row(i);
            let (ds, dc) = point.sin_cos;
            let (mut s, mut c) = (Real::from(low) * point.angle).sin_cos();
            for k in 0..counts {
                let out = &mut block[k * LOBE_WIDTH..(k + 1) * LOBE_WIDTH];
                for (j, &w) in row.iter().enumerate() {
                    out[j] += s * w;
                    out[WIDTH + j] += c * w;
                }
                out[2 * WIDTH] += s * s;
                out[2 * WIDTH + 1] += c * c;
                out[2 * WIDTH + 2] += s * c;
                (s, c) = (s * dc + c * ds, c * dc - s * ds);
            }
        }
        LobeSums { low, high, sums }
    }

    /// The moments of the lobe columns of count `k` about grid frequency `frequency` (1/m) of
    /// `axis`'s cyclic columns, per block.
    pub(super) fn lobe_moments_about(
        &self,
        data: &CircleData,
        axis: usize,
        frequency: Real,
        k: u32,
    ) -> LobeMoments {
        let mut sums = vec![[[Complex::new(0.0, 0.0); ORDER]; 2]; self.count];
        for (i, point) in data.points.iter().enumerate() {
            let c = data.cyclic_c(axis, i);
            let (s, k_) = (TAU * frequency * data.test.radius * c).sin_cos();
            let lobe = (Real::from(k) * point.angle).sin_cos();
            let block = &mut sums[usize::from(self.block_of[i])];
            let mut term = Complex::new(c * k_, c * s);
            let [with_sin, with_cos] = block;
            for (a, b) in with_sin.iter_mut().zip(with_cos.iter_mut()) {
                *a += term * lobe.0;
                *b += term * lobe.1;
                term *= c;
            }
        }
        LobeMoments { blocks: sums }
    }

    /// What the periodogram of `axis`'s cyclic columns needs from the data alone.
    pub(super) fn spectrum(&self, data: &CircleData, axis: usize) -> Spectrum {
        let grid = data.frequency_grid();
        let radius = data.test.radius;
        let c: Vec<Real> = (0..data.len()).map(|i| data.cyclic_c(axis, i)).collect();
        let positions: Vec<Real> = c.iter().map(|c| TAU * grid.step * radius * c).collect();
        let nufft = Nufft::new(&positions, grid.count);
        let factor = c
            .iter()
            .map(|&c| {
                let (s, k) = (TAU * grid.low * radius * c).sin_cos();
                Complex::new(c * k, c * s)
            })
            .collect();
        let doubled: Vec<Real> = positions.iter().map(|u| 2.0 * u).collect();
        let twice = Nufft::new(&doubled, grid.count);
        let mut double = Vec::with_capacity(self.count);
        let mut squares = vec![0.0; self.count];
        for (b, square) in squares.iter_mut().enumerate() {
            let members = (0..data.len()).filter(|&i| usize::from(self.block_of[i]) == b);
            double.push(twice.transform(members.map(|i| {
                let (s, k) = (2.0 * TAU * grid.low * radius * c[i]).sin_cos();
                (i, Complex::new(c[i] * c[i] * k, c[i] * c[i] * s))
            })));
            *square = (0..data.len())
                .filter(|&i| usize::from(self.block_of[i]) == b)
                .map(|i| c[i] * c[i])
                .sum();
        }
        Spectrum {
            nufft,
            factor,
            double,
            squares,
            tables: OnceLock::new(),
        }
    }

    /// The blocks' transforms of every table column for `spectrum` (see [`Spectrum::tables`]).
    pub(super) fn table_transforms(
        &self,
        data: &CircleData,
        spectrum: &Spectrum,
    ) -> Vec<Vec<Vec<Complex<Real>>>> {
        let mut members: Vec<Vec<usize>> = vec![Vec::new(); self.count];
        for i in 0..data.len() {
            members[usize::from(self.block_of[i])].push(i);
        }
        members
            .iter()
            .map(|rows| {
                (0..WIDTH)
                    .map(|j| {
                        spectrum.nufft.transform(
                            rows.iter()
                                .map(|&i| (i, spectrum.factor[i] * self.row(i)[j])),
                        )
                    })
                    .collect()
            })
            .collect()
    }
}

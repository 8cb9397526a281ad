//! Cross products of the cyclic and lobe columns without evaluating them reading by reading
//! in every fit.
//!
//! - **Cyclic columns near a grid frequency.** With c = cos θ (p) or sin θ (q), x = R·c, a
//!   cyclic column at frequency f = f_c + Δ is c·e^(2πi·f·x) = c·e^(2πi·f_c·x)·Σ_p (2πi·R·Δ)^p
//!   c^p/p! (real part: the cos column, imaginary: the sin column). Its cross product with any
//!   column w is therefore Σ_p (2πi·R·Δ)^p/p!·M_p, M_p = Σ w·c^(p+1)·e^(2πi·f_c·x): moments
//!   about the grid frequency f_c taken once per block for the static columns and the
//!   deviation ([`CentreMoments`]), after which a trial frequency within two grid steps of
//!   f_c costs [`ORDER`] terms per column. Within two steps |2π·R·Δ| ≤ π/2 (the step is
//!   1/(8R)) and the series is cut where its terms are below 2·10⁻¹⁷ of the moments; the
//!   columns' own products (cos², sin², sin·cos: half of 1 ± the doubled phase) use the
//!   doubled phase's moments, to [`DOUBLE_ORDER`] terms.
//! - **The periodogram** over the whole frequency grid is a non-uniform discrete Fourier
//!   transform of r·c·e^(2πi·f_low·x) at the positions 2π·step·x ([`Nufft`], Gaussian
//!   gridding after Greengard & Lee, SIAM Review 46 (2004) 443–454: the strengths spread on an
//!   oversampled regular grid with a Gaussian, a fast Fourier transform, then the Gaussian's
//!   transform divided out), relative error below 10⁻¹¹ of Σ|r·c|.
//! - **Lobe columns** sin kθ, cos kθ: their cross products with the static columns and the
//!   deviation for every lobe count, per block ([`LobeSums`]).

use super::blocks::{Blocks, WIDTH};
use super::normal::{Column, Dense, Fitter, SeriesPair};
use super::{CircleData, Term};
use crate::math::Real;
use rustfft::num_complex::Complex;
use rustfft::{Fft, FftPlanner};
use std::f64::consts::{PI, TAU};
use std::rc::Rc;
use std::sync::{Arc, OnceLock};

/// Terms of the moment series of a cyclic column (valid within two grid steps).
pub(super) const ORDER: usize = 22;
/// Terms of the doubled phase's series.
pub(super) const DOUBLE_ORDER: usize = 30;
/// Grid points on each side of a position the Gaussian is spread over.
const SPREAD: usize = 14;

/// The cyclic search's frequencies (1/m): lowest, step and how many (see
/// [`CircleData::significance`]).
#[derive(Clone, Copy, Debug)]
pub(super) struct FrequencyGrid {
    pub(super) low: Real,
    pub(super) high: Real,
    pub(super) step: Real,
    pub(super) count: usize,
}

impl CircleData {
    /// The cyclic search's frequency grid: from 1/(longest period) to 1/(shortest) in steps
    /// of 1/(8R), 4 per 1/(2R), the resolution over the diameter.
    pub(super) fn frequency_grid(&self) -> FrequencyGrid {
        let (low, high) = self.ranges.period;
        let (f_low, f_high) = (1.0 / high, 1.0 / low);
        let step = 1.0 / (8.0 * self.test.radius);
        let count = ((f_high - f_low) / step * (1.0 + 1e-12)).floor().max(0.0) as usize + 1;
        FrequencyGrid {
            low: f_low,
            high: f_high,
            step,
            count,
        }
    }

    /// The cyclic column's c (cos θ for p, sin θ for q) at reading `i`.
    pub(super) fn cyclic_c(&self, axis: usize, i: usize) -> Real {
        let (sin, cos) = self.points[i].sin_cos;
        if axis == 0 { cos } else { sin }
    }
}

/// The Taylor coefficients (i·a)^p/p! for p below `order`.
fn series(a: Real, order: usize) -> Vec<Complex<Real>> {
    let mut out = Vec::with_capacity(order);
    let mut term = Complex::new(1.0, 0.0);
    for p in 0..order {
        out.push(term);
        term = term * Complex::new(0.0, a) / (p + 1) as Real;
    }
    out
}

/// The moments of the cyclic columns of an axis about a grid frequency f_c, per block.
#[derive(Debug)]
pub(super) struct CentreMoments {
    /// Per block, for every table column w (statics, then the deviation): Σ w·c^(p+1)·
    /// e^(2πi·f_c·x), p below [`ORDER`] (`WIDTH` × `ORDER`).
    linear: Vec<Vec<Complex<Real>>>,
    /// Per block: Σ c^(2+p)·e^(4πi·f_c·x), p below [`DOUBLE_ORDER`].
    double: Vec<Vec<Complex<Real>>>,
    /// Per block: Σ c².
    squares: Vec<Real>,
    /// Per reading: c·e^(2πi·f_c·x).
    phasors: Vec<Complex<Real>>,
}

impl CentreMoments {
    fn new(data: &CircleData, blocks: &Blocks, axis: usize, frequency: Real) -> CentreMoments {
        let mut linear = vec![vec![Complex::new(0.0, 0.0); WIDTH * ORDER]; blocks.count];
        let mut double = vec![vec![Complex::new(0.0, 0.0); DOUBLE_ORDER]; blocks.count];
        let mut squares = vec![0.0; blocks.count];
        let mut powers = [Complex::new(0.0, 0.0); DOUBLE_ORDER];
        let mut phasors = Vec::with_capacity(data.len());
        for i in 0..data.len() {
            let b = usize::from(blocks.block_of[i]);
            let c = data.cyclic_c(axis, i);
            let phase = TAU * frequency * data.test.radius * c;
            let (s, k) = phase.sin_cos();
            let mut term = Complex::new(c * k, c * s);
            phasors.push(term);
            for power in powers.iter_mut().take(ORDER) {
                *power = term;
                term *= c;
            }
            let row = blocks.row(i);
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
}

/// [`CentreMoments`] summed over a fit's blocks.
#[derive(Debug)]
pub(super) struct CombinedMoments {
    /// The grid frequency (1/m).
    pub(super) frequency: Real,
    /// The moments of every block, and the readings' phasors.
    all: Arc<OnceLock<CentreMoments>>,
    linear: Vec<Complex<Real>>,
    double: Vec<Complex<Real>>,
    squares: Real,
}

impl CombinedMoments {
    /// The cross products of table column `j` with the sin and cos columns at
    /// `frequency`, from the Taylor coefficients `series` of its offset.
    pub(super) fn with_table(&self, j: usize, series: &[Complex<Real>]) -> (Real, Real) {
        let sum: Complex<Real> = self.linear[j * ORDER..(j + 1) * ORDER]
            .iter()
            .zip(series)
            .map(|(m, e)| m * e)
            .sum();
        (sum.im, sum.re)
    }

    /// The sin and cos columns' products at an offset whose doubled phase has Taylor
    /// coefficients `series`: (sin², cos², sin·cos).
    pub(super) fn own(&self, series: &[Complex<Real>]) -> (Real, Real, Real) {
        let sum: Complex<Real> = self.double.iter().zip(series).map(|(m, e)| m * e).sum();
        (
            (self.squares - sum.re) / 2.0,
            (self.squares + sum.re) / 2.0,
            sum.im / 2.0,
        )
    }
}

/// The offset series of a trial frequency from a grid frequency: for the cyclic columns
/// ([`ORDER`] terms) and for their products ([`DOUBLE_ORDER`] terms of the doubled phase).
pub(super) fn offset_series(
    radius: Real,
    offset: Real,
) -> (Vec<Complex<Real>>, Vec<Complex<Real>>) {
    let a = TAU * radius * offset;
    (series(a, ORDER), series(2.0 * a, DOUBLE_ORDER))
}

/// Per block, the lobe columns' cross products with the table's columns for every lobe count
/// searched, and their own products.
#[derive(Debug)]
pub(super) struct LobeSums {
    low: u32,
    high: u32,
    /// Per block, per count from `low`: Σ sin kθ·w and Σ cos kθ·w for every table column w,
    /// then Σ sin², Σ cos², Σ sin·cos.
    sums: Vec<Vec<Real>>,
}

/// Values per lobe count in [`LobeSums`].
const LOBE_WIDTH: usize = 2 * WIDTH + 3;

impl LobeSums {
    fn new(data: &CircleData, blocks: &Blocks) -> LobeSums {
        let (low, high) = data.ranges.lobes;
        let counts = (high + 1).saturating_sub(low) as usize;
        let mut sums = vec![vec![0.0; counts * LOBE_WIDTH]; blocks.count];
        for (i, point) in data.points.iter().enumerate() {
            let block = &mut sums[usize::from(blocks.block_of[i])];
            let row = blocks.row(i);
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
}

/// The products of a column with sin kθ and cos kθ for every lobe count searched, as one
/// non-uniform Fourier transform over the angles: Σ v·e^(ikθ) = Σ (v·e^(i·k_low·θ))·e^(imθ),
/// m = k − k_low.
#[derive(Debug)]
pub(super) struct LobeTransform {
    nufft: Nufft,
    /// Per reading, e^(i·k_low·θ).
    factor: Vec<Complex<Real>>,
}

impl LobeTransform {
    fn new(data: &CircleData) -> LobeTransform {
        let (low, high) = data.ranges.lobes;
        let positions: Vec<Real> = data
            .points
            .iter()
            .map(|p| {
                if p.angle >= PI {
                    p.angle - TAU
                } else {
                    p.angle
                }
            })
            .collect();
        LobeTransform {
            nufft: Nufft::new(&positions, (high + 1).saturating_sub(low) as usize),
            factor: data
                .points
                .iter()
                .map(|p| {
                    let (s, c) = (Real::from(low) * p.angle).sin_cos();
                    Complex::new(c, s)
                })
                .collect(),
        }
    }
}

/// The moments of the lobe columns of one count about a grid frequency of an axis's cyclic
/// columns, per block: Σ sin kθ·c^(p+1)·e^(2πi·f_c·x) and the same with cos kθ.
#[derive(Debug)]
pub(super) struct LobeMoments {
    blocks: Vec<[[Complex<Real>; ORDER]; 2]>,
}

impl LobeMoments {
    fn new(
        data: &CircleData,
        blocks: &Blocks,
        axis: usize,
        frequency: Real,
        k: u32,
    ) -> LobeMoments {
        let mut sums = vec![[[Complex::new(0.0, 0.0); ORDER]; 2]; blocks.count];
        for (i, point) in data.points.iter().enumerate() {
            let c = data.cyclic_c(axis, i);
            let (s, k_) = (TAU * frequency * data.test.radius * c).sin_cos();
            let lobe = (Real::from(k) * point.angle).sin_cos();
            let block = &mut sums[usize::from(blocks.block_of[i])];
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
}

/// [`LobeSums`] summed over a fit's blocks.
#[derive(Debug)]
pub(super) struct CombinedLobes {
    low: u32,
    high: u32,
    sums: Vec<Real>,
}

impl CombinedLobes {
    /// The sums of lobe count `k`, if it is in the searched range.
    fn of(&self, k: u32) -> Option<&[Real]> {
        (self.low..=self.high).contains(&k).then(|| {
            let k = (k - self.low) as usize;
            &self.sums[k * LOBE_WIDTH..(k + 1) * LOBE_WIDTH]
        })
    }
}

impl<'a> Fitter<'a> {
    /// The lobe sums over the fitted blocks.
    fn combined_lobes(&self) -> &CombinedLobes {
        self.lobes.get_or_init(|| {
            let all = self
                .blocks
                .lobes
                .get_or_init(|| LobeSums::new(self.data, self.blocks));
            let mut sums = vec![0.0; all.sums.first().map_or(0, Vec::len)];
            for (b, block) in all.sums.iter().enumerate() {
                if self.included[b] {
                    for (s, v) in sums.iter_mut().zip(block) {
                        *s += v;
                    }
                }
            }
            CombinedLobes {
                low: all.low,
                high: all.high,
                sums,
            }
        })
    }

    /// Σ over the fitted readings of lobe column (`k`, `index`) times table column `j`.
    pub(super) fn lobe_with(&self, k: u32, index: usize, j: usize) -> Option<Real> {
        let sums = self.combined_lobes().of(k)?;
        Some(sums[index * WIDTH + j])
    }

    /// Σ over the fitted readings of two lobe columns of count `k`.
    pub(super) fn lobe_self(&self, k: u32, a: usize, b: usize) -> Option<Real> {
        let sums = self.combined_lobes().of(k)?;
        Some(match (a, b) {
            (0, 0) => sums[2 * WIDTH],
            (1, 1) => sums[2 * WIDTH + 1],
            _ => sums[2 * WIDTH + 2],
        })
    }

    /// Σ over the fitted readings of `values` (at every reading) times sin kθ and cos kθ,
    /// for every lobe count k of the searched range: (sin, cos) per count from the lowest.
    pub(super) fn lobe_products(&self, values: &[Real]) -> Vec<(Real, Real)> {
        let transform = self
            .blocks
            .lobe_transform
            .get_or_init(|| LobeTransform::new(self.data));
        transform
            .nufft
            .transform(
                self.rows
                    .iter()
                    .map(|&i| (i, transform.factor[i] * values[i])),
            )
            .into_iter()
            .map(|z| (z.im, z.re))
            .collect()
    }

    /// The grid index nearest to `frequency` when it is within two grid steps of it.
    pub(super) fn centre_of(&self, frequency: Real) -> Option<usize> {
        let grid = self.data.frequency_grid();
        let k = ((frequency - grid.low) / grid.step)
            .round()
            .clamp(0.0, (grid.count.max(1) - 1) as Real) as usize;
        let centre = grid.low + grid.step * k as Real;
        ((frequency - centre).abs() <= 2.0 * grid.step).then_some(k)
    }

    /// The moments of `axis`'s cyclic columns about grid frequency `k`, over the fitted
    /// blocks (computed for every block once and kept in the [`Blocks`]).
    pub(super) fn combined(&self, axis: usize, k: usize) -> Rc<CombinedMoments> {
        if let Some(found) = self.centres.borrow().get(&(axis, k)) {
            return found.clone();
        }
        let grid = self.data.frequency_grid();
        let frequency = grid.low + grid.step * k as Real;
        let cell = self
            .blocks
            .centres
            .lock()
            .unwrap_or_else(|e| e.into_inner())
            .entry((axis, k))
            .or_insert_with(|| Arc::new(OnceLock::new()))
            .clone();
        let moments =
            cell.get_or_init(|| CentreMoments::new(self.data, self.blocks, axis, frequency));
        let mut linear = vec![Complex::new(0.0, 0.0); WIDTH * ORDER];
        let mut double = vec![Complex::new(0.0, 0.0); DOUBLE_ORDER];
        let mut squares = 0.0;
        for b in 0..self.blocks.count {
            if self.included[b] {
                for (s, v) in linear.iter_mut().zip(&moments.linear[b]) {
                    *s += v;
                }
                for (s, v) in double.iter_mut().zip(&moments.double[b]) {
                    *s += v;
                }
                squares += moments.squares[b];
            }
        }
        let combined = Rc::new(CombinedMoments {
            frequency,
            all: cell.clone(),
            linear,
            double,
            squares,
        });
        self.centres
            .borrow_mut()
            .insert((axis, k), combined.clone());
        combined
    }

    /// Σ over the fitted readings of a cyclic column times table column `j`, by its
    /// moments about the nearest grid frequency.
    pub(super) fn cyclic_with(&self, cyclic: &Dense, j: usize) -> Option<Real> {
        let Dense::Cyclic {
            axis,
            period,
            index,
        } = cyclic
        else {
            return None;
        };
        let frequency = 1.0 / period;
        let k = self.centre_of(frequency)?;
        let moments = self.combined(*axis, k);
        let series = self.series_at(frequency - moments.frequency);
        let (sin, cos) = moments.with_table(j, &series.0);
        Some(if *index == 0 { sin } else { cos })
    }

    /// [`offset_series`] at `offset`, the last one kept.
    fn series_at(&self, offset: Real) -> SeriesPair {
        let mut last = self.last_series.borrow_mut();
        match &*last {
            Some((known, series)) if known.to_bits() == offset.to_bits() => series.clone(),
            _ => {
                let series = Rc::new(offset_series(self.data.test.radius, offset));
                *last = Some((offset, series.clone()));
                series
            }
        }
    }

    /// `axis`'s cyclic columns at `period` at every reading, (c·sin, c·cos) of the phase, from
    /// the phasors c·e^(2πi·f_c·x) at the nearest grid frequency times e^(2πi·R·Δ·c), Δ the
    /// offset: |2π·R·Δ·c| ≤ π/8 within half a grid step, where the rotation's Taylor series
    /// is cut after its 14th power (remainder below 10⁻¹⁸). None off the grid.
    pub(super) fn cyclic_near_centre(
        &self,
        axis: usize,
        period: Real,
    ) -> Option<Vec<(Real, Real)>> {
        let frequency = 1.0 / period;
        let k = self.centre_of(frequency)?;
        let moments = self.combined(axis, k);
        let offset = frequency - moments.frequency;
        let grid = self.data.frequency_grid();
        if offset.abs() > 0.5 * grid.step * (1.0 + 1e-9) {
            return None;
        }
        let phasors = &moments.all.get()?.phasors;
        let scale = TAU * self.data.test.radius * offset;
        Some(
            phasors
                .iter()
                .enumerate()
                .map(|(i, p)| {
                    let a = scale * self.data.cyclic_c(axis, i);
                    let a2 = a * a;
                    let cos = 1.0
                        + a2 * (-1.0 / 2.0
                            + a2 * (1.0 / 24.0
                                + a2 * (-1.0 / 720.0
                                    + a2 * (1.0 / 40320.0
                                        + a2 * (-1.0 / 3628800.0
                                            + a2 * (1.0 / 479001600.0
                                                + a2 * (-1.0 / 87178291200.0)))))));
                    let sin = a
                        * (1.0
                            + a2 * (-1.0 / 6.0
                                + a2 * (1.0 / 120.0
                                    + a2 * (-1.0 / 5040.0
                                        + a2 * (1.0 / 362880.0
                                            + a2 * (-1.0 / 39916800.0
                                                + a2 * (1.0 / 6227020800.0)))))));
                    (p.re * sin + p.im * cos, p.re * cos - p.im * sin)
                })
                .collect(),
        )
    }

    /// The moments about grid frequency `centre` of `axis`'s cyclic columns of lobe column
    /// (`k`, `index`) over the fitted readings.
    pub(super) fn lobe_moments(
        &self,
        axis: usize,
        centre: usize,
        k: u32,
        index: usize,
    ) -> Vec<Complex<Real>> {
        let grid = self.data.frequency_grid();
        let at = grid.low + grid.step * centre as Real;
        let cell = self
            .blocks
            .lobe_moments
            .lock()
            .unwrap_or_else(|e| e.into_inner())
            .entry((axis, centre, k))
            .or_insert_with(|| Arc::new(OnceLock::new()))
            .clone();
        let moments = cell.get_or_init(|| LobeMoments::new(self.data, self.blocks, axis, at, k));
        let mut sums = vec![Complex::new(0.0, 0.0); ORDER];
        for (b, block) in moments.blocks.iter().enumerate() {
            if self.included[b] {
                for (s, m) in sums.iter_mut().zip(&block[index]) {
                    *s += m;
                }
            }
        }
        sums
    }

    /// Σ over the fitted readings of a cyclic column times a lobe column, by the lobe
    /// column's moments about the cyclic column's nearest grid frequency.
    pub(super) fn cyclic_lobe(&self, cyclic: &Dense, lobe: &Dense) -> Option<Real> {
        let (
            Dense::Cyclic {
                axis,
                period,
                index,
            },
            Dense::Lobe { k, index: which },
        ) = (cyclic, lobe)
        else {
            return None;
        };
        let frequency = 1.0 / period;
        let centre = self.centre_of(frequency)?;
        let grid = self.data.frequency_grid();
        let at = grid.low + grid.step * centre as Real;
        let moments = self.lobe_moments(*axis, centre, *k, *which);
        let series = self.series_at(frequency - at);
        let sum: Complex<Real> = moments.iter().zip(&series.0).map(|(m, e)| m * e).sum();
        Some(if *index == 0 { sum.im } else { sum.re })
    }

    /// Σ over the fitted readings of two cyclic columns of the same axis and period.
    pub(super) fn cyclic_self(&self, a: &Dense, b: &Dense) -> Option<Real> {
        let (
            Dense::Cyclic {
                axis,
                period,
                index: i,
            },
            Dense::Cyclic {
                axis: other,
                period: p,
                index: j,
            },
        ) = (a, b)
        else {
            return None;
        };
        if axis != other || period.to_bits() != p.to_bits() {
            return None;
        }
        let frequency = 1.0 / period;
        let k = self.centre_of(frequency)?;
        let moments = self.combined(*axis, k);
        let series = self.series_at(frequency - moments.frequency);
        let (ss, cc, sc) = moments.own(&series.1);
        Some(match (i, j) {
            (0, 0) => ss,
            (1, 1) => cc,
            _ => sc,
        })
    }

    /// The moments Σ v·c^(p+1)·e^(2πi·f_c·x) over the fitted readings of `values` (reading,
    /// value), about `moments`' grid frequency of `axis`'s cyclic columns.
    pub(super) fn moments_of(
        &self,
        axis: usize,
        moments: &CombinedMoments,
        values: impl Iterator<Item = (usize, Real)>,
    ) -> Vec<Complex<Real>> {
        let phasors = &moments
            .all
            .get()
            .expect("combined moments are made from computed ones")
            .phasors;
        let mut sums = vec![Complex::new(0.0, 0.0); ORDER];
        for (i, v) in values {
            if v == 0.0 || !self.fitted(i) {
                continue;
            }
            let c = self.data.cyclic_c(axis, i);
            let mut term = phasors[i] * v;
            for sum in sums.iter_mut() {
                *sum += term;
                term *= c;
            }
        }
        sums
    }

    /// The period (m) of `axis`'s cyclic columns whose two columns alone remove the largest
    /// fraction of `residual` (given at every reading, read over the fitted ones), and that
    /// fraction: [`CircleData::cyclic_periodogram`] by a non-uniform Fourier transform.
    pub(super) fn periodogram(&self, axis: usize, residual: &[Real]) -> (Real, Real) {
        let spectrum = self.spectrum(axis);
        let transform = spectrum.nufft.transform(
            self.rows
                .iter()
                .map(|&i| (i, spectrum.factor[i] * residual[i])),
        );
        let total: Real = self.rows.iter().map(|&i| residual[i] * residual[i]).sum();
        self.peak(spectrum, &transform, total)
    }

    /// [`Fitter::periodogram`] of the residual of the fit of `columns` with `coefficients`
    /// (residual sum of squares `rss`): the transform of the deviation less the static
    /// columns' share, from the blocks' transforms of the table's columns, and of the rest
    /// (sparse changes, cyclic and lobe columns) reading by reading.
    pub(super) fn fit_periodogram(
        &self,
        axis: usize,
        columns: &[Column],
        coefficients: &[Real],
        rss: Real,
    ) -> (Real, Real) {
        let spectrum = self.spectrum(axis);
        let mut weights = [0.0; WIDTH];
        weights[super::blocks::Y] = 1.0;
        let mut rest = vec![0.0; self.data.len()];
        let mut dense = false;
        for (column, &c) in columns.iter().zip(coefficients) {
            match column.dense.statics() {
                Some(mix) => {
                    for (j, w) in mix {
                        weights[j] -= c * w;
                    }
                }
                None => {
                    dense = true;
                    let values = self.dense_values(&column.dense);
                    for &i in &self.rows {
                        rest[i] -= c * values[i];
                    }
                }
            }
            for (&i, v) in column.sparse.rows.iter().zip(&column.sparse.values) {
                rest[i as usize] -= c * v;
            }
        }
        let mut transform = if dense {
            spectrum
                .nufft
                .transform(self.rows.iter().map(|&i| (i, spectrum.factor[i] * rest[i])))
        } else {
            let touched: Vec<usize> = columns
                .iter()
                .flat_map(|c| c.sparse.rows.iter().map(|&i| i as usize))
                .filter(|&i| self.fitted(i))
                .collect::<std::collections::BTreeSet<usize>>()
                .into_iter()
                .collect();
            spectrum
                .nufft
                .transform(touched.iter().map(|&i| (i, spectrum.factor[i] * rest[i])))
        };
        let tables = spectrum
            .tables
            .get_or_init(|| spectrum.table_transforms(self.data, self.blocks));
        for (b, block) in tables.iter().enumerate() {
            if !self.included[b] {
                continue;
            }
            for (j, &w) in weights.iter().enumerate() {
                if w == 0.0 {
                    continue;
                }
                for (t, v) in transform.iter_mut().zip(&block[j]) {
                    *t += v * w;
                }
            }
        }
        self.peak(spectrum, &transform, rss)
    }

    /// What the periodogram needs of `axis`'s columns from the data alone.
    fn spectrum(&self, axis: usize) -> &'a Spectrum {
        self.blocks.spectra[axis].get_or_init(|| Spectrum::new(self.data, self.blocks, axis))
    }

    /// The periodogram's peak from the transform of r·c (`transform`, per grid frequency)
    /// and Σ r² (`total`) over the fitted readings.
    fn peak(&self, spectrum: &Spectrum, transform: &[Complex<Real>], total: Real) -> (Real, Real) {
        let grid = self.data.frequency_grid();
        let mut double = vec![Complex::new(0.0, 0.0); grid.count];
        let mut squares = 0.0;
        for b in 0..self.blocks.count {
            if self.included[b] {
                for (s, v) in double.iter_mut().zip(&spectrum.double[b]) {
                    *s += v;
                }
                squares += spectrum.squares[b];
            }
        }
        let mut best = (grid.low, 0.0);
        for k in 0..grid.count {
            let (s1, s2) = (transform[k].im, transform[k].re);
            let a11 = (squares - double[k].re) / 2.0;
            let a22 = (squares + double[k].re) / 2.0;
            let a12 = double[k].im / 2.0;
            let det = a11 * a22 - a12 * a12;
            if det > 0.0 && total > 0.0 {
                let reduction = (s1 * s1 * a22 - 2.0 * s1 * s2 * a12 + s2 * s2 * a11) / det;
                let fraction = (reduction / total).clamp(0.0, 1.0);
                if fraction > best.1 {
                    best = (grid.low + grid.step * k as Real, fraction);
                }
            }
        }
        (1.0 / best.0, best.1)
    }
}

/// What the periodogram of an axis's cyclic columns needs from the data alone.
#[derive(Debug)]
pub(super) struct Spectrum {
    /// The transform at the positions 2π·step·x.
    nufft: Nufft,
    /// Per reading: c·e^(2πi·f_low·x).
    factor: Vec<Complex<Real>>,
    /// Per block, per grid frequency: Σ c²·e^(4πi·f·x).
    double: Vec<Vec<Complex<Real>>>,
    /// Per block: Σ c².
    squares: Vec<Real>,
    /// Per block, per table column, the transform of the column times c·e^(2πi·f_low·x),
    /// when a fit's periodogram has needed them.
    tables: OnceLock<Vec<Vec<Vec<Complex<Real>>>>>,
}

impl Spectrum {
    /// The blocks' transforms of every table column (see `tables`).
    fn table_transforms(&self, data: &CircleData, blocks: &Blocks) -> Vec<Vec<Vec<Complex<Real>>>> {
        let mut members: Vec<Vec<usize>> = vec![Vec::new(); blocks.count];
        for i in 0..data.len() {
            members[usize::from(blocks.block_of[i])].push(i);
        }
        members
            .iter()
            .map(|rows| {
                (0..WIDTH)
                    .map(|j| {
                        self.nufft
                            .transform(rows.iter().map(|&i| (i, self.factor[i] * blocks.row(i)[j])))
                    })
                    .collect()
            })
            .collect()
    }
    fn new(data: &CircleData, blocks: &Blocks, axis: usize) -> Spectrum {
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
        let mut double = Vec::with_capacity(blocks.count);
        let mut squares = vec![0.0; blocks.count];
        for (b, square) in squares.iter_mut().enumerate() {
            let members = (0..data.len()).filter(|&i| usize::from(blocks.block_of[i]) == b);
            double.push(twice.transform(members.map(|i| {
                let (s, k) = (2.0 * TAU * grid.low * radius * c[i]).sin_cos();
                (i, Complex::new(c[i] * c[i] * k, c[i] * c[i] * s))
            })));
            *square = (0..data.len())
                .filter(|&i| usize::from(blocks.block_of[i]) == b)
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
}

/// The non-uniform discrete Fourier transform F(m) = Σ_j a_j·e^(i·m·u_j), m = 0 … M − 1, at
/// fixed positions u_j in [−π, π), by Gaussian gridding.
pub(super) struct Nufft {
    modes: usize,
    /// The first grid point each position spreads to (2·[`SPREAD`] + 1 points on).
    first: Vec<usize>,
    /// The Gaussian's values there.
    weights: Vec<Real>,
    /// e^(i·m₀·u_j): the modes are centred on m₀ = M/2.
    shift: Vec<Complex<Real>>,
    /// Per mode: the Gaussian's transform divided out, and the grid's normalisation.
    deconvolution: Vec<Real>,
    /// The grid index of each mode.
    index: Vec<usize>,
    fft: Arc<dyn Fft<Real>>,
}

impl std::fmt::Debug for Nufft {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("Nufft")
            .field("modes", &self.modes)
            .field("grid", &self.fft.len())
            .finish()
    }
}

impl Nufft {
    /// The transform at `positions` (rad, in [−π, π)) for `modes` modes.
    pub(super) fn new(positions: &[Real], modes: usize) -> Nufft {
        let modes = modes.max(1);
        let grid = (2 * modes).next_power_of_two().max(64);
        let ratio = grid as Real / modes as Real;
        // Greengard & Lee's τ for spreading over SPREAD points each side at oversampling R.
        let tau = PI * SPREAD as Real / ((modes * modes) as Real * ratio * (ratio - 0.5));
        let h = TAU / grid as Real;
        let centre = (modes / 2) as i64;
        let width = 2 * SPREAD + 1;
        let mut first = Vec::with_capacity(positions.len());
        let mut weights = Vec::with_capacity(positions.len() * width);
        let mut shift = Vec::with_capacity(positions.len());
        for &u in positions {
            let nearest = (u / h).round() as i64;
            let start = nearest - SPREAD as i64;
            first.push(start.rem_euclid(grid as i64) as usize);
            for t in 0..width {
                let d = (start + t as i64) as Real * h - u;
                weights.push((-d * d / (4.0 * tau)).exp());
            }
            let (s, c) = (centre as Real * u).sin_cos();
            shift.push(Complex::new(c, s));
        }
        let scale = (PI / tau).sqrt() / grid as Real;
        let deconvolution = (0..modes)
            .map(|m| {
                let m = (m as i64 - centre) as Real;
                scale * (m * m * tau).exp()
            })
            .collect();
        let index = (0..modes)
            .map(|m| (m as i64 - centre).rem_euclid(grid as i64) as usize)
            .collect();
        Nufft {
            modes,
            first,
            weights,
            shift,
            deconvolution,
            index,
            fft: FftPlanner::new().plan_fft_inverse(grid),
        }
    }

    /// F(m) for the strengths `(j, a_j)` (positions not given have none).
    pub(super) fn transform(
        &self,
        strengths: impl Iterator<Item = (usize, Complex<Real>)>,
    ) -> Vec<Complex<Real>> {
        let grid = self.fft.len();
        let width = 2 * SPREAD + 1;
        let mut values = vec![Complex::new(0.0, 0.0); grid];
        for (j, a) in strengths {
            let a = a * self.shift[j];
            let start = self.first[j];
            let weights = &self.weights[j * width..(j + 1) * width];
            if start + width <= grid {
                for (v, w) in values[start..start + width].iter_mut().zip(weights) {
                    *v += a * w;
                }
            } else {
                for (t, w) in weights.iter().enumerate() {
                    values[(start + t) % grid] += a * w;
                }
            }
        }
        self.fft.process(&mut values);
        (0..self.modes)
            .map(|m| values[self.index[m]] * self.deconvolution[m])
            .collect()
    }
}

impl Blocks {
    /// [`CircleData::cyclic_periodogram`] of `residual` (given at every reading) over every
    /// reading of `data` (these blocks' data), by the non-uniform Fourier transform the fits
    /// use: the same peak to the transform's accuracy, without the grid's M passes over the
    /// readings.
    pub fn cyclic_periodogram(
        &self,
        data: &CircleData,
        term: Term,
        residual: &[Real],
    ) -> (Real, Real) {
        let fitter = Fitter::new(data, self, vec![true; self.count]);
        fitter.periodogram(usize::from(term == Term::CyclicQ), residual)
    }
}

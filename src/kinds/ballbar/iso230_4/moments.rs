//! What the cyclic and lobe columns' cross products are taken from, summed per block from the
//! data alone (made and kept by the [`Blocks`](super::Blocks)) and over a fit's blocks
//! (`spectral.rs` reads them).
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
//! - **The periodogram** over the whole frequency grid: what it needs of an axis's cyclic
//!   columns from the data alone ([`Spectrum`]).
//! - **Lobe columns** sin kθ, cos kθ: their cross products with the static columns and the
//!   deviation for every lobe count, per block ([`LobeSums`]).

use super::CircleData;
use super::statics::WIDTH;
use crate::discovery::nufft::Nufft;
use crate::math::Real;
use rustfft::num_complex::Complex;
use std::f64::consts::{PI, TAU};
use std::rc::Rc;
use std::sync::{Arc, OnceLock};

/// Terms of the moment series of a cyclic column (valid within two grid steps).
pub(super) const ORDER: usize = 22;
/// Terms of the doubled phase's series.
pub(super) const DOUBLE_ORDER: usize = 30;

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
    pub(super) linear: Vec<Vec<Complex<Real>>>,
    /// Per block: Σ c^(2+p)·e^(4πi·f_c·x), p below [`DOUBLE_ORDER`].
    pub(super) double: Vec<Vec<Complex<Real>>>,
    /// Per block: Σ c².
    pub(super) squares: Vec<Real>,
    /// Per reading: c·e^(2πi·f_c·x).
    pub(super) phasors: Vec<Complex<Real>>,
}

/// [`CentreMoments`] summed over a fit's blocks.
#[derive(Debug)]
pub(super) struct CombinedMoments {
    /// The grid frequency (1/m).
    pub(super) frequency: Real,
    /// The moments of every block, and the readings' phasors.
    pub(super) all: Arc<OnceLock<CentreMoments>>,
    pub(super) linear: Vec<Complex<Real>>,
    pub(super) double: Vec<Complex<Real>>,
    pub(super) squares: Real,
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

/// The Taylor coefficients of a cyclic offset and of its doubled phase.
pub(super) type SeriesPair = Rc<(Vec<Complex<Real>>, Vec<Complex<Real>>)>;

/// Per block, the lobe columns' cross products with the table's columns for every lobe count
/// searched, and their own products.
#[derive(Debug)]
pub(super) struct LobeSums {
    pub(super) low: u32,
    pub(super) high: u32,
    /// Per block, per count from `low`: Σ sin kθ·w and Σ cos kθ·w for every table column w,
    /// then Σ sin², Σ cos², Σ sin·cos.
    pub(super) sums: Vec<Vec<Real>>,
}

/// Values per lobe count in [`LobeSums`].
pub(super) const LOBE_WIDTH: usize = 2 * WIDTH + 3;

/// The products of a column with sin kθ and cos kθ for every lobe count searched, as one
/// non-uniform Fourier transform over the angles: Σ v·e^(ikθ) = Σ (v·e^(i·k_low·θ))·e^(imθ),
/// m = k − k_low.
#[derive(Debug)]
pub(super) struct LobeTransform {
    pub(super) nufft: Nufft,
    /// Per reading, e^(i·k_low·θ).
    pub(super) factor: Vec<Complex<Real>>,
}

impl LobeTransform {
    pub(super) fn new(data: &CircleData) -> LobeTransform {
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
    pub(super) blocks: Vec<[[Complex<Real>; ORDER]; 2]>,
}

/// [`LobeSums`] summed over a fit's blocks.
#[derive(Debug)]
pub(super) struct CombinedLobes {
    pub(super) low: u32,
    pub(super) high: u32,
    pub(super) sums: Vec<Real>,
}

impl CombinedLobes {
    /// The sums of lobe count `k`, if it is in the searched range.
    pub(super) fn of(&self, k: u32) -> Option<&[Real]> {
        (self.low..=self.high).contains(&k).then(|| {
            let k = (k - self.low) as usize;
            &self.sums[k * LOBE_WIDTH..(k + 1) * LOBE_WIDTH]
        })
    }
}

/// What the periodogram of an axis's cyclic columns needs from the data alone.
#[derive(Debug)]
pub(super) struct Spectrum {
    /// The transform at the positions 2π·step·x.
    pub(super) nufft: Nufft,
    /// Per reading: c·e^(2πi·f_low·x).
    pub(super) factor: Vec<Complex<Real>>,
    /// Per block, per grid frequency: Σ c²·e^(4πi·f·x).
    pub(super) double: Vec<Vec<Complex<Real>>>,
    /// Per block: Σ c².
    pub(super) squares: Vec<Real>,
    /// Per block, per table column, the transform of the column times c·e^(2πi·f_low·x),
    /// when a fit's periodogram has needed them.
    pub(super) tables: OnceLock<Vec<Vec<Vec<Complex<Real>>>>>,
}

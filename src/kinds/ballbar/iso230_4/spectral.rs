//! Cross products of the cyclic and lobe columns without evaluating them reading by reading
//! in every fit, from their moments and sums per block (`moments.rs`; see there for the
//! series), and the cyclic periodogram over the whole frequency grid: a non-uniform discrete
//! Fourier transform of r·c·e^(2πi·f_low·x) at the positions 2π·step·x
//! (`crate::discovery::nufft`), relative error below 10⁻¹¹ of Σ|r·c|.

use super::blocks::Blocks;
use super::columns::{Column, Dense};
use super::moments::{
    CombinedLobes, CombinedMoments, DOUBLE_ORDER, LobeTransform, ORDER, SeriesPair, Spectrum,
    offset_series,
};
use super::normal::Fitter;
use super::statics::{WIDTH, Y};
use super::{CircleData, Term};
use crate::math::Real;
use rustfft::num_complex::Complex;
use std::f64::consts::TAU;
use std::rc::Rc;
use std::sync::{Arc, OnceLock};

impl<'a> Fitter<'a> {
    /// The lobe sums over the fitted blocks.
    fn combined_lobes(&self) -> &CombinedLobes {
        self.lobes.get_or_init(|| {
            let all = self
                .blocks
                .lobes
                .get_or_init(|| self.blocks.lobe_sums(self.data));
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
        let moments = cell.get_or_init(|| self.blocks.centre_moments(self.data, axis, frequency));
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
        let moments = cell.get_or_init(|| self.blocks.lobe_moments_about(self.data, axis, at, k));
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
        weights[Y] = 1.0;
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
            .get_or_init(|| self.blocks.table_transforms(self.data, spectrum));
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
        self.blocks.spectra[axis].get_or_init(|| self.blocks.spectrum(self.data, axis))
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

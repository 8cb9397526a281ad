//! The period search's periodogram ([`PositioningProblem::periodogram_peak`]): the fraction of
//! a residual's sum of squares that `a·sin(2πf·x) + b·cos(2πf·x) + c` removes, at every trial
//! frequency f.
//!
//! Its normal equations have seven sums per frequency, of which five (Σsin², Σsin·cos, Σcos²,
//! Σsin, Σcos, weighted by the readings at each position) depend only on the positions, not on
//! the residual. A search asks for the periodogram of many residuals (every model, every pass)
//! over the same few sets of positions (one per fold), so those five sums, with the 2 × 2
//! system's eigen-decomposition, are taken once per set of positions ([`Spectrum`], kept in
//! [`PerTraining`](super::memo::PerTraining)); a residual then needs only its two cross sums
//! Σsin·r and Σcos·r per frequency, which are the imaginary and real parts of one non-uniform
//! Fourier transform over all the frequencies at once ([`Nufft`]: about 1e-13 of Σ|r| from
//! the direct sums, tested).

use super::PositioningProblem;
use super::problem::distinct;
use crate::discovery::least_squares::RANK_TOLERANCE;
use crate::discovery::nufft::Nufft;
use crate::math::Real;
use rustfft::num_complex::Complex;
use std::f64::consts::TAU;

/// Frequencies between exact restarts of the periodogram's rotation.
const RESTART: usize = 64;

/// Interleaved partial sums of the periodogram's normal equations.
const LANES: usize = 2;

impl PositioningProblem {
    /// The periodogram's frequency step and lowest frequency (1/m): from 1/travel to
    /// 1/min_period, 4 points per 1/travel.
    pub(super) fn frequency_grid(&self) -> (Real, Real) {
        let span = (2.0 * self.half_range).max(self.options.min_period);
        (1.0 / (4.0 * span), 1.0 / span)
    }

    /// The number of frequencies the period search tests, from the grid's lowest to
    /// 1/min_period.
    pub(super) fn frequency_count(&self) -> usize {
        let (step, f_low) = self.frequency_grid();
        ((1.0 / self.options.min_period - f_low) / step).ceil() as usize + 1
    }

    /// The frequency (1/m) whose sinusoid removes the largest fraction of `r`'s sum of squares
    /// over the readings where `train` is true (`r` holds one value per such reading, in
    /// order), and that fraction.
    ///
    /// Readings at one position share their sine and cosine, so the sums of every trial
    /// frequency are taken over the distinct positions (a laser file reads a few dozen targets
    /// many times), each weighted by its readings: the same normal equations, a tenth of the
    /// work. The sums that do not depend on `r` are taken once per `train` (see the module
    /// documentation).
    pub(super) fn periodogram_peak(&self, train: &[bool], r: &[Real]) -> (Real, Real) {
        let spectrum = self.spectra.get(train, || {
            let (step, f_low) = self.frequency_grid();
            let count = self.frequency_count();
            let x: Vec<Real> = (0..self.x.len())
                .filter(|&i| train[i])
                .map(|i| self.x[i])
                .collect();
            Spectrum::new(&x, f_low, step, count)
        });
        spectrum.peak(r)
    }
}

/// The periodogram of one set of positions, less the residual: the distinct positions (each
/// with its number of readings), the trial frequencies `f_low + step·k` (k < `count`), and per
/// frequency the sums and the eigen-decomposition that depend on the positions only.
pub(super) struct Spectrum {
    /// The distinct position (group) of every reading.
    group_of: Vec<usize>,
    /// Each group's position (m) and number of readings.
    x: Vec<Real>,
    count: Vec<Real>,
    readings: Real,
    f_low: Real,
    step: Real,
    /// sin and cos of 2π·step·x per group: one frequency step's rotation.
    rotation: (Vec<Real>, Vec<Real>),
    terms: Vec<Term>,
    /// The transform Σ_g a_g·e^(i·m·u_g) at u_g = 2π·step·(x_g − x_mid), with
    /// a_g = r_g·e^(2πi·f_low·x_g) (`start`) and e^(2πi·m·step·x_mid) (`turn`) per frequency m.
    nufft: Nufft,
    start: Vec<Complex<Real>>,
    turn: Vec<Complex<Real>>,
}

/// One frequency's position-only part: Σsin and Σcos (weighted by readings), the centred 2 × 2
/// matrix's eigenvalues and the unit eigenvector of the larger.
#[derive(Clone, Copy)]
struct Term {
    s1: Real,
    c1: Real,
    largest: Real,
    smallest: Real,
    eigenvector: (Real, Real),
}

impl Spectrum {
    /// The spectrum of the positions `x` (one per reading; repeats make groups) at the
    /// frequencies `f_low + step·k`, k < `count` (1/m).
    pub(super) fn new(x: &[Real], f_low: Real, step: Real, count: usize) -> Spectrum {
        let (positions, group_of) = distinct(x);
        let mut weights = vec![0.0; positions.len()];
        for &g in &group_of {
            weights[g] += 1.0;
        }
        let rotation = positions
            .iter()
            .map(|&p| (TAU * step * p).sin_cos())
            .unzip();
        let middle = positions
            .first()
            .zip(positions.last())
            .map_or(0.0, |(a, b)| 0.5 * (a + b));
        // |x − x_mid| is at most half the travel and the step a quarter of 1/travel: |u| ≤ π/4.
        let u: Vec<Real> = positions
            .iter()
            .map(|&p| TAU * step * (p - middle))
            .collect();
        let nufft = Nufft::new(&u, count);
        let phasor = |angle: Real| {
            let (s, c) = angle.sin_cos();
            Complex::new(c, s)
        };
        let start = positions.iter().map(|&p| phasor(TAU * f_low * p)).collect();
        let turn = (0..count)
            .map(|m| phasor(TAU * m as Real * step * middle))
            .collect();
        let mut spectrum = Spectrum {
            group_of,
            x: positions,
            count: weights,
            readings: x.len() as Real,
            f_low,
            step,
            rotation,
            terms: Vec::with_capacity(count),
            nufft,
            start,
            turn,
        };
        let n = spectrum.readings;
        let mut terms = Vec::with_capacity(count);
        spectrum.sweep(count, |sin, cos| {
            let [ss, sc, cc, s1, c1] = spectrum_sums(sin, cos, &spectrum.count);
            let (a, b, d) = (ss - s1 * s1 / n, sc - s1 * c1 / n, cc - c1 * c1 / n);
            let (half_trace, radius) = (0.5 * (a + d), (0.25 * (a - d) * (a - d) + b * b).sqrt());
            let largest = half_trace + radius;
            // The larger eigenvalue's unit eigenvector (the better conditioned of the two
            // forms); the other's is at right angles.
            let (p, q) = if a >= d {
                (largest - d, b)
            } else {
                (b, largest - a)
            };
            let norm = (p * p + q * q).sqrt();
            let eigenvector = if norm > 0.0 {
                (p / norm, q / norm)
            } else {
                (1.0, 0.0)
            };
            terms.push(Term {
                s1,
                c1,
                largest,
                smallest: half_trace - radius,
                eigenvector,
            });
        });
        spectrum.terms = terms;
        spectrum
    }

    /// Calls `visit` with the sines and cosines of every group at each frequency in turn,
    /// stepped by a rotation (restarted from the exact value every [`RESTART`] frequencies,
    /// so rounding stays near 1e-14).
    fn sweep(&self, count: usize, mut visit: impl FnMut(&[Real], &[Real])) {
        let g = self.x.len();
        let (mut sin, mut cos) = (vec![0.0; g], vec![0.0; g]);
        let (rotation_sin, rotation_cos) = &self.rotation;
        for k in 0..count {
            if k % RESTART == 0 {
                let f = self.f_low + self.step * k as Real;
                for ((s, c), &x) in sin.iter_mut().zip(cos.iter_mut()).zip(&self.x) {
                    (*s, *c) = (TAU * f * x).sin_cos();
                }
            } else {
                let rotations = rotation_sin.iter().zip(rotation_cos);
                for ((s, c), (&rs, &rc)) in sin.iter_mut().zip(cos.iter_mut()).zip(rotations) {
                    // sin(a + b), cos(a + b).
                    (*s, *c) = (*s * rc + *c * rs, *c * rc - *s * rs);
                }
            }
            visit(&sin, &cos);
        }
    }

    /// The frequency (1/m) whose sinusoid removes the largest fraction of the sum of squares
    /// of `r` (one value per reading, in the order the positions were given), and that
    /// fraction; the last of equal maxima, as `Iterator::max_by` takes it.
    pub(super) fn peak(&self, r: &[Real]) -> (Real, Real) {
        let mut best = (self.f_low, Real::NEG_INFINITY);
        for (k, fraction) in self.fractions(r).into_iter().enumerate() {
            if fraction >= best.1 {
                best = (self.f_low + self.step * k as Real, fraction);
            }
        }
        if best.1 == Real::NEG_INFINITY {
            (self.f_low, 0.0)
        } else {
            best
        }
    }

    /// The fraction of `r`'s sum of squares each trial frequency removes, in order.
    fn fractions(&self, r: &[Real]) -> Vec<Real> {
        let mut sum = vec![0.0; self.x.len()];
        for (&g, r) in self.group_of.iter().zip(r) {
            sum[g] += r;
        }
        let total: Real = r.iter().map(|v| v * v).sum();
        let r1: Real = sum.iter().sum();
        // Σ_g r_g·e^(2πi·f_m·x_g) = Σcos·r + i·Σsin·r at every frequency f_m at once.
        let transform = self
            .nufft
            .transform(sum.iter().zip(&self.start).map(|(r, a)| a * r).enumerate());
        transform
            .iter()
            .zip(&self.turn)
            .zip(&self.terms)
            .map(|((t, turn), term)| {
                let t = t * turn;
                self.fraction(term, [t.im, t.re], total, r1)
            })
            .collect()
    }

    /// The fraction of the sum of squares `total` removed by `a·sin + b·cos + c` at one
    /// frequency, from its position-only `term`, the residual's cross sums Σsin·r and Σcos·r
    /// and its sum `r1`.
    ///
    /// The constant's equation eliminated: the centred 2 × 2 system M·k = w of the sine and
    /// the cosine. What the three columns remove (total − residual sum of squares) is
    /// wᵀ·M⁺·w plus the mean's share; M⁺ by M's eigenvalues, cut as the least squares cut
    /// singular values: [`RANK_TOLERANCE`] of the constant column's norm √n, squared here
    /// (sin² + cos² = 1 at every reading, so n is the sinusoid's scale too). At a frequency
    /// that puts every position on a whole number of cycles, the sine is round-off and the
    /// cosine the constant: only the mean removes anything.
    fn fraction(&self, term: &Term, [sr, cr]: [Real; 2], total: Real, r1: Real) -> Real {
        let n = self.readings;
        if n <= 0.0 || total <= 0.0 {
            return 0.0;
        }
        let w = (sr - term.s1 * r1 / n, cr - term.c1 * r1 / n);
        let cut = n * RANK_TOLERANCE * RANK_TOLERANCE;
        let mut removed = r1 * r1 / n;
        if term.largest > cut {
            let e = term.eigenvector;
            for (lambda, (x, y)) in [(term.largest, e), (term.smallest, (-e.1, e.0))] {
                if lambda > cut {
                    removed += (x * w.0 + y * w.1).powi(2) / lambda;
                }
            }
        }
        (removed / total).clamp(0.0, 1.0)
    }
}

/// Σw·sin², Σw·sin·cos, Σw·cos², Σw·sin, Σw·cos over the groups (`w` their readings), in
/// [`LANES`] interleaved partial sums that the compiler can keep in vector registers.
fn spectrum_sums(sin: &[Real], cos: &[Real], w: &[Real]) -> [Real; 5] {
    let mut lanes = [[0.0; LANES]; 5];
    let chunks = sin
        .chunks_exact(LANES)
        .zip(cos.chunks_exact(LANES))
        .zip(w.chunks_exact(LANES));
    for ((s, c), w) in chunks {
        for l in 0..LANES {
            let (ws, wc) = (w[l] * s[l], w[l] * c[l]);
            lanes[0][l] += ws * s[l];
            lanes[1][l] += ws * c[l];
            lanes[2][l] += wc * c[l];
            lanes[3][l] += ws;
            lanes[4][l] += wc;
        }
    }
    let mut sums = lanes.map(|lane| lane.iter().sum::<Real>());
    for j in sin.len() - sin.len() % LANES..sin.len() {
        let (ws, wc) = (w[j] * sin[j], w[j] * cos[j]);
        for (sum, term) in sums
            .iter_mut()
            .zip([ws * sin[j], ws * cos[j], wc * cos[j], ws, wc])
        {
            *sum += term;
        }
    }
    sums
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::discovery::least_squares::Design;

    /// The fraction `Spectrum` gives at the one frequency `f` (1/m).
    fn fraction_at(x: &[Real], r: &[Real], f: Real) -> Real {
        let (peak, fraction) = Spectrum::new(x, f, 1.0, 1).peak(r);
        assert_eq!(peak, f);
        fraction
    }

    #[test]
    fn grouped_reduction_equals_a_least_squares_on_every_reading() {
        // Positions read two to four times each (whole millimetres), a 25 mm sinusoid, an
        // offset and deterministic scatter.
        let mut x = Vec::new();
        let mut r = Vec::new();
        for k in 0..41_usize {
            let position = (5 + 17 * k) as Real * 1e-3;
            for repeat in 0..(2 + k % 3) {
                x.push(position);
                r.push(
                    1.3e-6 * (TAU * position / 0.025).sin() + 0.1e-6
                        - 0.2e-6 * (TAU * position / 0.025).cos()
                        + 0.05e-6 * (((k * 7 + repeat * 3) % 11) as Real / 11.0 - 0.5),
                );
            }
        }
        // 41 positions: ten chunks of the partial sums and one left over.
        assert_eq!(Spectrum::new(&x, 1.0, 1.0, 1).x.len(), 41);
        let total: Real = r.iter().map(|v| v * v).sum();
        for period_mm in [3.7, 25.0, 61.0, 400.0] {
            let f = 1.0 / (period_mm * 1e-3);
            let mut design = Design::new(x.len());
            design.push(x.iter().map(|&p| (TAU * f * p).sin()).collect());
            design.push(x.iter().map(|&p| (TAU * f * p).cos()).collect());
            design.push(vec![1.0; x.len()]);
            let fitted = design.times(&design.solve(&r));
            let sse: Real = r.iter().zip(&fitted).map(|(r, f)| (r - f).powi(2)).sum();
            let direct = 1.0 - sse / total;
            let grouped = fraction_at(&x, &r, f);
            assert!(
                (grouped - direct).abs() < 1e-10,
                "period {period_mm} mm: {grouped} against {direct}"
            );
        }
    }

    #[test]
    fn on_a_whole_number_of_cycles_only_the_mean_is_removed() {
        // Positions on a 5 mm grid and a 5 mm period: the sine is round-off (about 1e-13)
        // and the cosine is 1 everywhere, so the sinusoid adds nothing to the constant and
        // the fraction removed is the mean's, (Σr)²/n over Σr², not a fit of round-off.
        let x: Vec<Real> = (1..=30).map(|k| (5 * k) as Real * 1e-3).collect();
        let r: Vec<Real> = (0..30)
            .map(|k| 1e-6 * (0.3 + ((k * 7) % 11) as Real / 11.0))
            .collect();
        let total: Real = r.iter().map(|v| v * v).sum();
        let mean_share = r.iter().sum::<Real>().powi(2) / 30.0 / total;
        let fraction = fraction_at(&x, &r, 1.0 / 5e-3);
        assert!(
            (fraction - mean_share).abs() < 1e-12,
            "{fraction} against {mean_share}"
        );
    }

    #[test]
    fn the_transform_gives_the_least_squares_fraction_at_every_frequency() {
        // Scattered whole-millimetre positions over 5–704 mm, 20 of them read twice; a residual
        // with a 25 mm and a 7.3 mm sinusoid, an offset and scatter. At each of the 1 397
        // frequencies from 1/0.7 to 1/(2 mm) (the last puts every position on a whole or half
        // cycle: a sine of round-off), the fraction from the transform against a least squares
        // on every reading (`Design`: its own QR, SVD and rank cut), to 1e-9.
        let x: Vec<Real> = (0..60)
            .map(|k| ((k * 37) % 700 + 5) as Real * 1e-3)
            .chain((0..20).map(|k| ((k * 37) % 700 + 5) as Real * 1e-3))
            .collect();
        let r: Vec<Real> = x
            .iter()
            .enumerate()
            .map(|(i, &p)| {
                1e-6 * (TAU * p / 25e-3 + 0.4).sin()
                    + 0.4e-6 * (TAU * p / 7.3e-3).cos()
                    + 0.3e-6
                    + 0.1e-6 * ((i * 7) % 11) as Real / 11.0
            })
            .collect();
        let (f_low, step): (Real, Real) = (1.0 / 0.7, 1.0 / 2.8);
        let count = ((1.0 / 2e-3 - f_low) / step).ceil() as usize + 1;
        assert_eq!(count, 1397);
        let spectrum = Spectrum::new(&x, f_low, step, count);
        let fractions = spectrum.fractions(&r);
        let total: Real = r.iter().map(|v| v * v).sum();
        let mut worst: Real = 0.0;
        for (k, fraction) in fractions.iter().enumerate() {
            let f = f_low + step * k as Real;
            let mut design = Design::new(x.len());
            let sin: Vec<Real> = x.iter().map(|&p| (TAU * f * p).sin()).collect();
            // `Design` scales each column to unit norm, which would make a sine of round-off
            // (about 1e-13 at every position) a column of its own: leave it out.
            if sin.iter().any(|v| v.abs() > 1e-9) {
                design.push(sin);
            }
            design.push(x.iter().map(|&p| (TAU * f * p).cos()).collect());
            design.push(vec![1.0; x.len()]);
            let fitted = design.times(&design.solve(&r));
            let sse: Real = r.iter().zip(&fitted).map(|(r, f)| (r - f).powi(2)).sum();
            worst = worst.max((fraction - (1.0 - sse / total)).abs());
        }
        assert!(worst < 1e-9, "{worst}");
        // The peak is the grid frequency nearest 1/25 mm, the larger sinusoid's.
        let (peak, _) = spectrum.peak(&r);
        assert!((peak - 40.0).abs() <= step / 2.0, "{peak}");
    }
}

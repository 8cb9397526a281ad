//! The amplitude spectrum of one error-motion record, each line marked synchronous or
//! asynchronous (ISO 230-7 §5.2 f "frequency content plot", A.7.5 "frequency analysis such as
//! FFT can be used to separate the synchronous and asynchronous components").
//!
//! # What it models
//!
//! The `K` revolutions of `M` samples are concatenated into one record `x[n]`, `N = K·M`, in the
//! angle domain, and transformed with an FFT of that exact length (no window, no padding):
//!
//! ```text
//! X[j] = Σ_n x[n] e^{−2πi jn/N},   line j = 1..=N/2
//! frequency  j/K cycles per revolution (UPR)
//! amplitude  2|X[j]|/N for j < N/2,  |X[j]|/N at j = N/2 (N even)
//! ```
//!
//! A sinusoid `a·cos(f·θ + φ)` of the unwrapped angle `θ`, whose frequency `f` (UPR) is a
//! multiple of `1/K`, falls on line `j = f·K` with amplitude exactly `a`. Lines with
//! `j % K == 0` are the integer multiples of the rotation frequency, the synchronous error
//! motion; every other line, sub-harmonics such as a cage at 0.45 UPR included, is
//! asynchronous (§3.5.2, §3.5.5). The synchronous lines are exactly the harmonics of the
//! synchronous (revolution-averaged) profile: averaging `K` revolutions is the
//! comb filter that keeps the bins at multiples of `K`.
//!
//! # What it leaves out
//!
//! Windowing, so a component not on a line leaks into its neighbours (records taken on the
//! index grid put every synchronous component on a line); phases; the mean (line 0); time-domain
//! spectra of records not sampled on the angle grid (resample them first with
//! [`super::motion::resample`]). Conversion to Hz assumes a constant speed ([`Spectrum::hz`]).
//!
//! # Cost
//!
//! The record is real, so its transform is a real-input FFT (`realfft`: one complex FFT of
//! length `N/2` and a twiddle pass, half the work of a complex FFT of length `N`). Each thread
//! keeps its plans and its buffers, so a file's tests share them instead of allocating (and
//! page-faulting) megabytes per record. [`largest_lines`] keeps only the `n` lines asked for,
//! without building the list of all `N/2`.

use super::motion::Revolutions;
use crate::math::Real;
use mtwin_kernels::RealFftPlanner;
use realfft::num_complex::Complex;
use serde::Serialize;
use std::cell::RefCell;
use std::cmp::Ordering;

/// One spectral line.
#[derive(Clone, Copy, Debug, PartialEq, Serialize)]
pub struct Line {
    /// Frequency in cycles per revolution (UPR): `j/K` for line `j` of a `K`-revolution record.
    pub per_revolution: Real,
    /// One-sided amplitude of the sinusoid at this frequency, in the signal's unit (m, or rad
    /// for tilt): half its peak-to-valley.
    pub amplitude: Real,
    /// Whether the frequency is an integer multiple of the rotation frequency.
    pub synchronous: bool,
}

/// The amplitude spectrum of a record.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct Spectrum {
    /// Lines `1..=N/2` of the concatenated `K × M` record, in increasing frequency.
    pub lines: Vec<Line>,
    /// Number of revolutions `K` of the record: the line spacing is `1/K` UPR.
    pub revolutions: usize,
}

/// What one thread keeps between records: the plans (twiddles) rustfft and realfft made, one
/// per length, and the buffers of the last length transformed.
struct Workspace {
    planner: RealFftPlanner,
    input: Vec<Real>,
    output: Vec<Complex<Real>>,
    scratch: Vec<Complex<Real>>,
}

thread_local! {
    /// This thread's plans and buffers (a few times the record's size; kept for the next
    /// record, which in a file of tests has the same length).
    static WORKSPACE: RefCell<Workspace> = RefCell::new(Workspace {
        planner: RealFftPlanner::new(),
        input: Vec::new(),
        output: Vec::new(),
        scratch: Vec::new(),
    });
}

/// Transforms the concatenated record of `r` and hands `use_lines` the coefficients
/// `X[0..=N/2]` (the rest are their conjugate mirror).
fn transform<T>(r: &Revolutions, use_lines: impl FnOnce(&[Complex<Real>]) -> T) -> T {
    let x = r.values();
    let n = x.len();
    WORKSPACE.with(|workspace| {
        let workspace = &mut *workspace.borrow_mut();
        let fft = workspace.planner.plan_fft_forward(n);
        // realfft uses its input as working space: copy the record into the kept buffer.
        workspace.input.clear();
        workspace.input.extend_from_slice(x);
        workspace
            .output
            .resize(fft.complex_len(), Complex::new(0.0, 0.0));
        workspace
            .scratch
            .resize(fft.get_scratch_len(), Complex::new(0.0, 0.0));
        fft.process_with_scratch(
            &mut workspace.input,
            &mut workspace.output,
            &mut workspace.scratch,
        )
        .expect("buffers sized by the plan");
        use_lines(&workspace.output[..n / 2 + 1])
    })
}

/// The amplitude of line `j` of a record of `n` values from `|X[j]|²` (module docs).
fn amplitude(j: usize, n: usize, norm_sqr: Real) -> Real {
    let scale = if 2 * j == n { 1.0 } else { 2.0 };
    // |X| as √(re² + im²): amplitudes are far from overflow, and libm's hypot costs more
    // than the FFT.
    scale * norm_sqr.sqrt() / n as Real
}

/// Line `j` of a `k_count`-revolution record.
fn make_line(j: usize, amplitude: Real, k_count: usize) -> Line {
    Line {
        per_revolution: j as Real / k_count as Real,
        amplitude,
        synchronous: j.is_multiple_of(k_count),
    }
}

/// The amplitude spectrum of the concatenated record (formulas in the module docs). One
/// real-input FFT of length `K·M`, planned for that length, any length (not only powers of
/// two).
pub fn spectrum(r: &Revolutions) -> Spectrum {
    let n = r.values().len();
    let k_count = r.count();
    let lines = transform(r, |x| {
        x.iter()
            .enumerate()
            .skip(1)
            .map(|(j, xj)| make_line(j, amplitude(j, n, xj.norm_sqr()), k_count))
            .collect()
    });
    Spectrum {
        lines,
        revolutions: k_count,
    }
}

/// The cosine and sine coefficients `[a_k, b_k]`, k = 1..=k_max (entry `k − 1`), of one
/// revolution `profile` sampled at `θ_m = 2πm/M`: `p(θ) = a_0 + Σ a_k cos kθ + b_k sin kθ`,
/// `a_k = (2/M) Σ p_m cos kθ_m`, `b_k = (2/M) Σ p_m sin kθ_m` (one real-input FFT). Exact for
/// a profile of harmonics below Nyquist; `k_max` must be below `M/2` (panics otherwise, or
/// for fewer than 3 samples).
pub fn harmonics(profile: &[Real], k_max: usize) -> Vec<[Real; 2]> {
    let m = profile.len();
    assert!(
        2 * k_max < m,
        "harmonic {k_max} is not below Nyquist of {m} samples"
    );
    let r = Revolutions::new(m, profile.to_vec()).expect("one revolution of at least 3 samples");
    let scale = 2.0 / m as Real;
    // X_k = Σ p_m e^{−ikθ_m} = (M/2)(a_k − i b_k).
    transform(&r, |x| {
        x[1..=k_max]
            .iter()
            .map(|c| [scale * c.re, -scale * c.im])
            .collect()
    })
}

/// `spectrum(r).largest(n, synchronous)` without building the list of all lines: the same
/// lines in the same order, for a fraction of the cost when `n` is small.
pub fn largest_lines(r: &Revolutions, n: usize, synchronous: Option<bool>) -> Vec<Line> {
    if n == 0 {
        return Vec::new();
    }
    if n > SMALL_N {
        // Many lines asked for: the full list and a selection cost no more.
        return spectrum(r).largest(n, synchronous);
    }
    let len = r.values().len();
    let k_count = r.count();
    transform(r, |x| {
        let mut largest = Largest::new(n);
        // Once `n` lines are kept, a line whose |X|² is at most that of the last one kept has
        // at most its amplitude (the amplitude is a monotone function of |X|² for all lines
        // but the Nyquist one) and a higher frequency, so it cannot enter: no square root.
        let mut floor = Real::NEG_INFINITY;
        for (j, xj) in x.iter().enumerate().skip(1) {
            let norm_sqr = xj.norm_sqr();
            if norm_sqr <= floor && 2 * j != len {
                continue;
            }
            if synchronous.is_some_and(|s| j.is_multiple_of(k_count) != s) {
                continue;
            }
            largest.offer(make_line(j, amplitude(j, len, norm_sqr), k_count), j);
            if let Some(last) = largest.full_last() {
                floor = x[last].norm_sqr();
            }
        }
        largest.into_lines()
    })
}

/// Up to this many lines asked for, they are kept in a small sorted list while the lines go
/// by; beyond, all candidates are collected and the `n` largest selected.
const SMALL_N: usize = 32;

/// The ranking of [`Spectrum::largest`]: larger amplitude first, then (equal amplitudes) lower
/// frequency first. A total order on the lines of one spectrum, so the `n` largest and their
/// order are the same whichever way they are found.
fn ranking(a: &Line, b: &Line) -> Ordering {
    b.amplitude
        .total_cmp(&a.amplitude)
        .then(a.per_revolution.total_cmp(&b.per_revolution))
}

/// The `n` best lines offered so far, best first (insertion into a list of at most `n`),
/// each with its index `j`.
struct Largest {
    n: usize,
    kept: Vec<(Line, usize)>,
}

impl Largest {
    fn new(n: usize) -> Largest {
        Largest {
            n,
            kept: Vec::with_capacity(n),
        }
    }

    fn offer(&mut self, line: Line, j: usize) {
        if self.n == 0 {
            return;
        }
        if self.kept.len() == self.n {
            if ranking(&line, &self.kept[self.n - 1].0) != Ordering::Less {
                return;
            }
            self.kept.pop();
        }
        let at = self
            .kept
            .partition_point(|(k, _)| ranking(k, &line) == Ordering::Less);
        self.kept.insert(at, (line, j));
    }

    /// The index of the last line kept, once `n` are.
    fn full_last(&self) -> Option<usize> {
        (self.kept.len() == self.n)
            .then(|| self.kept.last().map(|&(_, j)| j))
            .flatten()
    }

    fn into_lines(self) -> Vec<Line> {
        self.kept.into_iter().map(|(line, _)| line).collect()
    }
}

impl Spectrum {
    /// The `n` lines of largest amplitude, largest first (equal amplitudes: lower frequency
    /// first), among the synchronous lines (`Some(true)`), the asynchronous ones
    /// (`Some(false)`) or all (`None`). Fewer if fewer lines qualify.
    pub fn largest(&self, n: usize, synchronous: Option<bool>) -> Vec<Line> {
        let candidates = self
            .lines
            .iter()
            .filter(|l| synchronous.is_none_or(|s| l.synchronous == s))
            .copied();
        if n <= SMALL_N {
            let mut largest = Largest::new(n);
            candidates.for_each(|line| largest.offer(line, 0));
            return largest.into_lines();
        }
        let mut picked: Vec<Line> = candidates.collect();
        // The n largest first (linear time), then only those sorted.
        if picked.len() > n {
            picked.select_nth_unstable_by(n - 1, ranking);
        }
        picked.truncate(n);
        picked.sort_unstable_by(ranking);
        picked
    }

    /// The frequency of `line` in Hz at a constant speed of `revolutions_per_second`.
    pub fn hz(&self, line: &Line, revolutions_per_second: Real) -> Real {
        line.per_revolution * revolutions_per_second
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::f64::consts::TAU;

    /// `K` revolutions of `M` samples of `f(unwrapped angle)`.
    fn record(m: usize, k: usize, f: impl Fn(Real) -> Real) -> Revolutions {
        let values = (0..m * k).map(|i| f(TAU * i as Real / m as Real)).collect();
        Revolutions::new(m, values).expect("a record")
    }

    /// `largest_lines` and `Spectrum::largest`, by insertion and by selection, give the same
    /// lines in the same order, ties (equal amplitudes) included.
    #[test]
    fn every_way_to_the_largest_lines_agrees() {
        let noisy = record(50, 6, |u| {
            (3.0 * u).cos() + 0.3 * (0.5 * u + 1.0).sin() + 1e-3 * (17.3 * u * u).sin()
        });
        // Every line exactly zero: the ranking falls back on frequency.
        let flat = record(8, 3, |_| 0.0);
        for r in [&noisy, &flat] {
            let full = spectrum(r);
            for synchronous in [None, Some(true), Some(false)] {
                let all: Vec<Line> = {
                    let mut v: Vec<Line> = full
                        .lines
                        .iter()
                        .filter(|l| synchronous.is_none_or(|s| l.synchronous == s))
                        .copied()
                        .collect();
                    v.sort_by(ranking);
                    v
                };
                for n in [0, 1, 2, 8, SMALL_N, SMALL_N + 1, 100, usize::MAX] {
                    let want = &all[..n.min(all.len())];
                    assert_eq!(full.largest(n, synchronous), want, "largest {n}");
                    assert_eq!(largest_lines(r, n, synchronous), want, "largest_lines {n}");
                }
            }
        }
    }
}

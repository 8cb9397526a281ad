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

use super::motion::Revolutions;
use crate::math::Real;
use rustfft::FftPlanner;
use rustfft::num_complex::Complex;
use serde::Serialize;

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

thread_local! {
    /// The FFT planner of this thread, with the plans it has made.
    static PLANNER: std::cell::RefCell<FftPlanner<Real>> = std::cell::RefCell::new(FftPlanner::new());
}

/// The amplitude spectrum of the concatenated record (formulas in the module docs). One FFT of
/// length `K·M`, planned for that length, any length (not only powers of two).
pub fn spectrum(r: &Revolutions) -> Spectrum {
    let x = r.values();
    let n = x.len();
    let k_count = r.count();
    let mut buffer: Vec<Complex<Real>> = x.iter().map(|&v| Complex::new(v, 0.0)).collect();
    // rustfft's planner keeps the plans (twiddles) it made: one per thread serves every record
    // of a length, so a file's tests share one plan instead of recomputing it.
    PLANNER.with(|planner| {
        planner
            .borrow_mut()
            .plan_fft_forward(n)
            .process(&mut buffer)
    });
    let half = n / 2;
    let lines = (1..=half)
        .map(|j| {
            let scale = if 2 * j == n { 1.0 } else { 2.0 };
            Line {
                per_revolution: j as Real / k_count as Real,
                // |X| as √(re² + im²): amplitudes are far from overflow, and libm's hypot
                // costs more than the FFT.
                amplitude: scale * buffer[j].norm_sqr().sqrt() / n as Real,
                synchronous: j.is_multiple_of(k_count),
            }
        })
        .collect();
    Spectrum {
        lines,
        revolutions: k_count,
    }
}

impl Spectrum {
    /// The `n` lines of largest amplitude, largest first, among the synchronous lines
    /// (`Some(true)`), the asynchronous ones (`Some(false)`) or all (`None`). Fewer if fewer
    /// lines qualify.
    pub fn largest(&self, n: usize, synchronous: Option<bool>) -> Vec<Line> {
        let mut picked: Vec<Line> = self
            .lines
            .iter()
            .filter(|l| synchronous.is_none_or(|s| l.synchronous == s))
            .copied()
            .collect();
        let larger = |a: &Line, b: &Line| b.amplitude.total_cmp(&a.amplitude);
        // The n largest first (linear time), then only those sorted.
        if n > 0 && picked.len() > n {
            picked.select_nth_unstable_by(n - 1, larger);
        }
        picked.truncate(n);
        picked.sort_by(larger);
        picked
    }

    /// The frequency of `line` in Hz at a constant speed of `revolutions_per_second`.
    pub fn hz(&self, line: &Line, revolutions_per_second: Real) -> Real {
        line.per_revolution * revolutions_per_second
    }
}

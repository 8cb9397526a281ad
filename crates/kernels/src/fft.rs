//! FFT planners for `f64`: rustfft's and realfft's, planned here so that their code (every
//! butterfly of every instruction set) is compiled in this crate only. A plan is a trait
//! object; running it costs one indirect call, as it did before.

use realfft::RealToComplex;
use rustfft::Fft;
use std::sync::Arc;

/// rustfft's [`rustfft::FftPlanner`] for `f64` (the fastest algorithm for the machine it runs
/// on; plans kept for reuse by length).
pub struct FftPlanner(rustfft::FftPlanner<f64>);

impl FftPlanner {
    /// A planner with no plan yet.
    #[inline(never)]
    #[allow(clippy::new_without_default)]
    pub fn new() -> FftPlanner {
        FftPlanner(rustfft::FftPlanner::new())
    }

    /// The forward transform of `len` values (unnormalised, `e^{−2πi jk/len}`).
    #[inline(never)]
    pub fn plan_fft_forward(&mut self, len: usize) -> Arc<dyn Fft<f64>> {
        self.0.plan_fft_forward(len)
    }

    /// The inverse transform of `len` values (unnormalised, `e^{+2πi jk/len}`).
    #[inline(never)]
    pub fn plan_fft_inverse(&mut self, len: usize) -> Arc<dyn Fft<f64>> {
        self.0.plan_fft_inverse(len)
    }
}

/// realfft's [`realfft::RealFftPlanner`] for `f64`: transforms of real input, half the work
/// of a complex transform of the same length.
pub struct RealFftPlanner(realfft::RealFftPlanner<f64>);

impl RealFftPlanner {
    /// A planner with no plan yet.
    #[inline(never)]
    #[allow(clippy::new_without_default)]
    pub fn new() -> RealFftPlanner {
        RealFftPlanner(realfft::RealFftPlanner::new())
    }

    /// The forward transform of `len` real values: `len / 2 + 1` complex coefficients.
    #[inline(never)]
    pub fn plan_fft_forward(&mut self, len: usize) -> Arc<dyn RealToComplex<f64>> {
        self.0.plan_fft_forward(len)
    }
}

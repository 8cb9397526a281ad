//! mtwin's numeric kernels, compiled once and optimised.
//!
//! rustfft's planners and nalgebra's decompositions are generic: each crate that calls them
//! for `f64` compiles its own copy, at its own optimisation level. In mtwin that copy was an
//! eighth of the library's code (rustfft's planner alone brings every SIMD butterfly, 450 k
//! lines of LLVM IR), compiled twice by `cargo test` (the library and its unit tests) and at
//! the light optimisation of the crate, where the least-squares searches of discovery spent
//! most of their time in unoptimised Householder and Givens steps.
//!
//! Here they are instantiated once, behind functions that are not generic and not inlined,
//! in a crate the build profile optimises fully. The results are the same to the bit: Rust
//! does not reassociate floating-point arithmetic at any optimisation level, so the same
//! algorithm on the same input gives the same numbers.
//!
//! ```
//! use mtwin_kernels::{Complex, FftPlanner, linalg};
//! use nalgebra::DMatrix;
//!
//! // The DFT of a unit impulse is flat.
//! let fft = FftPlanner::new().plan_fft_forward(8);
//! let mut buffer = vec![Complex::new(0.0, 0.0); 8];
//! buffer[0] = Complex::new(1.0, 0.0);
//! fft.process(&mut buffer);
//! assert!(buffer.iter().all(|c| *c == Complex::new(1.0, 0.0)));
//!
//! // The singular values of diag(3, 4) are 4 and 3.
//! let svd = linalg::svd(DMatrix::from_diagonal(&nalgebra::dvector![3.0, 4.0]), true, true);
//! let mut s: Vec<f64> = svd.singular_values.iter().copied().collect();
//! s.sort_by(f64::total_cmp);
//! assert_eq!(s, [3.0, 4.0]);
//! ```

pub mod fft;
pub mod linalg;

pub use fft::{FftPlanner, RealFftPlanner};
pub use realfft::RealToComplex;
pub use rustfft::Fft;
pub use rustfft::num_complex::Complex;

//! Artefact form from error motion: Donaldson reversal (and its face analogue), multi-probe
//! separation per harmonic with the harmonics a probe layout cannot see, and tilt from two
//! radial stations.
//!
//! All inputs are **synchronous profiles** — one revolution of `M` samples per probe, already
//! averaged over revolutions by the caller — with sample `m` at spindle angle
//! `θ_m = 2πm/M`. SI throughout (m, rad).
//!
//! # Conventions
//!
//! * Spindle angle θ, positive rotation about +z. A probe fixed at stator azimuth φ sees the
//!   artefact point at rotor azimuth ψ = φ − θ.
//! * Artefact form `h(ψ)`: outward radial deviation of the artefact surface (a hill is
//!   positive), zero mean; its Fourier series is `h(ψ) = Σ_k H_k e^{ikψ}`.
//! * Error motion `E(θ) = (E_X, E_Y)`: displacement of the artefact's centre relative to the
//!   probes at the probes' height, including eccentricity (a 1-UPR part of E).
//! * A probe facing the axis reads positive when the surface moves away from it (ISO 230-7
//!   A.7.2): `reading_j(θ) = −(E_X cos φ_j + E_Y sin φ_j) − h(φ_j − θ)`.
//! * Discrete Fourier coefficients: `c_k = (1/M) Σ_m x_m e^{−ikθ_m}`, so
//!   `x(θ) = Σ_k c_k e^{ikθ}`, `c_{−k} = conj(c_k)`, and harmonic `k ≥ 1` has amplitude
//!   `2|c_k|`.
//!
//! # What is modelled
//!
//! * [`donaldson_reversal`] (ISO 230-7 Annex B, procedures P and S at once). Set-up 1: probe
//!   at φ = 0. Set-up 2: artefact turned 180° on the rotor **and** probe moved to φ = π. With
//!   the convention above `r1 = −E_X(θ) − h(−θ)` and `r2 = +E_X(θ) − h(−θ)`, hence
//!   `E_X = (r2 − r1)/2` and `h(−θ) = −(r1 + r2)/2`. Whatever follows the artefact (its form
//!   and its centring on the rotor) comes out as form; whatever stays with the rotor (the
//!   spindle's own motion, including its fundamental) comes out as motion.
//! * [`face_reversal`]: the same 180° reversal on a face track at radius R, after Estler: the
//!   tilt part of the face motion reverses, the face form and the axial motion do not, so the
//!   reversal gives the tilt part alone and face form plus axial motion; an on-axis axial
//!   record, when given, removes the axial motion.
//! * [`separate`]: multi-probe separation (Ozono / Whitehouse family) by per-harmonic least
//!   squares for `P ≥ 3` probes at arbitrary azimuths, under two models ([`Model`]):
//!   the general **two-direction** model (X_k, Y_k independent: any, e.g. elliptical, error
//!   motion) and the pyOutRun-style **single-whirl** model, kept to show how it leaks a
//!   non-circular motion into the form. Each harmonic's column-scaled design has a condition
//!   number; above a limit the harmonic is **blind** (harmonic suppression) and neither its
//!   form nor its motion is estimated. [`blind_harmonics`] and [`condition_numbers`] report a
//!   layout without data.
//! * [`tilt_from_stations`]: tilt error motion from the radial motions at two heights.
//!
//! # Left out
//!
//! * Asynchronous error motion: inputs are synchronous averages; per-revolution separation
//!   would need the same solve on each revolution (the design is the same) and is the
//!   caller's choice.
//! * Probe angle and gain errors, probe misalignment, the track shift of a reversal: the
//!   models assume exact azimuths and unit gains; such errors show only in `residual_rms`
//!   (when `P` exceeds the number of unknowns) or bias the result.
//! * Multi-step (Whitehouse re-indexing) separation.
//! * Harmonics above `k_max` (and the Nyquist line) are ignored: no anti-aliasing is done here.
//! * Gauges, fixed by convention: at k = 0 probe zeros, static centre offset and form mean are
//!   indistinguishable, so all are set to zero (every output has zero mean). At k = 1 the
//!   form's first harmonic (the artefact's centring) cannot be told from the fundamental
//!   motion; it is assigned to the motion and form harmonic 1 is zero.

use mtwin_kernels::FftPlanner;
use nalgebra::{DMatrix, DVector};
use thiserror::Error;

use crate::math::Real;

/// Complex numbers of the per-harmonic solves (nalgebra's re-export of `num_complex`).
pub type Complex = nalgebra::Complex<Real>;

/// Default condition-number limit above which a harmonic is blind.
pub const DEFAULT_CONDITION_LIMIT: Real = 1e3;

/// Fewest samples per revolution for multi-probe separation: harmonic 2 must lie below
/// Nyquist (`2·2 < M`).
pub const MIN_SAMPLES: usize = 5;

/// Fewest samples per revolution for a reversal.
pub const MIN_REVERSAL_SAMPLES: usize = 2;

/// Why a separation cannot be computed.
#[derive(Debug, Clone, PartialEq, Error)]
pub enum SeparationError {
    /// Multi-probe separation needs at least three probes.
    #[error("{0} probe(s): multi-probe separation needs at least 3")]
    TooFewProbes(usize),
    /// Two inputs that must have the same length do not.
    #[error("{what}: expected length {expected}, found {found}")]
    LengthMismatch {
        /// Which input.
        what: &'static str,
        /// The length required.
        expected: usize,
        /// The length given.
        found: usize,
    },
    /// A NaN or infinite value.
    #[error("{what}: non-finite value at index {index}")]
    NotFinite {
        /// Which input.
        what: &'static str,
        /// Index of the first offending value.
        index: usize,
    },
    /// Too few samples per revolution.
    #[error("{samples} sample(s) per revolution: at least {min} needed")]
    TooFewSamples {
        /// Samples given.
        samples: usize,
        /// Samples needed.
        min: usize,
    },
    /// The highest harmonic asked for is below 2 or not below Nyquist.
    #[error("k_max = {k_max} must satisfy 2 ≤ k_max < M/2 with M = {samples}")]
    HarmonicRange {
        /// Highest harmonic asked for.
        k_max: usize,
        /// Samples per revolution.
        samples: usize,
    },
    /// The condition-number limit is not a finite number ≥ 1.
    #[error("condition-number limit {0} must be finite and at least 1")]
    BadLimit(Real),
    /// The two stations of a tilt evaluation are at the same height (or not finite).
    #[error("station heights {0} and {1} must be finite and distinct")]
    Stations(Real, Real),
}

/// Result of a radial Donaldson reversal.
#[derive(Clone, Debug, PartialEq)]
pub struct Reversal {
    /// Spindle error motion along the set-up-1 probe direction's axis, `E_X(θ_m)` (m), on
    /// the θ grid `θ_m = 2πm/M`; zero mean.
    pub motion: Vec<Real>,
    /// Artefact form `h(ψ_m)` (m), outward positive, on the ψ grid `ψ_m = 2πm/M`; zero mean.
    /// Includes the artefact's centring on the rotor (a first harmonic).
    pub form: Vec<Real>,
}

/// Donaldson reversal (ISO 230-7 Annex B) of two synchronous profiles.
///
/// `setup1`: probe at stator azimuth 0. `setup2`: artefact turned 180° on the rotor and probe
/// moved to azimuth π, same angle reference. Both of length `M ≥ 2`, sample `m` at
/// `θ_m = 2πm/M`. Returns `E_X = (r2 − r1)/2` and `h(−θ) = −(r1 + r2)/2` (re-indexed onto the
/// ψ grid), each with its mean removed (probe zeros).
pub fn donaldson_reversal(setup1: &[Real], setup2: &[Real]) -> Result<Reversal, SeparationError> {
    check_pair(setup1, setup2)?;
    let (motion, form) = reverse(setup1, setup2);
    Ok(Reversal { motion, form })
}

/// Result of a face reversal.
#[derive(Clone, Debug, PartialEq)]
pub struct FaceReversal {
    /// The part of the face error motion at azimuth 0 that reverses with the set-up (m), on
    /// the θ grid: `W(θ) = −n_z·R·E_B(θ)` for a face of outward normal `n_z·ẑ` (`n_z = ±1`)
    /// probed at radius R, `E_B` the tilt about y (rad); zero mean.
    pub tilt: Vec<Real>,
    /// Face form `g(ψ_m)` (m), outward normal positive, on the ψ grid; zero mean. Without an
    /// axial record it still holds the axial error motion along the outward normal,
    /// `g(ψ) + E_N(θ = −ψ)`.
    pub form: Vec<Real>,
    /// Whether the axial error motion was removed from `form` using the on-axis record.
    pub axial_removed: bool,
}

/// Face reversal: Donaldson's 180° reversal on a face track (after Estler).
///
/// A probe at radius R faces the artefact's face and reads positive when the face moves away
/// from it. The face point at azimuth φ moves along the face's outward normal by
/// `F(θ, φ) = E_N(θ) + W(θ) cos φ + V(θ) sin φ`, axial motion `E_N` plus the tilt part, so
/// `r1 = −(E_N + W) − g(−θ)` (probe at φ = 0) and, after turning the artefact 180° on the
/// rotor and moving the probe to φ = π, `r2 = −(E_N − W) − g(−θ)`. Hence
/// `W = (r2 − r1)/2` and `g(−θ) + E_N(θ) = −(r1 + r2)/2`.
///
/// `axial`, when given, is the synchronous reading of a probe on the axis of rotation facing
/// the same way (`−E_N(θ)` plus a constant, the face centre's form being a constant); it is
/// added to `−(r1 + r2)/2` to leave the face form alone.
pub fn face_reversal(
    setup1: &[Real],
    setup2: &[Real],
    axial: Option<&[Real]>,
) -> Result<FaceReversal, SeparationError> {
    check_pair(setup1, setup2)?;
    if let Some(a) = axial {
        check_len("axial", setup1.len(), a.len())?;
        check_finite("axial", a)?;
    }
    let (tilt, mut form) = reverse(setup1, setup2);
    if let Some(a) = axial {
        let m_len = a.len();
        let mean = a.iter().sum::<Real>() / m_len as Real;
        // form is on the ψ grid: ψ_m = −θ_{(M−m) mod M}.
        for (m, g) in form.iter_mut().enumerate() {
            *g += a[(m_len - m) % m_len] - mean;
        }
    }
    Ok(FaceReversal {
        tilt,
        form,
        axial_removed: axial.is_some(),
    })
}

/// `(r2 − r1)/2` on the θ grid and `−(r1 + r2)/2` moved to the ψ grid, both zero-mean.
fn reverse(r1: &[Real], r2: &[Real]) -> (Vec<Real>, Vec<Real>) {
    let m_len = r1.len();
    let mut motion: Vec<Real> = r1.iter().zip(r2).map(|(a, b)| 0.5 * (b - a)).collect();
    let mut form = vec![0.0; m_len];
    for m in 0..m_len {
        // ψ = −θ_m = 2π(M − m)/M.
        form[(m_len - m) % m_len] = -0.5 * (r1[m] + r2[m]);
    }
    remove_mean(&mut motion);
    remove_mean(&mut form);
    (motion, form)
}

fn check_pair(r1: &[Real], r2: &[Real]) -> Result<(), SeparationError> {
    if r1.len() < MIN_REVERSAL_SAMPLES {
        return Err(SeparationError::TooFewSamples {
            samples: r1.len(),
            min: MIN_REVERSAL_SAMPLES,
        });
    }
    check_len("setup2", r1.len(), r2.len())?;
    check_finite("setup1", r1)?;
    check_finite("setup2", r2)
}

fn check_len(what: &'static str, expected: usize, found: usize) -> Result<(), SeparationError> {
    if expected == found {
        Ok(())
    } else {
        Err(SeparationError::LengthMismatch {
            what,
            expected,
            found,
        })
    }
}

fn check_finite(what: &'static str, values: &[Real]) -> Result<(), SeparationError> {
    match values.iter().position(|v| !v.is_finite()) {
        None => Ok(()),
        Some(index) => Err(SeparationError::NotFinite { what, index }),
    }
}

fn remove_mean(values: &mut [Real]) {
    let mean = values.iter().sum::<Real>() / values.len() as Real;
    values.iter_mut().for_each(|v| *v -= mean);
}

/// The per-harmonic model of the error motion in a multi-probe separation.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Model {
    /// General radial error motion: per harmonic k, `X_k` and `Y_k` independent (a
    /// forward and a backward whirl, e.g. an elliptical orbit). Design rows
    /// `[−cos φ_j, −sin φ_j, −e^{−ikφ_j}]` for unknowns `X_k, Y_k, H_{−k}`.
    TwoDirection,
    /// pyOutRun-style: one forward whirl per harmonic, `E_X + iE_Y = Σ_{k>0} A_k e^{ikθ}`, i.e.
    /// `Y_k = −i X_k` (`E_Y` lags `E_X` by a quarter period of the harmonic). Design rows
    /// `[−e^{−iφ_j}, −e^{−ikφ_j}]` for unknowns `X_k, H_{−k}`. Cannot hold a non-circular
    /// error motion: the backward whirl leaks into the form and the residual.
    SingleWhirl,
}

/// Options of [`separate`].
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Options {
    /// Highest harmonic estimated; `None` for `⌈M/2⌉ − 1` (the highest below Nyquist).
    pub k_max: Option<usize>,
    /// Condition number (column-scaled design) above which a harmonic is blind.
    pub condition_limit: Real,
}

impl Default for Options {
    fn default() -> Self {
        Self {
            k_max: None,
            condition_limit: DEFAULT_CONDITION_LIMIT,
        }
    }
}

/// Result of a multi-probe separation.
#[derive(Clone, Debug, PartialEq)]
pub struct Separation {
    /// The model used.
    pub model: Model,
    /// Highest harmonic estimated.
    pub k_max: usize,
    /// Artefact form `h(ψ_m)` (m) on the ψ grid `ψ_m = 2πm/M`: harmonics 2..=k_max that are
    /// not blind.
    pub form: Vec<Real>,
    /// `E_X(θ_m)` (m) on the θ grid: harmonics 1..=k_max not blind (harmonic 1 includes
    /// eccentricity and the artefact's centring).
    pub motion_x: Vec<Real>,
    /// `E_Y(θ_m)` (m) on the θ grid, as `motion_x`.
    pub motion_y: Vec<Real>,
    /// Fourier coefficients `H_k`, k = 0..=k_max, of the form (`h(ψ) = Σ H_k e^{ikψ}`);
    /// zero at k = 0, 1 and at blind harmonics.
    pub form_spectrum: Vec<Complex>,
    /// Fourier coefficients `X_k`, k = 0..=k_max, of `E_X(θ)`; zero at k = 0 and blind k.
    pub motion_x_spectrum: Vec<Complex>,
    /// Fourier coefficients `Y_k`, k = 0..=k_max, of `E_Y(θ)`; zero at k = 0 and blind k.
    pub motion_y_spectrum: Vec<Complex>,
    /// Harmonics not estimated because their condition number exceeds the limit (ascending;
    /// normally from 2 up, 1 only for a degenerate layout such as collinear probes).
    pub blind: Vec<usize>,
    /// Condition number of the column-scaled design per harmonic, index k = 0..=k_max. At
    /// k = 0 nothing is estimated (gauge) and the entry is 1; at k = 1 it is the design
    /// without the form column.
    pub condition: Vec<Real>,
    /// RMS (m) over probes and angles of the part of the readings, at the harmonics
    /// estimated, that the model leaves unexplained. Zero for consistent noise-free data; with
    /// as many probes as unknowns (3 probes, two-direction model, k ≥ 2) a harmonic has no
    /// redundancy and contributes nothing whatever the data (the fundamental, with two
    /// unknowns, still does). Blind harmonics, k = 0 and k > k_max are not counted.
    pub residual_rms: Real,
    /// The per-sample RMS error of the form, `E_X` and `E_Y` profiles that the misfit implies
    /// (m): at each harmonic with more probes than unknowns, the misfit's variance per probe
    /// `|r_k|²/(P − n)` propagated through the least squares, `(AᴴA)⁻¹`, summed over the
    /// harmonics (each counts twice, for k and −k). Errors of the readings that the model
    /// can hold (as many as its unknowns at each harmonic) are not seen; the estimate takes
    /// them to be as large as those it sees.
    pub misfit_error_rms: [Real; 3],
    /// The degrees of freedom of each of those estimates (Welch–Satterthwaite over the
    /// harmonics, each harmonic's misfit carrying `2(P − n)`): few when the content is in a
    /// few harmonics, so its coverage factor is Student's, not 2.
    pub misfit_dof: [Real; 3],
    /// The harmonics at which the layout has no more probes than unknowns: its misfit is
    /// zero there whatever the readings' errors, so [`Separation::misfit_error_rms`] holds
    /// nothing of them.
    pub unchecked: Vec<usize>,
}

/// Multi-probe error separation of synchronous profiles.
///
/// `readings[j]` is probe `j`'s synchronous profile (length `M`, sample `m` at `θ_m = 2πm/M`)
/// for the probe at stator azimuth `azimuths[j]` (rad), in the convention of the module.
/// Per harmonic k = 1..=k_max the readings' Fourier coefficients are fitted by least squares
/// to the [`Model`]'s design (columns scaled to unit norm, solved by SVD); harmonics whose
/// condition number exceeds `options.condition_limit` are blind (set to zero, listed).
///
/// Errors: fewer than 3 probes, readings and azimuths of different counts, profiles of
/// different lengths, non-finite values, `M < 5`, `k_max` outside `2 ≤ k_max < M/2`, a limit
/// not finite or below 1.
pub fn separate<R: AsRef<[Real]>>(
    readings: &[R],
    azimuths: &[Real],
    model: Model,
    options: Options,
) -> Result<Separation, SeparationError> {
    let p = readings.len();
    if p < 3 {
        return Err(SeparationError::TooFewProbes(p));
    }
    check_len("azimuths", p, azimuths.len())?;
    check_finite("azimuths", azimuths)?;
    let m_len = readings[0].as_ref().len();
    if m_len < MIN_SAMPLES {
        return Err(SeparationError::TooFewSamples {
            samples: m_len,
            min: MIN_SAMPLES,
        });
    }
    for r in readings {
        check_len("readings", m_len, r.as_ref().len())?;
        check_finite("readings", r.as_ref())?;
    }
    let k_max = options.k_max.unwrap_or((m_len - 1) / 2);
    if k_max < 2 || 2 * k_max >= m_len {
        return Err(SeparationError::HarmonicRange {
            k_max,
            samples: m_len,
        });
    }
    let limit = options.condition_limit;
    if !limit.is_finite() || limit < 1.0 {
        return Err(SeparationError::BadLimit(limit));
    }

    // Fourier coefficients of every probe, harmonics 0..=k_max, probe-major.
    let mut planner = FftPlanner::new();
    let forward = planner.plan_fft_forward(m_len);
    let mut buffer = vec![Complex::new(0.0, 0.0); m_len];
    let mut scratch = vec![Complex::new(0.0, 0.0); forward.get_inplace_scratch_len()];
    let mut coeffs = vec![Complex::new(0.0, 0.0); p * (k_max + 1)];
    let inv_m = 1.0 / m_len as Real;
    for (j, r) in readings.iter().enumerate() {
        for (b, &v) in buffer.iter_mut().zip(r.as_ref()) {
            *b = Complex::new(v, 0.0);
        }
        forward.process_with_scratch(&mut buffer, &mut scratch);
        for k in 0..=k_max {
            coeffs[j * (k_max + 1) + k] = buffer[k] * inv_m;
        }
    }

    let zero = Complex::new(0.0, 0.0);
    let mut form_spectrum = vec![zero; k_max + 1];
    let mut motion_x_spectrum = vec![zero; k_max + 1];
    let mut motion_y_spectrum = vec![zero; k_max + 1];
    let mut condition = vec![1.0; k_max + 1];
    let mut blind = Vec::new();
    let mut residual_sq = 0.0;
    let mut error_ms = [0.0; 3];
    // Σ v²/ν per profile, for Welch–Satterthwaite.
    let mut spread = [0.0; 3];
    let mut unchecked = Vec::new();
    let mut rhs = DVector::from_element(p, zero);
    for k in 1..=k_max {
        let design = HarmonicDesign::new(azimuths, model, k);
        condition[k] = design.condition;
        if !within(design.condition, limit) {
            blind.push(k);
            continue;
        }
        for j in 0..p {
            rhs[j] = coeffs[j * (k_max + 1) + k];
        }
        let Some(x) = design.solve(&rhs) else {
            blind.push(k);
            continue;
        };
        // Residual of the scaled system equals that of the unscaled one.
        let fitted = &design.scaled * &x;
        let misfit = (&rhs - fitted).norm_squared();
        residual_sq += misfit;
        let unknowns = design.scale.len();
        if p > unknowns {
            let variance = misfit / (p - unknowns) as Real;
            let dof = 2.0 * (p - unknowns) as Real;
            let gains = design.variance_gains();
            let slots: &[usize] = match (model, k) {
                (Model::TwoDirection, 1) => &[1, 2],
                (Model::TwoDirection, _) => &[1, 2, 0],
                (Model::SingleWhirl, 1) => &[1],
                (Model::SingleWhirl, _) => &[1, 0],
            };
            // Column c estimates profile slots[c] (0 form, 1 E_X, 2 E_Y); a single whirl's
            // E_Y is −i E_X, as uncertain.
            for (c, &slot) in slots.iter().enumerate() {
                let v = 2.0 * variance * gains[c];
                let targets: &[usize] = if model == Model::SingleWhirl && slot == 1 {
                    &[1, 2]
                } else {
                    std::slice::from_ref(&slots[c])
                };
                for &t in targets {
                    error_ms[t] += v;
                    spread[t] += v * v / dof;
                }
            }
        } else {
            unchecked.push(k);
        }
        let unknowns: Vec<Complex> = x.iter().zip(&design.scale).map(|(y, s)| y / *s).collect();
        let (xk, yk, gk) = match (model, k) {
            (Model::TwoDirection, 1) => (unknowns[0], unknowns[1], zero),
            (Model::TwoDirection, _) => (unknowns[0], unknowns[1], unknowns[2]),
            (Model::SingleWhirl, 1) => (unknowns[0], -Complex::i() * unknowns[0], zero),
            (Model::SingleWhirl, _) => (unknowns[0], -Complex::i() * unknowns[0], unknowns[1]),
        };
        motion_x_spectrum[k] = xk;
        motion_y_spectrum[k] = yk;
        // The fitted coefficient is H_{−k}; h is real, so H_k = conj(H_{−k}).
        form_spectrum[k] = gk.conj();
    }

    let inverse = planner.plan_fft_inverse(m_len);
    let mut scratch = vec![zero; inverse.get_inplace_scratch_len()];
    let mut synthesise = |spectrum: &[Complex]| -> Vec<Real> {
        buffer.iter_mut().for_each(|b| *b = zero);
        for (k, &c) in spectrum.iter().enumerate().skip(1) {
            buffer[k] = c;
            buffer[m_len - k] = c.conj();
        }
        inverse.process_with_scratch(&mut buffer, &mut scratch);
        buffer.iter().map(|c| c.re).collect()
    };
    let form = synthesise(&form_spectrum);
    let motion_x = synthesise(&motion_x_spectrum);
    let motion_y = synthesise(&motion_y_spectrum);

    Ok(Separation {
        model,
        k_max,
        form,
        motion_x,
        motion_y,
        form_spectrum,
        motion_x_spectrum,
        motion_y_spectrum,
        blind,
        condition,
        // Parseval: harmonics k and M − k each carry |c_k|².
        residual_rms: (2.0 * residual_sq / p as Real).sqrt(),
        misfit_error_rms: error_ms.map(Real::sqrt),
        misfit_dof: std::array::from_fn(|i| {
            if spread[i] > 0.0 {
                error_ms[i] * error_ms[i] / spread[i]
            } else {
                Real::INFINITY
            }
        }),
        unchecked,
    })
}

/// Condition numbers of a layout's column-scaled per-harmonic designs, index k = 0..=k_max
/// (entry 0 is 1: nothing is estimated at k = 0; entry 1 is the design without the form
/// column). Infinite where the design is rank-deficient (fewer probes than unknowns, a zero
/// column, exact dependence) or an azimuth is not finite.
pub fn condition_numbers(azimuths: &[Real], model: Model, k_max: usize) -> Vec<Real> {
    let mut condition = vec![1.0; k_max + 1];
    for (k, c) in condition.iter_mut().enumerate().skip(1) {
        *c = if azimuths.iter().all(|a| a.is_finite()) {
            HarmonicDesign::new(azimuths, model, k).condition
        } else {
            Real::INFINITY
        };
    }
    condition
}

/// The harmonics 1..=k_max that the layout `azimuths` cannot separate under `model`: those
/// whose column-scaled design has a condition number above `limit` (or not finite).
///
/// Harmonic 1 appears only for a degenerate layout (e.g. all probes on one line), since its
/// design holds the motion alone. With fewer than 3 probes every harmonic from 2 up is blind.
pub fn blind_harmonics(azimuths: &[Real], model: Model, k_max: usize, limit: Real) -> Vec<usize> {
    condition_numbers(azimuths, model, k_max)
        .iter()
        .enumerate()
        .skip(1)
        .filter(|(_, c)| !within(**c, limit))
        .map(|(k, _)| k)
        .collect()
}

/// The harmonics of `blind` at which some probe's synchronous profile (`profiles`, one per
/// probe on the θ grid) holds more than its noise: where form or motion is present but the
/// layout cannot tell which, so neither is known.
///
/// At a blind harmonic the design has a null combination of form and motion that no probe
/// reads; a form and a motion that cancel in every probe is a coincidence of no physical
/// source, so a blind harmonic at which every probe reads only noise holds neither. The
/// noise level of each probe is taken from the median amplitude of its harmonics 2 up to
/// Nyquist (most of which hold none): for a Rayleigh amplitude of scale σ the median is
/// σ·√(2 ln 2), and noise alone exceeds σ·√(2 ln(N/0.05)) at any of the N = probes × blind
/// harmonics tested with probability at most 5 %. Amplitudes under 1 pm count as none
/// (rounding in a noise-free record).
pub fn blind_with_content<R: AsRef<[Real]>>(profiles: &[R], blind: &[usize]) -> Vec<usize> {
    if blind.is_empty() || profiles.is_empty() {
        return Vec::new();
    }
    let tests = (profiles.len() * blind.len()) as Real;
    let factor = (2.0 * (tests / 0.05).ln()).sqrt() / (2.0 * std::f64::consts::LN_2).sqrt();
    let mut planner = FftPlanner::new();
    let spectra: Vec<(Vec<Real>, Real)> = profiles
        .iter()
        .map(|profile| {
            let profile = profile.as_ref();
            let m = profile.len();
            let mut buffer: Vec<rustfft::num_complex::Complex<Real>> = profile
                .iter()
                .map(|&v| rustfft::num_complex::Complex::new(v, 0.0))
                .collect();
            planner.plan_fft_forward(m).process(&mut buffer);
            let amplitudes: Vec<Real> = buffer
                .iter()
                .take(m.div_ceil(2))
                .map(|c| 2.0 * c.norm() / m as Real)
                .collect();
            let median = crate::io::plausible::median(amplitudes.iter().skip(2).copied().collect())
                .unwrap_or(0.0);
            (amplitudes, (factor * median).max(1e-12))
        })
        .collect();
    blind
        .iter()
        .copied()
        .filter(|&k| {
            spectra
                .iter()
                .any(|(amplitudes, level)| amplitudes.get(k).is_some_and(|a| a > level))
        })
        .collect()
}

/// Whether a condition number is within the limit (false for NaN and infinity).
fn within(condition: Real, limit: Real) -> bool {
    condition <= limit
}

/// Norm (per √P) below which a design column counts as zero: azimuths within 1e-10 rad of
/// making it vanish, far below any probe's angular placement.
const ZERO_COLUMN: Real = 1e-10;

/// One harmonic's least-squares problem: the column-scaled design and its SVD.
struct HarmonicDesign {
    scaled: DMatrix<Complex>,
    scale: Vec<Real>,
    svd: Option<nalgebra::SVD<Complex, nalgebra::Dyn, nalgebra::Dyn>>,
    condition: Real,
}

impl HarmonicDesign {
    fn new(azimuths: &[Real], model: Model, k: usize) -> Self {
        let p = azimuths.len();
        let kf = k as Real;
        let cols = match (model, k) {
            (Model::TwoDirection, 1) => 2,
            (Model::TwoDirection, _) => 3,
            (Model::SingleWhirl, 1) => 1,
            (Model::SingleWhirl, _) => 2,
        };
        let mut a = DMatrix::from_fn(p, cols, |j, c| {
            let phi = azimuths[j];
            let form = -Complex::from_polar(1.0, -kf * phi);
            match (model, c) {
                (Model::TwoDirection, 0) => Complex::new(-phi.cos(), 0.0),
                (Model::TwoDirection, 1) => Complex::new(-phi.sin(), 0.0),
                (Model::SingleWhirl, 0) => -Complex::from_polar(1.0, -phi),
                _ => form,
            }
        });
        let scale: Vec<Real> = (0..cols).map(|c| a.column(c).norm()).collect();
        // Entries are of modulus ≤ 1; a column this small is zero up to the round-off of
        // sin/cos (e.g. the sine column of probes at 0 and π), and scaling it up to unit norm
        // would hide the rank deficiency.
        let tiny = ZERO_COLUMN * (p as Real).sqrt();
        let degenerate = p < cols || scale.iter().any(|s| s.is_nan() || *s <= tiny);
        if degenerate {
            return Self {
                scaled: a,
                scale,
                svd: None,
                condition: Real::INFINITY,
            };
        }
        for (c, s) in scale.iter().enumerate() {
            a.column_mut(c).iter_mut().for_each(|v| *v /= *s);
        }
        let svd = mtwin_kernels::linalg::complex_svd(a.clone(), true, true);
        let sv = &svd.singular_values;
        let max = sv.iter().copied().fold(0.0, Real::max);
        let min = sv.iter().copied().fold(Real::INFINITY, Real::min);
        let condition = if min > 0.0 { max / min } else { Real::INFINITY };
        Self {
            scaled: a,
            scale,
            svd: Some(svd),
            condition,
        }
    }

    /// `[(AᴴA)⁻¹]_cc` of the unscaled design, column by column: the variance of unknown `c`
    /// per unit variance of each probe's coefficient (`Σ_i |V_ci|²/σ_i²`, over the column
    /// scale squared).
    fn variance_gains(&self) -> Vec<Real> {
        let Some(svd) = &self.svd else {
            return vec![Real::INFINITY; self.scale.len()];
        };
        let v_t = svd.v_t.as_ref().expect("computed with V");
        (0..self.scale.len())
            .map(|c| {
                let sum: Real = svd
                    .singular_values
                    .iter()
                    .enumerate()
                    .map(|(i, sigma)| v_t[(i, c)].norm_sqr() / (sigma * sigma))
                    .sum();
                sum / (self.scale[c] * self.scale[c])
            })
            .collect()
    }

    /// Least-squares solution of the scaled system, or `None` if it cannot be formed.
    fn solve(&self, rhs: &DVector<Complex>) -> Option<DVector<Complex>> {
        mtwin_kernels::linalg::complex_svd_solve(self.svd.as_ref()?, rhs, 0.0).ok()
    }
}

/// Tilt error motion from the radial error motions at two heights.
#[derive(Clone, Debug, PartialEq)]
pub struct Tilt {
    /// Rotation about x, `E_A(θ_m)` (rad): `−(E_Y(z_upper) − E_Y(z_lower)) / (z_upper − z_lower)`.
    pub about_x: Vec<Real>,
    /// Rotation about y, `E_B(θ_m)` (rad): `(E_X(z_upper) − E_X(z_lower)) / (z_upper − z_lower)`.
    pub about_y: Vec<Real>,
}

/// Tilt error motion (ISO 230-7 tilt, small angles) from the radial error motions
/// `(E_X, E_Y)` separated at two stations at heights `z_lower`, `z_upper` along the axis.
///
/// A small rotation `(E_A, E_B)` moves the axis point at height z by
/// `(E_B·z, −E_A·z)`, so differences between the stations give the rotations; the
/// translation common to both stations cancels.
pub fn tilt_from_stations(
    lower: (&[Real], &[Real]),
    upper: (&[Real], &[Real]),
    z_lower: Real,
    z_upper: Real,
) -> Result<Tilt, SeparationError> {
    let dz = z_upper - z_lower;
    if !dz.is_finite() || dz == 0.0 {
        return Err(SeparationError::Stations(z_lower, z_upper));
    }
    let m_len = lower.0.len();
    check_len("lower E_Y", m_len, lower.1.len())?;
    check_len("upper E_X", m_len, upper.0.len())?;
    check_len("upper E_Y", m_len, upper.1.len())?;
    check_finite("lower E_X", lower.0)?;
    check_finite("lower E_Y", lower.1)?;
    check_finite("upper E_X", upper.0)?;
    check_finite("upper E_Y", upper.1)?;
    Ok(Tilt {
        about_x: lower
            .1
            .iter()
            .zip(upper.1)
            .map(|(l, u)| -(u - l) / dz)
            .collect(),
        about_y: lower
            .0
            .iter()
            .zip(upper.0)
            .map(|(l, u)| (u - l) / dz)
            .collect(),
    })
}

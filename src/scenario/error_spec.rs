//! The `[errors.NAME]` table as written (file units), before any check: the terms of the
//! error function ([`ErrorSpec`] and its parts), the time- and speed-dependent terms, and the
//! terms that measured inputs drive (the `temperature`, `heating` and `drift` keys, see
//! [`super::inputs`]). The error model ([`super::errors`]) and the inputs' terms
//! ([`super::inputs`]) both read these, and neither imports the other's file for them.

use super::ScenarioErrorKind;
use crate::math::Real;
use serde::{Deserialize, Serialize};

/// The terms of one error parameter, in file units (the `[errors.NAME]` table).
#[derive(Debug, Clone, Default, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct ErrorSpec {
    /// Constant (translations).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub constant_um: Option<Real>,
    /// Constant (rotations).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub constant_urad: Option<Real>,
    /// Polynomial coefficients from degree 0, in µm per (mm or deg)^k.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub polynomial_um: Option<Vec<Real>>,
    /// Polynomial coefficients from degree 0, in µrad per (mm or deg)^k.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub polynomial_urad: Option<Vec<Real>>,
    /// Lost motion (the axis lags the command by half of it against its direction of travel).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub reversal_um: Option<Real>,
    /// Angular lost motion.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub reversal_urad: Option<Real>,
    /// Cyclic errors.
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub harmonic: Vec<HarmonicSpec>,
    /// A measured map.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub table: Option<TableSpec>,
    /// Asynchronous sinusoids: time-dependent content (see [`crate::errors::Dynamics`]).
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub asynchronous: Vec<SinusoidSpec>,
    /// Band-limited random motion.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub random: Option<RandomSpec>,
    /// A factor on the whole parameter against the speed of its axis.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub speed: Option<SpeedSpec>,
    /// Terms driven by a measured sensor's temperature (see [`super::inputs`]).
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub temperature: Vec<TemperatureTermSpec>,
    /// Terms from heat sources no sensor sees.
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub heating: Vec<HeatingTermSpec>,
    /// Drifts linear in time.
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub drift: Vec<DriftTermSpec>,
}

/// `amplitude · sin(2π · frequency_hz · t + phase)` or `amplitude · sin(per_revolution · q +
/// phase)` with `q` the axis's unwrapped angle.
#[derive(Debug, Clone, Default, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct SinusoidSpec {
    /// Amplitude (translations).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub amplitude_um: Option<Real>,
    /// Amplitude (rotations).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub amplitude_urad: Option<Real>,
    /// Frequency in Hz.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub frequency_hz: Option<Real>,
    /// Frequency in cycles per revolution of the axis (axes of rotation).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub per_revolution: Option<Real>,
    /// Phase at time zero (angle zero).
    #[serde(default)]
    pub phase_deg: Real,
}

/// Band-limited random motion of a given RMS, flat in its band.
#[derive(Debug, Clone, Default, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct RandomSpec {
    /// RMS (translations).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub rms_um: Option<Real>,
    /// RMS (rotations).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub rms_urad: Option<Real>,
    /// The band in Hz, `[low, high]`.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub band_hz: Option<[Real; 2]>,
    /// The band in cycles per revolution of the axis, `[low, high]`.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub band_per_revolution: Option<[Real; 2]>,
}

/// A factor on the whole parameter at knots of the axis speed (magnitude), interpolated
/// linearly, end values held.
#[derive(Debug, Clone, Default, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct SpeedSpec {
    /// Speeds of an axis of rotation (min⁻¹).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub rpm: Option<Vec<Real>>,
    /// Speeds of a linear axis (mm/min).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub mm_per_min: Option<Vec<Real>>,
    /// The factor at each speed.
    pub factor: Vec<Real>,
}

/// `amplitude · sin(360° · q / period + phase)`.
#[derive(Debug, Clone, Default, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct HarmonicSpec {
    /// Period along a linear axis.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub period_mm: Option<Real>,
    /// Period about a rotary axis.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub period_deg: Option<Real>,
    /// Amplitude (translations).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub amplitude_um: Option<Real>,
    /// Amplitude (rotations).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub amplitude_urad: Option<Real>,
    /// Phase at q = 0.
    #[serde(default)]
    pub phase_deg: Real,
}

/// Values at knots, interpolated linearly or by a natural cubic spline; end values held
/// outside.
#[derive(Debug, Clone, Default, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct TableSpec {
    /// Knots along a linear axis.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub positions_mm: Option<Vec<Real>>,
    /// Knots about a rotary axis.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub positions_deg: Option<Vec<Real>>,
    /// Values (translations).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub values_um: Option<Vec<Real>>,
    /// Values (rotations).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub values_urad: Option<Vec<Real>>,
    /// `linear` (default) or `cubic`.
    #[serde(default)]
    pub interpolation: InterpolationSpec,
}

/// Table interpolation as written in files.
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "lowercase")]
pub enum InterpolationSpec {
    /// Straight lines.
    #[default]
    Linear,
    /// Natural cubic spline.
    Cubic,
}

/// A term driven by a measured sensor's temperature: `c · (T_lagged − reference)`.
#[derive(Debug, Clone, Default, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct TemperatureTermSpec {
    /// The sensor (a `temp_<sensor>_degc` column of `[inputs] temperatures`).
    pub sensor: String,
    /// The temperature at which the term is zero (°C).
    pub reference_degc: Real,
    /// Time constant of the structure behind the sensor (min); none by default.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub lag_min: Option<Real>,
    /// Time constant of the sensor behind the structure (min); none by default: the term
    /// reads `T + τ·dT/dt`, the rate from the record's neighbouring samples
    /// ([`crate::math::local_rates`]).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub sensor_lag_min: Option<Real>,
    /// µm per °C (translations).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub um_per_degc: Option<Real>,
    /// µm per metre of travel per °C: an expansion (translations).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub um_per_m_per_degc: Option<Real>,
    /// µrad per °C (rotations).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub urad_per_degc: Option<Real>,
    /// µrad per metre of travel per °C (rotations).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub urad_per_m_per_degc: Option<Real>,
}

/// A heat source no sensor sees: `c · (1 − e^(−(t − from)/τ))` from `from_min` on.
#[derive(Debug, Clone, Default, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct HeatingTermSpec {
    /// Time constant (min).
    pub tau_min: Real,
    /// When it starts (min from the start); 0 by default.
    #[serde(default)]
    pub from_min: Real,
    /// Final value (µm, translations).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub um: Option<Real>,
    /// Final value per metre of travel (µm/m, translations).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub um_per_m: Option<Real>,
    /// Final value (µrad, rotations).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub urad: Option<Real>,
    /// Final value per metre of travel (µrad/m, rotations).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub urad_per_m: Option<Real>,
}

/// A drift linear in time: `c · (t − from)`.
#[derive(Debug, Clone, Default, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct DriftTermSpec {
    /// When the drift is zero (min from the start); 0 by default.
    #[serde(default)]
    pub from_min: Real,
    /// µm per hour (translations).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub um_per_h: Option<Real>,
    /// µm per metre of travel per hour (translations).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub um_per_m_per_h: Option<Real>,
    /// µrad per hour (rotations).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub urad_per_h: Option<Real>,
    /// µrad per metre of travel per hour (rotations).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub urad_per_m_per_h: Option<Real>,
}

/// What is wrong with one key of an `[errors.NAME]` table: the kind, the key's path inside the
/// table (e.g. `table.positions_deg`) and the message.
pub(crate) type SpecError = (ScenarioErrorKind, String, String);

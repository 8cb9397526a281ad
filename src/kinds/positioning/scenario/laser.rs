//! The `[laser]` section: the interferometer that measures a laser test, its set-up, air and
//! material compensation, noise and zeroing.
//!
//! ```toml
//! [laser]
//! beam_offset_mm = [0.0, 0.0, 60.0]   # reflector from the tool tip, tool frame (Abbe offset)
//! misalignment_urad = [0.0, 0.0]      # beam tilt towards the two other axes, ISO order (cosine error)
//! resolution_nm = 1.0
//! noise_nm = 10.0
//! compensation = "sensors"            # or "off": standard air assumed
//! air = { temperature_degc = 20.0, pressure_hpa = 1013.25, humidity_pct = 50.0 }
//! sensor_offsets = { temperature_degc = 0.0, pressure_hpa = 0.0, humidity_pct = 0.0 }
//! material = { expansion_ppm_per_degc = 11.7, temperature_degc = 20.0 }   # NDE, optional
//! dead_path_mm = 100.0                # beam length at the zero (matters when the air changes)
//! zero = "each_run"                   # or "once" (drift tests)
//! interferometer_on = "workpiece"     # or "tool" (the reverse set-up)
//! ```

use crate::kinds::positioning::air::Air;
use crate::kinds::positioning::laser::{AirCompensation, Laser, MaterialCompensation};
use crate::kinds::positioning::setup::{Mounting, Zeroing};
use crate::machine::Axis;
use crate::math::{M_PER_MM, RAD_PER_URAD, Real, Vector};
use crate::scenario::bounds::{self, Bound};
use crate::scenario::{Context, ScenarioError, ScenarioErrorKind};
use serde::Deserialize;
use toml::Spanned;

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
pub(crate) struct RawLaser {
    #[serde(default)]
    beam_offset_mm: Option<Spanned<[Real; 3]>>,
    #[serde(default)]
    misalignment_urad: Option<Spanned<[Real; 2]>>,
    #[serde(default = "default_resolution")]
    resolution_nm: Spanned<Real>,
    #[serde(default)]
    noise_nm: Option<Spanned<Real>>,
    #[serde(default)]
    compensation: Option<Spanned<String>>,
    #[serde(default)]
    air: Option<Spanned<RawAir>>,
    #[serde(default)]
    sensor_offsets: Option<Spanned<RawAir>>,
    #[serde(default)]
    material: Option<Spanned<RawMaterial>>,
    /// `each_run` (default) or `once`.
    #[serde(default)]
    zero: Option<Spanned<String>>,
    #[serde(default)]
    dead_path_mm: Option<Spanned<Real>>,
    /// `workpiece` (default) or `tool`.
    #[serde(default)]
    interferometer_on: Option<Spanned<String>>,
}

fn default_resolution() -> Spanned<Real> {
    Spanned::new(0..0, 1.0)
}

#[derive(Deserialize, Clone, Copy, Default)]
#[serde(deny_unknown_fields)]
struct RawAir {
    temperature_degc: Option<Real>,
    pressure_hpa: Option<Real>,
    humidity_pct: Option<Real>,
}

#[derive(Deserialize, Clone)]
#[serde(deny_unknown_fields)]
struct RawMaterial {
    expansion_ppm_per_degc: Real,
    /// A fixed material temperature…
    temperature_degc: Option<Real>,
    /// …or a sensor on a node of the thermal model, with its offset.
    node: Option<String>,
    #[serde(default)]
    offset_degc: Real,
}

/// The first key of `[laser]` that a drift test (ISO 230-3 §7.2.5: air compensation on, NDE
/// off, zeroed once at the start) cannot honour, with its span and why.
pub(crate) fn drift_conflict(raw: &Spanned<RawLaser>) -> Option<(std::ops::Range<usize>, String)> {
    let l = raw.get_ref();
    if let Some(c) = l.compensation.as_ref().filter(|c| c.get_ref() == "off") {
        return Some((
            c.span(),
            "laser.compensation: a drift test uses the air compensation (ISO 230-3 §7.2.5)".into(),
        ));
    }
    if let Some(m) = &l.material {
        return Some((m.span(), "laser.material: a drift test does not use NDE, which would hide the scale's expansion (ISO 230-3 §7.2.5)".into()));
    }
    if let Some(z) = l.zero.as_ref().filter(|z| z.get_ref() != "once") {
        return Some((
            z.span(),
            "laser.zero: a drift test is zeroed once, at the start".into(),
        ));
    }
    None
}

/// The span of `[laser] air.temperature_degc`, when given.
pub(crate) fn air_temperature_given(raw: &Spanned<RawLaser>) -> Option<std::ops::Range<usize>> {
    let l = raw.get_ref();
    l.air
        .as_ref()
        .filter(|a| a.get_ref().temperature_degc.is_some())
        .map(|a| a.span())
}

/// Whether `[laser]` says when to zero.
pub(crate) fn zero_given(raw: Option<&Spanned<RawLaser>>) -> bool {
    raw.is_some_and(|r| r.get_ref().zero.is_some())
}

/// The laser of the `[laser]` section on `axis` with its material sensor's node, or an ideal
/// laser (1 nm resolution, no noise, exact air compensation, reflector at the tool tip) without
/// the section.
pub(crate) fn laser_for(
    context: &Context<'_>,
    axis: Axis,
    raw: Option<&Spanned<RawLaser>>,
) -> Result<(Laser, Option<(String, Real)>), ScenarioError> {
    match raw {
        Some(raw) => laser_spec(context, axis, raw),
        None => Ok((
            Laser {
                axis,
                beam_offset: Vector::ZERO,
                misalignment: [0.0, 0.0],
                resolution: 1e-9,
                noise: 0.0,
                air: Air::STANDARD,
                compensation: AirCompensation::Sensors {
                    temperature_offset: 0.0,
                    pressure_offset: 0.0,
                    humidity_offset: 0.0,
                },
                material: None,
                dead_path: 0.0,
                zero: Zeroing::EachRun,
                mounting: Mounting::InterferometerOnWorkpiece,
            },
            None,
        )),
    }
}

fn laser_spec(
    context: &Context<'_>,
    axis: Axis,
    raw: &Spanned<RawLaser>,
) -> Result<(Laser, Option<(String, Real)>), ScenarioError> {
    let l = raw.get_ref();
    let fail = |span: std::ops::Range<usize>, key: &str, message: String| {
        let span = if span.is_empty() { raw.span() } else { span };
        context.error(
            Some(span),
            ScenarioErrorKind::Value,
            format!("laser.{key}: {message}"),
        )
    };
    let within = |values: &[Real],
                  bound: Bound,
                  span: std::ops::Range<usize>,
                  key: &str|
     -> Result<(), ScenarioError> {
        bound
            .check_each(values)
            .map_err(|message| fail(span, key, message))
    };
    let beam_offset = match &l.beam_offset_mm {
        Some(v) => {
            within(v.get_ref(), bounds::OFFSET_MM, v.span(), "beam_offset_mm")?;
            Vector::from_array(*v.get_ref()) * M_PER_MM
        }
        None => Vector::ZERO,
    };
    let misalignment = match &l.misalignment_urad {
        Some(v) => {
            within(
                v.get_ref(),
                bounds::MISALIGNMENT_URAD,
                v.span(),
                "misalignment_urad",
            )?;
            v.get_ref().map(|m| m * RAD_PER_URAD)
        }
        None => [0.0, 0.0],
    };
    let one = |v: &Spanned<Real>, bound: Bound, key: &str| -> Result<Real, ScenarioError> {
        within(&[*v.get_ref()], bound, v.span(), key).map(|()| *v.get_ref())
    };
    let resolution = one(&l.resolution_nm, bounds::RESOLUTION_NM, "resolution_nm")? * 1e-9;
    let noise = match &l.noise_nm {
        Some(v) => one(v, bounds::NOISE_NM, "noise_nm")? * 1e-9,
        None => 0.0,
    };
    let air_raw = l.air.as_ref().map(|a| *a.get_ref()).unwrap_or_default();
    let air = Air {
        temperature: air_raw
            .temperature_degc
            .unwrap_or(Air::STANDARD.temperature),
        pressure: air_raw
            .pressure_hpa
            .map_or(Air::STANDARD.pressure, |p| p * 100.0),
        humidity: air_raw.humidity_pct.unwrap_or(Air::STANDARD.humidity),
    };
    let air_span = l.air.as_ref().map_or(0..0, |a| a.span());
    let plausible_air = (-10.0..=60.0).contains(&air.temperature)
        && (50_000.0..=120_000.0).contains(&air.pressure)
        && (0.0..=100.0).contains(&air.humidity);
    if !plausible_air {
        return Err(fail(
            air_span,
            "air",
            "expected -10..60 °C, 500..1200 hPa, 0..100 %RH".into(),
        ));
    }
    let offsets = l
        .sensor_offsets
        .as_ref()
        .map(|a| *a.get_ref())
        .unwrap_or_default();
    let offset_values = [
        offsets.temperature_degc,
        offsets.pressure_hpa,
        offsets.humidity_pct,
    ]
    .map(|v| v.unwrap_or(0.0));
    within(
        &offset_values,
        Bound::symmetric(1000.0, "a sensor that far off is broken"),
        l.sensor_offsets.as_ref().map_or(0..0, |a| a.span()),
        "sensor_offsets",
    )?;
    let assumed = Air {
        temperature: air.temperature + offset_values[0],
        pressure: air.pressure + offset_values[1] * 100.0,
        humidity: air.humidity + offset_values[2],
    };
    let plausible_assumed = (-10.0..=60.0).contains(&assumed.temperature)
        && (50_000.0..=120_000.0).contains(&assumed.pressure)
        && (0.0..=100.0).contains(&assumed.humidity);
    if !plausible_assumed {
        let span = l.sensor_offsets.as_ref().map_or(0..0, |a| a.span());
        return Err(fail(
            span,
            "sensor_offsets",
            "the sensors would read beyond -10..60 °C, 500..1200 hPa or 0..100 %RH".into(),
        ));
    }
    let compensation = match l.compensation.as_ref().map(|c| c.get_ref().as_str()) {
        None | Some("sensors") => AirCompensation::Sensors {
            temperature_offset: offset_values[0],
            pressure_offset: offset_values[1] * 100.0,
            humidity_offset: offset_values[2],
        },
        Some("off") => AirCompensation::Off,
        Some(other) => {
            let span = l.compensation.as_ref().map_or(0..0, |c| c.span());
            return Err(fail(
                span,
                "compensation",
                format!("\"{other}\": expected \"sensors\" or \"off\""),
            ));
        }
    };
    let (material, material_sensor) = match &l.material {
        Some(m) => {
            let RawMaterial {
                expansion_ppm_per_degc,
                temperature_degc,
                node,
                offset_degc,
            } = m.get_ref().clone();
            let material = |values: &[Real], bound: Bound, key: &str| {
                within(values, bound, m.span(), &format!("material.{key}"))
            };
            material(
                &[expansion_ppm_per_degc],
                bounds::EXPANSION_PPM_PER_DEGC,
                "expansion_ppm_per_degc",
            )?;
            material(
                &[offset_degc],
                Bound::symmetric(50.0, "a sensor that far off is broken"),
                "offset_degc",
            )?;
            if let Some(t) = temperature_degc {
                material(&[t], bounds::TEMPERATURE_DEGC, "temperature_degc")?;
            }
            let sensor = match (temperature_degc, node) {
                (Some(_), None) => None,
                (None, Some(node)) => Some((node, offset_degc)),
                _ => {
                    return Err(fail(
                        m.span(),
                        "material",
                        "give either temperature_degc or node (a thermal-model node)".into(),
                    ));
                }
            };
            let fixed = temperature_degc.unwrap_or(20.0);
            (
                Some(MaterialCompensation {
                    expansion: expansion_ppm_per_degc * 1e-6,
                    measured_temperature: fixed,
                }),
                sensor,
            )
        }
        None => (None, None),
    };
    let dead_path = match &l.dead_path_mm {
        Some(v) => {
            let bound = Bound {
                lo: 0.0,
                hi: 80_000.0,
                why: "80 m: the longest laser paths",
            };
            one(v, bound, "dead_path_mm")? * M_PER_MM
        }
        None => 0.0,
    };
    let zero = match l.zero.as_ref().map(|z| z.get_ref().as_str()) {
        None | Some("each_run") => Zeroing::EachRun,
        Some("once") => Zeroing::Once,
        Some(other) => {
            let span = l.zero.as_ref().map_or(0..0, |z| z.span());
            return Err(fail(
                span,
                "zero",
                format!("\"{other}\": expected \"each_run\" or \"once\""),
            ));
        }
    };
    let mounting = match l.interferometer_on.as_ref().map(|m| m.get_ref().as_str()) {
        None | Some("workpiece") => Mounting::InterferometerOnWorkpiece,
        Some("tool") => Mounting::InterferometerOnTool,
        Some(other) => {
            let span = l.interferometer_on.as_ref().map_or(0..0, |m| m.span());
            return Err(fail(
                span,
                "interferometer_on",
                format!("\"{other}\": expected \"workpiece\" or \"tool\""),
            ));
        }
    };
    let laser = Laser {
        axis,
        beam_offset,
        misalignment,
        resolution,
        noise,
        air,
        compensation,
        material,
        dead_path,
        zero,
        mounting,
    };
    Ok((laser, material_sensor))
}

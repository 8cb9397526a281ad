//! The time- and speed-dependent terms of `[errors.NAME]` (`asynchronous`, `random`,
//! `speed`), checked and turned into the parameter's [`Dynamics`].

use crate::errors::{
    Dynamics, Frequency, Interpolation, ParameterName, RandomMotion, Sinusoid, Table,
};
use crate::math::{RAD_PER_URAD, Real};
use crate::scenario::ScenarioErrorKind;
use crate::scenario::bounds::{self, Bound};
use crate::scenario::error_spec::{ErrorSpec, SpecError};

/// The highest frequency of an error motion in cycles per revolution: beyond it the
/// spindle's own probes (and its structure) cannot follow.
const HIGHEST_PER_REVOLUTION: Real = 1000.0;

/// The first time- or speed-dependent key of a spec, for messages.
pub(super) fn dynamic_key(spec: &ErrorSpec) -> &'static str {
    if !spec.asynchronous.is_empty() {
        "asynchronous"
    } else if spec.random.is_some() {
        "random"
    } else {
        "speed"
    }
}

/// Turns the time- and speed-dependent terms of `[errors.NAME]` (`asynchronous`, `random`,
/// `speed`) into [`Dynamics`] (SI); the random motion is realised from `seed`.
pub(super) fn spec_to_dynamics(
    spec: &ErrorSpec,
    name: ParameterName,
    seed: u64,
) -> Result<Dynamics, SpecError> {
    use ScenarioErrorKind::{Units, Value};
    let translation = name.motion().is_translation();
    let (unit, other_unit) = if translation {
        ("um", "urad")
    } else {
        ("urad", "um")
    };
    let rotary = name.axis().is_some_and(|axis| !axis.is_linear());
    let pick =
        |um: Option<Real>, urad: Option<Real>| if translation { (um, urad) } else { (urad, um) };
    let fail = |kind, key: String, message: String| -> SpecError { (kind, key, message) };
    let finite = |key: &str, v: Real| {
        if v.is_finite() {
            Ok(())
        } else {
            Err(fail(Value, key.to_string(), "not a finite number".into()))
        }
    };
    let within = |key: &str, v: Real, bound: Bound| {
        bound
            .check(v)
            .map(|_| ())
            .map_err(|message| fail(Value, key.to_string(), message))
    };
    let amplitude_bound = Bound::symmetric(bounds::AMPLITUDE_UM.hi, bounds::AMPLITUDE_UM.why);
    let frequency_bound = |per_revolution: bool| {
        if per_revolution {
            Bound {
                lo: 0.0,
                hi: HIGHEST_PER_REVOLUTION,
                why: "no error motion of a spindle has more waves a turn",
            }
        } else {
            bounds::FREQUENCY_HZ
        }
    };
    let mut dynamics = Dynamics::default();
    for (i, a) in spec.asynchronous.iter().enumerate() {
        let key = |field: &str| format!("asynchronous[{i}].{field}");
        let (amplitude, other) = pick(a.amplitude_um, a.amplitude_urad);
        if other.is_some() {
            return Err(fail(
                Units,
                key(&format!("amplitude_{other_unit}")),
                format!("{name} is in {unit}; give amplitude_{unit}"),
            ));
        }
        let amplitude_key = key(&format!("amplitude_{unit}"));
        let amplitude =
            amplitude.ok_or_else(|| fail(Value, amplitude_key.clone(), "required".into()))?;
        within(&amplitude_key, amplitude, amplitude_bound)?;
        finite(&key("phase_deg"), a.phase_deg)?;
        let frequency = match (a.frequency_hz, a.per_revolution) {
            (Some(f), None) => {
                within(&key("frequency_hz"), f, frequency_bound(false))?;
                if f <= 0.0 {
                    return Err(fail(
                        Value,
                        key("frequency_hz"),
                        format!("must be positive, got {f}"),
                    ));
                }
                Frequency::Hz(f)
            }
            (None, Some(r)) => {
                within(&key("per_revolution"), r, frequency_bound(true))?;
                if !rotary {
                    return Err(fail(
                        Value,
                        key("per_revolution"),
                        "a frequency per revolution needs an axis of rotation; give frequency_hz"
                            .into(),
                    ));
                }
                if r <= 0.0 {
                    return Err(fail(
                        Value,
                        key("per_revolution"),
                        format!("must be positive, got {r}"),
                    ));
                }
                Frequency::PerRevolution(r)
            }
            _ => {
                return Err(fail(
                    Value,
                    key("frequency_hz"),
                    "give one of frequency_hz or per_revolution".into(),
                ));
            }
        };
        dynamics.sinusoids.push(Sinusoid {
            frequency,
            amplitude: amplitude * RAD_PER_URAD,
            phase: a.phase_deg * crate::math::RAD_PER_DEG,
        });
    }
    if let Some(r) = &spec.random {
        let (rms, other) = pick(r.rms_um, r.rms_urad);
        if other.is_some() {
            return Err(fail(
                Units,
                format!("random.rms_{other_unit}"),
                format!("{name} is in {unit}; give rms_{unit}"),
            ));
        }
        let rms_key = format!("random.rms_{unit}");
        let rms = rms.ok_or_else(|| fail(Value, rms_key.clone(), "required".into()))?;
        within(&rms_key, rms, bounds::AMPLITUDE_UM)?;
        let (band, per_revolution, band_key) = match (r.band_hz, r.band_per_revolution) {
            (Some(b), None) => (b, false, "random.band_hz"),
            (None, Some(b)) if rotary => (b, true, "random.band_per_revolution"),
            (None, Some(_)) => {
                return Err(fail(
                    Value,
                    "random.band_per_revolution".into(),
                    "a band per revolution needs an axis of rotation; give band_hz".into(),
                ));
            }
            _ => {
                return Err(fail(
                    Value,
                    "random.band_hz".into(),
                    "give one of band_hz or band_per_revolution".into(),
                ));
            }
        };
        if !(band[0].is_finite() && band[1].is_finite() && 0.0 <= band[0] && band[0] < band[1]) {
            return Err(fail(
                Value,
                band_key.into(),
                format!(
                    "expected [low, high] with 0 <= low < high, got [{}, {}]",
                    band[0], band[1]
                ),
            ));
        }
        within(band_key, band[1], frequency_bound(per_revolution))?;
        dynamics.random = Some(RandomMotion::realise(
            rms * RAD_PER_URAD,
            (band[0], band[1]),
            per_revolution,
            seed,
            name,
        ));
    }
    if let Some(v) = &spec.speed {
        let (speeds, key, scale) = match (&v.rpm, &v.mm_per_min, rotary) {
            (Some(s), None, true) => (s, "speed.rpm", std::f64::consts::TAU / 60.0),
            (None, Some(s), false) => (s, "speed.mm_per_min", crate::math::M_PER_MM / 60.0),
            _ => {
                let expected = if rotary {
                    "speed.rpm"
                } else {
                    "speed.mm_per_min"
                };
                return Err(fail(
                    Units,
                    expected.into(),
                    format!(
                        "the speeds of axis {} are given as {expected}",
                        name.axis().map_or('?', |a| a.letter())
                    ),
                ));
            }
        };
        let fastest = if rotary {
            Bound {
                lo: 0.0,
                hi: 200_000.0,
                why: "the fastest spindles turn at about 150 000 min⁻¹",
            }
        } else {
            Bound {
                lo: 0.0,
                ..bounds::FEED_MM_PER_MIN
            }
        };
        let factors = Bound {
            lo: 0.0,
            hi: 1000.0,
            why: "a speed multiplies an error motion by at most a thousand",
        };
        for (values, key, bound) in [(speeds, key, fastest), (&v.factor, "speed.factor", factors)] {
            for (i, x) in values.iter().enumerate() {
                bound.check(*x).map_err(|message| {
                    fail(Value, key.into(), format!("value {}: {message}", i + 1))
                })?;
            }
        }
        let table = Table::new(
            speeds.iter().map(|s| s * scale).collect(),
            v.factor.clone(),
            Interpolation::Linear,
        )
        .map_err(|e| fail(Value, key.into(), e.to_string()))?;
        dynamics.speed_factor = Some(table);
    }
    Ok(dynamics)
}

//! The probes: the instrument defaults of `[spindle]`, each `[[spindle.probe]]` (radial,
//! axial or face, where it senses the artefact, its gain, noise, resolution, bandwidth and
//! range), and the nest of ISO 230-7 Fig 12 when none is given.

use super::super::instrument::{Artefact, ArtefactKind, ProbeKind, ProbeSpec};
use super::{M_PER_NM, RawSpindle, bandwidth, number};
use crate::math::{M_PER_MM, M_PER_UM, RAD_PER_DEG, Real};
use crate::scenario::{Checker, ScenarioError};
use serde::Deserialize;
use toml::Spanned;

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
pub(super) struct RawProbe {
    name: Spanned<String>,
    kind: Spanned<String>,
    azimuth_deg: Option<Spanned<Real>>,
    height_mm: Option<Spanned<Real>>,
    radius_mm: Option<Spanned<Real>>,
    gain_error: Option<Spanned<Real>>,
    noise_nm: Option<Spanned<Real>>,
    resolution_nm: Option<Spanned<Real>>,
    bandwidth_hz: Option<Spanned<Real>>,
    range_um: Option<Spanned<Real>>,
}

/// The instrument defaults of the section, which each probe may override.
struct ProbeDefaults {
    noise: Real,
    resolution: Real,
    bandwidth: Option<Real>,
    range: Real,
}

/// The probes of the section on `artefact`: those given, each named once, else the default
/// nest; with the section's instrument defaults.
pub(super) fn probes(
    check: &Checker<'_>,
    s: &RawSpindle,
    artefact: &Artefact,
) -> Result<Vec<ProbeSpec>, ScenarioError> {
    let defaults = ProbeDefaults {
        noise: number(check, &s.noise_nm, "noise_nm", 2.0, (0.0, false, 1e6))? * M_PER_NM,
        resolution: number(
            check,
            &s.resolution_nm,
            "resolution_nm",
            0.1,
            (0.0, false, 1e6),
        )? * M_PER_NM,
        bandwidth: bandwidth(check, &s.bandwidth_hz, "bandwidth_hz", Some(10_000.0))?,
        range: number(check, &s.range_um, "range_um", 50.0, (0.0, true, 1e4))? * M_PER_UM,
    };
    if s.probe.is_empty() {
        return Ok(default_nest(artefact, &defaults));
    }
    let mut probes: Vec<ProbeSpec> = Vec::new();
    for (index, p) in s.probe.iter().enumerate() {
        let probe = probe(check, index, p, artefact, &defaults)?;
        if probes.iter().any(|other| other.name == probe.name) {
            return Err(check.fail(
                Some(p.get_ref().name.span()),
                &format!("probe[{index}].name"),
                format!("\"{}\" is given twice", probe.name),
            ));
        }
        probes.push(probe);
    }
    Ok(probes)
}

/// The five-probe nest of ISO 230-7 Fig 12 (three probes on a single sphere).
fn default_nest(artefact: &Artefact, d: &ProbeDefaults) -> Vec<ProbeSpec> {
    let second = match artefact.kind {
        ArtefactKind::Sphere => None,
        ArtefactKind::TwoSpheres { separation } => Some(separation),
        ArtefactKind::Cylinder { length } => Some(length),
    };
    let spec = |name: &str, kind| ProbeSpec {
        name: name.into(),
        kind,
        gain_error: 0.0,
        noise: d.noise,
        resolution: d.resolution,
        bandwidth: d.bandwidth,
        range: d.range,
    };
    let radial = |azimuth_deg: Real, height| ProbeKind::Radial {
        azimuth: azimuth_deg * RAD_PER_DEG,
        height,
    };
    let mut probes = vec![spec("x1", radial(0.0, 0.0)), spec("y1", radial(90.0, 0.0))];
    if let Some(h) = second {
        probes.push(spec("x2", radial(0.0, h)));
        probes.push(spec("y2", radial(90.0, h)));
    }
    probes.push(spec("z", ProbeKind::Axial));
    probes
}

/// One `[[spindle.probe]]` entry.
fn probe(
    check: &Checker<'_>,
    index: usize,
    raw: &Spanned<RawProbe>,
    artefact: &Artefact,
    d: &ProbeDefaults,
) -> Result<ProbeSpec, ScenarioError> {
    let p = raw.get_ref();
    let key = |field: &str| format!("probe[{index}].{field}");
    let name = p.name.get_ref().trim().to_string();
    let valid = name.starts_with(|c: char| c.is_ascii_lowercase())
        && name
            .chars()
            .all(|c| c.is_ascii_lowercase() || c.is_ascii_digit() || c == '_');
    if !valid {
        return Err(check.fail(
            Some(p.name.span()),
            &key("name"),
            format!(
                "\"{name}\": expected lower-case letters, digits and _, starting with a letter (it names the column NAME_um)"
            ),
        ));
    }
    let kind_name = p.kind.get_ref().as_str();
    let unused = |value: &Option<Spanned<Real>>, field: &str| match value {
        Some(v) => Err(check.fail(
            Some(v.span()),
            &key(field),
            format!(
                "{} {kind_name} probe has no {field}",
                if kind_name.starts_with(['a', 'e', 'i', 'o', 'u']) {
                    "an"
                } else {
                    "a"
                }
            ),
        )),
        None => Ok(()),
    };
    let azimuth = number(
        check,
        &p.azimuth_deg,
        &key("azimuth_deg"),
        0.0,
        (-360.0, false, 360.0),
    )? * RAD_PER_DEG;
    let kind = match kind_name {
        "radial" => {
            unused(&p.radius_mm, "radius_mm")?;
            let height = number(
                check,
                &p.height_mm,
                &key("height_mm"),
                0.0,
                (-2000.0, false, 2000.0),
            )? * M_PER_MM;
            let tolerance = 1e-9;
            let (ok, expected) = match artefact.kind {
                ArtefactKind::Sphere => (
                    height.abs() <= tolerance,
                    "0 (the sphere's equator)".to_string(),
                ),
                ArtefactKind::TwoSpheres { separation } => (
                    height.abs() <= tolerance || (height - separation).abs() <= tolerance,
                    format!(
                        "0 or {} (the spheres' equators)",
                        crate::math::trimmed(separation / M_PER_MM, 6)
                    ),
                ),
                ArtefactKind::Cylinder { length } => (
                    (-tolerance..=length + tolerance).contains(&height),
                    format!(
                        "from 0 to {} (along the cylinder)",
                        crate::math::trimmed(length / M_PER_MM, 6)
                    ),
                ),
            };
            if !ok {
                return Err(check.fail(
                    p.height_mm.as_ref().map(|v| v.span()),
                    &key("height_mm"),
                    format!(
                        "{} mm: a radial probe on a {} senses at a height of {expected} mm",
                        height / M_PER_MM,
                        artefact.kind.name()
                    ),
                ));
            }
            ProbeKind::Radial { azimuth, height }
        }
        "axial" => {
            unused(&p.radius_mm, "radius_mm")?;
            unused(&p.height_mm, "height_mm")?;
            unused(&p.azimuth_deg, "azimuth_deg")?;
            ProbeKind::Axial
        }
        "face" => {
            unused(&p.height_mm, "height_mm")?;
            if !matches!(artefact.kind, ArtefactKind::Cylinder { .. }) {
                return Err(check.fail(
                    Some(p.kind.span()),
                    &key("kind"),
                    format!(
                        "a face probe needs a flat end face: the artefact is a {}; use kind = \"cylinder\"",
                        artefact.kind.name()
                    ),
                ));
            }
            let radius = number(
                check,
                &p.radius_mm,
                &key("radius_mm"),
                Real::NAN,
                (0.0, true, 2000.0),
            )? * M_PER_MM;
            if radius.is_nan() {
                return Err(check.fail(
                    Some(raw.span()),
                    &key("radius_mm"),
                    "a face probe needs its radius_mm",
                ));
            }
            if radius >= artefact.radius {
                return Err(check.fail(
                    p.radius_mm.as_ref().map(|v| v.span()),
                    &key("radius_mm"),
                    format!(
                        "{} mm is off the end face (radius {} mm)",
                        radius / M_PER_MM,
                        artefact.radius / M_PER_MM
                    ),
                ));
            }
            ProbeKind::Face { radius, azimuth }
        }
        other => {
            return Err(check.fail(
                Some(p.kind.span()),
                &key("kind"),
                format!("expected \"radial\", \"axial\" or \"face\", got \"{other}\""),
            ));
        }
    };
    let gain_error = number(
        check,
        &p.gain_error,
        &key("gain_error"),
        0.0,
        (-0.5, false, 0.5),
    )?;
    Ok(ProbeSpec {
        name,
        kind,
        gain_error,
        noise: number(
            check,
            &p.noise_nm,
            &key("noise_nm"),
            d.noise / M_PER_NM,
            (0.0, false, 1e6),
        )? * M_PER_NM,
        resolution: number(
            check,
            &p.resolution_nm,
            &key("resolution_nm"),
            d.resolution / M_PER_NM,
            (0.0, false, 1e6),
        )? * M_PER_NM,
        bandwidth: bandwidth(check, &p.bandwidth_hz, &key("bandwidth_hz"), d.bandwidth)?,
        range: number(
            check,
            &p.range_um,
            &key("range_um"),
            d.range / M_PER_UM,
            (0.0, true, 1e4),
        )? * M_PER_UM,
    })
}

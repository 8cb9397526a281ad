//! `[spindle.artefact]`: what the probes sense, a sphere, two spheres or a cylinder, and how
//! it is set up on the axis (stick-out, eccentricity, tilt) and formed (undulations).

use super::super::instrument::{Artefact, ArtefactKind, FormHarmonic};
use super::{M_PER_NM, number};
use crate::machine::Axis;
use crate::math::{M_PER_MM, M_PER_UM, RAD_PER_DEG, RAD_PER_URAD, Real};
use crate::scenario::{Checker, ScenarioError};
use serde::Deserialize;
use toml::Spanned;

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
pub(super) struct RawArtefact {
    kind: Option<Spanned<String>>,
    diameter_mm: Option<Spanned<Real>>,
    length_mm: Option<Spanned<Real>>,
    separation_mm: Option<Spanned<Real>>,
    stickout_mm: Option<Spanned<Real>>,
    eccentricity_um: Option<Spanned<[Real; 2]>>,
    tilt_urad: Option<Spanned<[Real; 2]>>,
    form: Option<Spanned<Vec<Spanned<RawForm>>>>,
}

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct RawForm {
    per_revolution: i64,
    amplitude_nm: Real,
    #[serde(default)]
    phase_deg: Real,
}

/// The `[spindle.artefact]` table.
pub(super) fn artefact(
    check: &Checker<'_>,
    axis: Axis,
    raw: Option<&Spanned<RawArtefact>>,
) -> Result<Artefact, ScenarioError> {
    let empty = RawArtefact {
        kind: None,
        diameter_mm: None,
        length_mm: None,
        separation_mm: None,
        stickout_mm: None,
        eccentricity_um: None,
        tilt_urad: None,
        form: None,
    };
    let a = raw.map_or(&empty, |r| r.get_ref());
    let kind_name = a.kind.as_ref().map(|k| (k.get_ref().as_str(), k.span()));
    let kind = kind_name.as_ref().map_or("cylinder", |(k, _)| k);
    let radius = number(
        check,
        &a.diameter_mm,
        "artefact.diameter_mm",
        25.0,
        (0.0, true, 1000.0),
    )? / 2.0
        * M_PER_MM;
    let only = |value: &Option<Spanned<Real>>, key: &str, kind_needed: &str| match value {
        Some(v) if kind != kind_needed => Err(check.fail(
            Some(v.span()),
            key,
            format!("only a {kind_needed} has it (this artefact is a {kind})"),
        )),
        _ => Ok(()),
    };
    only(&a.length_mm, "artefact.length_mm", "cylinder")?;
    only(&a.separation_mm, "artefact.separation_mm", "two_spheres")?;
    let kind = match kind {
        "sphere" => ArtefactKind::Sphere,
        "two_spheres" => {
            let separation = number(
                check,
                &a.separation_mm,
                "artefact.separation_mm",
                80.0,
                (0.0, true, 2000.0),
            )? * M_PER_MM;
            if separation <= 2.0 * radius {
                return Err(check.fail(
                    a.separation_mm.as_ref().map(|v| v.span()),
                    "artefact.separation_mm",
                    format!(
                        "the spheres ({} mm) would overlap: their centres must be more than a diameter apart",
                        2.0 * radius / M_PER_MM
                    ),
                ));
            }
            ArtefactKind::TwoSpheres { separation }
        }
        "cylinder" => ArtefactKind::Cylinder {
            length: number(
                check,
                &a.length_mm,
                "artefact.length_mm",
                80.0,
                (0.0, true, 2000.0),
            )? * M_PER_MM,
        },
        other => {
            return Err(check.fail(
                kind_name.map(|(_, span)| span),
                "artefact.kind",
                format!("expected \"sphere\", \"two_spheres\" or \"cylinder\", got \"{other}\""),
            ));
        }
    };
    let table_axis = axis != Axis::S;
    let stickout = number(
        check,
        &a.stickout_mm,
        "artefact.stickout_mm",
        if table_axis { 100.0 } else { 0.0 },
        (-2000.0, false, 2000.0),
    )? * M_PER_MM;
    let pair = |value: &Option<Spanned<[Real; 2]>>, key: &str, scale: Real, limit: Real| {
        let Some(v) = value else {
            return Ok([0.0; 2]);
        };
        let [x, y] = *v.get_ref();
        if x.is_finite() && y.is_finite() && x.hypot(y) <= limit {
            Ok([x * scale, y * scale])
        } else {
            Err(check.fail(
                Some(v.span()),
                key,
                format!("expected two finite numbers, at most {limit} together, got [{x}, {y}]"),
            ))
        }
    };
    let eccentricity = pair(
        &a.eccentricity_um,
        "artefact.eccentricity_um",
        M_PER_UM,
        1000.0,
    )?;
    let tilt = pair(&a.tilt_urad, "artefact.tilt_urad", RAD_PER_URAD, 10_000.0)?;
    let mut form = Vec::new();
    if let Some(list) = &a.form {
        for (i, h) in list.get_ref().iter().enumerate() {
            let f = h.get_ref();
            let key = format!("artefact.form[{i}]");
            if !(2..=10_000).contains(&f.per_revolution) {
                let why = if f.per_revolution == 1 {
                    "1 undulation per revolution is the artefact's eccentricity: give it as eccentricity_um"
                } else {
                    "expected a whole number of undulations per revolution from 2 to 10000"
                };
                return Err(check.fail(
                    Some(h.span()),
                    &format!("{key}.per_revolution"),
                    format!("{}: {why}", f.per_revolution),
                ));
            }
            if !(f.amplitude_nm.is_finite() && f.amplitude_nm.abs() <= 1e6) {
                return Err(check.fail(
                    Some(h.span()),
                    &format!("{key}.amplitude_nm"),
                    format!(
                        "expected a finite amplitude within ±1e6 nm, got {}",
                        f.amplitude_nm
                    ),
                ));
            }
            if !f.phase_deg.is_finite() {
                return Err(check.fail(
                    Some(h.span()),
                    &format!("{key}.phase_deg"),
                    "expected a finite phase",
                ));
            }
            form.push(FormHarmonic {
                per_revolution: f.per_revolution as u32,
                amplitude: f.amplitude_nm * M_PER_NM,
                phase: f.phase_deg * RAD_PER_DEG,
            });
        }
    }
    Ok(Artefact {
        kind,
        radius,
        stickout,
        eccentricity,
        tilt,
        form,
    })
}

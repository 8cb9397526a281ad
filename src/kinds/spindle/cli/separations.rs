//! The form separations in the report: JSON, text and polar plots of the form and of the
//! error motion, each with its harmonics and its values about every centre.

use super::{bounds, motion_curves, round, rpm, slug, uncertainty_json, values_json};
use crate::kinds::spindle::evaluate::{Separated, SeparatedMotion, compact_list};
use crate::kinds::spindle::plot::{PolarCurve, polar_svg};
use crate::math::Real;
use serde_json::{Value, json};

/// µm per m.
const UM: Real = 1e6;

/// Harmonic amplitudes shown per quantity in the text.
const SHOWN: usize = 4;

/// How each method treats the first harmonic (stated in the JSON and the text).
fn first_harmonic(s: &Separated) -> &'static str {
    match s.method {
        "face reversal" | "face reversal with axial motion" => {
            "the face's 1 UPR is its wobble on the rotor (not square to the axis) and the motion's the axis's own 1-UPR tilt; LSC, MRS, MIC and MCC values do not count either, PC values count both"
        }
        "reversal" => {
            "the form's 1 UPR is the artefact's centring on the rotor and the motion's the axis's own 1-UPR motion; LSC, MRS, MIC and MCC values do not count either, PC values count both"
        }
        _ => {
            "the layout cannot tell the form's 1 UPR from a motion: it is given to the motion (centring included) and the form starts at 2 UPR; LSC, MRS, MIC and MCC values do not count it"
        }
    }
}

/// Why a separation gives no synchronous value: harmonics its layout cannot see at which the
/// probes read something.
pub(super) fn blind_reason(s: &Separated) -> String {
    format!(
        "the probe layout cannot see harmonics {}, and at {} the probes read more than their noise: form or motion is there, and which is unknown",
        compact_list(&s.blind),
        compact_list(&s.unknown)
    )
}

/// `{"a": [a_2 …], "b": [b_2 …]}` (µm) from harmonic 2 to k_max, null where the layout is blind.
fn harmonics_json(harmonics: &[[Real; 2]], blind: &[usize]) -> Value {
    let column = |i: usize| -> Vec<Value> {
        harmonics
            .iter()
            .enumerate()
            .skip(1)
            .map(|(k, ab)| {
                if blind.contains(&(k + 1)) {
                    Value::Null
                } else {
                    round(ab[i] * UM)
                }
            })
            .collect()
    };
    json!({ "from": 2, "a": column(0), "b": column(1) })
}

fn motion_json(s: &Separated, m: &SeparatedMotion) -> Value {
    let determined = s.unknown.is_empty();
    let values: Vec<Value> = m.values.iter().map(|v| values_json(v, UM)).collect();
    let first = m.harmonics[0];
    json!({
        "axis": m.axis,
        "azimuth_deg": m.azimuth.map(|a| round(a.to_degrees())),
        "first_harmonic_um": [round(first[0] * UM), round(first[1] * UM)],
        "harmonics_um": harmonics_json(&m.harmonics, &s.blind),
        "asynchronous_um": round(m.values[0].asynchronous * UM),
        "values": if determined { json!(values) } else { Value::Null },
        "values_seen": (!determined).then_some(values),
    })
}

fn form_json(s: &Separated) -> Value {
    let determined = s.unknown.is_empty();
    let values: Vec<Value> = s
        .form_values
        .iter()
        .map(|f| {
            json!({
                "centre": f.centre.to_string(),
                "offset": [round(f.offset[0] * UM), round(f.offset[1] * UM)],
                "value": round(f.value() * UM),
            })
        })
        .collect();
    let first = s.form_harmonics[0];
    json!({
        "first_harmonic_um": (s.method != "multi-probe")
            .then(|| [round(first[0] * UM), round(first[1] * UM)]),
        "harmonics_um": harmonics_json(&s.form_harmonics, &s.blind),
        "values": if determined { json!(values) } else { Value::Null },
        "values_seen": (!determined).then_some(values),
    })
}

/// One separation's JSON (keys in `mtwin analyze spindle --help`).
pub(super) fn json(s: &Separated) -> Value {
    let determined = s.unknown.is_empty();
    json!({
        "method": s.method,
        "probes": s.probes,
        "speed_rpm": round(rpm(s.speed)),
        "harmonics_max": s.k_max,
        "first_harmonic": first_harmonic(s),
        "blind": s.blind,
        "unknown": s.unknown,
        "not_determined": (!determined).then(|| blind_reason(s)),
        "form": form_json(s),
        "form_um": s.form.iter().map(|v| round(v * UM)).collect::<Vec<_>>(),
        "motion": s.motions.iter().map(|m| motion_json(s, m)).collect::<Vec<_>>(),
        "uncertainty": uncertainty_json(&s.uncertainty, UM),
    })
}

/// `k: amplitude` of the largest harmonics from 2 up (µm).
fn largest(harmonics: &[[Real; 2]]) -> String {
    let mut by_size: Vec<(usize, Real)> = harmonics
        .iter()
        .enumerate()
        .skip(1)
        .map(|(i, [a, b])| (i + 1, a.hypot(*b) * UM))
        .filter(|(_, amplitude)| *amplitude >= 5e-5)
        .collect();
    by_size.sort_by(|x, y| y.1.total_cmp(&x.1).then(x.0.cmp(&y.0)));
    if by_size.is_empty() {
        return "none above 0.0001".to_string();
    }
    by_size
        .iter()
        .take(SHOWN)
        .map(|(k, a)| format!("{k} UPR {a:.4}"))
        .collect::<Vec<_>>()
        .join(", ")
}

/// One separation in the report for people.
pub(super) fn text(s: &Separated) -> String {
    let determined = s.unknown.is_empty();
    let mut out = format!(
        "\n{} {} at {:.0} min⁻¹: artefact form and error motion separated (µm; harmonics 1–{})\n",
        s.method,
        s.probes.join("+"),
        rpm(s.speed),
        s.k_max
    );
    if !determined {
        out += &format!(
            "  not determined: {}; the values below are over the harmonics the layout sees\n",
            blind_reason(s)
        );
    } else if !s.blind.is_empty() {
        out += &format!(
            "  blind to harmonics {}, where no probe reads more than its noise\n",
            compact_list(&s.blind)
        );
    }
    let header: String = s
        .form_values
        .iter()
        .map(|f| format!(" {:>9}", f.centre.to_string()))
        .collect();
    out += &format!("  {:<22}{header}\n", "");
    let row = |label: &str, values: Vec<Real>| -> String {
        let cells: String = values.iter().map(|v| format!(" {:>9.4}", v * UM)).collect();
        format!("  {label:<22}{cells}\n")
    };
    out += &row(
        "form (roundness)",
        s.form_values.iter().map(|f| f.value()).collect(),
    );
    for m in &s.motions {
        out += &row(
            &format!("motion {} sync", m.axis),
            m.values.iter().map(|v| v.synchronous).collect(),
        );
        out += &row(
            &format!("motion {} total", m.axis),
            m.values.iter().map(|v| v.total).collect(),
        );
    }
    let asynchronous: Vec<String> = s
        .motions
        .iter()
        .map(|m| format!("{} {:.4}", m.axis, m.values[0].asynchronous * UM))
        .collect();
    out += &format!("  asynchronous motion: {}\n", asynchronous.join(", "));
    out += &format!("  form harmonics: {}\n", largest(&s.form_harmonics));
    for m in &s.motions {
        out += &format!("  motion {} harmonics: {}\n", m.axis, largest(&m.harmonics));
    }
    out += &format!(
        "  U (k = 2): synchronous values ±{:.4}; total, asynchronous ±{:.4}{}\n",
        s.uncertainty.synchronous * UM,
        s.uncertainty.single * UM,
        if s.uncertainty.missing.is_empty() {
            String::new()
        } else {
            format!(" (a lower bound: {})", s.uncertainty.missing.join("; "))
        }
    );
    out += &format!("  first harmonic: {}\n", first_harmonic(s));
    out
}

/// The polar plots of a separation: the form, and each direction of the motion (total and
/// synchronous), about their preferred centres (LSC).
pub(super) fn plots(s: &Separated, angles: &[Real]) -> Vec<(String, Vec<u8>)> {
    let m = angles.len();
    let tag = format!(
        "{}_{}_{}rpm",
        slug(s.method),
        slug(&s.probes.join("_")),
        rpm(s.speed).round()
    );
    let mut files = Vec::new();
    let form_centre = &s.form_values[0];
    let notes: Vec<String> = s
        .form_values
        .iter()
        .map(|f| format!("{}: {:.4} µm", f.centre, f.value() * UM))
        .collect();
    let svg = polar_svg(
        &format!(
            "artefact form by {} ({}), {:.0} min⁻¹",
            s.method,
            s.probes.join("+"),
            rpm(s.speed)
        ),
        &[PolarCurve {
            label: "form (outward)",
            angles,
            values: &s.form,
            stroke: "#063",
            width: 1.5,
        }],
        form_centre.offset,
        (form_centre.low, form_centre.high),
        &notes,
    );
    files.push((format!("form_{tag}.svg"), svg.into_bytes()));
    for motion in &s.motions {
        let preferred = &motion.values[0];
        let total = motion.signal.values();
        let total_angles: Vec<Real> = (0..total.len()).map(|i| angles[i % m]).collect();
        let synchronous = crate::kinds::spindle::analysis::motion::synchronous(&motion.signal);
        let notes: Vec<String> = motion
            .values
            .iter()
            .map(|v| {
                format!(
                    "{}: sync {:.4}, async {:.4}, total {:.4} µm",
                    v.centre,
                    v.synchronous * UM,
                    v.asynchronous * UM,
                    v.total * UM
                )
            })
            .collect();
        let svg = polar_svg(
            &format!(
                "separated error motion {} by {} ({}), {:.0} min⁻¹",
                motion.axis,
                s.method,
                s.probes.join("+"),
                rpm(s.speed)
            ),
            &motion_curves(&total_angles, total, angles, &synchronous),
            preferred.offset,
            bounds(&synchronous, angles, preferred.offset),
            &notes,
        );
        files.push((
            format!("motion_{tag}_{}.svg", slug(&motion.axis)),
            svg.into_bytes(),
        ));
    }
    files
}

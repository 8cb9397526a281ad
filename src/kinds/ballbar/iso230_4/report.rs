//! The reports of an evaluation: [`BallbarEvaluation::to_json`] (stable keys, lengths in µm)
//! and [`BallbarEvaluation::to_text`] (for people), each with the legend of every term.

use super::data::SENSE_NAMES;
use super::{BallbarEvaluation, Term};
use crate::machine::Plane;
use crate::math::{M_PER_MM, M_PER_UM, RAD_PER_DEG, Real, fixed};
use serde_json::{Value, json};
use std::fmt::Write;

/// The report key of `axis`'s reversal lag (`reversal_lag_x_ms`): 0 is p, 1 is q.
pub fn lag_key(plane: Plane, axis: usize) -> String {
    let letter = if axis == 0 {
        plane.first()
    } else {
        plane.second()
    };
    format!("reversal_lag_{}_ms", letter.letter().to_ascii_lowercase())
}

/// What a reversal lag is, for the legend.
const LAG_CONVENTION: &str = "reversal lag δ of the axis: time from its programmed reversal (p: 0°/180°, q: 90°/270°, as the trace's angles place it) to its actual one, where its backlash, lateral play and spike act (its servo lag less the lag in the start the software detected: near 0 when the start is detected from the machine's motion, ≈ 1/Kv when the angles are the command's; negative when it reverses early)";

/// Rounds for reports: 4 decimals, no −0.
fn round(value: Real) -> Value {
    json!(fixed(value, 4).parse::<Real>().unwrap_or(value))
}

/// Metres to µm, rounded.
fn um(value: Real) -> Value {
    round(value / M_PER_UM)
}

impl BallbarEvaluation {
    /// The report with stable keys (lengths in µm, the plane's axis letters in the names).
    pub fn to_json(&self) -> Value {
        let plane = self.test.plane;
        let p = plane.first().letter().to_ascii_lowercase();
        let q = plane.second().letter().to_ascii_lowercase();
        let option = |v: Option<Real>| v.map_or(Value::Null, um);
        let mut report = json!({
            "kind": "ballbar",
            "standard": "ISO 230-4",
            "plane": plane.to_string(),
            "radius_mm": round(self.test.radius / M_PER_MM),
            "feed_mm_per_min": round(self.test.feed / M_PER_MM * 60.0),
            "n_readings": self.counts[0] + self.counts[1],
            "n_ccw": self.counts[0],
            "n_cw": self.counts[1],
            "span_ccw_deg": self.spans[0].map(|s| round(s / RAD_PER_DEG)),
            "span_cw_deg": self.spans[1].map(|s| round(s / RAD_PER_DEG)),
            "G_ccw_um": option(self.circular_deviation[0]),
            "G_cw_um": option(self.circular_deviation[1]),
            "G_um": option(self.bidirectional_deviation),
            "H_um": option(self.hysteresis),
            "F_max_um": um(self.radial_max),
            "F_min_um": um(self.radial_min),
            format!("centre_offset_{p}_um"): um(self.centre_offset[0]),
            format!("centre_offset_{q}_um"): um(self.centre_offset[1]),
            "mean_radial_deviation_um": um(self.mean_radial_deviation),
        });
        match &self.diagnostics {
            Err(reason) => {
                report["diagnostics"] = Value::Null;
                report["diagnostics_skipped"] = json!(reason);
            }
            Ok(d) => {
                let mut values = serde_json::Map::new();
                let mut conventions = serde_json::Map::new();
                for term in Term::DIAGNOSTICS {
                    let (_, scale) = term.unit();
                    let estimate = d.get(term);
                    values.insert(
                        term.key(plane),
                        estimate.map_or(
                            Value::Null,
                            |e| json!({"value": round(e.value * scale), "u": round(e.u * scale)}),
                        ),
                    );
                    conventions.insert(term.key(plane), json!(term.convention()));
                    let pair = |v: Option<(Real, Real)>, scale: Real| {
                        v.map_or(
                            Value::Null,
                            |(v, u)| json!({"value": round(v * scale), "u": round(u * scale)}),
                        )
                    };
                    match term {
                        Term::ReversalSpikeP | Term::ReversalSpikeQ => {
                            values.insert(
                                format!("{}_decay_ms", term.name(plane)),
                                pair(estimate.and_then(|e| e.shape), 1e3),
                            );
                        }
                        Term::CyclicP | Term::CyclicQ => {
                            values.insert(
                                format!("{}_period_mm", term.name(plane)),
                                pair(estimate.and_then(|e| e.shape), 1.0 / M_PER_MM),
                            );
                            values.insert(
                                format!("{}_phase_deg", term.name(plane)),
                                pair(estimate.and_then(|e| e.phase), 1.0 / RAD_PER_DEG),
                            );
                        }
                        _ => {}
                    }
                }
                for axis in 0..2 {
                    values.insert(
                        lag_key(plane, axis),
                        d.reversal_lag[axis].map_or(
                            Value::Null,
                            |(v, u)| json!({"value": round(v * 1e3), "u": round(u * 1e3)}),
                        ),
                    );
                    conventions.insert(lag_key(plane, axis), json!(LAG_CONVENTION));
                }
                report["diagnostics"] = Value::Object(values);
                report["unidentifiable"] = d
                    .unidentifiable
                    .iter()
                    .map(|(t, why)| json!({"term": t.key(plane), "reason": why}))
                    .collect();
                report["notes"] = json!(d.notes);
                report["residual_rms_um"] = um(d.rms);
                report["dof"] = json!(d.dof);
                report["conventions"] = json!({
                    "axes": format!("p = {}, q = {}; θ from +p toward +q; σ = +1 ccw, −1 cw; deviation = measured − nominal radius, + outward", plane.first(), plane.second()),
                    "uncertainty": "standard uncertainty σ̂·√((JᵀJ)⁻¹)ⱼⱼ, σ̂² = RSS/(n − k); optimistic when the residuals are serially correlated",
                    "terms": Value::Object(conventions),
                });
            }
        }
        report
    }

    /// The report for people.
    pub fn to_text(&self) -> String {
        let plane = self.test.plane;
        let mut out = String::new();
        let cell =
            |v: Option<Real>| v.map_or_else(|| "-".to_string(), |v| format!("{:.3}", v / M_PER_UM));
        let _ = writeln!(
            out,
            "ISO 230-4 circular test, plane {plane} (p = {}, q = {}): radius {} mm, feed {} mm/min",
            plane.first(),
            plane.second(),
            fixed(self.test.radius / M_PER_MM, 3),
            fixed(self.test.feed / M_PER_MM * 60.0, 1)
        );
        for (s, name) in SENSE_NAMES.iter().enumerate() {
            if let Some(span) = self.spans[s] {
                let _ = writeln!(
                    out,
                    "  {name}: {} readings over {:.1}°",
                    self.counts[s],
                    span / RAD_PER_DEG
                );
            }
        }
        let _ = writeln!(out);
        let line = |out: &mut String, name: &str, v: Option<Real>| {
            let _ = writeln!(out, "  {name:<44}{:>10} µm", cell(v));
        };
        line(
            &mut out,
            "circular deviation G ccw",
            self.circular_deviation[0],
        );
        line(
            &mut out,
            "circular deviation G cw",
            self.circular_deviation[1],
        );
        line(
            &mut out,
            "bidirectional circular deviation G(b)",
            self.bidirectional_deviation,
        );
        line(&mut out, "circular hysteresis H", self.hysteresis);
        line(
            &mut out,
            "largest radial deviation F_max",
            Some(self.radial_max),
        );
        line(
            &mut out,
            "smallest radial deviation F_min",
            Some(self.radial_min),
        );
        line(
            &mut out,
            &format!("centre offset {}", plane.first()),
            Some(self.centre_offset[0]),
        );
        line(
            &mut out,
            &format!("centre offset {}", plane.second()),
            Some(self.centre_offset[1]),
        );
        line(
            &mut out,
            "mean radial deviation",
            Some(self.mean_radial_deviation),
        );
        let _ = writeln!(
            out,
            "  (centre offset removed exactly by a least-squares circle; F relative to the nominal radius)"
        );
        let _ = writeln!(
            out,
            "  centre offset: of the ISO 230-4 least-squares circle through the trace, every shape in it included\n  \
             centre_offset_* below: of the joint fit, where backlash, bows and the other terms take their own share"
        );
        match &self.diagnostics {
            Err(reason) => {
                let _ = writeln!(out, "\nDiagnostics not computed: {reason}");
            }
            Ok(d) => {
                let _ = writeln!(
                    out,
                    "\nDiagnostics (joint least-squares fit, value ± standard uncertainty; residual RMS {:.3} µm, {} dof):",
                    d.rms / M_PER_UM,
                    d.dof
                );
                for (term, e) in &d.estimates {
                    let (unit, scale) = term.unit();
                    let unit = unit.replace("um", "µm").replace("_per_", "/");
                    let _ = write!(
                        out,
                        "  {:<24}{:>10.3} ± {:<8.3} {unit}",
                        term.name(plane),
                        e.value * scale,
                        e.u * scale
                    );
                    if let Some((v, u)) = e.shape {
                        let _ = match term {
                            Term::CyclicP | Term::CyclicQ => write!(
                                out,
                                "   period {:.3} ± {:.3} mm",
                                v / M_PER_MM,
                                u / M_PER_MM
                            ),
                            _ => write!(out, "   decay {:.2} ± {:.2} ms", v * 1e3, u * 1e3),
                        };
                    }
                    if let Some((v, u)) = e.phase {
                        let _ = write!(
                            out,
                            ", phase {:.1} ± {:.1}°",
                            v / RAD_PER_DEG,
                            u / RAD_PER_DEG
                        );
                    }
                    let _ = writeln!(out);
                }
                for (axis, lag) in d.reversal_lag.iter().enumerate() {
                    if let Some((v, u)) = lag {
                        let name = lag_key(plane, axis);
                        let _ = writeln!(
                            out,
                            "  {:<24}{:>10.3} ± {:<8.3} ms",
                            &name[..name.len() - 3],
                            v * 1e3,
                            u * 1e3
                        );
                    }
                }
                if !d.unidentifiable.is_empty() {
                    let _ = writeln!(out, "\nNot identifiable from these data:");
                    for (term, why) in &d.unidentifiable {
                        let _ = writeln!(out, "  {:<24}{why}", term.name(plane));
                    }
                }
                for note in &d.notes {
                    let _ = writeln!(out, "  note: {note}");
                }
                let _ = writeln!(
                    out,
                    "\nConventions: p = {}, q = {}; θ from +p toward +q; σ = +1 ccw, −1 cw; deviation = measured − nominal radius (+ outward).",
                    plane.first(),
                    plane.second()
                );
                for term in Term::DIAGNOSTICS {
                    let _ = writeln!(out, "  {:<24}{}", term.name(plane), term.convention());
                }
                let _ = writeln!(out, "  {:<24}{LAG_CONVENTION}", "reversal_lag");
                let _ = writeln!(
                    out,
                    "Uncertainties assume independent residuals and are optimistic for a real (serially correlated) trace."
                );
            }
        }
        out
    }
}

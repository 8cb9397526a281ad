//! The extended model written as a scenario fragment (`discover positioning --write-model`).

use super::{DiscoveryError, PositioningDiscovery, PositioningEffect};
use crate::math::{M_PER_MM, M_PER_UM, Real, fixed};

impl PositioningDiscovery {
    /// The extended model as a scenario fragment: the axis's positioning error
    /// `E<axis><axis>` at the reference temperature (profile table, plus the accepted
    /// reversal, cyclic and polynomial terms) and, as comments, the thermal and time terms the
    /// scenario schema cannot express yet. With `extends` (a scenario path relative to the
    /// fragment) the fragment is a scenario that `mtwin run` simulates: the base scenario with
    /// this error replacing its own. `source` names the table in the header.
    pub fn to_scenario_fragment(
        &self,
        source: &str,
        extends: Option<&str>,
    ) -> Result<String, DiscoveryError> {
        let axis = self.problem.axis.ok_or_else(|| {
            DiscoveryError(
                "--write-model: the table has no axis column, so the error's name (EXX, EYY or EZZ) is unknown"
                    .into(),
            )
        })?;
        let (score, fit) = self.selection.last();
        let (knots, values) = fit.profile();
        // The profile is the error at the reference temperature; the twin's thermal model
        // expands from 20 °C, so move it there with the base model's nominal expansion.
        let to_20 = fit
            .reference_temperature
            .map_or(0.0, |t| self.problem.options.expansion * (t - 20.0));
        let values: Vec<Real> = knots
            .iter()
            .zip(values)
            .map(|(x, v)| v - to_20 * x)
            .collect();
        let source: String = source.chars().filter(|c| !c.is_control()).collect();
        let number = |v: Real| fixed(v, 4);
        let list = |values: Vec<Real>| {
            values
                .into_iter()
                .map(number)
                .collect::<Vec<_>>()
                .join(", ")
        };
        let mut out = String::new();
        out.push_str(&format!(
            "# Extended model found by `mtwin discover positioning {source}`:\n# {} (held-out RMS {} µm; base model {} µm).\n",
            self.model_name(self.selection.steps.len()),
            fixed(score.cv_rms / M_PER_UM, 3),
            fixed(self.selection.baseline.0.cv_rms / M_PER_UM, 3)
        ));
        if let Some(t) = fit.reference_temperature {
            out.push_str(&format!(
                "# E{axis}{axis} below is the error at 20 °C: the profile at the reference run's {} °C less\n# the nominal expansion ({} µm/(m·°C)) between the two.\n",
                fixed(t, 2),
                fixed(self.problem.options.expansion * 1e6, 2)
            ));
        }
        if let Some(base) = extends {
            out.push_str(&format!(
                "schema = 1\nextends = {}\n",
                toml::Value::String(base.replace('\\', "/"))
            ));
        } else {
            out.push_str(
                "# Add `schema = 1` and `extends = \"<the machine's scenario>\"` to run it.\n",
            );
        }
        out.push_str(&format!("\n[errors.E{axis}{axis}]\n"));
        let mm = |v: &Real| v / M_PER_MM;
        let um = |v: &Real| v / M_PER_UM;
        if knots.len() == 1 {
            out.push_str(&format!("constant_um = {}\n", number(values[0] / M_PER_UM)));
        } else {
            out.push_str(&format!(
                "table = {{ positions_mm = [{}], values_um = [{}], interpolation = \"linear\" }}\n",
                list(knots.iter().map(mm).collect()),
                list(values.iter().map(um).collect())
            ));
        }
        let mut comments = Vec::new();
        for &effect in &fit.effects {
            let p = fit.params(effect);
            match effect {
                PositioningEffect::Reversal => {
                    out.push_str(&format!("reversal_um = {}\n", number(p["lost_motion_um"])));
                }
                PositioningEffect::Periodic => out.push_str(&format!(
                    "harmonic = [{{ period_mm = {}, amplitude_um = {}, phase_deg = {} }}]\n",
                    number(p["period_mm"]),
                    number(p["amplitude_um"]),
                    number(p["phase_deg"])
                )),
                PositioningEffect::NonlinearScale => {
                    // q2·ξ² + q3·ξ³ with ξ = (x − c)/h, expanded in powers of x (mm).
                    let (q2, q3) = (p["quadratic_um"], p["cubic_um"]);
                    let (c, h) = (
                        self.problem.centre / M_PER_MM,
                        self.problem.half_range / M_PER_MM,
                    );
                    let coefficients = [
                        q2 * c * c / (h * h) - q3 * c.powi(3) / h.powi(3),
                        -2.0 * q2 * c / (h * h) + 3.0 * q3 * c * c / h.powi(3),
                        q2 / (h * h) - 3.0 * q3 * c / h.powi(3),
                        q3 / h.powi(3),
                    ];
                    out.push_str(&format!(
                        "polynomial_um = [{}]\n",
                        coefficients
                            .iter()
                            .map(|v| format!("{v:e}"))
                            .collect::<Vec<_>>()
                            .join(", ")
                    ));
                }
                _ => comments.push(format!(
                    "#   {}: {}",
                    effect.id(),
                    p.iter()
                        .map(|(k, v)| format!("{k} = {}", number(*v)))
                        .collect::<Vec<_>>()
                        .join(", ")
                )),
            }
        }
        if !comments.is_empty() {
            out.push_str(
                "\n# Found but not expressible in a scenario yet (the twin's thermal network is not fitted\n# by discovery, and error functions have no temperature or time input):\n",
            );
            for line in comments {
                out.push_str(&line);
                out.push('\n');
            }
        }
        Ok(out)
    }
}

//! The extended model written as a scenario fragment (`discover positioning --write-model`).

use super::{DiscoveryError, PositioningDiscovery, PositioningEffect};
use crate::math::{M_PER_MM, M_PER_UM, Real, fixed};

impl PositioningDiscovery {
    /// The extended model as a scenario fragment: the axis's positioning error
    /// `E<axis><axis>` at the reference temperature (profile table, plus the accepted
    /// reversal, cyclic and polynomial terms), its temperature, heating and drift terms
    /// ([`crate::errors::ContextTerm`]: the nominal expansion with `thermal_scale`,
    /// `thermal_offset`, `thermal_lag`, `second_heat_source`, `time_drift`) reading the table
    /// itself as the measured temperature record (`[inputs] temperatures = source`, the table's
    /// path relative to the fragment), and as comments the lost-motion changes a scenario
    /// cannot express. With `extends` (a scenario path relative to the fragment) the fragment
    /// is a scenario that `mtwin run` simulates: the base scenario with this error replacing
    /// its own and, when there are temperature terms, the base's thermal network errors off.
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
        let source: String = source.chars().filter(|c| !c.is_control()).collect();
        let number = |v: Real| fixed(v, 4);
        let precise = |v: Real| fixed(v, 6);
        let list = |values: Vec<Real>| {
            values
                .into_iter()
                .map(number)
                .collect::<Vec<_>>()
                .join(", ")
        };
        let thermal = self.thermal_terms(fit);
        let mut out = String::new();
        out.push_str(&format!(
            "# Extended model found by `mtwin discover positioning {source}`:\n# {} (held-out RMS {} µm; base model {} µm).\n",
            self.model_name(self.selection.steps.len()),
            fixed(score.cv_rms / M_PER_UM, 3),
            fixed(self.selection.baseline.0.cv_rms / M_PER_UM, 3)
        ));
        if let Some(t) = fit.reference_temperature {
            out.push_str(&format!(
                "# E{axis}{axis} below is the error at the reference run's {} °C; its temperature terms read\n# the measured record (the table itself), so `mtwin run` replays the file's conditions.\n",
                fixed(t, 2),
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
        if !thermal.is_empty() {
            out.push_str(&format!(
                "\n[inputs]\ntemperatures = {}\n",
                toml::Value::String(source.replace('\\', "/"))
            ));
            out.push_str(
                "# The terms below are the whole thermal model of this axis: the thermal network's own\n# error terms are off (the network still runs and drives the sensors the record lacks).\nthermal_network_errors = false\n",
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
        for line in &thermal {
            out.push_str(line);
            out.push('\n');
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
                    precise(p["period_mm"]),
                    number(p["amplitude_um"]),
                    precise(p["phase_deg"])
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
                PositioningEffect::ReversalPosition | PositioningEffect::ReversalThermal => {
                    comments.push(format!(
                        "#   {}: {}",
                        effect.id(),
                        p.iter()
                            .map(|(k, v)| format!("{k} = {}", number(*v)))
                            .collect::<Vec<_>>()
                            .join(", ")
                    ))
                }
                // Written as temperature, heating and drift terms above.
                PositioningEffect::ThermalLag
                | PositioningEffect::SensorLag
                | PositioningEffect::ThermalScale
                | PositioningEffect::ThermalOffset
                | PositioningEffect::SecondHeatSource
                | PositioningEffect::TimeDrift => {}
            }
        }
        if !comments.is_empty() {
            out.push_str(
                "\n# Found but not expressible in a scenario yet (lost motion is a constant of the error\n# function; it has no position or temperature dependence), so `mtwin run` leaves them out:\n",
            );
            for line in comments {
                out.push_str(&line);
                out.push('\n');
            }
        }
        Ok(out)
    }

    /// The fit's temperature and time terms as `[errors.*]` keys: the expansion (nominal plus
    /// `thermal_scale`) and `thermal_offset` on the measured sensor, ahead by `sensor_lag` and through
    /// `thermal_lag`'s lag, from the fit's reference temperature; `second_heat_source` as heating from the first
    /// reading; `time_drift` as a drift from the reference run's mean time. Empty without a
    /// temperature column (the base model then has no thermal term).
    fn thermal_terms(&self, fit: &super::PositioningFit) -> Vec<String> {
        let precise = |v: Real| fixed(v, 6);
        let coefficient = |effect| {
            fit.effects
                .contains(&effect)
                .then(|| fit.coefficients_of(effect).expect("in the fit")[0])
        };
        let mut lines = Vec::new();
        if let (Some(sensor), Some(reference)) = (&self.problem.sensor, fit.reference_temperature) {
            let mut lag = String::new();
            if let Some(tau) = fit.searched.sensor_in(&fit.effects) {
                lag.push_str(&format!(", sensor_lag_min = {}", precise(tau / 60.0)));
            }
            if let Some(tau) = fit.searched.lag_in(&fit.effects) {
                lag.push_str(&format!(", lag_min = {}", precise(tau / 60.0)));
            }
            let head = format!(
                "{{ sensor = {}, reference_degc = {}",
                toml::Value::String(sensor.clone()),
                precise(reference)
            );
            let expansion = self.problem.options.expansion
                + coefficient(PositioningEffect::ThermalScale).unwrap_or(0.0);
            let mut terms = vec![format!(
                "{head}, um_per_m_per_degc = {}{lag} }}",
                precise(expansion * 1e6)
            )];
            if let Some(c) = coefficient(PositioningEffect::ThermalOffset) {
                terms.push(format!(
                    "{head}, um_per_degc = {}{lag} }}",
                    precise(c * 1e6)
                ));
            }
            lines.push(format!("temperature = [\n  {},\n]", terms.join(",\n  ")));
        }
        let time = |i: usize| self.problem.time.as_ref().map_or(0.0, |t| t[i]);
        if let Some(b) = coefficient(PositioningEffect::SecondHeatSource) {
            let tau = fit.searched.heat_tau.expect("searched with the effect");
            lines.push(format!(
                "heating = [{{ um_per_m = {}, tau_min = {}, from_min = {} }}]",
                precise(b * 1e6),
                precise(tau / 60.0),
                precise(time(self.problem.order[0]) / 60.0)
            ));
        }
        if let Some(d) = coefficient(PositioningEffect::TimeDrift) {
            lines.push(format!(
                "drift = [{{ um_per_h = {}, from_min = {} }}]",
                precise(d * 1e6),
                precise(fit.reference.time / 60.0)
            ));
        }
        lines
    }
}

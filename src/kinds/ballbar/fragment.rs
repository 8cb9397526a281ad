//! The model ball-bar discovery found, written as a scenario fragment that `mtwin run` takes
//! (`mtwin discover ballbar FILE.csv --write-model MODEL.toml --extends SCENARIO.toml`).
//!
//! What a trace measures and the scenario term that makes it, for the plane (p, q):
//!
//! | discovered | written |
//! |---|---|
//! | squareness S (µm/m) | XY: `EC0Y = −S`; YZ: `EA0Z = −S`; ZX: `EB0Z = +S` (µrad) |
//! | scale mismatch Δk (ppm) | `Epp` slope +Δk/2, `Eqq` slope −Δk/2 (a trace sees only the difference) |
//! | backlash b of an axis, as a step | its `Eaa` `reversal_um = b` (the error model's half-step) |
//! | backlash b of an axis, as play | `[servo]` `play_um = b` (the drive crosses the gap) |
//! | reversal spike h, τ of an axis | `[servo]` `spike_um = h`, `spike_decay_ms = τ` |
//! | servo mismatch Δℓ (ms) | `[servo]` p's `kv_per_s` = (1 − f_p)/(ℓ_q + Δℓ), ℓ_q q's lag in the base |
//! | lateral play l of p (XY only) | `EYX` `reversal_um = l` |
//!
//! The rest is written as comments with its values, each for a stated reason: the centre
//! offset and the radius are the set-up and the bar, not the machine; a bow, a cyclic error
//! and lobes are functions of absolute position, which a trace (centred on an unknown point)
//! does not give; the radius drift and a radius that depends on the sense have no scenario
//! term. Lateral play outside XY is a comment too: its sign has not been checked by a round
//! trip there.
//!
//! Each written error replaces the base scenario's error of the same name (as every
//! extension does), and each written `[servo]` key replaces the base's key for that axis.

use super::discovery::BallbarDiscovery;
use crate::machine::{Axis, Plane};
use crate::math::{Real, fixed};
use crate::program::Servo;
use serde_json::Value;
use std::collections::BTreeMap;

impl BallbarDiscovery {
    /// The fragment (see the module documentation): `source` names the table in the header,
    /// `extends` (a path relative to the fragment) makes it a runnable scenario, whose servo
    /// (`base_servo`) gives the lag the servo mismatch is relative to (the defaults without).
    pub fn to_scenario_fragment(
        &self,
        source: &str,
        extends: Option<&str>,
        base_servo: Option<&Servo>,
    ) -> String {
        let json = self.to_json();
        let plane: Plane = self.test().plane;
        let (p, q) = (plane.first(), plane.second());
        let finals = &json["final"]["params"];
        let value = |effect: &str, key: &str| finals[effect][key].as_f64();
        let number = |v: Real| fixed(v, 4);
        let source: String = source.chars().filter(|c| !c.is_control()).collect();
        let mut out = format!(
            "# Extended model found by `mtwin discover ballbar {source}`:\n# {} (held-out RMS {} µm; base model {} µm).\n",
            json["final"]["model"].as_str().unwrap_or(""),
            fixed(json["final"]["cv_rms_um"].as_f64().unwrap_or(0.0), 3),
            fixed(json["baseline"]["cv_rms_um"].as_f64().unwrap_or(0.0), 3),
        );
        match extends {
            Some(base) => out.push_str(&format!(
                "schema = 1\nextends = {}\n",
                toml::Value::String(base.replace('\\', "/"))
            )),
            None => out.push_str(
                "# Add `schema = 1` and `extends = \"<the machine's scenario>\"` to run it.\n",
            ),
        }
        // Error terms by name, then servo keys by axis.
        let mut errors: BTreeMap<String, Vec<String>> = BTreeMap::new();
        let mut servo: BTreeMap<usize, (Axis, Vec<String>)> = BTreeMap::new();
        // The final model's effects written above or as their own comment.
        let mut handled: Vec<String> = Vec::new();
        let mut comments: Vec<String> = Vec::new();
        let base = &finals["base"];
        if let Some(s) = base["squareness_um_per_m"].as_f64() {
            let (name, sign) = match plane {
                Plane::XY => ("EC0Y", -1.0),
                Plane::YZ => ("EA0Z", -1.0),
                Plane::ZX => ("EB0Z", 1.0),
            };
            errors
                .entry(name.into())
                .or_default()
                .push(format!("constant_urad = {}", number(sign * s)));
        }
        if let Some(k) = base["scale_mismatch_ppm"].as_f64() {
            // ppm = µm/m = 1e-3 µm/mm.
            for (axis, half) in [(p, 0.5 * k), (q, -0.5 * k)] {
                errors
                    .entry(format!("E{axis}{axis}"))
                    .or_default()
                    .push(format!("polynomial_um = [0.0, {}]", fixed(half * 1e-3, 9)));
            }
        }
        for (axis, id) in [(p, p.to_string()), (q, q.to_string())] {
            let lower = id.to_lowercase();
            let backlash = format!("backlash_{lower}");
            if let Some(b) = value(&backlash, "backlash_um") {
                if value(&backlash, "play_um").is_some() {
                    servo
                        .entry(axis.index())
                        .or_insert((axis, Vec::new()))
                        .1
                        .push(format!("play_um = {}", number(b.abs())));
                } else {
                    errors
                        .entry(format!("E{axis}{axis}"))
                        .or_default()
                        .push(format!("reversal_um = {}", number(b)));
                }
                handled.push(backlash);
            }
            let spike = format!("reversal_spike_{lower}");
            if let (Some(h), Some(tau)) = (value(&spike, "amplitude_um"), value(&spike, "decay_ms"))
            {
                servo
                    .entry(axis.index())
                    .or_insert((axis, Vec::new()))
                    .1
                    .extend([
                        format!("spike_um = {}", number(h)),
                        format!("spike_decay_ms = {}", number(tau)),
                    ]);
                handled.push(spike);
            }
        }
        if let Some(mismatch_ms) = value("servo_mismatch", "servo_mismatch_ms") {
            let base_servo = base_servo.cloned().unwrap_or_default();
            let (sp, sq) = (base_servo.axes[p.index()], base_servo.axes[q.index()]);
            let lag_p = sq.lag_time() + mismatch_ms * 1e-3;
            handled.push("servo_mismatch".into());
            if lag_p > 0.0 {
                servo
                    .entry(p.index())
                    .or_insert((p, Vec::new()))
                    .1
                    .push(format!(
                        "kv_per_s = {}",
                        fixed((1.0 - sp.feed_forward) / lag_p, 6)
                    ));
            } else {
                comments.push(format!(
                    "servo_mismatch: {} ms, more than {q}'s whole lag ({} ms): no gain of {p} gives it",
                    number(mismatch_ms),
                    number(sq.lag_time() * 1e3)
                ));
            }
        }
        let lateral = format!("lateral_play_{}", p.to_string().to_lowercase());
        if let Some(l) = value(&lateral, "lateral_play_um") {
            handled.push(lateral.clone());
            if plane == Plane::XY {
                errors
                    .entry("EYX".into())
                    .or_default()
                    .push(format!("reversal_um = {}", number(l)));
            } else {
                comments.push(format!(
                    "{lateral}: lateral_play_um = {} (E{q}{p} reversal_um; its sign outside XY is unchecked)",
                    number(l)
                ));
            }
        }
        // Everything else in the final model, as comments with its values.
        if let Some(map) = finals.as_object() {
            for (effect, params) in map {
                if effect == "base" || handled.contains(effect) {
                    continue;
                }
                comments.push(format!("{effect}: {}", params_line(params)));
            }
        }
        comments.push(format!(
            "set-up and bar (not the machine): {}",
            params_line(&strip(base, &["squareness_um_per_m", "scale_mismatch_ppm"]))
        ));
        out.push_str(
            "# Not written (no scenario term, or a function of absolute position the trace does not give):\n",
        );
        for c in &comments {
            out.push_str(&format!("#   {c}\n"));
        }
        for (name, lines) in &errors {
            out.push_str(&format!("\n[errors.{name}]\n"));
            for line in lines {
                out.push_str(line);
                out.push('\n');
            }
        }
        if !servo.is_empty() {
            out.push_str("\n[servo]\n");
            for (axis, keys) in servo.values() {
                out.push_str(&format!("{axis} = {{ {} }}\n", keys.join(", ")));
            }
        }
        out
    }
}

/// `key = value, …` of a JSON object of numbers.
fn params_line(params: &Value) -> String {
    params
        .as_object()
        .into_iter()
        .flatten()
        .map(|(k, v)| format!("{k} = {v}"))
        .collect::<Vec<_>>()
        .join(", ")
}

/// `object` without `keys`.
fn strip(object: &Value, keys: &[&str]) -> Value {
    let mut object = object.clone();
    if let Some(map) = object.as_object_mut() {
        for k in keys {
            map.remove(*k);
        }
    }
    object
}

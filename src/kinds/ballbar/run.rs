//! Running the ball-bar tests: each circle through the servo loops and the twin, measured by
//! the virtual ball-bar; and the set-up, circles and controller as injected, for the truth
//! (per axis `kv_per_s`, …, `spike_um`, and `play_um` when the axis has play).

use super::scenario::BallbarTest;
use super::table::BallbarTable;
use crate::twin::Twin;
use serde_json::{Value, json};

/// One table per circle of `test`, in its order; each circle's noise seeded from `seed` and
/// its plane.
pub fn simulate(twin: &Twin, test: &BallbarTest, seed: u64) -> Vec<BallbarTable> {
    test.circles
        .iter()
        .map(|circle| {
            let plane = circle.plane;
            let mut rng = crate::math::seeded_rng(seed, &format!("ballbar {plane}"));
            test.ballbar.measure(twin, circle, &test.servo, &mut rng)
        })
        .collect()
}

/// The ball-bar set-up, the circles and the controller, in file units; per plane the servo
/// mismatch the loops give (lag time of the first axis − the second's).
pub fn truth(test: &BallbarTest) -> Value {
    let bar = &test.ballbar;
    let servo = &test.servo;
    // Play is recorded when an axis has some (absent: none), so that the truth of a test
    // without play reads as before.
    let axis_servo = |axis: crate::machine::Axis| {
        let s = servo.axis(axis);
        let mut record = json!({
            "kv_per_s": s.kv,
            "feed_forward": s.feed_forward,
            "lag_ms": s.lag_time() * 1e3,
            "spike_um": s.spike_height * 1e6,
            "spike_decay_ms": s.spike_decay * 1e3,
            "vibration_um": s.vibration_amplitude * 1e6,
            "vibration_hz": s.vibration_frequency,
        });
        if s.play > 0.0 {
            record["play_um"] = json!(s.play * 1e6);
        }
        record
    };
    json!({
        "length_mm": bar.length * 1e3,
        "setup_offset_um": (bar.setup_offset * 1e6).to_array(),
        "calibration_um": bar.calibration_error * 1e6,
        "noise_um": bar.noise * 1e6,
        "resolution_um": bar.resolution * 1e6,
        "sample_rate_hz": bar.sample_rate,
        "circles": test.circles.iter().map(|c| json!({
            "plane": c.plane.to_string(),
            "file": format!("ballbar_{}.csv", c.plane.lower()),
            "feed_mm_per_min": c.feed * 60e3,
            "centre": c.centre.0.iter().zip(["x_mm", "y_mm", "z_mm", "a_deg", "b_deg", "c_deg"])
                .map(|(v, k)| (k.to_string(), json!(if k.ends_with("mm") { v * 1e3 } else { v.to_degrees() })))
                .collect::<serde_json::Map<_, _>>(),
            "data_start_deg": c.data_start.to_degrees(),
            "data_arc_deg": c.data_arc.to_degrees(),
            "overshoot_deg": c.overshoot.to_degrees(),
            "acceleration_mm_per_s2": c.acceleration * 1e3,
            "dwell_s": c.dwell,
            "servo_mismatch_ms": (servo.axis(c.plane.first()).lag_time() - servo.axis(c.plane.second()).lag_time()) * 1e3,
        })).collect::<Vec<_>>(),
        "servo": {
            "ipo_period_ms": servo.ipo_period * 1e3,
            "X": axis_servo(crate::machine::Axis::X),
            "Y": axis_servo(crate::machine::Axis::Y),
            "Z": axis_servo(crate::machine::Axis::Z),
        },
    })
}

/// One line for people: the ISO 230-4 figures of a simulated table (its conditions are in it).
pub fn summary(table: &BallbarTable) -> String {
    let c = table.conditions;
    let (Some(plane), Some(radius), Some(feed)) = (c.plane, c.radius, c.feed) else {
        return format!("ball-bar: {} readings", table.readings.len());
    };
    let test = super::CircularTest {
        plane,
        radius,
        feed,
    };
    match super::iso230_4::evaluate(table, &test) {
        Ok(e) => {
            let um = |v: Option<crate::math::Real>| {
                v.map_or_else(|| "-".to_string(), |v| format!("{:.3} µm", v * 1e6))
            };
            format!(
                "ball-bar {plane}: G = {}, H = {}",
                um(e.bidirectional_deviation),
                um(e.hysteresis)
            )
        }
        Err(e) => format!("ball-bar {plane}: {e}"),
    }
}

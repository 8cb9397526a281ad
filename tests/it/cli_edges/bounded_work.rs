//! Work bounded by the scenario's values: dynamic R-tests, ball-bar interpolation, air oscillation.

use super::*;

/// A dynamic R-test (issue 42, audit of what a scenario can set): an interpolation period of
/// 1e-7 ms made `run` step the servo loops for hours; a feed of 1 °/min over ten turns at 100 kHz
/// would allocate 2e10 readings. Each value has its physical range, and the sweep its work.
#[test]
fn a_dynamic_rtest_is_bounded_by_its_values_and_its_work() {
    let dir = tempfile::tempdir().unwrap();
    let dynamic = |extra: &str, angle: &str| {
        RTEST_SWEEP
            .replace(
                "[[rtest.test]]",
                &format!("mode = \"dynamic\"\n{extra}\n[[rtest.test]]"),
            )
            .replace("ANGLE", angle)
    };
    for (extra, expected) in [
        (
            "ipo_period_ms = 1e-7",
            "expected 0.05 … 100 (CNC interpolation cycles",
        ),
        ("rotary_feed_deg_per_min = 1e9", "expected 1 … 72000"),
        ("sample_rate_hz = 1e9", "expected 1 … 100000"),
        ("kv_per_s = { C = 1e6 }", "expected a gain of 1 … 1000 /s"),
    ] {
        let file = scenario_file(dir.path(), "dynamic.toml", &dynamic(extra, "360.0"));
        let message = refused_at(&["check", &file], &file, 7);
        assert!(message.contains(expected), "{extra}: {message}");
    }
    // Values in range, but ten turns at 1 °/min read at 100 kHz: 2e10 readings, refused at the
    // test (its [[rtest.test]] line) before any work.
    let file = scenario_file(
        dir.path(),
        "dynamic.toml",
        &dynamic(
            "rotary_feed_deg_per_min = 1.0\nsample_rate_hz = 1e5",
            "3600.0",
        ),
    );
    let message = refused_at(&["check", &file], &file, 9);
    assert!(
        message.contains("readings") && message.contains("at most 5000000"),
        "{message}"
    );
    // The bundled speed: accepted.
    accepted(&scenario_file(
        dir.path(),
        "dynamic.toml",
        &dynamic("", "360.0"),
    ));
}

#[test]
fn a_ball_bar_interpolation_period_far_below_any_controllers_is_refused() {
    let dir = tempfile::tempdir().unwrap();
    let text = std::fs::read_to_string(scenario("vmc3_ballbar_xy.toml"))
        .unwrap()
        .replace("../models", "MODELS")
        .replace("[servo]\n", "[servo]\nipo_period_ms = 1e-7\n");
    let file = scenario_file(dir.path(), "ipo.toml", &text);
    let line = text
        .lines()
        .position(|l| l.starts_with("ipo_period_ms"))
        .unwrap()
        + 1;
    let message = refused_at(&["check", &file], &file, line);
    assert!(message.contains("expected 0.05 … 100 ms"), "{message}");
}

/// The thermal run steps by a twentieth of the air's oscillation when that is shorter than
/// `max_interval_s`: a period of 1e-6 min used to pass `check` (which counted steps of
/// `max_interval_s`) and make `run` step 5e9 times. The step limit now counts the real steps.
#[test]
fn a_fast_air_oscillation_cannot_slip_past_the_thermal_step_limit() {
    let dir = tempfile::tempdir().unwrap();
    let text = std::fs::read_to_string(scenario("teach_warmup.toml"))
        .unwrap()
        .replace("../models", "MODELS")
        .replace(
            "ambient_degc = 20.0\n",
            "ambient_degc = 20.0\noscillation = { amplitude_degc = 0.2, period_min = PERIOD }\n",
        );
    let line = text.lines().position(|l| l == "[thermal]").unwrap() + 1;
    let file = scenario_file(dir.path(), "fast.toml", &text.replace("PERIOD", "1e-6"));
    let message = refused_at(&["check", &file], &file, line);
    assert!(
        message.contains("thermal.oscillation.period_min")
            && message.contains("more than five million steps"),
        "{message}"
    );
    // An air conditioner's 20 min cycle: accepted.
    accepted(&scenario_file(
        dir.path(),
        "slow.toml",
        &text.replace("PERIOD", "20.0"),
    ));
}

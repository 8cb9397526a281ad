//! Model discovery on ball-bar tables: an effect the base model lacks is hidden in a simulated
//! circular test and must be found, named and measured; a trace with nothing hidden must get
//! nothing added.
//!
//! The traces come from a small machine simulated here, independently of the fit's columns:
//! the axes follow their commands with servo lags (so they reverse that much after their
//! programmed reversals), backlash acts against each axis's actual direction, a cyclic error
//! moves an axis by A·sin(2π·position/P + φ), a lobed form moves the tool radially by
//! A·sin(kθ + φ), a drift grows the bar with time; the reading is the exact distance
//! |tool − centre ball| − R plus white noise (0.2 µm), at the programmed angle. Every trace has
//! the base model's terms (centre offset, squareness, scale errors, a bar length error) and
//! servo lags of 30 ms. Circles of R = 150 mm at 1000 mm/min sampled at 125 Hz, ccw then cw
//! with 45° lead-in and lead-out arcs, in the XY plane (p = X, q = Y).

use mtwin::kinds::ballbar::iso230_4::CircularTest;
use mtwin::kinds::ballbar::{BallbarEffect, discover_ballbar};
use mtwin::kinds::ballbar::{BallbarReading, BallbarTable, Sense};
use mtwin::machine::Plane;
use mtwin::math::{seeded_rng, standard_normal};
use std::f64::consts::TAU;

const R: f64 = 0.150;
const V: f64 = 1.0 / 60.0; // 1000 mm/min in m/s
const RATE: f64 = 125.0;
const UM: f64 = 1e-6;
const NOISE: f64 = 0.2 * UM;

/// What is hidden in a trace beyond the base terms (SI).
#[derive(Clone, Copy, Debug, Default)]
struct Hidden {
    /// Lost motion of p and q (m).
    backlash: [f64; 2],
    /// Extra lag of p over q (s).
    servo: f64,
    /// Cyclic error of p: amplitude (m), period (m), phase (rad).
    cyclic_p: (f64, f64, f64),
    /// Cyclic error of q, the same way.
    cyclic_q: (f64, f64, f64),
    /// Lobed form: lobes, radial amplitude (m), phase (rad).
    lobes: (u32, f64, f64),
    /// Bar growth rate (m/s).
    drift: f64,
    /// Centre offset beyond the base trace's 12 and −7 µm (m).
    extra_centre: [f64; 2],
    /// Lateral play: the p carriage shifts along q by ±l/2 with p's direction of travel, and
    /// the q carriage along p with q's (m).
    lateral_play: [f64; 2],
    /// Straightness: a bow of p along q, S·(1 − (p/R)²), and of q along p (m).
    straightness: [f64; 2],
    /// The ccw circle larger than the cw one by this (m).
    sense_radius: f64,
    /// A reversal spike of each axis: height (m) and decay (s); the axis lags behind its
    /// new direction by h·e^(−Δt/τ) after it reverses.
    spike: [(f64, f64); 2],
}

/// The simulated table of one test.
fn simulate(hidden: &Hidden, seed: u64) -> BallbarTable {
    let mut rng = seeded_rng(seed, "ballbar discovery noise");
    let centre = [
        12.0 * UM + hidden.extra_centre[0],
        -7.0 * UM + hidden.extra_centre[1],
    ];
    let (squareness, scale, bar) = (15e-6, [8e-6, -4e-6], 1.5 * UM);
    let lag = [0.030 + hidden.servo, 0.030];
    let omega = V / R;
    let dt = 1.0 / RATE;
    let lead = 45f64.to_radians() / omega;
    let t_arc = TAU / omega;
    let mut readings = Vec::new();
    let mut clock = 0.0;
    for (sense, start) in [(Sense::Ccw, 0.0), (Sense::Cw, TAU)] {
        let sigma = sense.sign();
        let theta = |t: f64| start + sigma * omega * t;
        let mut k = -(lead / dt).ceil() as i64;
        loop {
            // Half a sample off the start, so no sample falls exactly on a reversal.
            let t = (k as f64 + 0.5) * dt;
            k += 1;
            if t > t_arc + lead {
                break;
            }
            let th = theta(t);
            let command = [R * th.cos(), R * th.sin()];
            let mut axis = [0.0; 2];
            for a in 0..2 {
                // The axis follows its command delayed by its lag, and reverses that late.
                let delayed = theta(t - lag[a]);
                let direction = sigma
                    * if a == 0 {
                        -delayed.sin()
                    } else {
                        delayed.cos()
                    };
                let nominal = R * if a == 0 { delayed.cos() } else { delayed.sin() };
                axis[a] =
                    (1.0 + scale[a]) * nominal - direction.signum() * hidden.backlash[a] / 2.0;
            }
            for (a, (amplitude, period, phase)) in
                [hidden.cyclic_p, hidden.cyclic_q].into_iter().enumerate()
            {
                if period > 0.0 {
                    axis[a] += amplitude * (TAU * command[a] / period + phase).sin();
                }
            }
            // Each axis's direction of travel and the time since it last reversed (p reverses
            // at 0° and 180° of the axes' own angle, q at 90° and 270°).
            let actual = [theta(t - lag[0]), theta(t - lag[1])];
            let direction = [-sigma * actual[0].sin(), sigma * actual[1].cos()];
            let since = [
                (sigma * actual[0]).rem_euclid(std::f64::consts::PI) / omega,
                (sigma * (actual[1] - std::f64::consts::FRAC_PI_2))
                    .rem_euclid(std::f64::consts::PI)
                    / omega,
            ];
            let mut shift = [0.0; 2];
            for a in 0..2 {
                let (height, decay) = hidden.spike[a];
                if height != 0.0 {
                    shift[a] -= direction[a].signum() * height * (-since[a] / decay).exp();
                }
                shift[1 - a] += direction[a].signum() * hidden.lateral_play[a] / 2.0;
                let along = axis[a] / R;
                shift[1 - a] += hidden.straightness[a] * (1.0 - along * along);
            }
            let tool = [
                axis[0] + shift[0] + squareness * axis[1] + centre[0],
                axis[1] + shift[1] + centre[1],
            ];
            let (lobes, lobe_amplitude, lobe_phase) = hidden.lobes;
            let form = lobe_amplitude * (f64::from(lobes) * th + lobe_phase).sin();
            let time = clock + t + lead;
            if (0.0..t_arc).contains(&t) {
                readings.push(BallbarReading {
                    sense,
                    angle: th.rem_euclid(TAU) % TAU,
                    deviation: tool[0].hypot(tool[1]) - R
                        + sigma * hidden.sense_radius / 2.0
                        + form
                        + bar
                        + hidden.drift * time
                        + NOISE * standard_normal(&mut rng),
                    time: Some(time),
                });
            }
        }
        clock += t_arc + 2.0 * lead + 2.0;
    }
    BallbarTable {
        readings,
        ..Default::default()
    }
}

fn xy() -> CircularTest {
    CircularTest {
        plane: Plane::XY,
        radius: R,
        feed: V,
    }
}

/// Runs discovery and returns the accepted effects and the final parameters of `effect`.
fn discover(
    hidden: &Hidden,
    seed: u64,
    effect: Option<BallbarEffect>,
) -> (
    Vec<BallbarEffect>,
    Option<std::collections::BTreeMap<&'static str, f64>>,
) {
    let table = simulate(hidden, seed);
    let t0 = std::time::Instant::now();
    let found = discover_ballbar(&table, &xy(), |_| {}).unwrap();
    println!("seed {seed}: {:?} in {:?}", found.accepted(), t0.elapsed());
    if seed == 1 {
        println!("{}", found.to_text());
    }
    (found.accepted(), effect.and_then(|e| found.final_params(e)))
}

#[test]
fn hidden_backlash_of_y_is_found_and_measured() {
    let hidden = Hidden {
        backlash: [0.0, 3.0 * UM],
        ..Hidden::default()
    };
    for seed in 1..=2 {
        let (accepted, params) = discover(&hidden, seed, Some(BallbarEffect::BacklashQ));
        assert_eq!(accepted, [BallbarEffect::BacklashQ], "seed {seed}");
        let params = params.unwrap();
        let b = params["backlash_um"];
        assert!((b - 3.0).abs() < 0.15, "seed {seed}: {b} µm");
        // Y reverses its 30 ms servo lag after the programmed 90° and 270° (125 Hz: ±4 ms).
        let lag = params["reversal_lag_ms"];
        assert!((lag - 30.0).abs() < 4.0, "seed {seed}: lag {lag} ms");
    }
}

#[test]
fn a_hidden_five_lobe_form_is_found_and_measured() {
    let hidden = Hidden {
        lobes: (5, 1.0 * UM, 0.4),
        ..Hidden::default()
    };
    for seed in 1..=2 {
        let (accepted, params) = discover(&hidden, seed, Some(BallbarEffect::Lobes));
        assert_eq!(accepted, [BallbarEffect::Lobes], "seed {seed}");
        let params = params.unwrap();
        assert_eq!(params["lobes"], 5.0);
        assert!((params["amplitude_um"] - 1.0).abs() < 0.05, "{params:?}");
        assert!(
            (params["phase_deg"] - 0.4f64.to_degrees()).abs() < 3.0,
            "{params:?}"
        );
    }
}

#[test]
fn a_hidden_cyclic_error_of_x_is_found_with_its_period() {
    let hidden = Hidden {
        cyclic_p: (1.0 * UM, 0.010, 0.7),
        ..Hidden::default()
    };
    for seed in 1..=2 {
        let (accepted, params) = discover(&hidden, seed, Some(BallbarEffect::CyclicP));
        assert_eq!(accepted, [BallbarEffect::CyclicP], "seed {seed}");
        let params = params.unwrap();
        assert!((params["period_mm"] - 10.0).abs() < 0.01, "{params:?}");
        assert!((params["amplitude_um"] - 1.0).abs() < 0.05, "{params:?}");
        assert!(
            (params["phase_deg"] - 0.7f64.to_degrees()).abs() < 3.0,
            "{params:?}"
        );
    }
}

#[test]
fn a_radius_drift_is_found_with_its_rate() {
    // The bar grows 0.5 µm/min: about 1.1 µm over the two circles.
    let hidden = Hidden {
        drift: 0.5 * UM / 60.0,
        ..Hidden::default()
    };
    for seed in 1..=2 {
        let (accepted, params) = discover(&hidden, seed, Some(BallbarEffect::RadiusDrift));
        assert_eq!(accepted, [BallbarEffect::RadiusDrift], "seed {seed}");
        let rate = params.unwrap()["rate_um_per_min"];
        assert!((rate - 0.5).abs() < 0.025, "{rate}");
    }
}

#[test]
fn two_hidden_effects_are_both_found() {
    // A servo mismatch (p lags 0.3 ms more: 2.5 µm of σ·sin 2θ) and backlash of X (2 µm).
    let hidden = Hidden {
        servo: 0.3e-3,
        backlash: [2.0 * UM, 0.0],
        ..Hidden::default()
    };
    let table = simulate(&hidden, 3);
    let found = discover_ballbar(&table, &xy(), |_| {}).unwrap();
    let mut accepted = found.accepted();
    accepted.sort();
    assert_eq!(
        accepted,
        [BallbarEffect::ServoMismatch, BallbarEffect::BacklashP]
    );
    let servo = found.final_params(BallbarEffect::ServoMismatch).unwrap()["servo_mismatch_ms"];
    assert!((servo - 0.3).abs() < 0.015, "{servo}");
    let backlash = found.final_params(BallbarEffect::BacklashP).unwrap()["backlash_um"];
    assert!((backlash - 2.0).abs() < 0.1, "{backlash}");
    let json = found.to_json();
    assert_eq!(json["kind"], "ballbar");
    assert_eq!(json["plane"], "XY");
    let names: Vec<&str> = json["steps"]
        .as_array()
        .unwrap()
        .iter()
        .map(|s| s["effect"].as_str().unwrap())
        .collect();
    assert!(
        names.contains(&"backlash_x") && names.contains(&"servo_mismatch"),
        "{names:?}"
    );
    for step in json["steps"].as_array().unwrap() {
        for key in [
            "cause",
            "evidence",
            "params",
            "rms_um",
            "cv_rms_um",
            "gain_um",
            "gain_pct",
            "gain_z",
            "rest_z",
            "z_needed",
        ] {
            assert!(!step[key].is_null(), "{key}");
        }
        // One held-out RMS per angular sector (8); the pooled one lies between the extremes.
        let folds: Vec<f64> = step["fold_cv_rms_um"]
            .as_array()
            .unwrap()
            .iter()
            .map(|v| v.as_f64().unwrap())
            .collect();
        assert_eq!(folds.len(), 8);
        let cv = step["cv_rms_um"].as_f64().unwrap();
        let (low, high) = folds
            .iter()
            .fold((f64::INFINITY, 0.0_f64), |(l, h), &f| (l.min(f), h.max(f)));
        assert!(
            low - 1e-4 <= cv && cv <= high + 1e-4,
            "{folds:?} against {cv}"
        );
    }
    assert!(json["final"]["params"]["backlash_x"]["backlash_um"].is_number());
    assert!(json["final"]["params"]["base"]["squareness_um_per_m"].is_number());
    assert!(
        json["baseline"]["cv_rms_um"].as_f64().unwrap()
            > json["final"]["cv_rms_um"].as_f64().unwrap()
    );
    // The base terms are what the simulation put in: 15 µrad of squareness, 12 ppm of scale
    // mismatch, a 12 µm, −7 µm centre offset.
    let base = &json["final"]["params"]["base"];
    assert!(
        (base["squareness_um_per_m"].as_f64().unwrap() - 15.0).abs() < 0.3,
        "{base}"
    );
    assert!(
        (base["scale_mismatch_ppm"].as_f64().unwrap() - 12.0).abs() < 0.3,
        "{base}"
    );
    assert!(
        (base["centre_offset_x_um"].as_f64().unwrap() - 12.0).abs() < 0.05,
        "{base}"
    );
    assert!(
        (base["centre_offset_y_um"].as_f64().unwrap() + 7.0).abs() < 0.05,
        "{base}"
    );
}

/// Issue 36, item 2: the trace's angles are the programmed ones, so a centre offset seen by
/// axes 30 ms behind their commands turns by σ·v·ℓ/R (the angle lag ℓ = 30 ms). The full fit
/// estimates ℓ only on both senses' full circles; a fold holds a 45° sector out, so before
/// the lag was held every fold was fitted without it and the held-out RMS came out above the
/// in-sample one by the lag's share (about 0.16 µm RMS here, beside 0.2 µm of noise), which
/// made real effects fail and noise pass. Now each model's ℓ is estimated once on the whole
/// trace and held in all its folds: the final (here the base) model's must be the simulated 30 ms within three standard errors
/// (σ_ℓ = noise / (v/R·|c|·√(n/2)), the derivative column σ·(v/R)·(c_p sin θ − c_q cos θ)
/// having an RMS of (v/R)·|c|/√2 over the circle), the base model's held-out RMS must be its
/// in-sample RMS within 2 % (white noise and 5 terms over 7 000 readings: the expected excess
/// is a few parts in a thousand), and nothing is added to the clean trace.
#[test]
fn the_servo_angle_lag_is_estimated_once_and_held_in_every_fold() {
    let hidden = Hidden {
        extra_centre: [28.0 * UM, -20.0 * UM],
        ..Hidden::default()
    };
    let centre = (40.0f64 * UM).hypot(27.0 * UM);
    for seed in 1..=3 {
        let table = simulate(&hidden, seed);
        let n = table.readings.len() as f64;
        let found = discover_ballbar(&table, &xy(), |_| {}).unwrap();
        let json = found.to_json();
        let lag_ms = json["validation"]["angle_lag_ms"].as_f64().unwrap();
        let sigma_ms = NOISE / (V / R * centre * (n / 2.0).sqrt()) * 1e3;
        let base = &json["baseline"];
        let (rms, cv) = (
            base["rms_um"].as_f64().unwrap(),
            base["cv_rms_um"].as_f64().unwrap(),
        );
        println!(
            "seed {seed}: angle lag {lag_ms} ms (30 ± {:.2}), base RMS {rms} µm, held-out {cv} µm, accepted {:?}",
            3.0 * sigma_ms,
            found.accepted()
        );
        assert!(
            (lag_ms - 30.0).abs() <= 3.0 * sigma_ms,
            "seed {seed}: {lag_ms} ms"
        );
        assert!(
            cv <= 1.02 * rms,
            "seed {seed}: held-out {cv} against {rms} µm"
        );
        assert!(found.accepted().is_empty(), "{}", found.to_text());
        assert!(found.to_text().contains("held in all its fits"));
    }
}

#[test]
fn a_clean_trace_gets_nothing_added() {
    // The base terms and white noise only, over 20 seeds: every acceptance is a false one.
    let mut false_acceptances = 0;
    let mut proposals = 0;
    for seed in 100..120 {
        let table = simulate(&Hidden::default(), seed);
        let mut tested = 0;
        let found = discover_ballbar(&table, &xy(), |_| tested += 1).unwrap();
        proposals += tested;
        false_acceptances += found.accepted().len();
        if !found.accepted().is_empty() {
            println!("seed {seed}: {}", found.to_text());
        }
    }
    println!(
        "clean traces: {false_acceptances} false acceptances, {proposals} candidates tested in 20 seeds"
    );
    assert_eq!(false_acceptances, 0);
}

/// Issue 15, item 2: every effect the table can test is scored (accepted, or rejected with
/// its held-out score in the last round, which scores every testable effect not yet in the
/// model); the others are listed with the reason. Both senses (everything testable) and one
/// sense (the sense-dependent effects untestable).
#[test]
fn every_effect_is_scored_or_the_report_says_why_not() {
    let hidden = Hidden {
        backlash: [0.0, 3.0 * UM],
        ..Hidden::default()
    };
    let table = simulate(&hidden, 6);
    let ccw = BallbarTable {
        readings: table
            .readings
            .iter()
            .filter(|r| r.sense == Sense::Ccw)
            .copied()
            .collect(),
        ..Default::default()
    };
    for (table, untestable) in [(table, 0), (ccw, 4)] {
        let found = discover_ballbar(&table, &xy(), |_| {}).unwrap();
        assert_eq!(found.untestable().len(), untestable);
        assert!(found.untestable().iter().all(|(_, why)| !why.is_empty()));
        let mut seen: Vec<BallbarEffect> = found.accepted();
        seen.extend(found.rejected().iter().map(|r| r.effect));
        seen.extend(found.untestable().iter().map(|(e, _)| *e));
        seen.sort();
        assert_eq!(seen, BallbarEffect::ALL, "each effect once");
        // A rejected effect's held-out RMS is a real score, near the final model's.
        let last = found.final_score().cv_rms;
        for r in found.rejected() {
            assert!(
                r.cv_rms.is_finite() && (r.cv_rms - last).abs() < 0.2 * last,
                "{:?}: {} against {last}",
                r.effect,
                r.cv_rms
            );
        }
        let json = found.to_json();
        let listed = json["steps"].as_array().unwrap().len()
            + json["rejected"].as_array().unwrap().len()
            + json["untestable"].as_array().unwrap().len();
        assert_eq!(listed, BallbarEffect::ALL.len());
        assert!(
            found
                .to_text()
                .contains("Every effect this table can test was scored")
        );
    }
}

#[test]
fn one_sense_cannot_test_the_sense_dependent_effects() {
    let table = simulate(&Hidden::default(), 4);
    let ccw = BallbarTable {
        readings: table
            .readings
            .iter()
            .filter(|r| r.sense == Sense::Ccw)
            .copied()
            .collect(),
        ..Default::default()
    };
    let found = discover_ballbar(&ccw, &xy(), |_| {}).unwrap();
    let untestable: Vec<BallbarEffect> = found.untestable().iter().map(|(e, _)| *e).collect();
    assert_eq!(
        untestable,
        [
            BallbarEffect::ServoMismatch,
            BallbarEffect::LateralPlayP,
            BallbarEffect::LateralPlayQ,
            BallbarEffect::SenseRadius
        ]
    );
    assert!(found.untestable()[0].1.contains("both senses"));
    assert!(found.accepted().is_empty(), "{:?}", found.accepted());
    let json = found.to_json();
    assert_eq!(json["untestable"][0]["effect"], "servo_mismatch");
}

#[test]
fn too_few_readings_are_refused() {
    let table = simulate(&Hidden::default(), 5);
    let sparse = BallbarTable {
        readings: table.readings.iter().step_by(150).copied().collect(),
        ..Default::default()
    };
    let error = discover_ballbar(&sparse, &xy(), |_| {}).unwrap_err();
    assert!(error.to_string().contains("at least 200"), "{error}");
    let bad = CircularTest { feed: 0.0, ..xy() };
    let error = discover_ballbar(&table, &bad, |_| {}).unwrap_err();
    assert!(error.to_string().contains("feed 0 mm/min"), "{error}");
}

/// Issue 36, item 3: on every shape of trace the reader accepts (both senses or one, full
/// circles or partial arcs, with a time column or without, when the time is the readings'
/// order), each effect planted alone in the simulator above, at 10–30 times the noise, is
/// taken up by its own terms (the fit with it leaves at most half of what the base model
/// leaves beyond the noise's expected sum of squares n·σ², which the n ≈ 14 000 readings fix
/// to about 1 %), or the problem names it untestable with a reason. Which are testable is written
/// here by hand for the full-circle shapes (one sense cannot tell the sense-dependent terms
/// from the base); on partial arcs the problem's own identifiability decides and the test asks
/// only that each effect acts or is named.
#[test]
fn every_effect_acts_or_is_named_untestable_on_every_trace_shape() {
    use crate::common::discovery_rss;
    use mtwin::discovery::engine::Problem;
    use mtwin::kinds::ballbar::discovery::BallbarProblem;
    let planted = |effect: BallbarEffect| -> Hidden {
        let h = Hidden::default();
        match effect {
            BallbarEffect::ServoMismatch => Hidden { servo: 0.0006, ..h },
            BallbarEffect::BacklashP => Hidden {
                backlash: [4.0 * UM, 0.0],
                ..h
            },
            BallbarEffect::BacklashQ => Hidden {
                backlash: [0.0, 4.0 * UM],
                ..h
            },
            BallbarEffect::LateralPlayP => Hidden {
                lateral_play: [4.0 * UM, 0.0],
                ..h
            },
            BallbarEffect::LateralPlayQ => Hidden {
                lateral_play: [0.0, 4.0 * UM],
                ..h
            },
            BallbarEffect::ReversalSpikeP => Hidden {
                spike: [(6.0 * UM, 0.015), (0.0, 1.0)],
                ..h
            },
            BallbarEffect::ReversalSpikeQ => Hidden {
                spike: [(0.0, 1.0), (6.0 * UM, 0.015)],
                ..h
            },
            BallbarEffect::StraightnessP => Hidden {
                straightness: [4.0 * UM, 0.0],
                ..h
            },
            BallbarEffect::StraightnessQ => Hidden {
                straightness: [0.0, 4.0 * UM],
                ..h
            },
            BallbarEffect::CyclicP => Hidden {
                cyclic_p: (3.0 * UM, 0.010, 0.4),
                ..h
            },
            BallbarEffect::CyclicQ => Hidden {
                cyclic_q: (3.0 * UM, 0.010, 0.4),
                ..h
            },
            BallbarEffect::Lobes => Hidden {
                lobes: (5, 3.0 * UM, 0.3),
                ..h
            },
            BallbarEffect::RadiusDrift => Hidden {
                drift: 0.05 * UM,
                ..h
            },
            BallbarEffect::SenseRadius => Hidden {
                sense_radius: 4.0 * UM,
                ..h
            },
        }
    };
    let shapes: [(&str, bool, bool, Option<f64>); 5] = [
        ("full circles, both senses", true, true, None),
        (
            "full circles, both senses, no time column",
            true,
            false,
            None,
        ),
        ("full circle, ccw only", false, true, None),
        ("220° arcs, both senses", true, true, Some(220.0)),
        (
            "220° arcs, both senses, no time column",
            true,
            false,
            Some(220.0),
        ),
    ];
    for (name, both, timed, arc) in shapes {
        for effect in BallbarEffect::ALL {
            let test = xy();
            let mut table = simulate(&planted(effect), 3);
            table.readings.retain(|r| {
                (both || r.sense == Sense::Ccw) && arc.is_none_or(|a| r.angle.to_degrees() <= a)
            });
            if !timed {
                table.readings.iter_mut().for_each(|r| r.time = None);
            }
            let problem = BallbarProblem::new(&table, &test).unwrap();
            let reason = problem
                .untestable()
                .iter()
                .find(|(e, _)| *e == effect)
                .map(|(_, why)| why.clone());
            if arc.is_none() {
                let expected = both
                    || !matches!(
                        effect,
                        BallbarEffect::ServoMismatch
                            | BallbarEffect::LateralPlayP
                            | BallbarEffect::LateralPlayQ
                            | BallbarEffect::SenseRadius
                    );
                assert_eq!(
                    reason.is_none(),
                    expected,
                    "{name}: {effect:?}, reason {reason:?}"
                );
            }
            match reason {
                Some(why) => {
                    println!("{name}: {effect:?} untestable: {why}");
                    assert!(!why.is_empty());
                }
                None => {
                    let rss = |effects: &[BallbarEffect]| discovery_rss(&problem, effects);
                    // What each model leaves beyond the noise's own sum of squares.
                    let noise = problem.n_samples() as f64 * NOISE * NOISE;
                    let (base, with) = (rss(&[]) - noise, rss(&[effect]) - noise);
                    println!(
                        "{name}: {effect:?} excess sum of squares {:.1} → {:.1} µm² (noise {:.1})",
                        base / UM / UM,
                        with / UM / UM,
                        noise / UM / UM
                    );
                    assert!(with <= 0.5 * base, "{name}: {effect:?} {base} → {with}");
                }
            }
        }
    }
}

/// Issue 36, item 5: a term taken as a stand-in must not stay once the true terms explain it.
/// Lateral play of both axes, 1 µm each: σ·(|sin θ| + |cos θ|)·l/2 is mostly a constant per
/// sense (its mean over the circle is 4/π of l/2), which `sense_radius` (σ·d/2) alone
/// describes to within the variation of |sin θ| + |cos θ| (from 1 to √2). The final model must
/// be the two plays, without `sense_radius` (once a stand-in refitted to −0.001 µm and stayed),
/// which the report names as the close alternative for each play instead.
///
/// The simulator shifts the p carriage along q by +sgn(ṗ)·l/2, the model by −sgn(ṗ)·lp/2
/// (`Term::LateralPlayP`'s doc): the truth in the model's terms is −1 µm. Standard error of each
/// play: the column σ·|sin θ|/2 has an RMS of 1/(2√2) per µm, so 0.2 µm of noise over 14 138
/// readings gives 0.2/(0.354·√14138) = 0.0048 µm, 1.3 times that (0.006 µm) for the two
/// columns' correlation of 2/π (their shared σ-constant); the tolerance is 5 of those.
#[test]
fn a_stand_in_does_not_stay_once_the_true_terms_explain_it() {
    let hidden = Hidden {
        lateral_play: [1.0 * UM, 1.0 * UM],
        ..Hidden::default()
    };
    let found = discover_ballbar(&simulate(&hidden, 1), &xy(), |_| {}).unwrap();
    let mut accepted = found.accepted();
    accepted.sort();
    assert_eq!(
        accepted,
        [BallbarEffect::LateralPlayP, BallbarEffect::LateralPlayQ],
        "{}",
        found.to_text()
    );
    // Lateral play cannot time a reversal (continuous there): no lag is given, and the
    // report says why (before, the search's ends were printed: −199.75 and 194.8 ms).
    for effect in [BallbarEffect::LateralPlayP, BallbarEffect::LateralPlayQ] {
        let params = found.final_params(effect).unwrap();
        let play = params["lateral_play_um"];
        assert!((play + 1.0).abs() < 0.03, "{effect:?}: {play} µm");
        assert!(!params.contains_key("reversal_lag_ms"), "{params:?}");
    }
    let json = found.to_json();
    let notes: Vec<&str> = json["notes"]
        .as_array()
        .unwrap()
        .iter()
        .map(|n| n.as_str().unwrap())
        .collect();
    for key in ["reversal_lag_x_ms:", "reversal_lag_y_ms:"] {
        assert!(
            notes
                .iter()
                .any(|n| n.starts_with(key) && n.contains("lateral play cannot")),
            "{notes:?}"
        );
    }
    let alternatives: Vec<(&str, &str)> = json["alternatives"]
        .as_array()
        .unwrap()
        .iter()
        .map(|a| {
            (
                a["effect"].as_str().unwrap(),
                a["instead_of"].as_str().unwrap(),
            )
        })
        .collect();
    for play in ["lateral_play_x", "lateral_play_y"] {
        assert!(
            alternatives.contains(&("sense_radius", play)),
            "{alternatives:?}"
        );
    }
}

#[test]
fn a_spike_slower_than_any_searched_stays_in_the_model_without_values() {
    // A 3 µm spike of X decaying over 500 ms, beyond the 200 ms the decay search reaches: the
    // effect explains much of the trace and is accepted, but its height and decay, at the end
    // of the range, are not measurements (analyze printed 200.00 ± 1.72 ms, 3.58 ± 0.02 µm).
    let hidden = Hidden {
        spike: [(3.0 * UM, 0.5), (0.0, 0.0)],
        ..Hidden::default()
    };
    let found = discover_ballbar(&simulate(&hidden, 1), &xy(), |_| {}).unwrap();
    assert!(
        found.accepted().contains(&BallbarEffect::ReversalSpikeP),
        "{}",
        found.to_text()
    );
    let params = found.final_params(BallbarEffect::ReversalSpikeP).unwrap();
    assert!(
        !params.contains_key("amplitude_um") && !params.contains_key("decay_ms"),
        "{params:?}"
    );
    let json = found.to_json();
    assert!(
        json["notes"].as_array().unwrap().iter().any(|n| n
            .as_str()
            .unwrap()
            .starts_with("reversal_spike_x: its decay reaches the longest searched")),
        "{}",
        json["notes"]
    );
}

/// The report is the same, byte for byte, on one thread and on two: the folds' fits, the
/// searches inside them and the base model's evidence run in parallel, and every parallel
/// result is gathered in a fixed order. The trace has backlash with play, a spike and a cyclic
/// error, so the lag, decay and period searches and the play search all run.
#[test]
fn the_report_does_not_depend_on_the_thread_count() {
    let hidden = Hidden {
        backlash: [1.5 * UM, 2.0 * UM],
        spike: [(2.0 * UM, 0.02), (0.0, 0.0)],
        cyclic_p: (0.8 * UM, 0.010, 0.4),
        ..Hidden::default()
    };
    let table = simulate(&hidden, 11);
    let report = |threads: usize| {
        crate::common::on_threads(threads, || {
            let found = discover_ballbar(&table, &xy(), |_| {}).unwrap();
            (
                found.to_json().to_string(),
                found.to_text(),
                found.accepted(),
            )
        })
    };
    let (one, two) = (report(1), report(2));
    assert_eq!(one.0, two.0);
    assert_eq!(one.1, two.1);
    // The search did something to compare: the planted backlash and cyclic error were taken.
    for effect in [BallbarEffect::BacklashP, BallbarEffect::CyclicP] {
        assert!(
            one.2.contains(&effect),
            "{effect:?} not accepted: {}",
            one.1
        );
    }
}

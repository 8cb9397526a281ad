//! The spindle lesson.

use super::*;

#[test]
fn spindle_lesson_grows_the_band_and_takes_off_the_set_up_eccentricity() {
    // teach_spindle.toml: one probe x1 at azimuth 0 on vmc3's spindle (fixed sensitive
    // direction). It reads −EXS and the eccentricity e as −|e|·cos(−θ − α) (tests/
    // spindle_twin.rs), so with the injected EXS = 0.20 cos 2θ + 0.06 sin(3θ + 30°) µm (no mean,
    // no 1 UPR) and e = (2.5, 1.5) µm the synchronous signal is
    //   S(θ) = −0.20 cos 2θ − 0.06 sin(3θ + 30°) − 2.5 cos θ + 1.5 sin θ   (µm):
    // its fundamental is −2.5 cos θ + 1.5 sin θ, and without mean and fundamental −EXS is left.
    // What else reaches the 16-revolution mean at one angle: the cage line (0.04 µm at
    // 0.43 UPR) at most 0.04/(16 sin 0.43π) = 0.0026 µm, the ball pass (0.02 µm at 4.6 UPR)
    // 0.02/(16 sin 0.6π) = 0.0013 µm, the random motion (0.01 µm RMS, independent from turn to
    // turn) 0.0025 µm per angle, 0.01 µm at 4σ, the probe noise 0.5 nm, the 10 kHz low-pass's
    // lag 1e-3 × 2.9 µm = 0.003 µm: 0.02 µm at most. Taking off the mean and the 1-UPR term
    // can enlarge a bound by 1 + 1 + 4/π: 0.06 µm bounds both comparisons (the drawing's f32
    // rounding is below 1e-5 µm at these scales).
    const TOLERANCE_UM: f64 = 0.06;
    let exs = |t: f64| 0.20 * (2.0 * t).cos() + 0.06 * (3.0 * t + 30f64.to_radians()).sin();
    let fundamental = |t: f64| -2.5 * t.cos() + 1.5 * t.sin();
    let (scenario, simulation, recording) = record("teach_spindle.toml");
    let test = scenario.spindle_test.as_ref().unwrap();
    let [ex, ey] = test.artefact.eccentricity;
    assert!((ex - 2.5e-6).abs() < 1e-15 && (ey - 1.5e-6).abs() < 1e-15);
    assert_eq!((test.revolutions, test.samples_per_revolution), (16, 256));
    let table = simulation.spindle.as_ref().unwrap();
    let (k, m) = (16, 256);

    // The raw reading, every sample at its time (the programme starts at 0 s).
    let x1 = recording.scalars("spindle_um/x1");
    assert_eq!(x1.len(), k * m);
    for ((t, v), (time, reading)) in x1
        .iter()
        .zip(table.record.time.iter().zip(&table.record.readings[0]))
    {
        assert!((t - time).abs() < 2e-9 && (v - reading * 1e6).abs() < 1e-9);
    }

    // The band grows a revolution at a time, then all of them fade behind the mean.
    let revolutions = strips(&recording, "spindle_polar/revolutions");
    let counts: Vec<usize> = revolutions.iter().map(|(_, s)| s.len()).collect();
    let mut expected: Vec<usize> = (1..=k).collect();
    expected.push(k);
    assert_eq!(counts, expected);
    assert!(
        revolutions
            .iter()
            .all(|(_, s)| s.iter().all(|p| p.len() == m + 1))
    );
    // Revolution r is drawn when it ends, after its last sample and before the next one.
    for (r, (t, _)) in revolutions.iter().take(k).enumerate() {
        let last = table.record.time[(r + 1) * m - 1];
        assert!((t - last).abs() < 2e-9, "revolution {r}: {t} vs {last}");
    }

    // The fundamental taken off: first and last step differ by −2.5 cos θ + 1.5 sin θ µm.
    let steps = strips(&recording, "spindle_polar/fundamental/synchronous");
    assert_eq!(steps.len(), 21);
    let first = read_polar(&recording, "spindle_polar/fundamental", &steps[0].1[0]);
    let last = read_polar(&recording, "spindle_polar/fundamental", &steps[20].1[0]);
    assert_eq!(first.len(), m + 1);
    for ((angle, with), (same, without)) in first.iter().zip(&last) {
        let gap = (angle - same).rem_euclid(std::f64::consts::TAU);
        assert!(
            gap.min(std::f64::consts::TAU - gap) < 1e-4,
            "{angle} vs {same}"
        );
        let expected = fundamental(*angle);
        assert!(
            (with - without - expected).abs() < TOLERANCE_UM,
            "at {angle} rad: {with} − {without} vs {expected} µm"
        );
    }

    // What is left is the injected synchronous error motion, as x1 reads it: −EXS.
    let motion = strips(&recording, "spindle_polar/error_motion/synchronous");
    assert_eq!(motion.len(), 1);
    let drawn = read_polar(&recording, "spindle_polar/error_motion", &motion[0].1[0]);
    let mut worst: f64 = 0.0;
    for (angle, deviation) in &drawn {
        worst = worst.max((deviation + exs(*angle)).abs());
    }
    assert!(worst < TOLERANCE_UM, "error motion off −EXS by {worst} µm");

    // The legend names what is drawn, and the 3D scene holds the analyser.
    let text = recording.text(viz::LESSON);
    let entities = recording.entities();
    for entity in [
        "spindle_polar/synchronous",
        "spindle_polar/inner",
        "spindle_polar/outer",
        "spindle_polar/asynchronous/revolutions",
        "spindle_polar/fundamental/centre",
        "spindle_polar/error_motion/synchronous",
        "world/tool_nominal/spindle_artefact",
        "world/workpiece_nominal/spindle_probes",
        "spindle_um/<probe>",
    ] {
        assert!(
            text.contains(&format!("`{entity}`")),
            "{entity} not in the legend"
        );
        if !entity.contains('<') {
            assert!(
                entities.iter().any(|e| e == &format!("/{entity}")),
                "{entity} not logged"
            );
        }
    }
    assert!(!recording.arrows(&viz::tool_tip_error(20000.0)).is_empty());
}

//! The thermal twin: the default machine model's warm-up against the plausibility the issue
//! asks of it, and a warm-up experiment (Lu 2012 Ch. 5 style) in which the laser's deviations
//! follow position × screw temperature rise exactly as the injected model says, and the origin
//! drifts when it sits at the free end of the screw.

use mtwin::errors::ErrorModel;
use mtwin::kinds::positioning::Air;
use mtwin::kinds::positioning::LinearCycle;
use mtwin::kinds::positioning::laser::{AirCompensation, Laser, Mounting, Zeroing};
use mtwin::machine::{Axis, AxisValues, Machine, Workspace};
use mtwin::math::{Vector, seeded_rng};
use mtwin::program::Approach;
use mtwin::program::{MeasurePoint, Program, Step};
use mtwin::thermal::{Ambient, MachineThermal, ScrewSpec, ThermalStepper};
use mtwin::twin::{Twin, run_thermal};

fn vmc3() -> Machine {
    Machine::from_urdf_file(concat!(env!("CARGO_MANIFEST_DIR"), "/models/vmc3.urdf")).unwrap()
}

#[test]
fn default_model_warms_up_like_a_machine_tool() {
    // X idling at 4 800 mm/min (0.08 m/s) from 20 °C, 6 h in 60 s steps: the nut rises a few
    // °C, the screw lags it with a warm-up time constant of 20-90 min, and after 3 h the screw
    // is stable (it rises less than 10 % of its final rise in the following hour).
    let machine = vmc3();
    let thermal =
        MachineThermal::ballscrew_default(&machine, Ambient::constant(20.0), &[]).unwrap();
    let (nut, screw) = (
        thermal.network.node("x_nut").unwrap(),
        thermal.network.node("x_screw").unwrap(),
    );
    let mut speeds = AxisValues::ZERO;
    speeds[Axis::X] = 0.08;
    let mut powers = vec![0.0; thermal.network.nodes().len()];
    thermal.powers(&speeds, 0.0, &mut powers);
    let final_rise = thermal.network.steady_state(&powers, 20.0).unwrap();
    let (nut_rise, screw_rise) = (final_rise[nut] - 20.0, final_rise[screw] - 20.0);
    assert!((1.0..6.0).contains(&nut_rise), "nut rise {nut_rise} °C");
    assert!(
        screw_rise > 0.3 * nut_rise && screw_rise < nut_rise,
        "screw rise {screw_rise} °C"
    );

    let mut stepper = ThermalStepper::new(&thermal.network, 20.0);
    let mut history = vec![20.0];
    for _ in 0..360 {
        stepper.step(60.0, &powers, 20.0);
        history.push(stepper.temperatures()[screw]);
    }
    let minutes_to_63 = history
        .iter()
        .position(|t| t - 20.0 >= 0.632 * screw_rise)
        .unwrap();
    assert!(
        (20..=90).contains(&minutes_to_63),
        "screw time constant {minutes_to_63} min"
    );
    let (at_3h, at_4h) = (history[180] - 20.0, history[240] - 20.0);
    assert!(
        at_4h - at_3h < 0.1 * screw_rise,
        "still rising {} °C in the 4th hour",
        at_4h - at_3h
    );
}

/// Targets 0..750 mm every 50 mm, forward then backward (5 mm overrun), between warm-ups of
/// 30 min at 4 800 mm/min over the whole stroke: four laser runs.
fn warm_up_experiment() -> (LinearCycle, Program) {
    let mut rest = AxisValues::ZERO;
    rest[Axis::Y] = 0.205;
    rest[Axis::Z] = 0.1;
    let cycle = LinearCycle {
        axis: Axis::X,
        targets: (0..=15).map(|i| 0.05 * i as f64).collect(),
        runs: 1,
        overrun: 0.005,
        feed: 0.05,
        dwell: 1.0,
        rest,
    };
    let mut steps = Vec::new();
    for run in 0..4 {
        if run > 0 {
            steps.push(Step::WarmUp {
                axis: Axis::X,
                from: 0.0,
                to: 0.75,
                feed: 0.08,
                duration: 1800.0,
            });
        }
        steps.push(Step::Move {
            to: vec![(Axis::X, -0.005)],
            feed: 0.08,
        });
        steps.extend(cycle.run_steps(run));
    }
    let mut start = rest;
    start[Axis::X] = -0.005;
    (cycle, Program { start, steps })
}

#[test]
fn warm_up_deviations_follow_position_times_screw_temperature_rise() {
    // Origin at the free end (fixed end at X = 760 mm, as on the V30 of Lu 2012), an ideal
    // laser zeroed at 0 mm each run. Injected: e(x, T) = α·(T_screw - 20)·(x - 0.76). So each
    // reading is e(x, T_now) - e(0, T_at_zero), from the screw temperatures the twin recorded.
    let machine = vmc3();
    let thermal = MachineThermal::ballscrew_default(
        &machine,
        Ambient::constant(20.0),
        &[(
            Axis::X,
            ScrewSpec {
                fixed_end: 0.76,
                expansion: 11.7e-6,
            },
        )],
    )
    .unwrap();
    let screw = thermal.network.node("x_screw").unwrap();
    let twin = Twin {
        errors: ErrorModel::empty(&machine),
        machine,
    };
    let (cycle, program) = warm_up_experiment();
    let records = run_thermal(&twin, &thermal, &program, 60.0, &mut []);
    assert_eq!(records.len(), 4 * 2 * 16);
    let laser = Laser {
        axis: Axis::X,
        beam_offset: Vector::ZERO,
        misalignment: [0.0, 0.0],
        resolution: 0.0,
        noise: 0.0,
        air: Air::STANDARD,
        compensation: AirCompensation::Off,
        material: None,
        dead_path: 0.0,
        zero: Zeroing::EachRun,
        mounting: Mounting::InterferometerOnWorkpiece,
    };
    let visits: Vec<_> = records.iter().map(|r| r.visit).collect();
    let poses: Vec<_> = records.iter().map(|r| r.pose).collect();
    let table = laser.measure(&visits, &poses, &cycle.targets, &mut seeded_rng(1, "laser"));
    let alpha = 11.7e-6;
    let error = |x: f64, t: f64| alpha * (t - 20.0) * (x - 0.76);
    let mut last_up = Vec::new();
    for (k, (reading, record)) in table.readings.iter().zip(&records).enumerate() {
        let zero = &records[k - k % 32]; // each run has 32 readings; its first is the zero
        let expected = error(reading.target, record.temperatures[screw])
            - error(0.0, zero.temperatures[screw]);
        assert!(
            (reading.deviation - expected).abs() < 1e-12,
            "reading {k}: {} vs {expected}",
            reading.deviation
        );
        if reading.approach == Approach::Up && (reading.target - 0.75).abs() < 1e-12 {
            last_up.push((reading.deviation, record.temperatures[screw]));
        }
    }
    // The screw warms run after run, and the error at 750 mm grows with it: 11.7e-6·ΔT·0.75.
    assert!(
        last_up
            .windows(2)
            .all(|w| w[1].1 > w[0].1 + 0.1 && w[1].0 > w[0].0),
        "{last_up:?}"
    );
    let (dev, temperature) = last_up[3];
    assert!(
        (dev / (alpha * 0.75) - (temperature - 20.0)).abs() < 0.05,
        "{dev} m at {temperature} °C"
    );
}

#[test]
fn the_origin_drifts_when_it_is_at_the_free_end() {
    // After 60 min of X idling, the tool at X = 0: with the fixed end at 760 mm the origin has
    // moved by α·ΔT·(0 - 0.76) < 0; with the fixed end at the origin it has not moved.
    let machine = vmc3();
    let mut start = AxisValues::ZERO;
    start[Axis::Y] = 0.205;
    let program = Program {
        start,
        steps: vec![
            Step::WarmUp {
                axis: Axis::X,
                from: 0.0,
                to: 0.75,
                feed: 0.08,
                duration: 3600.0,
            },
            Step::Measure(MeasurePoint {
                run: 0,
                target: 0,
                approach: Approach::Down,
            }),
        ],
    };
    let twin = Twin {
        errors: ErrorModel::empty(&machine),
        machine: machine.clone(),
    };
    let drift = |fixed_end: f64| {
        let thermal = MachineThermal::ballscrew_default(
            &machine,
            Ambient::constant(20.0),
            &[(
                Axis::X,
                ScrewSpec {
                    fixed_end,
                    expansion: 11.7e-6,
                },
            )],
        )
        .unwrap();
        let screw = thermal.network.node("x_screw").unwrap();
        let record = run_thermal(&twin, &thermal, &program, 60.0, &mut [])
            .pop()
            .unwrap();
        let nominal = Workspace::new(&machine).workpiece_from_tool(
            &machine,
            &record.visit.state.position,
            None,
        );
        (
            record.pose.translation.x - nominal.translation.x,
            record.temperatures[screw] - 20.0,
        )
    };
    let (free, rise) = drift(0.76);
    assert!(rise > 0.5, "screw rise {rise}");
    assert!(
        (free - 11.7e-6 * rise * -0.76).abs() < 1e-12 && free < -3e-6,
        "origin drift {free}"
    );
    let (fixed, _) = drift(0.0);
    assert!(fixed.abs() < 1e-15, "{fixed}");
}

#[test]
fn the_warm_up_scenario_files_follow_the_injected_thermal_model() {
    // Through the written files: between two runs at the same target and direction the cold
    // errors cancel, so the change in deviation is
    //   α·[(T₂(x) - T₁(x))·(x - 0.76) - (T₂(zero) - T₁(zero))·(0.005 - 0.76)]
    // with the true screw temperatures from truth.json (the zero is each run's first reading,
    // at 5 mm). The laser adds 20 nm of noise per reading (two readings: 28 nm) and 1 nm
    // steps: allow 5 × 28 nm + 2 nm.
    use mtwin::app::{Scenario, run_scenario};
    let scenario = Scenario::load(concat!(
        env!("CARGO_MANIFEST_DIR"),
        "/scenarios/vmc3_warmup_laser.toml"
    ))
    .unwrap();
    let output = run_scenario(&scenario).unwrap();
    let file = |name: &str| {
        output
            .files
            .iter()
            .find(|(n, _)| n == name)
            .unwrap()
            .1
            .clone()
    };
    let csv = String::from_utf8(file("positioning.csv")).unwrap();
    let rows: Vec<Vec<String>> = csv
        .lines()
        .filter(|l| !l.starts_with('#'))
        .skip(1)
        .map(|l| l.split(',').map(String::from).collect())
        .collect();
    assert_eq!(rows.len(), 7 * 2 * 16);
    let truth: serde_json::Value = serde_json::from_slice(&file("truth.json")).unwrap();
    let states = &truth["thermal_states"];
    let screw = states["nodes"]
        .as_array()
        .unwrap()
        .iter()
        .position(|n| n == "x_screw")
        .unwrap();
    let temperature = |row: usize| states["temperatures_degc"][row][screw].as_f64().unwrap();
    let alpha = 11.7e-6;
    let per_run = 32;
    let mut checked = 0;
    for run in 1..7 {
        for k in 0..per_run {
            let (a, b) = (k, run * per_run + k); // same target and direction, run 1 and run `run + 1`
            assert_eq!((&rows[a][2], &rows[a][3]), (&rows[b][2], &rows[b][3]));
            let x = rows[a][3].parse::<f64>().unwrap() * 1e-3;
            let change =
                (rows[b][4].parse::<f64>().unwrap() - rows[a][4].parse::<f64>().unwrap()) * 1e-6;
            let (zero_a, zero_b) = (0, run * per_run);
            let expected = alpha
                * ((temperature(b) - temperature(a)) * (x - 0.76)
                    - (temperature(zero_b) - temperature(zero_a)) * (0.005 - 0.76));
            assert!(
                (change - expected).abs() < 5.0 * 28e-9 + 2e-9,
                "run {} row {k}: {change} vs {expected}",
                run + 1
            );
            checked += 1;
        }
    }
    assert_eq!(checked, 6 * 32);
    // And the error really grew: at 755 mm the last run is more than 15 µm off the first.
    let last_up = |run: usize| rows[run * per_run + 15][4].parse::<f64>().unwrap();
    assert!(
        last_up(6) - last_up(0) > 15.0,
        "{} µm",
        last_up(6) - last_up(0)
    );
}

#[test]
fn the_linear_motion_test_reads_as_iso_230_3_asks() {
    // Targets 20 and 740 mm at 10 000 mm/min with 2 s dwells: a bidirectional cycle takes
    // 2·(0.72 m / (1/6 m/s) + 2 s) = 12.64 s, so 4 h hold 1139 cycles; a reading pair every 5th
    // (227) after the first pair, then 12 cool-down visits 5 min apart: 240 pairs.
    use mtwin::kinds::positioning::LinearMotionTest;
    use mtwin::program::visits;
    let mut rest = AxisValues::ZERO;
    rest[Axis::Y] = 0.205;
    let test = LinearMotionTest {
        axis: Axis::X,
        targets: [0.02, 0.74],
        feed: 10.0 / 60.0,
        dwell: 2.0,
        cycling: 4.0 * 3600.0,
        read_every: 5,
        cooldown: 3600.0,
        visit_interval: 300.0,
        rest,
    };
    let readings = visits(&test.program().timeline(f64::INFINITY));
    assert_eq!(readings.len(), 2 * 240);
    assert!(
        readings
            .iter()
            .all(|v| (v.point.target == 0) == (v.point.approach == Approach::Down))
    );
    let cooldown: Vec<f64> = readings
        .iter()
        .filter(|v| v.point.run >= 228 && v.point.target == 0)
        .map(|v| v.time)
        .collect();
    assert_eq!(cooldown.len(), 12);
    assert!(
        cooldown
            .windows(2)
            .all(|w| (w[1] - w[0] - 300.0).abs() < 1e-9),
        "{cooldown:?}"
    );
    assert!(cooldown[0] > 4.0 * 3600.0 && cooldown[11] <= 5.0 * 3600.0 + 60.0);
}

#[test]
fn the_linear_motion_scenario_drift_follows_the_screw_temperature() {
    // Zeroed once: at each target the drift from its first reading is
    // α·(T_screw(t) - T_screw(t₀))·(P - 0.76) (origin at the free end), within the noise of two
    // readings (5 × 28 nm + 2 nm). P1 = 20 mm drifts strongly negative, P2 = 740 mm barely.
    use mtwin::app::{Scenario, run_scenario};
    let scenario = Scenario::load(concat!(
        env!("CARGO_MANIFEST_DIR"),
        "/scenarios/vmc3_iso230_3_linear.toml"
    ))
    .unwrap();
    let output = run_scenario(&scenario).unwrap();
    let file = |name: &str| {
        output
            .files
            .iter()
            .find(|(n, _)| n == name)
            .unwrap()
            .1
            .clone()
    };
    let csv = String::from_utf8(file("positioning.csv")).unwrap();
    let rows: Vec<Vec<String>> = csv
        .lines()
        .filter(|l| !l.starts_with('#'))
        .skip(1)
        .map(|l| l.split(',').map(String::from).collect())
        .collect();
    let truth: serde_json::Value = serde_json::from_slice(&file("truth.json")).unwrap();
    let states = &truth["thermal_states"];
    let screw = states["nodes"]
        .as_array()
        .unwrap()
        .iter()
        .position(|n| n == "x_screw")
        .unwrap();
    let temperature = |row: usize| states["temperatures_degc"][row][screw].as_f64().unwrap();
    let deviation = |row: usize| rows[row][4].parse::<f64>().unwrap() * 1e-6;
    for (first, p) in [(0usize, 0.02), (1, 0.74)] {
        let mut largest: f64 = 0.0;
        for row in (first..rows.len()).step_by(2) {
            let drift = deviation(row) - deviation(first);
            let expected = 11.7e-6 * (temperature(row) - temperature(first)) * (p - 0.76);
            assert!(
                (drift - expected).abs() < 5.0 * 28e-9 + 2e-9,
                "P = {p}, row {row}: {drift} vs {expected}"
            );
            largest = largest.max(drift.abs());
        }
        if p < 0.5 {
            assert!(largest > 20e-6, "P1 drifts: {largest}");
        } else {
            assert!(
                largest < 2e-6,
                "P2 near the fixed end barely drifts: {largest}"
            );
        }
    }
}

#[test]
fn material_compensation_on_the_screw_hides_its_expansion() {
    // The warm-up experiment again, with the laser's NDE sensor on the X screw and the screw's
    // own 11.7 ppm/K: the reading is scaled by 1 - α·(T_screw - 20), which undoes the screw's
    // expansion α·ΔT·(x - x₀) to second order (α²ΔT² ~ 1e-9). The 20 µm warm-up drift vanishes,
    // which is why ISO 230-3 §7.2.5 forbids NDE in drift tests. Between the first and last runs
    // at 755 mm only the noise of two readings remains (5 × 28 nm + 2 nm).
    use mtwin::app::{Scenario, run_scenario};
    let original = std::fs::read_to_string(concat!(
        env!("CARGO_MANIFEST_DIR"),
        "/scenarios/vmc3_warmup_laser.toml"
    ))
    .unwrap();
    let text = original
        .replace("machine = \"../models/vmc3.urdf\"", &format!("machine = '{}/models/vmc3.urdf'", env!("CARGO_MANIFEST_DIR")))
        .replace("compensation = \"sensors\"", "compensation = \"sensors\"\nmaterial = { expansion_ppm_per_degc = 11.7, node = \"x_screw\" }");
    assert_ne!(text, original);
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("nde.toml");
    std::fs::write(&path, text).unwrap();
    let output = run_scenario(&Scenario::load(&path).unwrap()).unwrap();
    let csv = String::from_utf8(
        output
            .files
            .iter()
            .find(|(n, _)| n == "positioning.csv")
            .unwrap()
            .1
            .clone(),
    )
    .unwrap();
    let rows: Vec<Vec<String>> = csv
        .lines()
        .filter(|l| !l.starts_with('#'))
        .skip(1)
        .map(|l| l.split(',').map(String::from).collect())
        .collect();
    let at = |row: usize| rows[row][4].parse::<f64>().unwrap();
    assert_eq!(rows[15][3], "755.000000");
    let change = at(6 * 32 + 15) - at(15);
    assert!(
        change.abs() < 5.0 * 0.028 + 0.002,
        "drift with NDE {change} µm"
    );
    // A node the thermal model lacks is refused.
    std::fs::write(
        &path,
        std::fs::read_to_string(&path)
            .unwrap()
            .replace("node = \"x_screw\"", "node = \"x_scale\""),
    )
    .unwrap();
    let error = Scenario::load(&path).unwrap_err();
    assert!(error.to_string().contains("x_scale"), "{error}");
}

#[test]
fn heat_inputs_follow_the_axis_and_spindle_speeds() {
    // 250 W per m/s into the X nut and 150 W per m/s into its motor: at 0.08 m/s, 20 W and 12 W;
    // the spindle bearing takes 0.05 W per rad/s: 50 W at 1000 rad/s; nothing else is heated.
    let machine = vmc3();
    let thermal =
        MachineThermal::ballscrew_default(&machine, Ambient::constant(20.0), &[]).unwrap();
    let mut speeds = AxisValues::ZERO;
    speeds[Axis::X] = 0.08;
    let mut powers = vec![0.0; thermal.network.nodes().len()];
    thermal.powers(&speeds, 1000.0, &mut powers);
    let node = |name: &str| powers[thermal.network.node(name).unwrap()];
    assert!((node("x_nut") - 20.0).abs() < 1e-12 && (node("x_motor") - 12.0).abs() < 1e-12);
    assert!((node("spindle_bearing") - 50.0).abs() < 1e-12);
    assert!((powers.iter().sum::<f64>() - 82.0).abs() < 1e-12);
}

#[test]
fn a_programme_heats_a_node_as_the_closed_form_says() {
    // One node (1000 J/K, 2 W/K to 20 °C air) heated by 250 W per m/s of X. X moves 0.6 m at
    // 0.01 m/s (2.5 W for 60 s), then dwells 440 s: T(60) = 20 + 1.25·(1 - e^(-60/500)), and
    // T(500) = 20 + (T(60) - 20)·e^(-440/500). Intervals of 7 s or 1000 s give the same.
    use mtwin::thermal::{HeatDriver, HeatSource, ThermalErrors, ThermalNetwork, ThermalNode};
    let machine = vmc3();
    let network = ThermalNetwork::new(
        vec![ThermalNode {
            name: "x_nut".into(),
            capacity: 1000.0,
            to_ambient: 2.0,
        }],
        &[],
    )
    .unwrap();
    let thermal = MachineThermal {
        errors: ThermalErrors::new(&machine, 1, vec![]).unwrap(),
        network,
        sources: vec![HeatSource {
            node: 0,
            driver: HeatDriver::AxisSpeed(Axis::X),
            coefficient: 250.0,
        }],
        ambient: Ambient::constant(20.0),
        initial: 20.0,
    };
    let program = Program {
        start: AxisValues::ZERO,
        steps: vec![
            Step::Move {
                to: vec![(Axis::X, 0.6)],
                feed: 0.01,
            },
            Step::Dwell(440.0),
            Step::Measure(MeasurePoint {
                run: 0,
                target: 0,
                approach: Approach::Up,
            }),
        ],
    };
    let twin = Twin {
        errors: ErrorModel::empty(&machine),
        machine,
    };
    let t60 = 20.0 + 1.25 * (1.0 - (-60.0f64 / 500.0).exp());
    let expected = 20.0 + (t60 - 20.0) * (-440.0f64 / 500.0).exp();
    for max_interval in [7.0, 1000.0] {
        let record = run_thermal(&twin, &thermal, &program, max_interval, &mut [])
            .pop()
            .unwrap();
        assert!((record.visit.time - 500.0).abs() < 1e-9);
        assert!(
            (record.temperatures[0] - expected).abs() < 1e-9,
            "{max_interval}: {} vs {expected}",
            record.temperatures[0]
        );
    }
}

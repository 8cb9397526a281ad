//! The thermal network against closed-form step responses (one node; two nodes through their
//! eigen-decomposition, solved by hand here), step-length independence of the exact
//! integration, and the temperature sensor model.

use mtwin::math::seeded_rng;
use mtwin::thermal::{
    SensorSpec, TemperatureSensor, ThermalNetwork, ThermalNetworkError, ThermalNode, ThermalStepper,
};

/// The integration is exact for piecewise-constant inputs: only round-off remains.
const EXACT_DEGC: f64 = 1e-9;

fn node(name: &str, capacity: f64, to_ambient: f64) -> ThermalNode {
    ThermalNode {
        name: name.into(),
        capacity,
        to_ambient,
    }
}

/// Runs `total` seconds in steps of `dt` (the last one shorter if needed).
fn run(stepper: &mut ThermalStepper, total: f64, dt: f64, power: &[f64], ambient: f64) {
    let mut t = 0.0;
    while t < total - 1e-9 {
        let step = dt.min(total - t);
        stepper.step(step, power, ambient);
        t += step;
    }
}

#[test]
fn one_node_follows_the_exponential_step_response() {
    // C = 1000 J/K, G = 2 W/K to 20 °C air, P = 10 W: τ = C/G = 500 s, steady rise P/G = 5 K.
    let network = ThermalNetwork::new(vec![node("nut", 1000.0, 2.0)], &[]).unwrap();
    for (t, dt) in [
        (500.0, 500.0),
        (500.0, 10.0),
        (1234.0, 7.0),
        (3000.0, 250.0),
    ] {
        let mut stepper = ThermalStepper::new(&network, 20.0);
        run(&mut stepper, t, dt, &[10.0], 20.0);
        let expected = 20.0 + 5.0 * (1.0 - (-t / 500.0f64).exp());
        let got = stepper.temperatures()[0];
        assert!(
            (got - expected).abs() < EXACT_DEGC,
            "t = {t}, dt = {dt}: {got} vs {expected}"
        );
    }
    assert_eq!(network.steady_state(&[10.0], 20.0).unwrap(), [25.0]);
}

#[test]
fn two_nodes_follow_their_modal_solution() {
    // Node 1 (C1 = 2000 J/K, heated with 50 W) is linked to node 2 (C2 = 20000 J/K) by
    // G12 = 5 W/K; node 2 loses to 20 °C air through G2a = 10 W/K; all start at 20 °C.
    // Steady: T2 = 20 + 50/10 = 25 °C, T1 = T2 + 50/5 = 35 °C.
    // dT/dt = A (T - T_ss), A = [[-G12/C1, G12/C1], [G12/C2, -(G12 + G2a)/C2]].
    let (c1, c2, g12, g2a, p) = (2000.0, 20000.0, 5.0, 10.0, 50.0);
    let network = ThermalNetwork::new(
        vec![node("n1", c1, 0.0), node("n2", c2, g2a)],
        &[("n1", "n2", g12)],
    )
    .unwrap();
    let (a11, a12, a21, a22): (f64, f64, f64, f64) =
        (-g12 / c1, g12 / c1, g12 / c2, -(g12 + g2a) / c2);
    let (trace, det) = (a11 + a22, a11 * a22 - a12 * a21);
    let root = (trace * trace - 4.0 * det).sqrt();
    let (l1, l2) = ((trace + root) / 2.0, (trace - root) / 2.0);
    // Eigenvectors from the first row: v = (a12, λ - a11).
    let (v1, v2) = ([a12, l1 - a11], [a12, l2 - a11]);
    // Initial offset from the steady state (-15, -5) = k1·v1 + k2·v2.
    let (e1, e2) = (20.0 - 35.0, 20.0 - 25.0);
    let d = v1[0] * v2[1] - v2[0] * v1[1];
    let (k1, k2) = ((e1 * v2[1] - v2[0] * e2) / d, (v1[0] * e2 - e1 * v1[1]) / d);
    // Time constants 1/|λ|: about 37 and 6 minutes.
    assert!((1.0 / -l1 / 60.0 - 37.4).abs() < 0.1 && (1.0 / -l2 / 60.0 - 5.94).abs() < 0.1);
    for (t, dt) in [(60.0, 60.0), (600.0, 13.0), (3600.0, 600.0), (7200.0, 1.0)] {
        let mut stepper = ThermalStepper::new(&network, 20.0);
        run(&mut stepper, t, dt, &[p, 0.0], 20.0);
        let expected = [
            35.0 + k1 * v1[0] * (l1 * t).exp() + k2 * v2[0] * (l2 * t).exp(),
            25.0 + k1 * v1[1] * (l1 * t).exp() + k2 * v2[1] * (l2 * t).exp(),
        ];
        for (got, want) in stepper.temperatures().iter().zip(expected) {
            assert!(
                (got - want).abs() < EXACT_DEGC,
                "t = {t}, dt = {dt}: {got} vs {want}"
            );
        }
    }
    let steady = network.steady_state(&[p, 0.0], 20.0).unwrap();
    assert!((steady[0] - 35.0).abs() < 1e-12 && (steady[1] - 25.0).abs() < 1e-12);
}

#[test]
fn ambient_changes_reach_the_nodes_through_their_conductances() {
    // No heat input, air steps from 20 to 23 °C: a single node follows 3·(1 - e^(-t/τ)).
    let network = ThermalNetwork::new(vec![node("bed", 50000.0, 25.0)], &[]).unwrap();
    let mut stepper = ThermalStepper::new(&network, 20.0);
    run(&mut stepper, 2000.0, 100.0, &[0.0], 23.0);
    let expected = 20.0 + 3.0 * (1.0 - (-2000.0 / 2000.0f64).exp());
    assert!((stepper.temperatures()[0] - expected).abs() < EXACT_DEGC);
}

#[test]
fn bad_networks_are_refused() {
    let bad = |nodes: Vec<ThermalNode>, links: &[(&str, &str, f64)]| {
        ThermalNetwork::new(nodes, links).unwrap_err()
    };
    assert!(matches!(
        bad(vec![node("a", 0.0, 1.0)], &[]),
        ThermalNetworkError::Capacity(_)
    ));
    assert!(matches!(
        bad(vec![node("a", 1.0, -1.0)], &[]),
        ThermalNetworkError::Conductance(_)
    ));
    assert!(matches!(
        bad(vec![node("a", 1.0, f64::NAN)], &[]),
        ThermalNetworkError::Conductance(_)
    ));
    assert!(matches!(
        bad(vec![node("a", 1.0, 1.0)], &[("a", "b", 1.0)]),
        ThermalNetworkError::Link(_)
    ));
    assert!(matches!(
        bad(vec![node("a", 1.0, 1.0)], &[("a", "a", 1.0)]),
        ThermalNetworkError::Link(_)
    ));
    assert!(matches!(
        bad(vec![node("a", 1.0, 1.0), node("a", 2.0, 1.0)], &[]),
        ThermalNetworkError::Duplicate(_)
    ));
    let isolated = ThermalNetwork::new(vec![node("a", 1.0, 0.0)], &[]).unwrap();
    assert!(
        isolated.steady_state(&[1.0], 20.0).is_none(),
        "no path to the air: no steady state"
    );
}

#[test]
fn sensor_lags_offsets_and_quantises() {
    // τ = 20 s, node steps from 20 to 30 °C: after 20 s the sensor has closed 1 - e⁻¹ of the gap.
    let spec = SensorSpec {
        name: "nut".into(),
        offset: 0.0,
        noise: 0.0,
        resolution: 0.0,
        time_constant: 20.0,
    };
    let mut sensor = TemperatureSensor::new(spec, 20.0, seeded_rng(1, "nut"));
    sensor.follow(30.0, 30.0, 20.0);
    let reading = sensor.read(30.0);
    assert!((reading - (30.0 - 10.0 * (-1.0f64).exp())).abs() < 1e-12);
    // Offset 0.3 °C and 0.1 °C resolution on a settled 25.04 °C node: 25.34 → 25.3.
    let spec = SensorSpec {
        name: "air".into(),
        offset: 0.3,
        noise: 0.0,
        resolution: 0.1,
        time_constant: 0.0,
    };
    let mut sensor = TemperatureSensor::new(spec, 25.04, seeded_rng(1, "air"));
    assert!((sensor.read(25.04) - 25.3).abs() < 1e-12);
}

#[test]
fn sensor_noise_has_its_standard_deviation_and_depends_only_on_the_seed() {
    let spec = SensorSpec {
        name: "column".into(),
        offset: 0.0,
        noise: 0.05,
        resolution: 0.0,
        time_constant: 0.0,
    };
    let readings = |seed: u64| {
        let mut sensor = TemperatureSensor::new(spec.clone(), 20.0, seeded_rng(seed, "column"));
        (0..20000).map(|_| sensor.read(20.0)).collect::<Vec<_>>()
    };
    let a = readings(3);
    assert_eq!(a, readings(3));
    assert_ne!(a, readings(4));
    let n = a.len() as f64;
    let mean = a.iter().sum::<f64>() / n;
    let sd = (a.iter().map(|x| (x - mean).powi(2)).sum::<f64>() / (n - 1.0)).sqrt();
    // 20000 draws: the sample sd is within 3 % of σ (its own sd is σ/√(2n) ≈ 0.5 %), and the
    // mean within 4 standard errors (σ/√n ≈ 3.5e-4 °C).
    assert!((sd / 0.05 - 1.0).abs() < 0.03, "sd {sd}");
    assert!((mean - 20.0).abs() < 4.0 * 0.05 / n.sqrt(), "mean {mean}");
}

mod thermal_errors {
    use mtwin::errors::ErrorModel;
    use mtwin::machine::{Axis, AxisValues, Machine, MachineState, Workspace};
    use mtwin::math::Vector;
    use mtwin::thermal::{ThermalErrors, ThermalTerm, ThermalTermError};

    fn vmc3() -> Machine {
        Machine::from_urdf_file(concat!(env!("CARGO_MANIFEST_DIR"), "/models/vmc3.urdf")).unwrap()
    }

    /// The deviation the thermal terms alone cause at `state` with node `temperatures`.
    fn deviation(
        machine: &Machine,
        terms: Vec<ThermalTerm>,
        temperatures: &[f64],
        state: &MachineState,
    ) -> Vector {
        let thermal = ThermalErrors::new(machine, temperatures.len(), terms).unwrap();
        let mut extra = vec![[0.0; 6]; machine.slot_count()];
        thermal.slot_twists(temperatures, state, &mut extra);
        let errors = ErrorModel::empty(machine);
        let mut workspace = Workspace::new(machine);
        let nominal = workspace
            .workpiece_from_tool(machine, &state.position, None)
            .translation;
        errors
            .workpiece_from_tool_with(machine, &mut workspace, state, Some(&extra))
            .translation
            - nominal
    }

    fn at_x(x_mm: f64) -> MachineState {
        MachineState::at(AxisValues::from_file_units(&[
            (Axis::X, x_mm),
            (Axis::Y, 200.0),
            (Axis::Z, 100.0),
        ]))
    }

    #[test]
    fn screw_expansion_grows_from_the_fixed_end() {
        // Steel screw (11.7e-6/K) 5 K above its reference. Origin at the fixed end: +29.25 µm at
        // X = 500 mm, nothing at 0. Origin at the free end (fixed end at 760 mm): the origin
        // drifts by -11.7e-6·5·0.76 = -44.46 µm and the error vanishes at the fixed end.
        let machine = vmc3();
        let screw = |fixed_end: f64| ThermalTerm::ScrewExpansion {
            axis: Axis::X,
            screw: 0,
            expansion: 11.7e-6,
            fixed_end,
            reference: 20.0,
        };
        let d = deviation(&machine, vec![screw(0.0)], &[25.0], &at_x(500.0));
        assert!(
            (d - Vector::new(29.25e-6, 0.0, 0.0)).length() < 1e-12,
            "{d:?}"
        );
        assert!(deviation(&machine, vec![screw(0.0)], &[25.0], &at_x(0.0)).length() < 1e-15);
        let origin = deviation(&machine, vec![screw(0.76)], &[25.0], &at_x(0.0));
        assert!((origin.x + 44.46e-6).abs() < 1e-12, "{origin:?}");
        assert!(deviation(&machine, vec![screw(0.76)], &[25.0], &at_x(760.0)).length() < 1e-15);
    }

    #[test]
    fn spindle_growth_and_column_tilt_move_the_tool_as_derived() {
        let machine = vmc3();
        // 1 µm/K at 10 K above reference: the tip moves 10 µm down (-Z, towards the table).
        let growth = ThermalTerm::SpindleGrowth {
            node: 0,
            growth: 1e-6,
            reference: 20.0,
        };
        let d = deviation(&machine, vec![growth], &[30.0], &at_x(300.0));
        assert!(
            (d - Vector::new(0.0, 0.0, -10e-6)).length() < 1e-12,
            "{d:?}"
        );
        // 2 µrad/K × 1.5 K front-back = 3 µrad about X at the head, whose reference point is
        // 0.35 m behind and 0.30 m above the tip: (dy, dz) = ε·(0.30, 0.35) to first order.
        let tilt = ThermalTerm::ColumnTilt {
            front: 0,
            back: 1,
            tilt: 2e-6,
        };
        let d = deviation(&machine, vec![tilt], &[21.5, 20.0], &at_x(300.0));
        assert!(
            (d - Vector::new(0.0, 0.9e-6, 1.05e-6)).length() < 1e-11,
            "{d:?}"
        );
    }

    #[test]
    fn terms_that_do_not_fit_are_refused() {
        let machine = vmc3();
        let on_a = ThermalTerm::ScrewExpansion {
            axis: Axis::A,
            screw: 0,
            expansion: 1e-5,
            fixed_end: 0.0,
            reference: 20.0,
        };
        assert_eq!(
            ThermalErrors::new(&machine, 1, vec![on_a]).unwrap_err(),
            ThermalTermError::Axis(Axis::A)
        );
        let missing = ThermalTerm::SpindleGrowth {
            node: 3,
            growth: 1e-6,
            reference: 20.0,
        };
        assert_eq!(
            ThermalErrors::new(&machine, 2, vec![missing]).unwrap_err(),
            ThermalTermError::Node(3)
        );
    }
}

#[test]
fn sensor_lag_behind_a_ramp_is_tau_times_the_rate_whatever_the_step() {
    // A node rising at 0.01 °C/s for 10 min, a 120 s lag: the first-order hold is exact for a
    // ramp, so after the transient the sensor trails by τ·r = 1.2 °C (less the transient
    // τ·r·e^(-t/τ) = 1.2·e^(-5) = 0.008 °C still left at 600 s), with 1 s steps or 60 s steps.
    let spec = SensorSpec {
        name: "nut".into(),
        offset: 0.0,
        noise: 0.0,
        resolution: 0.0,
        time_constant: 120.0,
    };
    for dt in [1.0, 60.0, 600.0] {
        let mut sensor = TemperatureSensor::new(spec.clone(), 20.0, seeded_rng(1, "nut"));
        let mut t = 0.0;
        while t < 600.0 - 1e-9 {
            sensor.follow(20.0 + 0.01 * t, 20.0 + 0.01 * (t + dt), dt);
            t += dt;
        }
        let lag = 26.0 - sensor.read(26.0);
        let expected = 1.2 * (1.0 - (-5.0f64).exp());
        assert!(
            (lag - expected).abs() < 1e-9,
            "dt = {dt}: lag {lag} vs {expected}"
        );
    }
}

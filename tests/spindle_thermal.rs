//! The ISO 230-3 §6 spindle thermal test (`[iso230_3_spindle]`): the section parsed on its own
//! (beside a scenario loaded without it), run through the thermal twin, and its `drift` table
//! evaluated by `mtwin analyze drift`. The temperatures and the Z drift are checked against the
//! closed-form step response of a two-node network and against an explicit Euler integration
//! of the whole default network written here; the analysis against the table's own ranges.

use mtwin::app::Scenario;
use mtwin::kinds::drift::spindle_test::{self, SpeedProgramme, SpindleThermalTest};
use mtwin::kinds::drift::{DriftTable, SpindleThermalRun};
use mtwin::machine::Machine;
use mtwin::scenario::ThermalSetup;
use mtwin::thermal::{
    Ambient, HeatDriver, HeatSource, MachineThermal, SensorSpec, ThermalErrors, ThermalNetwork,
    ThermalNode, ThermalTerm,
};
use mtwin::twin::Twin;
use std::path::PathBuf;

fn root() -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR"))
}

/// vmc3 without geometric errors, from the bundled ETVE scenario (the spindle section is not
/// registered in `Scenario` for this test: it is parsed on its own below).
fn twin() -> Twin {
    let scenario = Scenario::load(root().join("scenarios/vmc3_iso230_3_etve.toml")).unwrap();
    assert!(
        scenario.error_specs.is_empty(),
        "the ETVE scenario injects no geometric errors"
    );
    scenario.twin
}

const BUNDLED: &str = "scenarios/vmc3_iso230_3_spindle.toml";

/// The bundled scenario's `[thermal]` and `[iso230_3_spindle]`.
fn bundled(machine: &Machine) -> (SpindleThermalTest, ThermalSetup) {
    let text = std::fs::read_to_string(root().join(BUNDLED)).unwrap();
    let etve = std::fs::read_to_string(root().join("scenarios/vmc3_iso230_3_etve.toml")).unwrap();
    let machine_line = "machine = \"../models/vmc3.urdf\"";
    assert!(text.contains(machine_line) && etve.contains(machine_line));
    spindle_test::parse_sections(BUNDLED, &text, machine)
        .unwrap()
        .expect("the scenario has the section")
}

/// A scenario text with `section` as its `[iso230_3_spindle]` and the bundled `[thermal]`.
fn with_section(section: &str) -> String {
    format!(
        "schema = 1\nmachine = \"../models/vmc3.urdf\"\nseed = 1\n\n[thermal]\nambient_degc = 20.0\n\n[iso230_3_spindle]\n{section}"
    )
}

const NEST: &str =
    "nest = { first_mm = 20.0, spacing_mm = 100.0, noise_um = 0.02, resolution_um = 0.01 }\n";
const HOLD: &str = "hold_mm = { x = 380.0, y = 205.0, z = 260.0 }\n";

fn parse(section: &str, machine: &Machine) -> (SpindleThermalTest, ThermalSetup) {
    spindle_test::parse_sections("t.toml", &with_section(section), machine)
        .unwrap()
        .unwrap()
}

// ---------------------------------------------------------------------------------------------
// The two-node network: bearing (heated by the spindle) and housing (whose growth is the Z
// drift), each losing heat to the air, linked to each other.

/// Capacities (J/K), conductances (W/K), heat per spindle speed (W per rad/s), growth (m/K):
/// the default model's bearing and housing, the housing's link to the column lumped into its
/// loss to the air (8 + 5 W/K).
const C_B: f64 = 3_000.0;
const C_H: f64 = 20_000.0;
const G_BA: f64 = 2.0;
const G_HA: f64 = 13.0;
const G_BH: f64 = 10.0;
const HEAT: f64 = 0.05;
const GROWTH: f64 = 1e-6;
const AIR: f64 = 20.0;

fn two_node_setup(machine: &Machine) -> ThermalSetup {
    let node = |name: &str, capacity, to_ambient| ThermalNode {
        name: name.into(),
        capacity,
        to_ambient,
    };
    let network = ThermalNetwork::new(
        vec![
            node("spindle_bearing", C_B, G_BA),
            node("spindle_housing", C_H, G_HA),
        ],
        &[("spindle_bearing", "spindle_housing", G_BH)],
    )
    .unwrap();
    let errors = ThermalErrors::new(
        machine,
        2,
        vec![ThermalTerm::SpindleGrowth {
            node: 1,
            growth: GROWTH,
            reference: AIR,
        }],
    )
    .unwrap();
    let thermometer = |name: &str| SensorSpec {
        name: name.into(),
        offset: 0.0,
        noise: 0.0,
        resolution: 0.0,
        time_constant: 0.0,
    };
    ThermalSetup {
        thermal: MachineThermal {
            network,
            sources: vec![HeatSource {
                node: 0,
                driver: HeatDriver::Spindle,
                coefficient: HEAT,
            }],
            errors,
            ambient: Ambient::constant(AIR),
            initial: AIR,
        },
        sensors: vec![(0, thermometer("bearing")), (1, thermometer("spindle"))],
        max_interval: 60.0,
    }
}

/// The rises above the air `x = (x_b, x_h)` obey `x' = A·x + (P/C_b, 0)`. Its closed form over
/// a time `t` with constant heat `p` (W), from `x0`:
/// `x(t) = x_ss + exp(A·t)·(x0 − x_ss)`, with `x_ss = −A⁻¹·(p/C_b, 0)` and, by Sylvester's
/// formula for the 2 × 2 matrix with real eigenvalues λ₁ ≠ λ₂,
/// `exp(A·t) = (e^(λ₁t)·(A − λ₂I) − e^(λ₂t)·(A − λ₁I)) / (λ₁ − λ₂)`.
fn two_node(x0: [f64; 2], p: f64, t: f64) -> [f64; 2] {
    let a = [
        [-(G_BA + G_BH) / C_B, G_BH / C_B],
        [G_BH / C_H, -(G_HA + G_BH) / C_H],
    ];
    let trace = a[0][0] + a[1][1];
    let det = a[0][0] * a[1][1] - a[0][1] * a[1][0];
    let root = (trace * trace - 4.0 * det).sqrt();
    let (l1, l2) = ((trace + root) / 2.0, (trace - root) / 2.0);
    // Steady state: A·x_ss = −(p/C_b, 0).
    let rhs = [-p / C_B, 0.0];
    let ss = [
        (rhs[0] * a[1][1] - a[0][1] * rhs[1]) / det,
        (a[0][0] * rhs[1] - a[1][0] * rhs[0]) / det,
    ];
    let (e1, e2) = ((l1 * t).exp(), (l2 * t).exp());
    let m = |i: usize, j: usize| {
        let id = if i == j { 1.0 } else { 0.0 };
        (e1 * (a[i][j] - l2 * id) - e2 * (a[i][j] - l1 * id)) / (l1 - l2)
    };
    let d = [x0[0] - ss[0], x0[1] - ss[1]];
    [
        ss[0] + m(0, 0) * d[0] + m(0, 1) * d[1],
        ss[1] + m(1, 0) * d[0] + m(1, 1) * d[1],
    ]
}

/// The closed-form rises at `t` s for a spindle set at `changes` (`(from s, rad/s)`, in order,
/// the last one the stop), piece by piece.
fn two_node_at(changes: &[(f64, f64)], t: f64) -> [f64; 2] {
    let mut x = [0.0, 0.0];
    for (k, &(at, speed)) in changes.iter().enumerate() {
        if at >= t {
            break;
        }
        let until = changes.get(k + 1).map_or(t, |next| next.0.min(t));
        x = two_node(x, HEAT * speed, until - at);
    }
    x
}

fn rpm(speed: f64) -> f64 {
    speed * std::f64::consts::TAU / 60.0
}

fn channel<'a>(run: &'a SpindleThermalRun, name: &str, truth: bool) -> &'a [f64] {
    let list = if truth {
        &run.true_channels
    } else {
        &run.table.channels
    };
    &list.iter().find(|c| c.name == name).unwrap().values
}

#[test]
fn z_drift_follows_the_closed_form_step_response_and_cools_back_after_the_stop() {
    let twin = twin();
    let (test, _) = parse(
        &format!(
            "{HOLD}constant = {{ speed_rpm = 6000.0, run_min = 240.0, stop_min = 60.0 }}\nsample_min = 1.0\n{NEST}"
        ),
        &twin.machine,
    );
    let setup = two_node_setup(&twin.machine);
    let run = spindle_test::simulate(&twin, &test, &setup, 7);
    // A reading every minute from 0 to 300 min.
    assert_eq!(run.table.times.len(), 301);
    assert!((run.table.times[300] - 18_000.0).abs() < 1e-6);
    let omega = rpm(6000.0);
    let changes = [(0.0, omega), (240.0 * 60.0, 0.0)];
    let (z_true, z_read) = (channel(&run, "z", true), channel(&run, "z", false));
    // The exact integration of the twin against the closed form: floating-point agreement
    // (1 nK on rises of a few kelvin; 1 pm on micrometres).
    for (row, record) in run.records.iter().enumerate() {
        let t = record.visit.time;
        let [xb, xh] = two_node_at(&changes, t);
        let rise_b = record.temperatures[0] - AIR;
        let rise_h = record.temperatures[1] - AIR;
        assert!(
            (rise_b - xb).abs() < 1e-9,
            "bearing at {t} s: {rise_b} K, closed form {xb} K"
        );
        assert!(
            (rise_h - xh).abs() < 1e-9,
            "housing at {t} s: {rise_h} K, closed form {xh} K"
        );
        // The growth pushes the tool towards the workpiece: Z = −k·ΔT_housing.
        let z = -GROWTH * xh;
        assert!(
            (z_true[row] - z).abs() < 1e-12,
            "Z at {t} s: {} m, closed form {z} m",
            z_true[row]
        );
        // A pure translation along the spindle axis: the radial sensors read nothing.
        for name in ["x1", "y1", "x2", "y2"] {
            assert!(
                channel(&run, name, true)[row].abs() < 1e-15,
                "{name} at {t} s"
            );
        }
        // The nest's reading: the truth with 0.02 µm noise (4.5 σ over 1 505 draws) and a
        // 0.01 µm resolution (half a step).
        let bound = 4.5 * 0.02e-6 + 0.005e-6;
        assert!(
            (z_read[row] - z_true[row]).abs() <= bound + 1e-15,
            "Z read at {t} s"
        );
    }
    // The heat is the spindle's: 0.05 W per rad/s at 6000 rpm, 31.4 W; the steady housing rise
    // is P·G_bh / (G_bh·G_ha + G_ba·G_bh + G_ba·G_ha) by the two nodes' balance (hand
    // derivation), and after 4 h (9.4 slow time constants of 25.6 min) the run is there.
    let p = HEAT * omega;
    let steady_h = p * G_BH / (G_BH * G_HA + G_BA * G_BH + G_BA * G_HA);
    let at_stop = 240;
    assert!((run.table.times[at_stop] - 14_400.0).abs() < 1e-6);
    let rise_at_stop = run.records[at_stop].temperatures[1] - AIR;
    assert!(
        (rise_at_stop - steady_h).abs() < 1e-3 * steady_h,
        "{rise_at_stop} K after 4 h, steady {steady_h} K"
    );
    // The drift stops growing with the spindle: after the stop |Z| never exceeds its value at
    // the stop, falls from one reading to the next from 2 min after it on, and the last hour
    // takes it below a fifth (the slow mode alone would leave e^(−60/25.6) = 0.096).
    let stop_z = z_true[at_stop].abs();
    for row in at_stop + 1..z_true.len() {
        assert!(z_true[row].abs() <= stop_z * (1.0 + 1e-6), "row {row}");
        if row > at_stop + 2 {
            assert!(
                z_true[row].abs() < z_true[row - 1].abs(),
                "row {row} does not cool"
            );
        }
    }
    assert!(
        z_true[300].abs() < 0.2 * stop_z,
        "{} of {stop_z}",
        z_true[300]
    );
    assert!(stop_z > 1e-6, "a drift the nest resolves: {stop_z} m");
    println!(
        "two-node: P = {p:.2} W, housing +{rise_at_stop:.4} K, Z {:.4} µm at the stop, {:.4} µm after 1 h stopped",
        z_true[at_stop] * 1e6,
        z_true[300] * 1e6
    );
}

#[test]
fn the_spectrum_turns_the_spindle_at_each_speed_for_its_duration() {
    let twin = twin();
    // Steps that end between readings (every 2 min): 12.5, 3.25, 20 and 1.5 min.
    let (test, _) = parse(
        &format!(
            "{HOLD}spectrum = [\n  {{ speed_rpm = 4000.0, duration_min = 12.5 }},\n  {{ speed_rpm = 0.0, duration_min = 3.25 }},\n  {{ speed_rpm = 9000.0, duration_min = 20.0 }},\n  {{ speed_rpm = 2000.0, duration_min = 1.5 }},\n]\nstop_min = 61.0\nsample_min = 2.0\n{NEST}"
        ),
        &twin.machine,
    );
    let run_min = 12.5 + 3.25 + 20.0 + 1.5;
    assert!((test.speeds.run_period() - run_min * 60.0).abs() < 1e-9);
    let setup = two_node_setup(&twin.machine);
    let run = spindle_test::simulate(&twin, &test, &setup, 3);
    // Readings: every 2 min up to 98 min, then the end of the running period (37.25 min) and
    // the end (98.25 min) between them.
    let mut expected: Vec<f64> = (0..=49).map(|k| k as f64 * 120.0).collect();
    expected.extend([run_min * 60.0, (run_min + 61.0) * 60.0]);
    expected.sort_by(f64::total_cmp);
    assert_eq!(run.table.times.len(), expected.len());
    for (got, want) in run.table.times.iter().zip(&expected) {
        assert!(
            (got - want).abs() < 1e-6,
            "reading at {got} s, expected {want} s"
        );
    }
    let changes = [
        (0.0, rpm(4000.0)),
        (12.5 * 60.0, 0.0),
        (15.75 * 60.0, rpm(9000.0)),
        (35.75 * 60.0, rpm(2000.0)),
        (run_min * 60.0, 0.0),
    ];
    let z = channel(&run, "z", true);
    for (row, record) in run.records.iter().enumerate() {
        let t = record.visit.time;
        let [xb, xh] = two_node_at(&changes, t);
        assert!(
            (record.temperatures[0] - AIR - xb).abs() < 1e-9,
            "bearing at {t} s"
        );
        assert!(
            (record.temperatures[1] - AIR - xh).abs() < 1e-9,
            "housing at {t} s"
        );
        assert!((z[row] + GROWTH * xh).abs() < 1e-12, "Z at {t} s");
        // The speed that turned the spindle up to the reading (0 at the start, and the last
        // step's 2000 rpm at the end of the running period: read before the stop).
        let before = changes
            .iter()
            .take_while(|(at, _)| *at < t - 1e-6)
            .last()
            .map_or(0.0, |c| c.1);
        assert!((run.speeds[row] - before).abs() < 1e-9, "speed at {t} s");
    }
    let conditions = &run.table.conditions;
    assert_eq!(conditions.programme.as_deref(), Some("spectrum"));
    assert_eq!(
        conditions.spectrum.as_deref(),
        Some(
            "4000 rpm for 12.5 min, 0 rpm for 3.25 min, 9000 rpm for 20 min, 2000 rpm for 1.5 min"
        )
    );
    // 12.5 + 3.25 + 20 + 1.5 min running, 61 min stopped.
    assert!((conditions.run_period.unwrap() - 37.25 * 60.0).abs() < 1e-9);
    assert!((conditions.stop.unwrap() - 61.0 * 60.0).abs() < 1e-9);
    assert!(matches!(test.speeds, SpeedProgramme::Spectrum(ref s) if s.len() == 4));
}

/// The default network integrated by explicit Euler with step `dt` s, the spindle heat `power`
/// W on `spindle_bearing` until `run` s, constant air: every node's rise at the times asked.
fn euler(setup: &ThermalSetup, power: f64, run: f64, dt: f64, times: &[f64]) -> Vec<Vec<f64>> {
    let network = &setup.thermal.network;
    let nodes = network.nodes();
    let bearing = network.node("spindle_bearing").unwrap();
    let mut x = vec![0.0; nodes.len()];
    let mut flow = vec![0.0; nodes.len()];
    let mut out = Vec::new();
    let mut t = 0.0;
    for &target in times {
        while t < target - 1e-9 {
            let h = dt.min(target - t);
            flow.iter_mut().for_each(|f| *f = 0.0);
            for (i, node) in nodes.iter().enumerate() {
                flow[i] -= node.to_ambient * x[i];
            }
            for &(i, j, g) in network.links() {
                flow[i] += g * (x[j] - x[i]);
                flow[j] += g * (x[i] - x[j]);
            }
            if t + h / 2.0 < run {
                flow[bearing] += power;
            }
            for (i, node) in nodes.iter().enumerate() {
                x[i] += h * flow[i] / node.capacity;
            }
            t += h;
        }
        out.push(x.clone());
    }
    out
}

#[test]
fn the_bundled_scenario_follows_an_euler_integration_of_the_whole_network() {
    let twin = twin();
    let (test, setup) = bundled(&twin.machine);
    let run = spindle_test::simulate(&twin, &test, &setup, 1);
    assert_eq!(
        run.table.times.len(),
        301,
        "a reading a minute for 4 h + 1 h"
    );
    let node = |name: &str| setup.thermal.network.node(name).unwrap();
    let (bearing, housing) = (node("spindle_bearing"), node("spindle_housing"));
    let (front, back) = (node("column_front"), node("column_back"));
    // The default model's heat: 0.05 W per rad/s (its doc: 52 W at 10 000 rpm).
    let power = 0.05 * rpm(6000.0);
    let dt = 0.25;
    let rises = euler(&setup, power, 240.0 * 60.0, dt, &run.table.times);
    // Explicit Euler's global error for a stable linear network is about dt/2 × |λ|max times
    // the size of the transient: |λ|max ≈ (2 + 10)/3000 s⁻¹ (the bearing), so 5e-4 of the
    // rise; the tolerance is that of the largest rise.
    let peak = rises.iter().map(|r| r[bearing]).fold(0.0, f64::max);
    let tolerance = 5e-4 * peak;
    let (a_true, z_true) = {
        let y1 = channel(&run, "y1", true);
        let y2 = channel(&run, "y2", true);
        let a: Vec<f64> = y1
            .iter()
            .zip(y2)
            .map(|(p, q)| (p - q) / test.nest.spacing)
            .collect();
        (a, channel(&run, "z", true))
    };
    let mut worst = 0.0_f64;
    for (row, (record, rise)) in run.records.iter().zip(&rises).enumerate() {
        for n in [bearing, housing, front, back] {
            let twin_rise = record.temperatures[n] - 20.0;
            worst = worst.max((twin_rise - rise[n]).abs());
            assert!(
                (twin_rise - rise[n]).abs() <= tolerance,
                "node {n} at row {row}: {twin_rise} K, Euler {} K",
                rise[n]
            );
        }
        // The column tilts the head about X by ε = 2 µrad per K of front − back; the pairs read it
        // (a rigid mandrel: exact).
        let tilt = 2e-6 * (rise[front] - rise[back]);
        let tilt_tolerance = 2e-6 * 2.0 * tolerance;
        assert!(
            (a_true[row] - tilt).abs() <= tilt_tolerance + 1e-12,
            "A at row {row}: {} rad, Euler {tilt} rad",
            a_true[row]
        );
        // The tilt turns the head about its Z slot's origin (the `Z` joint's child frame): in
        // vmc3.urdf the tool point is (0, 0.35, −0.30) m from it (joints `S` and `tool_holder`),
        // so ε × r moves it by (0, 0.30·ε, 0.35·ε), and X1/Y1, `first` up the mandrel, by
        // (0, (0.30 − first)·ε, ·). Z adds the housing's growth, −1 µm/K (hand derivation).
        let z = -1e-6 * rise[housing] + 0.35 * tilt;
        let bound = 1e-6 * tolerance + 0.35 * tilt_tolerance + 1e-12;
        assert!(
            (z_true[row] - z).abs() <= bound,
            "Z at row {row}: {} m, {z} m ± {bound}",
            z_true[row]
        );
        let lever = 0.30 - test.nest.first;
        let y1 = lever * tilt;
        let y1_true = channel(&run, "y1", true)[row];
        assert!(
            (y1_true - y1).abs() <= lever * tilt_tolerance + 1e-12,
            "Y1 at row {row}: {y1_true} m, {y1} m"
        );
        // Nothing moves X: the screws stay at the air's temperature.
        for name in ["x1", "x2"] {
            assert!(
                channel(&run, name, true)[row].abs() < 1e-12,
                "{name} at row {row}"
            );
        }
    }
    // The thermometers: `bearing` on the bearing, `spindle` on the housing, both lagging 20 s.
    let names: Vec<&str> = run
        .table
        .temperatures
        .iter()
        .map(|(n, _)| n.as_str())
        .collect();
    assert_eq!(names, ["air", "bearing", "spindle"]);
    let last = |name: &str| {
        *run.table
            .temperatures
            .iter()
            .find(|(n, _)| n == name)
            .unwrap()
            .1
            .last()
            .unwrap()
    };
    assert!((last("air") - 20.0).abs() <= 4.5 * 0.02 + 0.005);
    let at_stop = |name: &str| {
        run.table
            .temperatures
            .iter()
            .find(|(n, _)| n == name)
            .unwrap()
            .1[240]
    };
    assert!(at_stop("bearing") > at_stop("spindle") && at_stop("spindle") > 21.0);
    println!(
        "bundled: Euler agrees within {worst:.2e} K (tolerance {tolerance:.2e} K); at the stop bearing +{:.3} K, housing +{:.3} K, Z {:.3} µm, A {:.4} µrad; after 1 h stopped Z {:.3} µm",
        rises[240][bearing],
        rises[240][housing],
        z_true[240] * 1e6,
        a_true[240] * 1e6,
        z_true[300] * 1e6
    );
}

/// A drift table as its CSV text has it, parsed here by hand.
struct Csv {
    /// The header's column names.
    names: Vec<String>,
    /// Each column's numbers, as written (min, µm, µrad, °C).
    columns: Vec<Vec<f64>>,
    /// The preamble's `# key = value` lines.
    preamble: Vec<(String, String)>,
}

fn csv_columns(text: &str) -> Csv {
    let mut preamble = Vec::new();
    let mut lines = text.lines();
    let header = loop {
        let line = lines.next().unwrap();
        match line.strip_prefix('#') {
            Some(comment) => {
                if let Some((k, v)) = comment.split_once('=') {
                    preamble.push((k.trim().to_string(), v.trim().to_string()));
                }
            }
            None => break line,
        }
    };
    let names: Vec<String> = header.split(',').map(str::to_string).collect();
    let mut columns = vec![Vec::new(); names.len()];
    for line in lines {
        for (k, cell) in line.split(',').enumerate() {
            columns[k].push(cell.parse::<f64>().unwrap());
        }
    }
    Csv {
        names,
        columns,
        preamble,
    }
}

/// max − min over the rows with `time_min ≤ until`, signed by the larger excursion from the
/// first value (ISO 230-3 §3.1 as the digest reads Fig. 7).
fn signed(times: &[f64], values: &[f64], until: f64) -> f64 {
    let inside: Vec<f64> = times
        .iter()
        .zip(values)
        .filter(|(t, _)| **t <= until + 1e-9)
        .map(|(_, v)| *v)
        .collect();
    let (lo, hi) = inside
        .iter()
        .fold((f64::INFINITY, f64::NEG_INFINITY), |(l, h), v| {
            (l.min(*v), h.max(*v))
        });
    let start = values[0];
    if hi - start >= start - lo {
        hi - lo
    } else {
        lo - hi
    }
}

#[test]
fn analyze_drift_reports_the_tables_own_ranges_and_stop_criterion() {
    let twin = twin();
    let (test, setup) = bundled(&twin.machine);
    let run = spindle_test::simulate(&twin, &test, &setup, 1);
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("drift.csv");
    let mut bytes = Vec::new();
    run.table.write_csv(&mut bytes).unwrap();
    std::fs::write(&path, &bytes).unwrap();
    // `mtwin analyze drift FILE --json`, through the verb the command line runs.
    let verb = mtwin::kinds::drift::cli::KIND.analyze.unwrap();
    let path_text = path.to_str().unwrap();
    let matches = (verb.command)().get_matches_from(["drift", path_text, "--json"]);
    let printed = (verb.run)(&matches, &mut |_| {}, &mtwin::app::ScenarioFiles).unwrap();
    let report: serde_json::Value = serde_json::from_str(&printed).unwrap();
    assert_eq!(report["kind"], "drift");
    assert_eq!(report["test"], "iso230_3_spindle");
    assert_eq!(report["ambient_sensor"], "air");
    assert_eq!(report["spacing_mm"], 150.0);
    // Every key the twin wrote is read and said again; none is left unused.
    let said = &report["conditions"];
    assert_eq!(said["control"], "hold");
    assert_eq!(said["hold_mm"], "x 380, y 205, z 260");
    assert_eq!(said["programme"], "constant");
    assert_eq!(said["speed_rpm"], 6000.0);
    assert_eq!(said["run_min"], 240.0);
    assert_eq!(said["stop_min"], 60.0);
    assert_eq!(report["preamble_not_used"], serde_json::json!([]));
    assert_eq!(report["cautions"], serde_json::json!([]));
    // The file by hand: its conditions and its columns.
    let text = String::from_utf8(bytes).unwrap();
    let Csv {
        names,
        columns,
        preamble,
    } = csv_columns(&text);
    let said = |key: &str| {
        preamble
            .iter()
            .find(|(k, _)| k == key)
            .map(|(_, v)| v.as_str())
    };
    assert_eq!(said("test"), Some("iso230_3_spindle"));
    assert_eq!(said("programme"), Some("constant"));
    assert_eq!(said("speed_rpm"), Some("6000"));
    assert_eq!(said("run_min"), Some("240"));
    assert_eq!(said("stop_min"), Some("60"));
    assert_eq!(said("control"), Some("hold"));
    assert_eq!(said("hold_mm"), Some("x 380, y 205, z 260"));
    assert_eq!(
        names,
        [
            "time_min",
            "x1_um",
            "y1_um",
            "x2_um",
            "y2_um",
            "z_um",
            "temp_air_degc",
            "temp_bearing_degc",
            "temp_spindle_degc"
        ]
    );
    let column = |name: &str| &columns[names.iter().position(|n| n == name).unwrap()];
    let times = column("time_min");
    let l_mm = 150.0;
    let mut series: Vec<(String, Vec<f64>)> = ["x1", "y1", "x2", "y2", "z"]
        .iter()
        .map(|n| (n.to_string(), column(&format!("{n}_um")).clone()))
        .collect();
    // The tilts from the pairs (µm / mm = mrad → ×1000 µrad): A = (Y1 − Y2)/l, B = (X2 − X1)/l.
    let pair = |p: &str, q: &str| -> Vec<f64> {
        column(p)
            .iter()
            .zip(column(q))
            .map(|(a, b)| (a - b) / l_mm * 1e3)
            .collect()
    };
    series.push(("a".into(), pair("y1_um", "y2_um")));
    series.push(("b".into(), pair("x2_um", "x1_um")));
    let entries = report["channels"].as_array().unwrap();
    assert_eq!(entries.len(), 7);
    for (name, values) in &series {
        let entry = entries.iter().find(|c| c["name"] == name.as_str()).unwrap();
        let unit = entry["unit"].as_str().unwrap();
        let first = signed(times, values, 60.0);
        let whole = signed(times, values, f64::INFINITY);
        // The report rounds to 1e-6 of its unit; the tilts come from CSV values rounded to 1 pm.
        let close = |reported: &serde_json::Value, mine: f64| {
            (reported.as_f64().unwrap() - mine).abs() <= 2e-6
        };
        assert!(
            close(&entry[format!("range_60_{unit}")], first),
            "{name}: {} vs {first}",
            entry[format!("range_60_{unit}")]
        );
        assert!(
            close(&entry[format!("range_{unit}")], whole),
            "{name}: {} vs {whole}",
            entry[format!("range_{unit}")]
        );
        // d(·)_t over the running period the preamble states (run_min = 240), not the record.
        let running = signed(times, values, 240.0);
        assert!(
            close(&entry[format!("range_run_{unit}")], running),
            "{name}: {} vs {running}",
            entry[format!("range_run_{unit}")]
        );
        // The 15 % rule (ISO 230-3 §6.2) by brute force: the first reading at or after 120 min
        // whose last 60 min (readings on the minute grid, so t − 60 min is a reading) vary less
        // than 15 % of the largest |d − d(0)| in the first hour.
        let first_hour = times
            .iter()
            .zip(values)
            .filter(|(t, _)| **t <= 60.0)
            .map(|(_, v)| (v - values[0]).abs())
            .fold(0.0, f64::max);
        let stop = times
            .iter()
            .enumerate()
            .filter(|(_, t)| **t >= 120.0 - 1e-9)
            .find_map(|(k, t)| {
                let window: Vec<f64> = (0..=k)
                    .filter(|&j| times[j] >= t - 60.0 - 1e-9)
                    .map(|j| values[j])
                    .collect();
                let lo = window.iter().copied().fold(f64::INFINITY, f64::min);
                let hi = window.iter().copied().fold(f64::NEG_INFINITY, f64::max);
                (hi - lo < 0.15 * first_hour).then_some(*t)
            });
        match (entry["stop_min"].as_f64(), stop) {
            (Some(reported), Some(mine)) => assert!(
                (reported - mine).abs() < 1e-6,
                "{name}: stop {reported} vs {mine}"
            ),
            (None, None) => {}
            other => panic!("{name}: stop criterion {other:?}"),
        }
    }
    // The Z drift meets the criterion while the spindle runs: the housing settles within the
    // 4 h (slow time constant about half an hour), so the standard would let it stop early.
    let z = entries.iter().find(|c| c["name"] == "z").unwrap();
    let z_stop = z["stop_min"].as_f64().unwrap();
    assert!((120.0..240.0).contains(&z_stop), "Z stop {z_stop} min");
    // The spindle pushes the tool down: negative Z drift, several micrometres.
    assert!(z["range_um"].as_f64().unwrap() < -1.0, "{z}");
    // truth.json's running-period range (Table 1's d(ZOC)_t) against the noise-free channel,
    // and the measured table within the nest's noise of it.
    let truth = spindle_test::truth(&test, &run);
    let z_truth = truth["true_channels"]
        .as_array()
        .unwrap()
        .iter()
        .find(|c| c["name"] == "z")
        .unwrap();
    let true_z = channel(&run, "z", true);
    let true_minutes: Vec<f64> = run.table.times.iter().map(|t| t / 60.0).collect();
    let running = signed(&true_minutes, true_z, 240.0) * 1e6;
    assert!((z_truth["range_run_um"].as_f64().unwrap() - running).abs() < 1e-9);
    // A noisy range differs from the true one by at most twice the largest noise value plus a
    // resolution step: 4.5 σ over the 1 505 nest draws.
    let (sigma_um, step_um) = (test.nest.noise * 1e6, test.nest.resolution * 1e6);
    let bound = 2.0 * 4.5 * sigma_um + step_um;
    for key in ["range_60_um", "range_um"] {
        let (measured, truth) = (z[key].as_f64().unwrap(), z_truth[key].as_f64().unwrap());
        assert!(
            (measured - truth).abs() <= bound,
            "Z {key}: {measured} µm, true {truth} µm ± {bound}"
        );
    }
    // The tilt A (the column's, about X) the same way: a pair's difference has √2 σ, over l.
    let a = entries.iter().find(|c| c["name"] == "a").unwrap();
    let a_truth = truth["true_channels"]
        .as_array()
        .unwrap()
        .iter()
        .find(|c| c["name"] == "a")
        .unwrap();
    let tilt_bound = (2.0 * 4.5 * 2f64.sqrt() * sigma_um + 2.0 * step_um) / l_mm * 1e3;
    let (measured, true_a) = (
        a["range_urad"].as_f64().unwrap(),
        a_truth["range_urad"].as_f64().unwrap(),
    );
    assert!(
        (measured - true_a).abs() <= tilt_bound,
        "A: {measured} µrad, true {true_a} µrad ± {tilt_bound}"
    );
    assert!(
        true_a > 2.0 * tilt_bound,
        "A {true_a} µrad is above the pair noise {tilt_bound}"
    );
    assert_eq!(truth["speed_rpm_at_readings"][0], 0.0);
    assert_eq!(truth["speed_rpm_at_readings"][240], 6000.0);
    assert_eq!(truth["speed_rpm_at_readings"][241], 0.0);
    // The text report for people has the stop column (the ETVE's does not).
    let matches = (verb.command)().get_matches_from(["drift", path_text]);
    let people = (verb.run)(&matches, &mut |_| {}, &mtwin::app::ScenarioFiles).unwrap();
    assert!(people.contains("stop min"), "{people}");
    // The table reads back whole.
    let back = DriftTable::read(&path).unwrap();
    assert_eq!(back.conditions.test.as_deref(), Some("iso230_3_spindle"));
    println!("{}\n{people}", run.summary());
}

#[test]
fn the_same_seed_gives_the_same_bytes_and_another_seed_other_noise() {
    let twin = twin();
    let (test, setup) = bundled(&twin.machine);
    let bytes = |seed: u64| {
        let run = spindle_test::simulate(&twin, &test, &setup, seed);
        let mut out = Vec::new();
        run.table.write_csv(&mut out).unwrap();
        let truth = serde_json::to_vec(&spindle_test::truth(&test, &run)).unwrap();
        (out, truth, run.true_channels)
    };
    let (a, truth_a, true_a) = bytes(1);
    let (b, truth_b, true_b) = bytes(1);
    assert!(a == b && truth_a == truth_b, "same seed, different bytes");
    let (c, _, true_c) = bytes(2);
    assert_ne!(a, c, "another seed draws other noise");
    // The truth does not depend on the seed.
    assert_eq!(true_a, true_b);
    assert_eq!(true_a, true_c);
    // Parsing the same text twice gives the same test.
    let (again, _) = bundled(&twin.machine);
    assert_eq!(test, again);
}

#[test]
fn bad_sections_are_refused_with_the_key_and_line() {
    let twin = twin();
    let constant = "constant = { speed_rpm = 6000.0, run_min = 240.0, stop_min = 60.0 }\n";
    // The section's header is line 8 of `with_section`'s text, its first key line 9.
    let cases: Vec<(String, &str, usize)> = vec![
        (
            format!("{HOLD}{NEST}"),
            "iso230_3_spindle.constant or spectrum: give the spindle speed programme",
            8,
        ),
        (
            format!("{HOLD}constant = {{ speed_rpm = -5.0 }}\n{NEST}"),
            "iso230_3_spindle.constant.speed_rpm: -5 rpm; expected a spindle speed above 0",
            10,
        ),
        (
            format!("{HOLD}constant = {{ speed_rpm = 0.0 }}\n{NEST}"),
            "constant.speed_rpm: 0 rpm",
            10,
        ),
        (
            format!("{HOLD}constant = {{ speed_rpm = 6000.0, run_min = 0.0 }}\n{NEST}"),
            "iso230_3_spindle.constant.run_min: 0 min; expected more than 0",
            10,
        ),
        (
            format!("{HOLD}constant = {{ speed_rpm = 6000.0, stop_min = 30.0 }}\n{NEST}"),
            "iso230_3_spindle.constant.stop_min: 30 min; ISO 230-3 §6.2 stops the spindle for at least 1 h",
            10,
        ),
        (
            format!("{HOLD}{constant}stop_min = 60.0\n{NEST}"),
            "iso230_3_spindle.stop_min: with constant, give the stop inside it",
            11,
        ),
        (
            format!(
                "{HOLD}{constant}spectrum = [{{ speed_rpm = 1.0, duration_min = 1.0 }}]\n{NEST}"
            ),
            "iso230_3_spindle.spectrum: give constant or spectrum, not both",
            11,
        ),
        (
            format!("{HOLD}spectrum = []\n{NEST}"),
            "iso230_3_spindle.spectrum: empty",
            10,
        ),
        (
            format!(
                "{HOLD}spectrum = [\n  {{ speed_rpm = 3000.0, duration_min = 20.0 }},\n  {{ speed_rpm = 0.0, duration_min = 0.0 }},\n]\n{NEST}"
            ),
            "iso230_3_spindle.spectrum[1].duration_min: 0 min; expected more than 0",
            12,
        ),
        (
            format!(
                "{HOLD}spectrum = [\n  {{ speed_rpm = 3000.0, duration_min = 20.0 }},\n  {{ speed_rpm = -1.0, duration_min = 5.0 }},\n]\n{NEST}"
            ),
            "iso230_3_spindle.spectrum[1].speed_rpm: -1 rpm; expected 0 (a stop)",
            12,
        ),
        (
            format!("{HOLD}spectrum = [{{ speed_rpm = 0.0, duration_min = 5.0 }}]\n{NEST}"),
            "spectrum: every step is a stop",
            10,
        ),
        (
            format!(
                "{HOLD}spectrum = [{{ speed_rpm = 100.0, duration_min = 5.0 }}]\nstop_min = 59.0\n{NEST}"
            ),
            "iso230_3_spindle.stop_min: 59 min; ISO 230-3 §6.2",
            11,
        ),
        (
            format!("{HOLD}{constant}sample_min = 6.0\n{NEST}"),
            "iso230_3_spindle.sample_min: 6 min; ISO 230-3 §6.2 asks for a reading at least every 5 min",
            11,
        ),
        (
            format!("hold_mm = {{ x = 900.0 }}\n{constant}{NEST}"),
            "iso230_3_spindle.hold_mm.x: 900 mm is outside the travel of X",
            9,
        ),
        (
            format!("hold_mm = {{ q = 1.0 }}\n{constant}{NEST}"),
            "iso230_3_spindle.hold_mm.q: expected x, y or z",
            9,
        ),
        (
            format!("{HOLD}{constant}nest = {{ first_mm = 20.0, spacing_mm = 0.0 }}\n"),
            "iso230_3_spindle.nest.spacing_mm: 0: expected 1 … 1000 (a test mandrel is at most a metre long)",
            11,
        ),
        (
            format!("{HOLD}{constant}{NEST}air = {{ noise_degc = -1.0 }}\n"),
            "iso230_3_spindle.air.noise_degc: -1: expected 0 … 5",
            12,
        ),
    ];
    for (section, message, line) in cases {
        let error = spindle_test::parse_sections("t.toml", &with_section(&section), &twin.machine)
            .unwrap_err();
        let text = error.to_string();
        assert!(
            text.contains(message),
            "{section}\n→ {text}\n(expected {message})"
        );
        assert_eq!(error.line(), Some(line), "{section}\n→ {text}");
        assert!(text.starts_with(&format!("t.toml:{line}: ")), "{text}");
    }
    // A type error and an unknown key: TOML's own message, at the line.
    let error = spindle_test::parse_sections(
        "t.toml",
        &with_section(&format!(
            "{HOLD}constant = {{ speed_rpm = \"fast\" }}\n{NEST}"
        )),
        &twin.machine,
    )
    .unwrap_err();
    assert_eq!(error.line(), Some(10), "{error}");
    let error = spindle_test::parse_sections(
        "t.toml",
        &with_section(&format!("{HOLD}{constant}{NEST}speed = 3\n")),
        &twin.machine,
    )
    .unwrap_err();
    assert!(
        error.to_string().contains("unknown field `speed`"),
        "{error}"
    );
    assert_eq!(error.line(), Some(12), "{error}");
    // No [thermal]: the test has nothing to run through.
    let text = format!("schema = 1\nseed = 1\n\n[iso230_3_spindle]\n{HOLD}{constant}{NEST}");
    let error = spindle_test::parse_sections("t.toml", &text, &twin.machine).unwrap_err();
    assert!(
        error
            .to_string()
            .contains("iso230_3_spindle is a thermal test: add a [thermal] section"),
        "{error}"
    );
    assert_eq!(error.line(), Some(4));
    // A [thermal] sensor named like the ambient thermometer.
    let text = format!(
        "schema = 1\n\n[thermal]\nsensors = [{{ node = \"spindle_housing\", name = \"air\" }}]\n\n[iso230_3_spindle]\n{HOLD}{constant}{NEST}"
    );
    let error = spindle_test::parse_sections("t.toml", &text, &twin.machine).unwrap_err();
    assert!(
        error
            .to_string()
            .contains("the name of the spindle test's ambient thermometer"),
        "{error}"
    );
    // Without the section: nothing, and no error.
    let text = "schema = 1\n\n[thermal]\nambient_degc = 20.0\n";
    assert!(
        spindle_test::parse_sections("t.toml", text, &twin.machine)
            .unwrap()
            .is_none()
    );
}

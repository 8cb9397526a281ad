//! The virtual laser interferometer and the ISO 230-2 test cycle: the Abbe error of a pitch
//! error seen through a beam offset, air refraction against the Edlén sensitivities
//! (compensated and not), the cosine error, material compensation, and the cycle's timing.

use mtwin::errors::{ErrorFunction, ErrorModel, ErrorParameter};
use mtwin::kinds::positioning::PositioningTable;
use mtwin::kinds::positioning::laser::{
    AirCompensation, Laser, MaterialCompensation, Mounting, Zeroing,
};
use mtwin::kinds::positioning::{Air, HENE_WAVELENGTH_UM};
use mtwin::kinds::positioning::{LinearCycle, irregular_targets};
use mtwin::machine::{Axis, AxisValues, Machine};
use mtwin::math::{Vector, seeded_rng};
use mtwin::program::Approach;
use mtwin::twin::Twin;

fn vmc3() -> Machine {
    Machine::from_urdf_file(concat!(env!("CARGO_MANIFEST_DIR"), "/models/vmc3.urdf")).unwrap()
}

/// A noiseless, unquantised laser on X in standard air with compensation off (so the
/// refraction ratio is exactly 1).
fn ideal_laser() -> Laser {
    Laser {
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
    }
}

/// X from 10 to 710 mm, 8 targets, 2 runs, Y and Z at 200 and 100 mm.
fn cycle() -> LinearCycle {
    let mut rest = AxisValues::ZERO;
    rest[Axis::Y] = 0.2;
    rest[Axis::Z] = 0.1;
    LinearCycle {
        axis: Axis::X,
        targets: (0..8).map(|i| 0.01 + 0.1 * i as f64).collect(),
        runs: 2,
        overrun: 0.005,
        feed: 2.0 / 60.0,
        dwell: 1.0,
        rest,
    }
}

fn measure(laser: &Laser, errors: &ErrorModel, machine: &Machine) -> PositioningTable {
    let cycle = cycle();
    let visits = cycle.visits();
    let twin = Twin {
        machine: machine.clone(),
        errors: errors.clone(),
    };
    laser.measure(
        &visits,
        &twin.poses(&visits),
        &cycle.targets,
        &mut seeded_rng(1, "laser"),
    )
}

#[test]
fn a_pitch_error_seen_through_a_beam_offset_is_an_abbe_error() {
    // EBX = k·x (pitch of the table, rotation about Y). Raising the reflector by h above the
    // tool tip lengthens the arm from the X carriage by h along +Z, so the reflector moves by
    // an extra (k·x·e_y) × (h·e_z) = +k·x·h along X. Zeroed at the first target x₀, the
    // deviations with and without the offset differ by k·h·(x - x₀), positive for k, h > 0.
    let machine = vmc3();
    let k = 20e-6; // rad per metre of X: 14 µrad at 700 mm
    let h = 0.1;
    let errors = ErrorModel::new(
        &machine,
        vec![ErrorParameter {
            name: "EBX".parse().unwrap(),
            function: ErrorFunction::Polynomial(vec![0.0, k]),
        }],
    )
    .unwrap();
    let at_tip = measure(&ideal_laser(), &errors, &machine);
    let raised = measure(
        &Laser {
            beam_offset: Vector::new(0.0, 0.0, h),
            ..ideal_laser()
        },
        &errors,
        &machine,
    );
    for (a, b) in at_tip.readings.iter().zip(&raised.readings) {
        let expected = k * h * (a.target - 0.01);
        // First order in ε (≤ 14 µrad): the neglected term ε²·h/2 is below 1e-11 m.
        assert!(
            (b.deviation - a.deviation - expected).abs() < 1e-11,
            "x = {}: {} vs {}",
            a.target,
            b.deviation - a.deviation,
            expected
        );
    }
    // At 710 mm: 20e-6 · 0.1 · 0.7 = 1.4 µm.
    let last = raised
        .readings
        .iter()
        .zip(&at_tip.readings)
        .find(|(r, _)| (r.target - 0.71).abs() < 1e-12)
        .unwrap();
    assert!((last.0.deviation - last.1.deviation - 1.4e-6).abs() < 1e-11);
}

#[test]
fn air_refractive_index_has_the_edlen_sensitivities() {
    // About -0.93 ppm per °C and +0.27 ppm per hPa near 20 °C, 1013.25 hPa (central
    // differences). The temperature figure is that of dry air: at a constant relative humidity
    // the water vapour pressure also rises with temperature (~6 %/°C), adding about -0.03 ppm/°C.
    let n = |t: f64, p: f64, h: f64| {
        Air {
            temperature: t,
            pressure: p,
            humidity: h,
        }
        .refractive_index(HENE_WAVELENGTH_UM)
    };
    let (t0, p0, h0) = (20.0, 101_325.0, 50.0);
    let n0 = n(t0, p0, h0);
    // The published value (NIST Engineering Metrology Toolbox, modified Edlén, 633 nm, 20 °C,
    // 101.325 kPa, 50 %RH) is n ≈ 1.0002714: within 2 parts in 10⁴ of n - 1.
    assert!((n0 - 1.000_271_4).abs() < 5e-8, "n = {n0}");
    let per_degc = (n(t0 + 0.5, p0, 0.0) - n(t0 - 0.5, p0, 0.0)) / n0 * 1e6;
    let per_degc_humid = (n(t0 + 0.5, p0, h0) - n(t0 - 0.5, p0, h0)) / n0 * 1e6;
    assert!(
        (per_degc_humid - per_degc + 0.03).abs() < 0.01,
        "humidity share {}",
        per_degc_humid - per_degc
    );
    let per_hpa = (n(t0, p0 + 50.0, h0) - n(t0, p0 - 50.0, h0)) / n0 * 1e6;
    let per_pct = (n(t0, p0, h0 + 5.0) - n(t0, p0, h0 - 5.0)) / 10.0 / n0 * 1e6;
    assert!((per_degc + 0.93).abs() < 0.02, "{per_degc} ppm/°C");
    assert!((per_hpa - 0.27).abs() < 0.01, "{per_hpa} ppm/hPa");
    assert!((per_pct + 0.0085).abs() < 0.002, "{per_pct} ppm/%RH");
}

#[test]
fn uncompensated_air_errors_follow_the_edlen_sensitivity_and_compensation_removes_them() {
    // Air at 25 °C. Without compensation the instrument divides by standard air's index, so
    // every displacement reads n(25)/n(20) - 1 ≈ -5 × 0.93 ppm short: ≈ -3.26 µm over 700 mm.
    // With its sensors (exact) it reads true; with its temperature sensor 1 °C high, about
    // +0.93 ppm long.
    let machine = vmc3();
    let errors = ErrorModel::empty(&machine);
    let warm = Air {
        temperature: 25.0,
        ..Air::STANDARD
    };
    let span = 0.7;
    let last = |table: &PositioningTable| {
        table
            .readings
            .iter()
            .find(|r| (r.target - 0.71).abs() < 1e-12 && r.approach == Approach::Up)
            .unwrap()
            .deviation
    };
    let off = measure(
        &Laser {
            air: warm,
            ..ideal_laser()
        },
        &errors,
        &machine,
    );
    let exact_ratio = warm.refractive_index(HENE_WAVELENGTH_UM)
        / Air::STANDARD.refractive_index(HENE_WAVELENGTH_UM)
        - 1.0;
    assert!((last(&off) - exact_ratio * span).abs() < 1e-12);
    assert!(
        (last(&off) / span * 1e6 + 5.0 * 0.93).abs() < 0.1,
        "{} ppm",
        last(&off) / span * 1e6
    );
    let sensors = |temperature_offset: f64| AirCompensation::Sensors {
        temperature_offset,
        pressure_offset: 0.0,
        humidity_offset: 0.0,
    };
    let on = measure(
        &Laser {
            air: warm,
            compensation: sensors(0.0),
            ..ideal_laser()
        },
        &errors,
        &machine,
    );
    assert!(last(&on).abs() < 1e-12, "compensated: {}", last(&on));
    let biased = measure(
        &Laser {
            air: warm,
            compensation: sensors(1.0),
            ..ideal_laser()
        },
        &errors,
        &machine,
    );
    assert!(
        (last(&biased) / span * 1e6 - 0.93).abs() < 0.03,
        "{} ppm",
        last(&biased) / span * 1e6
    );
}

#[test]
fn a_misaligned_beam_reads_short_by_the_cosine_error() {
    // Beam tilted by θ = 1 mrad: it reads L·cos θ, short by L·θ²/2 = 0.35 µm over 700 mm.
    let machine = vmc3();
    let laser = Laser {
        misalignment: [0.0, 1e-3],
        ..ideal_laser()
    };
    let table = measure(&laser, &ErrorModel::empty(&machine), &machine);
    let reading = table
        .readings
        .iter()
        .find(|r| (r.target - 0.71).abs() < 1e-12)
        .unwrap();
    let expected = 0.7 * (1.0 / (1.0f64 + 1e-6).sqrt() - 1.0);
    assert!((reading.deviation - expected).abs() < 1e-12 && (expected + 0.35e-6).abs() < 1e-9);
}

#[test]
fn material_compensation_scales_to_twenty_degrees() {
    // NDE with 11.7 ppm/K and a material at 22 °C: readings shrink by 23.4 ppm: -16.38 µm at 700 mm.
    let machine = vmc3();
    let laser = Laser {
        material: Some(MaterialCompensation {
            expansion: 11.7e-6,
            measured_temperature: 22.0,
        }),
        ..ideal_laser()
    };
    let table = measure(&laser, &ErrorModel::empty(&machine), &machine);
    let reading = table
        .readings
        .iter()
        .find(|r| (r.target - 0.71).abs() < 1e-12)
        .unwrap();
    assert!((reading.deviation + 23.4e-6 * 0.7).abs() < 1e-12);
}

#[test]
fn lost_motion_appears_as_the_reversal_value() {
    // EXX lost motion 3 µm: the axis lags by 1.5 µm against its travel. Zeroed at the first
    // target approached upwards, the up readings read 0 and the down readings +3 µm.
    let machine = vmc3();
    let errors = ErrorModel::new(
        &machine,
        vec![ErrorParameter {
            name: "EXX".parse().unwrap(),
            function: ErrorFunction::Reversal(3e-6),
        }],
    )
    .unwrap();
    let table = measure(&ideal_laser(), &errors, &machine);
    for r in &table.readings {
        let expected = if r.approach == Approach::Up {
            0.0
        } else {
            3e-6
        };
        assert!((r.deviation - expected).abs() < 1e-12, "{r:?}");
    }
}

#[test]
fn the_linear_cycle_visits_every_target_both_ways_on_time() {
    // Targets 100, 200 mm, overrun 5 mm, 600 mm/min (10 mm/s), dwell 1 s, from 95 mm:
    // up 100 at 0.5 + 1 = 1.5 s, 200 at 1.5 + 10 + 1 = 12.5 s; overrun to 205 (13.0 s), down
    // 200 at 14.5 s, 100 at 25.5 s; back to 95 (26.0 s), run 2 starts at 100 at 27.5 s.
    let cycle = LinearCycle {
        axis: Axis::X,
        targets: vec![0.1, 0.2],
        runs: 2,
        overrun: 0.005,
        feed: 0.01,
        dwell: 1.0,
        rest: AxisValues::ZERO,
    };
    let visits = cycle.visits();
    assert_eq!(visits.len(), 8);
    let times: Vec<f64> = visits.iter().map(|v| v.time).collect();
    for (got, want) in times
        .iter()
        .zip([1.5, 12.5, 14.5, 25.5, 27.5, 38.5, 40.5, 51.5])
    {
        assert!((got - want).abs() < 1e-9, "{times:?}");
    }
    let order: Vec<(usize, Approach)> = visits
        .iter()
        .map(|v| (v.point.target, v.point.approach))
        .collect();
    assert_eq!(
        order[..4],
        [
            (0, Approach::Up),
            (1, Approach::Up),
            (1, Approach::Down),
            (0, Approach::Down)
        ]
    );
    assert_eq!(
        visits[2].state.direction(Axis::X),
        mtwin::machine::Direction::Negative
    );
}

#[test]
fn irregular_targets_keep_their_ends_and_stay_near_the_even_spacing() {
    let targets = irregular_targets(0.01, 0.75, 9, &mut seeded_rng(5, "targets"));
    let spacing = 0.74 / 8.0;
    assert_eq!((targets[0], targets[8]), (0.01, 0.75));
    for (i, t) in targets.iter().enumerate() {
        assert!((t - (0.01 + spacing * i as f64)).abs() <= spacing / 4.0);
    }
    // Irregular: the interior spacings are not all equal.
    let gaps: Vec<f64> = targets.windows(2).map(|w| w[1] - w[0]).collect();
    assert!(gaps.iter().any(|g| (g - spacing).abs() > 1e-6));
    assert_eq!(
        targets,
        irregular_targets(0.01, 0.75, 9, &mut seeded_rng(5, "targets"))
    );
}

#[test]
fn the_bundled_test_recovers_the_injected_lost_motion() {
    // vmc3_iso230_2.toml injects 3 µm of lost motion on X; the analysis of the simulated file
    // must give B̄ = -3 µm (the axis lags against its travel: x̄↑ - x̄↓ = -3 µm) to within the
    // laser noise: 20 nm per reading, so B̄'s standard error is 20 nm·√(2/5)/√9 ≈ 4 nm; allow
    // 5 standard errors plus the 1 nm resolution.
    use mtwin::app::{Scenario, run_scenario};
    use mtwin::kinds::positioning::iso230_2::evaluate;
    let scenario = Scenario::load(concat!(
        env!("CARGO_MANIFEST_DIR"),
        "/scenarios/vmc3_iso230_2.toml"
    ))
    .unwrap();
    let output = run_scenario(&scenario).unwrap();
    let bytes = &output
        .files
        .iter()
        .find(|(n, _)| n == "positioning.csv")
        .unwrap()
        .1;
    let table = PositioningTable::parse(bytes, "positioning.csv").unwrap();
    let result = evaluate(&table).unwrap();
    let mean_reversal = result.both.unwrap().mean_reversal;
    assert!(
        (mean_reversal + 3e-6).abs() < 5.0 * 4.2e-9 + 1e-9,
        "B̄ = {mean_reversal}"
    );
}

#[test]
fn the_dead_path_drifts_with_the_air_even_when_compensated() {
    // No motion between the zero and a reading, 1 m of dead path, the air 1 °C warmer at the
    // reading, sensors exact. The fringe count still changes by the dead path's optical length:
    // reading = L_dead·(n(21 °C) - n(20 °C)) / n(21 °C) ≈ -0.96 µm at 50 %RH (Edlén: about
    // -0.93 ppm/°C dry, -0.03 ppm/°C more from the humidity).
    let machine = vmc3();
    let laser = Laser {
        dead_path: 1.0,
        compensation: AirCompensation::Sensors {
            temperature_offset: 0.0,
            pressure_offset: 0.0,
            humidity_offset: 0.0,
        },
        ..ideal_laser()
    };
    let visit = |run: usize, time: f64| mtwin::program::Visit {
        point: mtwin::program::MeasurePoint {
            run,
            target: 0,
            approach: Approach::Up,
        },
        time,
        state: mtwin::machine::MachineState::at(AxisValues::ZERO),
    };
    let visits = [visit(0, 0.0), visit(0, 600.0)];
    let twin = Twin {
        machine: machine.clone(),
        errors: ErrorModel::empty(&machine),
    };
    let poses = twin.poses(&visits);
    let table = laser.measure_in_air(
        &visits,
        &poses,
        Some(&[20.0, 21.0]),
        None,
        &[0.0],
        &mut seeded_rng(1, "laser"),
    );
    let n = |t: f64| {
        Air {
            temperature: t,
            ..Air::STANDARD
        }
        .refractive_index(HENE_WAVELENGTH_UM)
    };
    let expected = 1.0 * (n(21.0) - n(20.0)) / n(21.0);
    assert!(
        (table.readings[1].deviation - expected).abs() < 1e-15,
        "{}",
        table.readings[1].deviation
    );
    assert!((expected + 0.96e-6).abs() < 0.03e-6, "{expected}");
    // Without a dead path the same change leaves nothing.
    let table = Laser {
        dead_path: 0.0,
        ..laser
    }
    .measure_in_air(
        &visits,
        &poses,
        Some(&[20.0, 21.0]),
        None,
        &[0.0],
        &mut seeded_rng(1, "laser"),
    );
    assert!(table.readings[1].deviation.abs() < 1e-18);
}

#[test]
fn the_reverse_set_up_reads_what_the_usual_one_reads() {
    // Both set-ups measure the same two points, tip-side and workpiece-side; only which one
    // carries the beam differs. EXX = k·x (a pure translation): identical readings.
    let machine = vmc3();
    let model = |name: &str, k: f64| {
        ErrorModel::new(
            &machine,
            vec![ErrorParameter {
                name: name.parse().unwrap(),
                function: ErrorFunction::Polynomial(vec![0.0, k]),
            }],
        )
        .unwrap()
    };
    let reverse = |laser: Laser| Laser {
        mounting: Mounting::InterferometerOnTool,
        ..laser
    };
    let scale = model("EXX", 15e-6);
    let (f, r) = (
        measure(&ideal_laser(), &scale, &machine),
        measure(&reverse(ideal_laser()), &scale, &machine),
    );
    for (f, r) in f.readings.iter().zip(&r.readings) {
        assert!(
            (f.deviation - r.deviation).abs() < 1e-15,
            "{} vs {}",
            f.deviation,
            r.deviation
        );
    }
    // EBX = k·x (the table pitching) seen 0.1 m above the tip: an Abbe error of up to
    // 20e-6·0.7·0.4 m ≈ 5.6 µm in both set-ups; they differ only at second order, when the beam
    // on the tool and the reflector on the table see the rotation from different sides:
    // ε²·arm ≈ (14 µrad)²·0.4 m ≈ 1e-10 m.
    let pitch = model("EBX", 20e-6);
    let raised = Laser {
        beam_offset: Vector::new(0.0, 0.0, 0.1),
        ..ideal_laser()
    };
    let (f, r) = (
        measure(&raised, &pitch, &machine),
        measure(&reverse(raised.clone()), &pitch, &machine),
    );
    let mut largest: f64 = 0.0;
    for (f, r) in f.readings.iter().zip(&r.readings) {
        assert!(
            (f.deviation - r.deviation).abs() < 2e-10,
            "{} vs {}",
            f.deviation,
            r.deviation
        );
        largest = largest.max(f.deviation.abs());
    }
    assert!(largest > 4e-6, "the Abbe error shows: {largest}");
}

//! Running the R-test: calibrate the nest, then each test's poses through the twin, read by
//! the nest and converted by its software; and the set-up as injected, for the truth.

use super::instrument::{Calibration, Conversion, calibration_offsets, fit_sensitivity, um};
use super::program::{Pose, describe_angles, dynamic_poses, follow, static_poses};
use super::scenario::{Mode, RTest, Zero};
use super::table::{RtestRow, RtestTable};
use crate::io::Conditions;
use crate::machine::{Axis, MachineState, Workspace};
use crate::math::{M_PER_MM, Real, Vector, rigid_inverse, trimmed};
use crate::twin::Twin;
use rand_chacha::ChaCha8Rng;
use serde_json::{Value, json};

/// Why an R-test could not be simulated.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
#[non_exhaustive]
pub enum RtestRunError {
    /// A pose cannot be reached.
    #[error("R-test: {0}")]
    Follow(#[from] super::program::FollowError),
    /// The sphere left a probe's range.
    #[error(
        "R-test \"{test}\" at {angles}: probe {probe} reads {reading_um:.1} µm, beyond its range of ±{range_um:.0} µm (errors this large need a coarser check first, or a larger range)"
    )]
    OutOfRange {
        /// The test.
        test: String,
        /// The pose, for people.
        angles: String,
        /// 1-based probe number.
        probe: usize,
        /// Its reading (µm).
        reading_um: Real,
        /// Its range (µm).
        range_um: Real,
    },
    /// The calibration did not give a usable conversion.
    #[error("R-test calibration: {0}")]
    Singular(#[from] super::instrument::SingularNest),
}

/// The R-test table of `test` on `twin`; the nest's noise seeded from `seed`.
pub fn simulate(twin: &Twin, test: &RTest, seed: u64) -> Result<RtestTable, RtestRunError> {
    let machine = &twin.machine;
    let mut workspace = Workspace::new(machine);
    let mut rng = crate::math::seeded_rng(seed, "rtest nest");
    let conversion = calibrate(twin, test, &mut workspace, &mut rng)?;
    let rotary: Vec<Axis> = machine.rotary_axes().map(|i| i.axis).collect();
    let mut rows = Vec::new();
    let mut readings = vec![0.0; test.nest.probes.len()];
    let mut change = vec![0.0; test.nest.probes.len()];
    let mut first: Option<Vec<Real>> = None;
    // The programme's clock at the start of each test: the error model is evaluated at it
    // (drift, heating and time-dependent error motions act through the sequence), while the
    // table's `time_s` is the time since the start of the test. The next test starts one dwell
    // (static) or one sample period (dynamic) after the last reading of the one before.
    let mut clock = 0.0;
    for k_test in &test.tests {
        let (mut poses, gap): (Vec<Pose>, Real) = match &test.mode {
            Mode::Static { dwell } => (
                static_poses(machine, &mut workspace, k_test, test.sphere, *dwell)?,
                *dwell,
            ),
            Mode::Dynamic(dynamic) => (
                dynamic_poses(machine, &mut workspace, k_test, test.sphere, dynamic)?,
                1.0 / dynamic.sample_rate,
            ),
        };
        for pose in &mut poses {
            pose.state.time = clock + pose.time;
        }
        clock += poses.last().map_or(0.0, |pose| pose.time) + gap;
        if test.zero == Zero::EachTest {
            first = None;
        }
        for (index, pose) in poses.iter().enumerate() {
            // The controller follows the stated sphere; the sphere is where the preset left it.
            let v = sphere_in_nest(
                twin,
                &mut workspace,
                &pose.state,
                test.sphere + test.sphere_setup,
            );
            test.nest.read(v, &mut rng, &mut readings);
            if let Some((probe, reading)) = readings
                .iter()
                .enumerate()
                .find(|(_, d)| d.abs() > test.nest.range)
            {
                return Err(RtestRunError::OutOfRange {
                    test: k_test.name.clone(),
                    angles: describe_angles(machine, &pose.command),
                    probe: probe + 1,
                    reading_um: um(*reading),
                    range_um: um(test.nest.range),
                });
            }
            let zero = first.get_or_insert_with(|| readings.clone());
            for ((c, d), z) in change.iter_mut().zip(&readings).zip(zero.iter()) {
                *c = d - z;
            }
            let sphere_move = conversion.displacement(&change);
            // The tool relative to the sphere is the opposite of the sphere relative to the
            // nest; the software turns it into machine axes by the nominal tool orientation.
            workspace.workpiece_from_tool(machine, &pose.command, None);
            let world_from_tool = workspace.world_from_ends().0.matrix3;
            let mut angles = [None; 3];
            for axis in &rotary {
                angles[axis.coordinate()] = Some(pose.command[*axis]);
            }
            rows.push(RtestRow {
                test: k_test.name.clone(),
                point: Some(index),
                time: Some(pose.time),
                angles,
                linear: Some(Vector::new(
                    pose.command[Axis::X],
                    pose.command[Axis::Y],
                    pose.command[Axis::Z],
                )),
                deviation: -(world_from_tool * sphere_move),
                probes: readings.clone(),
            });
        }
    }
    Ok(RtestTable {
        rows,
        conditions: conditions(twin, test),
        columns_not_read: Vec::new(),
    })
}

/// The sphere centre in the actual nest frame at `state`: where the probes see it.
pub fn sphere_in_nest(
    twin: &Twin,
    workspace: &mut Workspace,
    state: &MachineState,
    sphere: Vector,
) -> Vector {
    let actual = twin
        .errors
        .workpiece_from_tool(&twin.machine, workspace, state);
    rigid_inverse(&actual).transform_point3(sphere)
}

/// The software's conversion: nominal, or the six-point calibration run at the first test's
/// start (the machine moves the nest by the commanded steps; the readings come from the twin).
fn calibrate(
    twin: &Twin,
    test: &RTest,
    workspace: &mut Workspace,
    rng: &mut ChaCha8Rng,
) -> Result<Conversion, RtestRunError> {
    let step = match test.nest.calibration {
        Calibration::Nominal => return Ok(Conversion::new(test.nest.nominal_sensitivity())?),
        Calibration::SixPoint { step } => step,
    };
    let machine = &twin.machine;
    let angles = test.tests[0].angles_at(machine, 0.0);
    let centre = follow(machine, workspace, &angles, test.sphere)?;
    let workpiece_from_nest = workspace
        .workpiece_from_tool(machine, &centre, None)
        .matrix3;
    let positions = calibration_offsets(step);
    let mut readings = Vec::with_capacity(positions.len());
    for v in positions {
        // The sphere at v in the nest frame: the tool tip at sphere − R·v.
        let command = follow(
            machine,
            workspace,
            &angles,
            test.sphere - workpiece_from_nest * v,
        )?;
        let seen = sphere_in_nest(
            twin,
            workspace,
            &MachineState::at(command),
            test.sphere + test.sphere_setup,
        );
        let mut d = vec![0.0; test.nest.probes.len()];
        test.nest.read(seen, rng, &mut d);
        if let Some((probe, reading)) = d
            .iter()
            .enumerate()
            .find(|(_, d)| d.abs() > test.nest.range)
        {
            return Err(RtestRunError::OutOfRange {
                test: "six-point calibration".into(),
                angles: describe_angles(machine, &command),
                probe: probe + 1,
                reading_um: um(*reading),
                range_um: um(test.nest.range),
            });
        }
        readings.push(d);
    }
    Ok(Conversion::new(fit_sensitivity(&positions, &readings))?)
}

/// The preamble of the table.
fn conditions(twin: &Twin, test: &RTest) -> Conditions {
    let s = test.sphere / M_PER_MM;
    let mut pairs = vec![
        ("machine", twin.machine.name().to_string()),
        (
            "sphere_mm",
            format!(
                "{} {} {}",
                trimmed(s.x, 6),
                trimmed(s.y, 6),
                trimmed(s.z, 6)
            ),
        ),
        (
            "sphere_diameter_mm",
            trimmed(2.0 * test.nest.sphere_radius / M_PER_MM, 6),
        ),
        (
            "tip",
            match test.nest.tip {
                super::instrument::Tip::Flat => "flat".into(),
                super::instrument::Tip::Point { .. } => "point".into(),
            },
        ),
        (
            "calibration",
            match test.nest.calibration {
                Calibration::Nominal => "nominal".into(),
                Calibration::SixPoint { .. } => "six_point".into(),
            },
        ),
        (
            "mode",
            match test.mode {
                Mode::Static { .. } => "static".into(),
                Mode::Dynamic(_) => "dynamic".into(),
            },
        ),
    ];
    if test.zero == Zero::FirstPose {
        pairs.push(("zero", Zero::FirstPose.name().into()));
    }
    pairs.push(("frame", super::table::FRAMES[0].into()));
    Conditions::from_pairs(pairs)
}

/// The nest and the tests as injected, in file units.
pub fn truth(test: &RTest) -> Value {
    let nest = &test.nest;
    json!({
        "sphere_mm": (test.sphere / M_PER_MM).to_array(),
        "sphere_setup_um": (test.sphere_setup / crate::math::M_PER_UM).to_array(),
        "sphere_diameter_mm": 2.0 * nest.sphere_radius / M_PER_MM,
        "tip": match nest.tip {
            super::instrument::Tip::Flat => json!({"kind": "flat"}),
            super::instrument::Tip::Point { radius } => json!({"kind": "point", "radius_mm": radius / M_PER_MM}),
        },
        "probes": nest.probes.iter().map(|p| json!({
            "nominal_axis": p.nominal_axis.to_array(),
            "axis": p.axis.to_array(),
            "gain_error": p.gain_error,
        })).collect::<Vec<_>>(),
        "noise_um": um(nest.noise),
        "resolution_um": um(nest.resolution),
        "range_mm": nest.range / M_PER_MM,
        "zero": test.zero.name(),
        "calibration": match nest.calibration {
            Calibration::Nominal => json!({"kind": "nominal"}),
            Calibration::SixPoint { step } => json!({"kind": "six_point", "step_mm": step / M_PER_MM}),
        },
        "tests": test.tests.iter().map(|t| {
            let mut test = json!({
                "name": t.name,
                "points": t.points,
                "from_deg": rotary_degrees(&t.from),
                "to_deg": rotary_degrees(&t.to),
            });
            if t.back {
                // Only when set: the truth of a test one way is as it always was.
                test["back"] = json!(true);
            }
            test
        }).collect::<Vec<_>>(),
    })
}

fn rotary_degrees(values: &crate::machine::AxisValues) -> Value {
    [Axis::A, Axis::B, Axis::C]
        .into_iter()
        .filter(|a| values[*a] != 0.0)
        .map(|a| (a.to_string(), json!(values[a].to_degrees())))
        .collect::<serde_json::Map<_, _>>()
        .into()
}

/// One line for people: each test's deviation ranges.
pub fn summary(table: &RtestTable) -> String {
    let parts: Vec<String> = super::analysis::evaluate(table)
        .map(|e| {
            e.tests
                .iter()
                .map(|t| {
                    format!(
                        "R-test {}: ranges X {:.2}, Y {:.2}, Z {:.2} µm",
                        t.name, t.range_um[0], t.range_um[1], t.range_um[2]
                    )
                })
                .collect()
        })
        .unwrap_or_else(|e| vec![format!("R-test: {e}")]);
    parts.join("; ")
}

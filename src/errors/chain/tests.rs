//! The planned evaluation against the plain composition it replaces, on every bundled
//! machine with errors of every kind: the same poses, slot frames and slot motions to the
//! bit (`==`, which does not tell the signs of zero apart), but within `REGROUPED` for models
//! with a located rotary axis line on the workpiece branch.

use super::*;
use crate::errors::binding::Action;
use crate::errors::{
    ContextTerm, Driver, Dynamics, ErrorFunction, ErrorParameter, Frequency, Interpolation,
    ParameterContext, ParameterDynamics, ParameterName, Sinusoid, Table,
};
use crate::machine::Side;
use crate::machine::{Axis, Direction, axis_angle, plain_workpiece_from_tool, random_position};
use crate::math::seeded_rng;
use crate::math::{Vector, rigid_inverse, small_motion};
use rand::RngExt;
use rand_chacha::ChaCha8Rng;
use std::f64::consts::TAU;

/// The slot motions as mtwin built them before the plan: every parameter summed at every
/// pose, every small motion and axis-line motion composed in full.
fn plain_motions(
    model: &ErrorModel,
    machine: &Machine,
    state: &MachineState,
    extra: Option<&[[Real; 6]]>,
) -> Vec<Pose> {
    let slots = machine.slot_count();
    let (mut relative, mut line) = (vec![[0.0; 6]; slots], vec![[0.0; 6]; slots]);
    for (parameter, binding) in model.parameters.iter().zip(&model.bindings) {
        let component = parameter.name.motion().index();
        match binding.action {
            Action::Component(axis) => {
                relative[binding.slot][component] += parameter.function.value(
                    binding.argument(state.position[axis]),
                    state.direction(axis),
                );
            }
            Action::Constant => {
                relative[binding.slot][component] += super::super::constant(&parameter.function)
            }
            Action::Squareness(_) | Action::RotaryLocation(_) => {
                line[binding.slot][component] += super::super::constant(&parameter.function);
            }
        }
    }
    for (entry, binding) in model.dynamics.iter().zip(&model.dynamic_bindings) {
        let q = state.position[binding.axis];
        let factor = entry.dynamics.factor(state.velocity[binding.axis]);
        let mut value = factor * entry.dynamics.asynchronous(state.time, q);
        if let Some(index) = binding.parameter.filter(|_| factor != 1.0) {
            value += (factor - 1.0)
                * model.parameters[index].function.value(
                    model.bindings[index].argument(q),
                    state.direction(binding.axis),
                );
        }
        relative[binding.slot][binding.component] += value;
    }
    model.context.add(state, &mut relative, &mut line);
    if let Some(extra) = extra {
        for (twist, add) in relative.iter_mut().zip(extra) {
            for (value, a) in twist.iter_mut().zip(add) {
                *value += a;
            }
        }
    }
    (0..slots)
        .map(|slot| {
            let t = relative[slot];
            let motion = small_motion(Vector::new(t[0], t[1], t[2]), Vector::new(t[3], t[4], t[5]));
            let l = line[slot];
            if l == [0.0; 6] {
                return motion;
            }
            let info = &machine.axes()[slot];
            let q = state.position[info.axis];
            let line_motion = if info.axis.is_linear() {
                let direction = info.axis.unit();
                let tilted =
                    small_motion(Vector::ZERO, Vector::new(l[3], l[4], l[5])).matrix3 * direction;
                Pose::from_translation((tilted - direction) * q)
            } else {
                let line_pose =
                    small_motion(Vector::new(l[0], l[1], l[2]), Vector::new(l[3], l[4], l[5]));
                let rotation = Pose::from_mat3(axis_angle(info.joint_axis, q));
                let carried =
                    line_pose * rotation * rigid_inverse(&line_pose) * rigid_inverse(&rotation);
                match info.side {
                    Side::Tool => carried,
                    Side::Workpiece => rigid_inverse(&carried),
                }
            };
            line_motion * motion
        })
        .collect()
}

fn small(rng: &mut ChaCha8Rng) -> Real {
    rng.random_range(-2e-5..2e-5)
}

/// A function of every kind the axis allows (a continuous axis's repeat every turn). With
/// `whole_turns`, harmonics of rotary axes have a whole number of periods per turn (a
/// [`TurnSeries`]); without, continuous axes have none.
fn function(
    rng: &mut ChaCha8Rng,
    continuous: bool,
    travel: (Real, Real),
    whole_turns: bool,
) -> ErrorFunction {
    let harmonic = |rng: &mut ChaCha8Rng| ErrorFunction::Harmonic {
        period: if whole_turns {
            TAU / rng.random_range(1..4) as Real
        } else {
            (travel.1 - travel.0) / rng.random_range(0.5..7.0)
        },
        amplitude: small(rng),
        phase: rng.random_range(0.0..TAU),
    };
    if continuous && !whole_turns {
        return ErrorFunction::Reversal(small(rng));
    }
    let table = |rng: &mut ChaCha8Rng| {
        let (low, high) = if continuous { (0.0, TAU) } else { travel };
        let n = rng.random_range(2..7);
        let positions = (0..n)
            .map(|i| low + (high - low) * i as Real / (n - 1) as Real)
            .collect();
        let mut values: Vec<Real> = (0..n).map(|_| small(rng)).collect();
        if continuous {
            values[n - 1] = values[0];
        }
        let interpolation = if rng.random_bool(0.5) {
            Interpolation::Linear
        } else {
            Interpolation::Cubic
        };
        ErrorFunction::Table(Table::new(positions, values, interpolation).unwrap())
    };
    match rng.random_range(0..6) {
        0 => ErrorFunction::Constant(small(rng)),
        1 if !continuous => ErrorFunction::Polynomial((0..4).map(|_| small(rng)).collect()),
        2 => table(rng),
        3 => ErrorFunction::Reversal(small(rng)),
        4 => ErrorFunction::Sum(vec![
            ErrorFunction::Constant(small(rng)),
            harmonic(rng),
            harmonic(rng),
        ]),
        _ => harmonic(rng),
    }
}

/// About half of every parameter the machine has, with dynamics on some component errors
/// and context terms (time-driven, so no record is needed) on a few parameters.
fn rich_model(machine: &Machine, rng: &mut ChaCha8Rng, whole_turns: bool) -> ErrorModel {
    let mut parameters = Vec::new();
    for name in ParameterName::all() {
        if !rng.random_bool(0.5) {
            continue;
        }
        let Ok(binding) = super::super::Binding::of(machine, name) else {
            continue;
        };
        let function = match (binding.action, name.axis().and_then(|a| machine.axis(a))) {
            (Action::Component(axis), Some(info)) => {
                let travel = info.limits.unwrap_or((0.0, TAU));
                let whole_turns = whole_turns && !axis.is_linear();
                function(rng, binding.periodic, travel, whole_turns)
            }
            _ => ErrorFunction::Constant(small(rng)),
        };
        parameters.push(ErrorParameter { name, function });
    }
    let model = ErrorModel::new(machine, parameters).unwrap();
    let mut dynamics = Vec::new();
    let mut context = Vec::new();
    for name in ParameterName::all() {
        let Ok(binding) = super::super::Binding::of(machine, name) else {
            continue;
        };
        if matches!(binding.action, Action::Component(_)) && rng.random_bool(0.15) {
            let speed_factor = rng.random_bool(0.5).then(|| {
                Table::new(vec![0.0, 10.0], vec![1.0, 2.5], Interpolation::Linear).unwrap()
            });
            let frequency = Frequency::Hz(rng.random_range(1.0..100.0));
            dynamics.push(ParameterDynamics {
                name,
                dynamics: Dynamics {
                    sinusoids: vec![Sinusoid {
                        frequency,
                        amplitude: small(rng),
                        phase: 0.3,
                    }],
                    random: None,
                    speed_factor,
                },
            });
        }
        if rng.random_bool(0.1) {
            let driver = if rng.random_bool(0.5) {
                Driver::Drift { from: 1.0 }
            } else {
                Driver::Heating {
                    tau: 300.0,
                    from: 0.0,
                }
            };
            context.push(ParameterContext {
                name,
                terms: vec![ContextTerm {
                    driver,
                    coefficient: 1e-9,
                    per_position: false,
                }],
            });
        }
    }
    model
        .with_dynamics(machine, dynamics)
        .unwrap()
        .with_context(machine, context, None)
        .unwrap()
}

fn random_state(machine: &Machine, rng: &mut ChaCha8Rng) -> MachineState {
    let position = random_position(machine, rng);
    let mut state = MachineState::at(position).at_time(rng.random_range(0.0..1000.0));
    for axis in Axis::ALL {
        state = state.with_velocity(axis, rng.random_range(-20.0..20.0));
        if rng.random_bool(0.3) {
            state.direction[axis.index()] = Direction::Negative;
        }
    }
    state
}

/// How far the walk about a workpiece-side rotary axis line (`rel⁻¹ · L · R · L⁻¹`) may be
/// from the plain composition (`(L·R·L⁻¹·R⁻¹)⁻¹`-composed, inverted, then `R`): the same
/// product regrouped, so a few units in the last place of entries of order 1 (rotation)
/// and of the metre-sized translations (2.2e-16 each), 1e-8 µm.
const REGROUPED: Real = 8.0 * f64::EPSILON;

#[test]
fn planned_chain_is_the_plain_chain_to_the_bit() {
    // To the bit for models without a located rotary line on the workpiece branch; within
    // [`REGROUPED`] for those with one.
    compare_with_plain_chain(false, None);
}

#[test]
fn harmonics_per_turn_agree_with_their_sines() {
    // The recurrence and the sine differ by ulps of the amplitudes (µm, µrad), which shows
    // as round-off of the metre-sized chain at most.
    compare_with_plain_chain(true, Some(1e-15));
}

/// Whether the entries of `a` and `b` are equal (`tolerance` `None`; `==`, blind to the
/// sign of zero) or within `tolerance` of each other.
fn same(a: &[Pose], b: &[Pose], tolerance: Option<Real>) -> bool {
    let entries =
        |poses: &[Pose]| -> Vec<Real> { poses.iter().flat_map(|p| p.to_cols_array()).collect() };
    same_values(&entries(a), &entries(b), tolerance)
}

fn same_values(a: &[Real], b: &[Real], tolerance: Option<Real>) -> bool {
    a.len() == b.len()
        && a.iter().zip(b).all(|(x, y)| match tolerance {
            None => x == y,
            Some(tolerance) => (x - y).abs() <= tolerance,
        })
}

/// Runs the planned chain against the plain one on random models and states.
fn compare_with_plain_chain(whole_turns: bool, tolerance: Option<Real>) {
    let mut rng = seeded_rng(2, "planned chain");
    for path in ["vmc3", "trunnion5", "headtable5"] {
        let file = format!("{}/models/{path}.urdf", env!("CARGO_MANIFEST_DIR"));
        let machine = Machine::from_urdf_file(&file).unwrap();
        let mut workspace = Workspace::new(&machine);
        for _ in 0..40 {
            let mut model = rich_model(&machine, &mut rng, whole_turns);
            if rng.random_bool(0.3) {
                // New coefficients: the plan follows.
                let scaled: Vec<Real> = model.coefficients().iter().map(|c| -2.0 * c).collect();
                model.set_coefficients(&scaled);
            }
            let regrouped = model.plan.lines.iter().any(Option::is_some);
            let tolerance = match (regrouped, tolerance) {
                (true, tolerance) => Some(tolerance.unwrap_or(0.0).max(REGROUPED)),
                (false, tolerance) => tolerance,
            };
            for _ in 0..25 {
                let state = random_state(&machine, &mut rng);
                let extra: Vec<[Real; 6]> = (0..machine.slot_count())
                    .map(|_| {
                        let mut t = [0.0; 6];
                        if rng.random_bool(0.3) {
                            t.iter_mut().for_each(|v| *v = small(&mut rng));
                        }
                        t
                    })
                    .collect();
                let at = format!("{} at {state:?}", machine.name());
                for extra in [None, Some(&extra[..])] {
                    let pose =
                        model.workpiece_from_tool_with(&machine, &mut workspace, &state, extra);
                    let motions = plain_motions(&model, &machine, &state, extra);
                    let (plain, world_from_slot, ends) =
                        plain_workpiece_from_tool(&machine, &state.position, Some(&motions));
                    assert!(
                        same(&[pose], &[plain], tolerance),
                        "{at}: {pose} vs {plain}"
                    );
                    assert!(same(
                        workspace.world_from_slot(),
                        &world_from_slot,
                        tolerance
                    ));
                    let (tool, workpiece) = workspace.world_from_ends();
                    assert!(same(&[tool, workpiece], &ends, tolerance), "{at}");
                    // The whole slot motions, lines included, are the plain ones.
                    let planned_motions =
                        model.slot_motions(&machine, &mut workspace, &state, extra);
                    assert!(same(&planned_motions, &motions, tolerance), "{at}");
                }
                let nominal = plain_workpiece_from_tool(&machine, &state.position, None).0;
                let motions = plain_motions(&model, &machine, &state, None);
                let actual = plain_workpiece_from_tool(&machine, &state.position, Some(&motions)).0;
                let planned = model.deviation(&machine, &mut workspace, &state);
                let plain = Deviation::between(&nominal, &actual);
                assert!(
                    same_values(&planned.to_array(), &plain.to_array(), tolerance),
                    "{at}"
                );
            }
        }
    }
}

/// A workspace keeps the fixed slot motions of the plan it last evaluated and recomputes only
/// the others: two models taking turns on one workspace, with evaluations that write other
/// motions in between (extra twists, explicit slot motions), give every pose to the bit as a
/// fresh workspace does.
#[test]
fn a_shared_workspace_gives_what_a_fresh_one_gives() {
    let mut rng = seeded_rng(3, "shared workspace");
    // Models whose walk turns about a located line with a varying relative motion
    // (`AxisLine::turned_by`), counted so that the path is known to be exercised.
    let mut turned_by = 0;
    for path in ["vmc3", "trunnion5", "headtable5"] {
        let file = format!("{}/models/{path}.urdf", env!("CARGO_MANIFEST_DIR"));
        let machine = Machine::from_urdf_file(&file).unwrap();
        let slots = machine.slot_count();
        let mut shared = Workspace::new(&machine);
        for _ in 0..10 {
            let models = [0, 1].map(|_| rich_model(&machine, &mut rng, false));
            for model in &models {
                turned_by += (0..slots)
                    .filter(|&s| {
                        model.plan.lines[s].is_some() && model.plan.slots[s].relative.is_none()
                    })
                    .count();
            }
            for _ in 0..40 {
                let model = &models[rng.random_range(0..2)];
                let state = random_state(&machine, &mut rng);
                match rng.random_range(0..4) {
                    0 => {
                        let extra: Vec<[Real; 6]> = (0..slots)
                            .map(|_| [0.0, 0.0, 0.0, small(&mut rng), 0.0, 0.0])
                            .collect();
                        model.workpiece_from_tool_with(&machine, &mut shared, &state, Some(&extra));
                    }
                    1 => {
                        let motions: Vec<Pose> = (0..slots)
                            .map(|_| small_motion(Vector::X * small(&mut rng), Vector::ZERO))
                            .collect();
                        shared.workpiece_from_tool(&machine, &state.position, Some(&motions));
                    }
                    _ => {}
                }
                let pose = model.workpiece_from_tool(&machine, &mut shared, &state);
                let fresh =
                    model.workpiece_from_tool(&machine, &mut Workspace::new(&machine), &state);
                assert!(same(&[pose], &[fresh], None), "{path}: {pose} vs {fresh}");
            }
        }
    }
    assert!(
        turned_by > 0,
        "no model turned about a line with a varying motion"
    );
}

/// A model is bound to its machine's joint directions as well as to its axes and sides: the
/// plan turns a located rotary line about the bound machine's joint axis
/// (`AxisLine::turned_by`), and two machines with the same axes on the same sides may differ
/// there, as an identified machine (`mtwin identify`'s URDF) differs from the nominal one by
/// its axes' tilts. trunnion5 with C tilted by 100 µrad: a model bound to it gives the plain
/// chain's poses, a model bound to the nominal file is refused by it (turning C's line about
/// the nominal axis, its poses would be off by up to the tilt times the table's radius, tens
/// of µm at this tilt, µm at an identified machine's), and a
/// second load of the nominal file is the same machine, with the same poses to the bit.
#[test]
fn a_machine_with_a_tilted_joint_is_not_the_bound_one() {
    let file = format!("{}/models/trunnion5.urdf", env!("CARGO_MANIFEST_DIR"));
    let text = std::fs::read_to_string(&file).unwrap();
    // trunnion5's first `0 0 -1` axis is C's (A turns about −x, Z and S about +z).
    let tilted_text = text.replacen(r#"<axis xyz="0 0 -1"/>"#, r#"<axis xyz="0 1e-4 -1"/>"#, 1);
    assert_ne!(tilted_text, text);
    let machine = Machine::from_urdf_str(&text, "trunnion5.urdf").unwrap();
    let again = Machine::from_urdf_str(&text, "trunnion5.urdf").unwrap();
    let tilted = Machine::from_urdf_str(&tilted_text, "tilted.urdf").unwrap();
    let name = |n: &str| n.parse::<ParameterName>().unwrap();
    // A located C line (EX0C, EA0C) with a varying relative motion (ECC): the turned line.
    let parameters = vec![
        ErrorParameter {
            name: name("EX0C"),
            function: ErrorFunction::Constant(12e-6),
        },
        ErrorParameter {
            name: name("EA0C"),
            function: ErrorFunction::Constant(300e-6),
        },
        ErrorParameter {
            name: name("ECC"),
            function: ErrorFunction::Harmonic {
                period: TAU / 2.0,
                amplitude: 50e-6,
                phase: 0.3,
            },
        },
    ];
    let model = ErrorModel::new(&machine, parameters.clone()).unwrap();
    let on_tilted = ErrorModel::new(&tilted, parameters).unwrap();
    let c = machine
        .axes()
        .iter()
        .position(|i| i.axis == Axis::C)
        .unwrap();
    for m in [&model, &on_tilted] {
        assert!(m.plan.lines[c].is_some() && m.plan.slots[c].relative.is_none());
    }
    let mut rng = seeded_rng(5, "tilted joint");
    let mut ws = [&machine, &again, &tilted].map(Workspace::new);
    for _ in 0..20 {
        let state = random_state(&machine, &mut rng);
        let pose = model.workpiece_from_tool(&machine, &mut ws[0], &state);
        assert_eq!(pose, model.workpiece_from_tool(&again, &mut ws[1], &state));
        let planned = on_tilted.workpiece_from_tool(&tilted, &mut ws[2], &state);
        let motions = plain_motions(&on_tilted, &tilted, &state, None);
        let plain = plain_workpiece_from_tool(&tilted, &state.position, Some(&motions)).0;
        assert!(
            same(&[planned], &[plain], Some(REGROUPED)),
            "{planned} vs {plain}"
        );
    }
    let state = random_state(&machine, &mut rng);
    let refused = std::panic::catch_unwind(|| {
        let mut ws = Workspace::new(&tilted);
        model.workpiece_from_tool(&tilted, &mut ws, &state)
    })
    .expect_err("a model bound to the nominal machine passed for the tilted one's");
    let message = refused
        .downcast_ref::<String>()
        .expect("a formatted panic message");
    assert!(message.contains("bound to another machine"), "{message}");
}

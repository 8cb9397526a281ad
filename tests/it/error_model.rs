//! The ISO 230-1 error model against hand derivations: one injected error of each family
//! (linear component, squareness, rotary component, rotary location, tool) gives the deviation
//! derived by hand from the machines' documented geometry, sign and Abbe lever arm included;
//! zero errors give the nominal pose; the exact chain and the linearised model agree to second
//! order; the Jacobian agrees with central finite differences of the exact chain.
//!
//! Single-error hand formulas here are exact (rotations written with sin/cos), so the chain
//! must match them to round-off: 1 pm on positions of ~1 m.

use crate::common::*;
use mtwin::errors::{
    Deviation, ErrorFunction, ErrorModel, ErrorParameter, Interpolation, ParameterName, Table,
};
use mtwin::machine::{Axis, AxisValues, Direction, Machine, MachineState, Workspace};
use mtwin::math::{M_PER_UM, RAD_PER_DEG, RAD_PER_URAD, Real, Vector};

const EXACT_M: Real = 1e-12;

fn name(text: &str) -> ParameterName {
    text.parse().unwrap()
}

fn single(machine: &Machine, parameter: &str, function: ErrorFunction) -> ErrorModel {
    ErrorModel::new(
        machine,
        vec![ErrorParameter {
            name: name(parameter),
            function,
        }],
    )
    .unwrap()
}

fn deviation(machine: &Machine, errors: &ErrorModel, state: &MachineState) -> Deviation {
    errors.deviation(machine, &mut Workspace::new(machine), state)
}

fn at(values: &[(Axis, Real)]) -> MachineState {
    MachineState::at(AxisValues::from_file_units(values))
}

/// Every parameter name the machine accepts.
fn all_names(machine: &Machine) -> Vec<ParameterName> {
    let mut names = Vec::new();
    for info in machine.axes() {
        for m in ['X', 'Y', 'Z', 'A', 'B', 'C'] {
            for text in [format!("E{m}{}", info.axis), format!("E{m}0{}", info.axis)] {
                if let Ok(n) = text.parse::<ParameterName>() {
                    names.push(n);
                }
            }
        }
    }
    names.extend(["EXT", "EYT", "EZT"].map(name));
    names
}

#[test]
fn zero_errors_give_the_nominal_pose() {
    for machine_name in MACHINES {
        let machine = machine(machine_name);
        let zero_everywhere: Vec<ErrorParameter> = all_names(&machine)
            .into_iter()
            .map(|n| ErrorParameter {
                name: n,
                function: ErrorFunction::Constant(0.0),
            })
            .collect();
        assert!(
            zero_everywhere.len() >= 3 * 6 + 3 + 3,
            "{machine_name}: every family present"
        );
        let models = [
            ErrorModel::empty(&machine),
            ErrorModel::new(&machine, zero_everywhere).unwrap(),
        ];
        let mut rng = rng(&format!("{machine_name} zero"));
        let mut workspace = Workspace::new(&machine);
        for _ in 0..100 {
            let state = MachineState::at(random_position(&machine, &mut rng));
            let nominal = workspace.workpiece_from_tool(&machine, &state.position, None);
            for errors in &models {
                let actual = errors.workpiece_from_tool(&machine, &mut workspace, &state);
                assert_eq!(
                    actual,
                    nominal,
                    "{machine_name}: {}",
                    describe(&state.position)
                );
            }
        }
    }
}

#[test]
fn positioning_and_straightness_shift_the_tool_whichever_branch_moves() {
    // EXX on vmc3's table axis and EZZ on its head axis: the tool moves by the error along +X
    // and +Z relative to the workpiece (tool-relative sign convention).
    let vmc3 = machine("vmc3");
    let state = at(&[(Axis::X, 400.0), (Axis::Y, 100.0), (Axis::Z, 250.0)]);
    let cases = [
        ("EXX", Vector::X),
        ("EYX", Vector::Y),
        ("EZZ", Vector::Z),
        ("EXZ", Vector::X),
    ];
    for (parameter, direction) in cases {
        let errors = single(&vmc3, parameter, ErrorFunction::Constant(5.0 * M_PER_UM));
        let d = deviation(&vmc3, &errors, &state);
        assert_close(
            d.translation,
            direction * 5.0 * M_PER_UM,
            EXACT_M,
            parameter,
        );
    }
}

#[test]
fn lost_motion_lags_against_the_direction_of_travel() {
    let vmc3 = machine("vmc3");
    let errors = single(&vmc3, "EXX", ErrorFunction::Reversal(4.0 * M_PER_UM));
    let mut state = at(&[(Axis::X, 300.0)]);
    assert_close(
        deviation(&vmc3, &errors, &state).translation,
        Vector::X * -2.0 * M_PER_UM,
        EXACT_M,
        "moving +",
    );
    state.direction[Axis::X.index()] = Direction::Negative;
    assert_close(
        deviation(&vmc3, &errors, &state).translation,
        Vector::X * 2.0 * M_PER_UM,
        EXACT_M,
        "moving -",
    );
}

#[test]
fn angular_errors_of_linear_axes_have_their_abbe_arm() {
    // vmc3 geometry (URDF header): the X carriage reference point is at (-x, -y, 0.90) in the
    // world and the tip at (-0.38, -0.205, 1.10 + z), so the arm from the X carriage to the tip
    // is (-0.38 + x, -0.205 + y, 0.20 + z). The Z head reference point is 0.35 m behind the
    // spindle axis and 0.30 m above the tip: arm (0, 0.35, -0.30), whatever x, y, z.
    // A rotation R of the tool about the carriage point moves the tip by (R - I)·arm.
    let vmc3 = machine("vmc3");
    let (x, y, z) = (0.52, 0.13, 0.31);
    let state = at(&[(Axis::X, x * 1e3), (Axis::Y, y * 1e3), (Axis::Z, z * 1e3)]);
    let epsilon = 25.0 * RAD_PER_URAD;
    let arm_x = Vector::new(-0.38 + x, -0.205 + y, 0.20 + z);
    let arm_z = Vector::new(0.0, 0.35, -0.30);
    let cases = [
        ("EAX", rx(epsilon), arm_x),
        ("EBX", ry(epsilon), arm_x),
        ("ECX", rz(epsilon), arm_x),
        ("EAZ", rx(epsilon), arm_z),
        ("EBZ", ry(epsilon), arm_z),
        ("ECZ", rz(epsilon), arm_z),
    ];
    for (parameter, rotation, arm) in cases {
        let errors = single(&vmc3, parameter, ErrorFunction::Constant(epsilon));
        let d = deviation(&vmc3, &errors, &state);
        assert_close(
            d.translation,
            apply(rotation, arm) - arm,
            EXACT_M,
            parameter,
        );
        // And the tool axis tilts by the same rotation.
        let dk = apply(rotation, Vector::Z) - Vector::Z;
        assert!(
            (d.tilt[0] - dk.x).abs() < 1e-15 && (d.tilt[1] - dk.y).abs() < 1e-15,
            "{parameter} tilt"
        );
    }
    // First-order reading of one case: ECX = 25 µrad at y = 130 mm moves the tip by
    // -25e-6 · (-0.205 + 0.13) m = +1.875 µm in X, to within the neglected second-order term
    // ε²/2 · |arm| ≈ 0.05 nm.
    let errors = single(&vmc3, "ECX", ErrorFunction::Constant(epsilon));
    let dx = deviation(&vmc3, &errors, &state).translation.x;
    assert!((dx - 1.875e-6).abs() < 1e-10, "ECX Abbe error {dx}");
}

#[test]
fn squareness_tilts_the_line_of_travel() {
    // EC0Y: Y travels along Rz(s)·e_y, so the tip moves by (Rz(s) - I)·(0, y, 0); EB0Z and EA0Z
    // tilt Z about Y and X. All zero at the axis zero.
    let vmc3 = machine("vmc3");
    let s = 30.0 * RAD_PER_URAD;
    let (y, z) = (0.4, 0.5);
    let state = at(&[(Axis::X, 200.0), (Axis::Y, y * 1e3), (Axis::Z, z * 1e3)]);
    let cases = [
        ("EC0Y", rz(s), Vector::new(0.0, y, 0.0)),
        ("EB0Z", ry(s), Vector::new(0.0, 0.0, z)),
        ("EA0Z", rx(s), Vector::new(0.0, 0.0, z)),
    ];
    for (parameter, rotation, travel) in cases {
        let errors = single(&vmc3, parameter, ErrorFunction::Constant(s));
        let d = deviation(&vmc3, &errors, &state);
        assert_close(
            d.translation,
            apply(rotation, travel) - travel,
            EXACT_M,
            parameter,
        );
        assert_eq!(
            d.tilt,
            [0.0, 0.0],
            "{parameter}: squareness does not tilt the tool"
        );
    }
    // EC0Y > 0 opens the angle between +X and +Y travel: 90° + s.
    let errors = single(&vmc3, "EC0Y", ErrorFunction::Constant(s));
    let tip = |y_mm: Real| {
        let st = at(&[(Axis::Y, y_mm)]);
        machine("vmc3")
            .workpiece_from_tool(&st.position)
            .translation
            + deviation(&vmc3, &errors, &st).translation
    };
    let travel = tip(400.0) - tip(0.0);
    let angle = travel.normalize().dot(Vector::X).acos();
    assert!(
        (angle - (std::f64::consts::FRAC_PI_2 + s)).abs() < 1e-12,
        "angle {angle}"
    );
}

#[test]
fn rotary_component_errors_act_about_and_along_the_fixed_axis() {
    // trunnion5: the C axis is the workpiece z axis through the workpiece origin, and the C
    // slot frame is the cradle frame, turned from the workpiece frame by Rz(-c).
    let trunnion = machine("trunnion5");
    let (a, c) = (35.0, 110.0);
    let state = at(&[
        (Axis::X, 400.0),
        (Axis::Y, 100.0),
        (Axis::Z, 200.0),
        (Axis::A, a),
        (Axis::C, c),
    ]);
    let c_rad = c * RAD_PER_DEG;
    let tip = trunnion.workpiece_from_tool(&state.position).translation;
    let epsilon = 40.0 * RAD_PER_URAD;
    let e = 6.0 * M_PER_UM;

    // ECC: C reached c + ε, so the tip turns by ε about the workpiece z axis …
    let errors = single(&trunnion, "ECC", ErrorFunction::Constant(epsilon));
    let d = deviation(&trunnion, &errors, &state).translation;
    assert_close(d, apply(rz(epsilon), tip) - tip, EXACT_M, "ECC");
    // … which is the nominal pose at c + ε.
    let mut turned = state.position;
    turned[Axis::C] += epsilon;
    assert_close(
        d,
        trunnion.workpiece_from_tool(&turned).translation - tip,
        EXACT_M,
        "ECC = C + ε",
    );

    // EXC: a radial error motion along the fixed X of C appears in workpiece coordinates as
    // Rz(c)·(e, 0, 0), whatever A.
    let errors = single(&trunnion, "EXC", ErrorFunction::Constant(e));
    let d = deviation(&trunnion, &errors, &state).translation;
    assert_close(
        d,
        Vector::new(e * c_rad.cos(), e * c_rad.sin(), 0.0),
        EXACT_M,
        "EXC",
    );

    // EAC: a tilt error motion about the fixed X of C, through the table centre.
    let errors = single(&trunnion, "EAC", ErrorFunction::Constant(epsilon));
    let d = deviation(&trunnion, &errors, &state).translation;
    let in_slot = apply(rz(-c_rad), tip);
    assert_close(
        d,
        apply(rz(c_rad), apply(rx(epsilon), in_slot) - in_slot),
        EXACT_M,
        "EAC",
    );

    // EBB on headtable5's swivel head: B reached b + ε, so the tip swings about the B pivot.
    let head = machine("headtable5");
    let state = at(&[
        (Axis::X, 300.0),
        (Axis::Z, 100.0),
        (Axis::B, -40.0),
        (Axis::C, 60.0),
    ]);
    let errors = single(&head, "EBB", ErrorFunction::Constant(epsilon));
    let mut turned = state.position;
    turned[Axis::B] += epsilon;
    let expected = head.workpiece_from_tool(&turned).translation
        - head.workpiece_from_tool(&state.position).translation;
    assert_close(
        deviation(&head, &errors, &state).translation,
        expected,
        EXACT_M,
        "EBB = B + ε",
    );
}

#[test]
fn rotary_location_errors_vanish_at_zero_and_grow_as_the_axis_turns() {
    // Turning by R about a line displaced by δ moves a point by (I - R)·δ relative to turning
    // about the nominal line. On trunnion5 (workpiece frame = C table frame):
    //   EX0C = δ:   deviation = (I - Rz(c))·(δ, 0, 0)        (2δ at c = 180°)
    //   EY0A = δ:   deviation = Rz(c)·(I - Rx(a))·(0, δ, 0)
    let trunnion = machine("trunnion5");
    let delta = 9.0 * M_PER_UM;
    for (a, c) in [(0.0, 0.0), (0.0, 180.0), (-60.0, 75.0), (90.0, 300.0)] {
        let state = at(&[
            (Axis::X, 250.0),
            (Axis::Y, 300.0),
            (Axis::Z, 150.0),
            (Axis::A, a),
            (Axis::C, c),
        ]);
        let (a, c) = (a * RAD_PER_DEG, c * RAD_PER_DEG);
        let ex0c = single(&trunnion, "EX0C", ErrorFunction::Constant(delta));
        let dx = Vector::new(delta, 0.0, 0.0);
        assert_close(
            deviation(&trunnion, &ex0c, &state).translation,
            dx - apply(rz(c), dx),
            EXACT_M,
            "EX0C",
        );
        let ey0a = single(&trunnion, "EY0A", ErrorFunction::Constant(delta));
        let dy = Vector::new(0.0, delta, 0.0);
        let expected = apply(rz(c), dy - apply(rx(a), dy));
        assert_close(
            deviation(&trunnion, &ey0a, &state).translation,
            expected,
            EXACT_M,
            "EY0A",
        );
    }
    // EB0C = ε: the C axis line is tilted about Y (through the table centre, in the cradle
    // frame), so the table turns by L·Rz(-c)·L⁻¹ with L = Ry(ε): the tool, at r in the cradle
    // frame, is seen at L·Rz(c)·L⁻¹·r instead of Rz(c)·r.
    let epsilon = 50.0 * RAD_PER_URAD;
    let state = at(&[
        (Axis::X, 250.0),
        (Axis::Y, 300.0),
        (Axis::Z, 150.0),
        (Axis::A, 20.0),
        (Axis::C, 130.0),
    ]);
    let c = 130.0 * RAD_PER_DEG;
    let tip = trunnion.workpiece_from_tool(&state.position).translation;
    let r = apply(rz(-c), tip);
    let expected = apply(mul(mul(ry(epsilon), rz(c)), ry(-epsilon)), r) - tip;
    let eb0c = single(&trunnion, "EB0C", ErrorFunction::Constant(epsilon));
    assert_close(
        deviation(&trunnion, &eb0c, &state).translation,
        expected,
        EXACT_M,
        "EB0C",
    );

    // On the tool side the same definition: EX0B = δ on headtable5 moves the B pivot line, so
    // the tip turned by Ry(b) about it moves by (I - Ry(b))·(δ, 0, 0), seen through Rz(c).
    let head = machine("headtable5");
    let state = at(&[
        (Axis::X, 300.0),
        (Axis::Z, 100.0),
        (Axis::B, -40.0),
        (Axis::C, 60.0),
    ]);
    let (b, c) = (-40.0 * RAD_PER_DEG, 60.0 * RAD_PER_DEG);
    let ex0b = single(&head, "EX0B", ErrorFunction::Constant(delta));
    let dx = Vector::new(delta, 0.0, 0.0);
    let expected = apply(rz(c), dx - apply(ry(b), dx));
    assert_close(
        deviation(&head, &ex0b, &state).translation,
        expected,
        EXACT_M,
        "EX0B",
    );
}

#[test]
fn tool_errors_act_along_the_tool_frame() {
    // headtable5 at (b, c): the tool frame seen from the workpiece is Rz(c)·Ry(b) (spindle at
    // zero), so a tool length error e moves the tip by e along the tool axis and an offset e
    // along the tool frame's x.
    let head = machine("headtable5");
    let (b, c) = (25.0, -70.0);
    let state = at(&[
        (Axis::X, 300.0),
        (Axis::Y, 200.0),
        (Axis::B, b),
        (Axis::C, c),
    ]);
    let frame = mul(rz(c * RAD_PER_DEG), ry(b * RAD_PER_DEG));
    let e = 7.0 * M_PER_UM;
    for (parameter, axis) in [("EZT", Vector::Z), ("EXT", Vector::X), ("EYT", Vector::Y)] {
        let errors = single(&head, parameter, ErrorFunction::Constant(e));
        assert_close(
            deviation(&head, &errors, &state).translation,
            apply(frame, axis) * e,
            EXACT_M,
            parameter,
        );
    }
}

/// A model with every family and function kind on `machine`, scaled by `scale`.
fn rich_model(machine: &Machine, scale: Real) -> ErrorModel {
    let um = scale * M_PER_UM;
    let urad = scale * RAD_PER_URAD;
    let mut parameters = vec![
        ErrorParameter {
            name: name("EXX"),
            function: ErrorFunction::Sum(vec![
                ErrorFunction::Polynomial(vec![1.0 * um, 15.0 * um, -20.0 * um]),
                ErrorFunction::Reversal(3.0 * um),
                ErrorFunction::Harmonic {
                    period: 0.01,
                    amplitude: 0.5 * um,
                    phase: 0.3,
                },
            ]),
        },
        ErrorParameter {
            name: name("EZX"),
            function: ErrorFunction::Table(
                Table::new(
                    vec![0.0, 0.2, 0.4, 0.8],
                    vec![0.0, 2.0 * um, 1.0 * um, -um],
                    Interpolation::Cubic,
                )
                .unwrap(),
            ),
        },
        ErrorParameter {
            name: name("EYY"),
            function: ErrorFunction::Table(
                Table::new(
                    vec![0.0, 0.3, 0.6],
                    vec![1.0 * um, -2.0 * um, 0.5 * um],
                    Interpolation::Linear,
                )
                .unwrap(),
            ),
        },
        ErrorParameter {
            name: name("ECX"),
            function: ErrorFunction::Polynomial(vec![5.0 * urad, -12.0 * urad]),
        },
        ErrorParameter {
            name: name("EAY"),
            function: ErrorFunction::Constant(8.0 * urad),
        },
        ErrorParameter {
            name: name("EBZ"),
            function: ErrorFunction::Polynomial(vec![-4.0 * urad, 20.0 * urad]),
        },
        ErrorParameter {
            name: name("EC0Y"),
            function: ErrorFunction::Constant(20.0 * urad),
        },
        ErrorParameter {
            name: name("EB0Z"),
            function: ErrorFunction::Constant(-12.0 * urad),
        },
        ErrorParameter {
            name: name("EA0Z"),
            function: ErrorFunction::Constant(7.0 * urad),
        },
        ErrorParameter {
            name: name("EZT"),
            function: ErrorFunction::Constant(-5.0 * um),
        },
        ErrorParameter {
            name: name("EXT"),
            function: ErrorFunction::Constant(2.0 * um),
        },
    ];
    for info in machine.rotary_axes() {
        let a = info.axis;
        let across: Vec<char> = ['X', 'Y', 'Z']
            .into_iter()
            .filter(|m| Axis::from_letter(*m).unwrap().coordinate() != a.coordinate())
            .collect();
        let tilts: Vec<char> = ['A', 'B', 'C']
            .into_iter()
            .filter(|m| Axis::from_letter(*m).unwrap().coordinate() != a.coordinate())
            .collect();
        let own = ['A', 'B', 'C'][a.coordinate()];
        parameters.push(ErrorParameter {
            name: name(&format!("E{}0{a}", across[0])),
            function: ErrorFunction::Constant(9.0 * um),
        });
        parameters.push(ErrorParameter {
            name: name(&format!("E{}0{a}", across[1])),
            function: ErrorFunction::Constant(-6.0 * um),
        });
        parameters.push(ErrorParameter {
            name: name(&format!("E{}0{a}", tilts[0])),
            function: ErrorFunction::Constant(15.0 * urad),
        });
        parameters.push(ErrorParameter {
            name: name(&format!("E{}0{a}", tilts[1])),
            function: ErrorFunction::Constant(-10.0 * urad),
        });
        parameters.push(ErrorParameter {
            name: name(&format!("E{own}0{a}")),
            function: ErrorFunction::Constant(25.0 * urad),
        });
        parameters.push(ErrorParameter {
            name: name(&format!("E{own}{a}")),
            function: ErrorFunction::Harmonic {
                period: 2.0 * std::f64::consts::PI,
                amplitude: 6.0 * urad,
                phase: 0.5,
            },
        });
        parameters.push(ErrorParameter {
            name: name(&format!("E{}{a}", across[0])),
            function: ErrorFunction::Constant(3.0 * um),
        });
    }
    ErrorModel::new(machine, parameters).unwrap()
}

fn states(machine: &Machine, test: &str) -> Vec<MachineState> {
    let mut rng = rng(test);
    (0..20)
        .map(|i| {
            let mut state = MachineState::at(random_position(machine, &mut rng));
            if i % 2 == 1 {
                state.direction = [Direction::Negative; 7];
            }
            state
        })
        .collect()
}

fn linearised(
    errors: &ErrorModel,
    machine: &Machine,
    workspace: &mut Workspace,
    state: &MachineState,
) -> [Real; 5] {
    let mut columns = vec![[0.0; 5]; errors.coefficient_count()];
    errors.jacobian(machine, workspace, state, &mut columns);
    let coefficients = errors.coefficients();
    let mut out = [0.0; 5];
    for (column, c) in columns.iter().zip(&coefficients) {
        for row in 0..5 {
            out[row] += column[row] * c;
        }
    }
    out
}

fn norm(v: [Real; 5]) -> Real {
    v.iter().map(|x| x * x).sum::<Real>().sqrt()
}

#[test]
fn exact_chain_and_linearised_model_agree_to_second_order() {
    // The residual exact - J·θ is O(θ²): scaling every error by 2 multiplies it by 4 (within
    // 5 %, the third-order share at these sizes).
    for machine_name in MACHINES {
        let machine = machine(machine_name);
        let mut workspace = Workspace::new(&machine);
        for state in states(&machine, &format!("{machine_name} second order")) {
            let residual = |scale: Real, workspace: &mut Workspace| {
                let errors = rich_model(&machine, scale);
                let exact = errors.deviation(&machine, workspace, &state).to_array();
                let linear = linearised(&errors, &machine, workspace, &state);
                (
                    norm(std::array::from_fn(|i| exact[i] - linear[i])),
                    norm(linear),
                )
            };
            let (r1, l1) = residual(10.0, &mut workspace);
            let (r2, _) = residual(20.0, &mut workspace);
            let ratio = r2 / r1;
            assert!(
                (ratio - 4.0).abs() < 0.2,
                "{machine_name}: residual ratio {ratio} ({r1:e} → {r2:e})"
            );
            // And the residual is small beside the deviation: second order in ~1e-4 rad.
            assert!(
                r1 < 1e-3 * l1,
                "{machine_name}: residual {r1:e} vs deviation {l1:e}"
            );
        }
    }
}

#[test]
fn jacobian_matches_central_differences_of_the_exact_chain() {
    // Columns at zero error against (f(+h) - f(-h)) / 2h of the exact chain, h = 1e-7 (SI).
    // The second-order term cancels in a central difference; what remains is round-off,
    // ~1e-16 m / 2e-7 ≈ 1e-9, so 1e-7 is a strict bound on entries of order 1.
    let h = 1e-7;
    for machine_name in MACHINES {
        let machine = machine(machine_name);
        let mut workspace = Workspace::new(&machine);
        let mut errors = rich_model(&machine, 1.0);
        let n = errors.coefficient_count();
        let labels = errors.coefficient_labels();
        for state in states(&machine, &format!("{machine_name} jacobian"))
            .iter()
            .take(6)
        {
            errors.set_coefficients(&vec![0.0; n]);
            let mut columns = vec![[0.0; 5]; n];
            errors.jacobian(&machine, &mut workspace, state, &mut columns);
            for k in 0..n {
                let mut shifted = vec![0.0; n];
                shifted[k] = h;
                errors.set_coefficients(&shifted);
                let plus = errors.deviation(&machine, &mut workspace, state).to_array();
                shifted[k] = -h;
                errors.set_coefficients(&shifted);
                let minus = errors.deviation(&machine, &mut workspace, state).to_array();
                for row in 0..5 {
                    let fd = (plus[row] - minus[row]) / (2.0 * h);
                    let error = (columns[k][row] - fd).abs();
                    assert!(
                        error < 1e-7,
                        "{machine_name} {} row {row}: J = {}, FD = {fd}",
                        labels[k],
                        columns[k][row]
                    );
                }
            }
        }
    }
}

#[test]
fn parameter_names_round_trip_and_invalid_ones_are_refused() {
    for text in [
        "EXX", "EYX", "ECC", "EX0C", "EC0C", "EC0Y", "EB0Z", "EA0Z", "EZT", "EAS",
    ] {
        assert_eq!(name(text).to_string(), text);
    }
    for text in ["EXQ", "EX0X", "EZ0C", "EA0Y", "EAT", "EX0S", "XX", "EXXX"] {
        assert!(
            text.parse::<ParameterName>().is_err(),
            "{text} should be refused"
        );
    }
}

#[test]
fn stacked_jacobian_shows_what_cannot_be_told_apart() {
    // On a 3-axis machine with the spindle at zero, a constant positioning error of X and a
    // tool offset along the tool frame's x both move the tip by the same vector everywhere:
    // their columns are equal, the design matrix loses rank, and its null vector is
    // (1, -1)/√2 on those two coefficients. A slope of EXX and the yaw ECX (Abbe arm varying
    // with Y) are told apart.
    let vmc3 = machine("vmc3");
    let grid: Vec<MachineState> = (0..5)
        .flat_map(|i| {
            (0..4).map(move |j| {
                at(&[
                    (Axis::X, 190.0 * i as Real),
                    (Axis::Y, 100.0 * j as Real),
                    (Axis::Z, 200.0),
                ])
            })
        })
        .collect();
    let mut workspace = Workspace::new(&vmc3);
    let ambiguous = ErrorModel::new(
        &vmc3,
        vec![
            ErrorParameter {
                name: name("EXX"),
                function: ErrorFunction::Constant(0.0),
            },
            ErrorParameter {
                name: name("EXT"),
                function: ErrorFunction::Constant(0.0),
            },
        ],
    )
    .unwrap();
    let matrix = ambiguous.stacked_jacobian(&vmc3, &mut workspace, &grid);
    assert_eq!(matrix.shape(), (5 * grid.len(), 2));
    let svd = mtwin_kernels::linalg::svd(matrix, false, true);
    let (largest, smallest) = (svd.singular_values.max(), svd.singular_values.min());
    assert!(
        smallest < 1e-12 * largest,
        "singular values {:?}",
        svd.singular_values
    );
    let v_t = svd.v_t.unwrap();
    let null = v_t.row(svd.singular_values.imin());
    assert!(
        (null[0] + null[1]).abs() < 1e-12 && (null[0].abs() - 0.5f64.sqrt()).abs() < 1e-12,
        "{null}"
    );

    let separable = ErrorModel::new(
        &vmc3,
        vec![
            ErrorParameter {
                name: name("EXX"),
                function: ErrorFunction::Polynomial(vec![0.0, 0.0]),
            },
            ErrorParameter {
                name: name("ECX"),
                function: ErrorFunction::Constant(0.0),
            },
        ],
    )
    .unwrap();
    let svd = mtwin_kernels::linalg::svd(
        separable.stacked_jacobian(&vmc3, &mut workspace, &grid),
        false,
        false,
    );
    let ratio = svd.singular_values.min() / svd.singular_values.max();
    assert!(ratio > 1e-2, "condition {ratio}: {:?}", svd.singular_values);
}

#[test]
fn errors_of_a_continuous_axis_repeat_every_turn() {
    // C on trunnion5 turns without end: its errors at -90° and at 270° are the same.
    let trunnion = machine("trunnion5");
    let table = Table::new(
        vec![
            0.0,
            std::f64::consts::FRAC_PI_2,
            std::f64::consts::PI,
            1.5 * std::f64::consts::PI,
            std::f64::consts::TAU,
        ],
        vec![0.0, 3e-6, 0.0, -5e-6, 0.0],
        Interpolation::Linear,
    )
    .unwrap();
    let errors = single(&trunnion, "ECC", ErrorFunction::Table(table));
    let a = deviation(
        &trunnion,
        &errors,
        &at(&[(Axis::X, 300.0), (Axis::C, -90.0)]),
    );
    let b = deviation(
        &trunnion,
        &errors,
        &at(&[(Axis::X, 300.0), (Axis::C, 270.0)]),
    );
    // The two poses are the same (C differs by a full turn); so must be the deviations, which
    // is the tip turned by ECC = -5 µrad: non-zero.
    assert_close(a.translation, b.translation, EXACT_M, "-90° vs 270°");
    assert!(a.translation.length() > 1e-7, "{:?}", a.translation);
    // What cannot repeat every turn is refused.
    let refuse = |function: ErrorFunction| {
        ErrorModel::new(
            &trunnion,
            vec![ErrorParameter {
                name: name("ECC"),
                function,
            }],
        )
        .unwrap_err()
    };
    assert!(matches!(
        refuse(ErrorFunction::Polynomial(vec![0.0, 1e-6])),
        mtwin::errors::ErrorModelError::NotPeriodic { .. }
    ));
    let period = 100.0 * RAD_PER_DEG; // 3.6 periods per turn
    assert!(matches!(
        refuse(ErrorFunction::Harmonic {
            period,
            amplitude: 1e-6,
            phase: 0.0
        }),
        mtwin::errors::ErrorModelError::NotPeriodic { .. }
    ));
}

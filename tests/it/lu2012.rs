//! The summed 21-component model of Lu (2012, Eqs. 4.11–4.18) against a hand computation, and
//! what it gets wrong beside the chain: the lever arm of the head's angular errors (tool length
//! and which branch the axis is on), the Abbe offset between a carriage and the tool, and the
//! extra terms of squareness applied as a full rotation.

use crate::common::*;
use mtwin::errors::{ErrorFunction, ErrorModel, ErrorParameter, lu2012_deviation};
use mtwin::machine::{Axis, Machine, MachineState, Workspace};
use mtwin::math::{M_PER_UM, RAD_PER_URAD, Real, Vector};
use mtwin::twin::{EvaluationModel, Twin};

fn model(machine: &Machine, parameters: &[(&str, ErrorFunction)]) -> ErrorModel {
    let parameters = parameters
        .iter()
        .map(|(n, f)| ErrorParameter {
            name: n.parse().unwrap(),
            function: f.clone(),
        })
        .collect();
    ErrorModel::new(machine, parameters).unwrap()
}

fn at_m(x: Real, y: Real, z: Real) -> MachineState {
    let mut state = MachineState::default();
    state.position[Axis::X] = x;
    state.position[Axis::Y] = y;
    state.position[Axis::Z] = z;
    state
}

fn both(machine: &Machine, errors: &ErrorModel, state: &MachineState) -> (Vector, Vector) {
    let chain = errors
        .deviation(machine, &mut Workspace::new(machine), state)
        .translation;
    (chain, lu2012_deviation(errors, machine, state).unwrap())
}

/// First-order comparisons: the chain's neglected terms are ε²·|arm| < 1e-10 m here.
const FIRST_ORDER_M: Real = 1e-10;

#[test]
fn lu_model_matches_a_hand_computation() {
    // ECX = 10 µrad, EBZ = 5 µrad, EC0Y = 20 µrad, EXX = 3 µm at (X, Y, Z) = (100, 200, 50) mm:
    //   V_x = -Y(ΣZ + εz(r)) + Z(ΣY + εy(r)) + ΔX = -0.2·30e-6 + 0.05·5e-6 + 3e-6 = -2.75 µm
    //   V_y = -Z(ΣX + εx(r)) + X(ΣZ + εz(r)) + ΔY = 0.1·30e-6                  =  3.00 µm
    //   V_z = -X(ΣY + εy(r)) + Y(ΣX + εx(r)) + ΔZ = -0.1·5e-6                  = -0.50 µm
    let vmc3 = machine("vmc3");
    let errors = model(
        &vmc3,
        &[
            ("ECX", ErrorFunction::Constant(10.0 * RAD_PER_URAD)),
            ("EBZ", ErrorFunction::Constant(5.0 * RAD_PER_URAD)),
            ("EC0Y", ErrorFunction::Constant(20.0 * RAD_PER_URAD)),
            ("EXX", ErrorFunction::Constant(3.0 * M_PER_UM)),
        ],
    );
    let v = lu2012_deviation(&errors, &vmc3, &at_m(0.1, 0.2, 0.05)).unwrap();
    assert_close(
        v,
        Vector::new(-2.75e-6, 3.0e-6, -0.5e-6),
        1e-15,
        "Lu Eq. 4.18",
    );
}

#[test]
fn lu_model_puts_the_head_errors_on_the_wrong_lever_arm() {
    // EAZ = 10 µrad (the head pitching about X). Chain: the head turns about its carriage
    // point, 0.35 m behind and 0.30 m above the tip (0.15 m spindle + 0.15 m tool), so
    // (dy, dz) = ε·(0.30, 0.35) = (3.0, 3.5) µm wherever the table is. Lu: every rotation acts
    // on the commanded point, (dy, dz) = ε·(-Z, Y) = (-2.0, 3.0) µm at Y = 0.3, Z = 0.2 m.
    let vmc3 = machine("vmc3");
    let epsilon = 10.0 * RAD_PER_URAD;
    let errors = model(&vmc3, &[("EAZ", ErrorFunction::Constant(epsilon))]);
    let state = at_m(0.5, 0.3, 0.2);
    let (chain, lu) = both(&vmc3, &errors, &state);
    assert_close(
        chain,
        Vector::new(0.0, 3.0e-6, 3.5e-6),
        FIRST_ORDER_M,
        "chain",
    );
    assert_close(lu, Vector::new(0.0, -2.0e-6, 3.0e-6), 1e-15, "Lu");
    // The disagreement, 5.0 µm in Y and 0.5 µm in Z, grows with the table's Y and the head's Z
    // although the head's rotation has nothing to do with where the table is.
    assert_close(
        chain - lu,
        Vector::new(0.0, 5.0e-6, 0.5e-6),
        FIRST_ORDER_M,
        "disagreement",
    );

    // A 100 mm longer tool lengthens the chain's arm by 0.10 m: +1.0 µm in Y. Lu cannot see it.
    let text = std::fs::read_to_string(format!("{}/models/vmc3.urdf", env!("CARGO_MANIFEST_DIR")))
        .unwrap();
    let long_tool = text.replace(
        "<child link=\"tool\"/>\n    <origin xyz=\"0 0 -0.15\"",
        "<child link=\"tool\"/>\n    <origin xyz=\"0 0 -0.25\"",
    );
    assert_ne!(long_tool, text, "the tool holder origin was found");
    let long = Machine::from_urdf_str(&long_tool, "vmc3-long-tool.urdf").unwrap();
    let errors_long = model(&long, &[("EAZ", ErrorFunction::Constant(epsilon))]);
    let (chain_long, lu_long) = both(&long, &errors_long, &state);
    assert_close(
        chain_long - chain,
        Vector::new(0.0, 1.0e-6, 0.0),
        FIRST_ORDER_M,
        "tool length",
    );
    assert_eq!(lu_long, lu);
}

#[test]
fn lu_model_misses_the_abbe_offset_of_a_varying_angular_error() {
    // ECX = k·x (yaw of the table growing along X). Chain: arm from the X carriage to the tip is
    // (-0.38 + x, -0.205 + y, 0.20 + z), so dy = k·x·(-0.38 + x). Lu: dy = k·x·x. They differ by
    // -0.38·k·x, which no datum shift removes: 0.38 m is the offset, at X = 0, between the
    // carriage reference point and the tool.
    let vmc3 = machine("vmc3");
    let k = 20.0 * RAD_PER_URAD; // per metre of X
    let errors = model(&vmc3, &[("ECX", ErrorFunction::Polynomial(vec![0.0, k]))]);
    for x in [0.1, 0.4, 0.7] {
        let (chain, lu) = both(&vmc3, &errors, &at_m(x, 0.2, 0.1));
        assert!(
            ((chain.y - lu.y) - (-0.38 * k * x)).abs() < FIRST_ORDER_M,
            "x = {x}: {}",
            chain.y - lu.y
        );
    }
}

#[test]
fn lu_model_adds_squareness_terms_a_chain_does_not_have() {
    // EC0Y = 20 µrad: both give V_x = -Y·s, but Lu's full rotation also adds V_y = X·s
    // (10 µm at X = 0.5 m), which moving Y along a tilted line does not produce.
    let vmc3 = machine("vmc3");
    let s = 20.0 * RAD_PER_URAD;
    let errors = model(&vmc3, &[("EC0Y", ErrorFunction::Constant(s))]);
    let (chain, lu) = both(&vmc3, &errors, &at_m(0.5, 0.3, 0.2));
    assert_close(
        chain,
        Vector::new(-0.3 * s, 0.0, 0.0),
        FIRST_ORDER_M,
        "chain",
    );
    assert_close(lu, Vector::new(-0.3 * s, 0.5 * s, 0.0), 1e-15, "Lu");
}

#[test]
fn lu_model_is_refused_on_five_axis_machines() {
    let trunnion = machine("trunnion5");
    let twin = Twin {
        errors: ErrorModel::empty(&trunnion),
        machine: trunnion,
    };
    let state = MachineState::default();
    assert!(
        twin.deviation(
            &mut Workspace::new(&twin.machine),
            &state,
            EvaluationModel::Lu2012
        )
        .is_err()
    );
}

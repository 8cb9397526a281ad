//! ISO 230-4 circular test figures and ball-bar diagnostics against closed-form traces.
//!
//! The traces come from a small machine simulated here, independently of the fit's basis
//! columns: every error moves the axes (or the tool) as its physical definition says, and the
//! reading is the exact distance |tool − centre ball| − R, at the programmed angle. An axis
//! follows its command delayed by its servo lag, so it reverses that much after its programmed
//! reversal; its direction comes from its delayed command's velocity, its reversal times from
//! that velocity's zero crossings (interpolated between samples). Circles of R = 150 mm at 1000 mm/min sampled at 250 Hz, ccw then cw, each with a
//! 45° lead-in and lead-out arc as a ball-bar test runs them.

use mtwin::kinds::ballbar::iso230_4::{
    BallbarError, BallbarEvaluation, CircularTest, Term, diagnostic_column, evaluate,
};
use mtwin::kinds::ballbar::{BallbarReading, BallbarTable, Sense};
use mtwin::machine::Plane;
use mtwin::math::{seeded_rng, standard_normal};
use std::f64::consts::{PI, TAU};

const R: f64 = 0.150;
const V: f64 = 1.0 / 60.0; // 1000 mm/min in m/s
const RATE: f64 = 250.0;
const UM: f64 = 1e-6;

/// The machine's errors in the plane's (p, q) frame, SI.
#[derive(Clone, Copy, Debug, Default)]
struct Machine {
    /// Bar length error (m).
    bar: f64,
    /// Machine circle centre relative to the centre ball (m).
    centre: [f64; 2],
    /// + when the angle between +p and +q travel is less than 90° (rad).
    squareness: f64,
    /// Scale errors of p and q.
    scale: [f64; 2],
    /// Servo lags (s): the axis follows its command delayed by this.
    lag: [f64; 2],
    /// Lost motion (m): the axis lags its command by half of it against its travel.
    backlash: [f64; 2],
    /// Lateral play (m): the carriage shifts across by −sgn(velocity)·play/2.
    play: [f64; 2],
    /// Reversal spike: height (m) and decay (s).
    spike: [(f64, f64); 2],
    /// Straightness bow, peak-to-valley over the diameter (m).
    straightness: [f64; 2],
    /// Cyclic error: amplitude (m), period (m), phase (rad).
    cyclic: [(f64, f64, f64); 2],
}

/// One traverse: sense, first data angle (°), data arc (°), lead-in and lead-out arc (°).
#[derive(Clone, Copy)]
struct Run {
    sense: Sense,
    start_deg: f64,
    arc_deg: f64,
    lead_deg: f64,
}

fn full_circles() -> Vec<Run> {
    vec![
        Run {
            sense: Sense::Ccw,
            start_deg: 0.0,
            arc_deg: 360.0,
            lead_deg: 45.0,
        },
        Run {
            sense: Sense::Cw,
            start_deg: 360.0,
            arc_deg: 360.0,
            lead_deg: 45.0,
        },
    ]
}

/// Arcs from `start_deg` over `arc_deg`, ccw then back cw, no lead-in (a partial arc in a
/// vertical plane starts and stops at its ends).
fn arcs(start_deg: f64, arc_deg: f64) -> Vec<Run> {
    vec![
        Run {
            sense: Sense::Ccw,
            start_deg,
            arc_deg,
            lead_deg: 0.0,
        },
        Run {
            sense: Sense::Cw,
            start_deg: start_deg + arc_deg,
            arc_deg,
            lead_deg: 0.0,
        },
    ]
}

/// Simulates the ball-bar readings of `machine` over `runs`, with `noise` (m, standard
/// deviation) drawn from `seed`.
fn simulate(machine: &Machine, runs: &[Run], noise: f64, seed: u64) -> BallbarTable {
    let mut rng = seeded_rng(seed, "ballbar noise");
    let omega = V / R;
    let dt = 1.0 / RATE;
    let mut readings = Vec::new();
    let mut clock = 0.0;
    for run in runs {
        let sigma = run.sense.sign();
        let arc = run.arc_deg.to_radians();
        let lead = run.lead_deg.to_radians() / omega;
        let t_arc = arc / omega;
        let theta = |t: f64| run.start_deg.to_radians() + sigma * omega * t;
        let velocity = |t: f64| {
            let th = theta(t);
            [-R * th.sin() * sigma * omega, R * th.cos() * sigma * omega]
        };
        let mut last: [Option<(f64, f64)>; 2] = [None; 2]; // last non-zero velocity (t, v)
        let mut reversal: [Option<f64>; 2] = [None; 2];
        let first = -(lead / dt).ceil() as i64;
        let mut k = first;
        loop {
            // Half a sample off the run's start, so no sample falls exactly on a reversal.
            let t = (k as f64 + 0.5) * dt;
            k += 1;
            if t > t_arc + lead {
                break;
            }
            let th = theta(t);
            let command = [R * th.cos(), R * th.sin()];
            let vel = [
                velocity(t - machine.lag[0])[0],
                velocity(t - machine.lag[1])[1],
            ];
            let mut direction = [0.0; 2];
            for axis in 0..2 {
                if vel[axis] != 0.0 {
                    if let Some((t0, v0)) = last[axis]
                        && v0.signum() != vel[axis].signum()
                    {
                        reversal[axis] = Some(t0 + (t - t0) * v0 / (v0 - vel[axis]));
                    }
                    last[axis] = Some((t, vel[axis]));
                    direction[axis] = vel[axis].signum();
                } else {
                    direction[axis] = velocity(t - machine.lag[axis] + 1e-6)[axis].signum();
                }
            }
            let mut axis_position = [0.0; 2];
            for axis in 0..2 {
                let delayed = theta(t - machine.lag[axis]);
                let nominal = if axis == 0 {
                    delayed.cos()
                } else {
                    delayed.sin()
                };
                let (amplitude, period, phase) = machine.cyclic[axis];
                let cyclic = if period > 0.0 {
                    amplitude * (TAU * command[axis] / period + phase).sin()
                } else {
                    0.0
                };
                let (height, decay) = machine.spike[axis];
                let stick = match reversal[axis] {
                    Some(tr) if height != 0.0 => height * (-(t - tr) / decay).exp(),
                    _ => 0.0,
                };
                let other = 1 - axis;
                axis_position[axis] = (1.0 + machine.scale[axis]) * R * nominal + cyclic
                    - direction[axis] * (machine.backlash[axis] / 2.0 + stick)
                    // the other carriage's lateral play and straightness act along this axis
                    - direction[other] * machine.play[other] / 2.0
                    + machine.straightness[other] * (1.0 - (command[other] / R).powi(2));
            }
            let tool = [
                axis_position[0] + machine.squareness * axis_position[1] + machine.centre[0],
                axis_position[1] + machine.centre[1],
            ];
            let inside = if run.arc_deg >= 360.0 {
                (0.0..t_arc).contains(&t)
            } else {
                (0.0..=t_arc).contains(&t)
            };
            if inside {
                let mut angle = th.rem_euclid(TAU);
                if angle >= TAU {
                    angle = 0.0;
                }
                readings.push(BallbarReading {
                    sense: run.sense,
                    angle,
                    deviation: tool[0].hypot(tool[1]) - R
                        + machine.bar
                        + noise * standard_normal(&mut rng),
                    time: Some(clock + t + lead),
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

fn test_in(plane: Plane) -> CircularTest {
    CircularTest {
        plane,
        radius: R,
        feed: V,
    }
}

fn xy() -> CircularTest {
    test_in(Plane::XY)
}

/// The deviation of the reading of `sense` nearest `deg`.
fn reading_at(table: &BallbarTable, sense: Sense, deg: f64) -> f64 {
    table
        .readings
        .iter()
        .filter(|r| r.sense == sense)
        .min_by(|a, b| {
            let d = |r: &BallbarReading| {
                let x = (r.angle - deg.to_radians()).rem_euclid(TAU);
                x.min(TAU - x)
            };
            d(a).total_cmp(&d(b))
        })
        .unwrap()
        .deviation
}

/// The peak radial effect of one SI unit of each term (m per unit): converts a parameter to
/// µm of trace for tolerances and cross-talk.
fn gain(term: Term) -> f64 {
    match term {
        Term::Squareness | Term::ScaleMismatch => R / 2.0,
        Term::ServoMismatch => V / 2.0,
        Term::BacklashP | Term::BacklashQ | Term::LateralPlayP | Term::LateralPlayQ => 0.5,
        _ => 1.0,
    }
}

/// One injected error per diagnostic (SI values as reported by the fit).
fn injections() -> Vec<(Term, f64, Machine)> {
    let m = Machine::default;
    vec![
        (
            Term::Radius,
            2.0 * UM,
            Machine {
                bar: 2.0 * UM,
                ..m()
            },
        ),
        (
            Term::CentreP,
            15.0 * UM,
            Machine {
                centre: [15.0 * UM, 0.0],
                ..m()
            },
        ),
        (
            Term::CentreQ,
            -10.0 * UM,
            Machine {
                centre: [0.0, -10.0 * UM],
                ..m()
            },
        ),
        (
            Term::Squareness,
            20e-6,
            Machine {
                squareness: 20e-6,
                ..m()
            },
        ),
        (
            Term::ScaleMismatch,
            10e-6,
            Machine {
                scale: [5e-6, -5e-6],
                ..m()
            },
        ),
        (
            Term::ServoMismatch,
            0.5e-3,
            Machine {
                lag: [30.5e-3, 30e-3],
                ..m()
            },
        ),
        (
            Term::BacklashP,
            4.0 * UM,
            Machine {
                backlash: [4.0 * UM, 0.0],
                ..m()
            },
        ),
        (
            Term::BacklashQ,
            3.0 * UM,
            Machine {
                backlash: [0.0, 3.0 * UM],
                ..m()
            },
        ),
        (
            Term::LateralPlayP,
            3.0 * UM,
            Machine {
                play: [3.0 * UM, 0.0],
                ..m()
            },
        ),
        (
            Term::LateralPlayQ,
            2.0 * UM,
            Machine {
                play: [0.0, 2.0 * UM],
                ..m()
            },
        ),
        (
            Term::StraightnessP,
            2.0 * UM,
            Machine {
                straightness: [2.0 * UM, 0.0],
                ..m()
            },
        ),
        (
            Term::StraightnessQ,
            -1.5 * UM,
            Machine {
                straightness: [0.0, -1.5 * UM],
                ..m()
            },
        ),
        (
            Term::ReversalSpikeP,
            SPIKE_P.0,
            Machine {
                spike: [SPIKE_P, (0.0, 1.0)],
                ..m()
            },
        ),
        (
            Term::ReversalSpikeQ,
            SPIKE_Q.0,
            Machine {
                spike: [(0.0, 1.0), SPIKE_Q],
                ..m()
            },
        ),
        (
            Term::CyclicP,
            1.0 * UM,
            Machine {
                cyclic: [(1.0 * UM, 0.010, 0.7), (0.0, 0.0, 0.0)],
                ..m()
            },
        ),
        (
            Term::CyclicQ,
            0.8 * UM,
            Machine {
                cyclic: [(0.0, 0.0, 0.0), (0.8 * UM, 0.016, -1.0)],
                ..m()
            },
        ),
    ]
}

/// Every error of [`injections`] at once.
fn everything() -> Machine {
    let mut all = Machine::default();
    for (_, _, m) in injections() {
        all.bar += m.bar;
        all.squareness += m.squareness;
        for a in 0..2 {
            all.centre[a] += m.centre[a];
            all.scale[a] += m.scale[a];
            all.lag[a] = all.lag[a].max(m.lag[a]);
            all.backlash[a] += m.backlash[a];
            all.play[a] += m.play[a];
            all.straightness[a] += m.straightness[a];
            if m.spike[a].0 != 0.0 {
                all.spike[a] = m.spike[a];
            }
            if m.cyclic[a].1 != 0.0 {
                all.cyclic[a] = m.cyclic[a];
            }
        }
    }
    all
}

fn value(evaluation: &BallbarEvaluation, term: Term) -> Option<f64> {
    let d = evaluation.diagnostics.as_ref().unwrap();
    d.get(term).map(|e| e.value)
}

/// Tolerance on a recovered parameter: 5 % of the truth or 0.2 µm of trace, whichever is
/// larger. A spike's height is read back to the instant the axis reversed, which a trace
/// sampled every Δt places only within a sample interval: its height is known to a factor
/// e^(±Δt/(2τ)), which adds h·Δt/(2τ) (5 % for τ = 20 ms at 250 Hz).
fn tolerance(term: Term, truth: f64) -> f64 {
    let sampling = match term {
        Term::ReversalSpikeP => truth.abs() / (2.0 * RATE * SPIKE_P.1),
        Term::ReversalSpikeQ => truth.abs() / (2.0 * RATE * SPIKE_Q.1),
        _ => 0.0,
    };
    (0.05 * truth.abs()).max(0.2 * UM / gain(term)) + sampling
}

/// The injected spikes: height (m) and decay (s).
const SPIKE_P: (f64, f64) = (5.0 * UM, 0.02);
const SPIKE_Q: (f64, f64) = (4.0 * UM, 0.04);

#[test]
fn columns_follow_the_stated_conventions_by_hand() {
    let test = xy();
    let shape = mtwin::kinds::ballbar::iso230_4::Shape::default();
    let at = |deg: f64, sense: f64| {
        mtwin::kinds::ballbar::iso230_4::BasisPoint::new(deg.to_radians(), sense, 0.0, [true; 2])
    };
    let column = |term: Term, deg: f64, sense: f64| {
        diagnostic_column(term, 0, &at(deg, sense), &test, &shape)
    };
    let close = |a: f64, b: f64| assert!((a - b).abs() < 1e-12, "{a} != {b}");
    let c = |deg: f64| deg.to_radians().cos();
    let s = |deg: f64| deg.to_radians().sin();
    // θ = 0 points along +p: a centre offset along p reads +1 there, along q +1 at 90°.
    close(column(Term::CentreP, 0.0, 1.0), 1.0);
    close(column(Term::CentreQ, 90.0, 1.0), 1.0);
    // Squareness: (R/2)·sin 2θ, +R/2 at 45°, −R/2 at 135°, both senses.
    close(column(Term::Squareness, 45.0, 1.0), R / 2.0);
    close(column(Term::Squareness, 135.0, -1.0), -R / 2.0);
    // Scale mismatch: (R/2)·cos 2θ.
    close(column(Term::ScaleMismatch, 0.0, 1.0), R / 2.0);
    close(column(Term::ScaleMismatch, 90.0, 1.0), -R / 2.0);
    // Servo mismatch: σ·(v/2)·sin 2θ: + ccw, − cw at 45°.
    close(column(Term::ServoMismatch, 45.0, 1.0), V / 2.0);
    close(column(Term::ServoMismatch, 45.0, -1.0), -V / 2.0);
    // Backlash of p: steps at 0° and 180°; ccw just after 0° p runs negative and reads
    // +cos θ/2, just before 360° it runs positive and reads −cos θ/2; cw the other way.
    close(column(Term::BacklashP, 1.0, 1.0), c(1.0) / 2.0);
    close(column(Term::BacklashP, 359.0, 1.0), -c(359.0) / 2.0);
    close(column(Term::BacklashP, 1.0, -1.0), -c(1.0) / 2.0);
    close(column(Term::BacklashP, 179.0, 1.0), c(179.0) / 2.0);
    close(column(Term::BacklashP, 181.0, 1.0), -c(181.0) / 2.0);
    // Backlash of q: steps at 90° and 270°; ccw below 90° q runs positive: −sin θ/2.
    close(column(Term::BacklashQ, 89.0, 1.0), -s(89.0) / 2.0);
    close(column(Term::BacklashQ, 91.0, 1.0), s(91.0) / 2.0);
    // Lateral play: +σ·|sin θ|/2 for p, −σ·|cos θ|/2 for q.
    close(column(Term::LateralPlayP, 270.0, 1.0), 0.5);
    close(column(Term::LateralPlayP, 90.0, -1.0), -0.5);
    close(column(Term::LateralPlayQ, 180.0, 1.0), -0.5);
    // Straightness: sin³θ and cos³θ.
    close(column(Term::StraightnessP, 90.0, 1.0), 1.0);
    close(column(Term::StraightnessP, 30.0, 1.0), 0.125);
    close(column(Term::StraightnessQ, 60.0, -1.0), 0.125);
    // Spike of p: 1° after the reversal at 0° ccw (and at 360° cw), decayed over R·1°/v.
    let decay = shape.decay[0];
    let dt = R * 1f64.to_radians() / V;
    close(
        column(Term::ReversalSpikeP, 1.0, 1.0),
        c(1.0) * (-dt / decay).exp(),
    );
    close(
        column(Term::ReversalSpikeP, 359.0, -1.0),
        c(1.0) * (-dt / decay).exp(),
    );
    // ... and nothing before it (359° ccw is 179° after the reversal at 180°).
    close(column(Term::ReversalSpikeP, 359.0, 1.0), 0.0);
    // Cyclic p at θ = 0: p = R, cos θ·sin(2πR/P).
    let period = shape.period[0];
    close(column(Term::CyclicP, 0.0, 1.0), (TAU * R / period).sin());
}

#[test]
fn simulated_errors_read_as_the_conventions_say_and_are_recovered_with_their_sign() {
    let near =
        |a: f64, b: f64, tol: f64| assert!((a - b).abs() < tol, "{} µm != {} µm", a / UM, b / UM);
    // Squareness: the q travel tilts toward +p, the tool at (R cos θ + s·R sin θ, R sin θ).
    let s = 20e-6;
    let machine = Machine {
        squareness: s,
        ..Machine::default()
    };
    let table = simulate(&machine, &full_circles(), 0.0, 0);
    near(
        reading_at(&table, Sense::Ccw, 45.0),
        R * s / 2.0,
        0.005 * UM,
    );
    near(
        reading_at(&table, Sense::Cw, 135.0),
        -R * s / 2.0,
        0.005 * UM,
    );
    let e = evaluate(&table, &xy()).unwrap();
    near(value(&e, Term::Squareness).unwrap(), s, 0.01e-6);
    // Servo mismatch: p lags 0.5 ms more than q: +v·Δτ/2 at 45° ccw, − cw.
    let machine = Machine {
        lag: [30.5e-3, 30e-3],
        ..Machine::default()
    };
    let table = simulate(&machine, &full_circles(), 0.0, 0);
    near(
        reading_at(&table, Sense::Ccw, 45.0),
        V * 0.5e-3 / 2.0,
        0.05 * UM,
    );
    near(
        reading_at(&table, Sense::Cw, 45.0),
        -V * 0.5e-3 / 2.0,
        0.05 * UM,
    );
    let e = evaluate(&table, &xy()).unwrap();
    near(value(&e, Term::ServoMismatch).unwrap(), 0.5e-3, 0.005e-3);
    // Backlash of p (4 µm): ccw steps from −2 µm to +2 µm at 0° and (through cos θ < 0)
    // from −2 µm to +2 µm at 180°; cw the other way.
    let machine = Machine {
        backlash: [4.0 * UM, 0.0],
        ..Machine::default()
    };
    let table = simulate(&machine, &full_circles(), 0.0, 0);
    near(reading_at(&table, Sense::Ccw, 359.9), -2.0 * UM, 0.01 * UM);
    near(reading_at(&table, Sense::Ccw, 0.1), 2.0 * UM, 0.01 * UM);
    near(reading_at(&table, Sense::Ccw, 179.9), -2.0 * UM, 0.01 * UM);
    near(reading_at(&table, Sense::Ccw, 180.1), 2.0 * UM, 0.01 * UM);
    near(reading_at(&table, Sense::Cw, 0.1), -2.0 * UM, 0.01 * UM);
    near(reading_at(&table, Sense::Cw, 359.9), 2.0 * UM, 0.01 * UM);
    let e = evaluate(&table, &xy()).unwrap();
    near(value(&e, Term::BacklashP).unwrap(), 4.0 * UM, 0.01 * UM);
    // Centre offset along +p: +15 µm at 0°, −15 µm at 180°, nothing at 90°.
    let machine = Machine {
        centre: [15.0 * UM, 0.0],
        ..Machine::default()
    };
    let table = simulate(&machine, &full_circles(), 0.0, 0);
    near(reading_at(&table, Sense::Ccw, 0.0), 15.0 * UM, 0.01 * UM);
    near(reading_at(&table, Sense::Ccw, 180.0), -15.0 * UM, 0.01 * UM);
    near(reading_at(&table, Sense::Ccw, 90.0), 0.0, 0.01 * UM);
    let e = evaluate(&table, &xy()).unwrap();
    near(e.centre_offset[0], 15.0 * UM, 0.001 * UM);
    near(value(&e, Term::CentreP).unwrap(), 15.0 * UM, 0.001 * UM);
    assert_eq!(e.to_json()["centre_offset_x_um"], 15.0);
}

#[test]
fn each_diagnostic_alone_is_recovered_with_small_cross_talk() {
    let terms = Term::DIAGNOSTICS;
    let short = |t: Term| {
        let name = t.name(Plane::XY);
        name.split('_')
            .map(|w| &w[..w.len().min(4)])
            .collect::<Vec<_>>()
            .join("_")
    };
    println!(
        "cross-talk (µm of trace: value × peak radial effect per unit), noise-free, XY full circles:"
    );
    print!("{:>16}", "injected \\ fit");
    for t in terms {
        print!("{:>12}", short(t));
    }
    println!();
    let mut worst: f64 = 0.0;
    for (term, truth, machine) in injections() {
        let table = simulate(&machine, &full_circles(), 0.0, 0);
        let e = evaluate(&table, &xy()).unwrap();
        let d = e.diagnostics.as_ref().unwrap();
        assert!(d.unidentifiable.is_empty(), "{:?}", d.unidentifiable);
        print!("{:>16}", short(term));
        for t in terms {
            let v = value(&e, t).unwrap();
            print!("{:>12.4}", v * gain(t) / UM);
            if t == term {
                assert!(
                    (v - truth).abs() <= tolerance(t, truth),
                    "{t:?}: {v} vs {truth}"
                );
            } else {
                worst = worst.max((v * gain(t)).abs());
            }
        }
        println!();
        match term {
            Term::ReversalSpikeP | Term::ReversalSpikeQ => {
                let (decay, _) = d.get(term).unwrap().shape.unwrap();
                let truth = machine.spike[usize::from(term == Term::ReversalSpikeQ)].1;
                assert!((decay / truth - 1.0).abs() < 0.05, "{term:?} decay {decay}");
            }
            Term::CyclicP | Term::CyclicQ => {
                let axis = usize::from(term == Term::CyclicQ);
                let (period, _) = d.get(term).unwrap().shape.unwrap();
                let (_, truth, phase) = machine.cyclic[axis];
                assert!(
                    (period / truth - 1.0).abs() < 0.001,
                    "{term:?} period {period}"
                );
                let (fitted, _) = d.get(term).unwrap().phase.unwrap();
                let wrapped = (fitted - phase + PI).rem_euclid(TAU) - PI;
                assert!(wrapped.abs() < 0.02, "{term:?} phase {fitted} vs {phase}");
            }
            _ => {}
        }
    }
    println!("largest cross-talk {:.4} µm", worst / UM);
    // The only cross-talk above round-off is second order: unequal servo lags also shrink
    // the circle differently along p and q, R·ω²·(τp² − τq²)/2 = 0.028 µm of cos 2θ.
    assert!(worst < 0.04 * UM, "cross-talk {} µm", worst / UM);
}

#[test]
fn all_diagnostics_together_are_recovered_through_noise() {
    let truth_of = |term: Term| {
        injections()
            .into_iter()
            .find(|(t, _, _)| *t == term)
            .map(|(_, v, _)| v)
            .unwrap()
    };
    let machine = everything();
    for seed in 1..=3 {
        let table = simulate(&machine, &full_circles(), 0.2 * UM, seed);
        let e = evaluate(&table, &xy()).unwrap();
        let d = e.diagnostics.as_ref().unwrap();
        assert!(d.unidentifiable.is_empty(), "{:?}", d.unidentifiable);
        assert!(d.notes.is_empty(), "{:?}", d.notes);
        assert!(
            (d.rms / (0.2 * UM) - 1.0).abs() < 0.05,
            "residual {} µm",
            d.rms / UM
        );
        for term in Term::DIAGNOSTICS {
            let truth = truth_of(term);
            let e = d.get(term).unwrap();
            assert!(
                (e.value - truth).abs() <= tolerance(term, truth),
                "seed {seed} {term:?}: {} ± {} vs {truth}",
                e.value,
                e.u
            );
            assert!(
                e.u > 0.0 && e.u < 0.5 * tolerance(term, truth),
                "{term:?} u {}",
                e.u
            );
        }
        for axis in 0..2 {
            let spike = if axis == 0 {
                Term::ReversalSpikeP
            } else {
                Term::ReversalSpikeQ
            };
            let (decay, u) = d.get(spike).unwrap().shape.unwrap();
            assert!(
                (decay / machine.spike[axis].1 - 1.0).abs() < 0.1,
                "seed {seed}: decay {decay} ± {u}"
            );
            // The axis reverses its servo lag after its programmed reversal: 30.5 ms for p,
            // 30 ms for q; a 250 Hz trace places a reversal within ±2 ms.
            let (lag, u) = d.reversal_lag[axis].unwrap();
            println!("seed {seed}: reversal lag {} ± {} ms", lag * 1e3, u * 1e3);
            assert!(
                (lag - machine.lag[axis]).abs() < 2.5e-3 && u < 2.5e-3,
                "seed {seed}: lag {lag} ± {u}"
            );
            let cyclic = if axis == 0 {
                Term::CyclicP
            } else {
                Term::CyclicQ
            };
            let (period, _) = d.get(cyclic).unwrap().shape.unwrap();
            assert!(
                (period / machine.cyclic[axis].1 - 1.0).abs() < 0.001,
                "seed {seed}: period {period}"
            );
        }
    }
}

#[test]
fn partial_arcs_recover_what_is_identifiable_and_flag_the_rest() {
    // YZ: the upper half, θ from 0° to 180°, Y reversing at both ends (never crossed);
    // ZX: θ from 270° through 0° to 90°, X reversing at both ends.
    for (plane, start, flagged) in [
        (Plane::YZ, 0.0, [Term::StraightnessP, Term::ReversalSpikeP]),
        (
            Plane::ZX,
            270.0,
            [Term::StraightnessQ, Term::ReversalSpikeQ],
        ),
    ] {
        // Every error but the two these arcs cannot show.
        let mut machine = everything();
        let other = usize::from(flagged[0] == Term::StraightnessQ);
        machine.straightness[other] = 0.0;
        machine.spike[other] = (0.0, 1.0);
        let table = simulate(&machine, &arcs(start, 180.0), 0.2 * UM, 7);
        let e = evaluate(&table, &test_in(plane)).unwrap();
        assert!((e.spans[0].unwrap().to_degrees() - 180.0).abs() < 0.05);
        let d = e.diagnostics.as_ref().unwrap();
        let unidentifiable: Vec<Term> = d.unidentifiable.iter().map(|(t, _)| *t).collect();
        assert_eq!(unidentifiable, flagged, "{plane}: {:?}", d.unidentifiable);
        println!("{}", e.to_text());
        for (term, truth, _) in injections() {
            if flagged.contains(&term) {
                assert!(d.get(term).is_none());
                assert!(e.to_json()["diagnostics"][term.key(plane)].is_null());
                continue;
            }
            let (truth, value) = (truth, d.get(term).unwrap().value);
            assert!(
                (value - truth).abs() <= tolerance(term, truth),
                "{plane} {term:?}: {value} vs {truth}"
            );
        }
    }
}

/// A table from (angle °, deviation µm) pairs per sense, ccw first.
fn hand_table(ccw: &[(f64, f64)], cw: &[(f64, f64)]) -> BallbarTable {
    let reading = |sense: Sense, &(deg, um): &(f64, f64)| BallbarReading {
        sense,
        angle: f64::to_radians(deg),
        deviation: um * UM,
        time: None,
    };
    BallbarTable {
        readings: ccw
            .iter()
            .map(|r| reading(Sense::Ccw, r))
            .chain(cw.iter().map(|r| reading(Sense::Cw, r)))
            .collect(),
        ..Default::default()
    }
}

#[test]
fn iso_values_match_a_hand_computation() {
    // 24 readings per sense every 15°. ccw: 1 + 2·cos 2θ µm plus a 1.5 µm bump at 30° and
    // 210°; cw: −1 + 2·cos 2θ µm. On this grid cos 2θ is orthogonal to 1, cos θ and sin θ,
    // and the two opposite bumps add nothing to cos θ and sin θ, so every fit's centre is 0:
    // - ccw's own fit: r₀ = 1 + 2·1.5/24 = 1.125; residual max 1 + 2·cos 60° + 1.5 − 1.125
    //   = 2.375 (at 30°), min −2 − 0.125 = −2.125 (at 90°): G_ccw = 4.5 µm;
    // - cw's own fit: r₀ = −1; residual 2·cos 2θ: G_cw = 4 µm;
    // - the common fit: r₀ = 3/48 = 0.0625; ccw max 3.5 − 0.0625 = 3.4375 (at 30°), cw min
    //   −3 − 0.0625 = −3.0625 (at 90°): G = 6.5 µm;
    // - H: the traces share their angles; ccw − cw = 2 µm, 3.5 µm at the bumps: H = 3.5 µm;
    // - F: the deviations themselves (centre 0): F_max = 3.5 µm, F_min = −3 µm.
    let bump = |deg: f64| {
        if deg == 30.0 || deg == 210.0 {
            1.5
        } else {
            0.0
        }
    };
    let angles: Vec<f64> = (0..24).map(|k| 15.0 * k as f64).collect();
    let two = |deg: f64| 2.0 * (2.0 * deg.to_radians()).cos();
    let ccw: Vec<(f64, f64)> = angles
        .iter()
        .map(|&a| (a, 1.0 + two(a) + bump(a)))
        .collect();
    let cw: Vec<(f64, f64)> = angles.iter().rev().map(|&a| (a, -1.0 + two(a))).collect();
    let e = evaluate(&hand_table(&ccw, &cw), &xy()).unwrap();
    let near = |a: Option<f64>, b: f64| {
        let a = a.unwrap() / UM;
        assert!((a - b).abs() < 1e-9, "{a} != {b}");
    };
    near(e.circular_deviation[0], 4.5);
    near(e.circular_deviation[1], 4.0);
    near(e.bidirectional_deviation, 6.5);
    near(e.hysteresis, 3.5);
    near(Some(e.radial_max), 3.5);
    near(Some(e.radial_min), -3.0);
    near(Some(e.mean_radial_deviation), 0.0625);
    near(Some(e.centre_offset[0].abs()), 0.0);
    let json = e.to_json();
    for (key, value) in [
        ("G_ccw_um", 4.5),
        ("G_cw_um", 4.0),
        ("G_um", 6.5),
        ("H_um", 3.5),
        ("F_max_um", 3.5),
        ("F_min_um", -3.0),
    ] {
        assert_eq!(json[key], value, "{key}");
    }
    // 48 readings are too few for the diagnostics, which say so.
    assert!(json["diagnostics"].is_null());
    assert!(
        json["diagnostics_skipped"]
            .as_str()
            .unwrap()
            .contains("200")
    );

    // H interpolates: cw readings halfway between the ccw ones (7.5° + 15°k), alternating
    // −1 ± 0.3 µm; ccw constant +1 µm. The alternation is orthogonal to 1, cos θ and sin θ,
    // so the common fit is r₀ = 0, no centre. At every ccw angle the interpolated cw trace
    // is the mean of its neighbours, −1 µm (at 0° between 352.5° and 7.5°, across the wrap):
    // H = 2 µm, where pairing with the nearest reading would give 2.3 µm. G = 1 − (−1.3).
    let ccw: Vec<(f64, f64)> = angles.iter().map(|&a| (a, 1.0)).collect();
    let cw: Vec<(f64, f64)> = (0..24)
        .rev()
        .map(|k| {
            (
                7.5 + 15.0 * k as f64,
                -1.0 + if k % 2 == 0 { 0.3 } else { -0.3 },
            )
        })
        .collect();
    let e = evaluate(&hand_table(&ccw, &cw), &xy()).unwrap();
    near(e.hysteresis, 2.0);
    near(e.bidirectional_deviation, 2.3);
    near(e.circular_deviation[0], 0.0);
    near(e.circular_deviation[1], 0.6);
}

#[test]
fn one_sense_is_evaluated_with_the_sense_dependent_terms_flagged() {
    let machine = everything();
    let table = simulate(&machine, &full_circles(), 0.2 * UM, 3);
    let ccw = BallbarTable {
        readings: table
            .readings
            .iter()
            .filter(|r| r.sense == Sense::Ccw)
            .copied()
            .collect(),
        ..Default::default()
    };
    let e = evaluate(&ccw, &xy()).unwrap();
    assert!(e.circular_deviation[0].is_some() && e.circular_deviation[1].is_none());
    assert!(e.bidirectional_deviation.is_none() && e.hysteresis.is_none());
    let json = e.to_json();
    for key in ["G_cw_um", "G_um", "H_um"] {
        assert!(json[key].is_null(), "{key}");
    }
    assert!(json["G_ccw_um"].is_number());
    let d = e.diagnostics.as_ref().unwrap();
    let flagged: Vec<Term> = d.unidentifiable.iter().map(|(t, _)| *t).collect();
    assert_eq!(
        flagged,
        [Term::ServoMismatch, Term::LateralPlayP, Term::LateralPlayQ]
    );
    assert!(
        d.unidentifiable[0].1.contains("squareness"),
        "{}",
        d.unidentifiable[0].1
    );
    let listed: Vec<&str> = json["unidentifiable"]
        .as_array()
        .unwrap()
        .iter()
        .map(|u| u["term"].as_str().unwrap())
        .collect();
    assert_eq!(
        listed,
        [
            "servo_mismatch_ms",
            "lateral_play_x_um",
            "lateral_play_y_um"
        ]
    );
    assert!(json["diagnostics"]["servo_mismatch_ms"].is_null());
    // What one sense does show: backlash, straightness, spikes, cyclic errors. (The servo
    // mismatch is in the squareness and the lateral play in the radius and scale mismatch.)
    for (term, truth, _) in injections() {
        if matches!(
            term,
            Term::BacklashP
                | Term::BacklashQ
                | Term::StraightnessP
                | Term::StraightnessQ
                | Term::ReversalSpikeP
                | Term::ReversalSpikeQ
                | Term::CyclicP
                | Term::CyclicQ
        ) {
            let value = d.get(term).unwrap().value;
            assert!(
                (value - truth).abs() <= tolerance(term, truth),
                "{term:?}: {value} vs {truth}"
            );
        }
    }
    let apparent = 20e-6 + V * 0.5e-3 / R; // s + v·Δτ/R: servo mismatch read as squareness
    let squareness = d.get(Term::Squareness).unwrap().value;
    assert!(
        (squareness / apparent - 1.0).abs() < 0.01,
        "{squareness} vs {apparent}"
    );
}

#[test]
fn absent_spikes_and_cyclic_errors_are_reported_without_decay_or_period() {
    // Backlash and centre offsets only: the spikes and cyclic errors the searches find in
    // the noise are well below the noise (0.2 µm), and below their significance levels the decay and the period
    // are null, with a note.
    let machine = Machine {
        centre: [5.0 * UM, -3.0 * UM],
        backlash: [2.0 * UM, 2.0 * UM],
        ..Machine::default()
    };
    let test = xy();
    let table = simulate(&machine, &full_circles(), 0.2 * UM, 11);
    let e = evaluate(&table, &test).unwrap();
    let d = e.diagnostics.as_ref().unwrap();
    let json = e.to_json();
    // The cyclic threshold for R = 150 mm, periods 1 mm to 75 mm tested every 1/(8R) = 1/1.2 m
    // in frequency: M = (1000 − 13.33)·1.2 + 1 = 1185 periods, √(2·ln(1185/0.05)) = 4.4886.
    let data = mtwin::kinds::ballbar::iso230_4::CircleData::new(&table, &test).unwrap();
    assert!(
        (data.significance(Term::CyclicP) - 4.4886).abs() < 0.0005,
        "{}",
        data.significance(Term::CyclicP)
    );
    // A spike's: its onset searched over 81 lags and its decay over 16: M = 1296 shapes,
    // √(2·ln(1296/0.05)) = 4.5084.
    assert!(
        (data.significance(Term::ReversalSpikeP) - 4.5084).abs() < 0.0005,
        "{}",
        data.significance(Term::ReversalSpikeP)
    );
    for term in [
        Term::ReversalSpikeP,
        Term::ReversalSpikeQ,
        Term::CyclicP,
        Term::CyclicQ,
    ] {
        let estimate = d.get(term).unwrap();
        assert!(estimate.value.abs() < 0.1 * UM, "{term:?}: {estimate:?}");
        let significant = estimate.value.abs() >= data.significance(term) * estimate.u;
        assert_eq!(
            estimate.shape.is_some(),
            significant,
            "{term:?}: {estimate:?}"
        );
        let shape_key = match term {
            Term::CyclicP | Term::CyclicQ => format!("{}_period_mm", term.name(Plane::XY)),
            _ => format!("{}_decay_ms", term.name(Plane::XY)),
        };
        assert_eq!(
            json["diagnostics"][&shape_key].is_null(),
            !significant,
            "{shape_key}"
        );
        let noted = d.notes.iter().any(|n| n.starts_with(&term.key(Plane::XY)));
        assert_eq!(noted, !significant, "{:?}", d.notes);
    }
    for term in [Term::CyclicP, Term::CyclicQ] {
        assert!(d.get(term).unwrap().shape.is_none(), "{term:?}");
    }
}

#[test]
fn json_keys_carry_the_plane_letters_and_units() {
    let machine = everything();
    let table = simulate(&machine, &full_circles(), 0.2 * UM, 5);
    let json = evaluate(&table, &test_in(Plane::YZ)).unwrap().to_json();
    assert_eq!(json["plane"], "YZ");
    assert_eq!(json["radius_mm"], 150.0);
    assert_eq!(json["feed_mm_per_min"], 1000.0);
    assert_eq!(json["n_readings"], table.readings.len());
    for key in [
        "G_ccw_um",
        "G_cw_um",
        "G_um",
        "H_um",
        "F_max_um",
        "F_min_um",
        "centre_offset_y_um",
        "centre_offset_z_um",
        "mean_radial_deviation_um",
    ] {
        assert!(json[key].is_number(), "{key}");
    }
    let d = &json["diagnostics"];
    for key in [
        "radius_deviation_um",
        "centre_offset_y_um",
        "squareness_um_per_m",
        "scale_mismatch_ppm",
        "servo_mismatch_ms",
        "backlash_y_um",
        "backlash_z_um",
        "lateral_play_z_um",
        "straightness_y_um",
        "reversal_spike_z_um",
        "reversal_spike_z_decay_ms",
        "cyclic_y_um",
        "cyclic_y_period_mm",
        "cyclic_z_phase_deg",
        "reversal_lag_y_ms",
        "reversal_lag_z_ms",
    ] {
        assert!(
            d[key]["value"].is_number() && d[key]["u"].is_number(),
            "{key}: {}",
            d[key]
        );
    }
    // The same error in YZ is named after Y and Z; p = Y carries the 4 µm backlash.
    assert!((d["backlash_y_um"]["value"].as_f64().unwrap() - 4.0).abs() < 0.2);
    assert!((d["servo_mismatch_ms"]["value"].as_f64().unwrap() - 0.5).abs() < 0.025);
    assert!((d["reversal_lag_y_ms"]["value"].as_f64().unwrap() - 30.5).abs() < 2.5);
    assert!(json["conventions"]["terms"]["backlash_y_um"].is_string());
    assert!(json["unidentifiable"].as_array().unwrap().is_empty());
}

#[test]
fn bad_input_is_refused_with_a_clear_message() {
    let table = simulate(&Machine::default(), &full_circles(), 0.0, 0);
    let few = BallbarTable {
        readings: table
            .readings
            .iter()
            .filter(|r| r.sense == Sense::Ccw)
            .chain(
                table
                    .readings
                    .iter()
                    .filter(|r| r.sense == Sense::Cw)
                    .step_by(800),
            )
            .copied()
            .collect(),
        ..Default::default()
    };
    let error = evaluate(&few, &xy()).unwrap_err();
    assert_eq!(error, BallbarError::TooFewReadings { sense: "cw", n: 18 });
    assert!(error.to_string().contains("at least 20"), "{error}");
    assert_eq!(
        evaluate(&BallbarTable::default(), &xy()),
        Err(BallbarError::Empty)
    );
    let bad = |radius: f64, feed: f64| {
        evaluate(
            &table,
            &CircularTest {
                plane: Plane::XY,
                radius,
                feed,
            },
        )
        .unwrap_err()
        .to_string()
    };
    assert!(bad(0.0, V).contains("radius 0 mm"), "{}", bad(0.0, V));
    assert!(
        bad(R, f64::NAN).contains("feed NaN mm/min"),
        "{}",
        bad(R, f64::NAN)
    );
    // A 60° arc cannot locate a centre.
    let short = simulate(&Machine::default(), &arcs(10.0, 60.0), 0.0, 0);
    let error = evaluate(&short, &xy()).unwrap_err();
    assert!(
        matches!(error, BallbarError::SpanTooSmall { sense: "ccw", .. }),
        "{error}"
    );
    assert!(error.to_string().contains("60.0°"), "{error}");
}

#[test]
fn noise_rarely_makes_a_spike_or_a_cyclic_error_significant() {
    // 12 noisy traces of a machine with neither: how often does the search call one
    // significant? Each at the Bonferroni level of its search (at most 5 % per term by
    // construction): a spike over its lags and decays (at the former 2u, 10 % per term over
    // 30 seeds with the lag pinned by backlash, and most traces of an axis without backlash),
    // a cyclic error over its periods (3 % measured).
    let machine = Machine {
        centre: [5.0 * UM, -3.0 * UM],
        backlash: [2.0 * UM, 2.0 * UM],
        ..Machine::default()
    };
    let mut spikes = 0;
    let mut cyclic = 0;
    for seed in 0..12 {
        let table = simulate(&machine, &full_circles(), 0.2 * UM, 100 + seed);
        let e = evaluate(&table, &xy()).unwrap();
        let d = e.diagnostics.as_ref().unwrap();
        let significant = |t: Term| usize::from(d.get(t).unwrap().shape.is_some());
        spikes += significant(Term::ReversalSpikeP) + significant(Term::ReversalSpikeQ);
        cyclic += significant(Term::CyclicP) + significant(Term::CyclicQ);
    }
    println!("significant by chance in 24 tries: spikes {spikes}, cyclic {cyclic}");
    assert!(spikes <= 3, "{spikes} of 24");
    assert!(cyclic <= 3, "{cyclic} of 24");
}

#[test]
fn a_centre_ball_set_a_third_of_a_millimetre_off_leaves_no_shape_in_the_figures() {
    // A perfect machine's circle (radius R about the programmed centre) read by a bar whose
    // centre ball sits at c = (0.3, −0.2) mm: D = |R·u − c| exactly, no noise. The trace is
    // d = D − R ≈ −u·c + (u⊥·c)²/(2R), the second term 0.22 µm at 2θ; removed only to first
    // order it read as 0.43 µm of G and as squareness. Exact removal leaves nothing: G, H and
    // F_max − F_min below 1 nm (the square root's rounding is 1e-17 m).
    let c = [0.3e-3, -0.2e-3];
    let mut readings = Vec::new();
    for (sense, sign) in [(Sense::Ccw, 1.0), (Sense::Cw, -1.0)] {
        for k in 0..3600 {
            let angle = (sign * k as f64 * 0.1_f64).to_radians().rem_euclid(TAU);
            let (s, co) = angle.sin_cos();
            let distance = (R * co - c[0]).hypot(R * s - c[1]);
            readings.push(BallbarReading {
                sense,
                angle,
                deviation: distance - R,
                time: None,
            });
        }
    }
    let table = BallbarTable {
        readings,
        ..Default::default()
    };
    let evaluation = evaluate(&table, &xy()).unwrap();
    let nm = 1e-9;
    for g in evaluation.circular_deviation {
        assert!(g.unwrap() < nm, "{evaluation:#?}");
    }
    assert!(evaluation.bidirectional_deviation.unwrap() < nm);
    assert!(evaluation.radial_max - evaluation.radial_min < nm);
    // The centre found is the ball's, to 1 nm: d ≈ r₀ + c_p cos θ + c_q sin θ with (c_p, c_q) = −c.
    assert!(
        (evaluation.centre_offset[0] + c[0]).abs() < nm,
        "{:?}",
        evaluation.centre_offset
    );
    assert!(
        (evaluation.centre_offset[1] + c[1]).abs() < nm,
        "{:?}",
        evaluation.centre_offset
    );
}

#[test]
fn a_trace_run_at_ninety_percent_feed_override_is_named_as_unexplained() {
    use mtwin::kinds::ballbar::plausible::unexplained;
    // An out-of-round machine (12 µm of 2θ) traced with 0.05 µm of noise; the software
    // assigns angles at the programmed feed, the machine runs at `override_` of it, so the
    // reading labelled θ was taken at override·θ. At 100 % the diagnostic fit's terms take the
    // 2θ shape; at 90 % the shape lands at the wrong angles and the fit leaves micrometres,
    // dozens of times the noise.
    let trace = |override_: f64| {
        let mut rng = seeded_rng(3, "feed override");
        let mut readings = Vec::new();
        for (sense, sign) in [(Sense::Ccw, 1.0), (Sense::Cw, -1.0)] {
            for k in 0..3600 {
                let labelled = (sign * k as f64 * 0.1_f64).to_radians();
                let actual = override_ * labelled;
                readings.push(BallbarReading {
                    sense,
                    angle: labelled.rem_euclid(TAU),
                    deviation: 12.0 * UM * (2.0 * actual).cos()
                        + 0.05 * UM * standard_normal(&mut rng),
                    time: None,
                });
            }
        }
        BallbarTable {
            readings,
            ..Default::default()
        }
    };
    let said = |table: &BallbarTable| {
        let evaluation = evaluate(table, &xy()).unwrap();
        let rms = evaluation.diagnostics.as_ref().unwrap().rms;
        unexplained(table, rms, "the diagnostic fit")
    };
    let clean = trace(1.0);
    assert_eq!(said(&clean), None);
    let overridden = trace(0.9);
    let caution = said(&overridden).expect("named");
    assert!(caution.contains("feed override"), "{caution}");
}

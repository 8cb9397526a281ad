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
/// Where in its interval each sample falls (0.382: 1 − 1/golden ratio, far from the halves
/// and quarters that round lags make).
const SAMPLE_PHASE: f64 = 0.382;
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
            // 0.382 of a sample off the run's start, so no sample falls exactly on a programmed
            // reversal nor on one lagged by the round lags the tests use. With half a sample,
            // 30 ms (7.5 samples at 250 Hz) put a sample on the actual reversal, where the sign
            // of a velocity rounded to zero decided whether the spike had begun (after it in one
            // sense, before in the other): a tie no real trace has, which read as a spike 12 %
            // low and 17 % long.
            let t = (k as f64 + SAMPLE_PHASE) * dt;
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
        // Noise-free, any searched term is significant; one that fits the rounding at the end
        // of its searched range is withdrawn (no number, so no cross-talk).
        let withdrawn = |t: Term| {
            d.unidentifiable
                .iter()
                .any(|(w, why)| *w == t && why.contains("searched"))
        };
        assert!(
            d.unidentifiable
                .iter()
                .all(|(t, _)| *t != term && withdrawn(*t)),
            "{:?}",
            d.unidentifiable
        );
        print!("{:>16}", short(term));
        for t in terms {
            let v = if withdrawn(t) {
                0.0
            } else {
                value(&e, t).unwrap()
            };
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

mod reversal_and_arcs;
mod values_and_edges;

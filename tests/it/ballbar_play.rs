//! Backlash as real play (issue 15, item 6): the carriage stands still while the motor
//! crosses the gap after a reversal, then follows offset by half the gap against its travel.
//!
//! - the twin's servo model with play, against the definition of a dead band;
//! - the scenario key `servo.X.play_um` and the truth it records;
//! - the ISO 230-4 diagnostics of traces with play of 2–8 µm on each axis, alone and with a
//!   reversal spike, at 500–3000 mm/min, made two ways: through mtwin's servo and twin, and by
//!   an independent simulator written here (a first-order lag on a sampled command, a dead
//!   band behind it, angles assigned from the command at the sampling time, as software that
//!   does not time its trace from the machine's motion would): backlash recovered within 5 %,
//!   no spike where none was planted, a planted spike with its sign;
//! - clean traces of both kinds at 500–3000 mm/min leave residuals at the noise;
//! - traces with lost motion as today's instantaneous half-step are still read as a step.
//!
//! Physical tolerances: the noise is 0.1 µm per reading. A spike below 3 × the noise
//! (0.3 µm) at its peak is within the scatter of the single readings it would sit on and is
//! "not there" on a plot; backlash within 5 % is the figure (0.1–0.4 µm here, 1–4 ×
//! the noise); a residual RMS within 5 % of the noise means the model leaves less than
//! √(1.05² − 1) = 0.32 × the noise of systematic error (a pure-noise residual of ~10⁴ readings
//! scatters by 1/√(2n) < 1 % about the noise).

use crate::common;

use mtwin::app::Scenario;
use mtwin::errors::ErrorFunction;
use mtwin::kinds::ballbar::instrument::Ballbar;
use mtwin::kinds::ballbar::iso230_4::{self, CircularTest, Diagnostics, Term};
use mtwin::kinds::ballbar::{BallbarReading, BallbarTable, Sense};
use mtwin::kinds::ballbar::{CircularInterpolation, run_circle};
use mtwin::machine::{Axis, AxisValues, Plane};
use mtwin::math::{Real, Vector, seeded_rng, standard_normal};
use mtwin::program::{AxisServo, Servo};
use mtwin::twin::Twin;
use std::f64::consts::{PI, TAU};

const UM: Real = 1e-6;
const RADIUS: Real = 0.1;
const NOISE: Real = 0.1 * UM;
const RATE: Real = 250.0;
/// The feeds of the tests (mm/min).
const FEEDS: [Real; 4] = [500.0, 1000.0, 2000.0, 3000.0];
/// A spike smaller than this at its peak is not there (3 × the noise).
const NO_SPIKE: Real = 3.0 * NOISE;
/// Backlash recovered within this fraction.
const BACKLASH_TOLERANCE: Real = 0.05;
/// Residual RMS at most this multiple of the noise.
const RESIDUAL_MULTIPLE: Real = 1.05;

fn feed(mm_per_min: Real) -> Real {
    mm_per_min * 1e-3 / 60.0
}

fn twin(errors: &[(&str, ErrorFunction)]) -> Twin {
    common::twin(&common::machine("vmc3"), errors)
}

/// The vmc3 XY circle of 100 mm about X 380, Y 205, Z 300 mm, full, 180° overshoots.
fn circle(feed_mm_per_min: Real) -> CircularInterpolation {
    CircularInterpolation {
        plane: Plane::XY,
        centre: AxisValues::from_file_units(&[
            (Axis::X, 380.0),
            (Axis::Y, 205.0),
            (Axis::Z, 300.0),
        ]),
        radius: RADIUS,
        feed: feed(feed_mm_per_min),
        data_start: 0.0,
        data_arc: TAU,
        overshoot: PI,
        acceleration: 2.0,
        dwell: 1.0,
    }
}

/// A servo with play `play` (m) and spike `spike` (m, s) on X and Y, default loops.
fn servo(play: [Real; 2], spike: [(Real, Real); 2]) -> Servo {
    let mut servo = Servo::default();
    for axis in 0..2 {
        servo.axes[axis] = AxisServo {
            play: play[axis],
            spike_height: spike[axis].0,
            spike_decay: if spike[axis].0 > 0.0 {
                spike[axis].1
            } else {
                AxisServo::DEFAULT.spike_decay
            },
            ..AxisServo::DEFAULT
        };
    }
    servo
}

/// A trace of `twin` through `servo` at `feed_mm_per_min`: 0.1 µm noise, no resolution step,
/// a 20 µm, −12 µm set-up offset.
fn twin_trace(twin: &Twin, servo: &Servo, feed_mm_per_min: Real, seed: u64) -> BallbarTable {
    let bar = Ballbar {
        length: RADIUS,
        setup_offset: Vector::new(20e-6, -12e-6, 0.0),
        calibration_error: 0.0,
        resolution: 0.0,
        noise: NOISE,
        sample_rate: RATE,
    };
    bar.measure(
        twin,
        &circle(feed_mm_per_min),
        servo,
        &mut seeded_rng(seed, "ballbar play"),
    )
}

fn test_of(feed_mm_per_min: Real) -> CircularTest {
    CircularTest {
        plane: Plane::XY,
        radius: RADIUS,
        feed: feed(feed_mm_per_min),
    }
}

fn diagnose(table: &BallbarTable, feed_mm_per_min: Real) -> Diagnostics {
    iso230_4::evaluate(table, &test_of(feed_mm_per_min))
        .unwrap()
        .diagnostics
        .unwrap()
}

fn value(d: &Diagnostics, term: Term) -> Real {
    d.get(term).map_or(0.0, |e| e.value)
}

// ---------------------------------------------------------------------------------------
// An independent simulator: a sampled command, a first-order lag, a dead band.
// ---------------------------------------------------------------------------------------

/// What the independent simulator draws.
#[derive(Clone, Copy)]
struct Drive {
    /// Position-loop gain of p and q (1/s).
    kv: [Real; 2],
    /// Gap of the dead band of p and q (m).
    play: [Real; 2],
    /// Spike height (m, + outward) and decay (s) of p and q, from when the carriage reverses.
    spike: [(Real, Real); 2],
    /// Centre of the machine's circle relative to the centre ball (m).
    centre: [Real; 2],
}

/// A full-circle test, ccw then cw, each run 180° before and after the data arc, at
/// `feed_mm_per_min`. The command is sampled every 0.1 ms and held; the motor follows it
/// through a first-order lag, x ← x + (c − x)·(1 − e^(−Kv·h)); the carriage follows the motor
/// through the dead band (carriage = motor clamped to ± gap/2 about it); when the carriage
/// starts to move in a new direction it sticks by h·e^(−Δt/τ) in that direction. The bar reads
/// |carriage + centre| − R + noise every 4 ms on the data arc, and each reading gets the
/// programmed angle at its sampling instant.
fn independent_trace(drive: &Drive, feed_mm_per_min: Real, seed: u64) -> BallbarTable {
    noisy_independent_trace(drive, feed_mm_per_min, seed, NOISE)
}

/// [`independent_trace`] with `noise` (m, standard deviation) on every reading.
fn noisy_independent_trace(
    drive: &Drive,
    feed_mm_per_min: Real,
    seed: u64,
    noise: Real,
) -> BallbarTable {
    let v = feed(feed_mm_per_min);
    let omega = v / RADIUS;
    let step = 1e-4;
    let every = (1.0 / RATE / step).round() as usize;
    let mut rng = seeded_rng(seed, "independent ballbar");
    let mut readings = Vec::new();
    let mut clock = 0.0;
    for sense in [Sense::Ccw, Sense::Cw] {
        let sigma = sense.sign();
        // Data arc from 0 (ccw) or 2π (cw); the run starts half a turn before it.
        let entry = if sigma > 0.0 { 0.0 } else { TAU };
        let start = entry - sigma * PI;
        let command = |t: Real| {
            let angle = start + sigma * omega * t;
            ([RADIUS * angle.cos(), RADIUS * angle.sin()], angle)
        };
        let (c0, _) = command(0.0);
        let mut motor = c0;
        // First motion's direction, the carriage pushed that way.
        let (c1, _) = command(1e-3);
        let mut push = [0.0; 2];
        let mut carriage = [0.0; 2];
        let mut reversed: [Option<Real>; 2] = [None; 2];
        for a in 0..2 {
            push[a] = (c1[a] - c0[a]).signum();
            carriage[a] = motor[a] - push[a] * drive.play[a] / 2.0;
        }
        let duration = 2.0 * PI / omega + TAU / omega;
        let steps = (duration / step).round() as usize;
        for k in 1..=steps {
            let t = k as Real * step;
            let (c, angle) = command(t - step);
            for a in 0..2 {
                motor[a] += (c[a] - motor[a]) * (1.0 - (-drive.kv[a] * step).exp());
                let half = drive.play[a] / 2.0;
                if carriage[a] < motor[a] - half {
                    carriage[a] = motor[a] - half;
                    if push[a] < 0.0 {
                        push[a] = 1.0;
                        reversed[a] = Some(t);
                    }
                } else if carriage[a] > motor[a] + half {
                    carriage[a] = motor[a] + half;
                    if push[a] > 0.0 {
                        push[a] = -1.0;
                        reversed[a] = Some(t);
                    }
                }
            }
            if k % every != 0 {
                continue;
            }
            let programmed = angle + sigma * omega * step;
            let past_entry = sigma * (programmed - entry);
            if !(0.0..TAU).contains(&past_entry) {
                continue;
            }
            let mut tool = [0.0; 2];
            for a in 0..2 {
                let (height, decay) = drive.spike[a];
                let stick = match reversed[a] {
                    Some(at) if height != 0.0 => height * (-(t - at) / decay).exp(),
                    _ => 0.0,
                };
                tool[a] = carriage[a] - push[a] * stick + drive.centre[a];
            }
            readings.push(BallbarReading {
                sense,
                angle: programmed.rem_euclid(TAU) % TAU,
                deviation: tool[0].hypot(tool[1]) - RADIUS + noise * standard_normal(&mut rng),
                time: Some(clock + t),
            });
        }
        clock += duration + 1.0;
    }
    BallbarTable {
        readings,
        ..Default::default()
    }
}

const DEFAULT_KV: Real = 100.0 / 3.0;

// ---------------------------------------------------------------------------------------
// The servo model
// ---------------------------------------------------------------------------------------

#[test]
fn with_play_the_carriage_stands_still_over_the_gap_then_follows_offset_by_half_of_it() {
    // Play of X only: the motor (the loop) is what it is without play, so the two runs differ
    // in X by carriage − motor. By the definition of the dead band: never more than b/2; once
    // the motor has come back b from its extreme after a reversal, exactly −(b/2)·d (d the
    // direction of travel); in between the carriage stands at the reversal's extreme − b/2·d_old.
    // Y, without play, is untouched.
    let b = 6.0 * UM;
    let circle = circle(1000.0);
    let plain = run_circle(&circle, &Servo::default(), 1e-3);
    let played = run_circle(&circle, &servo([b, 0.0], [(0.0, 0.0); 2]), 1e-3);
    assert_eq!(plain.len(), played.len());
    let x = |s: &mtwin::kinds::ballbar::ServoSample| s.state.position[Axis::X];
    let y = |s: &mtwin::kinds::ballbar::ServoSample| s.state.position[Axis::Y];
    let mut extreme: Option<(Real, Real)> = None; // (motor at the last reversal, d after it)
    let (mut steady, mut standing) = (0, 0);
    for (i, (m, c)) in plain.iter().zip(&played).enumerate() {
        assert_eq!(y(m), y(c), "Y moved at sample {i}");
        let offset = x(c) - x(m);
        assert!(
            offset.abs() <= b / 2.0 * (1.0 + 1e-9),
            "{offset} at sample {i}"
        );
        let d = m.state.direction[Axis::X.index()].sign();
        if i > 0 && plain[i - 1].state.direction[Axis::X.index()].sign() != d {
            // The motor's extreme lies between these samples: the larger (smaller) of the two
            // plus at most the travel of one sample.
            let previous = x(&plain[i - 1]);
            extreme = Some((
                if d < 0.0 {
                    previous.max(x(m))
                } else {
                    previous.min(x(m))
                },
                d,
            ));
        }
        match extreme {
            Some((turn, d)) if d * (x(m) - turn) < b * 0.999 && d * (x(m) - turn) > 0.0 => {
                // Taking up the gap: the carriage still at the extreme's − b/2·d_old
                // (to the sampling of the extreme: one millisecond at the axis's speed there).
                let at_rest = turn + d * b / 2.0;
                let speed_bound = 2.0 * circle.feed * 1e-3 * (circle.feed * 1e-3 / RADIUS);
                assert!(
                    (x(c) - at_rest).abs() <= speed_bound + 1e-12,
                    "sample {i}: carriage {} µm from the extreme's, bound {} µm",
                    (x(c) - at_rest) / UM,
                    speed_bound / UM
                );
                standing += 1;
            }
            _ => {
                if extreme.is_some() || i > 100 {
                    let expected = -d * b / 2.0;
                    if extreme.is_some_and(|(turn, d)| d * (x(m) - turn) >= b * 1.001) {
                        assert!(
                            (offset - expected).abs() < 1e-12,
                            "sample {i}: {offset} vs {expected}"
                        );
                        steady += 1;
                    }
                }
            }
        }
    }
    // 4 reversals of X over the two runs (180° overshoots: 720° per run); the take-up over
    // R·(1 − cos φ) = b is φ = 0.63° here, 1.1 mm of path, 66 ms at 1000 mm/min.
    assert!(standing > 4 * 50, "{standing} samples taking up the gap");
    assert!(steady > plain.len() / 2, "{steady} steady samples");
}

#[test]
fn without_play_the_servo_is_unchanged_and_play_is_validated() {
    // Play 0 is the default and the runs are bit-identical to the default servo's.
    let circle = circle(2000.0);
    let a = run_circle(&circle, &Servo::default(), 4e-3);
    let b = run_circle(&circle, &servo([0.0; 2], [(0.0, 0.0); 2]), 4e-3);
    assert_eq!(a, b);
    assert_eq!(AxisServo::DEFAULT.play, 0.0);
    for bad in [-1e-6, Real::NAN, Real::INFINITY] {
        let s = AxisServo {
            play: bad,
            ..AxisServo::DEFAULT
        };
        assert!(s.problem().is_some_and(|p| p.contains("play")), "{bad}");
    }
}

// ---------------------------------------------------------------------------------------
// The scenario
// ---------------------------------------------------------------------------------------

fn scenario_text(x: &str) -> String {
    format!(
        "schema = 1\n\
         machine = '{}/models/vmc3.urdf'\n\
         seed = 1\n\
         \n\
         [ballbar]\n\
         planes = [\"XY\"]\n\
         length_mm = 100.0\n\
         feed_mm_per_min = 1000.0\n\
         centre_mm = {{ x = 380.0, y = 205.0, z = 300.0 }}\n\
         \n\
         [servo]\n\
         X = {{ {x} }}\n\
         Y = {{ kv_per_s = 33.3 }}\n",
        env!("CARGO_MANIFEST_DIR")
    )
}

#[test]
fn the_scenario_takes_play_um_records_it_and_refuses_a_negative_one() {
    let dir = tempfile::TempDir::new().unwrap();
    let path = dir.path().join("play.toml");
    std::fs::write(&path, scenario_text("kv_per_s = 33.3, play_um = 4.5")).unwrap();
    let scenario = Scenario::load(&path).unwrap();
    let test = scenario.ballbar_test.unwrap();
    assert!((test.servo.axes[0].play - 4.5e-6).abs() < 1e-18);
    assert_eq!(test.servo.axes[1].play, 0.0);
    let truth = mtwin::kinds::ballbar::run::truth(&test);
    assert_eq!(truth["servo"]["X"]["play_um"].as_f64(), Some(4.5));
    // No play: nothing recorded (the truth of a test without play reads as before).
    assert!(truth["servo"]["Y"].get("play_um").is_none());

    let text = scenario_text("kv_per_s = 33.3, play_um = -2.0");
    std::fs::write(&path, &text).unwrap();
    let error = Scenario::load(&path).unwrap_err();
    let message = error.to_string();
    let line = text.lines().position(|l| l.contains("play_um")).unwrap() + 1;
    assert_eq!(error.line(), Some(line), "{message}");
    assert!(
        message.starts_with(&format!("{}:{line}: ", path.display())),
        "{message}"
    );
    assert!(message.contains("servo.X.play_um"), "{message}");
    assert!(message.contains("-2"), "{message}");
}

// ---------------------------------------------------------------------------------------
// The analysis
// ---------------------------------------------------------------------------------------

/// Play of X and Y (µm) per feed: 2–8 µm on each axis.
const PLAYS: [(Real, [Real; 2]); 4] = [
    (500.0, [2.0, 8.0]),
    (1000.0, [5.0, 3.0]),
    (2000.0, [8.0, 2.0]),
    (3000.0, [4.0, 6.0]),
];

/// The planted spikes: height (m, outward) and decay (s) of X and Y.
const SPIKES: [(Real, Real); 2] = [(2.0 * UM, 0.02), (1.5 * UM, 0.025)];

/// Checks backlash within 5 %, the spikes (planted: sign and size; else below 3 × the
/// noise) and the residual; returns the problems.
fn check(
    what: &str,
    d: &Diagnostics,
    play: [Real; 2],
    spike: [(Real, Real); 2],
    spike_tolerance: Real,
) -> Vec<String> {
    let mut problems = Vec::new();
    for axis in 0..2 {
        let (backlash, spike_term) = if axis == 0 {
            (Term::BacklashP, Term::ReversalSpikeP)
        } else {
            (Term::BacklashQ, Term::ReversalSpikeQ)
        };
        let got = value(d, backlash);
        let error = got / play[axis] - 1.0;
        let h = value(d, spike_term);
        let significant = d.get(spike_term).is_some_and(|e| e.shape.is_some());
        let decay = d.get(spike_term).and_then(|e| e.shape).map_or(0.0, |s| s.0);
        println!(
            "{what} axis {axis}: backlash {:.3} µm (truth {:.1}, {:+.2} %), spike {:.3} µm{} decay {:.1} ms (truth {:.1}), play column {:.3} µm, lag {:.1} ms",
            got / UM,
            play[axis] / UM,
            100.0 * error,
            h / UM,
            if significant { " significant" } else { "" },
            decay * 1e3,
            spike[axis].0 / UM,
            d.fit.shape.play[axis] / UM,
            d.fit.shape.lag[axis] * 1e3,
        );
        if error.abs() > BACKLASH_TOLERANCE {
            problems.push(format!(
                "{what}: backlash of axis {axis} {} µm vs {} µm",
                got / UM,
                play[axis] / UM
            ));
        }
        let truth = spike[axis].0;
        if truth == 0.0 {
            if h.abs() >= NO_SPIKE {
                problems.push(format!(
                    "{what}: an unplanted spike of axis {axis}: {} µm",
                    h / UM
                ));
            }
        } else if !(h > 0.0 && (h - truth).abs() <= spike_tolerance * truth && significant) {
            problems.push(format!(
                "{what}: spike of axis {axis} {} µm (significant: {significant}) vs {} µm",
                h / UM,
                truth / UM
            ));
        }
    }
    let ratio = d.rms / NOISE;
    println!("{what}: residual {ratio:.3} × the noise");
    if ratio > RESIDUAL_MULTIPLE {
        problems.push(format!("{what}: residual {ratio:.3} × the noise"));
    }
    problems
}

/// A spike's height is read back to the carriage's reversal, which a 250 Hz trace places
/// only within its 4 ms samples. With play the reversal is located by the take-up beside the
/// spike's onset, to a fraction of a sample; when a sample lies that close to the onset the
/// fit may put it on the wrong side and trade it against the height: the height is then known
/// to a factor e^(±Δt/τ) (one sample, 22 % at τ = 20 ms), and 5 % beside (seen: −25 % at
/// τ = 15 ms, 500 mm/min, 2 of 6 seeds of the independent simulator).
fn spike_tolerance(decay: Real) -> Real {
    (1.0 / (RATE * decay)).exp() - 1.0 + 0.05
}

#[test]
fn real_play_in_the_twin_is_read_as_backlash_without_a_spike() {
    let twin = twin(&[]);
    let mut problems = Vec::new();
    for (seed, (feed, play)) in PLAYS.iter().enumerate() {
        let play = play.map(|b| b * UM);
        let servo = servo(play, [(0.0, 0.0); 2]);
        let table = twin_trace(&twin, &servo, *feed, seed as u64 + 1);
        let d = diagnose(&table, *feed);
        problems.extend(check(
            &format!("twin {feed} mm/min"),
            &d,
            play,
            [(0.0, 0.0); 2],
            0.0,
        ));
        // The fit drew real play, not the step.
        if d.fit.shape.play.contains(&0.0) {
            problems.push(format!("twin {feed}: the fit kept the step"));
        }
    }
    assert!(problems.is_empty(), "{}", problems.join("\n"));
}

#[test]
fn real_play_with_a_real_spike_in_the_twin_is_read_with_the_spikes_sign() {
    // An outward spike of 2 µm (X, τ 20 ms) and 1.5 µm (Y, τ 25 ms), where the carriage
    // reverses, beside play of 2–8 µm.
    let twin = twin(&[]);
    let spike = SPIKES;
    let mut problems = Vec::new();
    for (seed, (feed, play)) in PLAYS.iter().enumerate() {
        let play = play.map(|b| b * UM);
        let table = twin_trace(&twin, &servo(play, spike), *feed, seed as u64 + 11);
        let d = diagnose(&table, *feed);
        problems.extend(check(
            &format!("twin + spike {feed} mm/min"),
            &d,
            play,
            spike,
            spike_tolerance(spike[0].1.min(spike[1].1)),
        ));
    }
    assert!(problems.is_empty(), "{}", problems.join("\n"));
}

#[test]
fn real_play_from_an_independent_simulator_is_read_as_backlash() {
    let mut problems = Vec::new();
    for (seed, (feed, play)) in PLAYS.iter().enumerate() {
        let drive = Drive {
            kv: [DEFAULT_KV, 30.0],
            play: play.map(|b| b * UM),
            spike: [(0.0, 0.0); 2],
            centre: [20.0 * UM, -12.0 * UM],
        };
        let table = independent_trace(&drive, *feed, seed as u64 + 21);
        let d = diagnose(&table, *feed);
        problems.extend(check(
            &format!("independent {feed} mm/min"),
            &d,
            drive.play,
            drive.spike,
            0.0,
        ));
    }
    assert!(problems.is_empty(), "{}", problems.join("\n"));
}

#[test]
fn real_play_and_a_spike_from_an_independent_simulator_are_told_apart() {
    let spike = SPIKES;
    let mut problems = Vec::new();
    for (seed, (feed, play)) in PLAYS.iter().enumerate() {
        let drive = Drive {
            kv: [DEFAULT_KV, DEFAULT_KV],
            play: play.map(|b| b * UM),
            spike,
            centre: [20.0 * UM, -12.0 * UM],
        };
        let table = independent_trace(&drive, *feed, seed as u64 + 31);
        let d = diagnose(&table, *feed);
        problems.extend(check(
            &format!("independent + spike {feed} mm/min"),
            &d,
            drive.play,
            spike,
            spike_tolerance(spike[0].1.min(spike[1].1)),
        ));
    }
    assert!(problems.is_empty(), "{}", problems.join("\n"));
}

#[test]
fn clean_traces_leave_residuals_at_the_noise_at_every_feed() {
    // No fault but a 20 µm set-up offset: the independent simulator's angles are the
    // command's, 1/Kv (30 ms) ahead of the axes, which turns the offset by v/(R·Kv) in
    // opposite directions in the two senses (0.2 µm at 2000 mm/min); the twin's are the axes'.
    let twin = twin(&[]);
    let mut problems = Vec::new();
    for (k, feed) in FEEDS.iter().enumerate() {
        let drive = Drive {
            kv: [DEFAULT_KV, DEFAULT_KV],
            play: [0.0; 2],
            spike: [(0.0, 0.0); 2],
            centre: [20.0 * UM, -12.0 * UM],
        };
        let tables = [
            (
                "independent",
                independent_trace(&drive, *feed, k as u64 + 41),
            ),
            (
                "twin",
                twin_trace(&twin, &Servo::default(), *feed, k as u64 + 51),
            ),
        ];
        for (what, table) in tables {
            let d = diagnose(&table, *feed);
            let ratio = d.rms / NOISE;
            println!(
                "clean {what} {feed} mm/min: residual {ratio:.3} × the noise, angle lag {:.2} ms",
                d.fit.shape.angle_lag * 1e3
            );
            if ratio > RESIDUAL_MULTIPLE {
                problems.push(format!("clean {what} {feed}: residual {ratio:.3} × noise"));
            }
            for term in [
                Term::BacklashP,
                Term::BacklashQ,
                Term::ReversalSpikeP,
                Term::ReversalSpikeQ,
            ] {
                let v = value(&d, term);
                if v.abs() >= NO_SPIKE {
                    problems.push(format!("clean {what} {feed}: {term:?} {} µm", v / UM));
                }
            }
        }
    }
    assert!(problems.is_empty(), "{}", problems.join("\n"));
}

#[test]
fn lost_motion_as_a_half_step_is_still_read_as_a_step() {
    // Today's twin: the error model's reversal term, an instantaneous half-step. The fit
    // keeps the step (play column 0) and recovers it within 5 %, no spike.
    let mut problems = Vec::new();
    for (seed, (feed, play)) in PLAYS.iter().enumerate() {
        let play = play.map(|b| b * UM);
        let twin = twin(&[
            ("EXX", ErrorFunction::Reversal(play[0])),
            ("EYY", ErrorFunction::Reversal(play[1])),
        ]);
        let table = twin_trace(&twin, &Servo::default(), *feed, seed as u64 + 61);
        let d = diagnose(&table, *feed);
        problems.extend(check(
            &format!("half-step {feed} mm/min"),
            &d,
            play,
            [(0.0, 0.0); 2],
            0.0,
        ));
        if d.fit.shape.play != [0.0; 2] {
            problems.push(format!(
                "half-step {feed}: the fit drew play {:?}",
                d.fit.shape.play
            ));
        }
    }
    assert!(problems.is_empty(), "{}", problems.join("\n"));
}

/// The drive of the lag coverage checks: real play of `play` (m) on both axes, no spike, the
/// Kv of the other tests.
fn play_drive(play: Real) -> Drive {
    Drive {
        kv: [DEFAULT_KV, 30.0],
        play: [play, play],
        spike: [(0.0, 0.0); 2],
        centre: [20.0 * UM, -12.0 * UM],
    }
}

/// The reported reversal lags of `play` (m) under `noise` (m) at 1000 mm/min over `seeds`,
/// each as (seed, axis, lag, u, its distance from the truth in u). The truth is the motor's
/// reversal, 1/Kv after the programmed one in the trace's angles (stamped from the command):
/// at 2 µm of play and 0.1 µm of noise the analysis gives 30.26 ± 0.39 and 33.52 ± 0.38 ms
/// for 30 and 33.33 ms (seed 1).
fn play_lags(
    play: Real,
    noise: Real,
    seeds: std::ops::RangeInclusive<u64>,
) -> Vec<(u64, usize, Real, Real, Real)> {
    let drive = play_drive(play);
    let mut lags = Vec::new();
    for seed in seeds {
        let table = noisy_independent_trace(&drive, 1000.0, seed, noise);
        let d = diagnose(&table, 1000.0);
        for (axis, lag) in d.reversal_lag.iter().enumerate() {
            if let Some((lag, u)) = *lag {
                let z = (lag - 1.0 / drive.kv[axis]).abs() / u;
                lags.push((seed, axis, lag, u, z));
            }
        }
    }
    lags
}

/// The reversal lag's u holds when the lost motion is real play (the other mechanism from the
/// step `tests/it/iso230_4.rs` simulates): 0.6 µm under 0.3 µm of noise, seeds 1 to 10. No lag
/// may be more than 3 u off (before the other mechanism's set was joined up to twice the
/// change-point bound, seed 2 gave x 45.67 ± 0.40 ms for 30 ms), and at most 2 of 20 beyond
/// 2 u (binomial probability 7.5 % at 95 % coverage).
#[test]
fn reversal_lag_u_covers_real_play_at_low_signal_to_noise() {
    let lags = play_lags(0.6 * UM, 0.3 * UM, 1..=10);
    assert_eq!(lags.len(), 20, "every lag located: {lags:?}");
    let beyond = |k: Real| lags.iter().filter(|l| l.4 > k).collect::<Vec<_>>();
    assert!(beyond(3.0).is_empty(), "{:?}", beyond(3.0));
    assert!(beyond(2.0).len() <= 2, "{:?}", beyond(2.0));
}

/// A measurement, not a check: how often the reported reversal lag misses the motor's reversal
/// by more than 2 and 3 of its u, for real play of 0.4, 0.6 and 1 µm under 0.3 µm of noise,
/// seeds 1–40 and 41–80 (80 lags each). Measured 2026-11-30, beyond 2 u (3 u), seeds 1–40 then
/// 41–80, with the other mechanism's set joined within one change-point bound (7.35·σ̂²):
/// 0.4 µm 1 (0), 2 (2); 0.6 µm 2 (2), 2 (2); 1 µm 0 (0), 1 (1); within twice it, as
/// `locate_lag` does: none of 480. Median u 10.0, 10.1 and 11.1 ms (8.4–9.5 before). Run with
/// `--ignored --nocapture`.
#[test]
#[ignore = "a measurement of the reversal lag's coverage with real play (about a minute in the test profile): run on purpose"]
fn reversal_lag_coverage_with_real_play() {
    for play in [0.4, 0.6, 1.0] {
        for seeds in [1..=40, 41..=80] {
            let lags = play_lags(play * UM, 0.3 * UM, seeds.clone());
            let mut us: Vec<Real> = lags.iter().map(|l| l.3).collect();
            us.sort_by(Real::total_cmp);
            let mut zs: Vec<Real> = lags.iter().map(|l| l.4).collect();
            zs.sort_by(Real::total_cmp);
            let beyond = |k: Real| lags.iter().filter(|l| l.4 > k).count();
            println!(
                "play {play} µm, seeds {seeds:?}: {} located, {} beyond 2 u, {} beyond 3 u, median u {:.2} ms, 95th percentile of |error|/u {:.2}",
                lags.len(),
                beyond(2.0),
                beyond(3.0),
                us.get(us.len() / 2).copied().unwrap_or(Real::NAN) * 1e3,
                zs.get(zs.len() * 95 / 100).copied().unwrap_or(Real::NAN)
            );
        }
    }
}

//! The programme timeline against hand timings: moves (per-axis speeds along a straight
//! line), dwells, warm-up cycles, spindle speed, measurement events and interval splitting.

use mtwin::machine::{Axis, AxisValues, Direction};
use mtwin::program::Approach;
use mtwin::program::{Event, MeasurePoint, Program, Step, visits};

fn intervals(timeline: &[Event]) -> Vec<(f64, AxisValues, f64)> {
    timeline
        .iter()
        .filter_map(|e| match e {
            Event::Interval(i) => Some((i.duration, i.speed, i.spindle)),
            Event::Measure(_) => None,
        })
        .collect()
}

#[test]
fn a_diagonal_move_splits_its_speed_between_the_axes() {
    // From (0, 0) to (0.3, 0.4) m at 0.05 m/s: 0.5 m in 10 s, X at 0.03 and Y at 0.04 m/s;
    // with intervals of at most 4 s: three of 10/3 s.
    let program = Program {
        start: AxisValues::ZERO,
        steps: vec![Step::Move {
            to: vec![(Axis::X, 0.3), (Axis::Y, 0.4)],
            feed: 0.05,
        }],
    };
    let pieces = intervals(&program.timeline(4.0));
    assert_eq!(pieces.len(), 3);
    for (duration, speed, _) in &pieces {
        assert!((duration - 10.0 / 3.0).abs() < 1e-12);
        assert!((speed[Axis::X] - 0.03).abs() < 1e-15 && (speed[Axis::Y] - 0.04).abs() < 1e-15);
        assert_eq!(speed[Axis::Z], 0.0);
    }
}

#[test]
fn a_warm_up_cycle_runs_at_its_feed_and_returns_home() {
    // X at 0.1 m; warm-up between 0 and 0.75 m at 0.08 m/s for 600 s: lead-in 0.1 m (1.25 s),
    // 48 m of running = 32 full back-and-forth strokes of 1.5 m, ending at 0; back home 0.1 m
    // (1.25 s). Total 602.5 s at 0.08 m/s; the last motion is positive. Then a dwell with the
    // spindle at 100 rad/s and a measurement at 602.5 + 60 s.
    let mut start = AxisValues::ZERO;
    start[Axis::X] = 0.1;
    let point = MeasurePoint {
        run: 0,
        target: 0,
        approach: Approach::Up,
    };
    let program = Program {
        start,
        steps: vec![
            Step::WarmUp {
                axis: Axis::X,
                from: 0.0,
                to: 0.75,
                feed: 0.08,
                duration: 600.0,
            },
            Step::Spindle(100.0),
            Step::Dwell(60.0),
            Step::Measure(point),
        ],
    };
    let timeline = program.timeline(1000.0);
    let pieces = intervals(&timeline);
    assert_eq!(pieces.len(), 2);
    assert!((pieces[0].0 - 602.5).abs() < 1e-9 && (pieces[0].1[Axis::X] - 0.08).abs() < 1e-15);
    assert_eq!((pieces[1].0, pieces[1].2), (60.0, 100.0));
    let measured = visits(&timeline);
    assert_eq!(measured.len(), 1);
    assert!((measured[0].time - 662.5).abs() < 1e-9);
    assert_eq!(measured[0].point, point);
    assert_eq!(measured[0].state.position[Axis::X], 0.1);
    assert_eq!(measured[0].state.direction(Axis::X), Direction::Positive);
}

#[test]
fn the_drawn_path_follows_the_strokes_by_hand_and_meets_every_measurement() {
    // The warm-up above: at t = 1.25 + 5 s X has run 0.4 m up from 0 (0.4 m); at
    // t = 1.25 + 12.5 s it has run 1.0 m: to 0.75 and 0.25 back (0.5 m); after the
    // 602.5 s cycle and the 60 s dwell it stands at home (0.1 m); a diagonal move follows,
    // and the path ends when and where the measurement is taken.
    let mut start = AxisValues::ZERO;
    start[Axis::X] = 0.1;
    let program = Program {
        start,
        steps: vec![
            Step::WarmUp {
                axis: Axis::X,
                from: 0.0,
                to: 0.75,
                feed: 0.08,
                duration: 600.0,
            },
            Step::Dwell(60.0),
            Step::Move {
                to: vec![(Axis::X, 0.5), (Axis::Y, 0.3)],
                feed: 0.05,
            },
            Step::Measure(MeasurePoint {
                run: 0,
                target: 0,
                approach: Approach::Up,
            }),
        ],
    };
    let path = program.path(0.25);
    let at = |t: f64| {
        path.iter()
            .find(|(time, _)| (time - t).abs() < 1e-9)
            .map(|(_, p)| *p)
            .unwrap_or_else(|| panic!("no sample at {t} s"))
    };
    assert!((at(0.0)[Axis::X] - 0.1).abs() < 1e-12);
    assert!((at(1.25)[Axis::X] - 0.0).abs() < 1e-12);
    assert!((at(6.25)[Axis::X] - 0.4).abs() < 1e-12);
    assert!((at(13.75)[Axis::X] - 0.5).abs() < 1e-12);
    assert!((at(662.5)[Axis::X] - 0.1).abs() < 1e-12);
    // The diagonal move from (0.1, 0) to (0.5, 0.3): 0.5 m at 0.05 m/s, half-way at 5 s.
    let mid = at(667.5);
    assert!((mid[Axis::X] - 0.3).abs() < 1e-12 && (mid[Axis::Y] - 0.15).abs() < 1e-12);
    // Samples increase in time and end where the timeline ends, at the measured position.
    assert!(path.windows(2).all(|w| w[1].0 > w[0].0));
    let visit = visits(&program.timeline(1000.0))[0];
    let (end_time, end) = *path.last().expect("samples");
    assert!((end_time - visit.time).abs() < 1e-9);
    for axis in [Axis::X, Axis::Y, Axis::Z] {
        assert!((end[axis] - visit.state.position[axis]).abs() < 1e-12);
    }
}

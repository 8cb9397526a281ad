//! Clockwise and counter-clockwise runs of a rotary axis pooled into one evaluation (ISO 230-7
//! §6: tables are turned several times each way, "CW and CCW", and the synchronous and
//! asynchronous values taken over the rotations).
//!
//! **What it does.** For an axis other than the spindle `S` (§6 is for rotary tables and
//! heads; a spindle is tested one way, at three speeds, §5), each forward segment with a
//! backward segment of the same set-up and the opposite speed gives a pooled segment: every
//! test seen in both has its backward revolutions laid back out on the axis angle (a backward
//! record is laid out on the angle travelled, `2π − θ`, so its sample `m` is at axis angle
//! `θ_{(M − m) mod M}`) and appended to the forward ones, and the whole is scored as one
//! record. A direction-dependent motion (a reversal error of the drive, a table lifting one
//! way) then shows as asynchronous motion, bounded by the band between the two senses; the
//! per-direction segments stay in the report beside it.
//!
//! **Left out.** Partial rotations of swivelling heads (`analyze spindle` refuses partial
//! arcs) and the choice between pooling and per-direction values, which the standard leaves to
//! the test's purpose: both are reported.

use super::{Candidate, EvaluateError, Options, Segment, score, uncertainty};
use crate::kinds::spindle::analysis::motion::{Direction, Grid, Revolutions};
use crate::kinds::spindle::record::SpindleRecord;
use crate::machine::Axis;

/// The label a pooled segment's set-up carries.
pub const BOTH_SENSES: &str = "both senses";

/// The forward revolutions of `forward` and the backward ones of `backward`, laid out on the
/// axis angle.
fn pooled_signal(forward: &Revolutions, backward: &Revolutions) -> Revolutions {
    let m = forward.samples_per_revolution();
    let mut values = forward.values().to_vec();
    for revolution in backward.values().chunks_exact(m) {
        values.extend((0..m).map(|i| revolution[(m - i) % m]));
    }
    Revolutions::new(m, values).expect("laid out like its runs")
}

/// The pooled segments of a record (module docs); none for a spindle.
pub(super) fn pooled(
    record: &SpindleRecord,
    segments: &[Segment],
    options: &Options,
) -> Result<Vec<Segment>, EvaluateError> {
    let mut out = Vec::new();
    if record.axis == Axis::S {
        return Ok(out);
    }
    for forward in segments.iter().filter(|s| s.speed > 0.0) {
        let Some(backward) = segments
            .iter()
            .find(|s| s.setup == forward.setup && s.speed == -forward.speed)
        else {
            continue;
        };
        let candidates: Vec<Candidate> = forward
            .tests
            .iter()
            .filter_map(|test| {
                let other = backward.tests.iter().find(|t| t.name == test.name)?;
                Some(Candidate {
                    name: test.name.clone(),
                    direction: test.direction,
                    sensing: test.sensing,
                    probes: test
                        .probes
                        .iter()
                        .map(|name| {
                            record
                                .probe(name)
                                .expect("a test's probes are the record's")
                        })
                        .collect(),
                    height: test.height,
                    signal: pooled_signal(&test.signal, &other.signal),
                })
            })
            .collect();
        let Some(first) = candidates.first() else {
            continue;
        };
        let m = first.signal.samples_per_revolution();
        let grid = Grid::new(m).map_err(|source| EvaluateError::Motion {
            test: first.name.clone(),
            source,
        })?;
        // Each radial probe's 1-UPR amplitude over both senses, for the budget's centring.
        let mut centrings = vec![0.0; record.probes.len()];
        for c in &candidates {
            if let ([i], Direction::Radial) = (c.probes.as_slice(), c.direction) {
                centrings[*i] = uncertainty::centring(&c.signal);
            }
        }
        let tests = candidates
            .into_iter()
            .map(|c| score(c, &record.probes, &centrings, &grid, options))
            .collect::<Result<Vec<_>, _>>()?;
        out.push(Segment {
            setup: if forward.setup.is_empty() {
                BOTH_SENSES.to_string()
            } else {
                format!("{} ({BOTH_SENSES})", forward.setup)
            },
            speed: forward.speed,
            revolutions: forward.revolutions + backward.revolutions,
            pooled: true,
            tests,
        });
    }
    Ok(out)
}

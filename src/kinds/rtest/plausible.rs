//! What an R-test table's own data say against its labels, as cautions for the report and
//! a problem `identify` refuses to compensate from: a test that repeats another reading for
//! reading ([`crate::io::plausible::copied_block`]: a test exported twice, or pasted under a
//! new name), one test in another unit, angles that read as radians in a table without
//! commanded positions, and one pose off the path the poses beside it trace (a chip on the
//! nest, a knock, a typo: [`lone_pose`]). (Whether an angle column is the tilting axis's or
//! the turntable's only the machine can say: `identify` checks every angle against its
//! joint's limits.)

use super::rows::{RtestRow, RtestTable};
use crate::io::plausible::{Block, copied_block, copy_sentence, spread};
use crate::math::{Real, trimmed};
use std::f64::consts::TAU;

/// The deviations of each test as blocks (x, y, z of every row, in file order).
pub fn test_blocks(table: &RtestTable) -> Vec<Block> {
    let mut blocks: Vec<Block> = Vec::new();
    for row in &table.rows {
        let label = format!("test \"{}\"", row.test);
        let index = match blocks.iter().position(|b| b.label == label) {
            Some(index) => index,
            None => {
                blocks.push(Block {
                    label,
                    readings: Vec::new(),
                });
                blocks.len() - 1
            }
        };
        blocks[index]
            .readings
            .extend([row.deviation.x, row.deviation.y, row.deviation.z]);
    }
    blocks
}

/// A test that repeats another reading for reading.
pub fn copied_test(table: &RtestTable) -> Option<String> {
    let blocks = test_blocks(table);
    copied_block(&blocks).map(|pair| copy_sentence(&blocks, pair))
}

/// How many times more or less than the other tests one may span before it reads as another
/// unit: 100. Tests of one machine differ (a full turn against a short swing), but not by a
/// factor of a hundred.
pub const ODD_TEST: Real = 100.0;

/// The smallest sweep (in the file's numbers) of some test that, with no angle beyond 2π,
/// makes a table read as radians: 1.5, i.e. 86° if radians. R-tests turn their axes through
/// tens of degrees or full turns; one whose every angle stays within ±6.283 "degrees" while
/// a test sweeps more than 1.5 of them is in radians.
pub const RADIAN_SWEEP: Real = 1.5;

/// Every caution for the R-test report of `table`: a copied test, and angles in radians
/// where no commanded positions let the reader refuse them
/// (the reader judges tables with `x_mm, y_mm, z_mm` itself).
pub fn cautions(table: &RtestTable) -> Vec<String> {
    let blocks = test_blocks(table);
    let mut found: Vec<String> = copied_block(&blocks)
        .map(|pair| copy_sentence(&blocks, pair))
        .into_iter()
        .collect();
    found.extend(
        crate::io::plausible::odd_block(&blocks, ODD_TEST)
            .map(|odd| crate::io::plausible::odd_sentence("dx_um, dy_um, dz_um", &blocks, odd)),
    );
    found.extend(radians_without_positions(table));
    found.extend(lone_pose(table));
    found.extend(misnamed_tests(table));
    found.extend(stuck_probes(table));
    found
}

/// The fewest poses of a test reading one deviation component bit for bit that read as a
/// stuck probe of the nest: 8 (and ten times the component's longest other rest). The
/// nest's probes read to 0.1 µm or better and the sphere moves between poses.
pub const STUCK_POSES: usize = 8;

/// A deviation component that holds one value through [`STUCK_POSES`] poses of a test: a
/// probe of the nest stuck, out of its range or disconnected.
fn stuck_probes(table: &RtestTable) -> Vec<String> {
    let mut found = Vec::new();
    for (name, rows) in table.tests() {
        for (c, column) in ["dx_um", "dy_um", "dz_um"].iter().enumerate() {
            let values: Vec<Real> = rows.iter().map(|r| r.deviation[c]).collect();
            if let Some((first, count)) = crate::io::plausible::stuck(&values, STUCK_POSES) {
                found.push(format!(
                    "test \"{name}\": `{column}` holds {} µm unchanged from pose {} to {} ({count} poses): a probe of the nest stuck, out of its range or disconnected? The test's path and fitted circle carry it",
                    trimmed(values[first] * 1e6, 4),
                    first + 1,
                    first + count
                ));
            }
        }
    }
    found
}

/// Tests whose name states an angle (`A-45`, `C0`: a letter of a rotary axis and a number, as
/// the twin and ISO 10791-6's K1…K4 names write them) that the table holds at another value
/// all through the test: names exchanged between tests, or the angle columns of another
/// table. The report's figures go under the names.
fn misnamed_tests(table: &RtestTable) -> Vec<String> {
    let mut found = Vec::new();
    let columns = ["a_deg", "b_deg", "c_deg"];
    for (name, rows) in table.tests() {
        for token in name.split([' ', '_', ',', '/']) {
            let mut chars = token.chars();
            let Some(axis) = chars.next().and_then(|c| "ABC".find(c)) else {
                continue;
            };
            let Ok(stated) = chars.as_str().parse::<Real>() else {
                continue;
            };
            let held: Vec<Real> = rows.iter().filter_map(|r| r.angles[axis]).collect();
            if held.len() != rows.len() || spread(held.iter().copied()) > 1e-9 {
                continue;
            }
            let read = held[0].to_degrees();
            if (read - stated).abs() > 0.5 {
                found.push(format!(
                    "test \"{name}\": its name says {token} but `{}` holds {} through the test: names exchanged between tests, or the axis zeroed elsewhere? Its figures are reported under that name",
                    columns[axis],
                    trimmed(read, 4)
                ));
            }
        }
    }
    found
}

/// The smallest step (m) off the path of its neighbours a pose must take to be named: 2 µm,
/// above the curvature an R-test path shows between poses 10° apart (its 15 µm radius bends
/// 0.2 µm there) and the noise of the nest's probes.
pub const SMALLEST_GLITCH: Real = 2e-6;

/// A pose off the path its two neighbours trace: the length of its deviation less their mean,
/// more than [`crate::io::plausible::LONE_READING`] times the robust scatter of that same
/// figure over every inner pose of every test, and more than [`SMALLEST_GLITCH`]. The path of
/// an R-test is smooth in the swept angle (error motions of a few harmonics), so the second
/// difference of the poses in file order is small everywhere but at a disturbed pose; poses
/// not in angle order only make every difference large and nothing is named.
pub fn lone_pose(table: &RtestTable) -> Option<String> {
    let mut steps: Vec<(&str, usize, Real)> = Vec::new();
    for (name, rows) in table.tests() {
        for k in 1..rows.len().saturating_sub(1) {
            let mean = (rows[k - 1].deviation + rows[k + 1].deviation) * 0.5;
            steps.push((name, k, (rows[k].deviation - mean).length()));
        }
    }
    let scale = 1.4826 * crate::io::plausible::median(steps.iter().map(|s| s.2).collect())?;
    let &(name, k, step) = steps.iter().max_by(|a, b| a.2.total_cmp(&b.2))?;
    (step > crate::io::plausible::LONE_READING * scale && step > SMALLEST_GLITCH).then(|| {
        format!(
            "test \"{name}\": pose {} in file order lies {} µm off the path its neighbours trace, more than {} times the poses' typical {} µm: a chip on the nest, a knock or a typo? It sets the test's range and its fitted circle",
            k + 1,
            trimmed(step * 1e6, 4),
            crate::io::plausible::LONE_READING,
            trimmed(scale * 1e6, 3)
        )
    })
}

fn radians_without_positions(table: &RtestTable) -> Option<String> {
    if table.rows.iter().any(|r| r.linear.is_some()) {
        return None;
    }
    let columns: Vec<usize> = (0..3)
        .filter(|&i| table.rows.iter().any(|r| r.angles[i].is_some()))
        .collect();
    let written = |r: &RtestRow, i: usize| r.angles[i].map(Real::to_degrees);
    let within = table.rows.iter().all(|r| {
        columns
            .iter()
            .all(|&i| written(r, i).is_none_or(|v| v.abs() <= TAU + 1e-6))
    });
    let mut tests: Vec<&str> = table.rows.iter().map(|r| r.test.as_str()).collect();
    tests.dedup();
    let widest = tests
        .iter()
        .flat_map(|test| {
            columns.iter().map(move |&i| {
                let values = table
                    .rows
                    .iter()
                    .filter(|r| r.test == *test)
                    .filter_map(|r| written(r, i));
                (test, i, spread(values))
            })
        })
        .max_by(|a, b| a.2.total_cmp(&b.2))?;
    let names = ["a_deg", "b_deg", "c_deg"];
    (within && widest.2 > RADIAN_SWEEP).then(|| {
        format!(
            "column `{}`: no angle of the table passes 2π = 6.283 while test \"{}\" sweeps {} of them: radians in the degree columns? (an R-test turns its axes through tens of degrees; without x_mm, y_mm, z_mm the reader cannot check)",
            names[widest.1],
            widest.0,
            trimmed(widest.2, 3)
        )
    })
}

/// How many standard errors the probes' response to `dz` must stand from zero in a test before
/// its sign is judged: 5.
pub const SIGN_EVIDENCE: Real = 5.0;

/// `dx_um, dy_um, dz_um` against the raw probe readings of the same rows. The nest's probes
/// all look at the sphere from the spindle side and read + when the sphere pushes them in, so
/// the sum of their readings falls as the tool rises from the sphere (+`dz`, tool relative to
/// the sphere): by Σ aᵢ·ẑ per µm, √3 for the three orthogonal probes of the usual nest, √3 + 1
/// with a fourth looking down, less with the head tilted. In each test the sum is fitted
/// against `dx, dy, dz` (least squares with an offset); when every test whose `dz` response
/// stands [`SIGN_EVIDENCE`] standard errors from zero (at least one) shows it rising, the
/// deviations and the probe readings are in opposite conventions: the deviations are the
/// sphere relative to the tool (every location error would come out with the opposite sign,
/// and a compensation from them would double the error), or the probes read + when they
/// extend. A test with the head swung through wide angles, or too little `dz` to show it, is
/// not judged; a table without probe columns cannot be.
pub fn sign_contradiction(table: &RtestTable) -> Option<String> {
    let mut judged = Vec::new();
    for (name, rows) in table.tests() {
        let rows: Vec<_> = rows.into_iter().filter(|r| !r.probes.is_empty()).collect();
        if rows.len() < 8 {
            continue;
        }
        let design = nalgebra::DMatrix::from_fn(rows.len(), 4, |i, k| match k {
            0 => 1.0,
            _ => rows[i].deviation[k - 1] * 1e6,
        });
        let sum = nalgebra::DVector::from_iterator(
            rows.len(),
            rows.iter().map(|r| r.probes.iter().sum::<Real>() * 1e6),
        );
        let normal = design.tr_mul(&design);
        let Some(inverse) = mtwin_kernels::linalg::try_inverse(normal.clone()) else {
            continue;
        };
        let fit = &inverse * design.tr_mul(&sum);
        let residual = &sum - &design * &fit;
        let variance = residual.norm_squared() / (rows.len() - 4) as Real;
        let error = (variance * inverse[(3, 3)]).sqrt();
        let slope = fit[3];
        if slope.abs() >= SIGN_EVIDENCE * error && error.is_finite() {
            judged.push((name, slope, error));
        }
    }
    let rising = judged.iter().filter(|(_, slope, _)| *slope > 0.0).count();
    (rising > 0 && rising == judged.len()).then(|| {
        let (name, slope, error) = &judged[0];
        format!(
            "the probes' readings rise with dz_um (test \"{name}\": their sum {} ± {} µm per µm of dz; the nest's probes look at the sphere from the spindle, so it falls, by √3 for three orthogonal probes): dx_um, dy_um, dz_um are the sphere relative to the tool (this table's are the tool relative to the sphere: negate them), or probe1_um… read + as the probe extends (negate those); every location error would come out with the opposite sign",
            trimmed(*slope, 3),
            trimmed(*error, 2)
        )
    })
}

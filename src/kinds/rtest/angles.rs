//! The angles' unit, checked against what the table itself says: while one rotary axis turns
//! under tool-centre-point control, the commanded linear positions (`x_mm`, `y_mm`, `z_mm`)
//! follow the sphere (or the tool's pivot) round a circle through the same angle. Angles in
//! radians in a `_deg` column (a 360° test written as 6.28) disagree with that circle by a
//! factor of 57.3, and are refused before any figure is formed from them.
//!
//! Tests without the linear columns, with more than one rotary axis turning, or whose
//! positions do not lie on a circle (the sphere on the axis, a pivot of zero length) carry no
//! such evidence and are not judged.

use super::rows::RtestRow;
use crate::io::TableError;
use crate::math::{M_PER_MM, Real, Vector, trimmed};

/// How far the angle the positions turn through may differ from the angles' own sweep: 5 %
/// and half a degree (commanded positions are exact to the controller's resolution, so this
/// only absorbs their rounding in the file).
const AGREEMENT: Real = 0.05;
const AGREEMENT_RAD: Real = 0.5 * std::f64::consts::PI / 180.0;

/// The smallest circle (radius) and bulge (the third pose's distance from the chord of the
/// other two) that say something: below them the positions hardly move.
const SMALLEST_RADIUS: Real = 1.0 * M_PER_MM;
const SMALLEST_BULGE: Real = 0.05 * M_PER_MM;

/// A step between two poses longer than this is not followed round its arc (the chord of a
/// half turn is ambiguous).
const LONGEST_STEP_RAD: Real = 170.0 * std::f64::consts::PI / 180.0;

/// Checks each test of `rows` (lines: each row's line in `file`) as the module says.
pub(super) fn check(
    rows: &[RtestRow],
    lines: &[Option<u64>],
    file: &str,
) -> Result<(), TableError> {
    let mut start = 0;
    while start < rows.len() {
        let end = start
            + rows[start..]
                .iter()
                .take_while(|r| r.test == rows[start].test)
                .count();
        check_test(&rows[start..end], lines[start], file)?;
        start = end;
    }
    Ok(())
}

fn check_test(rows: &[RtestRow], line: Option<u64>, file: &str) -> Result<(), TableError> {
    let Some(positions) = rows
        .iter()
        .map(|r| r.linear)
        .collect::<Option<Vec<Vector>>>()
    else {
        return Ok(());
    };
    // The one rotary axis that turns.
    let turning: Vec<usize> = (0..3)
        .filter(|&k| {
            let values: Vec<Real> = rows.iter().filter_map(|r| r.angles[k]).collect();
            values.len() == rows.len() && values.iter().any(|v| (v - values[0]).abs() > 1e-9)
        })
        .collect();
    let [k] = turning[..] else {
        return Ok(());
    };
    let angles: Vec<Real> = rows.iter().map(|r| r.angles[k].unwrap_or(0.0)).collect();
    let steps: Vec<Real> = angles.windows(2).map(|w| (w[1] - w[0]).abs()).collect();
    if steps.iter().any(|s| *s > LONGEST_STEP_RAD) {
        return Ok(());
    }
    let Some((centre, radius)) = circle(&positions) else {
        return Ok(());
    };
    // Every pose on that circle (1 % of its radius): otherwise the linear axes do more than
    // follow the rotary one.
    if positions
        .iter()
        .any(|p| ((*p - centre).length() - radius).abs() > 0.01 * radius)
    {
        return Ok(());
    }
    let turned: Real = positions
        .windows(2)
        .map(|w| 2.0 * ((w[1] - w[0]).length() / (2.0 * radius)).min(1.0).asin())
        .sum();
    let stated: Real = steps.iter().sum();
    if (turned - stated).abs() <= AGREEMENT * turned.max(stated) + AGREEMENT_RAD {
        return Ok(());
    }
    let column = ["a_deg", "b_deg", "c_deg"][k];
    let deg = |rad: Real| trimmed(rad.to_degrees(), 2);
    let as_radians = stated.to_degrees();
    let why = if (turned - as_radians).abs() <= AGREEMENT * turned.max(as_radians) + AGREEMENT_RAD {
        format!(
            "`{column}` holds radians (read as radians, it turns {}°)",
            deg(as_radians)
        )
    } else {
        "the angles and the positions are not of the same test, or one is in another unit".into()
    };
    Err(TableError::new(
        file,
        line,
        format!(
            "test \"{}\": the commanded positions x_mm, y_mm, z_mm turn through {}° round a circle of radius {} mm, but `{column}` turns through {}°: {why}",
            rows[0].test,
            deg(turned),
            trimmed(radius / M_PER_MM, 3),
            deg(stated)
        ),
    ))
}

/// The circle (centre, radius) through the first pose, the one farthest from it and the one
/// farthest from the chord between them; `None` when the positions hardly move or lie on a
/// line.
fn circle(positions: &[Vector]) -> Option<(Vector, Real)> {
    let a = positions[0];
    let b = *positions
        .iter()
        .max_by(|p, q| (**p - a).length().total_cmp(&(**q - a).length()))?;
    let ab = b - a;
    let bulge = |p: &Vector| ab.cross(*p - a).length() / ab.length().max(Real::MIN_POSITIVE);
    let c = *positions
        .iter()
        .max_by(|p, q| bulge(p).total_cmp(&bulge(q)))?;
    if bulge(&c) < SMALLEST_BULGE {
        return None;
    }
    let ac = c - a;
    let normal = ab.cross(ac);
    let centre = a
        + (normal.cross(ab) * ac.length_squared() + ac.cross(normal) * ab.length_squared())
            / (2.0 * normal.length_squared());
    let radius = (a - centre).length();
    (radius >= SMALLEST_RADIUS).then_some((centre, radius))
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Poses of a test turning C from 0 to `sweep_deg` in `n` steps, the sphere 150 mm from
    /// the axis at (10, 20, 30) mm, angles written as `written(deg)`.
    fn test(sweep_deg: Real, n: usize, written: impl Fn(Real) -> Real) -> Vec<RtestRow> {
        (0..=n)
            .map(|i| {
                let deg = sweep_deg * i as Real / n as Real;
                let (s, c) = deg.to_radians().sin_cos();
                let p = Vector::new(10.0 + 150.0 * c, 20.0 + 150.0 * s, 30.0) * M_PER_MM;
                RtestRow {
                    test: "c360".into(),
                    point: Some(i),
                    time: None,
                    angles: [Some(0.0), None, Some(written(deg).to_radians())],
                    linear: Some(p),
                    deviation: Vector::ZERO,
                    probes: Vec::new(),
                }
            })
            .collect()
    }

    #[test]
    fn the_circle_through_three_poses_is_the_one_they_lie_on() {
        let rows = test(90.0, 6, |d| d);
        let positions: Vec<Vector> = rows.iter().map(|r| r.linear.unwrap()).collect();
        let (centre, radius) = circle(&positions).unwrap();
        assert!((centre - Vector::new(0.010, 0.020, 0.030)).length() < 1e-12);
        assert!((radius - 0.150).abs() < 1e-12);
    }

    #[test]
    fn degrees_pass_and_radians_are_named() {
        let lines = vec![Some(2); 13];
        assert!(check(&test(360.0, 12, |d| d), &lines, "t.csv").is_ok());
        assert!(check(&test(90.0, 12, |d| d), &lines, "t.csv").is_ok());
        // 360° written as 6.283: the positions turn 57.3 times further than the column.
        let error = check(&test(360.0, 12, |d| d.to_radians()), &lines, "t.csv")
            .unwrap_err()
            .to_string();
        assert!(error.starts_with("t.csv:2: test \"c360\""), "{error}");
        assert!(
            error.contains(
                "turn through 360° round a circle of radius 150 mm, but `c_deg` turns through 6.28°"
            ),
            "{error}"
        );
        assert!(error.contains("`c_deg` holds radians"), "{error}");
        // Another factor is named as a disagreement, not as radians.
        let error = check(&test(90.0, 12, |d| d / 2.0), &lines, "t.csv")
            .unwrap_err()
            .to_string();
        assert!(error.contains("not of the same test"), "{error}");
    }

    #[test]
    fn tests_without_evidence_are_not_judged() {
        let lines = vec![Some(2); 13];
        // No linear columns.
        let mut rows = test(360.0, 12, |d| d.to_radians());
        rows.iter_mut().for_each(|r| r.linear = None);
        assert!(check(&rows, &lines, "t.csv").is_ok());
        // The sphere on the axis: the positions do not move.
        let mut rows = test(360.0, 12, |d| d.to_radians());
        rows.iter_mut().for_each(|r| r.linear = Some(Vector::ZERO));
        assert!(check(&rows, &lines, "t.csv").is_ok());
    }
}

//! The R-test plot (SVG): per test, the tool's deviation relative to the sphere against the
//! swept angle, one curve per direction (X, Y, Z), and the XY trajectory of the deviation
//! enlarged, as R-test software draws it.

use super::table::RtestTable;
use crate::machine::Axis;
use crate::math::{M_PER_UM, Real};
use std::fmt::Write;

const PANEL_W: Real = 420.0;
const PANEL_H: Real = 260.0;
const MARGIN: Real = 46.0;
const COLOURS: [&str; 3] = ["#d62728", "#2ca02c", "#1f77b4"];

/// The SVG document for every test of `table`: one row of two panels per test.
pub fn svg(table: &RtestTable) -> String {
    let tests = table.tests();
    let width = 2.0 * (PANEL_W + 2.0 * MARGIN);
    let height = tests.len() as Real * (PANEL_H + 2.0 * MARGIN);
    let mut out = format!(
        "<svg xmlns=\"http://www.w3.org/2000/svg\" width=\"{width}\" height=\"{height}\" \
         font-family=\"sans-serif\" font-size=\"11\">\n<rect width=\"100%\" height=\"100%\" fill=\"white\"/>\n"
    );
    for (row, (name, rows)) in tests.iter().enumerate() {
        let top = row as Real * (PANEL_H + 2.0 * MARGIN) + MARGIN;
        let swept = [Axis::A, Axis::B, Axis::C]
            .into_iter()
            .filter(|a| rows.iter().all(|r| r.angle(*a).is_some()))
            .max_by(|a, b| span(rows, *a).total_cmp(&span(rows, *b)));
        let theta: Vec<Real> = match swept {
            Some(axis) => rows
                .iter()
                .map(|r| r.angle(axis).unwrap_or(0.0).to_degrees())
                .collect(),
            None => (0..rows.len()).map(|i| i as Real).collect(),
        };
        let label = swept.map_or("pose".to_string(), |a| format!("{a} (deg)"));
        let values: Vec<[Real; 3]> = rows
            .iter()
            .map(|r| (r.deviation / M_PER_UM).to_array())
            .collect();
        // Left: deviation against the angle.
        let (t_lo, t_hi) = bounds(theta.iter().copied());
        let (v_lo, v_hi) = bounds(values.iter().flatten().copied());
        let left = MARGIN;
        let _ = writeln!(
            out,
            "<text x=\"{left}\" y=\"{}\" font-weight=\"bold\">{} — deviation of the tool relative to the sphere (µm) vs {label}</text>",
            top - 12.0,
            escape(name)
        );
        frame(&mut out, left, top, (t_lo, t_hi), (v_lo, v_hi));
        for (j, colour) in COLOURS.iter().enumerate() {
            let points: Vec<(Real, Real)> = theta
                .iter()
                .zip(&values)
                .map(|(t, v)| {
                    (
                        scale(*t, t_lo, t_hi, left, left + PANEL_W),
                        scale(v[j], v_lo, v_hi, top + PANEL_H, top),
                    )
                })
                .collect();
            polyline(&mut out, &points, colour);
            let _ = writeln!(
                out,
                "<text x=\"{}\" y=\"{}\" fill=\"{colour}\">{}</text>",
                left + PANEL_W - 60.0 + 20.0 * j as Real,
                top + 14.0,
                ["X", "Y", "Z"][j]
            );
        }
        // Right: the XY trajectory, equal scales.
        let left = 3.0 * MARGIN + PANEL_W;
        let half = values
            .iter()
            .flat_map(|v| [v[0].abs(), v[1].abs()])
            .fold(0.0, Real::max)
            .max(0.01)
            * 1.1;
        let side = PANEL_H;
        let _ = writeln!(
            out,
            "<text x=\"{left}\" y=\"{}\">XY trajectory (µm, equal scales)</text>",
            top - 12.0
        );
        frame(&mut out, left, top, (-half, half), (-half, half));
        let points: Vec<(Real, Real)> = values
            .iter()
            .map(|v| {
                (
                    scale(v[0], -half, half, left, left + side),
                    scale(v[1], -half, half, top + side, top),
                )
            })
            .collect();
        polyline(&mut out, &points, "#444");
    }
    out += "</svg>\n";
    out
}

fn span(rows: &[&super::table::RtestRow], axis: Axis) -> Real {
    let (lo, hi) = bounds(rows.iter().filter_map(|r| r.angle(axis)));
    hi - lo
}

fn bounds(values: impl Iterator<Item = Real>) -> (Real, Real) {
    let (lo, hi) = values.fold((Real::INFINITY, Real::NEG_INFINITY), |(lo, hi), v| {
        (lo.min(v), hi.max(v))
    });
    if !(lo.is_finite() && hi.is_finite()) {
        return (0.0, 1.0);
    }
    let pad = ((hi - lo) * 0.05).max(0.01);
    (lo - pad, hi + pad)
}

fn scale(v: Real, lo: Real, hi: Real, to_lo: Real, to_hi: Real) -> Real {
    to_lo + (v - lo) / (hi - lo) * (to_hi - to_lo)
}

/// The panel's box with its axis limits written at the corners.
fn frame(out: &mut String, left: Real, top: Real, x: (Real, Real), y: (Real, Real)) {
    let width = if (x.0 + x.1).abs() < 1e-12 && (y.0 + y.1).abs() < 1e-12 {
        PANEL_H
    } else {
        PANEL_W
    };
    let _ = writeln!(
        out,
        "<rect x=\"{left}\" y=\"{top}\" width=\"{width}\" height=\"{PANEL_H}\" fill=\"none\" stroke=\"#999\"/>"
    );
    let _ = writeln!(
        out,
        "<text x=\"{left}\" y=\"{}\">{:.2}</text><text x=\"{}\" y=\"{}\" text-anchor=\"end\">{:.2}</text>",
        top + PANEL_H + 14.0,
        x.0,
        left + width,
        top + PANEL_H + 14.0,
        x.1
    );
    let _ = writeln!(
        out,
        "<text x=\"{}\" y=\"{}\" text-anchor=\"end\">{:.2}</text><text x=\"{}\" y=\"{}\" text-anchor=\"end\">{:.2}</text>",
        left - 4.0,
        top + PANEL_H,
        y.0,
        left - 4.0,
        top + 10.0,
        y.1
    );
}

fn polyline(out: &mut String, points: &[(Real, Real)], colour: &str) {
    let coordinates: Vec<String> = points
        .iter()
        .map(|(x, y)| format!("{x:.2},{y:.2}"))
        .collect();
    let _ = writeln!(
        out,
        "<polyline fill=\"none\" stroke=\"{colour}\" stroke-width=\"1.5\" points=\"{}\"/>",
        coordinates.join(" ")
    );
}

fn escape(text: &str) -> String {
    text.replace('&', "&amp;")
        .replace('<', "&lt;")
        .replace('>', "&gt;")
}

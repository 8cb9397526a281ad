//! Plots of spindle records as SVG a person can open in a browser, written by hand (no
//! dependency): the error motion polar plot (ISO 230-7 §3.6), line charts (a value against
//! speed or time) and the spectrum (synchronous and asynchronous lines).
//!
//! Coordinates are written with one decimal (pixels, about 4 significant digits), so a plot of
//! many revolutions stays compact.
//!
//! # The polar plot's geometry
//!
//! The document is 900 × 600 px; the plot's centre is at (300, 310) px, θ counter-clockwise from
//! the right (+x), y of the page downward: a point at radius `R` and angle θ is drawn at
//! `(300 + R cos θ, 310 − R sin θ)`. A value `v` (m) at angle θ is drawn about the centre
//! `offset = (cx, cy)` in the limaçon sense, as its residual `ρ = v − cx cos θ − cy sin θ`
//! (ISO 230-7 §3.7), at the radius `R = r0 + scale·ρ`. The band `[lo, hi]` — the least and
//! greatest residual of all curves and of `bounds`, in µm — is drawn between 160 px and 240 px,
//! the outer third of the plot: `R = 160 + 80·(ρ − lo)/(hi − lo)` with ρ in µm (a band of no
//! width is widened by 5 % of its size each way). Rings mark the multiples of a step of 1, 2
//! or 5 × 10ⁿ µm within the band (the smallest step giving at most 5 steps across it). r0 is
//! only cosmetic (ISO 230-7 §5.3.2.3) and no value depends on it.

use crate::math::{M_PER_UM, Real};
use std::f64::consts::TAU;
use std::fmt::Write;

/// One curve of a polar plot: values at angles, drawn in one colour.
#[derive(Clone, Copy, Debug)]
pub struct PolarCurve<'a> {
    /// Its name in the legend.
    pub label: &'a str,
    /// The angles (rad), counter-clockwise; a revolution ends where the angle stops increasing,
    /// so a total plot (K revolutions × M angles) is one curve.
    pub angles: &'a [Real],
    /// The values (m), one per angle; pairs beyond the shorter slice are ignored, and pairs that
    /// are not finite are skipped.
    pub values: &'a [Real],
    /// The SVG colour of its stroke (`#1f77b4`, `black`, …).
    pub stroke: &'a str,
    /// The stroke's width (px).
    pub width: Real,
}

const POLAR_W: Real = 900.0;
const POLAR_H: Real = 600.0;
const CENTRE: (Real, Real) = (300.0, 310.0);
const R_INNER: Real = 160.0;
const R_OUTER: Real = 240.0;
const COLOURS: [&str; 6] = [
    "#1f77b4", "#d62728", "#2ca02c", "#ff7f0e", "#9467bd", "#8c564b",
];

/// A polar error-motion plot: radius = r0 + scale·(value − centre residual), drawn about the
/// centre `offset` (cx, cy) in the limaçon sense ρ = v − cx cosθ − cy sinθ; two concentric
/// circles at the min and max of the `bounds` curve (the value), axis labels in µm, a legend
/// with label and value text lines.
///
/// `offset` and `bounds` are in m (the least and greatest residual of the curve the value is
/// read from, about `offset`); `notes` are text lines under the legend (the values). Each curve
/// is drawn as one `<polyline>` per revolution with two points or more; a single revolution
/// that goes round the circle is closed, and a revolution followed by another is joined to the
/// next one's first point. Rings mark the band in µm, spokes every 30°, and the two `bounds`
/// circles are dashed; the legend also states the centre, the bounds and their difference. The geometry is in the
/// [module documentation](self).
pub fn polar_svg(
    title: &str,
    curves: &[PolarCurve<'_>],
    offset: [Real; 2],
    bounds: (Real, Real),
    notes: &[String],
) -> String {
    let residual = |theta: Real, v: Real| v - offset[0] * theta.cos() - offset[1] * theta.sin();
    // The curves' finite points, revolution by revolution, as (θ, ρ in µm).
    let revolutions: Vec<Vec<Vec<(Real, Real)>>> = curves
        .iter()
        .map(|curve| {
            let mut out: Vec<Vec<(Real, Real)>> = Vec::new();
            let mut last = Real::NEG_INFINITY;
            for (&theta, &v) in curve.angles.iter().zip(curve.values) {
                let rho = residual(theta, v) / M_PER_UM;
                if theta <= last || out.is_empty() {
                    out.push(Vec::new());
                }
                if theta.is_finite() {
                    last = theta;
                }
                if theta.is_finite()
                    && rho.is_finite()
                    && let Some(revolution) = out.last_mut()
                {
                    revolution.push((theta, rho));
                }
            }
            out.retain(|r| !r.is_empty());
            out
        })
        .collect();
    let bound_um = [bounds.0 / M_PER_UM, bounds.1 / M_PER_UM];
    let (lo, hi) = extent(
        revolutions
            .iter()
            .flatten()
            .flatten()
            .map(|(_, rho)| *rho)
            .chain(bound_um),
    );
    let (lo, hi) = widened(lo, hi);
    let step = nice_step((hi - lo) / 5.0);
    let radius = |rho: Real| R_INNER + (R_OUTER - R_INNER) * (rho - lo) / (hi - lo);
    let at = |r: Real, theta: Real| (CENTRE.0 + r * theta.cos(), CENTRE.1 - r * theta.sin());

    let mut out = header(POLAR_W, POLAR_H, title);
    let (cx, cy) = CENTRE;
    // Spokes and angle labels.
    for k in 0..12 {
        let theta = k as Real * TAU / 12.0;
        let (x, y) = at(R_OUTER + 6.0, theta);
        let (tx, ty) = at(R_OUTER + 20.0, theta);
        let _ = writeln!(
            out,
            "<line x1=\"{cx:.1}\" y1=\"{cy:.1}\" x2=\"{x:.1}\" y2=\"{y:.1}\" stroke=\"#e4e4e4\"/>\
             <text x=\"{tx:.1}\" y=\"{:.1}\" text-anchor=\"middle\" fill=\"#666\">{}°</text>",
            ty + 4.0,
            k * 30
        );
    }
    // Rings with their values (µm) on the upward spoke.
    let decimals = decimals(step);
    let first = (lo / step - 1e-9).ceil() as i64;
    let last = (hi / step + 1e-9).floor() as i64;
    for k in first..=last {
        let value = k as Real * step;
        let r = radius(value);
        let _ = writeln!(
            out,
            "<circle cx=\"{cx:.1}\" cy=\"{cy:.1}\" r=\"{r:.1}\" fill=\"none\" stroke=\"#ccc\"/>\
             <text x=\"{:.1}\" y=\"{:.1}\" font-size=\"9\" fill=\"#666\">{}</text>",
            cx + 3.0,
            cy - r - 2.0,
            fmt(value, decimals)
        );
    }
    let _ = writeln!(
        out,
        "<text x=\"{:.1}\" y=\"{:.1}\" font-size=\"9\" fill=\"#666\">ρ (µm)</text>",
        cx + 3.0,
        cy - R_OUTER - 34.0
    );
    // The centre, and the two circles of the value.
    let _ = writeln!(
        out,
        "<path d=\"M{:.1} {cy:.1}H{:.1}M{cx:.1} {:.1}V{:.1}\" stroke=\"#444\"/>",
        cx - 5.0,
        cx + 5.0,
        cy - 5.0,
        cy + 5.0
    );
    for b in bound_um.iter().filter(|b| b.is_finite()) {
        let _ = writeln!(
            out,
            "<circle cx=\"{cx:.1}\" cy=\"{cy:.1}\" r=\"{:.1}\" fill=\"none\" stroke=\"#000\" stroke-dasharray=\"4 3\"/>",
            radius(*b)
        );
    }
    // The curves.
    for (curve, revs) in curves.iter().zip(&revolutions) {
        let closes = revs.len() == 1 && goes_round(&revs[0]);
        for (k, revolution) in revs.iter().enumerate() {
            let mut points: Vec<(Real, Real)> = revolution.clone();
            if closes {
                points.push(revolution[0]);
            } else if let Some(next) = revs.get(k + 1) {
                points.push(next[0]);
            }
            if points.len() < 2 {
                continue;
            }
            let xy: Vec<(Real, Real)> = points
                .iter()
                .map(|(theta, rho)| at(radius(*rho), *theta))
                .collect();
            polyline(&mut out, &xy, curve.stroke, curve.width);
        }
    }
    // Legend.
    let left = 600.0;
    let mut y = 70.0;
    for curve in curves {
        legend_line(&mut out, left, y, curve.stroke, curve.width, curve.label);
        y += 18.0;
    }
    y += 8.0;
    let mut lines: Vec<String> = vec![
        format!(
            "centre: x {} µm, y {} µm",
            fmt(offset[0] / M_PER_UM, 3),
            fmt(offset[1] / M_PER_UM, 3)
        ),
        format!(
            "dashed circles: {} and {} µm",
            fmt(bound_um[0], 3),
            fmt(bound_um[1], 3)
        ),
        format!("their difference: {} µm", fmt(bound_um[1] - bound_um[0], 3)),
        format!("rings every {} µm", fmt(step, decimals)),
    ];
    lines.extend(notes.iter().cloned());
    for line in lines {
        let _ = writeln!(
            out,
            "<text x=\"{left}\" y=\"{y:.1}\">{}</text>",
            escape(&line)
        );
        y += 16.0;
    }
    out += "</svg>\n";
    out
}

/// Whether a revolution's angles, equally spaced, go round the circle.
fn goes_round(points: &[(Real, Real)]) -> bool {
    let n = points.len();
    if n < 3 {
        return false;
    }
    let span = points[n - 1].0 - points[0].0;
    span + span / (n - 1) as Real >= TAU * (1.0 - 1e-6)
}

const LINE_W: Real = 780.0;
const LINE_H: Real = 440.0;
/// The plotting area of line charts and spectra: left, top, width, height (px).
const AREA: (Real, Real, Real, Real) = (80.0, 50.0, 480.0, 320.0);

/// A line chart (e.g. error motion value against speed, or against time).
///
/// Each series `(label, points)` is one `<polyline>` (when it has two finite points or more),
/// with a dot at each point when it has 50 points or fewer, in the colours blue, red, green,
/// orange, purple, brown in turn. The axes run over the finite points rounded outward to a step
/// of 1, 2 or 5 × 10ⁿ (about 5 steps), the plotting area from (80, 50) to (560, 370) px: a
/// point (x, y) is drawn at `(80 + 480·(x − x_lo)/(x_hi − x_lo), 370 − 320·(y − y_lo)/(y_hi −
/// y_lo))`.
pub fn line_svg(
    title: &str,
    x_label: &str,
    y_label: &str,
    series: &[(&str, &[(Real, Real)])],
) -> String {
    let finite = |p: &&(Real, Real)| p.0.is_finite() && p.1.is_finite();
    let all = || series.iter().flat_map(|(_, s)| s.iter().filter(finite));
    let (x_lo, x_hi, x_step) = {
        let (lo, hi) = extent(all().map(|p| p.0));
        nice(lo, hi, 5.0)
    };
    let (y_lo, y_hi, y_step) = {
        let (lo, hi) = extent(all().map(|p| p.1));
        nice(lo, hi, 5.0)
    };
    let mut out = header(LINE_W, LINE_H, title);
    axes(
        &mut out,
        (x_lo, x_hi, x_step),
        (y_lo, y_hi, y_step),
        x_label,
        y_label,
    );
    let map = |(x, y): (Real, Real)| {
        let (left, top, w, h) = AREA;
        (
            left + w * (x - x_lo) / (x_hi - x_lo),
            top + h - h * (y - y_lo) / (y_hi - y_lo),
        )
    };
    let mut y = AREA.1 + 20.0;
    for (k, (label, points)) in series.iter().enumerate() {
        let colour = COLOURS[k % COLOURS.len()];
        let xy: Vec<(Real, Real)> = points.iter().filter(finite).map(|p| map(*p)).collect();
        if xy.len() >= 2 {
            polyline(&mut out, &xy, colour, 1.5);
        }
        if xy.len() <= 50 {
            for (x, y) in &xy {
                let _ = writeln!(
                    out,
                    "<circle cx=\"{x:.1}\" cy=\"{y:.1}\" r=\"2.5\" fill=\"{colour}\"/>"
                );
            }
        }
        legend_line(&mut out, AREA.0 + AREA.2 + 30.0, y, colour, 1.5, label);
        y += 18.0;
    }
    out += "</svg>\n";
    out
}

const SYNCHRONOUS: &str = "#1f77b4";
const ASYNCHRONOUS: &str = "#d62728";

/// A spectrum as bars: (cycles per revolution, amplitude µm, synchronous?) — synchronous and
/// asynchronous in two colours, labelled axis.
///
/// Each line with finite numbers is a `<line class="sync">` (blue) or `<line class="async">`
/// (red) from zero to its amplitude. The frequency axis runs from 0 to the highest frequency
/// rounded up, the amplitude axis from 0 (or the lowest amplitude, if negative) to the highest
/// rounded up, both to a step of 1, 2 or 5 × 10ⁿ, in the plotting area of [`line_svg`].
pub fn spectrum_svg(title: &str, lines: &[(Real, Real, bool)]) -> String {
    let finite: Vec<&(Real, Real, bool)> = lines
        .iter()
        .filter(|l| l.0.is_finite() && l.1.is_finite())
        .collect();
    let (x_lo, x_hi, x_step) = {
        let (lo, hi) = extent(finite.iter().map(|l| l.0).chain([0.0]));
        nice(lo, hi.max(lo + 1.0), 5.0)
    };
    let (y_lo, y_hi, y_step) = {
        let (lo, hi) = extent(finite.iter().map(|l| l.1).chain([0.0]));
        nice(lo, hi, 5.0)
    };
    let mut out = header(LINE_W, LINE_H, title);
    axes(
        &mut out,
        (x_lo, x_hi, x_step),
        (y_lo, y_hi, y_step),
        "cycles per revolution (UPR)",
        "amplitude (µm)",
    );
    let (left, top, w, h) = AREA;
    let px = |x: Real| left + w * (x - x_lo) / (x_hi - x_lo);
    let py = |y: Real| top + h - h * (y - y_lo) / (y_hi - y_lo);
    for (f, a, synchronous) in finite {
        let (class, colour) = if *synchronous {
            ("sync", SYNCHRONOUS)
        } else {
            ("async", ASYNCHRONOUS)
        };
        let x = px(*f);
        let _ = writeln!(
            out,
            "<line class=\"{class}\" x1=\"{x:.1}\" y1=\"{:.1}\" x2=\"{x:.1}\" y2=\"{:.1}\" stroke=\"{colour}\" stroke-width=\"2\"/>",
            py(0.0),
            py(*a)
        );
    }
    let x = left + w + 30.0;
    legend_line(&mut out, x, top + 20.0, SYNCHRONOUS, 2.0, "synchronous");
    legend_line(&mut out, x, top + 38.0, ASYNCHRONOUS, 2.0, "asynchronous");
    out += "</svg>\n";
    out
}

/// The document's opening: the root element, a white page and the title.
fn header(width: Real, height: Real, title: &str) -> String {
    format!(
        "<svg xmlns=\"http://www.w3.org/2000/svg\" width=\"{width}\" height=\"{height}\" \
         viewBox=\"0 0 {width} {height}\" font-family=\"sans-serif\" font-size=\"11\">\n\
         <rect width=\"100%\" height=\"100%\" fill=\"white\"/>\n\
         <text x=\"20\" y=\"28\" font-size=\"14\" font-weight=\"bold\">{}</text>\n",
        escape(title)
    )
}

/// The plotting area's frame, grid, tick labels and axis names.
fn axes(
    out: &mut String,
    (x_lo, x_hi, x_step): (Real, Real, Real),
    (y_lo, y_hi, y_step): (Real, Real, Real),
    x_label: &str,
    y_label: &str,
) {
    let (left, top, w, h) = AREA;
    let (xd, yd) = (decimals(x_step), decimals(y_step));
    for k in 0..=((x_hi - x_lo) / x_step).round() as usize {
        let value = x_lo + k as Real * x_step;
        let x = left + w * (value - x_lo) / (x_hi - x_lo);
        let _ = writeln!(
            out,
            "<line x1=\"{x:.1}\" y1=\"{top:.1}\" x2=\"{x:.1}\" y2=\"{:.1}\" stroke=\"#eee\"/>\
             <text x=\"{x:.1}\" y=\"{:.1}\" text-anchor=\"middle\">{}</text>",
            top + h,
            top + h + 14.0,
            fmt(value, xd)
        );
    }
    for k in 0..=((y_hi - y_lo) / y_step).round() as usize {
        let value = y_lo + k as Real * y_step;
        let y = top + h - h * (value - y_lo) / (y_hi - y_lo);
        let _ = writeln!(
            out,
            "<line x1=\"{left:.1}\" y1=\"{y:.1}\" x2=\"{:.1}\" y2=\"{y:.1}\" stroke=\"#eee\"/>\
             <text x=\"{:.1}\" y=\"{:.1}\" text-anchor=\"end\">{}</text>",
            left + w,
            left - 4.0,
            y + 4.0,
            fmt(value, yd)
        );
    }
    let _ = writeln!(
        out,
        "<rect x=\"{left:.1}\" y=\"{top:.1}\" width=\"{w:.1}\" height=\"{h:.1}\" fill=\"none\" stroke=\"#999\"/>\n\
         <text x=\"{:.1}\" y=\"{:.1}\" text-anchor=\"middle\">{}</text>\n\
         <text transform=\"translate({:.1} {:.1}) rotate(-90)\" text-anchor=\"middle\">{}</text>",
        left + w / 2.0,
        top + h + 34.0,
        escape(x_label),
        left - 50.0,
        top + h / 2.0,
        escape(y_label)
    );
}

/// A legend entry: a short line in the curve's colour, then its label.
fn legend_line(out: &mut String, left: Real, y: Real, colour: &str, width: Real, label: &str) {
    let _ = writeln!(
        out,
        "<line x1=\"{left:.1}\" y1=\"{:.1}\" x2=\"{:.1}\" y2=\"{:.1}\" stroke=\"{}\" stroke-width=\"{width:.1}\"/>\
         <text x=\"{:.1}\" y=\"{y:.1}\">{}</text>",
        y - 4.0,
        left + 24.0,
        y - 4.0,
        escape(colour),
        left + 30.0,
        escape(label)
    );
}

fn polyline(out: &mut String, points: &[(Real, Real)], colour: &str, width: Real) {
    let mut text = String::with_capacity(points.len() * 12);
    for (i, (x, y)) in points.iter().enumerate() {
        if i > 0 {
            text.push(' ');
        }
        let _ = write!(text, "{x:.1},{y:.1}");
    }
    let _ = writeln!(
        out,
        "<polyline fill=\"none\" stroke=\"{}\" stroke-width=\"{width:.1}\" points=\"{text}\"/>",
        escape(colour)
    );
}

/// The least and greatest finite value, `(0, 1)` when there is none.
fn extent(values: impl Iterator<Item = Real>) -> (Real, Real) {
    let (lo, hi) = values
        .filter(|v| v.is_finite())
        .fold((Real::INFINITY, Real::NEG_INFINITY), |(lo, hi), v| {
            (lo.min(v), hi.max(v))
        });
    if lo.is_finite() && hi.is_finite() {
        (lo, hi)
    } else {
        (0.0, 1.0)
    }
}

/// `[lo, hi]`, widened by 5 % of its size each way when it has no width.
fn widened(lo: Real, hi: Real) -> (Real, Real) {
    let size = match lo.abs().max(hi.abs()) {
        0.0 => 1.0,
        size => size,
    };
    if hi - lo <= 1e-9 * size {
        (lo - 0.05 * size, hi + 0.05 * size)
    } else {
        (lo, hi)
    }
}

/// The smallest step of 1, 2 or 5 × 10ⁿ not below `raw`.
fn nice_step(raw: Real) -> Real {
    let magnitude = 10.0_f64.powf(raw.log10().floor());
    [1.0, 2.0, 5.0, 10.0]
        .into_iter()
        .map(|m| m * magnitude)
        .find(|s| *s >= raw * (1.0 - 1e-9))
        .unwrap_or(10.0 * magnitude)
}

/// `[lo, hi]` (widened when of no width) rounded outward to a step of 1, 2 or 5 × 10ⁿ giving
/// at most `intervals` steps across the range: `(lo, hi, step)`.
fn nice(lo: Real, hi: Real, intervals: Real) -> (Real, Real, Real) {
    let (lo, hi) = widened(lo, hi);
    let step = nice_step((hi - lo) / intervals);
    let lo = (lo / step + 1e-9).floor() * step;
    let hi = (hi / step - 1e-9).ceil() * step;
    (lo, hi, step)
}

/// Decimals that show a multiple of `step` exactly.
fn decimals(step: Real) -> usize {
    (-(step.log10() + 1e-9).floor()).max(0.0) as usize
}

/// A number with `decimals` decimals, without a minus sign on zero.
fn fmt(value: Real, decimals: usize) -> String {
    crate::math::fixed(value, decimals)
}

fn escape(text: &str) -> String {
    text.replace('&', "&amp;")
        .replace('<', "&lt;")
        .replace('>', "&gt;")
        .replace('"', "&quot;")
}

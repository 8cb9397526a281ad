//! `mtwin analyze spindle`: the command line of this kind. Like `main.rs`, this is the binary's
//! layer: errors are `anyhow`'s, with the file named once.

use super::analysis::motion::{Direction, ErrorMotionValues, decompose};
use super::analysis::polar::Centre;
use super::discovery::bearing::Bearing;
use super::discovery::{DEFAULT_BASE_HARMONICS, Options as DiscoveryOptions, discover_spindle};
use super::evaluate::{Budget, Evaluation, Options, Test, TestUncertainty, evaluate};
use super::plot::{PolarCurve, line_svg, polar_svg, spectrum_svg};
use super::record::Sensing;
use super::table::{self, SpindleTable};
use crate::kinds::{Kind, ScenarioLoader, Verb};
use crate::math::Real;
use anyhow::{Context, Result};
use clap::{ArgMatches, Args, FromArgMatches};
use serde_json::{Value, json};
use std::f64::consts::TAU;
use std::path::PathBuf;

mod separations;

/// This kind in the registry.
pub const KIND: Kind = Kind {
    name: "spindle",
    tables_are: "spindle analyser tables",
    sections: &["spindle"],
    tables: &["spindle.csv"],
    analyze: Some(Verb {
        command: || {
            SpindleArgs::augment_args(clap::Command::new("spindle"))
                .about(
                    "Axis of rotation error motion (ISO 230-7): total, synchronous and \
                     asynchronous values about each polar-plot centre, per set-up and speed, \
                     the spectrum, and the artefact form separated by reversal or multi-probe",
                )
                .after_long_help(JSON_KEYS)
        },
        run: analyze,
    }),
    discover: Some(Verb {
        command: || {
            DiscoverArgs::augment_args(clap::Command::new("spindle"))
                .about(
                    "Spindle analyser records (ISO 230-7): asynchronous lines (named by bearing \
                     frequency), harmonics beyond the base, drift during the record, speed dependence",
                )
                .long_about(DISCOVER_ABOUT)
        },
        run: discover,
    }),
};

const DISCOVER_ABOUT: &str = "\
Spindle analyser records (ISO 230-7; the table of `analyze spindle`).

The base model, for every probe: each speed's mean and the harmonics 1..K of the axis angle
(--base-harmonics, default 2: the artefact's set-up eccentricity and an elliptical orbit).
Effects: harmonic (a synchronous order above K, searched), asynchronous_line (a frequency that
is no whole multiple of the rotation, searched; named by the bearing frequency it matches when
--bearing-* give the geometry, else by its ratio to the rotation), drift (the mean moving during
the record: linear or first-order, τ searched), speed_dependence (the harmonics 1..K differing
between speeds). Harmonics and lines may enter up to 4 times each. Held-out data: contiguous
blocks of revolutions in every speed; every testable effect is scored at every round.

JSON keys (--json): kind, setup, other_setups[], probes[], samples_per_revolution,
speeds_rpm[], revolutions[], n_samples, validation{scheme, folds, rule},
baseline{model, base_harmonics, rms_um, cv_rms_um, fold_cv_rms_um[], evidence{}},
steps[{effect, together_with, cause, evidence, params, rms_um, cv_rms_um, fold_cv_rms_um[],
gain_um, gain_pct, gain_z, rest_z, z_needed}], rejected[{effect, cv_rms_um, fold_cv_rms_um[],
gain_z, rest_z, z_needed, fails (the rule's condition it fails)}], untestable[{effect, reason}],
final{model, params{}, rms_um, cv_rms_um, fold_cv_rms_um[]}, cautions[] (what the record says
against its labels, as analyze says it), columns_not_read[]. params: harmonic
{per_revolution, amplitude{PROBE_um}}, asynchronous_line {per_revolution, harmonics, name, hz[],
amplitude{PROBE_um: [per speed]}}, drift {time_constant_s (null: linear), over_s,
drift{PROBE_um}}, speed_dependence {speeds_rpm[], amplitude{PROBE_um: {upr_k: [per speed]}}}.";

#[derive(Args)]
struct DiscoverArgs {
    /// The table (CSV, the columns of `analyze spindle`).
    file: PathBuf,
    /// Print JSON with stable keys instead of the report for people.
    #[arg(long)]
    json: bool,
    /// The set-up to search, for a record of several (default: the first in the file).
    #[arg(long, value_name = "NAME")]
    setup: Option<String>,
    /// The base model's harmonics of the angle, 1..=K: at most 64, and at most samples per
    /// revolution / 2 − 2 (a harmonic above the base is left to search below Nyquist); more is
    /// refused.
    #[arg(long, value_name = "K", default_value_t = DEFAULT_BASE_HARMONICS, allow_negative_numbers = true)]
    base_harmonics: usize,
    /// Rolling elements of the spindle bearing (with the two diameters: names lines by
    /// bearing frequency).
    #[arg(long, value_name = "N", requires_all = ["bearing_element_diameter_mm", "bearing_pitch_diameter_mm"], allow_negative_numbers = true)]
    bearing_elements: Option<usize>,
    /// Rolling-element diameter (mm).
    #[arg(long, value_name = "MM", requires = "bearing_elements")]
    bearing_element_diameter_mm: Option<Real>,
    /// Pitch diameter of the bearing (mm).
    #[arg(long, value_name = "MM", requires = "bearing_elements")]
    bearing_pitch_diameter_mm: Option<Real>,
    /// Contact angle of the bearing (°).
    #[arg(
        long,
        value_name = "DEG",
        default_value_t = 0.0,
        requires = "bearing_elements"
    )]
    bearing_contact_angle_deg: Real,
}

fn discover(
    matches: &ArgMatches,
    progress: &mut dyn FnMut(&str),
    _scenarios: &dyn ScenarioLoader,
) -> Result<String> {
    let args = DiscoverArgs::from_arg_matches(matches)?;
    let table = table::read(&args.file)?;
    let bearing = match (
        args.bearing_elements,
        args.bearing_element_diameter_mm,
        args.bearing_pitch_diameter_mm,
    ) {
        (Some(n), Some(d), Some(pitch)) => Some(Bearing::new(
            n,
            d * 1e-3,
            pitch * 1e-3,
            args.bearing_contact_angle_deg.to_radians(),
        )?),
        _ => None,
    };
    let options = DiscoveryOptions {
        setup: args.setup.clone(),
        base_harmonics: args.base_harmonics,
        bearing,
    };
    let discovery = discover_spindle(
        &table.record,
        table.samples_per_revolution,
        &options,
        |what| progress(what),
    )
    .with_context(|| format!("{}", args.file.display()))?;
    // What the record says against its labels, as analyze says it.
    let cautions = super::plausible::record_cautions(&table.record, table.samples_per_revolution);
    Ok(if args.json {
        let mut report = discovery.to_json();
        report["cautions"] = json!(cautions);
        report["columns_not_read"] = json!(table.columns_not_read);
        format!("{}\n", serde_json::to_string_pretty(&report)?)
    } else {
        let mut text = discovery.to_text();
        for caution in &cautions {
            text += &format!("CAUTION: {caution}\n");
        }
        text + &crate::io::not_read_line(&table.columns_not_read)
    })
}

const JSON_KEYS: &str = "\
Table: revolution, angle_deg and one NAME_um column per probe are required; setup, time_s and
speed_rpm are read when present. Probe geometry from the preamble (NAME_direction,
NAME_position_mm, NAME_sensing) or, for foreign exports, from the names x1 y1 x2 y2 z face.

Values (µm; tilt in µrad) are ISO 230-7 error motion values: the difference in radii of two
concentric circles about the centre, fitted to the synchronous plot (§3.7 Note 1); the
asynchronous value is the widest band at one angle (§3.8.4). Radial and tilt default to LSC,
axial and face to PC (Tab 1); the fundamental is removed by LSC, MRS, MIC, MCC and kept by PC.

JSON keys (--json):
  samples_per_revolution
  segments[]: setup, speed_rpm, revolutions, pooled (a rotary axis's CW and CCW runs at
    one speed evaluated together, ISO 230-7 §6; set-up ends in \"(both senses)\"), tests[]:
    name, direction (radial|axial|tilt|face), sensing (fixed|rotating), probes[], height_mm,
    unit (um|urad), values[] (preferred centre first): centre, offset [x, y], total (about
    the synchronous plot's centre), total_own_centre and total_own_offset (about the total
    plot's own centre of that kind), synchronous, asynchronous, fundamental (2·|1-UPR|),
    residual (the residual plot about its own centre), inner, outer;
    uncertainty (ISO 230-7 Annex F, k = 2): synchronous (U of the synchronous, fundamental and
    residual values, F.7), single (of total, asynchronous, inner, outer, F.6), complete,
    missing[] (what the budget lacks: U is then a lower bound), contributions[]: source, u,
    averages_over_revolutions (inputs: --device-uncertainty-um, --device-range-um,
    --drift-um, --roundness-um or the preamble's device_uncertainty_um, device_range_um,
    drift_um, artefact_roundness_um; resolution_nm or the readings' rounding);
    lines[]: per_revolution, hz, amplitude, synchronous (one-sided amplitude, largest first)
  speeds[]: test, unit, points[]: speed_rpm, synchronous, asynchronous (preferred centre)
  speed_shifts[]: speed-induced axis shift (§3.10.6) of each fixed-direction test seen at two
    speeds or more in one set-up and sense: test, unit, backwards, value (max − min of the mean
    position), uncertainty {k, value, complete}, points[]: speed_rpm, shift (mean position
    minus the first speed's)
  separations[]: method (reversal|multi-probe|face reversal|face reversal with axial motion:
    no probe on the axis, so the face form holds the axial motion), probes[], speed_rpm,
    harmonics_max (K),
    first_harmonic (how the method treats 1 UPR), blind[] (harmonics the layout cannot see),
    unknown[] (those of them where a probe reads more than its noise), not_determined (why
    the synchronous values are null when unknown[] is not empty), form_um[] (outward, on
    ψ = 360°·m/M),
    form: first_harmonic_um [a1, b1] (reversal: the centring; face: the wobble; null for
      multi-probe),
      harmonics_um {from: 2, a[], b[]} (h(ψ) = Σ a_k cos kψ + b_k sin kψ; null where blind),
      values[] (centre, offset, value: roundness about LSC, PC, MRS, MIC, MCC) or null, then
      values_seen[] over the harmonics seen;
    motion[] (reversal: along the probe; face reversal: R × tilt at the probe's azimuth;
      multi-probe: X, Y, rotating): axis, azimuth_deg,
      first_harmonic_um, harmonics_um, asynchronous_um, values[] (as a test's) or null, then
      values_seen[];
    uncertainty (as a test's: the probes' budget, and a layout's misfit)
  notes[]
  cautions[]: what the record says against its units and labels (a total over 100 µm: nm in
    the µm columns; every one under 5 nm: mm in them; a probe stuck or spiking; two probes on
    one signal; an eccentricity turning against the axis)
  columns_not_read[]: columns of the table the reader read past (no figure depends on them)
  setup: machine, artefact, structural_loop, axes (where the other axes stood), as the
    preamble says them (null when it does not); preamble_not_used[] (keys no reader took)";

#[derive(Args)]
struct SpindleArgs {
    /// The table (CSV with a header; see below).
    file: PathBuf,
    /// Print JSON with stable keys instead of the report for people.
    #[arg(long)]
    json: bool,
    /// Write the polar plots, spectra and value-against-speed charts (SVG) into this folder.
    #[arg(long, value_name = "DIR")]
    plot: Option<PathBuf>,
    /// Centres to score about, comma-separated (default: all five; the preferred one of ISO
    /// 230-7 Tab 1 always comes first).
    #[arg(long, value_delimiter = ',', value_name = "PC,LSC,MRS,MIC,MCC")]
    centres: Vec<String>,
    /// Also evaluate a fixed sensitive direction at this angle from X (degrees; repeat or
    /// comma-separate for several), from each pair of radial probes at one height: ISO 230-7
    /// formula (4), ΔX cos θ_f + ΔY sin θ_f (e.g. 30 for a tool 30° from the X probe).
    #[arg(
        long = "direction-deg",
        value_delimiter = ',',
        value_name = "DEG",
        allow_negative_numbers = true
    )]
    directions_deg: Vec<Real>,
    /// Expanded uncertainty (k = 2) of one probe channel from its calibration (ISO 230-7 F.1;
    /// overrides the preamble's device_uncertainty_um).
    #[arg(long, value_name = "UM")]
    device_uncertainty_um: Option<Real>,
    /// The probe's error range from its maker (F.2: U = 0.6 × range; overrides the preamble's
    /// device_range_um).
    #[arg(long, value_name = "UM")]
    device_range_um: Option<Real>,
    /// Range of a drift test with the axis stopped, as long as the record (F.3: U = 0.6 × range;
    /// overrides the preamble's drift_um).
    #[arg(long, value_name = "UM")]
    drift_um: Option<Real>,
    /// The artefact's roundness, peak to valley (overrides the preamble's
    /// artefact_roundness_um).
    #[arg(long, value_name = "UM")]
    roundness_um: Option<Real>,
}

fn analyze(
    matches: &ArgMatches,
    progress: &mut dyn FnMut(&str),
    _scenarios: &dyn ScenarioLoader,
) -> Result<String> {
    let args = SpindleArgs::from_arg_matches(matches)?;
    let table = table::read(&args.file)?;
    let mut options = Options::default();
    if !args.centres.is_empty() {
        options.centres = args
            .centres
            .iter()
            .map(|c| {
                c.parse::<Centre>()
                    .map_err(|e| anyhow::anyhow!("--centres: {e}"))
            })
            .collect::<Result<_>>()?;
    }
    if let Some(bad) = args.directions_deg.iter().find(|d| !d.is_finite()) {
        anyhow::bail!("--direction-deg {bad}: expected a finite angle in degrees");
    }
    options.fixed_directions = args.directions_deg.iter().map(|d| d.to_radians()).collect();
    options.budget = budget(&args, &table)?;
    progress(&format!(
        "evaluating {} samples of {} probes",
        table.record.len(),
        table.record.probes.len()
    ));
    let evaluation = evaluate(&table.record, table.samples_per_revolution, &options)
        .with_context(|| format!("{}", args.file.display()))?;
    if let Some(dir) = &args.plot {
        let files = plots(&table, &evaluation);
        crate::io::write_files(&files, dir)?;
        progress(&format!(
            "{} plots written to {}",
            files.len(),
            dir.display()
        ));
    }
    let cautions = super::plausible::cautions(&table.record, &evaluation);
    Ok(if args.json {
        let mut report = to_json(&evaluation);
        let (described, _) = super::stated::described(&table.conditions);
        report["setup"] = described;
        report["cautions"] = json!(cautions);
        report["columns_not_read"] = json!(table.columns_not_read);
        format!("{}\n", serde_json::to_string_pretty(&report)?)
    } else {
        let mut text = to_text(&table, &evaluation);
        for caution in &cautions {
            text += &format!("CAUTION: {caution}\n");
        }
        text + &crate::io::not_read_line(&table.columns_not_read)
    })
}

/// µm for lengths, µrad for tilts.
/// The Annex F inputs: each flag, else its preamble key, in µm (≥ 0).
fn budget(args: &SpindleArgs, table: &SpindleTable) -> Result<Budget> {
    let file = args.file.display().to_string();
    let pick = |flag: Option<Real>, name: &str, key: &str| -> Result<Option<Real>> {
        let value = match flag {
            Some(v) => Some(v),
            None => table.conditions.number(key, &file)?,
        };
        match value {
            Some(v) if !(v.is_finite() && v >= 0.0) => {
                anyhow::bail!("{name} = {v}: expected a finite number of µm, at least 0")
            }
            v => Ok(v.map(|v| v * 1e-6)),
        }
    };
    Ok(Budget {
        device: pick(
            args.device_uncertainty_um,
            "--device-uncertainty-um (or device_uncertainty_um)",
            "device_uncertainty_um",
        )?,
        device_range: pick(
            args.device_range_um,
            "--device-range-um (or device_range_um)",
            "device_range_um",
        )?,
        drift: pick(args.drift_um, "--drift-um (or drift_um)", "drift_um")?,
        roundness: pick(
            args.roundness_um,
            "--roundness-um (or artefact_roundness_um)",
            "artefact_roundness_um",
        )?,
        resolution: table
            .conditions
            .number("resolution_nm", &file)?
            .map(|q| q * 1e-9),
    })
}

fn unit(direction: Direction) -> (&'static str, Real) {
    match direction {
        Direction::Tilt => ("urad", 1e6),
        _ => ("um", 1e6),
    }
}

fn rpm(speed: Real) -> Real {
    speed * 60.0 / TAU
}

fn round(value: Real) -> Value {
    // 1 pm (or 1 prad): the readings' own resolution in the table.
    json!((value * 1e6).round() / 1e6)
}

fn values_json(v: &ErrorMotionValues, scale: Real) -> Value {
    json!({
        "centre": v.centre.to_string(),
        "offset": [round(v.offset[0] * scale), round(v.offset[1] * scale)],
        "total": round(v.total * scale),
        "total_own_centre": round(v.total_own_centre * scale),
        "total_own_offset": [round(v.total_own_offset[0] * scale), round(v.total_own_offset[1] * scale)],
        "synchronous": round(v.synchronous * scale),
        "asynchronous": round(v.asynchronous * scale),
        "fundamental": round(v.fundamental * scale),
        "residual": round(v.residual * scale),
        "inner": round(v.inner * scale),
        "outer": round(v.outer * scale),
    })
}

fn sensing_name(sensing: Sensing) -> &'static str {
    match sensing {
        Sensing::Fixed => "fixed",
        Sensing::Rotating => "rotating",
    }
}

fn test_json(test: &Test, speed: Real) -> Value {
    let (unit_name, scale) = unit(test.direction);
    json!({
        "name": test.name,
        "direction": test.direction.name(),
        "sensing": sensing_name(test.sensing),
        "probes": test.probes,
        "height_mm": round(test.height * 1e3),
        "unit": unit_name,
        "values": test.values.iter().map(|v| values_json(v, scale)).collect::<Vec<_>>(),
        "lines": test.lines.iter().map(|l| json!({
            "per_revolution": round(l.per_revolution),
            "hz": round(l.per_revolution * speed.abs() / TAU),
            "amplitude": round(l.amplitude * scale),
            "synchronous": l.synchronous,
        })).collect::<Vec<_>>(),
        "uncertainty": uncertainty_json(&test.uncertainty, scale),
    })
}

/// A test's Annex F budget (k = 2), in its unit.
fn uncertainty_json(u: &TestUncertainty, scale: Real) -> Value {
    json!({
        "k": 2,
        "synchronous": round(u.synchronous * scale),
        "single": round(u.single * scale),
        "complete": u.missing.is_empty(),
        "missing": u.missing,
        "contributions": u.contributions.iter().map(|c| json!({
            "source": c.source,
            "u": round(c.u * scale),
            "averages_over_revolutions": c.averages,
        })).collect::<Vec<_>>(),
    })
}

/// A test's values against speed: its name, direction and (speed min⁻¹, synchronous,
/// asynchronous) points.
type SpeedSeries = (String, Direction, Vec<(Real, Real, Real)>);

/// Each test's preferred-centre values against speed, for tests seen at two speeds or more.
fn speed_series(evaluation: &Evaluation) -> Vec<SpeedSeries> {
    let mut series: Vec<SpeedSeries> = Vec::new();
    for segment in &evaluation.segments {
        for test in &segment.tests {
            let name = if segment.setup.is_empty() {
                test.name.clone()
            } else {
                format!("{} ({})", test.name, segment.setup)
            };
            let point = (
                rpm(segment.speed),
                test.values[0].synchronous,
                test.values[0].asynchronous,
            );
            match series.iter_mut().find(|(n, _, _)| *n == name) {
                Some((_, _, points)) => points.push(point),
                None => series.push((name, test.direction, vec![point])),
            }
        }
    }
    series.retain(|(_, _, points)| points.len() >= 2);
    series
}

/// The JSON report (its keys are listed in `mtwin analyze spindle --help`).
pub fn to_json(evaluation: &Evaluation) -> Value {
    let segments: Vec<Value> = evaluation
        .segments
        .iter()
        .map(|s| {
            json!({
                "setup": s.setup,
                "speed_rpm": round(rpm(s.speed)),
                "revolutions": s.revolutions,
                "pooled": s.pooled,
                "tests": s.tests.iter().map(|t| test_json(t, s.speed)).collect::<Vec<_>>(),
            })
        })
        .collect();
    let speeds: Vec<Value> = speed_series(evaluation)
        .into_iter()
        .map(|(name, direction, points)| {
            let (unit_name, scale) = unit(direction);
            json!({
                "test": name,
                "unit": unit_name,
                "points": points.iter().map(|(speed, sync, asynchronous)| json!({
                    "speed_rpm": round(*speed),
                    "synchronous": round(sync * scale),
                    "asynchronous": round(asynchronous * scale),
                })).collect::<Vec<_>>(),
            })
        })
        .collect();
    let separations: Vec<Value> = evaluation
        .separations
        .iter()
        .map(separations::json)
        .collect();
    let shifts: Vec<Value> = evaluation
        .shifts
        .iter()
        .map(|shift| {
            let (unit_name, scale) = unit(shift.direction);
            json!({
                "test": shift.test,
                "unit": unit_name,
                "backwards": shift.backwards,
                "value": round(shift.value * scale),
                "uncertainty": {
                    "k": 2,
                    "value": round(shift.uncertainty * scale),
                    "complete": shift.complete,
                },
                "points": shift.points.iter().map(|(speed, x)| json!({
                    "speed_rpm": round(rpm(*speed)),
                    "shift": round(x * scale),
                })).collect::<Vec<_>>(),
            })
        })
        .collect();
    json!({
        "samples_per_revolution": evaluation.samples_per_revolution,
        "segments": segments,
        "speeds": speeds,
        "speed_shifts": shifts,
        "separations": separations,
        "notes": evaluation.notes,
    })
}

/// The report for people.
pub fn to_text(table: &SpindleTable, evaluation: &Evaluation) -> String {
    let axis = table.record.axis;
    let mut out = format!(
        "Axis of rotation {axis}: error motion (ISO 230-7), {} samples per revolution\n\
         values in µm (tilt in µrad); preferred centre first (Tab 1); total about the \
         synchronous plot's centre, tot.own about the total plot's own\n",
        evaluation.samples_per_revolution
    );
    let (described, lines) = super::stated::described(&table.conditions);
    out += &lines;
    for segment in &evaluation.segments {
        let setup = if segment.setup.is_empty() {
            String::new()
        } else {
            format!("set-up {}, ", segment.setup)
        };
        out += &format!(
            "\n{setup}{:.0} min⁻¹, {} revolutions\n  {:<30} {:<4} {:>9} {:>9} {:>9} {:>9} {:>9} {:>9} {:>9} {:>9}\n",
            rpm(segment.speed),
            segment.revolutions,
            "test",
            "ctr",
            "total",
            "tot.own",
            "sync",
            "async",
            "fund.",
            "resid.",
            "inner",
            "outer"
        );
        for test in &segment.tests {
            let (_, scale) = unit(test.direction);
            for (i, v) in test.values.iter().enumerate() {
                out += &format!(
                    "  {:<30} {:<4} {:>9.4} {:>9.4} {:>9.4} {:>9.4} {:>9.4} {:>9.4} {:>9.4} {:>9.4}\n",
                    if i == 0 { test.name.as_str() } else { "" },
                    v.centre.to_string(),
                    v.total * scale,
                    v.total_own_centre * scale,
                    v.synchronous * scale,
                    v.asynchronous * scale,
                    v.fundamental * scale,
                    v.residual * scale,
                    v.inner * scale,
                    v.outer * scale,
                );
            }
            let lines: Vec<String> = test
                .lines
                .iter()
                .take(4)
                .map(|l| {
                    format!(
                        "{:.2} UPR ({:.1} Hz) {:.4}{}",
                        l.per_revolution,
                        l.per_revolution * segment.speed.abs() / TAU,
                        l.amplitude * scale,
                        if l.synchronous { " sync" } else { " async" }
                    )
                })
                .collect();
            out += &format!("  {:<30} lines: {}\n", "", lines.join("; "));
            let u = &test.uncertainty;
            out += &format!(
                "  {:<30} U (k = 2): sync, fund., resid. ±{:.4}; total, async, inner, outer ±{:.4}{}\n",
                "",
                u.synchronous * scale,
                u.single * scale,
                if u.missing.is_empty() {
                    String::new()
                } else {
                    format!(" (a lower bound: {})", u.missing.join("; "))
                }
            );
        }
    }
    let series = speed_series(evaluation);
    if !series.is_empty() {
        out += "\nError motion against speed (preferred centre: synchronous / asynchronous):\n";
        for (name, direction, points) in &series {
            let (_, scale) = unit(*direction);
            let cells: Vec<String> = points
                .iter()
                .map(|(s, sync, asynchronous)| {
                    format!("{s:.0}: {:.4} / {:.4}", sync * scale, asynchronous * scale)
                })
                .collect();
            out += &format!("  {name}: {}\n", cells.join(",  "));
        }
    }
    if !evaluation.shifts.is_empty() {
        out += "\nSpeed-induced axis shift (§3.10.6; mean position from the first speed):\n";
        for shift in &evaluation.shifts {
            let (_, scale) = unit(shift.direction);
            let cells: Vec<String> = shift
                .points
                .iter()
                .map(|(speed, x)| format!("{:.0}: {:+.4}", rpm(*speed), x * scale))
                .collect();
            out += &format!(
                "  {}: {:.4} ± {:.4}{} ({})\n",
                shift.test,
                shift.value * scale,
                shift.uncertainty * scale,
                if shift.complete {
                    ""
                } else {
                    " (U a lower bound)"
                },
                cells.join(", ")
            );
        }
    }
    for s in &evaluation.separations {
        out += &separations::text(s);
    }
    for note in &evaluation.notes {
        out += &format!("\nnote: {note}\n");
    }
    out += &crate::io::not_used_line(
        described["preamble_not_used"]
            .as_array()
            .into_iter()
            .flatten()
            .filter_map(|k| k.as_str()),
    );
    out
}

/// Lowest and highest residual `v − cx cos θ − cy sin θ` of a profile about a centre offset.
fn bounds(values: &[Real], angles: &[Real], offset: [Real; 2]) -> (Real, Real) {
    values
        .iter()
        .zip(angles)
        .map(|(v, t)| v - offset[0] * t.cos() - offset[1] * t.sin())
        .fold((Real::INFINITY, Real::NEG_INFINITY), |(lo, hi), r| {
            (lo.min(r), hi.max(r))
        })
}

/// A motion's polar curves: every revolution (thin) and the synchronous profile (bold).
fn motion_curves<'a>(
    total_angles: &'a [Real],
    total: &'a [Real],
    angles: &'a [Real],
    synchronous: &'a [Real],
) -> [PolarCurve<'a>; 2] {
    [
        PolarCurve {
            label: "total",
            angles: total_angles,
            values: total,
            stroke: "#9ab",
            width: 0.6,
        },
        PolarCurve {
            label: "synchronous",
            angles,
            values: synchronous,
            stroke: "#c20",
            width: 1.8,
        },
    ]
}

/// A file-name-safe slug.
fn slug(text: &str) -> String {
    text.chars()
        .map(|c| if c.is_ascii_alphanumeric() { c } else { '_' })
        .collect::<String>()
        .trim_matches('_')
        .to_string()
}

/// The SVG files: per segment and test a polar plot and a spectrum, per test seen at several
/// speeds its values against speed, per separation the form.
pub fn plots(table: &SpindleTable, evaluation: &Evaluation) -> Vec<(String, Vec<u8>)> {
    let mut files = Vec::new();
    let m = evaluation.samples_per_revolution;
    let angles: Vec<Real> = (0..m).map(|i| TAU * i as Real / m as Real).collect();
    for segment in &evaluation.segments {
        let tag = format!(
            "{}{}rpm",
            if segment.setup.is_empty() {
                String::new()
            } else {
                format!("{}_", slug(&segment.setup))
            },
            rpm(segment.speed).round()
        );
        for test in &segment.tests {
            let (unit_name, scale) = unit(test.direction);
            let d = decompose(&test.signal);
            let preferred = &test.values[0];
            // The polar plot takes SI values (m; a tilt's rad drawn on the same scale).
            let total = test.signal.values();
            let total_angles: Vec<Real> = (0..total.len()).map(|i| angles[i % m]).collect();
            let title = format!(
                "{} — axis {}, {:.0} min⁻¹, {} revolutions",
                test.name,
                table.record.axis,
                rpm(segment.speed),
                segment.revolutions
            );
            let notes: Vec<String> = test
                .values
                .iter()
                .map(|v| {
                    format!(
                        "{}: sync {:.4}, async {:.4}, total {:.4} {unit_name}",
                        v.centre,
                        v.synchronous * scale,
                        v.asynchronous * scale,
                        v.total * scale
                    )
                })
                .collect();
            let bounds = bounds(&d.synchronous, &angles, preferred.offset);
            let svg = polar_svg(
                &title,
                &motion_curves(&total_angles, total, &angles, &d.synchronous),
                preferred.offset,
                bounds,
                &notes,
            );
            let name = slug(&test.name);
            files.push((format!("polar_{tag}_{name}.svg"), svg.into_bytes()));
            let lines: Vec<(Real, Real, bool)> = super::analysis::spectrum::spectrum(&test.signal)
                .lines
                .iter()
                .filter(|l| l.per_revolution <= 50.0)
                .map(|l| (l.per_revolution, l.amplitude * scale, l.synchronous))
                .collect();
            files.push((
                format!("spectrum_{tag}_{name}.svg"),
                spectrum_svg(&format!("spectrum — {title}"), &lines).into_bytes(),
            ));
        }
    }
    for (name, direction, points) in speed_series(evaluation) {
        let (unit_name, scale) = unit(direction);
        let sync: Vec<(Real, Real)> = points.iter().map(|p| (p.0, p.1 * scale)).collect();
        let asynchronous: Vec<(Real, Real)> = points.iter().map(|p| (p.0, p.2 * scale)).collect();
        files.push((
            format!("speed_{}.svg", slug(&name)),
            line_svg(
                &format!("{name}: error motion against speed"),
                "speed (min⁻¹)",
                &format!("value ({unit_name})"),
                &[("synchronous", &sync), ("asynchronous", &asynchronous)],
            )
            .into_bytes(),
        ));
    }
    for s in &evaluation.separations {
        files.extend(separations::plots(s, &angles));
    }
    files
}

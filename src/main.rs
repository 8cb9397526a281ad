//! `mtwin`: the command line of the machine-tool twin (a thin layer over the library).

use anyhow::{Context, Result, bail};
use clap::{Parser, Subcommand};
use mtwin::analysis::iso230_2;
use mtwin::analysis::iso230_4::{self, CircularTest};
use mtwin::analysis::thermal_series::thermal_series;
use mtwin::discovery::{PositioningOptions, discover_ballbar, discover_positioning};
use mtwin::io::{
    BallbarTable, DriftTable, PositioningTable, Scenario, Simulation, simulate, write_outputs,
};
use mtwin::machine::{Machine, Plane, Side};
use std::path::{Path, PathBuf};
use std::process::ExitCode;

/// A digital twin of a machine tool for metrology.
#[derive(Parser)]
#[command(version, about, long_about = None)]
struct Cli {
    #[command(subcommand)]
    command: Command,
}

#[derive(Subcommand)]
enum Command {
    /// Simulate a scenario: writes what it asks for (volumetric.csv, positioning.csv,
    /// ballbar_<plane>.csv), with truth.json and manifest.json, into --out.
    Run {
        /// The scenario (TOML).
        scenario: PathBuf,
        /// Output folder (created if needed; files in it with the same names are replaced).
        #[arg(long, value_name = "DIR")]
        out: PathBuf,
        /// Also write a teaching recording of the scenario for the rerun viewer 0.36
        /// (`rerun FILE.rrd`): the machine moving, its errors enlarged, every instrument's
        /// scene and discovery. Needs mtwin built with `--features viz`.
        #[arg(long, value_name = "FILE.rrd")]
        rrd: Option<PathBuf>,
    },
    /// Validate a scenario (.toml) or a machine model (.urdf) without running it.
    Check {
        /// The file.
        file: PathBuf,
    },
    /// The standards' figures from a measurement table (simulated or real).
    #[command(after_long_help = BALLBAR_CONVENTIONS)]
    Analyze {
        /// What the table holds: `positioning` (ISO 230-2: target_mm, deviation_um, and
        /// optionally axis, run, direction (+/-), time_min, temp_<sensor>_degc).
        kind: TableKind,
        /// The table (CSV with a header).
        file: PathBuf,
        /// Print JSON with stable keys instead of the report for people.
        #[arg(long)]
        json: bool,
        /// For `drift`: the duration of the performance test the ETVE is for (min).
        #[arg(long, value_name = "MIN", default_value_t = 60.0)]
        etve_min: f64,
        #[command(flatten)]
        circle: CircleArgs,
    },
    /// Model discovery: fit the twin's base model to a measurement table, show what it leaves,
    /// and add effects from the library while they lower the held-out RMS more than noise can.
    ///
    /// positioning: the base model is a reference error profile (piecewise linear through the
    /// targets of the coldest run, or the first without temperatures; its values fitted to all
    /// runs) plus the nominal thermal expansion of the axis, position × (temperature − the
    /// reference run's temperature) × the nominal coefficient. Effects: reversal,
    /// reversal_position, reversal_thermal, thermal_lag, thermal_scale, thermal_offset,
    /// second_heat_source, periodic, nonlinear_scale, time_drift. Held-out data: one run at a
    /// time with three runs or more, else contiguous blocks in time.
    ///
    /// ballbar (needs --plane, --radius-mm, --feed-mm-per-min): the base model is the radius,
    /// the centre offset, squareness and scale mismatch. Effects (axis letters of the plane):
    /// servo_mismatch, backlash_*, lateral_play_*, reversal_spike_*, straightness_*, cyclic_*,
    /// lobes (k per turn), radius_drift, sense_radius. Held-out data: angular sectors.
    #[command(verbatim_doc_comment)]
    Discover {
        /// What the table holds: `positioning` or `ballbar` (the tables of `analyze`).
        kind: DiscoverKind,
        /// The table (CSV with a header).
        file: PathBuf,
        /// Print JSON with stable keys instead of the report for people.
        #[arg(long)]
        json: bool,
        /// Write the extended model as a scenario fragment (TOML) that `mtwin run` accepts.
        #[arg(long, value_name = "FILE.toml")]
        write_model: Option<PathBuf>,
        /// With --write-model: the scenario of the machine the table was measured on; the
        /// fragment extends it, so `mtwin run FILE.toml` simulates the extended twin.
        #[arg(long, value_name = "SCENARIO.toml", requires = "write_model")]
        extends: Option<PathBuf>,
        /// Nominal expansion coefficient of the axis in the base model (µm/(m·°C)).
        #[arg(long, value_name = "PPM", default_value_t = 11.7)]
        expansion_ppm_per_degc: f64,
        /// The temperature column to use (`<sensor>` of temp_<sensor>_degc); default the first.
        #[arg(long, value_name = "NAME")]
        sensor: Option<String>,
        /// Shortest period the cyclic-error search considers (mm).
        #[arg(long, value_name = "MM", default_value_t = 2.0)]
        min_period_mm: f64,
        #[command(flatten)]
        circle: CircleArgs,
    },
}

/// The ball-bar diagnostics' conventions, for `analyze --help`.
const BALLBAR_CONVENTIONS: &str = "\
Ball-bar diagnostics (keys use the plane's axis letters; p = first axis, q = second;
θ from +p toward +q; σ = +1 ccw, −1 cw; d = measured − nominal radius, + outward):
  radius_deviation_um     constant radial deviation (bar length error, mean scale)
  centre_offset_p_um      centre of the machine's circle relative to the centre ball, along p (q alike)
  squareness_um_per_m     + when the angle between +p and +q travel is under 90°: (R·s/2)·sin 2θ
  scale_mismatch_ppm      kp − kq: (R·Δk/2)·cos 2θ
  servo_mismatch_ms       lag time of p − lag time of q (1/Kv), + when p lags: σ·(v·Δτ/2)·sin 2θ
  backlash_p_um           p lags the command by half of it against its travel: steps at 0°/180°
  lateral_play_p_um       the p carriage shifts along q by −sgn(ṗ)·l/2 (toward −q while p travels +): σ·|sin θ|·l/2
  reversal_spike_p_um     peak after p reverses, + outward, with its decay (_decay_ms)
  reversal_lag_p_ms       time from p's programmed reversal to its actual one (servo lag)
  straightness_p_um       bow of p along q, peak-to-valley over the diameter, middle toward +q: S·sin³θ
  cyclic_p_um             periodic error of p along p, with cyclic_p_period_mm and _phase_deg
Each comes with its standard uncertainty; what the data cannot separate is reported null
with the reason.";

/// The conditions of a circular test, which a ball-bar table does not hold.
#[derive(clap::Args)]
struct CircleArgs {
    /// For `ballbar`: the plane, first axis then second (XY, YZ or ZX); angles run from the
    /// first axis toward the second, counter-clockwise seen from +Z, +X, +Y.
    #[arg(long, value_name = "PLANE")]
    plane: Option<Plane>,
    /// For `ballbar`: the radius of the test, the bar's nominal length (mm).
    #[arg(long, value_name = "MM")]
    radius_mm: Option<f64>,
    /// For `ballbar`: the programmed feed (mm/min).
    #[arg(long, value_name = "MM_PER_MIN")]
    feed_mm_per_min: Option<f64>,
}

impl CircleArgs {
    /// The test conditions, all three required for a ball-bar table.
    fn test(&self) -> Result<CircularTest> {
        let (Some(plane), Some(radius_mm), Some(feed)) =
            (self.plane, self.radius_mm, self.feed_mm_per_min)
        else {
            bail!(
                "a ball-bar table needs its test conditions: --plane XY|YZ|ZX --radius-mm R --feed-mm-per-min F"
            );
        };
        if !(radius_mm.is_finite() && radius_mm > 0.0) {
            bail!("--radius-mm must be a positive number of millimetres, got {radius_mm}");
        }
        if !(feed.is_finite() && feed > 0.0) {
            bail!("--feed-mm-per-min must be a positive number, got {feed}");
        }
        Ok(CircularTest {
            plane,
            radius: radius_mm * 1e-3,
            feed: feed * 1e-3 / 60.0,
        })
    }

    /// Refuses circle flags on a table that is not a ball-bar table.
    fn refuse(&self, kind: &str) -> Result<()> {
        if self.plane.is_some() || self.radius_mm.is_some() || self.feed_mm_per_min.is_some() {
            bail!("--plane, --radius-mm and --feed-mm-per-min are for ball-bar tables, not {kind}");
        }
        Ok(())
    }
}

#[derive(Clone, Copy, clap::ValueEnum)]
enum DiscoverKind {
    /// Linear positioning deviations (laser interferometer).
    Positioning,
    /// Circular-test radial deviations (ball-bar, ISO 230-4).
    Ballbar,
}

#[derive(Clone, Copy, clap::ValueEnum)]
enum TableKind {
    /// Linear positioning deviations (laser interferometer), evaluated to ISO 230-2:2014.
    Positioning,
    /// Displacement channels against time (time_min, <channel>_um or _urad,
    /// temp_<sensor>_degc), evaluated to ISO 230-3:2007: drift ranges, stop criterion, ETVE.
    Drift,
    /// Ball-bar circular test (direction ccw/cw, angle_deg, deviation_um, optional time_s),
    /// evaluated to ISO 230-4 with the diagnostics of ball-bar software; needs --plane,
    /// --radius-mm and --feed-mm-per-min.
    Ballbar,
}

fn main() -> ExitCode {
    match execute(Cli::parse()) {
        Ok(()) => ExitCode::SUCCESS,
        Err(error) => {
            eprintln!("error: {error:#}");
            ExitCode::FAILURE
        }
    }
}

fn execute(cli: Cli) -> Result<()> {
    match cli.command {
        Command::Run { scenario, out, rrd } => {
            if let Some(path) = &rrd {
                check_recording_path(path)?;
            }
            let scenario = Scenario::load(&scenario)?;
            let simulation = simulate(&scenario)?;
            let output = simulation.output(&scenario);
            if let Some(path) = &rrd {
                record(path, &scenario, &simulation)?;
            }
            write_outputs(&output, &out)?;
            for (name, bytes) in &output.files {
                println!("{}  ({} bytes)", out.join(name).display(), bytes.len());
            }
            println!("seed {}", scenario.seed);
            Ok(())
        }
        Command::Check { file } => check(&file),
        Command::Discover {
            kind: DiscoverKind::Positioning,
            file,
            json,
            write_model,
            extends,
            expansion_ppm_per_degc,
            sensor,
            min_period_mm,
            circle,
        } => {
            circle.refuse("positioning tables")?;
            if !expansion_ppm_per_degc.is_finite() {
                bail!(
                    "--expansion-ppm-per-degc must be a finite number, got {expansion_ppm_per_degc}"
                );
            }
            if !(min_period_mm.is_finite() && min_period_mm > 0.0) {
                bail!(
                    "--min-period-mm must be a positive number of millimetres, got {min_period_mm}"
                );
            }
            let table = PositioningTable::read(&file)?;
            let options = PositioningOptions {
                expansion: expansion_ppm_per_degc * 1e-6,
                sensor,
                min_period: min_period_mm * 1e-3,
                ..PositioningOptions::default()
            };
            let discovery =
                discover_positioning(&table, options, |what| eprintln!("discover: {what}"))
                    .with_context(|| format!("{}", file.display()))?;
            if let Some(path) = &write_model {
                let base = match &extends {
                    Some(base) => {
                        Scenario::load(base)?;
                        Some(relative_path(base, path)?)
                    }
                    None => None,
                };
                let source = file.file_name().map_or_else(
                    || file.display().to_string(),
                    |n| n.to_string_lossy().into_owned(),
                );
                let fragment = discovery.to_scenario_fragment(&source, base.as_deref())?;
                write_atomically(path, fragment.as_bytes())?;
            }
            if json {
                println!("{}", serde_json::to_string_pretty(&discovery.to_json())?);
            } else {
                print!("{}", discovery.to_text());
                if let Some(path) = &write_model {
                    println!("\nExtended model written to {}", path.display());
                }
            }
            Ok(())
        }
        Command::Discover {
            kind: DiscoverKind::Ballbar,
            file,
            json,
            write_model,
            circle,
            ..
        } => {
            if write_model.is_some() {
                bail!(
                    "--write-model is for positioning tables: ball-bar diagnostics (servo, lost motion, spikes) are not all error-model terms"
                );
            }
            let test = circle.test()?;
            let table = BallbarTable::read(&file)?;
            let discovery = discover_ballbar(&table, &test, |what| eprintln!("discover: {what}"))
                .with_context(|| format!("{}", file.display()))?;
            if json {
                println!("{}", serde_json::to_string_pretty(&discovery.to_json())?);
            } else {
                print!("{}", discovery.to_text());
            }
            Ok(())
        }
        Command::Analyze {
            kind: TableKind::Ballbar,
            file,
            json,
            circle,
            ..
        } => {
            let test = circle.test()?;
            let table = BallbarTable::read(&file)?;
            let evaluation =
                iso230_4::evaluate(&table, &test).with_context(|| format!("{}", file.display()))?;
            if json {
                println!("{}", serde_json::to_string_pretty(&evaluation.to_json())?);
            } else {
                print!("{}", evaluation.to_text());
            }
            Ok(())
        }
        Command::Analyze {
            kind: TableKind::Drift,
            file,
            json,
            etve_min,
            circle,
        } => {
            circle.refuse("drift tables")?;
            if !(etve_min.is_finite() && etve_min > 0.0) {
                bail!("--etve-min must be a positive number of minutes, got {etve_min}");
            }
            let table = DriftTable::read(&file)?;
            let report = mtwin::analysis::iso230_3::drift_report(&table, etve_min * 60.0);
            if json {
                println!("{}", serde_json::to_string_pretty(&report)?);
            } else {
                print!("{}", drift_text(&report));
            }
            Ok(())
        }
        Command::Analyze {
            kind: TableKind::Positioning,
            file,
            json,
            circle,
            ..
        } => {
            circle.refuse("positioning tables")?;
            let table = PositioningTable::read(&file)?;
            match iso230_2::evaluate(&table) {
                Ok(result) if json => {
                    println!("{}", serde_json::to_string_pretty(&result.to_json(&table))?)
                }
                Ok(result) => print!("{}", result.to_text(&table)),
                // A drift test (e.g. ISO 230-3 §7) is a thermal series but not an ISO 230-2 test.
                Err(e) => match thermal_series(&table) {
                    Some(series) if json => {
                        println!(
                            "{}",
                            serde_json::to_string_pretty(
                                &series.report_json(&table, &e.to_string())
                            )?
                        );
                    }
                    Some(series) => {
                        print!("{}", series.to_text());
                        println!("\nNote: no ISO 230-2 figures: {e}; drift only.");
                    }
                    None => bail!("{}: {e}", file.display()),
                },
            }
            Ok(())
        }
    }
}

/// A recording path must name an `.rrd` file, and this mtwin must be able to write one.
fn check_recording_path(path: &Path) -> Result<()> {
    if path.extension().and_then(|e| e.to_str()) != Some("rrd") {
        bail!(
            "--rrd {}: expected a file name ending in .rrd",
            path.display()
        );
    }
    if !cfg!(feature = "viz") {
        bail!(
            "--rrd: this mtwin was built without teaching scenes; build it with `cargo build --release --features viz`"
        );
    }
    Ok(())
}

/// Writes the teaching recording through a temporary file beside `path`, so a failure leaves
/// no partial recording.
#[cfg(feature = "viz")]
fn record(path: &Path, scenario: &Scenario, simulation: &Simulation) -> Result<()> {
    let name = path
        .file_name()
        .with_context(|| format!("{}: not a file name", path.display()))?;
    let temporary = path.with_file_name(format!(".{}.partial", name.to_string_lossy()));
    let result = mtwin::viz::save(&temporary, scenario, simulation, &mut |what| {
        eprintln!("recording: {what}")
    });
    if let Err(e) = result {
        let _ = std::fs::remove_file(&temporary); // best effort: already failing
        return Err(e).with_context(|| format!("{}", path.display()));
    }
    std::fs::rename(&temporary, path).with_context(|| format!("cannot write {}", path.display()))
}

#[cfg(not(feature = "viz"))]
fn record(_: &Path, _: &Scenario, _: &Simulation) -> Result<()> {
    unreachable!("checked by check_recording_path")
}

fn check(file: &Path) -> Result<()> {
    match file.extension().and_then(|e| e.to_str()) {
        Some("urdf") => {
            let machine = Machine::from_urdf_file(file)?;
            println!("{}: ok, machine \"{}\"", file.display(), machine.name());
            describe(&machine);
        }
        Some("toml") => {
            let scenario = Scenario::load(file)?;
            let machine = &scenario.twin.machine;
            println!(
                "{}: ok, machine \"{}\" ({}), {} error parameters, seed {}",
                file.display(),
                machine.name(),
                scenario.machine_file.display(),
                scenario.twin.errors.parameters().len(),
                scenario.seed
            );
            if let Some(v) = &scenario.volumetric {
                let points: usize = v.grid.iter().map(|g| g.values.len()).product();
                println!(
                    "  volumetric map: {} model, {points} grid points",
                    v.model.name()
                );
            }
            if let Some(test) = &scenario.ballbar_test {
                for circle in &test.circles {
                    println!(
                        "  ball-bar: {} plane, {:.0} mm at {:.0} mm/min, {:.0}° data arc, {:.0} s",
                        circle.plane,
                        circle.radius * 1e3,
                        circle.feed * 6e4,
                        circle.data_arc.to_degrees(),
                        circle.duration()
                    );
                }
            }
        }
        _ => bail!(
            "{}: expected a scenario (.toml) or a machine model (.urdf)",
            file.display()
        ),
    }
    Ok(())
}

fn describe(machine: &Machine) {
    for info in machine.axes() {
        let side = if info.side == Side::Tool {
            "tool"
        } else {
            "workpiece"
        };
        let travel = match info.limits {
            Some((lower, upper)) if info.axis.is_linear() => {
                format!("{:.1} .. {:.1} mm", lower * 1e3, upper * 1e3)
            }
            Some((lower, upper)) => {
                format!("{:.1} .. {:.1} deg", lower.to_degrees(), upper.to_degrees())
            }
            None => "continuous".to_string(),
        };
        println!("  {}  {side:<9}  {travel}", info.axis);
    }
}

/// The drift report for people.
fn drift_text(report: &serde_json::Value) -> String {
    let mut out = format!(
        "ISO 230-3:2007 drift, ETVE for a {} min test{}\n\n{:>12} {:>14} {:>14} {:>10} {:>12} {:>16} {:>10}\n",
        report["etve_duration_min"],
        report["ambient_sensor"]
            .as_str()
            .map_or_else(String::new, |s| format!(" (ambient: {s})")),
        "channel",
        "first 60 min",
        "whole record",
        "stop min",
        "ETVE",
        "window min",
        "ΔT °C"
    );
    let cell = |v: &serde_json::Value| {
        v.as_f64()
            .map_or_else(|| "-".to_string(), |x| format!("{x:.3}"))
    };
    for c in report["channels"].as_array().into_iter().flatten() {
        let unit = c["unit"].as_str().unwrap_or("");
        let window = c["etve_window_min"].as_array().map_or_else(
            || "-".into(),
            |w| format!("{}-{}", cell(&w[0]), cell(&w[1])),
        );
        out += &format!(
            "{:>12} {:>10} {unit:<4}{:>10} {unit:<4}{:>10} {:>8} {unit:<4}{:>16} {:>10}\n",
            c["name"].as_str().unwrap_or(""),
            cell(&c[format!("range_60_{unit}")]),
            cell(&c[format!("range_{unit}")]),
            c["stop_min"]
                .as_f64()
                .map_or_else(|| "-".into(), |m| format!("{m:.0}")),
            cell(&c[format!("etve_{unit}")]),
            window,
            cell(&c["etve_ambient_range_degc"]),
        );
    }
    out
}

/// Writes `bytes` to `path` through a temporary file beside it, so a failure leaves no
/// partial file.
fn write_atomically(path: &Path, bytes: &[u8]) -> Result<()> {
    let name = path
        .file_name()
        .with_context(|| format!("{}: not a file name", path.display()))?;
    let temporary = path.with_file_name(format!(".{}.partial", name.to_string_lossy()));
    std::fs::write(&temporary, bytes)
        .with_context(|| format!("cannot write {}", temporary.display()))?;
    std::fs::rename(&temporary, path).with_context(|| format!("cannot write {}", path.display()))
}

/// `target` as a path relative to the folder that will hold `file` (both must exist but `file`).
fn relative_path(target: &Path, file: &Path) -> Result<String> {
    let folder = match file.parent() {
        Some(p) if !p.as_os_str().is_empty() => p,
        _ => Path::new("."),
    };
    let absolute = |p: &Path| {
        p.canonicalize()
            .with_context(|| format!("cannot resolve {}", p.display()))
    };
    let (target, folder) = (absolute(target)?, absolute(folder)?);
    let common = target
        .components()
        .zip(folder.components())
        .take_while(|(a, b)| a == b)
        .count();
    let mut relative = PathBuf::new();
    for _ in folder.components().skip(common) {
        relative.push("..");
    }
    relative.extend(target.components().skip(common));
    Ok(relative.to_string_lossy().replace('\\', "/"))
}

//! `mtwin analyze ballbar` and `mtwin discover ballbar`: the command line of this kind (flags,
//! help, the report on standard output). Like `main.rs`, this is the binary's layer: errors
//! are `anyhow`'s, with the file named once.

use super::discovery::discover_ballbar;
use super::iso230_4::{self, CircularTest};
use super::table::BallbarTable;
use crate::kinds::{Kind, ScenarioLoader, Verb};
use crate::machine::Plane;
use crate::math::{M_PER_MM, Real, trimmed};
use anyhow::{Context, Result, bail};
use clap::{ArgMatches, Args, FromArgMatches};
use std::path::PathBuf;

/// This kind in the registry.
pub const KIND: Kind = Kind {
    name: "ballbar",
    tables_are: "ball-bar tables",
    sections: &["ballbar", "servo"],
    tables: &["ballbar_<plane>.csv"],
    analyze: Some(Verb {
        command: || {
            CircleArgs::augment_args(clap::Command::new("ballbar"))
                    .about(
                        "Ball-bar circular test (direction ccw/cw, angle_deg, deviation_um, optional \
                         time_s), evaluated to ISO 230-4 with the diagnostics of ball-bar software; \
                         the plane, radius and feed from the table's preamble or from --plane, \
                         --radius-mm and --feed-mm-per-min",
                    )
                    .after_long_help(BALLBAR_CONVENTIONS)
        },
        run: analyze,
    }),
    discover: Some(Verb {
        command: || {
            DiscoverArgs::augment_args(clap::Command::new("ballbar"))
                .about("Circular-test radial deviations (ball-bar, ISO 230-4)")
                .long_about(DISCOVER_ABOUT)
        },
        run: discover,
    }),
};

const DISCOVER_ABOUT: &str = "\
Circular-test radial deviations (ball-bar, ISO 230-4); the plane, radius and feed from the
table's preamble or from --plane, --radius-mm and --feed-mm-per-min.

The base model is the radius, the centre offset, squareness and scale mismatch. Effects (axis
letters of the plane): servo_mismatch, backlash_*, lateral_play_*, reversal_spike_*,
straightness_*, cyclic_*, lobes (k per turn), radius_drift, sense_radius. Held-out data:
angular sectors.";

/// The ball-bar diagnostics' conventions, for `analyze ballbar --help`.
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
  reversal_lag_p_ms       time from p's programmed reversal to its actual one (servo lag), when a
                          significant backlash or spike of p places it (lateral play cannot)
  straightness_p_um       bow of p along q, peak-to-valley over the diameter, middle toward +q: S·sin³θ
  cyclic_p_um             periodic error of p along p, with cyclic_p_period_mm and _phase_deg
Each comes with its standard uncertainty; what the data cannot separate, and a decay or
period at an end of the range searched, is reported null with the reason.";

/// The table, and the conditions of the circular test where its preamble lacks them.
#[derive(Args)]
#[command(allow_negative_numbers = true)]
struct CircleArgs {
    /// The table (CSV with a header).
    file: PathBuf,
    /// Print JSON with stable keys instead of the report for people.
    #[arg(long)]
    json: bool,
    /// The plane, first axis then second (XY, YZ or ZX); angles run from the first axis
    /// toward the second, counter-clockwise seen from +Z, +X, +Y. Needed only when the
    /// table's preamble does not say (`# plane = XY`); it must agree when it does.
    #[arg(long, value_name = "PLANE")]
    plane: Option<Plane>,
    /// The radius of the test, the bar's nominal length (mm), when the preamble lacks it.
    #[arg(long, value_name = "MM", allow_negative_numbers = true)]
    radius_mm: Option<f64>,
    /// The programmed feed (mm/min), when the preamble lacks it.
    #[arg(long, value_name = "MM_PER_MIN", allow_negative_numbers = true)]
    feed_mm_per_min: Option<f64>,
}

#[derive(Args)]
struct DiscoverArgs {
    #[command(flatten)]
    circle: CircleArgs,
    /// Write the extended model as a scenario fragment (TOML) that `mtwin run` accepts:
    /// squareness, scale mismatch and lost motion as `[errors]`, play, spikes and the servo
    /// mismatch as `[servo]`; what has no scenario term as comments with its values.
    #[arg(long, value_name = "FILE.toml")]
    write_model: Option<PathBuf>,
    /// The scenario the written model extends (with `--write-model`): the fragment then runs
    /// as a scenario, and the servo mismatch is written relative to this scenario's servo.
    #[arg(long, value_name = "SCENARIO.toml", requires = "write_model")]
    extends: Option<PathBuf>,
}

impl CircleArgs {
    /// The test conditions of `table`: each from its preamble or from its flag (a flag that
    /// disagrees with the file is refused, naming both), then checked against what the data
    /// imply (the angles against the times give feed ÷ radius).
    fn test(&self, table: &BallbarTable) -> Result<CircularTest> {
        let file = self.file.display();
        let given = table.conditions;
        let plane = match (self.plane, given.plane) {
            (Some(flag), Some(stated)) if flag != stated => {
                bail!("--plane {flag} disagrees with {file}, whose preamble says plane = {stated}")
            }
            (flag, stated) => flag.or(stated),
        };
        let mm = |v: Real| trimmed(v / M_PER_MM, 6);
        let mm_per_min = |v: Real| trimmed(v / M_PER_MM * 60.0, 6);
        if let Some(r) = self.radius_mm
            && !(r.is_finite() && r > 0.0)
        {
            bail!("--radius-mm must be a positive number of millimetres, got {r}");
        }
        if let Some(f) = self.feed_mm_per_min
            && !(f.is_finite() && f > 0.0)
        {
            bail!("--feed-mm-per-min must be a positive number, got {f}");
        }
        let same = |a: Real, b: Real| (a - b).abs() <= 1e-9 * a.abs().max(b.abs());
        let radius = match (self.radius_mm.map(|r| r * M_PER_MM), given.radius) {
            (Some(flag), Some(stated)) if !same(flag, stated) => bail!(
                "--radius-mm {} disagrees with {file}, whose preamble says radius_mm = {}",
                mm(flag),
                mm(stated)
            ),
            (flag, stated) => flag.or(stated),
        };
        let feed = match (
            self.feed_mm_per_min.map(|f| f * M_PER_MM / 60.0),
            given.feed,
        ) {
            (Some(flag), Some(stated)) if !same(flag, stated) => bail!(
                "--feed-mm-per-min {} disagrees with {file}, whose preamble says feed_mm_per_min = {}",
                mm_per_min(flag),
                mm_per_min(stated)
            ),
            (flag, stated) => flag.or(stated),
        };
        let (Some(plane), Some(radius), Some(feed)) = (plane, radius, feed) else {
            let missing: Vec<&str> = [
                (plane.is_none(), "--plane XY|YZ|ZX"),
                (radius.is_none(), "--radius-mm R"),
                (feed.is_none(), "--feed-mm-per-min F"),
            ]
            .into_iter()
            .filter_map(|(absent, flag)| absent.then_some(flag))
            .collect();
            bail!(
                "a ball-bar table needs its test conditions and {file} does not give them all in \
                 its preamble: {}",
                missing.join(" ")
            );
        };
        // The data's own word on feed ÷ radius: the programmed angle against time.
        if let Some(speed) = super::plausible::speed_disagreement(table, radius, feed) {
            let stated = feed / radius;
            let source = |flag: bool, text: String| {
                if flag {
                    text
                } else {
                    format!("the preamble's {text}")
                }
            };
            bail!(
                "{file}: its angle_deg against time_s turn at {:.4} rad/s, which at {} gives a \
                     feed of {:.1} mm/min (or, at {}, a radius of {:.3} mm); the test conditions say \
                     {:.4} rad/s",
                speed,
                source(
                    self.radius_mm.is_some(),
                    format!("radius {} mm", mm(radius))
                ),
                mm_per_min(speed * radius).parse::<Real>().unwrap_or(0.0),
                source(
                    self.feed_mm_per_min.is_some(),
                    format!("feed {} mm/min", mm_per_min(feed))
                ),
                (feed / speed) / M_PER_MM,
                stated
            );
        }
        Ok(CircularTest {
            plane,
            radius,
            feed,
        })
    }
}

fn analyze(
    matches: &ArgMatches,
    _progress: &mut dyn FnMut(&str),
    _scenarios: &dyn ScenarioLoader,
) -> Result<String> {
    let args = CircleArgs::from_arg_matches(matches)?;
    let table = BallbarTable::read(&args.file)?;
    let test = args.test(&table)?;
    let evaluation =
        iso230_4::evaluate(&table, &test).with_context(|| format!("{}", args.file.display()))?;
    let mut cautions = super::plausible::cautions(&table, &test);
    if let Ok(diagnostics) = &evaluation.diagnostics {
        cautions.extend(super::plausible::unexplained(
            &table,
            diagnostics.rms,
            "the diagnostic fit",
        ));
    }
    Ok(if args.json {
        let mut report = evaluation.to_json();
        report["cautions"] = serde_json::json!(cautions);
        report["columns_not_read"] = serde_json::json!(table.columns_not_read);
        format!("{}\n", serde_json::to_string_pretty(&report)?)
    } else {
        let mut text = evaluation.to_text();
        for caution in &cautions {
            text += &format!("CAUTION: {caution}\n");
        }
        text + &crate::io::not_read_line(&table.columns_not_read)
    })
}

fn discover(
    matches: &ArgMatches,
    progress: &mut dyn FnMut(&str),
    scenarios: &dyn ScenarioLoader,
) -> Result<String> {
    let DiscoverArgs {
        circle: args,
        write_model,
        extends,
    } = DiscoverArgs::from_arg_matches(matches)?;
    if let Some(path) = &write_model {
        crate::io::check_folder_of(path)?;
    }
    // The base scenario is checked before the (long) discovery runs.
    let base = extends
        .as_ref()
        .map(|base| -> Result<_> {
            let servo = scenarios.ballbar_test(base)?.map(|t| t.servo);
            Ok((base, servo))
        })
        .transpose()?;
    let table = BallbarTable::read(&args.file)?;
    let test = args.test(&table)?;
    let discovery = discover_ballbar(&table, &test, |what| progress(what))
        .with_context(|| format!("{}", args.file.display()))?;
    if let Some(path) = &write_model {
        let relative = match &base {
            Some((base, _)) => Some(crate::io::relative_path(base, path)?),
            None => None,
        };
        let source = crate::io::relative_path(&args.file, path)?;
        let servo = base.as_ref().and_then(|(_, servo)| servo.as_ref());
        let fragment = discovery.to_scenario_fragment(&source, relative.as_deref(), servo);
        crate::io::write_atomically(path, fragment.as_bytes())?;
    }
    // What the table's data say against its labels, as analyze says it, and a final model
    // that leaves far more than the noise.
    let mut cautions = super::plausible::cautions(&table, &test);
    if let Some(last) = discovery.residual_steps().last() {
        let rms = (last
            .residuals
            .iter()
            .map(|r| r * r)
            .sum::<crate::math::Real>()
            / last.residuals.len().max(1) as crate::math::Real)
            .sqrt();
        cautions.extend(super::plausible::unexplained(
            &table,
            rms,
            &format!("the final model ({})", last.model),
        ));
    }
    Ok(if args.json {
        let mut report = discovery.to_json();
        report["cautions"] = serde_json::json!(cautions);
        report["columns_not_read"] = serde_json::json!(table.columns_not_read);
        format!("{}\n", serde_json::to_string_pretty(&report)?)
    } else {
        let mut text = discovery.to_text();
        for caution in &cautions {
            text += &format!("CAUTION: {caution}\n");
        }
        text += &crate::io::not_read_line(&table.columns_not_read);
        if let Some(path) = &write_model {
            text += &format!("\nExtended model written to {}\n", path.display());
        }
        text
    })
}

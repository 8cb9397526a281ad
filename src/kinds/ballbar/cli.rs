//! `mtwin analyze ballbar` and `mtwin discover ballbar`: the command line of this kind (flags,
//! help, the report on standard output). Like `main.rs`, this is the binary's layer: errors
//! are `anyhow`'s, with the file named once.

use super::discovery::discover_ballbar;
use super::iso230_4::{self, CircularTest};
use super::table::BallbarTable;
use crate::kinds::{Kind, Verb};
use crate::machine::Plane;
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
                         needs --plane, --radius-mm and --feed-mm-per-min",
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
Circular-test radial deviations (ball-bar, ISO 230-4); needs --plane, --radius-mm and
--feed-mm-per-min.

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
  reversal_lag_p_ms       time from p's programmed reversal to its actual one (servo lag)
  straightness_p_um       bow of p along q, peak-to-valley over the diameter, middle toward +q: S·sin³θ
  cyclic_p_um             periodic error of p along p, with cyclic_p_period_mm and _phase_deg
Each comes with its standard uncertainty; what the data cannot separate is reported null
with the reason.";

/// The table and the conditions of the circular test, which a ball-bar table does not hold.
#[derive(Args)]
struct CircleArgs {
    /// The table (CSV with a header).
    file: PathBuf,
    /// Print JSON with stable keys instead of the report for people.
    #[arg(long)]
    json: bool,
    /// The plane, first axis then second (XY, YZ or ZX); angles run from the first axis
    /// toward the second, counter-clockwise seen from +Z, +X, +Y.
    #[arg(long, value_name = "PLANE")]
    plane: Option<Plane>,
    /// The radius of the test, the bar's nominal length (mm).
    #[arg(long, value_name = "MM")]
    radius_mm: Option<f64>,
    /// The programmed feed (mm/min).
    #[arg(long, value_name = "MM_PER_MIN")]
    feed_mm_per_min: Option<f64>,
}

#[derive(Args)]
struct DiscoverArgs {
    #[command(flatten)]
    circle: CircleArgs,
    /// Refused: ball-bar diagnostics (servo, lost motion, spikes) are not all error-model
    /// terms, so there is no model to write.
    #[arg(long, value_name = "FILE.toml", hide = true)]
    write_model: Option<PathBuf>,
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
}

fn analyze(matches: &ArgMatches, _progress: &mut dyn FnMut(&str)) -> Result<String> {
    let args = CircleArgs::from_arg_matches(matches)?;
    let test = args.test()?;
    let table = BallbarTable::read(&args.file)?;
    let evaluation =
        iso230_4::evaluate(&table, &test).with_context(|| format!("{}", args.file.display()))?;
    Ok(if args.json {
        format!("{}\n", serde_json::to_string_pretty(&evaluation.to_json())?)
    } else {
        evaluation.to_text()
    })
}

fn discover(matches: &ArgMatches, progress: &mut dyn FnMut(&str)) -> Result<String> {
    let DiscoverArgs {
        circle: args,
        write_model,
    } = DiscoverArgs::from_arg_matches(matches)?;
    if write_model.is_some() {
        bail!(
            "--write-model is for positioning tables: ball-bar diagnostics (servo, lost motion, spikes) are not all error-model terms"
        );
    }
    let test = args.test()?;
    let table = BallbarTable::read(&args.file)?;
    let discovery = discover_ballbar(&table, &test, |what| progress(what))
        .with_context(|| format!("{}", args.file.display()))?;
    Ok(if args.json {
        format!("{}\n", serde_json::to_string_pretty(&discovery.to_json())?)
    } else {
        discovery.to_text()
    })
}

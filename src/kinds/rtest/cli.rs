//! `mtwin analyze rtest`: the command line of this kind. Like `main.rs`, this is the binary's
//! layer: errors are `anyhow`'s, with the file named once.

use super::analysis::{Fit, RtestEvaluation, evaluate};
use super::table::RtestTable;
use crate::kinds::{Kind, ScenarioLoader, Verb};
use anyhow::{Context, Result};
use clap::{ArgMatches, Args, FromArgMatches};
use std::path::PathBuf;

/// This kind in the registry.
pub const KIND: Kind = Kind {
    name: "rtest",
    tables_are: "R-test tables",
    sections: &["rtest"],
    tables: &["rtest.csv"],
    analyze: Some(Verb {
        command: || {
            RtestArgs::augment_args(clap::Command::new("rtest"))
                .about(
                    "R-test (ISO 10791-6 kinematic tests): per test the deviation ranges in X, Y, \
                     Z and the fitted circle or line of the tool relative to the sphere",
                )
                .after_long_help(JSON_KEYS)
        },
        run: analyze,
    }),
    discover: None,
};

const JSON_KEYS: &str = "\
Table: test, dx_um, dy_um, dz_um and a rotary angle (a_deg, b_deg, c_deg) are required; point,
time_s, x_mm/y_mm/z_mm and probe1_um… are read when present. d = tool (nest) relative to the
sphere centre, actual − nominal, along the machine's X, Y, Z, zeroed at each test's first pose.

JSON keys (--json), per entry of `tests`:
  name, poses, swept_axis (A|B|C|null), swept_deg [first, last]
  range_um [X, Y, Z]          max − min of the deviation along each axis (ISO 10791-6)
  max_deviation_um            largest length of the 3-D deviation
  fit.kind = circle           (swept ≥ 180°) d = centre_um + cos_um·cos θ + sin_um·sin θ,
                              radius_um = √((|cos|² + |sin|²)/2), residual_um (RMS)
  fit.kind = line             (shorter swings) d = intercept_um + slope_um_per_deg·θ, residual_um
  fit.kind = none             no rotary axis turns";

#[derive(Args)]
struct RtestArgs {
    /// The table (CSV with a header; see below).
    file: PathBuf,
    /// Print JSON with stable keys instead of the report for people.
    #[arg(long)]
    json: bool,
    /// Also draw each test (deviation against the swept angle, and the XY trajectory) into
    /// this SVG file.
    #[arg(long, value_name = "FILE.svg")]
    svg: Option<PathBuf>,
}

fn analyze(
    matches: &ArgMatches,
    _progress: &mut dyn FnMut(&str),
    _scenarios: &dyn ScenarioLoader,
) -> Result<String> {
    let args = RtestArgs::from_arg_matches(matches)?;
    let table = RtestTable::read(&args.file)?;
    let evaluation = evaluate(&table).with_context(|| format!("{}", args.file.display()))?;
    if let Some(path) = &args.svg {
        crate::io::write_atomically(path, super::plot::svg(&table).as_bytes())?;
    }
    let (setup, said) = table.setup_report();
    let cautions = super::plausible::cautions(&table);
    Ok(if args.json {
        let mut report = serde_json::to_value(&evaluation)?;
        report["setup"] = setup;
        report["cautions"] = serde_json::json!(cautions);
        report["columns_not_read"] = serde_json::json!(table.columns_not_read);
        format!("{}\n", serde_json::to_string_pretty(&report)?)
    } else {
        let mut text = to_text(&evaluation);
        for caution in &cautions {
            text += &format!("CAUTION: {caution}\n");
        }
        text += &crate::io::not_read_line(&table.columns_not_read);
        // The set-up after the title line.
        match text.split_once('\n') {
            Some((title, rest)) => format!("{title}\n{said}{rest}"),
            None => text + &said,
        }
    })
}

/// The report for people.
pub fn to_text(evaluation: &RtestEvaluation) -> String {
    let mut out = String::from(
        "R-test (ISO 10791-6): tool relative to the sphere, actual − nominal, machine axes\n",
    );
    for t in &evaluation.tests {
        out += &format!(
            "\n{} ({} poses{}):\n  deviation range  X {:.3}  Y {:.3}  Z {:.3} µm;  largest 3-D deviation {:.3} µm\n",
            t.name,
            t.poses,
            t.swept_axis.as_ref().map_or(String::new(), |a| format!(
                ", {a} from {:.1}° to {:.1}°",
                t.swept_deg[0], t.swept_deg[1]
            )),
            t.range_um[0],
            t.range_um[1],
            t.range_um[2],
            t.max_deviation_um
        );
        let v = |a: [f64; 3]| format!("({:.3}, {:.3}, {:.3})", a[0], a[1], a[2]);
        out += &match &t.fit {
            Fit::Circle {
                centre_um,
                cos_um,
                sin_um,
                radius_um,
                residual_um,
            } => format!(
                "  circle: radius {radius_um:.3} µm, centre {} µm, cos θ {} µm, sin θ {} µm, residual {residual_um:.3} µm\n",
                v(*centre_um),
                v(*cos_um),
                v(*sin_um)
            ),
            Fit::Line {
                intercept_um,
                slope_um_per_deg,
                residual_um,
            } => format!(
                "  line: {} µm + {} µm/° · θ, residual {residual_um:.3} µm\n",
                v(*intercept_um),
                v(*slope_um_per_deg)
            ),
            Fit::None => "  no rotary axis turns: nothing fitted\n".to_string(),
        };
    }
    out
}

//! `mtwin analyze probe`: the command line of this kind (flags, help, the report on standard
//! output). Like `main.rs`, this is the binary's layer: errors are `anyhow`'s.

use super::analysis::evaluate;
use super::table::ProbeTable;
use crate::kinds::{Kind, ScenarioLoader, Verb};
use crate::math::M_PER_MM;
use anyhow::{Context, Result, bail};
use clap::{ArgMatches, Args, FromArgMatches};
use std::path::PathBuf;

/// This kind in the registry.
pub const KIND: Kind = Kind {
    name: "probe",
    tables_are: "touch-probe tables",
    sections: &["probe"],
    tables: &["probe.csv", "spheres.csv"],
    analyze: Some(Verb {
        command: || {
            ProbeArgs::augment_args(clap::Command::new("probe"))
                .about(
                    "Touch-probe table (cycle, kind, feature, point, latched x_mm y_mm z_mm, approach \
                     i j k): sphere fits with form and radius error, ring diameter and roundness, \
                     ball-plate centre-distance errors; the stylus radius from the preamble or \
                     --stylus-radius-mm",
                )
                .after_long_help(JSON_KEYS)
        },
        run: analyze,
    }),
    discover: None,
};

/// The `--json` keys, for `analyze probe --help`.
const JSON_KEYS: &str = "\
--json keys (lengths in mm, deviations in µm, positions in machine axis coordinates):
  stylus_radius_mm        the stylus radius used to compensate
  spheres[]               one per sphere or plate-ball feature: cycle, kind (sphere|plate),
                          feature, a_deg/b_deg/c_deg (those the table has), centre_mm [x, y, z],
                          radius_mm (fit of the stylus centres − stylus radius), radius_error_um
                          (− calibrated; null without cal_diameter_mm), form_um (range of the
                          residuals), rms_um, p_ftu_um (ISO 10360-5, 25-point features; else
                          null), points
  rings[]                 cycle, kind, feature, angles, side (bore|plug), centre_mm, diameter_mm,
                          diameter_error_um (null without cal_diameter_mm), roundness_um
                          (range of the circle fit's residuals), points
  plates[]                per ball-plate placement: cycle, pairs, max_abs_error_um,
                          rms_error_um, distances[] {from, to, calibrated_mm, measured_mm,
                          error_um = measured − calibrated}
  mesh_points[]           cycle, feature, point, surface_mm (latched centre + stylus radius
                          along the approach)
  cautions[]              what the touches say against the set-up: approach vectors off the
                          feature's radius, a diameter far from the calibration, a short arc
  columns_not_read[]      columns of the table the reader read past (no figure depends on them)";

#[derive(Args)]
#[command(allow_negative_numbers = true)]
struct ProbeArgs {
    /// The `probe` table (CSV with a header).
    file: PathBuf,
    /// Print JSON with stable keys instead of the report for people.
    #[arg(long)]
    json: bool,
    /// The stylus radius the controller used (mm), when the preamble lacks it; it must agree
    /// when it has it.
    #[arg(long, value_name = "MM", allow_negative_numbers = true)]
    stylus_radius_mm: Option<f64>,
}

fn analyze(
    matches: &ArgMatches,
    _progress: &mut dyn FnMut(&str),
    _scenarios: &dyn ScenarioLoader,
) -> Result<String> {
    let args = ProbeArgs::from_arg_matches(matches)?;
    let file = args.file.display().to_string();
    let table = ProbeTable::read(&args.file)?;
    if let Some(r) = args.stylus_radius_mm
        && !(r.is_finite() && r >= 0.0)
    {
        bail!("--stylus-radius-mm must be a radius ≥ 0 in millimetres, got {r}");
    }
    let flag = args.stylus_radius_mm.map(|r| r * M_PER_MM);
    let radius = match (flag, table.conditions.stylus_radius) {
        (Some(f), Some(s)) if (f - s).abs() > 1e-12 => bail!(
            "--stylus-radius-mm {} disagrees with {file}, whose preamble says stylus_radius_mm = {}",
            f / M_PER_MM,
            s / M_PER_MM
        ),
        (f, s) => f.or(s),
    };
    let Some(radius) = radius else {
        bail!(
            "{file} does not give the stylus radius (`# stylus_radius_mm = R`): pass --stylus-radius-mm R"
        );
    };
    let evaluation = evaluate(&table, radius).with_context(|| file.clone())?;
    Ok(if args.json {
        format!("{}\n", serde_json::to_string_pretty(&evaluation.to_json())?)
    } else {
        evaluation.to_text()
    })
}

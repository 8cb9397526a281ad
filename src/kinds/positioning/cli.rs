//! `mtwin analyze positioning` and `mtwin discover positioning`: the command line of this
//! kind (flags, help, the report on standard output). Like `main.rs`, this is the binary's
//! layer: errors are `anyhow`'s, with the file named once.

use super::conditions::PositioningTest;
use super::discovery::{PositioningOptions, discover_positioning};
use super::iso230_2;
use super::table::PositioningTable;
use super::thermal_series::thermal_series;
use crate::kinds::{Kind, ScenarioLoader, Verb};
use anyhow::{Context, Result, bail};
use clap::{ArgMatches, Args, FromArgMatches};
use std::path::PathBuf;

/// This kind in the registry.
pub const KIND: Kind = Kind {
    name: "positioning",
    tables_are: "positioning tables",
    sections: &["iso230_2", "warmup", "iso230_3_linear", "laser"],
    tables: &["positioning.csv"],
    analyze: Some(Verb {
        command: || {
            AnalyzeArgs::augment_args(clap::Command::new("positioning")).about(
                "Linear positioning deviations (laser interferometer), evaluated to ISO 230-2:2014: \
                 target_mm, deviation_um, and optionally axis, run, direction (+/-), time_min, \
                 temp_<sensor>_degc",
            )
        },
        run: analyze,
    }),
    discover: Some(Verb {
        command: || {
            DiscoverArgs::augment_args(clap::Command::new("positioning"))
                .about("Linear positioning deviations (laser interferometer)")
                .long_about(DISCOVER_ABOUT)
        },
        run: discover,
    }),
};

const DISCOVER_ABOUT: &str = "\
Linear positioning deviations (laser interferometer).

The base model is a reference error profile (piecewise linear through the targets of the
coldest run, or the first without temperatures; its values fitted to all runs) plus the
nominal thermal expansion of the axis, position × (temperature − the reference run's
temperature) × the nominal coefficient. Effects: reversal, reversal_position,
reversal_thermal, thermal_lag, sensor_lag, thermal_scale, thermal_offset, second_heat_source,
periodic, nonlinear_scale, time_drift. Held-out data: one run at a time with three runs or more, else
contiguous blocks in time.";

#[derive(Args)]
struct AnalyzeArgs {
    /// The table (CSV with a header).
    file: PathBuf,
    /// Print JSON with stable keys instead of the report for people.
    #[arg(long)]
    json: bool,
    /// In a thermal series, list every run's time and temperatures (else a few of them).
    #[arg(long)]
    verbose: bool,
}

#[derive(Args)]
struct DiscoverArgs {
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
    #[arg(
        long,
        value_name = "PPM",
        default_value_t = 11.7,
        allow_negative_numbers = true
    )]
    expansion_ppm_per_degc: f64,
    /// The temperature column to use (`<sensor>` of temp_<sensor>_degc); default the first.
    #[arg(long, value_name = "NAME")]
    sensor: Option<String>,
    /// Shortest period the cyclic-error search considers (mm).
    #[arg(
        long,
        value_name = "MM",
        default_value_t = 2.0,
        allow_negative_numbers = true
    )]
    min_period_mm: f64,
}

fn analyze(
    matches: &ArgMatches,
    _progress: &mut dyn FnMut(&str),
    _scenarios: &dyn ScenarioLoader,
) -> Result<String> {
    let AnalyzeArgs {
        file,
        json,
        verbose,
    } = AnalyzeArgs::from_arg_matches(matches)?;
    let table = PositioningTable::read(&file)?;
    let axis = table
        .axis
        .map_or_else(|| "not named".to_string(), |a| a.to_string());
    // A drift test (ISO 230-3 §7) is a thermal series but not an ISO 230-2 test: by the
    // preamble's word, or because the ISO 230-2 evaluation finds it is not one.
    let stated_drift = table.conditions.test == Some(PositioningTest::Iso230_3Linear);
    let evaluation = if stated_drift {
        Err("the file's preamble names the ISO 230-3 §7 linear-motion test".to_string())
    } else {
        iso230_2::evaluate(&table).map_err(|e| e.to_string())
    };
    Ok(match evaluation {
        Ok(result) if json => format!(
            "{}\n",
            serde_json::to_string_pretty(&result.to_json(&table))?
        ),
        Ok(result) => result.to_text_with(&table, verbose),
        Err(why) => match thermal_series(&table) {
            Some(series) if json => format!(
                "{}\n",
                serde_json::to_string_pretty(&series.report_json(&table, &why))?
            ),
            Some(series) if stated_drift => format!(
                "ISO 230-3 §7 linear-motion drift record, axis {axis} (test = iso230_3_linear in the file).\n{}{}{}",
                table.conditions.report().1,
                series.to_text_with(verbose),
                crate::io::not_used_line(&table.conditions.not_used)
                    + &crate::io::not_read_line(&table.columns_not_read)
            ),
            Some(series) => format!(
                "ISO 230-3 drift record, axis {axis}: no ISO 230-2 figures ({why}).\n{}{}{}",
                table.conditions.report().1,
                series.to_text_with(verbose),
                crate::io::not_used_line(&table.conditions.not_used)
                    + &crate::io::not_read_line(&table.columns_not_read)
            ),
            None => bail!("{}: {why}", file.display()),
        },
    })
}

fn discover(
    matches: &ArgMatches,
    progress: &mut dyn FnMut(&str),
    scenarios: &dyn ScenarioLoader,
) -> Result<String> {
    let args = DiscoverArgs::from_arg_matches(matches)?;
    let file = &args.file;
    if !args.expansion_ppm_per_degc.is_finite() {
        bail!(
            "--expansion-ppm-per-degc must be a finite number, got {}",
            args.expansion_ppm_per_degc
        );
    }
    if !(args.min_period_mm.is_finite() && args.min_period_mm > 0.0) {
        bail!(
            "--min-period-mm must be a positive number of millimetres, got {}",
            args.min_period_mm
        );
    }
    if let Some(path) = &args.write_model {
        crate::io::check_folder_of(path)?;
    }
    let table = PositioningTable::read(file)?;
    let options = PositioningOptions {
        expansion: args.expansion_ppm_per_degc * 1e-6,
        sensor: args.sensor,
        min_period: args.min_period_mm * 1e-3,
        ..PositioningOptions::default()
    };
    let discovery = discover_positioning(&table, options, |what| progress(what))
        .with_context(|| format!("{}", file.display()))?;
    if let Some(path) = &args.write_model {
        let base = match &args.extends {
            Some(base) => {
                scenarios.check(base)?;
                Some(crate::io::relative_path(base, path)?)
            }
            None => None,
        };
        // The table is the measured temperature record of the model's temperature terms.
        let source = crate::io::relative_path(file, path)?;
        let fragment = discovery.to_scenario_fragment(&source, base.as_deref())?;
        crate::io::write_atomically(path, fragment.as_bytes())?;
    }
    // What the table's data say against its labels, as analyze says it: discovery fits
    // whatever it is given, so a caution here is a caution on every effect it names.
    let cautions = super::plausible::data_cautions(&table);
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
        if let Some(path) = &args.write_model {
            text += &format!("\nExtended model written to {}\n", path.display());
        }
        text
    })
}

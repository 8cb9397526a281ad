//! `mtwin analyze drift`: the command line of this kind (flags, help, the report on standard
//! output). Like `main.rs`, this is the binary's layer: errors are `anyhow`'s.

use super::iso230_3::drift_report;
use super::table::DriftTable;
use crate::kinds::{Kind, Verb};
use anyhow::{Result, bail};
use clap::{ArgMatches, Args, FromArgMatches};
use std::path::PathBuf;

/// This kind in the registry.
pub const KIND: Kind = Kind {
    name: "drift",
    tables_are: "drift tables",
    sections: &[],
    tables: &[],
    analyze: Some(Verb {
        command: || {
            AnalyzeArgs::augment_args(clap::Command::new("drift")).about(
                "Displacement channels against time (time_min, <channel>_um or _urad, \
                 temp_<sensor>_degc), evaluated to ISO 230-3:2007: drift ranges, stop criterion, ETVE",
            )
        },
        run: analyze,
    }),
    discover: None,
};

#[derive(Args)]
struct AnalyzeArgs {
    /// The table (CSV with a header).
    file: PathBuf,
    /// Print JSON with stable keys instead of the report for people.
    #[arg(long)]
    json: bool,
    /// The duration of the performance test the ETVE is for (min).
    #[arg(long, value_name = "MIN", default_value_t = 60.0)]
    etve_min: f64,
}

fn analyze(matches: &ArgMatches, _progress: &mut dyn FnMut(&str)) -> Result<String> {
    let AnalyzeArgs {
        file,
        json,
        etve_min,
    } = AnalyzeArgs::from_arg_matches(matches)?;
    if !(etve_min.is_finite() && etve_min > 0.0) {
        bail!("--etve-min must be a positive number of minutes, got {etve_min}");
    }
    let table = DriftTable::read(&file)?;
    let report = drift_report(&table, etve_min * 60.0);
    Ok(if json {
        format!("{}\n", serde_json::to_string_pretty(&report)?)
    } else {
        drift_text(&report)
    })
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
        // Keys use the file's spelling; people read µm and µrad.
        let shown = match unit {
            "um" => "µm",
            "urad" => "µrad",
            other => other,
        };
        let window = c["etve_window_min"].as_array().map_or_else(
            || "-".into(),
            |w| format!("{}-{}", cell(&w[0]), cell(&w[1])),
        );
        out += &format!(
            "{:>12} {:>10} {shown:<4}{:>10} {shown:<4}{:>10} {:>8} {shown:<4}{:>16} {:>10}\n",
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

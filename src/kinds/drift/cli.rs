//! `mtwin analyze drift`: the command line of this kind (flags, help, the report on standard
//! output). Like `main.rs`, this is the binary's layer: errors are `anyhow`'s.

use super::iso230_3::drift_report;
use super::table::DriftTable;
use crate::io::not_used_line;
use crate::kinds::{Kind, ScenarioLoader, Verb};
use crate::math::trimmed;
use anyhow::{Result, bail};
use clap::{ArgMatches, Args, FromArgMatches};
use std::path::PathBuf;

/// This kind in the registry.
pub const KIND: Kind = Kind {
    name: "drift",
    tables_are: "drift tables",
    sections: &["iso230_3_etve", "iso230_3_spindle"],
    tables: &["drift.csv"],
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
    #[arg(
        long,
        value_name = "MIN",
        default_value_t = 60.0,
        allow_negative_numbers = true
    )]
    etve_min: f64,
    /// The distance l between the two sensors of a pair (x1/x2, y1/y2), for the tilts A and B,
    /// when the table's preamble does not say (`# spacing_mm = 100`); it must agree when it does.
    #[arg(long, value_name = "MM", allow_negative_numbers = true)]
    spacing_mm: Option<f64>,
    /// The temperature column of the ambient air (`<sensor>` of temp_<sensor>_degc), when the
    /// preamble does not say (`# ambient_sensor = air`); default the first.
    #[arg(long, value_name = "NAME")]
    ambient_sensor: Option<String>,
}

fn analyze(
    matches: &ArgMatches,
    _progress: &mut dyn FnMut(&str),
    _scenarios: &dyn ScenarioLoader,
) -> Result<String> {
    let AnalyzeArgs {
        file,
        json,
        etve_min,
        spacing_mm,
        ambient_sensor,
    } = AnalyzeArgs::from_arg_matches(matches)?;
    if !(etve_min.is_finite() && etve_min > 0.0) {
        bail!("--etve-min must be a positive number of minutes, got {etve_min}");
    }
    if let Some(mm) = spacing_mm
        && !(mm.is_finite() && mm > 0.0)
    {
        bail!("--spacing-mm must be a positive number of millimetres, got {mm}");
    }
    let mut table = DriftTable::read(&file)?;
    let shown = file.display();
    let spacing = match (table.conditions.spacing, spacing_mm) {
        (Some(stated), Some(flag)) if (stated * 1e3 - flag).abs() > 1e-9 * flag.max(1.0) => bail!(
            "--spacing-mm {flag} disagrees with {shown}, whose preamble says spacing_mm = {}",
            trimmed(stated * 1e3, 6)
        ),
        (stated, flag) => stated.or(flag.map(|mm| mm * 1e-3)),
    };
    match (&table.conditions.ambient_sensor, ambient_sensor) {
        (Some(stated), Some(flag)) if *stated != flag => bail!(
            "--ambient-sensor {flag} disagrees with {shown}, whose preamble says ambient_sensor = {stated}"
        ),
        (None, Some(flag)) => {
            if !table.temperatures.iter().any(|(name, _)| *name == flag) {
                let names: Vec<&str> = table.temperatures.iter().map(|(n, _)| n.as_str()).collect();
                bail!(
                    "--ambient-sensor {flag}: {shown} has no column temp_{flag}_degc (its sensors: {})",
                    if names.is_empty() {
                        "none".to_string()
                    } else {
                        names.join(", ")
                    }
                );
            }
            table.conditions.ambient_sensor = Some(flag);
        }
        _ => {}
    }
    let report = drift_report(&table, etve_min * 60.0, spacing);
    Ok(if json {
        format!("{}\n", serde_json::to_string_pretty(&report)?)
    } else {
        drift_text(&report)
    })
}

/// What the preamble said of the test, one line (ISO 230-3 §5.4 asks the report to state the
/// control mode and where the sensors were), and for a spindle test its programme.
fn conditions_text(c: &serde_json::Value) -> String {
    let mut said = Vec::new();
    if let Some(control) = c["control"].as_str() {
        said.push(format!("control {control}"));
    }
    if let Some(hold) = c["hold_mm"].as_str() {
        said.push(format!("axes at {hold} mm"));
    }
    if let Some(first) = c["first_mm"].as_f64() {
        said.push(format!(
            "first pair {} mm above the tool point",
            trimmed(first, 3)
        ));
    }
    let mut out = if said.is_empty() {
        String::new()
    } else {
        format!("Conditions: {}.\n", said.join(", "))
    };
    let programme = match (
        c["programme"].as_str(),
        c["speed_rpm"].as_f64(),
        c["spectrum"].as_str(),
    ) {
        (Some("constant"), Some(rpm), _) => Some(format!("constant {} rpm", trimmed(rpm, 3))),
        (Some("spectrum"), _, Some(steps)) => Some(format!("spectrum {steps}")),
        _ => None,
    };
    if let Some(run) = c["run_min"].as_f64() {
        out += &format!(
            "Spindle {}running for t = {} min{}; d(·)_t is taken over the running period.\n",
            programme.map_or_else(String::new, |p| format!("programme {p}, ")),
            trimmed(run, 3),
            c["stop_min"].as_f64().map_or_else(String::new, |s| format!(
                ", then stopped for {} min",
                trimmed(s, 3)
            ))
        );
    }
    out
}

/// The drift report for people.
fn drift_text(report: &serde_json::Value) -> String {
    let etve_test = report["test"].as_str() == Some("iso230_3_etve");
    let mut out = format!(
        "ISO 230-3:2007 {}, ETVE for a {} min test{}\n",
        if etve_test {
            "§5 ETVE test (test = iso230_3_etve in the file)"
        } else {
            "drift record"
        },
        report["etve_duration_min"],
        report["ambient_sensor"]
            .as_str()
            .map_or_else(String::new, |s| format!(" (ambient: {s})")),
    );
    if let Some(l) = report["spacing_mm"].as_f64() {
        out += &format!(
            "Tilts from the sensor pairs {} mm apart: A = (Y1 − Y2)/l about X, B = (X2 − X1)/l about Y.\n",
            trimmed(l, 3)
        );
    }
    out += &conditions_text(&report["conditions"]);
    let run_min = report["conditions"]["run_min"].as_f64();
    // ISO 230-3 §5 has no stop criterion: the ETVE test runs as long as possible.
    out += &format!(
        "\n{:>8} {:>14} {}{:>14} {}{:>14} {:>12} {:>8}\n",
        "channel",
        "first 60 min",
        run_min.map_or_else(String::new, |t| format!(
            "{:>14} ",
            format!("t = {} min", trimmed(t, 1))
        )),
        "whole record",
        if etve_test {
            String::new()
        } else {
            format!("{:>9} ", "stop min")
        },
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
            |w| {
                let minute = |v: &serde_json::Value| {
                    v.as_f64().map_or_else(|| "-".into(), |m| trimmed(m, 1))
                };
                format!("{}–{}", minute(&w[0]), minute(&w[1]))
            },
        );
        let stop = if etve_test {
            String::new()
        } else {
            format!(
                "{:>9} ",
                c["stop_min"]
                    .as_f64()
                    .map_or_else(|| "-".into(), |m| format!("{m:.0}"))
            )
        };
        let run = if run_min.is_some() {
            format!("{:>9} {shown:<4} ", cell(&c[format!("range_run_{unit}")]))
        } else {
            String::new()
        };
        out += &format!(
            "{:>8} {:>9} {shown:<4} {run}{:>9} {shown:<4} {stop}{:>9} {shown:<4} {:>12} {:>8}\n",
            c["name"].as_str().unwrap_or("").to_uppercase(),
            cell(&c[format!("range_60_{unit}")]),
            cell(&c[format!("range_{unit}")]),
            cell(&c[format!("etve_{unit}")]),
            window,
            cell(&c["etve_ambient_range_degc"]),
        );
    }
    for caution in report["cautions"].as_array().into_iter().flatten() {
        out += &format!("CAUTION: {}\n", caution.as_str().unwrap_or(""));
    }
    out += &not_used_line(
        report["preamble_not_used"]
            .as_array()
            .into_iter()
            .flatten()
            .filter_map(|k| k.as_str()),
    );
    let not_read: Vec<&str> = report["columns_not_read"]
        .as_array()
        .into_iter()
        .flatten()
        .filter_map(|k| k.as_str())
        .collect();
    out += &crate::io::not_read_line(&not_read);
    out
}

//! The spindle table's preamble keys that describe the rows — `revolutions`, `speeds_rpm` and
//! `setups`, which [`super::run`] writes — checked against the rows, so that a preamble cannot
//! say one thing while the data say another.
//!
//! The writer's structure: for each set-up of `setups` (in order), for each speed of
//! `speeds_rpm` (in order), one run of `revolutions` recorded revolutions. So, when a key is
//! given:
//!
//! * `revolutions = N`: every run has `N` revolutions;
//! * `speeds_rpm = w1 w2 …`: every set-up's runs, in file order, are at `w1, w2, …` (rpm,
//!   signed; a speed matches within [`SPEED_TOLERANCE`] of it or 0.001 rpm, as a speed derived
//!   from rounded times carries their rounding);
//! * `setups = a b …`: the set-ups in order of first appearance are `a, b, …` (a table without
//!   a `setup` column is one unnamed set-up, which matches a list of one).
//!
//! A mismatch is an error at the preamble line naming the key, what it says and what the rows
//! say (with the line where the run in question starts).

use crate::io::{Conditions, TableError};
use crate::math::{Real, trimmed};

/// Relative tolerance on a speed (0.1 %).
pub const SPEED_TOLERANCE: Real = 1e-3;

/// One run as read: its set-up, speed, revolutions and the line of its first row.
pub(super) struct RunSummary<'a> {
    pub setup: &'a str,
    pub speed_rpm: Real,
    pub revolutions: usize,
    pub line: Option<u64>,
}

fn at(line: Option<u64>) -> String {
    line.map_or_else(String::new, |l| format!(" (line {l})"))
}

fn rpm_list(speeds: &[Real]) -> String {
    speeds
        .iter()
        .map(|w| trimmed(*w, 3))
        .collect::<Vec<_>>()
        .join(" ")
}

/// Checks `revolutions`, `speeds_rpm` and `setups`, when the preamble gives them, against
/// `runs` (every run of the table, in file order).
pub(super) fn check(
    conditions: &Conditions,
    file: &str,
    runs: &[RunSummary<'_>],
) -> Result<(), TableError> {
    let fail = |line: u64, message: String| TableError::new(file, Some(line), message);
    if let Some((text, line)) = conditions.get("revolutions") {
        let stated = text
            .parse::<usize>()
            .ok()
            .filter(|n| *n > 0)
            .ok_or_else(|| {
                fail(
                    line,
                    format!("revolutions = {text}: expected a positive whole number"),
                )
            })?;
        if let Some(run) = runs.iter().find(|r| r.revolutions != stated) {
            return Err(fail(
                line,
                format!(
                    "revolutions = {stated} in the preamble, but the run of set-up `{}` at {} rpm{} \
                     has {} revolutions",
                    run.setup,
                    trimmed(run.speed_rpm, 3),
                    at(run.line),
                    run.revolutions
                ),
            ));
        }
    }
    let mut setups: Vec<&str> = Vec::new();
    for run in runs {
        if !setups.contains(&run.setup) {
            setups.push(run.setup);
        }
    }
    if let Some((text, line)) = conditions.get("speeds_rpm") {
        let stated: Vec<Real> = text
            .split_whitespace()
            .map(|v| v.parse::<Real>().ok().filter(|v| v.is_finite()))
            .collect::<Option<Vec<_>>>()
            .filter(|v| !v.is_empty())
            .ok_or_else(|| {
                fail(
                    line,
                    format!("speeds_rpm = {text}: expected speeds in rpm separated by spaces"),
                )
            })?;
        let same = |a: Real, b: Real| (a - b).abs() <= (SPEED_TOLERANCE * b.abs()).max(1e-3);
        for setup in &setups {
            let these: Vec<&RunSummary<'_>> = runs.iter().filter(|r| r.setup == *setup).collect();
            let found: Vec<Real> = these.iter().map(|r| r.speed_rpm).collect();
            let matches =
                found.len() == stated.len() && found.iter().zip(&stated).all(|(a, b)| same(*a, *b));
            if !matches {
                return Err(fail(
                    line,
                    format!(
                        "speeds_rpm = {} in the preamble, but set-up `{setup}` was recorded at {} rpm \
                         (its runs from{})",
                        rpm_list(&stated),
                        rpm_list(&found),
                        at(these[0].line)
                    ),
                ));
            }
        }
    }
    if let Some((text, line)) = conditions.get("setups") {
        let stated: Vec<&str> = text.split_whitespace().collect();
        let unnamed = setups == [""] && stated.len() == 1;
        if stated != setups && !unnamed {
            let found: Vec<String> = setups.iter().map(|s| format!("`{s}`")).collect();
            return Err(fail(
                line,
                format!(
                    "setups = {text} in the preamble, but the rows' set-ups are {}",
                    found.join(", ")
                ),
            ));
        }
    }
    check_described(conditions, file, &setups)
}

/// The keys that describe the set-up rather than the rows (ISO 230-7 §5.2), as
/// [`super::run`] writes them: each is read, checked for its form, and said again by the
/// report ([`described`]).
///
/// * `machine`, `artefact`, `structural_loop`: text, not empty;
/// * where the other axes stood: `<letter>_mm` for a linear axis, `<letter>_deg` for a rotary
///   one (`s_deg` for the spindle), a finite number each;
/// * `reversed_setup`, `turned_setup`: the definitions of those set-ups, given exactly when
///   the rows hold such a set-up (a `reversed`, a `turned_<deg>`).
fn check_described(conditions: &Conditions, file: &str, setups: &[&str]) -> Result<(), TableError> {
    for key in ["machine", "artefact", "structural_loop"] {
        if let Some((text, line)) = conditions.get(key)
            && text.is_empty()
        {
            return Err(TableError::new(
                file,
                Some(line),
                format!("{key} = : expected a description, or no line"),
            ));
        }
    }
    for (key, _) in position_keys() {
        conditions.number(&key, file)?;
    }
    for (key, kind, has) in [
        ("reversed_setup", "reversed", setups.contains(&"reversed")),
        (
            "turned_setup",
            "turned_<deg>",
            setups.iter().any(|s| s.starts_with("turned_")),
        ),
    ] {
        if let Some((_, line)) = conditions.get(key)
            && !has
        {
            return Err(TableError::new(
                file,
                Some(line),
                format!(
                    "{key} defines a {kind} set-up, but no row is in one (set-ups: {})",
                    if setups == [""] {
                        "none named".to_string()
                    } else {
                        setups.join(" ")
                    }
                ),
            ));
        }
    }
    Ok(())
}

/// The preamble keys of where the other axes stood, with their units: `x_mm` … `w_mm`,
/// `a_deg` … `c_deg`, `s_deg`.
fn position_keys() -> impl Iterator<Item = (String, &'static str)> {
    "xyzuvw"
        .chars()
        .map(|l| (format!("{l}_mm"), " mm"))
        .chain("abcs".chars().map(|l| (format!("{l}_deg"), "°")))
}

/// What the preamble says of the set-up, for the report: JSON (`machine`, `artefact`,
/// `structural_loop`, `axes` (where the other axes stood, as text), `preamble_not_used`) and
/// lines for people. Keys no reader took are named as not used.
pub fn described(conditions: &Conditions) -> (serde_json::Value, String) {
    let text = |key: &str| conditions.get(key).map(|(v, _)| v.to_string());
    let axes: Vec<String> = position_keys()
        .filter_map(|(key, unit)| {
            let (value, _) = conditions.get(&key)?;
            Some(format!("{} {value}{unit}", &key[..1]))
        })
        .collect();
    let (machine, artefact, looped) = (text("machine"), text("artefact"), text("structural_loop"));
    let not_used: Vec<String> = conditions.unread().into_iter().map(|(k, _)| k).collect();
    let mut said = Vec::new();
    if let Some(m) = &machine {
        said.push(format!("machine {m}"));
    }
    if let Some(a) = &artefact {
        said.push(format!("artefact {a}"));
    }
    if !axes.is_empty() {
        said.push(format!("other axes at {}", axes.join(", ")));
    }
    let mut lines = if said.is_empty() {
        String::new()
    } else {
        format!("Set-up: {}.\n", said.join("; "))
    };
    if let Some(l) = &looped {
        lines += &format!("Structural loop: {l}.\n");
    }
    let json = serde_json::json!({
        "machine": machine,
        "artefact": artefact,
        "structural_loop": looped,
        "axes": axes.join(", "),
        "preamble_not_used": not_used,
    });
    (json, lines)
}

//! What `mtwin score` says around the score itself: an estimate and a truth given the wrong
//! way round, and whether anything could check that the truth belongs to the run the
//! estimate's tables came from.

use serde_json::Value;
use std::path::Path;

/// The refusal when the file given as the estimate is a truth (`mtwin = "truth"`), said before
/// anything else is asked of it.
pub fn truth_as_estimate(estimate: &Value, file: &Path) -> Option<String> {
    (estimate.get("mtwin").and_then(Value::as_str) == Some("truth")).then(|| {
        format!(
            "{}: a truth (mtwin = \"truth\") given as the estimate: give the estimate.json `mtwin identify --out` wrote first, then the truth",
            file.display()
        )
    })
}

/// The caution when the estimate or the truth names no scenario (`scenario_sha256`): only when
/// both do can `score` check that the truth is of the run the estimate's tables came from.
pub fn unchecked_scenario(
    estimate: &Value,
    estimate_file: &Path,
    truth: &Value,
    truth_file: &Path,
) -> Option<String> {
    let named = |file: &Value| {
        file.get("scenario_sha256")
            .and_then(Value::as_str)
            .is_some()
    };
    let (file, what) = match (named(estimate), named(truth)) {
        (true, true) => return None,
        (true, false) => (truth_file, "it is of"),
        (false, _) => (estimate_file, "its tables came from"),
    };
    Some(format!(
        "{} does not name the scenario {what}, so nothing checked that this truth is of the run its tables came from (tables edited, or read without the manifest.json `mtwin run` wrote beside them)",
        file.display()
    ))
}

/// The score as `mtwin score` prints it: the report with a `CAUTION` line for each of
/// `cautions`, or with `json` its JSON with a `cautions` array.
pub fn printed(score: &crate::estimate::score::Score, cautions: &[String], json: bool) -> String {
    if json {
        let mut value = score.to_json();
        value["cautions"] = serde_json::json!(cautions);
        format!("{value:#}\n")
    } else {
        let mut text = score.report();
        for caution in cautions {
            text += &format!("CAUTION: {caution}.\n");
        }
        text
    }
}

//! JSON pieces shared by the discovery reports.

use super::*;

/// The rejected candidates as JSON: `effect` (from `id`), `cv_rms_um`, `fold_cv_rms_um`,
/// their test (`gain_z`, `rest_z`, `z_needed`) and `fails`, the number in [`RULE`] of the
/// first condition the candidate fails ([`Test::failed_condition`]).
pub fn rejected_json<E: Copy>(
    rejected: &[Rejected<E>],
    id: impl Fn(E) -> String,
) -> Vec<serde_json::Value> {
    rejected
        .iter()
        .map(|r| {
            let mut object = serde_json::Map::new();
            object.insert("effect".into(), id(r.effect).into());
            object.insert(
                "cv_rms_um".into(),
                round_json(r.cv_rms / crate::math::M_PER_UM),
            );
            object.insert("fold_cv_rms_um".into(), fold_rms_json(&r.fold_mse));
            test_keys(&mut object, &r.test);
            object.insert("fails".into(), r.test.failed_condition().into());
            serde_json::Value::Object(object)
        })
        .collect()
}

/// A test's keys in a JSON object: `gain_z`, `z_needed`, `rest_z`; on files of few folds
/// `in_sample` (`z`, `rest_z`, `z_needed`, `grid`: [`InSample`]); and `passed_on` (`held-out`
/// or `in-sample`) when the gains are significant ([`Test::evidence`]).
pub(super) fn test_keys(object: &mut serde_json::Map<String, serde_json::Value>, test: &Test) {
    object.insert("gain_z".into(), round_json(test.z));
    object.insert("z_needed".into(), round_json(test.threshold));
    object.insert("rest_z".into(), round_json(test.rest_z));
    if let Some(s) = &test.in_sample {
        object.insert(
            "in_sample".into(),
            serde_json::json!({
                "z": round_json(s.z),
                "rest_z": round_json(s.rest_z),
                "z_needed": round_json(s.threshold),
                "grid": s.grid,
            }),
        );
    }
    if let Some(evidence) = test.evidence() {
        object.insert("passed_on".into(), evidence.into());
    }
}

/// An accepted step's test for people: `z 12.3, without the best fold 8.1, ≥ 2.58`; when only
/// the in-sample route passes, that route first: `in-sample evidence: z 9.1, without the fold
/// that gains most 6.2, ≥ 3.40; held out z 2.1, 0.7`.
pub(crate) fn test_text(test: &Test) -> String {
    match test.in_sample {
        Some(s) if !test.held_out_significant() && s.significant() => format!(
            "in-sample evidence: z {:.1}, without the fold that gains most {:.1}, ≥ {:.2}; held out z {:.1}, {:.1}",
            s.z, s.rest_z, s.threshold, test.z, test.rest_z
        ),
        _ => format!(
            "z {:.1}, without the best fold {:.1}, ≥ {:.2}",
            test.z, test.rest_z, test.threshold
        ),
    }
}

/// A test's in-sample route for a line of a list: `; in-sample z 9.1, 6.2 / 3.40`, or
/// nothing on files of more folds.
pub(super) fn in_sample_text(test: &Test) -> String {
    test.in_sample.map_or(String::new(), |s| {
        format!(
            "; in-sample z {:.1}, {:.1} / {:.2}",
            s.z, s.rest_z, s.threshold
        )
    })
}

/// The rejected candidates for people, one per line: held-out RMS, its test and the condition
/// of the rule it fails; under a candidate whose combined z passes (condition 2) but that
/// fails condition (3) or (1), the held-out RMS of each fold, so a user sees which runs held
/// out gain and which lose.
pub(crate) fn rejected_text<E: Copy>(
    rejected: &[Rejected<E>],
    id: impl Fn(E) -> String,
    decimals: usize,
) -> String {
    let mut out = String::new();
    if rejected.is_empty() {
        return out;
    }
    let in_sample = if rejected.iter().any(|r| r.test.in_sample.is_some()) {
        "; the in-sample z likewise"
    } else {
        ""
    };
    out.push_str(&format!("\nTested and rejected (held-out RMS; held-out gain; its z, and without the fold that contributes most, against the z needed{in_sample}; the condition of the rule it fails):\n"));
    for r in rejected {
        let fails = r
            .test
            .failed_condition()
            .map_or(String::from("passes, not taken"), |c| {
                format!("fails ({c})")
            });
        out.push_str(&format!(
            "  {:<20} {} µm; {:+.1} %; z {:.1}, {:.1} / {:.2}{}; {fails}\n",
            id(r.effect),
            crate::math::fixed(r.cv_rms / crate::math::M_PER_UM, decimals),
            100.0 * r.test.gain,
            r.test.z,
            r.test.rest_z,
            r.test.threshold,
            in_sample_text(&r.test),
        ));
        if r.test.z >= r.test.threshold {
            out.push_str(&format!("      {}\n", fold_rms_text(&r.fold_mse, decimals)));
        }
    }
    out
}

/// Rounds a reported number to 4 decimals (0.1 nm in µm), without −0.
pub fn round_json(value: Real) -> serde_json::Value {
    serde_json::json!(
        crate::math::fixed(value, 4)
            .parse::<Real>()
            .unwrap_or(value)
    )
}

/// Each fold's held-out RMS in µm (from its mean square, rounded by [`round_json`]): the JSON's
/// `fold_cv_rms_um`, so a user sees which folds a gain comes from.
pub fn folds_json(score: &Score) -> serde_json::Value {
    fold_rms_json(&score.fold_mse)
}

/// [`folds_json`] from the folds' mean squares.
pub(super) fn fold_rms_json(fold_mse: &[Real]) -> serde_json::Value {
    serde_json::Value::Array(
        fold_mse
            .iter()
            .map(|m| round_json(m.sqrt() / crate::math::M_PER_UM))
            .collect(),
    )
}

/// Each fold's held-out RMS for people: `folds: 0.412 0.398 … µm` to `decimals`.
pub(crate) fn folds_text(score: &Score, decimals: usize) -> String {
    fold_rms_text(&score.fold_mse, decimals)
}

/// [`folds_text`] from the folds' mean squares.
pub(super) fn fold_rms_text(fold_mse: &[Real], decimals: usize) -> String {
    let values: Vec<String> = fold_mse
        .iter()
        .map(|m| crate::math::fixed(m.sqrt() / crate::math::M_PER_UM, decimals))
        .collect();
    format!("folds: {} µm", values.join(" "))
}

/// An effect's parameters for people: `key = value, …` to 3 decimals (the JSON gives 4).
pub(crate) fn params_text(params: &std::collections::BTreeMap<&'static str, Real>) -> String {
    params
        .iter()
        .map(|(k, v)| format!("{k} = {v:.3}"))
        .collect::<Vec<_>>()
        .join(", ")
}

/// The heading of the final model's values in a report for people: they are the refit on all
/// data with every accepted effect, the values of `--json`'s `final`, which differ from each
/// step's values at acceptance.
pub(crate) const FINAL_VALUES: &str =
    "  values refit with every accepted effect (the --json `final`):";

/// An effect's parameters as a JSON object, rounded by [`round_json`].
pub(crate) fn params_json(
    params: &std::collections::BTreeMap<&'static str, Real>,
) -> serde_json::Value {
    serde_json::Value::Object(
        params
            .iter()
            .map(|(k, v)| (k.to_string(), round_json(*v)))
            .collect(),
    )
}

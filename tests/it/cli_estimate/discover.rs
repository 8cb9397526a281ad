//! `identify --discover` and `--drift=rate` from the command line, on the foreign session of
//! `tests/data/rtest/` (what they find is checked in `estimate::discover`).

use super::*;

/// The foreign session's arguments: the machine, the base, the table and its sphere and noise.
fn session_args(table: &str) -> Vec<std::ffi::OsString> {
    let mut args: Vec<std::ffi::OsString> = vec!["identify".into(), "--machine".into()];
    args.push(root("models/trunnion5.urdf").into());
    for a in ["--params", "EX0C,EY0C,EA0C,EB0C"] {
        args.push(a.into());
    }
    args.push(format!("rtest:{}", root("tests/data/rtest").join(table).display()).into());
    for a in [
        "--rtest-sphere-mm",
        "76.6044,64.2788,250",
        "--sigma-um",
        "rtest=0.153",
    ] {
        args.push(a.into());
    }
    args
}

/// The report names each accepted term with its cause and gain and the extended `--params`;
/// `--json` carries the same under `discovery`, and the estimate is the one `--params` with
/// the accepted terms and `--drift=rate` give by hand (the same JSON but for `discovery`).
#[test]
fn identify_discover_reports_the_terms_and_estimates_with_them() {
    let mut args = session_args("foreign_session.csv");
    args.push("--discover".into());
    let text = ok(&mtwin(&args));
    for expected in [
        "Model selection (identify --discover): from --params EX0C,EY0C,EA0C,EB0C",
        "+ EXC.harmonic[2]: C's radial error motion along X, 2 times per turn",
        "+ ECC.reversal: C's lost motion (reversal)",
        "+ drift_rate: the R-test pivot drifting in time",
        "The estimate below is made with --params EX0C,EY0C,EA0C,EB0C,EXC.harmonic[2],ECC.reversal --drift=rate",
        "drift_per_h.z",
    ] {
        assert!(text.contains(expected), "{expected} not in:\n{text}");
    }
    args.push("--json".into());
    let json: Value = serde_json::from_str(&ok(&mtwin(&args))).unwrap();
    let discovery = &json["discovery"];
    assert_eq!(
        discovery["params"],
        "EX0C,EY0C,EA0C,EB0C,EXC.harmonic[2],ECC.reversal"
    );
    assert_eq!(discovery["drift"], "rate");
    assert_eq!(discovery["steps"].as_array().unwrap().len(), 3);
    // The same fit asked for by hand.
    let mut by_hand = session_args("foreign_session.csv");
    by_hand[4] = "EX0C,EY0C,EA0C,EB0C,EXC.harmonic[2],ECC.reversal".into();
    by_hand.extend(["--drift=rate".into(), "--json".into()]);
    let hand: Value = serde_json::from_str(&ok(&mtwin(&by_hand))).unwrap();
    let mut without = json.clone();
    without.as_object_mut().unwrap().remove("discovery");
    assert_eq!(without, hand);
}

/// A table of one test gives nothing to hold out: refused with the reason, nothing written.
#[test]
fn identify_discover_on_one_test_is_refused() {
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("out");
    let mut args = session_args("foreign_ck1.csv");
    args.extend(["--discover".into(), "--out".into(), out.clone().into()]);
    let message = failed(&mtwin(&args));
    assert!(
        message.contains("model selection needs at least two groups of readings"),
        "{message}"
    );
    assert!(!out.exists());
}

/// `--drift` bare, before the table, is a drift per test (the table is not taken for its
/// form); `--drift=rate` one rate through the table.
#[test]
fn the_drift_flag_bare_before_a_table_and_with_its_form() {
    let args = session_args("foreign_session.csv");
    let (head, tail) = args.split_at(5);
    let with = |flag: &str| {
        let mut all = head.to_vec();
        all.push(flag.into());
        all.extend_from_slice(tail);
        ok(&mtwin(&all))
    };
    let per_test = with("--drift");
    assert!(per_test.contains("C out and back 4.drift.z"), "{per_test}");
    let rate = with("--drift=rate");
    assert!(rate.contains("drift_per_h.z"), "{rate}");
    assert!(!rate.contains(".drift.z"), "{rate}");
}

//! Plots of `analyze spindle`: one SVG per kind and nothing else, refused into a folder under
//! a file, and no files left behind when a rename fails.

use super::*;

#[test]
fn plots_are_svg_files_named_by_kind_and_nothing_else() {
    let dir = tempfile::tempdir().unwrap();
    let full = run_vmc3_spindle(dir.path());
    let table = dir.path().join("spindle.csv");
    first_revolutions(&full, &table, 2, &[]);
    let plots = dir.path().join("plots");
    let json = analyze_json(&table, &["--plot".as_ref(), plots.as_os_str()]);
    let segments = array(&json["segments"]);
    let tests_per_segment = array(&segments[0]["tests"]).len();
    let names = entries(&plots);
    let count = |prefix: &str| names.iter().filter(|n| n.starts_with(prefix)).count();
    // A polar plot and a spectrum per segment and test, a chart against speed per test.
    assert_eq!(
        count("polar_"),
        segments.len() * tests_per_segment,
        "{names:?}"
    );
    assert_eq!(count("spectrum_"), segments.len() * tests_per_segment);
    assert_eq!(count("speed_"), array(&json["speeds"]).len());
    assert_eq!(
        names.len(),
        count("polar_") + count("spectrum_") + count("speed_"),
        "nothing else (no temporaries): {names:?}"
    );
    for name in &names {
        assert!(name.ends_with(".svg"), "{name}");
        let svg = std::fs::read_to_string(plots.join(name)).unwrap();
        assert_well_formed_svg(&svg, name);
    }
    // One plot per speed: each speed of the record is named in some polar plot's name.
    for segment in segments {
        let tag = format!("_{}rpm_", number(&segment["speed_rpm"]));
        assert_eq!(
            names
                .iter()
                .filter(|n| n.starts_with("polar_") && n.contains(&tag))
                .count(),
            tests_per_segment,
            "{tag}: {names:?}"
        );
    }
}

#[test]
fn plots_into_a_folder_under_a_file_fail_and_write_nothing() {
    let dir = tempfile::tempdir().unwrap();
    let blocker = dir.path().join("not_a_folder");
    std::fs::write(&blocker, "a regular file\n").unwrap();
    let plots = blocker.join("plots");
    let before = entries(dir.path());
    let output = analyze(
        &data("small.csv"),
        &["--json".as_ref(), "--plot".as_ref(), plots.as_os_str()],
    );
    assert!(!output.status.success());
    assert!(output.stdout.is_empty(), "{}", text(&output.stdout));
    let stderr = text(&output.stderr);
    assert!(stderr.contains("not_a_folder"), "{stderr}");
    assert_eq!(
        entries(dir.path()),
        before,
        "nothing written beside the file"
    );
    assert_eq!(
        std::fs::read_to_string(&blocker).unwrap(),
        "a regular file\n"
    );
}

/// Was a bug (src/io/write.rs, `write_files`): the files are first written as `.NAME.partial`
/// and then renamed one by one; when a rename failed (here: the target name is taken by a
/// folder), the files renamed before it stayed, and so did the temporaries not yet renamed,
/// although the function promises that a failure leaves none of the new files. Blocking the
/// first plot's name or the fourth's must leave the folder as it was.
#[test]
fn a_plot_that_cannot_be_renamed_leaves_no_files_behind() {
    let dir = tempfile::tempdir().unwrap();
    // The names the plots take, from a run that succeeds.
    let good = dir.path().join("good");
    let output = analyze(&data("small.csv"), &["--plot".as_ref(), good.as_os_str()]);
    assert!(output.status.success(), "{}", text(&output.stderr));
    let names = entries(&good);
    assert_eq!(names.len(), 6, "{names:?}");
    for blocked in [names.first().unwrap(), names.last().unwrap()] {
        let plots = dir.path().join(format!("blocked_{blocked}"));
        std::fs::create_dir_all(plots.join(blocked)).unwrap();
        let output = analyze(
            &data("small.csv"),
            &["--json".as_ref(), "--plot".as_ref(), plots.as_os_str()],
        );
        assert!(!output.status.success(), "{blocked} is a folder");
        assert!(output.stdout.is_empty());
        assert!(text(&output.stderr).contains(blocked.as_str()));
        assert_eq!(
            entries(&plots),
            std::slice::from_ref(blocked),
            "only the folder that was there before"
        );
    }
}

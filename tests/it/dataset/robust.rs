//! `mtwin dataset` under real schedulers and careless hands, from the reproducers in
//! `shared/repro/`: several processes making the same shard at once (a resubmitted Slurm
//! array task, a Ray retry) all succeed and leave the bytes one process leaves; a run or a case
//! written into a dataset folder, or a dataset into a run folder, is refused with the other
//! left as it was; so are unrelated files beside a dataset and a stray file in a table folder.

use super::{VOLUMETRIC, files, path};
use std::path::Path;
use std::process::{Child, Command, Output};
use std::time::{Duration, Instant};

fn run(args: &[&str]) -> Output {
    Command::new(env!("CARGO_BIN_EXE_mtwin"))
        .args(args)
        .output()
        .unwrap()
}

fn ok(args: &[&str]) -> String {
    let output = run(args);
    assert!(
        output.status.success(),
        "mtwin {args:?}: {}",
        String::from_utf8_lossy(&output.stderr)
    );
    String::from_utf8(output.stdout).unwrap()
}

/// The error of a command that must fail (and not by a panic).
fn refused(args: &[&str]) -> String {
    let output = run(args);
    let stderr = String::from_utf8_lossy(&output.stderr).into_owned();
    assert!(!output.status.success(), "mtwin {args:?} was accepted");
    assert_ne!(output.status.code(), Some(101), "a panic: {stderr}");
    stderr
}

fn spawn(args: &[&str]) -> Child {
    Command::new(env!("CARGO_BIN_EXE_mtwin"))
        .args(args)
        .stdout(std::process::Stdio::null())
        .stderr(std::process::Stdio::piped())
        .spawn()
        .unwrap()
}

/// Whether some private folder under `dir/.tmp` has a file in it: a maker is writing.
fn writing(dir: &Path) -> bool {
    let Ok(folders) = std::fs::read_dir(dir.join(".tmp")) else {
        return false;
    };
    folders
        .flatten()
        .any(|f| std::fs::read_dir(f.path()).is_ok_and(|mut d| d.next().is_some()))
}

#[test]
fn makers_of_the_same_shard_at_once_all_succeed_with_the_bytes_of_one() {
    // shared/repro/dataset_same_shard_twice.sh: a later maker of a shard cleared the earlier
    // one's live temporary folder, and the earlier one failed with ENOENT.
    let tmp = tempfile::tempdir().unwrap();
    let (alone, together) = (tmp.path().join("alone"), tmp.path().join("together"));
    let args = ["--count", "1600", "--shard", "1/4", "--threads", "1"];
    let with = |out: &Path| -> Vec<String> {
        let mut all = vec!["dataset".to_string(), VOLUMETRIC.into(), "--out".into()];
        all.push(path(out).into());
        all.extend(args.iter().map(|a| a.to_string()));
        all
    };
    let alone_args = with(&alone);
    ok(&alone_args.iter().map(String::as_str).collect::<Vec<_>>());

    let together_args = with(&together);
    let together_args: Vec<&str> = together_args.iter().map(String::as_str).collect();
    let first = spawn(&together_args);
    // The others start while the first is writing its files, as a retried task would.
    let started = Instant::now();
    while !writing(&together) && started.elapsed() < Duration::from_secs(120) {
        std::thread::sleep(Duration::from_millis(5));
    }
    assert!(writing(&together), "the first maker never started writing");
    let makers = [first, spawn(&together_args), spawn(&together_args)];
    assert!(
        writing(&together),
        "the first maker was done before the others started: the test needs a longer shard"
    );
    for (index, maker) in makers.into_iter().enumerate() {
        let output = maker.wait_with_output().unwrap();
        assert!(
            output.status.success(),
            "maker {index} failed: {}",
            String::from_utf8_lossy(&output.stderr)
        );
    }
    let (a, b) = (files(&alone), files(&together));
    assert_eq!(
        a.keys().collect::<Vec<_>>(),
        b.keys().collect::<Vec<_>>(),
        "the same files, and no private folder left"
    );
    assert!(a == b, "the same bytes as one maker alone");
    assert!(a.keys().any(|k| k.ends_with("part-0.parquet")));
}

#[test]
fn threads_making_the_same_shard_at_once_all_succeed_with_the_bytes_of_one() {
    use mtwin::app::dataset::{Dataset, Options, generate};
    let tmp = tempfile::tempdir().unwrap();
    let dataset = Dataset::load(VOLUMETRIC).unwrap();
    let options = |out: &Path| Options {
        count: 80,
        shards: 2,
        only: Some(0),
        threads: Some(1),
        out: out.to_path_buf(),
    };
    let (alone, together) = (tmp.path().join("alone"), tmp.path().join("together"));
    generate(&dataset, &options(&alone), &|_| {}).unwrap();
    let results: Vec<_> = std::thread::scope(|scope| {
        let makers: Vec<_> = (0..3)
            .map(|_| scope.spawn(|| generate(&dataset, &options(&together), &|_| {})))
            .collect();
        makers.into_iter().map(|m| m.join().unwrap()).collect()
    });
    for result in results {
        result.unwrap();
    }
    assert!(files(&alone) == files(&together), "the same bytes");
}

/// `mtwin dataset` of 20 cases in 2 shards into `out`.
fn dataset_args(out: &Path) -> Vec<&str> {
    vec![
        "dataset",
        VOLUMETRIC,
        "--count",
        "20",
        "--shards",
        "2",
        "--out",
        path(out),
    ]
}

#[test]
fn one_kind_of_output_is_not_written_into_a_folder_holding_another() {
    // shared/repro/dataset_case_overwrites_manifest.sh: `--case K --out DIR` (and `mtwin run
    // --out DIR`) into a dataset folder replaced its manifest.json, rc 0.
    let tmp = tempfile::tempdir().unwrap();
    let set = tmp.path().join("set");
    let args_made = dataset_args(&set);
    ok(&args_made);
    let before = files(&set);

    let set_str = path(&set);
    for args in [
        vec!["dataset", VOLUMETRIC, "--case", "5", "--out", set_str],
        vec!["run", VOLUMETRIC, "--out", set_str],
    ] {
        let stderr = refused(&args);
        assert!(
            stderr.contains(set_str) && stderr.contains("a dataset") && stderr.contains("20 cases"),
            "{args:?}: {stderr}"
        );
        assert!(
            files(&set) == before,
            "{args:?}: the dataset folder is untouched"
        );
    }
    // The same dataset command into its own folder still resumes (nothing to do).
    let printed = ok(&args_made);
    assert!(printed.contains("2 shard(s) already complete"), "{printed}");
    assert!(files(&set) == before);

    // The reverse: a dataset into a run folder (a case's, or `mtwin run`'s).
    for (name, maker) in [
        ("case", vec!["dataset", VOLUMETRIC, "--case", "5", "--out"]),
        ("run", vec!["run", VOLUMETRIC, "--out"]),
    ] {
        let folder = tmp.path().join(name);
        let mut args = maker.clone();
        args.push(path(&folder));
        ok(&args);
        ok(&args); // a run folder takes a run again
        let before = files(&folder);
        let stderr = refused(&dataset_args(&folder));
        assert!(
            stderr.contains(path(&folder))
                && stderr.contains("a run of vmc3_dataset_volumetric.toml"),
            "{stderr}"
        );
        assert!(
            files(&folder) == before,
            "{name}: the run folder is untouched"
        );
    }

    // A folder of unrelated files (hidden ones aside) is refused, and nothing is written.
    let mine = tmp.path().join("mine");
    std::fs::create_dir(&mine).unwrap();
    std::fs::write(mine.join("notes.txt"), b"mine").unwrap();
    let args = dataset_args(&mine);
    let stderr = refused(&args);
    assert!(stderr.contains("notes.txt"), "{stderr}");
    assert_eq!(files(&mine).len(), 1);
    assert!(!mine.join("_shards").exists());
    std::fs::remove_file(mine.join("notes.txt")).unwrap();
    std::fs::write(mine.join(".nfs0000000001"), b"").unwrap();
    ok(&args); // hidden files only: as good as empty
}

#[test]
fn stray_files_in_a_dataset_folder_are_refused_by_name() {
    let tmp = tempfile::tempdir().unwrap();
    let set = tmp.path().join("set");
    let args = [
        "dataset", VOLUMETRIC, "--count", "8", "--shards", "2", "--out",
    ];
    let mut args = args.to_vec();
    args.push(path(&set));
    ok(&args);
    let before = files(&set);
    let strays = [
        "notes.txt",
        "volumetric/notes.txt",
        "volumetric/machine=vmc3/extra.parquet",
        "cases/machine=vmc3/split=train/shard=0/part-1.parquet",
    ];
    for stray in strays {
        let file = set.join(stray);
        std::fs::write(&file, b"not the dataset's").unwrap();
        let stderr = refused(&args);
        let name = Path::new(stray).file_name().unwrap().to_str().unwrap();
        assert!(stderr.contains(name), "{stray}: {stderr}");
        std::fs::remove_file(&file).unwrap();
        assert!(files(&set) == before, "{stray}: nothing else changed");
    }
    // Names readers skip (hidden, or starting with `_`) are no trouble.
    std::fs::write(set.join("volumetric").join("_SUCCESS"), b"").unwrap();
    std::fs::write(set.join(".DS_Store"), b"").unwrap();
    let printed = ok(&args);
    assert!(printed.contains("2 shard(s) already complete"), "{printed}");
}

/// A prior whose draws can leave what the scenario accepts is refused by `check`, at its line,
/// before any case runs (issue 34: a prior crossing a scenario limit used to pass `check` and
/// fail part-way through the dataset). Each prior is tried at the ends of its reach: a
/// uniform's ends, a bounded prior's bounds, 4.9 standard deviations for an unbounded one.
#[test]
fn a_prior_that_can_cross_a_scenario_limit_is_refused_at_its_line() {
    let dir = tempfile::tempdir().unwrap();
    let base = std::fs::read_to_string(format!(
        "{}/scenarios/vmc3_dataset_ballbar.toml",
        env!("CARGO_MANIFEST_DIR")
    ))
    .unwrap()
    .replace(
        "../models",
        &format!("{}/models", env!("CARGO_MANIFEST_DIR")),
    );
    let prior = "\"ballbar.noise_um\" = { lognormal = [0.1, 0.3], bounds = [0.02, 0.5] }";
    assert!(base.contains(prior));
    let line = base.lines().position(|l| l == prior).unwrap() + 1;
    for (replacement, expected) in [
        // The transducer reads ±1 mm: a calibration error up to 2 mm is no ball-bar.
        (
            "\"ballbar.calibration_um\" = { uniform = [0.0, 2000.0] }",
            "ballbar.calibration_um can reach 2000 (the upper end of its prior)",
        ),
        // Noise is never negative; 0.1 ± 0.05 µm unbounded reaches −0.145 at 4.9 sd.
        (
            "\"ballbar.noise_um\" = { normal = [0.1, 0.05] }",
            "ballbar.noise_um can reach -0.145 (the lower end of its prior, 4.9 standard deviations out)",
        ),
    ] {
        let file = dir.path().join("prior.toml");
        std::fs::write(&file, base.replace(prior, replacement)).unwrap();
        let path = file.to_str().unwrap();
        let message = refused(&["check", path]);
        assert!(
            message.contains(&format!("{path}:{line}")) && message.contains(expected),
            "{replacement}: {message}"
        );
    }
    // The bundled priors stay inside: the scenario checks.
    let file = dir.path().join("bundled.toml");
    std::fs::write(&file, &base).unwrap();
    ok(&["check", file.to_str().unwrap()]);
}

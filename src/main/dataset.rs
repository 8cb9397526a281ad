//! `mtwin dataset`: many cases of a scenario into a Parquet dataset, or one case into a folder
//! (`--case`), with a progress bar.

use anyhow::{Result, bail};
use mtwin::app::{simulate, write_outputs};
use std::path::Path;

/// `mtwin dataset`.
pub(super) fn dataset(
    scenario: &Path,
    count: Option<u64>,
    out: &Path,
    shards: Option<u64>,
    shard: Option<&str>,
    threads: Option<usize>,
    case: Option<u64>,
) -> Result<()> {
    use mtwin::app::dataset::{Dataset, Options, Progress, generate};
    let dataset = Dataset::load(scenario)?;
    if let Some(id) = case {
        let case = dataset.case(id);
        let scenario = dataset.scenario_of(&case)?;
        let mut output = simulate(&scenario)?.output(&scenario)?;
        let values: serde_json::Map<String, serde_json::Value> = (dataset.section.priors.iter())
            .zip(&case.values)
            .map(|(prior, value)| (prior.path.column(), serde_json::json!(value)))
            .collect();
        let record = serde_json::json!({
            "case_id": case.id,
            "case_seed": case.seed,
            "split": case.split(),
            "values": values,
        });
        let mut bytes = serde_json::to_vec_pretty(&record)?;
        bytes.push(b'\n');
        output
            .files
            .insert(output.files.len() - 1, ("case.json".into(), bytes));
        write_outputs(&output, out)?;
        for (name, bytes) in &output.files {
            say!("{}  ({} bytes)", out.join(name).display(), bytes.len());
        }
        say!("case {id} (seed {}, {})", case.seed, case.split());
        return Ok(());
    }
    let Some(count) = count.or(dataset.section.count) else {
        bail!("how many cases? give --count N (or `count` in the scenario's [dataset] section)");
    };
    let (shards, only) = match shard {
        Some(text) => {
            let parsed = text
                .split_once('/')
                .and_then(|(i, n)| Some((i.parse::<u64>().ok()?, n.parse::<u64>().ok()?)));
            let Some((i, n)) = parsed else {
                bail!("--shard {text}: expected I/N, as in --shard 3/16");
            };
            (n, Some(i))
        }
        None => (
            shards.unwrap_or_else(|| dataset.default_shards(count)),
            None,
        ),
    };
    let options = Options {
        count,
        shards,
        only,
        threads,
        out: out.to_path_buf(),
    };
    let bar = indicatif::ProgressBar::new(0);
    bar.set_style(
        indicatif::ProgressStyle::with_template(
            "{bar:40} {pos}/{len} cases, {per_sec}, {eta} left",
        )
        .expect("a valid template"),
    );
    let started = std::time::Instant::now();
    let summary = generate(&dataset, &options, &|progress| match progress {
        Progress::Total(total) => bar.set_length(total),
        Progress::Made(made) => bar.inc(made),
    });
    bar.finish_and_clear();
    let summary = summary?;
    let seconds = started.elapsed().as_secs_f64();
    if !summary.skipped.is_empty() {
        say!(
            "{} shard(s) already complete, skipped",
            summary.skipped.len()
        );
    }
    if summary.cases > 0 {
        say!(
            "{} cases, {} measurement rows in {:.1} s ({:.0} cases/s)",
            summary.cases,
            summary.readings,
            seconds,
            summary.cases as f64 / seconds
        );
    }
    if summary.complete {
        say!(
            "{}: complete ({} in {})",
            out.join("manifest.json").display(),
            mtwin::app::dataset::counted(count, "case", "cases"),
            mtwin::app::dataset::counted(shards, "shard", "shards")
        );
    } else {
        say!(
            "{}: shard(s) {:?} of {shards} written; manifest.json follows when every shard is",
            out.display(),
            summary.made
        );
    }
    Ok(())
}

//! False acceptances: noise-only tables of every layout, where nothing may be accepted.

use super::*;

/// Noise only, 140 tables (100 ISO layouts, 40 scattered): observed 0 false acceptances; the
/// test allows 1 (0.7 %), which a systematic weakness of the rule would exceed.
#[test]
fn nothing_hidden_accepts_nothing() {
    let mut false_positives = Vec::new();
    for seed in 1..=100 {
        let d = discover(&Plan::iso(5, seed).table(|_| 0.0));
        if !d.accepted().is_empty() {
            false_positives.push((seed, d.accepted()));
        }
    }
    for seed in 1..=40 {
        let d = discover(&Plan::scattered(5, 15, seed).table(|_| 0.0));
        if !d.accepted().is_empty() {
            false_positives.push((1000 + seed, d.accepted()));
        }
    }
    println!("false positives: {false_positives:?}");
    assert!(false_positives.len() <= 1, "{false_positives:?}");
}

/// False acceptances on noise by layout: `seeds` noise-only ISO tables of each number of runs
/// (contiguous folds for 1 and 2 runs, leave-one-run-out from 3); returns, per layout, the
/// seeds that accepted something.
fn false_acceptances(runs: &[usize], seeds: std::ops::RangeInclusive<u64>) -> Vec<Vec<u64>> {
    runs.iter()
        .map(|&runs| {
            seeds
                .clone()
                .filter(|&seed| {
                    !discover(&Plan::iso(runs, seed).table(|_| 0.0))
                        .accepted()
                        .is_empty()
                })
                .collect()
        })
        .collect()
}

/// Noise only, 60 tables each of 1, 2, 3 and 7 runs (the 5-run layout is above). Issue 15
/// asks for at most 5 % on single-run files: at most 3 of 60; for the others at most 1 of 60
/// (the rule's family-wise 2.5 % per round, and no more than the old rule's 0 in 140 on 5
/// runs would allow by chance).
#[test]
fn nothing_hidden_in_few_or_many_runs_rarely_accepts_anything() {
    let layouts = [1, 2, 3, 7];
    let found = false_acceptances(&layouts, 1..=60);
    println!("false acceptances in 60 tables of 1, 2, 3, 7 runs: {found:?}");
    assert!(found[0].len() <= 3, "{found:?}");
    for seeds in &found[1..] {
        assert!(seeds.len() <= 1, "{found:?}");
    }
}

/// The measurement behind the README's rates: 500 noise-only tables of each layout (1, 2, 3,
/// 5, 7 runs). About five minutes in release; run with `--ignored --nocapture`.
#[test]
#[ignore = "a measurement over 2 500 tables (about five minutes in release): run on purpose"]
fn false_acceptance_rates_by_layout() {
    let layouts = [1, 2, 3, 5, 7];
    let found = false_acceptances(&layouts, 1..=500);
    for (runs, seeds) in layouts.iter().zip(&found) {
        println!("{runs} runs: {} of 500 {seeds:?}", seeds.len());
    }
}

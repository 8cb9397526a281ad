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

/// The in-sample route's level on noise: over `seeds` noise-only three-run tables (3 folds,
/// where the route applies), each first-round candidate's in-sample z (the F of its fit to all
/// readings as a normal deviate): how many candidates exceed 1.645 (5 % if the F is calibrated:
/// the parameter count, the degrees of freedom and the noise variance right), how many tables
/// have one at or above its Bonferroni threshold Φ⁻¹(1 − 0.025/(C·G)) (at most 2.5 % of
/// tables), and how many pass the route (with the fold that gains most left out as well).
fn in_sample_level(seeds: std::ops::RangeInclusive<u64>) -> (usize, usize, usize, usize) {
    let (mut candidates, mut over, mut tables_over, mut tables_passing) = (0, 0, 0, 0);
    for seed in seeds {
        let d = discover(&Plan::iso(3, seed).table(|_| 0.0));
        let (mut any_over, mut any_passing) = (false, false);
        for s in d.rejected().iter().filter_map(|r| r.test.in_sample) {
            candidates += 1;
            over += usize::from(s.z > 1.645);
            any_over |= s.z >= s.threshold;
            any_passing |= s.significant();
        }
        tables_over += usize::from(any_over);
        tables_passing += usize::from(any_passing);
    }
    (candidates, over, tables_over, tables_passing)
}

/// The in-sample route holds its level on 100 noise-only three-run tables: between 2.5 and
/// 8 % of the candidates beyond z = 1.645 (5 % nominal; the candidates of a table share its
/// noise, so the count scatters more than a binomial's; a searched parameter left uncounted
/// doubles its F), at most 4
/// tables with a candidate at its threshold (2.5 % nominal), and none passing. Measured on
/// 500 tables (`in_sample_level_on_noise`): 226 of 4 500 candidates beyond 1.645 (5.0 %), 11
/// tables with one at its threshold (2.2 %), none passing.
#[test]
fn the_in_sample_route_holds_its_level_on_noise() {
    let (candidates, over, tables_over, tables_passing) = in_sample_level(1..=100);
    let rate = over as f64 / candidates as f64;
    assert!(candidates >= 800, "{candidates} candidates");
    assert!((0.025..=0.08).contains(&rate), "{over} of {candidates}");
    assert!(tables_over <= 4, "{tables_over} tables at the threshold");
    assert_eq!(tables_passing, 0);
}

/// [`the_in_sample_route_holds_its_level_on_noise`] on 500 tables. About 40 s in the test
/// profile; run with `--ignored --nocapture`.
#[test]
#[ignore = "a measurement over 500 tables (about 40 s): run on purpose"]
fn in_sample_level_on_noise() {
    let (candidates, over, tables_over, tables_passing) = in_sample_level(1..=500);
    println!(
        "three runs, 500 noise tables: {over} of {candidates} candidates beyond z = 1.645, {tables_over} tables with one at its threshold, {tables_passing} passing"
    );
}

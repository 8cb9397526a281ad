use super::*;

mod acceptance;

#[test]
fn contiguous_folds_are_blocks_in_time_order() {
    // Samples taken in the order 2, 0, 1, 3, 4, 5 into 3 folds of 2.
    let folds = Folds::contiguous(&[2, 0, 1, 3, 4, 5], 3);
    assert_eq!(folds.of_sample, vec![0, 1, 0, 1, 2, 2]);
    assert_eq!(
        folds.training(1),
        vec![true, false, true, false, true, true]
    );
}

/// A linear problem with known truth: every effect is one column (a smooth shape of the
/// sample index), the base model an intercept, five contiguous folds of 40 samples.
struct Linear {
    names: Vec<&'static str>,
    columns: Vec<Vec<Real>>,
    y: Vec<Real>,
    folds: Folds,
}

const SAMPLES: usize = 200;

/// A smooth shape over the samples: `sin(2π·cycles·t + phase)`, t in [0, 1).
fn shape(cycles: Real, phase: Real) -> Vec<Real> {
    (0..SAMPLES)
        .map(|i| (std::f64::consts::TAU * cycles * i as Real / SAMPLES as Real + phase).sin())
        .collect()
}

impl Linear {
    /// The effects `names` with their `columns`, and data `truth` plus noise of `sigma`.
    fn new(
        names: &[&'static str],
        columns: Vec<Vec<Real>>,
        truth: &[Real],
        sigma: Real,
        seed: u64,
    ) -> Linear {
        use crate::math::{seeded_rng, standard_normal};
        let mut rng = seeded_rng(seed, "linear problem");
        let y = truth
            .iter()
            .map(|t| t + sigma * standard_normal(&mut rng))
            .collect();
        Linear {
            names: names.to_vec(),
            columns,
            y,
            folds: Folds::new(
                "contiguous".into(),
                (0..SAMPLES).map(|i| i / 40).collect(),
                5,
            ),
        }
    }
}

impl Problem for Linear {
    type Effect = usize;
    type Fit = Vec<Real>;

    fn id(&self, effect: usize) -> String {
        self.names[effect].into()
    }

    fn n_samples(&self) -> usize {
        SAMPLES
    }

    fn folds(&self) -> &Folds {
        &self.folds
    }

    fn fit(&self, effects: &[usize], train: &[bool]) -> Vec<Real> {
        let rows: Vec<usize> = (0..SAMPLES).filter(|&i| train[i]).collect();
        let mut design = crate::discovery::least_squares::Design::new(rows.len());
        design.push(vec![1.0; rows.len()]);
        for &e in effects {
            design.push(rows.iter().map(|&i| self.columns[e][i]).collect());
        }
        let c = design.solve(&rows.iter().map(|&i| self.y[i]).collect::<Vec<_>>());
        (0..SAMPLES)
            .map(|i| {
                let predicted: Real = c[0]
                    + effects
                        .iter()
                        .zip(&c[1..])
                        .map(|(&e, k)| self.columns[e][i] * k)
                        .sum::<Real>();
                self.y[i] - predicted
            })
            .collect()
    }

    fn residuals(&self, fit: &Vec<Real>) -> Vec<Real> {
        fit.clone()
    }

    fn proposals(&self, effects: &[usize], _fit: &Vec<Real>) -> Vec<(usize, String)> {
        (0..self.names.len())
            .filter(|e| !effects.contains(e))
            .map(|e| (e, NO_DIAGNOSTIC.to_string()))
            .collect()
    }
}

fn sorted(mut effects: Vec<usize>) -> Vec<usize> {
    effects.sort();
    effects
}

/// The moves of a selection, without their numbers.
fn actions(selection: &Selection<usize, Vec<Real>>) -> Vec<Action<usize>> {
    selection.moves.iter().map(|m| m.action.clone()).collect()
}

/// The data are a + b. The library also has m = a + b + 0.3·d (d not in the library),
/// which alone explains most of it: forward selection takes m first, then no single
/// effect passes and the pair a, b enters, and it stops with m still in (three terms for
/// two). The stepwise search scores the pair a, b in the first round beside m: each of a
/// and b passes added to the other, and the pair predicts the held-out data better than
/// m, so it enters instead, and m never does.
#[test]
fn a_first_term_that_mimics_two_true_ones_gives_way_to_them() {
    let (a, b, d) = (shape(1.3, 0.2), shape(2.1, 1.1), shape(0.6, 2.0));
    let m: Vec<Real> = (0..SAMPLES).map(|i| a[i] + b[i] + 0.3 * d[i]).collect();
    let truth: Vec<Real> = (0..SAMPLES).map(|i| a[i] + b[i]).collect();
    let names = ["m", "a", "b", "j1", "j2"];
    let columns = vec![m, a, b, shape(3.7, 0.4), shape(5.3, 2.9)];
    for seed in 1..=5 {
        let problem = Linear::new(&names, columns.clone(), &truth, 0.05, seed);
        let forward = forward_selection(&problem, |_| {});
        assert_eq!(
            actions(&forward),
            [Action::Add(vec![0]), Action::Add(vec![2, 1])],
            "seed {seed}"
        );
        let stepwise = stepwise_selection(&problem, Search::FULL, |_| {});
        assert_eq!(actions(&stepwise), [Action::Add(vec![2, 1])], "seed {seed}");
        assert_eq!(stepwise.steps[0].together, vec![1]);
        // The final model explains the data to the noise, and the steps are its prefixes.
        let last = stepwise.last().0.cv_rms;
        assert!(last < 1.2 * 0.05, "seed {seed}: held-out RMS {last}");
        assert!(last < forward.last().0.cv_rms, "seed {seed}");
        assert_eq!(stepwise.steps[0].score, score(&problem, &[2]).0);
    }
}

/// The data are 3·c + 2·e + a + b, with m = a + b + 0.3·d as above (effects m, a, b, c, e,
/// j1, j2; noise 0.05, seeded by `seed`).
fn mimic_problem(seed: u64) -> Linear {
    let (a, b, c, d, e) = (
        shape(1.3, 0.2),
        shape(2.1, 1.1),
        shape(0.8, 0.5),
        shape(0.6, 2.0),
        shape(4.4, 1.7),
    );
    let m: Vec<Real> = (0..SAMPLES).map(|i| a[i] + b[i] + 0.3 * d[i]).collect();
    let truth: Vec<Real> = (0..SAMPLES)
        .map(|i| 3.0 * c[i] + 2.0 * e[i] + a[i] + b[i])
        .collect();
    let names = ["m", "a", "b", "c", "e", "j1", "j2"];
    let columns = vec![m, a, b, c, e, shape(3.7, 0.4), shape(5.3, 2.9)];
    Linear::new(&names, columns, &truth, 0.05, seed)
}

/// Every triple is scored, not only the best pair's: with data 3·c + a + b and m = a + b +
/// 0.3·d beside them, the best pair is c with m, and a, b and c together do not extend it
/// (the search used to take c and m, then a and b, then remove m). Now the first move adds
/// a, b and c at once, and nothing is removed.
#[test]
fn every_triple_is_scored_so_three_true_effects_enter_at_once() {
    let (a, b, c, d) = (
        shape(1.3, 0.2),
        shape(2.1, 1.1),
        shape(0.8, 0.5),
        shape(0.6, 2.0),
    );
    let m: Vec<Real> = (0..SAMPLES).map(|i| a[i] + b[i] + 0.3 * d[i]).collect();
    let truth: Vec<Real> = (0..SAMPLES).map(|i| 3.0 * c[i] + a[i] + b[i]).collect();
    let names = ["m", "a", "b", "c", "j1", "j2"];
    let columns = vec![m, a, b, c, shape(3.7, 0.4), shape(5.3, 2.9)];
    for seed in 1..=5 {
        let problem = Linear::new(&names, columns.clone(), &truth, 0.05, seed);
        let selection = stepwise_selection(&problem, Search::FULL, |_| {});
        let first = match &selection.moves[0].action {
            Action::Add(added) => sorted(added.clone()),
            other => panic!("seed {seed}: {other:?}"),
        };
        assert_eq!(first, vec![1, 2, 3], "seed {seed}: {:?}", selection.moves);
        assert!(
            !selection.backed_out(),
            "seed {seed}: {:?}",
            selection.moves
        );
        assert_eq!(sorted(selection.effects()), vec![1, 2, 3], "seed {seed}");
    }
}

/// On [`mimic_problem`] the first round takes c, e and m (a block of three, m standing for
/// a + b). Then no single effect passes and the pair a, b enters (with j1 on seed 5); m
/// (and j1) now explain nothing the others do not, and the search removes them, ending on
/// the true set with the path saying so. Forward selection, whose blocks are pairs, stops
/// more than ten times the noise away.
#[test]
fn a_term_that_others_explain_is_removed() {
    for seed in 1..=5 {
        let problem = mimic_problem(seed);
        let forward = forward_selection(&problem, |_| {});
        assert!(
            forward.last().0.cv_rms > 10.0 * 0.05,
            "seed {seed}: {:?}",
            forward.moves
        );
        let stepwise = stepwise_selection(&problem, Search::FULL, |_| {});
        assert!(stepwise.backed_out());
        assert!(
            actions(&stepwise).contains(&Action::Remove(0)),
            "seed {seed}"
        );
        assert_eq!(sorted(stepwise.effects()), vec![1, 2, 3, 4], "seed {seed}");
        assert!(stepwise.last().0.cv_rms < 1.2 * 0.05, "seed {seed}");
        // The steps are the final model's prefixes, in the order its effects entered.
        let effects = stepwise.effects();
        for (k, step) in stepwise.steps.iter().enumerate() {
            assert_eq!(step.score, score(&problem, &effects[..=k]).0);
        }
    }
}

/// Two effects with the same column on the data (x and x2): the final model takes one, and
/// the exchange for the other is reported as an alternative with the same held-out RMS.
#[test]
fn exactly_collinear_effects_are_alternatives() {
    let (x, c) = (shape(1.0, 0.3), shape(2.6, 1.7));
    let truth: Vec<Real> = (0..SAMPLES).map(|i| 2.0 * x[i] + 1.5 * c[i]).collect();
    let names = ["x", "x2", "c", "j1", "j2"];
    let columns = vec![x.clone(), x, c, shape(3.7, 0.4), shape(5.3, 2.9)];
    for seed in 1..=5 {
        let problem = Linear::new(&names, columns.clone(), &truth, 0.05, seed);
        let selection = stepwise_selection(&problem, Search::FULL, |_| {});
        let effects = sorted(selection.effects());
        assert!(
            effects == vec![0, 2] || effects == vec![1, 2],
            "seed {seed}: {effects:?}"
        );
        let kept = if effects[0] == 0 { 0 } else { 1 };
        let alternative = selection
            .alternatives
            .iter()
            .find(|a| a.removed == kept)
            .unwrap_or_else(|| panic!("seed {seed}: {:?}", selection.alternatives));
        assert_eq!(alternative.added, 1 - kept);
        assert!((alternative.cv_rms - selection.last().0.cv_rms).abs() < 1e-12);
        assert!(!alternative.test.passes());
        // c has no stand-in: exchanging it loses what it explains.
        assert!(
            selection.alternatives.iter().all(|a| a.removed != 2),
            "{:?}",
            selection.alternatives
        );
    }
}

/// Problems where many sets of effects can explain the data: seven effects, each a sparse
/// mixture of five smooth shapes (the weights drawn once, rounded), the data e0 + e1 +
/// 0.7·e2 + 0.5·e3 and noise of 0.3, eight noise draws; twelve random problems of eight
/// effects, four of them in the data; and the five [`mimic_problem`]s. Four true effects,
/// one more than a block holds, make the search back out.
fn tangled_problems() -> Vec<Linear> {
    use crate::math::{seeded_rng, standard_normal};
    let base = [
        shape(0.883, 1.224),
        shape(1.880, -0.323),
        shape(2.489, -0.188),
        shape(3.525, -0.058),
        shape(4.174, -0.904),
    ];
    let weights: [[Real; 5]; 7] = [
        [1.41, 0.0, 0.0, 0.0, 0.0],
        [0.0, -1.35, -0.83, 0.0, 0.0],
        [0.0, -1.40, 0.0, 0.84, 1.08],
        [1.75, -1.09, 0.0, 1.17, 0.0],
        [-1.18, 0.0, 0.0, 2.49, -2.0],
        [0.0, 0.0, 0.0, -0.92, -1.51],
        [-0.98, 0.0, 0.0, 0.0, -0.96],
    ];
    let mixed: Vec<Vec<Real>> = weights
        .iter()
        .map(|w| {
            (0..SAMPLES)
                .map(|i| (0..5).map(|k| w[k] * base[k][i]).sum())
                .collect()
        })
        .collect();
    let truth: Vec<Real> = (0..SAMPLES)
        .map(|i| mixed[0][i] + mixed[1][i] + 0.7 * mixed[2][i] + 0.5 * mixed[3][i])
        .collect();
    let names = ["e0", "e1", "e2", "e3", "e4", "e5", "e6", "e7"];
    let mut problems: Vec<Linear> = (1..=8)
        .map(|seed| Linear::new(&names[..7], mixed.clone(), &truth, 0.3, seed))
        .collect();
    for seed in 1..=12 {
        let mut rng = seeded_rng(seed, "random problem");
        let mut draw = || standard_normal(&mut rng);
        let columns: Vec<Vec<Real>> = (0..8)
            .map(|_| {
                let (a, b, c) = (draw(), draw(), draw());
                let (f, g) = (shape(1.0 + 3.0 * a.abs(), b), shape(0.5 + 2.0 * c.abs(), a));
                (0..SAMPLES).map(|i| f[i] + 0.5 * c * g[i]).collect()
            })
            .collect();
        let weights = [draw(), draw(), draw(), draw()];
        let truth: Vec<Real> = (0..SAMPLES)
            .map(|i| (0..4).map(|k| weights[k] * columns[k][i]).sum())
            .collect();
        problems.push(Linear::new(&names, columns, &truth, 0.1, seed));
    }
    problems.extend((1..=5).map(mimic_problem));
    problems
}

/// On [`tangled_problems`] every move keeps the search's invariants — an addition or swap
/// lowers the held-out RMS by at least 5 %, a removal takes an effect worth less than that,
/// no model is visited twice — and the moves lead to the final model; the steps are its
/// prefixes; the result is the same on one thread as on several. The problems make the
/// search back out: removals and swaps (one effect for two) both happen among them.
#[test]
fn every_move_keeps_the_invariants_and_threads_do_not_change_the_result() {
    let (mut removals, mut swaps) = (0, 0);
    for (seed, problem) in tangled_problems().into_iter().enumerate() {
        let selection = stepwise_selection(&problem, Search::FULL, |_| {});
        let mut model: Vec<usize> = Vec::new();
        let mut visited = vec![model.clone()];
        for m in &selection.moves {
            match &m.action {
                Action::Remove(e) => {
                    assert!(m.test.gain < MIN_RELATIVE_GAIN, "{m:?}");
                    model.retain(|x| x != e);
                    removals += 1;
                }
                Action::Add(added) => {
                    assert!(
                        m.cv_rms <= (1.0 - MIN_RELATIVE_GAIN) * m.cv_rms_before,
                        "{m:?}"
                    );
                    model.extend(added);
                }
                Action::Swap { removed, added } => {
                    swaps += 1;
                    assert!(
                        m.cv_rms <= (1.0 - MIN_RELATIVE_GAIN) * m.cv_rms_before,
                        "{m:?}"
                    );
                    model.retain(|x| x != removed);
                    model.extend(added);
                }
            }
            let set = sorted(model.clone());
            assert!(!visited.contains(&set), "seed {seed}: back to {set:?}");
            visited.push(set);
        }
        assert_eq!(sorted(model), sorted(selection.effects()));
        let effects = selection.effects();
        for (k, step) in selection.steps.iter().enumerate() {
            assert_eq!(step.score, score(&problem, &effects[..=k]).0);
        }
        let one = rayon::ThreadPoolBuilder::new()
            .num_threads(1)
            .build()
            .unwrap();
        let again = one.install(|| stepwise_selection(&problem, Search::FULL, |_| {}));
        assert_eq!(again.effects(), effects);
        assert_eq!(again.moves, selection.moves);
        assert_eq!(again.alternatives, selection.alternatives);
        assert_eq!(again.last().0, selection.last().0);
    }
    println!("{removals} removals, {swaps} swaps");
    assert!(removals > 0 && swaps > 0);
}

/// [`Linear`] whose effects `pair.0` and `pair.1` cannot be in one model; it counts the fits
/// asked of a model holding both.
struct Exclusive<'a> {
    inner: &'a Linear,
    pair: (usize, usize),
    both: std::sync::atomic::AtomicUsize,
}

impl Problem for Exclusive<'_> {
    type Effect = usize;
    type Fit = Vec<Real>;

    fn id(&self, effect: usize) -> String {
        self.inner.id(effect)
    }

    fn n_samples(&self) -> usize {
        self.inner.n_samples()
    }

    fn folds(&self) -> &Folds {
        self.inner.folds()
    }

    fn fit(&self, effects: &[usize], train: &[bool]) -> Vec<Real> {
        if effects.contains(&self.pair.0) && effects.contains(&self.pair.1) {
            self.both.fetch_add(1, std::sync::atomic::Ordering::Relaxed);
        }
        self.inner.fit(effects, train)
    }

    fn residuals(&self, fit: &Vec<Real>) -> Vec<Real> {
        self.inner.residuals(fit)
    }

    fn proposals(&self, effects: &[usize], fit: &Vec<Real>) -> Vec<(usize, String)> {
        self.inner.proposals(effects, fit)
    }

    fn compatible(&self, a: usize, b: usize) -> bool {
        (a, b) != self.pair && (b, a) != self.pair
    }
}

/// The data are a + 0.2·b, but a and b are declared incompatible: neither search ever fits a
/// model holding both (not as a single added to the other, a block, or an exchange), and each
/// ends with a (which explains most of the data alone) without b; without the declaration the
/// search ends with both.
#[test]
fn incompatible_effects_are_never_in_one_model() {
    let (a, b) = (shape(1.3, 0.2), shape(2.1, 1.1));
    let truth: Vec<Real> = (0..SAMPLES).map(|i| a[i] + 0.2 * b[i]).collect();
    let names = ["a", "b", "j1", "j2"];
    let columns = vec![a, b, shape(3.7, 0.4), shape(5.3, 2.9)];
    for seed in 1..=3 {
        let linear = Linear::new(&names, columns.clone(), &truth, 0.05, seed);
        assert_eq!(
            sorted(stepwise_selection(&linear, Search::FULL, |_| {}).effects()),
            [0, 1]
        );
        let exclusive = Exclusive {
            inner: &linear,
            pair: (0, 1),
            both: 0.into(),
        };
        for effects in [
            stepwise_selection(&exclusive, Search::FULL, |_| {}).effects(),
            forward_selection(&exclusive, |_| {}).effects(),
        ] {
            assert!(
                effects.contains(&0) && !effects.contains(&1),
                "seed {seed}: {effects:?}"
            );
        }
        assert_eq!(exclusive.both.into_inner(), 0, "seed {seed}");
    }
}

/// Held-out gains beyond noise that fail only condition (1) are shown, not hidden: the data
/// are a + b, plus an alternating ±30 in fold 0 alone that no effect of the library (a, b,
/// j1, j2) describes (a run held out that the model can only extrapolate to). That fold
/// dominates the pooled held-out mean square (at least 900/5 = 180; |a + b| ≤ 2, so a
/// candidate can remove at most 4 of it and lower the pooled RMS by 1 − √(180/184) = 1.1 % at
/// most), while in the other four folds a + b leave only the noise (0.05). Nothing is
/// accepted, and the held-back blocks are exactly the blocks whose test, computed here on its
/// own, is beyond noise with a pooled gain below 5 %, and in which each effect added to the
/// others gains beyond noise too (at one test's threshold) — a + b among them.
#[test]
fn significant_gains_one_fold_outweighs_are_held_back_in_the_report() {
    let (a, b) = (shape(1.3, 0.2), shape(2.1, 1.1));
    let truth: Vec<Real> = (0..SAMPLES)
        .map(|i| {
            let unmodelled = match (i < 40, i % 2) {
                (true, 0) => 30.0,
                (true, _) => -30.0,
                _ => 0.0,
            };
            a[i] + b[i] + unmodelled
        })
        .collect();
    let names = ["a", "b", "j1", "j2"];
    let columns = vec![a, b, shape(3.7, 0.4), shape(5.3, 2.9)];
    let mut held_back = 0;
    for seed in 1..=5 {
        let problem = Linear::new(&names, columns.clone(), &truth, 0.05, seed);
        let selection = stepwise_selection(&problem, Search::FULL, |_| {});
        assert!(
            selection.steps.is_empty(),
            "seed {seed}: {:?}",
            selection.moves
        );
        let base = score(&problem, &[]).0;
        let folds = problem.folds();
        let mut expected: Vec<Vec<usize>> = Vec::new();
        for size in 2..=3 {
            let blocks: Vec<Vec<usize>> = match size {
                2 => (0..4)
                    .flat_map(|i| (i + 1..4).map(move |j| vec![i, j]))
                    .collect(),
                _ => (0..4)
                    .flat_map(|i| {
                        (i + 1..4).flat_map(move |j| (j + 1..4).map(move |k| vec![i, j, k]))
                    })
                    .collect(),
            };
            let family = blocks.len();
            for block in blocks {
                let with = score(&problem, &block).0;
                let test = Test::new(&base, &with, folds, family);
                // Each effect added to the others gains beyond noise (at one test's threshold).
                let every = block.iter().all(|leaving| {
                    let rest: Vec<usize> = block.iter().copied().filter(|k| k != leaving).collect();
                    Test::new(&score(&problem, &rest).0, &with, folds, 1).significant()
                });
                if test.significant() && every && test.gain < MIN_RELATIVE_GAIN {
                    assert!(test.gain < 0.011, "seed {seed}: {block:?} {test:?}");
                    expected.push(block);
                }
            }
        }
        let mut shown: Vec<Vec<usize>> = selection
            .held_back
            .iter()
            .map(|h| {
                assert_eq!(h.idle, None, "seed {seed}: {h:?}");
                assert_eq!(h.test.failed_condition(), Some(1), "seed {seed}: {h:?}");
                sorted(h.effects.clone())
            })
            .collect();
        shown.sort();
        expected.sort();
        assert_eq!(shown, expected, "seed {seed}");
        assert!(shown.contains(&vec![0, 1]), "seed {seed}: {shown:?}");
        held_back += shown.len();
        let text = selection.nothing_text(|e| names[e].to_string());
        assert!(
            text.contains("held-out gains beyond noise come from"),
            "seed {seed}: {text}"
        );
    }
    println!("{held_back} blocks held back in 5 seeds");
}

/// The text shows the first [`HELD_BACK_SHOWN`] held-back blocks and counts the rest; the
/// JSON has every one, with why.
#[test]
fn the_report_shows_five_held_back_blocks_and_counts_the_rest() {
    let problem = mimic_problem(1);
    let (base, fit) = score(&problem, &[]);
    let test = Test {
        gain: 0.01,
        z: 4.0,
        threshold: 2.5,
        rest_z: 3.0,
        in_sample: None,
    };
    let held_back: Vec<HeldBack<usize>> = (0..7)
        .map(|k| HeldBack {
            effects: vec![k % 7, (k + 1) % 7],
            cv_rms: 1.0e-6 * (k + 1) as Real,
            fold_mse: vec![1.0e-12; 5],
            test,
            idle: (k == 0).then_some(1),
        })
        .collect();
    let selection = Selection {
        baseline: (base, fit),
        steps: Vec::new(),
        rejected: Vec::new(),
        moves: Vec::new(),
        alternatives: Vec::new(),
        held_back,
    };
    let id = |e: usize| problem.names[e].to_string();
    let text = selection.held_back_text(id, 3);
    assert_eq!(
        text.matches("folds: 1.000 1.000 1.000 1.000 1.000 µm")
            .count(),
        5,
        "{text}"
    );
    assert!(
        text.contains("  and 2 more (the JSON report lists them all)"),
        "{text}"
    );
    assert!(
        text.contains(
            "m + a: 1.000 µm; +1.0 %; z 4.0, 3.0 / 2.50; a does not earn its place in it"
        ),
        "{text}"
    );
    assert!(
        text.contains(
            "a + b: 2.000 µm; +1.0 %; z 4.0, 3.0 / 2.50; its pooled held-out gain falls short"
        ),
        "{text}"
    );
    let json = selection.held_back_json(id);
    assert_eq!(json.len(), 7);
    assert_eq!(json[0]["not_earning_its_place"], "a");
    assert_eq!(json[1]["not_earning_its_place"], serde_json::Value::Null);
    assert_eq!(json[6]["effects"], serde_json::json!(["j2", "m"]));
    assert_eq!(
        selection.nothing_text(id),
        "  nothing passes the rule, though held-out gains beyond noise come from 7 blocks held back (below: why each was not taken, and the held-out RMS of each fold)\n"
    );
}

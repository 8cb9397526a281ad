//! Forward selection ([`forward_selection`]).

use super::*;

/// Forward selection: from the base model, score every proposed effect by held-out RMS and
/// accept the best one that passes its [`Test`]; when none does, accept the best pair of
/// proposed effects that passes (two terms that only together explain the residual, e.g. a
/// sensor that warms both sooner and more than the screw); repeat until nothing passes.
/// `progress` hears about each test.
pub fn forward_selection<P: Problem + Sync>(
    problem: &P,
    mut progress: impl FnMut(&str),
) -> Selection<P::Effect, P::Fit>
where
    P::Effect: Sync,
    P::Fit: Send,
{
    let baseline = score(problem, &[]);
    let folds = problem.folds();
    let mut steps: Vec<Accepted<P::Effect, P::Fit>> = Vec::new();
    let mut effects: Vec<P::Effect> = Vec::new();
    let mut moves: Vec<Move<P::Effect>> = Vec::new();
    loop {
        let (current, current_fit) = match steps.last() {
            Some(step) => (&step.score, &step.fit),
            None => (&baseline.0, &baseline.1),
        };
        let proposals = admissible_proposals(problem, &effects, current_fit);
        let mut tested: Tested<P> = Vec::new();
        for (effect, evidence) in proposals {
            progress(&format!("testing {}", problem.id(effect)));
            let mut trial = effects.clone();
            trial.push(effect);
            let (candidate, fit) = score(problem, &trial);
            tested.push((effect, evidence, candidate, fit));
        }
        let tests: Vec<Test> = tested
            .iter()
            .map(|(_, _, candidate, _)| Test::new(current, candidate, folds, tested.len()))
            .collect();
        let best = (0..tested.len())
            .filter(|&i| tests[i].passes())
            .min_by(|&a, &b| tested[a].2.cv_rms.total_cmp(&tested[b].2.cv_rms));
        if let Some(i) = best {
            let (effect, evidence, score, fit) = tested.swap_remove(i);
            effects.push(effect);
            moves.push(Move {
                action: Action::Add(vec![effect]),
                cv_rms_before: current.cv_rms,
                cv_rms: score.cv_rms,
                test: tests[i],
            });
            steps.push(Accepted {
                effect,
                evidence,
                score,
                fit,
                together_with: None,
                together: Vec::new(),
                test: tests[i],
            });
            continue;
        }
        if let Some((first, second, score, fit, test)) =
            best_pair(problem, &effects, current, &tested, &mut progress)
        {
            // Both enter: the first with its own score (what it does alone), the second with
            // the pair's, so each step reads "the model up to here".
            let (a, b) = (tested[first].0, tested[second].0);
            let take = |i: usize| tested[i].clone();
            let (_, evidence_a, score_a, fit_a) = take(first);
            let (_, evidence_b, _, _) = take(second);
            effects.extend([a, b]);
            moves.push(Move {
                action: Action::Add(vec![a, b]),
                cv_rms_before: current.cv_rms,
                cv_rms: score.cv_rms,
                test,
            });
            steps.push(Accepted {
                effect: a,
                evidence: evidence_a,
                score: score_a,
                fit: fit_a,
                together_with: Some(b),
                together: vec![b],
                test,
            });
            steps.push(Accepted {
                effect: b,
                evidence: evidence_b,
                score,
                fit,
                together_with: Some(a),
                together: vec![a],
                test,
            });
            continue;
        }
        let rejected = tested
            .into_iter()
            .zip(tests)
            .map(|((effect, _, score, _), test)| Rejected {
                effect,
                cv_rms: score.cv_rms,
                fold_mse: score.fold_mse,
                test,
            })
            .collect();
        return Selection {
            baseline,
            steps,
            rejected,
            moves,
            alternatives: Vec::new(),
            held_back: Vec::new(),
        };
    }
}

/// Tested candidates: effect, evidence, score, fit.
type Tested<P> = Vec<(<P as Problem>::Effect, String, Score, <P as Problem>::Fit)>;

/// The best pair of `tested` that passes its [`Test`] against `current` (among all pairs of
/// the round): the indices (the better of the two alone first), the pair's score, fit and test.
fn best_pair<P: Problem + Sync>(
    problem: &P,
    effects: &[P::Effect],
    current: &Score,
    tested: &Tested<P>,
    progress: &mut impl FnMut(&str),
) -> Option<(usize, usize, Score, P::Fit, Test)>
where
    P::Effect: Sync,
    P::Fit: Send,
{
    let pairs = tested.len() * tested.len().saturating_sub(1) / 2;
    let mut best: Option<(usize, usize, Score, P::Fit, Test)> = None;
    for i in 0..tested.len() {
        for j in i + 1..tested.len() {
            if !problem.compatible(tested[i].0, tested[j].0) {
                continue;
            }
            let (a, b) = if tested[i].2.cv_rms <= tested[j].2.cv_rms {
                (i, j)
            } else {
                (j, i)
            };
            progress(&format!(
                "testing {} with {}",
                problem.id(tested[a].0),
                problem.id(tested[b].0)
            ));
            let (pair, fit) = score(problem, &[effects, &[tested[a].0, tested[b].0]].concat());
            let test = Test::new(current, &pair, problem.folds(), pairs);
            if test.passes()
                && best
                    .as_ref()
                    .is_none_or(|(_, _, s, _, _)| pair.cv_rms < s.cv_rms)
            {
                best = Some((a, b, pair, fit, test));
            }
        }
    }
    best
}

//! The stepwise search that can back out of a wrong step ([`stepwise_selection`]).

use super::book::{Book, Member, subsets};
use super::*;

/// The most effects one addition of [`stepwise_selection`] brings in together (a block).
pub const LARGEST_BLOCK: usize = 3;

/// The stepwise search in words, for reports (each move's test is the one [`RULE`] describes).
pub const STEPWISE_RULE: &str = "a search by held-out RMS in moves, each judged by one test: a candidate passes when \
     it (1) lowers the pooled held-out RMS by at least 5 %, (2) has held-out gains sum(r0^2 - r1^2) whose per-fold z \
     (the gain over its standard error under noise with the fold's variance and lag-one correlation, from the \
     candidate's held-out residuals), combined by Stouffer with each fold weighted by the z it would have if the \
     candidate were true, reach the normal quantile of 1 - 0.025/C for the C candidates of its kind (Bonferroni), and \
     (3) still reaches it without the fold that contributes most. ADD the best passing single effect (C the singles), \
     or a block of two or three that passes (C all the blocks of its size, every one of them scored) with every \
     effect earning its place (passing its test added to the rest of the block, at the singles' threshold, or at \
     one test's when no single effect passes) when no single passes or its held-out RMS is 5 % lower than the best \
     single's. REMOVE, after every addition or swap, while the model without one of its effects has a held-out RMS less than 5 % higher (the effect is no \
     longer worth a term), the effect whose removal leaves the lowest. SWAP, when nothing can be added, one effect of \
     the model for one candidate or two (each of two lowering the held-out RMS by 5 %): the exchange with the lowest \
     held-out RMS among those that pass against the model (C the exchanges). Never back to a model already visited; \
     stop when nothing moves. Alternatives: the exchanges of one effect of the final model for one candidate that \
     come close: the final model's held-out RMS is less than 5 % below theirs";

/// The lean search in words: [`Search::LEAN`] (blocks only when no single passes, one-for-one
/// swaps), for reports.
pub const LEAN_STEPWISE_RULE: &str = "a search by held-out RMS in moves, each judged by one test: a candidate passes when \
     it (1) lowers the pooled held-out RMS by at least 5 %, (2) has held-out gains sum(r0^2 - r1^2) whose per-fold z \
     (the gain over its standard error under noise with the fold's variance and lag-one correlation, from the \
     candidate's held-out residuals), combined by Stouffer with each fold weighted by the z it would have if the \
     candidate were true, reach the normal quantile of 1 - 0.025/C for the C candidates of its kind (Bonferroni), and \
     (3) still reaches it without the fold that contributes most. ADD the best passing single effect (C the singles), \
     or, when none passes, the best pair that passes (C the pairs) with each effect passing its test added to the \
     other (C = 1). REMOVE, after every addition or swap, while the model without one of its effects has a held-out \
     RMS less than 5 % higher (the effect is no longer worth a term), the effect whose removal leaves the lowest. SWAP, \
     when nothing can be added, one effect of the model for one candidate: the exchange with the lowest held-out RMS \
     among those that pass against the model (C the exchanges). Never back to a model already visited; stop when \
     nothing moves. Alternatives: the exchanges of one effect of the final model for one candidate that come close: \
     the final model's held-out RMS is less than 5 % below theirs";

/// How widely a [`stepwise_selection`] looks in each round.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Search {
    /// The most effects one addition brings in together (2 or 3; 1: no blocks).
    pub largest_block: usize,
    /// Whether blocks are scored in every round, so that a block explaining what the best
    /// single only mimics can enter instead of it; otherwise only when no single passes (as
    /// [`forward_selection`] tries pairs).
    pub blocks_every_round: bool,
    /// Whether a swap may bring in two candidates for one effect (else one for one).
    pub swap_pairs: bool,
}

impl Search {
    /// Every move [`stepwise_selection`] documents: blocks of up to [`LARGEST_BLOCK`] in every
    /// round, swaps of one effect for one or two ([`STEPWISE_RULE`]).
    pub const FULL: Search = Search {
        largest_block: LARGEST_BLOCK,
        blocks_every_round: true,
        swap_pairs: true,
    };
    /// Forward selection's additions (a pair only when no single passes) with removals and
    /// one-for-one swaps ([`LEAN_STEPWISE_RULE`]): for problems whose fits are costly and
    /// whose library is large (the ball-bar's 14 effects make 91 pairs a round). On a table
    /// with nothing in it, it scores what [`forward_selection`] scores.
    pub const LEAN: Search = Search {
        largest_block: 2,
        blocks_every_round: false,
        swap_pairs: false,
    };

    /// The search in words, for reports.
    pub fn rule(&self) -> &'static str {
        if *self == Search::LEAN {
            LEAN_STEPWISE_RULE
        } else {
            STEPWISE_RULE
        }
    }
}

/// Stepwise selection: forward steps by the held-out rule ([`Test`]), with blocks, removals
/// and exchanges, so that a term taken early that mimics a combination of others can leave.
///
/// From the base model, each round:
///
/// 1. **Add.** Every proposed effect is scored added to the model (C = the proposals), every
///    pair and every triple of proposals (up to [`LARGEST_BLOCK`]); a block is tested against
///    the model with C = all the blocks of its size (Bonferroni over the whole family). Every
///    triple is scored, not only those extending the best pair: the best pair can be a wrong
///    one (on a warm-up record, the lost motion with a sensor lead standing in for the
///    screw's lag), and the triple that explains the data (the lost motion, the lag and the
///    expansion change) does not extend it. A block must also have every one
///    of its effects earn its place: each must pass its [`Test`] added to the rest of the
///    block, at the singles' threshold when some single effect passes (no effect rides on
///    another), at one test's (C = 1) when none passes — the residual needs several effects
///    at once, the case [`forward_selection`] meets with a pair (and takes it without
///    asking). A held-out gain alone is not enough there: where a searched time constant
///    makes one fold's prediction unstable (a cold run held out, its state extrapolated from
///    warm runs), adding any term moves that fold by more than 5 %, and a term with nothing
///    to explain would ride in. The best single that passes enters,
///    unless the best block that passes has a held-out RMS at least [`MIN_RELATIVE_GAIN`]
///    lower (its extra effects must be worth their terms): a block that explains what the
///    best single only mimics then enters instead; with no single passing, the best block.
/// 2. **Remove**, after every addition or swap: while the model without one of its effects
///    has a held-out RMS less than [`MIN_RELATIVE_GAIN`] higher than the model's, that effect
///    is no longer worth a term by the rule's own measure (others now explain what it
///    absorbed); the one whose removal leaves the lowest held-out RMS leaves, and the check
///    repeats. Entering asks a significant gain of 5 % or more, staying only the 5 %: as in
///    classical stepwise regression, the bar to leave is lower than the bar to enter, so an
///    effect that just entered does not leave at once.
/// 3. **Swap**, when nothing can be added: every effect of the model exchanged for every
///    proposal and for every pair of proposals (a term that mimics two others gives way to
///    them; each of a pair must lower the exchanged model's held-out RMS by
///    [`MIN_RELATIVE_GAIN`]); the exchange with the lowest held-out RMS among those that pass
///    their [`Test`] against the model (C = the exchanges) is made, then step 2.
///
/// It stops when nothing moves. Every addition and swap passes the rule's condition (1) and
/// so lowers the held-out RMS by at least [`MIN_RELATIVE_GAIN`]; a removal raises it by less
/// than that and shrinks the model. The search keeps the models it has been at and never
/// moves to one of them again (an effect that left cannot come straight back anyway: its
/// gain is below the 5 % an addition needs), so it visits each of the finitely many models at
/// most once and ends.
///
/// On a file with no effect in it the first round is the only one: the singles and pairs that
/// [`forward_selection`] tests, and the triples, whose family adds at most 2.5 % to the bound
/// on a false acceptance whether some or all of them are scored (removal and swaps only act
/// on a model that has effects).
///
/// The returned [`Selection`] has the final model's effects as `steps` (each a prefix scored
/// again), the path as `moves`, the last round's single candidates as `rejected`, and as
/// `alternatives` the exchanges of one final effect for one candidate (scored in the last
/// swap round) that come close — the final model's held-out RMS is less than
/// [`MIN_RELATIVE_GAIN`] below theirs, so by the rule's condition (1) it does not beat them
/// — and in which the incoming effect does something (the exchanged model has a lower
/// held-out RMS than the final model without the outgoing effect): two causes the file cannot
/// separate; and as `held_back` the last round's blocks whose gains are beyond noise but that
/// the rule did not take ([`HeldBack`]). Every scored model is kept (score and fit) and found
/// again by its effects, so no model is fitted twice; models are scored in parallel and
/// gathered in order, so the result does not depend on the thread count. `progress` hears about each model scored.
pub fn stepwise_selection<P: Problem + Sync>(
    problem: &P,
    search: Search,
    mut progress: impl FnMut(&str),
) -> Selection<P::Effect, P::Fit>
where
    P::Effect: Sync,
    P::Fit: Send,
{
    let progress: &mut dyn FnMut(&str) = &mut progress;
    let folds = problem.folds();
    let mut book = Book::new(problem);
    let mut model: Vec<Member<P::Effect>> = Vec::new();
    let mut moves: Vec<Move<P::Effect>> = Vec::new();
    loop {
        let effects: Vec<P::Effect> = model.iter().map(|m| m.effect).collect();
        let here = book.at(&effects, progress);
        if !book.visited.contains(&here) {
            book.visited.push(here);
        }
        let current = book.score(here).clone();
        let proposals = admissible_proposals(problem, &effects, book.fit(here));
        let with = |extra: &[P::Effect]| [effects.as_slice(), extra].concat();
        // Singles, then the proposals ranked by what each does alone (a block lists its
        // effects in that order, the better alone first).
        let singles: Vec<Vec<P::Effect>> = proposals.iter().map(|(e, _)| with(&[*e])).collect();
        let single_at = book.score_all(&singles, progress);
        let single_tests: Vec<Test> = single_at
            .iter()
            .map(|&i| Test::new(&current, book.score(i), folds, proposals.len()))
            .collect();
        let best_single = (0..proposals.len())
            .filter(|&i| single_tests[i].passes() && !book.visited(&singles[i]))
            .min_by(|&a, &b| book.by_cv_rms(single_at[a], single_at[b]));
        let mut ranked: Vec<usize> = (0..proposals.len()).collect();
        ranked.sort_by(|&a, &b| book.by_cv_rms(single_at[a], single_at[b]));
        // A block competes with the best single: when a single passes, each of the block's
        // effects must pass as a single added to the rest of the block.
        let (block, held_back) =
            if search.largest_block >= 2 && (search.blocks_every_round || best_single.is_none()) {
                best_block(
                    &mut book,
                    &effects,
                    &current,
                    &proposals,
                    &ranked,
                    &single_at,
                    best_single.map(|_| proposals.len()),
                    search.largest_block,
                    progress,
                )
            } else {
                (None, Vec::new())
            };
        let single = best_single.map(|i| (vec![i], single_at[i], single_tests[i], proposals.len()));
        // A block wins over a passing single only when its extra effects are worth their
        // terms: its held-out RMS at least MIN_RELATIVE_GAIN below the single's.
        let addition = match (single, block) {
            (Some(single), Some(block))
                if Test::new(book.score(single.1), book.score(block.1), folds, 1).gain
                    >= MIN_RELATIVE_GAIN =>
            {
                Some(block)
            }
            (Some(single), _) => Some(single),
            (None, block) => block,
        };
        if let Some((block, at, test, family)) = addition {
            let added: Vec<P::Effect> = block.iter().map(|&i| proposals[i].0).collect();
            enter(
                &mut model,
                proposals.as_slice(),
                &block,
                moves.len(),
                family,
            );
            moves.push(Move {
                action: Action::Add(added),
                cv_rms_before: current.cv_rms,
                cv_rms: book.score(at).cv_rms,
                test,
            });
            remove_idle(&mut book, &mut model, &mut moves, progress);
            continue;
        }
        if model.is_empty() {
            return finish(
                &mut book,
                model,
                single_at,
                single_tests,
                &proposals,
                moves,
                Vec::new(),
                held_back,
                progress,
            );
        }
        // Exchanges of one effect for one proposal, then for two (a term that mimics a
        // combination of two others gives way to them).
        let n = proposals.len();
        let mut exchanges: Vec<(usize, Vec<usize>, Vec<P::Effect>)> = Vec::new();
        for size in 1..=if search.swap_pairs { 2 } else { 1 } {
            for j in 0..model.len() {
                let incoming: Vec<Vec<usize>> = if size == 1 {
                    ranked.iter().map(|&i| vec![i]).collect()
                } else {
                    (0..n)
                        .flat_map(|a| (a + 1..n).map(move |b| (a, b)))
                        .map(|(a, b)| vec![ranked[a], ranked[b]])
                        .filter(|p| problem.compatible(proposals[p[0]].0, proposals[p[1]].0))
                        .collect()
                };
                for added in incoming {
                    let mut swapped: Vec<P::Effect> = effects.clone();
                    swapped.remove(j);
                    swapped.extend(added.iter().map(|&i| proposals[i].0));
                    exchanges.push((j, added, swapped));
                }
            }
        }
        let models: Vec<Vec<P::Effect>> = exchanges.iter().map(|(_, _, m)| m.clone()).collect();
        let at = book.score_all(&models, progress);
        let family = exchanges.len();
        let tests: Vec<Test> = at
            .iter()
            .map(|&i| Test::new(&current, book.score(i), folds, family))
            .collect();
        // Two incoming effects must each be worth a term in the exchanged model: without
        // either, the model (the one-for-one exchange) is at least MIN_RELATIVE_GAIN worse.
        let worth = |k: usize| {
            let (j, added, _) = &exchanges[k];
            added.len() == 1
                || added.iter().all(|&leaving| {
                    exchanges
                        .iter()
                        .position(|(jj, other, _)| {
                            jj == j
                                && other.len() == 1
                                && added.contains(&other[0])
                                && other[0] != leaving
                        })
                        .is_some_and(|w| {
                            Test::new(book.score(at[w]), book.score(at[k]), folds, 1).gain
                                >= MIN_RELATIVE_GAIN
                        })
                })
        };
        let best = (0..family)
            .filter(|&k| tests[k].passes() && worth(k) && !book.visited.contains(&at[k]))
            .min_by(|&a, &b| book.by_cv_rms(at[a], at[b]));
        if let Some(k) = best {
            let (j, added, _) = &exchanges[k];
            let removed = model.remove(*j).effect;
            enter(&mut model, proposals.as_slice(), added, moves.len(), family);
            moves.push(Move {
                action: Action::Swap {
                    removed,
                    added: added.iter().map(|&i| proposals[i].0).collect(),
                },
                cv_rms_before: current.cv_rms,
                cv_rms: book.score(at[k]).cv_rms,
                test: tests[k],
            });
            remove_idle(&mut book, &mut model, &mut moves, progress);
            continue;
        }
        // The final model: the one-for-one exchanges that come close, whose incoming effect
        // does something.
        let mut alternatives: Vec<Alternative<P::Effect>> = Vec::new();
        for (k, (j, added, _)) in exchanges.iter().enumerate() {
            if added.len() != 1 {
                continue;
            }
            let mut without: Vec<P::Effect> = effects.clone();
            without.remove(*j);
            let without = book.at(&without, progress);
            let exchanged = book.score(at[k]);
            let test = Test::new(exchanged, &current, folds, 1);
            if test.gain < MIN_RELATIVE_GAIN && exchanged.cv_rms < book.score(without).cv_rms {
                alternatives.push(Alternative {
                    removed: effects[*j],
                    added: proposals[added[0]].0,
                    cv_rms: book.score(at[k]).cv_rms,
                    test,
                });
            }
        }
        alternatives.sort_by(|a, b| a.cv_rms.total_cmp(&b.cv_rms));
        return finish(
            &mut book,
            model,
            single_at,
            single_tests,
            &proposals,
            moves,
            alternatives,
            held_back,
            progress,
        );
    }
}

/// Brings `proposals[i]` for each `i` of `chosen` into the model, as entered by move `entered`
/// among `family` candidates.
fn enter<E: Copy>(
    model: &mut Vec<Member<E>>,
    proposals: &[(E, String)],
    chosen: &[usize],
    entered: usize,
    family: usize,
) {
    for &i in chosen {
        model.push(Member {
            effect: proposals[i].0,
            evidence: proposals[i].1.clone(),
            entered,
            family,
        });
    }
}

/// An addition of proposals to the model: their indices into the proposals, the book entry of
/// the model with them, their test and its family size.
type Addition = (Vec<usize>, usize, Test, usize);

/// The admissible block of proposals with the lowest held-out RMS (indices into `proposals`,
/// in the order of `ranked`): its book entry, test and family size (see
/// [`stepwise_selection`]). With `singles` (the round's number of single candidates, when one
/// of them passes) each effect of a block must pass its [`Test`] added to the rest of the
/// block at that round's threshold; without, at one test's (C = 1). Also the blocks held back
/// ([`HeldBack`]): their gains, and each effect's added to the others, are beyond noise
/// (conditions 2 and 3) but the pooled gain is below [`MIN_RELATIVE_GAIN`] or an effect does
/// not earn its place, lowest held-out RMS first.
#[allow(clippy::too_many_arguments)]
fn best_block<P: Problem + Sync>(
    book: &mut Book<'_, P>,
    effects: &[P::Effect],
    current: &Score,
    proposals: &[(P::Effect, String)],
    ranked: &[usize],
    single_at: &[usize],
    singles: Option<usize>,
    largest: usize,
    progress: &mut dyn FnMut(&str),
) -> (Option<Addition>, Vec<HeldBack<P::Effect>>)
where
    P::Effect: Sync,
    P::Fit: Send,
{
    let n = ranked.len();
    let folds = book.problem.folds();
    let model = |block: &[usize]| -> Vec<P::Effect> {
        effects
            .iter()
            .copied()
            .chain(block.iter().map(|&i| proposals[i].0))
            .collect()
    };
    // Every pair, its effects in ranked order.
    let problem = book.problem;
    let compatible = |a: usize, b: usize| problem.compatible(proposals[a].0, proposals[b].0);
    let pairs: Vec<Vec<usize>> = (0..n)
        .flat_map(|a| (a + 1..n).map(move |b| vec![ranked[a], ranked[b]]))
        .filter(|p| compatible(p[0], p[1]))
        .collect();
    let pair_at = book.score_all(
        &pairs.iter().map(|p| model(p)).collect::<Vec<_>>(),
        progress,
    );
    // Every triple, its effects in ranked order.
    let triples: Vec<Vec<usize>> = if largest >= 3 {
        (0..n)
            .flat_map(|a| (a + 1..n).flat_map(move |b| (b + 1..n).map(move |c| (a, b, c))))
            .map(|(a, b, c)| vec![ranked[a], ranked[b], ranked[c]])
            .filter(|t| compatible(t[0], t[1]) && compatible(t[0], t[2]) && compatible(t[1], t[2]))
            .collect()
    } else {
        Vec::new()
    };
    let triple_at = book.score_all(
        &triples.iter().map(|t| model(t)).collect::<Vec<_>>(),
        progress,
    );
    let mut best: Option<Addition> = None;
    let mut held_back: Vec<HeldBack<P::Effect>> = Vec::new();
    let families = [
        (pairs, pair_at, subsets(n, 2)),
        (triples, triple_at, subsets(n, 3)),
    ];
    for (blocks, at, family) in &families {
        for (block, &i) in blocks.iter().zip(at) {
            let score = book.score(i);
            let test = Test::new(current, score, folds, *family);
            if !test.significant() || book.visited.contains(&i) {
                continue;
            }
            // Each effect's test added to the rest of the block (the block without it was
            // scored with the smaller blocks): at one test's threshold, and at the rule's.
            let members: Option<Vec<(Test, Test)>> = block
                .iter()
                .map(|&leaving| {
                    let rest: Vec<usize> =
                        block.iter().copied().filter(|&k| k != leaving).collect();
                    let without = if rest.len() == 1 {
                        Some(single_at[rest[0]])
                    } else {
                        book.find(&model(&rest))
                    };
                    without.map(|w| {
                        let one = Test::new(book.score(w), score, folds, 1);
                        (one, one.among(singles.unwrap_or(1)))
                    })
                })
                .collect();
            // A block with an effect whose gain given the others is within noise is another
            // block with a passenger: neither added nor shown.
            let Some(members) = members.filter(|m| m.iter().all(|(one, _)| one.significant()))
            else {
                continue;
            };
            // Every effect earns its place in the block: it passes its test at the rule's
            // threshold.
            let idle = members.iter().position(|(_, rule)| !rule.passes());
            if test.passes() && idle.is_none() {
                if best
                    .as_ref()
                    .is_none_or(|(_, b, _, _)| score.cv_rms < book.score(*b).cv_rms)
                {
                    best = Some((block.clone(), i, test, *family));
                }
            } else {
                held_back.push(HeldBack {
                    effects: block.iter().map(|&k| proposals[k].0).collect(),
                    cv_rms: score.cv_rms,
                    fold_mse: score.fold_mse.clone(),
                    test,
                    idle: idle
                        .filter(|_| test.passes())
                        .map(|k| proposals[block[k]].0),
                });
            }
        }
    }
    held_back.sort_by(|a, b| a.cv_rms.total_cmp(&b.cv_rms));
    (best, held_back)
}

/// Removes, one at a time, an effect that is no longer worth a term: the model without it
/// has a held-out RMS less than [`MIN_RELATIVE_GAIN`] higher (the one whose removal leaves
/// the lowest held-out RMS first; never back to a model the search has been at). See
/// [`stepwise_selection`].
fn remove_idle<P: Problem + Sync>(
    book: &mut Book<'_, P>,
    model: &mut Vec<Member<P::Effect>>,
    moves: &mut Vec<Move<P::Effect>>,
    progress: &mut dyn FnMut(&str),
) where
    P::Effect: Sync,
    P::Fit: Send,
{
    let folds = book.problem.folds();
    while !model.is_empty() {
        let effects: Vec<P::Effect> = model.iter().map(|m| m.effect).collect();
        let here = book.at(&effects, progress);
        if !book.visited.contains(&here) {
            book.visited.push(here);
        }
        let without: Vec<Vec<P::Effect>> = (0..effects.len())
            .map(|j| {
                let mut fewer = effects.clone();
                fewer.remove(j);
                fewer
            })
            .collect();
        let at = book.score_all(&without, progress);
        let tests: Vec<Test> = at
            .iter()
            .map(|&i| Test::new(book.score(i), book.score(here), folds, 1))
            .collect();
        let Some(j) = (0..effects.len())
            .filter(|&j| tests[j].gain < MIN_RELATIVE_GAIN && !book.visited.contains(&at[j]))
            .min_by(|&a, &b| book.by_cv_rms(at[a], at[b]))
        else {
            return;
        };
        moves.push(Move {
            action: Action::Remove(effects[j]),
            cv_rms_before: book.score(here).cv_rms,
            cv_rms: book.score(at[j]).cv_rms,
            test: tests[j],
        });
        model.remove(j);
    }
}

/// The selection from the final model: its prefixes scored as steps (a block's test on each
/// of its effects, with the C of the move that brought it in), the last round's singles as
/// rejected candidates.
#[allow(clippy::too_many_arguments)]
fn finish<P: Problem + Sync>(
    book: &mut Book<'_, P>,
    model: Vec<Member<P::Effect>>,
    single_at: Vec<usize>,
    single_tests: Vec<Test>,
    proposals: &[(P::Effect, String)],
    moves: Vec<Move<P::Effect>>,
    alternatives: Vec<Alternative<P::Effect>>,
    held_back: Vec<HeldBack<P::Effect>>,
    progress: &mut dyn FnMut(&str),
) -> Selection<P::Effect, P::Fit>
where
    P::Effect: Sync,
    P::Fit: Send,
{
    let folds = book.problem.folds();
    let rejected = proposals
        .iter()
        .zip(single_at.iter().zip(single_tests))
        .map(|((effect, _), (&i, test))| Rejected {
            effect: *effect,
            cv_rms: book.score(i).cv_rms,
            fold_mse: book.score(i).fold_mse.clone(),
            test,
        })
        .collect();
    let effects: Vec<P::Effect> = model.iter().map(|m| m.effect).collect();
    let prefixes: Vec<Vec<P::Effect>> =
        (0..=effects.len()).map(|k| effects[..k].to_vec()).collect();
    let at = book.score_all(&prefixes, progress);
    // Each step fitted with its effects in the order they entered (the book may hold the
    // same set fitted in another order: equal up to rounding, but the step's fit lists its
    // effects as the model's name does).
    let stale: Vec<usize> = (0..prefixes.len())
        .filter(|&k| book.models[at[k]].0 != prefixes[k])
        .collect();
    let refits: Vec<(Score, P::Fit)> = {
        use rayon::prelude::*;
        let problem = book.problem;
        stale
            .par_iter()
            .map(|&k| score(problem, &prefixes[k]))
            .collect()
    };
    let mut prefix: Vec<(Score, P::Fit)> = at
        .iter()
        .map(|&i| (book.score(i).clone(), book.fit(i).clone()))
        .collect();
    for (k, refit) in stale.into_iter().zip(refits) {
        prefix[k] = refit;
    }
    let mut steps = Vec::new();
    let mut start = 0;
    while start < model.len() {
        let end = start
            + model[start..]
                .iter()
                .take_while(|m| m.entered == model[start].entered)
                .count();
        let test = Test::new(&prefix[start].0, &prefix[end].0, folds, model[start].family);
        for (k, member) in model.iter().enumerate().take(end).skip(start) {
            let together: Vec<P::Effect> = effects[start..end]
                .iter()
                .copied()
                .filter(|&e| e != member.effect)
                .collect();
            steps.push(Accepted {
                effect: member.effect,
                evidence: member.evidence.clone(),
                score: prefix[k + 1].0.clone(),
                fit: prefix[k + 1].1.clone(),
                together_with: together.first().copied(),
                together,
                test,
            });
        }
        start = end;
    }
    Selection {
        baseline: prefix.swap_remove(0),
        steps,
        rejected,
        moves,
        alternatives,
        held_back,
    }
}

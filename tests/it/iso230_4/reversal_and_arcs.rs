//! What a trace cannot tell, said so: lateral play does not time its axis's reversal, a
//! spike outside the searched decays is withdrawn with the reason, and partial arcs recover
//! what they identify and flag the rest.

use super::*;

#[test]
fn lateral_play_alone_measures_the_play_and_does_not_time_the_reversal() {
    // Lateral play's radial share σ·|sin θ|·l/2 is continuous where p reverses (sin θ = 0
    // there; |cos θ| for q): moving the reversal by a 30 ms lag (0.2° at 1000 mm/min on a
    // 150 mm bar) changes it by at most 2·0.0033·l/2 = 3 nm over 7 readings a reversal, far
    // under the 0.1 µm noise. The play is measured; no lag is given for either axis (before,
    // the lag followed the noise that an insignificant spike fitted: −136 ± 1.7 ms for q).
    let machine = Machine {
        lag: [30e-3, 30e-3],
        play: [1.0 * UM, 1.0 * UM],
        ..Machine::default()
    };
    for seed in 1..=3 {
        let table = simulate(&machine, &full_circles(), 0.1 * UM, seed);
        let e = evaluate(&table, &xy()).unwrap();
        let d = e.diagnostics.as_ref().unwrap();
        for (axis, term, letter) in [(0, Term::LateralPlayP, 'x'), (1, Term::LateralPlayQ, 'y')] {
            let play = d.get(term).unwrap();
            assert!(
                (play.value - 1.0 * UM).abs() < 4.0 * play.u,
                "seed {seed} {term:?}: {} ± {} µm",
                play.value / UM,
                play.u / UM
            );
            assert_eq!(d.reversal_lag[axis], None, "seed {seed}");
            let key = format!("reversal_lag_{letter}_ms:");
            assert!(
                d.notes
                    .iter()
                    .any(|n| n.starts_with(&key) && n.contains("lateral play cannot")),
                "seed {seed}: {:?}",
                d.notes
            );
        }
    }
}

#[test]
fn the_most_lobes_searched_is_an_end_on_an_arc_and_a_count_on_a_whole_turn() {
    // A 250 Hz trace of R = 150 mm at 1000 mm/min has 14 137 readings a turn: lobe counts from 3
    // to 60. On a whole turn 61 lobes are orthogonal to every count searched, so 60 is a count
    // like 59; on the 180° arc they are not (∫ sin 60θ·cos 61θ dθ over 0..π is 1/121 − 1,
    // against π/2 for sin² 60θ), so a fit that ends at 60 may hold a feature of more.
    use mtwin::kinds::ballbar::iso230_4::{CircleData, Shape};
    for (runs, end) in [(full_circles(), false), (arcs(0.0, 180.0), true)] {
        let table = simulate(&Machine::default(), &runs, 0.1 * UM, 1);
        let data = CircleData::new(&table, &xy()).unwrap();
        assert_eq!(data.ranges.lobes, (3, 60));
        for (lobes, expected) in [(59, false), (60, end)] {
            let shape = Shape {
                lobes,
                ..Shape::default()
            };
            let why = data.shape_at_range_end(Term::Lobes, &shape);
            assert_eq!(why.is_some(), expected, "{lobes} lobes, arc {end}: {why:?}");
        }
    }
}

#[test]
fn a_spike_outside_the_searched_decays_is_withdrawn_with_the_reason() {
    // At 250 Hz the decays searched run from two sampling intervals (8 ms) to 200 ms. A 2 ms
    // spike of 3 µm is seen by one reading at most (e^(−2) of it 4 ms on): the fit had put its
    // decay at 8.00 ± 0.91 ms and its height at 1.06 µm. A 500 ms one, longer than any the
    // fit can take: 200.00 ± 1.72 ms and 3.58 ± 0.02 µm. Neither is a measurement. The spike
    // the other tests inject (5 µm, 20 ms), inside the range, keeps its values within their
    // tolerances (the control).
    for (spike, end) in [
        ((3.0 * UM, 2e-3), Some("shortest")),
        ((3.0 * UM, 0.5), Some("longest")),
        (SPIKE_P, None),
    ] {
        let machine = Machine {
            spike: [spike, (0.0, 1.0)],
            ..Machine::default()
        };
        for seed in 1..=2 {
            let table = simulate(&machine, &full_circles(), 0.1 * UM, seed);
            let e = evaluate(&table, &xy()).unwrap();
            let d = e.diagnostics.as_ref().unwrap();
            let withdrawn = d
                .unidentifiable
                .iter()
                .find(|(t, _)| *t == Term::ReversalSpikeP);
            match end {
                Some(end) => {
                    assert!(
                        d.get(Term::ReversalSpikeP).is_none(),
                        "{spike:?}, seed {seed}: {:?}",
                        d.get(Term::ReversalSpikeP)
                    );
                    let (_, reason) = withdrawn.unwrap();
                    assert!(reason.contains(end), "{reason}");
                }
                None => {
                    assert!(withdrawn.is_none(), "seed {seed}: {withdrawn:?}");
                    let estimate = d.get(Term::ReversalSpikeP).unwrap();
                    let (decay, _) = estimate.shape.unwrap();
                    assert!(
                        (decay / SPIKE_P.1 - 1.0).abs() < 0.1
                            && (estimate.value - SPIKE_P.0).abs()
                                <= tolerance(Term::ReversalSpikeP, SPIKE_P.0),
                        "seed {seed}: {} µm, {} ms",
                        estimate.value / UM,
                        decay * 1e3
                    );
                }
            }
        }
    }
}

#[test]
fn partial_arcs_recover_what_is_identifiable_and_flag_the_rest() {
    // YZ: the upper half, θ from 0° to 180°, Y reversing at both ends (never crossed);
    // ZX: θ from 270° through 0° to 90°, X reversing at both ends.
    for (plane, start, flagged) in [
        (Plane::YZ, 0.0, [Term::StraightnessP, Term::ReversalSpikeP]),
        (
            Plane::ZX,
            270.0,
            [Term::StraightnessQ, Term::ReversalSpikeQ],
        ),
    ] {
        // Every error but the two these arcs cannot show.
        let mut machine = everything();
        let other = usize::from(flagged[0] == Term::StraightnessQ);
        machine.straightness[other] = 0.0;
        machine.spike[other] = (0.0, 1.0);
        let table = simulate(&machine, &arcs(start, 180.0), 0.2 * UM, 7);
        let e = evaluate(&table, &test_in(plane)).unwrap();
        assert!((e.spans[0].unwrap().to_degrees() - 180.0).abs() < 0.05);
        let d = e.diagnostics.as_ref().unwrap();
        let unidentifiable: Vec<Term> = d.unidentifiable.iter().map(|(t, _)| *t).collect();
        assert_eq!(unidentifiable, flagged, "{plane}: {:?}", d.unidentifiable);
        println!("{}", e.to_text());
        for (term, truth, _) in injections() {
            if flagged.contains(&term) {
                assert!(d.get(term).is_none());
                assert!(e.to_json()["diagnostics"][term.key(plane)].is_null());
                continue;
            }
            let (truth, value) = (truth, d.get(term).unwrap().value);
            assert!(
                (value - truth).abs() <= tolerance(term, truth),
                "{plane} {term:?}: {value} vs {truth}"
            );
        }
    }
}

/// The reversal lag's u holds at low signal to noise: lost motion of 0.4 µm (a step, as this
/// simulator makes it) under 0.3 µm of noise, seeds 1 to 10 (20 lags). A 95 % band misses
/// one lag in twenty on average; more than 2 of 20 has a binomial probability of 7.5 %, and the
/// u this replaced missed 33 of 80 at this level (the measurement below).
#[test]
fn a_noise_free_spike_comes_back_with_its_decay_and_its_height_to_the_sampling() {
    // The spike h·e^(−Δt/τ) is in the model's family exactly, so a noise-free trace gives its
    // decay to the refinement (0.001 %) and the other columns' small share; 0.5 % is far under
    // the 17 % a sample on the reversal once made (a tie of this simulator's: the reading read
    // after the onset in one sense and before it in the other). The onset is placed only
    // within the 4 ms between samples (mid-way), so the height comes back within the sampling
    // factor e^(±2 ms/τ) = e^(±0.1), and within 2 u, u holding the onset's interval.
    let (height, decay) = (1.5 * UM, 0.02);
    let half_interval = 0.5 / RATE;
    for backlash in [0.0, 1.0 * UM] {
        let machine = Machine {
            lag: [30e-3, 30e-3],
            backlash: [backlash, backlash],
            spike: [(height, decay), (0.0, 1.0)],
            ..Machine::default()
        };
        let table = simulate(&machine, &full_circles(), 0.0, 1);
        let e = evaluate(&table, &xy()).unwrap();
        let spike = e
            .diagnostics
            .as_ref()
            .unwrap()
            .get(Term::ReversalSpikeP)
            .unwrap();
        let (tau, _) = spike.shape.unwrap();
        assert!(
            (tau / decay - 1.0).abs() < 5e-3,
            "lost motion {backlash}: decay {} ms",
            tau * 1e3
        );
        let factor = (half_interval / decay).exp();
        assert!(
            spike.value > height / factor && spike.value < height * factor,
            "lost motion {backlash}: height {} µm",
            spike.value / UM
        );
        assert!(
            (spike.value - height).abs() < 2.0 * spike.u,
            "lost motion {backlash}: {} ± {} µm",
            spike.value / UM,
            spike.u / UM
        );
    }
}

#[test]
fn reversal_lag_u_covers_the_true_lag_at_low_signal_to_noise() {
    let machine = Machine {
        lag: [30e-3, 30e-3],
        backlash: [0.4 * UM, 0.4 * UM],
        ..Machine::default()
    };
    let mut missed = Vec::new();
    for seed in 1..=10 {
        let table = simulate(&machine, &full_circles(), 0.3 * UM, seed);
        let e = evaluate(&table, &xy()).unwrap();
        for (axis, lag) in e
            .diagnostics
            .as_ref()
            .unwrap()
            .reversal_lag
            .iter()
            .enumerate()
        {
            let (lag, u) = lag.expect("a 0.4 µm step under 0.3 µm of noise is located");
            if (lag - 30e-3).abs() > 2.0 * u {
                missed.push((seed, axis, lag * 1e3, u * 1e3));
            }
        }
    }
    assert!(
        missed.len() <= 2,
        "beyond 2 u (seed, axis, lag ms, u ms): {missed:?}"
    );
}

/// Which mechanism lost motion has is said only where the trace tells them apart. At 0.4 µm
/// (a step) under 0.3 µm of noise the fit sometimes takes the gap instead; every such reading
/// must carry the caveat that a step fits nearly as well. At 2 µm under 0.1 µm no caveat.
#[test]
fn the_backlash_mechanism_is_named_with_a_caveat_only_where_the_trace_cannot_tell() {
    let notes = |backlash: f64, noise: f64, seed: u64| {
        let machine = Machine {
            lag: [30e-3, 30e-3],
            backlash: [backlash * UM, backlash * UM],
            ..Machine::default()
        };
        let table = simulate(&machine, &full_circles(), noise * UM, seed);
        let e = evaluate(&table, &xy()).unwrap();
        e.diagnostics.unwrap().notes
    };
    let caveat = "does not tell the two apart";
    let mut read_as_play = 0;
    for seed in 1..=10 {
        for note in notes(0.4, 0.3, seed) {
            if note.contains("read as play") {
                read_as_play += 1;
                assert!(note.contains(caveat), "seed {seed}: {note}");
            }
        }
    }
    assert!(
        read_as_play > 0,
        "no trace read as play: the check above tested nothing"
    );
    for seed in 1..=2 {
        let notes = notes(2.0, 0.1, seed);
        assert!(notes.iter().all(|n| !n.contains(caveat)), "{notes:?}");
    }
}

/// A measurement, not a check: how often the reported reversal lag misses the true 30 ms by
/// more than 2 and 3 of its u, for lost motion of 1, 0.6 and 0.4 µm (steps, as this
/// simulator makes them) under 0.3 µm of noise, 80 lags each of seeds 1–40 and 41–80. A 95 %
/// band would miss about 4. Measured 2026-11-30 on seeds 1–40, beyond 2 u (3 u):
///
/// | u from | 1 µm | 0.6 µm | 0.4 µm |
/// |---|---|---|---|
/// | Δχ² = 1 interval about the fitted lag | 6 (6) | 20 (18) | 38 (38) |
/// | its hull over the whole range | 6 (6) | 18 (17) | 36 (35) |
/// | with the other mechanism's lag within σ̂² | 6 (4) | 17 (15) | 33 (29) |
/// | Δχ² ≤ 7.35 (a change point's 95 %), half-width / 1.96 | 7 (7) | 21 (14) | 28 (14) |
/// | with the other mechanism's set within 7.35·σ̂², farther edge / 1.96 | 1 (1) | 1 (1) | 2 (1) |
/// | the same, the other mechanism's set within 14.7·σ̂² | 1 (1) | 0 (0) | 0 (0) |
///
/// The last is what `locate_lag` does; on seeds 41–80 it misses none, the 95th percentile of
/// |error|/u is 1.96, 1.96 and 1.82–1.91, and the median u 0.60, 11.6–11.9 and 10.8–11.2 ms.
/// The step's location is a change point, not a regular parameter, so Δχ² = 1 undercovers;
/// but most misses came from the backlash's two mechanisms: a gap of b taken up after the
/// reversal lasts √(2·b/(R·ω²)) (21 ms for 0.4 µm at 1000 mm/min on a 150 mm bar), so "gap
/// from 10 ms" reads like "step at 30 ms", and the chosen one's set did not hold the other's;
/// and a set not centred on the fitted lag. The one miss left (the step's fit 19·σ̂² worse
/// than the gap's, b = 1 µm, seed 6: 5.2 ± 2.1 ms) was the simulator's: with samples half an
/// interval off the run's start, 30 ms put a sample on the actual reversal, where a velocity
/// rounded to zero decided its side. Re-measured with the samples 0.382 of an interval off
/// (no tie): none of 480 beyond 2 u on either seed set, the 95th percentile of |error|/u 1.90,
/// 1.74–1.90 and 1.74–1.76, the median u 0.43, 12.0 and 11.1–11.2 ms. Real play (the other mechanism) is measured by `reversal_lag_coverage_with_real_play`. Run
/// with `--ignored --nocapture`.
#[test]
#[ignore = "a measurement of the reversal lag's coverage at low signal to noise (about 1 min in the test profile): run on purpose"]
fn reversal_lag_coverage_at_low_signal_to_noise() {
    for backlash in [1.0, 0.6, 0.4] {
        let machine = Machine {
            lag: [30e-3, 30e-3],
            backlash: [backlash * UM, backlash * UM],
            ..Machine::default()
        };
        for seeds in [1..=40, 41..=80] {
            let (mut beyond_2u, mut beyond_3u, mut us, mut zs) = (0, 0, Vec::new(), Vec::new());
            for seed in seeds.clone() {
                let table = simulate(&machine, &full_circles(), 0.3 * UM, seed);
                let e = evaluate(&table, &xy()).unwrap();
                for (lag, u) in e
                    .diagnostics
                    .as_ref()
                    .unwrap()
                    .reversal_lag
                    .into_iter()
                    .flatten()
                {
                    let z = (lag - 30e-3).abs() / u;
                    us.push(u);
                    zs.push(z);
                    beyond_2u += usize::from(z > 2.0);
                    beyond_3u += usize::from(z > 3.0);
                }
            }
            us.sort_by(f64::total_cmp);
            zs.sort_by(f64::total_cmp);
            println!(
                "lost motion {backlash} µm, seeds {seeds:?}: {} of 80 lags located, {beyond_2u} beyond 2 u, {beyond_3u} beyond 3 u, median u {:.2} ms, 95th percentile of |error|/u {:.2}",
                us.len(),
                us.get(us.len() / 2).copied().unwrap_or(f64::NAN) * 1e3,
                zs.get(zs.len() * 95 / 100).copied().unwrap_or(f64::NAN)
            );
        }
    }
}

/// A measurement, not a check: how often the searched shapes' values (a spike's decay and
/// height, a cyclic error's period and amplitude) miss the truth by more than 2 and 3 of their
/// u at low signal to noise, 0.3 µm of noise, seeds 1–40 and 41–80, where they are reported.
/// Measured 2026-11-30, value beyond 2 u (3 u), shape beyond 2 u (3 u), of 40 each (a 95 %
/// band: 2):
///
/// | case | value | shape |
/// |---|---|---|
/// | spike 1.5 µm, 20 ms, on 1 µm of lost motion | 4 (0), 2 (0) | 3 (1), 1 (1) |
/// | spike 1.5 µm, 20 ms, alone (reported in 39 and 40) | 0 (0), 1 (0) | 3 (1), 1 (1) |
/// | cyclic 0.3 µm, 10 mm | 2 (0), 1 (0) | 2 (0), 2 (0) |
///
/// The first measurement (seeds 1–40) found the spike's height biased, 11 (3) beyond 2 u with
/// lost motion and 4 (1) alone, mean 1.33 µm and 23.0 ms for 1.5 µm and 20 ms: so did a
/// noise-free trace (1.31 µm, 23.3 ms). The estimate was right and the simulator was not: a
/// sample fell on the actual reversal (samples half an interval off the run's start, a 30 ms
/// lag of 7.5 intervals), on the spike's side in one sense and before it in the other, and no
/// single onset fits both. With the samples 0.382 of an interval off, the noise-free trace
/// gives 20.00 ms and 1.473 µm (the onset placed mid-interval: the sampling factor, inside its
/// u of 0.032 µm), and the mean heights under noise are 1.45–1.46 µm. Run with
/// `--ignored --nocapture`.
#[test]
#[ignore = "a measurement of the searched shapes' coverage at low signal to noise (about a minute in the test profile): run on purpose"]
fn searched_shape_coverage_at_low_signal_to_noise() {
    let cases = [
        (
            "spike 1.5 µm, 20 ms, on 1 µm of lost motion",
            Term::ReversalSpikeP,
            (1.5 * UM, 0.02),
            Machine {
                lag: [30e-3, 30e-3],
                backlash: [1.0 * UM, 1.0 * UM],
                spike: [(1.5 * UM, 0.02), (0.0, 1.0)],
                ..Machine::default()
            },
        ),
        (
            "spike 1.5 µm, 20 ms, alone",
            Term::ReversalSpikeP,
            (1.5 * UM, 0.02),
            Machine {
                lag: [30e-3, 30e-3],
                spike: [(1.5 * UM, 0.02), (0.0, 1.0)],
                ..Machine::default()
            },
        ),
        (
            "cyclic 0.3 µm, 10 mm",
            Term::CyclicP,
            (0.3 * UM, 0.010),
            Machine {
                cyclic: [(0.3 * UM, 0.010, 0.7), (0.0, 0.0, 0.0)],
                ..Machine::default()
            },
        ),
    ];
    for ((name, term, (value, shape), machine), seeds) in cases
        .iter()
        .flat_map(|case| [(case, 1..=40), (case, 41..=80)])
    {
        let (mut reported, mut value_beyond, mut shape_beyond) = (0, [0; 2], [0; 2]);
        for seed in seeds.clone() {
            let table = simulate(machine, &full_circles(), 0.3 * UM, seed);
            let e = evaluate(&table, &xy()).unwrap();
            let Some(estimate) = e.diagnostics.as_ref().unwrap().get(*term) else {
                continue;
            };
            let Some((s, u_s)) = estimate.shape else {
                continue;
            };
            reported += 1;
            let z_value = (estimate.value.abs() - value).abs() / estimate.u;
            let z_shape = (s - shape).abs() / u_s;
            for (k, limit) in [2.0, 3.0].into_iter().enumerate() {
                value_beyond[k] += usize::from(z_value > limit);
                shape_beyond[k] += usize::from(z_shape > limit);
            }
        }
        println!(
            "{name}, seeds {seeds:?}: reported in {reported} of 40; value beyond 2 u (3 u) {} ({}), shape {} ({})",
            value_beyond[0], value_beyond[1], shape_beyond[0], shape_beyond[1]
        );
    }
}

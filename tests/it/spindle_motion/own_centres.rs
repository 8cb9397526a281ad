//! The residual plot and the total plot about their own centres (ISO 230-7 §3.8.6, §3.8.2
//! with §3.7.7 Note 1 "unless specified otherwise"), checked against brute force.

use super::*;
use mtwin::kinds::spindle::analysis::motion::values_about;

const CENTRES: [Centre; 5] = [
    Centre::Pc,
    Centre::Lsc,
    Centre::Mrs,
    Centre::Mic,
    Centre::Mcc,
];

/// `max − min` over `(k, m)` of `s[k, m] − c·(cos θ_m, sin θ_m)`: the total plot about `c`,
/// from the record itself.
fn pooled_range(r: &Revolutions, c: [f64; 2]) -> (f64, f64) {
    let m_count = r.samples_per_revolution();
    r.values()
        .iter()
        .enumerate()
        .map(|(i, v)| {
            let t = theta(i % m_count, m_count);
            v - c[0] * t.cos() - c[1] * t.sin()
        })
        .fold((f64::INFINITY, f64::NEG_INFINITY), |(lo, hi), x| {
            (lo.min(x), hi.max(x))
        })
}

/// A 2- and 3-UPR synchronous profile with an off-centre 1 UPR, plus an asynchronous line at
/// 0.37 UPR: the residual's own MRS, MIC and MCC centres are off PC, and the total plot's own
/// centres are not the synchronous plot's.
fn lopsided() -> Revolutions {
    let um = 1e-6;
    record(120, 7, |k, t| {
        0.9 * um * (t + 0.4).cos()
            + 0.3 * um * (2.0 * t).cos()
            + 0.2 * um * (3.0 * t + 0.5).sin()
            + 0.15 * um * (TAU * 0.37 * (k as f64 + t / TAU) + 0.2).sin()
    })
}

/// The residual `R = S − mean − fundamental` differs from `S` by a constant and a 1-UPR term,
/// which a fitted centre absorbs: about LSC, MRS, MIC and MCC its value is the synchronous
/// value; about PC it is the range of `R` — computed here from the profile by its own Fourier
/// sums, not by the module.
#[test]
fn the_residual_about_each_centre_is_its_own_fit() {
    let r = lopsided();
    let d = decompose(&r);
    let residual_pc = {
        let (lo, hi) = d
            .residual
            .iter()
            .fold((f64::INFINITY, f64::NEG_INFINITY), |(l, h), &x| {
                (l.min(x), h.max(x))
            });
        hi - lo
    };
    // R from the definition: S − mean(S) − a1 cos θ − b1 sin θ with a1, b1 summed here.
    let m_count = d.synchronous.len();
    let mean = d.synchronous.iter().sum::<f64>() / m_count as f64;
    let (mut a1, mut b1) = (0.0, 0.0);
    for (m, s) in d.synchronous.iter().enumerate() {
        a1 += s * theta(m, m_count).cos();
        b1 += s * theta(m, m_count).sin();
    }
    let (a1, b1) = (2.0 * a1 / m_count as f64, 2.0 * b1 / m_count as f64);
    let by_hand = (0..m_count)
        .map(|m| {
            let t = theta(m, m_count);
            d.synchronous[m] - mean - a1 * t.cos() - b1 * t.sin()
        })
        .fold((f64::INFINITY, f64::NEG_INFINITY), |(l, h), x| {
            (l.min(x), h.max(x))
        });
    close(residual_pc, by_hand.1 - by_hand.0, 1e-18, "R by hand");

    let all = values_about(&r, Direction::Radial, &CENTRES).unwrap();
    for v in &all {
        let want = match v.centre {
            Centre::Pc => residual_pc,
            _ => v.synchronous,
        };
        close(
            v.residual,
            want,
            1e-18,
            &format!("residual about {}", v.centre),
        );
    }
    // Not one number repeated: the residual's own MRS is below its range about PC.
    let mrs = all.iter().find(|v| v.centre == Centre::Mrs).unwrap();
    assert!(
        mrs.residual < residual_pc - 1e-9,
        "{} vs {residual_pc}",
        mrs.residual
    );
}

/// The total plot's own centre: PC and LSC are the synchronous plot's (least squares over
/// every revolution is least squares on their mean); MRS minimises the pooled range, MIC
/// maximises the pooled minimum, MCC minimises the pooled maximum. Each is checked against a
/// brute-force search over a 1 nm grid of centres about it (a value moves by at most 2 nm per
/// nm of centre, so the LP optimum is within 2 nm of the grid's best and never worse).
#[test]
fn the_total_about_its_own_centre_is_the_best_centre_for_the_whole_cloud() {
    let r = lopsided();
    let all = values_about(&r, Direction::Radial, &CENTRES).unwrap();
    let step = 1e-9;
    for v in &all {
        let about_own = pooled_range(&r, v.total_own_offset);
        close(
            about_own.1 - about_own.0,
            v.total_own_centre,
            1e-18,
            &format!("{}: the value is the range about its offset", v.centre),
        );
        let about_sync = pooled_range(&r, v.offset);
        close(
            v.total,
            about_sync.1 - about_sync.0,
            1e-18,
            "total about the sync centre",
        );
        if matches!(v.centre, Centre::Pc | Centre::Lsc) {
            assert_eq!(v.total_own_offset, v.offset, "{}", v.centre);
            assert_eq!(v.total_own_centre, v.total, "{}", v.centre);
            continue;
        }
        // The objective each centre optimises, over the pooled cloud.
        let objective = |c: [f64; 2]| {
            let (lo, hi) = pooled_range(&r, c);
            match v.centre {
                Centre::Mrs => hi - lo,
                Centre::Mic => -lo,
                _ => hi,
            }
        };
        let own = objective(v.total_own_offset);
        let mut best = f64::INFINITY;
        for i in -40..=40 {
            for j in -40..=40 {
                let c = [
                    v.total_own_offset[0] + i as f64 * step,
                    v.total_own_offset[1] + j as f64 * step,
                ];
                best = best.min(objective(c));
            }
        }
        assert!(own <= best + 1e-18, "{}: {own:e} > grid {best:e}", v.centre);
        assert!(best - own <= 2.0 * step, "{}: grid {best:e}", v.centre);
        // The synchronous plot's centre is no better for the cloud than the cloud's own.
        assert!(own <= objective(v.offset) + 1e-18, "{}", v.centre);
    }
    // The cloud's MRS is strictly better here than the synchronous plot's centre.
    let mrs = all.iter().find(|v| v.centre == Centre::Mrs).unwrap();
    assert!(mrs.total_own_centre < mrs.total - 1e-10, "{mrs:?}");
}

/// One revolution: the total plot is the synchronous plot, so each own centre is the
/// synchronous one.
#[test]
fn with_one_revolution_the_own_centre_is_the_synchronous_one() {
    let one = record(90, 1, |_, t| {
        1e-6 * ((2.0 * t).cos() + 0.4 * (3.0 * t).sin() + 0.7 * t.cos())
    });
    for v in values_about(&one, Direction::Radial, &CENTRES).unwrap() {
        close(
            v.total_own_centre,
            v.synchronous,
            1e-18,
            &format!("{}", v.centre),
        );
        close(v.total, v.synchronous, 1e-18, &format!("{}", v.centre));
    }
}

//! The fast fits against the model's definition, column by column: cross products from the
//! blocks' sums, the lag profile, the searches' trials, the periodogram by transform, and
//! whole fits of unions of blocks, each checked against the columns of
//! [`diagnostic_column`] over the same readings and refits of them.

use super::blocks::Blocks;
use super::linalg::Projection;
use super::normal::Fitter;
use super::profile::LagProfile;
use super::search::brent;
use super::{BasisPoint, CircleData, CircularTest, Shape, Term, diagnostic_column};
use crate::kinds::ballbar::table::{BallbarReading, BallbarTable, Sense};
use crate::machine::Plane;
use crate::math::Real;
use std::f64::consts::TAU;

/// A two-sense trace with reversal, spike, cyclic and lobe terms and noise, both senses from
/// 10° before 0° to 10° past a full turn; with `exact`, readings also at exactly 0°, 90°,
/// 180° and 270° (where the unlagged reversal columns are 0 and the lagged ones are not).
fn trace(exact: bool) -> CircleData {
    let test = CircularTest {
        plane: Plane::XY,
        radius: 0.1,
        feed: 0.01,
    };
    let truth = Shape {
        lag: [0.02, -0.03],
        decay: [0.015, 0.04],
        period: [0.007, 0.011],
        lobes: 5,
        play: [0.0, 0.0],
        angle_lag: 0.0,
    };
    let n = 3000;
    let mut readings = Vec::new();
    let mut time = 0.0;
    let mut state: u64 = 12345;
    let mut noise = || {
        state = state
            .wrapping_mul(6364136223846793005)
            .wrapping_add(1442695040888963407);
        ((state >> 11) as Real / (1u64 << 53) as Real - 0.5) * 1e-7
    };
    for (sense, sign) in [(Sense::Ccw, 1.0), (Sense::Cw, -1.0)] {
        for k in 0..n {
            let offset = if exact { 0.0 } else { 0.3 };
            let turn = -(10.0 as Real).to_radians()
                + (TAU + (20.0 as Real).to_radians()) * (k as Real + offset) / n as Real;
            let angle = if exact && k % 750 == 0 {
                ((k / 750) as Real * TAU / 4.0).rem_euclid(TAU)
            } else {
                (sign * turn).rem_euclid(TAU)
            };
            time += 0.01;
            let at = BasisPoint::new(angle, sign, time, [true; 2]);
            let mut d = 1e-6 + noise();
            for (term, size) in [
                (Term::CentreP, 3e-6),
                (Term::BacklashP, 2e-6),
                (Term::BacklashQ, 1e-6),
                (Term::ReversalSpikeP, 2e-6),
                (Term::ReversalSpikeQ, 1.5e-6),
                (Term::CyclicP, 0.5e-6),
                (Term::Lobes, 0.3e-6),
            ] {
                d += size * diagnostic_column(term, 0, &at, &test, &truth);
            }
            readings.push(BallbarReading {
                sense,
                angle,
                deviation: d,
                time: Some(time),
            });
        }
    }
    let table = BallbarTable {
        readings,
        ..Default::default()
    };
    CircleData::new(&table, &test).unwrap()
}

/// Shapes with lags of both signs, play, short and long decays, periods and an angle lag.
fn shapes() -> Vec<Shape> {
    let base = Shape::default();
    vec![
        base,
        Shape {
            lag: [0.021, -0.033],
            decay: [0.012, 0.05],
            period: [0.0071, 0.0109],
            lobes: 5,
            play: [0.0, 0.0],
            angle_lag: 0.0,
        },
        Shape {
            lag: [-0.05, 0.08],
            decay: [0.1, 0.003],
            period: [0.02, 0.0031],
            lobes: 7,
            play: [3e-6, 8e-6],
            angle_lag: 0.0,
        },
        Shape {
            lag: [0.0, -0.11],
            play: [2e-6, 0.0],
            angle_lag: 0.004,
            ..base
        },
    ]
}

/// Every term.
const ALL: [Term; 19] = [
    Term::Radius,
    Term::CentreP,
    Term::CentreQ,
    Term::Squareness,
    Term::ScaleMismatch,
    Term::ServoMismatch,
    Term::BacklashP,
    Term::BacklashQ,
    Term::LateralPlayP,
    Term::LateralPlayQ,
    Term::StraightnessP,
    Term::StraightnessQ,
    Term::ReversalSpikeP,
    Term::ReversalSpikeQ,
    Term::CyclicP,
    Term::CyclicQ,
    Term::Lobes,
    Term::RadiusDrift,
    Term::SenseRadius,
];

/// The blocks a fit includes and its readings.
type Fold = (Vec<bool>, Vec<usize>);

/// The data cut into 8 sectors of 45°, and the readings of each fold (all, then each sector
/// held out in turn, some of them).
fn folds(data: &CircleData) -> (Blocks, Vec<Fold>) {
    let sectors: Vec<usize> = data
        .points
        .iter()
        .map(|p| ((p.angle / TAU * 8.0) as usize).min(7))
        .collect();
    let blocks = Blocks::new(data, &sectors, 8);
    let folds = [None, Some(0), Some(3), Some(7)]
        .into_iter()
        .map(|held| {
            let included: Vec<bool> = (0..8).map(|b| Some(b) != held).collect();
            let rows = (0..data.len())
                .filter(|&i| Some(sectors[i]) != held)
                .collect();
            (included, rows)
        })
        .collect();
    (blocks, folds)
}

/// The residual sum of squares of `columns` refitted over `rows`.
fn refit(columns: Vec<Vec<Real>>, data: &CircleData, rows: &[usize]) -> Real {
    let y: Vec<Real> = rows.iter().map(|&i| data.deviation[i]).collect();
    Projection::new(columns, &y).rss
}

#[test]
fn columns_and_their_products_are_the_models() {
    for exact in [false, true] {
        let data = trace(exact);
        let all: Vec<usize> = (0..data.len()).collect();
        let (blocks, folds) = folds(&data);
        for (included, rows) in folds {
            let fitter = Fitter::new(&data, &blocks, included);
            for shape in shapes() {
                let columns = fitter.columns(&ALL, &shape);
                let direct = data.columns_on(&ALL, &shape, &rows);
                let everywhere = data.columns_on(&ALL, &shape, &all);
                assert_eq!(columns.len(), direct.len());
                let y: Vec<Real> = rows.iter().map(|&i| data.deviation[i]).collect();
                for a in 0..columns.len() {
                    // Values at every reading: the residual of the column alone, coefficient −1.
                    let values = fitter.residuals(&columns[a..=a], &[-1.0]);
                    for (i, (v, d)) in values.iter().zip(&data.deviation).enumerate() {
                        let value = v - d;
                        assert!(
                            (value - everywhere[a][i]).abs() <= 1e-12,
                            "column {a} at {i}: {value} vs {} ({shape:?})",
                            everywhere[a][i]
                        );
                    }
                    let dy: Real = direct[a].iter().zip(&y).map(|(u, v)| u * v).sum();
                    let cy = fitter.cross_y(&columns[a]);
                    assert!(
                        (dy - cy).abs() <= 1e-9 * (dy.abs() + 1e-12),
                        "y {a}: {dy} vs {cy}"
                    );
                    for b in a..columns.len() {
                        let d: Real = direct[a].iter().zip(&direct[b]).map(|(u, v)| u * v).sum();
                        let norms = |c: &[Real]| c.iter().map(|v| v * v).sum::<Real>();
                        let scale = (norms(&direct[a]) * norms(&direct[b])).sqrt();
                        let c = fitter.cross(&columns[a], &columns[b]);
                        assert!(
                            (d - c).abs() <= 1e-11 * scale + 1e-300,
                            "{a} × {b}: {d} vs {c} ({shape:?})"
                        );
                    }
                }
            }
        }
    }
}

#[test]
fn extra_columns_are_scored_as_a_refit_would() {
    let data = trace(false);
    let (blocks, folds) = folds(&data);
    let fixed = [Term::Radius, Term::CentreP, Term::CentreQ, Term::BacklashP];
    let extra = [Term::CyclicP, Term::ReversalSpikeQ];
    for (included, rows) in folds {
        let fitter = Fitter::new(&data, &blocks, included);
        let shape = shapes()[1];
        let columns = fitter.columns(&fixed, &shape);
        let extras = fitter.columns(&extra, &shape);
        let fit = fitter.project(&columns);
        let fb = nalgebra::DMatrix::from_fn(columns.len(), extras.len(), |i, j| {
            fitter.cross(&columns[i], &extras[j])
        });
        let bb = nalgebra::DMatrix::from_fn(extras.len(), extras.len(), |i, j| {
            fitter.cross(&extras[i], &extras[j])
        });
        let by: Vec<Real> = extras.iter().map(|c| fitter.cross_y(c)).collect();
        let both: Vec<Term> = fixed.iter().chain(&extra).copied().collect();
        let reference = refit(data.columns_on(&both, &shape, &rows), &data, &rows);
        let fast = fit.rss_from(&fb, &bb, &by);
        assert!(
            (fast - reference).abs() <= 1e-9 * reference,
            "{fast} vs {reference}"
        );
        assert!(
            (fit.rss - refit(data.columns_on(&fixed, &shape, &rows), &data, &rows)).abs()
                <= 1e-9 * fit.rss
        );
    }
}

#[test]
fn the_lag_profile_is_a_refit_at_every_lag() {
    let terms = [
        Term::Radius,
        Term::CentreP,
        Term::CentreQ,
        Term::BacklashP,
        Term::BacklashQ,
        Term::LateralPlayP,
        Term::ReversalSpikeP,
        Term::ReversalSpikeQ,
        Term::CyclicP,
    ];
    for exact in [false, true] {
        let data = trace(exact);
        let (blocks, folds) = folds(&data);
        for (included, rows) in folds {
            let fitter = Fitter::new(&data, &blocks, included);
            for shape in shapes().into_iter().filter(|s| s.angle_lag == 0.0) {
                for axis in 0..2 {
                    let (moving, fixed): (Vec<Term>, Vec<Term>) = terms
                        .iter()
                        .copied()
                        .partition(|t| t.reversal_axis() == Some(axis));
                    let columns = fitter.columns(&fixed, &shape);
                    let profile = LagProfile::new(&fitter, axis, &moving, &columns, &shape);
                    for lag in [
                        -0.2, -0.11, -0.0371, -0.004, 0.0, 0.004, 0.02, 0.0371, 0.13, 0.2,
                    ] {
                        let mut trial = shape;
                        trial.lag[axis] = lag;
                        let reference = refit(data.columns_on(&terms, &trial, &rows), &data, &rows);
                        let fast = profile.rss(lag);
                        assert!(
                            (fast - reference).abs() <= 1e-9 * reference,
                            "exact {exact}, axis {axis}, lag {lag}: {fast} vs {reference} ({shape:?})"
                        );
                    }
                }
            }
        }
    }
}

/// The searches of a spike decay, a cyclic period and a lobe count as they were made before
/// the fits ran on blocks: every trial a refit of the columns over the readings.
fn column_by_column(
    data: &CircleData,
    term: Term,
    fixed: &[Term],
    rows: &[usize],
    shape: &mut Shape,
    refine: bool,
) {
    let rss = |trial: &Shape| {
        let both: Vec<Term> = fixed.iter().chain([&term]).copied().collect();
        refit(data.columns_on(&both, trial, rows), data, rows)
    };
    match term {
        Term::ReversalSpikeP | Term::ReversalSpikeQ => {
            let axis = usize::from(term == Term::ReversalSpikeQ);
            let at = |tau: Real| {
                let mut trial = *shape;
                trial.decay[axis] = tau;
                rss(&trial)
            };
            let (low, high) = (data.ranges.decay.0.ln(), data.ranges.decay.1.ln());
            let grid: Vec<Real> = (0..16)
                .map(|k| low + (high - low) * k as Real / 15.0)
                .collect();
            let values: Vec<Real> = grid.iter().map(|g| at(g.exp())).collect();
            let best = (0..16)
                .min_by(|&a, &b| values[a].total_cmp(&values[b]))
                .unwrap_or(0);
            let (a, b) = (grid[best.saturating_sub(1)], grid[(best + 1).min(15)]);
            let (refined, value) = brent(|g| at(g.exp()), a, b);
            shape.decay[axis] = if value < values[best] {
                refined.exp()
            } else {
                grid[best].exp()
            };
        }
        Term::CyclicP | Term::CyclicQ => {
            let axis = usize::from(term == Term::CyclicQ);
            let grid = data.frequency_grid();
            let peak = if refine {
                1.0 / shape.period[axis]
            } else {
                let y: Vec<Real> = rows.iter().map(|&i| data.deviation[i]).collect();
                let fit = Projection::new(data.columns_on(fixed, shape, rows), &y);
                1.0 / data.cyclic_periodogram(term, rows, &fit.residual).0
            };
            let at = |f: Real| {
                let mut trial = *shape;
                trial.period[axis] = 1.0 / f;
                rss(&trial)
            };
            let (refined, value) = brent(
                at,
                (peak - grid.step).max(grid.low),
                (peak + grid.step).min(grid.high),
            );
            shape.period[axis] = if value < at(peak) {
                1.0 / refined
            } else {
                1.0 / peak
            };
        }
        _ => {
            let (low, high) = if refine {
                (
                    shape.lobes.saturating_sub(2).max(data.ranges.lobes.0),
                    (shape.lobes + 2).min(data.ranges.lobes.1),
                )
            } else {
                data.ranges.lobes
            };
            let mut best = (low, Real::INFINITY);
            for k in low..=high {
                let value = rss(&Shape { lobes: k, ..*shape });
                if value < best.1 {
                    best = (k, value);
                }
            }
            shape.lobes = best.0;
        }
    }
}

#[test]
fn searches_find_what_refits_column_by_column_find() {
    let data = trace(false);
    let (blocks, folds) = folds(&data);
    let linear = [
        Term::Radius,
        Term::CentreP,
        Term::CentreQ,
        Term::BacklashP,
        Term::BacklashQ,
        Term::Squareness,
    ];
    for (included, rows) in folds {
        let fitter = Fitter::new(&data, &blocks, included);
        for shape in shapes() {
            for (term, others) in [
                (Term::ReversalSpikeP, vec![Term::ReversalSpikeQ]),
                (
                    Term::ReversalSpikeQ,
                    vec![Term::ReversalSpikeP, Term::CyclicP],
                ),
                (Term::CyclicP, vec![Term::ReversalSpikeQ]),
                (Term::CyclicQ, vec![Term::CyclicP, Term::Lobes]),
                (Term::Lobes, vec![Term::CyclicP, Term::ReversalSpikeP]),
            ] {
                let fixed: Vec<Term> = linear.iter().chain(&others).copied().collect();
                let columns = fitter.columns(&fixed, &shape);
                for refine in [false, true] {
                    let (mut fast, mut reference) = (shape, shape);
                    fitter.search(term, &columns, &mut fast, refine);
                    column_by_column(&data, term, &fixed, &rows, &mut reference, refine);
                    // The same minimum of the residual sum of squares, to the refinement's
                    // last interval (2.5·10⁻⁵ of two grid steps, a few times that at the
                    // end: 5·10⁻⁵ of a decay in its log grid, 10⁻⁵ of a period).
                    let both: Vec<Term> = fixed.iter().chain([&term]).copied().collect();
                    let at = |s: &Shape| refit(data.columns_on(&both, s, &rows), &data, &rows);
                    let (a, b) = (at(&fast), at(&reference));
                    assert!(
                        (a - b).abs() <= 1e-9 * b,
                        "{term:?} (refine {refine}): {a} vs {b}"
                    );
                    let close =
                        |x: Real, y: Real, tolerance: Real| (x - y).abs() <= tolerance * x.abs();
                    assert!(
                        (0..2).all(|a| close(fast.decay[a], reference.decay[a], 5e-5)
                            && close(fast.period[a], reference.period[a], 1e-5))
                            && fast.lobes == reference.lobes,
                        "{term:?} (refine {refine}): {fast:?} vs {reference:?}"
                    );
                }
            }
        }
    }
}

#[test]
fn the_transformed_periodogram_finds_the_direct_ones_peak() {
    let data = trace(false);
    let (blocks, folds) = folds(&data);
    let fixed = [
        Term::Radius,
        Term::CentreP,
        Term::CentreQ,
        Term::BacklashP,
        Term::ReversalSpikeQ,
        Term::Lobes,
    ];
    let shape = shapes()[1];
    for (included, rows) in folds {
        let fitter = Fitter::new(&data, &blocks, included);
        let columns = fitter.columns(&fixed, &shape);
        let fit = fitter.project(&columns);
        let y: Vec<Real> = rows.iter().map(|&i| data.deviation[i]).collect();
        let residual = Projection::new(data.columns_on(&fixed, &shape, &rows), &y).residual;
        for (axis, term) in [(0, Term::CyclicP), (1, Term::CyclicQ)] {
            let (period, fraction) = data.cyclic_periodogram(term, &rows, &residual);
            let (fast, fast_fraction) =
                fitter.fit_periodogram(axis, &columns, &fit.coefficients, fit.rss);
            assert_eq!(period, fast, "{term:?}");
            assert!((fraction - fast_fraction).abs() <= 1e-9 * fraction);
            let mut everywhere = vec![0.0; data.len()];
            for (&i, r) in rows.iter().zip(&residual) {
                everywhere[i] = *r;
            }
            let (again, again_fraction) = fitter.periodogram(axis, &everywhere);
            assert_eq!(period, again);
            assert!((fraction - again_fraction).abs() <= 1e-9 * fraction);
        }
    }
}

#[test]
fn fits_of_unions_of_blocks_are_the_fits_of_their_readings() {
    let data = trace(false);
    let (blocks, folds) = folds(&data);
    let terms = [
        Term::Radius,
        Term::CentreP,
        Term::CentreQ,
        Term::Squareness,
        Term::BacklashP,
        Term::BacklashQ,
        Term::ReversalSpikeP,
        Term::CyclicP,
    ];
    for (included, rows) in folds {
        let mut train = vec![false; data.len()];
        for &i in &rows {
            train[i] = true;
        }
        assert_eq!(blocks.included(&train), Some(included.clone()));
        let sectors = data.fit_blocks(&blocks, &terms, &included);
        let alone = data.fit(&terms, &train);
        for (a, b) in sectors.residuals.iter().zip(&alone.residuals) {
            assert!((a - b).abs() <= 1e-12, "{a} vs {b}");
        }
        for (a, b) in [
            (sectors.shape.decay[0], alone.shape.decay[0]),
            (sectors.shape.period[0], alone.shape.period[0]),
        ] {
            assert!((a - b).abs() <= 1e-6 * a, "{a} vs {b}");
        }
    }
}

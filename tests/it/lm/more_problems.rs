//! The rest of the Moré–Garbow–Hillstrom problems, and linear and underdetermined problems.

use super::*;

/// MGH (4): f = 0 at (1e6, 2e-6) from (1, 1).
#[test]
fn mgh_brown_badly_scaled() {
    let s = solve_mgh(3, 2, &[1.0, 1.0], |x, f| {
        f[0] = x[0] - 1e6;
        f[1] = x[1] - 2e-6;
        f[2] = x[0] * x[1] - 2.0;
    });
    report("Brown badly scaled", &s);
    assert_ne!(s.termination, Termination::MaxIterations);
    // f1 = x1 − 1e6 can only be resolved to an ulp of 1e6 (1.2e-10): f ≤ a few ulps squared.
    assert!(2.0 * s.cost <= 1e-18, "f = {:e}", 2.0 * s.cost);
    assert!(relative_error(s.x[0], 1e6) <= 1e-12 && relative_error(s.x[1], 2e-6) <= 1e-12);
}

/// MGH (6), m = 10: f = 124.362... at x1 = x2 = 0.2578... from (0.3, 0.4).
#[test]
fn mgh_jennrich_sampson() {
    let s = solve_mgh(10, 2, &[0.3, 0.4], |x, f| {
        for (i, fi) in f.iter_mut().enumerate() {
            let i = (i + 1) as f64;
            *fi = 2.0 + 2.0 * i - ((x[0] * i).exp() + (x[1] * i).exp());
        }
    });
    report("Jennrich-Sampson", &s);
    assert_ne!(s.termination, Termination::MaxIterations);
    assert_published("f", 2.0 * s.cost, 124.362, 1e-3);
    assert_published("x1", s.x[0], 0.2578, 1e-4);
    assert_published("x2", s.x[1], 0.2578, 1e-4);
}

/// MGH (7): f = 0 at (1, 0, 0) from (−1, 0, 0).
#[test]
fn mgh_helical_valley() {
    let s = solve_mgh(3, 3, &[-1.0, 0.0, 0.0], |x, f| {
        let half_turns = if x[0].v < 0.0 { 0.5 } else { 0.0 };
        let theta = (x[1] / x[0]).atan() / (2.0 * std::f64::consts::PI) + half_turns;
        f[0] = (x[2] - theta * 10.0) * 10.0;
        f[1] = ((x[0] * x[0] + x[1] * x[1]).sqrt() - 1.0) * 10.0;
        f[2] = x[2];
    });
    report("Helical valley", &s);
    assert_ne!(s.termination, Termination::MaxIterations);
    assert!(2.0 * s.cost <= 1e-25);
    assert!((s.x[0] - 1.0).abs() <= 1e-12 && s.x[1].abs() <= 1e-12 && s.x[2].abs() <= 1e-12);
}

/// MGH (8): f = 8.21487...e-3 from (1, 1, 1).
#[test]
fn mgh_bard() {
    const Y: [f64; 15] = [
        0.14, 0.18, 0.22, 0.25, 0.29, 0.32, 0.35, 0.39, 0.37, 0.58, 0.73, 0.96, 1.34, 2.10, 4.39,
    ];
    let s = solve_mgh(15, 3, &[1.0, 1.0, 1.0], |x, f| {
        for (i, fi) in f.iter_mut().enumerate() {
            let u = (i + 1) as f64;
            let v = 16.0 - u;
            let w = u.min(v);
            *fi = Y[i] - (x[0] + u / (x[1] * v + x[2] * w));
        }
    });
    report("Bard", &s);
    assert_ne!(s.termination, Termination::MaxIterations);
    assert_published("f", 2.0 * s.cost, 8.21487e-3, 1e-8);
}

/// MGH (12), m = 10: f = 0 at (1, 10, 1), at (10, 1, −1) and wherever x1 = x2 and x3 = 0,
/// from (0, 10, 20).
#[test]
fn mgh_box_3d() {
    let s = solve_mgh(10, 3, &[0.0, 10.0, 20.0], |x, f| {
        for (i, fi) in f.iter_mut().enumerate() {
            let t = 0.1 * (i + 1) as f64;
            *fi =
                (-(x[0] * t)).exp() - (-(x[1] * t)).exp() - x[2] * ((-t).exp() - (-10.0 * t).exp());
        }
    });
    report("Box 3-D", &s);
    assert_ne!(s.termination, Termination::MaxIterations);
    assert!(2.0 * s.cost <= 1e-25);
    let near = |a: [f64; 3]| s.x.iter().zip(a).all(|(x, a)| (x - a).abs() <= 1e-8);
    let on_line = (s.x[0] - s.x[1]).abs() <= 1e-8 && s.x[2].abs() <= 1e-8;
    assert!(
        near([1.0, 10.0, 1.0]) || near([10.0, 1.0, -1.0]) || on_line,
        "{:?}",
        s.x
    );
}

/// MGH (13): f = 0 at the origin from (3, −1, 0, 1). The Jacobian is singular there (rank 2),
/// so convergence is only linear: a rank-deficiency test.
#[test]
fn mgh_powell_singular() {
    let s = solve_mgh(4, 4, &[3.0, -1.0, 0.0, 1.0], |x, f| {
        f[0] = x[0] + x[1] * 10.0;
        f[1] = (x[2] - x[3]) * 5f64.sqrt();
        f[2] = (x[1] - x[2] * 2.0) * (x[1] - x[2] * 2.0);
        f[3] = (x[0] - x[3]) * (x[0] - x[3]) * 10f64.sqrt();
    });
    report("Powell singular", &s);
    assert_ne!(s.termination, Termination::MaxIterations);
    assert!(s.x.iter().all(|v| v.is_finite()));
    assert!(2.0 * s.cost <= 1e-30, "f = {:e}", 2.0 * s.cost);
    assert!(s.x.iter().all(|v| v.abs() <= 1e-7), "{:?}", s.x);
    let sigma = mtwin_kernels::linalg::svd(s.jacobian.clone(), false, false).singular_values;
    let (hi, lo) = (sigma.max(), sigma.min());
    eprintln!("Powell singular: Jacobian singular values at the solution {sigma:?}");
    assert!(
        lo <= 1e-6 * hi,
        "the Jacobian at the solution should be near singular"
    );
}

/// MGH (16), m = 20: f = 85822.2... from (25, 5, −5, 1).
#[test]
fn mgh_brown_dennis() {
    let s = solve_mgh(20, 4, &[25.0, 5.0, -5.0, 1.0], |x, f| {
        for (i, fi) in f.iter_mut().enumerate() {
            let t = (i + 1) as f64 / 5.0;
            let a = x[0] + x[1] * t - t.exp();
            let b = x[2] + x[3] * t.sin() - t.cos();
            *fi = a * a + b * b;
        }
    });
    report("Brown-Dennis", &s);
    assert_ne!(s.termination, Termination::MaxIterations);
    assert_published("f", 2.0 * s.cost, 85822.2, 0.1);
}

/// MGH (17): f = 5.46489...e-5 from (0.5, 1.5, −1, 0.01, 0.02).
#[test]
fn mgh_osborne_1() {
    const Y: [f64; 33] = [
        0.844, 0.908, 0.932, 0.936, 0.925, 0.908, 0.881, 0.850, 0.818, 0.784, 0.751, 0.718, 0.685,
        0.658, 0.628, 0.603, 0.580, 0.558, 0.538, 0.522, 0.506, 0.490, 0.478, 0.467, 0.457, 0.448,
        0.438, 0.431, 0.424, 0.420, 0.414, 0.411, 0.406,
    ];
    let s = solve_mgh(33, 5, &[0.5, 1.5, -1.0, 0.01, 0.02], |x, f| {
        for (i, fi) in f.iter_mut().enumerate() {
            let t = 10.0 * i as f64;
            *fi = Y[i] - (x[0] + x[1] * (-(x[3] * t)).exp() + x[2] * (-(x[4] * t)).exp());
        }
    });
    report("Osborne 1", &s);
    assert_ne!(s.termination, Termination::MaxIterations);
    assert_published("f", 2.0 * s.cost, 5.46489e-5, 1e-10);
}

/// MGH (19): f = 4.01377...e-2 from (1.3, 0.65, 0.65, 0.7, 0.6, 3, 5, 7, 2, 4.5, 5.5).
#[test]
fn mgh_osborne_2() {
    const Y: [f64; 65] = [
        1.366, 1.191, 1.112, 1.013, 0.991, 0.885, 0.831, 0.847, 0.786, 0.725, 0.746, 0.679, 0.608,
        0.655, 0.616, 0.606, 0.602, 0.626, 0.651, 0.724, 0.649, 0.649, 0.694, 0.644, 0.624, 0.661,
        0.612, 0.558, 0.533, 0.495, 0.500, 0.423, 0.395, 0.375, 0.372, 0.391, 0.396, 0.405, 0.428,
        0.429, 0.523, 0.562, 0.607, 0.653, 0.672, 0.708, 0.633, 0.668, 0.645, 0.632, 0.591, 0.559,
        0.597, 0.625, 0.739, 0.710, 0.729, 0.720, 0.636, 0.581, 0.428, 0.292, 0.162, 0.098, 0.054,
    ];
    let x0 = [1.3, 0.65, 0.65, 0.7, 0.6, 3.0, 5.0, 7.0, 2.0, 4.5, 5.5];
    let s = solve_mgh(65, 11, &x0, |x, f| {
        for (i, fi) in f.iter_mut().enumerate() {
            let t = i as f64 / 10.0;
            let bump = |height: Dual, width: Dual, centre: Dual| {
                let d = centre - t;
                height * (-(d * d * width)).exp()
            };
            *fi = Y[i]
                - (x[0] * (-(x[4] * t)).exp()
                    + bump(x[1], x[5], x[8])
                    + bump(x[2], x[6], x[9])
                    + bump(x[3], x[7], x[10]));
        }
    });
    report("Osborne 2", &s);
    assert_ne!(s.termination, Termination::MaxIterations);
    assert_published("f", 2.0 * s.cost, 4.01377e-2, 1e-7);
}

// ---------------------------------------------------------------------------------------------
// Linear least squares: LM must land on the ordinary least-squares solution.

/// A straight line y = a + b t through 12 points with a deterministic scatter.
fn line_data() -> (Vec<f64>, Vec<f64>) {
    let t: Vec<f64> = (0..12).map(|i| 0.5 * i as f64 - 1.0).collect();
    let y = t
        .iter()
        .enumerate()
        .map(|(i, &ti)| 2.0 - 0.75 * ti + 0.01 * (((7 * i) % 5) as f64 - 2.0))
        .collect();
    (t, y)
}

/// Intercept, slope and residual sum of squares by the textbook formulas
/// b = Σ(t − t̄)(y − ȳ) / Σ(t − t̄)², a = ȳ − b t̄.
fn line_closed_form(t: &[f64], y: &[f64]) -> (f64, f64, f64) {
    let n = t.len() as f64;
    let (tm, ym) = (t.iter().sum::<f64>() / n, y.iter().sum::<f64>() / n);
    let sty: f64 = t.iter().zip(y).map(|(ti, yi)| (ti - tm) * (yi - ym)).sum();
    let stt: f64 = t.iter().map(|ti| (ti - tm).powi(2)).sum();
    let b = sty / stt;
    let a = ym - b * tm;
    let rss = t
        .iter()
        .zip(y)
        .map(|(ti, yi)| (yi - a - b * ti).powi(2))
        .sum();
    (a, b, rss)
}

/// Residuals r = X x − y for a design X given by its columns' functions of t; the Jacobian is
/// X, written out (or the default forward differences when `analytic` is false).
struct Linear {
    t: Vec<f64>,
    y: Vec<f64>,
    columns: Vec<fn(f64) -> f64>,
    analytic: bool,
}

impl Problem for Linear {
    fn residual_count(&self) -> usize {
        self.t.len()
    }
    fn parameter_count(&self) -> usize {
        self.columns.len()
    }
    fn residuals(&self, x: &[f64], out: &mut [f64]) {
        for (i, o) in out.iter_mut().enumerate() {
            let model: f64 = self
                .columns
                .iter()
                .zip(x)
                .map(|(f, xj)| f(self.t[i]) * xj)
                .sum();
            *o = model - self.y[i];
        }
    }
    fn jacobian(&self, x: &[f64], out: &mut DMatrix<f64>) {
        if !self.analytic {
            mtwin::estimate::lm::forward_difference_jacobian(self, x, out);
            return;
        }
        for i in 0..self.t.len() {
            for (j, f) in self.columns.iter().enumerate() {
                out[(i, j)] = f(self.t[i]);
            }
        }
    }
}

#[test]
fn linear_straight_line_is_the_least_squares_fit() {
    let (t, y) = line_data();
    let (a, b, rss) = line_closed_form(&t, &y);
    let problem = Linear {
        t,
        y,
        columns: vec![|_| 1.0, |t| t],
        analytic: true,
    };
    let s = solve(&problem, &[0.0, 0.0], &Options::default()).unwrap();
    report("straight line", &s);
    assert_ne!(s.termination, Termination::MaxIterations);
    assert!(relative_error(s.x[0], a) <= 1e-12, "a = {} vs {a}", s.x[0]);
    assert!(relative_error(s.x[1], b) <= 1e-12, "b = {} vs {b}", s.x[1]);
    assert!(
        relative_error(2.0 * s.cost, rss) <= 1e-10,
        "RSS {} vs {rss}",
        2.0 * s.cost
    );
    // From x₀ = 0 the first trust radius is `initial_damping` = 100, which holds the
    // Gauss–Newton step, exact for a linear problem.
    assert!(s.iterations <= 2, "{} iterations", s.iterations);
}

/// The default Jacobian (forward differences, from x₀ = 0 where the step falls back to
/// √ε): J is exact to ~1e-8 relative, which moves the solution of Jᵀr = 0 by about that much.
#[test]
fn linear_straight_line_with_the_default_jacobian() {
    let (t, y) = line_data();
    let (a, b, rss) = line_closed_form(&t, &y);
    let problem = Linear {
        t,
        y,
        columns: vec![|_| 1.0, |t| t],
        analytic: false,
    };
    let s = solve(&problem, &[0.0, 0.0], &Options::default()).unwrap();
    report("straight line, forward differences", &s);
    assert!(
        relative_error(s.x[0], a) <= 1e-6 && relative_error(s.x[1], b) <= 1e-6,
        "{:?}",
        s.x
    );
    assert!(relative_error(2.0 * s.cost, rss) <= 1e-8);
}

/// Columns 1, t, 2t and 0: the slope is split between two aliased parameters and the last
/// parameter has no effect (rank 2 of 4). The step stays finite, the fit is the straight-line
/// fit, the identifiable combination b + 2c is its slope, and the directions J cannot see do
/// not move from the start (the rank cut of the SVD): in the scaled coordinates D x, with
/// D = (‖1‖, ‖t‖, 2‖t‖, 1), the null direction of (b, c) is (1, −1), so ‖t‖ b = 2 ‖t‖ c.
#[test]
fn linear_rank_deficient_reaches_the_least_squares_minimum() {
    let (t, y) = line_data();
    let (a, slope, rss) = line_closed_form(&t, &y);
    let problem = Linear {
        t,
        y,
        columns: vec![|_| 1.0, |t| t, |t| 2.0 * t, |_| 0.0],
        analytic: true,
    };
    let x0 = [0.0, 0.0, 0.0, 0.5];
    let s = solve(&problem, &x0, &Options::default()).unwrap();
    report("rank-deficient line", &s);
    assert_ne!(s.termination, Termination::MaxIterations);
    assert!(s.x.iter().all(|v| v.is_finite()));
    assert!(
        relative_error(2.0 * s.cost, rss) <= 1e-10,
        "RSS {} vs {rss}",
        2.0 * s.cost
    );
    assert!(relative_error(s.x[0], a) <= 1e-12, "a = {} vs {a}", s.x[0]);
    assert!(
        relative_error(s.x[1] + 2.0 * s.x[2], slope) <= 1e-12,
        "{:?}",
        s.x
    );
    assert!(
        relative_error(s.x[1], 2.0 * s.x[2]) <= 1e-12,
        "null direction moved: {:?}",
        s.x
    );
    assert_eq!(
        s.x[3], 0.5,
        "a parameter with no effect stays where it started"
    );
}

/// Fewer residuals than parameters (m = 1, n = 2): the residual x1 + x2 − 3 reaches zero.
#[test]
fn underdetermined_problem_reaches_zero_residual() {
    struct Sum;
    impl Problem for Sum {
        fn residual_count(&self) -> usize {
            1
        }
        fn parameter_count(&self) -> usize {
            2
        }
        fn residuals(&self, x: &[f64], out: &mut [f64]) {
            out[0] = x[0] + x[1] - 3.0;
        }
    }
    let s = solve(&Sum, &[1.0, -1.0], &Options::default()).unwrap();
    report("underdetermined", &s);
    assert!(
        s.cost <= 1e-28 && (s.x[0] + s.x[1] - 3.0).abs() <= 1e-14,
        "{:?}",
        s.x
    );
}

/// r = ln x − 1 from x = 10: the first Gauss–Newton step goes to x < 0, where r is NaN; the
/// solver rejects it, shrinks the trust region and still reaches x = e.
#[test]
fn non_finite_trial_points_are_rejected() {
    struct Log;
    impl Problem for Log {
        fn residual_count(&self) -> usize {
            1
        }
        fn parameter_count(&self) -> usize {
            1
        }
        fn residuals(&self, x: &[f64], out: &mut [f64]) {
            out[0] = x[0].ln() - 1.0;
        }
        fn jacobian(&self, x: &[f64], out: &mut DMatrix<f64>) {
            out[(0, 0)] = 1.0 / x[0];
        }
    }
    let s = solve(&Log, &[10.0], &Options::default()).unwrap();
    report("log", &s);
    assert!((s.x[0] - std::f64::consts::E).abs() <= 1e-14, "{:?}", s.x);
}

#[test]
fn bad_inputs_are_errors_with_messages() {
    let (t, y) = line_data();
    let problem = Linear {
        t,
        y,
        columns: vec![|_| 1.0, |t| t],
        analytic: true,
    };
    let options = Options::default();

    let e = solve(&problem, &[0.0], &options).unwrap_err();
    assert_eq!(
        e,
        LmError::DimensionMismatch {
            expected: 2,
            found: 1
        }
    );
    assert!(
        e.to_string().contains("1 values") && e.to_string().contains("2 parameters"),
        "{e}"
    );

    let e = solve(&problem, &[0.0, f64::NAN], &options).unwrap_err();
    assert!(matches!(e, LmError::NonFiniteStart { index: 1, .. }), "{e}");

    let bad = Options {
        ftol: -1.0,
        ..Options::default()
    };
    let e = solve(&problem, &[0.0, 0.0], &bad).unwrap_err();
    assert!(
        matches!(e, LmError::InvalidOption { name: "ftol", .. }),
        "{e}"
    );
    assert!(e.to_string().contains("ftol"), "{e}");

    struct NanAtStart;
    impl Problem for NanAtStart {
        fn residual_count(&self) -> usize {
            2
        }
        fn parameter_count(&self) -> usize {
            1
        }
        fn residuals(&self, x: &[f64], out: &mut [f64]) {
            out[0] = x[0];
            out[1] = (x[0] - 1.0).sqrt();
        }
    }
    let e = solve(&NanAtStart, &[0.0], &options).unwrap_err();
    assert!(
        matches!(e, LmError::NonFiniteResiduals { index: 1, .. }),
        "{e}"
    );
    assert!(e.to_string().contains("residual 1"), "{e}");
}

/// Same problem, same start: bit-identical results.
#[test]
fn solve_is_deterministic() {
    let file = read_nist("Thurber");
    let data = file.data.clone();
    let problem = AutoDiff {
        m: file.observations,
        n: 7,
        analytic: true,
        f: move |b: &[Dual], out: &mut [Dual]| {
            for (o, row) in out.iter_mut().zip(&data) {
                *o = nist_model("Thurber", b, &row[1..]) - row[0];
            }
        },
    };
    let a = solve(&problem, &file.start[0], &Options::default()).unwrap();
    let b = solve(&problem, &file.start[0], &Options::default()).unwrap();
    assert_eq!(a.x, b.x);
    assert_eq!(a.residuals, b.residuals);
    assert_eq!(a.iterations, b.iterations);
}

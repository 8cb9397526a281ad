//! The Levenberg–Marquardt solver (`estimate::lm`) against independent published values:
//!
//! 1. NIST StRD nonlinear regression: data, starting values and certified values (parameters,
//!    their standard deviations, residual sum of squares) are read from the NIST files in
//!    `tests/data/nist/`, stored verbatim as NIST publishes them.
//! 2. Moré, Garbow & Hillstrom (1981), "Testing unconstrained optimization software",
//!    ACM TOMS 7(1) 17–41: the minima the paper lists (its f is the sum of squares, 2 × cost).
//! 3. Linear least squares against the textbook closed form, full rank and rank-deficient.
//!
//! All runs use `Options::default()`: nothing is tuned per problem.

use mtwin::estimate::lm::{LmError, Options, Problem, Solution, Termination, solve};
use nalgebra::DMatrix;
use std::ops::{Add, Div, Mul, Neg, Sub};

// ---------------------------------------------------------------------------------------------
// Forward-mode automatic differentiation: exact Jacobians for the test problems, written once
// as a model over `Dual`. The value part of every operation is the plain f64 operation, so the
// residuals are the f64 model's.

const MAX_PARAMETERS: usize = 11;

#[derive(Clone, Copy, Debug)]
struct Dual {
    v: f64,
    d: [f64; MAX_PARAMETERS],
}

impl Dual {
    fn c(v: f64) -> Self {
        Dual {
            v,
            d: [0.0; MAX_PARAMETERS],
        }
    }
    fn variable(v: f64, j: usize) -> Self {
        let mut d = [0.0; MAX_PARAMETERS];
        d[j] = 1.0;
        Dual { v, d }
    }
    /// f(self) with f'(self) = `slope`.
    fn chain(self, v: f64, slope: f64) -> Self {
        Dual {
            v,
            d: self.d.map(|di| slope * di),
        }
    }
    fn exp(self) -> Self {
        let e = self.v.exp();
        self.chain(e, e)
    }
    fn ln(self) -> Self {
        self.chain(self.v.ln(), 1.0 / self.v)
    }
    fn powf(self, p: f64) -> Self {
        self.chain(self.v.powf(p), p * self.v.powf(p - 1.0))
    }
    fn sqrt(self) -> Self {
        let s = self.v.sqrt();
        self.chain(s, 0.5 / s)
    }
    fn sin(self) -> Self {
        self.chain(self.v.sin(), self.v.cos())
    }
    fn cos(self) -> Self {
        self.chain(self.v.cos(), -self.v.sin())
    }
    fn atan(self) -> Self {
        self.chain(self.v.atan(), 1.0 / (1.0 + self.v * self.v))
    }
    /// The angle of the point (x, self), in (−π, π].
    fn atan2(self, x: Dual) -> Self {
        let r2 = x.v * x.v + self.v * self.v;
        Dual {
            v: self.v.atan2(x.v),
            d: std::array::from_fn(|k| (x.v * self.d[k] - self.v * x.d[k]) / r2),
        }
    }
}

impl Add for Dual {
    type Output = Dual;
    fn add(self, o: Dual) -> Dual {
        let mut d = self.d;
        d.iter_mut().zip(o.d).for_each(|(a, b)| *a += b);
        Dual { v: self.v + o.v, d }
    }
}
impl Sub for Dual {
    type Output = Dual;
    fn sub(self, o: Dual) -> Dual {
        let mut d = self.d;
        d.iter_mut().zip(o.d).for_each(|(a, b)| *a -= b);
        Dual { v: self.v - o.v, d }
    }
}
impl Mul for Dual {
    type Output = Dual;
    fn mul(self, o: Dual) -> Dual {
        let mut d = [0.0; MAX_PARAMETERS];
        for (k, dk) in d.iter_mut().enumerate() {
            *dk = self.d[k] * o.v + self.v * o.d[k];
        }
        Dual { v: self.v * o.v, d }
    }
}
impl Div for Dual {
    type Output = Dual;
    fn div(self, o: Dual) -> Dual {
        let mut d = [0.0; MAX_PARAMETERS];
        for (k, dk) in d.iter_mut().enumerate() {
            *dk = (self.d[k] * o.v - self.v * o.d[k]) / (o.v * o.v);
        }
        Dual { v: self.v / o.v, d }
    }
}
impl Neg for Dual {
    type Output = Dual;
    fn neg(self) -> Dual {
        Dual {
            v: -self.v,
            d: self.d.map(|x| -x),
        }
    }
}
impl Add<f64> for Dual {
    type Output = Dual;
    fn add(self, o: f64) -> Dual {
        Dual {
            v: self.v + o,
            d: self.d,
        }
    }
}
impl Sub<f64> for Dual {
    type Output = Dual;
    fn sub(self, o: f64) -> Dual {
        Dual {
            v: self.v - o,
            d: self.d,
        }
    }
}
impl Mul<f64> for Dual {
    type Output = Dual;
    fn mul(self, o: f64) -> Dual {
        Dual {
            v: self.v * o,
            d: self.d.map(|x| x * o),
        }
    }
}
impl Div<f64> for Dual {
    type Output = Dual;
    fn div(self, o: f64) -> Dual {
        Dual {
            v: self.v / o,
            d: self.d.map(|x| x / o),
        }
    }
}
impl Add<Dual> for f64 {
    type Output = Dual;
    fn add(self, o: Dual) -> Dual {
        o + self
    }
}
impl Sub<Dual> for f64 {
    type Output = Dual;
    fn sub(self, o: Dual) -> Dual {
        -o + self
    }
}
impl Mul<Dual> for f64 {
    type Output = Dual;
    fn mul(self, o: Dual) -> Dual {
        o * self
    }
}
impl Div<Dual> for f64 {
    type Output = Dual;
    fn div(self, o: Dual) -> Dual {
        Dual::c(self) / o
    }
}

/// A least-squares problem given by its residual function over `Dual`s; the Jacobian is either
/// exact (forward-mode AD) or the solver's default forward differences.
struct AutoDiff<F: Fn(&[Dual], &mut [Dual])> {
    m: usize,
    n: usize,
    f: F,
    analytic: bool,
}

impl<F: Fn(&[Dual], &mut [Dual])> AutoDiff<F> {
    fn eval(&self, x: &[f64], seed: bool) -> Vec<Dual> {
        let xd: Vec<Dual> = x
            .iter()
            .enumerate()
            .map(|(j, &v)| {
                if seed {
                    Dual::variable(v, j)
                } else {
                    Dual::c(v)
                }
            })
            .collect();
        let mut out = vec![Dual::c(0.0); self.m];
        (self.f)(&xd, &mut out);
        out
    }
}

impl<F: Fn(&[Dual], &mut [Dual])> Problem for AutoDiff<F> {
    fn residual_count(&self) -> usize {
        self.m
    }
    fn parameter_count(&self) -> usize {
        self.n
    }
    fn residuals(&self, x: &[f64], out: &mut [f64]) {
        for (o, r) in out.iter_mut().zip(self.eval(x, false)) {
            *o = r.v;
        }
    }
    fn jacobian(&self, x: &[f64], out: &mut DMatrix<f64>) {
        if !self.analytic {
            mtwin::estimate::lm::forward_difference_jacobian(self, x, out);
            return;
        }
        for (i, r) in self.eval(x, true).iter().enumerate() {
            for j in 0..self.n {
                out[(i, j)] = r.d[j];
            }
        }
    }
}

fn relative_error(value: f64, reference: f64) -> f64 {
    if reference == 0.0 {
        value.abs()
    } else {
        ((value - reference) / reference).abs()
    }
}

// ---------------------------------------------------------------------------------------------
// NIST StRD nonlinear regression.

/// One NIST StRD file: starting values, certified values and data, as published.
struct NistFile {
    start: [Vec<f64>; 2],
    certified: Vec<f64>,
    certified_sd: Vec<f64>,
    certified_rss: f64,
    observations: usize,
    /// Each row: the response, then the predictors.
    data: Vec<Vec<f64>>,
}

fn parse_number(token: &str, file: &str, line: usize) -> f64 {
    token
        .parse()
        .unwrap_or_else(|e| panic!("{file}, line {line}: {token:?} is not a number ({e})"))
}

fn read_nist(name: &str) -> NistFile {
    let path = format!("{}/tests/data/nist/{name}.dat", env!("CARGO_MANIFEST_DIR"));
    let text = std::fs::read_to_string(&path).unwrap_or_else(|e| panic!("{path}: {e}"));
    let lines: Vec<&str> = text.lines().map(str::trim_end).collect();
    let number_after = |label: &str| -> (f64, usize) {
        let (at, line) = lines
            .iter()
            .enumerate()
            .find(|(_, l)| l.trim_start().starts_with(label))
            .unwrap_or_else(|| panic!("{path}: no line starting with {label:?}"));
        let token = line.split_whitespace().last().unwrap();
        (parse_number(token, &path, at + 1), at + 1)
    };
    // "Data              (lines 61 to 74)" in the header: 1-based, inclusive.
    let data_lines = lines
        .iter()
        .find(|l| l.trim_start().starts_with("Data") && l.contains("(lines"))
        .unwrap_or_else(|| panic!("{path}: no data line range in the header"));
    let range: Vec<usize> = data_lines
        .split(|c: char| !c.is_ascii_digit())
        .filter(|s| !s.is_empty())
        .map(|s| s.parse().unwrap())
        .collect();
    let (first, last) = (range[0], range[1]);

    let (mut start1, mut start2, mut certified, mut certified_sd) =
        (vec![], vec![], vec![], vec![]);
    for (at, line) in lines.iter().enumerate() {
        let t = line.trim_start();
        let is_parameter = t.starts_with('b')
            && t[1..]
                .trim_start_matches(|c: char| c.is_ascii_digit())
                .trim_start()
                .starts_with('=');
        if !is_parameter {
            continue;
        }
        let values: Vec<f64> = t
            .split('=')
            .nth(1)
            .unwrap()
            .split_whitespace()
            .map(|tok| parse_number(tok, &path, at + 1))
            .collect();
        assert_eq!(
            values.len(),
            4,
            "{path}, line {}: expected 4 values",
            at + 1
        );
        start1.push(values[0]);
        start2.push(values[1]);
        certified.push(values[2]);
        certified_sd.push(values[3]);
    }
    let data: Vec<Vec<f64>> = lines[first - 1..last]
        .iter()
        .enumerate()
        .map(|(k, l)| {
            l.split_whitespace()
                .map(|tok| parse_number(tok, &path, first + k))
                .collect()
        })
        .collect();
    let printed: String = text.split_whitespace().collect();
    assert!(
        printed.contains(printed_model(name)),
        "{path}: the model is not {}",
        printed_model(name)
    );
    let (observations, _) = number_after("Number of Observations:");
    assert_eq!(
        data.len(),
        observations as usize,
        "{path}: observation count"
    );
    NistFile {
        start: [start1, start2],
        certified,
        certified_sd,
        certified_rss: number_after("Residual Sum of Squares:").0,
        observations: observations as usize,
        data,
    }
}

/// The model as each file prints it (whitespace removed); [`read_nist`] checks that the file
/// says this, so that [`nist_model`] is the model the certified values belong to.
fn printed_model(name: &str) -> &'static str {
    match name {
        "Misra1a" | "BoxBOD" => "y=b1*(1-exp[-b2*x])+e",
        "Misra1b" => "y=b1*(1-(1+b2*x/2)**(-2))+e",
        "Misra1c" => "y=b1*(1-(1+2*b2*x)**(-.5))+e",
        "Misra1d" => "y=b1*b2*x*((1+b2*x)**(-1))+e",
        "Chwirut1" => "y=exp[-b1*x]/(b2+b3*x)+e",
        "Chwirut2" => "y=exp(-b1*x)/(b2+b3*x)+e",
        "DanWood" => "y=b1*x**b2+e",
        "Lanczos1" | "Lanczos2" | "Lanczos3" => "y=b1*exp(-b2*x)+b3*exp(-b4*x)+b5*exp(-b6*x)+e",
        "Gauss1" | "Gauss2" | "Gauss3" => {
            "y=b1*exp(-b2*x)+b3*exp(-(x-b4)**2/b5**2)+b6*exp(-(x-b7)**2/b8**2)+e"
        }
        "Kirby2" => "y=(b1+b2*x+b3*x**2)/(1+b4*x+b5*x**2)+e",
        "Hahn1" | "Thurber" => "y=(b1+b2*x+b3*x**2+b4*x**3)/(1+b5*x+b6*x**2+b7*x**3)+e",
        "Nelson" => "log[y]=b1-b2*x1*exp[-b3*x2]+e",
        "MGH17" => "y=b1+b2*exp[-x*b4]+b3*exp[-x*b5]+e",
        "Roszman1" => "y=b1-b2*x-arctan[b3/(x-b4)]/pi+e",
        "ENSO" => {
            "y=b1+b2*cos(2*pi*x/12)+b3*sin(2*pi*x/12)+b5*cos(2*pi*x/b4)+b6*sin(2*pi*x/b4)\
             +b8*cos(2*pi*x/b7)+b9*sin(2*pi*x/b7)+e"
        }
        "MGH09" => "y=b1*(x**2+x*b2)/(x**2+x*b3+b4)+e",
        "MGH10" => "y=b1*exp[b2/(x+b3)]+e",
        "Eckerle4" => "y=(b1/b2)*exp[-0.5*((x-b3)/b2)**2]+e",
        "Rat42" => "y=b1/(1+exp[b2-b3*x])+e",
        "Rat43" => "y=b1/((1+exp[b2-b3*x])**(1/b4))+e",
        "Bennett5" => "y=b1*(b2+x)**(-1/b3)+e",
        _ => panic!("no model for {name}"),
    }
}

/// The NIST model ([`printed_model`]): prediction for parameters `b` at the predictors `x`
/// (Nelson's response is log y, see [`nist_response`]).
fn nist_model(name: &str, b: &[Dual], x: &[f64]) -> Dual {
    use std::f64::consts::PI;
    let x0 = x[0];
    match name {
        "Misra1a" | "BoxBOD" => b[0] * (1.0 - (-(b[1] * x0)).exp()),
        "Misra1b" => b[0] * (1.0 - (1.0 + b[1] * x0 / 2.0).powf(-2.0)),
        "Misra1c" => b[0] * (1.0 - (1.0 + 2.0 * b[1] * x0).powf(-0.5)),
        "Misra1d" => b[0] * b[1] * x0 * (1.0 + b[1] * x0).powf(-1.0),
        "Chwirut1" | "Chwirut2" => (-(b[0] * x0)).exp() / (b[1] + b[2] * x0),
        "DanWood" => b[0] * (b[1] * x0.ln()).exp(),
        "Lanczos1" | "Lanczos2" | "Lanczos3" => {
            b[0] * (-(b[1] * x0)).exp() + b[2] * (-(b[3] * x0)).exp() + b[4] * (-(b[5] * x0)).exp()
        }
        "Gauss1" | "Gauss2" | "Gauss3" => {
            let g1 = (b[3] - x0) / b[4];
            let g2 = (b[6] - x0) / b[7];
            b[0] * (-(b[1] * x0)).exp() + b[2] * (-(g1 * g1)).exp() + b[5] * (-(g2 * g2)).exp()
        }
        "Kirby2" => (b[0] + b[1] * x0 + b[2] * (x0 * x0)) / (1.0 + b[3] * x0 + b[4] * (x0 * x0)),
        "Hahn1" | "Thurber" => {
            (b[0] + b[1] * x0 + b[2] * x0.powi(2) + b[3] * x0.powi(3))
                / (1.0 + b[4] * x0 + b[5] * x0.powi(2) + b[6] * x0.powi(3))
        }
        "Nelson" => b[0] - b[1] * x0 * (-(b[2] * x[1])).exp(),
        "MGH17" => b[0] + b[1] * (-(b[3] * x0)).exp() + b[2] * (-(b[4] * x0)).exp(),
        // NIST prints arctan[b3/(x-b4)]; its certified values are those of the two-argument
        // arctangent atan2(b3, x − b4), in (0, π) here (b3 > 0, x − b4 < 0), which is π more
        // than the principal arctan. The principal branch fits the data equally well (same
        // RSS and b2, b3, b4) with b1 smaller by exactly 1. Ceres's examples/nist.cc does the same.
        "Roszman1" => b[0] - b[1] * x0 - b[2].atan2(x0 - b[3]) / PI,
        "ENSO" => {
            let w = 2.0 * PI * x0;
            b[0] + b[1] * (w / 12.0).cos()
                + b[2] * (w / 12.0).sin()
                + b[4] * (w / b[3]).cos()
                + b[5] * (w / b[3]).sin()
                + b[7] * (w / b[6]).cos()
                + b[8] * (w / b[6]).sin()
        }
        "MGH09" => b[0] * (x0 * x0 + x0 * b[1]) / (x0 * x0 + x0 * b[2] + b[3]),
        "MGH10" => b[0] * (b[1] / (b[2] + x0)).exp(),
        "Eckerle4" => {
            let u = (b[2] - x0) / b[1];
            (b[0] / b[1]) * (-0.5 * (u * u)).exp()
        }
        "Rat42" => b[0] / (1.0 + (b[1] - b[2] * x0).exp()),
        "Rat43" => b[0] / (((1.0 + (b[1] - b[2] * x0).exp()).ln() / b[3]).exp()),
        "Bennett5" => b[0] * (-((b[1] + x0).ln() / b[2])).exp(),
        _ => panic!("no model for {name}"),
    }
}

fn nist_response(name: &str, y: f64) -> f64 {
    if name == "Nelson" { y.ln() } else { y }
}

struct NistRun {
    name: &'static str,
    start: usize,
    analytic: bool,
    solution: Solution,
    max_parameter_error: f64,
    rss_error: f64,
    max_sd_error: f64,
}

/// Standard deviations of the parameters from the Jacobian at the solution,
/// s² = RSS / (m − n), cov = s² (JᵀJ)⁻¹ (through the SVD of J: (JᵀJ)⁻¹ = V Σ⁻² Vᵀ).
fn standard_deviations(jacobian: &DMatrix<f64>, rss: f64) -> Vec<f64> {
    let (m, n) = jacobian.shape();
    let s2 = rss / (m - n) as f64;
    let svd = mtwin_kernels::linalg::svd_unordered(jacobian.clone(), false, true);
    let v_t = svd.v_t.unwrap();
    (0..n)
        .map(|j| {
            let var: f64 = (0..n)
                .map(|k| (v_t[(k, j)] / svd.singular_values[k]).powi(2))
                .sum();
            (s2 * var).sqrt()
        })
        .collect()
}

fn run_nist(name: &'static str, start: usize, analytic: bool) -> NistRun {
    let file = read_nist(name);
    let n = file.certified.len();
    let m = file.observations;
    let data = file.data.clone();
    let problem = AutoDiff {
        m,
        n,
        analytic,
        f: move |b: &[Dual], out: &mut [Dual]| {
            for (o, row) in out.iter_mut().zip(&data) {
                *o = nist_model(name, b, &row[1..]) - nist_response(name, row[0]);
            }
        },
    };
    let solution = solve(&problem, &file.start[start - 1], &Options::default())
        .unwrap_or_else(|e| panic!("{name} start {start}: {e}"));
    let max_parameter_error = solution
        .x
        .iter()
        .zip(&file.certified)
        .map(|(&x, &c)| relative_error(x, c))
        .fold(0.0, f64::max);
    let rss = 2.0 * solution.cost;
    let rss_error = relative_error(rss, file.certified_rss);
    let sd = standard_deviations(&solution.jacobian, rss);
    let max_sd_error = sd
        .iter()
        .zip(&file.certified_sd)
        .map(|(&s, &c)| relative_error(s, c))
        .fold(0.0, f64::max);
    let run = NistRun {
        name,
        start,
        analytic,
        solution,
        max_parameter_error,
        rss_error,
        max_sd_error,
    };
    eprintln!(
        "{:<9} start {} {:<8} iterations {:>4} evaluations {:>4} {:?}: max rel. error of parameters {:.1e}, RSS {:.1e} (RSS {:.10e}, certified {:.10e}), standard deviations {:.1e}",
        run.name,
        run.start,
        if run.analytic { "exact J" } else { "FD J" },
        run.solution.iterations,
        run.solution.evaluations,
        run.solution.termination,
        run.max_parameter_error,
        run.rss_error,
        rss,
        file.certified_rss,
        run.max_sd_error,
    );
    run
}

/// Agreement required with NIST's certified values, as relative errors.
struct Tolerances {
    parameters: f64,
    rss: f64,
    standard_deviations: f64,
}

/// With exact Jacobians. NIST certifies 11 significant digits and considers 4 to 6 of them the
/// mark of a good double-precision solver on the harder problems (Ceres's examples/nist.cc
/// counts a run as solved at 4 digits); we ask for 6 on every problem: parameters within 1e-6.
/// The RSS is stationary at the minimum, so its error is second order in the parameters' and
/// limited by the 11 certified digits: 1e-9. The standard deviations (s² (JᵀJ)⁻¹ from the
/// returned Jacobian) are first order in the parameters' error: 1e-6.
const EXACT: Tolerances = Tolerances {
    parameters: 1e-6,
    rss: 1e-9,
    standard_deviations: 1e-6,
};

/// With the default forward-difference Jacobian: about 8 correct digits in J, and the error
/// moves the stationary point (Jᵀr = 0 with the wrong J) in proportion to the residual and to
/// the conditioning. NIST's lower mark of 4 digits for the parameters, 1e-8 for the RSS, and 3
/// digits for the standard deviations, where the Jacobian's error enters through (JᵀJ)⁻¹.
const FORWARD_DIFFERENCES: Tolerances = Tolerances {
    parameters: 1e-4,
    rss: 1e-8,
    standard_deviations: 1e-3,
};

/// Lanczos1's data are generated, with a certified RSS of 1.43e-25: residuals of about 8e-14,
/// only ~150 ulps of y (up to 2.5). Evaluating the model in f64 (three exponentials, a few
/// ulps each) changes each residual by ~1e-15, about 1 % of itself, so the RSS and the standard
/// deviations (∝ √RSS) can only be compared to 1e-2 on that problem; its parameters are held to
/// the common tolerances.
const LANCZOS1_ROUNDING: f64 = 1e-2;

/// Runs both NIST starts with exact and with forward-difference Jacobians, `Options::default()`
/// throughout; `converges[s]` says whether start s + 1 must reach the certified values. A
/// `false` is a recorded failure of this solver (the run stops elsewhere); it is printed, not
/// asserted, so that an improvement does not break the test.
fn check_nist(name: &'static str, converges: [bool; 2]) {
    for (start, must_converge) in [(1, converges[0]), (2, converges[1])] {
        for (analytic, tol) in [(true, EXACT), (false, FORWARD_DIFFERENCES)] {
            let run = run_nist(name, start, analytic);
            let (rss_tol, sd_tol) = if name == "Lanczos1" {
                (LANCZOS1_ROUNDING, LANCZOS1_ROUNDING)
            } else {
                (tol.rss, tol.standard_deviations)
            };
            let ok = run.solution.termination != Termination::MaxIterations
                && run.max_parameter_error <= tol.parameters
                && run.rss_error <= rss_tol
                && run.max_sd_error <= sd_tol;
            let jacobian = if analytic {
                "exact J"
            } else {
                "forward differences"
            };
            if must_converge {
                assert!(
                    ok,
                    "{name} start {start} ({jacobian}): parameters {:.1e}, RSS {:.1e}, \
                     standard deviations {:.1e}, {:?}",
                    run.max_parameter_error,
                    run.rss_error,
                    run.max_sd_error,
                    run.solution.termination
                );
            } else if ok {
                eprintln!("{name} start {start} ({jacobian}) now converges: update the test");
            }
        }
    }
}

macro_rules! nist_test {
    ($test:ident, $name:literal, converges: $converges:expr) => {
        #[test]
        fn $test() {
            check_nist($name, $converges);
        }
    };
}

// Lower difficulty.
nist_test!(nist_misra1a, "Misra1a", converges: [true, true]);
nist_test!(nist_chwirut2, "Chwirut2", converges: [true, true]);
nist_test!(nist_chwirut1, "Chwirut1", converges: [true, true]);
nist_test!(nist_lanczos3, "Lanczos3", converges: [true, true]);
nist_test!(nist_gauss1, "Gauss1", converges: [true, true]);
nist_test!(nist_gauss2, "Gauss2", converges: [true, true]);
nist_test!(nist_danwood, "DanWood", converges: [true, true]);
nist_test!(nist_misra1b, "Misra1b", converges: [true, true]);
// Average difficulty.
nist_test!(nist_kirby2, "Kirby2", converges: [true, true]);
nist_test!(nist_hahn1, "Hahn1", converges: [true, true]);
nist_test!(nist_nelson, "Nelson", converges: [true, true]);
nist_test!(nist_mgh17, "MGH17", converges: [true, true]);
nist_test!(nist_lanczos1, "Lanczos1", converges: [true, true]);
nist_test!(nist_lanczos2, "Lanczos2", converges: [true, true]);
nist_test!(nist_gauss3, "Gauss3", converges: [true, true]);
nist_test!(nist_misra1c, "Misra1c", converges: [true, true]);
nist_test!(nist_misra1d, "Misra1d", converges: [true, true]);
nist_test!(nist_roszman1, "Roszman1", converges: [true, true]);
nist_test!(nist_enso, "ENSO", converges: [true, true]);
// Higher difficulty.
nist_test!(nist_mgh09, "MGH09", converges: [true, true]);
nist_test!(nist_thurber, "Thurber", converges: [true, true]);
// Start 1 (b1 = b2 = 1) fails, with both Jacobians: within three steps the iterates reach
// b2 ≈ 111, where exp(−b2 x) ≈ 0 for every x ≥ 1, so the model is the constant b1 = mean(y) =
// 172.5 (RSS 9771.5, against the certified 1168.0) and the b2 column of J is ~1e-48: an
// asymptotic plateau with no gradient towards the minimum, left with SmallCostChange (exact J)
// or SmallGradient (forward differences). With initial_damping = 1 instead of MINPACK's 100 the
// first steps are shorter and start 1 converges, but the defaults are not tuned per problem.
nist_test!(nist_boxbod, "BoxBOD", converges: [false, true]);
nist_test!(nist_rat42, "Rat42", converges: [true, true]);
// Start 1 (b = 2, 400000, 25000) is the hard one (MGH's Meyer function, far start): it
// converges, slowly (≈ 300 trial steps along the curved valley b1 ≈ exp(−b2/(x + b3))).
nist_test!(nist_mgh10, "MGH10", converges: [true, true]);
nist_test!(nist_eckerle4, "Eckerle4", converges: [true, true]);
nist_test!(nist_rat43, "Rat43", converges: [true, true]);
nist_test!(nist_bennett5, "Bennett5", converges: [true, true]);

const NIST_NAMES: [&str; 27] = [
    "Misra1a", "Chwirut2", "Chwirut1", "Lanczos3", "Gauss1", "Gauss2", "DanWood", "Misra1b",
    "Kirby2", "Hahn1", "Nelson", "MGH17", "Lanczos1", "Lanczos2", "Gauss3", "Misra1c", "Misra1d",
    "Roszman1", "ENSO", "MGH09", "Thurber", "BoxBOD", "Rat42", "MGH10", "Eckerle4", "Rat43",
    "Bennett5",
];

/// The whole NIST table, printed and not asserted: `cargo test --test it lm::nist_table -- --ignored --nocapture`.
#[test]
#[ignore = "a printed table, not a check: run on purpose"]
fn nist_table() {
    for name in NIST_NAMES {
        for start in 1..=2 {
            for analytic in [true, false] {
                run_nist(name, start, analytic);
            }
        }
    }
}

// ---------------------------------------------------------------------------------------------
// Moré, Garbow & Hillstrom (1981), ACM TOMS 7(1) 17–41: functions, standard starting points
// and the minima the paper lists (its f = Σ fᵢ² = 2 × cost). The data tables (Bard, Osborne)
// are the paper's, as in MINPACK's test driver (ssqfcn). MGH's Meyer and Kowalik–Osborne
// functions are NIST's MGH10 and MGH09 above (NIST start 2 = MGH's start).

fn solve_mgh(m: usize, n: usize, x0: &[f64], f: impl Fn(&[Dual], &mut [Dual])) -> Solution {
    let problem = AutoDiff {
        m,
        n,
        analytic: true,
        f,
    };
    solve(&problem, x0, &Options::default()).unwrap()
}

/// `value` agrees with a published value given to `unit` in its last printed digit (the paper
/// prints truncated values, "48.9842..."): within one unit.
fn assert_published(what: &str, value: f64, published: f64, unit: f64) {
    assert!(
        (value - published).abs() <= unit,
        "{what}: {value:.10e}, published {published} (±{unit:e})"
    );
}

fn report(name: &str, s: &Solution) {
    eprintln!(
        "{name}: iterations {}, evaluations {}, {:?}, f = {:.6e}, x = {:?}",
        s.iterations,
        s.evaluations,
        s.termination,
        2.0 * s.cost,
        s.x
    );
}

/// MGH (1): f = 0 at (1, 1) from (−1.2, 1).
#[test]
fn mgh_rosenbrock() {
    let s = solve_mgh(2, 2, &[-1.2, 1.0], |x, f| {
        f[0] = (x[1] - x[0] * x[0]) * 10.0;
        f[1] = 1.0 - x[0];
    });
    report("Rosenbrock", &s);
    assert_ne!(s.termination, Termination::MaxIterations);
    assert!(2.0 * s.cost <= 1e-28);
    assert!(
        (s.x[0] - 1.0).abs() <= 1e-12 && (s.x[1] - 1.0).abs() <= 1e-12,
        "{:?}",
        s.x
    );
}

/// MGH (2): from (0.5, −2) a Gauss–Newton-type method is drawn to the local minimum
/// f = 48.9842... at (11.41..., −0.8968...); the global one is f = 0 at (5, 4). This solver
/// reaches the local minimum (as MINPACK's lmder does).
#[test]
fn mgh_freudenstein_roth() {
    let s = solve_mgh(2, 2, &[0.5, -2.0], |x, f| {
        f[0] = x[0] - 13.0 + ((5.0 - x[1]) * x[1] - 2.0) * x[1];
        f[1] = x[0] - 29.0 + ((x[1] + 1.0) * x[1] - 14.0) * x[1];
    });
    report("Freudenstein-Roth", &s);
    assert_ne!(s.termination, Termination::MaxIterations);
    assert_published("f", 2.0 * s.cost, 48.9842, 1e-4);
    assert_published("x1", s.x[0], 11.41, 1e-2);
    assert_published("x2", s.x[1], -0.8968, 1e-4);
}

/// MGH (3): f = 0 at (1.098...e-5, 9.106...) from (0, 1).
#[test]
fn mgh_powell_badly_scaled() {
    let s = solve_mgh(2, 2, &[0.0, 1.0], |x, f| {
        f[0] = x[0] * x[1] * 1e4 - 1.0;
        f[1] = (-x[0]).exp() + (-x[1]).exp() - 1.0001;
    });
    report("Powell badly scaled", &s);
    assert_ne!(s.termination, Termination::MaxIterations);
    assert!(2.0 * s.cost <= 1e-25);
    assert_published("x1", s.x[0], 1.098e-5, 1e-8);
    assert_published("x2", s.x[1], 9.106, 1e-3);
}

mod more_problems;

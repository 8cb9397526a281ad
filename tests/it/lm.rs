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
    let svd = jacobian.clone().svd_unordered(false, true);
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
    let sigma = s.jacobian.clone().svd(false, false).singular_values;
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

//! What a design can identify: its rank, the combinations of parameters it cannot see (in ISO
//! 230-1 names), what it does see of them, and the standard uncertainty of what it identifies.
//!
//! The input is the **design**: the stacked Jacobian of the readings with respect to the
//! parameters, one row per reading, each row divided by that reading's standard uncertainty, and
//! each column scaled to a common *µm-equivalent* unit (translations per µm, rotations per
//! µrad × 100 mm, polynomial coefficients per µm at the axis end, set-up nuisances per µm). An
//! entry is then "readings' standard deviations per µm-equivalent of the parameter", the singular
//! values `s` of the design are in 1/µm-eq, and `1/s` is the standard uncertainty (µm-eq) of the
//! combination of parameters along the matching right singular vector (unit norm). Everything
//! here is linear algebra on that matrix: the scaling is the caller's, and every figure (the
//! condition number and the observability indices included) is stated for that scaling.
//!
//! # The rank rule
//! The design's SVD `J = U·diag(s)·Vᵀ` (with `V` completed to a basis of the whole parameter
//! space when there are fewer readings than parameters). A right singular direction is
//! **identified** when `s ≥ tolerance = max(1/largest_uncertainty, 1e-10·s_max)` and `s > 0`:
//! the data pin it to `largest_uncertainty` (default 1000 µm-eq = 1 mm, beyond which the
//! small-error model means nothing) or better, and it is not a numerical zero. The others span
//! the **null space**: the combinations the data cannot tell from zero. The rank `r` is the
//! number of identified directions.
//!
//! # Parameters
//! Parameter `j` is **unidentifiable** when its *null share* `‖Nᵀ·e_j‖` exceeds [`NULL_SHARE`]
//! (`N`: an orthonormal basis of the null space, `e_j` the unit change of parameter `j`): the
//! length of the part of a change in that parameter alone that the data cannot see, 0 for a
//! parameter pinned by the identified directions, 1 for one the data do not see at all. Such a
//! parameter gets no number. Every other parameter is a combination of identified directions
//! and gets the standard uncertainty `u_j = √Σ_jj`, with `Σ = V_r·diag(1/s²)·V_rᵀ` (µm-eq²) the
//! covariance of the minimum-norm least-squares estimate, the pseudo-inverse restricted to the
//! `r` identified directions.
//!
//! # Combinations
//! - **Null combinations**: a readable basis of the null space, the reduced row echelon form of
//!   the null basis with the pivots taken in parameter order (partial pivoting within a column,
//!   a pivot at least a thousandth of what is left to reduce), so that each combination is as
//!   sparse as it can be: `EX0C − sphere1.x` reads "a change of EX0C with the opposite change of
//!   sphere1.x gives the same readings". The null basis is known only to the noise of the
//!   design (by Wedin's bound, its largest unidentified singular value over its smallest
//!   identified one: 10⁻⁷ for a Jacobian by finite differences); coefficients within a hundred
//!   times that are neither kept (when that small) nor ordered apart.
//! - **Seen combinations**: among the unidentifiable parameters, a basis of what the data do see
//!   (the orthogonal complement of the null space within the span of those parameters), in the
//!   same echelon form: with the null combination `EA0A − EA0C`, only `EA0A + EA0C` is seen.
//! - **Weak directions**: identified right singular vectors whose standard uncertainty `1/s`
//!   exceeds `weak_uncertainty` (default 10 µm-eq).
//!
//! A [`Combination`] holds unit-norm coefficients; [`Combination::describe`] writes it with its
//! largest coefficient scaled to 1, and every uncertainty of a combination reported here
//! ([`Identifiability::uncertainty`], the seen and weak ones, [`remedies`]) is that of the
//! combination as described, e.g. `u(EA0A + EA0C)`.
//!
//! # Figures over the identified directions
//! With `σ_1 ≥ … ≥ σ_r` the identified singular values (1/µm-eq) and `m` the number of rows:
//! - condition number `κ = σ_1/σ_r` (not squared, unlike FIGAROH's `cond_num`), on the
//!   column-scaled design, so it depends on the µm-equivalent scaling;
//! - O1 `= (σ_1·…·σ_r)^(1/r) / √m` (Borm & Menq; their `m` counts measurement configurations,
//!   each giving several readings; mtwin's rows are single readings, so `m` here is the number
//!   of readings and a configuration giving `k` readings makes this O1 smaller than theirs by
//!   `√k`);
//! - O2 `= σ_r/σ_1 = 1/κ` (Driels & Pathre);
//! - O3 `= σ_r` (minimum singular value, E-optimality; Nahvi et al.);
//! - O4 `= σ_r²/σ_1` (noise amplification index, as later literature writes it);
//! - O5 `= 1/Σ(1/σ_i)` (Sun & Hollerbach; A-optimality-like).
//!
//! All of them, and κ, are NaN when nothing is identified (`r = 0`).

use crate::math::Real;
use mtwin_kernels::linalg;
use nalgebra::DMatrix;
use serde_json::{Value, json};
use std::fmt::Write;

mod combination;

pub use combination::Combination;
use combination::readable;

/// A parameter whose null share (the length of its unit vector's projection onto the null
/// space) exceeds this is unidentifiable; the same bound decides whether a combination is
/// identified by a design ([`Identifiability::uncertainty`], [`remedies`]).
pub const NULL_SHARE: Real = 1e-6;

/// Singular values below this fraction of the largest are numerical zeros whatever the noise.
pub const NUMERICAL_ZERO: Real = 1e-10;

/// The thresholds of the analysis, in µm-equivalents (see the module documentation).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Options {
    /// A direction whose standard uncertainty `1/s` exceeds this (µm-eq) is unidentifiable
    /// (default 1000 = 1 mm: a direction the data pin no better than that is beyond the
    /// small-error model); directions with `s < 1e-10·s_max` are unidentifiable in any case.
    pub largest_uncertainty: Real,
    /// An identified direction whose standard uncertainty `1/s` exceeds this (µm-eq) is
    /// reported as weak (default 10).
    pub weak_uncertainty: Real,
}

impl Default for Options {
    fn default() -> Self {
        Self {
            largest_uncertainty: 1000.0,
            weak_uncertainty: 10.0,
        }
    }
}

impl Options {
    /// The singular value cut (1/µm-eq) for a design whose largest singular value is `s_max`:
    /// `max(1/largest_uncertainty, 1e-10·s_max)`.
    pub fn tolerance(&self, s_max: Real) -> Real {
        (1.0 / self.largest_uncertainty).max(NUMERICAL_ZERO * s_max)
    }
}

/// An identified direction that the data pin only loosely.
#[derive(Debug, Clone, PartialEq)]
pub struct Weak {
    /// The right singular vector, as a combination.
    pub combination: Combination,
    /// Its singular value `s` (1/µm-eq): `1/s` is the standard uncertainty along the unit vector.
    pub singular_value: Real,
    /// The standard uncertainty (µm-eq) of the combination as described (largest coefficient
    /// 1): `1/(s·leading)`.
    pub uncertainty: Real,
}

/// The observability indices over the identified singular values (formulas in the module
/// documentation; NaN when nothing is identified).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Observability {
    /// O1 = (Πσ)^(1/r)/√m, m the number of readings (Borm & Menq's D-optimality-like index).
    pub o1: Real,
    /// O2 = σ_min/σ_max, the inverse condition number (Driels & Pathre).
    pub o2: Real,
    /// O3 = σ_min (E-optimality).
    pub o3: Real,
    /// O4 = σ_min²/σ_max (noise amplification index).
    pub o4: Real,
    /// O5 = 1/Σ(1/σ_i) (A-optimality-like).
    pub o5: Real,
}

impl Observability {
    fn new(identified: &[Real], readings: usize) -> Self {
        let r = identified.len();
        if r == 0 {
            return Self {
                o1: Real::NAN,
                o2: Real::NAN,
                o3: Real::NAN,
                o4: Real::NAN,
                o5: Real::NAN,
            };
        }
        let max = identified[0];
        let min = identified[r - 1];
        let mean_log = identified.iter().map(|s| s.ln()).sum::<Real>() / r as Real;
        Self {
            o1: mean_log.exp() / (readings as Real).sqrt(),
            o2: min / max,
            o3: min,
            o4: min * min / max,
            o5: 1.0 / identified.iter().map(|s| 1.0 / s).sum::<Real>(),
        }
    }
}

/// The identifiability of a design (see the module documentation for every definition).
#[derive(Debug, Clone)]
pub struct Identifiability {
    /// The parameters' names, one per column.
    pub labels: Vec<String>,
    /// The number of readings (rows of the design).
    pub readings: usize,
    /// All `n` singular values (1/µm-eq), descending (zeros added when there are fewer readings
    /// than parameters).
    pub singular_values: Vec<Real>,
    /// The number of identified directions.
    pub rank: usize,
    /// The singular value cut actually used (1/µm-eq): identified when `s ≥ tolerance`.
    pub tolerance: Real,
    /// The unidentifiable parameters (columns, ascending): null share above [`NULL_SHARE`].
    pub unidentifiable: Vec<usize>,
    /// An orthonormal basis of the null space (n × (n − rank)), the unidentified right singular
    /// vectors.
    pub null_space: DMatrix<Real>,
    /// A readable basis of the null space: the combinations the data cannot tell from zero.
    pub null_combinations: Vec<Combination>,
    /// Among the unidentifiable parameters, a basis of what the data see.
    pub seen_combinations: Vec<Combination>,
    /// `σ_max/σ_min` over the identified directions, on the column-scaled design (NaN when
    /// nothing is identified).
    pub condition_number: Real,
    /// O1–O5 over the identified singular values.
    pub observability: Observability,
    /// The covariance (µm-eq²) of the minimum-norm estimate: the pseudo-inverse of `JᵀJ`
    /// restricted to the identified directions.
    pub covariance: DMatrix<Real>,
    /// The standard uncertainty (µm-eq) of each parameter; `None` for the unidentifiable ones.
    pub standard_uncertainty: Vec<Option<Real>>,
    /// The correlation of the estimates (n × n, parameter order). Rows and columns of the
    /// unidentifiable parameters are NaN (their diagonal too); the others have 1 on the diagonal.
    pub correlation: DMatrix<Real>,
    /// The identified directions with `1/s` above `weak_uncertainty`, weakest last.
    pub weak: Vec<Weak>,
}

/// The SVD of a design with the right singular vectors completed to a basis.
struct Decomposition {
    /// n singular values, descending.
    singular_values: Vec<Real>,
    /// n × n, column k the right singular vector of `singular_values[k]`.
    v: DMatrix<Real>,
    rank: usize,
    tolerance: Real,
}

impl Decomposition {
    fn new(design: &DMatrix<Real>, options: &Options) -> Self {
        assert!(
            design.iter().all(|x| x.is_finite()),
            "identifiability: the design holds a non-finite value"
        );
        let (m, n) = design.shape();
        if n == 0 {
            return Self {
                singular_values: Vec::new(),
                v: DMatrix::zeros(0, 0),
                rank: 0,
                tolerance: options.tolerance(0.0),
            };
        }
        // Fewer readings than parameters: pad with zero rows so that the thin SVD still gives
        // all n right singular vectors (the added singular values are zeros).
        let padded = if m < n {
            let mut p = DMatrix::zeros(n, n);
            p.rows_mut(0, m).copy_from(design);
            p
        } else {
            design.clone()
        };
        let svd = linalg::svd(padded, false, true);
        let v = svd.v_t.expect("V requested").transpose();
        let mut order: Vec<usize> = (0..n).collect();
        order.sort_by(|&a, &b| svd.singular_values[b].total_cmp(&svd.singular_values[a]));
        let singular_values: Vec<Real> = order.iter().map(|&k| svd.singular_values[k]).collect();
        let v = DMatrix::from_fn(n, n, |i, k| v[(i, order[k])]);
        let s_max = singular_values.first().copied().unwrap_or(0.0);
        let tolerance = options.tolerance(s_max);
        let rank = singular_values
            .iter()
            .take_while(|&&s| s > 0.0 && s >= tolerance)
            .count();
        Self {
            singular_values,
            v,
            rank,
            tolerance,
        }
    }

    fn null_space(&self) -> DMatrix<Real> {
        let n = self.v.nrows();
        self.v.columns(self.rank, n - self.rank).into_owned()
    }

    fn covariance(&self) -> DMatrix<Real> {
        let r = self.rank;
        let vr = self.v.columns(0, r);
        let scaled = DMatrix::from_fn(vr.nrows(), r, |i, k| {
            vr[(i, k)] / (self.singular_values[k] * self.singular_values[k])
        });
        &scaled * vr.transpose()
    }
}

/// The standard uncertainty of `combination` as described, or `None` when it has a share above
/// [`NULL_SHARE`] in the null space.
fn combination_uncertainty(
    combination: &Combination,
    null_space: &DMatrix<Real>,
    covariance: &DMatrix<Real>,
) -> Option<Real> {
    let n = covariance.nrows();
    if combination.terms.is_empty() || combination.terms.iter().any(|&(j, _)| j >= n) {
        return None;
    }
    let unit = combination.to_vector(n);
    if (null_space.transpose() * &unit).norm() > NULL_SHARE {
        return None;
    }
    let w = unit / combination.leading();
    Some(w.dot(&(covariance * &w)).max(0.0).sqrt())
}

/// Analyses `design` (rows: readings weighted by 1/σ; columns: parameters in µm-equivalents,
/// named by `labels`) under the rank rule of `options`.
///
/// # Panics
/// When `labels` does not name every column, or the design holds a non-finite value.
pub fn analyse(design: &DMatrix<Real>, labels: &[String], options: &Options) -> Identifiability {
    let (m, n) = design.shape();
    assert_eq!(
        labels.len(),
        n,
        "identifiability: {} labels for {n} columns",
        labels.len()
    );
    let d = Decomposition::new(design, options);
    let r = d.rank;
    let null_space = d.null_space();
    let covariance = d.covariance();

    let shares: Vec<Real> = (0..n).map(|j| null_space.row(j).norm()).collect();
    let unidentifiable: Vec<usize> = (0..n).filter(|&j| shares[j] > NULL_SHARE).collect();
    // Wedin's bound: the null basis is known to the perturbation of the design, which the
    // largest unidentified singular value shows (a Jacobian by finite differences: 10⁻⁷ of the
    // largest), over the gap to the smallest identified one.
    let noise = match (r, d.singular_values.get(r)) {
        (1.., Some(&s)) => s / d.singular_values[r - 1],
        _ => 0.0,
    };
    let null_combinations = readable(&null_space, noise);

    // What is seen among the unidentifiable parameters: the eigenvectors (eigenvalue ≈ 1) of the
    // projector onto the complement of the null space within their span.
    let k = unidentifiable.len();
    let seen_combinations = if k > 0 {
        let nt = DMatrix::from_fn(k, n - r, |a, b| null_space[(unidentifiable[a], b)]);
        let projector = DMatrix::identity(k, k) - &nt * nt.transpose();
        let eigen = linalg::symmetric_eigen(projector);
        let kept: Vec<usize> = (0..k).filter(|&i| eigen.eigenvalues[i] > 0.5).collect();
        let basis = DMatrix::from_fn(n, kept.len(), |row, col| {
            unidentifiable
                .iter()
                .position(|&j| j == row)
                .map_or(0.0, |a| eigen.eigenvectors[(a, kept[col])])
        });
        readable(&basis, noise)
    } else {
        Vec::new()
    };

    let identified = &d.singular_values[..r];
    let condition_number = if r > 0 {
        identified[0] / identified[r - 1]
    } else {
        Real::NAN
    };
    let standard_uncertainty: Vec<Option<Real>> = (0..n)
        .map(|j| (shares[j] <= NULL_SHARE).then(|| covariance[(j, j)].max(0.0).sqrt()))
        .collect();
    let correlation = DMatrix::from_fn(n, n, |i, j| {
        match (standard_uncertainty[i], standard_uncertainty[j]) {
            (Some(_), Some(_)) if i == j => 1.0,
            (Some(ui), Some(uj)) => covariance[(i, j)] / (ui * uj),
            _ => Real::NAN,
        }
    });
    let weak = (0..r)
        .filter(|&i| 1.0 / d.singular_values[i] > options.weak_uncertainty)
        .map(|i| {
            let combination = Combination::from_vector(&d.v.column(i).into_owned());
            let s = d.singular_values[i];
            let uncertainty = 1.0 / (s * combination.leading());
            Weak {
                combination,
                singular_value: s,
                uncertainty,
            }
        })
        .collect();

    Identifiability {
        labels: labels.to_vec(),
        readings: m,
        observability: Observability::new(identified, m),
        singular_values: d.singular_values,
        rank: r,
        tolerance: d.tolerance,
        unidentifiable,
        null_space,
        null_combinations,
        seen_combinations,
        condition_number,
        covariance,
        standard_uncertainty,
        correlation,
        weak,
    }
}

/// Three significant figures, trailing zeros trimmed (`0.5`, `1.73`, `0.00123`, `2.5e-7`).
pub(crate) fn significant(x: Real) -> String {
    if x == 0.0 || !x.is_finite() {
        return format!("{x}");
    }
    let magnitude = x.abs().log10().floor();
    let trim = |t: &str| {
        if t.contains('.') {
            t.trim_end_matches('0').trim_end_matches('.').to_string()
        } else {
            t.to_string()
        }
    };
    let text = if (-3.0..6.0).contains(&magnitude) {
        let decimals = (2.0 - magnitude).max(0.0) as usize;
        trim(&format!("{x:.decimals$}"))
    } else {
        let t = format!("{x:.2e}");
        let (mantissa, exponent) = t.split_once('e').unwrap_or((&t, "0"));
        format!("{}e{exponent}", trim(mantissa))
    };
    match text.strip_prefix('-') {
        Some(rest) => format!("−{rest}"),
        None => text,
    }
}

impl Identifiability {
    /// The number of parameters (columns).
    pub fn parameters(&self) -> usize {
        self.labels.len()
    }

    /// Whether every parameter is identifiable.
    pub fn all_identifiable(&self) -> bool {
        self.unidentifiable.is_empty()
    }

    /// The standard uncertainty (µm-eq) of `combination` as described (largest coefficient 1),
    /// or `None` when it has a share above [`NULL_SHARE`] in the null space (the data cannot
    /// give it a number).
    pub fn uncertainty(&self, combination: &Combination) -> Option<Real> {
        combination_uncertainty(combination, &self.null_space, &self.covariance)
    }

    /// A short text for people: rank, condition number, the unidentifiable parameters, each null
    /// combination, what is seen of them, the weak directions and O1–O5.
    pub fn report(&self) -> String {
        let n = self.parameters();
        let mut text = String::new();
        let _ = writeln!(
            text,
            "rank {} of {n} from {} readings (identified: standard uncertainty 1/s ≤ {} µm-eq, s ≥ {} per µm-eq)",
            self.rank,
            self.readings,
            significant(1.0 / self.tolerance),
            significant(self.tolerance),
        );
        let _ = writeln!(
            text,
            "condition number {} (σ_max/σ_min over the identified directions; columns in µm-equivalents)",
            significant(self.condition_number)
        );
        if !self.unidentifiable.is_empty() {
            let names: Vec<&str> = self
                .unidentifiable
                .iter()
                .map(|&j| self.labels[j].as_str())
                .collect();
            let _ = writeln!(text, "no number for: {}", names.join(", "));
        }
        for c in &self.null_combinations {
            let what = if c.terms.len() == 1 {
                "not seen at all"
            } else {
                "cannot be told apart"
            };
            let _ = writeln!(text, "{what}: {}", c.describe(&self.labels));
        }
        for c in &self.seen_combinations {
            let u = self.uncertainty(c).map_or("—".into(), significant);
            let _ = writeln!(
                text,
                "only {} is seen (u = {u} µm-eq)",
                c.describe(&self.labels)
            );
        }
        for w in &self.weak {
            let _ = writeln!(
                text,
                "weak: {} (u = {} µm-eq)",
                w.combination.describe(&self.labels),
                significant(w.uncertainty)
            );
        }
        let o = &self.observability;
        let _ = writeln!(
            text,
            "observability: O1 = {}, O2 = {}, O3 = {}, O4 = {}, O5 = {}",
            significant(o.o1),
            significant(o.o2),
            significant(o.o3),
            significant(o.o4),
            significant(o.o5)
        );
        text
    }

    /// The analysis with stable keys (non-finite numbers as `null`):
    /// - `readings`, `parameter_count`, `rank`;
    /// - `tolerance_per_um_eq`, `singular_values_per_um_eq` (all n, descending);
    /// - `condition_number`, `observability` {`o1`, `o2`, `o3`, `o4`, `o5`};
    /// - `parameters`: per column {`name`, `identifiable`, `standard_uncertainty_um_eq`
    ///   (`null` when unidentifiable)};
    /// - `unidentifiable`: names;
    /// - `null_combinations`: [`Combination::to_json`] objects;
    /// - `seen_combinations`: the same plus `uncertainty_um_eq` (of the combination as
    ///   described);
    /// - `weak`: the same plus `uncertainty_um_eq` and `singular_value_per_um_eq`;
    /// - `correlation`: n × n rows in parameter order, `null` for unidentifiable parameters.
    pub fn to_json(&self) -> Value {
        let number = |x: Real| if x.is_finite() { json!(x) } else { Value::Null };
        let parameters: Vec<Value> = self
            .labels
            .iter()
            .zip(&self.standard_uncertainty)
            .map(|(name, u)| {
                json!({
                    "name": name,
                    "identifiable": u.is_some(),
                    "standard_uncertainty_um_eq": u,
                })
            })
            .collect();
        let with = |c: &Combination, extra: &[(&str, Value)]| {
            let mut v = c.to_json(&self.labels);
            if let Value::Object(map) = &mut v {
                for (k, x) in extra {
                    map.insert((*k).to_string(), x.clone());
                }
            }
            v
        };
        let o = &self.observability;
        json!({
            "readings": self.readings,
            "parameter_count": self.parameters(),
            "rank": self.rank,
            "tolerance_per_um_eq": number(self.tolerance),
            "singular_values_per_um_eq": self.singular_values,
            "condition_number": number(self.condition_number),
            "observability": {
                "o1": number(o.o1), "o2": number(o.o2), "o3": number(o.o3),
                "o4": number(o.o4), "o5": number(o.o5),
            },
            "parameters": parameters,
            "unidentifiable": self.unidentifiable.iter().map(|&j| &self.labels[j]).collect::<Vec<_>>(),
            "null_combinations": self.null_combinations.iter().map(|c| c.to_json(&self.labels)).collect::<Vec<_>>(),
            "seen_combinations": self.seen_combinations.iter().map(|c| {
                with(c, &[("uncertainty_um_eq", json!(self.uncertainty(c)))])
            }).collect::<Vec<_>>(),
            "weak": self.weak.iter().map(|w| with(&w.combination, &[
                ("uncertainty_um_eq", number(w.uncertainty)),
                ("singular_value_per_um_eq", number(w.singular_value)),
            ])).collect::<Vec<_>>(),
            "correlation": self.correlation.row_iter().map(|row| {
                row.iter().map(|&x| number(x)).collect::<Vec<_>>()
            }).collect::<Vec<_>>(),
        })
    }
}

/// A design with the same `JᵀJ` and at most `n` rows (the R factor of its QR decomposition).
pub(crate) fn compress(design: DMatrix<Real>) -> DMatrix<Real> {
    if design.nrows() <= design.ncols() {
        design
    } else {
        linalg::qr_r(&linalg::qr(design))
    }
}

/// `a` over `b` (the same columns).
pub(crate) fn stack(a: &DMatrix<Real>, b: &DMatrix<Real>) -> DMatrix<Real> {
    assert_eq!(
        a.ncols(),
        b.ncols(),
        "identifiability: stacking designs of {} and {} columns",
        a.ncols(),
        b.ncols()
    );
    let mut s = DMatrix::zeros(a.nrows() + b.nrows(), a.ncols());
    s.rows_mut(0, a.nrows()).copy_from(a);
    s.rows_mut(a.nrows(), b.nrows()).copy_from(b);
    s
}

/// For each null combination of `base`, the candidate tests that would identify it and how
/// well: `(name, u)` with `u` the standard uncertainty (µm-eq) of the combination as described
/// (largest coefficient 1) from the design `base` stacked over that candidate's (weighted,
/// scaled, the same columns), best first. A candidate that leaves a share above [`NULL_SHARE`]
/// of the combination in the combined null space is not listed; a combination that only two
/// candidates together would identify gets no entry (run [`crate::estimate::plan::choose`]).
///
/// # Panics
/// When a candidate's columns differ from the base's, or a design holds a non-finite value.
pub fn remedies(
    base: &DMatrix<Real>,
    null: &[Combination],
    candidates: &[(String, DMatrix<Real>)],
    options: &Options,
) -> Vec<Vec<(String, Real)>> {
    let base = compress(base.clone());
    let combined: Vec<(String, DMatrix<Real>, DMatrix<Real>)> = candidates
        .iter()
        .map(|(name, design)| {
            let d = Decomposition::new(&stack(&base, design), options);
            (name.clone(), d.null_space(), d.covariance())
        })
        .collect();
    null.iter()
        .map(|c| {
            let mut found: Vec<(String, Real)> = combined
                .iter()
                .filter_map(|(name, null_space, covariance)| {
                    combination_uncertainty(c, null_space, covariance).map(|u| (name.clone(), u))
                })
                .collect();
            found.sort_by(|a, b| a.1.total_cmp(&b.1));
            found
        })
        .collect()
}

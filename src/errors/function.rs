//! Error functions: how an error parameter varies with its axis position and direction of
//! travel. SI inside: the argument in m (linear axes) or rad (rotary axes), the value in m
//! (translations) or rad (rotations).
//!
//! Each function is *linear in its coefficients* once its shape is fixed (polynomial degree,
//! table knots, harmonic period), which is what the Jacobian of [`super::ErrorModel`] is taken
//! with respect to. A harmonic `a·sin(2πq/P + φ)` has the coefficients
//! `(a·cos φ, a·sin φ)`: the amplitudes of `sin(2πq/P)` and `cos(2πq/P)`.

use crate::machine::Direction;
use crate::math::Real;
use std::f64::consts::TAU;

/// How a table interpolates between its knots.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Interpolation {
    /// Straight lines between knots.
    Linear,
    /// Natural cubic spline (zero second derivative at both ends).
    Cubic,
}

/// A measured error map: values at increasing positions. Outside the first and last knot the
/// end value is held.
#[derive(Clone, Debug, PartialEq)]
pub struct Table {
    positions: Vec<Real>,
    values: Vec<Real>,
    interpolation: Interpolation,
    /// Row-major n×n: the spline's second derivatives are `weights · values` (cubic only).
    second_derivative_weights: Vec<Real>,
    /// The second derivatives for the current values (cubic only).
    second_derivatives: Vec<Real>,
}

/// Why a table was rejected.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum TableError {
    /// Fewer than two knots, or positions and values of different lengths.
    #[error(
        "a table needs at least two knots and as many values as positions (got {positions} positions, {values} values)"
    )]
    Shape {
        /// Number of positions.
        positions: usize,
        /// Number of values.
        values: usize,
    },
    /// Positions not strictly increasing, or not finite (index from 0; displayed from 1).
    #[error("positions must be finite and strictly increasing (knot {} breaks it)", .0 + 1)]
    Order(usize),
    /// A value is not finite (index from 0; displayed from 1).
    #[error("value {} is not finite", .0 + 1)]
    Value(usize),
}

impl Table {
    /// A table of `values` at strictly increasing `positions` (SI).
    pub fn new(
        positions: Vec<Real>,
        values: Vec<Real>,
        interpolation: Interpolation,
    ) -> Result<Table, TableError> {
        let n = positions.len();
        if n < 2 || values.len() != n {
            return Err(TableError::Shape {
                positions: n,
                values: values.len(),
            });
        }
        for i in 0..n {
            if !positions[i].is_finite() || (i > 0 && positions[i] <= positions[i - 1]) {
                return Err(TableError::Order(i));
            }
            if !values[i].is_finite() {
                return Err(TableError::Value(i));
            }
        }
        let second_derivative_weights = match interpolation {
            Interpolation::Linear => Vec::new(),
            Interpolation::Cubic => natural_spline_weights(&positions),
        };
        let mut table = Table {
            positions,
            values,
            interpolation,
            second_derivative_weights,
            second_derivatives: Vec::new(),
        };
        table.update_second_derivatives();
        Ok(table)
    }

    /// Recomputes the spline's second derivatives after the values changed.
    fn update_second_derivatives(&mut self) {
        let n = self.values.len();
        self.second_derivatives = match self.interpolation {
            Interpolation::Linear => Vec::new(),
            Interpolation::Cubic => (0..n)
                .map(|i| {
                    (0..n)
                        .map(|j| self.second_derivative_weights[i * n + j] * self.values[j])
                        .sum()
                })
                .collect(),
        };
    }

    /// Knot positions (SI).
    pub fn positions(&self) -> &[Real] {
        &self.positions
    }

    /// Knot values (SI).
    pub fn values(&self) -> &[Real] {
        &self.values
    }

    /// The interpolation.
    pub fn interpolation(&self) -> Interpolation {
        self.interpolation
    }

    /// Interval index and local coordinate t ∈ [0, 1] of `q`, clamped to the table.
    fn locate(&self, q: Real) -> (usize, Real) {
        let n = self.positions.len();
        let q = q.clamp(self.positions[0], self.positions[n - 1]);
        let k = self.positions.partition_point(|&p| p <= q).clamp(1, n - 1) - 1;
        let h = self.positions[k + 1] - self.positions[k];
        (k, (q - self.positions[k]) / h)
    }

    /// The cubic terms' factors at local coordinate t of interval k: the weights of the second
    /// derivatives at knots k and k + 1.
    fn cubic_factors(&self, k: usize, t: Real) -> (Real, Real) {
        let h = self.positions[k + 1] - self.positions[k];
        let s = 1.0 - t;
        (h * h / 6.0 * (s * s * s - s), h * h / 6.0 * (t * t * t - t))
    }

    /// The interpolated value at `q` (SI); end values held outside the knots.
    pub fn value(&self, q: Real) -> Real {
        let (k, t) = self.locate(q);
        let mut value = (1.0 - t) * self.values[k] + t * self.values[k + 1];
        if self.interpolation == Interpolation::Cubic {
            let (a, b) = self.cubic_factors(k, t);
            value += a * self.second_derivatives[k] + b * self.second_derivatives[k + 1];
        }
        value
    }

    /// Appends the weight of each knot's value in the interpolated value at `q` (the table is
    /// linear in its values).
    fn basis(&self, q: Real, out: &mut Vec<Real>) {
        let (k, t) = self.locate(q);
        let n = self.values.len();
        let start = out.len();
        out.resize(start + n, 0.0);
        let weights = &mut out[start..];
        weights[k] = 1.0 - t;
        weights[k + 1] = t;
        if self.interpolation == Interpolation::Cubic {
            let (a, b) = self.cubic_factors(k, t);
            let w = &self.second_derivative_weights;
            for (j, weight) in weights.iter_mut().enumerate() {
                *weight += a * w[k * n + j] + b * w[(k + 1) * n + j];
            }
        }
    }
}

/// Row-major matrix W with M = W·y for the second derivatives M of the natural cubic spline
/// through (x, y): each column solves the tridiagonal system for one unit vector of values.
fn natural_spline_weights(x: &[Real]) -> Vec<Real> {
    let n = x.len();
    let mut weights = vec![0.0; n * n];
    if n < 3 {
        return weights; // two knots: the spline is the straight line
    }
    let h: Vec<Real> = x.windows(2).map(|w| w[1] - w[0]).collect();
    for column in 0..n {
        // Interior equations i = 1..n-2:
        // h[i-1] M[i-1] + 2 (h[i-1] + h[i]) M[i] + h[i] M[i+1] = 6 ((y[i+1]-y[i])/h[i] - (y[i]-y[i-1])/h[i-1])
        let y = |i: usize| if i == column { 1.0 } else { 0.0 };
        let m = n - 2;
        let mut diagonal = vec![0.0; m];
        let mut rhs = vec![0.0; m];
        for r in 0..m {
            let i = r + 1;
            diagonal[r] = 2.0 * (h[i - 1] + h[i]);
            rhs[r] = 6.0 * ((y(i + 1) - y(i)) / h[i] - (y(i) - y(i - 1)) / h[i - 1]);
        }
        // Thomas algorithm; sub-diagonal of row r is h[r], super-diagonal h[r+1].
        for r in 1..m {
            let factor = h[r] / diagonal[r - 1];
            diagonal[r] -= factor * h[r];
            rhs[r] -= factor * rhs[r - 1];
        }
        let mut solution = vec![0.0; m];
        for r in (0..m).rev() {
            let upper = if r + 1 < m {
                h[r + 1] * solution[r + 1]
            } else {
                0.0
            };
            solution[r] = (rhs[r] - upper) / diagonal[r];
        }
        for r in 0..m {
            weights[(r + 1) * n + column] = solution[r];
        }
    }
    weights
}

/// A function of a rotary axis's angle made of constants and harmonics with a whole number of
/// periods per turn, evaluated from the sine and cosine of the angle, which the chain knows
/// already from the joint's rotation: `a·sin(n·q + φ) = (a·cos φ)·sin(n·q) + (a·sin φ)·cos(n·q)`
/// with `sin(n·q)`, `cos(n·q)` by the angle-addition recurrence. No sine per harmonic and no
/// reduction to one turn (the same values, to a few ulps of the amplitudes).
#[derive(Clone, Debug, PartialEq)]
pub(crate) struct TurnSeries {
    /// The terms in the order of the function's sum.
    atoms: Vec<TurnAtom>,
}

/// One term of a [`TurnSeries`].
#[derive(Clone, Copy, Debug, PartialEq)]
enum TurnAtom {
    Constant(Real),
    /// `sin_part·sin(n·q) + cos_part·cos(n·q)`.
    Harmonic {
        cycles: u32,
        sin_part: Real,
        cos_part: Real,
    },
}

impl TurnSeries {
    /// Harmonics up to this many periods per turn take the recurrence (its error grows with the
    /// number of steps); the others their own sine.
    const MOST_CYCLES: u32 = 64;

    /// The value at the angle whose sine and cosine are `sin`, `cos`.
    #[inline]
    pub(crate) fn value(&self, sin: Real, cos: Real) -> Real {
        self.atoms.iter().fold(-0.0, |sum, atom| {
            sum + match *atom {
                TurnAtom::Constant(c) => c,
                TurnAtom::Harmonic {
                    cycles,
                    sin_part,
                    cos_part,
                } => {
                    let (mut s, mut c) = (sin, cos);
                    for _ in 1..cycles {
                        (s, c) = (s * cos + c * sin, c * cos - s * sin);
                    }
                    sin_part * s + cos_part * c
                }
            }
        })
    }
}

/// How one error parameter depends on its axis position `q` and direction of travel.
#[derive(Clone, Debug, PartialEq)]
pub enum ErrorFunction {
    /// A constant value.
    Constant(Real),
    /// `Σ c_k q^k`, coefficients from degree 0 up.
    Polynomial(Vec<Real>),
    /// Interpolated measured values.
    Table(Table),
    /// Cyclic error `amplitude · sin(2π q / period + phase)` (phase in rad).
    Harmonic {
        /// Period (m or rad), > 0.
        period: Real,
        /// Amplitude (m or rad).
        amplitude: Real,
        /// Phase (rad).
        phase: Real,
    },
    /// Lost motion (backlash) of size `value`: the axis lags the command by half of it against
    /// its direction of travel, i.e. `−sign(direction) · value / 2`.
    Reversal(Real),
    /// The sum of several functions.
    Sum(Vec<ErrorFunction>),
}

impl ErrorFunction {
    /// The value at position `q` (SI) while travelling in `direction`.
    pub fn value(&self, q: Real, direction: Direction) -> Real {
        match self {
            ErrorFunction::Constant(c) => *c,
            ErrorFunction::Polynomial(coefficients) => {
                coefficients.iter().rev().fold(0.0, |acc, c| acc * q + c)
            }
            ErrorFunction::Table(table) => table.value(q),
            ErrorFunction::Harmonic {
                period,
                amplitude,
                phase,
            } => amplitude * (TAU * q / period + phase).sin(),
            ErrorFunction::Reversal(value) => -direction.sign() * value / 2.0,
            ErrorFunction::Sum(terms) => terms.iter().map(|term| term.value(q, direction)).sum(),
        }
    }

    /// The function as a [`TurnSeries`] of a rotary axis's angle, when it is one: a constant,
    /// a harmonic with a whole number of periods per turn, or a sum of those (a sum of sums is
    /// left to [`ErrorFunction::value`]).
    pub(crate) fn turn_series(&self) -> Option<TurnSeries> {
        let atom = |function: &ErrorFunction| match *function {
            ErrorFunction::Constant(c) => Some(TurnAtom::Constant(c)),
            ErrorFunction::Harmonic {
                period,
                amplitude,
                phase,
            } => {
                let cycles = TAU / period;
                let whole = cycles.round();
                let exact = (cycles - whole).abs() <= 4.0 * Real::EPSILON * whole;
                (exact && whole >= 1.0 && whole <= Real::from(TurnSeries::MOST_CYCLES)).then(|| {
                    TurnAtom::Harmonic {
                        cycles: whole as u32,
                        sin_part: amplitude * phase.cos(),
                        cos_part: amplitude * phase.sin(),
                    }
                })
            }
            _ => None,
        };
        let atoms = match self {
            ErrorFunction::Sum(terms) => terms.iter().map(atom).collect::<Option<Vec<_>>>()?,
            single => vec![atom(single)?],
        };
        atoms
            .iter()
            .any(|a| matches!(a, TurnAtom::Harmonic { .. }))
            .then_some(TurnSeries { atoms })
    }

    /// Whether the value depends on neither position nor direction.
    pub fn is_constant(&self) -> bool {
        match self {
            ErrorFunction::Constant(_) => true,
            ErrorFunction::Polynomial(c) => c.len() <= 1,
            ErrorFunction::Sum(terms) => terms.iter().all(ErrorFunction::is_constant),
            _ => false,
        }
    }

    /// Why the function cannot describe an error of an axis that turns without end (repeating
    /// every `turn` rad, evaluated on [0, turn)), if it cannot: a polynomial of degree ≥ 1 or a
    /// reversal-free drift would jump at the end of the turn, a harmonic must fit a whole number
    /// of periods in a turn, and a table must cover exactly [0, turn] with equal end values.
    pub fn periodicity_problem(&self, turn: Real) -> Option<String> {
        match self {
            ErrorFunction::Constant(_) | ErrorFunction::Reversal(_) => None,
            ErrorFunction::Polynomial(c) if c.iter().skip(1).any(|v| *v != 0.0) => {
                Some("a polynomial in the angle of a continuous axis would jump at 360°; use harmonics or a table".into())
            }
            ErrorFunction::Polynomial(_) => None,
            ErrorFunction::Harmonic { period, .. } => {
                let cycles = turn / period;
                ((cycles - cycles.round()).abs() > 1e-9 || cycles.round() < 1.0).then(|| {
                    format!("a harmonic on a continuous axis needs a whole number of periods per turn (360° / period = {cycles})")
                })
            }
            ErrorFunction::Table(table) => {
                let (first, last) = (table.positions[0], table.positions[table.positions.len() - 1]);
                let (v0, vn) = (table.values[0], table.values[table.values.len() - 1]);
                let ends_match = (v0 - vn).abs() <= 1e-12 * v0.abs().max(vn.abs()).max(1e-12);
                let spans_turn = first.abs() < 1e-12 && (last - turn).abs() < 1e-9 * turn;
                (!(spans_turn && ends_match)).then(|| {
                    "a table on a continuous axis must run from 0° to 360° with the same value at both ends".to_string()
                })
            }
            ErrorFunction::Sum(terms) => terms.iter().find_map(|term| term.periodicity_problem(turn)),
        }
    }

    /// Number of linear coefficients.
    pub fn coefficient_count(&self) -> usize {
        match self {
            ErrorFunction::Constant(_) | ErrorFunction::Reversal(_) => 1,
            ErrorFunction::Polynomial(c) => c.len(),
            ErrorFunction::Table(table) => table.values.len(),
            ErrorFunction::Harmonic { .. } => 2,
            ErrorFunction::Sum(terms) => terms.iter().map(ErrorFunction::coefficient_count).sum(),
        }
    }

    /// Appends the linear coefficients (SI).
    pub fn coefficients(&self, out: &mut Vec<Real>) {
        match self {
            ErrorFunction::Constant(c) | ErrorFunction::Reversal(c) => out.push(*c),
            ErrorFunction::Polynomial(c) => out.extend_from_slice(c),
            ErrorFunction::Table(table) => out.extend_from_slice(&table.values),
            ErrorFunction::Harmonic {
                amplitude, phase, ..
            } => {
                out.push(amplitude * phase.cos());
                out.push(amplitude * phase.sin());
            }
            ErrorFunction::Sum(terms) => terms.iter().for_each(|term| term.coefficients(out)),
        }
    }

    /// Sets the linear coefficients from the front of `coefficients`; returns how many it used.
    pub fn set_coefficients(&mut self, coefficients: &[Real]) -> usize {
        match self {
            ErrorFunction::Constant(c) | ErrorFunction::Reversal(c) => {
                *c = coefficients[0];
                1
            }
            ErrorFunction::Polynomial(c) => {
                let n = c.len();
                c.copy_from_slice(&coefficients[..n]);
                n
            }
            ErrorFunction::Table(table) => {
                let n = table.values.len();
                table.values.copy_from_slice(&coefficients[..n]);
                table.update_second_derivatives();
                n
            }
            ErrorFunction::Harmonic {
                amplitude, phase, ..
            } => {
                let (sin_part, cos_part) = (coefficients[0], coefficients[1]);
                *amplitude = sin_part.hypot(cos_part);
                *phase = cos_part.atan2(sin_part);
                2
            }
            ErrorFunction::Sum(terms) => terms.iter_mut().fold(0, |used, term| {
                used + term.set_coefficients(&coefficients[used..])
            }),
        }
    }

    /// Appends the derivative of the value with respect to each linear coefficient at `q`.
    pub fn basis(&self, q: Real, direction: Direction, out: &mut Vec<Real>) {
        match self {
            ErrorFunction::Constant(_) => out.push(1.0),
            ErrorFunction::Reversal(_) => out.push(-direction.sign() / 2.0),
            ErrorFunction::Polynomial(c) => {
                let mut power = 1.0;
                for _ in 0..c.len() {
                    out.push(power);
                    power *= q;
                }
            }
            ErrorFunction::Table(table) => table.basis(q, out),
            ErrorFunction::Harmonic { period, .. } => {
                let angle = TAU * q / period;
                out.push(angle.sin());
                out.push(angle.cos());
            }
            ErrorFunction::Sum(terms) => {
                terms.iter().for_each(|term| term.basis(q, direction, out))
            }
        }
    }

    /// A short label per linear coefficient, e.g. `polynomial[2]`, `harmonic.sin`.
    pub fn coefficient_labels(&self, prefix: &str, out: &mut Vec<String>) {
        match self {
            ErrorFunction::Constant(_) => out.push(format!("{prefix}constant")),
            ErrorFunction::Reversal(_) => out.push(format!("{prefix}reversal")),
            ErrorFunction::Polynomial(c) => {
                out.extend((0..c.len()).map(|k| format!("{prefix}polynomial[{k}]")))
            }
            ErrorFunction::Table(table) => {
                out.extend((0..table.values.len()).map(|k| format!("{prefix}table[{k}]")))
            }
            ErrorFunction::Harmonic { .. } => {
                out.push(format!("{prefix}harmonic.sin"));
                out.push(format!("{prefix}harmonic.cos"));
            }
            ErrorFunction::Sum(terms) => {
                for (i, term) in terms.iter().enumerate() {
                    term.coefficient_labels(&format!("{prefix}{i}."), out);
                }
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    const UP: Direction = Direction::Positive;

    #[test]
    fn polynomial_is_evaluated_by_degree() {
        // 1 + 2q + 3q² at q = 2 → 1 + 4 + 12 = 17.
        assert_eq!(
            ErrorFunction::Polynomial(vec![1.0, 2.0, 3.0]).value(2.0, UP),
            17.0
        );
    }

    #[test]
    fn reversal_lags_against_travel() {
        let f = ErrorFunction::Reversal(4e-6);
        assert_eq!(f.value(0.1, Direction::Positive), -2e-6);
        assert_eq!(f.value(0.1, Direction::Negative), 2e-6);
    }

    #[test]
    fn linear_table_interpolates_and_holds_ends() {
        let t = ErrorFunction::Table(
            Table::new(
                vec![0.0, 1.0, 3.0],
                vec![0.0, 2.0, 6.0],
                Interpolation::Linear,
            )
            .unwrap(),
        );
        assert!((t.value(0.5, UP) - 1.0).abs() < 1e-15);
        assert!((t.value(2.0, UP) - 4.0).abs() < 1e-15);
        assert_eq!(t.value(-1.0, UP), 0.0);
        assert_eq!(t.value(5.0, UP), 6.0);
    }

    #[test]
    fn cubic_table_reproduces_a_straight_line_and_passes_through_knots() {
        // A natural spline through collinear points is that line (all M = 0).
        let line = Table::new(
            vec![0.0, 0.2, 0.5, 1.0],
            vec![1.0, 1.4, 2.0, 3.0],
            Interpolation::Cubic,
        )
        .unwrap();
        let f = ErrorFunction::Table(line);
        for q in [0.05, 0.33, 0.77] {
            assert!((f.value(q, UP) - (1.0 + 2.0 * q)).abs() < 1e-14);
        }
        let wiggle = Table::new(
            vec![0.0, 1.0, 2.0, 3.0],
            vec![0.0, 1.0, 0.0, 1.0],
            Interpolation::Cubic,
        )
        .unwrap();
        let g = ErrorFunction::Table(wiggle);
        for (q, v) in [(0.0, 0.0), (1.0, 1.0), (2.0, 0.0), (3.0, 1.0)] {
            assert!((g.value(q, UP) - v).abs() < 1e-14);
        }
        // Hand solution for equal spacing h = 1, natural ends: 4 M1 + M2 = -12, M1 + 4 M2 = 12
        // → M1 = -4, M2 = 4; at q = 0.5: 0.5·0 + 0.5·1 + (1/6)(0.125 - 0.5)(M0 + M1)
        // = 0.5 + (1/6)(-0.375)(-4) = 0.75.
        assert!((g.value(0.5, UP) - 0.75).abs() < 1e-14);
    }

    #[test]
    fn harmonic_coefficients_round_trip() {
        let mut f = ErrorFunction::Harmonic {
            period: 0.01,
            amplitude: 2e-6,
            phase: 0.7,
        };
        let mut c = Vec::new();
        f.coefficients(&mut c);
        let before = f.value(0.0123, UP);
        f.set_coefficients(&c);
        assert!((f.value(0.0123, UP) - before).abs() < 1e-20);
        let mut b = Vec::new();
        f.basis(0.0123, UP, &mut b);
        let linear: Real = b.iter().zip(&c).map(|(x, y)| x * y).sum();
        assert!((linear - before).abs() < 1e-20);
    }
}

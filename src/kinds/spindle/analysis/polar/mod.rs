//! Polar-plot centres and the values about them (ISO 230-7 §3.7, §3.8), computed exactly.
//!
//! **What it models.** A profile `p[m]` (m) at angles `θ_m` (rad) is a polar plot of
//! displacement versus rotation angle. The plot's radius `r0` is only a drawing scale, so every
//! value is computed in the linearised ("limaçon") model: moving the centre by `c = (cx, cy)`
//! changes the radial deviation at `θ` by `−(cx cosθ + cy sinθ)`, the residual about `c` is
//!
//! ```text
//! ρ_c[m] = p[m] − cx·cosθ_m − cy·sinθ_m
//! ```
//!
//! and the value about `c` is `max ρ_c − min ρ_c`, the separation of the two concentric circles
//! about `c` that just enclose the plot. The five centres of ISO 230-7 are:
//!
//! | centre | offset `c` |
//! |---|---|
//! | PC  | `(0, 0)`, the sensor zero |
//! | LSC | least-squares fit of `a0 + cx cosθ + cy sinθ` to `p` (3×3 normal equations; `2/M Σ p cosθ`, `2/M Σ p sinθ` for equally spaced full-circle angles) |
//! | MRS | minimises `max ρ_c − min ρ_c`: the LP `min u − l` s.t. `l ≤ ρ_c[m] ≤ u` |
//! | MIC | maximises `min ρ_c` (largest inscribed circle): the LP `max l` s.t. `ρ_c[m] ≥ l` |
//! | MCC | minimises `max ρ_c` (smallest circumscribed circle): the LP `min u` s.t. `ρ_c[m] ≤ u` |
//!
//! **The solver.** MRS, MIC and MCC are linear programmes in 3–4 unknowns with one or two
//! constraints per point. They are solved exactly by a small primal simplex on their duals
//! (3–4 equality rows, one column per constraint), which is the classical exchange (Stiefel)
//! algorithm: the basis is the set of 3 (MIC, MCC) or 4 (MRS) contact points, each iteration
//! brings in the point that violates the current circles most (Dantzig's rule, switching to
//! Bland's rule after repeated non-improving steps so degenerate profiles cannot cycle) and the
//! ratio test keeps the multipliers non-negative. The basis is re-factorised from scratch each
//! step (a 3×3 or 4×4 elimination), pricing is one pass over the points without allocation.
//! At the end the solver checks its certificate: every point inside the circles to
//! 1e-13 × max|p| (primal feasibility) and non-negative multipliers that balance the objective
//! (dual feasibility), and it returns the contact points. A general LP crate was not used:
//! `microlp` would bring `sprs` and `ndarray` for a 4-variable problem.
//!
//! **Ties.** MRS has a unique value; with distinct angles its centre is unique as well (1, cos,
//! sin is a Haar system on the circle). The smallest circumscribed (or largest inscribed)
//! circle of a sampled plot can be reached by a whole segment of centres, e.g. a pure 2-UPR
//! ellipse sampled at its vertices, and the range about them differs. The MCC (MIC) centre is
//! therefore the lexicographic optimum: among the centres with the smallest maximum (largest
//! minimum), the one with the largest minimum (smallest maximum), i.e. the smallest value.
//! This happens only when the optimum is degenerate (a multiplier of the contacts vanishes:
//! two antipodal contacts); the second LP is then solved by the same simplex, with the first
//! optimum relaxed by the pricing tolerance. Otherwise the three contacts fix the centre.
//!
//! **Partial arcs.** LSC and MRS are well defined for any angles with at least 3 (LSC) or 4
//! (MRS) distinct directions, e.g. the arc of a swivel table, though their offsets grow
//! sensitive as the arc shrinks. MIC and MCC are bounded only when the directions surround the
//! centre: they need every gap between neighbouring angles below [`MAX_ANGLE_GAP`] (179°),
//! otherwise [`PolarError::NotSurrounded`].
//!
//! **Left out.** The exact geometric circle fits on the drawn plot (they tend to the limaçon
//! result as `r0` grows, with a deviation about offset²/r0); constrained fits for partial arcs;
//! which centre a test must use (ISO 230-7 Table 1) and which data the centre is taken from
//! (the synchronous plot, §3.7 Note 1): that is the caller's business, see
//! [`range_about`] to evaluate other data about a given centre.

// The files, in reading order: `angles` (the profile's angles, the fit about a centre, the
// range about an offset), `centre` (the centres, a fit's result, the errors), `simplex` (MRS,
// MIC and MCC as linear programmes) and `extremes` (the residuals' extremes, scanned fast).
mod angles;
mod centre;
mod extremes;
mod simplex;

pub use angles::{Angles, fit, range_about};
pub use centre::{Centre, CentreFit, MAX_ANGLE_GAP, PolarError, UnknownCentre};

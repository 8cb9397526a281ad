//! ISO 230-4 circular tests of a ball-bar table: the standard's figures and the diagnostics a
//! service engineer reads from the trace.
//!
//! **Frame and signs.** The plane's axes are p (its first) and q (its second), see [`Plane`]:
//! XY → p = X, q = Y; YZ → p = Y, q = Z; ZX → p = Z, q = X. θ runs from +p toward +q; σ = +1
//! counter-clockwise (θ increasing), −1 clockwise. A reading is d = measured distance between
//! the balls − nominal radius R (actual − nominal, + outward). v is the feed (path speed),
//! sgn the sign function. SI inside (m, rad, s).
//!
//! # ISO 230-4 figures
//!
//! The offset of the machine's circle from the centre ball is removed by least squares,
//! d ≈ r₀ + c_p·cos θ + c_q·sin θ, after the readings have had its second-order part taken out
//! exactly (`data::exactly_centred`: an offset e would otherwise leave e²/(4R) at 2θ, 0.22 µm
//! for a centre set 0.36 mm off on a 150 mm bar, read as squareness).
//!
//! - `G_ccw`, `G_cw` circular deviation: max − min of the residuals of each sense's own fit;
//! - `G` bidirectional circular deviation G(b): max − min of both senses' residuals from one
//!   common fit (r₀, c_p, c_q);
//! - `H` circular hysteresis: max over θ of |d_ccw(θ) − d_cw(θ)| after the common centre
//!   removal, the cw trace linearly interpolated in θ at the ccw angles where both traces cover
//!   (across 0°/360° too);
//! - `F_max`, `F_min`: max and min of d − c_p·cos θ − c_q·sin θ (common fit): radial deviation
//!   from the nominal radius with the centre offset removed, r₀ kept.
//!
//! # Diagnostics
//!
//! One joint linear least-squares fit over both senses of d(θ, σ) = the sum of the columns
//! below ([`Term`], [`diagnostic_column`]); reversal lags, decay times and periods are
//! searched on the joint residual sum of squares.
//!
//! The angle of a reading is the one ball-bar software assigns: from the time since the
//! start it detected, at the programmed feed. An axis reverses when it actually does: δ after
//! the angle of its programmed reversal, δ its servo lag (1/K_v for a position loop without
//! feed-forward) less the lag already in the detected start. Software that detects the start
//! from the machine's motion (as real ball-bars and mtwin's do) leaves δ near 0, ± half a
//! servo mismatch; angles assigned from the command at the sampling time leave δ ≈ 1/K_v.
//! Backlash, lateral play and the spike of p act at θ_p = θ − σ·v·δ_p/R crossing 0° or 180°,
//! those of q at θ_q = θ − σ·v·δ_q/R crossing 90° or 270°; δ_p, δ_q are searched within
//! ± min(200 ms, the time for 30° of arc) whenever the model has a reversal term of the axis
//! (negative: the axis reverses before its programmed angle, lagging less than the detected
//! start). With δ = 0 the terms read as in the table (sgn(sin θ_p)·sin θ = |sin θ|, …).
//!
//! **Backlash as a step or as play.** Lost motion can reach the trace two ways. As an
//! instantaneous half-step at the reversal (the error model's reversal term: the carriage
//! lags b/2 against its travel and switches sides at once), the column is the table's. As
//! real play (a dead band of width b between motor and carriage, see
//! [`crate::program::servo`]) the carriage stands still after the motor reverses until the
//! motor has come back b; at a quadrant crossing the motor comes back u = R·(1 − cos φ) over
//! the arc φ since its reversal, so the carriage's lead over it in its new direction goes from
//! b/2 to −b/2 as u goes from 0 to b: the column is the step column times
//! w = 2·min(R·(1 − cos φ)/g, 1) − 1 with g = b ([`take_up`]), a parabola over the take-up arc
//! arccos(1 − b/R) ≈ √(2b/R) (0.63° for 6 µm on 100 mm), whatever the feed; it is the step as
//! g → 0. The fit draws both, the step and the play with g = |b| (searched parameters searched
//! again, g refitted from b until it settles), and keeps the one with the smaller residual
//! sum of squares (with backlash on both axes, also one axis as a step and the other as play);
//! a note says when play was chosen. With play a spike starts where the carriage reverses,
//! the take-up arc after the motor. Fitted with the step, play of b leaves an inward dip of
//! depth b at each reversal that the spike term reads as an inward spike.
//!
//! **The angle of the position-dependent terms.** A trace whose angles were assigned from the
//! command at the sampling time (not timed from the machine's motion) leads the direction the
//! axes actually reach by σ·v·ℓ/R, ℓ the common servo lag: the centre offset, squareness and
//! scale mismatch are then fitted at θ_a = θ − σ·v·ℓ/R, ℓ estimated from the trace
//! ([`CircleData::angle_lag`]: the centre offset turns by v·ℓ/R in opposite directions in the
//! two senses), used when it is significant (3 u) and both senses are full circles; 0 for
//! traces timed from the motion, such as mtwin's.
//!
//! | key | parameter | radial term |
//! |---|---|---|
//! | `radius_deviation_um` | c₀: bar length error, mean scale | c₀ |
//! | `centre_offset_p_um`, `_q_um` | centre of the machine's circle relative to the centre ball | c_p·cos θ + c_q·sin θ |
//! | `squareness_um_per_m` | s (rad), + when the angle between +p and +q travel is < 90° | (R·s/2)·sin 2θ |
//! | `scale_mismatch_ppm` | Δk = k_p − k_q | (R·Δk/2)·cos 2θ |
//! | `servo_mismatch_ms` | Δτ = τ_p − τ_q (lag = 1/K_v), + when p lags more | σ·(v·Δτ/2)·sin 2θ |
//! | `backlash_p_um` | b_p: p lags the command by b_p/2 against its travel, sgn ṗ = −σ·sgn(sin θ_p) | +σ·sgn(sin θ_p)·cos θ·b_p/2 (× w as play) |
//! | `backlash_q_um` | b_q, sgn q̇ = σ·sgn(cos θ_q) | −σ·sgn(cos θ_q)·sin θ·b_q/2 |
//! | `lateral_play_p_um` | l_p: the p carriage shifts along q by −sgn(ṗ)·l_p/2 | +σ·sgn(sin θ_p)·sin θ·l_p/2 (= +σ·\|sin θ\|·l_p/2 at δ_p = 0) |
//! | `lateral_play_q_um` | l_q: the q carriage shifts along p by −sgn(q̇)·l_q/2 | −σ·sgn(cos θ_q)·cos θ·l_q/2 (= −σ·\|cos θ\|·l_q/2) |
//! | `reversal_lag_p_ms`, `_q_ms` | δ_p, δ_q: time from the programmed to the actual reversal of the axis, reported when its backlash or spike is significant (lateral play, continuous at the reversal, cannot place it) and the profile likelihood over the lag, with those terms alone moving, rises by Δ RSS = 7.35·σ̂² (a change point's 95 % likelihood-ratio bound, Hansen 2000) inside the searched range on both sides (u the farther edge's distance over 1.96) | (locates the reversal terms) |
//! | `straightness_p_um` | S_p: bow of p along q, E_q = S_p·(1 − (p/R)²), middle toward +q | S_p·sin³θ |
//! | `straightness_q_um` | S_q: E_p = S_q·(1 − (q/R)²) | S_q·cos³θ |
//! | `reversal_spike_p_um`, `_decay_ms` | h_p, τ_p: after p reverses (θ_p = 0°, 180°) it sticks and lags in its new direction by h_p·e^(−Δt/τ_p), Δt = R·\|θ_p − θ_r\|/v | +h_p·\|cos θ\|·e^(−Δt/τ_p) |
//! | `reversal_spike_q_um`, `_decay_ms` | the same for q at 90°, 270° | +h_q·\|sin θ\|·e^(−Δt/τ_q) |
//! | `cyclic_p_um`, `_period_mm`, `_phase_deg` | periodic error A·sin(2π·p/P + φ) of p, p = R·cos θ from the circle centre | cos θ·[α·sin(2πp/P) + β·cos(2πp/P)], A = √(α² + β²), φ = atan2(β, α) |
//! | `cyclic_q_um`, … | the same for q, q = R·sin θ | sin θ·[α·sin(2πq/P) + β·cos(2πq/P)] |
//!
//! A spike counts only after a reversal the trace crossed: the same sense has readings within
//! 3° before it (a full circle counts as crossed at its start: tests run in with a lead-in
//! arc). Decays are searched from max(1 ms, two sampling intervals) to min(200 ms, the time
//! for 30° of arc): a shorter spike lies in one or two readings and cannot be told from noise.
//! A spike's height is read back to the instant the axis reversed, which a trace sampled
//! every Δt places only within a sample interval: the height is known to a factor
//! e^(±Δt/(2τ)), and its uncertainty includes h·u_δ/τ. Periods are searched from max(1 mm,
//! 4 sample spacings) to R/2. A spike amplitude below twice its uncertainty is reported with
//! a null decay. A cyclic amplitude needs more, as its
//! period is the best of the M periods searched (4 per 1/(2R) in frequency): noise alone
//! passes 2u at one of them nearly always, so the threshold is √(2·ln(M/0.05)) u (4.5 u for
//! R = 150 mm, M = 1185), which the largest of M noise amplitudes exceeds at most 5 % of the
//! time; below it the period is null ([`CircleData::significance`]). A significant spike or
//! cyclic term whose decay or period the search ends at an end of its range (the residual
//! still falling toward it: a spike shorter than the sampling resolves or longer than 200 ms,
//! a wavelength beyond R/2 or under 4 sample spacings) is listed as not identifiable, with the
//! reason, rather than reported: its height is that of the wrong shape
//! ([`CircleData::shape_at_range_end`]).
//!
//! **Uncertainties** are standard uncertainties σ̂·√((JᵀJ)⁻¹)ⱼⱼ, σ̂² = RSS/(n − k), J the fit's
//! columns plus the derivatives in the decays and periods of significant terms. They assume
//! independent residuals; a real trace's residuals are serially correlated, so they are
//! optimistic.
//!
//! **Identifiability.** A term the data cannot tell from the others is reported null with the
//! reason, never as a number: terms needing both senses when one is missing (servo mismatch is
//! then squareness, lateral play is radius and scale), spikes with no crossed reversal, and
//! any term whose variance the others inflate more than [`MAX_VARIANCE_INFLATION`] times (the
//! least important goes first; order of [`Term::DIAGNOSTICS`]).

// Read top-down in this order: model (terms and their columns), data (the prepared table),
// identify (what the data can give), fit (the joint fit), search (its searched parameters),
// profile (the lag profile), spectral (cyclic and lobe columns by their moments and
// transforms), normal (least squares from cross products), reversal (the reversal terms at a
// shape), columns (a fit's columns: dense part and sparse change), blocks (the readings cut
// into blocks, with the sums fits share), moments (the kinds of those sums; their non-uniform
// Fourier transform is `crate::discovery::nufft`), statics (the table's static columns),
// linalg (the least-squares algebra), diagnose (the diagnostics), figures (G, H, F and
// `evaluate`), report (text and JSON).
mod blocks;
mod columns;
mod data;
mod diagnose;
#[cfg(test)]
mod equivalence;
mod figures;
mod fit;
mod identify;
mod lag;
mod linalg;
mod model;
mod moments;
mod normal;
mod profile;
mod report;
mod reversal;
mod search;
mod spectral;
mod statics;

pub use blocks::Blocks;
pub use data::{CircleData, SearchRanges, covered_arc};
pub use diagnose::{Diagnostics, TermEstimate};
pub use figures::{BallbarEvaluation, evaluate};
pub use fit::ModelFit;
pub use lag::{LAG_SET, LagLocation};
pub use model::{
    BasisPoint, Shape, Term, arc_since_reversal, diagnostic_column, take_up, take_up_arc,
};
pub use report::lag_key;

use crate::machine::Plane;
use crate::math::Real;

/// The fewest readings a sense present in the table may have.
pub const MIN_READINGS: usize = 20;
/// The smallest angular span (°) a sense may cover for a circle fit.
pub const MIN_SPAN_DEG: Real = 90.0;
/// The fewest readings for the diagnostic fit (about 20 columns).
pub const MIN_DIAGNOSTIC_READINGS: usize = 200;
/// A term whose variance the other terms inflate more than this is unidentifiable (its
/// uncertainty would be more than √1000 ≈ 32 times that of an orthogonal design).
pub const MAX_VARIANCE_INFLATION: Real = 1000.0;

/// The conditions of a circular test, which the table does not hold.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct CircularTest {
    /// The plane of the circle.
    pub plane: Plane,
    /// Nominal radius (m).
    pub radius: Real,
    /// Path speed (m/s).
    pub feed: Real,
}

/// Why a ball-bar table cannot be evaluated.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
#[non_exhaustive]
pub enum BallbarError {
    /// The radius is not a finite positive length.
    #[error("radius {0} mm: expected a finite positive length")]
    Radius(Real),
    /// The feed is not a finite positive speed.
    #[error("feed {0} mm/min: expected a finite positive speed")]
    Feed(Real),
    /// The table has no readings.
    #[error("the table has no readings")]
    Empty,
    /// A reading holds a value that is not a finite number.
    #[error("reading {0}: the angle or the deviation is not a finite number")]
    NotFinite(usize),
    /// A sense with too few readings.
    #[error(
        "the {sense} trace has {n} reading(s): a circular test needs at least {MIN_READINGS} in each sense present"
    )]
    TooFewReadings {
        /// `ccw` or `cw`.
        sense: &'static str,
        /// How many it has.
        n: usize,
    },
    /// A sense covers too small an arc to fit a circle to.
    #[error(
        "the {sense} trace covers only {span_deg:.1}° of arc: fitting the centre needs at least {MIN_SPAN_DEG}°"
    )]
    SpanTooSmall {
        /// `ccw` or `cw`.
        sense: &'static str,
        /// Its span (°).
        span_deg: Real,
    },
}

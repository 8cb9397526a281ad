//! The extremes of a profile's residuals about an offset, scanned in interleaved lanes
//! (the pricing of the simplex and every centre fit go through here), and the profile's scale
//! for the tolerances.

use crate::math::Real;

/// `(min ρ, max ρ, argmin, argmax)` of `p` about `offset` (the first index of each on ties).
pub(super) fn extremes(
    dirs: &[[Real; 2]],
    p: &[Real],
    offset: [Real; 2],
) -> (Real, Real, usize, usize) {
    let [cx, cy] = offset;
    // Two passes of one key each run faster than one pass keeping both.
    let (arg_high, high) = first_max(dirs, p, |[c, s], v| v - cx * c - cy * s);
    let (arg_low, minus_low) = first_max(dirs, p, |[c, s], v| -(v - cx * c - cy * s));
    (-minus_low, high, arg_low, arg_high)
}

/// `(min ρ, max ρ)` of `p` about `offset`: [`extremes`] without the indices, in lanes of
/// `min` and `max` that the compiler turns into vector instructions.
pub(super) fn range_of(dirs: &[[Real; 2]], p: &[Real], offset: [Real; 2]) -> (Real, Real) {
    let [cx, cy] = offset;
    let mut low = [Real::INFINITY; LANES];
    let mut high = [Real::NEG_INFINITY; LANES];
    let rho = |[c, s]: [Real; 2], v: Real| v - cx * c - cy * s;
    let len = dirs.len().min(p.len());
    let whole = len - len % LANES;
    let chunks = dirs[..whole]
        .chunks_exact(LANES)
        .zip(p[..whole].chunks_exact(LANES));
    for (d, v) in chunks {
        for lane in 0..LANES {
            let r = rho(d[lane], v[lane]);
            low[lane] = low[lane].min(r);
            high[lane] = high[lane].max(r);
        }
    }
    for m in whole..len {
        let r = rho(dirs[m], p[m]);
        low[0] = low[0].min(r);
        high[0] = high[0].max(r);
    }
    let low = low.into_iter().fold(Real::INFINITY, Real::min);
    let high = high.into_iter().fold(Real::NEG_INFINITY, Real::max);
    (low, high)
}

/// Interleaved lanes of [`first_max`] and [`range_of`]: independent running extremes that the
/// processor overlaps, instead of one chain of compare-and-select through every point.
const LANES: usize = 4;

/// The largest `key(direction, value)` over the points and its first index (the one a plain
/// scan with a strict `>` keeps); `(0, −∞)` for no points. The pricing of the simplex and the
/// extremes of every centre fit go through here, so it is written for speed: the points are
/// scanned in [`LANES`] interleaved lanes, each keeping the first index of its own largest
/// key, and the lanes are merged at the end (largest key, then smallest index): the same index
/// and key as the plain scan.
#[inline(always)]
pub(super) fn first_max(
    dirs: &[[Real; 2]],
    p: &[Real],
    key: impl Fn([Real; 2], Real) -> Real,
) -> (usize, Real) {
    let len = dirs.len().min(p.len());
    let whole = len - len % LANES;
    let mut best = [Real::NEG_INFINITY; LANES];
    let mut at = [0usize; LANES];
    let chunks = dirs[..whole]
        .chunks_exact(LANES)
        .zip(p[..whole].chunks_exact(LANES));
    for (chunk, (d, v)) in chunks.enumerate() {
        for lane in 0..LANES {
            let k = key(d[lane], v[lane]);
            if k > best[lane] {
                best[lane] = k;
                at[lane] = chunk * LANES + lane;
            }
        }
    }
    for m in whole..len {
        let k = key(dirs[m], p[m]);
        let lane = m - whole;
        if k > best[lane] {
            best[lane] = k;
            at[lane] = m;
        }
    }
    let mut pick = 0;
    for lane in 1..LANES {
        if best[lane] > best[pick] || (best[lane] == best[pick] && at[lane] < at[pick]) {
            pick = lane;
        }
    }
    (at[pick], best[pick])
}

/// The profile's scale for the tolerances: `max |p|`.
pub(super) fn scale_of(p: &[Real]) -> Real {
    p.iter().fold(0.0, |m: Real, v| m.max(v.abs()))
}

//! The sine and cosine of a joint angle, without a branch that depends on the angle.
//!
//! [`libm::sincos`] (FreeBSD's `sincos`, under 1 ulp, the same on every platform) picks its
//! argument reduction by the range the angle lies in (no reduction below π/4, a one-step
//! reduction by 1, 2, 3 or 4 × π/2 up to 9π/4, the three-part reduction above) and its
//! quadrant by a `match`: on a machine's angles, spread over a turn, those branches are
//! mispredicted pose after pose (measured on trunnion5's nominal pose, 2026-12-01: 122 →
//! 107 ns with this function, its tiny-angle path included). [`sin_cos`]
//! takes every angle from 2⁻²⁷·√2 (below which, as in libm, the sine is the angle and the
//! cosine 1) to 2²⁰·π/2 through the one reduction libm uses above 9π/4 (FreeBSD's
//! `__rem_pio2` medium case: `n = rint(x·2/π)` and `x − n·π/2` with π/2 in two parts, a
//! second and third part only when the first cancels, which happens for angles within about
//! 2⁻¹⁶ of a multiple of π/2 and is predicted as not taken otherwise), the same kernels
//! (`__kernel_sin` with its tail, `__kernel_cos`), and chooses the quadrant by selects. Larger
//! angles, infinities and NaN go to [`libm::sincos`].
//!
//! It is libm's algorithm with one reduction everywhere, so its error bound is libm's (under
//! 1 ulp); against [`libm::sincos`] it differs by at most one unit in the last place, on some
//! angles below 9π/4 (the test below counts how many and bounds the difference).

use std::ops::{Add, Mul, Sub};
use wide::f64x2;

/// `1.5 / ε`: added and subtracted, rounds to an integer (round to nearest).
const TO_INT: f64 = 1.5 / f64::EPSILON;
/// 2/π (FreeBSD's constants, by their bits).
const INV_PIO2: f64 = f64::from_bits(0x3fe45f306dc9c883); // 0.6366197723675814
/// The first 33 bits of π/2, and π/2 − PIO2_1.
const PIO2_1: f64 = f64::from_bits(0x3ff921fb54400000); // 1.5707963267341256
const PIO2_1T: f64 = f64::from_bits(0x3dd0b4611a626331); // 6.077100506506192e-11
/// The next 33 bits, and the rest.
const PIO2_2: f64 = f64::from_bits(0x3dd0b4611a600000); // 6.077100506303966e-11
const PIO2_2T: f64 = f64::from_bits(0x3ba3198a2e037073); // 2.0222662487959506e-21
/// The next 33 bits, and the rest.
const PIO2_3: f64 = f64::from_bits(0x3ba3198a2e000000); // 2.0222662487111665e-21
const PIO2_3T: f64 = f64::from_bits(0x397b839a252049c1); // 8.4784276603689e-32
/// The high word of 2⁻²⁷·√2: below it, sin x rounds to x and cos x to 1.
const TINY_HIGH_WORD: u32 = 0x3e46_a09e;
/// The high word of 2²⁰·π/2: below it the medium reduction holds.
const MEDIUM_HIGH_WORD: u32 = 0x4139_21fb;

/// `(sin x, cos x)` (see the module documentation).
#[inline(always)]
pub(crate) fn sin_cos(x: f64) -> (f64, f64) {
    let high = high_word(x);
    if high < TINY_HIGH_WORD {
        // libm's answer below 2⁻²⁷·√2 (a spindle or table at zero): sin x = x, cos x = 1.
        return (x, 1.0);
    }
    if high >= MEDIUM_HIGH_WORD {
        return libm::sincos(x);
    }
    let (n, y0, y1) = reduce(x, high);
    quadrant(n, kernel_sin(y0, y1), kernel_cos(y0, y1))
}

/// Whether [`sin_cos`] takes `x` through its reduction (neither below 2⁻²⁷·√2 nor from
/// 2²⁰·π/2 on, nor infinite or NaN): the angles [`sin_cos_pair`] takes.
#[inline(always)]
pub(crate) fn is_medium(x: f64) -> bool {
    (TINY_HIGH_WORD..MEDIUM_HIGH_WORD).contains(&high_word(x))
}

/// [`sin_cos`] of two angles that [`is_medium`] accepts: lane by lane the same operations in
/// the same order, so the same bits, on two-lane vectors ([`f64x2`]: one SSE2 instruction
/// for both rotary axes where the scalar code took two). When either lane's first reduction
/// cancels, both go through [`sin_cos`].
#[inline(always)]
pub(crate) fn sin_cos_pair(x: [f64; 2]) -> [(f64, f64); 2] {
    let FirstRound { f_n, r, w, y0 } = first_round(f64x2::new(x));
    let y0_lanes = y0.to_array();
    if cancelled(high_word(x[0]), y0_lanes[0]) || cancelled(high_word(x[1]), y0_lanes[1]) {
        return x.map(sin_cos);
    }
    let y1 = (r - y0) - w;
    let (s, c) = (kernel_sin(y0, y1).to_array(), kernel_cos(y0, y1).to_array());
    let n = f_n.to_array();
    [
        quadrant(n[0] as i32, s[0], c[0]),
        quadrant(n[1] as i32, s[1], c[1]),
    ]
}

/// The arithmetic the kernels use, on one angle (`f64`) or two ([`f64x2`]): the same
/// operations lane by lane.
trait Lanes: Copy + From<f64> + Add<Output = Self> + Sub<Output = Self> + Mul<Output = Self> {}

impl<T> Lanes for T where T: Copy + From<f64> + Add<Output = T> + Sub<Output = T> + Mul<Output = T> {}

/// The first round of the medium reduction: `n = rint(x·2/π)` (as `f_n`), `r = x − n·PIO2_1`,
/// `w = n·PIO2_1T` and `y0 = r − w`.
#[derive(Clone, Copy)]
struct FirstRound<T> {
    f_n: T,
    r: T,
    w: T,
    y0: T,
}

#[inline(always)]
fn first_round<T: Lanes>(x: T) -> FirstRound<T> {
    let c = T::from;
    let f_n = x * c(INV_PIO2) + c(TO_INT) - c(TO_INT);
    let (r, w) = (x - f_n * c(PIO2_1), f_n * c(PIO2_1T));
    FirstRound {
        f_n,
        r,
        w,
        y0: r - w,
    }
}

/// Whether the first round cancelled (`y0` more than 16 binary orders below `x`, whose high
/// word is `high`): the reduction needs a second part of π/2.
#[inline(always)]
fn cancelled(high: u32, y0: f64) -> bool {
    ((high >> 20) as i32) - exponent(y0) > 16
}

/// The high word of `|x|`.
#[inline(always)]
fn high_word(x: f64) -> u32 {
    ((x.to_bits() >> 32) as u32) & 0x7fff_ffff
}

/// The biased exponent of `y`.
#[inline(always)]
fn exponent(y: f64) -> i32 {
    ((y.to_bits() >> 52) & 0x7ff) as i32
}

/// `(sin, cos)` of `n·π/2 + y` from `s = sin y` and `c = cos y`: quadrant `n mod 4` gives
/// (s, c), (c, −s), (−s, −c), (−c, s), by selects and sign bits.
#[inline(always)]
fn quadrant(n: i32, s: f64, c: f64) -> (f64, f64) {
    let odd = n & 1 != 0;
    let (sin, cos) = (if odd { c } else { s }, if odd { s } else { c });
    let sin_sign = ((n as u64 >> 1) & 1) << 63;
    let cos_sign = (((n as u64).wrapping_add(1) >> 1) & 1) << 63;
    (
        f64::from_bits(sin.to_bits() ^ sin_sign),
        f64::from_bits(cos.to_bits() ^ cos_sign),
    )
}

/// `x = n·π/2 + y0 + y1` for `|x| < 2²⁰·π/2` (`high`: the high word of `|x|`).
#[inline(always)]
fn reduce(x: f64, high: u32) -> (i32, f64, f64) {
    let FirstRound {
        f_n,
        mut r,
        mut w,
        mut y0,
    } = first_round(x);
    let n = f_n as i32;
    let ex = (high >> 20) as i32;
    // One more round with the next part of π/2 and its rest: (r, w, y0) from r.
    let round = |r: f64, part: f64, rest: f64| {
        let w = f_n * part;
        let next = r - w;
        let w = f_n * rest - ((r - next) - w);
        (next, w, next - w)
    };
    if cancelled(high, y0) {
        // The first part cancelled: a second round, good to 118 bits.
        (r, w, y0) = round(r, PIO2_2, PIO2_2T);
        if ex - exponent(y0) > 49 {
            // A third, good to 151 bits.
            (r, w, y0) = round(r, PIO2_3, PIO2_3T);
        }
    }
    (n, y0, (r - y0) - w)
}

/// sin(y0 + y1) on [−π/4, π/4] (`__kernel_sin` with its tail `y1`).
#[inline(always)]
fn kernel_sin<T: Lanes>(x: T, y: T) -> T {
    const S1: f64 = f64::from_bits(0xbfc5555555555549); // -0.16666666666666632
    const S2: f64 = f64::from_bits(0x3f8111111110f8a6); // 0.00833333333332249
    const S3: f64 = f64::from_bits(0xbf2a01a019c161d5); // -0.0001984126982985795
    const S4: f64 = f64::from_bits(0x3ec71de357b1fe7d); // 2.7557313707070068e-06
    const S5: f64 = f64::from_bits(0xbe5ae5e68a2b9ceb); // -2.5050760253406863e-08
    const S6: f64 = f64::from_bits(0x3de5d93a5acfd57c); // 1.58969099521155e-10
    let c = T::from;
    let z = x * x;
    let w = z * z;
    let r = c(S2) + z * (c(S3) + z * c(S4)) + z * w * (c(S5) + z * c(S6));
    let v = z * x;
    x - ((z * (c(0.5) * y - v * r) - y) - v * c(S1))
}

/// cos(y0 + y1) on [−π/4, π/4] (`__kernel_cos`).
#[inline(always)]
fn kernel_cos<T: Lanes>(x: T, y: T) -> T {
    const C1: f64 = f64::from_bits(0x3fa555555555554c); // 0.0416666666666666
    const C2: f64 = f64::from_bits(0xbf56c16c16c15177); // -0.001388888888887411
    const C3: f64 = f64::from_bits(0x3efa01a019cb1590); // 2.480158728947673e-05
    const C4: f64 = f64::from_bits(0xbe927e4f809c52ad); // -2.7557314351390663e-07
    const C5: f64 = f64::from_bits(0x3e21ee9ebdb4b1c4); // 2.087572321298175e-09
    const C6: f64 = f64::from_bits(0xbda8fae9be8838d4); // -1.1359647557788195e-11
    let c = T::from;
    let z = x * x;
    let w = z * z;
    let r = z * (c(C1) + z * (c(C2) + z * c(C3))) + w * w * (c(C4) + z * (c(C5) + z * c(C6)));
    let hz = c(0.5) * z;
    let w = c(1.0) - hz;
    w + (((c(1.0) - w) - hz) + (z * r - x * y))
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::math::seeded_rng;
    use rand::RngExt;

    /// Units in the last place between two finite values of the same sign (0 when equal).
    fn ulps(a: f64, b: f64) -> u64 {
        if a == b {
            return 0;
        }
        assert_eq!(
            a.is_sign_negative(),
            b.is_sign_negative(),
            "{a} against {b}"
        );
        a.to_bits().abs_diff(b.to_bits())
    }

    /// Against libm (under 1 ulp of the true value itself): at most one ulp apart on a million
    /// angles over ±3 turns and over ±2²¹·π/2 (the fallback), exactly at the reduction's edges
    /// (multiples of π/4, where the branches of libm change), and the same at zero, ±π/2 and
    /// the special values. A wrong constant or quadrant gives differences of whole units of
    /// the value, not of its last bit.
    #[test]
    fn within_one_ulp_of_libm_and_equal_on_most_angles() {
        let mut rng = seeded_rng(1, "sin_cos");
        let mut angles: Vec<f64> = (0..1_000_000)
            .map(|k| {
                let turn = std::f64::consts::TAU;
                if k % 10 == 0 {
                    rng.random_range(-4e6..4e6)
                } else {
                    rng.random_range(-3.0 * turn..3.0 * turn)
                }
            })
            .collect();
        for k in -40..=40 {
            let edge = f64::from(k) * std::f64::consts::FRAC_PI_4;
            angles.extend([edge, edge.next_up(), edge.next_down()]);
        }
        let mut differing = 0;
        for &x in &angles {
            let (s, c) = sin_cos(x);
            let (ls, lc) = libm::sincos(x);
            let worst = ulps(s, ls).max(ulps(c, lc));
            assert!(worst <= 1, "{x}: ({s}, {c}) against libm's ({ls}, {lc})");
            differing += usize::from(worst > 0);
        }
        // The differences come from the angles below 9π/4 that libm reduces otherwise.
        assert!(
            differing < angles.len() / 100,
            "{differing} of {}",
            angles.len()
        );
        for x in [
            0.0,
            -0.0,
            1e-300,
            std::f64::consts::FRAC_PI_2,
            -std::f64::consts::PI,
        ] {
            let (s, c) = sin_cos(x);
            assert!(ulps(s, x.sin()) <= 1 && ulps(c, x.cos()) <= 1, "{x}");
        }
        assert_eq!(sin_cos(0.0), (0.0, 1.0));
        // Two at a time, the same bits as one at a time (the medium angles, in pairs).
        let medium: Vec<f64> = angles.iter().copied().filter(|&x| is_medium(x)).collect();
        assert!(medium.len() > angles.len() * 9 / 10);
        for pair in medium.chunks_exact(2) {
            let both = sin_cos_pair([pair[0], pair[1]]);
            for (x, (s, c)) in pair.iter().zip(both) {
                let (one_s, one_c) = sin_cos(*x);
                assert_eq!(
                    (s.to_bits(), c.to_bits()),
                    (one_s.to_bits(), one_c.to_bits()),
                    "{x}"
                );
            }
        }
        for x in [f64::NAN, f64::INFINITY, f64::NEG_INFINITY] {
            let (s, c) = sin_cos(x);
            assert!(s.is_nan() && c.is_nan(), "{x}");
        }
    }
}

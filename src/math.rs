//! Scalar, vector and pose types, small-motion helpers, unit conversions and a 1-D minimiser.
//!
//! Everything inside mtwin is SI (m, rad, s) in `f64`; files and the command line use mm, µm,
//! µrad and degrees, converted here and only here. Poses are rigid transforms named
//! `a_from_b`: `a_from_b * p_b = p_a`.

use glam::{DAffine3, DMat3, DVec3};
use rand::SeedableRng;
use rand_chacha::ChaCha8Rng;
use sha2::{Digest, Sha256};

/// The scalar of the metrology path. f32 would give 0.06–0.12 µm at 1 m, the size of the
/// errors mtwin studies.
pub type Real = f64;
/// A 3-vector (position in m, direction, or rotation vector in rad).
pub type Vector = DVec3;
/// A 3×3 rotation matrix.
pub type Rotation = DMat3;
/// A rigid transform `a_from_b` (rotation and translation in m).
pub type Pose = DAffine3;

/// Metres per millimetre.
pub const M_PER_MM: Real = 1e-3;
/// Metres per micrometre.
pub const M_PER_UM: Real = 1e-6;
/// Radians per microradian.
pub const RAD_PER_URAD: Real = 1e-6;
/// Radians per degree.
pub const RAD_PER_DEG: Real = std::f64::consts::PI / 180.0;
/// Radians per arc-second.
pub const RAD_PER_ARCSEC: Real = std::f64::consts::PI / (180.0 * 3600.0);

/// The inverse of a rigid transform (rotation transposed, not a general matrix inverse).
pub fn rigid_inverse(a_from_b: &Pose) -> Pose {
    let b_from_a_rotation = a_from_b.matrix3.transpose();
    Pose::from_mat3_translation(
        b_from_a_rotation,
        -(b_from_a_rotation * a_from_b.translation),
    )
}

/// The exact rigid transform of a small motion: translation `delta` (m) after the rotation
/// whose rotation vector is `epsilon` (rad).
///
/// The rotation vector (exponential map) treats the three angles symmetrically, so there is no
/// order of elementary rotations to agree on; to first order it is `I + [epsilon]×`.
pub fn small_motion(delta: Vector, epsilon: Vector) -> Pose {
    Pose::from_mat3_translation(rotation_from_vector(epsilon), delta)
}

/// The rotation whose rotation vector is `epsilon` (rad), by Rodrigues' formula
/// `R = I + a·[ε]× + b·[ε]×²` with `a = sin θ / θ` and `b = (1 − cos θ) / θ²`, `θ = |ε|`.
///
/// Below θ = 10⁻³ rad (every error motion mtwin models), `a` and `b` come from their Taylor
/// series to θ⁴: the first term left out is below 2·10⁻²² of the one kept, far under f64's
/// rounding, so the matrix is exact to rounding without a square root or a sine.
pub fn rotation_from_vector(epsilon: Vector) -> Rotation {
    let theta_squared = epsilon.length_squared();
    let (a, b) = if theta_squared < 1e-6 {
        let t2 = theta_squared;
        (
            // Products with the reciprocals rather than divisions (slow, and on the chain's
            // critical path): the terms they round are below 2e-7 of the 1 or ½ they are
            // added to, so `a` and `b` move by an ulp at most.
            1.0 - t2 * (1.0 / 6.0) * (1.0 - t2 * (1.0 / 20.0)),
            0.5 - t2 * (1.0 / 24.0) * (1.0 - t2 * (1.0 / 30.0)),
        )
    } else {
        let theta = theta_squared.sqrt();
        let half_sin = (0.5 * theta).sin();
        (
            theta.sin() / theta,
            2.0 * half_sin * half_sin / theta_squared,
        )
    };
    let Vector { x, y, z } = epsilon;
    let (xx, yy, zz) = (b * x * x, b * y * y, b * z * z);
    let (xy, xz, yz) = (b * x * y, b * x * z, b * y * z);
    let (ax, ay, az) = (a * x, a * y, a * z);
    Rotation::from_cols(
        Vector::new(1.0 - (yy + zz), xy + az, xz - ay),
        Vector::new(xy - az, 1.0 - (xx + zz), yz + ax),
        Vector::new(xz + ay, yz - ax, 1.0 - (xx + yy)),
    )
}

/// URDF `rpy` (fixed-axis roll about x, then pitch about y, then yaw about z) as a rotation
/// matrix: `Rz(yaw) · Ry(pitch) · Rx(roll)`.
pub fn rotation_from_rpy(rpy: [Real; 3]) -> Rotation {
    DMat3::from_rotation_z(rpy[2]) * DMat3::from_rotation_y(rpy[1]) * DMat3::from_rotation_x(rpy[0])
}

/// A deterministic random generator for one named component of one scenario.
///
/// The stream depends only on the scenario seed and the component name (hashed with
/// SHA-256), so adding a component never changes the numbers another one draws.
pub fn seeded_rng(seed: u64, component: &str) -> ChaCha8Rng {
    let mut hasher = Sha256::new();
    hasher.update(seed.to_le_bytes());
    hasher.update(component.as_bytes());
    let digest = hasher.finalize();
    let mut key = [0u8; 32];
    key.copy_from_slice(&digest);
    ChaCha8Rng::from_seed(key)
}

/// A standard normal draw (Box–Muller on two uniforms), so that noise depends only on the
/// seeded stream it comes from.
pub fn standard_normal(rng: &mut ChaCha8Rng) -> Real {
    use rand::RngExt;
    let u1: Real = 1.0 - rng.random::<Real>(); // (0, 1]: ln is finite
    let u2: Real = rng.random::<Real>();
    (-2.0 * u1.ln()).sqrt() * (std::f64::consts::TAU * u2).cos()
}

/// Lower-case hexadecimal SHA-256 of some bytes (model and scenario identity in manifests).
pub fn sha256_hex(bytes: &[u8]) -> String {
    Sha256::digest(bytes)
        .iter()
        .map(|byte| format!("{byte:02x}"))
        .collect()
}

/// `value` with a fixed number of decimals for a file, never as `-0.000…` (a value that rounds
/// to zero is written as zero whatever its sign).
pub fn fixed(value: Real, decimals: usize) -> String {
    let text = format!("{value:.decimals$}");
    if text.starts_with('-') && text[1..].chars().all(|c| c == '0' || c == '.') {
        text[1..].to_string()
    } else {
        text
    }
}

/// `value` rounded to a multiple of `resolution`, as an instrument with that resolution reads
/// it (unchanged for a resolution of zero).
pub fn quantise(value: Real, resolution: Real) -> Real {
    if resolution > 0.0 {
        (value / resolution).round() * resolution
    } else {
        value
    }
}

/// `value` as a person writes it: at most `decimals` decimals, no trailing zeros (`150`,
/// `0.5`, `-2.25`).
pub fn trimmed(value: Real, decimals: usize) -> String {
    let text = fixed(value, decimals);
    if !text.contains('.') {
        return text;
    }
    let text = text.trim_end_matches('0').trim_end_matches('.');
    if text == "-0" {
        "0".into()
    } else {
        text.to_string()
    }
}

/// `value` for a message: as Rust writes it (`150`, `0.25`) when that is short, else in
/// scientific notation (`1.7976931348623157e308`, not 309 digits).
pub fn readable(value: Real) -> String {
    let plain = format!("{value}");
    if plain.len() > 24 {
        format!("{value:e}")
    } else {
        plain
    }
}

/// `text` with every decimal number longer than 24 characters (the way Rust writes 1e300)
/// rewritten in scientific notation: messages quote what they were given, and a value of 300
/// digits hides the message. A run of digits inside a word or a path (`run_123…`, `/123…/`)
/// is not a number and is left alone.
pub fn shorten_numbers(text: &str) -> String {
    let bytes = text.as_bytes();
    let is_part = |b: u8| b.is_ascii_digit() || b == b'.';
    let mut out = String::with_capacity(text.len());
    let mut i = 0;
    while i < bytes.len() {
        let starts_number = bytes[i].is_ascii_digit()
            && (i == 0
                || !(bytes[i - 1].is_ascii_alphanumeric() || b"_/.".contains(&bytes[i - 1])));
        if !starts_number {
            let next = text[i..].chars().next().map_or(1, char::len_utf8);
            out.push_str(&text[i..i + next]);
            i += next;
            continue;
        }
        let mut end = i;
        while end < bytes.len() && is_part(bytes[end]) {
            end += 1;
        }
        let token = text[i..end].trim_end_matches('.');
        let end = i + token.len();
        let inside_word =
            end < bytes.len() && (bytes[end].is_ascii_alphabetic() || b"_/".contains(&bytes[end]));
        match token.parse::<Real>() {
            Ok(value) if token.len() > 24 && !inside_word => out.push_str(&format!("{value:e}")),
            _ => out.push_str(token),
        }
        i = end;
    }
    out
}

/// The dot product Σ aᵢbᵢ of two slices of one length, summed in order.
pub fn dot(a: &[Real], b: &[Real]) -> Real {
    a.iter().zip(b).map(|(x, y)| x * y).sum()
}

/// The minimum of `f` over `[low, high]` by golden-section search (`iterations` shrinks the
/// bracket by 0.618 each); returns (argument, value).
pub fn golden_minimum(
    mut f: impl FnMut(Real) -> Real,
    mut low: Real,
    mut high: Real,
    iterations: usize,
) -> (Real, Real) {
    let ratio = (5.0_f64.sqrt() - 1.0) / 2.0;
    let mut a = high - ratio * (high - low);
    let mut b = low + ratio * (high - low);
    let (mut fa, mut fb) = (f(a), f(b));
    for _ in 0..iterations {
        if fa <= fb {
            high = b;
            b = a;
            fb = fa;
            a = high - ratio * (high - low);
            fa = f(a);
        } else {
            low = a;
            a = b;
            fa = fb;
            b = low + ratio * (high - low);
            fb = f(b);
        }
    }
    if fa <= fb { (a, fa) } else { (b, fb) }
}

/// The minimum of `f` over `[low, high]` by Brent's method (R. P. Brent, *Algorithms for
/// Minimization without Derivatives*, 1973, ch. 5): parabolic interpolation through the three
/// best points where it steps well inside the bracket, a golden-section step where it does
/// not. It stops when the best point is within `tolerance` (absolute, in the argument) of the
/// minimum's bracket middle, i.e. the bracket is narrower than about 4·`tolerance`; on a smooth
/// minimum that takes 6–12 evaluations where golden section needs 20 for 0.618²⁰ of the
/// bracket, and on a function that is not smooth (a step, a flat stretch) it falls back to
/// golden section and is never slower than that by more than a few evaluations. At most
/// `max_evaluations` evaluations of `f`. Returns (argument, value) of the best point seen.
///
/// ```
/// use mtwin::math::brent_minimum;
/// let (x, fx) = brent_minimum(|x| (x - 0.3).powi(2) + 1.0, -1.0, 2.0, 1e-8, 100);
/// assert!((x - 0.3).abs() < 1e-7 && (fx - 1.0).abs() < 1e-12);
/// ```
pub fn brent_minimum(
    mut f: impl FnMut(Real) -> Real,
    low: Real,
    high: Real,
    tolerance: Real,
    max_evaluations: usize,
) -> (Real, Real) {
    const GOLDEN: Real = 0.381_966_011_250_105_1; // (3 − √5)/2
    let (mut a, mut b) = if low <= high {
        (low, high)
    } else {
        (high, low)
    };
    let mut x = a + GOLDEN * (b - a);
    let (mut w, mut v) = (x, x);
    let mut fx = f(x);
    let (mut fw, mut fv) = (fx, fx);
    // `d` is the last step, `e` the one before it.
    let (mut d, mut e): (Real, Real) = (0.0, 0.0);
    let tol = tolerance.max(Real::MIN_POSITIVE);
    for _ in 1..max_evaluations.max(1) {
        let middle = 0.5 * (a + b);
        if (x - middle).abs() <= 2.0 * tol - 0.5 * (b - a) {
            break;
        }
        let mut golden = true;
        if e.abs() > tol {
            // The parabola through (v, fv), (w, fw), (x, fx): its vertex is x + p/q.
            let r = (x - w) * (fx - fv);
            let mut q = (x - v) * (fx - fw);
            let mut p = (x - v) * q - (x - w) * r;
            q = 2.0 * (q - r);
            if q > 0.0 {
                p = -p;
            } else {
                q = -q;
            }
            // Accept it when it lies inside the bracket and moves less than half the step
            // before last (so the steps shrink).
            if p.abs() < (0.5 * q * e).abs() && p > q * (a - x) && p < q * (b - x) {
                e = d;
                d = p / q;
                let u = x + d;
                if u - a < 2.0 * tol || b - u < 2.0 * tol {
                    d = tol.copysign(middle - x);
                }
                golden = false;
            }
        }
        if golden {
            e = if x >= middle { a - x } else { b - x };
            d = GOLDEN * e;
        }
        let u = if d.abs() >= tol {
            x + d
        } else {
            x + tol.copysign(d)
        };
        let fu = f(u);
        if fu <= fx {
            if u >= x {
                a = x;
            } else {
                b = x;
            }
            (v, fv) = (w, fw);
            (w, fw) = (x, fx);
            (x, fx) = (u, fu);
        } else {
            if u < x {
                a = u;
            } else {
                b = u;
            }
            if fu <= fw || w == x {
                (v, fv) = (w, fw);
                (w, fw) = (u, fu);
            } else if fu <= fv || v == x || v == w {
                (v, fv) = (u, fu);
            }
        }
    }
    (x, fx)
}

/// One step of a first-order lag with time constant `tau` (s) following a signal that goes
/// linearly from `from` to `to` over `dt` seconds (exact first-order hold): with
/// `r = (to − from)/dt`, the lagged value `lagged` becomes `to − τr + (lagged − from + τr)·e^(−dt/τ)`.
/// With `tau` zero there is no lag: the value is `to`. With `dt` zero (two readings at the
/// same time stamp, as in files that carry one stamp per run) no time passes, so the lagged
/// value holds: `lagged`, the limit of the formula as `dt → 0`. A lag that caught up at once
/// there would restart at every reading of such a file and could not act at all.
///
/// ```
/// use mtwin::math::first_order_lag;
/// // No time passes: the state holds, whatever the input did.
/// assert_eq!(first_order_lag(20.0, 20.0, 25.0, 0.0, 600.0), 20.0);
/// // No lag: the input itself.
/// assert_eq!(first_order_lag(20.0, 20.0, 25.0, 60.0, 0.0), 25.0);
/// ```
pub fn first_order_lag(lagged: Real, from: Real, to: Real, dt: Real, tau: Real) -> Real {
    match (tau > 0.0, dt > 0.0) {
        (false, _) => to,
        (true, true) => {
            let ramp = tau * (to - from) / dt;
            to - ramp + (lagged - from + ramp) * (-dt / tau).exp()
        }
        (true, false) => lagged,
    }
}

/// Shortest half-width (s) of the window of [`local_rates`].
pub const RATE_HALF_WINDOW_S: Real = 300.0;

/// The rate of change (unit/s) of a sampled signal at each of its samples, as a measured
/// record allows it: the slope of the least-squares line through the samples within a
/// half-width `h` of the sample's time, `h = max(5 min, 1.5·m)` with `m` the median of the
/// positive intervals between samples (so a sparse record, one sample in 15 min, still has
/// neighbours). No rate is drawn across a gap longer than `h` (a laser's idle time between
/// runs, when nothing is read): the window of a sample at a run's end holds only that run's.
/// A sample alone in its window (or whose window spans no time) has rate 0.
///
/// `times` (s) must be non-decreasing (repeated times are allowed); `values` has one value per
/// time. Simplified: a line, so a rate that changes within the window is averaged over it,
/// and near a gap or the record's ends the window is one-sided.
///
/// ```
/// use mtwin::math::local_rates;
/// // A ramp of 0.01 unit/s, read every 10 s, then a 20-min gap and a flat stretch.
/// let times = [0.0, 10.0, 20.0, 30.0, 1230.0, 1240.0, 1250.0];
/// let values = [1.0, 1.1, 1.2, 1.3, 5.0, 5.0, 5.0];
/// let rates = local_rates(&times, &values);
/// assert!(rates[..4].iter().all(|r| (r - 0.01).abs() < 1e-12));
/// assert!(rates[4..].iter().all(|r| r.abs() < 1e-12));
/// ```
pub fn local_rates(times: &[Real], values: &[Real]) -> Vec<Real> {
    local_lines(times, values)
        .into_iter()
        .map(|(_, rate)| rate)
        .collect()
}

/// The least-squares line of [`local_rates`] at each sample: its value there (the signal
/// smoothed over the window) and its slope (unit/s).
pub fn local_lines(times: &[Real], values: &[Real]) -> Vec<(Real, Real)> {
    let n = times.len();
    assert_eq!(n, values.len(), "one value per time");
    let mut intervals: Vec<Real> = times
        .windows(2)
        .map(|w| w[1] - w[0])
        .filter(|d| *d > 0.0)
        .collect();
    intervals.sort_by(Real::total_cmp);
    let typical = intervals.get(intervals.len() / 2).copied().unwrap_or(0.0);
    let half = RATE_HALF_WINDOW_S.max(1.5 * typical);
    let mut lines = vec![(0.0, 0.0); n];
    let (mut lo, mut hi) = (0, 0);
    for i in 0..n {
        while times[i] - times[lo] > half {
            lo += 1;
        }
        while hi < n && times[hi] - times[i] <= half {
            hi += 1;
        }
        let count = (hi - lo) as Real;
        let mean_t = times[lo..hi].iter().map(|t| t - times[i]).sum::<Real>() / count;
        let mean_v = values[lo..hi].iter().sum::<Real>() / count;
        let (mut stt, mut stv) = (0.0, 0.0);
        for j in lo..hi {
            let dt = times[j] - times[i] - mean_t;
            stt += dt * dt;
            stv += dt * (values[j] - mean_v);
        }
        let rate = if stt > 0.0 { stv / stt } else { 0.0 };
        // The line through the window's centroid, at this sample's time (offset 0).
        lines[i] = (mean_v - rate * mean_t, rate);
    }
    lines
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn huge_numbers_in_messages_become_scientific() {
        let max = format!("{}", f64::MAX);
        assert_eq!(max.len(), 309, "Rust writes f64::MAX with every digit");
        let message = format!("ballbar.calibration_um: expected at most 1000, got {max}.");
        assert_eq!(
            shorten_numbers(&message),
            "ballbar.calibration_um: expected at most 1000, got 1.7976931348623157e308."
        );
        assert_eq!(readable(f64::MAX), "1.7976931348623157e308");
        assert_eq!(readable(-0.25), "-0.25");
        // Short numbers, digits in words and paths, and non-ASCII text pass unchanged.
        let path = format!("/tmp/run_{}/x.csv: 150 µm at 0.5°", "1".repeat(30));
        assert_eq!(shorten_numbers(&path), path);
    }

    #[test]
    fn golden_section_finds_a_parabola_minimum() {
        let (x, fx) = golden_minimum(|x| (x - 0.3).powi(2) + 1.0, -1.0, 2.0, 60);
        assert!((x - 0.3).abs() < 1e-6 && (fx - 1.0).abs() < 1e-12);
    }

    /// Brent's method against closed-form minima: smooth ones it reaches to its tolerance in
    /// far fewer evaluations than golden section's 20; a minimum at the bracket's end it
    /// approaches to the tolerance; a step function (no parabola to fit) it still brackets,
    /// in no more evaluations than golden section to the same width plus a few.
    #[test]
    fn brent_reaches_closed_form_minima_in_few_evaluations() {
        let counted = |f: &dyn Fn(Real) -> Real, low: Real, high: Real, tol: Real| {
            let mut n = 0;
            let (x, fx) = brent_minimum(
                |x| {
                    n += 1;
                    f(x)
                },
                low,
                high,
                tol,
                200,
            );
            (x, fx, n)
        };
        // cosh(x − 1.2) + 0.1·(x − 1.2)⁴: minimum 1 at 1.2.
        let smooth = |x: Real| (x - 1.2).cosh() + 0.1 * (x - 1.2).powi(4);
        let (x, fx, n) = counted(&smooth, 0.0, 3.0, 1e-6);
        assert!((x - 1.2).abs() < 4e-6, "{x}");
        assert!((fx - 1.0).abs() < 1e-10);
        assert!(n <= 12, "{n} evaluations");
        // e^x − 2x: minimum at ln 2, off-centre in the bracket.
        let (x, _, n) = counted(&|x: Real| x.exp() - 2.0 * x, -3.0, 1.0, 1e-7);
        assert!((x - 2.0_f64.ln()).abs() < 4e-7, "{x}");
        assert!(n <= 14, "{n} evaluations");
        // Monotone: the minimum is the upper end, approached to the tolerance.
        let (x, _, _) = counted(&|x: Real| -x, 0.0, 1.0, 1e-6);
        assert!(1.0 - x < 4e-6, "{x}");
        // A step at 0.37 (flat either side, lower to its right): the best point found lies
        // right of the step and within the final bracket of it.
        let step = |x: Real| if x < 0.37 { 1.0 } else { 0.0 };
        let (x, fx, n) = counted(&step, 0.0, 1.0, 1e-5);
        assert_eq!(fx, 0.0);
        assert!(x >= 0.37);
        // Golden section to 4e-5 of the bracket takes ln(4e-5)/ln(0.618) ≈ 21 steps.
        assert!(n <= 21 + 8, "{n} evaluations");
    }

    /// Rodrigues with the series below 1 mrad against glam's quaternion exponential (an
    /// independent construction: half-angle sine and cosine, then the quaternion's matrix),
    /// from 1 nrad to 1 rad on both sides of the threshold.
    #[test]
    fn rotation_from_vector_matches_the_quaternion_exponential() {
        let directions = [
            Vector::new(0.3, -0.8, 0.52),
            Vector::new(-0.9, 0.1, 0.42),
            Vector::Z,
        ];
        for direction in directions {
            let direction = direction.normalize();
            for exponent in -18..=0 {
                let theta = 10f64.powf(exponent as Real / 2.0);
                for scale in [0.999, 1.0, 1.001] {
                    let epsilon = direction * theta * scale;
                    let ours = rotation_from_vector(epsilon);
                    let quaternion = DMat3::from_quat(glam::DQuat::from_scaled_axis(epsilon));
                    let difference = (ours - quaternion).to_cols_array();
                    let worst = difference.iter().fold(0.0_f64, |m, d| m.max(d.abs()));
                    assert!(worst < 4e-16, "θ = {theta:e}: {worst:e}");
                    let orthogonality = (ours * ours.transpose() - DMat3::IDENTITY).to_cols_array();
                    assert!(orthogonality.iter().all(|d| d.abs() < 4e-16));
                }
            }
        }
        assert_eq!(rotation_from_vector(Vector::ZERO), DMat3::IDENTITY);
    }

    #[test]
    fn rigid_inverse_composes_to_identity() {
        let pose = Pose::from_mat3_translation(
            rotation_from_rpy([0.3, -0.2, 1.1]),
            Vector::new(0.1, -0.4, 2.0),
        );
        let product = pose * rigid_inverse(&pose);
        assert!(product.abs_diff_eq(Pose::IDENTITY, 1e-15));
    }

    #[test]
    fn small_motion_is_first_order_skew() {
        // R ≈ I + [ε]×: the off-diagonal terms equal the rotation vector components to
        // within the second-order term εᵢεⱼ/2 ≤ |ε|²/2 = 7e-12.
        let e = Vector::new(1e-6, -2e-6, 3e-6);
        let m = small_motion(Vector::ZERO, e).matrix3;
        assert!((m.y_axis.z - e.x).abs() < 1e-11); // R[2][1] = εx
        assert!((m.z_axis.x - e.y).abs() < 1e-11); // R[0][2] = εy
        assert!((m.x_axis.y - e.z).abs() < 1e-11); // R[1][0] = εz
        // and the skew part is antisymmetric to first order
        assert!((m.z_axis.y + e.x).abs() < 1e-11); // R[1][2] = -εx
    }

    #[test]
    fn fixed_never_writes_negative_zero() {
        assert_eq!(fixed(-1e-9, 6), "0.000000");
        assert_eq!(fixed(-1.5e-6, 6), "-0.000002");
        assert_eq!(fixed(1.23456, 2), "1.23");
    }

    #[test]
    fn seeded_rng_depends_on_seed_and_name_only() {
        use rand::RngExt;
        let a: u64 = seeded_rng(7, "laser").random();
        let b: u64 = seeded_rng(7, "laser").random();
        let c: u64 = seeded_rng(7, "ballbar").random();
        let d: u64 = seeded_rng(8, "laser").random();
        assert_eq!(a, b);
        assert_ne!(a, c);
        assert_ne!(a, d);
    }

    /// A quadratic `a + b·t + c·t²` sampled evenly: where the window lies whole inside the
    /// stretch it is symmetric about the sample, and the least-squares slope of a quadratic
    /// over a symmetric window is its derivative `b + 2ct` there exactly (the odd moments
    /// vanish). A second stretch after a gap does not disturb it.
    #[test]
    fn local_rates_are_the_derivative_of_a_quadratic_inside_a_stretch() {
        let (a, b, c) = (20.0, 3e-4, -2e-8);
        let f = |t: Real| a + b * t + c * t * t;
        // 10 s apart for 30 min, then (after a 40-min gap) 10 s apart again.
        let mut times: Vec<Real> = (0..=180).map(|k| 10.0 * k as Real).collect();
        times.extend((0..=180).map(|k| 4200.0 + 10.0 * k as Real));
        let values: Vec<Real> = times.iter().map(|&t| f(t)).collect();
        let rates = local_rates(&times, &values);
        for (i, &t) in times.iter().enumerate() {
            let start = if t < 4200.0 { 0.0 } else { 4200.0 };
            if t - start >= RATE_HALF_WINDOW_S && start + 1800.0 - t >= RATE_HALF_WINDOW_S {
                let exact = b + 2.0 * c * t;
                assert!(
                    (rates[i] - exact).abs() <= 1e-12 * exact.abs(),
                    "t = {t}: {} against {exact}",
                    rates[i]
                );
            }
        }
        // A step across the gap is not a rate: no window reaches across it.
        let mut stepped = values.clone();
        for v in stepped.iter_mut().skip(181) {
            *v += 5.0;
        }
        let with_step = local_rates(&times, &stepped);
        assert!(
            with_step
                .iter()
                .zip(&rates)
                .all(|(x, y)| (x - y).abs() < 1e-12)
        );
    }

    /// A sparse record (one sample every 15 min) widens the window to 1.5 intervals: each
    /// interior sample's rate is the central difference of its neighbours (exact for a line).
    #[test]
    fn local_rates_of_a_sparse_record_use_the_neighbours() {
        let times: Vec<Real> = (0..8).map(|k| 900.0 * k as Real).collect();
        let values: Vec<Real> = times.iter().map(|t| 20.0 + 1e-4 * t).collect();
        for r in local_rates(&times, &values) {
            assert!((r - 1e-4).abs() < 1e-15, "{r}");
        }
        // A sample alone has no rate.
        assert_eq!(local_rates(&[0.0], &[21.0]), vec![0.0]);
        assert_eq!(local_rates(&[5.0, 5.0], &[21.0, 22.0]), vec![0.0, 0.0]);
    }
}

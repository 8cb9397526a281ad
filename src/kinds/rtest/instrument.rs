//! The virtual R-test head: a nest of three (or four) displacement probes in the spindle,
//! reading a precision sphere on the table, and the software that turns the readings into
//! the 3-D displacement of the sphere centre with the nest's own calibration.
//!
//! # Geometry (nest frame = the `tool` frame of the machine)
//!
//! The nest's reference point is the tool tip: where the probe axes meet, and where the sphere
//! centre sits when the readings are zero. Probe `i` has an axis `aᵢ` (unit, from the sphere
//! centre out to the probe); a reading is positive when the sphere pushes the probe in. The
//! three-probe nest has its axes at azimuths 0°, 120°, 240° (about the tool axis, from the
//! tool frame's x) and an elevation of asin(1/√3) = 35.264° above the plane normal to the
//! tool axis, so that they are mutually orthogonal; the fourth probe, when fitted, looks down
//! the tool axis (`a₄ = +z`).
//!
//! # Probe models
//!
//! With the sphere centre displaced by `v` (nest frame) from the reference point:
//!
//! - **flat** tips (the contact R-test of Weikert and of Ibaraki's lab): the face is normal to
//!   the probe axis, so `dᵢ = aᵢ·v` exactly, for as long as the contact stays on the face;
//! - **point** tips (a ball of radius `r` or a non-contact sensor, `r = 0`): the tip moves on
//!   the probe axis and touches the sphere of radius `R` where `|(ρ + d)·aᵢ − v| = ρ`,
//!   `ρ = R + r`, so `dᵢ = aᵢ·v − (ρ − √(ρ² − |v⊥|²))`: the cross-talk `≈ |v⊥|²/2ρ` of Hong and
//!   Ibaraki (2013), with `v⊥` the displacement across the probe axis.
//!
//! Each probe then has a gain error (`(1 + gᵢ)·d`), Gaussian noise and a resolution. Its true
//! axis differs from the nominal one by a direction error (elevation and azimuth).
//!
//! # Software
//!
//! The software knows the nominal axes only, or a sensitivity matrix `M` from the **six-point
//! calibration** (the machine moves the sphere to ±s along X, Y and Z of the nest from the
//! centre; each probe's reading is fitted as `dᵢ = d₀ᵢ + mᵢ·v` by least squares over the seven
//! positions, with `v` the displacement the *commanded* moves give: the calibration trusts the
//! linear axes, as the real one does). It zeroes the readings at the first pose of each test
//! and solves `M·v = d − d_first` (least squares with four probes).
//!
//! Simplifications, stated: the sphere is perfectly round (its form error is not modelled);
//! the probes have no dynamics (their bandwidth is far above the motion); a flat face is large
//! enough for the whole test (the contact never leaves it).

use crate::math::{M_PER_UM, Real, Rotation, Vector, quantise, standard_normal};
use rand_chacha::ChaCha8Rng;

/// The elevation of the probe axes of a three-probe nest: asin(1/√3), which makes them
/// mutually orthogonal.
pub fn orthogonal_elevation() -> Real {
    (1.0 / 3.0_f64.sqrt()).asin()
}

/// The probe tips.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Tip {
    /// A flat face normal to the probe axis: linear, no cross-talk.
    Flat,
    /// A ball of this radius (m) on the probe axis (0: a non-contact point sensor).
    Point {
        /// The tip ball's radius (m).
        radius: Real,
    },
}

/// How the software converts readings into a displacement.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Calibration {
    /// The nominal probe axes and unit gains.
    Nominal,
    /// The six-point calibration with steps of this size (m) along the nest's axes.
    SixPoint {
        /// The step (m).
        step: Real,
    },
}

/// One displacement probe of the nest.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Probe {
    /// The nominal axis (unit, nest frame, from the sphere centre out to the probe).
    pub nominal_axis: Vector,
    /// The true axis (unit, nest frame).
    pub axis: Vector,
    /// Relative gain error: the probe reads `(1 + gain_error)` times its travel.
    pub gain_error: Real,
}

/// The R-test head and the sphere it reads.
#[derive(Clone, Debug, PartialEq)]
pub struct Nest {
    /// The probes, three or four.
    pub probes: Vec<Probe>,
    /// The tips.
    pub tip: Tip,
    /// The sphere's radius (m).
    pub sphere_radius: Real,
    /// The probes' measuring range (m): a reading beyond ± this is an error of the test.
    pub range: Real,
    /// Standard deviation of each reading's noise (m).
    pub noise: Real,
    /// Resolution of each reading (m; 0 for none).
    pub resolution: Real,
    /// How the software converts readings.
    pub calibration: Calibration,
}

/// A probe axis at an azimuth about the tool axis and an elevation above the plane normal to
/// it (rad).
pub fn probe_axis(azimuth: Real, elevation: Real) -> Vector {
    Vector::new(
        elevation.cos() * azimuth.cos(),
        elevation.cos() * azimuth.sin(),
        elevation.sin(),
    )
}

impl Nest {
    /// The nominal axes of a nest of `count` (3 or 4) probes; see the module's geometry.
    pub fn nominal_axes(count: usize) -> Vec<Vector> {
        let elevation = orthogonal_elevation();
        let mut axes: Vec<Vector> = (0..3)
            .map(|i| probe_axis(i as Real * std::f64::consts::TAU / 3.0, elevation))
            .collect();
        if count > 3 {
            axes.push(Vector::Z);
        }
        axes
    }

    /// The exact travel of each probe (m, before gain, noise and resolution) with the sphere
    /// centre at `v` (nest frame) from the reference point, into `out`.
    pub fn travel(&self, v: Vector, out: &mut [Real]) {
        let rho = self.sphere_radius
            + match self.tip {
                Tip::Flat => 0.0,
                Tip::Point { radius } => radius,
            };
        for (probe, d) in self.probes.iter().zip(out.iter_mut()) {
            let along = probe.axis.dot(v);
            *d = match self.tip {
                Tip::Flat => along,
                Tip::Point { .. } => {
                    let across2 = (v.length_squared() - along * along).max(0.0);
                    along - (rho - (rho * rho - across2).max(0.0).sqrt())
                }
            };
        }
    }

    /// What the probes read with the sphere centre at `v` (nest frame): travel, gain, noise
    /// (drawn from `rng` in probe order) and resolution, into `out`.
    pub fn read(&self, v: Vector, rng: &mut ChaCha8Rng, out: &mut [Real]) {
        self.travel(v, out);
        for (probe, d) in self.probes.iter().zip(out.iter_mut()) {
            let noisy = *d * (1.0 + probe.gain_error) + self.noise * standard_normal(rng);
            *d = quantise(noisy, self.resolution);
        }
    }

    /// The software's sensitivity matrix from nominal axes: row `i` is `aᵢ` nominal.
    pub fn nominal_sensitivity(&self) -> Vec<Vector> {
        self.probes.iter().map(|p| p.nominal_axis).collect()
    }
}

/// The software's conversion: readings → the sphere centre's displacement in the nest frame,
/// by the sensitivity rows `m` (one per probe; least squares over four).
#[derive(Clone, Debug, PartialEq)]
pub struct Conversion {
    /// One sensitivity row per probe (reading per displacement, nest frame).
    pub rows: Vec<Vector>,
    /// `(MᵀM)⁻¹`: the solve.
    normal_inverse: Rotation,
}

/// Why the software cannot convert.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
#[error("the probe axes do not span three directions (sensitivity matrix singular)")]
pub struct SingularNest;

impl Conversion {
    /// The conversion by these sensitivity rows.
    pub fn new(rows: Vec<Vector>) -> Result<Conversion, SingularNest> {
        let mut normal = Rotation::ZERO;
        for m in &rows {
            normal += outer(*m, *m);
        }
        if normal.determinant().abs() < 1e-9 {
            return Err(SingularNest);
        }
        Ok(Conversion {
            rows,
            normal_inverse: normal.inverse(),
        })
    }

    /// The displacement of the sphere centre (nest frame) for reading changes `d`.
    pub fn displacement(&self, d: &[Real]) -> Vector {
        let mut rhs = Vector::ZERO;
        for (m, d) in self.rows.iter().zip(d) {
            rhs += *m * *d;
        }
        self.normal_inverse * rhs
    }
}

/// The outer product `a·bᵀ`.
fn outer(a: Vector, b: Vector) -> Rotation {
    Rotation::from_cols(a * b.x, a * b.y, a * b.z)
}

/// The six-point calibration's positions: the centre, then ± `step` along x, y, z of the nest.
pub fn calibration_offsets(step: Real) -> [Vector; 7] {
    [
        Vector::ZERO,
        Vector::X * step,
        -Vector::X * step,
        Vector::Y * step,
        -Vector::Y * step,
        Vector::Z * step,
        -Vector::Z * step,
    ]
}

/// Fits each probe's `dᵢ = d₀ᵢ + mᵢ·v` over the calibration positions `v` (the displacements
/// the commanded moves give) and their readings; returns the rows `mᵢ`.
pub fn fit_sensitivity(positions: &[Vector], readings: &[Vec<Real>]) -> Vec<Vector> {
    let probes = readings.first().map_or(0, Vec::len);
    (0..probes)
        .map(|i| {
            // Least squares for (d₀, m) with the design [1, v]: centre the positions.
            let n = positions.len() as Real;
            let mean_v = positions.iter().copied().sum::<Vector>() / n;
            let mean_d = readings.iter().map(|r| r[i]).sum::<Real>() / n;
            let mut normal = Rotation::ZERO;
            let mut rhs = Vector::ZERO;
            for (v, r) in positions.iter().zip(readings) {
                let c = *v - mean_v;
                normal += outer(c, c);
                rhs += c * (r[i] - mean_d);
            }
            normal.inverse() * rhs
        })
        .collect()
}

/// Micrometres, for messages.
pub(crate) fn um(value: Real) -> Real {
    value / M_PER_UM
}

#[cfg(test)]
mod tests {
    use super::*;

    fn nest(tip: Tip) -> Nest {
        Nest {
            probes: Nest::nominal_axes(3)
                .into_iter()
                .map(|a| Probe {
                    nominal_axis: a,
                    axis: a,
                    gain_error: 0.0,
                })
                .collect(),
            tip,
            sphere_radius: 12.7e-3,
            range: 2e-3,
            noise: 0.0,
            resolution: 0.0,
            calibration: Calibration::Nominal,
        }
    }

    #[test]
    fn the_three_probe_axes_are_orthonormal() {
        let a = Nest::nominal_axes(3);
        for i in 0..3 {
            assert!((a[i].length() - 1.0).abs() < 1e-15);
            for j in i + 1..3 {
                assert!(a[i].dot(a[j]).abs() < 1e-15, "{i}·{j}");
            }
        }
    }

    #[test]
    fn a_point_tip_reads_the_lateral_cross_talk_of_a_curved_surface() {
        // Sphere moved by u across probe 0's axis only: the flat probe reads nothing, the
        // point probe reads −(ρ − √(ρ² − u²)) (Hong & Ibaraki; ≈ u²/2ρ).
        let n_point = nest(Tip::Point { radius: 0.0 });
        let a = n_point.probes[0].axis;
        let across = a.cross(Vector::Z).normalize();
        let mut d = [0.0; 3];
        for u in [20e-6, 0.1e-3, 0.5e-3] {
            n_point.travel(across * u, &mut d);
            let rho: Real = 12.7e-3;
            let expected = -(rho - (rho * rho - u * u).sqrt());
            assert!(
                (d[0] - expected).abs() < 1e-15,
                "{u}: {} vs {expected}",
                d[0]
            );
            assert!((d[0] + u * u / (2.0 * rho)).abs() < 1e-3 * u * u / rho);
            nest(Tip::Flat).travel(across * u, &mut d);
            assert!(d[0].abs() < 1e-18);
        }
    }

    #[test]
    fn the_calibration_recovers_the_true_axes_and_gains() {
        // A direction error of probe 1 and a gain error of probe 2, read through the
        // six-point calibration: the fitted rows are (1 + g)·a_true.
        let mut n = nest(Tip::Flat);
        n.probes[1].axis = probe_axis(
            std::f64::consts::TAU / 3.0 + 2e-3,
            orthogonal_elevation() - 1e-3,
        );
        n.probes[2].gain_error = 5e-3;
        let positions = calibration_offsets(0.5e-3);
        let readings: Vec<Vec<Real>> = positions
            .iter()
            .map(|v| {
                let mut d = vec![0.0; 3];
                n.travel(*v, &mut d);
                d.iter_mut()
                    .zip(&n.probes)
                    .for_each(|(d, p)| *d *= 1.0 + p.gain_error);
                d
            })
            .collect();
        let rows = fit_sensitivity(&positions, &readings);
        for (row, p) in rows.iter().zip(&n.probes) {
            assert!((*row - p.axis * (1.0 + p.gain_error)).length() < 1e-12);
        }
        let conversion = Conversion::new(rows).unwrap();
        let v = Vector::new(3e-6, -7e-6, 11e-6);
        let mut d = [0.0; 3];
        n.travel(v, &mut d);
        d.iter_mut()
            .zip(&n.probes)
            .for_each(|(d, p)| *d *= 1.0 + p.gain_error);
        assert!((conversion.displacement(&d) - v).length() < 1e-17);
    }

    #[test]
    fn a_singular_nest_is_refused() {
        assert_eq!(
            Conversion::new(vec![Vector::X, Vector::X, Vector::Y]),
            Err(SingularNest)
        );
    }
}

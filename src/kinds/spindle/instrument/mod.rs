//! The virtual spindle error analyser: a precision artefact on one side of an axis of rotation,
//! displacement probes on the other, read through the twin.
//!
//! # Frames
//!
//! Everything here is in the **axis frames** of [`super::record`]: z along the nominal axis of
//! rotation, positive by the right-hand rule of the axis's positive rotation (the URDF joint
//! axis, so `−z` of the table for a C table on the workpiece branch, ISO 841), x along the
//! next machine direction in the cyclic order x → y → z (X for S and C, Y for A, Z for B) and
//! y = z × x; the origin at the artefact's **reference point** on the axis: a sphere's centre,
//! the lower sphere's centre of two, a cylinder's free-end face. The **stator frame** `F_s` is
//! fixed to the non-rotating side, the **rotor frame** `F_r` turns with the axis; they coincide
//! at angle 0 when the axis is perfect ([`AxisChain`] places them on the machine).
//!
//! The artefact's free end is towards `−z`. The reference point lies `stickout` below (towards
//! `−z`) the foot of the perpendicular from the rotor's end frame (`tool` for the spindle,
//! `workpiece` for a table axis) onto the nominal axis line, whichever side carries the
//! artefact: for a fixed sensitive direction the artefact is on the rotor, for a rotating one on
//! the stator at the same place. A second sphere, or the cylinder's length, lies towards `+z`.
//!
//! # The reading
//!
//! With `M` the actual pose of `F_r` in `F_s` from the twin (exactly `Rot_z(θ)` for a perfect
//! axis) and `G` the artefact's set-up pose on its carrier (eccentricity `e` and tilt `τ`, about
//! the reference point: `G = Trans(e)·Exp(τ)`), a probe sensing the nominal point `q` along its
//! direction `d` (both in its own frame) reads
//!
//! ```text
//! fixed sensing    (artefact on the rotor, probes on the stator):  X = M · G · Rot_z(−θ)
//! rotating sensing (artefact on the stator, probes on the rotor):  X = M⁻¹ · G · Rot_z(θ)
//! reading = d · (X·q − q) − h(ψ − β)        (radial probes; axial and face: no h)
//! ```
//!
//! `X·q − q` is the displacement, relative to the probe, of the artefact's material point that
//! would sit at `q` on a perfect axis with a perfect, centred artefact: positive along `d` when
//! the surface moves away from the probe (ISO 230-7 A.7.2). Only the surface's motion along the
//! probe's direction is read; the change of the gap from motion across a curved surface (ISO
//! 230-7 A.2.7, `E_N²/2R`: 4 pm for 10 µm on a 25 mm sphere) is left out. `h` is the artefact's
//! outward form deviation (a bump closer to the probe lowers the reading), a function of the
//! azimuth `ψ` in the frame of the artefact's carrier that the probe faces: `ψ = φ − θ` for a
//! fixed probe at stator azimuth `φ`, `ψ = φ + θ` for a rotating one; `β` is the angle the
//! set-up turned the artefact by on its carrier.
//!
//! So a fixed radial probe at azimuth `φ`, direction `−(cos φ, sin φ, 0)`, reads
//! `−(E_X cos φ + E_Y sin φ) − h(φ − θ)` with `E` the displacement of the artefact's section at
//! its height, eccentricity included, and a rotating one reads the ISO 230-7 formula (1)
//! projection of the rotor's motion with the opposite sign of the stator's view.
//!
//! # The probe's own errors, in this order
//!
//! 1. a gain error: `(1 + g)·reading`;
//! 2. its bandwidth: a first-order low-pass of cut-off `f_c` (time constant `τ = 1/(2π f_c)`),
//!    discretised step-invariantly and applied causally in sample order,
//!    `y_n = y_{n−1} + α (x_n − y_{n−1})`, `α = 1 − exp(−Δt/τ)`, started at the first input
//!    (each speed's record is preceded by whole settling revolutions that are not recorded);
//! 3. white Gaussian noise of a given standard deviation, from a stream seeded per probe, set-up
//!    and speed (the ziggurat standard normal of `rand_distr`);
//! 4. its resolution: the reading rounded to the nearest multiple of it (ties to even).

mod chain;

pub use chain::{AxisChain, ChainScratch, FrameError, RecordChain};

use super::record::{Sensing, SpindleProbe};
use crate::math::{Pose, Real, Vector, small_motion};
use rand::RngExt;
use rand_chacha::ChaCha8Rng;
use rand_distr::StandardNormal;
use std::f64::consts::PI;

/// The artefact's shape.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum ArtefactKind {
    /// One sphere: radial probes at its equator (height 0), an axial probe at its lower pole.
    Sphere,
    /// Two spheres on one mandrel, the second `separation` (m) above the first towards the
    /// carrier: radial probes at the equator of either (height 0 or `separation`).
    TwoSpheres {
        /// Distance between the centres (m).
        separation: Real,
    },
    /// A cylindrical test mandrel from its free-end face (height 0) up to `length` (m): radial
    /// probes at any height on it, face probes on its end face, an axial probe at the face's
    /// centre.
    Cylinder {
        /// Probed length (m).
        length: Real,
    },
}

impl ArtefactKind {
    /// Its name in scenarios.
    pub fn name(self) -> &'static str {
        match self {
            ArtefactKind::Sphere => "sphere",
            ArtefactKind::TwoSpheres { .. } => "two_spheres",
            ArtefactKind::Cylinder { .. } => "cylinder",
        }
    }
}

/// One harmonic of the artefact's form: `amplitude · sin(per_revolution · ψ + phase)`, outward.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct FormHarmonic {
    /// Undulations per revolution (2 or more: 0 is its size, 1 its eccentricity).
    pub per_revolution: u32,
    /// Amplitude (m).
    pub amplitude: Real,
    /// Phase at ψ = 0 (rad).
    pub phase: Real,
}

/// The test artefact and how it is set up on its carrier.
#[derive(Clone, Debug, PartialEq)]
pub struct Artefact {
    /// Its shape.
    pub kind: ArtefactKind,
    /// Radius of the spheres or of the cylinder (m).
    pub radius: Real,
    /// How far its reference point stands below the foot of the perpendicular from the rotor's
    /// end frame onto the axis, towards its free end (m).
    pub stickout: Real,
    /// Set-up eccentricity, x and y in the carrier's axis frame (m).
    pub eccentricity: [Real; 2],
    /// Set-up tilt about x and y of the carrier's axis frame, about the reference point (rad).
    pub tilt: [Real; 2],
    /// Form of every radial section (zero mean, no 1-UPR term), outward, a function of the
    /// azimuth in the artefact's own frame.
    pub form: Vec<FormHarmonic>,
}

impl Artefact {
    /// The outward form deviation (m) at azimuth `psi` of the artefact's own frame.
    pub fn form_at(&self, psi: Real) -> Real {
        self.form
            .iter()
            .map(|h| h.amplitude * (h.per_revolution as Real * psi + h.phase).sin())
            .sum()
    }

    /// Its set-up pose `G` on its carrier (carrier axis frame ← artefact) after a set-up turned
    /// it by `turn` (rad) about the axis: the eccentricity and tilt turn with it.
    pub fn setup_pose(&self, turn: Real) -> Pose {
        let (s, c) = turn.sin_cos();
        let rotate = |v: [Real; 2]| Vector::new(c * v[0] - s * v[1], s * v[0] + c * v[1], 0.0);
        small_motion(rotate(self.eccentricity), rotate(self.tilt))
    }

    /// The height (axis z, m) of the end an axial probe senses: a sphere's lower pole, the
    /// cylinder's free-end face.
    pub fn axial_end(&self) -> Real {
        match self.kind {
            ArtefactKind::Sphere | ArtefactKind::TwoSpheres { .. } => -self.radius,
            ArtefactKind::Cylinder { .. } => 0.0,
        }
    }

    /// For people and preambles: `sphere 25.4 mm`, `cylinder 25 mm × 80 mm`.
    pub fn describe(&self) -> String {
        let mm = |v: Real| crate::math::trimmed(v * 1e3, 6);
        match self.kind {
            ArtefactKind::Sphere => format!("sphere {} mm", mm(2.0 * self.radius)),
            ArtefactKind::TwoSpheres { separation } => format!(
                "two spheres {} mm, {} mm apart",
                mm(2.0 * self.radius),
                mm(separation)
            ),
            ArtefactKind::Cylinder { length } => {
                format!("cylinder {} mm x {} mm", mm(2.0 * self.radius), mm(length))
            }
        }
    }
}

/// Where a probe senses, in its own axis frame (stator for fixed sensing, rotor for rotating).
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum ProbeKind {
    /// Across the axis at azimuth `azimuth` (rad, from x towards y) and height `height` (m):
    /// it sits outside the artefact facing the axis, direction `−(cos φ, sin φ, 0)`.
    Radial {
        /// Azimuth φ (rad).
        azimuth: Real,
        /// Height along the axis (m).
        height: Real,
    },
    /// On the axis, below the artefact's free end, direction `+z`.
    Axial,
    /// On the cylinder's end face at `radius` (m) and `azimuth` (rad), direction `+z`.
    Face {
        /// Radius of the sensed point (m).
        radius: Real,
        /// Azimuth (rad).
        azimuth: Real,
    },
}

impl ProbeKind {
    /// Its name in scenarios.
    pub fn name(self) -> &'static str {
        match self {
            ProbeKind::Radial { .. } => "radial",
            ProbeKind::Axial => "axial",
            ProbeKind::Face { .. } => "face",
        }
    }
}

/// One displacement probe of the analyser and its own errors.
#[derive(Clone, Debug, PartialEq)]
pub struct ProbeSpec {
    /// Its name (lower-case letters, digits, `_`): the table's column is `<name>_um`.
    pub name: String,
    /// Where it senses.
    pub kind: ProbeKind,
    /// Relative gain error (0.001 = 0.1 %).
    pub gain_error: Real,
    /// Standard deviation of its white noise (m).
    pub noise: Real,
    /// Resolution (m; 0 for none).
    pub resolution: Real,
    /// Cut-off of its first-order low-pass (Hz); `None` for no filter.
    pub bandwidth: Option<Real>,
    /// Half its measuring range (m): a reading beyond ± this stops the run.
    pub range: Real,
}

/// A probe's geometry in one set-up, in its own axis frame.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Placement {
    /// The nominal sensed point (m).
    pub point: Vector,
    /// The unit direction along which artefact motion increases the reading.
    pub direction: Vector,
    /// The azimuth it faces in its own frame (rad), when the artefact's form applies to it.
    pub form_azimuth: Option<Real>,
}

impl ProbeSpec {
    /// Its geometry in a set-up; `opposite` moves a radial or face probe to the other side of
    /// the axis (azimuth + 180°), as Donaldson's reversal and Estler's face reversal do.
    pub fn placement(&self, artefact: &Artefact, opposite: bool) -> Placement {
        match self.kind {
            ProbeKind::Radial { azimuth, height } => {
                let phi = if opposite { azimuth + PI } else { azimuth };
                let (s, c) = phi.sin_cos();
                Placement {
                    point: Vector::new(artefact.radius * c, artefact.radius * s, height),
                    direction: Vector::new(-c, -s, 0.0),
                    form_azimuth: Some(phi),
                }
            }
            ProbeKind::Axial => Placement {
                point: Vector::new(0.0, 0.0, artefact.axial_end()),
                direction: Vector::Z,
                form_azimuth: None,
            },
            ProbeKind::Face { radius, azimuth } => {
                // Estler's face reversal moves the probe to the other side too.
                let phi = if opposite { azimuth + PI } else { azimuth };
                let (s, c) = phi.sin_cos();
                Placement {
                    point: Vector::new(radius * c, radius * s, 0.0),
                    direction: Vector::Z,
                    form_azimuth: None,
                }
            }
        }
    }

    /// The probe as the record describes it: its geometry in the first (normal) set-up.
    pub fn record_probe(&self, artefact: &Artefact, sensing: Sensing) -> SpindleProbe {
        let p = self.placement(artefact, false);
        SpindleProbe {
            name: self.name.clone(),
            direction: p.direction.to_array(),
            position: p.point.to_array(),
            sensing,
        }
    }

    /// The filter coefficient `α = 1 − exp(−Δt/τ)` at sample interval `dt` (s); 1 (no filter)
    /// without a bandwidth.
    pub fn filter_alpha(&self, dt: Real) -> Real {
        match self.bandwidth {
            Some(f) => -(-dt * std::f64::consts::TAU * f).exp_m1(),
            None => 1.0,
        }
    }
}

/// The true displacement a placement reads under `x` (see the module's formula), before the
/// form and the probe's own errors.
#[inline]
pub fn displacement(x: &Pose, placement: &Placement) -> Real {
    placement
        .direction
        .dot(x.transform_point3(placement.point) - placement.point)
}

/// One probe's electronics along one record: gain, low-pass, noise, resolution.
pub struct Channel<'a> {
    probe: &'a ProbeSpec,
    alpha: Real,
    state: Option<Real>,
    /// `1/resolution` (0 without one).
    steps_per_metre: Real,
}

/// `1.5·2⁵²`: adding and subtracting it rounds an `f64` below `2⁵¹` in magnitude to the nearest
/// whole number, ties to even (the FPU's rounding), without a call to `round`.
const ROUNDING: Real = 6_755_399_441_055_744.0;

impl<'a> Channel<'a> {
    /// The channel of `probe` sampling every `dt` seconds, its filter not yet started.
    pub fn new(probe: &'a ProbeSpec, dt: Real) -> Channel<'a> {
        Channel {
            probe,
            alpha: probe.filter_alpha(dt),
            state: None,
            steps_per_metre: if probe.resolution > 0.0 {
                1.0 / probe.resolution
            } else {
                0.0
            },
        }
    }

    /// Feeds the true reading `value` (m); returns the filtered signal (before noise).
    #[inline]
    pub fn filter(&mut self, value: Real) -> Real {
        let x = value * (1.0 + self.probe.gain_error);
        let y = match self.state {
            None => x,
            Some(y) => y + self.alpha * (x - y),
        };
        self.state = Some(y);
        y
    }

    /// What the analyser records of the filtered signal `y`: noise from `rng`, then resolution.
    #[inline]
    pub fn digitise(&mut self, y: Real, rng: &mut ChaCha8Rng) -> Real {
        let noisy = if self.probe.noise > 0.0 {
            let z: Real = rng.sample(StandardNormal);
            y + self.probe.noise * z
        } else {
            y
        };
        if self.steps_per_metre == 0.0 {
            return noisy;
        }
        let steps = noisy * self.steps_per_metre;
        let whole = if steps.abs() < 2_251_799_813_685_248.0 {
            (steps + ROUNDING) - ROUNDING
        } else {
            steps.round()
        };
        whole * self.probe.resolution
    }
}

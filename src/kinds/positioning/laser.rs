//! A virtual laser interferometer for linear positioning (ISO 230-2).
//!
//! The interferometer sits on the workpiece side with its beam along the axis under test; the
//! reflector rides on the tool side at `beam_offset` from the tool tip (tool frame) — the Abbe
//! offset between the measurement line and the functional point. The reading is the
//! displacement of the reflector relative to the interferometer along the beam, zeroed at the
//! first reading of each run (or once, for drift tests):
//!
//! ```text
//! optical = [n_air·(L_dead + u·Δp) − n_air,zero·L_dead] / n_assumed,
//!           Δp = p_reflector − p_reflector at the run's first reading
//! reading = quantise(optical · (1 − α_material·(T_material,measured − 20 °C)) + noise)
//! deviation = (P_first + reading) − P_target
//! ```
//!
//! `u` is the beam direction, tilted from the axis by the misalignment (cosine error);
//! `n_air` the true refractive index, `n_assumed` the one the instrument uses: that of its own
//! air sensors (each with an offset) through the Edlén equation, or of standard air when
//! compensation is off. Material (NDE) compensation, when on, scales the reading to 20 °C with
//! the material sensor's temperature.
//!
//! When the air temperature changes during a test ([`Laser::measure_in_air`]), the dead path
//! (the beam between interferometer and reflector at the zero) changes its optical length too,
//! which the reading cannot tell from motion.
//!
//! Simplified: the air is uniform along the beam, only its temperature changes; no beam shear,
//! no periodic nonlinearity of the interferometer optics.

use super::air::{Air, HENE_WAVELENGTH_UM};
use super::conditions::PositioningConditions;
pub use super::setup::{Mounting, Zeroing};
use super::table::{PositioningReading, PositioningTable};
use crate::machine::Axis;
use crate::math::{Pose, Real, Vector, standard_normal};
use crate::program::Visit;
use rand_chacha::ChaCha8Rng;

/// How the instrument finds the refractive index it divides by.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum AirCompensation {
    /// None: standard air (20 °C, 1013.25 hPa, 50 %RH) is assumed.
    Off,
    /// From its own sensors, which read the true air plus these offsets.
    Sensors {
        /// Air temperature sensor offset (°C).
        temperature_offset: Real,
        /// Pressure sensor offset (Pa).
        pressure_offset: Real,
        /// Humidity sensor offset (%RH).
        humidity_offset: Real,
    },
}

/// Material (NDE) compensation: the reading is scaled to 20 °C of the machine's scale material.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct MaterialCompensation {
    /// Expansion coefficient the instrument is told (1/K).
    pub expansion: Real,
    /// Material temperature as its sensor reads it (°C).
    pub measured_temperature: Real,
}

/// A laser interferometer set up on an axis.
#[derive(Clone, Debug, PartialEq)]
pub struct Laser {
    /// The axis along which the beam runs.
    pub axis: Axis,
    /// Reflector position relative to the tool tip, tool frame (m): the Abbe offset.
    pub beam_offset: Vector,
    /// Beam tilt from the axis (rad) towards the two other coordinate axes, in ISO order
    /// (an X beam tilted towards Y, then towards Z).
    pub misalignment: [Real; 2],
    /// Resolution (m).
    pub resolution: Real,
    /// White noise on each reading, 1σ (m).
    pub noise: Real,
    /// The true air along the beam.
    pub air: Air,
    /// Refractive-index compensation.
    pub compensation: AirCompensation,
    /// Material compensation, if on.
    pub material: Option<MaterialCompensation>,
    /// Beam length between interferometer and reflector at the zero (m): its optical length
    /// changes with the air but is not part of the measured displacement.
    pub dead_path: Real,
    /// Zero the reading at the first reading of each run (positioning tests) or only once, at
    /// the very first reading (drift tests, ISO 230-3).
    pub zero: Zeroing,
    /// Which side carries the interferometer.
    pub mounting: Mounting,
}

impl Laser {
    /// The beam direction in the workpiece frame: the axis direction plus the misalignment
    /// towards the other two axes, normalised.
    pub fn beam_direction(&self) -> Vector {
        let along = self.axis.unit();
        let across: Vec<Vector> = Vector::AXES
            .iter()
            .copied()
            .filter(|a| *a != along)
            .collect();
        (along + across[0] * self.misalignment[0] + across[1] * self.misalignment[1]).normalize()
    }

    /// What the instrument corrects, as a table's preamble says it: `none`, `air`
    /// (refractive index from its sensors), `nde` (material to 20 °C) or `air+nde`.
    pub fn compensation_name(&self) -> &'static str {
        match (self.compensation, self.material.is_some()) {
            (AirCompensation::Off, false) => "none",
            (AirCompensation::Off, true) => "nde",
            (AirCompensation::Sensors { .. }, false) => "air",
            (AirCompensation::Sensors { .. }, true) => "air+nde",
        }
    }

    /// The refractive index the instrument divides by.
    pub fn assumed_index(&self) -> Real {
        self.assumed_index_in(&self.air)
    }

    /// The refractive index the instrument divides by when the true air is `air`.
    fn assumed_index_in(&self, air: &Air) -> Real {
        match self.compensation {
            AirCompensation::Off => Air::STANDARD.refractive_index(HENE_WAVELENGTH_UM),
            AirCompensation::Sensors {
                temperature_offset,
                pressure_offset,
                humidity_offset,
            } => Air {
                temperature: air.temperature + temperature_offset,
                pressure: air.pressure + pressure_offset,
                humidity: air.humidity + humidity_offset,
            }
            .refractive_index(HENE_WAVELENGTH_UM),
        }
    }

    /// Measures the visits of a test, given the actual tool pose seen from the workpiece at each
    /// (`poses[i]` at `visits[i]`, from the twin with whatever errors it has); noise comes from
    /// `rng`. Returns a `positioning` table (without temperature columns).
    pub fn measure(
        &self,
        visits: &[Visit],
        poses: &[Pose],
        targets: &[Real],
        rng: &mut ChaCha8Rng,
    ) -> PositioningTable {
        self.measure_in_air(visits, poses, None, None, targets, rng)
    }

    /// [`Laser::measure`] with the air temperature (°C) at each visit, when it changes during
    /// the test (pressure and humidity stay as set), and the material sensor's reading (°C) at
    /// each visit for material compensation, when it follows the machine. The interferometer counts the optical
    /// path change, dead path included — `n(t)·(L_dead + L(t)) − n(t₀)·(L_dead + L(t₀))` — and
    /// divides by the index it assumes at the reading, so a change of the air between the zero
    /// and a reading leaves `L_dead·Δn/n` in it however good the compensation.
    pub fn measure_in_air(
        &self,
        visits: &[Visit],
        poses: &[Pose],
        air_temperatures: Option<&[Real]>,
        material_temperatures: Option<&[Real]>,
        targets: &[Real],
        rng: &mut ChaCha8Rng,
    ) -> PositioningTable {
        assert_eq!(visits.len(), poses.len(), "one pose per visit");
        if let Some(temperatures) = material_temperatures {
            assert_eq!(
                temperatures.len(),
                visits.len(),
                "one material temperature per visit"
            );
        }
        if let Some(temperatures) = air_temperatures {
            assert_eq!(
                temperatures.len(),
                visits.len(),
                "one air temperature per visit"
            );
        }
        let beam = self.beam_direction();
        let air_at = |i: usize| Air {
            temperature: air_temperatures.map_or(self.air.temperature, |t| t[i]),
            ..self.air
        };
        let material = |i: usize| {
            self.material.map_or(1.0, |m| {
                let measured = material_temperatures.map_or(m.measured_temperature, |t| t[i]);
                1.0 - m.expansion * (measured - 20.0)
            })
        };
        let mut readings = Vec::with_capacity(visits.len());
        // The reading is zeroed at a run's first reading (or the test's): (run, reflector there,
        // its target, the true index then).
        let mut zero: Option<(usize, Vector, Real, Real, Vector)> = None;
        for (i, (visit, pose)) in visits.iter().zip(poses).enumerate() {
            let here = pose.transform_point3(self.beam_offset);
            let target = targets[visit.point.target];
            let air = air_at(i);
            let n_true = air.refractive_index(HENE_WAVELENGTH_UM);
            let new_run = zero.is_none_or(|(run, ..)| run != visit.point.run);
            if zero.is_none() || (new_run && self.zero == Zeroing::EachRun) {
                let in_tool = crate::math::rigid_inverse(pose).transform_point3(here);
                zero = Some((visit.point.run, here, target, n_true, in_tool));
            }
            let (_, origin, first_target, n_zero, origin_in_tool) = zero.expect("set above");
            let travel = match self.mounting {
                Mounting::InterferometerOnWorkpiece => beam.dot(here - origin),
                // The reflector stays at `origin` on the workpiece; seen from the tool it moves
                // opposite to the tool, along the tool-fixed beam.
                Mounting::InterferometerOnTool => {
                    let tool_from_workpiece = crate::math::rigid_inverse(pose);
                    -beam.dot(tool_from_workpiece.transform_point3(origin) - origin_in_tool)
                }
            };
            let optical_change = n_true * (self.dead_path + travel) - n_zero * self.dead_path;
            let optical = optical_change / self.assumed_index_in(&air);
            let mut reading = optical * material(i);
            if self.noise > 0.0 {
                reading += self.noise * standard_normal(rng);
            }
            if self.resolution > 0.0 {
                reading = (reading / self.resolution).round() * self.resolution;
            }
            readings.push(PositioningReading {
                target,
                deviation: first_target + reading - target,
                approach: visit.point.approach,
                run: visit.point.run,
                time: Some(visit.time),
                temperatures: Vec::new(),
            });
        }
        let runs = visits
            .iter()
            .map(|v| v.point.run)
            .max()
            .map_or(0, |r| r + 1);
        PositioningTable {
            axis: Some(self.axis),
            runs: (1..=runs).map(|r| r.to_string()).collect(),
            sensors: Vec::new(),
            has_direction: true,
            readings,
            conditions: PositioningConditions::default(),
            columns_not_read: Vec::new(),
        }
    }
}

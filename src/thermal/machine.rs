//! A machine's thermal model: its network, the heat sources the programme drives, the ambient
//! air, and the thermal error terms.
//!
//! [`MachineThermal::ballscrew_default`] builds a plausible model for any bundled machine
//! (assumptions, not measurements; override them per machine when data exist):
//!
//! | node | capacity J/K | to air W/K | links W/K | heat |
//! |---|---|---|---|---|
//! | `<a>_nut` (nut, housing and the carriage around it, per linear axis) | 8 000 | 3 | screw 4 | 250 W per m/s of the axis |
//! | `<a>_screw` | 12 000 | 2 | motor 1.5 | — |
//! | `<a>_motor` (motor and thrust bearing) | 4 000 | 4 | | 150 W per m/s |
//! | `spindle_bearing` | 3 000 | 2 | housing 10 | 0.05 W per rad/s (52 W at 10 000 min⁻¹) |
//! | `spindle_housing` | 20 000 | 8 | column front 5 | — |
//! | `column_front`, `column_back` | 200 000 each | 20 each | each other 15 | — |
//! | `bed` | 500 000 | 40 | | — |
//! | `table` | 100 000 | 10 | X nut 2 | — |
//!
//! With them X idling at 4 800 mm/min warms its nut by 3.4 °C (63 % after 32 min) and its
//! screw, lagging, by 2.4 °C (63 % after 63 min, 95 % after about 3 h) — Lu 2012 Ch. 3 and 5
//! report warm-ups of 2.5–3 h. Y and Z, with no table to share the nut's heat, warm a little
//! more. `tests/it/thermal_twin.rs` checks these lie in the ranges the issue asks for. Friction heat is taken proportional to speed (Coulomb
//! friction); heat is spread evenly within a node. Thermal errors: each linear axis's screw
//! expands with 11.7 ppm/K (steel, unless set otherwise) from its fixed end (at the axis zero
//! unless set otherwise), the
//! spindle grows 1 µm/K, and the column tilts the head by 2 µrad per K of front–back difference.

use super::errors::{ThermalErrors, ThermalTerm, ThermalTermError};
use super::network::{ThermalNetwork, ThermalNode};
use crate::machine::{Axis, AxisValues, Machine};
use crate::math::Real;
use std::f64::consts::TAU;

/// The air temperature around the machine over time (°C, time in s).
#[derive(Clone, Debug, PartialEq)]
pub struct Ambient {
    /// Mean temperature.
    pub mean: Real,
    /// Steps: from each time on, this much is added.
    pub steps: Vec<(Real, Real)>,
    /// Amplitude of the daily cycle (peak − mean).
    pub daily_amplitude: Real,
    /// Time of the daily peak, from the start (s).
    pub daily_peak: Real,
    /// A fast oscillation (amplitude, period s), e.g. 15–30 cycles per hour from an air
    /// conditioner (ISO 230-3 Annex C).
    pub oscillation: Option<(Real, Real)>,
}

impl Ambient {
    /// A constant temperature.
    pub fn constant(temperature: Real) -> Ambient {
        Ambient {
            mean: temperature,
            steps: Vec::new(),
            daily_amplitude: 0.0,
            daily_peak: 0.0,
            oscillation: None,
        }
    }

    /// The temperature at `time`.
    pub fn at(&self, time: Real) -> Real {
        let steps: Real = self
            .steps
            .iter()
            .filter(|(t, _)| time >= *t)
            .map(|(_, dt)| dt)
            .sum();
        let daily = self.daily_amplitude * (TAU * (time - self.daily_peak) / 86_400.0).cos();
        let fast = self.oscillation.map_or(0.0, |(amplitude, period)| {
            amplitude * (TAU * time / period).sin()
        });
        self.mean + steps + daily + fast
    }
}

/// What drives a heat source.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum HeatDriver {
    /// The speed of an axis (W per m/s or per rad/s).
    AxisSpeed(Axis),
    /// The spindle speed (W per rad/s).
    Spindle,
}

/// Heat into a node, proportional to what drives it.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct HeatSource {
    /// The node heated.
    pub node: usize,
    /// What drives it.
    pub driver: HeatDriver,
    /// W per unit of the driver's speed.
    pub coefficient: Real,
}

/// A ball screw's thermal facts.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ScrewSpec {
    /// Axis position of the fixed (thrust-bearing) end (m).
    pub fixed_end: Real,
    /// Expansion coefficient (1/K).
    pub expansion: Real,
}

impl Default for ScrewSpec {
    /// Fixed end at the axis zero, steel.
    fn default() -> ScrewSpec {
        ScrewSpec {
            fixed_end: 0.0,
            expansion: 11.7e-6,
        }
    }
}

/// A machine's thermal model.
#[derive(Clone, Debug, PartialEq)]
pub struct MachineThermal {
    /// The network.
    pub network: ThermalNetwork,
    /// Heat sources.
    pub sources: Vec<HeatSource>,
    /// How temperatures move the tool.
    pub errors: ThermalErrors,
    /// The air.
    pub ambient: Ambient,
    /// Every node's temperature at the start (°C).
    pub initial: Real,
}

impl MachineThermal {
    /// The default model (see the module docs) for `machine`, every node starting at the air's
    /// temperature at time zero. The screws and the spindle have their nominal length at the
    /// ambient mean (the thermal errors are zero for a machine at the mean air temperature).
    /// `screws` gives, per linear axis, the axis position of its screw's fixed end (m) and its
    /// expansion coefficient (1/K); axes not listed have the fixed end at their zero and
    /// 11.7e-6/K.
    pub fn ballscrew_default(
        machine: &Machine,
        ambient: Ambient,
        screws: &[(Axis, ScrewSpec)],
    ) -> Result<MachineThermal, ThermalTermError> {
        let mut nodes = Vec::new();
        let mut links: Vec<(String, String, Real)> = Vec::new();
        let node = |name: String, capacity: Real, to_ambient: Real| ThermalNode {
            name,
            capacity,
            to_ambient,
        };
        let linear: Vec<Axis> = machine
            .axes()
            .iter()
            .map(|i| i.axis)
            .filter(|a| a.is_linear())
            .collect();
        for axis in &linear {
            let a = axis.letter().to_ascii_lowercase();
            nodes.push(node(format!("{a}_nut"), 8_000.0, 3.0));
            nodes.push(node(format!("{a}_screw"), 12_000.0, 2.0));
            nodes.push(node(format!("{a}_motor"), 4_000.0, 4.0));
            links.push((format!("{a}_nut"), format!("{a}_screw"), 4.0));
            links.push((format!("{a}_screw"), format!("{a}_motor"), 1.5));
        }
        nodes.push(node("spindle_bearing".into(), 3_000.0, 2.0));
        nodes.push(node("spindle_housing".into(), 20_000.0, 8.0));
        nodes.push(node("column_front".into(), 200_000.0, 20.0));
        nodes.push(node("column_back".into(), 200_000.0, 20.0));
        nodes.push(node("bed".into(), 500_000.0, 40.0));
        nodes.push(node("table".into(), 100_000.0, 10.0));
        links.push(("spindle_bearing".into(), "spindle_housing".into(), 10.0));
        links.push(("spindle_housing".into(), "column_front".into(), 5.0));
        links.push(("column_front".into(), "column_back".into(), 15.0));
        if linear.contains(&Axis::X) {
            links.push(("x_nut".into(), "table".into(), 2.0));
        }
        let link_refs: Vec<(&str, &str, Real)> = links
            .iter()
            .map(|(a, b, g)| (a.as_str(), b.as_str(), *g))
            .collect();
        let network = ThermalNetwork::new(nodes, &link_refs).expect("the default network is valid");
        let index = |name: &str| network.node(name).expect("default node");

        let mut sources = Vec::new();
        let mut terms = Vec::new();
        for axis in &linear {
            let a = axis.letter().to_ascii_lowercase();
            sources.push(HeatSource {
                node: index(&format!("{a}_nut")),
                driver: HeatDriver::AxisSpeed(*axis),
                coefficient: 250.0,
            });
            sources.push(HeatSource {
                node: index(&format!("{a}_motor")),
                driver: HeatDriver::AxisSpeed(*axis),
                coefficient: 150.0,
            });
            let spec = screws
                .iter()
                .find(|(f, _)| f == axis)
                .map_or(ScrewSpec::default(), |(_, s)| *s);
            terms.push(ThermalTerm::ScrewExpansion {
                axis: *axis,
                screw: index(&format!("{a}_screw")),
                expansion: spec.expansion,
                fixed_end: spec.fixed_end,
                reference: ambient.mean,
            });
        }
        sources.push(HeatSource {
            node: index("spindle_bearing"),
            driver: HeatDriver::Spindle,
            coefficient: 0.05,
        });
        terms.push(ThermalTerm::SpindleGrowth {
            node: index("spindle_housing"),
            growth: 1e-6,
            reference: ambient.mean,
        });
        terms.push(ThermalTerm::ColumnTilt {
            front: index("column_front"),
            back: index("column_back"),
            tilt: 2e-6,
        });
        let errors = ThermalErrors::new(machine, network.nodes().len(), terms)?;
        Ok(MachineThermal {
            initial: ambient.mean,
            network,
            sources,
            errors,
            ambient,
        })
    }

    /// The heat power into each node (W) with the axes moving at `speeds` (m/s, rad/s) and the
    /// spindle at `spindle` rad/s.
    pub fn powers(&self, speeds: &AxisValues, spindle: Real, out: &mut [Real]) {
        out.iter_mut().for_each(|p| *p = 0.0);
        for source in &self.sources {
            let speed = match source.driver {
                HeatDriver::AxisSpeed(axis) => speeds[axis],
                HeatDriver::Spindle => spindle,
            };
            out[source.node] += source.coefficient * speed.abs();
        }
    }
}

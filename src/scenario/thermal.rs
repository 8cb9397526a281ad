//! The `[thermal]` section: the machine's thermal model, its air and its temperature sensors.
//! A laser test (`crate::kinds::positioning`) and the ISO 230-3 ETVE test
//! (`crate::kinds::drift`) run through it.
//!
//! ```toml
//! [thermal]
//! ambient_degc = 20.0                       # mean air temperature (also the start of every node)
//! daily_amplitude_degc = 0.0                # daily cycle, peak at daily_peak_h after the start
//! daily_peak_h = 8.0
//! oscillation = { amplitude_degc = 0.2, period_min = 3.0 }   # e.g. an air conditioner
//! steps = [{ at_min = 120.0, by_degc = 1.0 }]
//! fixed_end_mm = { x = 760.0 }              # where each screw's thrust bearing is (default 0)
//! expansion_ppm_per_degc = { x = 11.7 }     # each screw's expansion (default 11.7, steel)
//! max_interval_s = 60.0                     # longest interval the heat inputs are held over
//! sensors = [{ node = "x_nut", noise_degc = 0.05, resolution_degc = 0.1, lag_s = 20.0, offset_degc = 0.0 }]
//! ```

use super::bounds::{self, Bound};
use super::{Context, ScenarioError, ScenarioErrorKind};
use crate::machine::{Axis, Machine};
use crate::math::{M_PER_MM, Real, seeded_rng};
use crate::program::Program;
use crate::thermal::{Ambient, MachineThermal, ScrewSpec, SensorSpec, TemperatureSensor};
use crate::twin::{ThermalRecord, Twin};
use serde::Deserialize;
use serde_json::{Value, json};
use std::collections::BTreeMap;
use toml::Spanned;

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
pub(crate) struct RawThermal {
    #[serde(default = "twenty")]
    ambient_degc: Real,
    #[serde(default)]
    daily_amplitude_degc: Real,
    #[serde(default)]
    daily_peak_h: Real,
    oscillation: Option<RawOscillation>,
    #[serde(default)]
    steps: Vec<RawStep>,
    #[serde(default)]
    fixed_end_mm: BTreeMap<String, Real>,
    #[serde(default)]
    expansion_ppm_per_degc: BTreeMap<String, Real>,
    #[serde(default = "sixty")]
    max_interval_s: Real,
    #[serde(default)]
    sensors: Vec<RawSensor>,
}

fn twenty() -> Real {
    20.0
}
fn sixty() -> Real {
    60.0
}

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct RawOscillation {
    amplitude_degc: Real,
    period_min: Real,
}

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct RawStep {
    at_min: Real,
    by_degc: Real,
}

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct RawSensor {
    node: String,
    name: Option<String>,
    #[serde(default)]
    offset_degc: Real,
    #[serde(default = "noise")]
    noise_degc: Real,
    #[serde(default = "resolution")]
    resolution_degc: Real,
    #[serde(default = "lag")]
    lag_s: Real,
}

fn noise() -> Real {
    0.05
}
fn resolution() -> Real {
    0.1
}
fn lag() -> Real {
    20.0
}

/// The thermal model of a scenario.
#[derive(Clone, Debug)]
pub struct ThermalSetup {
    /// The machine's thermal model.
    pub thermal: MachineThermal,
    /// Sensors: the node each follows and its characteristics.
    pub sensors: Vec<(usize, SensorSpec)>,
    /// The longest interval over which heat inputs are held (s).
    pub max_interval: Real,
}

impl ThermalSetup {
    /// `thermal model: 4 nodes, 1 sensor (x_nut)`, as `mtwin check` lists it.
    pub fn describe(&self) -> String {
        let names: Vec<&str> = self.sensors.iter().map(|(_, s)| s.name.as_str()).collect();
        format!(
            "thermal model: {} nodes, {} sensor{}{}",
            self.thermal.network.nodes().len(),
            names.len(),
            if names.len() == 1 { "" } else { "s" },
            if names.is_empty() {
                String::new()
            } else {
                format!(" ({})", names.join(", "))
            }
        )
    }

    /// The interval the thermal run steps by (s): [`ThermalSetup::max_interval`], or a
    /// twentieth of the air's fast oscillation when that is shorter (as
    /// [`crate::twin::run_thermal`] steps).
    pub fn step_interval(&self) -> Real {
        self.thermal
            .ambient
            .oscillation
            .map_or(self.max_interval, |(_, period)| {
                self.max_interval.min(period / 20.0)
            })
    }

    /// Refuses a programme of `duration` s that would take more than five million intervals
    /// of [`ThermalSetup::step_interval`] (the `[thermal]` section is at `span`): a long
    /// `max_interval_s` does not let a fast oscillation of the air through.
    pub(crate) fn check_steps(
        &self,
        context: &Context<'_>,
        span: std::ops::Range<usize>,
        duration: Real,
    ) -> Result<(), ScenarioError> {
        let step = self.step_interval();
        if duration / step > 5e6 {
            let why = if step < self.max_interval {
                "thermal.oscillation.period_min: the air's oscillation is followed in steps of a twentieth of its period"
            } else {
                "thermal.max_interval_s"
            };
            return Err(context.error(
                Some(span),
                ScenarioErrorKind::Value,
                format!(
                    "{why}: {:.1} h in steps of {} s is more than five million steps",
                    duration / 3600.0,
                    crate::math::readable(step)
                ),
            ));
        }
        Ok(())
    }

    /// Fresh sensors for a run, each with its own seeded noise stream.
    pub fn sensors(&self, seed: u64) -> Vec<(usize, TemperatureSensor)> {
        self.sensors
            .iter()
            .map(|(node, spec)| {
                let rng = seeded_rng(seed, &format!("sensor {}", spec.name));
                (
                    *node,
                    TemperatureSensor::new(spec.clone(), self.thermal.initial, rng),
                )
            })
            .collect()
    }

    /// Runs `program` on `twin` through this thermal model, fresh sensors seeded from `seed`
    /// read at every visit ([`crate::twin::run_thermal`]).
    pub fn run(&self, twin: &Twin, program: &Program, seed: u64) -> Vec<ThermalRecord> {
        let mut sensors = self.sensors(seed);
        crate::twin::run_thermal(
            twin,
            &self.thermal,
            program,
            self.max_interval,
            &mut sensors,
        )
    }
}

pub(crate) fn thermal_setup(
    context: &Context<'_>,
    machine: &Machine,
    raw: &Spanned<RawThermal>,
) -> Result<ThermalSetup, ScenarioError> {
    let t = raw.get_ref();
    let fail = |message: String| {
        context.section_error(raw.span(), ScenarioErrorKind::Value, "thermal.", message)
    };
    let numbers = [
        ("ambient_degc", t.ambient_degc, bounds::TEMPERATURE_DEGC),
        (
            "daily_amplitude_degc",
            t.daily_amplitude_degc,
            Bound::symmetric(35.0, "a day's swing in a workshop"),
        ),
        (
            "daily_peak_h",
            t.daily_peak_h,
            Bound {
                lo: 0.0,
                hi: 24.0,
                why: "an hour of the day",
            },
        ),
        (
            "max_interval_s",
            t.max_interval_s,
            Bound {
                lo: 0.001,
                hi: 3600.0,
                why: "1 ms to an hour: a thermal model steps no finer and no coarser",
            },
        ),
    ];
    for (key, value, bound) in numbers {
        bound
            .check(value)
            .map_err(|message| fail(format!("{key}: {message}")))?;
    }
    let oscillation = match &t.oscillation {
        Some(o) => {
            Bound::symmetric(35.0, "an air conditioner's swing")
                .check(o.amplitude_degc)
                .map_err(|message| fail(format!("oscillation.amplitude_degc: {message}")))?;
            Bound {
                lo: 1e-6,
                ..bounds::LAG_MIN
            }
            .check(o.period_min)
            .map_err(|message| fail(format!("oscillation.period_min: {message}")))?;
            Some((o.amplitude_degc, o.period_min * 60.0))
        }
        None => None,
    };
    for step in &t.steps {
        let when = Bound {
            lo: 0.0,
            hi: crate::io::CLOCK_MIN.limit,
            why: crate::io::CLOCK_MIN.why,
        };
        when.check(step.at_min)
            .map_err(|message| fail(format!("steps.at_min: {message}")))?;
        Bound::symmetric(70.0, "the width of a workshop's range")
            .check(step.by_degc)
            .map_err(|message| fail(format!("steps.by_degc: {message}")))?;
    }
    // The air stays in a workshop's range: its mean, the steps taken so far, the day's and
    // the oscillation's swings all at their worst.
    let mut order: Vec<&RawStep> = t.steps.iter().collect();
    order.sort_by(|a, b| a.at_min.total_cmp(&b.at_min));
    let swing = t.daily_amplitude_degc.abs() + oscillation.map_or(0.0, |(a, _)| a.abs());
    let mut level = t.ambient_degc;
    let (mut lowest, mut highest) = (level, level);
    for step in order {
        level += step.by_degc;
        lowest = lowest.min(level);
        highest = highest.max(level);
    }
    let (lowest, highest) = (lowest - swing, highest + swing);
    let workshop = bounds::TEMPERATURE_DEGC;
    if lowest < workshop.lo || highest > workshop.hi {
        return Err(fail(format!(
            "ambient_degc, steps, daily_amplitude_degc and oscillation: the air would reach {} … {} °C; expected {} … {} ({})",
            crate::math::trimmed(lowest, 3),
            crate::math::trimmed(highest, 3),
            workshop.lo,
            workshop.hi,
            workshop.why
        )));
    }
    let ambient = Ambient {
        mean: t.ambient_degc,
        steps: t
            .steps
            .iter()
            .map(|s| (s.at_min * 60.0, s.by_degc))
            .collect(),
        daily_amplitude: t.daily_amplitude_degc,
        daily_peak: t.daily_peak_h * 3600.0,
        oscillation,
    };
    let mut screws: Vec<(Axis, ScrewSpec)> = Vec::new();
    let axis_of = |key: &str, table: &str| match key {
        "x" => Ok(Axis::X),
        "y" => Ok(Axis::Y),
        "z" => Ok(Axis::Z),
        other => Err(fail(format!("{table}.{other}: expected x, y or z"))),
    };
    for (table, values) in [
        ("fixed_end_mm", &t.fixed_end_mm),
        ("expansion_ppm_per_degc", &t.expansion_ppm_per_degc),
    ] {
        for (key, value) in values {
            let axis = axis_of(key, table)?;
            let bound = match table {
                "fixed_end_mm" => bounds::OFFSET_MM,
                _ => bounds::EXPANSION_PPM_PER_DEGC,
            };
            bound
                .check(*value)
                .map_err(|message| fail(format!("{table}.{key}: {message}")))?;
            let index = match screws.iter().position(|(a, _)| *a == axis) {
                Some(i) => i,
                None => {
                    screws.push((axis, ScrewSpec::default()));
                    screws.len() - 1
                }
            };
            if table == "fixed_end_mm" {
                screws[index].1.fixed_end = value * M_PER_MM;
            } else {
                screws[index].1.expansion = value * 1e-6;
            }
        }
    }
    let thermal = MachineThermal::ballscrew_default(machine, ambient, &screws)
        .map_err(|e| fail(e.to_string()))?;
    let mut sensors = Vec::new();
    for s in &t.sensors {
        let node = thermal.network.node(&s.node).ok_or_else(|| {
            let names: Vec<&str> = thermal
                .network
                .nodes()
                .iter()
                .map(|n| n.name.as_str())
                .collect();
            fail(format!(
                "sensors: no node \"{}\"; the nodes are {}",
                s.node,
                names.join(", ")
            ))
        })?;
        let lag = Bound {
            hi: bounds::LAG_MIN.hi * 60.0,
            ..bounds::LAG_MIN
        };
        let values = [
            (
                "offset_degc",
                s.offset_degc,
                Bound::symmetric(50.0, "a sensor that far off is broken"),
            ),
            ("noise_degc", s.noise_degc, bounds::THERMOMETER_DEGC),
            (
                "resolution_degc",
                s.resolution_degc,
                bounds::THERMOMETER_DEGC,
            ),
            ("lag_s", s.lag_s, lag),
        ];
        for (key, value, bound) in values {
            bound
                .check(value)
                .map_err(|message| fail(format!("sensors ({}).{key}: {message}", s.node)))?;
        }
        let name = s.name.clone().unwrap_or_else(|| s.node.clone());
        if sensors
            .iter()
            .any(|(_, spec): &(usize, SensorSpec)| spec.name == name)
        {
            return Err(fail(format!(
                "sensors: two sensors are named \"{name}\"; give one a `name`"
            )));
        }
        if !name.chars().all(|c| c.is_ascii_alphanumeric() || c == '_') {
            return Err(fail(format!(
                "sensors: name \"{name}\" must be letters, digits and _ (it becomes temp_{name}_degc)"
            )));
        }
        sensors.push((
            node,
            SensorSpec {
                name,
                offset: s.offset_degc,
                noise: s.noise_degc,
                resolution: s.resolution_degc,
                time_constant: s.lag_s,
            },
        ));
    }
    Ok(ThermalSetup {
        thermal,
        sensors,
        max_interval: t.max_interval_s,
    })
}

impl ThermalSetup {
    /// The injected thermal model: nodes, links, heat sources, thermal error terms, air, sensors.
    pub fn truth(&self) -> Value {
        let setup = self;
        let thermal = &setup.thermal;
        let name = |i: usize| thermal.network.nodes()[i].name.clone();
        json!({
            "initial_degc": thermal.initial,
            "nodes": thermal.network.nodes().iter().map(|n| json!({
                "name": n.name, "capacity_j_per_k": n.capacity, "to_ambient_w_per_k": n.to_ambient,
            })).collect::<Vec<_>>(),
            "links": thermal.network.links().iter().map(|&(i, j, g)| json!({
                "nodes": [name(i), name(j)], "conductance_w_per_k": g,
            })).collect::<Vec<_>>(),
            "sources": thermal.sources.iter().map(|s| json!({
                "node": name(s.node), "driver": format!("{:?}", s.driver), "w_per_unit_speed": s.coefficient,
            })).collect::<Vec<_>>(),
            "terms": thermal.errors.terms().map(|t| format!("{t:?}")).collect::<Vec<_>>(),
            "ambient": {
                "mean_degc": thermal.ambient.mean,
                "steps": thermal.ambient.steps.iter().map(|(t, d)| json!({"at_min": t / 60.0, "by_degc": d})).collect::<Vec<_>>(),
                "daily_amplitude_degc": thermal.ambient.daily_amplitude,
                "daily_peak_h": thermal.ambient.daily_peak / 3600.0,
                "oscillation": thermal.ambient.oscillation.map(|(a, p)| json!({"amplitude_degc": a, "period_min": p / 60.0})),
            },
            "max_interval_s": setup.max_interval,
            "sensors": setup.sensors.iter().map(|(node, spec)| json!({
                "name": spec.name, "node": name(*node), "offset_degc": spec.offset, "noise_degc": spec.noise,
                "resolution_degc": spec.resolution, "lag_s": spec.time_constant,
            })).collect::<Vec<_>>(),
        })
    }

    /// The true node temperatures and air at every measurement: `{nodes: [names], time_min: [..],
    /// air_degc: [..], temperatures_degc: [[per node] per measurement]}`.
    pub fn states(&self, records: &[ThermalRecord]) -> Value {
        let setup = self;
        let round = |v: Real| (v * 1e6).round() / 1e6;
        json!({
            "nodes": setup.thermal.network.nodes().iter().map(|n| n.name.clone()).collect::<Vec<_>>(),
            "time_min": records.iter().map(|r| round(r.visit.time / 60.0)).collect::<Vec<_>>(),
            "air_degc": records.iter().map(|r| round(setup.thermal.ambient.at(r.visit.time))).collect::<Vec<_>>(),
            "temperatures_degc": records.iter().map(|r| r.temperatures.iter().map(|t| round(*t)).collect::<Vec<_>>()).collect::<Vec<_>>(),
        })
    }
}

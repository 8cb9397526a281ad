//! Running a scenario (`mtwin run`): every test kind it asks for through the twin, then the
//! output files (tables, `truth.json`, `manifest.json`) in memory, written whole.

use super::scenario::Scenario;
use crate::errors::{Lu2012Error, ParameterName};
use crate::kinds::ballbar::{self, BallbarTable};
use crate::kinds::drift::{self, EtveRun, SpindleThermalRun};
use crate::kinds::positioning::{self, LaserRun};
use crate::kinds::probe::{self, ProbeRun};
use crate::kinds::rtest::{self, RtestRunError, RtestTable};
use crate::kinds::spindle::{self, run::SpindleRunError, table::SpindleTable};
use crate::kinds::volumetric::{VolumetricMap, VolumetricRow, volumetric_map};
use crate::machine::Side;
use crate::math::sha256_hex;
use crate::scenario::ThermalSetup;
use serde_json::{Value, json};
use std::path::Path;

/// Why a run failed.
#[derive(Debug, thiserror::Error)]
#[non_exhaustive]
pub enum RunError {
    /// The evaluation model does not fit the machine.
    #[error(transparent)]
    Model(#[from] Lu2012Error),
    /// The model produced a deviation that is not a number (nothing is written).
    #[error("the deviation at grid point {row} is not finite; check the error functions")]
    NotFinite {
        /// The 0-based row of the volumetric map.
        row: usize,
    },
    /// The R-test could not be simulated.
    #[error(transparent)]
    Rtest(#[from] RtestRunError),
    /// The probing cycles could not be simulated.
    #[error(transparent)]
    Probe(#[from] probe::run::ProbeRunError),
    /// The spindle test could not be simulated.
    #[error(transparent)]
    Spindle(#[from] SpindleRunError),
    /// An output could not be written.
    #[error(transparent)]
    Write(#[from] crate::io::WriteError),
    /// A table holds a number that is not finite: a scenario value so large that the
    /// simulation overflowed (nothing is written).
    #[error(
        "{file}:{line}: {column} = {value} is not a finite number; a value of the scenario is too large for the simulation (an instrument's calibration, noise or an error function's coefficients): nothing written"
    )]
    NotFiniteTable {
        /// The table's file name.
        file: String,
        /// The 1-based line in it.
        line: u64,
        /// The column or preamble key.
        column: String,
        /// The text found there.
        value: String,
    },
    /// The output folder holds another kind of output (a dataset).
    #[error(
        "{dir}: holds {holds}; a run's files would replace its manifest.json: give another --out"
    )]
    Folder {
        /// The folder.
        dir: String,
        /// What it holds.
        holds: String,
    },
}

/// The files of one run, in memory, in the order they are listed in the manifest.
#[derive(Clone, Debug, PartialEq)]
pub struct RunOutput {
    /// `(file name, bytes)`; `manifest.json` last.
    pub files: Vec<(String, Vec<u8>)>,
}

/// What simulating a scenario produced, before anything is written: the measurement tables
/// and, beside them, what the twin knew (for the files and for the teaching scenes).
#[derive(Clone, Debug)]
pub struct Simulation {
    /// The volumetric map, if asked for.
    pub volumetric: Option<VolumetricMap>,
    /// The laser test, if asked for.
    pub laser: Option<LaserRun>,
    /// One ball-bar table per circle, in the scenario's order.
    pub ballbar: Vec<BallbarTable>,
    /// The ETVE test, if asked for.
    pub etve: Option<EtveRun>,
    /// The ISO 230-3 §6 spindle thermal test, if asked for.
    pub spindle_thermal: Option<SpindleThermalRun>,
    /// The R-test table, if asked for.
    pub rtest: Option<RtestTable>,
    /// The touch-probe run, if asked for.
    pub probe: Option<ProbeRun>,
    /// The spindle error analyser's table, if asked for.
    pub spindle: Option<SpindleTable>,
}

/// Simulates everything `scenario` asks for. Nothing here depends on the clock, the thread
/// count or the path the scenario was given by: the same scenario and seed give the same
/// results.
pub fn simulate(scenario: &Scenario) -> Result<Simulation, RunError> {
    let volumetric = match &scenario.volumetric {
        Some(spec) => {
            let map = volumetric_map(&scenario.twin, &spec.grid, spec.model)?;
            let finite = |r: &VolumetricRow| {
                r.deviation.translation.is_finite()
                    && r.deviation.tilt.iter().all(|t| t.is_finite())
            };
            if let Some(row) = map.rows.iter().position(|r| !finite(r)) {
                return Err(RunError::NotFinite { row });
            }
            Some(map)
        }
        None => None,
    };
    let laser = scenario.laser_test.as_ref().map(|test| {
        positioning::run::simulate(
            &scenario.twin,
            test,
            scenario.thermal.as_ref(),
            scenario.seed,
        )
    });
    let ballbar = scenario
        .ballbar_test
        .as_ref()
        .map_or_else(Vec::new, |test| {
            ballbar::run::simulate(&scenario.twin, test, scenario.seed)
        });
    let etve = scenario.etve_test.as_ref().map(|test| {
        let setup = scenario
            .thermal
            .as_ref()
            .expect("an ETVE test has a thermal model (checked when the scenario was loaded)");
        drift::run::simulate(&scenario.twin, test, setup, scenario.seed)
    });
    let spindle_thermal = scenario.spindle_thermal_test.as_ref().map(|test| {
        let setup = scenario.thermal.as_ref().expect(
            "a spindle thermal test has a thermal model (checked when the scenario was loaded)",
        );
        drift::spindle_test::simulate(&scenario.twin, test, setup, scenario.seed)
    });
    let rtest = scenario
        .rtest
        .as_ref()
        .map(|test| rtest::run::simulate(&scenario.twin, test, scenario.seed))
        .transpose()?;
    let probe = scenario
        .probe_test
        .as_ref()
        .map(|test| probe::run::simulate(&scenario.twin, test, scenario.seed))
        .transpose()?;
    let spindle = scenario
        .spindle_test
        .as_ref()
        .map(|test| spindle::run::simulate(&scenario.twin, test, scenario.seed))
        .transpose()?;
    Ok(Simulation {
        volumetric,
        laser,
        ballbar,
        etve,
        spindle_thermal,
        rtest,
        probe,
        spindle,
    })
}

/// Computes every output of `scenario` in memory ([`simulate`], then [`Simulation::output`]).
pub fn run_scenario(scenario: &Scenario) -> Result<RunOutput, RunError> {
    simulate(scenario)?.output(scenario)
}

impl Simulation {
    /// What the run found, for people: one short part per test (the volumetric map's largest
    /// and RMS deviation, the ISO 230-2 figures, each ball-bar circle's G and H).
    pub fn summary(&self) -> Vec<String> {
        let mut parts = Vec::new();
        parts.extend(self.volumetric.as_ref().map(VolumetricMap::summary));
        parts.extend(self.laser.as_ref().map(LaserRun::summary));
        parts.extend(self.ballbar.iter().map(ballbar::run::summary));
        parts.extend(self.etve.as_ref().map(EtveRun::summary));
        parts.extend(
            self.spindle_thermal
                .as_ref()
                .map(SpindleThermalRun::summary),
        );
        parts.extend(self.rtest.as_ref().map(rtest::run::summary));
        parts.extend(self.probe.as_ref().map(probe::run::summary));
        parts.extend(self.spindle.as_ref().map(spindle::run::summary));
        parts
    }

    /// The files of the run: `volumetric.csv`, `positioning.csv`, `ballbar_<plane>.csv`,
    /// `drift.csv`, `rtest.csv`, `probe.csv`, `spheres.csv`, `spindle.csv` (as the scenario asks), `truth.json` and `manifest.json`.
    ///
    /// Fails, with nothing to write, when a table holds a number that is not finite.
    pub fn output(&self, scenario: &Scenario) -> Result<RunOutput, RunError> {
        let mut files = self.tables(scenario)?;
        let records = (self.laser.as_ref())
            .and_then(|run| run.thermal.as_ref())
            .or(self.etve.as_ref().map(|run| &run.records))
            .or(self.spindle_thermal.as_ref().map(|run| &run.records));
        let thermal_truth = records.and_then(|r| Some(scenario.thermal.as_ref()?.states(r)));
        let mut truth = truth(scenario);
        if let (Some(test), Some(run)) = (&scenario.etve_test, &self.etve) {
            truth["etve_test"] = drift::run::truth(test, run);
        }
        if let (Some(test), Some(run)) = (&scenario.spindle_thermal_test, &self.spindle_thermal) {
            truth["spindle_thermal_test"] = drift::spindle_test::truth(test, run);
        }
        if let Some(test) = &scenario.rtest {
            truth["rtest"] = rtest::run::truth(test);
        }
        if let Some(test) = &scenario.probe_test {
            truth["probe_test"] = probe::run::truth(test);
        }
        if let Some(test) = &scenario.spindle_test {
            truth["spindle_test"] = spindle::run::truth(&scenario.twin, test);
        }
        if let Some(states) = thermal_truth {
            truth["thermal_states"] = states;
        }
        round_numbers(&mut truth);
        files.push(("truth.json".into(), to_json_bytes(&truth)));

        let listed: Vec<Value> = files
        .iter()
        .map(|(name, bytes)| json!({ "name": name, "bytes": bytes.len(), "sha256": sha256_hex(bytes) }))
        .collect();
        let manifest = json!({
            "mtwin_version": env!("CARGO_PKG_VERSION"),
            "scenario": { "file": file_name(&scenario.file), "sha256": scenario.sha256 },
            "machine": {
                "name": scenario.twin.machine.name(),
                "file": file_name(&scenario.machine_file),
                "sha256": scenario.machine_sha256,
            },
            "seed": scenario.seed,
            "volumetric_model": scenario.volumetric.as_ref().map(|v| v.model.name()),
            "files": listed,
        });
        files.push(("manifest.json".into(), to_json_bytes(&manifest)));
        Ok(RunOutput { files })
    }

    /// The measurement tables alone (`output`'s files before `truth.json`), as `(file name,
    /// bytes)`: what a dataset keeps of a case. Every number in them is finite, or this fails
    /// naming the first that is not.
    pub fn tables(&self, scenario: &Scenario) -> Result<Vec<(String, Vec<u8>)>, RunError> {
        let mut files: Vec<(String, Vec<u8>)> = Vec::new();
        if let Some(map) = &self.volumetric {
            let mut bytes = Vec::new();
            map.write_csv(&mut bytes)
                .expect("writing to memory cannot fail");
            files.push(("volumetric.csv".into(), bytes));
        }
        if let Some(run) = &self.laser {
            let mut bytes = Vec::new();
            run.table
                .write_csv(&mut bytes)
                .expect("writing to memory cannot fail");
            files.push(("positioning.csv".into(), bytes));
        }
        let circles = scenario.ballbar_test.iter().flat_map(|t| &t.circles);
        for (circle, table) in circles.zip(&self.ballbar) {
            let mut bytes = Vec::new();
            table
                .write_csv(&mut bytes)
                .expect("writing to memory cannot fail");
            files.push((format!("ballbar_{}.csv", circle.plane.lower()), bytes));
        }
        if let Some(run) = &self.etve {
            let mut bytes = Vec::new();
            run.table
                .write_csv(&mut bytes)
                .expect("writing to memory cannot fail");
            files.push(("drift.csv".into(), bytes));
        }
        if let Some(run) = &self.spindle_thermal {
            let mut bytes = Vec::new();
            run.table
                .write_csv(&mut bytes)
                .expect("writing to memory cannot fail");
            files.push(("drift.csv".into(), bytes));
        }
        if let Some(table) = &self.rtest {
            let rotary: Vec<_> = scenario
                .twin
                .machine
                .rotary_axes()
                .map(|i| i.axis)
                .collect();
            files.push(("rtest.csv".into(), table.to_csv(&rotary)));
        }
        if let Some(run) = &self.probe {
            let mut bytes = Vec::new();
            run.probe
                .write_csv(&mut bytes)
                .expect("writing to memory cannot fail");
            files.push(("probe.csv".into(), bytes));
            let mut bytes = Vec::new();
            run.spheres
                .write_csv(&mut bytes)
                .expect("writing to memory cannot fail");
            files.push(("spheres.csv".into(), bytes));
        }
        if let Some(table) = &self.spindle {
            files.push((
                "spindle.csv".into(),
                spindle::table::write_csv(table).into_bytes(),
            ));
        }
        for (file, bytes) in &files {
            if let Some((line, column, value)) = crate::io::first_non_finite(bytes) {
                return Err(RunError::NotFiniteTable {
                    file: file.clone(),
                    line,
                    column,
                    value,
                });
            }
        }
        Ok(files)
    }
}

impl RunOutput {
    /// The files already in `dir` that this run does not write (another run's, left as they
    /// are): names in order, hidden files left out. Empty when `dir` does not exist.
    pub fn others_in(&self, dir: &Path) -> Vec<String> {
        let Ok(entries) = std::fs::read_dir(dir) else {
            return Vec::new();
        };
        let mut others: Vec<String> = entries
            .filter_map(|e| e.ok())
            .filter(|e| e.path().is_file())
            .map(|e| e.file_name().to_string_lossy().into_owned())
            .filter(|name| !name.starts_with('.') && !self.files.iter().any(|(n, _)| n == name))
            .collect();
        others.sort();
        others
    }
}

/// Refuses a folder that holds a dataset (`mtwin dataset`): a run's files there would replace
/// its `manifest.json`. A run folder, an empty or absent one, or one with other files is fine
/// (a run leaves files it does not write as they are).
pub fn check_run_folder(dir: &Path) -> Result<(), RunError> {
    match super::folder::holds(dir) {
        super::folder::Holds::Dataset(holds) => Err(RunError::Folder {
            dir: dir.display().to_string(),
            holds,
        }),
        _ => Ok(()),
    }
}

/// Writes the files into `dir` (created if needed), all or none: see [`crate::io::write_files`].
/// A folder holding a dataset is refused ([`check_run_folder`]).
pub fn write_outputs(output: &RunOutput, dir: &Path) -> Result<(), RunError> {
    check_run_folder(dir)?;
    Ok(crate::io::write_files(&output.files, dir)?)
}

/// Every injected parameter, as written (file units), with where it acts, plus the linear
/// coefficients in SI in the order of the Jacobian.
fn truth(scenario: &Scenario) -> Value {
    let machine = &scenario.twin.machine;
    let mut errors = serde_json::Map::new();
    for parameter in scenario.twin.errors.parameters() {
        let name = parameter.name;
        let (kind, axis) = match name {
            ParameterName::Component { axis, .. } => ("component", Some(axis)),
            ParameterName::Location { axis, .. } if axis.is_linear() => ("squareness", Some(axis)),
            ParameterName::Location { axis, .. } => ("location", Some(axis)),
            ParameterName::Tool { .. } => ("tool", None),
        };
        let side = axis
            .and_then(|a| machine.axis(a))
            .map_or(Side::Tool, |info| info.side);
        errors.insert(
            name.to_string(),
            json!({
                "kind": kind,
                "axis": axis.map(|a| a.to_string()),
                "axis_side": if side == Side::Tool { "tool" } else { "workpiece" },
                "unit": name.file_unit(),
                "terms": scenario.error_specs.get(&name.to_string()),
            }),
        );
    }
    let coefficients: Vec<Value> = scenario
        .twin
        .errors
        .coefficient_labels()
        .into_iter()
        .zip(scenario.twin.errors.coefficients())
        .map(|(label, value)| json!({ "label": label, "value_si": value }))
        .collect();
    let laser_test = scenario.laser_test.as_ref().map(positioning::run::truth);
    let thermal_model = scenario.thermal.as_ref().map(ThermalSetup::truth);
    json!({
        "mtwin": "truth",
        "schema": 1,
        "machine": machine.name(),
        "machine_sha256": scenario.machine_sha256,
        "scenario_sha256": scenario.sha256,
        "seed": scenario.seed,
        "laser_test": laser_test,
        "ballbar_test": scenario.ballbar_test.as_ref().map(ballbar::run::truth),
        "thermal_model": thermal_model,
        "convention": "deviation = actual - nominal, workpiece frame. Component, tool and zero-position errors are \
                       motions of the tool relative to the workpiece in the frame of their axis; location errors \
                       (E?0?) are the axis line itself, actual - nominal, zero at the axis zero (ISO 230-1 names)",
        "errors": errors,
        "coefficients_si": coefficients,
    })
}

/// Every number of `value` rounded to 12 significant digits, so that values converted between
/// file units and SI read back as written (`0.1`, not `0.09999999999999999`); 12 digits keep
/// 1 pm in 1 m.
fn round_numbers(value: &mut Value) {
    match value {
        Value::Number(n) if n.is_f64() => {
            if let Some(x) = n.as_f64()
                && let Ok(rounded) = format!("{x:.11e}").parse::<f64>()
                && let Some(number) = serde_json::Number::from_f64(rounded)
            {
                *n = number;
            }
        }
        Value::Array(items) => items.iter_mut().for_each(round_numbers),
        Value::Object(map) => map.values_mut().for_each(round_numbers),
        _ => {}
    }
}

/// A JSON file's bytes: pretty-printed, one newline at the end.
pub(super) fn to_json_bytes(value: &Value) -> Vec<u8> {
    let mut bytes = serde_json::to_vec_pretty(value).expect("JSON values serialise");
    bytes.push(b'\n');
    bytes
}

fn file_name(path: &Path) -> String {
    path.file_name().map_or_else(
        || path.display().to_string(),
        |n| n.to_string_lossy().into_owned(),
    )
}

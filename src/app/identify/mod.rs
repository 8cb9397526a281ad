//! `mtwin identify`: measurement tables of any registered kind → readings → the estimate, its
//! report, and the identified machine written out for compensation.

use crate::errors::{ErrorFunction, ErrorModel};
use crate::estimate::fit::{self, EstimateError, Problem};
use crate::estimate::spec::{ParameterSet, SpecError};
use crate::estimate::{Readings, ReadingsError, compensate, report};
use crate::io::TableError;
use crate::kinds::{ballbar, positioning, probe, rtest};
use crate::machine::{Axis, Machine, MachineError};
use crate::math::Real;
use crate::scenario::{ScenarioError, spec_of};
use serde_json::Value;
use std::collections::BTreeMap;
use std::path::{Path, PathBuf};

pub mod candidates;
pub mod checks;
pub mod orders;
pub mod provenance;
pub mod select;

use provenance::Provenance;

/// The table kinds `identify` reads, by the name a table's first line gives
/// (`# mtwin rtest table`) or a `KIND:` prefix on the path.
pub const TABLE_KINDS: [&str; 4] = ["rtest", "spheres", "positioning", "ballbar"];

/// Why `identify` failed.
#[derive(Debug, thiserror::Error)]
#[non_exhaustive]
pub enum IdentifyError {
    /// The machine model.
    #[error(transparent)]
    Machine(#[from] MachineError),
    /// A table could not be read.
    #[error(transparent)]
    Table(#[from] TableError),
    /// A table could not be turned into readings.
    #[error(transparent)]
    Readings(#[from] ReadingsError),
    /// The parameter SPEC.
    #[error(transparent)]
    Spec(#[from] SpecError),
    /// The estimate.
    #[error(transparent)]
    Estimate(#[from] EstimateError),
    /// The scenario to compensate.
    #[error(transparent)]
    Scenario(#[from] ScenarioError),
    /// Something else about an input, with the file.
    #[error("{0}")]
    Input(String),
    /// The fit failed its own checks ([`checks`]): nothing is written.
    #[error(
        "the fit fails its own checks, so no estimate or compensation is written:\n{}\n{}\n(--accept-implausible writes them all the same, with these warnings)",
        .0.problems.iter().map(|p| format!("  - {p}")).collect::<Vec<_>>().join("\n"),
        .0.cause
    )]
    Implausible(checks::Findings),
    /// The tables' own data contradict counting them as given ([`Loaded::problems`]): no fit
    /// is made and nothing is written.
    #[error(
        "the tables fail their own checks, so no fit is made and no estimate or compensation is written:\n{}\n{}\n(--accept-implausible fits and writes them all the same, with these warnings)",
        .0.problems.iter().map(|p| format!("  - {p}")).collect::<Vec<_>>().join("\n"),
        .0.cause
    )]
    Contradicted(checks::Findings),
}

/// What `identify` is asked.
#[derive(Clone, Debug)]
pub struct Request {
    /// The machine model (URDF).
    pub machine: PathBuf,
    /// The parameters (see [`crate::estimate::spec`]).
    pub params: String,
    /// The tables, each `PATH` or `KIND:PATH`.
    pub tables: Vec<String>,
    /// Standard uncertainty per reading by kind (m), overriding the defaults.
    pub sigma: BTreeMap<String, Real>,
    /// The R-test sphere position is unknown (no preset at the first pose).
    pub free_setup: bool,
    /// Whether and how the R-test pivot drifts in time (see
    /// [`crate::kinds::rtest::readings::Setup::drift`]).
    pub drift: rtest::readings::Drift,
    /// Model selection first ([`crate::estimate::discover`]): the terms the held-out tests
    /// support join `params` before the estimate.
    pub discover: bool,
    /// Standard uncertainty of the R-test sphere position (m), overriding the default.
    pub sphere_setup: Option<Real>,
    /// The R-test sphere centre (workpiece frame, m) for tables that do not state it.
    pub rtest_sphere: Option<crate::math::Vector>,
    /// Monte Carlo trials.
    pub trials: usize,
    /// Monte Carlo seed.
    pub seed: u64,
    /// The scenario the tables were simulated from: a `compensated.toml` extending it is
    /// written (its errors minus the estimate), for `mtwin run`.
    pub scenario: Option<PathBuf>,
    /// Write the estimate and the compensation even when the fit fails its checks (as
    /// warnings); by default such a fit is refused.
    pub accept_implausible: bool,
    /// Where the Monte Carlo reports the trials it has done, if anywhere.
    pub progress: Option<fit::Progress>,
}

/// What `identify` produced.
pub struct Identified {
    /// The report for people.
    pub text: String,
    /// `estimate.json`.
    pub json: Value,
    /// Files for `--out` (name, bytes).
    pub files: Vec<(String, Vec<u8>)>,
}

/// The kind of a table: its `KIND:` prefix, or its first line `# mtwin KIND table`.
fn kind_of(argument: &str) -> Result<(String, PathBuf), IdentifyError> {
    if let Some((kind, path)) = argument.split_once(':')
        && TABLE_KINDS.contains(&kind)
    {
        return Ok((kind.to_string(), PathBuf::from(path)));
    }
    let path = PathBuf::from(argument);
    let text = std::fs::read_to_string(&path)
        .map_err(|e| IdentifyError::Input(format!("{argument}: cannot read: {e}")))?;
    let first = text
        .lines()
        .next()
        .unwrap_or("")
        .trim_start_matches('\u{feff}');
    TABLE_KINDS
        .iter()
        .find(|k| first.starts_with(&format!("# mtwin {k} table")))
        .map(|k| (k.to_string(), path))
        .ok_or_else(|| {
            IdentifyError::Input(format!(
                "{argument}: which measurement is this? Its first line does not say (`# mtwin rtest table`); prefix the path with its kind: {}",
                TABLE_KINDS.map(|k| format!("{k}:{argument}")).join(", ")
            ))
        })
}

/// The machine a table's preamble names (`# machine = NAME`), if it does.
fn machine_named(path: &Path) -> Option<String> {
    let text = std::fs::read_to_string(path).ok()?;
    text.lines()
        .take_while(|line| line.starts_with('#'))
        .find_map(|line| line.strip_prefix("# machine = "))
        .map(|name| name.trim().to_string())
}

/// The tables read for a fit.
pub struct Loaded {
    /// Each table's readings.
    pub sets: Vec<Readings>,
    /// What each table's folder says of where it came from.
    pub provenances: Vec<Provenance>,
    /// What the tables' own data say against counting them as given (a block copied inside
    /// a table, a ball-bar of one sense, a laser table covering a sliver of its axis), each a
    /// sentence naming the file: `identify` compensates from none of them.
    pub problems: Vec<String>,
    /// What each table's data say that `analyze` would print as a caution (a lone reading,
    /// a laser without air compensation in warm air, direction labels swapped, a stuck
    /// probe), each a sentence naming the file: the fit is made, and the estimate carries them.
    pub cautions: Vec<String>,
    /// The set-ups the tables were measured with ([`candidates::setup_key`]): an added test
    /// on one of them costs no set-up time.
    pub setups: Vec<String>,
    /// The sphere of the first R-test table (else of the first probing table), workpiece
    /// frame (m), where the tables say: where the remedies' R-tests and probing cycles stand.
    pub sphere: Option<crate::math::Vector>,
}

/// Reads every table into readings for `machine` ([`Loaded`]).
pub fn load_readings(request: &Request, machine: &Machine) -> Result<Loaded, IdentifyError> {
    let mut sets = Vec::new();
    let mut provenances = Vec::new();
    let mut problems = Vec::new();
    let mut cautions = Vec::new();
    let mut setups = Vec::new();
    let (mut rtest_sphere, mut probe_sphere) = (None, None);
    // The data rows of each table read so far, by their hash: a table given twice (or a
    // renamed copy) would count its readings twice and shrink every uncertainty by √2.
    let mut seen: BTreeMap<String, String> = BTreeMap::new();
    for argument in &request.tables {
        let (kind, path) = kind_of(argument)?;
        let file = path.display().to_string();
        let bytes = std::fs::read(&path)
            .map_err(|e| IdentifyError::Input(format!("{file}: cannot read: {e}")))?;
        let rows: Vec<&[u8]> = bytes
            .split(|b| *b == b'\n')
            .map(<[u8]>::trim_ascii)
            .filter(|l| !l.is_empty() && !l.starts_with(b"#"))
            .collect();
        provenances.push(Provenance::of(&path, &file, &bytes));
        let hash = crate::math::sha256_hex(&rows.join(&b'\n'));
        if let Some(earlier) = seen.insert(hash, file.clone()) {
            return Err(IdentifyError::Input(format!(
                "{file}: the same data rows as {earlier}: a table given twice would count its readings twice (every uncertainty √2 too small); give each measurement once"
            )));
        }
        if let Some(named) = machine_named(&path).filter(|n| n != machine.name()) {
            return Err(EstimateError::OtherMachine {
                file,
                table: named,
                machine: machine.name().to_string(),
            }
            .into());
        }
        let sigma = request.sigma.get(&kind).copied();
        match kind.as_str() {
            "rtest" => {
                let table = rtest::RtestTable::read(&path)?;
                let mut setup = rtest::readings::Setup {
                    free_sphere: request.free_setup,
                    drift: request.drift,
                    ..Default::default()
                };
                if let Some(s) = sigma {
                    setup.sigma = s;
                }
                if let Some(u) = request.sphere_setup {
                    setup.sphere_uncertainty = u;
                }
                setup.sphere = request.rtest_sphere;
                let sphere = (request.rtest_sphere)
                    .or_else(|| rtest::readings::sphere_of(&table, &file).ok());
                if let Some(sphere) = sphere {
                    setups.push(candidates::setup_key(candidates::Setup::Rtest(sphere)));
                    rtest_sphere = rtest_sphere.or(Some(sphere));
                }
                problems
                    .extend(rtest::plausible::copied_test(&table).map(|c| format!("{file}: {c}")));
                cautions.extend(
                    rtest::plausible::cautions(&table)
                        .into_iter()
                        .map(|c| format!("{file}: {c}")),
                );
                sets.push(rtest::readings::readings(&table, &file, machine, setup)?);
            }
            "spheres" => {
                let table = probe::SpheresTable::read(&path)?;
                let s = sigma.unwrap_or(probe::readings::DEFAULT_SIGMA);
                problems.extend(table.copied_sphere().map(|c| format!("{file}: {c}")));
                // Where the nominal chain puts the first sphere cycle's first centre, as the
                // readings' start has it.
                let first =
                    (table.spheres.iter()).find(|row| row.key.kind == probe::CycleKind::Sphere);
                if let Some(row) = first {
                    let mut axes = crate::machine::AxisValues::ZERO;
                    for (angle, axis) in row.key.rotary.iter().zip([Axis::A, Axis::B, Axis::C]) {
                        axes[axis] = angle.unwrap_or(0.0);
                    }
                    axes[Axis::X] = row.centre.x;
                    axes[Axis::Y] = row.centre.y;
                    axes[Axis::Z] = row.centre.z;
                    let sphere = machine.workpiece_from_tool(&axes).translation;
                    setups.push(candidates::setup_key(candidates::Setup::Probe(sphere)));
                    probe_sphere = probe_sphere.or(Some(sphere));
                }
                sets.push(probe::readings::readings(&table, &file, machine, s)?);
            }
            "positioning" => {
                let table = positioning::PositioningTable::read(&path)?;
                let mut setup = positioning::readings::Setup::default();
                if let Some(s) = sigma {
                    setup.sigma = s;
                }
                problems.extend(
                    positioning::plausible::copied_run(&table).map(|c| format!("{file}: {c}")),
                );
                problems.extend(short_coverage(&table, machine).map(|c| format!("{file}: {c}")));
                if let Some(axis) = table.axis {
                    setups.push(candidates::setup_key(candidates::Setup::Laser(axis)));
                }
                cautions.extend(
                    positioning::plausible::cautions(&table)
                        .into_iter()
                        .map(|c| format!("{file}: {c}")),
                );
                sets.push(positioning::readings::readings(
                    &table, &file, machine, &setup,
                )?);
            }
            "ballbar" => {
                let table = ballbar::BallbarTable::read(&path)?;
                if let Some(plane) = table.conditions.plane {
                    setups.push(candidates::setup_key(candidates::Setup::Ballbar(plane)));
                }
                let mut setup = ballbar::readings::Setup::default();
                if let Some(s) = sigma {
                    setup.sigma = s;
                }
                problems.extend(
                    ballbar::plausible::copied_sweep(&table).map(|c| format!("{file}: {c}")),
                );
                problems.extend(
                    ballbar::plausible::stated_speed_contradiction(&table)
                        .map(|c| format!("{file}: {c}")),
                );
                if let (Some(radius), Some(feed)) = (table.conditions.radius, table.conditions.feed)
                    && let Some(plane) = table.conditions.plane
                {
                    let test = ballbar::iso230_4::CircularTest {
                        plane,
                        radius,
                        feed,
                    };
                    problems.extend(
                        ballbar::plausible::one_sense(&table, &test)
                            .map(|c| format!("{file}: {c}")),
                    );
                    cautions.extend(
                        ballbar::plausible::cautions(&table, &test)
                            .into_iter()
                            .map(|c| format!("{file}: {c}")),
                    );
                }
                sets.push(ballbar::readings::readings(&table, &file, machine, &setup)?);
            }
            other => unreachable!("{other} is not in TABLE_KINDS"),
        }
    }
    // Readings rounded more coarsely than their stated uncertainty: the rounding, not the
    // noise, sets the residuals, and it does not average out along a smooth trace.
    for set in &sets {
        let sigma = set.mean_sigma();
        if let Some(step) = crate::io::plausible::rounded_to(&set.measured)
            && step / 12f64.sqrt() > sigma
        {
            problems.push(format!(
                "{}: every reading is a whole multiple of {} µm: the rounding alone ({} µm) exceeds the readings' stated uncertainty ({} µm); export at the instrument's resolution, or state --sigma-um of at least the rounding",
                set.source,
                crate::math::trimmed(step * 1e6, 3),
                crate::math::trimmed(step / 12f64.sqrt() * 1e6, 3),
                crate::math::trimmed(sigma * 1e6, 3)
            ));
        }
    }
    cautions.retain(|c| !problems.contains(c));
    Ok(Loaded {
        sets,
        provenances,
        problems,
        cautions,
        setups,
        sphere: rtest_sphere.or(probe_sphere),
    })
}

/// The smallest share of its axis's travel a laser table must cover for compensation: a
/// tenth. ISO 230-2 measures over the whole travel (up to 2 m); a compensation fitted over
/// less is extrapolated over the rest, and a table that covers a few percent is usually in
/// another unit (inches in `target_mm`: 760 mm of travel read as 30).
pub const SMALLEST_COVERAGE: crate::math::Real = 0.1;

/// The problem when `table`'s targets cover less than [`SMALLEST_COVERAGE`] of its axis's
/// travel on `machine`.
fn short_coverage(table: &positioning::PositioningTable, machine: &Machine) -> Option<String> {
    let axis = table.axis?;
    let (lower, upper) = machine.axis(axis)?.limits?;
    let covered = crate::io::plausible::spread(table.readings.iter().map(|r| r.target));
    (covered < SMALLEST_COVERAGE * (upper - lower)).then(|| {
        format!(
            "column `target_mm`: the targets cover {} mm of {axis}'s {} mm of travel, less than a tenth: a compensation from them would be extrapolated over the rest (inches or metres in the mm column?)",
            crate::math::trimmed(covered * 1e3, 3),
            crate::math::trimmed((upper - lower) * 1e3, 3)
        )
    })
}

/// Runs `identify`.
pub fn identify(request: &Request) -> Result<Identified, IdentifyError> {
    let machine = Machine::from_urdf_file(&request.machine)?;
    // Model selection first: the estimate is then that of the extended parameters.
    let discovery = match request.discover {
        true => Some(select::select(request, &machine)?),
        false => None,
    };
    let extended;
    let request = match &discovery {
        Some(found) => {
            extended = Request {
                params: found.params(),
                drift: if found.drift() {
                    rtest::readings::Drift::Rate
                } else {
                    request.drift
                },
                ..request.clone()
            };
            &extended
        }
        None => request,
    };
    let set = ParameterSet::parse(&request.params, &machine)?;
    let Loaded {
        sets,
        provenances,
        problems: data_problems,
        cautions: table_cautions,
        setups,
        sphere,
    } = load_readings(request, &machine)?;
    // What the tables' own data contradict is refused before any fit (the fit would only
    // dress it in estimates), unless the user accepts it.
    let data_cause = "likely cause: the tables' own data contradict counting them as given: \
                      remove the copy, correct the column's unit, or measure what is missing \
                      (a ball-bar's other sense; where the axes' servo gains are known to be \
                      matched, --accept-implausible fits one sense all the same)";
    if !data_problems.is_empty() && !request.accept_implausible {
        return Err(IdentifyError::Contradicted(checks::Findings {
            problems: data_problems,
            cause: data_cause.into(),
        }));
    }
    let scenario = match &request.scenario {
        Some(path) => Some(matching_scenario(path, &request.machine, &provenances)?),
        None => None,
    };
    let sources: Vec<String> = sets.iter().map(|s| s.source.clone()).collect();
    let problem = Problem::new(&machine, &set, &sets)?;
    let options = fit::Options {
        trials: request.trials,
        seed: request.seed,
        progress: request.progress.clone(),
        ..Default::default()
    };
    let fit = fit::estimate(&problem, &options)?;
    let machine_file = std::path::absolute(&request.machine)
        .unwrap_or_else(|_| request.machine.clone())
        .display()
        .to_string();
    let mut json = report::to_json(&set, &problem, &fit, &machine, &machine_file, &sources);
    let mut text = report::text(&set, &problem, &fit, &sources);
    json["provenance"] = provenances.iter().map(Provenance::to_json).collect();
    json["scenario_sha256"] = provenance::common_scenario(&provenances)
        .ok()
        .flatten()
        .into();
    if provenances.iter().all(|p| p.scenario.is_none()) {
        text += "\nProvenance: no table names the scenario it was made from (no manifest.json of `mtwin run` beside it, or the table edited since): that the tables are of this machine, and each of the axis or plane it says, rests on their own labels";
        text += if scenario.is_some() {
            "; compensated.toml assumes they come from --scenario.\n"
        } else {
            ".\n"
        };
    }
    if let Some(by_order) = orders::by_order(&machine, &set, &sets) {
        text += &by_order.text();
        json["identifiability_by_order"] = by_order.to_json();
    }
    if !fit.identifiability.null_combinations.is_empty() {
        let site = candidates::Site {
            sphere,
            rtest_sigma: (sets.iter().find(|s| s.kind == "rtest"))
                .map_or(rtest::readings::Setup::default().sigma, |s| s.sigma[0]),
            free_sphere: request.free_setup,
        };
        let tests = candidates::candidates(&machine, &set, &site, &TABLE_KINDS);
        let found = candidates::remedies(&set, &problem, &tests, &setups);
        text += &candidates::remedies_text(&found);
        json["remedies"] = found.iter().map(candidates::Remedy::to_json).collect();
    }
    let identified = report::identified_model(&set, &problem, &fit, &machine);
    let mut findings = checks::check(&fit, &sets, &sources, &identified, &machine);
    if !data_problems.is_empty() {
        if findings.passed() {
            findings.cause = data_cause.into();
        }
        findings.problems.extend(data_problems);
    }
    if !findings.passed() {
        if !request.accept_implausible {
            return Err(IdentifyError::Implausible(findings));
        }
        let mut caution = String::from(
            "CAUTION: the fit fails its own checks (written because of --accept-implausible):\n",
        );
        for problem in &findings.problems {
            caution += &format!("  - {problem}\n");
        }
        caution += &format!("  {}\n\n", findings.cause);
        text = caution + &text;
        json["warnings"] = serde_json::json!(findings.problems);
        json["warnings_cause"] = serde_json::json!(findings.cause);
    }
    if let Some(found) = &discovery {
        text = found.text() + &text;
        json["discovery"] = found.to_json();
    }
    let mut cautions = table_cautions;
    cautions.extend(checks::cautions(&fit));
    if !cautions.is_empty() {
        let said: String = cautions.iter().map(|c| format!("CAUTION: {c}\n")).collect();
        text = said + "\n" + &text;
        json["cautions"] = serde_json::json!(cautions);
    }
    let mut files = vec![(
        "estimate.json".to_string(),
        super::run::to_json_bytes(&json),
    )];
    let urdf_text = std::fs::read_to_string(&request.machine)
        .map_err(|e| IdentifyError::Input(format!("{machine_file}: cannot read: {e}")))?;
    let corrected = compensate::corrected_urdf(&urdf_text, &machine, &identified)
        .map_err(|e| IdentifyError::Input(format!("corrected URDF: {e}")))?;
    for (name, why) in &corrected.not_folded {
        text += &format!("not in {}_identified.urdf: {name}, {why}\n", machine.name());
    }
    files.push((
        format!("{}_identified.urdf", machine.name()),
        corrected.urdf.into_bytes(),
    ));
    // 10 mm and 1°, wider where LinuxCNC's 256 entries would not hold the travel (one turn
    // of a continuous axis at 1° is 361).
    let (spacing_m, spacing_rad) = compensate::linuxcnc_spacings(&machine, 0.01, 1f64.to_radians());
    let tables = compensate::linuxcnc_tables(&machine, &identified, spacing_m, spacing_rad)
        .map_err(|e| IdentifyError::Input(format!("LinuxCNC tables: {e}")))?;
    for (axis, table) in tables {
        files.push((format!("linuxcnc_{axis}.comp"), table.into_bytes()));
    }
    let tables =
        crate::estimate::sinumerik::lec_tables(&machine, &identified, 0.01, 1f64.to_radians())
            .map_err(|e| IdentifyError::Input(format!("SINUMERIK tables: {e}")))?;
    for (axis, table) in tables {
        files.push((format!("sinumerik_{axis}_eec.ini"), table.into_bytes()));
    }
    let tables =
        crate::estimate::heidenhain::com_tables(&machine, &identified, 0.01, 1f64.to_radians())
            .map_err(|e| IdentifyError::Input(format!("HEIDENHAIN tables: {e}")))?;
    for (axis, table) in tables {
        files.push((format!("heidenhain_{axis}.com"), table.into_bytes()));
    }
    if let Some((path, base)) = &scenario {
        files.push((
            "compensated.toml".to_string(),
            compensated_scenario(path, base, &identified)?.into_bytes(),
        ));
    }
    Ok(Identified { text, json, files })
}

/// The scenario `path` loaded, when it can be what the tables came from: it runs the machine
/// file `machine` (the same bytes), and every table whose folder names its scenario names
/// this one. Otherwise `compensated.toml` would subtract the estimate from another machine's
/// or another scenario's errors.
fn matching_scenario(
    path: &Path,
    machine: &Path,
    tables: &[Provenance],
) -> Result<(PathBuf, crate::app::Scenario), IdentifyError> {
    let scenario = crate::app::Scenario::load(path)?;
    let shown = path.display();
    let machine_bytes = std::fs::read(machine)
        .map_err(|e| IdentifyError::Input(format!("{}: cannot read: {e}", machine.display())))?;
    if crate::math::sha256_hex(&machine_bytes) != scenario.machine_sha256 {
        return Err(IdentifyError::Input(format!(
            "--scenario {shown} runs the machine {} (\"{}\"), not the file --machine {} gives (other bytes): compensated.toml would subtract this estimate from another machine's errors",
            scenario.machine_file.display(),
            scenario.twin.machine.name(),
            machine.display()
        )));
    }
    if let Some(table) = tables
        .iter()
        .find(|t| t.scenario.as_ref().is_some_and(|s| s.1 != scenario.sha256))
    {
        let (file, _) = table.scenario.as_ref().expect("found with a scenario");
        return Err(IdentifyError::Input(format!(
            "{}: its manifest.json says it was made from the scenario {file} (other bytes than --scenario {shown}): compensated.toml would subtract this estimate from another scenario's errors; give the scenario the tables were made from",
            table.file
        )));
    }
    Ok((path.to_path_buf(), scenario))
}

/// A scenario extending `scenario` whose errors are its own minus the estimate: the machine
/// after compensation with the identified model (first order: the controller subtracts the
/// predicted deviation).
fn compensated_scenario(
    scenario: &Path,
    base: &crate::app::Scenario,
    identified: &ErrorModel,
) -> Result<String, IdentifyError> {
    let mut out = format!(
        "# The machine of {} compensated with the identified errors (written by mtwin identify):\n\
         # each estimated parameter's truth minus its estimate.\n\
         schema = 1\nextends = {}\ndescription = \"compensated with mtwin identify\"\n",
        scenario.display(),
        toml::Value::String(
            std::path::absolute(scenario)
                .unwrap_or_else(|_| scenario.to_path_buf())
                .display()
                .to_string()
        )
    );
    for parameter in identified.parameters() {
        let truth = base.twin.errors.parameter(parameter.name);
        let negated = negate(&parameter.function);
        let remaining = match truth {
            Some(t) => ErrorFunction::Sum(vec![t.function.clone(), negated]),
            None => negated,
        };
        let spec = spec_of(&remaining, parameter.name);
        let mut table = toml::Table::new();
        table.insert(
            parameter.name.to_string(),
            toml::Value::try_from(spec).map_err(|e| IdentifyError::Input(e.to_string()))?,
        );
        let mut errors = toml::Table::new();
        errors.insert("errors".into(), toml::Value::Table(table));
        out += "\n";
        out += &toml::to_string(&errors).map_err(|e| IdentifyError::Input(e.to_string()))?;
    }
    Ok(out)
}

/// `−f`.
fn negate(function: &ErrorFunction) -> ErrorFunction {
    let mut out = function.clone();
    let mut coefficients = Vec::new();
    out.coefficients(&mut coefficients);
    coefficients.iter_mut().for_each(|c| *c = -*c);
    out.set_coefficients(&coefficients);
    out
}

/// What a plan may spend.
#[derive(Clone, Debug, PartialEq)]
pub enum Budget {
    /// Readings of R-tests (three per pose).
    Readings(usize),
    /// Minutes of tests of the given table kinds ([`TABLE_KINDS`]), by the planning figures of
    /// [`candidates`] (a set-up paid once for the tests made on it).
    Minutes {
        /// The minutes.
        minutes: Real,
        /// The kinds of test to choose from.
        kinds: Vec<String>,
    },
}

/// A test plan: from the candidate tests on `machine` ([`candidates::candidates`]; the R-tests
/// and probing cycles with the sphere at `sphere`, m, each R-test reading with the standard
/// uncertainty `sigma`, m), the tests that identify `params` best (D-optimal, greedy, then
/// exchanges) within `budget`. The sphere is needed when the kinds include R-tests or probing
/// cycles.
pub fn plan(
    machine_file: &Path,
    params: &str,
    sphere: Option<crate::math::Vector>,
    sigma: Real,
    budget: &Budget,
) -> Result<crate::estimate::plan::Plan, IdentifyError> {
    use crate::estimate::plan::{Costs, choose, choose_within};
    let machine = Machine::from_urdf_file(machine_file)?;
    let set = ParameterSet::parse(params, &machine)?;
    let kinds: Vec<&str> = match budget {
        Budget::Readings(_) => vec!["rtest"],
        Budget::Minutes { kinds, .. } => {
            if let Some(unknown) = kinds.iter().find(|k| !TABLE_KINDS.contains(&k.as_str())) {
                return Err(IdentifyError::Input(format!(
                    "test kind \"{unknown}\": expected one of {}",
                    TABLE_KINDS.join(", ")
                )));
            }
            kinds.iter().map(String::as_str).collect()
        }
    };
    if sphere.is_none() && kinds.iter().any(|k| ["rtest", "spheres"].contains(k)) {
        return Err(IdentifyError::Input(
            "--sphere-mm X,Y,Z: where the sphere of the R-tests and probing cycles stands (workpiece frame, mm); or leave them out with --kinds".into(),
        ));
    }
    let site = candidates::Site {
        sphere,
        rtest_sigma: sigma,
        free_sphere: false,
    };
    let tests = candidates::candidates(&machine, &set, &site, &kinds);
    if tests.is_empty() {
        return Err(IdentifyError::Input(format!(
            "{}: no test of the kinds {} can be planned on machine \"{}\" (the linear axes cannot follow the sphere, the machine has no rotary axis, or the kinds see none of the parameters)",
            machine_file.display(),
            kinds.join(", "),
            machine.name()
        )));
    }
    let designs: Vec<(String, nalgebra::DMatrix<Real>)> = (tests.iter())
        .map(|c| (c.name.clone(), c.design.clone()))
        .collect();
    let options = crate::estimate::identifiability::Options::default();
    Ok(match budget {
        Budget::Readings(readings) => choose(None, &designs, &set.labels, *readings, &options),
        Budget::Minutes { minutes, .. } => {
            let costs = Costs {
                run: tests.iter().map(|c| c.run_minutes).collect(),
                setup: (tests.iter())
                    .map(|c| Some((c.setup.clone(), c.setup_minutes)))
                    .collect(),
                present: Vec::new(),
                unit: "min",
            };
            choose_within(None, &designs, &costs, &set.labels, *minutes, &options)
        }
    })
}

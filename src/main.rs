//! `mtwin`: the command line of the machine-tool twin (a thin layer over the library).
//! `run` and `check` work on scenarios; `analyze` and `discover` have one subcommand per test
//! kind that serves them, taken from the registry ([`mtwin::kinds::KINDS`]).

use anyhow::{Result, bail};
use clap::builder::TypedValueParser as _;
use clap::{CommandFactory, FromArgMatches, Parser, Subcommand};
use mtwin::app::{Scenario, ScenarioFiles, Simulation, simulate, write_outputs};
use mtwin::kinds::{KINDS, Kind, Verb};
use mtwin::machine::{Machine, Side};
use std::path::{Path, PathBuf};
use std::process::ExitCode;

/// `println!` to standard output that does not panic when the reader has gone (`mtwin … |
/// head`): what cannot be printed is dropped.
macro_rules! say {
    ($($arg:tt)*) => {{
        use std::io::Write as _;
        let _ = writeln!(std::io::stdout(), $($arg)*);
    }};
}

/// `print!` of a whole report, likewise.
fn say_raw(text: &str) {
    use std::io::Write as _;
    let _ = std::io::stdout().write_all(text.as_bytes());
}

/// The binary's own modules live in `src/main/`, apart from the library's.
#[path = "main/dataset.rs"]
mod dataset;

/// The fewest Monte Carlo trials `identify` runs (a 95 % interval's tails need several
/// trials each beyond them).
const MIN_TRIALS: usize = 200;

/// A digital twin of a machine tool for metrology.
#[derive(Parser)]
#[command(version, about, long_about = None)]
struct Cli {
    #[command(subcommand)]
    command: Command,
}

#[derive(Subcommand)]
enum Command {
    /// Simulate a scenario: writes what it asks for (volumetric.csv, positioning.csv,
    /// ballbar_<plane>.csv), with truth.json and manifest.json, into --out.
    Run {
        /// The scenario (TOML).
        scenario: PathBuf,
        /// Output folder (created if needed; files in it with the same names are replaced).
        #[arg(long, value_name = "DIR")]
        out: PathBuf,
        /// Also write a teaching recording of the scenario for the rerun viewer 0.36
        /// (`rerun FILE.rrd`): the machine moving, its errors enlarged, every instrument's
        /// scene and discovery. Needs mtwin built with `--features viz`.
        #[arg(long, value_name = "FILE.rrd")]
        rrd: Option<PathBuf>,
    },
    /// Make a dataset: --count cases drawn from the priors of the scenario's [dataset]
    /// section, each run like `mtwin run`, written as Parquet into --out (a `cases` table with
    /// every drawn value, one table per measurement, manifest.json and a README.md dataset
    /// card). Case K depends on the seed and K alone. Shards are written whole (temporary
    /// names, then renamed) and recorded in _shards/; rerunning the same command skips
    /// complete shards and redoes the others. With --shard I/N only shard I is made (one
    /// process per shard on a cluster: the last to finish writes manifest.json).
    Dataset {
        /// The scenario (TOML) with a [dataset] section.
        scenario: PathBuf,
        /// Number of cases (default: [dataset] count).
        #[arg(long, value_name = "N", allow_negative_numbers = true)]
        count: Option<u64>,
        /// The dataset folder (created if needed), or with --case the run folder.
        #[arg(long, value_name = "DIR")]
        out: PathBuf,
        /// Shard layout (default: [dataset] shards, else one shard per 10 000 cases).
        #[arg(long, value_name = "N", allow_negative_numbers = true)]
        shards: Option<u64>,
        /// Make only shard I of N (0-based).
        #[arg(long, value_name = "I/N", conflicts_with = "shards")]
        shard: Option<String>,
        /// Worker threads, 1 to 1024 (default: all cores). The files do not depend on it.
        #[arg(long, value_name = "T", allow_negative_numbers = true,
              value_parser = clap::value_parser!(i64).range(1..=MAX_THREADS).map(|t| t as usize))]
        threads: Option<usize>,
        /// Write case K alone as a run folder, as `mtwin run` would (its tables, truth.json,
        /// manifest.json) with case.json (its seed, split and drawn values).
        #[arg(long, value_name = "K", conflicts_with_all = ["shard", "shards", "count", "threads"], allow_negative_numbers = true)]
        case: Option<u64>,
    },
    /// Validate a scenario (.toml) or a machine model (.urdf) without running it.
    Check {
        /// The file.
        file: PathBuf,
    },
    /// Estimate error parameters from measurement tables (R-test, sphere probing, laser
    /// positioning, ball-bar): identifiability first (what the tables cannot tell apart, in
    /// ISO names), then a Levenberg-Marquardt fit on the twin's exact chain, weighted by each
    /// instrument's uncertainty, with standard uncertainties, 95 % intervals and, with
    /// --monte-carlo, a GUM Supplement 1 propagation. With --out: estimate.json, the identified
    /// machine as a URDF, LinuxCNC pitch tables, and with --scenario a compensated scenario.
    Identify {
        /// The machine model the tables were measured on (URDF).
        #[arg(long, value_name = "M.urdf")]
        machine: PathBuf,
        /// The parameters: ISO names (EX0C, EC0Y, EXX:3 a polynomial, EXC:2 a rotary axis's
        /// Fourier series), lost motions (EXX.reversal, ECC.reversal) and presets (location,
        /// zero, squareness, tool, linear21[:N], reversal: every linear axis's lost motion,
        /// rotary_components[:C][:N]: the six component errors of the rotary axes), separated
        /// by commas.
        #[arg(long, value_name = "SPEC")]
        params: String,
        /// Measurement tables; a table whose first line does not name its kind takes a
        /// prefix: rtest:FILE, spheres:FILE, positioning:FILE, ballbar:FILE.
        #[arg(required = true, value_name = "TABLE")]
        tables: Vec<String>,
        /// Standard uncertainty of each reading of a kind, overriding its default
        /// (rtest 0.2, spheres 0.5, positioning 0.02, ballbar 0.104 µm), e.g.
        /// --sigma-um rtest=0.3 (repeatable).
        #[arg(long = "sigma-um", value_name = "KIND=UM")]
        sigma_um: Vec<String>,
        /// The R-test sphere position is unknown (no preset at the first pose): estimate it too.
        #[arg(long)]
        free_setup: bool,
        /// The R-test pivot drifts in time (thermal drift), each test its own zero; needs the
        /// tables' time_s. --drift (or --drift=per-test): each test linearly by its own
        /// amount, three nuisances per test; --drift=rate: at one rate through each table,
        /// three nuisances (µm per hour).
        #[arg(long, value_name = "FORM", num_args = 0..=1, require_equals = true,
              default_missing_value = "per-test", value_parser = ["per-test", "rate"])]
        drift: Option<String>,
        /// Model selection first: from --params (the base), add from a library (each rotary
        /// axis's component errors order by order, lost motions, squareness, a drift rate)
        /// the terms that predict K-tests and spheres held out of the fit better than noise
        /// can explain, report each with its held-out gain, then estimate with them.
        #[arg(long)]
        discover: bool,
        /// Standard uncertainty of the R-test sphere's position as the preset found it (µm;
        /// default 0.5), a set-up input of the Monte Carlo.
        #[arg(long, value_name = "UM", allow_negative_numbers = true)]
        sphere_setup_um: Option<f64>,
        /// The R-test sphere centre in the workpiece frame (mm), for an R-test export whose
        /// preamble does not state it.
        #[arg(
            long,
            value_name = "X,Y,Z",
            value_delimiter = ',',
            allow_negative_numbers = true
        )]
        rtest_sphere_mm: Option<Vec<f64>>,
        /// Monte Carlo trials (GUM Supplement 1) propagating the instruments' noise and the
        /// set-up uncertainties through the twin; 0 for none, at most 1 000 000 (the 10^6
        /// trials GUM Supplement 1 §7.2 expects to give a 95 % interval to one or two
        /// significant digits), run in batches of 10 000 with a progress bar.
        #[arg(long, value_name = "N", default_value_t = 0, allow_negative_numbers = true,
              value_parser = clap::value_parser!(i64).range(0..=MAX_MONTE_CARLO).map(|n| n as usize))]
        monte_carlo: usize,
        /// Seed of the Monte Carlo.
        #[arg(long, default_value_t = 1, allow_negative_numbers = true)]
        seed: u64,
        /// The scenario the tables were simulated from: --out then holds compensated.toml,
        /// that scenario compensated with the estimate, for `mtwin run`.
        #[arg(long, value_name = "SCENARIO.toml")]
        scenario: Option<PathBuf>,
        /// Print estimate.json instead of the report.
        #[arg(long)]
        json: bool,
        /// Report and write the estimate even when the fit fails its own checks (χ²/dof above
        /// 100, an estimate beyond 10 mm or 10 mrad, a residual beyond 1 mm, a number not
        /// finite), with the failures as warnings. Without it such a fit is refused and
        /// nothing is written.
        #[arg(long)]
        accept_implausible: bool,
        /// Write estimate.json, the identified URDF, LinuxCNC tables (and compensated.toml).
        #[arg(long, value_name = "DIR")]
        out: Option<PathBuf>,
    },
    /// Test design: from candidate R-tests (turns of the table at every 15° of the tilting
    /// axis, sweeps of the tilting axis; with a rotary axis's component errors in --params,
    /// each also with the sphere 80 mm higher and 60 mm further out), choose those that make
    /// the parameters identifiable with the smallest uncertainty for the readings spent
    /// (D-optimal: greedy, then exchanges of one test for another), and show the predicted
    /// standard uncertainty of every parameter after each test. With --budget-min, from
    /// candidates of every kind (also probing cycles at the R-tests' positions, laser lines
    /// along each linear axis, ball-bar circles in each plane) within minutes of testing.
    Plan {
        /// The machine model (URDF).
        #[arg(long, value_name = "M.urdf")]
        machine: PathBuf,
        /// The parameters, as for identify.
        #[arg(long, value_name = "SPEC")]
        params: String,
        /// The sphere centre of the R-tests and probing cycles, workpiece frame (mm); needed
        /// unless --kinds leaves both out.
        #[arg(
            long,
            value_name = "X,Y,Z",
            value_delimiter = ',',
            allow_negative_numbers = true
        )]
        sphere_mm: Option<Vec<f64>>,
        /// Standard uncertainty of each reading component (µm).
        #[arg(long, default_value_t = 0.2, allow_negative_numbers = true)]
        sigma_um: f64,
        /// Readings of R-tests to spend (three per pose), 3 to 30 000 (10 000 poses).
        #[arg(long, default_value_t = 240, allow_negative_numbers = true,
              value_parser = clap::value_parser!(i64).range(3..=MAX_BUDGET).map(|n| n as usize))]
        budget: usize,
        /// Minutes to spend instead, on tests of the --kinds (planning figures: a set-up is
        /// paid once for the tests made on it), 1 to 10 000.
        #[arg(
            long,
            value_name = "MIN",
            conflicts_with = "budget",
            allow_negative_numbers = true
        )]
        budget_min: Option<f64>,
        /// With --budget-min: the kinds of test to choose from (rtest, spheres, positioning,
        /// ballbar).
        #[arg(
            long,
            value_delimiter = ',',
            requires = "budget_min",
            default_value = "rtest,spheres,positioning,ballbar"
        )]
        kinds: Vec<String>,
        /// Print JSON instead of the report.
        #[arg(long)]
        json: bool,
    },
    /// Compare a measured positioning table with a simulated one (e.g. `mtwin run` of the
    /// model `mtwin discover positioning --write-model` wrote): per run and overall, the RMS,
    /// mean and largest of measured − simulated, and how far their times and temperatures
    /// differ.
    Compare {
        /// The measured table (positioning CSV).
        measured: PathBuf,
        /// The simulated table (positioning CSV).
        simulated: PathBuf,
        /// Print JSON instead of the report.
        #[arg(long)]
        json: bool,
    },
    /// Score an estimate against the truth: per parameter the error, the error over its
    /// uncertainty and whether the 95 % interval covers the truth; and the volumetric
    /// deviation over the working volume before and after compensating with the estimate.
    Score {
        /// estimate.json from `mtwin identify`.
        estimate: PathBuf,
        /// truth.json from `mtwin run`.
        truth: PathBuf,
        /// The machine model (URDF); default: the estimate's `machine_file`.
        #[arg(long, value_name = "M.urdf")]
        machine: Option<PathBuf>,
        /// Print JSON instead of the report.
        #[arg(long)]
        json: bool,
    },
}

/// The most worker threads `--threads` takes: far beyond the cores of one node, so only a typo
/// is refused.
const MAX_THREADS: i64 = 1024;
/// The most Monte Carlo trials `identify --monte-carlo` takes: GUM Supplement 1 §7.2's 10^6.
const MAX_MONTE_CARLO: i64 = 1_000_000;
/// The most readings `plan --budget` spends: 10 000 poses of three readings, beyond any
/// R-test a machine would stand still for.
const MAX_BUDGET: i64 = 30_000;
/// The most minutes `plan --budget-min` spends: a week of tests, beyond any calibration.
const MAX_MINUTES: f64 = 10_000.0;

/// The command line: `run` and `check`, then `analyze` and `discover` with a subcommand for
/// each kind that serves them.
fn command() -> clap::Command {
    let verbs = |name: &'static str, about: &'static str, verb: fn(&Kind) -> Option<Verb>| {
        let commands: Vec<clap::Command> = KINDS
            .iter()
            .filter_map(verb)
            .map(|verb| (verb.command)())
            .collect();
        // `mtwin VERB --help` tells each kind's long story (its model, for discovery).
        let details: String = commands
            .iter()
            .filter_map(|c| Some(format!("{}: {}\n\n", c.get_name(), c.get_long_about()?)))
            .collect();
        clap::Command::new(name)
            .about(about)
            .subcommand_required(true)
            .arg_required_else_help(true)
            .subcommand_value_name("KIND")
            .after_help(details.trim_end().to_string())
            .subcommands(commands)
    };
    Cli::command()
        .subcommand(verbs(
            "analyze",
            "The standards' figures from a measurement table (simulated or real)",
            |kind| kind.analyze,
        ))
        .subcommand(verbs(
            "discover",
            "Model discovery: fit the twin's base model to a measurement table, show what it \
             leaves, and add effects from the library while they lower the held-out RMS more \
             than noise can",
            |kind| kind.discover,
        ))
}

fn main() -> ExitCode {
    let matches = match command().try_get_matches() {
        Ok(matches) => matches,
        Err(error) => {
            if let Some(message) = flag_of_another_kind(&error) {
                eprintln!("error: {message}");
                return ExitCode::from(2);
            }
            error.exit()
        }
    };
    match execute(matches) {
        Ok(()) => ExitCode::SUCCESS,
        Err(error) => {
            // Messages quote the values they were given: 1e300 in scientific notation.
            let message = mtwin::math::shorten_numbers(&format!("{error:#}"));
            eprintln!("error: {message}");
            ExitCode::FAILURE
        }
    }
}

/// For a flag `analyze KIND` or `discover KIND` does not take, the kinds that take it.
fn flag_of_another_kind(error: &clap::Error) -> Option<String> {
    use clap::error::{ContextKind, ContextValue, ErrorKind};
    if error.kind() != ErrorKind::UnknownArgument {
        return None;
    }
    let Some(ContextValue::String(flag)) = error.get(ContextKind::InvalidArg) else {
        return None;
    };
    let long = flag.strip_prefix("--")?.split('=').next()?;
    let arguments: Vec<String> = std::env::args().collect();
    let verb = arguments
        .iter()
        .position(|a| a == "analyze" || a == "discover")?;
    let (verb, kind) = (&arguments[verb], arguments.get(verb + 1)?);
    let this = KINDS.iter().find(|k| k.name == kind.as_str())?;
    let owners: Vec<String> = KINDS
        .iter()
        .filter(|k| {
            [k.analyze, k.discover].into_iter().flatten().any(|v| {
                (v.command)()
                    .get_arguments()
                    .any(|a| a.get_long() == Some(long))
            })
        })
        .map(|k| format!("{} (mtwin {verb} {})", k.tables_are, k.name))
        .collect();
    (!owners.is_empty()).then(|| {
        format!(
            "--{long} is for {}, not {}",
            owners.join(" and "),
            this.tables_are
        )
    })
}

fn execute(matches: clap::ArgMatches) -> Result<()> {
    let serve = |verb_name: &str,
                 matches: &clap::ArgMatches,
                 verb: fn(&Kind) -> Option<Verb>|
     -> Result<()> {
        let (name, matches) = matches.subcommand().expect("a kind is required");
        let verb = KINDS
            .iter()
            .filter(|kind| kind.name == name)
            .find_map(verb)
            .expect("clap offers only registered kinds");
        let mut progress = |what: &str| eprintln!("{verb_name}: {what}");
        let output = (verb.run)(matches, &mut progress, &ScenarioFiles)?;
        say_raw(&output);
        Ok(())
    };
    match matches.subcommand() {
        Some(("analyze", matches)) => return serve("analyze", matches, |kind| kind.analyze),
        Some(("discover", matches)) => return serve("discover", matches, |kind| kind.discover),
        _ => {}
    }
    match Cli::from_arg_matches(&matches)?.command {
        Command::Run { scenario, out, rrd } => {
            if let Some(path) = &rrd {
                check_recording_path(path)?;
            }
            let scenario = Scenario::load(&scenario)?;
            let simulation = simulate(&scenario)?;
            let output = simulation.output(&scenario)?;
            mtwin::app::check_run_folder(&out)?;
            if let Some(path) = &rrd {
                record(path, &scenario, &simulation)?;
            }
            let others = output.others_in(&out);
            if !others.is_empty() {
                eprintln!(
                    "warning: {} holds files this run does not write ({}): another run's, left as they are",
                    out.display(),
                    others.join(", ")
                );
            }
            write_outputs(&output, &out)?;
            for (name, bytes) in &output.files {
                say!("{}  ({} bytes)", out.join(name).display(), bytes.len());
            }
            say!(
                "{} (seed {})",
                simulation.summary().join("; "),
                scenario.seed
            );
            Ok(())
        }
        Command::Check { file } => check(&file),
        Command::Dataset {
            scenario,
            count,
            out,
            shards,
            shard,
            threads,
            case,
        } => dataset::dataset(
            &scenario,
            count,
            &out,
            shards,
            shard.as_deref(),
            threads,
            case,
        ),
        Command::Identify {
            machine,
            params,
            tables,
            sigma_um,
            free_setup,
            drift,
            discover,
            sphere_setup_um,
            rtest_sphere_mm,
            monte_carlo,
            seed,
            scenario,
            json,
            accept_implausible,
            out,
        } => {
            if let Some(u) = sphere_setup_um
                && !(u.is_finite() && u >= 0.0)
            {
                bail!("--sphere-setup-um {u}: expected a number of µm, 0 or more");
            }
            let rtest_sphere = match &rtest_sphere_mm {
                Some(v) if v.len() == 3 && v.iter().all(|x| x.is_finite()) => {
                    Some(mtwin::math::Vector::new(v[0], v[1], v[2]) * 1e-3)
                }
                Some(_) => bail!("--rtest-sphere-mm: expected three numbers X,Y,Z (mm)"),
                None => None,
            };
            let mut sigma = std::collections::BTreeMap::new();
            for item in &sigma_um {
                let parsed = item
                    .split_once('=')
                    .and_then(|(k, v)| Some((k.trim(), v.trim().parse::<f64>().ok()?)))
                    .filter(|(k, v)| {
                        mtwin::app::identify::TABLE_KINDS.contains(k) && v.is_finite() && *v > 0.0
                    });
                let Some((kind, value)) = parsed else {
                    bail!(
                        "--sigma-um {item}: expected KIND=UM with KIND one of {} and a positive number of µm",
                        mtwin::app::identify::TABLE_KINDS.join(", ")
                    );
                };
                sigma.insert(kind.to_string(), value * 1e-6);
            }
            if monte_carlo > 0 && monte_carlo < MIN_TRIALS {
                bail!(
                    "--monte-carlo {monte_carlo}: at least {MIN_TRIALS} trials are needed to place a 95 % interval's 2.5 % tails (GUM Supplement 1 §7.2 asks M ≫ 1/(1 − p) = 20)"
                );
            }
            // The Monte Carlo's progress (hidden when stderr is not a terminal).
            let bar = indicatif::ProgressBar::new(monte_carlo as u64);
            bar.set_style(
                indicatif::ProgressStyle::with_template(
                    "Monte Carlo {bar:40} {pos}/{len} trials, {per_sec}, {eta} left",
                )
                .expect("a valid template"),
            );
            let progress = (monte_carlo > 0).then(|| {
                let bar = bar.clone();
                mtwin::estimate::fit::Progress(std::sync::Arc::new(move |done| {
                    bar.inc(done as u64)
                }))
            });
            let request = mtwin::app::identify::Request {
                machine,
                params,
                tables,
                sigma,
                free_setup,
                drift: match drift.as_deref() {
                    None => mtwin::kinds::rtest::readings::Drift::None,
                    Some("rate") => mtwin::kinds::rtest::readings::Drift::Rate,
                    Some(_) => mtwin::kinds::rtest::readings::Drift::PerTest,
                },
                discover,
                sphere_setup: sphere_setup_um.map(|u| u * 1e-6),
                rtest_sphere,
                trials: monte_carlo,
                seed,
                scenario,
                accept_implausible,
                progress,
            };
            let identified = mtwin::app::identify::identify(&request);
            bar.finish_and_clear();
            let identified = identified?;
            if json {
                say_raw(&format!("{:#}\n", identified.json));
            } else {
                say_raw(&identified.text);
            }
            if let Some(dir) = &out {
                std::fs::create_dir_all(dir).map_err(|e| {
                    anyhow::anyhow!("{}: cannot create the folder: {e}", dir.display())
                })?;
                mtwin::io::write_files(&identified.files, dir)?;
                for (name, bytes) in &identified.files {
                    eprintln!("{}  ({} bytes)", dir.join(name).display(), bytes.len());
                }
            }
            Ok(())
        }
        Command::Plan {
            machine,
            params,
            sphere_mm,
            sigma_um,
            budget,
            budget_min,
            kinds,
            json,
        } => {
            if !(sigma_um.is_finite() && sigma_um > 0.0) {
                bail!("--sigma-um {sigma_um}: expected a positive number of µm");
            }
            let sphere = match sphere_mm {
                Some(mm) if mm.len() == 3 && mm.iter().all(|v| v.is_finite()) => {
                    Some(mtwin::math::Vector::new(mm[0], mm[1], mm[2]) * 1e-3)
                }
                Some(_) => bail!("--sphere-mm: expected three numbers X,Y,Z (mm)"),
                None => None,
            };
            let budget = match budget_min {
                None => mtwin::app::identify::Budget::Readings(budget),
                Some(minutes) if minutes.is_finite() && (1.0..=MAX_MINUTES).contains(&minutes) => {
                    mtwin::app::identify::Budget::Minutes { minutes, kinds }
                }
                Some(minutes) => {
                    bail!("--budget-min {minutes}: expected a number of minutes from 1 to 10 000")
                }
            };
            let plan =
                mtwin::app::identify::plan(&machine, &params, sphere, sigma_um * 1e-6, &budget)?;
            if json {
                say_raw(&format!("{:#}\n", plan.to_json()));
            } else {
                say_raw(&plan.report());
            }
            Ok(())
        }
        Command::Compare {
            measured,
            simulated,
            json,
        } => {
            use mtwin::kinds::positioning::{PositioningTable, compare::compare};
            let (a, b) = (
                PositioningTable::read(&measured)?,
                PositioningTable::read(&simulated)?,
            );
            let comparison = compare(&a, &b).map_err(|e| {
                anyhow::anyhow!(
                    "{} against {}: {e}",
                    measured.display(),
                    simulated.display()
                )
            })?;
            if json {
                println!("{}", serde_json::to_string_pretty(&comparison.to_json())?);
            } else {
                print!(
                    "{}",
                    comparison.to_text(
                        &measured.display().to_string(),
                        &simulated.display().to_string()
                    )
                );
            }
            Ok(())
        }
        Command::Score {
            estimate,
            truth,
            machine,
            json,
        } => {
            let read = |path: &Path| -> Result<serde_json::Value> {
                let text = std::fs::read_to_string(path)
                    .map_err(|e| anyhow::anyhow!("{}: cannot read: {e}", path.display()))?;
                serde_json::from_str(&text).map_err(|e| {
                    anyhow::anyhow!(
                        "{}:{}:{}: not JSON: {e}",
                        path.display(),
                        e.line(),
                        e.column()
                    )
                })
            };
            let (estimate_json, truth_json) = (read(&estimate)?, read(&truth)?);
            if let Some(refusal) = mtwin::app::score::truth_as_estimate(&estimate_json, &estimate) {
                bail!(refusal);
            }
            let machine_file = match machine {
                Some(path) => path,
                None => match estimate_json["machine_file"].as_str() {
                    Some(file) => PathBuf::from(file),
                    None => bail!(
                        "{}: no machine_file; give the machine with --machine M.urdf",
                        estimate.display()
                    ),
                },
            };
            let machine = Machine::from_urdf_file(&machine_file)?;
            let score = mtwin::estimate::score::score(&estimate_json, &truth_json, &machine)?;
            let cautions: Vec<String> = mtwin::app::score::unchecked_scenario(
                &estimate_json,
                &estimate,
                &truth_json,
                &truth,
            )
            .into_iter()
            .collect();
            say_raw(&mtwin::app::score::printed(&score, &cautions, json));
            Ok(())
        }
    }
}

/// A recording path must name an `.rrd` file, and this mtwin must be able to write one.
fn check_recording_path(path: &Path) -> Result<()> {
    if path.extension().and_then(|e| e.to_str()) != Some("rrd") {
        bail!(
            "--rrd {}: expected a file name ending in .rrd",
            path.display()
        );
    }
    mtwin::io::check_folder_of(path)?;
    if !cfg!(feature = "viz") {
        bail!(
            "--rrd: this mtwin was built without teaching scenes; build it with `cargo build --release --features viz`"
        );
    }
    Ok(())
}

/// Writes the teaching recording through a temporary file beside `path`, so a failure leaves
/// no partial recording.
#[cfg(feature = "viz")]
fn record(path: &Path, scenario: &Scenario, simulation: &Simulation) -> Result<()> {
    use anyhow::Context;
    let name = path
        .file_name()
        .with_context(|| format!("{}: not a file name", path.display()))?;
    let temporary = path.with_file_name(format!(".{}.partial", name.to_string_lossy()));
    let result = mtwin::app::record::save(&temporary, scenario, simulation, &mut |what| {
        eprintln!("recording: {what}")
    });
    if let Err(e) = result {
        let _ = std::fs::remove_file(&temporary); // best effort: already failing
        return Err(e).with_context(|| format!("{}", path.display()));
    }
    std::fs::rename(&temporary, path).with_context(|| format!("cannot write {}", path.display()))
}

#[cfg(not(feature = "viz"))]
fn record(_: &Path, _: &Scenario, _: &Simulation) -> Result<()> {
    unreachable!("checked by check_recording_path")
}

fn check(file: &Path) -> Result<()> {
    match file.extension().and_then(|e| e.to_str()) {
        Some("urdf") => {
            let machine = Machine::from_urdf_file(file)?;
            say!("{}: ok, machine \"{}\"", file.display(), machine.name());
            describe(&machine);
        }
        Some("toml") => {
            let scenario = Scenario::load(file)?;
            // The dataset section too before anything is said: no "ok" before a refusal.
            let dataset = if mtwin::app::dataset::declared(file) {
                Some(mtwin::app::dataset::Dataset::load(file)?)
            } else {
                None
            };
            let machine = &scenario.twin.machine;
            say!(
                "{}: ok, machine \"{}\" ({}), {} error parameters, seed {}",
                file.display(),
                machine.name(),
                scenario.machine_file.display(),
                scenario.twin.errors.parameters().len(),
                scenario.seed
            );
            for line in scenario.describe() {
                say!("  {line}");
            }
            if let Some(dataset) = dataset {
                say!("  {}", dataset.describe());
            }
        }
        _ => bail!(
            "{}: expected a scenario (.toml) or a machine model (.urdf)",
            file.display()
        ),
    }
    Ok(())
}

fn describe(machine: &Machine) {
    for info in machine.axes() {
        let side = if info.side == Side::Tool {
            "tool"
        } else {
            "workpiece"
        };
        let travel = match info.limits {
            Some((lower, upper)) if info.axis.is_linear() => {
                format!("{:.1} .. {:.1} mm", lower * 1e3, upper * 1e3)
            }
            Some((lower, upper)) => {
                format!("{:.1} .. {:.1} deg", lower.to_degrees(), upper.to_degrees())
            }
            None => "continuous".to_string(),
        };
        say!("  {}  {side:<9}  {travel}", info.axis);
    }
}

//! `mtwin`: the command line of the machine-tool twin (a thin layer over the library).
//! `run` and `check` work on scenarios; `analyze` and `discover` have one subcommand per test
//! kind that serves them, taken from the registry ([`mtwin::kinds::KINDS`]).

use anyhow::{Result, bail};
use clap::{CommandFactory, FromArgMatches, Parser, Subcommand};
use mtwin::app::{Scenario, Simulation, simulate, write_outputs};
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
    /// Validate a scenario (.toml) or a machine model (.urdf) without running it.
    Check {
        /// The file.
        file: PathBuf,
    },
}

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
            eprintln!("error: {error:#}");
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
        let output = (verb.run)(matches, &mut |what| eprintln!("{verb_name}: {what}"))?;
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
            let output = simulation.output(&scenario);
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

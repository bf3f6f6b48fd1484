//! `vitro`: the command-line front end of the Vitro toolkit.
//!
//! ```text
//! vitro run SCENARIO [--seed N] [--until SECONDS] [--speed X] [--json] [--quiet] [--save-at SECONDS --save FILE]
//! vitro resume FILE [--until SECONDS] [--json|--quiet] [--record RUN.mcap]
//! vitro validate SCENARIO
//! vitro plan DOMAIN PROBLEM [--optimal] [--json]
//! vitro solve cops GRAPH.edges [--json]
//! vitro solve vrp INSTANCE [--solver savings|local-search|auction] [--budget N] [--seed S] [--json]
//! vitro solve pursuit GRAPH.edges --pursuers K [--visibility HOPS] [--algorithm mcts|minimax] [--evader exact|mcts|flee] --budget B --episodes N --turns T [--seed S] [--json]
//! vitro check levels [--json] [--calibration FILE]
//! vitro calibrate SCENARIO [--from physical] [--to discrete,interpolated] --out FILE [--jobs N] [--plot STEM]
//! vitro export kml RUN.mcap [--out FILE.kml]
//! vitro map info FILE.osm.pbf [--json]
//! vitro map render FILE.osm.pbf --out map.png [--terrain GRID] [--offset X,Y]
//! vitro terrain viewshed GRID --observer X,Y --observer-height H --target-height T --out MASK.asc
//! vitro batch EXPERIMENT.toml --out DIR [--jobs N] [--shard I/N] [--resume] [--slurm [--tasks N] [--time T]]
//! vitro search EXPERIMENT.toml --out DIR [--budget N] [--strategy adaptive|random] [--resume]
//! vitro merge DIR... --out DIR
//! vitro plot DIR --out PLOTS [--metric M]... [--hist M]... [--success M]
//! ```
//!
//! Exit codes: 0 success, 1 runtime error, 2 bad input (unreadable or malformed scenario,
//! value out of range, bad arguments), 4 the answer is a failure (no plan exists).
//!
//! The command is a library too: [`run`] is the whole `vitro` command, with missions of the
//! caller's beside the stock ones. A mission crate's own `vitro` is one line,
//!
//! ```text
//! fn main() -> std::process::ExitCode {
//!     vitro_cli::run(vec![&my_mission::Watch], std::env::args_os()).into()
//! }
//! ```
//!
//! and runs, validates, batches, searches, views and resumes `kind = "watch"` files as the
//! stock command does the evacuation's.

mod batch;
mod calibrate;
mod check;
mod export;
mod failure;
mod graph_file;
mod map;
mod missions;
mod plan;
mod record;
mod resume;
mod run;
mod run_args;
mod search;
mod solve;
mod solve_pursuit;
mod solve_vrp;
mod validate;
mod view;

pub(crate) use failure::Failure;

use clap::{Parser, Subcommand};
use std::ffi::OsString;
use std::path::PathBuf;
use vitro_mission::Mission;

/// Vitro: in vitro multi-agent simulation.
#[derive(Debug, Parser)]
#[command(name = "vitro", version, propagate_version = true)]
struct Cli {
    #[command(subcommand)]
    command: Command,
}

/// What to do.
#[derive(Debug, Subcommand)]
enum Command {
    /// Runs a scenario and reports its metrics.
    Run(run_args::RunArgs),
    /// Continues a run saved with `vitro run ... --save-at SECONDS --save FILE`.
    Resume(resume::ResumeArgs),
    /// Finds a plan for a PDDL problem (STRIPS with typing).
    Plan(plan::PlanArgs),
    /// Solves a game: `vitro solve cops GRAPH.edges`.
    #[command(subcommand)]
    Solve(solve::SolveCommand),
    /// Views of a map: `vitro map info FILE.osm.pbf`, `vitro map render FILE --out map.png`.
    #[command(subcommand)]
    Map(map::MapCommand),
    /// Terrain analysis: `vitro terrain viewshed FILE --observer X,Y ...`.
    #[command(subcommand)]
    Terrain(map::TerrainCommand),
    /// Exports a recording: `vitro export kml RUN.mcap [--out FILE.kml]`.
    #[command(subcommand)]
    Export(export::ExportCommand),
    /// Runs an experiment: a parameter sweep of a scenario, in parallel, resumable.
    Batch(batch::BatchArgs),
    /// Searches an experiment's [search] parameters for failing runs and shrinks them.
    Search(search::SearchArgs),
    /// Joins result directories (the shards) of one experiment into one.
    Merge(batch::MergeArgs),
    /// Plots a result directory (PNG and SVG).
    Plot(batch::PlotArgs),
    /// Fits the abstract levels' trip times to the concrete level's on sample trips over a
    /// scenario's town (a calibration file for `[fidelity] calibration`).
    Calibrate(calibrate::CalibrateArgs),
    /// Cross-level checks: `vitro check levels`.
    #[command(subcommand)]
    Check(check::CheckCommand),
    /// Watches a scenario run live, or replays a recording, in the browser.
    View(view::ViewArgs),
    /// Checks a scenario file without running it.
    Validate {
        /// The scenario file (TOML).
        scenario: PathBuf,
    },
}

/// Runs the `vitro` command on `args` (the first is the program's name) with `missions`
/// registered beside the stock ones ([`vitro_tools::install`]; none: the stock command);
/// returns the exit code: 0 success, 1 runtime error, 2 bad input or arguments, 4 the answer
/// is a failure. Help and errors are printed as the command prints them.
pub fn run<I, T>(missions: Vec<&'static dyn Mission>, args: I) -> u8
where
    I: IntoIterator<Item = T>,
    T: Into<OsString> + Clone,
{
    if !missions.is_empty()
        && let Err(e) = vitro_tools::install(missions)
    {
        eprintln!("error: {e}");
        return match e {
            vitro_tools::ToolError::Input(_) => 2,
            _ => 1,
        };
    }
    let cli = match Cli::try_parse_from(args) {
        Ok(cli) => cli,
        Err(e) => {
            let _ = e.print();
            return u8::try_from(e.exit_code()).unwrap_or(2);
        }
    };
    let result = match cli.command {
        Command::Run(args) => run::run(&args),
        Command::Resume(args) => resume::resume(&args),
        Command::Validate { scenario } => validate::validate(&scenario),
        Command::Batch(args) => batch::batch(&args),
        Command::Search(args) => search::search(&args),
        Command::Merge(args) => batch::merge_dirs(&args),
        Command::Plot(args) => batch::plot(&args),
        Command::Plan(args) => plan::plan(&args),
        Command::Solve(cmd) => solve::solve(&cmd),
        Command::Map(cmd) => map::map(&cmd),
        Command::Check(cmd) => check::check(&cmd),
        Command::Calibrate(args) => calibrate::calibrate(&args),
        Command::Terrain(cmd) => map::terrain(&cmd),
        Command::Export(cmd) => export::export(&cmd),
        Command::View(args) => view::view(&args),
    };
    match result {
        Ok(()) => 0,
        Err(Failure::Input(e)) => {
            eprintln!("error: {}", vitro_tools::chain(&*e));
            2
        }
        Err(Failure::Runtime(e)) => {
            eprintln!("error: {}", vitro_tools::chain(&*e));
            1
        }
        Err(Failure::Check(e)) => {
            eprintln!("error: {}", vitro_tools::chain(&*e));
            4
        }
    }
}

//! `vitro`: the command-line front end of the Vitro toolkit.
//!
//! ```text
//! vitro run SCENARIO [--seed N] [--until SECONDS] [--speed X] [--json] [--quiet]
//! vitro validate SCENARIO
//! ```
//!
//! Exit codes: 0 success, 1 runtime error, 2 bad input (unreadable or malformed scenario,
//! value out of range, bad arguments).

use anyhow::Context as _;
use clap::{Args, Parser, Subcommand};
use serde::Serialize;
use std::path::PathBuf;
use std::process::ExitCode;
use std::time::Instant;
use vitro_demo::config::{ConfigError, DemoConfig, MAX_END_S};
use vitro_demo::{DemoError, Metrics, Scenario};

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
    Run(RunArgs),
    /// Checks a scenario file without running it.
    Validate {
        /// The scenario file (TOML).
        scenario: PathBuf,
    },
}

#[derive(Debug, Args)]
struct RunArgs {
    /// The scenario file (TOML).
    scenario: PathBuf,
    /// Master seed (overrides the scenario's).
    #[arg(long)]
    seed: Option<u64>,
    /// Simulated seconds to run (overrides the scenario's `end_s`).
    #[arg(long, value_name = "SECONDS")]
    until: Option<f64>,
    /// Paces the run at X simulated seconds per wall second (0.1 to 1000); default: as fast
    /// as possible. Pacing never changes the outcome.
    #[arg(long, value_name = "X")]
    speed: Option<f64>,
    /// Prints one JSON object on stdout instead of the summary.
    #[arg(long)]
    json: bool,
    /// Prints only the trace hash (or only the JSON object with --json).
    #[arg(long)]
    quiet: bool,
}

/// How a command failed: the exit code follows.
#[derive(Debug)]
enum Failure {
    /// Bad input: exit 2.
    Input(anyhow::Error),
    /// Failure while running: exit 1.
    Runtime(anyhow::Error),
}

/// What `vitro run --json` prints.
#[derive(Serialize)]
struct Report<'a> {
    #[serde(flatten)]
    metrics: &'a Metrics,
    wall_time_s: f64,
    events_per_wall_s: f64,
    sim_s_per_wall_s: f64,
    speed: Option<f64>,
}

fn main() -> ExitCode {
    let cli = Cli::parse();
    let result = match cli.command {
        Command::Run(args) => run(&args),
        Command::Validate { scenario } => validate(&scenario),
    };
    match result {
        Ok(()) => ExitCode::SUCCESS,
        Err(Failure::Input(e)) => {
            eprintln!("error: {e:#}");
            ExitCode::from(2)
        }
        Err(Failure::Runtime(e)) => {
            eprintln!("error: {e:#}");
            ExitCode::from(1)
        }
    }
}

/// Loads a scenario; every problem is bad input.
fn load(path: &std::path::Path) -> Result<DemoConfig, Failure> {
    DemoConfig::load(path).map_err(|e| match e {
        ConfigError::Read { .. } => Failure::Input(e.into()),
        ConfigError::Content(d) => {
            Failure::Input(anyhow::Error::new(*d).context("invalid scenario"))
        }
    })
}

fn validate(path: &std::path::Path) -> Result<(), Failure> {
    let cfg = load(path)?;
    let scenario = Scenario::build(cfg).map_err(|e| Failure::Input(e.into()))?;
    let m = scenario.metrics();
    println!(
        "{}: ok ({} junctions, {} streets, {} cars, {} simulated seconds)",
        path.display(),
        m.junctions,
        m.streets,
        m.cars,
        scenario.config().end_s
    );
    Ok(())
}

fn run(args: &RunArgs) -> Result<(), Failure> {
    let mut cfg = load(&args.scenario)?;
    if let Some(seed) = args.seed {
        cfg.seed = seed;
    }
    if let Some(until) = args.until {
        if !(until > 0.0 && until <= MAX_END_S) {
            return Err(Failure::Input(anyhow::anyhow!(
                "--until {until}: expected a number of simulated seconds in (0, {MAX_END_S:e}]"
            )));
        }
        cfg.end_s = until;
    }
    let mut scenario = Scenario::build(cfg).map_err(|e| match e {
        DemoError::Invalid(_) => Failure::Input(e.into()),
        _ => Failure::Runtime(anyhow::Error::new(e).context("cannot build the scenario")),
    })?;
    if let Some(speed) = args.speed {
        scenario
            .simulation()
            .control()
            .set_speed(speed)
            .context("--speed")
            .map_err(Failure::Input)?;
    }
    if !args.quiet && !args.json {
        let c = scenario.config();
        eprintln!(
            "running {:?} from {} (seed {}, {} s simulated{})",
            c.name,
            args.scenario.display(),
            c.seed,
            c.end_s,
            args.speed
                .map(|s| format!(", paced at {s}x"))
                .unwrap_or_default()
        );
    }
    let started = Instant::now();
    let outcome = scenario.run();
    let wall = started.elapsed().as_secs_f64();
    outcome
        .with_context(|| format!("running {}", args.scenario.display()))
        .map_err(Failure::Runtime)?;
    let m = scenario.metrics();
    let per_wall = |x: f64| if wall > 0.0 { x / wall } else { 0.0 };
    let report = Report {
        metrics: &m,
        wall_time_s: wall,
        events_per_wall_s: per_wall(m.events as f64),
        sim_s_per_wall_s: per_wall(m.sim_time_s),
        speed: args.speed,
    };
    if args.json {
        let line = serde_json::to_string(&report)
            .context("encoding the report")
            .map_err(Failure::Runtime)?;
        println!("{line}");
    } else if args.quiet {
        println!("{:016x}", m.trace_hash);
    } else {
        print_summary(&report);
    }
    Ok(())
}

fn print_summary(r: &Report<'_>) {
    let m = r.metrics;
    println!("scenario     {} (seed {})", m.scenario, m.seed);
    println!(
        "world        {} junctions, {} streets, {} cars",
        m.junctions, m.streets, m.cars
    );
    println!(
        "time         {:.1} s simulated in {:.3} s wall ({:.0}x real time), stopped at {}",
        m.sim_time_s, r.wall_time_s, r.sim_s_per_wall_s, m.stop
    );
    println!(
        "events       {} ({:.0} per wall second)",
        m.events, r.events_per_wall_s
    );
    println!(
        "idleness     mean {:.1} s, worst {:.1} s ({} visits)",
        m.mean_idleness_s, m.max_idleness_s, m.visits
    );
    println!(
        "patrol       {} goals chosen, {} reached, {} given up to a better claim",
        m.decisions, m.goals_reached, m.yielded
    );
    println!(
        "messages     {} sent, {} received, {} lost, {} out of range",
        m.messages_sent, m.messages_received, m.messages_lost, m.messages_bounced
    );
    println!("trace hash   {:016x}", m.trace_hash);
}

//! `vitro run` and `vitro validate` of the patrolling-cars demo; mission scenarios go to
//! [`crate::mission`].

use crate::Failure;
use crate::run_args::RunArgs;
use anyhow::Context as _;
use serde::Serialize;
use std::time::Instant;
use vitro_demo::config::{ConfigError, DemoConfig, MAX_END_S};
use vitro_demo::{DemoError, Metrics, Scenario};

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

/// Loads a scenario; every problem is bad input.
fn load(path: &std::path::Path) -> Result<DemoConfig, Failure> {
    DemoConfig::load(path).map_err(|e| match e {
        ConfigError::Read { .. } => Failure::Input(e.into()),
        ConfigError::Content(d) => {
            Failure::Input(anyhow::Error::new(*d).context("invalid scenario"))
        }
    })
}

pub(crate) fn validate(path: &std::path::Path) -> Result<(), Failure> {
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

pub(crate) fn run(args: &RunArgs) -> Result<(), Failure> {
    if crate::mission::is_mission(&args.scenario) {
        return crate::mission::run(args);
    }
    if args.record.is_some() {
        return Err(Failure::Input(anyhow::anyhow!(
            "--record: only mission scenarios can be recorded"
        )));
    }
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

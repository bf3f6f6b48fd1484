//! `vitro run`: builds the scenario's mission (looked up by its `kind`), runs it (paced or
//! not, recorded or not) and prints a summary or one JSON object.

use crate::Failure;
use crate::missions::{failure, registry};
use crate::record::Recording;
use crate::run_args::RunArgs;
use anyhow::Context as _;
use indicatif::{ProgressBar, ProgressStyle};
use std::io::IsTerminal;
use std::time::Instant;
use vitro::time::{SimDuration, SimTime};
use vitro_mission::{BuildOptions, Run};

/// The longest run `--until` accepts, simulated seconds.
const MAX_UNTIL_S: f64 = 1.0e6;

pub(crate) fn run(args: &RunArgs) -> Result<(), Failure> {
    let options = BuildOptions {
        seed: args.seed,
        fidelity: args.fidelity.clone(),
    };
    let mut run = registry()
        .build(&args.scenario, &options)
        .map_err(|e| failure(&args.scenario, e))?;
    if let Some(until) = args.until {
        if !(until > 0.0 && until <= MAX_UNTIL_S) {
            return Err(Failure::Input(anyhow::anyhow!(
                "--until {until}: expected a number of simulated seconds in (0, {MAX_UNTIL_S:e}]"
            )));
        }
        run.set_end(run.end().min(SimTime::from_secs_f64(until)));
    }
    if let Some(speed) = args.speed {
        run.control()
            .set_speed(speed)
            .context("--speed")
            .map_err(Failure::Input)?;
    }
    let chatty = !args.quiet && !args.json;
    if chatty {
        eprintln!(
            "running {:?} from {} (seed {}, at most {:.0} s simulated{})",
            run.name(),
            args.scenario.display(),
            run.seed(),
            run.end().as_secs_f64(),
            args.speed
                .map(|s| format!(", paced at {s}x"))
                .unwrap_or_default()
        );
    }
    let bar = (chatty && std::io::stderr().is_terminal()).then(|| {
        let b = ProgressBar::new(run.end().as_secs_f64() as u64);
        b.set_style(
            ProgressStyle::with_template("{bar:40} {pos}/{len} s simulated, {msg}")
                .unwrap_or_else(|_| ProgressStyle::default_bar()),
        );
        b
    });
    let mut recorder = match &args.record {
        Some(path) => Some(Recording::create(path, run.as_ref()).map_err(Failure::Runtime)?),
        None => None,
    };
    let started = Instant::now();
    let chunk = run.sample().max(SimDuration::from_secs(1));
    let mut t = SimTime::ZERO;
    loop {
        t += chunk;
        let going = run
            .advance(t.min(run.end()))
            .with_context(|| format!("running {}", args.scenario.display()))
            .map_err(Failure::Runtime)?;
        if let Some(r) = recorder.as_mut() {
            r.frame(run.as_mut()).map_err(Failure::Runtime)?;
        }
        let log = run.drain_log();
        if args.verbose {
            for (at, line) in log {
                eprintln!("{at:8.1} s  {line}");
            }
        }
        if let Some(b) = &bar {
            b.set_position(run.now().as_secs_f64() as u64);
            b.set_message(format!("{} events", run.control().events_fired()));
        }
        if !going || t >= run.end() {
            break;
        }
    }
    if let Some(b) = bar {
        b.finish_and_clear();
    }
    if let Some(r) = recorder {
        r.finish().map_err(Failure::Runtime)?;
    }
    let wall = started.elapsed().as_secs_f64();
    let report = report(run.as_ref(), wall, args.speed);
    if args.json {
        let line = serde_json::to_string(&report)
            .context("encoding the report")
            .map_err(Failure::Runtime)?;
        println!("{line}");
    } else if args.quiet {
        println!("{:016x}", run.trace_hash());
    } else {
        print_summary(run.as_ref(), wall);
    }
    run.verdict()
        .map_err(|why| Failure::Check(anyhow::anyhow!(why)))
}

/// What `vitro run --json` prints: the run's own fields, then the scenario, the seed, the
/// trace hash and the wall-clock figures.
fn report(run: &dyn Run, wall: f64, speed: Option<f64>) -> serde_json::Value {
    let per_wall = |x: f64| if wall > 0.0 { x / wall } else { 0.0 };
    let events = run.control().events_fired();
    let sim_s = run.now().as_secs_f64();
    let mut out = run.report();
    out.entry("scenario").or_insert_with(|| run.name().into());
    out.insert("seed".into(), run.seed().into());
    out.insert("events".into(), events.into());
    out.entry("sim_time_s").or_insert_with(|| sim_s.into());
    out.insert(
        "trace_hash".into(),
        format!("{:016x}", run.trace_hash()).into(),
    );
    out.insert("wall_time_s".into(), wall.into());
    out.insert("events_per_wall_s".into(), per_wall(events as f64).into());
    out.insert("sim_s_per_wall_s".into(), per_wall(sim_s).into());
    out.insert("speed".into(), speed.into());
    out.into()
}

/// The human summary: the scenario, the mission's own lines, the time and the trace hash.
fn print_summary(run: &dyn Run, wall: f64) {
    let lines = run.summary();
    let width = lines
        .iter()
        .map(|(k, _)| k.len())
        .chain([10])
        .max()
        .unwrap_or(10)
        + 2;
    let events = run.control().events_fired();
    let sim_s = run.now().as_secs_f64();
    let per_wall = |x: f64| if wall > 0.0 { x / wall } else { 0.0 };
    println!("{:width$}{} (seed {})", "scenario", run.name(), run.seed());
    for (label, line) in &lines {
        println!("{label:width$}{line}");
    }
    println!(
        "{:width$}{sim_s:.1} s simulated in {wall:.3} s wall ({:.0}x real time), {events} events ({:.0}/s)",
        "time",
        per_wall(sim_s),
        per_wall(events as f64)
    );
    println!("{:width$}{:016x}", "trace hash", run.trace_hash());
}

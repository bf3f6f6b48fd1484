//! `vitro run`: builds the scenario's mission (looked up by its `kind`), runs it (paced or
//! not, recorded or not) and prints a summary or one JSON object.

use crate::Failure;
use crate::missions::{failure, registry};
use crate::record::Recording;
use crate::run_args::RunArgs;
use indicatif::{ProgressBar, ProgressStyle};
use std::io::IsTerminal;
use std::time::Instant;
use vitro_mission::{BuildOptions, Run};

pub(crate) fn run(args: &RunArgs) -> Result<(), Failure> {
    let options = BuildOptions {
        seed: args.seed,
        fidelity: args.fidelity.clone(),
    };
    let mut run = registry()
        .build(&args.scenario, &options)
        .map_err(|e| failure(&args.scenario, e))?;
    if let Some(until) = args.until {
        vitro_tools::set_until(run.as_mut(), until)?;
    }
    if let Some(speed) = args.speed {
        run.control()
            .set_speed(speed)
            .map_err(|e| Failure::Input(anyhow::Error::new(e).context("--speed")))?;
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
    let running = |e| {
        Failure::Runtime(
            anyhow::Error::new(e).context(format!("running {}", args.scenario.display())),
        )
    };
    vitro_tools::drive(run.as_mut(), running, |run| {
        if let Some(r) = recorder.as_mut() {
            r.frame(run).map_err(Failure::Runtime)?;
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
        Ok(())
    })?;
    if let Some(b) = bar {
        b.finish_and_clear();
    }
    if let Some(r) = recorder {
        r.finish().map_err(Failure::Runtime)?;
    }
    let wall = started.elapsed().as_secs_f64();
    let report = vitro_tools::report(run.as_ref(), wall, args.speed);
    if args.json {
        let line = serde_json::to_string(&report)
            .map_err(|e| Failure::Runtime(anyhow::Error::new(e).context("encoding the report")))?;
        println!("{line}");
    } else if args.quiet {
        println!("{:016x}", run.trace_hash());
    } else {
        print_summary(run.as_ref(), wall);
    }
    run.verdict()
        .map_err(|why| Failure::Check(anyhow::anyhow!(why)))
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

//! `vitro run`: builds the scenario's mission (looked up by its `kind`), runs it (paced or
//! not, recorded or not) and prints a summary or one JSON object.

use crate::Failure;
use crate::missions::{failure, registry};
use crate::record::Recording;
use crate::run_args::RunArgs;
use anyhow::Context as _;
use indicatif::{ProgressBar, ProgressStyle};
use std::io::IsTerminal;
use std::path::Path;
use std::time::Instant;
use vitro::time::{SimDuration, SimTime};
use vitro_mission::{BuildOptions, Run, Snapshot};
use vitro_tools::MAX_UNTIL_S;

pub(crate) fn run(args: &RunArgs) -> Result<(), Failure> {
    let options = BuildOptions {
        seed: args.seed,
        fidelity: args.fidelity.clone(),
    };
    let fail = |e| failure(&args.scenario, e);
    let (mission, text) = registry().read(&args.scenario).map_err(fail)?;
    let mut run = mission
        .build(&args.scenario, &text, &options)
        .map_err(|e| fail(e.into()))?;
    if let Some(until) = args.until {
        run.set_end(run.end().min(check_until(until)?));
    }
    // The snapshot to take on the way: when, and the file (created now, so that a path that
    // cannot be written fails before the run rather than after).
    let save = match (args.save_at, &args.save) {
        (Some(at), Some(path)) => {
            if !(0.0..=MAX_UNTIL_S).contains(&at) {
                return Err(Failure::Input(anyhow::anyhow!(
                    "--save-at {at}: expected a number of simulated seconds in [0, {MAX_UNTIL_S:e}]"
                )));
            }
            let file = std::fs::File::create(path)
                .with_context(|| format!("cannot write the snapshot {}", path.display()))
                .map_err(Failure::Input)?;
            Some(Save {
                at: SimTime::from_secs_f64(at),
                path,
                file,
                kind: mission.kind(),
                text: &text,
                options: &options,
                scenario: &args.scenario,
            })
        }
        _ => None,
    };
    let output = Output {
        resumed: false,
        speed: args.speed,
        record: args.record.as_deref(),
        json: args.json,
        quiet: args.quiet,
        verbose: args.verbose,
    };
    if !args.quiet && !args.json {
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
    drive(run.as_mut(), &args.scenario, &output, save)
}

/// Checks `--until` and returns it as a time.
pub(crate) fn check_until(until: f64) -> Result<SimTime, Failure> {
    if !(until > 0.0 && until <= MAX_UNTIL_S) {
        return Err(Failure::Input(anyhow::anyhow!(
            "--until {until}: expected a number of simulated seconds in (0, {MAX_UNTIL_S:e}]"
        )));
    }
    Ok(SimTime::from_secs_f64(until))
}

/// How a run reports: pacing, recording and what it prints.
pub(crate) struct Output<'a> {
    /// True for a resumed run (its recording starts with the state it resumes from; its
    /// report says where it resumed).
    pub(crate) resumed: bool,
    pub(crate) speed: Option<f64>,
    pub(crate) record: Option<&'a Path>,
    pub(crate) json: bool,
    pub(crate) quiet: bool,
    pub(crate) verbose: bool,
}

/// A snapshot to take when the run reaches `at`.
pub(crate) struct Save<'a> {
    at: SimTime,
    path: &'a Path,
    file: std::fs::File,
    kind: &'a str,
    text: &'a str,
    options: &'a BuildOptions,
    scenario: &'a Path,
}

impl Save<'_> {
    /// Writes the snapshot of `run`.
    fn write(self, run: &dyn Run) -> Result<(), Failure> {
        let snap = Snapshot::of(self.kind, self.scenario, self.text, self.options, run)
            .map_err(|e| Failure::Input(e.into()))?;
        snap.write(std::io::BufWriter::new(self.file))
            .with_context(|| format!("writing the snapshot {}", self.path.display()))
            .map_err(Failure::Runtime)?;
        if run.now() < self.at {
            eprintln!(
                "note: the run ended at {:.1} s, before --save-at {:.1} s: {} holds its end",
                run.now().as_secs_f64(),
                self.at.as_secs_f64(),
                self.path.display()
            );
        }
        Ok(())
    }
}

/// Runs `run` (read from `what`) from where it stands to its end: paced, recorded, saved on
/// the way as `output` and `save` say; then prints its report and returns its verdict.
pub(crate) fn drive(
    run: &mut dyn Run,
    what: &Path,
    output: &Output<'_>,
    mut save: Option<Save<'_>>,
) -> Result<(), Failure> {
    if let Some(speed) = output.speed {
        run.control()
            .set_speed(speed)
            .context("--speed")
            .map_err(Failure::Input)?;
    }
    let chatty = !output.quiet && !output.json;
    let bar = (chatty && std::io::stderr().is_terminal()).then(|| {
        let b = ProgressBar::new(run.end().as_secs_f64() as u64);
        b.set_style(
            ProgressStyle::with_template("{bar:40} {pos}/{len} s simulated, {msg}")
                .unwrap_or_else(|_| ProgressStyle::default_bar()),
        );
        b
    });
    let mut recorder = match output.record {
        // A path that cannot be created (a directory, no such folder) is bad input.
        Some(path) => Some(Recording::create(path, run).map_err(Failure::Input)?),
        None => None,
    };
    let start = run.now();
    if output.resumed
        && let Some(r) = recorder.as_mut()
    {
        r.frame(run).map_err(Failure::Runtime)?;
    }
    let started = Instant::now();
    let chunk = run.sample().max(SimDuration::from_secs(1)).as_nanos();
    // Chunks end on the same multiples of the chunk as an uninterrupted run's.
    let mut t = SimTime::from_nanos(start.as_nanos() / chunk * chunk);
    let running =
        |e| Failure::Runtime(anyhow::Error::new(e).context(format!("running {}", what.display())));
    loop {
        t += SimDuration::from_nanos(chunk);
        let target = t.min(run.end());
        if save.as_ref().is_some_and(|s| s.at <= target)
            && let Some(s) = save.take()
        {
            run.advance(s.at.max(run.now())).map_err(running)?;
            s.write(run)?;
        }
        let going = run.advance(target).map_err(running)?;
        if let Some(r) = recorder.as_mut() {
            r.frame(run).map_err(Failure::Runtime)?;
        }
        let log = run.drain_log();
        if output.verbose {
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
    if let Some(s) = save.take() {
        s.write(run)?;
    }
    if let Some(b) = bar {
        b.finish_and_clear();
    }
    if let Some(r) = recorder {
        r.finish().map_err(Failure::Runtime)?;
    }
    let wall = started.elapsed().as_secs_f64();
    let mut report = vitro_tools::report(run, wall, output.speed);
    if output.resumed {
        report.insert("resumed_at_s".into(), start.as_secs_f64().into());
    }
    if output.json {
        let line = serde_json::to_string(&report)
            .context("encoding the report")
            .map_err(Failure::Runtime)?;
        println!("{line}");
    } else if output.quiet {
        println!("{:016x}", run.trace_hash());
    } else {
        print_summary(run, wall);
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

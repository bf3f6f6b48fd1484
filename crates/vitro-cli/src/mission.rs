//! `vitro run` for mission scenarios (the evacuation mission): builds the mission, runs it
//! (paced or not, recorded or not), prints a summary or one JSON object.

use crate::Failure;
use crate::run_args::RunArgs;
use anyhow::Context as _;
use indicatif::{ProgressBar, ProgressStyle};
use serde::Serialize;
use std::io::IsTerminal;
use std::path::Path;
use std::time::Instant;
use vitro::time::{SimDuration, SimTime};
use vitro_evac::referee::Metrics;
use vitro_evac::{Mission, MissionError};
use vitro_tactical::scenario::Preset;

/// True if the file at `path` looks like a mission scenario (it has `[site]` or
/// `[[entity]]`); unreadable or malformed files are left to the demo's loader to report.
pub(crate) fn is_mission(path: &Path) -> bool {
    let Ok(text) = std::fs::read_to_string(path) else {
        return false;
    };
    match text.parse::<toml::Table>() {
        Ok(t) => t.contains_key("site") || t.contains_key("entity"),
        Err(_) => text.contains("[site]") || text.contains("[[entity]]"),
    }
}

/// Builds the mission of `path`: scenario problems are bad input, set-up failures runtime
/// errors.
pub(crate) fn build(
    path: &Path,
    seed: Option<u64>,
    fidelity: Option<&str>,
) -> Result<Mission, Failure> {
    let built = match fidelity {
        None => Mission::from_file(path, seed),
        Some(p) => {
            let preset = match p {
                "interpolated" => Preset::Interpolated,
                "physical" => Preset::Physical,
                _ => Preset::Discrete,
            };
            Mission::at_fidelity(path, seed, preset)
        }
    };
    built.map_err(|e| match e {
        MissionError::Scenario(d) => Failure::Input(
            anyhow::Error::new(d).context(format!("invalid scenario {}", path.display())),
        ),
        MissionError::Setup(_) => Failure::Runtime(anyhow::Error::new(e)),
    })
}

/// What `vitro run --json` prints for a mission.
#[derive(Serialize)]
pub(crate) struct Report {
    /// Scenario name.
    pub scenario: String,
    /// Seed.
    pub seed: u64,
    /// Fidelity level of each entity type present.
    pub levels: std::collections::BTreeMap<String, String>,
    #[serde(flatten)]
    pub metrics: Metrics,
    /// Trace hash, hexadecimal.
    pub trace_hash: String,
    /// Wall time of the run, seconds.
    pub wall_time_s: f64,
    /// Events per wall second.
    pub events_per_wall_s: f64,
    /// Simulated seconds per wall second.
    pub sim_s_per_wall_s: f64,
}

/// The levels of the entity types present in `m`.
pub(crate) fn levels(m: &Mission) -> std::collections::BTreeMap<String, String> {
    m.members
        .iter()
        .map(|x| (x.kind.name().to_string(), x.level.name().to_string()))
        .collect()
}

pub(crate) fn run(args: &RunArgs) -> Result<(), Failure> {
    let text = std::fs::read_to_string(&args.scenario).ok();
    let mut mission = build(&args.scenario, args.seed, args.fidelity.as_deref())?;
    let seed = args.seed.unwrap_or_else(|| seed_of(text.as_deref()));
    if let Some(until) = args.until {
        if !(until > 0.0 && until <= 1.0e6) {
            return Err(Failure::Input(anyhow::anyhow!(
                "--until {until}: expected a number of simulated seconds in (0, 1e6]"
            )));
        }
        mission.end = mission.end.min(SimTime::from_secs_f64(until));
    }
    if let Some(speed) = args.speed {
        mission
            .sim
            .control()
            .set_speed(speed)
            .context("--speed")
            .map_err(Failure::Input)?;
    }
    let chatty = !args.quiet && !args.json;
    if chatty {
        eprintln!(
            "running {:?} from {} (seed {seed}, at most {:.0} s simulated{})",
            mission.name,
            args.scenario.display(),
            mission.end.as_secs_f64(),
            args.speed
                .map(|s| format!(", paced at {s}x"))
                .unwrap_or_default()
        );
    }
    let bar = (chatty && std::io::stderr().is_terminal()).then(|| {
        let b = ProgressBar::new(mission.end.as_secs_f64() as u64);
        b.set_style(
            ProgressStyle::with_template("{bar:40} {pos}/{len} s simulated, {msg}")
                .unwrap_or_else(|_| ProgressStyle::default_bar()),
        );
        b
    });
    let mut recorder = match &args.record {
        Some(path) => {
            Some(crate::record::Recording::create(path, &mission).map_err(Failure::Runtime)?)
        }
        None => None,
    };
    let started = Instant::now();
    let chunk = mission.sample.max(SimDuration::from_secs(1));
    let mut t = SimTime::ZERO;
    loop {
        t += chunk;
        let going = mission.advance(t.min(mission.end));
        if let Some(r) = recorder.as_mut() {
            r.frame(&mut mission).map_err(Failure::Runtime)?;
        }
        if args.verbose {
            for (at, line) in mission.referee.log.iter() {
                eprintln!("{:8.1} s  {line}", at.as_secs_f64());
            }
        }
        if recorder.is_none() {
            mission.referee.log.clear();
        }
        if let Some(b) = &bar {
            b.set_position(mission.sim.now().as_secs_f64() as u64);
            b.set_message(format!("{} events", mission.sim.events_fired()));
        }
        if !going || t >= mission.end {
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
    let metrics = mission.metrics();
    let per_wall = |x: f64| if wall > 0.0 { x / wall } else { 0.0 };
    let report = Report {
        scenario: mission.name.clone(),
        seed,
        levels: levels(&mission),
        events_per_wall_s: per_wall(metrics.events as f64),
        sim_s_per_wall_s: per_wall(metrics.sim_time_s),
        metrics,
        trace_hash: format!("{:016x}", mission.sim.trace_hash()),
        wall_time_s: wall,
    };
    if args.json {
        let line = serde_json::to_string(&report)
            .context("encoding the report")
            .map_err(Failure::Runtime)?;
        println!("{line}");
    } else if args.quiet {
        println!("{}", report.trace_hash);
    } else {
        print_summary(&report);
    }
    if report.metrics.success {
        Ok(())
    } else {
        Err(Failure::Check(anyhow::anyhow!(
            "mission failed: the VIP was {}",
            if report.metrics.vip_down {
                "hit"
            } else {
                "not extracted in time"
            }
        )))
    }
}

/// The seed written in the scenario (for the report), 0 if unreadable.
fn seed_of(text: Option<&str>) -> u64 {
    text.and_then(|t| t.parse::<toml::Table>().ok())
        .and_then(|t| t.get("seed").and_then(|v| v.as_integer()))
        .map_or(0, |s| s as u64)
}

fn print_summary(r: &Report) {
    let m = &r.metrics;
    let opt = |x: Option<f64>| x.map_or("-".to_string(), |v| format!("{v:.1} s"));
    println!("scenario      {} (seed {})", r.scenario, r.seed);
    let levels: Vec<String> = r.levels.iter().map(|(k, v)| format!("{k} {v}")).collect();
    println!("levels        {}", levels.join(", "));
    println!(
        "outcome       {}, time to extraction {}",
        if m.success {
            "SUCCESS: the VIP is out"
        } else {
            "FAILURE"
        },
        opt(m.time_to_extraction_s)
    );
    println!(
        "team          {} casualties, uncovered {:.1} s, {} shots taken at it",
        m.casualties, m.time_uncovered_s, m.shots
    );
    println!(
        "adversaries   {} of {} detected, mean time to first report {}",
        m.adversaries_detected,
        m.adversaries,
        opt(m.mean_time_to_detection_s)
    );
    println!(
        "HVT           {}",
        if m.hvt_captured {
            format!("captured at {}", opt(m.hvt_capture_s))
        } else {
            "not captured".into()
        }
    );
    println!(
        "messages      {} sent, {} lost",
        m.messages_sent, m.messages_lost
    );
    println!(
        "cover plan    {} repairs, {} plan messages{}",
        m.plan_repairs,
        m.plan_messages,
        if m.plan_cuts > 0 {
            format!(", {} cut by the depth bound", m.plan_cuts)
        } else {
            String::new()
        }
    );
    if let Some(p) = m.patrol_capture_probability {
        let pct = |x: Option<f64>| x.map_or("-".into(), |x| format!("{:.0} %", 100.0 * x));
        println!(
            "patrol        capture probability {p:.2} (computed); truck within cover radius {}, within sensor range {} of the escort",
            pct(m.patrol_cover_fraction),
            pct(m.patrol_sight_fraction)
        );
    }
    println!(
        "time          {:.1} s simulated in {:.3} s wall ({:.0}x real time), {} events ({:.0}/s)",
        m.sim_time_s, r.wall_time_s, r.sim_s_per_wall_s, m.events, r.events_per_wall_s
    );
    println!("trace hash    {}", r.trace_hash);
}

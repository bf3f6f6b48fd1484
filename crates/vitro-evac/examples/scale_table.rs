//! The scaling table: the default evacuation mission with extra blocks of entities, run at
//! a fidelity level for a stretch of simulated time, one row per size.
//!
//! `cargo run --release -p vitro-evac --example scale_table -- [--sizes 150,500,2000,10000]
//!  [--levels discrete,interpolated] [--until S] [--until-big S] [--big N]`, or
//! `-- --row BLOCKS:LEVEL:UNTIL` for one row in this process (for a profiler); `--help`.
//!
//! Each extra block is 100 red troopers and 25 civilian cars (no start: placed by the
//! mission from the seed), with `hit_probability = 0` so no attack ends the mission early.
//! A size is rounded to whole blocks over the default scenario's entities. Every row runs
//! in a child process of its own (this example re-run with `--row`), so its peak resident
//! memory (`VmHWM` of `/proc/self/status`) is that row's alone.
//!
//! Columns: level; entities, every entity of the scenario (the mission's members: the
//! default scenario's 20 plus 125 per extra block; `--sizes 150,500,2000` gives 145, 520
//! and 2,020); the extra blocks; events fired, wall seconds of the run (setup excluded), µs
//! per event, simulated seconds per wall second, the run's CPU seconds and µs of CPU per
//! event (the thread's own time: steadier than wall time on a loaded machine), the setup's
//! wall seconds, peak RSS in MiB, the simulated seconds run and the run's trace hash (equal
//! before and after a change that must not alter the model). On stderr, each row adds how
//! vision's looks were answered (`Arena::look_counts`) and the line-of-sight memo's counts.

use std::path::Path;
use std::process::Command;
use std::time::Instant;
use vitro::time::SimTime;
use vitro_evac::Mission;
use vitro_evac::scenario::ScenarioFile;
use vitro_tactical::scenario::{FidelitySpec, Preset};

/// Red troopers in one extra block.
const BLOCK_RED: u32 = 100;
/// Civilian cars in one extra block.
const BLOCK_CARS: u32 = 25;
/// Largest group count the text uses (the groups name the entities, so the rows' trace hashes
/// depend on it).
const GROUP: u32 = 100;

fn scenario_path() -> String {
    concat!(
        env!("CARGO_MANIFEST_DIR"),
        "/../../scenarios/evacuation.toml"
    )
    .to_string()
}

/// `n` groups of `kind` in `[[entity]]` tables totalling `total`, named `{prefix}{k}`.
fn groups(out: &mut String, prefix: &str, kind: &str, side: &str, mut total: u32) {
    let mut k = 0;
    while total > 0 {
        let count = total.min(GROUP);
        k += 1;
        out.push_str(&format!(
            "\n[[entity]]\nname = \"{prefix}{k}\"\ntype = \"{kind}\"\nside = \"{side}\"\ncount = {count}\n"
        ));
        total -= count;
    }
}

/// The default scenario's text with `blocks` extra blocks and no hits.
fn scenario_text(base: &str, blocks: u32) -> Result<String, String> {
    let hit = "hit_probability = 0.3";
    if !base.contains(hit) {
        return Err(format!("the default scenario has no `{hit}` line"));
    }
    let mut text = base.replace(hit, "hit_probability = 0.0");
    groups(&mut text, "xred", "trooper", "red", blocks * BLOCK_RED);
    groups(&mut text, "xcar", "car", "neutral", blocks * BLOCK_CARS);
    Ok(text)
}

fn peak_rss_mib() -> f64 {
    let status = std::fs::read_to_string("/proc/self/status").unwrap_or_default();
    status
        .lines()
        .find_map(|l| l.strip_prefix("VmHWM:"))
        .and_then(|v| v.trim().trim_end_matches("kB").trim().parse::<f64>().ok())
        .map_or(f64::NAN, |kb| kb / 1024.0)
}

/// The calling thread's CPU time in seconds, from `/proc/thread-self/schedstat` (NaN where
/// unavailable).
fn thread_cpu_s() -> f64 {
    std::fs::read_to_string("/proc/thread-self/schedstat")
        .ok()
        .and_then(|s| s.split_whitespace().next()?.parse::<f64>().ok())
        .map_or(f64::NAN, |ns| ns / 1e9)
}

fn preset(level: &str) -> Result<Preset, String> {
    match level {
        "discrete" => Ok(Preset::Discrete),
        "interpolated" => Ok(Preset::Interpolated),
        "physical" => Ok(Preset::Physical),
        other => Err(format!("unknown level `{other}`")),
    }
}

/// One row, in this process.
fn row(blocks: u32, level: &str, until_s: f64) -> Result<(), Box<dyn std::error::Error>> {
    let path = scenario_path();
    let base = std::fs::read_to_string(&path)?;
    let text = scenario_text(&base, blocks)?;
    let t0 = Instant::now();
    let mut v = ScenarioFile::validate_text(Path::new(&path), &text).map_err(|d| d.render())?;
    v.loaded.file.fidelity = FidelitySpec {
        level: preset(level)?,
        ..FidelitySpec::default()
    };
    let mut mission = Mission::build(v, None)?;
    let setup = t0.elapsed().as_secs_f64();
    let entities = mission.members.len();
    let (t1, c1) = (Instant::now(), thread_cpu_s());
    mission.advance(SimTime::from_secs_f64(until_s));
    let wall = t1.elapsed().as_secs_f64();
    let cpu = thread_cpu_s() - c1;
    let events = mission.sim.events_fired();
    let sim_s = mission.sim.now().as_secs_f64();
    println!(
        "{level:>12} {entities:>8} {blocks:>6} {events:>10} {wall:>8.2} {:>9.2} {:>9.1} {cpu:>7.2} {:>9.2} {setup:>7.2} {:>8.1} {sim_s:>7.0} {:016x}",
        wall * 1e6 / events.max(1) as f64,
        sim_s / wall,
        cpu * 1e6 / events.max(1) as f64,
        peak_rss_mib(),
        mission.sim.trace_hash(),
    );
    let arena = mission.sim.env();
    eprintln!(
        "{:>12} looks {:?}, line of sight (memo, cast) {:?}",
        "",
        arena.look_counts(),
        arena.sight_counts()
    );
    Ok(())
}

fn arg<'a>(args: &'a [String], key: &str) -> Option<&'a str> {
    args.iter()
        .position(|a| a == key)
        .and_then(|i| args.get(i + 1))
        .map(String::as_str)
}

const USAGE: &str = "usage: scale_table [--sizes N,N,..] [--levels LEVEL,..] [--until S] \
                     [--big N] [--until-big S] | --row BLOCKS:LEVEL:UNTIL";

/// Options that take a value.
const OPTIONS: [&str; 6] = [
    "--row",
    "--sizes",
    "--levels",
    "--until",
    "--big",
    "--until-big",
];

/// Every argument an option of [`OPTIONS`] with its value: an unknown or a valueless one
/// is an error (the table takes minutes; a typo must not run the default one instead).
fn check(args: &[String]) -> Result<(), String> {
    let mut it = args.iter();
    while let Some(a) = it.next() {
        if !OPTIONS.contains(&a.as_str()) {
            return Err(format!("unknown argument {a}"));
        }
        if it.next().is_none() {
            return Err(format!("{a} takes a value"));
        }
    }
    Ok(())
}

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let args: Vec<String> = std::env::args().collect();
    if args.iter().any(|a| a == "--help" || a == "-h") {
        println!("{USAGE}");
        return Ok(());
    }
    if let Err(e) = check(&args[1..]) {
        eprintln!("scale_table: {e}\n{USAGE}");
        std::process::exit(2);
    }
    if let Some(spec) = arg(&args, "--row") {
        let parts: Vec<&str> = spec.split(':').collect();
        let [blocks, level, until] = parts.as_slice() else {
            return Err("--row BLOCKS:LEVEL:UNTIL".into());
        };
        return row(blocks.parse()?, level, until.parse()?);
    }
    let sizes: Vec<u32> = arg(&args, "--sizes")
        .unwrap_or("150,500,2000,10000")
        .split(',')
        .map(str::parse)
        .collect::<Result<_, _>>()?;
    let levels: Vec<String> = arg(&args, "--levels")
        .unwrap_or("discrete")
        .split(',')
        .map(String::from)
        .collect();
    let until: f64 = arg(&args, "--until").unwrap_or("600").parse()?;
    // Sizes from `--big` up run only to `--until-big` (a slow build's 10,000 entities).
    let big: u32 = arg(&args, "--big").unwrap_or("5000").parse()?;
    let until_big: f64 = arg(&args, "--until-big").unwrap_or("600").parse()?;
    let base = ScenarioFile::load(scenario_path()).map_err(|d| d.render())?;
    let default: u32 = base.file.entities.iter().map(|e| e.count.max(1)).sum();
    println!(
        "{:>12} {:>8} {:>6} {:>10} {:>8} {:>9} {:>9} {:>7} {:>9} {:>7} {:>8} {:>7} trace hash",
        "level",
        "entities",
        "blocks",
        "events",
        "wall s",
        "µs/event",
        "sim/wall",
        "cpu s",
        "cpu µs/ev",
        "setup s",
        "peak MiB",
        "sim s"
    );
    let exe = std::env::current_exe()?;
    for level in &levels {
        for &size in &sizes {
            let blocks = (size.saturating_sub(default) + (BLOCK_RED + BLOCK_CARS) / 2)
                / (BLOCK_RED + BLOCK_CARS);
            let u = if size >= big { until_big } else { until };
            let status = Command::new(&exe)
                .arg("--row")
                .arg(format!("{blocks}:{level}:{u}"))
                .status()?;
            if !status.success() {
                eprintln!("row {size} {level} failed: {status}");
            }
        }
    }
    Ok(())
}

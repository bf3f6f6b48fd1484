//! The mission's timeline, phase by phase, at a fidelity preset: where the time to extraction
//! goes (driving out, the squad's walk to the VIP, the pickup wait, the walk back, boarding,
//! the drive out), and how long the truck stood still in each phase.
//!
//! `cargo run --release -p vitro-evac --example evac_timeline -- LEVEL SEED [SCENARIO]`
//!
//! Prints one JSON object: the level, the seed, the commander's phase log (seconds), each
//! phase's duration, the truck's standing time per phase (speed under 0.2 m/s, sampled every
//! 0.5 s), the time to extraction and the trace hash. The scenario may name a calibration
//! (`[fidelity] calibration`); the preset replaces the file's levels, not its calibration.

use std::collections::BTreeMap;
use vitro::time::{SimDuration, SimTime};
use vitro_evac::EvacRun;
use vitro_evac::Mission;
use vitro_evac::agents::commander::{Commander, Phase};
use vitro_evac::scenario::ScenarioFile;
use vitro_tactical::scenario::{FidelitySpec, Preset};

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let args: Vec<String> = std::env::args().collect();
    let preset = match args.get(1).map(String::as_str) {
        Some("interpolated") => Preset::Interpolated,
        Some("physical") => Preset::Physical,
        _ => Preset::Discrete,
    };
    let seed: u64 = args.get(2).and_then(|s| s.parse().ok()).unwrap_or(1);
    let default = concat!(
        env!("CARGO_MANIFEST_DIR"),
        "/../../scenarios/evacuation.toml"
    );
    let path = args.get(3).map_or(default, String::as_str);
    let mut v = ScenarioFile::validate(path)?;
    v.loaded.file.fidelity = FidelitySpec {
        level: preset,
        ..FidelitySpec::default()
    };
    let mut m = Mission::build(v, Some(seed))?;
    m.end = SimTime::from_secs_f64(900.0);
    let step = SimDuration::from_secs_f64(0.5);
    let mut t = SimTime::ZERO;
    let mut standing: BTreeMap<String, f64> = BTreeMap::new();
    // The squad's walks (Pickup, Escort): the leader's time moving at full pace, at a
    // slow pace, halted away from the goal, and at the goal; the metres it walked.
    let mut walk: BTreeMap<String, [f64; 5]> = BTreeMap::new();
    let mut last_leader: Option<[f64; 3]> = None;
    // When each leg of the drives began (from the commander's stated plan, "leg k/n").
    let mut legs: Vec<(f64, String)> = Vec::new();
    let truck = m.brief.truck;
    let phase_of = |m: &EvacRun| {
        m.sim
            .agent(truck)
            .and_then(|a| a.as_any().downcast_ref::<Commander>())
            .map(|c| c.phase)
    };
    while !m.finished() {
        t += step;
        m.advance(t);
        if let (Some(p), Some(pose)) = (phase_of(&m), m.sim.env().pose(truck))
            && pose.speed.abs() < 0.2
        {
            *standing.entry(format!("{p:?}")).or_default() += 0.5;
        }
        let leg = m
            .sim
            .agent(truck)
            .and_then(|a| a.intention())
            .and_then(|i| i.plan.first().cloned())
            .filter(|p| p.starts_with("leg "))
            .map(|p| format!("{:?} {p}", phase_of(&m)));
        if let Some(leg) = leg
            && legs.last().is_none_or(|(_, l)| *l != leg)
        {
            legs.push((m.sim.now().as_secs_f64(), leg));
        }
        let squad = m
            .sim
            .agent(truck)
            .and_then(|a| a.as_any().downcast_ref::<Commander>())
            .and_then(|c| c.squad.clone());
        if let (Some(p), Some(sq)) = (phase_of(&m), squad)
            && let Some(pose) = m.sim.env().pose(sq.leader)
        {
            let w = walk.entry(format!("{p:?}")).or_default();
            let to_goal = libm::hypot(pose.pos[0] - sq.goal[0], pose.pos[1] - sq.goal[1]);
            let v = pose.speed.abs();
            let i = if to_goal < 3.0 && v < 0.05 {
                3
            } else if v < 0.05 {
                2
            } else if v < 0.9 {
                1
            } else {
                0
            };
            w[i] += 0.5;
            if let Some(q) = last_leader {
                w[4] += libm::hypot(pose.pos[0] - q[0], pose.pos[1] - q[1]);
            }
            last_leader = Some(pose.pos);
        } else {
            last_leader = None;
        }
        if phase_of(&m) == Some(Phase::Done) && m.metrics().success {
            break;
        }
    }
    let metrics = m.metrics();
    let log: Vec<(f64, String)> = m
        .sim
        .agent(truck)
        .and_then(|a| a.as_any().downcast_ref::<Commander>())
        .map(|c| {
            c.log
                .iter()
                .map(|(t, p)| (t.as_secs_f64(), format!("{p:?}")))
                .collect()
        })
        .unwrap_or_default();
    let mut phases: BTreeMap<String, f64> = BTreeMap::new();
    for w in log.windows(2) {
        *phases.entry(w[0].1.clone()).or_default() += w[1].0 - w[0].0;
    }
    let out = serde_json::json!({
        "level": format!("{preset:?}").to_lowercase(),
        "seed": seed,
        "log": log,
        "phases": phases,
        "standing": standing,
        "walk": walk,
        "legs": legs,
        "time_to_extraction_s": metrics.time_to_extraction_s,
        "success": metrics.success,
        "casualties": metrics.casualties,
        "trace": format!("{:016x}", m.sim.trace_hash()),
    });
    println!("{out}");
    Ok(())
}

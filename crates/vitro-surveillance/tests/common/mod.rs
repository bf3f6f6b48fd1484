//! Shared helpers of the mission tests: the default scenario, varied, built and run.

#![allow(dead_code)]

use std::path::{Path, PathBuf};
use vitro::time::SimTime;
use vitro_surveillance::Operation;
use vitro_surveillance::SurveillanceRun;
use vitro_surveillance::agents::station::Station;
use vitro_surveillance::agents::uav::Uav;

/// The default scenario's path.
pub fn path() -> PathBuf {
    PathBuf::from(concat!(
        env!("CARGO_MANIFEST_DIR"),
        "/../../scenarios/surveillance.toml"
    ))
}

/// The default scenario as a table.
pub fn scenario() -> toml::Table {
    let text = std::fs::read_to_string(path()).expect("the default scenario");
    toml::from_str(&text).expect("the default scenario parses")
}

/// Sets `key` (dotted, tables only) of `t` to `value`.
pub fn set(t: &mut toml::Table, key: &str, value: toml::Value) {
    let mut parts: Vec<&str> = key.split('.').collect();
    let last = parts.pop().expect("a key");
    let mut at = t;
    for p in parts {
        at = at
            .entry(p)
            .or_insert_with(|| toml::Value::Table(toml::Table::new()))
            .as_table_mut()
            .expect("a table");
    }
    at.insert(last.into(), value);
}

/// A run of `t` (as if read from the default scenario's path) with `seed`.
pub fn build(t: &toml::Table, seed: u64) -> SurveillanceRun {
    let text = toml::to_string(t).expect("a table prints");
    Operation::from_text(Path::new(&path()), &text, Some(seed), None).expect("the scenario builds")
}

/// Runs `op` to `s` seconds.
pub fn run_to(op: &mut SurveillanceRun, s: u64) {
    let until = SimTime::from_secs(s);
    while op.sim.now() < until && op.advance(until) {}
}

/// The station of a run.
pub fn station(op: &SurveillanceRun) -> &Station {
    op.sim
        .agent(op.members[0].id)
        .and_then(|a| a.as_any().downcast_ref::<Station>())
        .expect("the station")
}

/// The UAVs of a run, with their names.
pub fn uavs(op: &SurveillanceRun) -> Vec<(String, &Uav)> {
    op.members
        .iter()
        .filter_map(|m| {
            let u = op.sim.agent(m.id)?.as_any().downcast_ref::<Uav>()?;
            Some((m.name.clone(), u))
        })
        .collect()
}

//! Snapshots of a demo run: the simulation (town, cars, queue, streams, trace) and the
//! frames' memory of the cars, and back onto a fresh build of the scenario (the session
//! saves its own fields beside).

use crate::DemoRun;
use crate::patrol::Demo;
use serde::{Deserialize, Serialize};
use std::collections::BTreeMap;
use vitro::sim::Simulation;
use vitro_mission::SnapshotError;

/// A demo run's state (written and read back alike).
#[derive(Serialize, Deserialize)]
struct State {
    /// [`Simulation::save_snapshot`]'s bytes.
    sim: Vec<u8>,
    last: BTreeMap<u32, ([f64; 2], u64, f64)>,
}

fn corrupt(e: impl std::fmt::Display) -> SnapshotError {
    SnapshotError::Corrupt(e.to_string())
}

/// The run's simulation and the cars' last shown poses as bytes.
pub(crate) fn save(run: &DemoRun) -> Result<Vec<u8>, SnapshotError> {
    let mut sim = Vec::new();
    run.sim.save_snapshot(&mut sim).map_err(corrupt)?;
    let state = State {
        sim,
        last: run.last.clone(),
    };
    postcard::to_stdvec(&state).map_err(corrupt)
}

/// Puts the cars' poses of `bytes` into `run` (a fresh build of the same scenario) and
/// returns its simulation.
pub(crate) fn restore(run: &mut DemoRun, bytes: &[u8]) -> Result<Simulation<Demo>, SnapshotError> {
    let state: State = postcard::from_bytes(bytes).map_err(corrupt)?;
    let sim = Simulation::load_snapshot(state.sim.as_slice()).map_err(corrupt)?;
    run.last = state.last;
    Ok(sim)
}

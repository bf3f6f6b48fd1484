//! Snapshots of a demo run: the simulation (town, cars, queue, streams, trace) with the
//! run's own progress and the frames' memory, and back onto a fresh build of the scenario.

use crate::Scenario;
use crate::view::{DemoView, listen};
use serde::{Deserialize, Serialize};
use std::collections::BTreeMap;
use vitro::sim::{Simulation, StopReason};
use vitro::time::SimTime;
use vitro_mission::SnapshotError;
use vitro_record::MessageEvent;

/// A demo run's state (written and read back alike).
#[derive(Serialize, Deserialize)]
struct State {
    /// [`Simulation::save_snapshot`]'s bytes.
    sim: Vec<u8>,
    reached: SimTime,
    stop: Option<StopReason>,
    heard: Vec<MessageEvent>,
    last: BTreeMap<u32, ([f64; 2], u64, f64)>,
}

fn corrupt(e: impl std::fmt::Display) -> SnapshotError {
    SnapshotError::Corrupt(e.to_string())
}

impl DemoView {
    /// The run's whole state as bytes. Does not change the run.
    ///
    /// # Errors
    /// [`SnapshotError::Corrupt`] if it cannot be encoded.
    pub fn save_state(&self) -> Result<Vec<u8>, SnapshotError> {
        let s: &Scenario = &self.scenario;
        let mut sim = Vec::new();
        s.sim.save_snapshot(&mut sim).map_err(corrupt)?;
        let heard = self.heard.lock().unwrap_or_else(|p| p.into_inner()).clone();
        let state = State {
            sim,
            reached: s.reached,
            stop: s.stop,
            heard,
            last: self.last.clone(),
        };
        postcard::to_stdvec(&state).map_err(corrupt)
    }

    /// Puts a state [`save_state`](Self::save_state) made into this run, a fresh build of
    /// the same scenario.
    ///
    /// # Errors
    /// [`SnapshotError::Corrupt`] if the bytes do not decode, [`SnapshotError::Mismatch`] if
    /// they hold another number of cars.
    pub fn restore_state(&mut self, bytes: &[u8]) -> Result<(), SnapshotError> {
        let state: State = postcard::from_bytes(bytes).map_err(corrupt)?;
        let sim = Simulation::load_snapshot(state.sim.as_slice()).map_err(corrupt)?;
        let s = &mut self.scenario;
        if sim.entities().len() != s.sim.entities().len() {
            return Err(SnapshotError::Mismatch(format!(
                "{} entities saved, the scenario makes {}",
                sim.entities().len(),
                s.sim.entities().len()
            )));
        }
        s.sim = sim;
        s.reached = state.reached;
        s.stop = state.stop;
        listen(s, &self.heard);
        *self.heard.lock().unwrap_or_else(|p| p.into_inner()) = state.heard;
        self.last = state.last;
        Ok(())
    }
}

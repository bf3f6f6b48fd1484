//! Snapshots of a surveillance run: its whole state (arena and rigid-body world, agents,
//! queue, random streams, trace, losses) as bytes, and back onto a fresh build of the same
//! scenario.
//!
//! The agents are boxed [`Controller`]s, saved as an enum of the mission's three agent kinds, each
//! by its own serde derives. Their briefings (shared, rebuilt from the scenario) are not
//! written: the `brief` fields are marked `#[serde(with = "vitro_mission::snapshot::briefed")]`
//! and taken, on reading, from the run being restored.

use crate::agents::red::Prowler;
use crate::agents::station::Station;
use crate::agents::uav::Uav;
use crate::model::Field;
use crate::net::Net;
use crate::{Heard, Operation};
use serde::{Deserialize, Serialize};
use std::collections::BTreeMap;
use vitro::entity::EntityId;
use vitro::sim::{SimState, SimStateRef, Simulation};
use vitro::time::SimTime;
use vitro_mission::SnapshotError;
use vitro_mission::snapshot::briefed::Restoring;
use vitro_tactical::arena::{Arena, ArenaState, ArenaStateRef, Ev, site_digest};
use vitro_tactical::model::Controller;

/// An agent, borrowed, for saving.
#[derive(Serialize)]
enum AgentRef<'a> {
    Station(&'a Station),
    Uav(&'a Uav),
    Prowler(&'a Prowler),
}

/// An agent read back (boxed, as it will live: the same encoding as the borrowed form).
#[derive(Deserialize)]
enum AgentOwned {
    Station(Box<Station>),
    Uav(Box<Uav>),
    Prowler(Box<Prowler>),
}

#[allow(clippy::borrowed_box)] // the model's agent type is the box
fn agent_ref(u: &Box<dyn Controller<Field>>) -> Result<AgentRef<'_>, SnapshotError> {
    let any = (**u).as_any();
    if let Some(a) = any.downcast_ref::<Station>() {
        Ok(AgentRef::Station(a))
    } else if let Some(a) = any.downcast_ref::<Uav>() {
        Ok(AgentRef::Uav(a))
    } else if let Some(a) = any.downcast_ref::<Prowler>() {
        Ok(AgentRef::Prowler(a))
    } else {
        Err(SnapshotError::Unsupported(
            "a surveillance with an agent of another kind".into(),
        ))
    }
}

fn agent_box(a: AgentOwned) -> Result<Box<dyn Controller<Field>>, SnapshotError> {
    Ok(match a {
        AgentOwned::Station(a) => a as Box<dyn Controller<Field>>,
        AgentOwned::Uav(a) => a as Box<dyn Controller<Field>>,
        AgentOwned::Prowler(a) => a as Box<dyn Controller<Field>>,
    })
}

/// A surveillance run's state, borrowed (written).
#[derive(Serialize)]
struct StateRef<'a> {
    world: u64,
    sim: SimStateRef<'a, ArenaStateRef<'a>, AgentRef<'a>, Ev, Net>,
    lost: &'a BTreeMap<EntityId, SimTime>,
    next_loss: usize,
    next_sample: SimTime,
    finished: bool,
    heard: Heard,
    log: &'a Vec<(SimTime, String)>,
    station_log: usize,
}

/// A surveillance run's state, read back.
#[derive(Deserialize)]
struct State {
    world: u64,
    sim: SimState<ArenaState, AgentOwned, Ev, Net>,
    lost: BTreeMap<EntityId, SimTime>,
    next_loss: usize,
    next_sample: SimTime,
    finished: bool,
    heard: Heard,
    log: Vec<(SimTime, String)>,
    station_log: usize,
}

impl Operation {
    /// The run's whole state as bytes: everything but the static world and the shared
    /// briefings, which a restore takes from a fresh build. Does not change the run.
    ///
    /// # Errors
    /// [`SnapshotError::Unsupported`] if an agent is of a kind the mission does not save.
    pub fn save_state(&self) -> Result<Vec<u8>, SnapshotError> {
        let heard = match self.heard.lock() {
            Ok(h) => h.clone(),
            Err(p) => p.into_inner().clone(),
        };
        let state = StateRef {
            world: site_digest(&self.team.site),
            sim: self.sim.save_state(self.sim.env().state(), agent_ref)?,
            lost: &self.lost,
            next_loss: self.next_loss,
            next_sample: self.next_sample,
            finished: self.finished,
            heard,
            log: &self.log,
            station_log: self.station_log,
        };
        postcard::to_stdvec(&state).map_err(|e| SnapshotError::Corrupt(e.to_string()))
    }

    /// Puts a state [`save_state`](Self::save_state) made into this run, a fresh build of
    /// the same scenario with the same options.
    ///
    /// # Errors
    /// [`SnapshotError::Corrupt`] if the bytes do not decode, [`SnapshotError::Mismatch`] if
    /// this run's site is not the one the state was saved on.
    pub fn restore_state(&mut self, bytes: &[u8]) -> Result<(), SnapshotError> {
        let red = self.members.iter().find_map(|m| {
            let a = self.sim.agent(m.id)?;
            Some((**a).as_any().downcast_ref::<Prowler>()?.brief().clone())
        });
        let state: State = {
            let _shared = Restoring::new()
                .with(self.team.clone())
                .with(self.tasks.clone())
                .with_some(red);
            postcard::from_bytes(bytes).map_err(|e| SnapshotError::Corrupt(e.to_string()))?
        };
        if state.world != site_digest(&self.team.site) {
            return Err(SnapshotError::Mismatch(
                "the map or terrain the scenario names changed since the run was saved".into(),
            ));
        }
        let env = self.sim.env();
        let (site, roads, types) = (env.site.clone(), env.roads.clone(), env.types.clone());
        let calibration = env.calibration.clone();
        let mut sim = Simulation::restore_state(
            state.sim,
            |a| {
                Arena::restore(site, roads, types, a)
                    .map(|mut a| {
                        a.calibration = calibration;
                        a
                    })
                    .map_err(|e| SnapshotError::Corrupt(e.to_string()))
            },
            agent_box,
        )?;
        crate::listen(&mut sim, &self.heard);
        self.sim = sim;
        self.lost = state.lost;
        self.next_loss = state.next_loss;
        self.next_sample = state.next_sample;
        self.finished = state.finished;
        match self.heard.lock() {
            Ok(mut h) => *h = state.heard,
            Err(p) => *p.into_inner() = state.heard,
        }
        self.log = state.log;
        self.station_log = state.station_log;
        Ok(())
    }
}

//! Snapshots of a surveillance run: its simulation (arena and rigid-body world, agents,
//! queue, random streams, trace) and its losses as bytes, and back onto a fresh build of the
//! same scenario (the session saves its own fields beside).
//!
//! The agents are boxed [`Controller`]s, saved as an enum of the mission's three agent kinds
//! ([`vitro_mission::agent_kinds!`]), each by its own serde derives. Their briefings (shared,
//! rebuilt from the scenario) are not written: the `brief` fields are marked
//! `#[serde(with = "vitro_mission::snapshot::briefed")]` and taken, on reading, from the run
//! being restored.

use crate::SurveillanceRun;
use crate::agents::red::Prowler;
use crate::agents::station::Station;
use crate::agents::uav::Uav;
use crate::model::Field;
use crate::net::Net;
use serde::{Deserialize, Serialize};
use std::collections::BTreeMap;
use vitro::entity::EntityId;
use vitro::sim::{SimState, SimStateRef, Simulation};
use vitro::time::SimTime;
use vitro_mission::SnapshotError;
use vitro_mission::snapshot::briefed::Restoring;
use vitro_tactical::arena::{ArenaState, ArenaStateRef, Ev};
use vitro_tactical::model::Controller;

vitro_mission::agent_kinds! { Box<dyn Controller<Field>>:
    Station(Station),
    Uav(Uav),
    Prowler(Prowler),
}

/// The losses of a run: its own state beside the simulation.
#[derive(Serialize, Deserialize)]
struct Losses {
    lost: BTreeMap<EntityId, SimTime>,
    next_loss: usize,
    log: Vec<(SimTime, String)>,
    station_log: usize,
}

/// A surveillance run's state, borrowed (written).
#[derive(Serialize)]
struct StateRef<'a> {
    sim: SimStateRef<'a, ArenaStateRef<'a>, AgentRef<'a>, Ev, Net>,
    losses: Losses,
}

/// A surveillance run's state, read back.
#[derive(Deserialize)]
struct State {
    sim: SimState<ArenaState, AgentOwned, Ev, Net>,
    losses: Losses,
}

fn corrupt(e: impl std::fmt::Display) -> SnapshotError {
    SnapshotError::Corrupt(e.to_string())
}

/// The run's simulation and losses as bytes: everything but the static world and the shared
/// briefings, which a restore takes from a fresh build.
pub(crate) fn save(run: &SurveillanceRun) -> Result<Vec<u8>, SnapshotError> {
    let state = StateRef {
        sim: run.sim.save_state(run.sim.env().state(), agent_ref)?,
        losses: Losses {
            lost: run.lost.clone(),
            next_loss: run.next_loss,
            log: run.log.clone(),
            station_log: run.station_log,
        },
    };
    postcard::to_stdvec(&state).map_err(corrupt)
}

/// Puts the losses of `bytes` into `run` (a fresh build of the same scenario) and returns its
/// simulation.
pub(crate) fn restore(
    run: &mut SurveillanceRun,
    bytes: &[u8],
) -> Result<Simulation<Field>, SnapshotError> {
    let red = run.members.iter().find_map(|m| {
        let a = run.sim.agent(m.id)?;
        Some((**a).as_any().downcast_ref::<Prowler>()?.brief().clone())
    });
    let state: State = {
        let _shared = Restoring::new()
            .with(run.team.clone())
            .with(run.tasks.clone())
            .with_some(red);
        postcard::from_bytes(bytes).map_err(corrupt)?
    };
    let env = run.sim.env();
    let sim = Simulation::restore_state(state.sim, |a| env.rebuilt(a).map_err(corrupt), agent_box)?;
    let l = state.losses;
    (run.lost, run.next_loss, run.log, run.station_log) =
        (l.lost, l.next_loss, l.log, l.station_log);
    Ok(sim)
}

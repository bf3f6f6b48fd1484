//! Snapshots of an evacuation run: its simulation (arena and rigid-body world, agents, queue,
//! random streams, trace) and its referee as bytes, and back onto a fresh build of the same
//! scenario (the session saves its own fields beside).
//!
//! The agents are boxed [`Controller`]s; they are saved as an enum of the mission's agent
//! kinds ([`vitro_mission::agent_kinds!`]), each kind serialized by its own serde derives.
//! What every agent shares and the scenario rebuilds (the [`Brief`], the solved patrol game)
//! is not written: such fields are marked
//! `#[serde(with = "vitro_mission::snapshot::briefed")]` and are taken, on reading, from the
//! run being restored.

use crate::EvacRun;
use crate::agents::air::Aircraft;
use crate::agents::commander::Commander;
use crate::agents::red::{Adversary, Hvt};
use crate::agents::trooper::Trooper;
use crate::agents::ugv::Ugv;
use crate::brief::Brief;
use crate::radio::{Evac, Radio};
use crate::referee::Referee;
use serde::{Deserialize, Serialize};
use vitro::sim::{SimState, SimStateRef, Simulation};
use vitro::trace::stable_str_hash;
use vitro_behaviour::route::VisitNodes;
use vitro_mission::SnapshotError;
use vitro_mission::snapshot::briefed::Restoring;
use vitro_tactical::actuate::by_level::Drive;
use vitro_tactical::arena::{ArenaState, ArenaStateRef, Ev, site_digest};
use vitro_tactical::model::Controller;

vitro_mission::agent_kinds! { Box<dyn Controller<Evac>>:
    Commander(Commander),
    Trooper(Trooper),
    Adversary(Adversary),
    Hvt(Hvt),
    Car(VisitNodes<Drive>),
    Ugv(Ugv),
    Aircraft(Aircraft),
}

/// An evacuation's state, borrowed (written).
#[derive(Serialize)]
struct StateRef<'a> {
    sim: SimStateRef<'a, ArenaStateRef<'a>, AgentRef<'a>, Ev, Radio>,
    referee: &'a Referee,
}

/// An evacuation's state, read back.
#[derive(Deserialize)]
struct State {
    sim: SimState<ArenaState, AgentOwned, Ev, Radio>,
    referee: Referee,
}

/// The digest of what a run rebuilds from its scenario rather than saves: the site and the
/// formation program.
pub(crate) fn world(brief: &Brief) -> u64 {
    site_digest(&brief.site) ^ stable_str_hash(&brief.formation.program).rotate_left(1)
}

fn corrupt(e: impl std::fmt::Display) -> SnapshotError {
    SnapshotError::Corrupt(e.to_string())
}

/// The run's simulation and referee as bytes: everything but the static world and the shared
/// briefings, which a restore takes from a fresh build.
pub(crate) fn save(run: &EvacRun) -> Result<Vec<u8>, SnapshotError> {
    let state = StateRef {
        sim: run.sim.save_state(run.sim.env().state(), agent_ref)?,
        referee: &run.referee,
    };
    postcard::to_stdvec(&state).map_err(corrupt)
}

/// Puts the referee of `bytes` into `run` (a fresh build of the same scenario) and returns
/// its simulation.
pub(crate) fn restore(run: &mut EvacRun, bytes: &[u8]) -> Result<Simulation<Evac>, SnapshotError> {
    let game = run.members.iter().find_map(|m| {
        let a = (**run.sim.agent(m.id)?)
            .as_any()
            .downcast_ref::<Aircraft>()?;
        Some(a.patrol.as_ref()?.game.clone())
    });
    let state: State = {
        let _shared = Restoring::new().with(run.brief.clone()).with_some(game);
        postcard::from_bytes(bytes).map_err(corrupt)?
    };
    let env = run.sim.env();
    let sim = Simulation::restore_state(state.sim, |a| env.rebuilt(a).map_err(corrupt), agent_box)?;
    run.referee = state.referee;
    Ok(sim)
}

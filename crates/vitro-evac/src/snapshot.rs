//! Snapshots of an evacuation run: its whole state (arena and rigid-body world, agents,
//! queue, random streams, trace, referee) as bytes, and back onto a fresh build of the same
//! scenario.
//!
//! The agents are boxed [`Controller`]s; they are saved as an enum of the mission's agent
//! kinds ([`agent_kinds!`]), each kind serialized by its own serde derives. What every agent
//! shares and the scenario rebuilds (the [`Brief`], the solved patrol game) is not written:
//! such fields are marked `#[serde(with = "vitro_mission::snapshot::briefed")]` and are
//! taken, on reading, from the run being restored.

use crate::agents::air::Aircraft;
use crate::agents::commander::Commander;
use crate::agents::red::{Adversary, Hvt};
use crate::agents::trooper::Trooper;
use crate::agents::ugv::Ugv;
use crate::brief::Brief;
use crate::radio::{Evac, Radio};
use crate::referee::Referee;
use crate::{Heard, Mission};
use serde::{Deserialize, Serialize};
use vitro::sim::{SimState, SimStateRef, Simulation};
use vitro::time::SimTime;
use vitro::trace::stable_str_hash;
use vitro_mission::SnapshotError;
use vitro_mission::snapshot::briefed::Restoring;
use vitro_tactical::actuate::by_level::Drive;
use vitro_tactical::arena::{Arena, ArenaState, ArenaStateRef, Ev, site_digest};
use vitro_tactical::behaviour::route::VisitNodes;
use vitro_tactical::model::Controller;

/// The agent kinds of the mission, saved as an enum: one declaration makes the borrowed
/// form (written), the owned form (read), and the conversions from and to a boxed
/// controller.
macro_rules! agent_kinds {
    ($($kind:ident($ty:ty),)*) => {
        /// An agent, borrowed, for saving.
        #[derive(Serialize)]
        enum AgentRef<'a> {
            $($kind(&'a $ty),)*
        }
        /// An agent read back (boxed, as it will live: the same encoding as the borrowed
        /// form).
        #[derive(Deserialize)]
        enum AgentOwned {
            $($kind(Box<$ty>),)*
        }
        #[allow(clippy::borrowed_box)] // the model's agent type is the box
        fn agent_ref(c: &Box<dyn Controller<Evac>>) -> Result<AgentRef<'_>, SnapshotError> {
            let any = (**c).as_any();
            $(if let Some(a) = any.downcast_ref::<$ty>() {
                return Ok(AgentRef::$kind(a));
            })*
            Err(SnapshotError::Unsupported(format!(
                "an evacuation with an agent of another kind ({:?})",
                any.type_id()
            )))
        }
        fn agent_box(a: AgentOwned) -> Result<Box<dyn Controller<Evac>>, SnapshotError> {
            Ok(match a {
                $(AgentOwned::$kind(a) => a as Box<dyn Controller<Evac>>,)*
            })
        }
    };
}

agent_kinds! {
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
    world: u64,
    sim: SimStateRef<'a, ArenaStateRef<'a>, AgentRef<'a>, Ev, Radio>,
    referee: &'a Referee,
    heard: Heard,
    next_sample: SimTime,
    finished: bool,
}

/// An evacuation's state, read back.
#[derive(Deserialize)]
struct State {
    world: u64,
    sim: SimState<ArenaState, AgentOwned, Ev, Radio>,
    referee: Referee,
    heard: Heard,
    next_sample: SimTime,
    finished: bool,
}

/// The digest of what a run rebuilds from its scenario rather than saves: the site and the
/// formation program.
fn world_digest(brief: &Brief) -> u64 {
    site_digest(&brief.site) ^ stable_str_hash(&brief.formation.program).rotate_left(1)
}

impl Mission {
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
            world: world_digest(&self.brief),
            sim: self.sim.save_state(self.sim.env().state(), agent_ref)?,
            referee: &self.referee,
            heard,
            next_sample: self.next_sample,
            finished: self.finished,
        };
        postcard::to_stdvec(&state).map_err(|e| SnapshotError::Corrupt(e.to_string()))
    }

    /// Puts a state [`save_state`](Self::save_state) made into this mission, a fresh build
    /// of the same scenario with the same options.
    ///
    /// # Errors
    /// [`SnapshotError::Corrupt`] if the bytes do not decode, [`SnapshotError::Mismatch`] if
    /// this mission's site or program is not the one the state was saved on.
    pub fn restore_state(&mut self, bytes: &[u8]) -> Result<(), SnapshotError> {
        let game = self.members.iter().find_map(|m| {
            let agent = self.sim.agent(m.id)?;
            let a = (**agent).as_any().downcast_ref::<Aircraft>()?;
            Some(a.patrol.as_ref()?.game.clone())
        });
        let state: State = {
            let _shared = Restoring::new().with(self.brief.clone()).with_some(game);
            postcard::from_bytes(bytes).map_err(|e| SnapshotError::Corrupt(e.to_string()))?
        };
        if state.world != world_digest(&self.brief) {
            return Err(SnapshotError::Mismatch(
                "the map, terrain or formation program the scenario names changed since the run was saved".into(),
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
        self.referee = state.referee;
        match self.heard.lock() {
            Ok(mut h) => *h = state.heard,
            Err(p) => *p.into_inner() = state.heard,
        }
        self.next_sample = state.next_sample;
        self.finished = state.finished;
        Ok(())
    }
}

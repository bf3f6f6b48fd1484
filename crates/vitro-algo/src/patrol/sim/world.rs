//! The simulated world: where every unit and convoy is, the sensors and the actuator that
//! reach it, and the agents.

use std::sync::Arc;

use serde::Serialize;
use vitro::prelude::*;

use super::STEP;
use super::attack::Attacker;
use crate::graph::{Graph, NodeId};
use crate::patrol::PatrolPlan;

/// The simulated world: where every unit and convoy is.
pub struct PatrolWorld {
    pub(super) graph: Graph,
    /// Every mover's vertex.
    pub(super) at: EntityStorage<NodeId>,
    pub(super) units: Vec<EntityId>,
    pub(super) convoys: Vec<EntityId>,
    pub(super) period: usize,
    pub(super) refused: u64,
}

/// The patrol model's events.
#[derive(Clone, Copy, Debug, Serialize)]
pub enum PatrolEvent {
    /// A unit or convoy moves.
    Step,
    /// The attacker looks.
    Look,
}

/// The patrol model (see the module docs).
pub struct PatrolModel;

impl Model for PatrolModel {
    type Env = PatrolWorld;
    type Event = PatrolEvent;
    type Msg = ();
    type Agent = PatrolAgent;

    fn state_digest(env: &PatrolWorld) -> u64 {
        env.at.digest()
    }
}

/// The step being played (at a step's moves) or looked at (half a step later).
pub(super) fn step_of(now: SimTime) -> u64 {
    now.as_nanos() / STEP.as_nanos()
}

/// A mover's own vertex.
struct Here;
impl Sensor<PatrolWorld> for Here {
    type Reading = Option<NodeId>;
    fn read(&self, w: &PatrolWorld, me: EntityId, _: &mut Probe) -> Option<NodeId> {
        w.at.get(me).copied()
    }
}

/// What the attacker sees: the phase, every unit's vertex, every convoy's vertex.
pub struct Watch;

/// A [`Watch`] reading.
pub struct Sighting {
    /// The step's phase.
    pub phase: usize,
    /// Every unit's vertex, in unit order.
    pub units: Vec<NodeId>,
    /// Every convoy's vertex, in target order.
    pub convoys: Vec<NodeId>,
}

impl Sensor<PatrolWorld> for Watch {
    type Reading = Sighting;
    fn read(&self, w: &PatrolWorld, _: EntityId, probe: &mut Probe) -> Sighting {
        let where_ = |ids: &[EntityId]| -> Vec<NodeId> {
            ids.iter()
                .map(|&id| w.at.get(id).copied().unwrap_or(NodeId::MAX))
                .collect()
        };
        let period = w.period.max(1) as u64;
        Sighting {
            // Below the period, a usize.
            phase: (step_of(probe.now()) % period) as usize,
            units: where_(&w.units),
            convoys: where_(&w.convoys),
        }
    }
}

/// Why a move was refused.
#[derive(Debug, thiserror::Error)]
enum MoveError {
    #[error("no body")]
    NoBody,
    #[error("{from} -> {to} is not an edge")]
    NotAdjacent { from: NodeId, to: NodeId },
}

/// Moves a unit or convoy to a vertex: its own or a neighbour.
struct Drive;
impl Actuator<PatrolWorld, PatrolEvent> for Drive {
    type Command = NodeId;
    type Error = MoveError;
    fn actuate(
        &self,
        w: &mut PatrolWorld,
        me: EntityId,
        to: NodeId,
        _: &mut Effects<PatrolEvent>,
    ) -> Result<(), MoveError> {
        let Some(&from) = w.at.get(me) else {
            w.refused += 1;
            return Err(MoveError::NoBody);
        };
        if from != to && !w.graph.has_edge(from, to) {
            w.refused += 1;
            return Err(MoveError::NotAdjacent { from, to });
        }
        if from != to {
            w.at.insert(me, to);
        }
        Ok(())
    }
}

/// The agents of the patrol model.
pub enum PatrolAgent {
    /// A patrol unit following its plan.
    Unit {
        /// The plan.
        plan: Arc<PatrolPlan>,
        /// Which unit of the plan.
        unit: usize,
    },
    /// A convoy on its timetable.
    Convoy {
        /// Its vertex at every step of the period.
        schedule: Vec<NodeId>,
    },
    /// The attacker.
    Attacker(Box<Attacker>),
}

impl Agent<PatrolModel> for PatrolAgent {
    fn handle(&mut self, input: Input<'_, PatrolModel>, cx: &mut Context<'_, PatrolModel>) {
        let Input::Event(event) = input else {
            return;
        };
        match (self, event) {
            (PatrolAgent::Unit { plan, unit }, PatrolEvent::Step) => {
                if let Some(here) = cx.sense(&Here) {
                    let phase = plan.phase(step_of(cx.now()).saturating_sub(1));
                    let next = plan.next_vertex(*unit, here, phase, cx.rng("patrol"));
                    // A refused move is counted by the world; the unit stays.
                    let _ = cx.act(&Drive, next.unwrap_or(here));
                }
                cx.schedule_in(STEP, Target::Entity(cx.me()), PatrolEvent::Step);
            }
            (PatrolAgent::Convoy { schedule }, PatrolEvent::Step) => {
                let len = schedule.len().max(1) as u64;
                // Below the schedule's length, a usize.
                let i = (step_of(cx.now()) % len) as usize;
                if let Some(&to) = schedule.get(i) {
                    let _ = cx.act(&Drive, to);
                }
                cx.schedule_in(STEP, Target::Entity(cx.me()), PatrolEvent::Step);
            }
            (PatrolAgent::Attacker(attacker), PatrolEvent::Look) => {
                if attacker.look(cx) {
                    cx.schedule_in(STEP, Target::Entity(cx.me()), PatrolEvent::Look);
                } else {
                    cx.request_stop();
                }
            }
            _ => {}
        }
    }
}

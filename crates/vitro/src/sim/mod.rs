//! The simulation: a model's environment and agents driven by the event queue.
//!
//! A [`Model`] names four types: the environment (storages), the event payload, the message
//! content and the agent. Agents receive [`Input`]s and answer through a [`Context`], which
//! offers sensors, actuators, scheduling, messages and random streams, and never the
//! environment itself.

mod context;
pub mod control;
mod driver;
mod kernel;
mod snapshot;

pub use context::{Context, CostModel};
pub use control::{Clock, Control, ControlError, ManualClock, WallClock};
pub use driver::{Fired, Simulation, StopReason};
pub use snapshot::SnapshotError;

use crate::comm::{DeliveryError, Envelope};
use crate::entity::EntityId;
use crate::env::Effects;
use crate::time::SimTime;
use serde::Serialize;

/// The types of one simulation model, and its environment's behaviour.
pub trait Model: Sized + 'static {
    /// The environment: every storage of the world.
    type Env;
    /// Event payloads (typed; stored inline in the queue, no box per event).
    type Event: Serialize;
    /// Message contents.
    type Msg: Clone + Serialize;
    /// The agents (a single type, or an enum of agent kinds: dispatch stays static).
    type Agent: Agent<Self>;

    /// Handles an event targeted at the environment ([`Target::Env`](crate::event::Target)):
    /// physics steps, delayed actuator effects. Does nothing by default.
    fn on_env_event(env: &mut Self::Env, event: &Self::Event, fx: &mut Effects<'_, Self::Event>) {
        let _ = (env, event, fx);
    }

    /// The position sensor used by range-limited channels: where `who` is at `now` (models
    /// that move bodies by events may interpolate). `None` by default (no position).
    fn locate(env: &Self::Env, who: EntityId, now: SimTime) -> Option<[f64; 3]> {
        let _ = (env, who, now);
        None
    }

    /// A digest of the environment's state changes so far (combine the storages'
    /// `digest()`s). Part of the trace hash. Zero by default.
    fn state_digest(env: &Self::Env) -> u64 {
        let _ = env;
        0
    }
}

/// What an agent is woken by.
pub enum Input<'a, M: Model> {
    /// An event targeted at this agent, or broadcast.
    Event(&'a M::Event),
    /// A message delivered to this agent.
    Message(&'a Envelope<M::Msg>),
    /// A message this agent sent that could not be delivered.
    Undeliverable(&'a Envelope<M::Msg>, DeliveryError),
    /// A timer this agent set ([`Context::set_timer`]) with its key.
    Timer(u64),
}

impl<M: Model> Clone for Input<'_, M> {
    fn clone(&self) -> Self {
        *self
    }
}
impl<M: Model> Copy for Input<'_, M> {}

/// An agent: the brain of an entity. It reaches the world only through its [`Context`].
pub trait Agent<M: Model> {
    /// Reacts to one input.
    fn handle(&mut self, input: Input<'_, M>, cx: &mut Context<'_, M>);
}

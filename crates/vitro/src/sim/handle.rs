//! Typed handles to agents: [`Simulation::add`](super::Simulation::add) returns an
//! [`AgentHandle<A>`] for the agent of type `A` it added, and
//! [`Simulation::agent`](super::Simulation::agent) given that handle returns the `A`, so
//! code reading an agent's state after a run names its type once, where it adds it.
//!
//! A model's agent type ([`Model::Agent`]) holds agents of a type `A` when it implements
//! [`Holds<A>`]: every type holds itself, and a model whose agents are boxed trait objects
//! (or an enum of kinds) says how an `A` goes in and comes back out.
//!
//! ```
//! use vitro::prelude::*;
//!
//! struct Ping;
//! impl Model for Ping {
//!     type Env = ();
//!     type Event = ();
//!     type Msg = ();
//!     type Agent = Box<dyn Kind>;
//! }
//! // The model's agents: boxed, of any kind.
//! trait Kind: std::any::Any {
//!     fn handle(&mut self);
//!     fn as_any(&self) -> &dyn std::any::Any;
//! }
//! impl Agent<Ping> for Box<dyn Kind> {
//!     fn handle(&mut self, _: Input<'_, Ping>, _: &mut Context<'_, Ping>) {
//!         (**self).handle();
//!     }
//! }
//! impl<A: Kind> Holds<A> for Box<dyn Kind> {
//!     fn hold(agent: A) -> Self {
//!         Box::new(agent)
//!     }
//!     fn held(&self) -> Option<&A> {
//!         (**self).as_any().downcast_ref()
//!     }
//! }
//! struct Counter(u32);
//! impl Kind for Counter {
//!     fn handle(&mut self) {
//!         self.0 += 1;
//!     }
//!     fn as_any(&self) -> &dyn std::any::Any {
//!         self
//!     }
//! }
//!
//! let mut sim = Simulation::<Ping>::new((), 7);
//! let counter: AgentHandle<Counter> = sim.add("counter", Counter(0)).unwrap();
//! sim.schedule(SimTime::ZERO, Target::Entity(counter.id()), ()).unwrap();
//! sim.run_until(SimTime::MAX);
//! assert_eq!(sim.agent(&counter).unwrap().0, 1);
//! ```

use super::agent::Model;
use crate::entity::EntityId;
use std::fmt;
use std::hash::{Hash, Hasher};
use std::marker::PhantomData;

/// A model's agent type that holds agents of type `A`: how an `A` becomes one of the model's
/// agents, and how it is found in one again.
pub trait Holds<A>: Sized {
    /// The model's agent driven by `agent`.
    fn hold(agent: A) -> Self;
    /// The `A` this agent is, if it is one.
    fn held(&self) -> Option<&A>;
}

impl<A> Holds<A> for A {
    fn hold(agent: A) -> A {
        agent
    }
    fn held(&self) -> Option<&A> {
        Some(self)
    }
}

/// The entity of an agent of type `A` in a simulation (see
/// [`Simulation::add`](super::Simulation::add)).
pub struct AgentHandle<A> {
    id: EntityId,
    kind: PhantomData<fn() -> A>,
}

impl<A> AgentHandle<A> {
    pub(crate) fn new(id: EntityId) -> Self {
        AgentHandle {
            id,
            kind: PhantomData,
        }
    }

    /// The agent's entity.
    pub fn id(&self) -> EntityId {
        self.id
    }
}

impl<A> Clone for AgentHandle<A> {
    fn clone(&self) -> Self {
        *self
    }
}
impl<A> Copy for AgentHandle<A> {}
impl<A> PartialEq for AgentHandle<A> {
    fn eq(&self, other: &Self) -> bool {
        self.id == other.id
    }
}
impl<A> Eq for AgentHandle<A> {}
impl<A> Hash for AgentHandle<A> {
    fn hash<H: Hasher>(&self, state: &mut H) {
        self.id.hash(state);
    }
}
impl<A> fmt::Debug for AgentHandle<A> {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.debug_tuple("AgentHandle").field(&self.id).finish()
    }
}

impl<A> From<AgentHandle<A>> for EntityId {
    fn from(h: AgentHandle<A>) -> EntityId {
        h.id
    }
}

/// What [`Simulation::agent`](super::Simulation::agent) looks an agent up by: an
/// [`EntityId`] (the model's agent) or a handle (the agent's own type).
pub trait AgentKey<M: Model> {
    /// What the look-up returns.
    type Agent;
    /// The entity looked up.
    fn entity(&self) -> EntityId;
    /// The agent as `Self::Agent`, if it is one.
    fn pick(agent: &M::Agent) -> Option<&Self::Agent>;
}

impl<M: Model> AgentKey<M> for EntityId {
    type Agent = M::Agent;
    fn entity(&self) -> EntityId {
        *self
    }
    fn pick(agent: &M::Agent) -> Option<&M::Agent> {
        Some(agent)
    }
}

impl<M: Model, A> AgentKey<M> for &AgentHandle<A>
where
    M::Agent: Holds<A>,
{
    type Agent = A;
    fn entity(&self) -> EntityId {
        self.id
    }
    fn pick(agent: &M::Agent) -> Option<&A> {
        agent.held()
    }
}

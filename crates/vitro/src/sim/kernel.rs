//! The kernel: everything of a simulation but the environment and the agents.

use crate::comm::{DeliveryError, Envelope, Network};
use crate::entity::{CapabilityRegister, Entities, EntityId};
use crate::event::{EventId, EventQueue, Schedule, ScheduleError, Target};
use crate::rng::RngStreams;
use crate::time::SimTime;
use crate::trace::TraceHasher;
use serde::{Deserialize, Serialize};

/// What the queue holds. Messages are boxed so that plain events stay small (a queue slot is
/// as large as its largest variant); typed events are stored inline.
#[derive(Clone, Debug, Serialize, Deserialize)]
pub(crate) enum Queued<E, Msg> {
    /// Scheduled by the environment, an actuator or the harness.
    Event(Target, E),
    /// Scheduled by an agent for itself (only it may cancel it).
    Own(EntityId, E),
    Message(Box<Envelope<Msg>>),
    Bounce(Box<(Envelope<Msg>, DeliveryError)>),
    Timer(EntityId, u64),
}

#[derive(Clone, Debug, Serialize, Deserialize)]
pub(crate) struct Kernel<E, Msg> {
    pub queue: EventQueue<Queued<E, Msg>>,
    pub rngs: RngStreams,
    pub entities: Entities,
    pub register: CapabilityRegister,
    pub network: Network,
    pub trace: TraceHasher,
    pub fired: u64,
    /// Entities with an agent, in registration order (broadcast order).
    pub agent_order: Vec<EntityId>,
    /// Per entity: has an agent.
    pub has_agent: Vec<bool>,
    pub stop_requested: bool,
    pub trace_payloads: bool,
}

impl<E, Msg> Kernel<E, Msg> {
    pub fn new(seed: u64) -> Self {
        Kernel {
            queue: EventQueue::new(),
            rngs: RngStreams::new(seed),
            entities: Entities::default(),
            register: CapabilityRegister::default(),
            network: Network::default(),
            trace: TraceHasher::default(),
            fired: 0,
            agent_order: Vec::new(),
            has_agent: Vec::new(),
            stop_requested: false,
            trace_payloads: true,
        }
    }
}

impl<E, Msg> Schedule<E> for Kernel<E, Msg> {
    fn now(&self) -> SimTime {
        self.queue.now()
    }
    fn schedule_at(
        &mut self,
        at: SimTime,
        target: Target,
        event: E,
    ) -> Result<EventId, ScheduleError> {
        self.queue.push(at, Queued::Event(target, event))
    }
    fn cancel(&mut self, id: EventId) -> bool {
        self.queue.cancel(id)
    }
}

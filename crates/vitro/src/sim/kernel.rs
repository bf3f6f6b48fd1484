//! The kernel: everything of a simulation but the environment and the agents.

use super::round::{Round, RoundId};
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
    /// A firing of a round (its index in `Kernel::rounds`).
    Round(u32),
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
    /// The rounds ([`RoundId`] indexes).
    pub rounds: Vec<Round>,
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
            rounds: Vec::new(),
        }
    }

    /// Makes `e` a member of round `r`; false if it was one already or there is no such
    /// round. An idle round (no member at its last firing) is scheduled again, at the first
    /// instant of its period not before now.
    pub fn join_round(&mut self, r: RoundId, e: EntityId) -> bool {
        let now = self.queue.now();
        let Some(round) = self.rounds.get_mut(r.0 as usize) else {
            return false;
        };
        let joined = round.join(e);
        if !round.pending {
            let p = round.period.as_nanos().max(1);
            let behind = now.as_nanos().saturating_sub(round.next_at.as_nanos());
            let at = round.next_at.as_nanos() + behind.div_ceil(p) * p;
            round.next_at = SimTime::from_nanos(at);
            round.pending = true;
            // Not before now by construction.
            let _ = self.queue.push(round.next_at, Queued::Round(r.0));
        }
        joined
    }

    /// Ends `e`'s membership of round `r` (a firing under way still skips it if its turn
    /// has not come); false if it was not a member.
    pub fn leave_round(&mut self, r: RoundId, e: EntityId) -> bool {
        self.rounds
            .get_mut(r.0 as usize)
            .is_some_and(|round| round.leave(e))
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

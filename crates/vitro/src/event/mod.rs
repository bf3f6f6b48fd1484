//! Events: the pending-event queue and event addressing.

pub mod queue;

pub use queue::{EventId, EventQueue, Popped, ScheduleError};

use crate::entity::EntityId;
use crate::time::SimTime;
use serde::{Deserialize, Serialize};

/// An event or timer an agent scheduled for itself, through its
/// [`Context`](crate::sim::Context): the only kind of event an agent may cancel.
///
/// An agent cannot make one from an [`EventId`] (there is no public constructor), so the
/// events of the environment and of other agents are out of its reach at compile time:
///
/// ```compile_fail,E0423
/// use vitro::event::{EventId, OwnEventId};
/// fn forge(id: EventId) -> OwnEventId {
///     OwnEventId(id) // private field: does not build
/// }
/// ```
///
/// (A value read back from a snapshot is checked again when cancelled: the kernel cancels only
/// a pending event of the calling agent's own.)
#[derive(Copy, Clone, Debug, PartialEq, Eq, PartialOrd, Ord, Hash, Serialize, Deserialize)]
pub struct OwnEventId(EventId);

impl OwnEventId {
    /// Wraps the id of an event the kernel just scheduled for an agent itself.
    pub(crate) fn new(id: EventId) -> Self {
        OwnEventId(id)
    }
    /// The underlying event id (for logs and for matching a fired event).
    pub fn id(self) -> EventId {
        self.0
    }
}

/// Who receives an event.
#[derive(Copy, Clone, Debug, PartialEq, Eq, PartialOrd, Ord, Hash, Serialize, Deserialize)]
pub enum Target {
    /// One entity's agent.
    Entity(EntityId),
    /// Every registered agent, in registration order.
    Broadcast,
    /// The environment itself (physics steps, delayed actuator effects, ...).
    Env,
}

/// Something events can be scheduled on: the simulation kernel implements it.
///
/// Sensors, actuators and the environment see the kernel only through this trait.
pub trait Schedule<Ev> {
    /// The current simulated time.
    fn now(&self) -> SimTime;
    /// Schedules `event` for `target` at `at` (not before now).
    fn schedule_at(
        &mut self,
        at: SimTime,
        target: Target,
        event: Ev,
    ) -> Result<EventId, ScheduleError>;
    /// Cancels a pending event; false if it already fired or was cancelled.
    fn cancel(&mut self, id: EventId) -> bool;
}

//! Events: the pending-event queue and event addressing.

pub mod queue;

pub use queue::{EventId, EventQueue, Popped, ScheduleError};

use crate::entity::EntityId;
use crate::time::SimTime;
use serde::{Deserialize, Serialize};

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

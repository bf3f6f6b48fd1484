//! The simulation: a model's environment and agents driven by the event queue.
//!
//! A [`Model`] names four types: the environment (storages), the event payload, the message
//! content and the agent. Agents receive [`Input`]s and answer through a [`Context`], which
//! offers sensors, actuators, scheduling, messages and random streams, and never the
//! environment itself.

mod agent;
pub mod control;
mod driver;
mod handle;
mod kernel;
mod round;
mod snapshot;

pub use agent::{Agent, Context, CostModel, Input, Model};
pub use control::{Clock, Control, ControlError, ManualClock, WallClock};
pub use driver::{Fired, Simulation, StopReason};
pub use handle::{AgentHandle, AgentKey, Holds};
pub use round::RoundId;
pub use snapshot::{SimState, SimStateRef, SnapshotError};

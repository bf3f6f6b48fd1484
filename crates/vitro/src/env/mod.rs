//! The environment: state in storages, read by sensors and written by actuators.
//!
//! Agents never hold a reference to the environment: a [`Context`](crate::sim::Context) only
//! offers [`sense`](crate::sim::Context::sense) (through a [`Sensor`]) and
//! [`act`](crate::sim::Context::act) (through an [`Actuator`]). Storages are plain data owned by
//! the model's environment type; only sensor and actuator implementations receive it.

pub mod actuator;
pub mod sensor;
pub mod storage;

pub use actuator::{Actuator, Effects};
pub use sensor::{Probe, Sensor};
pub use storage::{EntityStorage, GraphStorage, KeyValueStorage, NodeId, WRITE_LOG};

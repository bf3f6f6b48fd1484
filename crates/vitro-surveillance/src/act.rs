//! The mission's actuators: movement at whatever level each entity was given (the tactical
//! environment's level-dispatching top actuators).

pub use vitro_tactical::actuate::by_level::{Drive, Pilot, Walk};

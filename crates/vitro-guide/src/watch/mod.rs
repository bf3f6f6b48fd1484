//! The perimeter watch, the mission [the mission tutorial](crate::tutorial_5_mission) builds:
//! two guards (UGVs) patrol the junctions round a depot while red walkers make for it; a
//! guard sees walkers only with its own camera and radios each new one to the other guards.
//! Every body runs at the level the scenario's `[fidelity]` gives its type.
//!
//! - [`scenario`]: the file (the shared tables and `[watch]`), read and checked;
//! - [`agents`]: the guard (the walker is the stock `VisitNodes`);
//! - [`setup`]: a run's simulation from a checked file;
//! - [`mission`]: the metrics, the run's [`Play`](vitro_mission::session::Play) and the
//!   [`Mission`](vitro_mission::Mission) the tools look up by `kind = "watch"`.

pub mod agents;
pub mod mission;
pub mod scenario;
pub mod setup;

pub use mission::{PerimeterWatch, WatchRun};

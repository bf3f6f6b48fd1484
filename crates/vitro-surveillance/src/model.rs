//! The mission's model: the shared tactical model ([`Tactical`]) with the mission's own
//! radio vocabulary [`Net`].
//!
//! Every entity moves as it does in any other tactical mission (the arena's events, its
//! levels, its sensors); only the messages differ. The agents are any
//! [`Controller<Field>`](vitro_tactical::model::Controller), read back after a run by the
//! handle [`Simulation::add`](vitro::sim::Simulation::add) returned.

use crate::net::Net;
use vitro_tactical::model::Tactical;

/// The surveillance model: the tactical arena, its messages [`Net`].
pub type Field = Tactical<Net>;

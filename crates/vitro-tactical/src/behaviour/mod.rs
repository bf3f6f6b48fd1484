//! Reusable behaviours: controllers any mission can give its agents.
//!
//! Each is written against a top actuator or an autopilot only, never against a storage, so
//! it runs unchanged at every level of fidelity (the pattern of `vitro`'s
//! `examples/layered.rs`):
//!
//! - [`route`]: visit a list of nodes ([`VisitNodes`](route::VisitNodes)) through any
//!   goal-node actuator, or fly a list of legs ([`FlightMission`](route::FlightMission))
//!   through any autopilot;
//! - [`formation`]: a squad that walks in formation, its leader and members programmed in
//!   the rule language of `vitro_algo::rules`.
//!
//! The mission-specific controllers (the evacuation's patrol, hunt and cover agents) live in
//! their mission's crate; the algorithms they play (the patrol game, the pursuit search, plan
//! repair) are in `vitro-algo`, where any mission reuses them.

pub mod formation;
pub mod route;

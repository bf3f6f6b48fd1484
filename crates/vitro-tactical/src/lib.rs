//! # vitro-tactical: the tactical environment every mission shares
//!
//! On a static site from `vitro-site` (the town, its terrain, line of sight), this crate
//! holds what moves and what senses: entities at several levels of fidelity ([`entity`]:
//! vehicles at nodes, on the ground mesh or as rigid bodies; troopers at nodes or directed;
//! aircraft on lattices, kinematic or with rotor dynamics), with their type parameters from
//! public specifications ([`types`]), live in the [`arena`] (the storages) beside their
//! [`condition`]s; layered actuators ([`actuate`]) and [`autopilot`]s move them, so a
//! controller written against the top actuator runs unchanged at every level of the
//! [`model`]. Agents learn about the [`world`] through [`sensor`]s and talk over the
//! [`radio`]. Reusable [`behaviour`]s (route following, flight legs, formations programmed in
//! the rule language) and the scenario tables missions share ([`scenario`]) sit on top; the
//! cross-level [`check`] re-checks stated properties at each level.
//!
//! A mission (the evacuation in `vitro-evac`) is an application of this crate: its agents,
//! its briefing and its referee live in a crate of their own.

pub mod actuate;
pub mod arena;
pub mod autopilot;
pub mod behaviour;
pub mod check;
pub mod condition;
pub mod entity;
pub mod model;
pub mod radio;
pub mod scenario;
pub mod sensor;
pub mod types;
pub mod world;

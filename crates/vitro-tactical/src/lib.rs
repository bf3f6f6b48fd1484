//! # vitro-tactical: the tactical world
//!
//! A real town from OpenStreetMap ([`map`]) set on a real elevation model ([`terrain`]) as a
//! [`site`], line of sight against both ([`los`]), terrain [`viewshed`]s, and the sensors
//! that use them ([`sensor`]) over a tactical [`world`]; [`info`] and [`render`] give views
//! of a map for the command line.
//!
//! Entities at several levels of fidelity ([`entity`]: vehicles at nodes, on the ground mesh
//! or as rigid bodies; troopers at nodes or directed; aircraft on lattices, kinematic or
//! with rotor dynamics), with their type parameters from public specifications ([`types`]),
//! live in the [`arena`]; layered actuators ([`actuate`]) and [`autopilot`]s move them, so
//! one controller ([`mission`]) runs unchanged at every level of the [`model`]; the
//! cross-level [`check`] re-checks stated properties at each level.

pub mod actuate;
pub mod arena;
pub mod autopilot;
pub mod check;
pub mod condition;
pub mod entity;
pub mod evac;
pub mod formation;
pub mod geo;
pub mod info;
pub mod los;
pub mod map;
pub mod mission;
pub mod model;
pub mod radio;
pub mod render;
pub mod scenario;
pub mod sensor;
pub mod site;
pub mod terrain;
pub mod types;
pub mod viewshed;
pub mod world;

//! # vitro-tactical: the tactical world
//!
//! A real town from OpenStreetMap ([`map`]) set on a real elevation model ([`terrain`]) as a
//! [`site`], line of sight against both ([`los`]), terrain [`viewshed`]s, and the sensors
//! that use them ([`sensor`]) over a tactical [`world`]; [`info`] and [`render`] give views
//! of a map for the command line.

pub mod actuate;
pub mod arena;
pub mod autopilot;
pub mod check;
pub mod entity;
pub mod geo;
pub mod info;
pub mod los;
pub mod map;
pub mod mission;
pub mod model;
pub mod render;
pub mod sensor;
pub mod site;
pub mod terrain;
pub mod types;
pub mod viewshed;
pub mod world;

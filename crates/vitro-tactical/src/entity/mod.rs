//! Bodies at several levels of fidelity: the state the storages hold, and the laws that move
//! them. Nothing here reaches the environment or the event queue: the [`arena`](crate::arena)
//! holds these rows in storages, the [`actuate`](crate::actuate) and
//! [`autopilot`](crate::autopilot) layers drive them.
//!
//! | entity | levels |
//! |---|---|
//! | car, cargo truck, MDARS | [`discrete`] (a node) / [`ground::interpolated`] (x, y on the ground mesh) / [`ground::physical`] (a rigid body on the terrain) |
//! | trooper (blue, red, VIP) | [`discrete`] / [`troop`] (x, y, heading) |
//! | fixed-wing UAV | [`air::Lattice`] (maneuvers on a grid) / [`air::ctol`] (kinematic) |
//! | helicopter UAV | [`air::Lattice`] / [`air::vtol`] (rotor dynamics) |

pub mod air;
pub mod discrete;
pub mod ground;
pub mod roads;
pub mod route;
pub mod stretch;
pub mod troop;

use schemars::JsonSchema;
use serde::{Deserialize, Serialize};

/// A level of fidelity (lower-case in files: `"discrete"`, `"physical"`, ...).
#[derive(
    Copy, Clone, Debug, PartialEq, Eq, PartialOrd, Ord, Hash, Serialize, Deserialize, JsonSchema,
)]
#[serde(rename_all = "lowercase")]
pub enum Level {
    /// Nodes of a graph or cells of a grid; moves are events.
    Discrete,
    /// Ground vehicle moving along the street polyline with acceleration limits.
    Interpolated,
    /// Ground vehicle as a rigid body on the terrain (rapier3d).
    Physical,
    /// Trooper with a position and a heading.
    Directed,
    /// Fixed-wing UAV driven by yaw rate, flight-path angle and airspeed.
    Kinematic,
    /// Helicopter UAV as a rigid body driven by its rotor controls.
    Dynamic,
}

impl Level {
    /// Lower-case name.
    pub fn name(self) -> &'static str {
        match self {
            Level::Discrete => "discrete",
            Level::Interpolated => "interpolated",
            Level::Physical => "physical",
            Level::Directed => "directed",
            Level::Kinematic => "kinematic",
            Level::Dynamic => "dynamic",
        }
    }
}

impl std::fmt::Display for Level {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str(self.name())
    }
}

/// Where a body is and how it moves, whatever its level.
#[derive(Copy, Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct Pose {
    /// World position, metres (ground vehicles and troops: on the ground).
    pub pos: [f64; 3],
    /// Heading, radians counter-clockwise from east.
    pub heading: f64,
    /// Speed, m/s (discrete levels: the speed of the move under way, 0 at rest).
    pub speed: f64,
    /// The level the body lives at.
    pub level: Level,
}

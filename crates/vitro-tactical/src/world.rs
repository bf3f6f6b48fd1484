//! The tactical environment: the static site and the bodies of the entities.
//!
//! Only sensors and actuators receive a [`World`] (the `vitro` core keeps agents away from it).

use serde::{Deserialize, Serialize};
use std::sync::Arc;
use vitro::entity::EntityId;
use vitro::env::EntityStorage;
use vitro_site::site::Site;

/// Allegiance of an entity.
#[derive(Copy, Clone, Debug, PartialEq, Eq, PartialOrd, Ord, Hash, Serialize, Deserialize)]
pub enum Side {
    /// Own forces.
    Blue,
    /// Adversaries.
    Red,
    /// Civilians, bystanders.
    Neutral,
}

impl Side {
    /// All sides, in a fixed order.
    pub const ALL: [Side; 3] = [Side::Blue, Side::Red, Side::Neutral];
}

/// The physical state of an entity that sensors look at.
#[derive(Copy, Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct Body {
    /// Position of the body's base (its feet, wheels, or an aircraft's centre), world metres.
    pub pos: [f64; 3],
    /// Heading, radians counter-clockwise from east (+x).
    pub heading: f64,
    /// Allegiance.
    pub side: Side,
    /// Height, metres: its sensors sit on top, and it is seen if its middle is seen.
    pub height: f64,
}

impl Body {
    /// A body standing at `pos`, facing `heading`.
    pub fn new(pos: [f64; 3], heading: f64, side: Side, height: f64) -> Self {
        Body {
            pos,
            heading,
            side,
            height,
        }
    }
    /// Where its sensors are: the top of the body.
    pub fn eye(&self) -> [f64; 3] {
        [self.pos[0], self.pos[1], self.pos[2] + self.height]
    }
    /// The point others must see to see it: the middle of the body.
    pub fn centre(&self) -> [f64; 3] {
        [self.pos[0], self.pos[1], self.pos[2] + self.height / 2.0]
    }
}

/// The tactical environment: a shared static [`Site`] and an [`EntityStorage`] of bodies.
#[derive(Clone, Debug)]
pub struct World {
    /// Town, terrain, line-of-sight scene (shared between runs).
    pub site: Arc<Site>,
    /// Bodies by entity.
    pub bodies: EntityStorage<Body>,
}

impl World {
    /// A world on `site` with no bodies yet.
    pub fn new(site: Arc<Site>) -> Self {
        World {
            site,
            bodies: EntityStorage::default(),
        }
    }
    /// The body of `id`.
    pub fn body(&self, id: EntityId) -> Option<&Body> {
        self.bodies.get(id)
    }
}

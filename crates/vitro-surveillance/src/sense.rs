//! The mission's own sensor: an entity's own state (a UAV knows whether it still flies).
//! The camera and its locks are the toolkit's tracking sensor
//! (`vitro_tactical::sensor::track`); the own position is `vitro_tactical::arena::OwnPose`.

use vitro::entity::EntityId;
use vitro::env::{Probe, Sensor};
use vitro_tactical::arena::Arena;
use vitro_tactical::condition::Status;

/// Whether the entity is active (flying, driving, walking): false once it is down.
#[derive(Copy, Clone, Debug, Default)]
pub struct Alive;

impl Sensor<Arena> for Alive {
    type Reading = bool;
    fn read(&self, w: &Arena, me: EntityId, _: &mut Probe<'_>) -> bool {
        w.conditions
            .get(me)
            .is_some_and(|c| c.status == Status::Active)
    }
}

//! Tactical bodies as recordings draw them: sides and entities of the arena in
//! [`vitro_record`]'s terms, for a mission's frames.

use crate::entity::Pose;
use crate::world::Side;
use vitro::entity::EntityId;
use vitro_record::EntityState;

/// A side as recordings name it.
pub fn side(s: Side) -> vitro_record::Side {
    match s {
        Side::Blue => vitro_record::Side::Friendly,
        Side::Red => vitro_record::Side::Hostile,
        Side::Neutral => vitro_record::Side::Neutral,
    }
}

/// Entity `id` named `name`, of `kind` (e.g. `"trooper"`) and `allegiance`, drawn at `pose` in
/// condition `status` (e.g. `"active"`).
pub fn entity(
    id: EntityId,
    name: &str,
    kind: &str,
    allegiance: Side,
    pose: &Pose,
    status: String,
) -> EntityState {
    EntityState {
        id: id.0,
        name: name.to_owned(),
        kind: kind.to_owned(),
        side: side(allegiance),
        level: pose.level.name().into(),
        pos: pose.pos,
        heading: pose.heading,
        speed: pose.speed,
        status,
    }
}

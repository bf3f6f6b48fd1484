//! The entities of a mission as its scenario declares them.

use vitro::entity::EntityId;
use vitro_tactical::condition::Role;
use vitro_tactical::entity::Level;
use vitro_tactical::scenario::EntityType;
use vitro_tactical::world::Side;

/// One entity of the mission as the scenario declares it.
#[derive(Clone, Debug, PartialEq)]
pub struct Member {
    /// Its id.
    pub id: EntityId,
    /// Its unique name.
    pub name: String,
    /// Its type in the scenario.
    pub kind: EntityType,
    /// Its role in the world.
    pub role: Role,
    /// Its side.
    pub side: Side,
    /// Its level of fidelity.
    pub level: Level,
    /// Its start, town metres, if the file gives one.
    pub start: Option<[f64; 2]>,
    /// Its altitude above the ground (aircraft), metres.
    pub altitude: Option<f64>,
}

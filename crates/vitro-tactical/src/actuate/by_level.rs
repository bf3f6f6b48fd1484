//! Top actuators at a chosen level: one per family, each handing the command to that level's
//! own actuator or autopilot, so a mission gives every entity the level its scenario names
//! and its controllers stay level-blind. A level the family has not (a vehicle driven at the
//! directed level) is refused with an error ([`MoveError::NoSuchLevel`],
//! [`FlyError::NoSuchLevel`]), never taken for another.
//!
//! ```
//! use vitro_tactical::actuate::by_level::{Drive, Pilot, Walk};
//! use vitro_tactical::entity::Level;
//! // A truck driven at the physical level, a trooper walking directed, a UAV on its lattice.
//! let (truck, trooper, uav) = (Drive(Level::Physical), Walk(Level::Directed), Pilot(Level::Discrete));
//! assert_eq!(truck.0, Level::Physical);
//! # let _ = (trooper, uav);
//! ```

use crate::actuate::{MoveError, ground, troop};
use crate::arena::{Arena, Ev};
use crate::autopilot::{self, FlyError};
use crate::entity::Level;
use crate::entity::air::FlightCommand;
use serde::{Deserialize, Serialize};
use vitro::entity::EntityId;
use vitro::env::{Actuator, Effects, NodeId};

/// GoToNode for a ground vehicle at its level.
#[derive(Copy, Clone, Debug, Serialize, Deserialize)]
pub struct Drive(pub Level);

impl Actuator<Arena, Ev> for Drive {
    type Command = NodeId;
    type Error = MoveError;
    fn actuate(
        &self,
        w: &mut Arena,
        me: EntityId,
        goal: NodeId,
        fx: &mut Effects<'_, Ev>,
    ) -> Result<(), MoveError> {
        match self.0 {
            Level::Interpolated => ground::interpolated::GoToNode.actuate(w, me, goal, fx),
            Level::Physical => ground::physical::GoToNode.actuate(w, me, goal, fx),
            Level::Discrete => ground::discrete::GoToNode.actuate(w, me, goal, fx),
            level @ (Level::Directed | Level::Kinematic | Level::Dynamic) => {
                Err(MoveError::NoSuchLevel(me, level))
            }
        }
    }
}

/// WalkToNode for a person on foot at its level.
#[derive(Copy, Clone, Debug, Serialize, Deserialize)]
pub struct Walk(pub Level);

impl Actuator<Arena, Ev> for Walk {
    type Command = NodeId;
    type Error = MoveError;
    fn actuate(
        &self,
        w: &mut Arena,
        me: EntityId,
        goal: NodeId,
        fx: &mut Effects<'_, Ev>,
    ) -> Result<(), MoveError> {
        match self.0 {
            Level::Directed => troop::directed::WalkToNode.actuate(w, me, goal, fx),
            Level::Discrete => troop::discrete::WalkToNode.actuate(w, me, goal, fx),
            level @ (Level::Interpolated | Level::Physical | Level::Kinematic | Level::Dynamic) => {
                Err(MoveError::NoSuchLevel(me, level))
            }
        }
    }
}

/// The autopilot of an aircraft at its level: the lattice at the discrete level, the
/// fixed-wing kinematic autopilot, or the helicopter's rotor-dynamics autopilot.
#[derive(Copy, Clone, Debug, Serialize, Deserialize)]
pub struct Pilot(pub Level);

impl Actuator<Arena, Ev> for Pilot {
    type Command = FlightCommand;
    type Error = FlyError;
    fn actuate(
        &self,
        w: &mut Arena,
        me: EntityId,
        cmd: FlightCommand,
        fx: &mut Effects<'_, Ev>,
    ) -> Result<(), FlyError> {
        match self.0 {
            Level::Kinematic => autopilot::ctol::Autopilot.actuate(w, me, cmd, fx),
            Level::Dynamic => autopilot::vtol::Autopilot.actuate(w, me, cmd, fx),
            Level::Discrete => autopilot::lattice::Autopilot.actuate(w, me, cmd, fx),
            level @ (Level::Interpolated | Level::Physical | Level::Directed) => {
                Err(FlyError::NoSuchLevel(me, level))
            }
        }
    }
}

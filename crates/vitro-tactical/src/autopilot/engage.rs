//! What every autopilot shares: checking a command, engaging it as the pilot state, and
//! telling the owner a waypoint was reached.

use crate::arena::{Arena, Ev};
use crate::entity::Level;
use crate::entity::air::{FlightCommand, Pilot};
use serde::{Deserialize, Serialize};
use vitro::entity::EntityId;
use vitro::env::Effects;
use vitro::event::Target;
use vitro::time::SimDuration;

/// Why an autopilot refused a command.
#[derive(Clone, Debug, PartialEq, thiserror::Error, Serialize, Deserialize)]
pub enum FlyError {
    /// The entity has no aircraft this autopilot flies.
    #[error("entity {0:?} has no aircraft this autopilot flies")]
    NoBody(EntityId),
    /// A waypoint command without waypoints.
    #[error("a waypoint command needs at least one waypoint")]
    NoWaypoints,
    /// A number is not finite.
    #[error("the command holds a value that is not a finite number")]
    NotFinite,
    /// The autopilot was built for a level no aircraft has (e.g. the physical level of a
    /// ground vehicle).
    #[error("entity {0:?}: no aircraft flies at the {level} level", level = .1.name())]
    NoSuchLevel(EntityId, Level),
}

/// Checks a command before an autopilot takes it.
pub(crate) fn validate(cmd: &FlightCommand) -> Result<(), FlyError> {
    let finite = |v: &[f64]| v.iter().all(|x| x.is_finite());
    match cmd {
        FlightCommand::Straight {
            heading,
            altitude,
            speed,
        } => {
            if !finite(&[*heading, *altitude, speed.unwrap_or(0.0)]) {
                return Err(FlyError::NotFinite);
            }
        }
        FlightCommand::Waypoints { points, speed } => {
            if points.is_empty() {
                return Err(FlyError::NoWaypoints);
            }
            if !points.iter().all(|p| finite(p)) || !speed.unwrap_or(0.0).is_finite() {
                return Err(FlyError::NotFinite);
            }
        }
    }
    Ok(())
}

/// Stores the command as the aircraft's pilot state.
pub(crate) fn engage(w: &mut Arena, me: EntityId, cmd: FlightCommand) {
    w.pilots.insert(
        me,
        Pilot {
            cmd,
            next: 0,
            plan: Vec::new(),
        },
    );
}

/// Tells `who` it reached waypoint `i`, now.
pub(crate) fn reached(who: EntityId, i: usize, fx: &mut Effects<'_, Ev>) {
    fx.schedule_in(
        SimDuration::ZERO,
        Target::Entity(who),
        Ev::Waypoint(i as u32),
    );
}

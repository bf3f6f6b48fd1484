//! The mission's actuators: movement at whatever level each entity type was given (the
//! tactical environment's level-dispatching top actuators, re-exported), and the mission's own acts — boarding
//! and leaving the truck, firing, capturing, showing up, being extracted. Each writes the
//! arena's bodies or [`conditions`](vitro_tactical::arena::Arena::conditions); agents reach them only
//! through their `Context`.

use rand::Rng;
use vitro::entity::EntityId;
use vitro::env::{Actuator, Effects};
use vitro_site::map::Mode;
pub use vitro_tactical::actuate::by_level::{Drive, Pilot, Walk};
use vitro_tactical::arena::{Arena, Ev};
use vitro_tactical::condition::Status;
use vitro_tactical::entity::Level;
use vitro_tactical::types::TroopKind;

/// Why a mission act was refused.
#[derive(Clone, Debug, PartialEq, thiserror::Error)]
pub enum ActError {
    /// The actor is not active (aboard, down, captured, hidden).
    #[error("entity {0:?} cannot act now")]
    NotActive(EntityId),
    /// The other party is too far away.
    #[error("entity {0:?} is out of reach")]
    OutOfReach(EntityId),
    /// The body is moving; boarding waits until it stands still.
    #[error("entity {0:?} is moving")]
    Moving(EntityId),
    /// A body could not be placed.
    #[error("cannot place entity {0:?}: {1}")]
    Place(EntityId, String),
}

fn active(w: &Arena, id: EntityId) -> bool {
    w.conditions
        .get(id)
        .is_some_and(|c| c.status == Status::Active)
}

fn ground_distance(w: &Arena, a: EntityId, b: EntityId) -> Option<f64> {
    let (pa, pb) = (w.pose(a)?.pos, w.pose(b)?.pos);
    Some(libm::hypot(pa[0] - pb[0], pa[1] - pb[1]))
}

/// Gets into a vehicle standing within `reach` metres: the body leaves the arena, the
/// condition becomes [`Status::Aboard`].
#[derive(Copy, Clone, Debug)]
pub struct Board {
    /// Most distance to the vehicle, metres.
    pub reach: f64,
}

impl Actuator<Arena, Ev> for Board {
    type Command = EntityId;
    type Error = ActError;
    fn actuate(
        &self,
        w: &mut Arena,
        me: EntityId,
        vehicle: EntityId,
        _: &mut Effects<'_, Ev>,
    ) -> Result<(), ActError> {
        if !active(w, me) {
            return Err(ActError::NotActive(me));
        }
        if ground_distance(w, me, vehicle).is_none_or(|d| d > self.reach) {
            return Err(ActError::OutOfReach(vehicle));
        }
        if !w.remove_trooper(me) {
            return Err(ActError::Moving(me));
        }
        w.conditions
            .update(me, |c| c.status = Status::Aboard(vehicle));
        Ok(())
    }
}

/// Lets passengers out of the acting vehicle: each named passenger aboard gets a body at
/// the walk-graph node nearest the vehicle, at `level`.
#[derive(Copy, Clone, Debug, serde::Serialize, serde::Deserialize)]
pub struct Dismount {
    /// The troopers' level.
    pub level: Level,
}

impl Actuator<Arena, Ev> for Dismount {
    type Command = Vec<(EntityId, TroopKind)>;
    type Error = ActError;
    fn actuate(
        &self,
        w: &mut Arena,
        me: EntityId,
        who: Vec<(EntityId, TroopKind)>,
        _: &mut Effects<'_, Ev>,
    ) -> Result<(), ActError> {
        let pose = w.pose(me).ok_or(ActError::NotActive(me))?;
        let p = w.site.to_town([pose.pos[0], pose.pos[1]]);
        let node = w
            .roads
            .of(Mode::Walk)
            .nearest_connected(p)
            .ok_or(ActError::Place(me, "no walk-graph node".into()))?;
        for (id, kind) in who {
            if w.conditions.get(id).map(|c| c.status) != Some(Status::Aboard(me)) {
                continue;
            }
            w.add_trooper(id, kind, self.level, node, pose.heading)
                .map_err(|e| ActError::Place(id, e.to_string()))?;
            w.conditions.update(id, |c| c.status = Status::Active);
        }
        Ok(())
    }
}

/// Fires at a target within `range` metres; hits with probability `p_hit` (drawn from the
/// shooter's `"fire"` stream). A hit person is down; a hit vehicle puts one of its
/// passengers down (drawn uniformly) if it has any. Returns whether it hit.
#[derive(Copy, Clone, Debug)]
pub struct Fire {
    /// Range, metres.
    pub range: f64,
    /// Probability of a hit.
    pub p_hit: f64,
}

impl Actuator<Arena, Ev> for Fire {
    type Command = EntityId;
    type Error = ActError;
    fn actuate(
        &self,
        w: &mut Arena,
        me: EntityId,
        target: EntityId,
        fx: &mut Effects<'_, Ev>,
    ) -> Result<(), ActError> {
        if !active(w, me) {
            return Err(ActError::NotActive(me));
        }
        if !active(w, target) || ground_distance(w, me, target).is_none_or(|d| d > self.range) {
            return Err(ActError::OutOfReach(target));
        }
        let rng = fx.rng("fire");
        if rng.random::<f64>() >= self.p_hit {
            return Ok(());
        }
        let person = w.conditions.get(target).is_some_and(|c| c.role.is_person());
        let victim = if person {
            Some(target)
        } else {
            let aboard: Vec<EntityId> = w
                .conditions
                .iter()
                .filter(|(_, c)| c.status == Status::Aboard(target))
                .map(|(id, _)| id)
                .collect();
            (!aboard.is_empty()).then(|| aboard[fx.rng("fire").random_range(0..aboard.len())])
        };
        if let Some(v) = victim {
            w.conditions.update(v, |c| c.status = Status::Down);
        }
        Ok(())
    }
}

/// Captures a target within `reach` metres (the high-value target).
#[derive(Copy, Clone, Debug)]
pub struct Capture {
    /// Most distance, metres.
    pub reach: f64,
}

impl Actuator<Arena, Ev> for Capture {
    type Command = EntityId;
    type Error = ActError;
    fn actuate(
        &self,
        w: &mut Arena,
        me: EntityId,
        target: EntityId,
        _: &mut Effects<'_, Ev>,
    ) -> Result<(), ActError> {
        if !active(w, me) || !active(w, target) {
            return Err(ActError::NotActive(target));
        }
        if ground_distance(w, me, target).is_none_or(|d| d > self.reach) {
            return Err(ActError::OutOfReach(target));
        }
        w.conditions.update(target, |c| c.status = Status::Captured);
        Ok(())
    }
}

/// Changes the actor's own status: showing up (hidden → active) or being extracted.
#[derive(Copy, Clone, Debug)]
pub struct SetStatus;

impl Actuator<Arena, Ev> for SetStatus {
    type Command = Status;
    type Error = ActError;
    fn actuate(
        &self,
        w: &mut Arena,
        me: EntityId,
        status: Status,
        _: &mut Effects<'_, Ev>,
    ) -> Result<(), ActError> {
        let now = w.conditions.get(me).map(|c| c.status);
        let allowed = matches!(
            (now, status),
            (Some(Status::Hidden), Status::Active)
                | (Some(Status::Active), Status::Extracted)
                | (Some(Status::Aboard(_)), Status::Extracted)
        );
        if !allowed {
            return Err(ActError::NotActive(me));
        }
        w.conditions.update(me, |c| c.status = status);
        Ok(())
    }
}

/// Lets every passenger of the acting vehicle out at the extraction point: each becomes
/// [`Status::Extracted`]. Returns nothing; a vehicle with no passengers changes nothing.
#[derive(Copy, Clone, Debug)]
pub struct Unload;

impl Actuator<Arena, Ev> for Unload {
    type Command = ();
    type Error = ActError;
    fn actuate(
        &self,
        w: &mut Arena,
        me: EntityId,
        _: (),
        _: &mut Effects<'_, Ev>,
    ) -> Result<(), ActError> {
        if !active(w, me) {
            return Err(ActError::NotActive(me));
        }
        let aboard: Vec<EntityId> = w
            .conditions
            .iter()
            .filter(|(_, c)| c.status == Status::Aboard(me))
            .map(|(id, _)| id)
            .collect();
        for id in aboard {
            w.conditions.update(id, |c| c.status = Status::Extracted);
        }
        Ok(())
    }
}

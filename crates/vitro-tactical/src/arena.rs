//! The arena: the tactical environment at every level of fidelity, as storages.
//!
//! One [`Arena`] holds a storage per entity family and level (vehicles at nodes, on the
//! ground mesh, as rigid bodies; troopers at nodes or directed; aircraft on lattices,
//! kinematic or dynamic), the route-following state of GoToNode and WalkToNode, and the
//! autopilots' state. An entity lives in exactly one body storage: that is its level. Only
//! sensors and actuators receive the arena; agents see it through them
//! ([`vitro::sim::Context`]).
//!
//! Continuous levels advance in fixed steps, each a [`Ev::Tick`] event for the environment:
//! one clock for the kinematic levels (interpolated vehicles, directed troops), one for the
//! rigid-body physics, one for the aircraft. A clock runs only while something it moves is
//! moving, so a run whose bodies have all arrived runs out of events.

mod grid;
mod look;
mod looks;
mod seen;
mod sight;
mod tracks;

use crate::condition::Condition;
use crate::entity::air::{
    AirKind, Lattice, LatticeBody, Pilot, ctol::CtolBody, dir_of, vtol::VtolBody,
};
use crate::entity::discrete::{AtNode, NodeKind};
use crate::entity::ground::interpolated::OnGround;
use crate::entity::ground::physical::{Chassis, Physics, PhysicsError};
use crate::entity::roads::Roads;
use crate::entity::route::Follow;
use crate::entity::troop::Walker;
use crate::entity::{Level, Pose};
use crate::types::{CtolKind, GroundKind, TroopKind, TypeBook, VtolKind};
use serde::{Deserialize, Serialize};
use std::sync::{Arc, Mutex};
pub(crate) use tracks::TrackCache;
use vitro::entity::EntityId;
use vitro::env::{Effects, EntityStorage, NodeId, Probe, Sensor};
use vitro::event::{EventId, Target};
use vitro::time::SimDuration;
use vitro::trace::TraceHasher;
use vitro_site::map::Mode;
use vitro_site::site::Site;

mod snapshot;
pub use looks::LookCounts;
pub use snapshot::{ArenaState, ArenaStateRef, RestoreError, site_digest};

/// A fixed-step clock of the arena.
#[derive(Copy, Clone, Debug, PartialEq, Eq, PartialOrd, Ord, Hash, Serialize, Deserialize)]
pub enum Clock {
    /// Interpolated vehicles and directed troopers.
    Kinematic,
    /// Rigid-body vehicles.
    Physics,
    /// Kinematic and dynamic aircraft.
    Flight,
}

impl Clock {
    const ALL: [Clock; 3] = [Clock::Kinematic, Clock::Physics, Clock::Flight];
    fn index(self) -> usize {
        self as usize
    }
}

/// The events of a tactical model.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub enum Ev {
    /// Starts a controller.
    Start,
    /// To an agent: its body reached the goal node of its last GoToNode / WalkToNode.
    Arrived(NodeId),
    /// To an agent: its vehicle could not make its way to the goal node of its last
    /// GoToNode, after the bounded recovery of [`Steps::recovery`] (backing out, turning in
    /// several moves) or [`Steps::stall_after`] without progress, for the reason given: the
    /// trip is given up and the body stops where it is; a new GoToNode plans again from
    /// there.
    Stalled(NodeId, StallReason),
    /// To an agent: its autopilot reached waypoint `i` of its current command.
    Waypoint(u32),
    /// To the environment: a node-level body reaches the next node of its trip.
    Hop(EntityId),
    /// To the environment: a lattice aircraft finishes its maneuver.
    Maneuver(EntityId),
    /// To the environment: one fixed step of a clock.
    Tick(Clock),
}

/// Step lengths of the clocks, and how long a stuck vehicle keeps trying.
#[derive(Copy, Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct Steps {
    /// Interpolated vehicles and directed troopers.
    pub kinematic: SimDuration,
    /// Rigid-body vehicles (the rapier step).
    pub physics: SimDuration,
    /// Aircraft guidance and kinematics.
    pub flight: SimDuration,
    /// Sub-steps of the helicopter dynamics (and its inner control loops) per flight step.
    pub rotor_substeps: u32,
    /// A rigid-body vehicle that gains less than [`STALL_PROGRESS_M`] along its trip for
    /// this long gives the trip up ([`Ev::Stalled`]), whatever its recovery is doing.
    pub stall_after: SimDuration,
    /// How hard a rigid-body vehicle tries to free itself before it gives a trip up.
    #[serde(default)]
    pub recovery: Recovery,
}

/// The bounded effort of a rigid-body vehicle's recovery: what it does when its track lies
/// behind it with the way ahead blocked, or it stops making progress (backs off, turns round
/// in several moves, tries again); with room ahead it swings round forwards instead.
#[derive(Copy, Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct Recovery {
    /// Time without progress along the trip (or turning towards it) that starts a recovery.
    pub stuck_after: SimDuration,
    /// Recoveries one trip may start; the next need gives the trip up
    /// ([`StallReason::RecoverySpent`]). 0 turns recovery off.
    pub max_attempts: u32,
    /// Moves (backwards or forwards) one recovery makes at most before it counts as failed.
    pub max_moves: u32,
    /// The longest one move lasts.
    pub move_time: SimDuration,
}

impl Default for Recovery {
    /// A recovery after 8 s without progress; 4 per trip, of at most 9 moves of at most 8 s.
    fn default() -> Self {
        Recovery {
            stuck_after: SimDuration::from_secs(8),
            max_attempts: 4,
            max_moves: 9,
            move_time: SimDuration::from_secs(8),
        }
    }
}

/// Why a vehicle gave its trip up ([`Ev::Stalled`]).
#[derive(Copy, Clone, Debug, PartialEq, Eq, Serialize, Deserialize)]
pub enum StallReason {
    /// No progress along the trip for [`Steps::stall_after`].
    NoProgress,
    /// It needed another recovery after spending all of [`Recovery::max_attempts`] (the
    /// last one's moves did not free it).
    RecoverySpent,
}

impl std::fmt::Display for StallReason {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str(match self {
            StallReason::NoProgress => "no progress along the trip for the stall time",
            StallReason::RecoverySpent => {
                "still stuck after every recovery the trip allows (backing out, turning round)"
            }
        })
    }
}

/// Progress along a trip that counts as moving on, metres.
pub const STALL_PROGRESS_M: f64 = 1.0;

impl Default for Steps {
    /// 100 ms kinematic, 20 ms physics, 50 ms flight with 5 rotor sub-steps (10 ms); a
    /// vehicle stalls after 120 s without progress or when its recoveries are spent
    /// ([`Recovery::default`]).
    fn default() -> Self {
        Steps {
            kinematic: SimDuration::from_millis(100),
            physics: SimDuration::from_millis(20),
            flight: SimDuration::from_millis(50),
            rotor_substeps: 5,
            stall_after: SimDuration::from_secs(120),
            recovery: Recovery::default(),
        }
    }
}

/// Why a body could not be placed.
#[derive(Debug, thiserror::Error)]
pub enum PlaceError {
    /// The node is not in the street graph.
    #[error("node {0:?} is not in the street graph")]
    NoNode(NodeId),
    /// The entity already has a body.
    #[error("entity {0:?} already has a body")]
    Taken(EntityId),
    /// The level does not exist for this family.
    #[error("{0} is not a level of this entity")]
    Level(Level),
    /// The physics world refused the vehicle.
    #[error(transparent)]
    Physics(#[from] PhysicsError),
}

/// The tactical environment at every level of fidelity.
#[derive(Debug)]
pub struct Arena {
    /// Town, terrain, line of sight.
    pub site: Arc<Site>,
    /// Entity type parameters.
    pub types: Arc<TypeBook>,
    /// Free street graphs (no forbidden segments).
    pub roads: Arc<Roads>,
    /// Step lengths.
    pub steps: Steps,
    /// Vehicles and troopers at nodes (discrete level).
    pub at_node: EntityStorage<AtNode>,
    /// Vehicles on the ground mesh (interpolated level).
    pub on_ground: EntityStorage<OnGround>,
    /// Vehicles as rigid bodies (physical level): the state copied after each step.
    pub chassis: EntityStorage<Chassis>,
    /// The rigid-body world behind [`chassis`](Self::chassis), built with the first vehicle.
    pub physics: Option<Physics>,
    /// Directed troopers.
    pub walkers: EntityStorage<Walker>,
    /// GoToNode / WalkToNode route following on the continuous levels.
    pub follow: EntityStorage<Follow>,
    /// Aircraft on their lattices (discrete level).
    pub lattice: EntityStorage<LatticeBody>,
    /// Fixed-wing aircraft (kinematic level).
    pub ctol: EntityStorage<CtolBody>,
    /// Helicopters (dynamic level).
    pub vtol: EntityStorage<VtolBody>,
    /// Autopilot state of every aircraft.
    pub pilots: EntityStorage<Pilot>,
    /// Role, side and state of the entities that have one (sensors and mission actuators).
    pub conditions: EntityStorage<Condition>,
    /// Tracks planned so far, by body kind, start and goal node (a trip depends on nothing
    /// else, and vehicles on rounds drive the same trips again).
    pub(crate) tracks: TrackCache,
    /// The calibration the abstract levels' trips follow (none: the profile as planned).
    /// Not part of the state: a function of the scenario.
    pub calibration: Option<Arc<crate::calibration::Calibration>>,
    /// Per clock: its next tick, while it runs.
    next_tick: [Option<EventId>; 3],
    /// The active bodies on a grid, for vision ([`bodies_near`](Self::bodies_near)), and
    /// what each looker's last look could see ([`in_sight`](Self::in_sight)).
    vision: Mutex<looks::Looks>,
    /// Line-of-sight answers so far ([`visible`](Self::visible)).
    sight: Mutex<sight::SightMemo>,
}

impl Arena {
    /// An empty arena on `site` with the built-in type parameters.
    pub fn new(site: Arc<Site>) -> Self {
        let roads = Arc::new(Roads::new(&site));
        Self::with(site, roads, Arc::new(TypeBook::builtin().clone()))
    }

    /// An empty arena on `site` with precomputed free street graphs and given type
    /// parameters (to share them between runs).
    pub fn with(site: Arc<Site>, roads: Arc<Roads>, types: Arc<TypeBook>) -> Self {
        Arena {
            site,
            types,
            roads,
            steps: Steps::default(),
            at_node: EntityStorage::default(),
            on_ground: EntityStorage::default(),
            chassis: EntityStorage::default(),
            physics: None,
            walkers: EntityStorage::default(),
            follow: EntityStorage::default(),
            lattice: EntityStorage::default(),
            ctol: EntityStorage::default(),
            vtol: EntityStorage::default(),
            pilots: EntityStorage::default(),
            conditions: EntityStorage::default(),
            tracks: TrackCache::default(),
            calibration: None,
            next_tick: [None; 3],
            vision: Mutex::default(),
            sight: Mutex::default(),
        }
    }

    /// True if `id` has a body here.
    pub fn has_body(&self, id: EntityId) -> bool {
        self.at_node.contains(id)
            || self.on_ground.contains(id)
            || self.chassis.contains(id)
            || self.walkers.contains(id)
            || self.lattice.contains(id)
            || self.ctol.contains(id)
            || self.vtol.contains(id)
    }

    /// World position of a street node on the ground.
    pub fn node_point(&self, mode: Mode, node: NodeId) -> Option<[f64; 3]> {
        self.site.street_point(mode, node)
    }

    /// Places a ground vehicle of `kind` at street node `node` at `level` (discrete,
    /// interpolated or physical), facing `heading`.
    pub fn add_vehicle(
        &mut self,
        id: EntityId,
        kind: GroundKind,
        level: Level,
        node: NodeId,
        heading: f64,
    ) -> Result<(), PlaceError> {
        if self.has_body(id) {
            return Err(PlaceError::Taken(id));
        }
        let pos = self
            .node_point(Mode::Drive, node)
            .ok_or(PlaceError::NoNode(node))?;
        match level {
            Level::Discrete => {
                let mut b = AtNode::new(NodeKind::Ground(kind), node);
                b.heading = heading;
                self.at_node.insert(id, b);
            }
            Level::Interpolated => {
                self.on_ground.insert(
                    id,
                    OnGround {
                        kind,
                        node,
                        pos,
                        heading,
                        speed: 0.0,
                        cmd: None,
                    },
                );
            }
            Level::Physical => {
                let site = self.site.clone();
                let dt = self.steps.physics.as_secs_f64();
                let ty = self.types.ground(kind).clone();
                let physics = self.physics.get_or_insert_with(|| Physics::new(&site, dt));
                let mut row =
                    physics.add_vehicle(&site, id, kind, &ty, [pos[0], pos[1]], heading)?;
                row.node = node;
                self.chassis.insert(id, row);
            }
            other => return Err(PlaceError::Level(other)),
        }
        Ok(())
    }

    /// Places a trooper of `kind` at walk-graph node `node` at `level` (discrete or
    /// directed), facing `heading`.
    pub fn add_trooper(
        &mut self,
        id: EntityId,
        kind: TroopKind,
        level: Level,
        node: NodeId,
        heading: f64,
    ) -> Result<(), PlaceError> {
        if self.has_body(id) {
            return Err(PlaceError::Taken(id));
        }
        let pos = self
            .node_point(Mode::Walk, node)
            .ok_or(PlaceError::NoNode(node))?;
        match level {
            Level::Discrete => {
                let mut b = AtNode::new(NodeKind::Troop(kind), node);
                b.heading = heading;
                self.at_node.insert(id, b);
            }
            Level::Directed => {
                self.walkers.insert(
                    id,
                    Walker {
                        kind,
                        node,
                        pos,
                        heading,
                        speed: 0.0,
                        cmd: None,
                    },
                );
            }
            other => return Err(PlaceError::Level(other)),
        }
        Ok(())
    }

    /// Takes a trooper's body out of the arena (it boards a vehicle); refused (false) if it
    /// has no trooper body or is under way.
    pub fn remove_trooper(&mut self, id: EntityId) -> bool {
        let at_rest = match (self.at_node.get(id), self.walkers.get(id)) {
            (Some(b), _) => matches!(b.kind, NodeKind::Troop(_)) && b.trip.is_none(),
            (None, Some(w)) => w.cmd.is_none() && !self.follow.contains(id),
            (None, None) => false,
        };
        if at_rest {
            self.at_node.remove(id);
            self.walkers.remove(id);
        }
        at_rest
    }

    /// Places a fixed-wing aircraft of `kind` at world point `pos` at `level` (discrete or
    /// kinematic), flying `heading` at cruise speed. (It is held there until its autopilot's
    /// first command starts the flight clock.)
    pub fn add_ctol(
        &mut self,
        id: EntityId,
        kind: CtolKind,
        level: Level,
        pos: [f64; 3],
        heading: f64,
    ) -> Result<(), PlaceError> {
        if self.has_body(id) {
            return Err(PlaceError::Taken(id));
        }
        let ty = self.types.ctol(kind);
        match level {
            Level::Discrete => {
                let lattice = Lattice::for_ctol(ty);
                self.lattice.insert(
                    id,
                    LatticeBody {
                        kind: AirKind::Ctol(kind),
                        lattice,
                        cell: lattice.cell_of(pos),
                        dir: dir_of(heading),
                        speed: ty.cruise_speed,
                        moving_to: None,
                        pending: None,
                    },
                );
            }
            Level::Kinematic => {
                self.ctol
                    .insert(id, CtolBody::new(kind, ty, pos, heading, ty.cruise_speed));
            }
            other => return Err(PlaceError::Level(other)),
        }
        Ok(())
    }

    /// Places a helicopter of `kind` hovering at world point `pos` at `level` (discrete or
    /// dynamic), facing `heading`.
    pub fn add_vtol(
        &mut self,
        id: EntityId,
        kind: VtolKind,
        level: Level,
        pos: [f64; 3],
        heading: f64,
    ) -> Result<(), PlaceError> {
        if self.has_body(id) {
            return Err(PlaceError::Taken(id));
        }
        let ty = self.types.vtol(kind);
        match level {
            Level::Discrete => {
                let lattice = Lattice::for_vtol(ty);
                self.lattice.insert(
                    id,
                    LatticeBody {
                        kind: AirKind::Vtol(kind),
                        lattice,
                        cell: lattice.cell_of(pos),
                        dir: dir_of(heading),
                        speed: 0.0,
                        moving_to: None,
                        pending: None,
                    },
                );
            }
            Level::Dynamic => {
                self.vtol
                    .insert(id, VtolBody::hovering(kind, ty, pos, heading));
            }
            other => return Err(PlaceError::Level(other)),
        }
        Ok(())
    }

    /// Where `id` is and how it moves, whatever its level.
    pub fn pose(&self, id: EntityId) -> Option<Pose> {
        if let Some(b) = self.at_node.get(id) {
            let pos = self.node_point(b.kind.mode(), b.node)?;
            return Some(Pose {
                pos,
                heading: b.heading,
                speed: b.speed,
                level: Level::Discrete,
            });
        }
        if let Some(b) = self.on_ground.get(id) {
            return Some(Pose {
                pos: b.pos,
                heading: b.heading,
                speed: b.speed,
                level: Level::Interpolated,
            });
        }
        if let Some(b) = self.chassis.get(id) {
            return Some(Pose {
                pos: b.ground_point(),
                heading: b.heading(),
                speed: b.speed,
                level: Level::Physical,
            });
        }
        if let Some(b) = self.walkers.get(id) {
            return Some(Pose {
                pos: b.pos,
                heading: b.heading,
                speed: b.speed,
                level: Level::Directed,
            });
        }
        if let Some(b) = self.lattice.get(id) {
            return Some(Pose {
                pos: b.lattice.point(b.cell),
                heading: b.heading(),
                speed: b.speed,
                level: Level::Discrete,
            });
        }
        if let Some(b) = self.ctol.get(id) {
            return Some(Pose {
                pos: b.pos,
                heading: b.heading,
                speed: b.speed,
                level: Level::Kinematic,
            });
        }
        if let Some(b) = self.vtol.get(id) {
            return Some(Pose {
                pos: b.pos,
                heading: b.att[2],
                speed: libm::sqrt(b.vel.iter().map(|v| v * v).sum()),
                level: Level::Dynamic,
            });
        }
        None
    }

    /// Starts `clock` (its first tick one step from now) unless it is running.
    pub fn wake(&mut self, clock: Clock, fx: &mut Effects<'_, Ev>) {
        if self.next_tick[clock.index()].is_none() {
            let id = fx.schedule_in(self.step_of(clock), Target::Env, Ev::Tick(clock));
            self.next_tick[clock.index()] = Some(id);
        }
    }

    /// True if the environment event being handled is the next tick of `clock` (a stale or
    /// forged tick is not: it would step the clock twice). Always true outside the
    /// environment's event handler (a harness stepping the clock itself).
    pub fn is_due(&self, clock: Clock, fx: &Effects<'_, Ev>) -> bool {
        fx.fired().is_none() || fx.fired() == self.next_tick[clock.index()]
    }

    /// Schedules the next tick of `clock` if `busy`, or marks it stopped.
    pub fn keep(&mut self, clock: Clock, busy: bool, fx: &mut Effects<'_, Ev>) {
        self.next_tick[clock.index()] =
            busy.then(|| fx.schedule_in(self.step_of(clock), Target::Env, Ev::Tick(clock)));
    }

    /// The step of `clock`.
    pub fn step_of(&self, clock: Clock) -> SimDuration {
        match clock {
            Clock::Kinematic => self.steps.kinematic,
            Clock::Physics => self.steps.physics,
            Clock::Flight => self.steps.flight,
        }
    }

    /// True if `clock` is running.
    pub fn is_running(&self, clock: Clock) -> bool {
        self.next_tick[clock.index()].is_some()
    }

    /// A digest of every storage's writes (part of the trace hash).
    pub fn digest(&self) -> u64 {
        let mut h = TraceHasher::default();
        for d in [
            self.at_node.digest(),
            self.on_ground.digest(),
            self.chassis.digest(),
            self.walkers.digest(),
            self.follow.digest(),
            self.lattice.digest(),
            self.ctol.digest(),
            self.vtol.digest(),
            self.pilots.digest(),
            self.conditions.digest(),
        ] {
            h.write_u64(d);
        }
        for c in Clock::ALL {
            h.write_u64(u64::from(self.is_running(c)));
        }
        h.finish()
    }
}

/// Own position: the body's pose (a perfect GPS and compass).
#[derive(Copy, Clone, Debug, Default)]
pub struct OwnPose;

impl Sensor<Arena> for OwnPose {
    type Reading = Option<Pose>;
    fn read(&self, env: &Arena, me: EntityId, _: &mut Probe<'_>) -> Option<Pose> {
        env.pose(me)
    }
}

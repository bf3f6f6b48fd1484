//! The standard scenarios of the cross-level check: one route across the town, driven,
//! walked and flown by one controller per family at each level.
//!
//! - [`Drive`]: [`VisitNodes`] over `GoToNode` (discrete, interpolated, physical);
//! - [`Walk`]: [`VisitNodes`] over `WalkToNode` (discrete, directed);
//! - [`Fly`]: [`FlightMission`] over the autopilots (lattice; kinematic or dynamic), along
//!   the drive route's junctions at a constant altitude above the highest ground under it.

use super::{CheckError, Family, Run, Scenario, Setup, record};
use vitro::entity::EntityId;
use vitro::env::{Actuator, NodeId};
use vitro::event::Target;
use vitro::sim::Simulation;
use vitro::time::SimTime;
use vitro_behaviour::route::{FlightMission, Leg, VisitNodes};
use vitro_site::map::Mode;
use vitro_tactical::actuate::{self, MoveError};
use vitro_tactical::arena::{Arena, Ev};
use vitro_tactical::autopilot::{self, FlyError};
use vitro_tactical::entity::Level;
use vitro_tactical::entity::air::{AirKind, FlightCommand};
use vitro_tactical::entity::roads::FreeGraph;
use vitro_tactical::entity::route::Track;
use vitro_tactical::model::{Controller, Tactical};
use vitro_tactical::types::{GroundKind, TroopKind, VtolKind};

/// Spacing of the flight route's waypoints: junctions closer than this are skipped, metres.
pub const WAYPOINT_SPACING: f64 = 150.0;
/// Height of the flight route above the highest ground under it, metres.
pub const FLIGHT_HEIGHT: f64 = 100.0;

/// The standard trip on `mode`'s free graph ([`Setup::standard_trip`]).
pub fn trip(setup: &Setup, mode: Mode) -> Result<(NodeId, NodeId), CheckError> {
    setup
        .standard_trip(mode)
        .ok_or_else(|| CheckError::Scenario {
            scenario: format!("{mode:?} trip"),
            message: "the street graph has no connected part".into(),
        })
}

fn scenario_error(name: &str, e: impl std::fmt::Display) -> CheckError {
    CheckError::Scenario {
        scenario: name.to_owned(),
        message: e.to_string(),
    }
}

/// The flight route along the drive path from `from` to `to`: junctions at least
/// [`WAYPOINT_SPACING`] apart (and the last), at [`FLIGHT_HEIGHT`] above the highest
/// ground of the path.
pub fn flight_route(setup: &Setup, from: NodeId, to: NodeId) -> Result<Vec<[f64; 3]>, CheckError> {
    let g: &FreeGraph = &setup.roads.drive;
    let path = g
        .path(from, to)
        .map_err(|e| scenario_error("flight route", e))?;
    let pts: Vec<[f64; 3]> = path
        .iter()
        .filter_map(|&n| g.graph.node(n).map(|s| setup.site.on_ground(s.pos)))
        .collect();
    let top = pts.iter().map(|p| p[2]).fold(f64::MIN, f64::max);
    let mut route: Vec<[f64; 3]> = Vec::new();
    for (i, p) in pts.iter().enumerate() {
        let far = route
            .last()
            .is_none_or(|q| libm::hypot(p[0] - q[0], p[1] - q[1]) >= WAYPOINT_SPACING);
        if i > 0 && (far || i + 1 == pts.len()) {
            route.push([p[0], p[1], top + FLIGHT_HEIGHT]);
        }
    }
    if route.is_empty() {
        return Err(scenario_error(
            "flight route",
            "the path is a single junction",
        ));
    }
    Ok(route)
}

/// The standard scenarios on `setup`'s town.
pub fn standard(setup: &Setup) -> Result<Vec<Box<dyn Scenario>>, CheckError> {
    let (a, b) = trip(setup, Mode::Drive)?;
    let (wa, wb) = trip(setup, Mode::Walk)?;
    let route = flight_route(setup, a, b)?;
    let mut out: Vec<Box<dyn Scenario>> = Vec::new();
    for kind in GroundKind::ALL {
        out.push(Box::new(Drive {
            kind,
            from: a,
            to: b,
        }));
    }
    for kind in TroopKind::ALL {
        out.push(Box::new(Walk {
            kind,
            from: wa,
            to: wb,
        }));
    }
    out.push(Box::new(Fly {
        aircraft: AirKind::Ctol(vitro_tactical::types::CtolKind::Procerus),
        route: route.clone(),
    }));
    for kind in VtolKind::ALL {
        out.push(Box::new(Fly {
            aircraft: AirKind::Vtol(kind),
            route: route.clone(),
        }));
    }
    Ok(out)
}

/// Runs a [`VisitNodes`] controller to `to` through `goto`; the body is placed by `place`.
pub fn visit<A>(
    setup: &Setup,
    name: &str,
    to: NodeId,
    goto: A,
    place: impl FnOnce(&mut Arena, EntityId) -> Result<(), vitro_tactical::arena::PlaceError>,
    limit: f64,
) -> Result<Recorded, CheckError>
where
    A: Actuator<Arena, Ev, Command = NodeId, Error = MoveError> + 'static,
{
    let mut sim: Simulation<Tactical> = Simulation::new(setup.arena(), setup.seed);
    let controller: Box<dyn Controller> = Box::new(VisitNodes::new(vec![to], goto));
    let id = sim
        .add_agent(name, controller)
        .map_err(|e| scenario_error(name, e))?;
    place(sim.env_mut(), id).map_err(|e| scenario_error(name, e))?;
    sim.schedule(SimTime::ZERO, Target::Entity(id), Ev::Start)
        .map_err(|e| scenario_error(name, e))?;
    let finished = |s: &Simulation<Tactical>| {
        s.agent(id)
            .and_then(|c| c.as_any().downcast_ref::<VisitNodes<A>>())
            .is_some_and(|v| v.finished() || v.error.is_some())
    };
    let (samples, sim_s, wall) = record(&mut sim, id, SimTime::from_secs_f64(limit), finished);
    let v = sim
        .agent(id)
        .and_then(|c| c.as_any().downcast_ref::<VisitNodes<A>>());
    if let Some(e) = v.and_then(|v| v.error.clone()) {
        return Err(scenario_error(name, e));
    }
    let arrival = v
        .and_then(|v| v.log.iter().find(|l| l.1 == to))
        .map(|l| l.0.as_secs_f64());
    Ok(Recorded {
        samples,
        arrival,
        sim_seconds: sim_s,
        wall_seconds: wall,
        events: sim.events_fired(),
    })
}

/// What a node-visiting run recorded.
pub struct Recorded {
    /// The body's trajectory.
    pub samples: Vec<super::Sample>,
    /// When it reached its goal (seconds), if it did.
    pub arrival: Option<f64>,
    /// Simulated seconds run.
    pub sim_seconds: f64,
    /// Wall-clock seconds the run took.
    pub wall_seconds: f64,
    /// Events fired.
    pub events: u64,
}

/// A vehicle type driving from `from` to `to`.
pub struct Drive {
    /// The type.
    pub kind: GroundKind,
    /// Start node (drive graph).
    pub from: NodeId,
    /// Goal node.
    pub to: NodeId,
}

impl Scenario for Drive {
    fn entity(&self) -> String {
        self.kind.key().to_owned()
    }
    fn levels(&self) -> Vec<Level> {
        vec![Level::Discrete, Level::Interpolated, Level::Physical]
    }
    fn run(&self, setup: &Setup, level: Level) -> Result<Run, CheckError> {
        let name = self.entity();
        let ty = setup.types.ground(self.kind);
        let path = setup
            .roads
            .drive
            .path(self.from, self.to)
            .map_err(|e| scenario_error(&name, e))?;
        let track = Track::plan_vehicle(
            &setup.site,
            &setup.roads.drive,
            &path,
            ty,
            &setup.types.speed_limits,
        )
        .map_err(|e| scenario_error(&name, e))?;
        let heading = track.heading_at(0.0);
        let limit = 3.0 * track.duration() + 300.0;
        let (kind, from, to) = (self.kind, self.from, self.to);
        let place = move |a: &mut Arena, id| a.add_vehicle(id, kind, level, from, heading);
        let r = match level {
            Level::Discrete => visit(
                setup,
                &name,
                to,
                actuate::ground::discrete::GoToNode,
                place,
                limit,
            )?,
            Level::Interpolated => visit(
                setup,
                &name,
                to,
                actuate::ground::interpolated::GoToNode,
                place,
                limit,
            )?,
            _ => visit(
                setup,
                &name,
                to,
                actuate::ground::physical::GoToNode,
                place,
                limit,
            )?,
        };
        Ok(Run {
            entity: name,
            family: Family::Ground,
            level,
            samples: r.samples,
            arrival: r.arrival,
            reference: None,
            max_speed: ty.max_speed(),
            min_speed: None,
            altitude: None,
            sim_seconds: r.sim_seconds,
            wall_seconds: r.wall_seconds,
            events: r.events,
        })
    }
}

/// A trooper type walking from `from` to `to`.
pub struct Walk {
    /// The type.
    pub kind: TroopKind,
    /// Start node (walk graph).
    pub from: NodeId,
    /// Goal node.
    pub to: NodeId,
}

impl Scenario for Walk {
    fn entity(&self) -> String {
        format!("{}_trooper", self.kind.key())
    }
    fn levels(&self) -> Vec<Level> {
        vec![Level::Discrete, Level::Directed]
    }
    fn run(&self, setup: &Setup, level: Level) -> Result<Run, CheckError> {
        let name = self.entity();
        let troops = &setup.types.troops;
        let path = setup
            .roads
            .walk
            .path(self.from, self.to)
            .map_err(|e| scenario_error(&name, e))?;
        let track = Track::plan_walk(
            &setup.site,
            &setup.roads.walk,
            &path,
            troops,
            troops.of(self.kind).load,
        )
        .map_err(|e| scenario_error(&name, e))?;
        let heading = track.heading_at(0.0);
        let limit = 3.0 * track.duration() + 300.0;
        let (kind, from, to) = (self.kind, self.from, self.to);
        let place = move |a: &mut Arena, id| a.add_trooper(id, kind, level, from, heading);
        let r = match level {
            Level::Discrete => visit(
                setup,
                &name,
                to,
                actuate::troop::discrete::WalkToNode,
                place,
                limit,
            )?,
            _ => visit(
                setup,
                &name,
                to,
                actuate::troop::directed::WalkToNode,
                place,
                limit,
            )?,
        };
        Ok(Run {
            entity: name,
            family: Family::Troop,
            level,
            samples: r.samples,
            arrival: r.arrival,
            reference: None,
            max_speed: troops.unloaded_speed,
            min_speed: None,
            altitude: None,
            sim_seconds: r.sim_seconds,
            wall_seconds: r.wall_seconds,
            events: r.events,
        })
    }
}

/// An aircraft flying `route` (waypoints) from a start 300 m before its first waypoint.
pub struct Fly {
    /// The airframe.
    pub aircraft: AirKind,
    /// The waypoints, at one altitude.
    pub route: Vec<[f64; 3]>,
}

impl Fly {
    /// Where the aircraft starts and its heading there: 300 m before the first waypoint,
    /// flying towards it.
    pub fn start(&self) -> ([f64; 3], f64) {
        let p = self.route[0];
        let q = self
            .route
            .get(1)
            .copied()
            .unwrap_or([p[0] + 1.0, p[1], p[2]]);
        let h = libm::atan2(q[1] - p[1], q[0] - p[0]);
        (
            [
                p[0] - 300.0 * libm::cos(h),
                p[1] - 300.0 * libm::sin(h),
                p[2],
            ],
            h,
        )
    }

    fn mission<P>(&self, setup: &Setup, level: Level, pilot: P) -> Result<Run, CheckError>
    where
        P: Actuator<Arena, Ev, Command = FlightCommand, Error = FlyError> + 'static,
    {
        let name = self.entity();
        let (start, heading) = self.start();
        let mut sim: Simulation<Tactical> = Simulation::new(setup.arena(), setup.seed);
        let legs = vec![Leg::Waypoints(self.route.clone())];
        let controller: Box<dyn Controller> = Box::new(FlightMission::new(legs, pilot));
        let id = sim
            .add_agent(&name, controller)
            .map_err(|e| scenario_error(&name, e))?;
        let placed = match self.aircraft {
            AirKind::Ctol(k) => sim.env_mut().add_ctol(id, k, level, start, heading),
            AirKind::Vtol(k) => sim.env_mut().add_vtol(id, k, level, start, heading),
        };
        placed.map_err(|e| scenario_error(&name, e))?;
        sim.schedule(SimTime::ZERO, Target::Entity(id), Ev::Start)
            .map_err(|e| scenario_error(&name, e))?;
        let (max_speed, min_speed, slow) = match self.aircraft {
            AirKind::Ctol(k) => {
                let t = setup.types.ctol(k);
                (t.max_speed, Some(t.min_speed), t.min_speed)
            }
            AirKind::Vtol(k) => {
                let t = setup.types.vtol(k);
                (t.max_speed, None, t.cruise_speed.min(5.0))
            }
        };
        let length: f64 = self
            .route
            .windows(2)
            .map(|w| libm::hypot(w[1][0] - w[0][0], w[1][1] - w[0][1]))
            .sum::<f64>()
            + 300.0;
        let limit = 3.0 * length / slow + 300.0;
        let finished = |s: &Simulation<Tactical>| {
            s.agent(id)
                .and_then(|c| c.as_any().downcast_ref::<FlightMission<P>>())
                .is_some_and(|m| m.finished() || m.error.is_some())
        };
        let (samples, sim_seconds, wall_seconds) =
            record(&mut sim, id, SimTime::from_secs_f64(limit), finished);
        let m = sim
            .agent(id)
            .and_then(|c| c.as_any().downcast_ref::<FlightMission<P>>());
        if let Some(e) = m.and_then(|m| m.error.clone()) {
            return Err(scenario_error(&name, e));
        }
        Ok(Run {
            entity: name,
            family: match self.aircraft {
                AirKind::Ctol(_) => Family::Ctol,
                AirKind::Vtol(_) => Family::Vtol,
            },
            level,
            samples,
            arrival: m.and_then(|m| m.legs_done.first()).map(|t| t.as_secs_f64()),
            reference: None,
            max_speed,
            min_speed,
            altitude: Some(self.route[0][2]),
            sim_seconds,
            wall_seconds,
            events: sim.events_fired(),
        })
    }
}

impl Scenario for Fly {
    fn entity(&self) -> String {
        match self.aircraft {
            AirKind::Ctol(k) => k.key().to_owned(),
            AirKind::Vtol(k) => k.key().to_owned(),
        }
    }
    fn levels(&self) -> Vec<Level> {
        match self.aircraft {
            AirKind::Ctol(_) => vec![Level::Discrete, Level::Kinematic],
            AirKind::Vtol(_) => vec![Level::Discrete, Level::Dynamic],
        }
    }
    fn run(&self, setup: &Setup, level: Level) -> Result<Run, CheckError> {
        match (self.aircraft, level) {
            (_, Level::Discrete) => self.mission(setup, level, autopilot::lattice::Autopilot),
            (AirKind::Ctol(_), _) => self.mission(setup, level, autopilot::ctol::Autopilot),
            (AirKind::Vtol(_), _) => self.mission(setup, level, autopilot::vtol::Autopilot),
        }
    }
}

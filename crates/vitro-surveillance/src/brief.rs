//! What each agent is told before the mission: legitimate, pre-briefed knowledge. Nothing
//! else reaches an agent but its own sensors and the radio.
//!
//! | agent | briefed with |
//! |---|---|
//! | UAV | the map (town and terrain), the operation area and the track spacing (for its own search when it holds no sector, entered at a corner set by its place in the roster), the team roster and the station's id, its own type, level, altitude and cruise speed, its camera and tracking settings, the radio discipline (and how far it goes to look for a target a teammate reported) and the contract net's deadlines |
//! | station | where it is parked (the scenario's point), the map, the allocation method (and the central search's budget and pace), the team roster, the sectors of the operation area, the timetable of the areas it will be tasked with (their sectors come with the tasking), the radio discipline and the contract net's deadlines |
//! | red unit | the map (its street graph), how far it goes and how long it pauses |
//!
//! No agent is told where the red units are, which sectors a UAV holds, or whether a UAV
//! is still flying: the UAVs learn sectors from the station's calls, the station learns who
//! holds what and who is alive from the UAVs' reports, and targets are known only through
//! each UAV's own camera and its teammates' sighting reports.

use crate::scenario::AllocationMethod;
use crate::sector::{Rect, Sector};
use std::sync::Arc;
use vitro::entity::EntityId;
use vitro::protocol::CnetConfig;
use vitro::sim::CostModel;
use vitro::time::{SimDuration, SimTime};
use vitro_site::map::Mode;
use vitro_site::site::Site;
use vitro_tactical::entity::Level;
use vitro_tactical::entity::roads::Roads;
use vitro_tactical::sensor::track::TrackConfig;

/// The radio discipline shared by the team and the station.
#[derive(Copy, Clone, Debug, PartialEq)]
pub struct Discipline {
    /// Period of a UAV's status report.
    pub heartbeat: SimDuration,
    /// Silence after which the station presumes a UAV lost.
    pub lost_after: SimDuration,
    /// Period of the sighting reports.
    pub report: SimDuration,
    /// How long a teammate's report of a track is taken as current.
    pub report_fresh: SimDuration,
    /// The contract net's deadlines.
    pub cnet: CnetConfig,
}

/// What every UAV is told.
#[derive(Clone, Debug)]
pub struct TeamBrief {
    /// The town and its terrain (the map).
    pub site: Arc<Site>,
    /// The station (the contract net's manager).
    pub station: EntityId,
    /// The UAVs, in id order.
    pub team: Vec<EntityId>,
    /// The operation area, town metres (searched whole by a UAV that holds no sector).
    pub area: Rect,
    /// Distance between search tracks, metres.
    pub spacing_m: f64,
    /// Its camera and locks.
    pub tracking: TrackConfig,
    /// Time between two looks.
    pub period: SimDuration,
    /// Radius of a fixed-wing UAV's orbit round a target, metres.
    pub orbit_m: f64,
    /// How long it searches for a lost track.
    pub reacquire: SimDuration,
    /// How far it goes to look for a target a teammate reported, metres.
    pub cue_m: f64,
    /// The radio discipline.
    pub discipline: Discipline,
}

/// What one UAV is told about itself.
#[derive(Copy, Clone, Debug, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct Airframe {
    /// Its level of fidelity.
    pub level: Level,
    /// True for a fixed-wing aircraft (it cannot hover: it orbits).
    pub fixed_wing: bool,
    /// Its height above the ground, metres.
    pub altitude_m: f64,
    /// Its cruise speed, m/s.
    pub cruise_mps: f64,
}

/// What the station is told.
#[derive(Clone, Debug)]
pub struct StationBrief {
    /// Where it is parked, town metres (the scenario's point): the central plan's tours
    /// start there.
    pub home: [f64; 2],
    /// The town and its terrain (the map): to read the UAVs' reported positions.
    pub site: Arc<Site>,
    /// How it shares the sectors out.
    pub method: AllocationMethod,
    /// The central search's iterations.
    pub budget: u64,
    /// Simulated time the central search takes.
    pub search_cost: CostModel,
    /// The UAVs, in id order.
    pub team: Vec<EntityId>,
    /// The sectors of the operation area, searched from the start.
    pub sectors: Vec<Sector>,
    /// The areas it will be tasked with, with their sectors, in time order.
    pub tasking: Vec<(SimTime, Vec<Sector>)>,
    /// A failed call is made again after this long.
    pub retry: SimDuration,
    /// The radio discipline.
    pub discipline: Discipline,
}

/// What a red unit is told.
#[derive(Clone, Debug)]
pub struct RedBrief {
    /// The street graphs (the map).
    pub roads: Arc<Roads>,
    /// The town and its terrain.
    pub site: Arc<Site>,
    /// Distance to the next destination, metres `[min, max]`.
    pub leg_m: [f64; 2],
    /// Pause at each destination, seconds `[min, max]`.
    pub dwell_s: [f64; 2],
}

/// How one red unit moves.
#[derive(Copy, Clone, Debug, PartialEq, Eq, serde::Serialize, serde::Deserialize)]
pub struct Gait {
    /// On foot (walk graph) or by road (drive graph).
    pub mode: Mode,
    /// Its level of fidelity.
    pub level: Level,
}

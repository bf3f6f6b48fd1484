//! # vitro-check: one controller at every level of fidelity, its properties re-checked on each
//!
//! The levels of `vitro-tactical` (a vehicle hopping between nodes, a point on the ground
//! mesh, a rigid body) are only interchangeable if a controller keeps its stated properties
//! on each. This crate runs the controllers (the generic ones of `vitro-behaviour`, or a
//! user's own) on a town ([`Setup`]) at each level and judges
//! every run.
//!
//! A [`Scenario`] runs one controller for one entity at a given level and returns the
//! recorded [`Run`] (trajectory, arrival, limits); a [`Property`] judges a run. A
//! [`Registry`] holds both; [`Registry::run`] runs every scenario at each of its levels
//! (its reference level, the discrete one, first: its arrival time is the *discrete
//! estimate* the others are held to) and produces one [`Row`] per (entity, level, property)
//! that applies, with each level's speed in simulated seconds per wall-clock second.
//!
//! [`Registry::standard`] checks, on the real town: each vehicle type driving across town
//! at the discrete, interpolated and physical levels; each trooper type walking at the
//! discrete and directed levels; the fixed-wing UAV and both helicopters flying the same
//! route at their two levels. Its properties ([`property`]): the goal is reached; ground
//! bodies never enter a forbidden zone; the arrival time is within a stated tolerance of the
//! discrete estimate; the trajectory has no jump larger than the type's top speed × the
//! time step + 5 cm; a helicopter holds its commanded altitude within ±3 m; a fixed-wing
//! aircraft never flies below its minimum speed.
//!
//! Users add their own controllers (a [`Scenario`] that builds a simulation with them and
//! records it with [`record`]) and their own [`Property`]s:
//!
//! ```no_run
//! use vitro_check::{Property, Registry, Run, Verdict};
//! use vitro_tactical::setup::Setup;
//! use vitro_site::site::Site;
//!
//! /// No ground body ever climbs above 400 m.
//! struct Below400;
//! impl Property for Below400 {
//!     fn name(&self) -> &str { "below 400 m" }
//!     fn evaluate(&self, run: &Run, _: &Site) -> Option<Verdict> {
//!         let top = run.samples.iter().map(|s| s.pos[2]).fold(f64::MIN, f64::max);
//!         Some(Verdict { pass: top <= 400.0, value: top, limit: "<= 400 m".into() })
//!     }
//! }
//! let setup = Setup::default_town().unwrap();
//! let mut registry = Registry::standard(&setup).unwrap();
//! registry.add_property(Box::new(Below400));
//! let report = registry.run(&setup).unwrap();
//! println!("{}", report.table());
//! ```

pub mod property;
mod registry;
pub mod scenario;

pub use registry::{CheckReport, LevelSpeed, Registry, Row, check_levels};

use serde::Serialize;
use std::time::Instant;
use vitro::entity::EntityId;
use vitro::sim::Simulation;
use vitro::time::SimTime;
use vitro_site::site::Site;
use vitro_tactical::entity::Level;
use vitro_tactical::model::Tactical;
use vitro_tactical::setup::{Setup, SetupError};

/// Why a check could not run.
#[derive(Debug, thiserror::Error)]
pub enum CheckError {
    /// The town could not be set up.
    #[error(transparent)]
    Setup(#[from] SetupError),
    /// A scenario could not be set up.
    #[error("scenario {scenario}: {message}")]
    Scenario {
        /// The scenario's entity name.
        scenario: String,
        /// What went wrong.
        message: String,
    },
}

/// What kind of entity a run is of (properties choose by it).
#[derive(Copy, Clone, Debug, PartialEq, Eq, PartialOrd, Ord, Hash, Serialize)]
pub enum Family {
    /// Car, truck, UGV.
    Ground,
    /// Trooper.
    Troop,
    /// Fixed-wing UAV.
    Ctol,
    /// Helicopter UAV.
    Vtol,
}

/// One recorded pose.
#[derive(Copy, Clone, Debug, PartialEq, Serialize)]
pub struct Sample {
    /// Simulated time, seconds.
    pub t: f64,
    /// World position, metres.
    pub pos: [f64; 3],
    /// Speed, m/s.
    pub speed: f64,
}

/// One scenario run at one level: what the properties judge.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct Run {
    /// The entity (type) name, e.g. `car`.
    pub entity: String,
    /// Its family.
    pub family: Family,
    /// The level it ran at.
    pub level: Level,
    /// Its trajectory: a sample after every event that moved time on.
    pub samples: Vec<Sample>,
    /// When it reached its goal (seconds), if it did.
    pub arrival: Option<f64>,
    /// The discrete estimate of the arrival (filled in by the registry from the reference
    /// level's run).
    pub reference: Option<f64>,
    /// The type's top speed, m/s.
    pub max_speed: f64,
    /// The type's minimum speed (fixed-wing aircraft), m/s.
    pub min_speed: Option<f64>,
    /// The commanded altitude (aircraft on a level route), world metres.
    pub altitude: Option<f64>,
    /// Simulated seconds run.
    pub sim_seconds: f64,
    /// Wall-clock seconds the run took.
    pub wall_seconds: f64,
    /// Events fired.
    pub events: u64,
}

/// A property's judgement of one run.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct Verdict {
    /// Whether it holds.
    pub pass: bool,
    /// The measured value (its meaning is the property's; NaN if there is none).
    pub value: f64,
    /// The bound it was held to, in words.
    pub limit: String,
}

/// A property of a run.
pub trait Property: Send + Sync {
    /// Its name in the report.
    fn name(&self) -> &str;
    /// Its verdict on `run` on `site`, or `None` where it does not apply.
    fn evaluate(&self, run: &Run, site: &Site) -> Option<Verdict>;
}

/// A controller run for one entity at given levels.
pub trait Scenario: Send + Sync {
    /// The entity (type) name in the report.
    fn entity(&self) -> String;
    /// The levels it runs at; the first is the reference (discrete) level.
    fn levels(&self) -> Vec<Level>;
    /// Runs at `level`.
    fn run(&self, setup: &Setup, level: Level) -> Result<Run, CheckError>;
}

/// Runs `sim` until `done` holds or `until`, recording `id`'s pose after every event that
/// moved time on; returns the samples, the simulated and the wall-clock seconds.
pub fn record(
    sim: &mut Simulation<Tactical>,
    id: EntityId,
    until: SimTime,
    mut done: impl FnMut(&Simulation<Tactical>) -> bool,
) -> (Vec<Sample>, f64, f64) {
    let mut samples: Vec<Sample> = Vec::new();
    let t0 = sim.now().as_secs_f64();
    let wall = Instant::now();
    sim.run(until, |s| {
        if let Some(p) = s.env().pose(id) {
            let t = s.now().as_secs_f64();
            let sample = Sample {
                t,
                pos: p.pos,
                speed: p.speed,
            };
            match samples.last_mut() {
                Some(last) if last.t == t => *last = sample,
                _ => samples.push(sample),
            }
        }
        done(s)
    });
    let wall = wall.elapsed().as_secs_f64();
    (samples, sim.now().as_secs_f64() - t0, wall)
}

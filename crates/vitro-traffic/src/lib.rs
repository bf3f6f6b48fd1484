//! # vitro-traffic: a scenario that tests the bodies rather than a mission
//!
//! Vehicles (cars, trucks, UGVs) and troopers start at distinct seeded random junctions of
//! the town's main free street graph (the walk graph for troopers) and tour it: each goes to
//! a seeded random junction through its level's top actuator
//! (`vitro_tactical::actuate::by_level::{Drive, Walk}`), then to another, until the run
//! ends. A vehicle that gives a trip up ([`Ev::Stalled`]) counts a stall and plans its next
//! trip from where it stands. The run measures trips, stalls, vehicle-hours, the mean trip
//! time and the longest time a vehicle was commanded to move but did not (`deadlock_s`),
//! at any level of fidelity, from one scenario file (`kind = "traffic"`, see
//! `scenarios/traffic.toml`).
//!
//! Collisions: the arena reports no contact between bodies at any level (node-level bodies
//! may share a junction, the kinematic ones pass through each other, and the rigid bodies'
//! contacts stay inside the physics), so `collisions` is absent from every report rather
//! than a 0 that was never measured.
//!
//! ```no_run
//! use std::path::Path;
//! use vitro_mission::Run;
//!
//! let path = Path::new("scenarios/traffic.toml");
//! let text = std::fs::read_to_string(path)?;
//! let mut run = vitro_traffic::Streets::from_text(path, &text, Some(1), None)?;
//! let end = run.end;
//! while Run::advance(&mut run, end)? {}
//! println!("{:?}", Run::metrics(&run));
//! # Ok::<(), Box<dyn std::error::Error>>(())
//! ```

mod plugin;
pub mod scenario;
mod tour;

pub use plugin::{Metrics, Traffic};
pub use tour::Tour;

use rand::{Rng, SeedableRng};
use rand_chacha::ChaCha8Rng;
use std::path::Path;
use std::sync::Arc;
use vitro::entity::EntityId;
use vitro::env::NodeId;
use vitro::event::Target;
use vitro::rng::Owner;
use vitro::sim::Simulation;
use vitro::time::SimTime;
use vitro_mission::session::{Session, Setup};
use vitro_tactical::actuate::by_level::{Drive, Walk};
use vitro_tactical::arena::{Arena, Ev};
use vitro_tactical::entity::Level;
use vitro_tactical::entity::roads::{FreeGraph, Roads};
use vitro_tactical::model::{Controller, Tactical};
use vitro_tactical::scenario::{Diagnostics, EntityType, Preset};
use vitro_tactical::types::{GroundKind, TroopKind, TypeBook};
use vitro_tactical::world::Side;

/// One run of the traffic scenario.
pub type TrafficRun = Session<Streets>;

/// Why a traffic run could not be built.
#[derive(Debug, thiserror::Error)]
pub enum TrafficError {
    /// The scenario is not valid.
    #[error("{}", .0.report())]
    Scenario(Diagnostics),
    /// The town cannot hold the traffic asked for.
    #[error("{0}")]
    Setup(String),
}

/// One body in the traffic.
#[derive(Clone, Debug)]
pub struct Member {
    /// Its entity.
    pub id: EntityId,
    /// Its name (`car-3`).
    pub name: String,
    /// Its type in the file.
    pub kind: EntityType,
    /// Its side.
    pub side: Side,
    /// Its level of fidelity.
    pub level: Level,
}

/// What the referee keeps of one body between two looks.
#[derive(Clone, Debug, Default)]
struct Watch {
    /// Where it was at the last look.
    last: Option<[f64; 3]>,
    /// How long it has been commanded to move without moving, seconds.
    waiting_s: f64,
}

/// The traffic's own part of a run: who is in it and what the referee sees of them.
#[derive(Debug)]
pub struct Streets {
    /// Every body, in file order.
    pub members: Vec<Member>,
    /// Time between two looks of the referee.
    check: vitro::time::SimDuration,
    /// Speeds below this count as standing still.
    still_mps: f64,
    /// The next look.
    next_check: SimTime,
    /// One per member.
    watch: Vec<Watch>,
    /// The longest wait of any vehicle so far, seconds.
    longest_wait_s: f64,
    /// Who waited it.
    longest_waiter: Option<EntityId>,
}

/// The main-part nodes of `g`, in id order.
fn main_nodes(g: &FreeGraph) -> Vec<NodeId> {
    (0..g.graph.node_count() as u32)
        .map(NodeId)
        .filter(|n| g.main.get(n.0 as usize).copied().unwrap_or(false))
        .collect()
}

/// The heading (radians from east) of the first street leaving `n`, 0 if none does.
fn street_heading(g: &FreeGraph, n: NodeId) -> f64 {
    let Some(here) = g.graph.node(n).map(|s| s.pos) else {
        return 0.0;
    };
    g.graph
        .neighbors(n)
        .filter_map(|(m, _, _)| g.graph.node(m).map(|s| s.pos))
        .map(|p| libm::atan2(p[1] - here[1], p[0] - here[0]))
        .next()
        .unwrap_or(0.0)
}

fn ground_kind(t: EntityType) -> GroundKind {
    match t {
        EntityType::Truck => GroundKind::CargoTruck,
        EntityType::Ugv => GroundKind::Mdars,
        _ => GroundKind::Car,
    }
}

impl Streets {
    /// Builds a run of the scenario `text` read from `path`, with `seed` instead of the
    /// file's if given, at the levels of `preset` if given.
    ///
    /// # Errors
    /// [`TrafficError::Scenario`] with every problem of the file;
    /// [`TrafficError::Setup`] if the town has fewer free junctions than bodies.
    pub fn from_text(
        path: &Path,
        text: &str,
        seed: Option<u64>,
        preset: Option<Preset>,
    ) -> Result<TrafficRun, TrafficError> {
        let mut v = scenario::validate_text(path, text).map_err(TrafficError::Scenario)?;
        if let Some(level) = preset {
            v.file.fidelity.set_preset(level);
        }
        let f = &v.file;
        let seed = seed.unwrap_or(f.seed);
        let setup = Setup::from_secs(
            f.name.clone(),
            seed,
            f.end.time_s,
            f.record.sample_s,
            f.start,
        );
        let site = Arc::new(v.site);
        let roads = Arc::new(Roads::new(&site));
        let mut arena = Arena::with(site, roads.clone(), Arc::new(TypeBook::builtin().clone()));
        arena.calibration = v.calibration.map(Arc::new);
        let mut sim: Simulation<Tactical> = Simulation::new(arena, seed);
        let mut rng = sim.rngs_mut().stream(Owner::Global, "traffic").clone();
        let drive = main_nodes(&roads.drive);
        let walk = main_nodes(&roads.walk);
        let (drive_nodes, walk_nodes) = (Arc::new(drive.clone()), Arc::new(walk.clone()));
        let (mut free_drive, mut free_walk) = (drive, walk);
        let mut members = Vec::new();
        for e in &f.entities {
            let level = f.fidelity.level_of(e.kind);
            for name in e.names() {
                let vehicle = e.kind.is_vehicle();
                let free = if vehicle {
                    &mut free_drive
                } else {
                    &mut free_walk
                };
                if free.is_empty() {
                    return Err(TrafficError::Setup(format!(
                        "no free junction left for {name}: the town has fewer junctions than {}",
                        if vehicle { "vehicles" } else { "troopers" }
                    )));
                }
                let start = free.swap_remove(rng.random_range(0..free.len()));
                let own = ChaCha8Rng::seed_from_u64(rng.random());
                let agent: Box<dyn Controller> = if vehicle {
                    Box::new(Tour::new(drive_nodes.clone(), Drive(level), own))
                } else {
                    Box::new(Tour::new(walk_nodes.clone(), Walk(level), own))
                };
                let id = sim
                    .add_agent(name.clone(), agent)
                    .map_err(|e| TrafficError::Setup(e.to_string()))?;
                let placed = if vehicle {
                    let heading = street_heading(&roads.drive, start);
                    (sim.env_mut()).add_vehicle(id, ground_kind(e.kind), level, start, heading)
                } else {
                    let heading = street_heading(&roads.walk, start);
                    (sim.env_mut()).add_trooper(id, TroopKind::Blue, level, start, heading)
                };
                placed.map_err(|e| TrafficError::Setup(format!("{name}: {e}")))?;
                sim.schedule(SimTime::ZERO, Target::Entity(id), Ev::Start)
                    .map_err(|e| TrafficError::Setup(e.to_string()))?;
                members.push(Member {
                    id,
                    name,
                    kind: e.kind,
                    side: e.side.side(),
                    level,
                });
            }
        }
        let check = vitro::time::SimDuration::from_secs_f64(f.traffic.check_s);
        let streets = Streets {
            watch: vec![Watch::default(); members.len()],
            members,
            check,
            still_mps: f.traffic.still_mps,
            next_check: SimTime::ZERO + check,
            longest_wait_s: 0.0,
            longest_waiter: None,
        };
        Ok(Session::new(setup, sim, streets))
    }

    /// The referee's look at `now`: every body commanded to move that has not moved since
    /// the last look (by more than a centimetre per look, nor at speed) waited one more
    /// check period.
    fn look(run: &mut TrafficRun, now: SimTime) {
        if now < run.play.next_check {
            return;
        }
        let dt = run.play.check.as_secs_f64();
        while run.play.next_check <= now {
            run.play.next_check += run.play.check;
        }
        let (sim, play) = (&run.sim, &mut run.play);
        for (m, w) in play.members.iter().zip(play.watch.iter_mut()) {
            let Some(pose) = sim.env().pose(m.id) else {
                continue;
            };
            let commanded = sim
                .agent(m.id)
                .and_then(|a| a.as_any().downcast_ref::<Tour<Drive>>())
                .is_some_and(|t| t.goal.is_some());
            let moved = w
                .last
                .is_none_or(|p| libm::hypot(pose.pos[0] - p[0], pose.pos[1] - p[1]) > 0.01);
            w.last = Some(pose.pos);
            if !commanded || moved || libm::fabs(pose.speed) >= play.still_mps {
                w.waiting_s = 0.0;
                continue;
            }
            w.waiting_s += dt;
            if w.waiting_s > play.longest_wait_s {
                play.longest_wait_s = w.waiting_s;
                play.longest_waiter = Some(m.id);
            }
        }
    }
}

//! Building a run from a checked scenario: the arena on the site, the radio, the guards on
//! their ring and the walkers at the edge of their approach, each body at its level.

use super::agents::{Guard, Watch};
use super::scenario::Validated;
use rand::{Rng, SeedableRng};
use rand_chacha::ChaCha8Rng;
use std::sync::Arc;
use vitro::prelude::*;
use vitro_behaviour::route::VisitNodes;
use vitro_site::map::Mode;
use vitro_tactical::actuate::by_level::{Drive, Walk};
use vitro_tactical::arena::{Arena, Ev};
use vitro_tactical::condition::{Condition, Role};
use vitro_tactical::entity::roads::{FreeGraph, Roads};
use vitro_tactical::scenario::EntityType;
use vitro_tactical::types::{GroundKind, TroopKind, TypeBook};

/// Why a checked scenario could not be set up.
#[derive(Clone, Debug, PartialEq, thiserror::Error)]
pub enum SetupError {
    /// No street or footpath junction where the mission needs one.
    #[error("no {0} junction {1}")]
    NoJunction(&'static str, &'static str),
    /// An entity could not be added or placed.
    #[error("cannot place {0}: {1}")]
    Place(String, String),
}

/// A run's cast, as the referee and the views need it.
pub struct Cast {
    /// The guards.
    pub guards: Vec<AgentHandle<Guard>>,
    /// The walkers.
    pub walkers: Vec<EntityId>,
    /// Every entity's name and type, in id order.
    pub kinds: Vec<(String, EntityType)>,
}

// ANCHOR: setup
/// The simulation of the checked scenario `v` with `seed`, and its cast.
///
/// # Errors
/// [`SetupError`]: no junction where one is needed, or a body that cannot be placed.
pub fn build(v: &Validated, seed: u64) -> Result<(Simulation<Watch>, Cast), SetupError> {
    let (f, w) = (&v.file, &v.file.watch);
    let roads = Arc::new(Roads::new(&v.site));
    let arena = Arena::with(
        v.site.clone(),
        roads.clone(),
        Arc::new(TypeBook::builtin().clone()),
    );
    let mut sim = Simulation::<Watch>::new(arena, seed);
    sim.network_mut().set_default_link(f.channel.link());
    // The ring: the junctions nearest eight points round the depot, in turn.
    let (drive, walk) = (roads.of(Mode::Drive), roads.of(Mode::Walk));
    let mut ring: Vec<NodeId> = Vec::new();
    for k in 0..8 {
        let a = f64::from(k) * std::f64::consts::FRAC_PI_4;
        let p = [
            w.depot[0] + w.ring_m * libm::cos(a),
            w.depot[1] + w.ring_m * libm::sin(a),
        ];
        if let Some(n) = drive.nearest_connected(p).filter(|n| !ring.contains(n)) {
            ring.push(n);
        }
    }
    if ring.is_empty() {
        return Err(SetupError::NoJunction("street", "near the depot"));
    }
    let goal = walk
        .nearest_connected(w.depot)
        .ok_or(SetupError::NoJunction("footpath", "near the depot"))?;
    // Walkers start on footpath junctions `approach_m` from the depot, drawn from the seed.
    let [lo, hi] = w.approach_m;
    let far: Vec<NodeId> = (0..walk.graph.node_count() as u32)
        .map(NodeId)
        .filter(|n| walk.main[n.0 as usize])
        .filter(|&n| {
            walk.graph.node(n).is_some_and(|s| {
                let d = libm::hypot(s.pos[0] - w.depot[0], s.pos[1] - w.depot[1]);
                (lo..=hi).contains(&d)
            })
        })
        .collect();
    let mut rng = ChaCha8Rng::seed_from_u64(seed);
    let mut cast = Cast {
        guards: Vec::new(),
        walkers: Vec::new(),
        kinds: Vec::new(),
    };
    let n_guards = (f.entities.iter())
        .filter(|e| e.kind.is_vehicle())
        .map(|e| e.count as usize)
        .sum::<usize>()
        .max(1);
    for e in &f.entities {
        let level = f.fidelity.level_of(e.kind);
        for name in e.names() {
            let place = |e: &dyn ToString| SetupError::Place(name.clone(), e.to_string());
            let here = e
                .start
                .map(|p| (drive.nearest_connected(p), walk.nearest_connected(p)));
            let id = if e.kind.is_vehicle() {
                // A guard starts at its share of the ring and patrols it from there.
                let i = cast.guards.len() * ring.len() / n_guards;
                let mut route = ring.clone();
                route.rotate_left((i + 1) % ring.len().max(1));
                let start = here.and_then(|h| h.0).unwrap_or(ring[i]);
                let guard = Guard::new(route, Drive(level), w.camera.vision(), secs(w.look_s));
                let g = sim.add(name.clone(), guard).map_err(|e| place(&e))?;
                let kind = match e.kind {
                    EntityType::Truck => GroundKind::CargoTruck,
                    EntityType::Car => GroundKind::Car,
                    _ => GroundKind::Mdars,
                };
                let facing = heading(drive, start, ring[(i + 1) % ring.len()]);
                sim.env_mut()
                    .add_vehicle(g.id(), kind, level, start, facing)
                    .map_err(|e| place(&e))?;
                cast.guards.push(g);
                g.id()
            } else {
                // A walker: the stock route behaviour, one node long, at its level.
                let start = match here.and_then(|h| h.1) {
                    Some(n) => n,
                    None if far.is_empty() => {
                        return Err(SetupError::NoJunction("footpath", "at `approach_m`"));
                    }
                    None => far[rng.random_range(0..far.len())],
                };
                let walker = VisitNodes::new(vec![goal], Walk(level));
                let id = sim.add(name.clone(), walker).map_err(|e| place(&e))?.id();
                sim.env_mut()
                    .add_trooper(id, TroopKind::Red, level, start, 0.0)
                    .map_err(|e| place(&e))?;
                cast.walkers.push(id);
                id
            };
            let role = Role::from(e.kind);
            sim.env_mut()
                .conditions
                .insert(id, Condition::new(role, e.side.side(), role.height()));
            sim.schedule(SimTime::ZERO, Target::Entity(id), Ev::Start)
                .map_err(|e| place(&e))?;
            cast.kinds.push((name, e.kind));
        }
    }
    Ok((sim, cast))
}
// ANCHOR_END: setup

fn secs(s: f64) -> SimDuration {
    SimDuration::from_secs_f64(s)
}

/// The heading from street junction `a` to `b` of `g` (0 when either is missing).
fn heading(g: &FreeGraph, a: NodeId, b: NodeId) -> f64 {
    match (g.graph.node(a), g.graph.node(b)) {
        (Some(a), Some(b)) => libm::atan2(b.pos[1] - a.pos[1], b.pos[0] - a.pos[0]),
        _ => 0.0,
    }
}

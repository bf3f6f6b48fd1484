//! How fast each level of fidelity runs: a scene of 20 vehicles, 40 troopers and 6 aircraft
//! on the real town, run for 10 simulated minutes at each level, printing simulated seconds
//! per wall-clock second.
//!
//! `cargo run --release -p vitro-behaviour --example level_speed [SIM_SECONDS]`
//!
//! Scenes: every entity at its discrete level; at its continuous level (interpolated
//! vehicles, directed troopers, kinematic and dynamic aircraft); with the vehicles as rigid
//! bodies instead. Then each family alone at each of its levels. Vehicles and troopers
//! patrol between random junctions of the main street network (a named random stream of the
//! seed picks them); two fixed-wing aircraft fly a box over the town, two helicopters
//! loiter over a vehicle and two loop over another.

use rand::Rng;
use rand_chacha::ChaCha8Rng;
use std::time::Instant;
use vitro::prelude::*;
use vitro::rng::Owner;
use vitro_behaviour::route::{FlightMission, Leg, VisitNodes};
use vitro_tactical::actuate::{ground, troop};
use vitro_tactical::arena::Ev;
use vitro_tactical::autopilot;
use vitro_tactical::entity::Level;
use vitro_tactical::entity::roads::FreeGraph;
use vitro_tactical::model::{Controller, Tactical};
use vitro_tactical::setup::Setup;
use vitro_tactical::types::{CtolKind, GroundKind, TroopKind, VtolKind};

/// Levels of one scene run: `None` leaves a family out.
#[derive(Copy, Clone)]
struct Scene {
    name: &'static str,
    vehicles: Option<Level>,
    troops: Option<Level>,
    aircraft: Option<(Level, Level)>,
}

/// `n` distinct nodes of the main part of `g`, drawn from `rng`.
fn nodes(g: &FreeGraph, rng: &mut ChaCha8Rng, n: usize) -> Vec<NodeId> {
    let main: Vec<NodeId> = (0..g.graph.node_count() as u32)
        .map(NodeId)
        .filter(|n| g.main[n.0 as usize])
        .collect();
    let mut out: Vec<NodeId> = Vec::new();
    while out.len() < n.min(main.len()) {
        let c = main[rng.random_range(0..main.len())];
        if !out.contains(&c) {
            out.push(c);
        }
    }
    out
}

/// A patrol over `route` for a vehicle at `level`.
fn vehicle(level: Level, route: Vec<NodeId>) -> Box<dyn Controller> {
    match level {
        Level::Discrete => Box::new(repeat(route, ground::discrete::GoToNode)),
        Level::Interpolated => Box::new(repeat(route, ground::interpolated::GoToNode)),
        _ => Box::new(repeat(route, ground::physical::GoToNode)),
    }
}

fn repeat<A>(route: Vec<NodeId>, a: A) -> VisitNodes<A> {
    let mut v = VisitNodes::new(route, a);
    v.repeat = true;
    v
}

fn build(setup: &Setup, scene: Scene, seed: u64) -> Simulation<Tactical> {
    let mut sim: Simulation<Tactical> = Simulation::new(setup.arena(), seed);
    let mut rng = sim.rngs_mut().stream(Owner::Global, "scene").clone();
    let (drive, walk) = (&setup.roads.drive, &setup.roads.walk);
    let mut vehicles = Vec::new();
    if let Some(level) = scene.vehicles {
        let starts = nodes(drive, &mut rng, 20);
        for (i, &start) in starts.iter().enumerate() {
            let route = nodes(drive, &mut rng, 3);
            let kind = GroundKind::ALL[i % 3];
            let id = sim
                .add_agent(format!("vehicle{i}"), vehicle(level, route))
                .expect("fresh name");
            sim.env_mut()
                .add_vehicle(id, kind, level, start, 0.0)
                .expect("a free node");
            // A body the aircraft's cameras can see (they find their targets by looking).
            let seen = vitro_tactical::condition::Condition::new(
                vitro_tactical::condition::Role::Car,
                vitro_tactical::world::Side::Neutral,
                1.5,
            );
            sim.env_mut().conditions.insert(id, seen);
            vehicles.push(id);
        }
    }
    if let Some(level) = scene.troops {
        let starts = nodes(walk, &mut rng, 40);
        for (i, &start) in starts.iter().enumerate() {
            let route = nodes(walk, &mut rng, 3);
            let kind = TroopKind::ALL[i % 3];
            let c: Box<dyn Controller> = match level {
                Level::Discrete => Box::new(repeat(route, troop::discrete::WalkToNode)),
                _ => Box::new(repeat(route, troop::directed::WalkToNode)),
            };
            let id = sim.add_agent(format!("trooper{i}"), c).expect("fresh name");
            sim.env_mut()
                .add_trooper(id, kind, level, start, 0.0)
                .expect("a free node");
        }
    }
    if let Some((ctol_level, vtol_level)) = scene.aircraft {
        let c = setup.site.offset;
        let z = 520.0;
        let corners = [
            [-700.0, -600.0],
            [700.0, -600.0],
            [700.0, 600.0],
            [-700.0, 600.0],
        ];
        let boxed: Vec<[f64; 3]> = (0..20)
            .flat_map(|_| corners.iter().map(|d| [c[0] + d[0], c[1] + d[1], z]))
            .collect();
        let far = 1e6;
        for i in 0..6 {
            let start = [c[0] - 900.0 + 60.0 * i as f64, c[1], z];
            let legs = match (i, vehicles.get(i)) {
                (0 | 1, _) | (_, None) => vec![Leg::Waypoints(boxed.clone())],
                (2 | 3, Some(&target)) => vec![Leg::Loiter {
                    target,
                    radius: 150.0,
                    height: 150.0,
                    secs: far,
                }],
                (_, Some(&target)) => vec![Leg::Loop {
                    target,
                    half_length: 300.0,
                    axis: 0.0,
                    height: 150.0,
                    passes: 1000,
                }],
            };
            let name = format!("aircraft{i}");
            if i < 2 {
                let m: Box<dyn Controller> = match ctol_level {
                    Level::Discrete => {
                        Box::new(FlightMission::new(legs, autopilot::lattice::Autopilot))
                    }
                    _ => Box::new(FlightMission::new(legs, autopilot::ctol::Autopilot)),
                };
                let id = sim.add_agent(name, m).expect("fresh name");
                sim.env_mut()
                    .add_ctol(id, CtolKind::Procerus, ctol_level, start, 0.0)
                    .expect("a level of the fixed-wing");
            } else {
                let m: Box<dyn Controller> = match vtol_level {
                    Level::Discrete => {
                        Box::new(FlightMission::new(legs, autopilot::lattice::Autopilot))
                    }
                    _ => Box::new(FlightMission::new(legs, autopilot::vtol::Autopilot)),
                };
                let kind = VtolKind::ALL[i % 2];
                let id = sim.add_agent(name, m).expect("fresh name");
                sim.env_mut()
                    .add_vtol(id, kind, vtol_level, start, 0.0)
                    .expect("a level of the helicopter");
                // Its camera looks from its body.
                let body = vitro_tactical::condition::Condition::new(
                    vitro_tactical::condition::Role::Vidar,
                    vitro_tactical::world::Side::Blue,
                    0.5,
                );
                sim.env_mut().conditions.insert(id, body);
            }
        }
    }
    let ids: Vec<EntityId> = sim.entities().ids().collect();
    for id in ids {
        sim.schedule(SimTime::ZERO, Target::Entity(id), Ev::Start)
            .expect("t = 0");
    }
    sim
}

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let secs: u64 = std::env::args()
        .nth(1)
        .map(|s| s.parse())
        .transpose()?
        .unwrap_or(600);
    let setup = Setup::default_town()?;
    let (d, i, p, r, k, y) = (
        Level::Discrete,
        Level::Interpolated,
        Level::Physical,
        Level::Directed,
        Level::Kinematic,
        Level::Dynamic,
    );
    let scenes = [
        Scene {
            name: "all discrete",
            vehicles: Some(d),
            troops: Some(d),
            aircraft: Some((d, d)),
        },
        Scene {
            name: "all continuous",
            vehicles: Some(i),
            troops: Some(r),
            aircraft: Some((k, y)),
        },
        Scene {
            name: "physical vehicles",
            vehicles: Some(p),
            troops: Some(r),
            aircraft: Some((k, y)),
        },
        Scene {
            name: "20 vehicles, discrete",
            vehicles: Some(d),
            troops: None,
            aircraft: None,
        },
        Scene {
            name: "20 vehicles, interpolated",
            vehicles: Some(i),
            troops: None,
            aircraft: None,
        },
        Scene {
            name: "20 vehicles, physical",
            vehicles: Some(p),
            troops: None,
            aircraft: None,
        },
        Scene {
            name: "40 troopers, discrete",
            vehicles: None,
            troops: Some(d),
            aircraft: None,
        },
        Scene {
            name: "40 troopers, directed",
            vehicles: None,
            troops: Some(r),
            aircraft: None,
        },
        Scene {
            name: "6 aircraft, discrete",
            vehicles: None,
            troops: None,
            aircraft: Some((d, d)),
        },
        Scene {
            name: "6 aircraft, kinematic+dynamic",
            vehicles: None,
            troops: None,
            aircraft: Some((k, y)),
        },
    ];
    println!(
        "{secs} simulated seconds per scene (the aircraft scenes loiter and loop over vehicles \
         only when vehicles are in the scene)\n"
    );
    println!(
        "{:<30} {:>8} {:>10} {:>9} {:>16}",
        "scene", "entities", "events", "wall s", "sim s / wall s"
    );
    for scene in scenes {
        let mut sim = build(&setup, scene, 7);
        let n = sim.entities().len();
        let t0 = Instant::now();
        sim.run_until(SimTime::from_secs(secs));
        let wall = t0.elapsed().as_secs_f64();
        println!(
            "{:<30} {:>8} {:>10} {:>9.3} {:>16.0}",
            scene.name,
            n,
            sim.events_fired(),
            wall,
            secs as f64 / wall
        );
    }
    Ok(())
}

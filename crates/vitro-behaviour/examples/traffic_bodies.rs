//! Bodies in traffic: 20 vehicles (cars, cargo trucks, MDARS UGVs in turn) started at random
//! junctions of the town's main street network, all facing east whatever the street, each
//! driving a tour of random junctions over and over, at the discrete, interpolated and
//! physical levels. Prints, per level and over the seeds: trips completed, vehicles that gave
//! a trip up (stalls, with their reasons) and stalls per 20 vehicle-hours.
//!
//! `cargo run --release -p vitro-behaviour --example traffic_bodies [SIM_SECONDS] [SEEDS]`
//!
//! A vehicle's controller stops at its first stall, so the stall count is also the number of
//! vehicles out of the traffic by the end.

use rand::Rng;
use rand_chacha::ChaCha8Rng;
use std::collections::BTreeMap;
use vitro::prelude::*;
use vitro::rng::Owner;
use vitro_behaviour::route::VisitNodes;
use vitro_tactical::actuate::MoveError;
use vitro_tactical::actuate::by_level::Drive;
use vitro_tactical::arena::Ev;
use vitro_tactical::entity::Level;
use vitro_tactical::entity::roads::FreeGraph;
use vitro_tactical::model::Tactical;
use vitro_tactical::setup::Setup;
use vitro_tactical::types::GroundKind;

/// Vehicles in the scene.
const VEHICLES: usize = 20;
/// Junctions in each vehicle's tour.
const TOUR: usize = 4;

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

/// What one run at one level gave.
#[derive(Default)]
struct Tally {
    trips: usize,
    stalls: usize,
    reasons: BTreeMap<String, usize>,
    vehicle_hours: f64,
}

fn run(setup: &Setup, level: Level, seed: u64, secs: u64, t: &mut Tally) {
    let mut sim: Simulation<Tactical> = Simulation::new(setup.arena(), seed);
    let mut rng = sim.rngs_mut().stream(Owner::Global, "traffic").clone();
    let drive = &setup.roads.drive;
    let starts = nodes(drive, &mut rng, VEHICLES);
    let mut ids = Vec::new();
    for (i, &start) in starts.iter().enumerate() {
        let mut v = VisitNodes::new(nodes(drive, &mut rng, TOUR), Drive(level));
        v.repeat = true;
        let id = sim
            .add_agent(format!("vehicle{i}"), Box::new(v))
            .expect("fresh name");
        sim.env_mut()
            .add_vehicle(id, GroundKind::ALL[i % 3], level, start, 0.0)
            .expect("a free node");
        sim.schedule(SimTime::ZERO, Target::Entity(id), Ev::Start)
            .expect("t = 0");
        ids.push(id);
    }
    sim.run(SimTime::from_secs(secs), |_| false);
    for id in ids {
        let Some(v) = sim
            .agent(id)
            .and_then(|c| c.as_any().downcast_ref::<VisitNodes<Drive>>())
        else {
            continue;
        };
        t.trips += v.log.len();
        t.vehicle_hours += secs as f64 / 3600.0;
        if let Some(e) = &v.error {
            t.stalls += 1;
            let why = match e {
                MoveError::Stalled(_, _, r) => format!("{r:?}"),
                other => format!("{other}"),
            };
            *t.reasons.entry(why).or_default() += 1;
        }
    }
}

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let mut args = std::env::args().skip(1);
    let secs: u64 = args.next().map(|s| s.parse()).transpose()?.unwrap_or(1800);
    let seeds: u64 = args.next().map(|s| s.parse()).transpose()?.unwrap_or(5);
    let setup = Setup::default_town()?;
    println!(
        "{VEHICLES} vehicles, {secs} s, seeds 1..={seeds}\n{:<13} {:>6} {:>7} {:>14}  reasons",
        "level", "trips", "stalls", "per 20 veh-h"
    );
    for level in [Level::Discrete, Level::Interpolated, Level::Physical] {
        let mut t = Tally::default();
        for seed in 1..=seeds {
            run(&setup, level, seed, secs, &mut t);
        }
        println!(
            "{:<13} {:>6} {:>7} {:>14.2}  {:?}",
            level.name(),
            t.trips,
            t.stalls,
            t.stalls as f64 * 20.0 / t.vehicle_hours.max(1e-9),
            t.reasons
        );
    }
    Ok(())
}

//! # The Vitro demo: cars patrolling a town over a lossy radio
//!
//! A small scenario that exercises the whole core until the real mission exists:
//!
//! - a generated street graph ([`town`]) in a `GraphStorage`, cars in an `EntityStorage`
//!   (junction + progress along the street, continuous x, y), and a visit log ([`world`]);
//! - a position sensor ([`world::Gps`]), a navigator ([`world::Navigator`]) and a
//!   [`world::GoToNode`] actuator that moves a car along the shortest route over time;
//! - a patrol controller ([`patrol::Patroller`]) that picks the least recently visited junction
//!   it knows of and claims it over a delayed, lossy, range-limited broadcast channel;
//! - the classic patrolling metrics at the end ([`Metrics`]): mean and worst node idleness.
//!
//! ```
//! use vitro_demo::{Scenario, config::DemoConfig};
//! let mut cfg = DemoConfig::parse("demo.toml", include_str!("../../../scenarios/demo.toml")).unwrap();
//! cfg.end_s = 300.0;
//! let mut run = Scenario::build(cfg.clone()).unwrap();
//! let m = run.run();
//! assert_eq!(m.sim_time_s, 300.0);
//! assert!(m.visits > 0 && m.messages_sent > 0);
//!
//! // Same scenario, same seed: the same trace.
//! let mut again = Scenario::build(cfg).unwrap();
//! assert_eq!(again.run().trace_hash, m.trace_hash);
//! ```

pub mod config;
pub mod patrol;
mod plugin;
mod snapshot;
pub mod town;
pub mod view;
pub mod world;

use config::{DemoConfig, Invalid};
pub use patrol::Demo;
use patrol::Patroller;
pub use plugin::PatrollingCars;
use rand::Rng;
use serde::{Serialize, Serializer};
use std::collections::BTreeMap;
use vitro::entity::{EntityError, EntityId};
use vitro::event::ScheduleError;
use vitro::prelude::*;
use vitro::rng::{Owner, RngStreams};
use vitro_mission::session::{Session, Setup};
pub use world::Event;
use world::Town;

/// Why the demo could not be built or run.
#[derive(Debug, thiserror::Error)]
pub enum DemoError {
    /// A configuration value is out of range.
    #[error("invalid scenario: {0}")]
    Invalid(#[from] Invalid),
    /// An entity could not be created.
    #[error("cannot create an entity: {0}")]
    Entity(#[from] EntityError),
    /// The start could not be scheduled.
    #[error("cannot schedule the start: {0}")]
    Schedule(#[from] ScheduleError),
    /// A car's controller stopped on an error.
    #[error("{car} failed at t={at}: {reason}")]
    AgentFailed {
        /// The car's name.
        car: String,
        /// When the run stopped.
        at: SimTime,
        /// What went wrong.
        reason: String,
    },
}

/// A run of the demo: the generic run with the demo's own part, [`Scenario`].
pub type DemoRun = Session<Scenario>;

/// The demo's own part of a run: its configuration, its cars, and each car's last shown pose
/// (the simulation, the settings and the advance loop are the [`Session`]'s).
pub struct Scenario {
    cfg: DemoConfig,
    cars: Vec<EntityId>,
    /// Each car's last shown position and time, for its heading and speed.
    last: BTreeMap<u32, ([f64; 2], u64, f64)>,
}

impl Scenario {
    /// Builds the town, the network and the cars of `cfg` (which is validated first).
    pub fn build(cfg: DemoConfig) -> Result<DemoRun, DemoError> {
        cfg.validate()?;
        let streams = RngStreams::new(cfg.seed);
        let streets = town::generate(&cfg.town, &mut streams.fresh(Owner::Global, "town"));
        let junctions = streets.node_count();
        let mut sim = Simulation::<Demo>::new(Town::new(streets), cfg.seed);
        let ch = &cfg.channel;
        sim.network_mut().set_default_link(LinkParams {
            delay: SimDuration::from_secs_f64(ch.delay_ms / 1e3),
            jitter: SimDuration::from_secs_f64(ch.jitter_ms / 1e3),
            loss: ch.loss,
            range_m: ch.range_m,
            bandwidth_bps: None,
        });

        // Distinct random starting junctions (a partial shuffle).
        let mut spots: Vec<u32> = (0..junctions as u32).collect();
        let rng = sim.rngs_mut().stream(Owner::Global, "placement");
        let count = cfg.cars.count as usize;
        for i in 0..count.min(spots.len()) {
            let j = rng.random_range(i..spots.len());
            spots.swap(i, j);
        }
        let cost = CostModel {
            base: SimDuration::ZERO,
            per_unit: SimDuration::from_micros(cfg.cars.think_us_per_node),
        };
        let tick = SimDuration::from_secs_f64(cfg.cars.tick_s);
        let mut cars = Vec::with_capacity(count);
        for (i, &spot) in spots.iter().take(count).enumerate() {
            let car = sim.add_agent(
                format!("car-{}", i + 1),
                Patroller::new(junctions, cost, cfg.cars.distance_weight),
            )?;
            sim.env_mut()
                .park(car, NodeId(spot), cfg.cars.speed_mps, tick)
                .ok_or(Invalid {
                    key: "cars.count",
                    expected: "no more cars than junctions".to_owned(),
                    found: cfg.cars.count.to_string(),
                })?;
            cars.push(car);
        }
        sim.schedule(SimTime::ZERO, Target::Broadcast, Event::Start)?;
        let setup = Setup::from_secs(cfg.name.clone(), cfg.seed, cfg.end_s, 1.0, cfg.start);
        let last = BTreeMap::new();
        Ok(Session::new(setup, sim, Scenario { cfg, cars, last }))
    }

    /// The configuration it was built from.
    pub fn config(&self) -> &DemoConfig {
        &self.cfg
    }

    /// The cars, in creation order.
    pub fn cars(&self) -> &[EntityId] {
        &self.cars
    }

    /// The first car whose controller failed, as an error.
    fn failure(run: &DemoRun) -> Result<(), DemoError> {
        for &car in &run.cars {
            if let Some(reason) = run.sim.agent(car).and_then(Patroller::failure) {
                return Err(DemoError::AgentFailed {
                    car: run.sim.entities().name(car).unwrap_or("?").to_owned(),
                    at: run.sim.now(),
                    reason: reason.to_owned(),
                });
            }
        }
        Ok(())
    }

    /// The metrics of the run so far, observed up to the time it reached.
    fn measure(run: &DemoRun) -> Metrics {
        let env = run.sim.env();
        let n = env.streets().node_count();
        let t = run.reached().as_nanos();
        let (mut gap_sq, mut max_gap, mut visits) = (0u128, 0u64, 0u64);
        for i in 0..n {
            let log = env.visit_log(NodeId(i as u32));
            let open = run.reached().saturating_since(log.last).as_nanos();
            gap_sq += log.gap_sq + u128::from(open).pow(2);
            max_gap = max_gap.max(log.max_gap.as_nanos()).max(open);
            visits += log.visits;
        }
        // Time-averaged idleness: the integral of (t - last visit) over the run, per junction.
        let mean_ns = if n == 0 || t == 0 {
            0.0
        } else {
            gap_sq as f64 / 2.0 / n as f64 / t as f64
        };
        let mut m = Metrics {
            scenario: run.cfg.name.clone(),
            seed: run.cfg.seed,
            junctions: n,
            streets: env.streets().edge_count() / 2,
            cars: run.cars.len(),
            stop: run.stop().map_or("not run", stop_name).to_owned(),
            sim_time_s: run.reached().as_secs_f64(),
            events: run.sim.events_fired(),
            mean_idleness_s: mean_ns / 1e9,
            max_idleness_s: max_gap as f64 / 1e9,
            visits,
            decisions: 0,
            goals_reached: 0,
            yielded: 0,
            messages_sent: 0,
            messages_received: 0,
            messages_lost: 0,
            messages_bounced: 0,
            trace_hash: run.sim.trace_hash(),
        };
        for (_, _, c) in run.sim.network().all_counts() {
            m.messages_sent += c.sent;
            m.messages_received += c.received;
            m.messages_lost += c.lost;
            m.messages_bounced += c.bounced;
        }
        for s in run.cars.iter().filter_map(|&c| run.sim.agent(c)) {
            let s = s.stats();
            m.decisions += s.decisions;
            m.goals_reached += s.goals_reached;
            m.yielded += s.yielded;
        }
        m
    }
}

fn stop_name(r: StopReason) -> &'static str {
    match r {
        StopReason::Time => "end time",
        StopReason::QueueEmpty => "no event left",
        StopReason::Condition => "condition",
        StopReason::Requested => "stopped by an agent",
        StopReason::Control => "stopped by control",
    }
}

/// What a demo run measured.
#[derive(Clone, Debug, Default, PartialEq, Serialize)]
pub struct Metrics {
    /// The scenario's name.
    pub scenario: String,
    /// The master seed.
    pub seed: u64,
    /// Junctions of the town.
    pub junctions: usize,
    /// Streets (undirected).
    pub streets: usize,
    /// Cars.
    pub cars: usize,
    /// Why the run stopped.
    pub stop: String,
    /// Simulated time covered, in seconds.
    pub sim_time_s: f64,
    /// Events fired.
    pub events: u64,
    /// Time-averaged idleness over all junctions (seconds since the last visit).
    pub mean_idleness_s: f64,
    /// Worst idleness: the longest any junction went unvisited.
    pub max_idleness_s: f64,
    /// Junction visits by all cars.
    pub visits: u64,
    /// Goals chosen by all cars.
    pub decisions: u64,
    /// Goals reached.
    pub goals_reached: u64,
    /// Goals given up to a better claim.
    pub yielded: u64,
    /// Message copies sent (a broadcast counts once per receiver).
    pub messages_sent: u64,
    /// Copies delivered.
    pub messages_received: u64,
    /// Copies lost on the channel.
    pub messages_lost: u64,
    /// Copies returned to the sender (out of range).
    pub messages_bounced: u64,
    /// The trace hash (hex in JSON).
    #[serde(serialize_with = "hex")]
    pub trace_hash: u64,
}

fn hex<S: Serializer>(h: &u64, s: S) -> Result<S::Ok, S::Error> {
    s.serialize_str(&format!("{h:016x}"))
}

#[cfg(test)]
mod tests {
    use super::*;

    fn cfg() -> DemoConfig {
        DemoConfig::parse("demo.toml", include_str!("../../../scenarios/demo.toml")).unwrap()
    }

    fn run(cfg: DemoConfig) -> Metrics {
        let mut s = Scenario::build(cfg).unwrap();
        let m = s.run();
        assert_eq!(s.stop(), Some(StopReason::Time));
        m
    }

    #[test]
    fn seeds_decide_the_trace() {
        let mut c = cfg();
        c.end_s = 600.0;
        let a = run(c.clone());
        let b = run(c.clone());
        assert_eq!(a, b);
        c.seed += 1;
        assert_ne!(run(c).trace_hash, a.trace_hash);
    }

    #[test]
    fn patrol_covers_the_town() {
        let mut c = cfg();
        c.end_s = 3600.0;
        let m = run(c);
        // Every junction was visited at least once well before the end.
        assert!(m.max_idleness_s < 1800.0, "{m:?}");
        assert!(m.mean_idleness_s > 0.0 && m.mean_idleness_s < m.max_idleness_s);
        assert!(m.visits >= m.junctions as u64);
        assert!(m.goals_reached > 0 && m.decisions >= m.goals_reached);
        // Every copy is delivered, lost or bounced, but for the few still in flight.
        let settled = m.messages_received + m.messages_lost + m.messages_bounced;
        assert!(
            settled <= m.messages_sent && m.messages_sent - settled <= 36,
            "{m:?}"
        );
    }

    #[test]
    fn more_cars_patrol_better() {
        let mut c = cfg();
        c.end_s = 3600.0;
        c.cars.count = 1;
        let one = run(c.clone());
        c.cars.count = 6;
        let six = run(c);
        assert!(
            six.mean_idleness_s * 2.0 < one.mean_idleness_s,
            "{one:?} {six:?}"
        );
    }

    #[test]
    fn claims_spread_the_cars() {
        // A perfect channel against a dead one: hearing claims keeps cars off each other's
        // goals, so the town is covered better.
        let mut c = cfg();
        c.end_s = 3600.0;
        c.channel.loss = 0.0;
        c.channel.range_m = None;
        let talk = run(c.clone());
        c.channel.loss = 1.0;
        let mute = run(c);
        assert_eq!(mute.messages_received, 0);
        assert_eq!(mute.messages_lost, mute.messages_sent);
        assert!(talk.yielded > 0);
        assert!(
            talk.mean_idleness_s < mute.mean_idleness_s,
            "{talk:?} {mute:?}"
        );
    }

    #[test]
    fn snapshot_resumes_the_same_run() {
        let mut c = cfg();
        c.end_s = 900.0;
        let whole = run(c.clone());

        let mut first = Scenario::build(c.clone()).unwrap();
        first.sim.run_until(SimTime::from_secs(400));
        let mut bytes = Vec::new();
        first.sim.save_snapshot(&mut bytes).unwrap();
        let mut resumed = Scenario::build(c).unwrap();
        resumed.sim = Simulation::load_snapshot(bytes.as_slice()).unwrap();
        assert_eq!(resumed.run(), whole);
        assert_eq!(resumed.stop(), Some(StopReason::Time));
    }

    #[test]
    fn running_in_steps_is_the_same_run() {
        let mut c = cfg();
        c.end_s = 900.0;
        let whole = run(c.clone());
        let mut s = Scenario::build(c).unwrap();
        let mut last = 0.0;
        for t in [100, 250, 600, 900, 1000] {
            s.advance(SimTime::from_secs(t));
            let m = s.metrics();
            assert_eq!(m.sim_time_s, (t as f64).min(900.0));
            assert!(m.sim_time_s >= last);
            last = m.sim_time_s;
        }
        assert_eq!(s.metrics(), whole);
    }

    #[test]
    fn idleness_of_an_unvisited_town_is_elapsed_time() {
        let mut c = cfg();
        c.end_s = 10.0;
        c.cars.speed_mps = 0.001; // nobody reaches a junction in 10 s
        let m = run(c);
        assert_eq!(m.visits, 0);
        assert_eq!(m.max_idleness_s, 10.0);
        assert!((m.mean_idleness_s - 5.0).abs() < 1e-9);
    }
}

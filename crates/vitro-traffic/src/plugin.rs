//! The traffic scenario as a plug-in of the tools: [`Traffic`] is the kind `"traffic"`, a
//! [`TrafficRun`] one of its runs, [`Metrics`] what it measures.

use crate::{Streets, Tour, TrafficError, TrafficRun, scenario};
use serde::Serialize;
use std::path::Path;
use vitro::time::SimTime;
use vitro_mission::scene::site_scene;
use vitro_mission::session::Play;
use vitro_mission::{BuildOptions, Metric, MetricTable, MissionError, Run, metric_table};
use vitro_record::{Frame, Scene};
use vitro_tactical::actuate::by_level::{Drive, Walk};
use vitro_tactical::arena::site_digest;
use vitro_tactical::model::Tactical;
use vitro_tactical::record::entity;
use vitro_tactical::scenario::Preset;

/// The traffic scenario, registered as `kind = "traffic"`.
#[derive(Clone, Copy, Debug, Default)]
pub struct Traffic;

/// What a traffic run measures.
#[derive(Clone, Debug, Default, PartialEq, Serialize)]
pub struct Metrics {
    /// Vehicles in the run.
    pub vehicles: usize,
    /// Troopers in the run.
    pub troopers: usize,
    /// Trips the vehicles completed (arrived at the junction they were sent to).
    pub trips_completed: usize,
    /// Trips the troopers completed.
    pub trooper_trips: usize,
    /// Trips the vehicles gave up ([`vitro_tactical::arena::Ev::Stalled`]).
    pub stalls: usize,
    /// Vehicles that stalled at least once.
    pub vehicles_stalled: usize,
    /// Stalls for which the vehicle was still stuck after every recovery the trip allows.
    pub stalls_recovery_spent: usize,
    /// Vehicles times simulated hours.
    pub vehicle_hours: f64,
    /// Stalls per 20 vehicle-hours.
    pub stalls_per_20_vh: f64,
    /// Contacts between bodies: not measured at any level (the arena reports none), so
    /// always missing.
    pub collisions: Option<f64>,
    /// Mean duration of the vehicles' completed trips, seconds (none before the first).
    pub mean_trip_s: Option<f64>,
    /// Mean duration of the troopers' completed trips, seconds.
    pub mean_trooper_trip_s: Option<f64>,
    /// The longest time any vehicle was commanded to move but did not, seconds (to the
    /// resolution of `traffic.check_s`).
    pub deadlock_s: f64,
    /// Bodies whose tour stopped on an actuator's refusal (no route from where they are).
    pub stopped: usize,
    /// Simulated seconds reached.
    pub sim_time_s: f64,
}

impl MetricTable for Metrics {
    fn table(&self) -> Vec<(&'static str, Metric)> {
        metric_table!(self; vehicles, troopers, trips_completed, trooper_trips, stalls,
            vehicles_stalled, stalls_recovery_spent, vehicle_hours, stalls_per_20_vh, collisions, mean_trip_s,
            mean_trooper_trip_s, deadlock_s, stopped, sim_time_s)
    }
}

fn mission_error(e: TrafficError) -> MissionError {
    match e {
        TrafficError::Scenario(d) => MissionError::Scenario(d.report()),
        e @ TrafficError::Setup(_) => MissionError::Setup(e.to_string()),
    }
}

fn mean(xs: &[f64]) -> Option<f64> {
    (!xs.is_empty()).then(|| xs.iter().sum::<f64>() / xs.len() as f64)
}

/// Measures `run` now.
fn measure(run: &TrafficRun) -> Metrics {
    let now = run.sim.now().max(run.reached());
    let hours = now.as_secs_f64() / 3600.0;
    let mut m = Metrics {
        sim_time_s: now.as_secs_f64(),
        deadlock_s: run.play.longest_wait_s,
        ..Metrics::default()
    };
    let (mut trips, mut walks) = (Vec::new(), Vec::new());
    for x in &run.members {
        let agent = run.sim.agent(x.id).map(|a| a.as_any());
        if let Some(t) = agent.and_then(|a| a.downcast_ref::<Tour<Drive>>()) {
            m.vehicles += 1;
            m.trips_completed += t.trips.len();
            m.stalls += t.stalls.len();
            m.vehicles_stalled += usize::from(!t.stalls.is_empty());
            m.stalls_recovery_spent += (t.stalls.iter())
                .filter(|s| s.1 == vitro_tactical::arena::StallReason::RecoverySpent)
                .count();
            m.stopped += usize::from(t.goal.is_none() && t.error.is_some());
            trips.extend(t.trips.iter().map(|(a, b)| (*b - *a).as_secs_f64()));
        } else if let Some(t) = agent.and_then(|a| a.downcast_ref::<Tour<Walk>>()) {
            m.troopers += 1;
            m.trooper_trips += t.trips.len();
            m.stopped += usize::from(t.goal.is_none() && t.error.is_some());
            walks.extend(t.trips.iter().map(|(a, b)| (*b - *a).as_secs_f64()));
        }
    }
    m.vehicle_hours = m.vehicles as f64 * hours;
    m.stalls_per_20_vh = if m.vehicle_hours > 0.0 {
        m.stalls as f64 * 20.0 / m.vehicle_hours
    } else {
        0.0
    };
    m.mean_trip_s = mean(&trips);
    m.mean_trooper_trip_s = mean(&walks);
    m
}

impl vitro_mission::Mission for Traffic {
    fn kind(&self) -> &'static str {
        "traffic"
    }

    fn about(&self) -> &'static str {
        "vehicles and troopers tour seeded random junctions of the town: trips, stalls, waits"
    }

    fn validate(&self, path: &Path, text: &str) -> Result<String, MissionError> {
        let v =
            scenario::validate_text(path, text).map_err(|d| MissionError::Scenario(d.report()))?;
        let f = &v.file;
        let count = |vehicle: bool| -> u64 {
            (f.entities.iter())
                .filter(|e| e.kind.is_vehicle() == vehicle)
                .map(|e| u64::from(e.count))
                .sum()
        };
        Ok(format!(
            "{:?}: {} vehicles, {} troopers, {} simulated seconds, fidelity {}",
            f.name,
            count(true),
            count(false),
            f.end.time_s,
            f.fidelity.level.name(),
        ))
    }

    fn build(
        &self,
        path: &Path,
        text: &str,
        options: &BuildOptions,
    ) -> Result<Box<dyn Run>, MissionError> {
        let preset = Preset::named(options.fidelity.as_deref())
            .map_err(|e| MissionError::Scenario(e.to_string()))?;
        let run = Streets::from_text(path, text, options.seed, preset).map_err(mission_error)?;
        Ok(Box::new(run))
    }

    fn fidelity_levels(&self) -> &'static [&'static str] {
        &Preset::NAMES
    }

    fn metric_names(&self) -> Vec<&'static str> {
        TrafficRun::metric_names()
    }
}

impl Play for Streets {
    type Model = Tactical;
    type Metrics = Metrics;
    type Heard = ();

    fn metrics(run: &TrafficRun) -> Metrics {
        measure(run)
    }

    fn scene(run: &TrafficRun) -> Scene {
        site_scene(
            &run.sim.env().site,
            run.name.clone(),
            run.start.unix_millis(),
        )
    }

    fn frame(run: &mut TrafficRun, frame: &mut Frame) {
        let w = run.sim.env();
        let mut entities = Vec::new();
        let mut intentions = Vec::new();
        for m in &run.members {
            let Some(p) = w.pose(m.id) else {
                continue;
            };
            let agent = run.sim.agent(m.id);
            let moving = agent.and_then(|a| a.intention());
            let status = if moving.is_some() { "moving" } else { "idle" };
            entities.push(entity(
                m.id,
                &m.name,
                m.kind.name(),
                m.side,
                &p,
                status.to_owned(),
            ));
            if let Some(i) = moving {
                intentions.push(vitro_record::Intention {
                    id: m.id.0,
                    text: i.text,
                    ..vitro_record::Intention::default()
                });
            }
        }
        frame.entities = entities;
        frame.intentions = intentions;
    }

    fn next_stop(&self) -> SimTime {
        self.next_check
    }

    fn at_stop(run: &mut TrafficRun, now: SimTime) {
        Streets::look(run, now);
    }

    fn world(run: &TrafficRun) -> u64 {
        site_digest(&run.sim.env().site)
    }

    fn summary(_: &TrafficRun, m: &Metrics) -> Vec<(String, String)> {
        let opt = |x: Option<f64>| x.map_or("-".to_string(), |v| format!("{v:.1} s"));
        vec![
            (
                "vehicles".into(),
                format!(
                    "{} vehicles, {} trips (mean {}), {} stalls of {} vehicles ({:.2} per 20 vehicle-hours), longest wait {:.0} s",
                    m.vehicles,
                    m.trips_completed,
                    opt(m.mean_trip_s),
                    m.stalls,
                    m.vehicles_stalled,
                    m.stalls_per_20_vh,
                    m.deadlock_s
                ),
            ),
            (
                "troopers".into(),
                format!(
                    "{} troopers, {} trips (mean {})",
                    m.troopers,
                    m.trooper_trips,
                    opt(m.mean_trooper_trip_s)
                ),
            ),
            (
                "collisions".into(),
                "not measured (the arena reports no contact between bodies)".into(),
            ),
        ]
    }
}

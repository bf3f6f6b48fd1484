//! The sample flights of the aircraft calibration
//! ([`vitro_tactical::calibration::air`]): waypoint routes over the town, flown at the
//! lattice and at the type's continuous level; the fit of each type; and the evaluation of a
//! calibration on fresh flights.
//!
//! A sample flight starts over a point of the town (on a lattice cell's centre, so that both
//! levels start from the same place) at the type's mission height above the ground, on a
//! random heading, and flies one to four legs of 150 to 700 m with turns up to 150° at the
//! waypoints; every waypoint is at the mission height above the ground under it, and every
//! other flight adds climbs and descents of up to 40 m. A helicopter starts from a hover and
//! stops at the last waypoint; the fixed-wing aircraft starts at cruise speed.

use crate::evaluate::Prediction;
use crate::trips::par_map;
use rand::{Rng, SeedableRng};
use rand_chacha::ChaCha8Rng;
use std::collections::BTreeMap;
use std::f64::consts::{PI, TAU};
use std::sync::Arc;
use vitro::env::Actuator;
use vitro::event::Target;
use vitro::sim::Simulation;
use vitro::time::SimTime;
use vitro_behaviour::route::{FlightMission, Leg};
use vitro_check::CheckError;
use vitro_tactical::arena::{Arena, Ev};
use vitro_tactical::autopilot::{self, FlyError};
use vitro_tactical::calibration::air::{
    AirFeatures, AirFit, FlightRecord, air_key, concrete_level, envelope,
};
use vitro_tactical::calibration::{Calibration, Residuals};
use vitro_tactical::entity::Level;
use vitro_tactical::entity::air::{AirKind, FlightCommand, Lattice, dir_of};
use vitro_tactical::model::{Controller, Tactical};
use vitro_tactical::setup::Setup;
use vitro_tactical::types::{CtolKind, VtolKind};

/// Largest turn at a waypoint of a sample flight, radians (150°).
pub const MAX_TURN: f64 = 5.0 * PI / 6.0;
/// Largest extra climb or descent at a waypoint, metres.
pub const MAX_EXTRA_CLIMB_M: f64 = 40.0;

/// One sample flight.
#[derive(Clone, Debug, PartialEq)]
pub struct Flight {
    /// The aircraft type.
    pub kind: AirKind,
    /// Start point, world metres (a lattice cell's centre).
    pub start: [f64; 3],
    /// Start heading, radians from east.
    pub heading: f64,
    /// The waypoints, world metres.
    pub points: Vec<[f64; 3]>,
    /// True if the fit may use it (else it is held out).
    pub fit: bool,
}

/// How many flights to draw.
#[derive(Clone, Debug, PartialEq)]
pub struct FlightSampling {
    /// Flights per aircraft type used by the fit.
    pub fit_per_type: usize,
    /// Flights per aircraft type held out.
    pub held_out_per_type: usize,
    /// Leg length range, metres.
    pub leg_m: (f64, f64),
    /// Most waypoints per flight.
    pub max_waypoints: usize,
    /// The aircraft types (default: every one).
    pub kinds: Vec<AirKind>,
    /// Seed of the draw.
    pub seed: u64,
}

impl Default for FlightSampling {
    fn default() -> Self {
        FlightSampling {
            fit_per_type: 12,
            held_out_per_type: 6,
            leg_m: (150.0, 700.0),
            max_waypoints: 4,
            kinds: std::iter::once(AirKind::Ctol(CtolKind::Procerus))
                .chain(VtolKind::ALL.iter().map(|&k| AirKind::Vtol(k)))
                .collect(),
            seed: 1,
        }
    }
}

/// The height above the ground a type flies its sample flights at (the default mission's),
/// metres.
pub fn mission_height(kind: AirKind) -> f64 {
    match kind {
        AirKind::Ctol(_) => 150.0,
        AirKind::Vtol(VtolKind::Vidar) => 80.0,
        AirKind::Vtol(VtolKind::Skeldar) => 100.0,
    }
}

/// The lattice of a type.
pub fn lattice_of(setup: &Setup, kind: AirKind) -> Lattice {
    match kind {
        AirKind::Ctol(k) => Lattice::for_ctol(setup.types.ctol(k)),
        AirKind::Vtol(k) => Lattice::for_vtol(setup.types.vtol(k)),
    }
}

/// Draws the sample flights (see the module doc): the first `fit_per_type` of a type are
/// fitted, the rest held out.
pub fn sample_flights(setup: &Setup, s: &FlightSampling) -> Vec<Flight> {
    let site = &setup.site;
    let e = site.map.extent;
    // The inner 80 % of the town.
    let inside = |p: [f64; 2]| {
        let (mx, my) = (0.1 * (e[2] - e[0]), 0.1 * (e[3] - e[1]));
        p[0] >= e[0] + mx && p[0] <= e[2] - mx && p[1] >= e[1] + my && p[1] <= e[3] - my
    };
    let mut out = Vec::new();
    for (ki, &kind) in s.kinds.iter().enumerate() {
        let mut rng = ChaCha8Rng::seed_from_u64(s.seed);
        rng.set_stream(100 + ki as u64);
        let h = mission_height(kind);
        let lattice = lattice_of(setup, kind);
        let total = s.fit_per_type + s.held_out_per_type;
        let (mut made, mut tries) = (0, 0);
        while made < total && tries < 100 * total.max(1) {
            tries += 1;
            let town = [rng.random_range(e[0]..e[2]), rng.random_range(e[1]..e[3])];
            if !inside(town) {
                continue;
            }
            let heading = rng.random_range(0.0..TAU);
            let legs = rng.random_range(1..=s.max_waypoints.max(1));
            let climbs = made % 2 == 1;
            let mut at = town;
            let mut course = heading + rng.random_range(-PI..PI);
            let mut pts = Vec::new();
            for i in 0..legs {
                if i > 0 {
                    course += rng.random_range(-MAX_TURN..MAX_TURN);
                }
                let len = rng.random_range(s.leg_m.0..s.leg_m.1);
                let next = [
                    at[0] + len * libm::cos(course),
                    at[1] + len * libm::sin(course),
                ];
                if !inside(next) {
                    break;
                }
                let extra = if climbs {
                    rng.random_range(-MAX_EXTRA_CLIMB_M..MAX_EXTRA_CLIMB_M)
                } else {
                    0.0
                };
                let g = site.on_ground(next);
                pts.push([g[0], g[1], g[2] + h + extra]);
                at = next;
            }
            if pts.len() < legs {
                continue;
            }
            let g = site.on_ground(town);
            let start = lattice.point(lattice.cell_of([g[0], g[1], g[2] + h]));
            out.push(Flight {
                kind,
                start,
                heading: wrap(heading),
                points: pts,
                fit: made < s.fit_per_type,
            });
            made += 1;
        }
    }
    out
}

fn wrap(a: f64) -> f64 {
    vitro_tactical::entity::route::wrap_angle(a)
}

/// The features of a flight as the lattice sees them at its start (its cell, its lattice
/// heading, at rest for a helicopter), at cruise speed.
pub fn features(setup: &Setup, f: &Flight) -> AirFeatures {
    let lattice = lattice_of(setup, f.kind);
    let (_, cruise, climb) = envelope(&setup.types, f.kind);
    let start = lattice.point(lattice.cell_of(f.start));
    let heading = f64::from(dir_of(f.heading)) * std::f64::consts::FRAC_PI_4;
    let rest = matches!(f.kind, AirKind::Vtol(_));
    AirFeatures::of(start, heading, rest, &f.points, cruise, climb)
}

/// Flies `f` at `level` (the lattice or the type's continuous level; with `calibration` on
/// the arena if given); the time its last waypoint was reached, seconds (`None`: it crashed
/// or did not get there within three times the route at the slowest speed + 300 s).
pub fn fly(
    setup: &Setup,
    f: &Flight,
    level: Level,
    calibration: Option<Arc<Calibration>>,
) -> Result<Option<f64>, CheckError> {
    let setup = Setup {
        calibration,
        ..setup.clone()
    };
    match (f.kind, level) {
        (_, Level::Discrete) => mission(&setup, f, level, autopilot::lattice::Autopilot),
        (AirKind::Ctol(_), _) => mission(&setup, f, level, autopilot::ctol::Autopilot),
        (AirKind::Vtol(_), _) => mission(&setup, f, level, autopilot::vtol::Autopilot),
    }
}

fn mission<P>(setup: &Setup, f: &Flight, level: Level, pilot: P) -> Result<Option<f64>, CheckError>
where
    P: Actuator<Arena, Ev, Command = FlightCommand, Error = FlyError> + 'static,
{
    let name = air_key(f.kind);
    let err = |e: String| CheckError::Scenario {
        scenario: name.to_owned(),
        message: e,
    };
    let mut sim: Simulation<Tactical> = Simulation::new(setup.arena(), setup.seed);
    let legs = vec![Leg::Waypoints(f.points.clone())];
    let controller: Box<dyn Controller> = Box::new(FlightMission::new(legs, pilot));
    let id = sim
        .add_agent(name, controller)
        .map_err(|e| err(e.to_string()))?;
    let placed = match f.kind {
        AirKind::Ctol(k) => sim.env_mut().add_ctol(id, k, level, f.start, f.heading),
        AirKind::Vtol(k) => sim.env_mut().add_vtol(id, k, level, f.start, f.heading),
    };
    placed.map_err(|e| err(e.to_string()))?;
    sim.schedule(SimTime::ZERO, Target::Entity(id), Ev::Start)
        .map_err(|e| err(e.to_string()))?;
    let ((slow, _), _, _) = envelope(&setup.types, f.kind);
    let slow = slow.max(2.0);
    let length = features(setup, f).length_m;
    let limit = SimTime::from_secs_f64(3.0 * length / slow + 300.0);
    let mission = |s: &Simulation<Tactical>| {
        s.agent(id)
            .and_then(|c| c.as_any().downcast_ref::<FlightMission<P>>())
            .map(|m| (m.finished(), m.error.clone(), m.legs_done.first().copied()))
    };
    let crashed = |s: &Simulation<Tactical>| s.env().pose(id).is_none();
    sim.run(limit, |s| {
        crashed(s) || mission(s).is_none_or(|(done, e, _)| done || e.is_some())
    });
    match mission(&sim) {
        Some((_, Some(e), _)) => Err(err(e.to_string())),
        Some((_, None, done)) => Ok(done.map(|t| t.as_secs_f64())),
        None => Ok(None),
    }
}

/// Runs a calibration needs for `flights`: each at its concrete level and at the lattice,
/// uncalibrated and calibrated.
pub fn runs_needed(flights: &[Flight]) -> usize {
    3 * flights.len()
}

/// Flies every flight at `level` (or each at its concrete level, `None`) on `threads`
/// threads; the arrival times in order.
fn fly_all(
    setup: &Setup,
    flights: &[Flight],
    level: Option<Level>,
    cal: Option<Arc<Calibration>>,
    threads: usize,
    tick: &(dyn Fn() + Sync),
) -> Result<Vec<Option<f64>>, CheckError> {
    let out = par_map(
        flights,
        threads,
        |f| {
            fly(
                setup,
                f,
                level.unwrap_or(concrete_level(f.kind)),
                cal.clone(),
            )
        },
        tick,
    );
    if out.len() != flights.len() {
        return Err(CheckError::Scenario {
            scenario: "aircraft calibration".into(),
            message: "a flight's run failed".into(),
        });
    }
    out.into_iter().collect()
}

/// Fits every aircraft type of `flights` (see [`vitro_tactical::calibration::air`]) into `cal` (its `aircraft`
/// and `flights`, replaced), then flies every flight again on the calibrated lattice for
/// the residuals. `tick` is called after each run ([`runs_needed`] in all). Flights that
/// did not arrive at some level are left out.
pub fn calibrate_air(
    setup: &Setup,
    flights: &[Flight],
    cal: &mut Calibration,
    threads: usize,
    tick: &(dyn Fn() + Sync),
) -> Result<(), CheckError> {
    let feats: Vec<AirFeatures> = flights.iter().map(|f| features(setup, f)).collect();
    let concrete = fly_all(setup, flights, None, None, threads, tick)?;
    let before = fly_all(setup, flights, Some(Level::Discrete), None, threads, tick)?;
    let mut groups: BTreeMap<&'static str, Vec<usize>> = BTreeMap::new();
    for (i, f) in flights.iter().enumerate() {
        groups.entry(air_key(f.kind)).or_default().push(i);
    }
    cal.aircraft.clear();
    for (entity, idx) in &groups {
        let (mut x, mut y) = (Vec::new(), Vec::new());
        for &i in idx.iter().filter(|&&i| flights[i].fit) {
            let (Some(c), Some(_)) = (concrete[i], before[i]) else {
                continue;
            };
            // The calibrated lattice flies the predicted time itself (its own detours are
            // taken out by the effective speed): the target is the concrete time.
            x.push(feats[i].row());
            y.push(c);
        }
        let p = crate::fit::least_squares(&x, &y, [1.0, 0.0, 0.0, 0.0, 0.0]);
        cal.aircraft.push(AirFit {
            entity: (*entity).to_owned(),
            level: Level::Discrete.name().to_owned(),
            concrete: concrete_level(flights[idx[0]].kind).name().to_owned(),
            alpha: p[0],
            beta: p[1],
            kappa: p[2],
            gamma: p[3],
            delta: p[4],
            flights: x.len(),
            fit_residuals: Residuals::default(),
            held_out: Residuals::default(),
        });
    }
    let shared = Arc::new(cal.clone());
    let after = fly_all(
        setup,
        flights,
        Some(Level::Discrete),
        Some(shared),
        threads,
        tick,
    )?;
    cal.unfinished += [&concrete, &before, &after]
        .iter()
        .map(|v| v.iter().filter(|r| r.is_none()).count())
        .sum::<usize>();
    for fit in &mut cal.aircraft {
        let idx = &groups[fit.entity.as_str()];
        for (set, slot) in [(true, &mut fit.fit_residuals), (false, &mut fit.held_out)] {
            let (mut c, mut b, mut a) = (Vec::new(), Vec::new(), Vec::new());
            for &i in idx.iter().filter(|&&i| flights[i].fit == set) {
                if let (Some(ci), Some(bi), Some(ai)) = (concrete[i], before[i], after[i]) {
                    c.push(ci);
                    b.push(bi);
                    a.push(ai);
                }
            }
            *slot = Residuals::of(&c, &b, &a);
        }
    }
    cal.flights = flights
        .iter()
        .enumerate()
        .filter_map(|(i, f)| {
            Some(FlightRecord {
                entity: air_key(f.kind).to_owned(),
                set: if f.fit { "fit" } else { "held_out" }.into(),
                waypoints: f.points.len(),
                features: feats[i],
                concrete_s: concrete[i]?,
                before_s: before[i]?,
                after_s: after[i]?,
            })
        })
        .collect();
    Ok(())
}

/// The concrete level and the paired times: concrete, before, after.
type Paired = (Level, Vec<f64>, Vec<f64>, Vec<f64>);

/// How well the lattice predicts the continuous level per aircraft type on `flights`
/// (fresh ones), without and with `cal`: one [`Prediction`] per type that has a fit,
/// passing if the calibrated mean absolute error is within `tolerance_pct`. `tick` is
/// called after each run ([`runs_needed`] in all).
pub fn evaluate_air(
    setup: &Setup,
    cal: &Arc<Calibration>,
    flights: &[Flight],
    tolerance_pct: f64,
    threads: usize,
    tick: &(dyn Fn() + Sync),
) -> Result<Vec<Prediction>, CheckError> {
    let concrete = fly_all(setup, flights, None, None, threads, tick)?;
    let before = fly_all(setup, flights, Some(Level::Discrete), None, threads, tick)?;
    let after = fly_all(
        setup,
        flights,
        Some(Level::Discrete),
        Some(cal.clone()),
        threads,
        tick,
    )?;
    let mut groups: BTreeMap<&'static str, Paired> = BTreeMap::new();
    for (i, f) in flights.iter().enumerate() {
        if cal.air_fit(f.kind).is_none() {
            continue;
        }
        let g = groups.entry(air_key(f.kind)).or_insert((
            concrete_level(f.kind),
            Vec::new(),
            Vec::new(),
            Vec::new(),
        ));
        if let (Some(c), Some(b), Some(a)) = (concrete[i], before[i], after[i]) {
            g.1.push(c);
            g.2.push(b);
            g.3.push(a);
        }
    }
    Ok(groups
        .into_iter()
        .map(|(entity, (concrete, c, b, a))| {
            let residuals = Residuals::of(&c, &b, &a);
            Prediction {
                entity: entity.to_owned(),
                level: Level::Discrete,
                concrete,
                pass: residuals.n > 0 && residuals.mape_pct_after <= tolerance_pct,
                residuals,
                tolerance_pct,
            }
        })
        .collect())
}

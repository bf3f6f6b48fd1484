//! Aircraft at their levels: the coordinated turn, the helicopter's hover, and one mission
//! flown by both aircraft types at both levels.

// Measurements of the outcome (distances, angles, fits), not model code: platform math is
// allowed here (clippy.toml bans it where it could change a trace hash).
#![allow(clippy::disallowed_methods)]

mod common;

use common::{Samples, record, sim, start, town};
use std::sync::Arc;
use vitro::prelude::*;
use vitro_behaviour::route::{FlightMission, Leg};
use vitro_tactical::arena::{Arena, Ev};
use vitro_tactical::autopilot::{self, FlyError};
use vitro_tactical::entity::Level;
use vitro_tactical::entity::air::ctol::FlyCmd;
use vitro_tactical::model::{Controller, Tactical};
use vitro_tactical::types::{BUILTIN_TYPES, CtolKind, G, TypeBook, VtolKind};

/// Holds a constant yaw rate, flight path and airspeed.
struct Circle(FlyCmd);

impl Controller for Circle {
    fn handle(&mut self, input: Input<'_, Tactical>, cx: &mut Context<'_, Tactical>) {
        if let Input::Event(Ev::Start) = input {
            cx.act(&autopilot::ctol::FlyKinematic, self.0).unwrap();
        }
    }
}

/// Least-squares circle through points (Kåsa): centre and radius.
fn fit_circle(pts: &[[f64; 2]]) -> ([f64; 2], f64) {
    // Minimise Σ (x² + y² + D x + E y + F)²: least squares of [x y 1] · [D E F] = -(x²+y²).
    let a = nalgebra::DMatrix::from_fn(pts.len(), 3, |i, j| [pts[i][0], pts[i][1], 1.0][j]);
    let rhs = nalgebra::DVector::from_fn(pts.len(), |i, _| {
        -(pts[i][0] * pts[i][0] + pts[i][1] * pts[i][1])
    });
    let x = a
        .svd(true, true)
        .solve(&rhs, 1e-12)
        .expect("points not all on one line");
    let centre = [-x[0] / 2.0, -x[1] / 2.0];
    let r = (centre[0] * centre[0] + centre[1] * centre[1] - x[2]).sqrt();
    (centre, r)
}

#[test]
fn coordinated_turns_have_radius_v2_over_g_tan_bank() {
    // The test flies the kinematic model at 54.6 m/s, above the small Procerus airframe's
    // 25 m/s: the same model with the speed envelope widened.
    let text = BUILTIN_TYPES
        .replace("max_speed = 25.0", "max_speed = 60.0")
        .replace("max_bank_deg = 45.0", "max_bank_deg = 50.0");
    let types = Arc::new(TypeBook::from_toml(&text).unwrap());
    for (bank, expected) in [(30.0f64, 525.6), (45.0, 303.5)] {
        let (site, roads) = town();
        let mut s: Simulation<Tactical> =
            Simulation::new(Arena::with(site, roads, types.clone()), 1);
        let v = 54.6;
        let rate = G * bank.to_radians().tan() / v;
        let id = s
            .add_agent(
                "uav",
                Box::new(Circle(FlyCmd {
                    yaw_rate: rate,
                    flight_path: 0.0,
                    airspeed: v,
                })),
            )
            .unwrap();
        s.env_mut()
            .add_ctol(
                id,
                CtolKind::Procerus,
                Level::Kinematic,
                [2880.0, 2880.0, 800.0],
                0.0,
            )
            .unwrap();
        s.env_mut().ctol.update(id, |b| b.speed = v);
        start(&mut s, id);
        let period = 2.0 * std::f64::consts::PI / rate;
        let samples = record(&mut s, id, SimTime::from_secs_f64(10.0 + period));
        // After rolling in (under 1 s at 90°/s), one full circle.
        let pts: Vec<[f64; 2]> = samples
            .iter()
            .filter(|(t, _, _)| *t >= 10.0)
            .map(|(_, p, _)| [p[0], p[1]])
            .collect();
        assert!(pts.len() > 100);
        let (_, r) = fit_circle(&pts);
        println!(
            "bank {bank}: fitted radius {r:.2} m (formula {:.2} m)",
            v * v / (G * bank.to_radians().tan())
        );
        assert!(
            (r - expected).abs() <= 0.02 * expected,
            "bank {bank}: radius {r:.1} m, expected {expected} m"
        );
        // Level and at the commanded speed throughout.
        assert!(
            samples
                .iter()
                .all(|(_, p, sp)| (p[2] - 800.0).abs() < 1e-6 && (*sp - v).abs() < 1e-9)
        );
    }
}

/// Hovers at a point (a one-waypoint mission), for the disturbance test.
fn hover_at(kind: VtolKind, p: [f64; 3]) -> (Simulation<Tactical>, EntityId) {
    let mut s = sim(9);
    let mission = FlightMission::new(vec![Leg::Waypoints(vec![p])], autopilot::vtol::Autopilot);
    let id = s.add_agent("heli", Box::new(mission)).unwrap();
    s.env_mut()
        .add_vtol(id, kind, Level::Dynamic, p, 0.3)
        .unwrap();
    start(&mut s, id);
    (s, id)
}

#[test]
fn helicopters_hold_altitude_after_a_disturbance() {
    for kind in VtolKind::ALL {
        let p = [2500.0, 2600.0, 450.0];
        let (mut s, id) = hover_at(kind, p);
        s.run_until(SimTime::from_secs(10));
        // A gust: dropping at 4 m/s, rolled 15°, yawing at 0.5 rad/s, drifting at 3 m/s.
        s.env_mut().vtol.update(id, |b| {
            b.vel = [3.0, 0.0, -4.0];
            b.att[0] += 15f64.to_radians();
            b.rates[2] = 0.5;
        });
        let t0 = s.now().as_secs_f64();
        let samples: Samples = record(&mut s, id, SimTime::from_secs(70));
        let worst = samples
            .iter()
            .filter(|(t, _, _)| *t > t0)
            .map(|(_, q, _)| (q[2] - p[2]).abs())
            .fold(0.0, f64::max);
        println!("{kind:?}: worst altitude error after the gust {worst:.2} m");
        assert!(
            worst < 3.0,
            "{kind:?}: {worst:.2} m off the commanded altitude"
        );
        let (_, last, speed) = *samples.last().unwrap();
        assert!(
            (last[2] - p[2]).abs() < 0.2,
            "{kind:?}: settles at {last:?}"
        );
        assert!(speed < 0.2, "{kind:?}: still moving at {speed} m/s");
        let drift = ((last[0] - p[0]).powi(2) + (last[1] - p[1]).powi(2)).sqrt();
        assert!(drift < 2.0, "{kind:?}: {drift:.2} m from the hover point");
    }
}

/// A route over the town: four corners of a 1.2 km box, 120 m above the highest ground.
fn route() -> Vec<[f64; 3]> {
    let (site, _) = town();
    let c = site.offset;
    let corners = [
        [-600.0, -500.0],
        [600.0, -500.0],
        [600.0, 500.0],
        [-600.0, 500.0],
    ];
    let top = corners
        .iter()
        .filter_map(|d| site.ground([c[0] + d[0], c[1] + d[1]]))
        .fold(0.0, f64::max);
    corners
        .iter()
        .map(|d| [c[0] + d[0], c[1] + d[1], top + 120.0])
        .collect()
}

fn fly<P>(place: impl FnOnce(&mut Arena, EntityId), pilot: P) -> (Option<f64>, Samples, Vec<u32>)
where
    P: Actuator<Arena, Ev, Command = vitro_tactical::entity::air::FlightCommand, Error = FlyError>
        + 'static,
{
    let mut s = sim(2);
    let id = s
        .add_agent(
            "uav",
            Box::new(FlightMission::new(vec![Leg::Waypoints(route())], pilot)),
        )
        .unwrap();
    place(s.env_mut(), id);
    start(&mut s, id);
    let samples = record(&mut s, id, SimTime::from_secs(900));
    let m = s
        .agent(id)
        .and_then(|c| c.as_any().downcast_ref::<FlightMission<P>>())
        .unwrap();
    assert_eq!(m.error, None);
    let order: Vec<u32> = m.log.iter().map(|l| l.2).collect();
    (m.legs_done.first().map(|t| t.as_secs_f64()), samples, order)
}

#[test]
fn one_mission_flies_both_aircraft_types_at_both_levels() {
    let book = TypeBook::builtin();
    let start_at = |r: &[[f64; 3]]| [r[0][0] - 400.0, r[0][1], r[0][2]];
    let r = route();
    let p0 = start_at(&r);
    let ctol = book.ctol(CtolKind::Procerus);
    for level in [Level::Discrete, Level::Kinematic] {
        let pilot_run = |lvl: Level| match lvl {
            Level::Discrete => fly(
                |a, id| a.add_ctol(id, CtolKind::Procerus, lvl, p0, 0.0).unwrap(),
                autopilot::lattice::Autopilot,
            ),
            _ => fly(
                |a, id| a.add_ctol(id, CtolKind::Procerus, lvl, p0, 0.0).unwrap(),
                autopilot::ctol::Autopilot,
            ),
        };
        let (done, samples, order) = pilot_run(level);
        assert_eq!(order, [0, 1, 2, 3], "{level}");
        assert!(done.is_some());
        // It never flies slower than its minimum speed, nor jumps.
        assert!(
            samples.iter().all(|s| s.2 >= ctol.min_speed - 1e-9),
            "{level}"
        );
        for w in samples.windows(2) {
            let d = ((w[1].1[0] - w[0].1[0]).powi(2) + (w[1].1[1] - w[0].1[1]).powi(2)).sqrt();
            assert!(d <= ctol.max_speed * (w[1].0 - w[0].0) + 0.01);
        }
    }
    for kind in VtolKind::ALL {
        let ty = book.vtol(kind);
        for level in [Level::Discrete, Level::Dynamic] {
            let (done, samples, order) = match level {
                Level::Discrete => fly(
                    |a, id| a.add_vtol(id, kind, level, p0, 0.0).unwrap(),
                    autopilot::lattice::Autopilot,
                ),
                _ => fly(
                    |a, id| a.add_vtol(id, kind, level, p0, 0.0).unwrap(),
                    autopilot::vtol::Autopilot,
                ),
            };
            assert_eq!(order, [0, 1, 2, 3], "{kind:?} {level}");
            let done = done.unwrap();
            // Cruising between the waypoints at the commanded altitude.
            let worst = samples
                .iter()
                .map(|(_, p, _)| (p[2] - r[0][2]).abs())
                .fold(0.0, f64::max);
            assert!(worst < 3.0, "{kind:?} {level}: {worst} m off altitude");
            for w in samples.windows(2) {
                let d = ((w[1].1[0] - w[0].1[0]).powi(2) + (w[1].1[1] - w[0].1[1]).powi(2)).sqrt();
                assert!(d <= ty.max_speed * (w[1].0 - w[0].0) + 0.01);
            }
            println!("{kind:?} {level}: {done:.1} s");
        }
    }
}

/// A car driving across the town (interpolated), and one aircraft flying `legs` over it;
/// returns the plan distance from aircraft to car at every sample after `settle` seconds.
fn over_a_car<P>(
    place: impl FnOnce(&mut Arena, EntityId, [f64; 3]),
    legs: impl FnOnce(EntityId) -> Vec<Leg>,
    pilot: P,
    settle: f64,
) -> (Vec<f64>, FlightMission<P>)
where
    P: Actuator<Arena, Ev, Command = vitro_tactical::entity::air::FlightCommand, Error = FlyError>
        + Clone
        + 'static,
{
    use vitro_behaviour::route::VisitNodes;
    use vitro_tactical::actuate::ground::interpolated::GoToNode;
    use vitro_tactical::types::GroundKind;
    let (site, roads) = town();
    let e = site.map.extent;
    let a = roads
        .drive
        .nearest_connected([e[0] * 0.3, e[1] * 0.3])
        .unwrap();
    let b = roads
        .drive
        .nearest_connected([e[2] * 0.3, e[3] * 0.3])
        .unwrap();
    let mut s = sim(4);
    let car = s
        .add_agent("car", Box::new(VisitNodes::new(vec![b, a], GoToNode)))
        .unwrap();
    s.env_mut()
        .add_vehicle(car, GroundKind::Car, Level::Interpolated, a, 0.0)
        .unwrap();
    let at = s.env().pose(car).unwrap().pos;
    let uav = s
        .add_agent(
            "uav",
            Box::new(FlightMission::new(legs(car), pilot.clone())),
        )
        .unwrap();
    place(s.env_mut(), uav, [at[0] - 300.0, at[1], at[2] + 150.0]);
    // Both are bodies the UAV's camera can see (the car is the target it finds and follows:
    // the mission knows no other way where the car is).
    use vitro_tactical::condition::{Condition, Role};
    use vitro_tactical::world::Side;
    let cars = Condition::new(Role::Car, Side::Neutral, 1.5);
    s.env_mut().conditions.insert(car, cars);
    s.env_mut()
        .conditions
        .insert(uav, Condition::new(Role::Procerus, Side::Blue, 0.5));
    start(&mut s, car);
    start(&mut s, uav);
    let mut d = Vec::new();
    s.run(SimTime::from_secs(400), |s| {
        if s.now().as_secs_f64() > settle {
            let (p, q) = (
                s.env().pose(uav).unwrap().pos,
                s.env().pose(car).unwrap().pos,
            );
            d.push(((p[0] - q[0]).powi(2) + (p[1] - q[1]).powi(2)).sqrt());
        }
        false
    });
    let m = s
        .agent(uav)
        .and_then(|c| c.as_any().downcast_ref::<FlightMission<P>>())
        .unwrap()
        .clone();
    (d, m)
}

#[test]
fn loiter_circles_a_moving_car_and_loops_pass_over_it() {
    let loiter = |radius: f64| {
        move |car| {
            vec![Leg::Loiter {
                target: car,
                radius,
                height: 150.0,
                secs: 1e6,
            }]
        }
    };
    // Fixed-wing, kinematic: 150 m circles around the car while it drives at up to 50 km/h.
    let (d, m) = over_a_car(
        |a, id, p| {
            a.add_ctol(id, CtolKind::Procerus, Level::Kinematic, p, 0.0)
                .unwrap()
        },
        loiter(150.0),
        autopilot::ctol::Autopilot,
        60.0,
    );
    assert!(m.error.is_none());
    let (lo, hi) = d
        .iter()
        .fold((f64::MAX, 0.0f64), |(l, h), &x| (l.min(x), h.max(x)));
    println!("fixed-wing loiter: {lo:.0}..{hi:.0} m");
    assert!(
        lo > 50.0 && hi < 320.0,
        "fixed-wing loiter: {lo:.0}..{hi:.0} m"
    );
    // Helicopter, dynamic: the same mission code.
    let (d, m) = over_a_car(
        |a, id, p| {
            a.add_vtol(id, VtolKind::Skeldar, Level::Dynamic, p, 0.0)
                .unwrap()
        },
        loiter(100.0),
        autopilot::vtol::Autopilot,
        60.0,
    );
    assert!(m.error.is_none());
    let (lo, hi) = d
        .iter()
        .fold((f64::MAX, 0.0f64), |(l, h), &x| (l.min(x), h.max(x)));
    println!("helicopter loiter: {lo:.0}..{hi:.0} m");
    assert!(
        lo > 25.0 && hi < 250.0,
        "helicopter loiter: {lo:.0}..{hi:.0} m"
    );
    // Loops: passes over the car, each end 250 m beyond it.
    let (d, m) = over_a_car(
        |a, id, p| {
            a.add_ctol(id, CtolKind::Procerus, Level::Kinematic, p, 0.0)
                .unwrap()
        },
        |car| {
            vec![Leg::Loop {
                target: car,
                half_length: 250.0,
                axis: 0.0,
                height: 150.0,
                passes: 6,
            }]
        },
        autopilot::ctol::Autopilot,
        0.0,
    );
    assert!(m.finished() && m.error.is_none(), "{:?}", m.log);
    assert!(d.iter().any(|&x| x < 60.0), "never over the car");
}

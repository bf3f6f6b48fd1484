//! The environment's event handlers act only on the event they scheduled: a hop, a maneuver
//! or a clock tick that is stale or forged (here: scheduled by the harness, the only party
//! besides the environment that can still name the environment as a target) changes nothing.

mod common;

use common::{sim, start, town};
use vitro::prelude::*;
use vitro_behaviour::route::VisitNodes;
use vitro_tactical::actuate::ground::{discrete, interpolated};
use vitro_tactical::arena::{Clock, Ev};
use vitro_tactical::entity::Level;
use vitro_tactical::model::Controller;
use vitro_tactical::types::GroundKind;

/// A car from one side of the town to the other at `level`, with `forged` environment events
/// scheduled by the harness at the given times. Returns the arrival time (s) and where the car
/// is every 5 s.
fn drive(level: Level, forged: &[(f64, Ev)]) -> (Option<f64>, Vec<[f64; 3]>) {
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
    let mut s = sim(3);
    let ctl: Box<dyn Controller> = match level {
        Level::Discrete => Box::new(VisitNodes::new(vec![b], discrete::GoToNode)),
        _ => Box::new(VisitNodes::new(vec![b], interpolated::GoToNode)),
    };
    let car = s.add_agent("car", ctl).unwrap();
    s.env_mut()
        .add_vehicle(car, GroundKind::Car, level, a, 0.0)
        .unwrap();
    start(&mut s, car);
    for (t, ev) in forged {
        let ev = match ev {
            Ev::Hop(_) => Ev::Hop(car),
            other => other.clone(),
        };
        s.schedule(SimTime::from_secs_f64(*t), Target::Env, ev)
            .unwrap();
    }
    let mut track = Vec::new();
    for k in 1..=120 {
        s.run_until(SimTime::from_secs(5 * k));
        track.push(s.env().pose(car).map(|p| p.pos).unwrap_or([f64::NAN; 3]));
    }
    let arrival = s
        .agent(car)
        .and_then(|c| c.as_any().downcast_ref::<VisitNodes<discrete::GoToNode>>())
        .map(|v| v.log.last().map(|l| l.0.as_secs_f64()))
        .or_else(|| {
            s.agent(car)
                .and_then(|c| {
                    c.as_any()
                        .downcast_ref::<VisitNodes<interpolated::GoToNode>>()
                })
                .map(|v| v.log.last().map(|l| l.0.as_secs_f64()))
        })
        .flatten();
    (arrival, track)
}

#[test]
fn forged_hops_do_not_move_a_discrete_body() {
    let honest = drive(Level::Discrete, &[]);
    assert!(honest.0.is_some(), "the car arrives");
    // Ten forged hops while it drives: each would jump it one node ahead if obeyed.
    let forged: Vec<(f64, Ev)> = (0..10)
        .map(|i| (3.0 + 7.3 * f64::from(i), Ev::Hop(EntityId(0))))
        .collect();
    let attacked = drive(Level::Discrete, &forged);
    assert_eq!(honest, attacked);
}

#[test]
fn forged_ticks_do_not_step_a_clock_twice() {
    let honest = drive(Level::Interpolated, &[]);
    assert!(honest.0.is_some(), "the car arrives");
    let forged: Vec<(f64, Ev)> = (0..40)
        .map(|i| (1.05 + 2.5 * f64::from(i), Ev::Tick(Clock::Kinematic)))
        .collect();
    let attacked = drive(Level::Interpolated, &forged);
    assert_eq!(honest, attacked);
}

//! Ground vehicles at the discrete, interpolated and physical levels on the real town:
//! one controller (`VisitNodes`) over `GoToNode` at each level.

mod common;

use common::{Samples, plan_drive, record, sim, start, town};
use vitro::prelude::*;
use vitro_behaviour::route::VisitNodes;
use vitro_tactical::actuate::MoveError;
use vitro_tactical::actuate::ground::{discrete, interpolated, physical};
use vitro_tactical::arena::{Arena, Ev};
use vitro_tactical::entity::Level;
use vitro_tactical::entity::route::Track;
use vitro_tactical::model::{Controller, Tactical};
use vitro_tactical::types::{BUILTIN_TYPES, GroundKind, TypeBook};

/// Two connected nodes about 1.3 km apart across the town.
fn trip() -> (NodeId, NodeId) {
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
    (a, b)
}

fn plan(kind: GroundKind, a: NodeId, b: NodeId, types: &TypeBook) -> Track {
    let (_, roads) = town();
    let path = roads.drive.path(a, b).unwrap();
    plan_drive(&roads, &path, kind, types)
}

struct Run {
    arrival: Option<f64>,
    samples: Samples,
    hash: u64,
}

fn drive<A>(kind: GroundKind, level: Level, goto: A, seed: u64) -> Run
where
    A: Actuator<Arena, Ev, Command = NodeId, Error = MoveError> + 'static,
{
    let (a, b) = trip();
    let heading = plan(kind, a, b, TypeBook::builtin()).heading_at(0.0);
    let mut s = sim(seed);
    let id = s
        .add_agent("vehicle", Box::new(VisitNodes::new(vec![b], goto)))
        .unwrap();
    s.env_mut()
        .add_vehicle(id, kind, level, a, heading)
        .unwrap();
    start(&mut s, id);
    let samples = record(&mut s, id, SimTime::from_secs(1800));
    let v = s
        .agent(id)
        .and_then(|c| c.as_any().downcast_ref::<VisitNodes<A>>())
        .unwrap();
    assert_eq!(v.error, None);
    Run {
        arrival: v.log.last().filter(|l| l.1 == b).map(|l| l.0.as_secs_f64()),
        samples,
        hash: s.trace_hash(),
    }
}

fn assert_sound(run: &Run, vmax: f64) {
    let (site, _) = town();
    for w in run.samples.windows(2) {
        let ((t0, p0, _), (t1, p1, _)) = (w[0], w[1]);
        let jump = ((p1[0] - p0[0]).powi(2) + (p1[1] - p0[1]).powi(2)).sqrt();
        assert!(
            jump <= vmax * (t1 - t0) + 0.05,
            "jump {jump} m in {} s",
            t1 - t0
        );
    }
    for (t, p, _) in &run.samples {
        assert!(
            !site.is_forbidden([p[0], p[1]]),
            "forbidden at t = {t}: {p:?}"
        );
    }
}

#[test]
fn every_vehicle_arrives_at_every_level_near_the_discrete_estimate() {
    let (a, b) = trip();
    for kind in GroundKind::ALL {
        let ty = TypeBook::builtin().ground(kind);
        let est = plan(kind, a, b, TypeBook::builtin()).duration();
        let d = drive(kind, Level::Discrete, discrete::GoToNode, 1);
        let i = drive(kind, Level::Interpolated, interpolated::GoToNode, 1);
        let p = drive(kind, Level::Physical, physical::GoToNode, 1);
        let (td, ti, tp) = (d.arrival.unwrap(), i.arrival.unwrap(), p.arrival.unwrap());
        assert!((td - est).abs() < 1e-6, "{kind:?}: {td} vs {est}");
        assert!(
            (ti - est).abs() <= 0.02 * est + 1.0,
            "{kind:?}: {ti} vs {est}"
        );
        assert!(
            (tp - est).abs() <= 0.12 * est + 5.0,
            "{kind:?}: {tp} vs {est}"
        );
        // The physical vehicle may overshoot the street limit a little, never its type's
        // top speed; the others never jump.
        for r in [&d, &i, &p] {
            assert_sound(r, ty.max_speed());
        }
        // The physical body really is on the ground, moving.
        assert!(p.samples.iter().any(|s| s.2 > 5.0));
    }
}

#[test]
fn power_and_mass_set_travel_times() {
    let (a, b) = trip();
    let book = TypeBook::builtin();
    let car = plan(GroundKind::Car, a, b, book).duration();
    let truck = plan(GroundKind::CargoTruck, a, b, book).duration();
    let mdars = plan(GroundKind::Mdars, a, b, book).duration();
    assert!(car < truck && truck < mdars, "{car} {truck} {mdars}");
    // A truck with a quarter of the engine is slower on the same streets, and a heavier one
    // too.
    let weak = BUILTIN_TYPES.replace("power_kw = 216.0", "power_kw = 54.0");
    let weak = TypeBook::from_toml(&weak).unwrap();
    let slow = plan(GroundKind::CargoTruck, a, b, &weak).duration();
    assert!(slow > truck * 1.02, "{slow} vs {truck}");
    let heavy = BUILTIN_TYPES.replace("mass = 10000.0", "mass = 20000.0");
    let heavy = TypeBook::from_toml(&heavy).unwrap();
    let laden = plan(GroundKind::CargoTruck, a, b, &heavy).duration();
    assert!(laden > truck && laden < slow, "{laden} vs {truck}, {slow}");
}

#[test]
fn physical_level_is_reproducible_over_ten_runs() {
    let hashes: Vec<u64> = (0..10)
        .map(|_| drive(GroundKind::Mdars, Level::Physical, physical::GoToNode, 42).hash)
        .collect();
    assert!(hashes.iter().all(|&h| h == hashes[0]), "{hashes:x?}");
}

/// Asks for a goal, then at once for another.
struct Impatient<A> {
    goals: [NodeId; 2],
    goto: A,
    answers: Vec<Result<(), MoveError>>,
}

impl<A> Controller for Impatient<A>
where
    A: Actuator<Arena, Ev, Command = NodeId, Error = MoveError> + 'static,
{
    fn handle(&mut self, input: Input<'_, Tactical>, cx: &mut Context<'_, Tactical>) {
        if let Input::Event(Ev::Start) = input {
            for g in self.goals {
                let r = cx.act(&self.goto, g);
                self.answers.push(r);
            }
        }
    }
}

#[test]
fn a_vehicle_under_way_refuses_a_new_goal() {
    let (a, b) = trip();
    let mut s = sim(3);
    let id = s
        .add_agent(
            "car",
            Box::new(Impatient {
                goals: [b, a],
                goto: interpolated::GoToNode,
                answers: vec![],
            }),
        )
        .unwrap();
    s.env_mut()
        .add_vehicle(id, GroundKind::Car, Level::Interpolated, a, 0.0)
        .unwrap();
    let other = s
        .add_agent(
            "truck",
            Box::new(Impatient {
                goals: [b, b],
                goto: physical::GoToNode,
                answers: vec![],
            }),
        )
        .unwrap();
    s.env_mut()
        .add_vehicle(other, GroundKind::CargoTruck, Level::Discrete, a, 0.0)
        .unwrap();
    start(&mut s, id);
    start(&mut s, other);
    s.run_until(SimTime::from_secs(1));
    let car = s
        .agent(id)
        .and_then(|c| {
            c.as_any()
                .downcast_ref::<Impatient<interpolated::GoToNode>>()
        })
        .map(|c| c.answers.clone());
    assert_eq!(car, Some(vec![Ok(()), Err(MoveError::UnderWay(id))]));
    // A body at another level is not this actuator's.
    let truck = s
        .agent(other)
        .and_then(|c| c.as_any().downcast_ref::<Impatient<physical::GoToNode>>())
        .map(|c| c.answers.clone());
    assert_eq!(
        truck,
        Some(vec![
            Err(MoveError::NoBody(other)),
            Err(MoveError::NoBody(other))
        ])
    );
}

//! The physical level turns round as a driver would: the route to the rigid-body car's third
//! checkpoint starts behind it and it has a steering lock; it turns round and gets there.
//! The street leaves room to swing round forwards at full lock, so it gets there with its
//! recovery turned off too (a dead end too narrow for that is a stall with its reason:
//! `tests/bodies.rs`). (The guide's tutorial, part 2, drives this tour.)

use vitro::prelude::*;
use vitro_behaviour::route::VisitNodes;
use vitro_tactical::actuate::MoveError;
use vitro_tactical::actuate::ground::{discrete, physical};
use vitro_tactical::arena::{Arena, Ev, Recovery};
use vitro_tactical::entity::Level;
use vitro_tactical::entity::route::Track;
use vitro_tactical::model::Tactical;
use vitro_tactical::setup::Setup;
use vitro_tactical::types::GroundKind;

/// Drives the tour at `level` until the car is done or has an error; the controller.
fn tour<A>(setup: &Setup, level: Level, goto: A, recovery: Recovery) -> VisitNodes<A>
where
    A: Actuator<Arena, Ev, Command = NodeId, Error = MoveError> + Clone + 'static,
{
    let e = setup.site.map.extent;
    let node = |fx: f64, fy: f64| {
        let p = [e[0] + fx * (e[2] - e[0]), e[1] + fy * (e[3] - e[1])];
        setup.roads.drive.nearest_connected(p).unwrap()
    };
    let start = node(0.45, 0.45);
    let checkpoints = vec![node(0.5, 0.5), node(0.55, 0.55), node(0.6, 0.5)];
    let drive = &setup.roads.drive;
    let path = drive.path(start, checkpoints[0]).unwrap();
    let ty = setup.types.ground(GroundKind::Car);
    let heading = Track::plan_vehicle(&setup.site, drive, &path, ty, &setup.types.speed_limits)
        .unwrap()
        .heading_at(0.0);
    let mut sim = Simulation::<Tactical>::new(setup.arena(), setup.seed);
    sim.env_mut().steps.recovery = recovery;
    let car = sim
        .add_agent("car", Box::new(VisitNodes::new(checkpoints, goto)))
        .unwrap();
    sim.env_mut()
        .add_vehicle(car, GroundKind::Car, level, start, heading)
        .unwrap();
    sim.schedule(SimTime::ZERO, Target::Entity(car), Ev::Start)
        .unwrap();
    let brain = |s: &Simulation<Tactical>| {
        s.agent(car)
            .and_then(|c| c.as_any().downcast_ref::<VisitNodes<A>>())
            .cloned()
            .unwrap()
    };
    sim.run(SimTime::from_secs(600), |s| {
        let b = brain(s);
        b.finished() || b.error.is_some()
    });
    brain(&sim)
}

#[test]
fn a_car_that_cannot_turn_on_the_spot_turns_in_several_moves() {
    let setup = Setup::default_town().unwrap();
    // The discrete car turns on the spot at a junction: all three checkpoints.
    let d = tour(
        &setup,
        Level::Discrete,
        discrete::GoToNode,
        Recovery::default(),
    );
    assert!(d.finished() && d.error.is_none(), "{:?}", d.error);
    // The rigid-body car backs and turns round on the way to the third: all three too.
    let p = tour(
        &setup,
        Level::Physical,
        physical::GoToNode,
        Recovery::default(),
    );
    assert!(p.finished() && p.error.is_none(), "{:?}", p.error);
    assert_eq!(
        p.log.iter().map(|l| l.1).collect::<Vec<_>>(),
        d.log.iter().map(|l| l.1).collect::<Vec<_>>()
    );
}

#[test]
fn without_recovery_the_car_swings_round_forwards_where_the_street_leaves_room() {
    let setup = Setup::default_town().unwrap();
    let d = tour(
        &setup,
        Level::Discrete,
        discrete::GoToNode,
        Recovery::default(),
    );
    // No recovery: the route to the third checkpoint starts behind the car, which turns
    // towards it at full lock (pure pursuit of a point behind) and gets round in one swing.
    let off = Recovery {
        max_attempts: 0,
        ..Recovery::default()
    };
    let p = tour(&setup, Level::Physical, physical::GoToNode, off);
    assert!(p.finished() && p.error.is_none(), "{:?}", p.error);
    assert_eq!(
        p.log.iter().map(|l| l.1).collect::<Vec<_>>(),
        d.log.iter().map(|l| l.1).collect::<Vec<_>>()
    );
}

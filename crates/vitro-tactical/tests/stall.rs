//! The physical level fails honestly: a rigid-body car that cannot make its way (here: the
//! route to its third checkpoint starts behind it, and it has a steering lock) gives the
//! trip up after the arena's stall time and tells its controller, instead of creeping for
//! ever towards an arrival that cannot come. (The guide's tutorial, part 2, drives this tour.)

use vitro::prelude::*;
use vitro_tactical::actuate::MoveError;
use vitro_tactical::actuate::ground::{discrete, physical};
use vitro_tactical::arena::{Arena, Ev};
use vitro_tactical::behaviour::route::VisitNodes;
use vitro_tactical::check::Setup;
use vitro_tactical::entity::Level;
use vitro_tactical::entity::route::Track;
use vitro_tactical::model::Tactical;
use vitro_tactical::types::GroundKind;

/// Drives the tour at `level` until the car is done or has an error; the controller.
fn tour<A>(setup: &Setup, level: Level, goto: A) -> VisitNodes<A>
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
fn a_car_that_cannot_turn_gives_its_trip_up_and_says_so() {
    let setup = Setup::default_town().unwrap();
    // The discrete car turns on the spot at a junction: all three checkpoints.
    let d = tour(&setup, Level::Discrete, discrete::GoToNode);
    assert!(d.finished() && d.error.is_none(), "{:?}", d.error);
    // The rigid-body car reaches the first two, then stalls on the third, and is told so
    // within the stall time (30 s) of its last progress, long before the 600 s limit.
    let p = tour(&setup, Level::Physical, physical::GoToNode);
    assert_eq!(p.log.len(), 2, "{:?}", p.log);
    let third = d.log[2].1;
    assert!(
        matches!(p.error, Some(MoveError::Stalled(_, n)) if n == third),
        "{:?}",
        p.error
    );
}

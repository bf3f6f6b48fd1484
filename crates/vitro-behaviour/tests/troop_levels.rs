//! Troopers at the discrete and directed levels on the real town: one controller
//! (`VisitNodes`) over `WalkToNode` at each level; walking speed from the carried load.

mod common;

use common::{Samples, record, sim, start, town};
use vitro::prelude::*;
use vitro_behaviour::route::VisitNodes;
use vitro_tactical::actuate::MoveError;
use vitro_tactical::actuate::troop::{directed, discrete};
use vitro_tactical::arena::{Arena, Ev};
use vitro_tactical::entity::Level;
use vitro_tactical::entity::route::Track;
use vitro_tactical::types::{TroopKind, TypeBook};

fn trip() -> (NodeId, NodeId) {
    let (site, roads) = town();
    let e = site.map.extent;
    let a = roads.walk.nearest_connected([e[0] * 0.2, 0.0]).unwrap();
    let b = roads
        .walk
        .nearest_connected([e[2] * 0.2, e[3] * 0.2])
        .unwrap();
    (a, b)
}

fn walk<A>(kind: TroopKind, level: Level, goto: A) -> (Option<f64>, Samples)
where
    A: Actuator<Arena, Ev, Command = NodeId, Error = MoveError> + 'static,
{
    let (a, b) = trip();
    let mut s = sim(5);
    let id = s
        .add_agent("trooper", Box::new(VisitNodes::new(vec![b], goto)))
        .unwrap();
    s.env_mut().add_trooper(id, kind, level, a, 0.0).unwrap();
    start(&mut s, id);
    let samples = record(&mut s, id, SimTime::from_secs(4 * 3600));
    let v = s
        .agent(id)
        .and_then(|c| c.as_any().downcast_ref::<VisitNodes<A>>())
        .unwrap();
    assert_eq!(v.error, None);
    (v.log.last().map(|l| l.0.as_secs_f64()), samples)
}

#[test]
fn heavier_loads_walk_slower() {
    let (a, b) = trip();
    let (site, roads) = town();
    let book = TypeBook::builtin();
    let path = roads.walk.path(a, b).unwrap();
    let t = |k: TroopKind| {
        Track::plan_walk(
            &site,
            &roads.walk,
            &path,
            &book.troops,
            book.troops.of(k).load,
        )
        .unwrap()
        .duration()
    };
    let (blue, red, vip) = (t(TroopKind::Blue), t(TroopKind::Red), t(TroopKind::Vip));
    assert!(blue > red && red > vip, "{blue} {red} {vip}");
    // No faster than the unloaded speed on the level.
    let len = Track::plan_walk(&site, &roads.walk, &path, &book.troops, 0.0)
        .unwrap()
        .length();
    assert!(vip >= len / book.troops.unloaded_speed - 1e-6);
}

#[test]
fn directed_troopers_arrive_near_the_discrete_estimate_and_stay_free() {
    let (site, _) = town();
    let book = TypeBook::builtin();
    for kind in TroopKind::ALL {
        let (td, d) = walk(kind, Level::Discrete, discrete::WalkToNode);
        let (tr, r) = walk(kind, Level::Directed, directed::WalkToNode);
        let (td, tr) = (td.unwrap(), tr.unwrap());
        // Turning on the spot at corners costs a little time, never much.
        assert!(
            tr >= td - 1.0 && tr <= 1.02 * td + 2.0,
            "{kind:?}: {tr} vs {td}"
        );
        for samples in [&d, &r] {
            for w in samples.windows(2) {
                let ((t0, p0, _), (t1, p1, _)) = (w[0], w[1]);
                let jump = ((p1[0] - p0[0]).powi(2) + (p1[1] - p0[1]).powi(2)).sqrt();
                assert!(jump <= book.troops.unloaded_speed * (t1 - t0) + 0.01);
            }
            assert!(
                samples
                    .iter()
                    .all(|(_, p, _)| !site.is_forbidden([p[0], p[1]]))
            );
        }
    }
}

#[test]
fn a_directed_trip_starts_where_the_body_stands() {
    // A body steered off its last node (by MoveAndTurn alone, as a formation slot does)
    // starts its next trip from the walk node nearest it, not from the stale last node:
    // it takes as long as a trooper that started there, not the whole way.
    let (a, b) = trip();
    let (site, roads) = town();
    let path = roads.walk.path(a, b).unwrap();
    let m = path[path.len() / 2];
    let at_m = site.street_point(vitro_site::map::Mode::Walk, m).unwrap();
    let trip_time = |start: NodeId, moved: Option<[f64; 3]>| {
        let mut s = sim(5);
        let id = s
            .add_agent(
                "trooper",
                Box::new(VisitNodes::new(vec![b], directed::WalkToNode)),
            )
            .unwrap();
        s.env_mut()
            .add_trooper(id, TroopKind::Blue, Level::Directed, start, 0.0)
            .unwrap();
        if let Some(p) = moved {
            s.env_mut().walkers.update(id, |w| w.pos = p);
        }
        common::start(&mut s, id);
        record(&mut s, id, SimTime::from_secs(4 * 3600));
        let v = s
            .agent(id)
            .and_then(|c| {
                c.as_any()
                    .downcast_ref::<VisitNodes<directed::WalkToNode>>()
            })
            .unwrap();
        assert_eq!(v.error, None);
        v.log.last().map(|l| l.0.as_secs_f64()).expect("it arrived")
    };
    let whole = trip_time(a, None);
    let from_m = trip_time(m, None);
    let steered = trip_time(a, Some(at_m));
    assert!(from_m < 0.8 * whole, "{from_m} s of {whole} s");
    assert!(
        (steered - from_m).abs() <= 0.05 * from_m + 10.0,
        "steered to the middle: {steered} s; from the middle {from_m} s, the whole way {whole} s"
    );
}

//! Bodies that make their way where a driver would: a vehicle started facing into a dead end
//! arrives, at the interpolated and the physical level (at the physical one by swinging
//! round forwards where there is room, and by backing and turning in several moves where
//! there is not; with recovery turned off it gives the trip up there instead); a truck
//! turned off its way with room to swing round makes no manoeuvre; two vehicles nose to nose
//! on one street both arrive; a UGV parked on the truck's route holds it up briefly.

mod common;

use common::{sim, start, town};
use vitro::prelude::*;
use vitro_behaviour::route::VisitNodes;
use vitro_site::geo::dist;
use vitro_tactical::actuate::MoveError;
use vitro_tactical::actuate::by_level::Drive;
use vitro_tactical::arena::{Recovery, StallReason};
use vitro_tactical::entity::Level;
use vitro_tactical::model::Tactical;
use vitro_tactical::types::GroundKind;

/// One vehicle to drive: its type, start node, heading and goal.
#[derive(Clone)]
struct Trip {
    kind: GroundKind,
    from: NodeId,
    heading: f64,
    to: NodeId,
}

/// Drives `trips` together at `level` for at most `limit` seconds; each vehicle's
/// controller after the run.
fn drive(level: Level, trips: &[Trip], recovery: Recovery, limit: u64) -> Vec<VisitNodes<Drive>> {
    let mut s = sim(1);
    s.env_mut().steps.recovery = recovery;
    let mut ids = Vec::new();
    for (i, t) in trips.iter().enumerate() {
        let id = s
            .add_agent(
                format!("vehicle{i}"),
                Box::new(VisitNodes::new(vec![t.to], Drive(level))),
            )
            .unwrap();
        s.env_mut()
            .add_vehicle(id, t.kind, level, t.from, t.heading)
            .unwrap();
        start(&mut s, id);
        ids.push(id);
    }
    let brains = |s: &Simulation<Tactical>| -> Vec<VisitNodes<Drive>> {
        ids.iter()
            .map(|&id| {
                s.agent(id)
                    .and_then(|c| c.as_any().downcast_ref::<VisitNodes<Drive>>())
                    .cloned()
                    .unwrap()
            })
            .collect()
    };
    s.run(SimTime::from_secs(limit), |s| {
        brains(s).iter().all(|b| b.finished() || b.error.is_some())
    });
    brains(&s)
}

/// The first four dead ends of the main street graph (in node order) whose one street runs
/// at least 30 m before the next junction, each with that junction.
fn dead_ends() -> Vec<(NodeId, NodeId)> {
    let (_, roads) = town();
    let g = &roads.drive;
    (0..g.graph.node_count() as u32)
        .map(NodeId)
        .filter(|&n| g.main[n.0 as usize] && g.degree(n) == 1)
        .filter_map(|n| {
            let m = g.graph.neighbors(n).next()?.0;
            let (a, b) = (g.graph.node(n)?.pos, g.graph.node(m)?.pos);
            (dist(a, b) >= 30.0).then_some((n, m))
        })
        .take(4)
        .collect()
}

/// A vehicle at the end of a dead end, facing on into it (away from the only way out), sent
/// to the town's centre.
fn into_the_dead_end(kind: GroundKind, (end, junction): (NodeId, NodeId)) -> Trip {
    let (site, roads) = town();
    let g = &roads.drive;
    let (a, b) = (
        g.graph.node(junction).unwrap().pos,
        g.graph.node(end).unwrap().pos,
    );
    let e = site.map.extent;
    let centre = g
        .nearest_connected([(e[0] + e[2]) / 2.0, (e[1] + e[3]) / 2.0])
        .unwrap();
    Trip {
        kind,
        from: end,
        heading: libm::atan2(b[1] - a[1], b[0] - a[0]),
        to: centre,
    }
}

/// Recovery turned off.
fn off() -> Recovery {
    Recovery {
        max_attempts: 0,
        ..Recovery::default()
    }
}

#[test]
fn a_vehicle_started_facing_into_a_dead_end_arrives() {
    let ends = dead_ends();
    assert_eq!(ends.len(), 4);
    for kind in [GroundKind::Car, GroundKind::Mdars] {
        for &end in &ends {
            let trip = into_the_dead_end(kind, end);
            for level in [Level::Interpolated, Level::Physical] {
                let v = &drive(level, std::slice::from_ref(&trip), Recovery::default(), 900)[0];
                assert!(
                    v.finished() && v.error.is_none(),
                    "{kind:?} in the dead end at {:?}, {} level: {:?}",
                    end.0,
                    level.name(),
                    v.error
                );
            }
        }
    }
}

#[test]
fn without_recovery_a_dead_end_too_narrow_to_swing_round_in_is_a_stall_with_its_reason() {
    // Where the dead end leaves room, the car swings round forwards as it would anyway; in
    // at least one of the four it cannot, and without recovery it gives the trip up.
    let stalls = dead_ends()
        .into_iter()
        .map(|end| into_the_dead_end(GroundKind::Car, end))
        .filter(|trip| {
            let v = &drive(Level::Physical, std::slice::from_ref(trip), off(), 900)[0];
            matches!(
                v.error,
                Some(MoveError::Stalled(_, n, StallReason::NoProgress)) if n == trip.to
            )
        })
        .count();
    assert!(stalls >= 1, "no dead end needed a recovery");
}

/// The standard trip across town (the check's) and the nodes of its path.
fn across_town() -> Vec<NodeId> {
    let (site, roads) = town();
    let e = site.map.extent;
    let a = roads
        .drive
        .nearest_connected([e[0] * 0.6, e[1] * 0.6])
        .unwrap();
    let b = roads
        .drive
        .nearest_connected([e[2] * 0.6, e[3] * 0.6])
        .unwrap();
    roads.drive.path(a, b).unwrap()
}

/// Heading from node `a` to node `b` of the drive graph.
fn heading(a: NodeId, b: NodeId) -> f64 {
    let (_, roads) = town();
    let g = &roads.drive.graph;
    let (p, q) = (g.node(a).unwrap().pos, g.node(b).unwrap().pos);
    libm::atan2(q[1] - p[1], q[0] - p[0])
}

#[test]
fn two_vehicles_started_nose_to_nose_on_one_street_both_arrive() {
    let (_, roads) = town();
    let g = &roads.drive.graph;
    let path = across_town();
    // The first street of the trip at least 60 m long, driven both ways.
    let i = (1..path.len() - 2)
        .find(|&i| {
            let (p, q) = (
                g.node(path[i]).unwrap().pos,
                g.node(path[i + 1]).unwrap().pos,
            );
            dist(p, q) >= 60.0
                && roads.drive.path(path[i + 1], path[0]).unwrap().get(1) == Some(&path[i])
        })
        .expect("a long street on the trip");
    let (a, b) = (path[i], path[i + 1]);
    let trips = [
        Trip {
            kind: GroundKind::Car,
            from: a,
            heading: heading(a, b),
            to: *path.last().unwrap(),
        },
        Trip {
            kind: GroundKind::Car,
            from: b,
            heading: heading(b, a),
            to: path[0],
        },
    ];
    for level in [Level::Interpolated, Level::Physical] {
        for (k, v) in drive(level, &trips, Recovery::default(), 1200)
            .iter()
            .enumerate()
        {
            assert!(
                v.finished() && v.error.is_none(),
                "vehicle {k} at the {} level: {:?}",
                level.name(),
                v.error
            );
        }
    }
}

#[test]
fn a_ugv_parked_on_the_trucks_route_holds_it_up_less_than_a_minute() {
    let path = across_town();
    let truck = Trip {
        kind: GroundKind::CargoTruck,
        from: path[0],
        heading: heading(path[0], path[1]),
        to: *path.last().unwrap(),
    };
    // The UGV holds at the second junction of the truck's route, facing along it.
    let ugv = Trip {
        kind: GroundKind::Mdars,
        from: path[2],
        heading: heading(path[2], path[3]),
        to: path[2],
    };
    for level in [Level::Interpolated, Level::Physical] {
        let alone = &drive(
            level,
            std::slice::from_ref(&truck),
            Recovery::default(),
            1800,
        )[0];
        let with = &drive(
            level,
            &[truck.clone(), ugv.clone()],
            Recovery::default(),
            1800,
        )[0];
        let t = |v: &VisitNodes<Drive>| v.log.last().map(|l| l.0.as_secs_f64());
        let (Some(t0), Some(t1)) = (t(alone), t(with)) else {
            panic!(
                "{} level: {:?} / {:?}",
                level.name(),
                alone.error,
                with.error
            );
        };
        assert!(
            with.error.is_none() && t1 <= t0 + 60.0,
            "{} level: {t1} s with the UGV, {t0} s alone, {:?}",
            level.name(),
            with.error
        );
    }
}

#[test]
fn a_truck_turned_off_its_way_with_room_to_swing_round_makes_no_manoeuvre() {
    // Started at a right angle to its way, either side, on the standard trip's first street:
    // the truck swings wide onto it, and arrives when it would with its recovery turned off
    // (it backed or turned in several moves on none of the trips).
    let path = across_town();
    let h = heading(path[0], path[1]);
    for turn in [std::f64::consts::FRAC_PI_2, -std::f64::consts::FRAC_PI_2] {
        let trip = Trip {
            kind: GroundKind::CargoTruck,
            from: path[0],
            heading: h + turn,
            to: *path.last().unwrap(),
        };
        let t = |recovery| {
            let v = &drive(Level::Physical, std::slice::from_ref(&trip), recovery, 1800)[0];
            assert!(v.finished() && v.error.is_none(), "{turn}: {:?}", v.error);
            v.log.last().map(|l| l.0)
        };
        assert_eq!(t(Recovery::default()), t(off()), "start turn {turn} rad");
    }
}

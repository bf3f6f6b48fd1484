//! Planned tracks on the real town are the same bits however they are built: from the
//! shared stretches of street ([`vitro_tactical::entity::stretch`]) cold or warm, and as the
//! point-by-point planner made them before (a frozen hash).

mod common;

use common::{plan_drive, town};
use vitro::env::NodeId;
use vitro::trace::TraceHasher;
use vitro_tactical::entity::roads::Roads;
use vitro_tactical::entity::route::{Track, dist3};
use vitro_tactical::types::{GroundKind, TypeBook};

/// Trips between spread-out connected nodes of `mode`'s free graph.
fn trips(roads: &vitro_tactical::entity::roads::FreeGraph, n: usize) -> Vec<Vec<NodeId>> {
    let nodes: Vec<NodeId> = (0..roads.main.len() as u32)
        .map(NodeId)
        .filter(|n| roads.main[n.0 as usize])
        .collect();
    let step = (nodes.len() / (2 * n)).max(1);
    (0..n)
        .filter_map(|k| {
            let a = nodes[(k * step) % nodes.len()];
            let b = nodes[(nodes.len() / 2 + 3 * k * step) % nodes.len()];
            roads.path(a, b).ok().filter(|p| p.len() > 1)
        })
        .collect()
}

/// The tracks of a set of car and walking trips, each planned on `roads` twice.
fn tracks(roads: &Roads) -> Vec<Track> {
    let (site, _) = town();
    let types = TypeBook::builtin();
    let mut out = Vec::new();
    for path in trips(&roads.drive, 12) {
        for kind in [GroundKind::Car, GroundKind::CargoTruck] {
            let plan = || plan_drive(roads, &path, kind, types);
            let cold = plan();
            assert_eq!(cold, plan(), "a warm plan differs from the cold one");
            out.push(cold);
        }
    }
    for path in trips(&roads.walk, 6) {
        let walk = Track::plan_walk(&site, &roads.walk, &path, &types.troops, 20.0).unwrap();
        out.push(walk);
    }
    out
}

#[test]
fn tracks_are_the_same_bits_cold_warm_and_as_before() {
    let (site, shared) = town();
    let fresh = Roads::new(&site);
    let (a, b) = (tracks(&fresh), tracks(&shared));
    assert_eq!(a, b, "fresh and shared roads plan different tracks");
    assert!(a.len() >= 20, "only {} tracks", a.len());
    let mut h = TraceHasher::default();
    for t in &a {
        assert!(t.pts.len() > 10);
        // Each distance is the previous one plus the piece's length, in order.
        for i in 1..t.pts.len() {
            assert_eq!(
                t.s[i].to_bits(),
                (t.s[i - 1] + dist3(t.pts[i - 1], t.pts[i])).to_bits()
            );
        }
        h.digest(t);
    }
    // Frozen from the point-by-point planner (before stretches): every bit of every track.
    assert_eq!(h.finish(), 8579209668051703109);
}

#[test]
fn a_one_node_path_is_a_track_at_rest_there() {
    let (site, roads) = town();
    let types = TypeBook::builtin();
    let node = (0..roads.drive.main.len() as u32)
        .map(NodeId)
        .find(|n| roads.drive.main[n.0 as usize])
        .unwrap();
    let car = plan_drive(&roads, &[node], GroundKind::Car, types);
    assert_eq!((car.pts.len(), car.length(), car.duration()), (1, 0.0, 0.0));
    assert_eq!(car.goal(), Some(node));
    let walk = Track::plan_walk(&site, &roads.walk, &[node], &types.troops, 20.0).unwrap();
    assert_eq!((walk.pts.len(), walk.duration()), (1, 0.0));
    // And no path at all: an empty track.
    assert_eq!(plan_drive(&roads, &[], GroundKind::Car, types).pts.len(), 0);
}

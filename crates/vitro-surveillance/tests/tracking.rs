//! Tracking is honest: a UAV's lock rests on its own camera only. Every fresh fix is of a
//! target the camera can physically see (range, line of sight past buildings and
//! terrain); a red unit out of the cameras' range is never tracked, however long the run.

mod common;

use common::{build, run_to, scenario, set, uavs};
use toml::Value;
use vitro::time::SimTime;
use vitro_tactical::world::Body;

/// The body friend-or-foe vision looks at, from the umpire's view of the arena.
fn body(op: &vitro_surveillance::SurveillanceRun, id: vitro::entity::EntityId) -> Option<Body> {
    let w = op.sim.env();
    let c = w.conditions.get(id)?;
    let p = w.pose(id)?;
    Some(Body::new(p.pos, p.heading, c.side, c.height))
}

#[test]
fn every_fresh_fix_is_of_a_target_in_plain_sight() {
    let mut t = scenario();
    set(&mut t, "end.time_s", Value::Float(600.0));
    let mut op = build(&t, 11);
    let vision = op.team.tracking.vision;
    let site = op.team.site.clone();
    let mut fixes = 0;
    for s in 1..=600 {
        run_to(&mut op, s);
        let now = SimTime::from_secs(s);
        for (name, u) in uavs(&op) {
            let id = op
                .members
                .iter()
                .find(|m| m.name == name)
                .map(|m| m.id)
                .unwrap();
            for l in u.locks().filter(|l| l.seen_at == now) {
                let (me, target) = (body(&op, id).unwrap(), body(&op, l.target).unwrap());
                assert!(
                    vision.can_see(&site, &me, &target),
                    "{name} has a fresh fix of #{} it cannot see at {s} s",
                    l.target.0
                );
                assert_eq!(l.pos, target.pos, "a fix is where the target is");
                fixes += 1;
            }
        }
    }
    assert!(fixes > 50, "the UAVs saw something ({fixes} fixes)");
}

#[test]
fn red_units_out_of_range_are_never_tracked() {
    let mut t = scenario();
    // The UAVs fly 120 m up; a 100 m camera reaches nobody on the ground.
    set(&mut t, "sensors.camera.range_m", Value::Float(100.0));
    set(&mut t, "end.time_s", Value::Float(900.0));
    let mut op = build(&t, 11);
    let m = op.run();
    assert_eq!(m.red_detected, 0);
    assert_eq!(m.mean_tracked_share, 0.0);
    assert_eq!(m.mean_time_to_detection_s, None);
    assert!(uavs(&op).iter().all(|(_, u)| u.spans.is_empty()));
}

#[test]
fn a_working_camera_finds_and_follows_red_units() {
    let mut t = scenario();
    set(&mut t, "end.time_s", Value::Float(900.0));
    let mut op = build(&t, 11);
    let m = op.run();
    assert!(m.red_detected >= 4, "{m:?}");
    assert!(m.mean_tracked_share > 0.05, "{m:?}");
    let t = m.mean_time_to_detection_s.unwrap();
    assert!(t > 0.0 && t < 900.0);
    // Each red unit's record agrees with the means.
    let shares: f64 = m.red.values().map(|r| r.tracked_share).sum();
    assert!((shares / f64::from(m.red_units) - m.mean_tracked_share).abs() < 1e-12);
}

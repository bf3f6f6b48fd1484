//! Aircraft that fly into the ground or into a building crash: an outcome, not a body
//! flying on under the terrain or through walls. A helicopter sent to a point 50 m below the
//! ground, or into the middle of a building, goes down (its condition `Down`, its body gone,
//! so nothing waits on it for ever); one sent to a point 50 m above the ground flies there
//! and hovers.

mod common;

use common::{sim, start};
use vitro::prelude::*;
use vitro_behaviour::route::{FlightMission, Leg};
use vitro_tactical::autopilot;
use vitro_tactical::condition::{Condition, Role, Status};
use vitro_tactical::entity::Level;
use vitro_tactical::types::VtolKind;
use vitro_tactical::world::Side;

/// A Skeldar 100 m above the town's centre sent to `to` (world x, y and the height above
/// the ground there): its status and whether it still has a body after 200 s.
fn fly_to(to: [f64; 3]) -> (Option<Status>, bool) {
    let mut s = sim(5);
    let c = s.env().site.offset;
    let ground = |x: f64, y: f64| s.env().site.ground([x, y]).expect("on the terrain");
    let from = [c[0], c[1], ground(c[0], c[1]) + 100.0];
    let to = [to[0], to[1], ground(to[0], to[1]) + to[2]];
    let mission = FlightMission::new(vec![Leg::Waypoints(vec![to])], autopilot::vtol::Autopilot);
    let id = s.add_agent("heli", Box::new(mission)).unwrap();
    s.env_mut()
        .add_vtol(id, VtolKind::Skeldar, Level::Dynamic, from, 0.0)
        .unwrap();
    let body = Condition::new(Role::Skeldar, Side::Blue, 0.5);
    s.env_mut().conditions.insert(id, body);
    start(&mut s, id);
    s.run_until(SimTime::from_secs(200));
    let status = s.env().conditions.get(id).map(|c| c.status);
    (status, s.env().pose(id).is_some())
}

#[test]
fn a_helicopter_flown_into_the_ground_or_a_building_crashes() {
    let s = sim(5);
    let c = s.env().site.offset;
    let east = |h: f64| [c[0] + 300.0, c[1], h];
    assert_eq!(fly_to(east(50.0)), (Some(Status::Active), true));
    assert_eq!(fly_to(east(-50.0)), (Some(Status::Down), false));
    // The tallest building within 400 m of the start: into its middle, half way up.
    let site = &s.env().site;
    let b = site
        .map
        .buildings
        .iter()
        .filter(|b| {
            let p = site.to_world(b.footprint.centroid());
            (p[0] - c[0]).abs() < 400.0 && (p[1] - c[1]).abs() < 400.0
        })
        .max_by(|a, b| a.height.total_cmp(&b.height))
        .expect("a building near the centre");
    assert!(b.height >= 6.0, "a building of {} m", b.height);
    let p = site.to_world(b.footprint.centroid());
    assert!(
        b.footprint.contains(b.footprint.centroid()),
        "a convex enough footprint"
    );
    assert_eq!(
        fly_to([p[0], p[1], b.height / 2.0]),
        (Some(Status::Down), false)
    );
}

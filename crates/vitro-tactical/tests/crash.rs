//! Aircraft that fly into the ground crash: an outcome, not a body flying on under the
//! terrain. A helicopter sent to a point 50 m below the ground goes down (its condition
//! `Down`, its body gone, so nothing waits on it for ever); one sent to a point 50 m above
//! the ground flies there and hovers.

mod common;

use common::{sim, start};
use vitro::prelude::*;
use vitro_tactical::autopilot;
use vitro_tactical::behaviour::route::{FlightMission, Leg};
use vitro_tactical::condition::{Condition, Role, Status};
use vitro_tactical::entity::Level;
use vitro_tactical::types::VtolKind;
use vitro_tactical::world::Side;

/// A Skeldar 100 m above the town's centre sent to a point 300 m east, `above` metres
/// above the ground there: its status and whether it still has a body after 200 s.
fn fly_to(above: f64) -> (Option<Status>, bool) {
    let mut s = sim(5);
    let c = s.env().site.offset;
    let ground = |x: f64, y: f64| s.env().site.ground([x, y]).expect("on the terrain");
    let from = [c[0], c[1], ground(c[0], c[1]) + 100.0];
    let to = [c[0] + 300.0, c[1], ground(c[0] + 300.0, c[1]) + above];
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
fn a_helicopter_flown_into_the_ground_crashes() {
    assert_eq!(fly_to(50.0), (Some(Status::Active), true));
    assert_eq!(fly_to(-50.0), (Some(Status::Down), false));
}

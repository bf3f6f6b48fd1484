//! The tracking sensor in an arena: a lock is held only while the owner's own camera sees
//! the target (a building in the way, the range, the owner's own state).

use std::sync::Arc;
use vitro::entity::EntityId;
use vitro::env::{Probe, Sensor};
use vitro::rng::RngStreams;
use vitro::time::SimTime;
use vitro_site::geo::Polygon;
use vitro_site::map::{Building, TownMap};
use vitro_site::site::{Site, SiteConfig};
use vitro_site::terrain::Terrain;
use vitro_tactical::arena::Arena;
use vitro_tactical::condition::{Condition, Role, Status};
use vitro_tactical::entity::Level;
use vitro_tactical::sensor::FriendFoeVision;
use vitro_tactical::sensor::track::{Look, TrackConfig, TrackEvent, Tracker};
use vitro_tactical::types::VtolKind;
use vitro_tactical::world::Side;

const ME: EntityId = EntityId(0);
const RED: EntityId = EntityId(1);

/// A flat 1 km square with one 20 x 20 x 10 m building at the world point (500, 500); a
/// helicopter of ours at (400, 500), 5 m up, and a red one at `red`.
fn arena(red: [f64; 3]) -> Arena {
    let footprint = Polygon::new(
        vec![[-10.0, -10.0], [10.0, -10.0], [10.0, 10.0], [-10.0, 10.0]],
        vec![],
    )
    .unwrap();
    let map = TownMap::from_buildings(vec![Building {
        osm_id: 1,
        footprint,
        height: 10.0,
    }]);
    let terrain = Terrain::flat(101, 101, 10.0, 0.0).unwrap();
    let config = SiteConfig {
        offset: Some([500.0, 500.0]),
        ..SiteConfig::default()
    };
    let mut a = Arena::new(Arc::new(Site::new(map, terrain, &config).unwrap()));
    a.add_vtol(
        ME,
        VtolKind::Vidar,
        Level::Dynamic,
        [400.0, 500.0, 5.0],
        0.0,
    )
    .unwrap();
    a.add_vtol(RED, VtolKind::Skeldar, Level::Dynamic, red, 0.0)
        .unwrap();
    a.conditions
        .insert(ME, Condition::new(Role::Vidar, Side::Blue, 1.0));
    a.conditions
        .insert(RED, Condition::new(Role::Skeldar, Side::Red, 1.0));
    a
}

fn camera() -> FriendFoeVision {
    FriendFoeVision {
        range: 300.0,
        half_fov: std::f64::consts::PI,
        p0: 1.0,
        k: 0.0,
        misidentification: 0.0,
    }
}

/// `looks` looks of our camera, one a second: the tracker's events at each.
fn track(a: &Arena, looks: u64, tracker: &mut Tracker) -> Vec<Vec<TrackEvent>> {
    let mut rngs = RngStreams::new(3);
    (0..looks)
        .map(|s| {
            let now = SimTime::from_secs(s);
            let seen =
                Look(tracker.config().vision).read(a, ME, &mut Probe::new(now, ME, &mut rngs));
            tracker.update(now, &seen)
        })
        .collect()
}

fn tracker() -> Tracker {
    Tracker::new(TrackConfig {
        vision: camera(),
        misses_to_lose: 2,
        ..TrackConfig::default()
    })
}

#[test]
fn a_target_in_the_open_is_locked_and_held() {
    let a = arena([450.0, 560.0, 2.0]);
    let mut t = tracker();
    let events = track(&a, 5, &mut t);
    assert_eq!(events[0], [TrackEvent::Acquired(RED)]);
    assert!(events[1..].iter().all(Vec::is_empty));
    let lock = t.get(RED).unwrap();
    assert_eq!(lock.pos, [450.0, 560.0, 2.0]);
    assert_eq!(lock.seen_at, SimTime::from_secs(4));
}

#[test]
fn a_target_behind_a_building_is_never_locked() {
    let a = arena([600.0, 500.0, 2.0]);
    let mut t = tracker();
    assert!(track(&a, 10, &mut t).iter().all(Vec::is_empty));
    assert!(t.is_empty());
}

#[test]
fn a_target_out_of_range_is_never_locked() {
    let a = arena([800.0, 800.0, 2.0]);
    let mut t = tracker();
    assert!(track(&a, 10, &mut t).iter().all(Vec::is_empty));
}

#[test]
fn a_lock_is_lost_once_the_target_hides_and_the_misses_run_out() {
    let mut a = arena([450.0, 560.0, 2.0]);
    let mut t = tracker();
    track(&a, 2, &mut t);
    assert!(t.get(RED).is_some());
    // It moves behind the building: the camera keeps the last fix, and loses it after two
    // missed looks.
    a.vtol.update(RED, |b| b.pos = [600.0, 500.0, 2.0]);
    let events = track(&a, 2, &mut t);
    assert_eq!(events, [vec![], vec![TrackEvent::Lost(RED)]]);
}

#[test]
fn an_owner_that_is_down_sees_nothing() {
    let mut a = arena([450.0, 560.0, 2.0]);
    a.conditions.update(ME, |c| c.status = Status::Down);
    let mut t = tracker();
    assert!(track(&a, 3, &mut t).iter().all(Vec::is_empty));
}

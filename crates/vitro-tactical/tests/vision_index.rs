//! Vision through the arena's grid of bodies and its line-of-sight memo sees exactly what a
//! scan of every entity sees, in the same order and with the same random draws, while
//! bodies move (a few at a time, and more at once than the storages' write logs hold),
//! change state and leave.

use rand::{Rng, SeedableRng};
use rand_chacha::ChaCha8Rng;
use std::sync::Arc;
use vitro::entity::EntityId;
use vitro::env::{Probe, Sensor, WRITE_LOG};
use vitro::rng::{Owner, RngStreams};
use vitro::time::SimTime;
use vitro_site::geo::Polygon;
use vitro_site::map::{Building, TownMap};
use vitro_site::site::{Site, SiteConfig};
use vitro_site::terrain::Terrain;
use vitro_tactical::arena::Arena;
use vitro_tactical::condition::{Condition, Role, Status};
use vitro_tactical::entity::Level;
use vitro_tactical::sensor::track::Look;
use vitro_tactical::sensor::{FriendFoeVision, Sighting};
use vitro_tactical::types::VtolKind;
use vitro_tactical::world::Side;

/// Bodies in the arena.
const N: u32 = 400;

/// A flat 1 km square with a row of buildings, and `N` helicopters of the three sides
/// scattered low over it (some of them inactive).
fn arena(rng: &mut ChaCha8Rng) -> Arena {
    let buildings = (0..8u32)
        .map(|i| {
            let x = f64::from(i) * 100.0 - 350.0;
            Building {
                osm_id: i64::from(i),
                footprint: Polygon::new(
                    vec![
                        [x - 15.0, -15.0],
                        [x + 15.0, -15.0],
                        [x + 15.0, 15.0],
                        [x - 15.0, 15.0],
                    ],
                    vec![],
                )
                .unwrap(),
                height: 12.0,
            }
        })
        .collect();
    let map = TownMap::from_buildings(buildings);
    let terrain = Terrain::flat(101, 101, 10.0, 0.0).unwrap();
    let config = SiteConfig {
        offset: Some([500.0, 500.0]),
        ..SiteConfig::default()
    };
    let mut a = Arena::new(Arc::new(Site::new(map, terrain, &config).unwrap()));
    for i in 0..N {
        let id = EntityId(i);
        let pos = [
            rng.random_range(0.0..1000.0),
            rng.random_range(0.0..1000.0),
            3.0,
        ];
        let heading = rng.random_range(-4.0..4.0);
        a.add_vtol(id, VtolKind::Vidar, Level::Dynamic, pos, heading)
            .unwrap();
        let side = Side::ALL[rng.random_range(0..3)];
        let mut c = Condition::new(Role::Vidar, side, 1.0);
        if rng.random_bool(0.1) {
            c.status = Status::Down;
        }
        a.conditions.insert(id, c);
    }
    a
}

/// What a scan of every entity in id order sees from `me` (the reference).
fn scan(a: &Arena, v: &FriendFoeVision, me: EntityId, rngs: &mut RngStreams) -> Vec<Sighting> {
    let Some(mine) = a.body(me) else {
        return Vec::new();
    };
    let rng = rngs.stream(Owner::Entity(me), "fof");
    a.conditions
        .iter()
        .filter(|(id, _)| *id != me)
        .filter_map(|(id, _)| {
            let b = a.body(id)?;
            v.look(&a.site, &mine, id, &b, &mut *rng)
        })
        .collect()
}

#[test]
fn the_grid_sees_what_a_scan_sees() {
    let mut rng = ChaCha8Rng::seed_from_u64(19);
    let mut a = arena(&mut rng);
    let vision = FriendFoeVision {
        range: 180.0,
        half_fov: 1.0,
        p0: 0.9,
        k: 1.0,
        misidentification: 0.2,
    };
    let (mut grid_rngs, mut scan_rngs) = (RngStreams::new(5), RngStreams::new(5));
    let mut seen = 0;
    for round in 0..40 {
        // Every tenth round moves more bodies than a write log holds: the grid looks every
        // body up again.
        let moves = if round % 10 == 9 { 2 * WRITE_LOG } else { 7 };
        for _ in 0..moves {
            let id = EntityId(rng.random_range(0..N));
            let (dx, dy) = (rng.random_range(-60.0..60.0), rng.random_range(-60.0..60.0));
            a.vtol.update(id, |b| {
                b.pos[0] += dx;
                b.pos[1] += dy;
                b.att[2] += 0.3;
            });
        }
        // Some go down, some come back, one leaves the arena and returns.
        for _ in 0..3 {
            let id = EntityId(rng.random_range(0..N));
            let down = rng.random_bool(0.5);
            a.conditions.update(id, |c| {
                c.status = if down { Status::Down } else { Status::Active }
            });
        }
        let gone = EntityId(rng.random_range(0..N));
        let body = a.vtol.remove(gone);
        for i in (0..N).step_by(7) {
            let me = EntityId(i);
            let mut probe = Probe::new(SimTime::from_secs(round), me, &mut grid_rngs);
            let got = Look(vision).read(&a, me, &mut probe);
            let want = scan(&a, &vision, me, &mut scan_rngs);
            assert_eq!(got, want, "round {round}, observer {i}");
            seen += got.len();
        }
        if let Some(b) = body {
            a.vtol.insert(gone, b);
        }
    }
    assert!(seen > 500, "the test looks at crowds: {seen} sightings");
    let (hits, casts) = a.sight_counts();
    assert!(
        hits > 0 && casts > 0,
        "{hits} answers from the memo, {casts} cast"
    );
    let counts = a.look_counts();
    assert!(
        counts.updated > 100 && counts.computed > 100,
        "looks: {counts:?}"
    );
}

/// Every third observer looks through the arena and by a scan, each from its own streams;
/// the two must agree.
fn look_all(a: &Arena, v: &FriendFoeVision, t: u64, grid: &mut RngStreams, scan_: &mut RngStreams) {
    for i in (0..N).step_by(3) {
        let me = EntityId(i);
        let mut probe = Probe::new(SimTime::from_secs(t), me, grid);
        let got = Look(*v).read(a, me, &mut probe);
        assert_eq!(got, scan(a, v, me, scan_), "look {t}, observer {i}");
    }
}

#[test]
fn a_remembered_look_sees_what_a_scan_sees() {
    let mut rng = ChaCha8Rng::seed_from_u64(23);
    let mut a = arena(&mut rng);
    let v = FriendFoeVision {
        range: 150.0,
        half_fov: 1.2,
        p0: 0.9,
        k: 1.0,
        misidentification: 0.3,
    };
    let observers = (0..N)
        .step_by(3)
        .filter(|i| a.body(EntityId(*i)).is_some())
        .count() as u64;
    let (mut g, mut s) = (RngStreams::new(9), RngStreams::new(9));
    // Nothing moves: after the first look, every look comes from the memo.
    for t in 0..3 {
        look_all(&a, &v, t, &mut g, &mut s);
    }
    let c = a.look_counts();
    assert_eq!(
        (c.computed, c.remembered, c.updated),
        (observers, 2 * observers, 0)
    );
    // A body written again with the same bits changes nothing.
    a.vtol.update(EntityId(5), |b| b.pos[0] += 0.0);
    look_all(&a, &v, 3, &mut g, &mut s);
    assert_eq!(a.look_counts().remembered, 3 * observers);
    // One body moves a little, another changes side, another goes down, an observer
    // turns: the looks are brought up to date (and agree with the scan), the observer who
    // turned looks afresh; the next looks are answered from the memo.
    let turner = (0..N)
        .step_by(3)
        .find(|i| a.body(EntityId(*i)).is_some())
        .unwrap();
    a.vtol.update(EntityId(10), |b| b.pos[1] += 0.5);
    a.conditions.update(EntityId(20), |c| c.side = Side::Red);
    a.conditions
        .update(EntityId(31), |c| c.status = Status::Down);
    a.vtol.update(EntityId(turner), |b| b.att[2] += 0.01);
    for t in 4..6 {
        look_all(&a, &v, t, &mut g, &mut s);
    }
    let c = a.look_counts();
    assert_eq!(
        c.computed,
        observers + 1,
        "only the turned observer looks afresh"
    );
    // The others go through the four changes once, and examine again only the changed
    // bodies in their range: few of the four per look.
    assert_eq!(c.updated, observers - 1);
    assert!(
        c.examined > 4 && c.examined < 2 * observers,
        "{} bodies examined again in {observers} looks",
        c.examined
    );
    assert_eq!(c.remembered + c.updated + c.computed, 6 * observers);
    // Many changes between two looks: more than a look goes through, so it looks afresh.
    for t in 0..100 {
        for _ in 0..60 {
            let id = EntityId(rng.random_range(0..N));
            a.vtol.update(id, |b| b.pos[0] += 1.0);
        }
        look_one(&a, &v, t, turner, &mut g, &mut s);
    }
    look_all(&a, &v, 100, &mut g, &mut s);
    let d = a.look_counts();
    assert!(d.computed >= c.computed + observers - 1, "{d:?}");
    // Another sensor (a longer range) from the same observers is another question.
    let far = FriendFoeVision { range: 400.0, ..v };
    look_all(&a, &far, 101, &mut g, &mut s);
    assert_eq!(a.look_counts().computed, d.computed + observers);
}

/// One observer looks, through the arena and by a scan.
fn look_one(
    a: &Arena,
    v: &FriendFoeVision,
    t: u64,
    i: u32,
    grid: &mut RngStreams,
    scan_: &mut RngStreams,
) {
    let me = EntityId(i);
    let mut probe = Probe::new(SimTime::from_secs(t), me, grid);
    let got = Look(*v).read(a, me, &mut probe);
    assert_eq!(got, scan(a, v, me, scan_), "look {t}, observer {i}");
}

#[test]
fn bodies_near_holds_every_body_in_range() {
    let mut rng = ChaCha8Rng::seed_from_u64(7);
    let a = arena(&mut rng);
    for _ in 0..200 {
        let (x, y) = (
            rng.random_range(-100.0..1100.0),
            rng.random_range(-100.0..1100.0),
        );
        let r = rng.random_range(0.0..400.0);
        let near = a.bodies_near(x, y, r);
        assert!(near.windows(2).all(|w| w[0].0 < w[1].0), "id order");
        for (id, _) in a.conditions.iter() {
            if let Some(b) = a.body(id) {
                let d = ((b.pos[0] - x).powi(2) + (b.pos[1] - y).powi(2)).sqrt();
                let listed = near.iter().any(|(n, nb)| *n == id && *nb == b);
                assert!(d > r || listed, "{id:?} at {d:.1} m of a {r:.1} m query");
            }
        }
    }
}

#[test]
fn looks_with_many_visions_in_turn_see_what_a_scan_sees() {
    // The memo names a look's vision by an index in a short table, emptied (with the
    // memos) when more than it holds have been used: visions taken in turn, more of them
    // than the table holds, while bodies move, must still see what a scan sees; and a look
    // draws as `in_sight` followed by `draw` in id order.
    let mut rng = ChaCha8Rng::seed_from_u64(31);
    let mut a = arena(&mut rng);
    let (mut g, mut s) = (RngStreams::new(3), RngStreams::new(3));
    for t in 0..90u32 {
        let v = FriendFoeVision {
            range: 100.0 + f64::from(t % 80) * 2.0,
            half_fov: 0.8 + f64::from(t % 3) * 0.5,
            p0: 0.9,
            k: 1.0,
            misidentification: 0.3,
        };
        // Each observer looks with the round's vision, bodies move, it looks again (the
        // second look brings the first up to date).
        for pass in 0..2 {
            if pass == 1 {
                for _ in 0..5 {
                    let id = EntityId(rng.random_range(0..N));
                    a.vtol.update(id, |b| b.pos[1] += 3.0);
                }
            }
            for i in (0..N).step_by(11) {
                look_one(&a, &v, u64::from(2 * t + pass), i, &mut g, &mut s);
            }
        }
        // The same look, its two halves apart, from copies of one stream.
        let me = EntityId(t % N);
        if let Some(mine) = a.body(me) {
            let mut r1 = ChaCha8Rng::seed_from_u64(u64::from(t));
            let mut r2 = r1.clone();
            let halves: Vec<Sighting> = a
                .in_sight(me, &mine, &v)
                .iter()
                .filter_map(|x| v.draw(x, &mut r1))
                .collect();
            assert_eq!(a.look(me, &mine, &v, &mut r2), halves, "look {t}");
        }
    }
    let c = a.look_counts();
    assert!(c.updated > 0 && c.computed > 0, "{c:?}");
}

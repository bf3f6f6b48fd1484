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
        // Every tenth round moves more bodies than a write log holds: the grid rebuilds.
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

//! Sensors: occlusion by a building, the detection curve, identification errors, GPS noise.

// Measurements of the outcome (distances, angles, fits), not model code: platform math is
// allowed here (clippy.toml bans it where it could change a trace hash).
#![allow(clippy::disallowed_methods)]

use std::sync::Arc;
use vitro::entity::EntityId;
use vitro::env::{Probe, Sensor};
use vitro::rng::RngStreams;
use vitro::time::SimTime;
use vitro_site::geo::Polygon;
use vitro_site::map::{Building, TownMap};
use vitro_site::site::{Site, SiteConfig};
use vitro_site::terrain::Terrain;
use vitro_tactical::sensor::{FriendFoeVision, Gps, ProximityVision};
use vitro_tactical::world::{Body, Side, World};

/// A flat 1 km square with one 20 x 20 x 10 m building at the world point (500, 500).
fn world() -> World {
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
    World::new(Arc::new(Site::new(map, terrain, &config).unwrap()))
}

fn trooper(x: f64, y: f64, heading: f64, side: Side) -> Body {
    Body::new([x, y, 0.0], heading, side, 1.8)
}

fn sure_eyes() -> FriendFoeVision {
    FriendFoeVision {
        range: 300.0,
        half_fov: 60f64.to_radians(),
        p0: 1.0,
        k: 0.0,
        misidentification: 0.0,
    }
}

#[test]
fn a_foe_behind_a_building_is_seen_once_it_steps_out() {
    let mut w = world();
    let (me, foe) = (EntityId(0), EntityId(1));
    w.bodies.insert(me, trooper(400.0, 500.0, 0.0, Side::Blue));
    w.bodies.insert(foe, trooper(600.0, 500.0, 0.0, Side::Red));
    let mut rngs = RngStreams::new(1);
    let eyes = sure_eyes();
    let mut look = |w: &World| eyes.read(w, me, &mut Probe::new(SimTime::ZERO, me, &mut rngs));
    assert!(look(&w).is_empty(), "hidden behind the building");
    // Proximity vision ignores walls.
    let near = ProximityVision { range: 250.0 }.read(
        &w,
        me,
        &mut Probe::new(SimTime::ZERO, me, &mut RngStreams::new(1)),
    );
    assert_eq!(near.len(), 1);
    assert_eq!(near[0].id, foe);
    // It steps north, out of the building's shadow.
    w.bodies.update(foe, |b| b.pos[1] = 540.0);
    let seen = look(&w);
    assert_eq!(seen.len(), 1);
    assert_eq!((seen[0].id, seen[0].seen_as), (foe, Side::Red));
    assert!((seen[0].distance - (200.0f64.powi(2) + 40.0f64.powi(2)).sqrt()).abs() < 1e-9);
    // Out of the field of view when the observer turns away, out of range when far.
    w.bodies.update(me, |b| b.heading = std::f64::consts::PI);
    assert!(look(&w).is_empty());
    w.bodies.update(me, |b| {
        b.heading = 0.0;
        b.pos[0] = 200.0;
    });
    assert!(look(&w).is_empty());
}

/// Over many looks, the detection count at each distance matches p(d) within 4.5 standard
/// deviations, and misidentifications match their rate.
#[test]
fn detection_rate_follows_the_curve() {
    let mut w = world();
    let eyes = FriendFoeVision {
        range: 200.0,
        half_fov: std::f64::consts::PI,
        p0: 0.9,
        k: 1.5,
        misidentification: 0.2,
    };
    let me = EntityId(0);
    w.bodies.insert(me, trooper(100.0, 100.0, 0.0, Side::Blue));
    let distances = [10.0, 60.0, 110.0, 160.0, 190.0];
    for (i, d) in distances.iter().enumerate() {
        // Targets spread around the observer, away from the building.
        let a = i as f64 * 0.3;
        w.bodies.insert(
            EntityId(i as u32 + 1),
            trooper(100.0 + d * a.cos(), 100.0 + d * a.sin(), 0.0, Side::Red),
        );
    }
    let trials = 4000;
    let mut rngs = RngStreams::new(42);
    let mut hits = vec![0usize; distances.len()];
    let mut wrong = 0usize;
    for _ in 0..trials {
        for s in eyes.read(&w, me, &mut Probe::new(SimTime::ZERO, me, &mut rngs)) {
            hits[s.id.index() - 1] += 1;
            wrong += usize::from(s.seen_as != Side::Red);
        }
    }
    for (i, &d) in distances.iter().enumerate() {
        let p = eyes.detection_probability(d);
        let n = trials as f64;
        let sd = (n * p * (1.0 - p)).sqrt();
        let dev = (hits[i] as f64 - n * p).abs();
        assert!(
            dev <= 4.5 * sd + 1.0,
            "d = {d}: {} hits, expected {}",
            hits[i],
            n * p
        );
    }
    let total: usize = hits.iter().sum();
    let (n, p) = (total as f64, eyes.misidentification);
    assert!((wrong as f64 - n * p).abs() <= 4.5 * (n * p * (1.0 - p)).sqrt());
}

#[test]
fn gps_noise_has_the_configured_spread_and_is_reproducible() {
    let mut w = world();
    let me = EntityId(3);
    w.bodies.insert(me, trooper(100.0, 200.0, 0.0, Side::Blue));
    let mut rngs = RngStreams::new(5);
    let mut probe = Probe::new(SimTime::ZERO, me, &mut rngs);
    assert_eq!(
        Gps::default().read(&w, me, &mut probe),
        Some([100.0, 200.0, 0.0])
    );
    assert_eq!(Gps::default().read(&w, EntityId(9), &mut probe), None);
    let gps = Gps { sigma: 3.0 };
    let xs: Vec<f64> = (0..20_000)
        .map(|_| gps.read(&w, me, &mut probe).unwrap()[0] - 100.0)
        .collect();
    let mean = xs.iter().sum::<f64>() / xs.len() as f64;
    let sd = (xs.iter().map(|x| (x - mean).powi(2)).sum::<f64>() / xs.len() as f64).sqrt();
    assert!(
        mean.abs() < 0.1 && (sd - 3.0).abs() < 0.1,
        "mean {mean}, sd {sd}"
    );
    // Same seed, same first reading.
    let first = |seed| {
        let mut r = RngStreams::new(seed);
        gps.read(&w, me, &mut Probe::new(SimTime::ZERO, me, &mut r))
    };
    assert_eq!(first(5), first(5));
    assert_ne!(first(5), first(6));
}

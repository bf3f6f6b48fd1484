//! Line of sight: hand-made scenes and the real town on the real terrain.

use rand::{Rng, SeedableRng};
use rand_chacha::ChaCha8Rng;
use vitro_site::geo::Polygon;
use vitro_site::los::{LosScene, Prism};
use vitro_site::map::{MapConfig, TownMap};
use vitro_site::site::{Site, SiteConfig};
use vitro_site::terrain::Terrain;

const DATA: &str = concat!(env!("CARGO_MANIFEST_DIR"), "/../../data");

fn rect(x0: f64, y0: f64, x1: f64, y1: f64) -> Polygon {
    Polygon::new(vec![[x0, y0], [x1, y0], [x1, y1], [x0, y1]], vec![]).unwrap()
}

fn flat() -> Terrain {
    Terrain::flat(21, 21, 10.0, 0.0).unwrap()
}

fn scene(t: &Terrain, boxes: &[(Polygon, f64)]) -> LosScene {
    let prisms: Vec<Prism<'_>> = boxes
        .iter()
        .map(|(p, h)| Prism {
            footprint: p,
            base: 0.0,
            top: *h,
        })
        .collect();
    LosScene::new(t, &prisms, &[]).unwrap()
}

/// Both queries must agree; returns the answer.
fn los(s: &LosScene, a: [f64; 3], b: [f64; 3]) -> bool {
    let v = s.visible(a, b);
    assert_eq!(
        v,
        s.visible_brute_force(a, b),
        "BVH and brute force disagree"
    );
    v
}

#[test]
fn a_wall_between() {
    let t = flat();
    let s = scene(&t, &[(rect(100.0, 60.0, 101.0, 140.0), 5.0)]);
    assert!(!los(&s, [50.0, 100.0, 2.0], [150.0, 100.0, 2.0]));
    assert!(
        los(&s, [50.0, 100.0, 6.0], [150.0, 100.0, 6.0]),
        "over the wall"
    );
    assert!(
        los(&s, [50.0, 150.0, 2.0], [150.0, 150.0, 2.0]),
        "past its end"
    );
    assert!(
        los(&s, [50.0, 100.0, 2.0], [150.0, 200.0, 2.0]),
        "slanting past its end"
    );
    assert!(los(&s, [50.0, 100.0, 2.0], [90.0, 100.0, 2.0]), "same side");
    let hit = s
        .first_hit([50.0, 100.0, 2.0], [150.0, 100.0, 2.0])
        .unwrap();
    assert!((hit - 50.0).abs() < 1e-3, "{hit}");
    // The batch query gives the same answers in order.
    let from = [50.0, 100.0, 2.0];
    let targets = [
        [150.0, 100.0, 2.0],
        [150.0, 200.0, 2.0],
        [150.0, 100.0, 9.0],
    ];
    assert_eq!(s.visible_from(from, &targets), [false, true, true]);
    let pairs: Vec<_> = targets.iter().map(|&b| (from, b)).collect();
    assert_eq!(s.visible_pairs(&pairs), [false, true, true]);
}

#[test]
fn a_hill_between() {
    // A round hill 60 m high in the middle of a 1 km square.
    let t = Terrain::from_fn(41, 41, 25.0, |x, y| {
        let r2 = (x - 512.5).powi(2) + (y - 512.5).powi(2);
        60.0 * libm::exp(-r2 / (2.0 * 80.0f64.powi(2)))
    })
    .unwrap();
    let s = LosScene::terrain_only(&t).unwrap();
    let g = |x: f64, y: f64, up: f64| [x, y, t.height(x, y).unwrap() + up];
    assert!(!los(&s, g(200.0, 512.5, 2.0), g(800.0, 512.5, 2.0)));
    assert!(los(&s, g(200.0, 512.5, 80.0), g(800.0, 512.5, 80.0)));
    assert!(
        los(&s, g(200.0, 100.0, 2.0), g(800.0, 100.0, 2.0)),
        "beside the hill"
    );
    // From a mast on the summit, the foot of the hill is seen (target on the ground).
    assert!(los(&s, g(512.5, 512.5, 20.0), g(700.0, 512.5, 0.0)));
}

#[test]
fn grazing_a_roof_edge() {
    let t = flat();
    let s = scene(&t, &[(rect(40.0, 40.0, 50.0, 50.0), 10.0)]);
    // Level lines just over and just under the roof.
    assert!(los(&s, [20.0, 45.0, 10.01], [80.0, 45.0, 10.01]));
    assert!(!los(&s, [20.0, 45.0, 9.99], [80.0, 45.0, 9.99]));
    // A rising line just over (then just under) the near roof edge...
    let low = [20.0, 45.0, 2.0];
    let high = [20.0, 45.0, 30.0];
    // The point `k` times as far from `a` as the edge point `e`, on the line through both.
    let through = |a: [f64; 3], e: [f64; 3], k: f64| {
        [a[0] + k * (e[0] - a[0]), a[1], a[2] + k * (e[2] - a[2])]
    };
    assert!(los(&s, low, through(low, [40.0, 45.0, 10.01], 3.0)));
    assert!(!los(&s, low, through(low, [40.0, 45.0, 9.99], 3.0)));
    // ...and a falling line just over (then just under) the far roof edge.
    assert!(los(&s, high, through(high, [50.0, 45.0, 10.01], 1.3)));
    assert!(!los(&s, high, through(high, [50.0, 45.0, 9.99], 1.3)));
    // Down onto the roof's edge from above: a point 1 cm outside the wall is seen from
    // straight above... and one just inside is on the roof, hidden from below.
    assert!(los(&s, [50.01, 45.0, 30.0], [50.01, 45.0, 0.5]));
    assert!(!los(&s, [49.99, 45.0, 30.0], [49.99, 45.0, 0.5]));
}

#[test]
fn both_ends_inside_a_building() {
    let t = flat();
    let s = scene(
        &t,
        &[
            (rect(40.0, 40.0, 60.0, 60.0), 8.0),
            (rect(80.0, 40.0, 100.0, 60.0), 8.0),
        ],
    );
    // Same building: nothing between the two points.
    assert!(los(&s, [42.0, 45.0, 1.5], [58.0, 55.0, 1.5]));
    // Different buildings: two walls between.
    assert!(!los(&s, [50.0, 50.0, 1.5], [90.0, 50.0, 1.5]));
    // Inside to outside, and to the sky through the roof.
    assert!(!los(&s, [50.0, 50.0, 1.5], [70.0, 50.0, 1.5]));
    assert!(!los(&s, [50.0, 50.0, 1.5], [50.0, 50.0, 50.0]));
}

fn kotka_site() -> Site {
    let map = TownMap::load(format!("{DATA}/maps/kotka.osm.pbf"), &MapConfig::default()).unwrap();
    let terrain = Terrain::load(format!("{DATA}/terrain/valley_64x64_90m.asc")).unwrap();
    Site::new(map, terrain, &SiteConfig::default()).unwrap()
}

/// On the real valley: the mesh answer matches a dense profile of the bilinear surface
/// wherever the profile is decisive (clear or blocked by more than the mesh's deviation).
#[test]
fn real_terrain_matches_the_height_profile() {
    let t = Terrain::load(format!("{DATA}/terrain/valley_64x64_90m.asc")).unwrap();
    let s = LosScene::terrain_only(&t).unwrap();
    let margin = t.mesh_deviation() + 0.1;
    let [x0, y0, x1, y1] = t.extent();
    let mut rng = ChaCha8Rng::seed_from_u64(7);
    let (mut clear, mut blocked) = (0, 0);
    for _ in 0..400 {
        let mut p = || {
            let (x, y) = (rng.random_range(x0..x1), rng.random_range(y0..y1));
            [x, y, t.height(x, y).unwrap() + rng.random_range(2.0..60.0)]
        };
        let (a, b) = (p(), p());
        // Lowest clearance over the bilinear surface, away from the trimmed ends.
        let n = 2000;
        let lowest = (20..n - 20)
            .map(|k| {
                let f = k as f64 / n as f64;
                let q = [0, 1, 2].map(|i| a[i] + f * (b[i] - a[i]));
                q[2] - t.height(q[0], q[1]).unwrap()
            })
            .fold(f64::INFINITY, f64::min);
        let v = s.visible(a, b);
        if lowest > margin {
            assert!(v, "clear by {lowest} m but reported hidden: {a:?} {b:?}");
            clear += 1;
        } else if lowest < -margin {
            assert!(
                !v,
                "blocked by {} m but reported visible: {a:?} {b:?}",
                -lowest
            );
            blocked += 1;
        }
    }
    assert!(
        clear > 20 && blocked > 20,
        "clear {clear}, blocked {blocked}"
    );
}

#[test]
fn real_town_bvh_matches_brute_force_and_buildings_stand_on_the_ground() {
    let site = kotka_site();
    for b in &site.buildings {
        for p in &b.footprint.outer {
            assert!(b.base <= site.ground(*p).unwrap() + 1e-9);
        }
        assert!(b.roof > b.base);
    }
    let segs = &site.map.walk.segments;
    let mut rng = ChaCha8Rng::seed_from_u64(3);
    let mut point = || {
        let s = &segs[rng.random_range(0..segs.len())];
        let p = s.points[rng.random_range(0..s.points.len())];
        let mut q = site.on_ground(p);
        q[2] += 2.0;
        q
    };
    let mut seen = 0;
    for _ in 0..300 {
        let (a, b) = (point(), point());
        seen += usize::from(los(&site.los, a, b));
    }
    assert!(seen > 0 && seen < 300, "seen {seen} of 300");
}

//! Line-of-sight throughput in the real town on the real terrain: BVH vs every triangle.
//!
//! `cargo run --release -p vitro-site --example los_bench [PAIRS]`
//!
//! Pairs of random street points (uniform along the walking network), each 2 m above the
//! ground, are checked through the BVH and by a brute-force loop over all triangles (on a
//! subset, as it is slow); the answers must agree.

use rand::{Rng, SeedableRng};
use rand_chacha::ChaCha8Rng;
use std::hint::black_box;
use std::time::Instant;
use vitro_site::map::{MapConfig, Mode, TownMap};
use vitro_site::site::{Site, SiteConfig};
use vitro_site::terrain::Terrain;

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let root = concat!(env!("CARGO_MANIFEST_DIR"), "/../..");
    let pairs: usize = match std::env::args().nth(1) {
        Some(n) => n.parse()?,
        None => 200_000,
    };
    let map = TownMap::load(
        format!("{root}/data/maps/kotka.osm.pbf"),
        &MapConfig::default(),
    )?;
    let terrain = Terrain::load(format!("{root}/data/terrain/valley_64x64_90m.asc"))?;
    let t0 = Instant::now();
    let site = Site::new(map, terrain, &SiteConfig::default())?;
    println!(
        "scene: {} triangles ({} ground, {} buildings and bridges), built in {:.0} ms",
        site.los.triangle_count(),
        site.los.terrain_triangle_count(),
        site.los.triangle_count() - site.los.terrain_triangle_count(),
        t0.elapsed().as_secs_f64() * 1e3
    );

    // Street points, uniform by length along the walking network's segments.
    let segs = &site.map.streets(Mode::Walk).segments;
    let cum: Vec<f64> = segs
        .iter()
        .scan(0.0, |acc, s| {
            *acc += s.length;
            Some(*acc)
        })
        .collect();
    let total = cum.last().copied().ok_or("no streets")?;
    let mut rng = ChaCha8Rng::seed_from_u64(2024);
    let mut point = || {
        let at = rng.random_range(0.0..total);
        let i = cum.partition_point(|&c| c < at).min(segs.len() - 1);
        let mut along = at - if i == 0 { 0.0 } else { cum[i - 1] };
        let pts = &segs[i].points;
        let mut p = pts[pts.len() - 1];
        for w in pts.windows(2) {
            let l = vitro_site::geo::dist(w[0], w[1]);
            if along <= l && l > 0.0 {
                let f = along / l;
                p = [
                    w[0][0] + f * (w[1][0] - w[0][0]),
                    w[0][1] + f * (w[1][1] - w[0][1]),
                ];
                break;
            }
            along -= l;
        }
        let mut q = site.on_ground(p);
        q[2] += 2.0;
        q
    };
    let queries: Vec<([f64; 3], [f64; 3])> = (0..pairs).map(|_| (point(), point())).collect();

    let t = Instant::now();
    let seen = queries
        .iter()
        .filter(|&&(a, b)| site.los.visible(a, b))
        .count();
    let bvh = t.elapsed().as_secs_f64();
    let brute_n = (pairs / 200).clamp(1, 2000);
    let t = Instant::now();
    let mut agree = 0;
    for &(a, b) in &queries[..brute_n] {
        let v = black_box(site.los.visible_brute_force(a, b));
        agree += usize::from(v == site.los.visible(a, b));
    }
    let brute = t.elapsed().as_secs_f64();
    assert_eq!(agree, brute_n, "brute force and BVH disagree");

    let qps = |n: usize, s: f64| n as f64 / s;
    let (q_bvh, q_brute) = (qps(pairs, bvh), qps(brute_n, brute));
    println!(
        "{pairs} pairs of street points 2 m above ground, {:.1} % in sight",
        100.0 * seen as f64 / pairs as f64
    );
    println!(
        "BVH:          {:>12.0} queries/s ({:.2} µs each)",
        q_bvh,
        1e6 / q_bvh
    );
    println!(
        "brute force:  {:>12.0} queries/s ({:.0} µs each, {brute_n} pairs, all agree)",
        q_brute,
        1e6 / q_brute
    );
    println!("speed-up BVH / brute force: {:.0}x", q_bvh / q_brute);
    Ok(())
}

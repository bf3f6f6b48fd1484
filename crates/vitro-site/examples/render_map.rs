//! Renders the Kotka extract set on the valley terrain to `docs/map.png`.
//!
//! `cargo run --release -p vitro-site --example render_map [OUT.png [X0,Y0,X1,Y1]]`
//! (the optional window, in world metres, draws a close-up).

use std::time::Instant;
use vitro_site::map::{MapConfig, TownMap};
use vitro_site::render::{RenderOptions, render_site};
use vitro_site::site::{Site, SiteConfig};
use vitro_site::terrain::Terrain;

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let root = concat!(env!("CARGO_MANIFEST_DIR"), "/../..");
    let out = std::env::args()
        .nth(1)
        .unwrap_or_else(|| format!("{root}/docs/map.png"));
    let t0 = Instant::now();
    let map = TownMap::load(
        format!("{root}/data/maps/kotka.osm.pbf"),
        &MapConfig::default(),
    )?;
    let terrain = Terrain::load(format!("{root}/data/terrain/valley_64x64_90m.asc"))?;
    let site = Site::new(map, terrain, &SiteConfig::default())?;
    let window = match std::env::args().nth(2) {
        Some(w) => {
            let v: Vec<f64> = w.split(',').map(str::parse).collect::<Result<_, _>>()?;
            let [a, b, c, d] = v[..] else {
                return Err("window must be X0,Y0,X1,Y1".into());
            };
            Some([a, b, c, d])
        }
        None => None,
    };
    let opts = RenderOptions {
        window,
        title: "Kotka (OSM extract) on the Jacksboro valley terrain".into(),
        attribution: vec!["Terrain: USGS-derived sample shipped with matplotlib".into()],
        ..RenderOptions::default()
    };
    if let Some(dir) = std::path::Path::new(&out).parent() {
        std::fs::create_dir_all(dir)?;
    }
    let size = render_site(&site, &opts, &out)?;
    println!(
        "wrote {out}: {} x {} px, town offset {:?}, {:.2} s",
        size.width,
        size.height,
        site.offset,
        t0.elapsed().as_secs_f64()
    );
    Ok(())
}

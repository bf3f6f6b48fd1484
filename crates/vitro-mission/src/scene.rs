//! The static world of a mission on a town: [`site_scene`] draws a [`Site`] as a [`Scene`]
//! (its streets, footpaths, buildings, bridges, water and terrain, geo-referenced), and a
//! mission adds its own layers, e.g. its named places. A mission on no map starts from
//! [`Scene::flat`] instead.
//!
//! ```no_run
//! # fn scene(site: &vitro_site::site::Site, name: String, start_ms: i64) -> vitro_record::Scene {
//! let mut scene = vitro_mission::scene::site_scene(site, name, start_ms);
//! scene.places.insert("depot".into(), site.on_ground([120.0, -40.0]));
//! scene
//! # }
//! ```

use std::collections::BTreeMap;
use vitro_record::{Building, Geo, Heightmap, Scene};
use vitro_site::map::Mode;
use vitro_site::site::Site;

/// Terrain samples per side of the scene's heightmap (at most).
pub const TERRAIN_SAMPLES: usize = 96;

/// The site as a scene named `name`, simulated time 0 at `start_unix_ms` on the calendar,
/// with no places.
pub fn site_scene(site: &Site, name: String, start_unix_ms: i64) -> Scene {
    let e = site.map.extent;
    let [ox, oy] = site.offset;
    Scene {
        name,
        start_unix_ms,
        geo: geo(site),
        extent: [e[0] + ox, e[1] + oy, e[2] + ox, e[3] + oy],
        streets: lines(site, Mode::Drive),
        paths: lines(site, Mode::Walk),
        buildings: (site.buildings.iter())
            .map(|b| Building {
                footprint: b.footprint.outer.clone(),
                base: b.base,
                height: b.roof - b.base,
            })
            .collect(),
        bridges: site.bridges.iter().map(|b| b.deck.clone()).collect(),
        forbidden: (site.map.water.iter())
            .map(|w| w.area.outer.iter().map(|&p| site.to_world(p)).collect())
            .collect(),
        places: BTreeMap::new(),
        terrain: heightmap(site),
    }
}

/// The geo-reference of the site's world frame.
pub fn geo(site: &Site) -> Geo {
    let p = site.map.projection;
    let [lat1, lon1] = p.unproject([1000.0, 1000.0]);
    Geo {
        lat0: p.lat0,
        lon0: p.lon0,
        m_per_deg_lat: 1000.0 / (lat1 - p.lat0),
        m_per_deg_lon: 1000.0 / (lon1 - p.lon0),
        offset: site.offset,
        z0: 0.0,
    }
}

/// The terrain sampled on a square grid of at most [`TERRAIN_SAMPLES`] per side.
pub fn heightmap(site: &Site) -> Heightmap {
    let e = site.terrain.extent();
    let span = (e[2] - e[0]).max(e[3] - e[1]);
    let cell = span / (TERRAIN_SAMPLES - 1) as f64;
    let nx = (((e[2] - e[0]) / cell) as usize + 1).min(TERRAIN_SAMPLES);
    let ny = (((e[3] - e[1]) / cell) as usize + 1).min(TERRAIN_SAMPLES);
    let mut z = Vec::with_capacity(nx * ny);
    for j in 0..ny {
        for i in 0..nx {
            let x = (e[0] + i as f64 * cell).min(e[2]);
            let y = (e[1] + j as f64 * cell).min(e[3]);
            z.push(site.ground([x, y]).unwrap_or(0.0) as f32);
        }
    }
    Heightmap {
        nx,
        ny,
        origin: [e[0], e[1]],
        cell,
        z,
    }
}

/// The street segments of `mode` as world polylines.
fn lines(site: &Site, mode: Mode) -> Vec<Vec<[f64; 3]>> {
    (0..site.map.streets(mode).segments.len())
        .filter_map(|i| site.segment_path(mode, i))
        .collect()
}

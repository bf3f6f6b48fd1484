//! # vitro-site: the static world a mission happens in
//!
//! A real town from OpenStreetMap ([`map`]: street and walk graphs, buildings, bridges,
//! water, forbidden zones: [`map::ForbiddenZones`]) set on a real elevation model ([`terrain`]: ESRI ASCII
//! grids and GeoTIFF) as one [`site`] in local town metres ([`geo`]). On it, line of sight
//! against the terrain and the buildings ([`los`], over a bounding-volume hierarchy) and
//! terrain [`viewshed`]s; [`info`] and [`render`] give a map's facts and its picture for the
//! command line and the docs.
//!
//! Nothing here moves: the site is the environment's fixed part, shared read-only by every
//! run (`Arc<Site>`). Bodies, sensors and agents live in the crates above it
//! (`vitro-tactical`, then one crate per mission).
//!
//! ```no_run
//! use vitro_site::map::{MapConfig, TownMap};
//! use vitro_site::site::{Site, SiteConfig};
//! use vitro_site::terrain::Terrain;
//!
//! let map = TownMap::load("data/maps/kotka.osm.pbf", &MapConfig::default())?;
//! let terrain = Terrain::load("data/terrain/valley_64x64_90m.asc")?;
//! let site = Site::new(map, terrain, &SiteConfig::default())?;
//! // Two points 2 m above the ground, 50 m apart in town metres.
//! let (a, b) = (site.on_ground([0.0, 0.0]), site.on_ground([50.0, 0.0]));
//! let eye = |p: [f64; 3]| [p[0], p[1], p[2] + 2.0];
//! println!("clear line of sight: {}", site.los.visible(eye(a), eye(b)));
//! # Ok::<(), Box<dyn std::error::Error>>(())
//! ```

pub mod geo;
pub mod info;
pub mod los;
pub mod map;
pub mod render;
pub mod site;
pub mod terrain;
pub mod viewshed;

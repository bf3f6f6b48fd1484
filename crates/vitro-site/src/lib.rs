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
//! ```
//! use vitro_site::map::{MapConfig, Mode, TownMap};
//! use vitro_site::site::{Site, SiteConfig};
//! use vitro_site::terrain::Terrain;
//!
//! // The repository's data (`data/`): Kotka from OpenStreetMap, a real elevation model.
//! let data = concat!(env!("CARGO_MANIFEST_DIR"), "/../../data");
//! let map = TownMap::load(format!("{data}/maps/kotka.osm.pbf"), &MapConfig::default())?;
//! let terrain = Terrain::load(format!("{data}/terrain/valley_64x64_90m.asc"))?;
//! let site = Site::new(map, terrain, &SiteConfig::default())?;
//!
//! // Town metres (x east, y north of the map's centre) to world metres on the terrain.
//! let centre = site.to_world([0.0, 0.0]);
//! assert_eq!(centre, site.offset);
//! // Street junctions sit on the ground; buildings have forbidden zones around them.
//! let junction = site.street_point(Mode::Drive, vitro::env::NodeId(0)).unwrap();
//! assert_eq!(site.ground([junction[0], junction[1]]).map(|z| (z - junction[2]).abs() < 1e-9), Some(true));
//! assert!(!site.zones.is_empty());
//!
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

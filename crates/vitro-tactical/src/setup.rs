//! A town to run the environment on: the site, its free street graphs, the type parameters,
//! a seed and an optional calibration, from which fresh [`Arena`]s are made.
//!
//! [`Setup::default_town`] is the repository's own town (Kotka on the valley terrain), the
//! one the cross-level check, the calibration and the tests run on.

use crate::arena::Arena;
use crate::calibration::Calibration;
use crate::entity::roads::Roads;
use crate::types::TypeBook;
use std::path::Path;
use std::sync::Arc;
use vitro::env::NodeId;
use vitro_site::map::{MapConfig, MapError, Mode, TownMap};
use vitro_site::site::{Site, SiteConfig, SiteError};
use vitro_site::terrain::{Terrain, TerrainError};

/// Why a town could not be set up.
#[derive(Debug, thiserror::Error)]
pub enum SetupError {
    /// The map could not be loaded.
    #[error(transparent)]
    Map(#[from] MapError),
    /// The terrain could not be loaded.
    #[error(transparent)]
    Terrain(#[from] TerrainError),
    /// The town does not fit the terrain.
    #[error(transparent)]
    Site(#[from] SiteError),
}

/// What runs are set up on: the site, its free street graphs, the type parameters, a seed.
#[derive(Clone, Debug)]
pub struct Setup {
    /// Town on terrain.
    pub site: Arc<Site>,
    /// Free street graphs of the site.
    pub roads: Arc<Roads>,
    /// Type parameters.
    pub types: Arc<TypeBook>,
    /// Master seed of every run.
    pub seed: u64,
    /// The calibration of the abstract levels the runs use (none: uncalibrated).
    pub calibration: Option<Arc<Calibration>>,
}

/// The map of the default town (in the repository's `data/`).
pub const DEFAULT_MAP: &str = concat!(env!("CARGO_MANIFEST_DIR"), "/../../data/maps/kotka.osm.pbf");
/// The terrain of the default town (in the repository's `data/`).
pub const DEFAULT_TERRAIN: &str = concat!(
    env!("CARGO_MANIFEST_DIR"),
    "/../../data/terrain/valley_64x64_90m.asc"
);

impl Setup {
    /// A setup on `site` with the built-in types and seed 1.
    pub fn new(site: Arc<Site>) -> Self {
        let roads = Arc::new(Roads::new(&site));
        Setup {
            site,
            roads,
            types: Arc::new(TypeBook::builtin().clone()),
            seed: 1,
            calibration: None,
        }
    }

    /// The town of `map` (.osm.pbf) centred on `terrain` (ESRI ASCII grid or GeoTIFF).
    pub fn from_files(map: &Path, terrain: &Path) -> Result<Self, SetupError> {
        let town = TownMap::load(map, &MapConfig::default())?;
        let ground = Terrain::load(terrain)?;
        let site = Site::new(town, ground, &SiteConfig::default())?;
        Ok(Self::new(Arc::new(site)))
    }

    /// The real town on the real terrain: [`DEFAULT_MAP`] on [`DEFAULT_TERRAIN`].
    pub fn default_town() -> Result<Self, SetupError> {
        Self::from_files(Path::new(DEFAULT_MAP), Path::new(DEFAULT_TERRAIN))
    }

    /// A fresh arena for one run.
    pub fn arena(&self) -> Arena {
        let mut a = Arena::with(self.site.clone(), self.roads.clone(), self.types.clone());
        a.calibration = self.calibration.clone();
        a
    }

    /// The standard trip on `mode`'s free graph: the main-part nodes nearest to the points
    /// 60 % of the way from the town's centre to its south-west and north-east corners
    /// (`None` if the graph has no connected part).
    pub fn standard_trip(&self, mode: Mode) -> Option<(NodeId, NodeId)> {
        let e = self.site.map.extent;
        let g = self.roads.of(mode);
        Some((
            g.nearest_connected([e[0] * 0.6, e[1] * 0.6])?,
            g.nearest_connected([e[2] * 0.6, e[3] * 0.6])?,
        ))
    }
}

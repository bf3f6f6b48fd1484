//! Shared set-up of the tests: the real town on the real terrain, loaded once.

#![allow(dead_code)]

use std::sync::{Arc, OnceLock};
use vitro::env::NodeId;
use vitro_site::map::{MapConfig, TownMap};
use vitro_site::site::{Site, SiteConfig};
use vitro_site::terrain::Terrain;
use vitro_tactical::entity::roads::Roads;
use vitro_tactical::entity::route::Track;
use vitro_tactical::types::{GroundKind, TypeBook};

/// Kotka on the valley terrain, with its free street graphs.
pub fn town() -> (Arc<Site>, Arc<Roads>) {
    static TOWN: OnceLock<(Arc<Site>, Arc<Roads>)> = OnceLock::new();
    TOWN.get_or_init(|| {
        let root = concat!(env!("CARGO_MANIFEST_DIR"), "/../..");
        let map = TownMap::load(
            format!("{root}/data/maps/kotka.osm.pbf"),
            &MapConfig::default(),
        )
        .unwrap();
        let terrain = Terrain::load(format!("{root}/data/terrain/valley_64x64_90m.asc")).unwrap();
        let site = Arc::new(Site::new(map, terrain, &SiteConfig::default()).unwrap());
        let roads = Arc::new(Roads::new(&site));
        (site, roads)
    })
    .clone()
}

/// The track of a ground vehicle of `kind` of `types` along `path` on the drive graph of
/// `roads` (the town's own, or fresh ones).
pub fn plan_drive(roads: &Roads, path: &[NodeId], kind: GroundKind, types: &TypeBook) -> Track {
    let (site, _) = town();
    Track::plan_vehicle(
        &site,
        &roads.drive,
        path,
        types.ground(kind),
        &types.speed_limits,
    )
    .unwrap()
}

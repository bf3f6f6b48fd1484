//! Shared set-up of the level tests: the real town on the real terrain, loaded once.

#![allow(dead_code)]

use std::sync::{Arc, OnceLock};
use vitro::prelude::*;
use vitro_site::map::{MapConfig, TownMap};
use vitro_site::site::{Site, SiteConfig};
use vitro_site::terrain::Terrain;
use vitro_tactical::arena::{Arena, Ev};
use vitro_tactical::entity::roads::Roads;
use vitro_tactical::entity::route::Track;
use vitro_tactical::model::Tactical;
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

/// A fresh arena on the town.
pub fn arena() -> Arena {
    let (site, roads) = town();
    Arena::with(site, roads, Arc::new(TypeBook::builtin().clone()))
}

/// A simulation of a fresh arena.
pub fn sim(seed: u64) -> Simulation<Tactical> {
    Simulation::new(arena(), seed)
}

/// Pose samples: (time s, position, speed).
pub type Samples = Vec<(f64, [f64; 3], f64)>;

/// Runs `sim` to `end`, sampling `id`'s pose after every event that moved time on:
/// (time, position, speed).
pub fn record(sim: &mut Simulation<Tactical>, id: EntityId, end: SimTime) -> Samples {
    let mut out: Samples = Vec::new();
    sim.run(end, |s| {
        if let Some(p) = s.env().pose(id) {
            let t = s.now().as_secs_f64();
            match out.last_mut() {
                Some(last) if last.0 == t => *last = (t, p.pos, p.speed),
                _ => out.push((t, p.pos, p.speed)),
            }
        }
        false
    });
    out
}

/// Starts `id`'s controller now.
pub fn start(sim: &mut Simulation<Tactical>, id: EntityId) {
    sim.schedule(sim.now(), Target::Entity(id), Ev::Start)
        .unwrap();
}

/// Percentile `q` (0..=1) of `v` (NaN if `v` is empty).
pub fn pct(v: &[f64], q: f64) -> f64 {
    let mut v = v.to_vec();
    v.sort_by(f64::total_cmp);
    v.get(((v.len().max(1) - 1) as f64 * q).round() as usize)
        .copied()
        .unwrap_or(f64::NAN)
}

/// A squad member whose legs are stuck (it never moves) but whose radio works: from its
/// first input on it reports its fix to `leader` every half second, as a member's
/// formation link does.
pub struct Stuck {
    /// Its leader.
    pub leader: EntityId,
    beacon: Option<vitro_behaviour::belief::Beacon>,
}

impl Stuck {
    /// A stuck member of `leader`'s squad.
    pub fn new(leader: EntityId) -> Self {
        Stuck {
            leader,
            beacon: None,
        }
    }
}

impl vitro_tactical::model::Controller for Stuck {
    fn handle(&mut self, input: Input<'_, Tactical>, cx: &mut Context<'_, Tactical>) {
        use vitro_behaviour::belief::Beacon;
        match (input, self.beacon.as_mut()) {
            (Input::Timer(Beacon::TIMER), Some(b)) => b.tick(cx),
            (_, None) => {
                let period = SimDuration::from_millis(500);
                let mut b = Beacon::new(period, vitro::comm::Address::Agent(self.leader));
                b.start(cx);
                self.beacon = Some(b);
            }
            _ => {}
        }
    }
}

//! The arena's state for snapshots: every storage, the rigid-body world and the clocks,
//! without the static world (site, street graphs, type parameters), which a restored run
//! takes from its rebuilt scenario.

use super::{Arena, TrackCache};
use crate::condition::Condition;
use crate::entity::air::{LatticeBody, Pilot, ctol::CtolBody, vtol::VtolBody};
use crate::entity::discrete::AtNode;
use crate::entity::ground::interpolated::OnGround;
use crate::entity::ground::physical::{Chassis, Physics};
use crate::entity::roads::Roads;
use crate::entity::route::{Follow, Track};
use crate::entity::troop::Walker;
use crate::types::TypeBook;
use serde::{Deserialize, Serialize};
use std::collections::BTreeMap;
use std::sync::Arc;
use vitro::entity::EntityId;
use vitro::env::EntityStorage;
use vitro::event::EventId;
use vitro::trace::TraceHasher;
use vitro_site::map::Mode;
use vitro_site::site::Site;

use super::Steps;

/// Declares the saved state twice, borrowed for writing and owned for reading, field for
/// field in the same order (so one reads what the other wrote).
macro_rules! arena_state {
    ($($(#[$doc:meta])* $field:ident: $ty:ty,)*) => {
        /// The arena's state, borrowed, for saving (see [`Arena::state`]).
        #[derive(Serialize)]
        pub struct ArenaStateRef<'a> {
            $($(#[$doc])* $field: &'a $ty,)*
            plans: Plans<&'a Track>,
        }
        /// The arena's saved state, read back (see [`Arena::restore`]).
        #[derive(Deserialize)]
        pub struct ArenaState {
            $($(#[$doc])* $field: $ty,)*
            plans: Plans<Track>,
        }
        impl Arena {
            /// The state of the arena for a snapshot: everything but the static world.
            pub fn state(&self) -> ArenaStateRef<'_> {
                ArenaStateRef { $($field: &self.$field,)* plans: self.plans() }
            }
            /// An arena of `site`, `roads` and `types` (rebuilt from the scenario) in a saved
            /// state.
            ///
            /// # Errors
            /// [`RestoreError`] if the state's plans do not fit its trips and routes.
            pub fn restore(
                site: Arc<Site>,
                roads: Arc<Roads>,
                types: Arc<TypeBook>,
                state: ArenaState,
            ) -> Result<Arena, RestoreError> {
                let mut arena = Arena {
                    site,
                    types,
                    roads,
                    // Planned tracks are a cache: a trip plans its track again when needed.
                    tracks: TrackCache::default(),
                    // So are the vision grid (rebuilt from the storages at its first query),
                    // the memo of looks and the line-of-sight memo.
                    vision: Default::default(),
                    sight: Default::default(),
                    // The calibration comes from the scenario: the caller sets it again.
                    calibration: None,
                    $($field: state.$field,)*
                };
                arena.fill_plans(state.plans)?;
                Ok(arena)
            }
            /// An arena of this one's static world (site, roads, types, calibration) in a
            /// saved state: a fresh build's arena taking the state of a saved run.
            ///
            /// # Errors
            /// [`RestoreError`] if the state's plans do not fit its trips and routes.
            pub fn rebuilt(&self, state: ArenaState) -> Result<Arena, RestoreError> {
                let (site, roads, types) = (self.site.clone(), self.roads.clone(), self.types.clone());
                let mut arena = Arena::restore(site, roads, types, state)?;
                arena.calibration = self.calibration.clone();
                Ok(arena)
            }
        }
    };
}

arena_state! {
    steps: Steps,
    at_node: EntityStorage<AtNode>,
    on_ground: EntityStorage<OnGround>,
    chassis: EntityStorage<Chassis>,
    physics: Option<Physics>,
    walkers: EntityStorage<Walker>,
    follow: EntityStorage<Follow>,
    lattice: EntityStorage<LatticeBody>,
    ctol: EntityStorage<CtolBody>,
    vtol: EntityStorage<VtolBody>,
    pilots: EntityStorage<Pilot>,
    conditions: EntityStorage<Condition>,
    next_tick: [Option<EventId>; 3],
}

/// The tracks of the trips and routes under way, which their rows leave out of their
/// serialized form (and of the digest): each distinct track once, and per entity its index.
#[derive(Serialize, Deserialize)]
struct Plans<T> {
    tracks: Vec<T>,
    trips: Vec<(EntityId, usize)>,
    follow: Vec<(EntityId, usize)>,
}

/// Why a saved arena state cannot be restored.
#[derive(Debug, thiserror::Error)]
#[error("the saved arena is inconsistent: {0}")]
pub struct RestoreError(String);

impl Arena {
    fn plans(&self) -> Plans<&Track> {
        let mut tracks: Vec<&Arc<Track>> = Vec::new();
        fn place<'a>(tracks: &mut Vec<&'a Arc<Track>>, t: &'a Arc<Track>) -> usize {
            match tracks.iter().position(|u| Arc::ptr_eq(u, t)) {
                Some(i) => i,
                None => {
                    tracks.push(t);
                    tracks.len() - 1
                }
            }
        }
        let trips = (self.at_node.iter())
            .filter_map(|(id, b)| Some((id, place(&mut tracks, &b.trip.as_ref()?.track))))
            .collect();
        let follow = (self.follow.iter())
            .map(|(id, f)| (id, place(&mut tracks, &f.track)))
            .collect();
        Plans {
            tracks: tracks.into_iter().map(|t| &**t).collect(),
            trips,
            follow,
        }
    }

    /// Puts the saved tracks back into the trips and routes under way.
    fn fill_plans(&mut self, plans: Plans<Track>) -> Result<(), RestoreError> {
        let tracks: Vec<Arc<Track>> = plans.tracks.into_iter().map(Arc::new).collect();
        let lookup = |pairs: Vec<(EntityId, usize)>| -> Result<BTreeMap<EntityId, Arc<Track>>, RestoreError> {
            pairs
                .into_iter()
                .map(|(id, i)| {
                    let t = tracks.get(i).ok_or_else(|| RestoreError(format!("no track {i}")))?;
                    Ok((id, t.clone()))
                })
                .collect()
        };
        let (trips, follow) = (lookup(plans.trips)?, lookup(plans.follow)?);
        let mut filled = 0;
        self.at_node.fill_unrecorded(|id, b| {
            if let (Some(trip), Some(t)) = (b.trip.as_mut(), trips.get(&id)) {
                trip.track = t.clone();
                filled += 1;
            }
        });
        let under_way = self
            .at_node
            .iter()
            .filter(|(_, b)| b.trip.is_some())
            .count();
        if filled != trips.len() || filled != under_way {
            return Err(RestoreError(format!(
                "{under_way} trips under way, {} tracks for them",
                trips.len()
            )));
        }
        let mut filled = 0;
        self.follow.fill_unrecorded(|id, f| {
            if let Some(t) = follow.get(&id) {
                f.track = t.clone();
                filled += 1;
            }
        });
        if filled != follow.len() || filled != self.follow.len() {
            return Err(RestoreError(format!(
                "{} routes under way, {} tracks for them",
                self.follow.len(),
                follow.len()
            )));
        }
        Ok(())
    }
}

/// A digest of the static world: the line-of-sight mesh (ground, buildings, bridges) and the
/// street points of both graphs. A snapshot stores it so that a run is resumed only on the
/// world it was saved on.
pub fn site_digest(site: &Site) -> u64 {
    let mut h = TraceHasher::default();
    let mesh = site.los.trimesh();
    for v in mesh.vertices() {
        for c in [v.x, v.y, v.z] {
            h.write_u64(u64::from(c.to_bits()));
        }
    }
    for t in mesh.indices() {
        for &i in t {
            h.write_u64(u64::from(i));
        }
    }
    for mode in [Mode::Drive, Mode::Walk] {
        let mut n = 0;
        while let Some(p) = site.street_point(mode, vitro::env::NodeId(n)) {
            for c in p {
                h.write_u64(c.to_bits());
            }
            n += 1;
        }
    }
    h.finish()
}

//! The arena's cache of planned tracks: a trip's track depends only on the body's kind, its
//! start and goal nodes (and the level, where a calibration stretches it), and vehicles on
//! rounds drive the same trips again, so a track planned once is shared by the trips that
//! drive it. The cache is transparent: a track taken from it is the one planning would give.

use crate::entity::Level;
use crate::entity::discrete::NodeKind;
use crate::entity::route::Track;
use std::collections::HashMap;
use std::sync::Arc;
use vitro::env::NodeId;

/// Most tracks kept at once; the cache is emptied when it is full.
const TRACK_CACHE_MAX: usize = 4096;

/// Most bytes of track the cache keeps at once (a track holds a point a metre, 56 bytes
/// each: 64 MiB is about 1,200 tracks of a kilometre); it is emptied when a new track would
/// pass it. The count alone let 10,000 entities' cars keep 4,096 long tracks, over 400 MiB.
const TRACK_CACHE_BYTES: usize = 64 << 20;

/// A cached track: body kind, start, goal, and the level if a calibration stretched it.
pub(crate) type TrackKey = (NodeKind, NodeId, NodeId, Option<Level>);

/// Planned tracks, shared by the trips that drive them.
#[derive(Debug, Default)]
pub(crate) struct TrackCache {
    tracks: HashMap<TrackKey, Arc<Track>>,
    /// Bytes the kept tracks hold ([`bytes`]).
    bytes: usize,
}

/// The bytes `t` holds on the heap.
fn bytes(t: &Track) -> usize {
    let floats = t.s.capacity() + t.limit.capacity() + t.v.capacity() + t.t.capacity();
    size_of::<[f64; 3]>() * t.pts.capacity()
        + size_of::<f64>() * floats
        + size_of::<(usize, NodeId)>() * t.nodes.capacity()
}

impl TrackCache {
    /// The track of `key`, planned by `plan` the first time.
    pub(crate) fn get_or_plan<E>(
        &mut self,
        key: TrackKey,
        plan: impl FnOnce() -> Result<Track, E>,
    ) -> Result<Arc<Track>, E> {
        if let Some(t) = self.tracks.get(&key) {
            return Ok(t.clone());
        }
        let t = Arc::new(plan()?);
        let b = bytes(&t);
        if self.tracks.len() >= TRACK_CACHE_MAX || self.bytes + b > TRACK_CACHE_BYTES {
            self.tracks.clear();
            self.bytes = 0;
        }
        self.tracks.insert(key, t.clone());
        self.bytes += b;
        Ok(t)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::types::GroundKind;

    /// A track of `n` points (only its size matters here).
    fn track(n: usize) -> Track {
        Track {
            pts: vec![[0.0; 3]; n],
            s: vec![0.0; n],
            limit: vec![0.0; n],
            v: vec![0.0; n],
            t: vec![0.0; n],
            nodes: Vec::new(),
        }
    }

    fn key(goal: u32) -> TrackKey {
        (
            NodeKind::Ground(GroundKind::Car),
            NodeId(0),
            NodeId(goal),
            None,
        )
    }

    #[test]
    fn a_track_is_planned_once_and_shared() {
        let mut c = TrackCache::default();
        let mut planned = 0;
        let mut get = |c: &mut TrackCache, goal| {
            c.get_or_plan(key(goal), || {
                planned += 1;
                Ok::<_, ()>(track(10))
            })
            .unwrap()
        };
        let a = get(&mut c, 1);
        let b = get(&mut c, 1);
        assert!(Arc::ptr_eq(&a, &b));
        get(&mut c, 2);
        assert_eq!(planned, 2);
        assert_eq!(c.bytes, 2 * bytes(&track(10)));
    }

    #[test]
    fn the_cache_keeps_at_most_its_bytes() {
        let mut c = TrackCache::default();
        // 100,000 points: 5.6 MB a track, so 11 fit in 64 MiB and the 12th empties the cache.
        let each = bytes(&track(100_000));
        let fit = TRACK_CACHE_BYTES / each;
        for goal in 0..fit as u32 {
            c.get_or_plan(key(goal), || Ok::<_, ()>(track(100_000)))
                .unwrap();
        }
        assert_eq!((c.tracks.len(), c.bytes), (fit, fit * each));
        c.get_or_plan(key(999), || Ok::<_, ()>(track(100_000)))
            .unwrap();
        assert_eq!((c.tracks.len(), c.bytes), (1, each));
        assert!(c.bytes <= TRACK_CACHE_BYTES);
    }

    #[test]
    fn a_failed_plan_keeps_nothing() {
        let mut c = TrackCache::default();
        assert_eq!(
            c.get_or_plan(key(1), || Err::<Track, _>("no path")),
            Err("no path")
        );
        assert!(c.tracks.is_empty() && c.bytes == 0);
    }
}

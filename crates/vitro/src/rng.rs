//! Deterministic random numbers: named streams derived from the master seed.
//!
//! A stream is identified by (owner, purpose): the owner is an entity or the simulation itself,
//! the purpose a name such as `"gps-noise"`. Its seed depends only on the master seed, the owner
//! and the purpose, so adding an entity never changes the numbers another entity draws.
//!
//! ```
//! use rand::Rng;
//! use vitro::entity::EntityId;
//! use vitro::rng::{Owner, RngStreams};
//! let mut a = RngStreams::new(42);
//! let mut b = RngStreams::new(42);
//! let _ = b.stream(Owner::Entity(EntityId(7)), "other").random::<u64>(); // b draws elsewhere first
//! let x: u64 = a.stream(Owner::Entity(EntityId(1)), "move").random();
//! let y: u64 = b.stream(Owner::Entity(EntityId(1)), "move").random();
//! assert_eq!(x, y);
//! ```

mod small;

use crate::entity::EntityId;
use crate::trace::{TraceHasher, stable_str_hash};
use rand::SeedableRng;
use rand_chacha::ChaCha8Rng;
use serde::{Deserialize, Serialize};
pub use small::SplitMix64;

/// Who owns a random stream.
#[derive(Copy, Clone, Debug, PartialEq, Eq, PartialOrd, Ord, Hash, Serialize, Deserialize)]
pub enum Owner {
    /// The simulation itself (channels, scenario set-up, ...).
    Global,
    /// One entity.
    Entity(EntityId),
}

/// The set of named random streams of one run.
///
/// Streams are kept per owner (the simulation first, then entities by id), each owner's in
/// order of first use: an owner's first stream inline in one dense table indexed by the
/// owner (one access finds it and its generator's position), the others in a list per
/// owner, scanned by the purposes' hashes (no name is read: a lookup costs a memory access
/// or two, which matters when thousands of agents draw in turn). A stream is thus known by
/// its owner and the [`stable_str_hash`] of its purpose, as its seed is: two purposes whose
/// names hash alike (a chance of 2^-64 a pair; hashes 0 and 1 count as alike, 0 marking an
/// empty row) would share one stream, where they would otherwise have had two streams of
/// the same seed. It serializes as the list of `(purpose, stream)` pairs per owner.
///
/// Besides the ChaCha8 streams ([`stream`](Self::stream)) it keeps small ones
/// ([`small`](Self::small): [`SplitMix64`], 8 bytes of state) for models whose many agents
/// each draw a few numbers per activation: an owner's first small stream is stored inline in
/// one dense table (16 bytes an owner), so finding and drawing from it touches one cache line.
#[derive(Clone, Debug)]
pub struct RngStreams {
    master: u64,
    /// Per owner slot: the key of its first stream (0: none yet), apart from the streams so
    /// that finding a stream reads a dense table (eight owners a cache line) and then only
    /// the lines of the generator that the draw reads.
    first_key: Vec<u64>,
    /// Per owner slot: its first stream (an empty row where `first_key` is 0).
    first: Vec<Stream>,
    /// Per owner slot: its streams beyond the first, in order of creation (may be shorter
    /// than `first`).
    more: Vec<Vec<Stream>>,
    /// Per owner slot: its first small stream (`key` 0: none yet).
    small: Vec<SmallStream>,
    /// Small streams beyond an owner's first: (owner slot, stream).
    small_more: Vec<(usize, SmallStream)>,
    /// The purposes of the small streams, by hash.
    small_names: std::collections::BTreeMap<u64, Box<str>>,
}

/// A small stream and the hash of its purpose (never 0: see [`small_key`]).
#[derive(Copy, Clone, Debug, Default)]
struct SmallStream {
    key: u64,
    rng: SplitMix64Slot,
}

/// A [`SplitMix64`] that has a `Default` (for empty table rows).
#[derive(Copy, Clone, Debug)]
struct SplitMix64Slot(SplitMix64);

impl Default for SplitMix64Slot {
    fn default() -> Self {
        SplitMix64Slot(SplitMix64::new(0))
    }
}

/// The key of a small stream's purpose: its [`stable_str_hash`], with 0 (the mark of an
/// empty row) moved to 1.
#[inline]
fn small_key(purpose: &str) -> u64 {
    stable_str_hash(purpose).max(1)
}

/// The key of a stream's purpose: its [`stable_str_hash`] (its seed's), with 0 (the mark of
/// an empty row) moved to 1.
#[inline]
fn stream_key(purpose: &str) -> u64 {
    stable_str_hash(purpose).max(1)
}

/// One named stream and the key of its name ([`stream_key`]). The key comes first and the
/// generator right after it (`repr(C)`), the whole aligned on a cache line (384 bytes): a
/// scan's first touch of a cold stream then brings in the first of the generator's numbers
/// too, and every stream of the dense table of first streams lies the same way across
/// lines. (The generator, as rustc lays out `rand_core`'s `BlockRng` today, holds its 64
/// numbers first and its position last, 304 bytes on: a draw reads the position's line and
/// the next numbers' line, which no order of this struct's fields brings together.)
#[derive(Clone, Debug)]
#[repr(C, align(64))]
struct Stream {
    key: u64,
    rng: ChaCha8Rng,
    name: Box<str>,
}

impl Stream {
    /// An empty row of the table of first streams.
    fn empty() -> Self {
        Stream {
            key: 0,
            rng: ChaCha8Rng::from_seed([0; 32]),
            name: "".into(),
        }
    }

    /// The stream of `name`, whose generator is `rng`.
    fn named(name: Box<str>, rng: ChaCha8Rng) -> Self {
        Stream {
            key: stream_key(&name),
            rng,
            name,
        }
    }
}

/// The serialized form of [`RngStreams`].
/// The small streams follow: each owner's first (purpose and generator) by owner slot, then
/// the others as `(owner slot, purpose, generator)` in order of creation.
#[derive(Serialize)]
#[serde(rename = "RngStreams")]
struct Wire<'a> {
    master: u64,
    streams: Vec<Vec<(&'a str, &'a ChaCha8Rng)>>,
    small: Vec<Option<(&'a str, SplitMix64)>>,
    small_more: Vec<(u64, &'a str, SplitMix64)>,
}

/// The deserialized form of [`RngStreams`].
#[derive(Deserialize)]
#[serde(rename = "RngStreams")]
struct WireOwned {
    master: u64,
    streams: Vec<Vec<(Box<str>, ChaCha8Rng)>>,
    small: Vec<Option<(Box<str>, SplitMix64)>>,
    small_more: Vec<(u64, Box<str>, SplitMix64)>,
}

impl Serialize for RngStreams {
    fn serialize<S: serde::Serializer>(&self, s: S) -> Result<S::Ok, S::Error> {
        let name = |k: &u64| self.small_names.get(k).map_or("", |n| &**n);
        let small = self
            .small
            .iter()
            .map(|x| (x.key != 0).then(|| (name(&x.key), x.rng.0)))
            .collect();
        let small_more = self
            .small_more
            .iter()
            .map(|(slot, x)| (*slot as u64, name(&x.key), x.rng.0))
            .collect();
        Wire {
            master: self.master,
            streams: self
                .first
                .iter()
                .enumerate()
                .map(|(slot, x)| {
                    let more = self.more.get(slot).map_or(&[][..], Vec::as_slice);
                    std::iter::once(x)
                        .filter(|x| x.key != 0)
                        .chain(more)
                        .map(|x| (&*x.name, &x.rng))
                        .collect()
                })
                .collect(),
            small,
            small_more,
        }
        .serialize(s)
    }
}

impl<'de> Deserialize<'de> for RngStreams {
    fn deserialize<D: serde::Deserializer<'de>>(d: D) -> Result<Self, D::Error> {
        let w = WireOwned::deserialize(d)?;
        let mut small_names = std::collections::BTreeMap::new();
        let mut named = |name: Box<str>, rng| {
            let key = small_key(&name);
            small_names.insert(key, name);
            SmallStream {
                key,
                rng: SplitMix64Slot(rng),
            }
        };
        let small: Vec<SmallStream> = w
            .small
            .into_iter()
            .map(|x| x.map_or_else(SmallStream::default, |(n, r)| named(n, r)))
            .collect();
        let mut small_more = Vec::with_capacity(w.small_more.len());
        for (slot, name, rng) in w.small_more {
            // Only an owner with a first small stream has others.
            let slot = usize::try_from(slot)
                .ok()
                .filter(|&s| small.get(s).is_some_and(|x| x.key != 0))
                .ok_or_else(|| serde::de::Error::custom("small stream of an unknown owner"))?;
            small_more.push((slot, named(name, rng)));
        }
        let mut first = Vec::with_capacity(w.streams.len());
        let mut first_key = Vec::with_capacity(w.streams.len());
        let mut more = Vec::new();
        for (slot, list) in w.streams.into_iter().enumerate() {
            let mut list = list.into_iter().map(|(n, r)| Stream::named(n, r));
            let x = list.next().unwrap_or_else(Stream::empty);
            first_key.push(x.key);
            first.push(x);
            let rest: Vec<Stream> = list.collect();
            if !rest.is_empty() {
                more.resize_with(slot + 1, Vec::new);
                more[slot] = rest;
            }
        }
        Ok(RngStreams {
            master: w.master,
            first_key,
            first,
            more,
            small,
            small_more,
            small_names,
        })
    }
}

impl RngStreams {
    /// Streams derived from `master_seed`.
    pub fn new(master_seed: u64) -> Self {
        RngStreams {
            master: master_seed,
            first_key: Vec::new(),
            first: Vec::new(),
            more: Vec::new(),
            small: Vec::new(),
            small_more: Vec::new(),
            small_names: std::collections::BTreeMap::new(),
        }
    }

    /// The master seed.
    pub fn master_seed(&self) -> u64 {
        self.master
    }

    /// The stream for (owner, purpose), created on first use.
    #[inline]
    pub fn stream(&mut self, owner: Owner, purpose: &str) -> &mut ChaCha8Rng {
        let slot = slot_of(owner);
        let key = stream_key(purpose);
        if self.first_key.get(slot) == Some(&key) {
            return &mut self.first[slot].rng;
        }
        self.stream_slow(owner, purpose)
    }

    /// The stream of (owner, purpose) when it is not its owner's first, or is new.
    #[cold]
    #[inline(never)]
    fn stream_slow(&mut self, owner: Owner, purpose: &str) -> &mut ChaCha8Rng {
        let slot = slot_of(owner);
        let key = stream_key(purpose);
        if self.first.len() <= slot {
            self.first.resize_with(slot + 1, Stream::empty);
            self.first_key.resize(slot + 1, 0);
        }
        let fresh = |master| Stream {
            key,
            name: purpose.into(),
            rng: ChaCha8Rng::from_seed(derive_seed(master, owner, stable_str_hash(purpose))),
        };
        if self.first_key[slot] == 0 {
            self.first_key[slot] = key;
            self.first[slot] = fresh(self.master);
            return &mut self.first[slot].rng;
        }
        if self.more.len() <= slot {
            self.more.resize_with(slot + 1, Vec::new);
        }
        let list = &mut self.more[slot];
        let i = match list.iter().position(|x| x.key == key) {
            Some(i) => i,
            None => {
                list.push(fresh(self.master));
                list.len() - 1
            }
        };
        &mut list[i].rng
    }

    /// The small stream ([`SplitMix64`]) for (owner, purpose), created on first use: a
    /// stream of its own, not the ChaCha8 one of the same name, and as independent of the
    /// other owners and purposes. For agents that draw a few numbers per activation by
    /// the thousand: its state is 8 bytes, kept inline for an owner's first purpose.
    ///
    /// ```
    /// use rand::Rng;
    /// use vitro::entity::EntityId;
    /// use vitro::rng::{Owner, RngStreams};
    /// let mut a = RngStreams::new(42);
    /// let mut b = RngStreams::new(42);
    /// let _ = b.small(Owner::Entity(EntityId(9)), "walk").random::<u64>(); // b draws elsewhere first
    /// let x: u64 = a.small(Owner::Entity(EntityId(1)), "walk").random();
    /// let y: u64 = b.small(Owner::Entity(EntityId(1)), "walk").random();
    /// assert_eq!(x, y);
    /// ```
    #[inline]
    pub fn small(&mut self, owner: Owner, purpose: &str) -> &mut SplitMix64 {
        let slot = slot_of(owner);
        let key = small_key(purpose);
        if self.small.get(slot).is_some_and(|x| x.key == key) {
            return &mut self.small[slot].rng.0;
        }
        self.small_slow(owner, purpose, key)
    }

    /// The small stream of (owner, purpose) when it is not its owner's first, or is new.
    #[cold]
    #[inline(never)]
    fn small_slow(&mut self, owner: Owner, purpose: &str, key: u64) -> &mut SplitMix64 {
        let slot = slot_of(owner);
        if self.small.len() <= slot {
            self.small.resize(slot + 1, SmallStream::default());
        }
        if self.small[slot].key != 0 {
            let at = self
                .small_more
                .iter()
                .position(|(s, x)| *s == slot && x.key == key);
            let at = match at {
                Some(i) => i,
                None => {
                    let x = self.new_small(owner, purpose, key);
                    self.small_more.push((slot, x));
                    self.small_more.len() - 1
                }
            };
            return &mut self.small_more[at].1.rng.0;
        }
        let x = self.new_small(owner, purpose, key);
        self.small[slot] = x;
        &mut self.small[slot].rng.0
    }

    /// A new small stream for (owner, purpose), its name remembered for snapshots.
    fn new_small(&mut self, owner: Owner, purpose: &str, key: u64) -> SmallStream {
        self.small_names
            .entry(key)
            .or_insert_with(|| purpose.into());
        SmallStream {
            key,
            rng: SplitMix64Slot(SplitMix64::new(derive_small_seed(self.master, owner, key))),
        }
    }

    /// A stream for (owner, purpose) independent of this set's state: same seed as
    /// [`stream`](Self::stream) would start from, useful for set-up code.
    pub fn fresh(&self, owner: Owner, purpose: &str) -> ChaCha8Rng {
        ChaCha8Rng::from_seed(derive_seed(self.master, owner, stable_str_hash(purpose)))
    }
}

/// The index of an owner's streams: the simulation first, then entities by id.
#[inline]
fn slot_of(owner: Owner) -> usize {
    match owner {
        Owner::Global => 0,
        Owner::Entity(e) => e.index() + 1,
    }
}

/// The seed of a small stream: as a ChaCha stream's, with a word of its own so that the two
/// kinds of stream of one (owner, purpose) are unrelated.
fn derive_small_seed(master: u64, owner: Owner, purpose: u64) -> u64 {
    let mut h = TraceHasher::default();
    h.write_u64(master);
    match owner {
        Owner::Global => h.write_u64(u64::MAX),
        Owner::Entity(e) => h.write_u64(e.0 as u64),
    }
    h.write_u64(purpose);
    h.write_u64(0x5350_4C49_544D_4958); // "SPLITMIX"
    h.finish()
}

fn derive_seed(master: u64, owner: Owner, purpose: u64) -> [u8; 32] {
    let mut h = TraceHasher::default();
    h.write_u64(master);
    match owner {
        Owner::Global => h.write_u64(u64::MAX),
        Owner::Entity(e) => h.write_u64(e.0 as u64),
    }
    h.write_u64(purpose);
    let mut seed = [0u8; 32];
    for (i, chunk) in seed.chunks_exact_mut(8).enumerate() {
        h.write_u64(i as u64);
        chunk.copy_from_slice(&h.finish().to_le_bytes());
    }
    seed
}

#[cfg(test)]
mod tests {
    use super::*;
    use rand::Rng;

    #[test]
    fn streams_differ_by_owner_purpose_and_seed() {
        let mut s = RngStreams::new(1);
        let a: u64 = s.stream(Owner::Entity(EntityId(0)), "a").random();
        let b: u64 = s.stream(Owner::Entity(EntityId(0)), "b").random();
        let c: u64 = s.stream(Owner::Entity(EntityId(1)), "a").random();
        let d: u64 = RngStreams::new(2)
            .stream(Owner::Entity(EntityId(0)), "a")
            .random();
        assert!(a != b && a != c && a != d);
    }

    #[test]
    fn first_and_later_streams_draw_from_their_seeds_whatever_the_order() {
        let e = |i| Owner::Entity(EntityId(i));
        let asks = [
            (e(4), "a"),
            (e(4), "b"),
            (e(2), "b"),
            (e(4), "c"),
            (Owner::Global, "a"),
        ];
        let mut s = RngStreams::new(3);
        let mut t = RngStreams::new(3);
        for round in 0..3 {
            for (i, &(o, p)) in asks.iter().enumerate() {
                let x: u64 = s.stream(o, p).random();
                // `t` asks in the other order, so its first streams are other purposes.
                let (o2, p2) = asks[asks.len() - 1 - i];
                let _: u64 = t.stream(o2, p2).random();
                let mut fresh = s.fresh(o, p);
                for _ in 0..round {
                    let _: u64 = fresh.random();
                }
                assert_eq!(x, fresh.random::<u64>(), "{o:?} {p} round {round}");
            }
        }
        for &(o, p) in &asks {
            assert_eq!(
                s.stream(o, p).random::<u64>(),
                t.stream(o, p).random::<u64>()
            );
        }
        assert_eq!(s.first.len(), 6);
        assert_eq!(s.more[5].len(), 2, "entity 4's later streams");
        assert_eq!(std::mem::align_of::<Stream>(), 64);
    }

    #[test]
    fn serde_round_trip_keeps_position() {
        let mut s = RngStreams::new(9);
        let _: u64 = s.stream(Owner::Global, "x").random();
        let bytes = postcard::to_stdvec(&s).unwrap();
        let mut r: RngStreams = postcard::from_bytes(&bytes).unwrap();
        let x: u64 = s.stream(Owner::Global, "x").random();
        let y: u64 = r.stream(Owner::Global, "x").random();
        assert_eq!(x, y);
    }

    #[test]
    fn serializes_as_name_and_stream_pairs_per_owner() {
        // The form snapshots hold: what `#[derive(Serialize)]` gave before the hashes.
        #[derive(Serialize)]
        struct Before {
            master: u64,
            streams: Vec<Vec<(Box<str>, ChaCha8Rng)>>,
            small: Vec<Option<(Box<str>, SplitMix64)>>,
            small_more: Vec<(u64, Box<str>, SplitMix64)>,
        }
        let mut s = RngStreams::new(9);
        let _: u64 = s.stream(Owner::Global, "a").random();
        let _: u64 = s.stream(Owner::Entity(EntityId(1)), "b").random();
        let _: u64 = s.stream(Owner::Entity(EntityId(1)), "c").random();
        let rng = |s: &mut RngStreams, o, p| s.stream(o, p).clone();
        let before = Before {
            master: 9,
            streams: vec![
                vec![("a".into(), rng(&mut s, Owner::Global, "a"))],
                vec![],
                vec![
                    ("b".into(), rng(&mut s, Owner::Entity(EntityId(1)), "b")),
                    ("c".into(), rng(&mut s, Owner::Entity(EntityId(1)), "c")),
                ],
            ],
            small: vec![],
            small_more: vec![],
        };
        let bytes = postcard::to_stdvec(&s).unwrap();
        assert_eq!(bytes, postcard::to_stdvec(&before).unwrap());
        let mut r: RngStreams = postcard::from_bytes(&bytes).unwrap();
        let x: u64 = s.stream(Owner::Entity(EntityId(1)), "c").random();
        let y: u64 = r.stream(Owner::Entity(EntityId(1)), "c").random();
        assert_eq!(x, y);
    }

    #[test]
    fn small_streams_are_independent_and_survive_a_round_trip() {
        let mut s = RngStreams::new(5);
        let e = |i| Owner::Entity(EntityId(i));
        let a: u64 = s.small(e(3), "walk").random();
        let b: u64 = s.small(e(3), "breed").random(); // not the owner's first: the overflow
        let c: u64 = s.small(e(4), "walk").random();
        let d: u64 = s.small(Owner::Global, "walk").random();
        let chacha: u64 = s.stream(e(3), "walk").random();
        let all = [a, b, c, d, chacha];
        for (i, x) in all.iter().enumerate() {
            assert!(all[i + 1..].iter().all(|y| y != x), "{all:?}");
        }
        // The same draws from a fresh set, whatever the order of creation.
        let mut t = RngStreams::new(5);
        assert_eq!(t.small(e(4), "walk").random::<u64>(), c);
        assert_eq!(t.small(e(3), "breed").random::<u64>(), b);
        assert_eq!(t.small(e(3), "walk").random::<u64>(), a);
        // A snapshot continues each stream where it was.
        let bytes = postcard::to_stdvec(&s).unwrap();
        let mut r: RngStreams = postcard::from_bytes(&bytes).unwrap();
        for (o, p) in [
            (e(3), "walk"),
            (e(3), "breed"),
            (e(4), "walk"),
            (Owner::Global, "walk"),
        ] {
            let x: u64 = s.small(o, p).random();
            let y: u64 = r.small(o, p).random();
            assert_eq!(x, y, "{o:?} {p}");
        }
        assert_eq!(
            postcard::to_stdvec(&r).unwrap(),
            postcard::to_stdvec(&s).unwrap()
        );
    }
}

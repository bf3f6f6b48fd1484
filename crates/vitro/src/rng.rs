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

use crate::entity::EntityId;
use crate::trace::{TraceHasher, stable_str_hash};
use rand::SeedableRng;
use rand_chacha::ChaCha8Rng;
use serde::{Deserialize, Serialize};

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
/// order of first use: a lookup is an index and a scan of that owner's few purposes by the
/// purposes' hashes, kept with the streams (no name is read: a lookup costs a memory access
/// or two, which matters when thousands of agents draw in turn). A stream is thus known by
/// its owner and the [`stable_str_hash`] of its purpose, as its seed is: two purposes whose
/// names hash alike (a chance of 2^-64 a pair) would share one stream, where they would
/// otherwise have had two streams of the same seed. It serializes as the list of
/// `(purpose, stream)` pairs per owner.
#[derive(Clone, Debug)]
pub struct RngStreams {
    master: u64,
    streams: Vec<Vec<Stream>>,
}

/// One named stream and the hash of its name. The hash comes first and the generator right
/// after it (`repr(C)`): a lookup's first touch of a cold stream then brings in the start
/// of the generator's state too.
#[derive(Clone, Debug)]
#[repr(C)]
struct Stream {
    key: u64,
    rng: ChaCha8Rng,
    name: Box<str>,
}

/// The serialized form of [`RngStreams`].
#[derive(Serialize)]
#[serde(rename = "RngStreams")]
struct Wire<'a> {
    master: u64,
    streams: Vec<Vec<(&'a str, &'a ChaCha8Rng)>>,
}

/// The deserialized form of [`RngStreams`].
#[derive(Deserialize)]
#[serde(rename = "RngStreams")]
struct WireOwned {
    master: u64,
    streams: Vec<Vec<(Box<str>, ChaCha8Rng)>>,
}

impl Serialize for RngStreams {
    fn serialize<S: serde::Serializer>(&self, s: S) -> Result<S::Ok, S::Error> {
        Wire {
            master: self.master,
            streams: self
                .streams
                .iter()
                .map(|l| l.iter().map(|x| (&*x.name, &x.rng)).collect())
                .collect(),
        }
        .serialize(s)
    }
}

impl<'de> Deserialize<'de> for RngStreams {
    fn deserialize<D: serde::Deserializer<'de>>(d: D) -> Result<Self, D::Error> {
        let w = WireOwned::deserialize(d)?;
        Ok(RngStreams {
            master: w.master,
            streams: w
                .streams
                .into_iter()
                .map(|l| {
                    l.into_iter()
                        .map(|(name, rng)| Stream {
                            key: stable_str_hash(&name),
                            name,
                            rng,
                        })
                        .collect()
                })
                .collect(),
        })
    }
}

impl RngStreams {
    /// Streams derived from `master_seed`.
    pub fn new(master_seed: u64) -> Self {
        RngStreams {
            master: master_seed,
            streams: Vec::new(),
        }
    }

    /// The master seed.
    pub fn master_seed(&self) -> u64 {
        self.master
    }

    /// The stream for (owner, purpose), created on first use.
    pub fn stream(&mut self, owner: Owner, purpose: &str) -> &mut ChaCha8Rng {
        let slot = match owner {
            Owner::Global => 0,
            Owner::Entity(e) => e.index() + 1,
        };
        if self.streams.len() <= slot {
            self.streams.resize_with(slot + 1, Vec::new);
        }
        let key = stable_str_hash(purpose);
        let list = &mut self.streams[slot];
        let i = match list.iter().position(|x| x.key == key) {
            Some(i) => i,
            None => {
                let seed = derive_seed(self.master, owner, key);
                list.push(Stream {
                    key,
                    name: purpose.into(),
                    rng: ChaCha8Rng::from_seed(seed),
                });
                list.len() - 1
            }
        };
        &mut list[i].rng
    }

    /// A stream for (owner, purpose) independent of this set's state: same seed as
    /// [`stream`](Self::stream) would start from, useful for set-up code.
    pub fn fresh(&self, owner: Owner, purpose: &str) -> ChaCha8Rng {
        ChaCha8Rng::from_seed(derive_seed(self.master, owner, stable_str_hash(purpose)))
    }
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
        };
        let bytes = postcard::to_stdvec(&s).unwrap();
        assert_eq!(bytes, postcard::to_stdvec(&before).unwrap());
        let mut r: RngStreams = postcard::from_bytes(&bytes).unwrap();
        let x: u64 = s.stream(Owner::Entity(EntityId(1)), "c").random();
        let y: u64 = r.stream(Owner::Entity(EntityId(1)), "c").random();
        assert_eq!(x, y);
    }
}

//! Entities: identities (id + name). An agent is a brain; its body is state in storages.

mod map;

pub use map::EntityMap;
use serde::{Deserialize, Serialize};
use std::collections::{BTreeMap, HashMap};
use std::fmt;
use std::hash::{BuildHasherDefault, Hasher};

/// Identity of an entity: a dense index, assigned in creation order.
#[derive(
    Copy, Clone, Debug, PartialEq, Eq, PartialOrd, Ord, Hash, Default, Serialize, Deserialize,
)]
#[serde(transparent)]
pub struct EntityId(pub u32);

impl EntityId {
    /// The index of this entity in creation order.
    pub fn index(self) -> usize {
        self.0 as usize
    }
}

impl fmt::Display for EntityId {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(f, "#{}", self.0)
    }
}

/// Errors of the entity directory.
#[derive(Debug, Clone, PartialEq, Eq, thiserror::Error)]
pub enum EntityError {
    /// Two entities may not share a name.
    #[error("an entity named {0:?} already exists")]
    DuplicateName(String),
}

/// The directory of all entities of a simulation: ids in creation order, unique names.
///
/// The empty name names nothing: an entity created with it is unnamed (known by its id
/// only), any number of entities may be, and `lookup("")` finds none of them. A model that
/// adds agents by the thousand and never looks them up by name (the newborns of a
/// predator-prey model, say) saves a name and its index entry each.
///
/// Names are found through an index on their [`stable_str_hash`](crate::trace::stable_str_hash)
/// (an entity whose name's hash another name already has goes to a second index by name, a
/// chance of 2^-64 a pair): creating an entity costs a hash and a hash-table insert, not
/// comparisons of names, which counts when a model adds agents by the thousand. The table is
/// keyed by the names' stable hashes themselves (no per-process seed) and never iterated.
/// Only the names are serialized; the index is rebuilt on the way in, and a duplicate name
/// there is an error.
#[derive(Clone, Debug, Default, Serialize, Deserialize)]
#[serde(try_from = "EntityNames", into = "EntityNames")]
pub struct Entities {
    names: Vec<String>,
    by_hash: HashMap<u64, EntityId, BuildHasherDefault<KeyIsHash>>,
    /// Names whose hash an earlier name has.
    collided: BTreeMap<String, EntityId>,
}

/// A hasher for keys that are already stable hashes: the key itself.
#[derive(Default)]
struct KeyIsHash(u64);

impl Hasher for KeyIsHash {
    fn finish(&self) -> u64 {
        self.0
    }
    fn write(&mut self, bytes: &[u8]) {
        // Only u64 keys come here (`write_u64`); any other input is folded in, to stay a hash.
        for &b in bytes {
            self.0 = (self.0.rotate_left(8) ^ u64::from(b)).wrapping_mul(0x9E37_79B9_7F4A_7C15);
        }
    }
    fn write_u64(&mut self, k: u64) {
        self.0 = k;
    }
}

/// The serialized form of [`Entities`]: the names in id order.
#[derive(Serialize, Deserialize)]
struct EntityNames {
    names: Vec<String>,
}

impl From<Entities> for EntityNames {
    fn from(e: Entities) -> Self {
        EntityNames { names: e.names }
    }
}

impl TryFrom<EntityNames> for Entities {
    type Error = EntityError;
    fn try_from(n: EntityNames) -> Result<Self, EntityError> {
        let mut e = Entities::default();
        for name in n.names {
            e.create(name)?;
        }
        Ok(e)
    }
}

impl Entities {
    /// Creates an entity with a unique name.
    pub fn create(&mut self, name: impl Into<String>) -> Result<EntityId, EntityError> {
        let name = name.into();
        let id = EntityId(u32::try_from(self.names.len()).expect("more than 2^32 entities"));
        if name.is_empty() {
            self.names.push(name);
            return Ok(id);
        }
        // One probe of the index: a new hash (the usual case), or a name to compare.
        match self.by_hash.entry(crate::trace::stable_str_hash(&name)) {
            std::collections::hash_map::Entry::Vacant(v) => {
                v.insert(id);
            }
            std::collections::hash_map::Entry::Occupied(o) => {
                if self.names[o.get().index()] == name || self.collided.contains_key(&name) {
                    return Err(EntityError::DuplicateName(name));
                }
                self.collided.insert(name.clone(), id);
            }
        }
        self.names.push(name);
        Ok(id)
    }
    /// The entity called `name`.
    pub fn lookup(&self, name: &str) -> Option<EntityId> {
        if name.is_empty() {
            return None;
        }
        let id = *self.by_hash.get(&crate::trace::stable_str_hash(name))?;
        if self.names[id.index()] == name {
            Some(id)
        } else {
            self.collided.get(name).copied()
        }
    }
    /// The name of `id`.
    pub fn name(&self, id: EntityId) -> Option<&str> {
        self.names.get(id.index()).map(String::as_str)
    }
    /// Number of entities.
    pub fn len(&self) -> usize {
        self.names.len()
    }
    /// True if there are no entities.
    pub fn is_empty(&self) -> bool {
        self.names.is_empty()
    }
    /// All ids, in creation order.
    pub fn ids(&self) -> impl Iterator<Item = EntityId> + '_ {
        (0..self.names.len() as u32).map(EntityId)
    }
}

/// Who offers which capability: a directory service ("yellow pages").
///
/// ```
/// use vitro::entity::{CapabilityRegister, EntityId};
/// let mut reg = CapabilityRegister::default();
/// reg.offer(EntityId(3), "transport");
/// reg.offer(EntityId(1), "transport");
/// reg.offer(EntityId(1), "surveillance");
/// assert_eq!(reg.providers("transport").collect::<Vec<_>>(), [EntityId(1), EntityId(3)]);
/// reg.withdraw(EntityId(1), "transport");
/// assert_eq!(reg.providers("transport").collect::<Vec<_>>(), [EntityId(3)]);
/// assert_eq!(reg.capabilities_of(EntityId(1)).collect::<Vec<_>>(), ["surveillance"]);
/// ```
#[derive(Clone, Debug, Default, Serialize, Deserialize)]
pub struct CapabilityRegister {
    providers: BTreeMap<String, std::collections::BTreeSet<EntityId>>,
}

impl CapabilityRegister {
    /// Registers `who` as offering `capability`. Returns false if it already did.
    pub fn offer(&mut self, who: EntityId, capability: &str) -> bool {
        self.providers
            .entry(capability.to_owned())
            .or_default()
            .insert(who)
    }
    /// Removes an offer. Returns false if there was none.
    pub fn withdraw(&mut self, who: EntityId, capability: &str) -> bool {
        let Some(set) = self.providers.get_mut(capability) else {
            return false;
        };
        let removed = set.remove(&who);
        if set.is_empty() {
            self.providers.remove(capability);
        }
        removed
    }
    /// Removes every offer of `who` (e.g. when it is destroyed).
    pub fn withdraw_all(&mut self, who: EntityId) {
        self.providers.retain(|_, set| {
            set.remove(&who);
            !set.is_empty()
        });
    }
    /// Entities offering `capability`, in id order (deterministic).
    pub fn providers(&self, capability: &str) -> impl Iterator<Item = EntityId> + '_ {
        self.providers
            .get(capability)
            .into_iter()
            .flat_map(|s| s.iter().copied())
    }
    /// True if `who` offers `capability`.
    pub fn offers(&self, who: EntityId, capability: &str) -> bool {
        self.providers
            .get(capability)
            .is_some_and(|s| s.contains(&who))
    }
    /// Capabilities offered by `who`, in name order.
    pub fn capabilities_of(&self, who: EntityId) -> impl Iterator<Item = &str> + '_ {
        self.providers
            .iter()
            .filter(move |(_, s)| s.contains(&who))
            .map(|(c, _)| c.as_str())
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_name_whose_hash_is_taken_is_still_found_and_snapshots_keep_names() {
        let mut e = Entities::default();
        let a = e.create("a").unwrap();
        // Pretend "b" hashes like an earlier entity's name.
        e.by_hash
            .insert(crate::trace::stable_str_hash("b"), EntityId(0));
        let b = e.create("b").unwrap();
        assert_eq!(e.collided.len(), 1);
        assert_eq!(
            (e.lookup("a"), e.lookup("b"), e.lookup("c")),
            (Some(a), Some(b), None)
        );
        assert!(e.create("b").is_err());
        let bytes = postcard::to_stdvec(&e).unwrap();
        let r: Entities = postcard::from_bytes(&bytes).unwrap();
        assert_eq!(
            (r.lookup("a"), r.lookup("b"), r.name(b)),
            (Some(a), Some(b), Some("b"))
        );
        // A duplicate name in a snapshot is an error, not a second entity.
        let dup = postcard::to_stdvec(&EntityNames {
            names: vec!["x".into(), "x".into()],
        })
        .unwrap();
        assert!(postcard::from_bytes::<Entities>(&dup).is_err());
    }

    #[test]
    fn the_empty_name_names_nothing() {
        let mut e = Entities::default();
        let a = e.create("").unwrap();
        let b = e.create("").unwrap();
        let c = e.create("c").unwrap();
        assert_eq!((a, b, c), (EntityId(0), EntityId(1), EntityId(2)));
        assert_eq!(
            (e.lookup(""), e.lookup("c"), e.name(b)),
            (None, Some(c), Some(""))
        );
        let r: Entities = postcard::from_bytes(&postcard::to_stdvec(&e).unwrap()).unwrap();
        assert_eq!((r.len(), r.lookup("c"), r.lookup("")), (3, Some(c), None));
    }

    #[test]
    fn names_are_unique_and_ids_dense() {
        let mut e = Entities::default();
        let a = e.create("car-1").unwrap();
        let b = e.create("car-2").unwrap();
        assert_eq!((a, b), (EntityId(0), EntityId(1)));
        assert_eq!(
            e.create("car-1"),
            Err(EntityError::DuplicateName("car-1".into()))
        );
        assert_eq!(e.lookup("car-2"), Some(b));
        assert_eq!(e.name(a), Some("car-1"));
    }

    #[test]
    fn withdraw_all_clears_offers() {
        let mut r = CapabilityRegister::default();
        r.offer(EntityId(0), "a");
        r.offer(EntityId(0), "b");
        r.offer(EntityId(1), "b");
        r.withdraw_all(EntityId(0));
        assert!(!r.offers(EntityId(0), "b"));
        assert_eq!(r.providers("b").collect::<Vec<_>>(), [EntityId(1)]);
        assert_eq!(r.providers("a").count(), 0);
    }
}

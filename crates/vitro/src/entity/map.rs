//! [`EntityMap`]: a map keyed by entity, stored densely by entity index.

use super::EntityId;
use serde::de::{Deserialize, Deserializer};
use serde::ser::{Serialize, SerializeMap, Serializer};
use std::collections::BTreeMap;

/// A map from entities to values, stored as a row per entity index: a lookup, an insert or
/// a removal is one indexed access (no tree walk, no hashing), and iteration goes in id
/// order, as a `BTreeMap<EntityId, T>`'s does.
///
/// For what an agent keeps about many others (the last fix of each, when it last reported
/// each): with thousands of entities, a tree's lookups are a measurable share of a run. Its
/// memory follows the largest id inserted below [`EntityMap::DENSE_IDS`], not the number of
/// entries, so a map that holds a handful of entries of a large population is better kept
/// in a `BTreeMap` or a short list. Ids from [`EntityMap::DENSE_IDS`] on (beyond any
/// scenario's population: a placeholder, an id named in a forged message) are kept in a tree
/// beside the rows, so any id is a valid key.
///
/// It serializes exactly as a `BTreeMap<EntityId, T>` with the same entries does (a map in
/// id order), and reads that form back, so a snapshot does not tell the two apart.
///
/// ```
/// use vitro::entity::{EntityId, EntityMap};
/// let mut m = EntityMap::new();
/// assert_eq!(m.insert(EntityId(7), "seven"), None);
/// m.insert(EntityId(2), "two");
/// assert_eq!(m.insert(EntityId(7), "sept"), Some("seven"));
/// assert_eq!(m.get(EntityId(7)), Some(&"sept"));
/// assert_eq!(m.len(), 2);
/// let ids: Vec<EntityId> = m.iter().map(|(id, _)| id).collect();
/// assert_eq!(ids, [EntityId(2), EntityId(7)]); // id order
/// assert_eq!(m.remove(EntityId(2)), Some("two"));
/// assert!(!m.contains_key(EntityId(2)));
/// ```
#[derive(Clone, Debug)]
pub struct EntityMap<T> {
    rows: Vec<Option<T>>,
    /// The entries of ids from [`Self::DENSE_IDS`] on.
    beyond: BTreeMap<EntityId, T>,
    len: usize,
}

impl<T> Default for EntityMap<T> {
    fn default() -> Self {
        Self::new()
    }
}

impl<T> EntityMap<T> {
    /// Ids below this are kept in rows; the others in a tree.
    pub const DENSE_IDS: u32 = 1 << 16;

    /// An empty map.
    pub const fn new() -> Self {
        EntityMap {
            rows: Vec::new(),
            beyond: BTreeMap::new(),
            len: 0,
        }
    }

    /// Number of entries.
    pub fn len(&self) -> usize {
        self.len
    }

    /// True if there is no entry.
    pub fn is_empty(&self) -> bool {
        self.len == 0
    }

    /// The value of `id`.
    #[inline]
    pub fn get(&self, id: EntityId) -> Option<&T> {
        match self.rows.get(id.index()) {
            Some(row) => row.as_ref(),
            None if id.0 >= Self::DENSE_IDS => self.beyond.get(&id),
            None => None,
        }
    }

    /// The value of `id`, mutable.
    #[inline]
    pub fn get_mut(&mut self, id: EntityId) -> Option<&mut T> {
        match self.rows.get_mut(id.index()) {
            Some(row) => row.as_mut(),
            None if id.0 >= Self::DENSE_IDS => self.beyond.get_mut(&id),
            None => None,
        }
    }

    /// True if `id` has a value.
    #[inline]
    pub fn contains_key(&self, id: EntityId) -> bool {
        self.get(id).is_some()
    }

    /// Sets the value of `id`; returns the one it replaces.
    #[inline]
    pub fn insert(&mut self, id: EntityId, value: T) -> Option<T> {
        if id.0 >= Self::DENSE_IDS {
            let old = self.beyond.insert(id, value);
            if old.is_none() {
                self.len += 1;
            }
            return old;
        }
        let i = id.index();
        if self.rows.len() <= i {
            self.rows.resize_with(i + 1, || None);
        }
        let old = self.rows[i].replace(value);
        if old.is_none() {
            self.len += 1;
        }
        old
    }

    /// Removes the value of `id` and returns it.
    pub fn remove(&mut self, id: EntityId) -> Option<T> {
        let old = if id.0 >= Self::DENSE_IDS {
            self.beyond.remove(&id)
        } else {
            self.rows.get_mut(id.index())?.take()
        };
        if old.is_some() {
            self.len -= 1;
        }
        old
    }

    /// Removes every entry.
    pub fn clear(&mut self) {
        self.rows.clear();
        self.beyond.clear();
        self.len = 0;
    }

    /// Keeps the entries for which `keep` holds (called in id order).
    pub fn retain(&mut self, mut keep: impl FnMut(EntityId, &mut T) -> bool) {
        for (i, row) in self.rows.iter_mut().enumerate() {
            if let Some(v) = row
                && !keep(EntityId(i as u32), v)
            {
                *row = None;
                self.len -= 1;
            }
        }
        let before = self.beyond.len();
        self.beyond.retain(|&id, v| keep(id, v));
        self.len -= before - self.beyond.len();
    }

    /// The entries in id order.
    pub fn iter(&self) -> impl Iterator<Item = (EntityId, &T)> {
        self.rows
            .iter()
            .enumerate()
            .filter_map(|(i, v)| Some((EntityId(i as u32), v.as_ref()?)))
            .chain(self.beyond.iter().map(|(&id, v)| (id, v)))
    }

    /// The ids with a value, in order.
    pub fn keys(&self) -> impl Iterator<Item = EntityId> + '_ {
        self.iter().map(|(id, _)| id)
    }

    /// The values in id order.
    pub fn values(&self) -> impl Iterator<Item = &T> {
        self.rows.iter().flatten().chain(self.beyond.values())
    }
}

impl<T: PartialEq> PartialEq for EntityMap<T> {
    /// Equal entries (however many empty rows either holds).
    fn eq(&self, other: &Self) -> bool {
        self.len == other.len && self.iter().eq(other.iter())
    }
}

impl<T: Eq> Eq for EntityMap<T> {}

impl<T> FromIterator<(EntityId, T)> for EntityMap<T> {
    fn from_iter<I: IntoIterator<Item = (EntityId, T)>>(iter: I) -> Self {
        let mut m = EntityMap::new();
        for (id, v) in iter {
            m.insert(id, v);
        }
        m
    }
}

impl<T: Serialize> Serialize for EntityMap<T> {
    fn serialize<S: Serializer>(&self, s: S) -> Result<S::Ok, S::Error> {
        let mut map = s.serialize_map(Some(self.len))?;
        for (id, v) in self.iter() {
            map.serialize_entry(&id, v)?;
        }
        map.end()
    }
}

impl<'de, T: Deserialize<'de>> Deserialize<'de> for EntityMap<T> {
    fn deserialize<D: Deserializer<'de>>(d: D) -> Result<Self, D::Error> {
        Ok(BTreeMap::<EntityId, T>::deserialize(d)?
            .into_iter()
            .collect())
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A tree and an entity map given the same operations.
    fn both(ops: &[(u32, Option<i64>)]) -> (BTreeMap<EntityId, i64>, EntityMap<i64>) {
        let (mut tree, mut map) = (BTreeMap::new(), EntityMap::new());
        for &(id, op) in ops {
            let id = EntityId(id);
            match op {
                Some(v) => assert_eq!(tree.insert(id, v), map.insert(id, v)),
                None => assert_eq!(tree.remove(&id), map.remove(id)),
            }
        }
        (tree, map)
    }

    #[test]
    fn behaves_as_a_tree_and_serializes_as_one() {
        let ops = [
            (9, Some(1)),
            (3, Some(2)),
            (9, Some(3)),
            (40, Some(4)),
            (3, None),
            (3, None),
            (0, Some(5)),
            (41, None),
            (u32::MAX, Some(6)),
            (1 << 16, Some(7)),
            ((1 << 16) - 1, Some(8)),
            (1 << 16, None),
        ];
        let (tree, map) = both(&ops);
        assert_eq!(map.len(), tree.len());
        assert!(map.iter().map(|(k, v)| (k, *v)).eq(tree.clone()));
        for id in (0..45).chain([(1 << 16) - 1, 1 << 16, u32::MAX - 1, u32::MAX]) {
            assert_eq!(map.get(EntityId(id)), tree.get(&EntityId(id)));
        }
        // A far id takes no row for every id below it.
        assert!(map.rows.len() <= 1 << 16);
        // The same bytes as the tree, and read back.
        let bytes = postcard::to_allocvec(&map).unwrap();
        assert_eq!(bytes, postcard::to_allocvec(&tree).unwrap());
        let back: EntityMap<i64> = postcard::from_bytes(&bytes).unwrap();
        assert_eq!(back, map);
    }

    #[test]
    fn retain_and_equality_ignore_empty_rows() {
        let far = u32::MAX;
        let (_, mut map) = both(&[(1, Some(1)), (5, Some(5)), (8, Some(8)), (far, Some(5))]);
        let mut visited = Vec::new();
        map.retain(|id, v| {
            visited.push(id.0);
            *v != 5
        });
        assert_eq!(visited, [1, 5, 8, far]);
        assert_eq!(map.len(), 2);
        // Equal to a map that never had row 5 or beyond 8, and not to one with another value.
        let (_, other) = both(&[(8, Some(8)), (1, Some(1))]);
        assert_eq!(map, other);
        let (_, third) = both(&[(8, Some(9)), (1, Some(1))]);
        assert_ne!(map, third);
        map.clear();
        assert!(map.is_empty() && map.iter().next().is_none());
    }
}

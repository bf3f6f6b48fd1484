//! Storages: where the state of the world lives.
//!
//! Partitioned by entity type ([`EntityStorage`]: one per body type, e.g. cars) or by data type
//! ([`KeyValueStorage`], [`GraphStorage`]). Every write feeds the storage's running digest, so
//! the sequence of state changes is part of the trace hash ([`digest`](EntityStorage::digest)).
//! Iteration is always in key order: nothing depends on a hasher's seed.

use crate::entity::EntityId;
use crate::trace::TraceHasher;
use serde::{Deserialize, Serialize};
use std::cmp::Ordering;
use std::collections::{BTreeMap, BinaryHeap};

/// Per-entity state of one entity type: a dense table indexed by [`EntityId`].
///
/// Besides its digest, a storage counts its writes and remembers the entities of the last
/// [`WRITE_LOG`] of them ([`written_since`](Self::written_since)), so a reader that keeps a
/// derived index (a spatial grid of the bodies, say) can catch up with the entities that
/// changed instead of reading them all. The count and the log are not part of a snapshot.
#[derive(Clone, Debug, Serialize, Deserialize)]
pub struct EntityStorage<T> {
    rows: Vec<Option<T>>,
    len: usize,
    digest: TraceHasher,
    #[serde(skip)]
    log: WriteLog,
}

/// How many of the latest writes an [`EntityStorage`] remembers the entity of.
pub const WRITE_LOG: usize = 64;

/// The write count and the entities of the latest [`WRITE_LOG`] writes (a ring).
#[derive(Clone, Debug)]
struct WriteLog {
    writes: u64,
    ring: [EntityId; WRITE_LOG],
}

impl Default for WriteLog {
    fn default() -> Self {
        WriteLog {
            writes: 0,
            ring: [EntityId(0); WRITE_LOG],
        }
    }
}

impl<T> Default for EntityStorage<T> {
    fn default() -> Self {
        EntityStorage {
            rows: Vec::new(),
            len: 0,
            digest: TraceHasher::default(),
            log: WriteLog::default(),
        }
    }
}

impl<T: Serialize> EntityStorage<T> {
    #[inline]
    fn record(&mut self, id: EntityId, op: u64) {
        let log = &mut self.log;
        log.ring[(log.writes % WRITE_LOG as u64) as usize] = id;
        log.writes += 1;
        self.digest.write_u64(((id.0 as u64) << 8) | op);
        if let Some(Some(v)) = self.rows.get(id.index()) {
            self.digest.digest(v);
        }
    }

    /// Inserts or replaces the state of `id`; returns the old state.
    pub fn insert(&mut self, id: EntityId, value: T) -> Option<T> {
        if self.rows.len() <= id.index() {
            self.rows.resize_with(id.index() + 1, || None);
        }
        let old = self.rows[id.index()].replace(value);
        if old.is_none() {
            self.len += 1;
        }
        self.record(id, 1);
        old
    }

    /// Changes the state of `id` in place; returns false (and does nothing) if it has none.
    pub fn update(&mut self, id: EntityId, f: impl FnOnce(&mut T)) -> bool {
        match self.rows.get_mut(id.index()) {
            Some(Some(v)) => {
                f(v);
                self.record(id, 2);
                true
            }
            _ => false,
        }
    }

    /// Removes the state of `id`.
    pub fn remove(&mut self, id: EntityId) -> Option<T> {
        let old = self.rows.get_mut(id.index()).and_then(Option::take);
        if old.is_some() {
            self.len -= 1;
            self.record(id, 3);
        }
        old
    }
}

impl<T> EntityStorage<T> {
    /// The state of `id`.
    pub fn get(&self, id: EntityId) -> Option<&T> {
        self.rows.get(id.index()).and_then(Option::as_ref)
    }
    /// True if `id` has state here.
    pub fn contains(&self, id: EntityId) -> bool {
        self.get(id).is_some()
    }
    /// Number of entities with state here.
    pub fn len(&self) -> usize {
        self.len
    }
    /// True if no entity has state here.
    pub fn is_empty(&self) -> bool {
        self.len == 0
    }
    /// All (id, state) pairs in id order.
    pub fn iter(&self) -> impl Iterator<Item = (EntityId, &T)> + '_ {
        self.rows
            .iter()
            .enumerate()
            .filter_map(|(i, v)| v.as_ref().map(|v| (EntityId(i as u32), v)))
    }
    /// Running digest of every write so far.
    pub fn digest(&self) -> u64 {
        self.digest.finish()
    }
    /// Writes (inserts, updates, removals) since this storage was made or restored.
    pub fn writes(&self) -> u64 {
        self.log.writes
    }
    /// The entities written since the storage had made `since` writes, oldest first
    /// (an entity written twice comes twice); `None` if that is more than [`WRITE_LOG`]
    /// writes ago, or in the future.
    ///
    /// ```
    /// use vitro::env::EntityStorage;
    /// use vitro::entity::EntityId;
    /// let mut s: EntityStorage<u8> = EntityStorage::default();
    /// s.insert(EntityId(3), 1);
    /// let mark = s.writes();
    /// s.update(EntityId(3), |v| *v = 2);
    /// s.insert(EntityId(5), 1);
    /// let ids: Vec<EntityId> = s.written_since(mark).unwrap().collect();
    /// assert_eq!(ids, [EntityId(3), EntityId(5)]);
    /// assert!(s.written_since(mark + 5).is_none());
    /// ```
    pub fn written_since(&self, since: u64) -> Option<impl Iterator<Item = EntityId> + '_> {
        let log = &self.log;
        if since > log.writes || log.writes - since > WRITE_LOG as u64 {
            return None;
        }
        Some((since..log.writes).map(move |i| log.ring[(i % WRITE_LOG as u64) as usize]))
    }
    /// Changes every row in place without recording a write. Only for filling in, after a
    /// snapshot is restored, what the rows' serialized form leaves out (`#[serde(skip)]`
    /// fields such as a cached plan, which the digest does not cover either): any other
    /// change made this way escapes the trace.
    pub fn fill_unrecorded(&mut self, mut f: impl FnMut(EntityId, &mut T)) {
        for (i, v) in self.rows.iter_mut().enumerate() {
            if let Some(v) = v {
                f(EntityId(i as u32), v);
            }
        }
    }
}

/// A key-value storage (data-type partition), ordered by key.
#[derive(Clone, Debug, Serialize, Deserialize)]
#[serde(bound(
    serialize = "K: Serialize, V: Serialize",
    deserialize = "K: Deserialize<'de> + Ord, V: Deserialize<'de>"
))]
pub struct KeyValueStorage<K, V> {
    map: BTreeMap<K, V>,
    digest: TraceHasher,
}

impl<K, V> Default for KeyValueStorage<K, V> {
    fn default() -> Self {
        KeyValueStorage {
            map: BTreeMap::new(),
            digest: TraceHasher::default(),
        }
    }
}

impl<K: Ord + Serialize, V: Serialize> KeyValueStorage<K, V> {
    /// Sets `key` to `value`; returns the old value.
    pub fn set(&mut self, key: K, value: V) -> Option<V> {
        self.digest.write_u64(1);
        self.digest.digest(&key);
        self.digest.digest(&value);
        self.map.insert(key, value)
    }
    /// Removes `key`.
    pub fn remove(&mut self, key: &K) -> Option<V> {
        let old = self.map.remove(key);
        if old.is_some() {
            self.digest.write_u64(2);
            self.digest.digest(key);
        }
        old
    }
    /// The value at `key`.
    pub fn get(&self, key: &K) -> Option<&V> {
        self.map.get(key)
    }
    /// All entries in key order.
    pub fn iter(&self) -> impl Iterator<Item = (&K, &V)> + '_ {
        self.map.iter()
    }
    /// Number of entries.
    pub fn len(&self) -> usize {
        self.map.len()
    }
    /// True if empty.
    pub fn is_empty(&self) -> bool {
        self.map.is_empty()
    }
    /// Running digest of every write so far.
    pub fn digest(&self) -> u64 {
        self.digest.finish()
    }
}

/// Index of a node in a [`GraphStorage`].
#[derive(
    Copy, Clone, Debug, PartialEq, Eq, PartialOrd, Ord, Hash, Default, Serialize, Deserialize,
)]
#[serde(transparent)]
pub struct NodeId(pub u32);

#[derive(Clone, Debug, Serialize, Deserialize)]
struct Edge<E> {
    to: NodeId,
    length: f64,
    data: E,
}

/// A directed graph storage (data-type partition): node data, edges with a length and data.
///
/// ```
/// use vitro::env::{GraphStorage, NodeId};
/// let mut g: GraphStorage<&str, ()> = GraphStorage::default();
/// let a = g.add_node("a");
/// let b = g.add_node("b");
/// let c = g.add_node("c");
/// g.add_undirected_edge(a, b, 1.0, ());
/// g.add_undirected_edge(b, c, 1.0, ());
/// g.add_edge(a, c, 5.0, ());
/// let (len, path) = g.shortest_path(a, c).unwrap();
/// assert_eq!((len, path), (2.0, vec![a, b, c]));
/// ```
#[derive(Clone, Debug, Serialize, Deserialize)]
pub struct GraphStorage<N, E> {
    nodes: Vec<N>,
    out: Vec<Vec<Edge<E>>>,
    n_edges: usize,
    digest: TraceHasher,
}

impl<N, E> Default for GraphStorage<N, E> {
    fn default() -> Self {
        GraphStorage {
            nodes: Vec::new(),
            out: Vec::new(),
            n_edges: 0,
            digest: TraceHasher::default(),
        }
    }
}

#[derive(PartialEq)]
struct Frontier(f64, u32);
impl Eq for Frontier {}
impl Ord for Frontier {
    fn cmp(&self, o: &Self) -> Ordering {
        // Min-heap on distance, ties by node id: deterministic.
        o.0.total_cmp(&self.0).then(o.1.cmp(&self.1))
    }
}
impl PartialOrd for Frontier {
    fn partial_cmp(&self, o: &Self) -> Option<Ordering> {
        Some(self.cmp(o))
    }
}

impl<N: Serialize, E: Serialize> GraphStorage<N, E> {
    /// Adds a node; returns its id.
    pub fn add_node(&mut self, data: N) -> NodeId {
        let id = NodeId(self.nodes.len() as u32);
        self.digest.write_u64(1);
        self.digest.digest(&data);
        self.nodes.push(data);
        self.out.push(Vec::new());
        id
    }
    /// Adds a directed edge `from -> to` of `length` (non-negative).
    pub fn add_edge(&mut self, from: NodeId, to: NodeId, length: f64, data: E) {
        self.digest.write_u64(2);
        self.digest.digest(&(from, to, length, &data));
        self.out[from.0 as usize].push(Edge { to, length, data });
        self.n_edges += 1;
    }
    /// Replaces the data of `node`.
    pub fn set_node(&mut self, node: NodeId, data: N) {
        self.digest.write_u64(3);
        self.digest.digest(&(node, &data));
        self.nodes[node.0 as usize] = data;
    }
}

impl<N: Serialize, E: Serialize + Clone> GraphStorage<N, E> {
    /// Adds edges both ways.
    pub fn add_undirected_edge(&mut self, a: NodeId, b: NodeId, length: f64, data: E) {
        self.add_edge(a, b, length, data.clone());
        self.add_edge(b, a, length, data);
    }
}

impl<N, E> GraphStorage<N, E> {
    /// Number of nodes.
    pub fn node_count(&self) -> usize {
        self.nodes.len()
    }
    /// Number of directed edges.
    pub fn edge_count(&self) -> usize {
        self.n_edges
    }
    /// The data of `node`.
    pub fn node(&self, node: NodeId) -> Option<&N> {
        self.nodes.get(node.0 as usize)
    }
    /// Outgoing edges of `node` as (target, length, data), in insertion order.
    pub fn neighbors(&self, node: NodeId) -> impl Iterator<Item = (NodeId, f64, &E)> + '_ {
        self.out
            .get(node.0 as usize)
            .into_iter()
            .flatten()
            .map(|e| (e.to, e.length, &e.data))
    }
    /// Length of the edge `a -> b` (the shortest if there are several).
    pub fn edge_length(&self, a: NodeId, b: NodeId) -> Option<f64> {
        self.neighbors(a)
            .filter(|(t, _, _)| *t == b)
            .map(|(_, l, _)| l)
            .min_by(f64::total_cmp)
    }
    /// Shortest path (Dijkstra) from `from` to `to`: its length and nodes, both ends included.
    pub fn shortest_path(&self, from: NodeId, to: NodeId) -> Option<(f64, Vec<NodeId>)> {
        let n = self.nodes.len();
        if from.0 as usize >= n || to.0 as usize >= n {
            return None;
        }
        let mut dist = vec![f64::INFINITY; n];
        let mut prev = vec![u32::MAX; n];
        let mut heap = BinaryHeap::new();
        dist[from.0 as usize] = 0.0;
        heap.push(Frontier(0.0, from.0));
        while let Some(Frontier(d, u)) = heap.pop() {
            if u == to.0 {
                break;
            }
            if d > dist[u as usize] {
                continue;
            }
            for e in &self.out[u as usize] {
                let nd = d + e.length;
                let v = e.to.0 as usize;
                if nd < dist[v] {
                    dist[v] = nd;
                    prev[v] = u;
                    heap.push(Frontier(nd, e.to.0));
                }
            }
        }
        if !dist[to.0 as usize].is_finite() {
            return None;
        }
        let mut path = vec![to];
        let mut cur = to.0;
        while cur != from.0 {
            cur = prev[cur as usize];
            path.push(NodeId(cur));
        }
        path.reverse();
        Some((dist[to.0 as usize], path))
    }
    /// Running digest of every write so far.
    pub fn digest(&self) -> u64 {
        self.digest.finish()
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn entity_storage_digest_tracks_writes() {
        let mut a = EntityStorage::default();
        let mut b = EntityStorage::default();
        a.insert(EntityId(2), 1.0f64);
        b.insert(EntityId(2), 1.0f64);
        assert_eq!(a.digest(), b.digest());
        a.update(EntityId(2), |v| *v += 1.0);
        assert_ne!(a.digest(), b.digest());
        assert_eq!(a.iter().collect::<Vec<_>>(), [(EntityId(2), &2.0)]);
        assert!(!a.update(EntityId(0), |_| {}));
        assert_eq!(a.remove(EntityId(2)), Some(2.0));
        assert!(a.is_empty());
    }

    #[test]
    fn unreachable_node_has_no_path() {
        let mut g: GraphStorage<(), ()> = GraphStorage::default();
        let a = g.add_node(());
        let b = g.add_node(());
        g.add_edge(b, a, 1.0, ());
        assert!(g.shortest_path(a, b).is_none());
        assert_eq!(g.shortest_path(a, a), Some((0.0, vec![a])));
        assert!(g.shortest_path(a, NodeId(9)).is_none());
    }
}

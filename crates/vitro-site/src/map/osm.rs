//! Reading an `.osm.pbf` file into memory: node coordinates, ways and relations with tags.
//!
//! Everything is kept in file order; node coordinates are looked up by id (never iterated), so
//! nothing depends on a hasher's seed.

use super::error::MapError;
use osmpbf::{Element, ElementReader, RelMemberType};
use std::collections::HashMap;
use std::io::Read;

/// Tags of one element, in file order.
#[derive(Clone, Debug, Default)]
pub(crate) struct Tags(Vec<(String, String)>);

impl Tags {
    fn from_iter<'a>(it: impl Iterator<Item = (&'a str, &'a str)>) -> Self {
        Tags(it.map(|(k, v)| (k.to_owned(), v.to_owned())).collect())
    }
    /// The value of `key`.
    pub(crate) fn get(&self, key: &str) -> Option<&str> {
        self.0
            .iter()
            .find(|(k, _)| k == key)
            .map(|(_, v)| v.as_str())
    }
    /// True if `key` is present (with any value).
    pub(crate) fn has(&self, key: &str) -> bool {
        self.get(key).is_some()
    }
    /// Adds a tag (tests build tags by hand).
    #[cfg(test)]
    pub(crate) fn push(&mut self, key: &str, value: &str) {
        self.0.push((key.to_owned(), value.to_owned()));
    }
    /// True if `key` is present with a value other than `no`.
    pub(crate) fn is_set(&self, key: &str) -> bool {
        self.get(key).is_some_and(|v| v != "no")
    }
}

/// A way: its node ids and tags.
#[derive(Clone, Debug)]
pub(crate) struct RawWay {
    pub id: i64,
    pub refs: Vec<i64>,
    pub tags: Tags,
}

/// A relation member that is a way.
#[derive(Clone, Debug)]
pub(crate) struct WayMember {
    pub way: i64,
    pub role: String,
}

/// A relation: its way members (node and relation members are not needed here) and tags.
#[derive(Clone, Debug)]
pub(crate) struct RawRelation {
    pub id: i64,
    pub ways: Vec<WayMember>,
    pub tags: Tags,
}

/// The whole file in memory.
#[derive(Debug, Default)]
pub(crate) struct RawOsm {
    /// (lat, lon) in degrees by node id: lookup only.
    coords: HashMap<i64, [f64; 2]>,
    /// Number of nodes in the file (plain and dense).
    pub node_count: usize,
    pub ways: Vec<RawWay>,
    pub relations: Vec<RawRelation>,
    /// Bounding box of all nodes: (min lat, min lon, max lat, max lon).
    pub bounds: Option<[f64; 4]>,
}

impl RawOsm {
    /// Reads every element of a PBF stream.
    pub(crate) fn read<R: Read + Send>(reader: R) -> Result<Self, MapError> {
        let mut raw = RawOsm::default();
        let mut bad_role = None;
        let mut bad_coord = None;
        // osmpbf decodes deltas and computes coordinates without checking for overflow (a
        // corrupt granularity, offset or delta), and its iterators do so before any element is
        // handed out, so no validation on this side can come first: in a build with overflow
        // checks a third-party decoder's overflow on hostile input panics inside the reader,
        // and is caught here and reported as malformed data. (Without overflow checks the
        // values wrap instead; the range check on every coordinate refuses those off the globe.)
        let read = std::panic::catch_unwind(std::panic::AssertUnwindSafe(|| {
            ElementReader::new(reader).for_each(|el| match el {
                Element::Node(n) => raw.add_node(n.id(), n.lat(), n.lon(), &mut bad_coord),
                Element::DenseNode(n) => raw.add_node(n.id(), n.lat(), n.lon(), &mut bad_coord),
                Element::Way(w) => raw.ways.push(RawWay {
                    id: w.id(),
                    refs: w.refs().collect(),
                    tags: Tags::from_iter(w.tags()),
                }),
                Element::Relation(r) => {
                    let mut ways = Vec::new();
                    for m in r.members() {
                        if m.member_type != RelMemberType::Way {
                            continue;
                        }
                        match m.role() {
                            Ok(role) => ways.push(WayMember {
                                way: m.member_id,
                                role: role.to_owned(),
                            }),
                            Err(_) => bad_role = Some(r.id()),
                        }
                    }
                    raw.relations.push(RawRelation {
                        id: r.id(),
                        ways,
                        tags: Tags::from_iter(r.tags()),
                    });
                }
            })
        }));
        read.map_err(|_| {
            MapError::Malformed(
                "the .osm.pbf decoder failed on corrupt data (a coordinate or delta out of range)"
                    .into(),
            )
        })??;
        if let Some(id) = bad_role {
            return Err(MapError::Malformed(format!(
                "relation {id} has a member role that is not valid UTF-8"
            )));
        }
        if let Some((id, lat, lon)) = bad_coord {
            return Err(MapError::Malformed(format!(
                "node {id} lies at latitude {lat}, longitude {lon}, off the globe"
            )));
        }
        Ok(raw)
    }

    /// Adds a node; the first one off the globe (latitude beyond ±90°, longitude beyond ±180°)
    /// is noted in `bad` instead.
    fn add_node(&mut self, id: i64, lat: f64, lon: f64, bad: &mut Option<(i64, f64, f64)>) {
        if !((-90.0..=90.0).contains(&lat) && (-180.0..=180.0).contains(&lon)) {
            bad.get_or_insert((id, lat, lon));
            return;
        }
        self.node_count += 1;
        self.coords.insert(id, [lat, lon]);
        let b = self.bounds.get_or_insert([lat, lon, lat, lon]);
        b[0] = b[0].min(lat);
        b[1] = b[1].min(lon);
        b[2] = b[2].max(lat);
        b[3] = b[3].max(lon);
    }

    /// (lat, lon) of node `id`, if the file has it.
    pub(crate) fn coord(&self, id: i64) -> Option<[f64; 2]> {
        self.coords.get(&id).copied()
    }
}

//! Area and structure features of the map: buildings, water, bridges.

use super::osm::{RawOsm, RawWay, Tags};
use crate::geo::{LocalProjection, P2, Polygon};
use serde::{Deserialize, Serialize};
use std::collections::BTreeMap;

/// Where building heights come from when the map does not say.
#[derive(Copy, Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct HeightRules {
    /// Height of one storey, metres (`building:levels` × this).
    pub level_height: f64,
    /// Height of a building with neither `height` nor `building:levels`, metres.
    pub default_height: f64,
}

impl Default for HeightRules {
    /// 3 m a storey; 6 m (two storeys) when untagged.
    fn default() -> Self {
        HeightRules {
            level_height: 3.0,
            default_height: 6.0,
        }
    }
}

/// A building: footprint and height above its base.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct Building {
    /// OSM id of the way or relation (negative for relations).
    pub osm_id: i64,
    /// Footprint in local metres.
    pub footprint: Polygon,
    /// Height from base to roof, metres.
    pub height: f64,
}

/// A water area (lake, river bank, reservoir...).
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct WaterArea {
    /// OSM id of the way or relation (negative for relations).
    pub osm_id: i64,
    /// Outline in local metres.
    pub area: Polygon,
}

/// A bridge: a way tagged `bridge` that carries a road, path or railway.
///
/// Its deck runs along `line`; placed on terrain, the deck height follows a straight ramp
/// between the ground at both ends, never dipping below the ground under it
/// (see [`crate::site::PlacedBridge`]).
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct Bridge {
    /// OSM id of the way.
    pub osm_id: i64,
    /// Deck centre line, local metres.
    pub line: Vec<P2>,
    /// Deck width, metres (`width` tag, else by class: 7 m for roads, 3 m otherwise).
    pub width: f64,
    /// The `layer` tag (1 when absent).
    pub layer: i32,
}

/// Parses a length tag such as `12`, `12.5 m`, `12m`; `None` if it is not metres.
pub(crate) fn parse_metres(v: &str) -> Option<f64> {
    let v = v.trim();
    let v = v.strip_suffix('m').unwrap_or(v).trim();
    v.parse::<f64>().ok().filter(|h| h.is_finite() && *h > 0.0)
}

/// Building height from its tags: `height`, else `building:levels` × level height, else the
/// default.
pub(crate) fn building_height(tags: &Tags, rules: &HeightRules) -> f64 {
    if let Some(h) = tags.get("height").and_then(parse_metres) {
        return h;
    }
    if let Some(l) = tags
        .get("building:levels")
        .and_then(|v| v.trim().parse::<f64>().ok())
        .filter(|l| l.is_finite() && *l > 0.0)
    {
        return l * rules.level_height;
    }
    rules.default_height
}

/// True if the tags describe a water area.
pub(crate) fn is_water(tags: &Tags) -> bool {
    tags.get("natural") == Some("water")
        || matches!(tags.get("waterway"), Some("riverbank" | "dock"))
        || matches!(tags.get("landuse"), Some("reservoir" | "basin"))
        || tags.has("water")
}

/// Builds the polygon of a closed way. Nodes missing from the file (a building cut by the
/// extract's edge) are skipped; what remains must still enclose an area.
pub(crate) fn way_polygon(raw: &RawOsm, w: &RawWay, proj: &LocalProjection) -> Option<Polygon> {
    if w.refs.len() < 4 || w.refs.first() != w.refs.last() {
        return None;
    }
    let pts: Vec<P2> = w
        .refs
        .iter()
        .filter_map(|&r| raw.coord(r).map(|[la, lo]| proj.project(la, lo)))
        .collect();
    Polygon::new(pts, vec![])
}

/// Assembles the rings of a multipolygon relation from its member ways; the first outer ring
/// becomes the polygon (further outer rings become their own polygons). Unclosable chains
/// (members cut off by the extract) are dropped.
pub(crate) fn relation_polygons(
    raw: &RawOsm,
    ways_by_id: &BTreeMap<i64, usize>,
    rel: &super::osm::RawRelation,
    proj: &LocalProjection,
) -> Vec<Polygon> {
    let mut outer = Vec::new();
    let mut inner = Vec::new();
    for m in &rel.ways {
        if let Some(&i) = ways_by_id.get(&m.way) {
            let refs = raw.ways[i].refs.clone();
            if m.role == "inner" {
                inner.push(refs);
            } else {
                outer.push(refs);
            }
        }
    }
    let to_pts = |ring: Vec<i64>| -> Option<Vec<P2>> {
        ring.iter()
            .map(|&r| raw.coord(r).map(|[la, lo]| proj.project(la, lo)))
            .collect()
    };
    let holes: Vec<Vec<P2>> = join_rings(inner).into_iter().filter_map(to_pts).collect();
    let outers: Vec<Vec<P2>> = join_rings(outer).into_iter().filter_map(to_pts).collect();
    outers
        .into_iter()
        .filter_map(|o| {
            let probe = Polygon::new(o.clone(), vec![])?;
            let mine = holes
                .iter()
                .filter(|h| h.first().is_some_and(|&p| probe.contains(p)))
                .cloned()
                .collect();
            Polygon::new(o, mine)
        })
        .collect()
}

/// Joins chains of node ids end to end into closed rings.
fn join_rings(mut chains: Vec<Vec<i64>>) -> Vec<Vec<i64>> {
    chains.retain(|c| c.len() >= 2);
    let mut rings = Vec::new();
    while let Some(mut ring) = chains.pop() {
        while ring.first() != ring.last() {
            let Some(&end) = ring.last() else { break };
            let Some(k) = chains
                .iter()
                .position(|c| c.first() == Some(&end) || c.last() == Some(&end))
            else {
                break;
            };
            let mut next = chains.remove(k);
            if next.first() != Some(&end) {
                next.reverse();
            }
            ring.extend_from_slice(&next[1..]);
        }
        if ring.len() >= 4 && ring.first() == ring.last() {
            rings.push(ring);
        }
    }
    rings
}

/// Deck width of a bridge way from its tags.
pub(crate) fn bridge_width(tags: &Tags) -> f64 {
    if let Some(w) = tags.get("width").and_then(parse_metres) {
        return w;
    }
    match tags.get("highway") {
        Some(
            "motorway" | "trunk" | "primary" | "secondary" | "tertiary" | "unclassified"
            | "residential" | "service" | "living_street" | "road",
        ) => 7.0,
        _ if tags.has("railway") => 5.0,
        _ => 3.0,
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn heights_from_tags() {
        let rules = HeightRules::default();
        let t = |kv: &[(&str, &str)]| {
            let mut tags = Tags::default();
            for (k, v) in kv {
                tags.push(k, v);
            }
            building_height(&tags, &rules)
        };
        assert_eq!(t(&[("height", "12.5 m")]), 12.5);
        assert_eq!(t(&[("height", "9"), ("building:levels", "5")]), 9.0);
        assert_eq!(t(&[("building:levels", "4")]), 12.0);
        assert_eq!(t(&[("height", "tall")]), 6.0);
        assert_eq!(t(&[]), 6.0);
    }

    #[test]
    fn water_tags() {
        let t = |k: &str, v: &str| {
            let mut tags = Tags::default();
            tags.push(k, v);
            is_water(&tags)
        };
        assert!(t("natural", "water") && t("waterway", "riverbank") && t("landuse", "reservoir"));
        assert!(!t("natural", "wood") && !t("waterway", "stream") && !t("landuse", "grass"));
    }

    #[test]
    fn rings_join_in_any_direction() {
        let rings = join_rings(vec![vec![1, 2, 3], vec![1, 4], vec![3, 4]]);
        assert_eq!(rings.len(), 1);
        assert_eq!(rings[0].len(), 5);
        assert_eq!(rings[0].first(), rings[0].last());
        assert!(join_rings(vec![vec![1, 2], vec![2, 3]]).is_empty());
    }
}

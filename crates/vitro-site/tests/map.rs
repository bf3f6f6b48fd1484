//! The real town: counts as stored in the file, street graphs, zones, placement.

use vitro::env::NodeId;
use vitro_site::geo::polyline_length;
use vitro_site::info::map_info;
use vitro_site::map::{ForbiddenZones, MapConfig, Mode, TownMap, ZoneConfig};
use vitro_site::site::{Site, SiteConfig};
use vitro_site::terrain::Terrain;

const DATA: &str = concat!(env!("CARGO_MANIFEST_DIR"), "/../../data");

fn kotka() -> TownMap {
    TownMap::load(format!("{DATA}/maps/kotka.osm.pbf"), &MapConfig::default()).unwrap()
}

#[test]
fn counts_as_stored_in_the_file() {
    let info = map_info(format!("{DATA}/maps/kotka.osm.pbf")).unwrap();
    assert_eq!(
        (
            info.nodes,
            info.ways,
            info.relations,
            info.buildings,
            info.highway_ways
        ),
        (14_222, 2_653, 5, 2_219, 343)
    );
    let json = serde_json::to_value(&info).unwrap();
    for key in [
        "nodes",
        "ways",
        "relations",
        "buildings",
        "highway_ways",
        "bbox",
    ] {
        assert!(json.get(key).is_some(), "{key}");
    }
    for g in ["drive_graph", "walk_graph"] {
        assert!(json[g]["nodes"].as_u64().unwrap() > 0 && json[g]["edges"].as_u64().unwrap() > 0);
    }
    // The extract is about 2.2 km square around 60.53 N, 26.95 E.
    assert!((info.bbox.min_lat - 60.52).abs() < 0.001 && (info.bbox.max_lon - 26.97).abs() < 0.001);
    assert!(
        info.size_m.iter().all(|s| (2100.0..2300.0).contains(s)),
        "{:?}",
        info.size_m
    );
}

/// Within ±10 % of other tools' counts on this file (data/README.md).
#[test]
fn street_graphs_land_in_the_sanity_band() {
    let info = map_info(format!("{DATA}/maps/kotka.osm.pbf")).unwrap();
    let near = |x: usize, want: f64| (x as f64 - want).abs() <= 0.1 * want;
    assert!(near(info.drive_graph.ways, 207.0), "{:?}", info.drive_graph);
    assert!(near(info.walk_graph.ways, 265.0), "{:?}", info.walk_graph);
    assert!(
        near(info.walk_graph.osm_nodes, 1147.0),
        "{:?}",
        info.walk_graph
    );
    assert!(
        near(info.walk_graph.osm_edges, 1215.0),
        "{:?}",
        info.walk_graph
    );
    assert!(near(info.building_polygons, 2208.0));
    // Junction graphs are smaller than the every-node ones.
    assert!(info.walk_graph.nodes < info.walk_graph.osm_nodes);
}

#[test]
fn graph_edges_are_consistent() {
    let town = kotka();
    for mode in [Mode::Drive, Mode::Walk] {
        let g = town.streets(mode);
        let mut one_way = 0;
        for n in 0..g.node_count() as u32 {
            for (to, len, e) in g.graph.neighbors(NodeId(n)) {
                let seg = &g.segments[e.segment as usize];
                assert!((len - polyline_length(&seg.points)).abs() < 1e-9 && len > 0.0);
                let (a, b) = if e.forward {
                    (seg.from, seg.to)
                } else {
                    (seg.to, seg.from)
                };
                assert_eq!((a, b), (NodeId(n), to));
                if g.graph.edge_length(to, NodeId(n)).is_none() {
                    one_way += 1;
                }
            }
        }
        match mode {
            Mode::Walk => assert_eq!(one_way, 0, "troops walk both ways"),
            Mode::Drive => assert!(one_way > 0, "the town has one-way streets (ramps)"),
        }
        // Junction graph: every node is a way end or shared.
        assert!(g.segments.len() >= g.node_count() / 2);
    }
    // Most of the walking network is one piece: reachable from the junction nearest the
    // centre (the rest are driveways and paths cut off by the extract's edge).
    let w = &town.walk;
    let start = w.nearest_node([0.0, 0.0]).unwrap();
    let mut seen = vec![false; w.node_count()];
    let mut stack = vec![start];
    seen[start.0 as usize] = true;
    while let Some(n) = stack.pop() {
        for (to, _, _) in w.graph.neighbors(n) {
            if !std::mem::replace(&mut seen[to.0 as usize], true) {
                stack.push(to);
            }
        }
    }
    let reached = seen.iter().filter(|&&s| s).count();
    println!(
        "walk graph: {reached} of {} junctions reachable from the centre",
        w.node_count()
    );
    assert!(reached * 10 > w.node_count() * 8);
    let far = (0..w.node_count() as u32)
        .map(NodeId)
        .filter(|n| seen[n.0 as usize])
        .max_by(|a, b| {
            let d = |n: &NodeId| w.pos(*n).map_or(0.0, |p| libm::hypot(p[0], p[1]));
            d(a).total_cmp(&d(b))
        })
        .unwrap();
    let (len, path) = w.graph.shortest_path(start, far).unwrap();
    assert!(len >= vitro_site::geo::dist(w.pos(start).unwrap(), w.pos(far).unwrap()));
    assert!(path.len() > 3);
}

#[test]
fn streets_are_mostly_free_and_buildings_forbidden() {
    let town = kotka();
    let zones = ForbiddenZones::new(&town, &ZoneConfig::default());
    assert_eq!(zones.len(), town.buildings.len() + town.water.len());
    for b in town.buildings.iter().take(200) {
        let c = b.footprint.centroid();
        if b.footprint.contains(c) {
            assert!(zones.is_forbidden(c));
            let f = zones.nearest_free(c);
            assert!(!zones.is_forbidden(f));
        }
    }
    let n = town.drive.node_count();
    let blocked = (0..n as u32)
        .filter(|&i| zones.is_forbidden(town.drive.pos(NodeId(i)).unwrap()))
        .count();
    assert!(blocked * 20 < n, "{blocked} of {n} junctions forbidden");
}

#[test]
fn the_town_sits_on_the_terrain() {
    let terrain = Terrain::load(format!("{DATA}/terrain/valley_64x64_90m.asc")).unwrap();
    let site = Site::new(kotka(), terrain.clone(), &SiteConfig::default()).unwrap();
    assert_eq!(site.offset, [2880.0, 2880.0]);
    // Streets follow the ground, and their 3D length is at least the plan length.
    for i in 0..site.map.drive.segments.len() {
        let seg = &site.map.drive.segments[i];
        let path = site.segment_path(Mode::Drive, i).unwrap();
        if !seg.bridge {
            for p in &path {
                assert!((p[2] - site.ground([p[0], p[1]]).unwrap()).abs() < 1e-9);
            }
        }
        assert!(site.segment_length_3d(Mode::Drive, i).unwrap() >= seg.length - 1e-6);
        // A street on a bridge runs on the deck: never under the ground, and a point 2 m
        // above it sees a point 2 m above its other end.
        if seg.bridge {
            for p in &path {
                assert!(p[2] >= site.ground([p[0], p[1]]).unwrap() - 1e-9);
            }
            let (a, b) = (path[0], path[path.len() - 1]);
            assert!(
                site.los
                    .visible([a[0], a[1], a[2] + 2.0], [b[0], b[1], b[2] + 2.0])
            );
        }
    }
    assert!(site.map.drive.segments.iter().any(|s| s.bridge));
    let placed = |offset| {
        let config = SiteConfig {
            offset: Some(offset),
            ..SiteConfig::default()
        };
        Site::new(kotka(), terrain.clone(), &config)
    };
    assert!(
        placed([500.0, 500.0]).is_err(),
        "town sticks out of the terrain"
    );
    let moved = placed([2000.0, 3000.0]).unwrap();
    assert_eq!(moved.on_ground([0.0, 0.0])[..2], [2000.0, 3000.0]);
}

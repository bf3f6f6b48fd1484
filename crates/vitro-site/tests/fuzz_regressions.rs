//! Inputs the fuzz targets (fuzz/) found that once panicked: each is now an error.

use vitro_site::map::{MapConfig, MapError, TownMap};

fn read(bytes: &[u8]) -> Result<TownMap, MapError> {
    TownMap::from_bytes(bytes, &MapConfig::default())
}

/// The message of a malformed-data error; any other outcome fails the test.
fn malformed(bytes: &[u8]) -> String {
    match read(bytes) {
        Err(MapError::Malformed(m)) => m,
        Err(e) => panic!("expected malformed data, got: {e}"),
        Ok(_) => panic!("expected malformed data, got a map"),
    }
}

/// Kotka's map with a dense block's granularity or offset corrupted: the coordinate
/// overflows inside the PBF reader.
#[test]
fn a_pbf_whose_coordinates_overflow_is_malformed() {
    let bytes = include_bytes!("fuzz/osm_pbf_coordinate_overflow.pbf");
    let e = read(bytes).expect_err("corrupt");
    assert!(
        matches!(e, MapError::Malformed(_) | MapError::Pbf(_)),
        "{e}"
    );
}

/// The small hand-made files below are one uncompressed data block holding dense nodes; this
/// one, a single node in Finland, reads: the others differ from it only where they are broken.
#[test]
fn a_minimal_pbf_with_one_node_reads() {
    let map = read(include_bytes!("fuzz/osm_pbf_one_node.pbf")).expect("one node");
    assert_eq!(map.counts.nodes, 1);
    assert!((map.bbox.min_lat - 60.0).abs() < 1e-9, "{:?}", map.bbox);
    assert!((map.bbox.min_lon - 26.9).abs() < 1e-9, "{:?}", map.bbox);
}

/// Granularity × longitude + offset overflows an i64 in osmpbf's dense node (`nano_lon`).
#[test]
fn a_dense_node_whose_longitude_overflows_is_malformed() {
    let m = malformed(include_bytes!("fuzz/osm_pbf_lon_overflow.pbf"));
    assert!(m.contains("out of range"), "{m}");
}

/// The delta-coded latitudes of two dense nodes add up past i64: the overflow is in osmpbf's
/// iterator, before any node is handed out.
#[test]
fn dense_node_deltas_that_overflow_are_malformed() {
    let m = malformed(include_bytes!("fuzz/osm_pbf_delta_overflow.pbf"));
    assert!(m.contains("out of range"), "{m}");
}

/// A node that decodes without overflow but lies at latitude 100°.
#[test]
fn a_node_off_the_globe_is_malformed() {
    let m = malformed(include_bytes!("fuzz/osm_pbf_off_the_globe.pbf"));
    assert!(m.contains("node 1") && m.contains("off the globe"), "{m}");
}

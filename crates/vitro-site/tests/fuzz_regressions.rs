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

/// An ESRI ASCII header that announces more cells than its text can hold (here 2^32-odd
/// rows): refused before the grid is allocated, not an allocation of hundreds of gigabytes.
#[test]
fn an_asc_header_announcing_more_cells_than_the_text_holds_is_refused() {
    let text = include_str!("fuzz/terrain_asc_huge_header.asc");
    let e = vitro_site::terrain::Terrain::parse_asc(text).expect_err("corrupt");
    assert!(e.to_string().contains("cells announced"), "{e}");
    let e = vitro_site::terrain::Terrain::parse_asc(
        "ncols 100000\nnrows 100000\nxllcorner 0\nyllcorner 0\ncellsize 1\n1 2 3\n",
    )
    .expect_err("too few values for the header");
    assert!(e.to_string().contains("cells announced"), "{e}");
}

/// A GeoTIFF whose SampleFormat tag holds no value (the decoder once indexed into it).
#[test]
fn a_geotiff_with_an_empty_sample_format_is_an_error() {
    let path = std::env::temp_dir().join(format!("vitro-fuzz-{}.tif", std::process::id()));
    std::fs::write(
        &path,
        include_bytes!("fuzz/geotiff_empty_sample_format.tif"),
    )
    .unwrap();
    let r = vitro_site::terrain::Terrain::load(&path);
    std::fs::remove_file(&path).unwrap();
    assert!(r.is_err());
}

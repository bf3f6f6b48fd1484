//! Inputs the fuzz targets (fuzz/) found that once panicked: each is now an error.

use vitro_site::map::{MapConfig, MapError, TownMap};

/// Kotka's map with a dense block's granularity or offset corrupted: the coordinate
/// overflows inside the PBF reader.
#[test]
fn a_pbf_whose_coordinates_overflow_is_malformed() {
    let bytes = include_bytes!("fuzz/osm_pbf_coordinate_overflow.pbf");
    let e = TownMap::from_bytes(bytes, &MapConfig::default()).expect_err("corrupt");
    assert!(
        matches!(e, MapError::Malformed(_) | MapError::Pbf(_)),
        "{e}"
    );
}

//! Terrain files and viewsheds on the real elevation data.

use vitro_site::los::LosScene;
use vitro_site::terrain::{Grid, Terrain};
use vitro_site::viewshed::{viewshed, viewshed_file};

const DATA: &str = concat!(env!("CARGO_MANIFEST_DIR"), "/../../data/terrain");

fn valley() -> Terrain {
    Terrain::load(format!("{DATA}/valley_64x64_90m.asc")).unwrap()
}

#[test]
fn geotiff_georeference_and_the_valley_cut_agree() {
    let tif = Terrain::load(format!("{DATA}/jacksboro_utm16.tif")).unwrap();
    let g = tif.grid();
    assert_eq!((g.ncols, g.nrows, g.cellsize), (344, 363, 90.0));
    // The documented origin is the upper-left corner.
    let top = g.origin[1] + g.nrows as f64 * g.cellsize;
    assert!((g.origin[0] - 730_939.2).abs() < 0.1 && (top - 4_069_226.2).abs() < 0.1);
    let nodata = g.values.iter().filter(|v| v.is_nan()).count();
    assert!(nodata > 0 && nodata < g.values.len() / 10, "{nodata}");
    assert!(g.range().unwrap()[0] > 0.0, "border zeros are no-data");
    // The ASCII grid is a cut of the GeoTIFF: same heights at the same coordinates.
    let valley = valley();
    let v = valley.grid();
    assert_eq!((v.ncols, v.nrows), (64, 64));
    assert_eq!(v.range(), Some([242.0, 442.0]));
    let dc = (v.origin[0] - g.origin[0]) / g.cellsize;
    let dr = (v.origin[1] - g.origin[1]) / g.cellsize;
    assert!(dc.fract().abs() < 1e-6 && dr.fract().abs() < 1e-6);
    for r in 0..v.nrows {
        for c in 0..v.ncols {
            assert_eq!(
                v.get(c, r),
                g.get(c + dc as usize, r + dr as usize),
                "{c},{r}"
            );
        }
    }
}

#[test]
fn surface_height_is_the_mesh() {
    let t = valley();
    let s = LosScene::terrain_only(&t).unwrap();
    let dev = t.mesh_deviation();
    for k in 0..200 {
        let (x, y) = (50.0 + 27.3 * k as f64, 60.0 + 13.1 * (k * 7 % 400) as f64);
        let h = t.surface_height(x, y).unwrap();
        let hit = s.first_hit([x, y, 1000.0], [x, y, 0.0]).unwrap();
        assert!(
            (1000.0 - hit - h).abs() < 0.01,
            "{x},{y}: {h} vs {}",
            1000.0 - hit
        );
        assert!((h - t.height(x, y).unwrap()).abs() <= dev + 1e-9);
    }
}

#[test]
fn viewshed_of_the_valley() {
    let t = valley();
    let g = t.grid();
    let obs = g.to_geo(g.cell_centre(32, 32));
    let low = viewshed(&t, obs, 2.0, 0.0).unwrap();
    let high = viewshed(&t, obs, 50.0, 0.0).unwrap();
    assert_eq!(low.get(32, 32), Some(1.0), "the observer sees its own cell");
    let count = |m: &Grid| m.values.iter().filter(|&&v| v == 1.0).count();
    let (n_low, n_high) = (count(&low), count(&high));
    assert!(
        n_low > 50 && n_low < n_high && n_high < 64 * 64,
        "{n_low} {n_high}"
    );
    // A higher eye sees everything a lower one sees (the ground is a height field).
    for (a, b) in low.values.iter().zip(&high.values) {
        assert!(*a <= *b);
    }
    // Written as an ESRI grid and read back.
    let dir = std::env::temp_dir().join(format!("vitro-viewshed-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let out = dir.join("mask.asc");
    let sum = viewshed_file(format!("{DATA}/valley_64x64_90m.asc"), obs, 2.0, 0.0, &out).unwrap();
    assert_eq!((sum.visible, sum.cells), (n_low, 64 * 64));
    let back = Grid::parse_asc(&std::fs::read_to_string(&out).unwrap()).unwrap();
    assert_eq!(back, low);
    std::fs::remove_dir_all(&dir).unwrap();
    assert!(viewshed(&t, [0.0, 0.0], 2.0, 0.0).is_err());
}

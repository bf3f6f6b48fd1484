//! `vitro map info`, `vitro map render`, `vitro terrain viewshed` on the real data in the repo.

mod common;

use common::vitro;

fn tmp(name: &str) -> String {
    std::env::temp_dir()
        .join(format!("vitro-cli-{}-{name}", std::process::id()))
        .to_string_lossy()
        .into_owned()
}

#[test]
fn map_info_counts_what_the_file_stores() {
    let (code, out, err) = vitro(&["map", "info", "data/maps/kotka.osm.pbf", "--json"]);
    assert_eq!(code, 0, "{err}");
    let v: serde_json::Value = serde_json::from_str(&out).expect("JSON");
    assert_eq!(v["nodes"], 14222);
    assert_eq!(v["ways"], 2653);
    assert_eq!(v["relations"], 5);
    assert_eq!(v["buildings"], 2219);
    assert_eq!(v["highway_ways"], 343);
    for g in ["drive_graph", "walk_graph"] {
        assert!(v[g]["nodes"].as_u64().is_some_and(|n| n > 100), "{g}");
        assert!(v[g]["edges"].as_u64().is_some_and(|n| n > 100), "{g}");
    }
    assert!(
        v["bbox"]["min_lat"]
            .as_f64()
            .is_some_and(|x| (60.5..60.6).contains(&x))
    );
}

#[test]
fn map_render_writes_a_png() {
    let out = tmp("map.png");
    let (code, stdout, err) = vitro(&[
        "map",
        "render",
        "data/maps/kotka.osm.pbf",
        "--terrain",
        "data/terrain/valley_64x64_90m.asc",
        "--width",
        "400",
        "--out",
        &out,
    ]);
    assert_eq!(code, 0, "{err}");
    assert!(stdout.contains("400 x"), "{stdout}");
    let bytes = std::fs::read(&out).expect("the PNG exists");
    let _ = std::fs::remove_file(&out);
    assert_eq!(&bytes[..8], b"\x89PNG\r\n\x1a\n");
    assert!(bytes.len() > 10_000, "a real picture, not an empty frame");
}

#[test]
fn viewshed_writes_a_mask_that_sees_around_the_observer() {
    let out = tmp("mask.asc");
    let args = [
        "terrain",
        "viewshed",
        "data/terrain/valley_64x64_90m.asc",
        "--observer",
        "757579,4045106",
        "--observer-height",
        "10",
        "--target-height",
        "2",
        "--out",
        &out,
    ];
    let (code, _, err) = vitro(&args);
    assert_eq!(code, 0, "{err}");
    let text = std::fs::read_to_string(&out).expect("the mask exists");
    let _ = std::fs::remove_file(&out);
    let cells: Vec<&str> = text
        .lines()
        .skip(6)
        .flat_map(str::split_whitespace)
        .collect();
    assert_eq!(cells.len(), 64 * 64);
    assert!(cells.iter().all(|c| *c == "0" || *c == "1"));
    let seen = cells.iter().filter(|c| **c == "1").count();
    assert!(
        seen > 10 && seen < 64 * 64,
        "some cells seen, not all: {seen}"
    );
    // The observer's own cell: column (757579-754699.2)/90 = 31, row from the top 63-(4045106-4042226.2)/90 = 31.
    assert_eq!(cells[31 * 64 + 31], "1");
}

#[test]
fn bad_terrain_and_observer_are_bad_input() {
    let bad = tmp("bad.asc");
    std::fs::write(
        &bad,
        "ncols 2\nnrows 2\nxllcorner 0\nyllcorner 0\ncellsize 1\n1 2\n3 x\n",
    )
    .expect("temp");
    let out = tmp("never.asc");
    let (code, _, err) = vitro(&[
        "terrain",
        "viewshed",
        &bad,
        "--observer",
        "0.5,0.5",
        "--observer-height",
        "1",
        "--target-height",
        "1",
        "--out",
        &out,
    ]);
    let _ = std::fs::remove_file(&bad);
    assert_eq!(code, 2);
    assert!(err.contains(":7:"), "the error names the line: {err}");
    let (code, _, err) = vitro(&[
        "terrain",
        "viewshed",
        "data/terrain/valley_64x64_90m.asc",
        "--observer",
        "0,0",
        "--observer-height",
        "1",
        "--target-height",
        "1",
        "--out",
        &out,
    ]);
    assert_eq!(code, 2);
    assert!(err.contains("not over the terrain"), "{err}");
    let (code, _, _) = vitro(&["map", "info", "README.md"]);
    assert_eq!(code, 2);
}

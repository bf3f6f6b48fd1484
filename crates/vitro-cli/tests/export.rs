//! `vitro export kml`: tracks from a recording, exit 2 for a missing or non-MCAP file.

mod common;

use common::vitro;
use vitro_record::{Recorder, synthetic};

fn tmp(name: &str) -> String {
    std::env::temp_dir()
        .join(format!("vitro-cli-export-{}-{name}", std::process::id()))
        .to_string_lossy()
        .into_owned()
}

fn recording(name: &str, frames: u64, entities: usize) -> String {
    let path = tmp(name);
    let scene = synthetic::scene();
    let mut rec = Recorder::create(&path, &scene).expect("create");
    for i in 0..frames {
        rec.frame(&synthetic::frame(&scene, i, entities))
            .expect("frame");
    }
    rec.finish().expect("finish");
    path
}

#[test]
fn export_kml_writes_one_track_per_entity() {
    let run = recording("run.mcap", 30, 7);
    let out = tmp("run.kml");
    let (code, stdout, err) = vitro(&["export", "kml", &run, "--out", &out]);
    assert_eq!(code, 0, "{err}");
    assert!(stdout.is_empty());
    assert!(err.contains("7 tracks over 30 frames"), "{err}");
    let doc = std::fs::read_to_string(&out).expect("the KML file");
    assert_eq!(doc.matches("<gx:Track>").count(), 7);
    assert_eq!(doc.matches("<when>").count(), 7 * 30);
    // Without --out, the same document on standard output.
    let (code, stdout, err) = vitro(&["export", "kml", &run]);
    assert_eq!(code, 0, "{err}");
    assert_eq!(stdout, doc);
    std::fs::remove_file(&run).ok();
    std::fs::remove_file(&out).ok();
}

#[test]
fn export_kml_refuses_missing_and_non_mcap_files_with_exit_2() {
    let missing = tmp("missing.mcap");
    let (code, _, err) = vitro(&["export", "kml", &missing]);
    assert_eq!(code, 2, "{err}");
    assert!(err.to_lowercase().contains("no such file"), "{err}");

    let text = tmp("notes.mcap");
    std::fs::write(&text, "not a recording\n").unwrap();
    let (code, _, err) = vitro(&["export", "kml", &text]);
    assert_eq!(code, 2, "{err}");
    assert!(err.contains("not an MCAP file"), "{err}");
    std::fs::remove_file(&text).ok();
}

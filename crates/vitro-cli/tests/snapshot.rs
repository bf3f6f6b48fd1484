//! `vitro run --save-at SECONDS --save FILE` and `vitro resume FILE`: the resumed run ends
//! with the uninterrupted run's trace hash at every fidelity level; a damaged, foreign or
//! out-of-date file is a clear error (exit 2), never a panic.

mod common;

use common::{repo, vitro};
use std::path::{Path, PathBuf};

/// A fresh scratch directory under the target directory.
fn scratch(name: &str) -> PathBuf {
    let dir = PathBuf::from(env!("CARGO_TARGET_TMPDIR")).join(format!("snapshot-{name}"));
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).expect("a scratch directory");
    dir
}

/// The trace hash a run printed, with its exit code: 0, or 4 when the mission failed (a
/// short run ends before the VIP is out), which a resumed run must repeat.
fn hash_of(out: &(i32, String, String)) -> String {
    assert!(
        out.0 == 0 || out.0 == 4,
        "exit {}, stderr: {}",
        out.0,
        out.2
    );
    format!("{} (exit {})", out.1.trim(), out.0)
}

fn s(p: &Path) -> &str {
    p.to_str().expect("a UTF-8 path")
}

/// Plain run, run with a snapshot on the way, and the resumed snapshot: one trace hash.
fn same_hash(scenario: &str, extra: &[&str], save_at: &str, dir: &Path, name: &str) {
    let file = dir.join(format!("{name}.snap"));
    let mut plain = vec!["run", scenario, "--quiet"];
    plain.extend_from_slice(extra);
    let whole = hash_of(&vitro(&plain));
    let mut saving = plain.clone();
    saving.extend_from_slice(&["--save-at", save_at, "--save", s(&file)]);
    assert_eq!(
        hash_of(&vitro(&saving)),
        whole,
        "{name}: saving changed the run"
    );
    let resumed = hash_of(&vitro(&["resume", s(&file), "--quiet"]));
    assert_eq!(resumed, whole, "{name}: the resumed run differs");
    let size = std::fs::metadata(&file).map(|m| m.len()).unwrap_or(0);
    eprintln!("{name}: trace {whole}, snapshot {size} bytes");
}

#[test]
fn the_evacuation_resumes_to_the_same_hash_at_every_level() {
    let dir = scratch("evac");
    // The physical level runs shorter: rigid-body steps are slow in a debug build.
    for (level, until, at) in [
        ("discrete", "600", "150"),
        ("interpolated", "600", "150"),
        ("physical", "200", "100"),
    ] {
        let extra = ["--seed", "42", "--until", until, "--fidelity", level];
        same_hash("scenarios/evacuation.toml", &extra, at, &dir, level);
    }
}

#[test]
fn the_surveillance_resumes_to_the_same_hash() {
    let dir = scratch("surveillance");
    let extra = ["--until", "600"];
    same_hash(
        "scenarios/surveillance.toml",
        &extra,
        "250",
        &dir,
        "surveillance",
    );
}

#[test]
fn the_surveillance_resumes_mid_auction_and_mid_plan_to_the_same_hash() {
    let dir = scratch("surveillance-methods");
    let text = std::fs::read_to_string(repo().join("scenarios/surveillance.toml")).unwrap();
    let data = format!("\"{}/data", s(&repo()));
    for method in ["auction", "central"] {
        // Saved 0.1 s after the area is tasked at 1200 s: a round open, or the search running.
        let file = dir.join(format!("{method}.toml"));
        let scenario = (text.replace("\"../data", &data)).replace(
            "method = \"contract-net\"",
            &format!("method = \"{method}\""),
        );
        std::fs::write(&file, scenario).unwrap();
        same_hash(s(&file), &["--until", "1300"], "1200.1", &dir, method);
    }
}

#[test]
fn the_demo_resumes_to_the_same_hash() {
    let dir = scratch("demo");
    same_hash(
        "scenarios/demo.toml",
        &["--until", "900"],
        "333.5",
        &dir,
        "demo",
    );
}

#[test]
fn resume_reports_json_records_from_the_resume_point_and_takes_until() {
    let dir = scratch("record");
    let file = dir.join("run.snap");
    let rec = dir.join("rest.mcap");
    let base = [
        "run",
        "scenarios/evacuation.toml",
        "--until",
        "120",
        "--quiet",
    ];
    let mut saving = base.to_vec();
    saving.extend_from_slice(&["--save-at", "60", "--save", s(&file)]);
    let whole = hash_of(&vitro(&saving));
    let out = vitro(&["resume", s(&file), "--json", "--record", s(&rec)]);
    assert_eq!(out.0, 4, "the VIP is not out at 120 s: {}", out.2);
    let v: serde_json::Value = serde_json::from_str(&out.1).expect("one JSON object");
    assert_eq!(
        hash_of(&(
            4,
            v["trace_hash"].to_string().replace('"', ""),
            String::new()
        )),
        whole
    );
    assert_eq!(v["resumed_at_s"].as_f64(), Some(60.0));
    assert_eq!(v["sim_time_s"].as_f64(), Some(120.0));
    let replay = vitro_record::Replay::open(&rec).expect("the recording opens");
    let (first, last) = replay.time_range().expect("frames");
    assert_eq!(
        first, 60_000_000_000,
        "the recording starts at the resume point"
    );
    assert_eq!(last, 120_000_000_000);
    // --until: a shorter resumed run is the shorter plain run.
    let short = hash_of(&vitro(&["resume", s(&file), "--until", "90", "--quiet"]));
    let plain = vitro(&[
        "run",
        "scenarios/evacuation.toml",
        "--until",
        "90",
        "--quiet",
    ]);
    assert_eq!(short, hash_of(&plain));
    let before = vitro(&["resume", s(&file), "--until", "30"]);
    assert_eq!(before.0, 2, "{}", before.2);
    assert!(before.2.contains("already"), "{}", before.2);
}

/// `vitro resume FILE` must exit 2 naming the problem, without a panic.
fn refused(file: &Path, why: &str) {
    let (code, _, err) = vitro(&["resume", s(file)]);
    assert_eq!(code, 2, "{}: {err}", file.display());
    assert!(
        err.contains(why),
        "{}: expected {why:?} in: {err}",
        file.display()
    );
    assert!(!err.contains("panicked"), "{err}");
}

#[test]
fn damaged_foreign_and_other_version_files_are_refused() {
    let dir = scratch("bad");
    let good = dir.join("good.snap");
    let (code, _, err) = vitro(&[
        "run",
        "scenarios/demo.toml",
        "--until",
        "100",
        "--quiet",
        "--save-at",
        "50",
        "--save",
        s(&good),
    ]);
    assert_eq!(code, 0, "{err}");
    let bytes = std::fs::read(&good).expect("the snapshot");
    let write = |name: &str, b: &[u8]| {
        let p = dir.join(name);
        std::fs::write(&p, b).expect("writes");
        p
    };
    refused(&write("empty.snap", b""), "not a Vitro snapshot");
    refused(&repo().join("scenarios/demo.toml"), "not a Vitro snapshot");
    refused(&write("head.snap", &bytes[..10]), "truncated snapshot");
    refused(
        &write("cut.snap", &bytes[..bytes.len() - 7]),
        "truncated snapshot",
    );
    let mut flipped = bytes.clone();
    let mid = bytes.len() / 2;
    flipped[mid] ^= 0x10;
    refused(&write("flipped.snap", &flipped), "corrupt snapshot");
    let mut longer = bytes.clone();
    longer.extend_from_slice(b"more");
    refused(&write("longer.snap", &longer), "corrupt snapshot");
    let mut newer = bytes.clone();
    newer[8] = 99;
    refused(&write("newer.snap", &newer), "format version 99");
    refused(&dir.join("missing.snap"), "missing.snap: No such file");
    let (code, _, err) = vitro(&["run", "scenarios/demo.toml", "--save-at", "5"]);
    assert_eq!(code, 2, "--save-at without --save: {err}");
}

#[test]
fn a_snapshot_resumes_only_on_the_world_it_was_saved_on() {
    let dir = scratch("world");
    let data = repo().join("data");
    let data = data.canonicalize().expect("the data directory");
    let program = dir.join("leader.jz");
    std::fs::copy(data.join("rules/formation/leader.jz"), &program).expect("copies");
    let text = std::fs::read_to_string(repo().join("scenarios/evacuation.toml"))
        .expect("the scenario")
        .replace(
            "# program = \"../data/rules/formation/wedge.rules\"",
            "program = \"leader.jz\"",
        )
        .replace("\"../data/", &format!("\"{}/", data.display()));
    assert!(text.contains("program = \"leader.jz\""));
    let scenario = dir.join("evac.toml");
    std::fs::write(&scenario, text).expect("writes");
    let file = dir.join("run.snap");
    let args = ["run", s(&scenario), "--until", "60", "--quiet"];
    let mut saving = args.to_vec();
    saving.extend_from_slice(&["--save-at", "30", "--save", s(&file)]);
    let whole = hash_of(&vitro(&saving));
    // The scenario file itself is not needed: the snapshot holds it.
    std::fs::remove_file(&scenario).expect("removes");
    assert_eq!(hash_of(&vitro(&["resume", s(&file), "--quiet"])), whole);
    // Another program under the same name: not the world the run was saved on.
    let mut changed = std::fs::read_to_string(&program).expect("reads");
    changed.push_str("\n// changed after the snapshot\n");
    std::fs::write(&program, changed).expect("writes");
    refused(&file, "does not match");
}

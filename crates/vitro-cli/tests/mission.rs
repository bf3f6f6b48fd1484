//! `vitro run` on the evacuation mission: the JSON report, exit codes, and that pacing and
//! recording do not change the trace hash.

mod common;

use common::vitro;
use serde_json::Value;

fn json(out: &str) -> Value {
    serde_json::from_str(out.trim()).expect("one JSON object on stdout")
}

#[test]
fn run_json_reports_the_mission() {
    // With the default seed the VIP is out after about nine minutes (the HVT hunt may go on
    // for the hour).
    let args = [
        "run",
        "scenarios/evacuation.toml",
        "--json",
        "--until",
        "600",
    ];
    let (code, out, err) = vitro(&args);
    assert_eq!(code, 0, "{err}");
    let v = json(&out);
    for key in [
        "success",
        "time_to_extraction_s",
        "trace_hash",
        "sim_time_s",
        "wall_time_s",
        "events",
        "casualties",
        "adversaries_detected",
        "time_uncovered_s",
        "hvt_captured",
        "messages_sent",
        "plan_repairs",
    ] {
        assert!(v.get(key).is_some(), "missing {key} in {v}");
    }
    assert_eq!(v["success"], Value::Bool(true));
    assert_eq!(v["levels"]["truck"], "discrete");
}

#[test]
fn pacing_and_recording_keep_the_trace() {
    let dir = std::env::temp_dir().join(format!("vitro-mission-{}", std::process::id()));
    std::fs::create_dir_all(&dir).expect("temp dir");
    let rec = dir.join("run.mcap");
    let rec = rec.to_str().expect("utf-8 path");
    let base = [
        "run",
        "scenarios/evacuation.toml",
        "--until",
        "40",
        "--json",
    ];
    let (c1, plain, e1) = vitro(&base);
    let paced: Vec<&str> = base.iter().copied().chain(["--speed", "1000"]).collect();
    let (c2, paced, e2) = vitro(&paced);
    let recorded: Vec<&str> = base.iter().copied().chain(["--record", rec]).collect();
    let (c3, recorded, e3) = vitro(&recorded);
    // Stopped at 40 s, the VIP is not out yet: a mission failure, exit 4.
    assert_eq!((c1, c2, c3), (4, 4, 4), "{e1}\n{e2}\n{e3}");
    let hash = |s: &str| json(s)["trace_hash"].as_str().map(str::to_owned);
    assert!(hash(&plain).is_some());
    assert_eq!(hash(&plain), hash(&paced), "pacing changed the run");
    assert_eq!(hash(&plain), hash(&recorded), "recording changed the run");
    assert!(std::fs::metadata(rec).map(|m| m.len() > 0).unwrap_or(false));
    let _ = std::fs::remove_dir_all(&dir);
}

#[test]
fn bad_flags_are_bad_input() {
    let (code, _, err) = vitro(&["run", "scenarios/evacuation.toml", "--until", "-3"]);
    assert_eq!(code, 2, "{err}");
    let (code, _, err) = vitro(&["run", "scenarios/evacuation.toml", "--speed", "1e9"]);
    assert_eq!(code, 2, "{err}");
}

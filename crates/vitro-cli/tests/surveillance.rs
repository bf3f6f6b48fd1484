//! The surveillance mission through the `vitro` command: `run --json` reports its metrics,
//! recording keeps the trace hash, `validate` takes the scenario and its experiment.

mod common;

use common::vitro;
use serde_json::Value;

fn json(out: &str) -> Value {
    serde_json::from_str(out.trim()).expect("one JSON object on stdout")
}

#[test]
fn run_json_reports_the_surveillance() {
    let args = [
        "run",
        "scenarios/surveillance.toml",
        "--json",
        "--until",
        "300",
    ];
    let (code, out, err) = vitro(&args);
    assert_eq!(code, 0, "{err}");
    let v = json(&out);
    for key in [
        "red_units",
        "red_detected",
        "mean_time_to_detection_s",
        "restricted_time_to_detection_s",
        "mean_tracked_share",
        "messages_sent",
        "messages_lost",
        "calls",
        "awards",
        "reallocations",
        "uavs_lost",
        "trace_hash",
        "red",
    ] {
        assert!(v.get(key).is_some(), "missing {key} in {v}");
    }
    assert_eq!(v["red_units"], 8);
    assert_eq!(v["levels"]["skeldar"], "discrete");
}

#[test]
fn recording_keeps_the_trace_and_files_validate() {
    let dir = std::env::temp_dir().join(format!("vitro-surveillance-{}", std::process::id()));
    std::fs::create_dir_all(&dir).expect("temp dir");
    let rec = dir.join("run.mcap");
    let rec = rec.to_str().expect("utf-8 path");
    let base = [
        "run",
        "scenarios/surveillance.toml",
        "--until",
        "60",
        "--quiet",
    ];
    let (c1, plain, e1) = vitro(&base);
    assert_eq!(c1, 0, "{e1}");
    let mut recorded = base.to_vec();
    recorded.extend(["--record", rec]);
    let (c2, again, e2) = vitro(&recorded);
    assert_eq!(c2, 0, "{e2}");
    assert_eq!(
        plain.trim(),
        again.trim(),
        "recording does not change the run"
    );
    assert!(std::fs::metadata(rec).is_ok_and(|m| m.len() > 0));
    std::fs::remove_dir_all(&dir).ok();
    for file in [
        "scenarios/surveillance.toml",
        "experiments/surveillance_uavs.toml",
    ] {
        let (code, _, err) = vitro(&["validate", file]);
        assert_eq!(code, 0, "{file}: {err}");
    }
}

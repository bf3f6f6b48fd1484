//! Runs the `vitro` binary as a user would: the demo, determinism across runs, seeds and
//! pacing, and a catalogue of malformed scenarios (each must exit 2 with a located message).

use std::path::{Path, PathBuf};
use std::process::{Command, Output};

fn vitro(args: &[&str]) -> Output {
    Command::new(env!("CARGO_BIN_EXE_vitro"))
        .args(args)
        .output()
        .expect("the vitro binary runs")
}

fn here(rel: &str) -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join(rel)
}

fn demo() -> String {
    here("../../scenarios/demo.toml").display().to_string()
}

fn small() -> String {
    here("tests/small.toml").display().to_string()
}

fn stdout(o: &Output) -> String {
    String::from_utf8_lossy(&o.stdout).into_owned()
}

fn stderr(o: &Output) -> String {
    String::from_utf8_lossy(&o.stderr).into_owned()
}

/// Runs with `--json` and returns the parsed object.
fn run_json(args: &[&str]) -> serde_json::Value {
    let mut all = vec!["run"];
    all.extend_from_slice(args);
    all.push("--json");
    let o = vitro(&all);
    assert_eq!(o.status.code(), Some(0), "stderr: {}", stderr(&o));
    let out = stdout(&o);
    assert_eq!(out.lines().count(), 1, "one JSON line: {out}");
    serde_json::from_str(&out).expect("stdout is JSON")
}

fn hash(v: &serde_json::Value) -> String {
    v["trace_hash"]
        .as_str()
        .expect("trace_hash is a string")
        .to_owned()
}

#[test]
fn demo_runs_and_reports_json() {
    let d = demo();
    let v = run_json(&[&d, "--until", "600"]);
    for key in [
        "trace_hash",
        "sim_time_s",
        "wall_time_s",
        "events",
        "mean_idleness_s",
        "max_idleness_s",
        "visits",
        "messages_sent",
        "messages_lost",
        "messages_bounced",
        "events_per_wall_s",
        "sim_s_per_wall_s",
    ] {
        assert!(v.get(key).is_some(), "missing {key} in {v}");
    }
    let h = hash(&v);
    assert_eq!(h.len(), 16);
    assert!(h.chars().all(|c| c.is_ascii_hexdigit()), "{h}");
    assert_eq!(v["sim_time_s"], 600.0);
    assert!(v["events"].as_u64().unwrap() > 1000, "{v}");
    assert!(v["messages_sent"].as_u64().unwrap() > 0, "{v}");
    let mean = v["mean_idleness_s"].as_f64().unwrap();
    let max = v["max_idleness_s"].as_f64().unwrap();
    assert!(0.0 < mean && mean < max && max <= 600.0, "{v}");
}

#[test]
fn plain_summary_names_the_essentials() {
    let o = vitro(&["run", &small()]);
    assert_eq!(o.status.code(), Some(0), "stderr: {}", stderr(&o));
    let out = stdout(&o);
    for word in [
        "small",
        "120.0 s simulated",
        "events",
        "idleness",
        "messages",
        "trace hash",
    ] {
        assert!(out.contains(word), "{word:?} missing from:\n{out}");
    }
    let q = vitro(&["run", &small(), "--quiet"]);
    let h = hash(&run_json(&[&small()]));
    assert_eq!(stdout(&q).trim(), h);
    assert!(stderr(&q).is_empty(), "quiet: {}", stderr(&q));
}

#[test]
fn same_seed_same_hash_paced_or_not() {
    let d = demo();
    let a = run_json(&[&d, "--until", "60", "--seed", "7"]);
    let b = run_json(&[&d, "--until", "60", "--seed", "7"]);
    let paced = run_json(&[&d, "--until", "60", "--seed", "7", "--speed", "1000"]);
    assert_eq!(hash(&a), hash(&b));
    assert_eq!(hash(&a), hash(&paced));
    assert_eq!(a["events"], paced["events"]);
    // 60 simulated seconds at 1000x take at least 60 ms of wall time.
    assert!(paced["wall_time_s"].as_f64().unwrap() >= 0.055, "{paced}");
    assert_eq!(paced["speed"], 1000.0);
}

#[test]
fn different_seed_different_hash() {
    let d = demo();
    let a = run_json(&[&d, "--until", "60", "--seed", "7"]);
    let b = run_json(&[&d, "--until", "60", "--seed", "8"]);
    assert_ne!(hash(&a), hash(&b));
}

/// Runs a malformed scenario: exit 2, and stderr names `file:line:column` and what was expected.
fn rejects(file: &str, line_col: &str, expected: &str) {
    let path = here(&format!("tests/bad/{file}")).display().to_string();
    let o = vitro(&["run", &path]);
    let err = stderr(&o);
    assert_eq!(o.status.code(), Some(2), "{file}: {err}");
    assert!(
        err.contains(&format!("{path}:{line_col}: ")),
        "{file}: no {line_col} in {err}"
    );
    assert!(err.contains(expected), "{file}: no {expected:?} in {err}");
    assert!(stdout(&o).is_empty(), "{file}: printed {}", stdout(&o));
}

#[test]
fn malformed_scenarios_exit_2_with_location() {
    rejects(
        "unknown_key.toml",
        "10:1",
        "unknown field `row`, expected one of `columns`, `rows`",
    );
    rejects(
        "wrong_type.toml",
        "15:9",
        "invalid type: string \"two\", expected u32",
    );
    rejects("bad_syntax.toml", "14:6", "unclosed table, expected `]`");
    rejects(
        "negative_count.toml",
        "15:9",
        "invalid value: integer `-2`, expected u32",
    );
    rejects(
        "loss_above_one.toml",
        "21:8",
        "invalid value 1.5 for `channel.loss`, expected a probability in [0, 1]",
    );
    rejects("missing_field.toml", "1:1", "missing field `seed`");
    rejects(
        "too_many_cars.toml",
        "15:9",
        "expected a number of cars in 1..=11",
    );
    rejects(
        "zero_block.toml",
        "10:11",
        "expected a length in metres in (0, 1e6]",
    );
}

#[test]
fn bad_arguments_exit_2() {
    let missing = here("tests/bad/no_such_file.toml").display().to_string();
    let o = vitro(&["run", &missing]);
    assert_eq!(o.status.code(), Some(2));
    assert!(
        stderr(&o).contains(&format!("cannot read scenario {missing}")),
        "{}",
        stderr(&o)
    );
    let s = small();
    for (args, expected) in [
        (
            vec!["run", &s, "--speed", "0.01"],
            "speed factor 0.01 outside",
        ),
        (
            vec!["run", &s, "--speed", "5000"],
            "speed factor 5000 outside",
        ),
        (vec!["run", &s, "--until=-5"], "--until -5: expected"),
        (vec!["run", &s, "--seed", "x"], "invalid value 'x'"),
        (vec!["walk", &s], "unrecognized subcommand"),
    ] {
        let o = vitro(&args);
        assert_eq!(o.status.code(), Some(2), "{args:?}: {}", stderr(&o));
        assert!(stderr(&o).contains(expected), "{args:?}: {}", stderr(&o));
    }
}

#[test]
fn validate_checks_without_running() {
    let o = vitro(&["validate", &demo()]);
    assert_eq!(o.status.code(), Some(0), "{}", stderr(&o));
    assert!(stdout(&o).contains("ok (76 junctions"), "{}", stdout(&o));
    let bad = here("tests/bad/loss_above_one.toml").display().to_string();
    assert_eq!(vitro(&["validate", &bad]).status.code(), Some(2));
}

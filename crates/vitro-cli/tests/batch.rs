//! `vitro batch`, `vitro merge` and `vitro plot` as a user runs them: identical results with
//! any job count, shards that merge into the unsharded result, a batch killed with SIGKILL
//! and resumed, failing runs, bad input.

use std::path::{Path, PathBuf};
use std::process::{Command, Output, Stdio};
use std::time::{Duration, Instant};

fn vitro(args: &[&str]) -> Output {
    Command::new(env!("CARGO_BIN_EXE_vitro"))
        .args(args)
        .output()
        .expect("the vitro binary runs")
}

fn stderr(o: &Output) -> String {
    String::from_utf8_lossy(&o.stderr).into_owned()
}

/// A fresh temporary directory for one test.
fn tmp(name: &str) -> PathBuf {
    let d = std::env::temp_dir().join(format!("vitro-cli-batch-{name}-{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&d);
    std::fs::create_dir_all(&d).expect("a temporary directory");
    d
}

fn scenario(rel: &str) -> String {
    Path::new(env!("CARGO_MANIFEST_DIR"))
        .join(rel)
        .display()
        .to_string()
}

/// Writes an experiment over `scenario` into `dir` and returns its path.
fn experiment(dir: &Path, scenario: &str, body: &str) -> String {
    let path = dir.join("exp.toml");
    let text = format!("scenario = {scenario:?}\n{body}");
    std::fs::write(&path, text).expect("the experiment is written");
    path.display().to_string()
}

const SMALL: &str = r#"
seed = 11
replicates = 2
[parameters]
"channel.loss" = [0.0, 0.5, 1.0]
"cars.count" = { start = 1, stop = 3, step = 2 }
[keep]
series = ["visits", "mean_idleness_s"]
every_s = 50.0
"#;

/// The rows of a CSV table, without the `wall_s` column (wall-clock time differs per run).
fn rows(path: &Path) -> Vec<Vec<String>> {
    let mut r = csv::Reader::from_path(path).expect("a CSV table");
    let header: Vec<String> = r
        .headers()
        .expect("a header")
        .iter()
        .map(str::to_owned)
        .collect();
    let wall = header.iter().position(|h| h == "wall_s");
    let mut out = vec![header.clone()];
    for rec in r.records() {
        out.push(
            rec.expect("a row")
                .iter()
                .map(str::to_owned)
                .collect::<Vec<_>>(),
        );
    }
    if let Some(w) = wall {
        for row in &mut out {
            row.remove(w);
        }
    }
    out
}

fn ok(o: &Output) {
    assert_eq!(o.status.code(), Some(0), "stderr: {}", stderr(o));
}

#[test]
fn same_results_with_one_or_two_jobs() {
    let d = tmp("jobs");
    let exp = experiment(&d, &scenario("tests/small.toml"), SMALL);
    let (a, b) = (d.join("a"), d.join("b"));
    ok(&vitro(&[
        "batch",
        &exp,
        "--out",
        &a.display().to_string(),
        "--jobs",
        "1",
    ]));
    ok(&vitro(&[
        "batch",
        &exp,
        "--out",
        &b.display().to_string(),
        "--jobs",
        "2",
    ]));
    let sa = rows(&a.join("summary.csv"));
    assert_eq!(sa.len(), 1 + 12, "12 runs");
    assert_eq!(
        sa[0][..7],
        [
            "run",
            "point",
            "replicate",
            "seed",
            "channel.loss",
            "cars.count",
            "mean_idleness_s"
        ]
    );
    assert_eq!(sa, rows(&b.join("summary.csv")));
    assert_eq!(rows(&a.join("series.csv")), rows(&b.join("series.csv")));
    // Runs differ from each other: seeds and outcomes.
    let h = sa[0]
        .iter()
        .position(|c| c == "trace_hash")
        .expect("a trace_hash column");
    let hashes: std::collections::BTreeSet<&String> = sa[1..].iter().map(|r| &r[h]).collect();
    assert!(hashes.len() > 6, "{hashes:?}");
    // Manifest: hashes, seeds, statuses.
    let m: serde_json::Value =
        serde_json::from_slice(&std::fs::read(a.join("manifest.json")).expect("a manifest"))
            .expect("JSON");
    assert_eq!(m["runs_total"], 12);
    assert_eq!(m["experiment"]["sha256"].as_str().map(str::len), Some(64));
    assert_eq!(m["runs"][3]["status"], "ok");
    assert_eq!(
        m["runs"][3]["seed"].as_u64().map(|s| s.to_string()),
        Some(sa[4][3].clone())
    );
    assert!(m["sessions"][0]["finished"].is_string());
}

#[test]
fn two_shards_merge_into_the_unsharded_result() {
    let d = tmp("shards");
    let exp = experiment(&d, &scenario("tests/small.toml"), SMALL);
    let dir = |n: &str| d.join(n).display().to_string();
    ok(&vitro(&["batch", &exp, "--out", &dir("all"), "-j", "2"]));
    ok(&vitro(&[
        "batch",
        &exp,
        "--out",
        &dir("s0"),
        "--shard",
        "0/2",
        "-j",
        "1",
    ]));
    ok(&vitro(&[
        "batch",
        &exp,
        "--out",
        &dir("s1"),
        "--shard",
        "1/2",
        "-j",
        "1",
    ]));
    assert_eq!(rows(&d.join("s0/summary.csv")).len(), 1 + 6);
    ok(&vitro(&[
        "merge",
        &dir("s1"),
        &dir("s0"),
        "--out",
        &dir("merged"),
    ]));
    assert_eq!(
        rows(&d.join("merged/summary.csv")),
        rows(&d.join("all/summary.csv"))
    );
    assert_eq!(
        rows(&d.join("merged/series.csv")),
        rows(&d.join("all/series.csv"))
    );
    // Refused: overlapping shards, an existing output, another experiment.
    let o = vitro(&["merge", &dir("s0"), &dir("all"), "--out", &dir("m2")]);
    assert_eq!(o.status.code(), Some(2), "{}", stderr(&o));
    assert!(stderr(&o).contains("overlap"), "{}", stderr(&o));
    let o = vitro(&["merge", &dir("s0"), &dir("s1"), "--out", &dir("merged")]);
    assert_eq!(o.status.code(), Some(2), "{}", stderr(&o));
    let other = tmp("shards-other");
    let exp2 = experiment(
        &other,
        &scenario("tests/small.toml"),
        &SMALL.replace("seed = 11", "seed = 12"),
    );
    ok(&vitro(&[
        "batch",
        &exp2,
        "--out",
        &dir("o1"),
        "--shard",
        "1/2",
    ]));
    let o = vitro(&["merge", &dir("s0"), &dir("o1"), "--out", &dir("m3")]);
    assert_eq!(o.status.code(), Some(2), "{}", stderr(&o));
    assert!(
        stderr(&o).contains("different experiments"),
        "{}",
        stderr(&o)
    );
}

/// `vitro batch` as one task of a job array: the shard comes from the environment.
fn vitro_task(args: &[&str], env: &[(&str, &str)]) -> Output {
    let mut c = Command::new(env!("CARGO_BIN_EXE_vitro"));
    c.args(args);
    for (k, v) in env {
        c.env(k, v);
    }
    c.output().expect("the vitro binary runs")
}

#[test]
fn a_slurm_job_array_shards_without_shard_flags() {
    let d = tmp("slurm");
    let exp = experiment(&d, &scenario("tests/small.toml"), SMALL);
    let dir = |n: &str| d.join(n).display().to_string();
    ok(&vitro(&["batch", &exp, "--out", &dir("all"), "-j", "2"]));
    // `sbatch --array=1-3`: tasks 1, 2, 3, each its own shard of three.
    let mut parts = Vec::new();
    for task in ["1", "2", "3"] {
        let out = dir(&format!("task{task}"));
        let o = vitro_task(
            &["batch", &exp, "--out", &out, "-j", "1"],
            &[
                ("SLURM_ARRAY_JOB_ID", "77"),
                ("SLURM_ARRAY_TASK_ID", task),
                ("SLURM_ARRAY_TASK_COUNT", "3"),
                ("SLURM_ARRAY_TASK_MIN", "1"),
            ],
        );
        ok(&o);
        let m: serde_json::Value = serde_json::from_str(
            &std::fs::read_to_string(Path::new(&out).join("manifest.json")).expect("a manifest"),
        )
        .expect("JSON");
        let index = task.parse::<u64>().expect("a number") - 1;
        assert_eq!(m["shard"]["index"], index);
        assert_eq!(m["shard"]["count"], 3);
        assert_eq!(
            m["shard_from"],
            format!("Slurm job array 77, task {task} (SLURM_ARRAY_TASK_ID)")
        );
        parts.push(out);
    }
    let mut args = vec!["merge"];
    args.extend(parts.iter().map(String::as_str));
    let merged = dir("merged");
    args.extend(["--out", merged.as_str()]);
    ok(&vitro(&args));
    assert_eq!(
        rows(&d.join("merged/summary.csv")),
        rows(&d.join("all/summary.csv"))
    );
    // A task id past the array is bad input, with the variable named.
    let o = vitro_task(
        &["batch", &exp, "--out", &dir("bad"), "-j", "1"],
        &[
            ("SLURM_ARRAY_TASK_ID", "5"),
            ("SLURM_ARRAY_TASK_COUNT", "3"),
        ],
    );
    assert_eq!(o.status.code(), Some(2), "{}", stderr(&o));
    assert!(stderr(&o).contains("SLURM_ARRAY_TASK_ID"), "{}", stderr(&o));
}

#[test]
fn slurm_prints_a_job_array_and_its_merge() {
    let d = tmp("sbatch");
    let exp = experiment(&d, &scenario("tests/small.toml"), SMALL);
    let out = d.join("out").display().to_string();
    let o = vitro(&[
        "batch", &exp, "--out", &out, "--slurm", "--tasks", "3", "-j", "4",
    ]);
    ok(&o);
    let script = String::from_utf8_lossy(&o.stdout);
    assert!(script.starts_with("#!/bin/bash"), "{script}");
    for part in [
        "--array=0-2",
        "--cpus-per-task=4",
        "--time=01:00:00",
        "afterok",
        " merge ",
    ] {
        assert!(script.contains(part), "{part} in {script}");
    }
    assert!(!d.join("out").exists(), "--slurm runs nothing");
    let o = vitro(&["batch", &exp, "--out", &out, "--slurm", "--time", "soon"]);
    assert_eq!(o.status.code(), Some(2), "{}", stderr(&o));
    let o = vitro(&["batch", &exp, "--out", &out, "--slurm", "--shard", "0/2"]);
    assert_eq!(o.status.code(), Some(2), "{}", stderr(&o));
}

#[test]
fn a_killed_batch_resumes_with_nothing_lost_or_duplicated() {
    let d = tmp("kill");
    // Runs long enough (a simulated hour of the demo each) to be killed midway.
    let exp = experiment(
        &d,
        &scenario("../../scenarios/demo.toml"),
        "seed = 5\nreplicates = 3\nend_s = 1800.0\n[parameters]\n\"channel.loss\" = [0.0, 0.3, 0.6, 0.9]\n\"cars.count\" = [3, 6]\n",
    );
    let killed = d.join("killed");
    let mut child = Command::new(env!("CARGO_BIN_EXE_vitro"))
        .args([
            "batch",
            &exp,
            "--out",
            &killed.display().to_string(),
            "-j",
            "2",
        ])
        .stderr(Stdio::null())
        .spawn()
        .expect("the batch starts");
    let journal = killed.join("runs.jsonl");
    let started = Instant::now();
    loop {
        let lines = std::fs::read_to_string(&journal).map_or(0, |s| s.lines().count());
        if lines >= 4 {
            break;
        }
        assert!(
            started.elapsed() < Duration::from_secs(120),
            "the batch recorded no runs"
        );
        std::thread::sleep(Duration::from_millis(20));
    }
    child.kill().expect("SIGKILL"); // SIGKILL on Unix: no clean-up runs
    child.wait().expect("the batch ends");
    let done = std::fs::read_to_string(&journal).expect("a journal");
    let recorded = done.lines().count();
    assert!(
        recorded < 24,
        "killed before the end: {recorded} runs recorded"
    );
    assert!(
        !killed.join("summary.csv").exists(),
        "tables come at the end"
    );
    // A write cut off by the kill: half a record, no newline.
    let first = done.lines().next().expect("a record");
    std::fs::write(&journal, format!("{done}{}", &first[..first.len() / 2])).expect("a torn tail");

    // Resuming another experiment into it, or without --resume, is refused.
    let other = experiment(
        &tmp("kill-other"),
        &scenario("../../scenarios/demo.toml"),
        "seed = 6\n",
    );
    let o = vitro(&[
        "batch",
        &other,
        "--out",
        &killed.display().to_string(),
        "--resume",
    ]);
    assert_eq!(o.status.code(), Some(2), "{}", stderr(&o));
    assert!(stderr(&o).contains("another experiment"), "{}", stderr(&o));
    let o = vitro(&["batch", &exp, "--out", &killed.display().to_string()]);
    assert_eq!(o.status.code(), Some(2), "{}", stderr(&o));
    assert!(stderr(&o).contains("--resume"), "{}", stderr(&o));

    let o = vitro(&[
        "batch",
        &exp,
        "--out",
        &killed.display().to_string(),
        "--resume",
        "-j",
        "2",
    ]);
    ok(&o);
    assert!(stderr(&o).contains("torn"), "{}", stderr(&o));
    assert!(
        stderr(&o).contains(&format!("{} done before", recorded)),
        "{}",
        stderr(&o)
    );
    let whole = d.join("whole");
    ok(&vitro(&[
        "batch",
        &exp,
        "--out",
        &whole.display().to_string(),
        "-j",
        "2",
    ]));
    let (a, b) = (
        rows(&killed.join("summary.csv")),
        rows(&whole.join("summary.csv")),
    );
    assert_eq!(a.len(), 1 + 24);
    assert_eq!(a, b);
    // The journal holds each run once.
    let text = std::fs::read_to_string(&journal).expect("a journal");
    assert_eq!(text.lines().count(), 24);
    assert!(text.ends_with('\n'));
    let m: serde_json::Value =
        serde_json::from_slice(&std::fs::read(killed.join("manifest.json")).expect("a manifest"))
            .expect("JSON");
    let sessions = m["sessions"].as_array().expect("sessions");
    assert_eq!(sessions.len(), 2);
    assert!(
        sessions[0]["finished"].is_null(),
        "the killed session never finished"
    );
}

#[test]
fn failing_runs_are_recorded_and_fail_the_command() {
    let d = tmp("fail");
    // 12 cars do not fit the small town (11 junctions): the scenario rejects those runs.
    let exp = experiment(
        &d,
        &scenario("tests/small.toml"),
        "seed = 1\nreplicates = 2\n[parameters]\n\"cars.count\" = [2, 12]\n",
    );
    let out = d.join("out");
    let o = vitro(&[
        "batch",
        &exp,
        "--out",
        &out.display().to_string(),
        "-j",
        "2",
    ]);
    assert_eq!(o.status.code(), Some(1), "{}", stderr(&o));
    let err = stderr(&o);
    assert!(err.contains("2 of 4 runs failed: 2, 3"), "{err}");
    assert!(err.contains("cars.count"), "{err}");
    let t = rows(&out.join("summary.csv"));
    let status = t[0]
        .iter()
        .position(|h| h == "status")
        .expect("a status column");
    let statuses: Vec<&str> = t[1..].iter().map(|r| r[status].as_str()).collect();
    assert_eq!(statuses, ["ok", "ok", "failed", "failed"]);
    assert!(
        t[3][status + 1].contains("invalid value 12 for `cars.count`"),
        "{:?}",
        t[3]
    );
    // Plots leave failed runs out and say so.
    let plots = d.join("plots");
    ok(&vitro(&[
        "plot",
        &out.display().to_string(),
        "--out",
        &plots.display().to_string(),
    ]));
    assert!(plots.join("mean_idleness_s-vs-cars.count.png").exists());
    assert!(plots.join("hist-mean_idleness_s.svg").exists());
}

#[test]
fn bad_input_exits_2_with_a_place() {
    let d = tmp("bad");
    let exp = experiment(
        &d,
        &scenario("tests/small.toml"),
        "seed = 1\n[parameters]\n\"channel.los\" = [0.1]\n",
    );
    let o = vitro(&["batch", &exp, "--out", &d.join("o").display().to_string()]);
    assert_eq!(o.status.code(), Some(2), "{}", stderr(&o));
    let err = stderr(&o);
    assert!(
        err.contains("exp.toml:4:17: unknown scenario key `channel.los`"),
        "{err}"
    );
    assert!(!d.join("o").exists(), "nothing is written for bad input");
    let o = vitro(&["batch", &exp, "--out", "x", "--shard", "2/2"]);
    assert_eq!(o.status.code(), Some(2), "{}", stderr(&o));
    let o = vitro(&["batch", "--print-schema"]);
    ok(&o);
    let schema: serde_json::Value = serde_json::from_slice(&o.stdout).expect("a JSON schema");
    assert_eq!(schema["title"], "Vitro experiment");
}

#[test]
fn mission_experiments_validate() {
    for name in [
        "mission_search",
        "mission_conditioned",
        "mission_uav_loss",
        "mission_repair",
    ] {
        let path = scenario(&format!("../../experiments/{name}.toml"));
        let o = vitro(&["validate", &path]);
        ok(&o);
        assert!(
            String::from_utf8_lossy(&o.stdout).contains(": ok (experiment"),
            "{name}"
        );
    }
}

#[test]
fn example_experiments_load() {
    for name in ["demo_sweep", "demo_lhs", "jobs_speedup"] {
        let path = scenario(&format!("../../experiments/{name}.toml"));
        let d = tmp(name);
        // One shard of many: checks the file and makes a single short run.
        let o = vitro(&[
            "batch",
            &path,
            "--out",
            &d.join("o").display().to_string(),
            "--shard",
            "0/1000",
        ]);
        ok(&o);
    }
}

//! `vitro search` as a user runs it: the same search with one or two jobs, a search killed
//! and resumed, minimal scenarios that `vitro run` fails again with their recorded trace
//! hash, bad `[search]` tables; and a conditioned `vitro batch`.

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

fn ok(o: &Output) {
    assert!(o.status.success(), "{}", stderr(o));
}

fn tmp(name: &str) -> PathBuf {
    let d = std::env::temp_dir().join(format!("vitro-cli-search-{name}-{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&d);
    std::fs::create_dir_all(&d).expect("a temporary directory");
    d
}

fn repo(rel: &str) -> String {
    Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("../..")
        .join(rel)
        .display()
        .to_string()
}

fn experiment(dir: &Path, scenario: &str, body: &str) -> String {
    let path = dir.join("exp.toml");
    std::fs::write(&path, format!("scenario = {scenario:?}\n{body}")).expect("written");
    path.display().to_string()
}

/// The rows of a CSV file without its `wall_s` column.
fn rows(path: &Path) -> Vec<String> {
    let text = std::fs::read_to_string(path).expect("a table");
    let mut lines = text.lines();
    let header: Vec<&str> = lines.next().expect("a header").split(',').collect();
    let wall = header.iter().position(|h| *h == "wall_s");
    std::iter::once(header.join(","))
        .chain(lines.map(|l| {
            let mut cells: Vec<&str> = l.split(',').collect();
            if let Some(w) = wall {
                cells.remove(w);
            }
            cells.join(",")
        }))
        .collect()
}

/// A demo search: long idleness counts as a failure; loss and fleet size searched.
const DEMO: &str = r#"
seed = 4
end_s = 600.0
[search]
budget = 24
population = 8
shrink = 1
shrink_budget = 12
[search.objective]
failure = "max_idleness_s > 400"
maximise = "max_idleness_s"
[search.parameters]
"channel.loss" = [0.0, 1.0]
"cars.count" = [1, 6]
"#;

#[test]
fn same_search_with_one_or_two_jobs_and_after_a_kill() {
    let d = tmp("jobs");
    let exp = experiment(&d, &repo("scenarios/demo.toml"), DEMO);
    let one = d.join("one");
    let o = vitro(&[
        "search",
        &exp,
        "--out",
        &one.display().to_string(),
        "-j",
        "1",
    ]);
    ok(&o);
    let two = d.join("two");
    ok(&vitro(&[
        "search",
        &exp,
        "--out",
        &two.display().to_string(),
        "-j",
        "2",
    ]));
    for t in ["summary.csv", "found.csv"] {
        assert_eq!(rows(&one.join(t)), rows(&two.join(t)), "{t}");
    }
    let found = rows(&one.join("found.csv"));
    assert!(
        found[0].starts_with("run,generation,seed,channel.loss,cars.count,objective,trace_hash"),
        "{found:?}"
    );
    assert!(found.len() > 1, "the search found failures: {}", stderr(&o));
    assert_eq!(rows(&one.join("summary.csv")).len(), 25);

    // Killed after a few runs, then resumed: the same search.
    let killed = d.join("killed");
    let mut child = Command::new(env!("CARGO_BIN_EXE_vitro"))
        .args([
            "search",
            &exp,
            "--out",
            &killed.display().to_string(),
            "-j",
            "1",
        ])
        .stderr(Stdio::null())
        .spawn()
        .expect("the search starts");
    let journal = killed.join("runs.jsonl");
    let started = Instant::now();
    while std::fs::read_to_string(&journal).map_or(0, |s| s.lines().count()) < 10 {
        assert!(
            started.elapsed() < Duration::from_secs(120),
            "no runs recorded"
        );
        std::thread::sleep(Duration::from_millis(10));
    }
    child.kill().expect("SIGKILL");
    child.wait().expect("the search ends");
    let o = vitro(&["search", &exp, "--out", &killed.display().to_string()]);
    assert_eq!(o.status.code(), Some(2), "{}", stderr(&o));
    assert!(stderr(&o).contains("--resume"), "{}", stderr(&o));
    let o = vitro(&[
        "search",
        &exp,
        "--out",
        &killed.display().to_string(),
        "--resume",
        "-j",
        "2",
    ]);
    ok(&o);
    assert!(stderr(&o).contains("done before"), "{}", stderr(&o));
    for t in ["summary.csv", "found.csv"] {
        assert_eq!(rows(&one.join(t)), rows(&killed.join(t)), "{t}");
    }
    // Another strategy in the same directory is refused.
    let o = vitro(&[
        "search",
        &exp,
        "--out",
        &killed.display().to_string(),
        "--resume",
        "--strategy",
        "random",
    ]);
    assert_eq!(o.status.code(), Some(2), "{}", stderr(&o));
    assert!(stderr(&o).contains("random search"), "{}", stderr(&o));
}

#[test]
fn minimal_mission_failures_run_again_with_their_hash() {
    let d = tmp("minimal");
    // Two minutes are too short to get the VIP out: every run fails (this checks the
    // mechanics, not the mission). Shrinking cuts entities and moves values back.
    let exp = experiment(
        &d,
        &repo("scenarios/evacuation.toml"),
        r#"
seed = 2
end_s = 60.0
[search]
budget = 4
population = 2
shrink = 1
shrink_budget = 10
[search.objective]
failure = "success == false"
[search.parameters]
"entity.4.count" = [2, 8]
"channel.loss" = [0.0, 0.5]
"#,
    );
    let out = d.join("out");
    let o = vitro(&[
        "search",
        &exp,
        "--out",
        &out.display().to_string(),
        "-j",
        "2",
    ]);
    ok(&o);
    let m: serde_json::Value =
        serde_json::from_slice(&std::fs::read(out.join("manifest.json")).expect("a manifest"))
            .expect("JSON");
    let minimal = m["search"]["minimal"]
        .as_array()
        .expect("minimal scenarios");
    assert_eq!(minimal.len(), 1, "{}", stderr(&o));
    let file = out.join(minimal[0]["file"].as_str().expect("a file"));
    let hash = minimal[0]["trace_hash"].as_str().expect("a hash");
    let text = std::fs::read_to_string(&file).expect("the minimal scenario");
    assert!(
        text.contains(&format!("# expected trace hash: {hash}")),
        "{text}"
    );
    let changes = minimal[0]["changes"].as_array().expect("changes");
    assert!(!changes.is_empty(), "it shrank: {text}");
    // It runs on its own, from its own folder, fails again, with the same trace hash.
    let run = vitro(&["run", &file.display().to_string(), "--quiet"]);
    assert_eq!(run.status.code(), Some(4), "{}", stderr(&run));
    assert_eq!(String::from_utf8_lossy(&run.stdout).trim(), hash);
}

#[test]
fn bad_search_tables_exit_2_with_a_place() {
    let d = tmp("bad");
    let demo = repo("scenarios/demo.toml");
    let cases = [
        (
            "[search]\nbudgett = 3\n[search.objective]\nfailure = \"visits < 3\"\n",
            "exp.toml:4:1",
            "unknown field `budgett`",
        ),
        (
            "[search.objective]\nfailure = \"visits < 3\"\n[search.parameters]\n\"channel.loss\" = [0.5, 0.5]\n",
            "exp.toml:6:18",
            "empty range",
        ),
        (
            "[search.objective]\nfailure = \"visit < 3\"\n[search.parameters]\n\"channel.loss\" = [0.0, 0.5]\n",
            "exp.toml:4:11",
            "unknown metric `visit`",
        ),
        (
            "[search.objective]\nmaximise = \"visits\"\n[search.parameters]\n\"channel.los\" = [0.0, 0.5]\n",
            "exp.toml:6:17",
            "unknown scenario key `channel.los`",
        ),
    ];
    for (body, place, what) in cases {
        let exp = experiment(&d, &demo, &format!("seed = 1\n{body}"));
        let o = vitro(&["search", &exp, "--out", &d.join("o").display().to_string()]);
        assert_eq!(o.status.code(), Some(2), "{body}: {}", stderr(&o));
        let err = stderr(&o);
        assert!(err.contains(place) && err.contains(what), "{body}: {err}");
        assert!(!err.contains("panicked"), "{err}");
        // `vitro validate` reports the same.
        let o = vitro(&["validate", &exp]);
        assert_eq!(o.status.code(), Some(2), "{}", stderr(&o));
    }
    assert!(!d.join("o").exists(), "nothing is written for bad input");
}

#[test]
fn conditioned_batch_stops_points_early_whatever_the_jobs() {
    let d = tmp("stop");
    let exp = experiment(
        &d,
        &repo("scenarios/demo.toml"),
        "seed = 3\nreplicates = 12\nend_s = 300.0\n[parameters]\n\"channel.loss\" = [0.0, 0.9]\n\
         [stop]\nmetric = \"visits\"\nhalf_width = 8.0\nmin_replicates = 3\n",
    );
    let a = d.join("a");
    let o = vitro(&["batch", &exp, "--out", &a.display().to_string(), "-j", "1"]);
    ok(&o);
    assert!(stderr(&o).contains("conditioned:"), "{}", stderr(&o));
    let b = d.join("b");
    ok(&vitro(&[
        "batch",
        &exp,
        "--out",
        &b.display().to_string(),
        "-j",
        "2",
    ]));
    assert_eq!(rows(&a.join("summary.csv")), rows(&b.join("summary.csv")));
    let m: serde_json::Value =
        serde_json::from_slice(&std::fs::read(a.join("manifest.json")).expect("a manifest"))
            .expect("JSON");
    let points = m["stop"]["points"].as_array().expect("points");
    assert_eq!(points.len(), 2);
    let made: u64 = points
        .iter()
        .map(|p| p["replicates"].as_u64().unwrap_or(0))
        .sum();
    assert_eq!(rows(&a.join("summary.csv")).len() as u64, 1 + made);
    for p in points {
        let n = p["replicates"].as_u64().unwrap_or(0);
        let met = p["met"].as_bool().unwrap_or(false);
        assert!((3..=12).contains(&n), "{p}");
        assert!(met || n == 12, "{p}");
        if met {
            assert!(p["half_width"].as_f64().unwrap_or(f64::NAN) <= 8.0, "{p}");
        }
    }
    let skipped = m["runs"]
        .as_array()
        .expect("runs")
        .iter()
        .filter(|r| r["status"] == "not_needed")
        .count() as u64;
    assert_eq!(skipped + made, 24);
    // Sharding a conditioned experiment is refused.
    let o = vitro(&["batch", &exp, "--out", "x", "--shard", "0/2"]);
    assert_eq!(o.status.code(), Some(2), "{}", stderr(&o));
}

//! Searches through the library with a toy model whose failures are known: the adaptive
//! strategy finds more of them than random sampling, results do not depend on the job count,
//! shrinking reaches the known smallest failing run, and bad `[search]` tables are located.

use std::collections::BTreeMap;
use std::path::{Path, PathBuf};
use vitro_batch::search::{SearchOptions, Strategy, run_search};
use vitro_batch::{Experiment, ExperimentError, RunOutput, RunSettings, Runner, Value};

/// A "world": groups of `[[unit]]` with a `count`, a knob `x` in [0, 1] and a `mode`. It
/// fails when `x > 0.8`, the mode is `"b"` and the first group has at least 3 units; the
/// guide metric `heat` grows toward that corner. Runs stop at `t = 10 x` when they fail.
struct Toy;

impl Runner for Toy {
    fn metric_names(&self, _: &toml::Table) -> Result<Vec<String>, String> {
        Ok(["fails", "heat", "sim_time_s", "trace_hash"]
            .map(String::from)
            .to_vec())
    }

    fn run(&self, s: &toml::Table, seed: u64, set: &RunSettings<'_>) -> Result<RunOutput, String> {
        let x = s["knob"]["x"].as_float().ok_or("x")?;
        let mode = s["knob"]["mode"].as_str().ok_or("mode")?;
        let units = s["unit"].as_array().ok_or("no units")?;
        let first = units
            .first()
            .and_then(|u| u.get("count"))
            .and_then(toml::Value::as_integer)
            .ok_or("the first group is needed")?;
        let t = 10.0 * x;
        let fails = x > 0.8 && mode == "b" && first >= 3 && set.end_s.is_none_or(|e| e > t);
        let heat = x + f64::from(u8::from(mode == "b")) + first as f64 / 10.0;
        let hash = format!("{:016x}", seed ^ (x.to_bits()) ^ (first as u64) << 40);
        let metrics = BTreeMap::from([
            ("fails".to_string(), Value::Bool(fails)),
            ("heat".to_string(), Value::Float(heat)),
            (
                "sim_time_s".to_string(),
                Value::Float(if fails { t } else { 100.0 }),
            ),
            ("trace_hash".to_string(), Value::Text(hash)),
        ]);
        Ok(RunOutput {
            metrics,
            series: vec![],
        })
    }

    fn scenario_file(
        &self,
        s: &toml::Table,
        seed: u64,
        end_s: Option<f64>,
        _: &Path,
    ) -> Result<String, String> {
        let mut t = s.clone();
        t.insert("seed".into(), toml::Value::Integer(seed as i64));
        if let Some(e) = end_s {
            t.insert("end_s".into(), toml::Value::Float(e));
        }
        toml::to_string(&t).map_err(|e| e.to_string())
    }
}

const SCENARIO: &str = "seed = 1\n[knob]\nx = 0.1\nmode = 'a'\n\
                        [[unit]]\ncount = 1\n[[unit]]\ncount = 4\n[[unit]]\ncount = 2\n";

const SEARCH: &str = "[search]\nbudget = 120\npopulation = 20\nshrink = 2\nshrink_budget = 60\n\
                      [search.objective]\nfailure = 'fails == true'\nmaximise = 'heat'\n\
                      [search.parameters]\n'knob.x' = [0.0, 1.0]\n\
                      'knob.mode' = { values = ['a', 'b', 'c', 'd'] }\n'unit.0.count' = [1, 8]\n";

fn tmp(name: &str) -> PathBuf {
    let d = std::env::temp_dir().join(format!("vitro-search-{name}-{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&d);
    std::fs::create_dir_all(&d).unwrap();
    d
}

fn load(dir: &Path, body: &str) -> Result<Experiment, ExperimentError> {
    std::fs::write(dir.join("s.toml"), SCENARIO).unwrap();
    let path = dir.join("e.toml");
    std::fs::write(&path, format!("scenario = 's.toml'\nseed = 1\n{body}")).unwrap();
    Experiment::load(&path, &Toy)
}

fn opts(out: &Path, strategy: Strategy, seed: u64, jobs: usize) -> SearchOptions {
    SearchOptions {
        out: out.to_owned(),
        jobs,
        resume: false,
        budget: None,
        strategy,
        seed: Some(seed),
        shrink: Some(0),
    }
}

#[test]
fn adaptive_finds_more_failures_than_random() {
    let d = tmp("compare");
    let exp = load(&d, SEARCH).unwrap();
    let (mut adaptive, mut random) = (0, 0);
    for seed in 1..=4 {
        for (strategy, total) in [
            (Strategy::Adaptive, &mut adaptive),
            (Strategy::Random, &mut random),
        ] {
            let out = d.join(format!("{}-{seed}", strategy.as_str()));
            let r = run_search(&exp, &Toy, &opts(&out, strategy, seed, 2), &|_| {}).unwrap();
            assert_eq!(r.planned, 120);
            *total += r.failures.len();
        }
    }
    // About 1 run in 40 fails under uniform sampling.
    assert!(random < 30, "random found {random}");
    assert!(adaptive >= 2 * random.max(1), "{adaptive} vs {random}");
}

#[test]
fn results_do_not_depend_on_jobs() {
    let d = tmp("jobs");
    let exp = load(&d, SEARCH).unwrap();
    let one = d.join("one");
    let two = d.join("two");
    run_search(&exp, &Toy, &opts(&one, Strategy::Adaptive, 3, 1), &|_| {}).unwrap();
    run_search(&exp, &Toy, &opts(&two, Strategy::Adaptive, 3, 2), &|_| {}).unwrap();
    let found = |d: &Path| std::fs::read_to_string(d.join("found.csv")).unwrap();
    assert_eq!(found(&one), found(&two));
    let strip = |p: &Path| -> Vec<String> {
        let text = std::fs::read_to_string(p).unwrap();
        text.lines()
            .map(|l| l.rsplit_once(',').map_or(l, |(a, _)| a).to_owned()) // wall_s is last
            .collect()
    };
    assert_eq!(
        strip(&one.join("summary.csv")),
        strip(&two.join("summary.csv"))
    );
}

#[test]
fn shrinking_reaches_the_smallest_failure() {
    let d = tmp("shrink");
    let exp = load(&d, SEARCH).unwrap();
    let out = d.join("out");
    let o = SearchOptions {
        shrink: Some(1),
        ..opts(&out, Strategy::Adaptive, 5, 2)
    };
    let r = run_search(&exp, &Toy, &o, &|_| {}).unwrap();
    assert!(!r.failures.is_empty());
    let m = &r.minimal[0];
    let text = std::fs::read_to_string(out.join(&m.file)).unwrap();
    assert!(text.contains(&format!("# expected trace hash: {}", m.trace_hash)));
    let s: toml::Table = toml::from_str(&text).unwrap();
    // Groups 1 and 2 are not needed; the first keeps exactly 3 units; x stays above 0.8
    // (the scenario's 0.1 does not fail) and the mode at "b"; the end is cut to t + 1.
    let units = s["unit"].as_array().unwrap();
    assert_eq!(units.len(), 1, "{text}");
    assert_eq!(units[0]["count"].as_integer(), Some(3), "{text}");
    let x = s["knob"]["x"].as_float().unwrap();
    assert!(x > 0.8, "{text}");
    assert_eq!(s["knob"]["mode"].as_str(), Some("b"));
    assert_eq!(
        s["end_s"].as_float(),
        Some((10.0 * x).ceil() + 1.0),
        "{text}"
    );
    // The shrunk scenario runs to the recorded failure and hash.
    let seed = s["seed"].as_integer().unwrap() as u64;
    let keep = exp.keep.clone();
    let again = Toy
        .run(
            &s,
            seed,
            &RunSettings {
                end_s: s["end_s"].as_float(),
                keep: &keep,
            },
        )
        .unwrap();
    assert_eq!(again.metrics["fails"], Value::Bool(true));
    assert_eq!(
        again.metrics["trace_hash"],
        Value::Text(m.trace_hash.clone())
    );
}

#[test]
fn bad_search_tables_are_located() {
    let d = tmp("bad");
    let cases = [
        (
            "[search]\nbudgt = 3\n",
            "e.toml:4:1",
            "unknown field `budgt`",
        ),
        (
            "[search.objective]\nfailure = 'fails == true'\n[search.parameters]\n'knob.x' = [1.0, 0.5]\n",
            "e.toml:6:12",
            "empty range",
        ),
        (
            "[search.objective]\nmaximise = 'hot'\n[search.parameters]\n'knob.x' = [0.0, 0.5]\n",
            "e.toml:4:12",
            "unknown metric `hot`",
        ),
        (
            "[search.objective]\nfailure = 'fails = true'\n[search.parameters]\n'knob.x' = [0.0, 0.5]\n",
            "e.toml:4:11",
            "invalid failure condition",
        ),
        (
            "[search.objective]\nfailure = 'fails == true'\n[search.parameters]\n'unit.0.count' = [1.5, 3]\n",
            "e.toml:6:18",
            "whole ends",
        ),
        (
            "[search.objective]\nfailure = 'fails == true'\n[search.parameters]\n'knob.mode' = { values = [] }\n",
            "e.toml:6:15",
            "empty range",
        ),
    ];
    for (body, place, what) in cases {
        match load(&d, body) {
            Err(ExperimentError::Invalid(l)) => {
                let s = l.to_string();
                assert!(s.contains(place) && s.contains(what), "{body}\n{s}");
            }
            other => panic!("{body}: expected an invalid experiment, got {other:?}"),
        }
    }
}

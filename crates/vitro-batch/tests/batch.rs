//! Batches through the library with a toy runner: faults, resume rules, merges, hypercubes.

use std::collections::BTreeMap;
use std::path::{Path, PathBuf};
use vitro_batch::journal::{self, Status};
use vitro_batch::table::Cells;
use vitro_batch::{
    BatchError, BatchOptions, Experiment, MergeError, RunOutput, RunSettings, Runner, SeriesRow,
    Value, merge, run_batch,
};

/// `score = 10 x + seed mod 7`; x = 3 panics, x = 4 is rejected.
struct Toy;

impl Runner for Toy {
    fn metric_names(&self, _: &toml::Table) -> Result<Vec<String>, String> {
        Ok(vec!["score".into(), "odd".into()])
    }

    fn run(&self, s: &toml::Table, seed: u64, set: &RunSettings<'_>) -> Result<RunOutput, String> {
        let x = s["model"]["x"].as_integer().ok_or("x is not an integer")?;
        match x {
            3 => panic!("x = 3 breaks the model"),
            4 => return Err("invalid value 4 for `model.x`".into()),
            _ => {}
        }
        let score = 10.0 * x as f64 + (seed % 7) as f64 + s["model"]["y"].as_float().unwrap_or(0.0);
        let metrics = BTreeMap::from([
            ("score".to_string(), Value::Float(score)),
            ("odd".to_string(), Value::Bool(seed % 2 == 1)),
        ]);
        let series = match set.keep.every_s {
            Some(every) => (1..=3)
                .map(|i| SeriesRow {
                    t_s: every * f64::from(i),
                    values: BTreeMap::from([(
                        "score".to_string(),
                        Value::Float(score * f64::from(i)),
                    )]),
                })
                .collect(),
            None => vec![],
        };
        Ok(RunOutput { metrics, series })
    }
}

fn tmp(name: &str) -> PathBuf {
    let d = std::env::temp_dir().join(format!("vitro-batch-{name}-{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&d);
    std::fs::create_dir_all(&d).unwrap();
    d
}

fn load(dir: &Path, body: &str) -> Experiment {
    std::fs::write(dir.join("s.toml"), "[model]\nx = 1\ny = 0.5\n").unwrap();
    let path = dir.join("e.toml");
    std::fs::write(&path, format!("scenario = 's.toml'\n{body}")).unwrap();
    Experiment::load(&path, &Toy).unwrap()
}

fn opts(out: &Path, jobs: usize) -> BatchOptions {
    BatchOptions {
        out: out.to_owned(),
        jobs,
        shard: None,
        shard_from: None,
        resume: false,
    }
}

#[test]
fn panics_and_errors_fail_only_their_runs() {
    let d = tmp("faults");
    let exp = load(
        &d,
        "seed = 1\nreplicates = 2\n[parameters]\n\"model.x\" = [1, 3, 4, 5]\n",
    );
    let out = d.join("out");
    let report = run_batch(&exp, &Toy, &opts(&out, 2), &|_| {}).unwrap();
    assert_eq!(report.ran, 8);
    let failed: Vec<u64> = report.failed.iter().map(|f| f.0).collect();
    assert_eq!(failed, [2, 3, 4, 5]);
    assert!(
        report.failed[0]
            .1
            .starts_with("panicked: x = 3 breaks the model")
    );
    assert_eq!(report.failed[2].1, "invalid value 4 for `model.x`");
    let recs = journal::read(&out).unwrap().records;
    assert_eq!(recs.iter().filter(|r| r.status == Status::Ok).count(), 4);
    let csv = std::fs::read_to_string(out.join("summary.csv")).unwrap();
    assert!(csv.starts_with("run,point,replicate,seed,model.x,score,odd,status,error,wall_s\n"));
    assert!(
        csv.contains(",failed,panicked: x = 3 breaks the model,"),
        "{csv}"
    );
    assert_eq!(csv.lines().count(), 9);
}

#[test]
fn resume_rules() {
    let d = tmp("resume");
    let exp = load(
        &d,
        "seed = 1\nreplicates = 3\n[parameters]\n\"model.x\" = [1, 2]\n",
    );
    let out = d.join("out");
    let mut o = opts(&out, 1);
    o.shard = Some("0/2".parse().unwrap());
    run_batch(&exp, &Toy, &o, &|_| {}).unwrap();
    // Again without --resume: refused. With it: nothing left to do.
    assert!(matches!(
        run_batch(&exp, &Toy, &o, &|_| {}),
        Err(BatchError::Exists(_))
    ));
    o.resume = true;
    let r = run_batch(&exp, &Toy, &o, &|_| {}).unwrap();
    assert_eq!((r.planned, r.skipped, r.ran), (3, 3, 0));
    // Another shard into the same directory: refused.
    o.shard = Some("1/2".parse().unwrap());
    let e = run_batch(&exp, &Toy, &o, &|_| {}).unwrap_err();
    assert!(e.is_input() && e.to_string().contains("shard 0/2"), "{e}");
    // A changed scenario: refused.
    std::fs::write(d.join("s.toml"), "[model]\nx = 1\ny = 0.25\n").unwrap();
    let changed = Experiment::load(&d.join("e.toml"), &Toy).unwrap();
    o.shard = Some("0/2".parse().unwrap());
    let e = run_batch(&changed, &Toy, &o, &|_| {}).unwrap_err();
    assert!(e.to_string().contains("scenario"), "{e}");
}

#[test]
fn merged_partial_shards_resume_to_the_whole() {
    let d = tmp("merge");
    let body = "seed = 9\nreplicates = 2\n[parameters]\n\"model.x\" = [1, 2, 5]\n[keep]\nseries = ['score']\nevery_s = 2.0\n";
    let exp = load(&d, body);
    let whole = d.join("whole");
    run_batch(&exp, &Toy, &opts(&whole, 2), &|_| {}).unwrap();
    // Two of three shards, merged: one third missing, then made by resuming the merge.
    let mut shards = Vec::new();
    for i in 0..2 {
        let mut o = opts(&d.join(format!("s{i}")), 1);
        o.shard = Some(format!("{i}/3").parse().unwrap());
        run_batch(&exp, &Toy, &o, &|_| {}).unwrap();
        shards.push(o.out);
    }
    let merged = d.join("merged");
    let r = merge(&shards, &merged).unwrap();
    assert_eq!((r.runs, r.total), (4, 6));
    assert!(matches!(
        merge(&shards, &merged),
        Err(MergeError::Exists(_))
    ));
    let mut o = opts(&merged, 2);
    o.resume = true;
    let r = run_batch(&exp, &Toy, &o, &|_| {}).unwrap();
    assert_eq!((r.skipped, r.ran), (4, 2));
    for table in ["summary.csv", "series.csv"] {
        let strip = |p: PathBuf| -> Vec<String> {
            std::fs::read_to_string(p)
                .unwrap()
                .lines()
                .map(|l| match l.rsplit_once(',') {
                    Some((head, _)) if table == "summary.csv" => head.to_owned(),
                    _ => l.to_owned(),
                })
                .collect()
        };
        assert_eq!(
            strip(merged.join(table)),
            strip(whole.join(table)),
            "{table}"
        );
    }
    assert!(matches!(
        merge(&[shards[0].clone(), shards[0].clone()], &d.join("m2")),
        Err(MergeError::Overlap { run: 0, .. })
    ));
}

#[test]
fn hypercube_runs_and_typed_tables() {
    let d = tmp("lhs");
    let exp = load(
        &d,
        "seed = 4\nreplicates = 2\n[parameters]\n\"model.x\" = [1, 2]\n[latin_hypercube]\nsamples = 5\nintervals = { \"model.y\" = [0.0, 1.0] }\n",
    );
    assert_eq!(exp.design.runs(), Some(20));
    let out = d.join("out");
    run_batch(&exp, &Toy, &opts(&out, 2), &|_| {}).unwrap();
    let m = vitro_batch::manifest::Manifest::load(&out)
        .unwrap()
        .unwrap();
    let mut recs = journal::read(&out).unwrap().records;
    recs.sort_by_key(|r| r.run);
    let t = vitro_batch::table::summary(&m, &recs);
    assert_eq!(t.rows, 20);
    let y = t.column("model.y").unwrap();
    assert!(matches!(
        &y.cells,
        Cells::Values(vitro_batch::table::Kind::Float, _)
    ));
    assert!(matches!(
        t.column("odd").unwrap().kind(),
        vitro_batch::table::Kind::Bool
    ));
    // Each of the 5 strata of model.y holds one sample (per level of model.x).
    let mut strata: Vec<usize> = recs[..10]
        .iter()
        .step_by(2)
        .map(|r| (r.params["model.y"].as_f64().unwrap() * 5.0) as usize)
        .collect();
    strata.sort_unstable();
    assert_eq!(strata, [0, 1, 2, 3, 4]);
    // Replicates share their point's levels; points differ.
    assert_eq!(recs[0].params, recs[1].params);
    assert_ne!(recs[0].params, recs[2].params);
}

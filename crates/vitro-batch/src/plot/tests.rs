//! Plot tests on a synthetic result set: which charts, what they hold, that files appear.

use super::*;
use crate::manifest::{FORMAT, FileInfo};
use crate::runner::Keep;
use std::collections::BTreeMap;

fn manifest(params: Vec<ParamInfo>, metrics: &[&str]) -> Manifest {
    let info = FileInfo {
        path: "x".into(),
        sha256: "0".into(),
    };
    Manifest {
        format: FORMAT,
        name: "t".into(),
        experiment: info.clone(),
        scenario: info,
        base_seed: 0,
        replicates: 3,
        common_random_numbers: false,
        end_s: None,
        parameters: params,
        keep: Keep {
            metrics: metrics.iter().map(|m| m.to_string()).collect(),
            series: vec![],
            every_s: None,
        },
        runs_total: 0,
        shard: None,
        shard_from: None,
        merged_from: vec![],
        sessions: vec![],
        stop: None,
        search: None,
        runs: vec![],
    }
}

fn param(path: &str, origin: Origin, levels: Vec<Value>) -> ParamInfo {
    ParamInfo {
        path: path.into(),
        origin,
        levels,
    }
}

/// Runs over loss x mode, 3 replicates; `score = 10 * loss + replicate`, `success` unless
/// mode is "b" and replicate 0; run 5 failed.
fn records() -> Vec<RunRecord> {
    let mut out = Vec::new();
    let mut k = 0;
    for (p, (loss, mode)) in [(0.0, "a"), (0.0, "b"), (0.5, "a"), (0.5, "b")]
        .iter()
        .enumerate()
    {
        for rep in 0..3u32 {
            let failed = k == 5;
            out.push(RunRecord {
                run: k,
                point: p as u64,
                replicate: rep,
                seed: k,
                params: BTreeMap::from([
                    ("loss".to_string(), Value::Float(*loss)),
                    ("mode".to_string(), Value::Text(mode.to_string())),
                ]),
                status: if failed { Status::Failed } else { Status::Ok },
                error: failed.then(|| "boom".to_string()),
                wall_s: 0.1,
                metrics: if failed {
                    BTreeMap::new()
                } else {
                    BTreeMap::from([
                        (
                            "score".to_string(),
                            Value::Float(10.0 * loss + f64::from(rep)),
                        ),
                        (
                            "success".to_string(),
                            Value::Bool(!(*mode == "b" && rep == 0)),
                        ),
                        ("label".to_string(), Value::Text("x".into())),
                    ])
                },
                series: vec![],
            });
            k += 1;
        }
    }
    out
}

fn two_params() -> Manifest {
    manifest(
        vec![
            param(
                "loss",
                Origin::List,
                vec![Value::Float(0.0), Value::Float(0.5)],
            ),
            param("mode", Origin::List, vec!["a".into(), "b".into()]),
        ],
        &["score", "success", "label"],
    )
}

#[test]
fn the_expected_charts() {
    let m = two_params();
    let charts = charts(&m, &records(), &PlotOptions::default()).unwrap();
    let names: Vec<&str> = charts.iter().map(|(n, _)| n.as_str()).collect();
    assert_eq!(
        names,
        [
            "score-vs-loss",
            "score-vs-mode",
            "success-vs-loss",
            "success-vs-mode",
            "hist-score",
            "hist-success",
            "success-rate-vs-mode"
        ]
    );
    // score vs loss: one line per mode; mode a at loss 0.5 has replicates 0, 1, 2 -> mean 6.
    let Chart::Xy(xy) = &charts[0].1 else {
        panic!("xy chart expected")
    };
    assert_eq!(xy.lines.len(), 2);
    assert_eq!(xy.lines[0].label.as_deref(), Some("mode = a"));
    let (x, ci) = xy.lines[0].points[1];
    assert_eq!((x, ci.n, ci.mean), (0.5, 3, 6.0));
    assert!(ci.lo < 6.0 && ci.hi > 6.0);
    // The failed run (loss 0, mode b, replicate 2) is left out.
    assert_eq!(xy.lines[1].points[0].1.n, 2);
    assert!(xy.note.contains("1 failed run left out"), "{}", xy.note);
    // Success rate per mode from the boolean metric: a 6/6, b 3/6 (one failed, one false).
    let Chart::Category(c) = &charts[6].1 else {
        panic!("category chart expected")
    };
    assert!(c.bars);
    assert_eq!(c.items[0].map(|m| m.mean), Some(1.0));
    assert_eq!(c.items[1].map(|m| (m.n, m.mean)), Some((6, 0.5)));
}

#[test]
fn status_is_success_without_a_success_metric() {
    let mut m = two_params();
    m.keep.metrics = vec!["score".into()];
    let charts = charts(&m, &records(), &PlotOptions::default()).unwrap();
    let Some((_, Chart::Category(c))) = charts.iter().find(|(n, _)| n == "success-rate-vs-mode")
    else {
        panic!("no success chart")
    };
    assert_eq!(c.items[1].map(|m| m.mean), Some(5.0 / 6.0));
}

#[test]
fn asking_for_unknown_or_non_boolean_metrics_fails() {
    let m = two_params();
    let opts = PlotOptions {
        metrics: vec!["nope".into()],
        ..Default::default()
    };
    assert!(matches!(
        charts(&m, &records(), &opts),
        Err(PlotError::UnknownMetric { .. })
    ));
    let opts = PlotOptions {
        success: Some("score".into()),
        ..Default::default()
    };
    assert!(matches!(
        charts(&m, &records(), &opts),
        Err(PlotError::NotBoolean(_))
    ));
}

#[test]
fn hypercube_parameters_get_dots() {
    let m = manifest(
        vec![param(
            "loss",
            Origin::LatinHypercube,
            vec![Value::Float(0.0), Value::Float(0.5)],
        )],
        &["score"],
    );
    let charts = charts(&m, &records(), &PlotOptions::default()).unwrap();
    let Chart::Xy(xy) = &charts[0].1 else {
        panic!("xy chart expected")
    };
    assert_eq!(xy.lines.len(), 1);
    assert!(!xy.lines[0].connect);
    assert_eq!(xy.lines[0].points.len(), 4); // one per design point
}

#[test]
fn files_are_written() {
    let dir = std::env::temp_dir().join(format!("vitro-plot-{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&dir);
    let m = two_params();
    let mut written = Vec::new();
    for (name, chart) in charts(&m, &records(), &PlotOptions::default()).unwrap() {
        std::fs::create_dir_all(&dir).unwrap();
        written.extend(draw::save(&chart, &dir.join(sanitize(&name))).unwrap());
    }
    assert_eq!(written.len(), 14);
    // A single category and an empty histogram draw too.
    let one = Chart::Category(draw::CategoryChart {
        title: "one".into(),
        x_desc: "x".into(),
        y_desc: "y".into(),
        note: String::new(),
        categories: vec!["only".into()],
        items: vec![stats::wilson(1, 2)],
        bars: true,
    });
    written.extend(draw::save(&one, &dir.join("one")).unwrap());
    let empty = Chart::Hist(draw::HistChart {
        title: "none".into(),
        x_desc: "x".into(),
        note: String::new(),
        edges: vec![],
        counts: vec![],
        mean: None,
    });
    written.extend(draw::save(&empty, &dir.join("empty")).unwrap());
    for f in &written {
        let bytes = std::fs::read(f).unwrap();
        if f.extension().is_some_and(|e| e == "png") {
            assert_eq!(&bytes[1..4], b"PNG", "{}", f.display());
        } else {
            assert!(
                String::from_utf8_lossy(&bytes).contains("<svg"),
                "{}",
                f.display()
            );
        }
    }
    assert_eq!(sanitize("a b/c.d"), "a_b_c.d");
}

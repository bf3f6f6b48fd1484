//! `vitro solve pursuit`: the theory check through the command line, and bad input.

mod common;

use common::{repo, vitro};

fn pursuit(graph: &str, extra: &[&str]) -> (i32, String, String) {
    let path = repo().join("data/graphs").join(graph);
    let p = path.to_string_lossy().into_owned();
    let mut args = vec!["solve", "pursuit", &p];
    args.extend_from_slice(extra);
    vitro(&args)
}

#[test]
fn cop_number_pursuers_capture_one_fewer_do_not() {
    let common = [
        "--budget",
        "100",
        "--episodes",
        "4",
        "--turns",
        "20",
        "--seed",
        "3",
        "--json",
    ];
    for (graph, cops) in [("cycle5.edges", 2u64), ("tree_balanced_2_3.edges", 1)] {
        for k in [cops - 1, cops].into_iter().filter(|&k| k > 0) {
            let ks = k.to_string();
            let mut args = vec!["--pursuers", &ks];
            args.extend_from_slice(&common);
            let (code, out, err) = pursuit(graph, &args);
            assert_eq!(code, 0, "{graph}: {err}");
            let v: serde_json::Value = serde_json::from_str(&out).expect("JSON");
            let expect = if k == cops { 1.0 } else { 0.0 };
            assert_eq!(
                v["capture_rate"].as_f64(),
                Some(expect),
                "{graph}, {k}: {out}"
            );
            assert!(
                v["evader"].as_str().is_some_and(|e| e.starts_with("exact")),
                "{out}"
            );
            let ci = v["capture_rate_ci95"].as_array().expect("interval");
            assert!(
                ci[0].as_f64() <= Some(expect) && ci[1].as_f64() >= Some(expect),
                "{out}"
            );
        }
    }
}

#[test]
fn text_report_names_the_evader_and_the_interval() {
    let (code, out, err) = pursuit(
        "grid4x4.edges",
        &[
            "--pursuers",
            "2",
            "--visibility",
            "1",
            "--algorithm",
            "minimax",
            "--budget",
            "200",
            "--episodes",
            "2",
            "--turns",
            "10",
        ],
    );
    assert_eq!(code, 0, "{err}");
    assert!(out.contains("capture_rate "), "{out}");
    assert!(out.contains("95% CI"), "{out}");
    assert!(out.contains("evader: exact"), "{out}");
    assert!(out.contains("mean capture turn"), "{out}");
}

#[test]
fn bad_input_is_exit_2_with_a_place() {
    let (code, _, err) = pursuit(
        "cycle5.edges",
        &[
            "--pursuers",
            "0",
            "--budget",
            "1",
            "--episodes",
            "1",
            "--turns",
            "1",
        ],
    );
    assert_eq!(code, 2);
    assert!(err.contains("--pursuers"), "{err}");
    let tmp = std::env::temp_dir().join(format!("vitro-pursuit-{}.edges", std::process::id()));
    std::fs::write(&tmp, "0 1\n1 two\n").expect("temp file");
    let p = tmp.to_string_lossy().into_owned();
    let (code, _, err) = vitro(&[
        "solve",
        "pursuit",
        &p,
        "--pursuers",
        "1",
        "--budget",
        "1",
        "--episodes",
        "1",
        "--turns",
        "1",
    ]);
    let _ = std::fs::remove_file(&tmp);
    assert_eq!(code, 2);
    assert!(err.contains(&format!("{p}:2:3")), "{err}");
}

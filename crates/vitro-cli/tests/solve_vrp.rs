//! `vitro solve vrp`: the shipped instances through the command line, and bad input.

mod common;

use common::{repo, vitro};

fn instance(file: &str) -> String {
    repo()
        .join("data/vrp")
        .join(file)
        .to_string_lossy()
        .into_owned()
}

#[test]
fn a_n32_k5_is_solved_to_its_optimum_and_reports_the_gap() {
    let p = instance("A-n32-k5.vrp");
    let (code, out, err) = vitro(&["solve", "vrp", &p, "--json", "--seed", "1"]);
    assert_eq!(code, 0, "{err}");
    let v: serde_json::Value = serde_json::from_str(&out).expect("JSON");
    assert_eq!(v["cost"].as_f64(), Some(784.0), "{out}");
    assert_eq!(v["best_known"].as_f64(), Some(784.0));
    assert_eq!(v["gap_percent"].as_f64(), Some(0.0));
    assert_eq!(v["vehicles_used"].as_u64(), Some(5));
    assert_eq!(v["feasible"].as_bool(), Some(true));
    let served: usize = v["routes"]
        .as_array()
        .expect("routes")
        .iter()
        .map(|r| r.as_array().map_or(0, Vec::len))
        .sum();
    assert_eq!(served, 31);

    let (code, out, err) = vitro(&["solve", "vrp", &p, "--solver", "auction"]);
    assert_eq!(code, 0, "{err}");
    assert!(
        out.contains("auction, 31 rounds") && out.contains("messages"),
        "{out}"
    );
    assert!(out.contains("gap to best-known 784"), "{out}");
    assert_eq!(
        out.lines().filter(|l| l.starts_with("route ")).count(),
        5,
        "{out}"
    );
}

#[test]
fn solomon_c101_25_is_solved_with_its_windows() {
    let p = instance("C101-25.txt");
    let (code, out, err) = vitro(&[
        "solve",
        "vrp",
        &p,
        "--solver",
        "local-search",
        "--budget",
        "500",
        "--json",
    ]);
    assert_eq!(code, 0, "{err}");
    let v: serde_json::Value = serde_json::from_str(&out).expect("JSON");
    let cost = v["cost"].as_f64().expect("cost");
    assert!((cost - 191.81).abs() < 0.01, "{out}");
    assert_eq!(v["vehicles_used"].as_u64(), Some(3));
    let (code, out, _) = vitro(&["solve", "vrp", &p, "--solver", "savings"]);
    assert_eq!(code, 0);
    assert!(out.starts_with("C101: cost"), "{out}");
}

#[test]
fn bad_instances_are_bad_input_with_a_place() {
    let tmp = std::env::temp_dir().join(format!("vitro-vrp-{}.vrp", std::process::id()));
    std::fs::write(
        &tmp,
        "NAME : x\nDIMENSION : 2\nCAPACITY : 5\nNODE_COORD_SECTION\n1 0 0\n2 1 y\n",
    )
    .expect("temp file");
    let p = tmp.to_string_lossy().into_owned();
    let (code, _, err) = vitro(&["solve", "vrp", &p]);
    let _ = std::fs::remove_file(&tmp);
    assert_eq!(code, 2, "{err}");
    assert!(
        err.contains(&p) && err.contains("line 6, column 5") && err.contains("a y coordinate"),
        "{err}"
    );
    let (code, _, err) = vitro(&["solve", "vrp", "no/such.vrp"]);
    assert_eq!(code, 2);
    assert!(err.contains("no/such.vrp"), "{err}");
}

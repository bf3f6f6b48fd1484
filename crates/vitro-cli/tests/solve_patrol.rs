//! `vitro solve patrol`: values, JSON shape, time-dependent and phase-locked policies, the
//! village instance, located input errors.

use std::process::Command;

const DATA: &str = concat!(env!("CARGO_MANIFEST_DIR"), "/../../data/patrol");

fn vitro(args: &[&str]) -> std::process::Output {
    Command::new(env!("CARGO_BIN_EXE_vitro"))
        .args(args)
        .output()
        .expect("the vitro binary runs")
}

fn json(args: &[&str]) -> serde_json::Value {
    let out = vitro(args);
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    serde_json::from_slice(&out.stdout).expect("one JSON object")
}

#[test]
fn static_instance_reports_the_certified_optimum() {
    let file = format!("{DATA}/static.toml");
    let report = json(&["solve", "patrol", &file, "--json"]);
    let value = report["value"].as_f64().unwrap();
    assert!((value - (4.0 * 3f64.sqrt() - 6.0)).abs() < 1e-4, "{value}");
    assert_eq!(report["exact"], true);
    let policy = &report["policy"][0];
    assert_eq!(policy["phases"].as_array().unwrap().len(), 1);
    // Every row is a probability distribution.
    for row in policy["phases"][0].as_array().unwrap() {
        let sum: f64 = row
            .as_array()
            .unwrap()
            .iter()
            .map(|m| m[1].as_f64().unwrap())
            .sum();
        assert!((sum - 1.0).abs() < 1e-9);
    }
    let text = vitro(&["solve", "patrol", &file]);
    let text = String::from_utf8(text.stdout).unwrap();
    assert!(text.contains("certified optimal"), "{text}");
}

#[test]
fn time_dependent_policies_do_at_least_as_well_on_a_convoy() {
    let file = format!("{DATA}/convoy.toml");
    let stationary = json(&["solve", "patrol", &file, "--json"]);
    let timed = json(&["solve", "patrol", &file, "--json", "--time-dependent"]);
    let (s, t) = (
        stationary["value"].as_f64().unwrap(),
        timed["value"].as_f64().unwrap(),
    );
    assert!(t <= s + 1e-9, "{t} vs {s}");
    // Certified optima (see the file): (3 - sqrt 5) / 2 and 0.
    assert!((s - (3.0 - 5f64.sqrt()) / 2.0).abs() < 1e-4, "{s}");
    assert!(t < 1e-6, "{t}");
    assert_eq!(timed["exact"], true);
    assert_eq!(timed["period"], 2);
    assert_eq!(timed["policy"][0]["phases"].as_array().unwrap().len(), 2);
    assert_eq!(
        stationary["policy"][0]["phases"].as_array().unwrap().len(),
        1
    );
}

/// Every row of every phase of every policy is a probability distribution, or empty (a
/// phase-locked unit not there then); returns the number of non-empty rows.
fn check_rows(report: &serde_json::Value) -> usize {
    let mut rows = 0;
    for policy in report["policy"].as_array().unwrap() {
        for phase in policy["phases"].as_array().unwrap() {
            for row in phase.as_array().unwrap() {
                let moves = row.as_array().unwrap();
                if moves.is_empty() {
                    continue;
                }
                let sum: f64 = moves.iter().map(|m| m[1].as_f64().unwrap()).sum();
                assert!((sum - 1.0).abs() < 1e-9, "{row}");
                rows += 1;
            }
        }
    }
    rows
}

#[test]
fn phase_locked_policies_do_at_least_as_well() {
    let file = format!("{DATA}/convoy.toml");
    let timed = json(&["solve", "patrol", &file, "--json", "--time-dependent"]);
    let locked = json(&["solve", "patrol", &file, "--json", "--phase-locked"]);
    assert_eq!(locked["phase_locked"], true);
    assert_eq!(locked["time_dependent"], true);
    let (t, l) = (
        timed["value"].as_f64().unwrap(),
        locked["value"].as_f64().unwrap(),
    );
    assert!(l <= t + 1e-9, "{l} vs {t}");
    assert!(check_rows(&locked) > 0);
    let text = vitro(&["solve", "patrol", &file, "--phase-locked"]);
    let text = String::from_utf8(text.stdout).unwrap();
    assert!(
        text.contains("phase-locked time-dependent policy"),
        "{text}"
    );
}

#[test]
fn the_village_loads_and_plans_two_units() {
    // No LP iterations: the candidate tubes and their starting policies only (the full solve
    // is the release example `patrol_village`).
    let file = format!("{DATA}/village.toml");
    let report = json(&[
        "solve",
        "patrol",
        &file,
        "--json",
        "--phase-locked",
        "--iterations",
        "0",
        "--restarts",
        "0",
    ]);
    assert_eq!(report["period"], 48);
    assert_eq!(report["policy"].as_array().unwrap().len(), 2);
    let value = report["value"].as_f64().unwrap();
    assert!((0.0..=1.0).contains(&value), "{value}");
    assert!(check_rows(&report) > 48);
    assert_eq!(report["stats"]["lp"]["solves"], 0);
}

#[test]
fn bad_input_exits_2_with_a_location() {
    let dir = std::env::temp_dir().join(format!("vitro-solve-patrol-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let file = dir.join("bad.toml");
    std::fs::write(
        &file,
        "[graph]\nedges = [[0, 1]]\n[[target]]\nnode = 5\nvalue = 1\ndeadline = 2\n[[patroller]]\n",
    )
    .unwrap();
    let out = vitro(&["solve", "patrol", file.to_str().unwrap()]);
    assert_eq!(out.status.code(), Some(2));
    let stderr = String::from_utf8_lossy(&out.stderr);
    assert!(stderr.contains("bad.toml:4:8"), "{stderr}");
    let missing = vitro(&["solve", "patrol", dir.join("none.toml").to_str().unwrap()]);
    assert_eq!(missing.status.code(), Some(2));
    std::fs::remove_dir_all(&dir).unwrap();
}

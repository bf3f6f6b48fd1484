//! `vitro plan`: exit codes and output of the planning command.

mod common;

use common::vitro;

#[test]
fn optimal_json_gives_the_known_length() {
    let (code, out, err) = vitro(&[
        "plan",
        "data/planning/depot/domain.pddl",
        "data/planning/depot/p02.pddl",
        "--optimal",
        "--json",
    ]);
    assert_eq!(code, 0, "{err}");
    let v: serde_json::Value = serde_json::from_str(&out).expect("one JSON object");
    assert_eq!(v["length"], 15);
    assert_eq!(v["plan"].as_array().map(Vec::len), Some(15));
    assert!(v["expanded"].as_u64().is_some_and(|n| n > 0));
}

#[test]
fn plain_output_lists_the_steps_and_the_length() {
    let d = "crates/vitro-cli/tests/pddl/switch-domain.pddl";
    let (code, out, _) = vitro(&["plan", d, "crates/vitro-cli/tests/pddl/switch-easy.pddl"]);
    assert_eq!(code, 0);
    assert!(out.contains("1  (switch-on)"), "{out}");
    assert!(out.contains("plan length 1"), "{out}");
}

#[test]
fn no_plan_exits_4_and_bad_input_exits_2() {
    let d = "crates/vitro-cli/tests/pddl/switch-domain.pddl";
    let (code, _, err) = vitro(&[
        "plan",
        d,
        "crates/vitro-cli/tests/pddl/switch-unsolvable.pddl",
    ]);
    assert_eq!(code, 4, "{err}");
    assert!(err.contains("no plan"), "{err}");
    let (code, _, err) = vitro(&["plan", d, "README.md"]);
    assert_eq!(code, 2);
    assert!(err.contains("README.md:1:1"), "{err}");
    let (code, _, err) = vitro(&["plan", d, "no/such/file.pddl"]);
    assert_eq!(code, 2);
    assert!(err.contains("no/such/file.pddl"), "{err}");
}

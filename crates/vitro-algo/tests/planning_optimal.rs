//! The long optimal-planning runs: A* with LM-cut on dwr problem-02 (35 steps) and depot
//! p03 (27 steps). Seconds optimised, minutes not: the workspace optimises `vitro-algo` in
//! test builds too (`[profile.dev.package.vitro-algo]`), so they run with every other test.

use vitro_algo::planning::pddl::{parse_domain, parse_problem};
use vitro_algo::planning::validate::validate_plan;
use vitro_algo::planning::{PddlSource, Planner, solve};

const DATA: &str = concat!(env!("CARGO_MANIFEST_DIR"), "/../../data/planning/");

/// Solves `problem` optimally, validates the plan independently, returns its length.
fn optimal_length(domain: &str, problem: &str) -> usize {
    let read = |f: &str| {
        std::fs::read_to_string(format!("{DATA}{f}")).unwrap_or_else(|e| panic!("{f}: {e}"))
    };
    let (dt, pt) = (read(domain), read(problem));
    let result = solve(
        PddlSource::new(domain, &dt),
        PddlSource::new(problem, &pt),
        Planner::Optimal,
    )
    .expect("solvable");
    let d = parse_domain(&dt, domain).expect("domain");
    let p = parse_problem(&d, &pt, problem).expect("problem");
    validate_plan(&d, &p, &result.plan).expect("the optimal plan is valid");
    assert_eq!(result.length, result.plan.len());
    result.length
}

#[test]
fn dwr_problem_02_optimal_is_35() {
    assert_eq!(optimal_length("dwr/domain.pddl", "dwr/problem-02.pddl"), 35);
}

#[test]
fn depot_p03_optimal_is_27() {
    assert_eq!(optimal_length("depot/domain.pddl", "depot/p03.pddl"), 27);
}

#[test]
fn depot_p01_p02_optimal_are_10_and_15() {
    assert_eq!(optimal_length("depot/domain.pddl", "depot/p01.pddl"), 10);
    assert_eq!(optimal_length("depot/domain.pddl", "depot/p02.pddl"), 15);
}

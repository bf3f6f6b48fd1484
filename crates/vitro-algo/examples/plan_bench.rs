//! Times the optimal and satisficing planners on one PDDL problem.
//!
//! ```text
//! cargo run --release -p vitro-algo --example plan_bench -- \
//!     data/planning/dwr/domain.pddl data/planning/dwr/problem-02.pddl
//! ```
//!
//! Prints, per planner, the plan length, states expanded, wall time and expansions per
//! second, after checking the plan with the independent validator.

use std::path::Path;
use std::process::ExitCode;
use std::time::Instant;

use vitro_algo::planning::pddl::{parse_domain, parse_problem};
use vitro_algo::planning::validate::validate_plan;
use vitro_algo::planning::{Planner, solve_files};

fn main() -> ExitCode {
    let args: Vec<String> = std::env::args().skip(1).collect();
    let [domain, problem] = args.as_slice() else {
        eprintln!("usage: plan_bench DOMAIN.pddl PROBLEM.pddl");
        return ExitCode::from(2);
    };
    match run(Path::new(domain), Path::new(problem)) {
        Ok(()) => ExitCode::SUCCESS,
        Err(e) => {
            eprintln!("error: {e}");
            ExitCode::FAILURE
        }
    }
}

fn run(domain: &Path, problem: &Path) -> Result<(), Box<dyn std::error::Error>> {
    println!("problem: {}", problem.display());
    let d = parse_domain(
        &std::fs::read_to_string(domain)?,
        &domain.display().to_string(),
    )?;
    let p = parse_problem(
        &d,
        &std::fs::read_to_string(problem)?,
        &problem.display().to_string(),
    )?;
    for planner in [Planner::Optimal, Planner::Satisficing] {
        let start = Instant::now();
        let result = solve_files(domain, problem, planner)?;
        let secs = start.elapsed().as_secs_f64();
        validate_plan(&d, &p, &result.plan)?;
        println!("{planner}:");
        println!(
            "  ground task: {} facts, {} actions; initial h = {}",
            result.facts, result.actions, result.initial_h
        );
        println!("  plan length: {} (validated)", result.length);
        println!(
            "  expanded: {}  generated: {}  evaluated: {}",
            result.expanded, result.generated, result.evaluated
        );
        println!("  wall time: {secs:.3} s");
        println!(
            "  expanded/s: {:.0}",
            result.expanded as f64 / secs.max(1e-9)
        );
    }
    Ok(())
}

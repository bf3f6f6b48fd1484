//! `vitro plan DOMAIN PROBLEM [--optimal] [--json]`: classical planning on PDDL files.

use crate::Failure;
use anyhow::anyhow;
use clap::Args;
use serde::Serialize;
use std::path::PathBuf;
use std::time::Instant;
use vitro_algo::planning::{PlanError, Planner, solve_files};

#[derive(Debug, Args)]
pub(crate) struct PlanArgs {
    /// The PDDL domain file (STRIPS with typing).
    domain: PathBuf,
    /// The PDDL problem file.
    problem: PathBuf,
    /// A shortest plan (A* with LM-cut) instead of a fast one (greedy best-first with FF).
    #[arg(long)]
    optimal: bool,
    /// Prints one JSON object on stdout.
    #[arg(long)]
    json: bool,
}

/// What `vitro plan --json` prints.
#[derive(Serialize)]
struct PlanReport<'a> {
    planner: &'a str,
    length: usize,
    plan: &'a [String],
    expanded: u64,
    generated: u64,
    facts: usize,
    actions: usize,
    wall_time_s: f64,
}

pub(crate) fn plan(args: &PlanArgs) -> Result<(), Failure> {
    let planner = if args.optimal {
        Planner::Optimal
    } else {
        Planner::Satisficing
    };
    vitro_tools::input_file(&args.domain)?;
    vitro_tools::input_file(&args.problem)?;
    let started = Instant::now();
    let result = solve_files(&args.domain, &args.problem, planner).map_err(|e| match e {
        PlanError::Io { .. } | PlanError::Parse(_) => Failure::Input(e.into()),
        PlanError::Ground(_) | PlanError::Unsolvable { .. } => Failure::Check(e.into()),
    })?;
    let wall = started.elapsed().as_secs_f64();
    let name = planner.to_string();
    if args.json {
        let report = PlanReport {
            planner: &name,
            length: result.length,
            plan: &result.plan,
            expanded: result.expanded,
            generated: result.generated,
            facts: result.facts,
            actions: result.actions,
            wall_time_s: wall,
        };
        let line = serde_json::to_string(&report).map_err(|e| Failure::Runtime(anyhow!(e)))?;
        println!("{line}");
    } else {
        for (i, step) in result.plan.iter().enumerate() {
            println!("{:>4}  {step}", i + 1);
        }
        println!(
            "plan length {} ({name}; {} states expanded, {} facts, {} ground actions, {wall:.3} s)",
            result.length, result.expanded, result.facts, result.actions
        );
    }
    Ok(())
}

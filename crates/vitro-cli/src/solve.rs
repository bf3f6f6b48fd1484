//! `vitro solve ...`: the game-theoretic solvers of `vitro-algo`.

use crate::Failure;
use crate::graph_file::load_graph;
use anyhow::anyhow;
use clap::{Args, Subcommand};
use serde::Serialize;
use std::path::{Path, PathBuf};
use std::time::Instant;
use vitro_algo::cops::{CopOptions, CopsError, Decision, cop_number};
use vitro_algo::patrol::{self, Instance, PatrolError, Policy, SolveOptions};

#[derive(Debug, Subcommand)]
pub(crate) enum SolveCommand {
    /// The cop number of a graph (cops and robber, full visibility), computed exactly.
    Cops(CopsArgs),
    /// The best randomised patrol of a patrolling game (static or moving targets).
    Patrol(PatrolArgs),
    /// Pursuit–evasion as a game: the pursuers' search against a smart evader, over many
    /// episodes (capture rate with its 95% interval).
    Pursuit(crate::solve_pursuit::PursuitArgs),
    /// A capacitated vehicle routing problem, with time windows (CVRPLIB or Solomon text).
    Vrp(crate::solve_vrp::VrpArgs),
}

#[derive(Debug, Args)]
pub(crate) struct PatrolArgs {
    /// The instance (TOML: `[graph]`, `[[target]]`, `[[patroller]]`).
    instance: PathBuf,
    /// Prints one JSON object on stdout.
    #[arg(long)]
    json: bool,
    /// Optimises time-dependent policies (one transition matrix per schedule phase).
    #[arg(long)]
    time_dependent: bool,
    /// Also searches phase-locked time-dependent policies (units that keep near the convoys
    /// they guard, attacked only where they can be); implies --time-dependent.
    #[arg(long)]
    phase_locked: bool,
    /// LP iterations per local search.
    #[arg(long, default_value_t = SolveOptions::default().local_iterations)]
    iterations: usize,
    /// Random restarts of each team local search.
    #[arg(long, default_value_t = SolveOptions::default().restarts)]
    restarts: usize,
    /// Seed of the random restarts.
    #[arg(long, default_value_t = 0)]
    seed: u64,
}

#[derive(Debug, Args)]
pub(crate) struct CopsArgs {
    /// The graph as an edge list: one `u v` pair per line, `#` comments.
    graph: PathBuf,
    /// Prints one JSON object on stdout.
    #[arg(long)]
    json: bool,
}

pub(crate) fn solve(cmd: &SolveCommand) -> Result<(), Failure> {
    match cmd {
        SolveCommand::Cops(args) => cops(args),
        SolveCommand::Patrol(args) => patrol(args),
        SolveCommand::Pursuit(args) => crate::solve_pursuit::pursuit(args),
        SolveCommand::Vrp(args) => crate::solve_vrp::vrp(args),
    }
}

#[derive(Serialize)]
struct CopsReport {
    cop_number: usize,
    nodes: usize,
    edges: usize,
    components: Vec<ComponentReport>,
    states_explored: u64,
    wall_time_s: f64,
}

#[derive(Serialize)]
struct ComponentReport {
    nodes: usize,
    cop_number: usize,
    decided_by: &'static str,
    capture_time: u32,
}

fn cops(args: &CopsArgs) -> Result<(), Failure> {
    let graph = load_graph(&args.graph)?;
    let started = Instant::now();
    let result = cop_number(&graph, &CopOptions::default()).map_err(|e| match e {
        CopsError::TooManyStates { .. } => Failure::Runtime(e.into()),
        other => Failure::Input(other.into()),
    })?;
    let report = CopsReport {
        cop_number: result.cop_number,
        nodes: graph.node_count(),
        edges: graph.edge_count(),
        components: result
            .components
            .iter()
            .map(|c| ComponentReport {
                nodes: c.nodes.len(),
                cop_number: c.cop_number,
                decided_by: match c.decided_by {
                    Decision::DominatingSet => "dominating set",
                    Decision::Retrograde => "retrograde analysis",
                },
                capture_time: c.capture_time,
            })
            .collect(),
        states_explored: result.states_explored,
        wall_time_s: started.elapsed().as_secs_f64(),
    };
    if args.json {
        let line = serde_json::to_string(&report).map_err(|e| Failure::Runtime(anyhow!(e)))?;
        println!("{line}");
    } else {
        println!(
            "cop number {} ({} nodes, {} edges, {} component(s); {} positions solved in {:.3} s)",
            report.cop_number,
            report.nodes,
            report.edges,
            report.components.len(),
            report.states_explored,
            report.wall_time_s
        );
        for (i, c) in report.components.iter().enumerate() {
            println!(
                "  component {i}: {} nodes, {} cop(s) by {}, capture in {} cop moves",
                c.nodes, c.cop_number, c.decided_by, c.capture_time
            );
        }
    }
    Ok(())
}

#[derive(Serialize)]
struct PatrolReport {
    /// The attacker's best expected gain against the policies.
    value: f64,
    /// The smallest capture probability over all attacks.
    capture_probability: f64,
    lower_bound: f64,
    exact: bool,
    time_dependent: bool,
    /// Whether phase-locked policies were searched.
    phase_locked: bool,
    period: usize,
    /// Per patroller: per phase, per vertex, the next-vertex probabilities.
    policy: Vec<PolicyReport>,
    stats: patrol::SolveStats,
    wall_time_s: f64,
}

#[derive(Serialize)]
struct PolicyReport {
    patroller: String,
    support: Vec<usize>,
    /// `phases[φ][i]`: the moves from `support[i]` at phase `φ` as `[next, probability]`;
    /// empty where a phase-locked unit is never at that vertex at that phase.
    phases: Vec<Vec<Vec<(usize, f64)>>>,
}

fn policy_report(name: &str, policy: &Policy) -> PolicyReport {
    let phases = (0..policy.phases())
        .map(|phase| {
            policy
                .support()
                .iter()
                .map(|&v| {
                    policy
                        .moves_at(v, phase)
                        .map(<[_]>::to_vec)
                        .unwrap_or_default()
                })
                .collect()
        })
        .collect();
    PolicyReport {
        patroller: name.to_string(),
        support: policy.support().to_vec(),
        phases,
    }
}

fn patrol_failure(path: &Path, e: PatrolError) -> Failure {
    match e {
        PatrolError::Parse {
            line,
            column,
            message,
        } => Failure::Input(anyhow!("{}:{line}:{column}: {message}", path.display())),
        PatrolError::Lp(_) => Failure::Runtime(anyhow!("{}: {e}", path.display())),
        PatrolError::Io { .. } => Failure::Input(e.into()),
        other => Failure::Input(anyhow!("{}: {other}", path.display())),
    }
}

fn patrol(args: &PatrolArgs) -> Result<(), Failure> {
    let path = &args.instance;
    vitro_tools::input_file(path)?;
    let instance = Instance::load(path).map_err(|e| patrol_failure(path, e))?;
    let period = instance.period().map_err(|e| patrol_failure(path, e))?;
    let options = SolveOptions {
        time_dependent: args.time_dependent || args.phase_locked,
        phase_locked: args.phase_locked,
        local_iterations: args.iterations,
        restarts: args.restarts,
        seed: args.seed,
        ..SolveOptions::default()
    };
    let started = Instant::now();
    let solution = patrol::solve_with(&instance, &options).map_err(|e| patrol_failure(path, e))?;
    let report = PatrolReport {
        value: solution.value,
        capture_probability: solution.capture_probability,
        lower_bound: solution.lower_bound,
        exact: solution.exact,
        time_dependent: options.time_dependent && period > 1,
        phase_locked: args.phase_locked && period > 1,
        period,
        policy: instance
            .patrollers
            .iter()
            .zip(&solution.policies)
            .map(|(p, policy)| policy_report(&p.name, policy))
            .collect(),
        stats: solution.stats,
        wall_time_s: started.elapsed().as_secs_f64(),
    };
    if args.json {
        let line = serde_json::to_string(&report).map_err(|e| Failure::Runtime(anyhow!(e)))?;
        println!("{line}");
        return Ok(());
    }
    println!(
        "value {:.6} (attacker's expected gain), capture probability {:.6}, {} (lower bound {:.6}); {} policy, period {period}, {:.3} s",
        report.value,
        report.capture_probability,
        if report.exact {
            "certified optimal"
        } else {
            "not certified"
        },
        report.lower_bound,
        match (report.phase_locked, report.time_dependent) {
            (true, _) => "phase-locked time-dependent",
            (false, true) => "time-dependent",
            (false, false) => "stationary",
        },
        report.wall_time_s
    );
    for p in &report.policy {
        println!("{}:", p.patroller);
        for (phase, rows) in p.phases.iter().enumerate() {
            if p.phases.len() > 1 {
                println!("  phase {phase}:");
            }
            for (v, row) in p
                .support
                .iter()
                .zip(rows)
                .filter(|(_, row)| !row.is_empty())
            {
                let moves: Vec<String> = row.iter().map(|(w, q)| format!("{w}: {q:.4}")).collect();
                println!("    {v} -> {}", moves.join(", "));
            }
        }
    }
    Ok(())
}

//! `vitro solve ...`: the game-theoretic solvers of `vitro-algo`.

use crate::Failure;
use anyhow::anyhow;
use clap::{Args, Subcommand};
use serde::Serialize;
use std::path::{Path, PathBuf};
use std::time::Instant;
use vitro_algo::cops::{CopOptions, CopsError, Decision, cop_number};
use vitro_algo::graph::{Graph, GraphError};

#[derive(Debug, Subcommand)]
pub(crate) enum SolveCommand {
    /// The cop number of a graph (cops and robber, full visibility), computed exactly.
    Cops(CopsArgs),
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
    }
}

/// Loads an edge list; errors name the file, line and column.
fn load_graph(path: &Path) -> Result<Graph, Failure> {
    Graph::load(path).map_err(|e| match e {
        GraphError::Parse {
            line,
            column,
            message,
        } => Failure::Input(anyhow!("{}:{line}:{column}: {message}", path.display())),
        other => Failure::Input(anyhow!("{}: {other}", path.display())),
    })
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

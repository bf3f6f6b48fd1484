//! `vitro solve pursuit`: pursuit–evasion as a game (the pursuers' search against a smart,
//! omniscient evader), evaluated over many episodes.

use crate::Failure;
use anyhow::anyhow;
use clap::{Args, ValueEnum};
use serde::Serialize;
use std::path::PathBuf;
use std::time::Instant;
use vitro_algo::pursuit::game::{
    ExactEvader, FleeingHider, GameEvader, MoIsmcts, MoIsmctsConfig, TeamStrategy,
    WorstCaseMinimax, WorstCaseMinimaxConfig, evaluate,
};
use vitro_algo::pursuit::{Arena, Budget, FullVisibility, HopRange, PursuitError};

/// The pursuers' search.
#[derive(Clone, Copy, Debug, PartialEq, Eq, ValueEnum)]
pub(crate) enum Algorithm {
    /// Multiple-observer information-set MCTS (budget: iterations per move).
    Mcts,
    /// Worst-case alpha-beta over information states (budget: expanded nodes per move).
    Minimax,
}

/// The evader.
#[derive(Clone, Copy, Debug, PartialEq, Eq, ValueEnum)]
pub(crate) enum EvaderKind {
    /// The solved cops-and-robber strategy, hiding when it can (omniscient); the greedy
    /// hider where the table would be too large.
    Exact,
    /// The same MO-ISMCTS on the evader's side, with the same budget.
    Mcts,
    /// Omniscient greedy: out of sight, then far from the pursuers.
    Flee,
}

#[derive(Debug, Args)]
pub(crate) struct PursuitArgs {
    /// The graph as an edge list: one `u v` pair per line, `#` comments.
    graph: PathBuf,
    /// Number of pursuers.
    #[arg(long)]
    pursuers: usize,
    /// The pursuers see the evader within this many edges of one of them (left out: always).
    #[arg(long)]
    visibility: Option<usize>,
    /// The pursuers' search.
    #[arg(long, value_enum, default_value_t = Algorithm::Mcts)]
    algorithm: Algorithm,
    /// The evader.
    #[arg(long, value_enum, default_value_t = EvaderKind::Exact)]
    evader: EvaderKind,
    /// Search budget per move (MCTS iterations or minimax nodes).
    #[arg(long)]
    budget: u64,
    /// Episodes to play.
    #[arg(long)]
    episodes: usize,
    /// Rounds per episode (each: the pursuers move, then the evader).
    #[arg(long)]
    turns: u32,
    /// Master seed (episode `i` uses stream `i` of it).
    #[arg(long, default_value_t = 0)]
    seed: u64,
    /// Prints one JSON object on stdout.
    #[arg(long)]
    json: bool,
}

#[derive(Serialize)]
struct PursuitReport {
    graph: String,
    nodes: usize,
    edges: usize,
    pursuers: usize,
    visibility_hops: Option<usize>,
    algorithm: String,
    budget: u64,
    evader: String,
    episodes: usize,
    turns: u32,
    seed: u64,
    captures: usize,
    capture_rate: f64,
    capture_rate_ci95: (f64, f64),
    mean_capture_turn: Option<f64>,
    mean_in_sight: f64,
    wall_time_s: f64,
}

fn positive(name: &str, value: u64) -> Result<(), Failure> {
    if value == 0 {
        Err(Failure::Input(anyhow!("--{name} must be at least 1")))
    } else {
        Ok(())
    }
}

pub(crate) fn pursuit(args: &PursuitArgs) -> Result<(), Failure> {
    positive("pursuers", args.pursuers as u64)?;
    positive("budget", args.budget)?;
    positive("episodes", args.episodes as u64)?;
    positive("turns", u64::from(args.turns))?;
    let graph = crate::graph_file::load_graph(&args.graph)?;
    let place = args.graph.display().to_string();
    let arena = match args.visibility {
        Some(h) => Arena::new(graph.clone(), &HopRange::new(&graph, h)),
        None => Arena::new(graph.clone(), &FullVisibility),
    }
    .map_err(|e: PursuitError| Failure::Input(anyhow!("{place}: {e}")))?;
    let budget = Budget::iterations(args.budget);
    let k = args.pursuers;
    let mut team = || -> Box<dyn TeamStrategy> {
        match args.algorithm {
            Algorithm::Mcts => Box::new(MoIsmcts::new(MoIsmctsConfig {
                budget,
                ..MoIsmctsConfig::default()
            })),
            Algorithm::Minimax => Box::new(WorstCaseMinimax::new(WorstCaseMinimaxConfig {
                budget,
                ..WorstCaseMinimaxConfig::default()
            })),
        }
    };
    let exact = match args.evader {
        EvaderKind::Exact => ExactEvader::new(&arena, k).ok(),
        _ => None,
    };
    let mut evader = || -> Box<dyn GameEvader> {
        match (args.evader, &exact) {
            (EvaderKind::Exact, Some(e)) => Box::new(e.clone()),
            (EvaderKind::Mcts, _) => Box::new(MoIsmcts::new(MoIsmctsConfig {
                budget,
                ..MoIsmctsConfig::default()
            })),
            _ => Box::new(FleeingHider),
        }
    };
    let algorithm = team().name();
    let evader_name = evader().name();
    let started = Instant::now();
    let summary = evaluate(
        &arena,
        k,
        args.episodes,
        args.turns,
        args.seed,
        &mut team,
        &mut evader,
    )
    .map_err(|e| Failure::Runtime(anyhow!("{place}: {e}")))?;
    let report = PursuitReport {
        graph: place,
        nodes: graph.node_count(),
        edges: graph.edge_count(),
        pursuers: k,
        visibility_hops: args.visibility,
        algorithm,
        budget: args.budget,
        evader: evader_name,
        episodes: summary.episodes,
        turns: args.turns,
        seed: args.seed,
        captures: summary.captures,
        capture_rate: summary.capture_rate,
        capture_rate_ci95: summary.capture_rate_ci95,
        mean_capture_turn: summary.mean_capture_round,
        mean_in_sight: summary.mean_in_sight,
        wall_time_s: started.elapsed().as_secs_f64(),
    };
    if args.json {
        let line = serde_json::to_string(&report).map_err(|e| Failure::Runtime(anyhow!(e)))?;
        println!("{line}");
        return Ok(());
    }
    println!(
        "{} ({} nodes, {} edges), visibility {}",
        report.graph,
        report.nodes,
        report.edges,
        match report.visibility_hops {
            Some(h) => format!("within {h} hop(s)"),
            None => "full".into(),
        }
    );
    println!("pursuers: {k} x {}", report.algorithm);
    println!("evader: {}", report.evader);
    println!(
        "capture_rate {:.3} (95% CI {:.3}-{:.3}; {}/{} episodes of {} turns, seed {})",
        report.capture_rate,
        report.capture_rate_ci95.0,
        report.capture_rate_ci95.1,
        report.captures,
        report.episodes,
        report.turns,
        report.seed
    );
    match report.mean_capture_turn {
        Some(t) => println!("mean capture turn {t:.2}"),
        None => println!("mean capture turn - (no capture)"),
    }
    println!(
        "evader in sight {:.1}% of turns; {:.2} s",
        100.0 * report.mean_in_sight,
        report.wall_time_s
    );
    Ok(())
}

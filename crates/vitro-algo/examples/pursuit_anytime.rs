//! Anytime evidence for pursuit as a game: capture rate against search budget, with 95 %
//! intervals, for both searches of [`vitro_algo::pursuit::game`] against the exact
//! (omniscient, hiding) evader, where the pursuers see only part of the board.
//!
//! `cargo run --release -p vitro-algo --example pursuit_anytime [EPISODES [HOPS [PURSUERS [MINIMAX_EPISODES]]]]`
//!
//! Setting (constants below): the 8 x 8 grid (`data/graphs/grid8x8.edges`, cop number 2),
//! PURSUERS pursuers (default 2) who see the evader only within HOPS hops (default 2), 40
//! rounds, EPISODES episodes per MO-ISMCTS point (default 100; MINIMAX_EPISODES, default
//! 30, per minimax point: it is ten times slower), seed 0: episode `i` uses stream `i` (random distinct pursuer starts; the
//! evader then places itself). Budgets B = 10 ... 3000: MO-ISMCTS gets B iterations per
//! move, the worst-case minimax `3 * B` expanded nodes. Prints the table and writes
//! `docs/pursuit_anytime.png`.

use plotters::prelude::*;
use plotters::style::{FontStyle, register_font};
use std::path::Path;
use std::time::Instant;
use vitro_algo::graph::Graph;
use vitro_algo::pursuit::game::{
    EvalSummary, ExactEvader, MoIsmcts, MoIsmctsConfig, WorstCaseMinimax, WorstCaseMinimaxConfig,
    evaluate,
};
use vitro_algo::pursuit::{Arena, Budget, HopRange};

static FONT: &[u8] = include_bytes!("../../../assets/fonts/DejaVuSans.ttf");
const ROOT: &str = concat!(env!("CARGO_MANIFEST_DIR"), "/../..");
const GRAPH: &str = "data/graphs/grid8x8.edges";
const ROUNDS: u32 = 40;
const SEED: u64 = 0;
const BUDGETS: [u64; 6] = [10, 30, 100, 300, 1000, 3000];
const NODES_PER_ITERATION: u64 = 3;

type Curve = (String, Vec<(u64, EvalSummary)>);

fn run(
    arena: &Arena,
    pursuers: usize,
    mcts: bool,
    b: u64,
    episodes: usize,
) -> Result<EvalSummary, String> {
    let exact = ExactEvader::new(arena, pursuers).map_err(|e| e.to_string())?;
    let mut team = || -> Box<dyn vitro_algo::pursuit::game::TeamStrategy> {
        if mcts {
            Box::new(MoIsmcts::new(MoIsmctsConfig {
                budget: Budget::iterations(b),
                ..MoIsmctsConfig::default()
            }))
        } else {
            Box::new(WorstCaseMinimax::new(WorstCaseMinimaxConfig {
                budget: Budget::iterations(b * NODES_PER_ITERATION),
                ..WorstCaseMinimaxConfig::default()
            }))
        }
    };
    evaluate(
        arena,
        pursuers,
        episodes,
        ROUNDS,
        SEED,
        &mut team,
        &mut || Box::new(exact.clone()),
    )
    .map_err(|e| e.to_string())
}

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let arg = |i: usize, default: usize| -> Result<usize, std::num::ParseIntError> {
        std::env::args().nth(i).map_or(Ok(default), |s| s.parse())
    };
    let (episodes, hops, pursuers) = (arg(1, 100)?, arg(2, 2)?, arg(3, 2)?);
    let minimax_episodes = arg(4, 30)?;
    let graph = Graph::load(format!("{ROOT}/{GRAPH}"))?;
    let arena = Arena::new(graph.clone(), &HopRange::new(&graph, hops))?;
    println!(
        "{GRAPH}: {} nodes, {} edges; {pursuers} pursuers seeing {hops} hop(s); {ROUNDS} rounds; {episodes} (MO-ISMCTS) and {minimax_episodes} (minimax) episodes per point; seed {SEED}",
        arena.node_count(),
        graph.edge_count()
    );
    println!("evader: exact (omniscient; solved cops-and-robber table, then hiding)\n");
    let mut curves: Vec<Curve> = Vec::new();
    for (name, mcts) in [
        ("MO-ISMCTS (B iterations)".to_string(), true),
        (
            format!("worst-case minimax (3·B nodes; {minimax_episodes} episodes)"),
            false,
        ),
    ] {
        let episodes = if mcts { episodes } else { minimax_episodes };
        if episodes == 0 {
            continue;
        }
        let t0 = Instant::now();
        // The budgets run two at a time (one per core); each point is deterministic.
        let mut points: Vec<(u64, EvalSummary)> = Vec::new();
        for pair in BUDGETS.chunks(2) {
            let results: Vec<Result<EvalSummary, String>> = std::thread::scope(|s| {
                let handles: Vec<_> = pair
                    .iter()
                    .map(|&b| {
                        let arena = &arena;
                        s.spawn(move || run(arena, pursuers, mcts, b, episodes))
                    })
                    .collect();
                handles
                    .into_iter()
                    .map(|h| h.join().unwrap_or_else(|_| Err("a worker panicked".into())))
                    .collect()
            });
            for (&b, r) in pair.iter().zip(results) {
                points.push((b, r?));
            }
        }
        println!("{name}   ({:.0} s)", t0.elapsed().as_secs_f64());
        println!(
            "  {:>6} | {:>8} | {:>15} | {:>12} | {:>9}",
            "B", "capture", "95% CI", "mean turn", "in sight"
        );
        for (b, s) in &points {
            println!(
                "  {b:>6} | {:>8.3} | {:>6.3} - {:>6.3} | {:>12} | {:>8.1}%",
                s.capture_rate,
                s.capture_rate_ci95.0,
                s.capture_rate_ci95.1,
                s.mean_capture_round
                    .map_or("-".into(), |t| format!("{t:.1}")),
                100.0 * s.mean_in_sight
            );
        }
        curves.push((name, points));
    }
    plot(
        Path::new(&format!("{ROOT}/docs/pursuit_anytime.png")),
        &curves,
        episodes,
        hops,
        pursuers,
    )?;
    println!("\nwrote docs/pursuit_anytime.png");
    Ok(())
}

fn plot(
    path: &Path,
    curves: &[Curve],
    episodes: usize,
    hops: usize,
    pursuers: usize,
) -> Result<(), Box<dyn std::error::Error>> {
    register_font("sans-serif", FontStyle::Normal, FONT)
        .map_err(|_| "the embedded font could not be loaded")?;
    let root = BitMapBackend::new(path, (960, 600)).into_drawing_area();
    root.fill(&WHITE)?;
    let mut chart = ChartBuilder::on(&root)
        .caption(
            format!("8x8 grid, {pursuers} pursuers seeing {hops} hop(s), exact hiding evader: capture rate vs budget (95% CI; MO-ISMCTS {episodes} episodes)"),
            ("sans-serif", 18),
        )
        .margin(20)
        .x_label_area_size(50)
        .y_label_area_size(60)
        .build_cartesian_2d((7f64..4200f64).log_scale(), 0f64..1.05f64)?;
    chart
        .configure_mesh()
        .x_desc(format!(
            "budget B per move (MO-ISMCTS: B iterations; minimax: {NODES_PER_ITERATION}·B nodes)"
        ))
        .y_desc(format!("capture rate within {ROUNDS} rounds"))
        .x_label_formatter(&|v| format!("{v:.0}"))
        .y_label_formatter(&|v| format!("{v:.1}"))
        .label_style(("sans-serif", 15))
        .axis_desc_style(("sans-serif", 17))
        .draw()?;
    let colours = [RED, BLUE];
    for (i, (name, points)) in curves.iter().enumerate() {
        let colour = colours[i % colours.len()];
        // Offset the two curves a little sideways so the intervals do not overlap.
        let shift = if i == 0 { 0.97 } else { 1.03 };
        let xy: Vec<(f64, f64)> = points
            .iter()
            .map(|(b, s)| (*b as f64 * shift, s.capture_rate))
            .collect();
        chart
            .draw_series(LineSeries::new(xy.clone(), colour.stroke_width(3)))?
            .label(name.clone())
            .legend(move |(x, y)| {
                PathElement::new(vec![(x, y), (x + 24, y)], colour.stroke_width(3))
            });
        // The 95 % intervals: a vertical bar with caps (a twentieth of a decade wide).
        for (b, s) in points {
            let x = *b as f64 * shift;
            let (lo, hi) = s.capture_rate_ci95;
            let (l, r) = (x / 1.06, x * 1.06);
            for seg in [
                vec![(x, lo), (x, hi)],
                vec![(l, lo), (r, lo)],
                vec![(l, hi), (r, hi)],
            ] {
                chart.draw_series(std::iter::once(PathElement::new(
                    seg,
                    colour.stroke_width(2),
                )))?;
            }
        }
        chart.draw_series(xy.iter().map(|&p| Circle::new(p, 5, colour.filled())))?;
    }
    chart
        .configure_series_labels()
        .position(SeriesLabelPosition::UpperLeft)
        .label_font(("sans-serif", 16))
        .background_style(WHITE.mix(0.9))
        .border_style(BLACK)
        .draw()?;
    root.present()?;
    Ok(())
}

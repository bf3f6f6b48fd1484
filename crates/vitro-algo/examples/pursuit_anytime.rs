//! Anytime pursuit–evasion on the real town: pursuer success against budget, and a table of
//! the algorithms against each other and the baselines.
//!
//! `cargo run --release -p vitro-algo --example pursuit_anytime [EPISODES]`
//!
//! The board is Kotka's walking graph (largest component) with line of sight between
//! junctions (eye height 1.7 m, range 250 m, over buildings, bridges and terrain), exported
//! once from vitro-tactical into `data/town/kotka_walk.{edges,vis,pos}` (see
//! `data/town/kotka_walk.md`). 3 pursuers, horizon 200 turns, a fixed seed set: episode `i`
//! uses seed `i` for the random start (pursuers anywhere, the evader at least 15 hops from
//! each, or as far as possible) and for the players. Budgets: MCTS gets `B` iterations per
//! move; minimax gets `30 * B` expanded nodes (one MCTS iteration simulates up to 30 turns),
//! so a point compares roughly equal work. Writes `docs/pursuit_anytime.png`.

use plotters::prelude::*;
use plotters::style::{FontStyle, register_font};
use rand::{Rng, SeedableRng};
use rand_chacha::ChaCha8Rng;
use std::path::Path;
use std::time::Instant;
use vitro_algo::graph::{Graph, NodeId};
use vitro_algo::pursuit::{
    Arena, Budget, EvaderStrategy, FleeingEvader, GreedyPursuers, Mcts, MctsConfig, Minimax,
    MinimaxConfig, PursuerStrategy, RandomEvader, RandomPursuers, VisibilityGraph, play,
};

static FONT: &[u8] = include_bytes!("../../../assets/fonts/DejaVuSans.ttf");
const ROOT: &str = concat!(env!("CARGO_MANIFEST_DIR"), "/../..");
const PURSUERS: usize = 3;
const HORIZON: u32 = 200;
const BUDGETS: [u64; 5] = [10, 30, 100, 300, 1000];
const NODES_PER_ITERATION: u64 = 30;
/// The budget of the head-to-head table.
const TABLE_BUDGET: u64 = 100;

#[derive(Clone, Copy, Debug, PartialEq)]
enum Player {
    Random,
    Greedy,
    Mcts(u64),
    Minimax(u64),
}

impl Player {
    fn name(self) -> String {
        match self {
            Player::Random => "random".into(),
            Player::Greedy => "greedy".into(),
            Player::Mcts(b) => format!("MCTS {b}"),
            Player::Minimax(b) => format!("minimax {}", b * NODES_PER_ITERATION),
        }
    }

    fn pursuers(self) -> Box<dyn PursuerStrategy> {
        match self {
            Player::Random => Box::new(RandomPursuers),
            Player::Greedy => Box::new(GreedyPursuers),
            Player::Mcts(b) => Box::new(mcts(b)),
            Player::Minimax(b) => Box::new(minimax(b)),
        }
    }

    fn evader(self) -> Box<dyn EvaderStrategy> {
        match self {
            Player::Random => Box::new(RandomEvader),
            Player::Greedy => Box::new(FleeingEvader),
            Player::Mcts(b) => Box::new(mcts(b)),
            Player::Minimax(b) => Box::new(minimax(b)),
        }
    }
}

fn mcts(b: u64) -> Mcts {
    Mcts::new(MctsConfig {
        budget: Budget::iterations(b),
        ..MctsConfig::default()
    })
}

fn minimax(b: u64) -> Minimax {
    Minimax::new(MinimaxConfig {
        budget: Budget::iterations(b * NODES_PER_ITERATION),
        ..MinimaxConfig::default()
    })
}

/// Builds the (pursuers, evader) pair of a curve at a budget.
type Matchup = fn(u64) -> (Player, Player);

/// Capture rate and mean capture time (over captures) of one matchup.
#[derive(Clone, Copy, Debug)]
struct Cell {
    rate: f64,
    mean_time: Option<f64>,
}

fn start(arena: &Arena, rng: &mut ChaCha8Rng) -> (Vec<NodeId>, NodeId) {
    let n = arena.node_count();
    let pursuers: Vec<NodeId> = (0..PURSUERS).map(|_| rng.random_range(0..n)).collect();
    // The evader starts at least 15 hops from every pursuer (or as far as the graph allows).
    let gap = |v: NodeId| {
        pursuers
            .iter()
            .map(|&p| arena.dist(p, v))
            .min()
            .unwrap_or(0)
    };
    let threshold = (0..n).map(gap).max().unwrap_or(0).min(15);
    let candidates: Vec<NodeId> = (0..n).filter(|&v| gap(v) >= threshold).collect();
    let evader = candidates[rng.random_range(0..candidates.len())];
    (pursuers, evader)
}

fn matchup(
    arena: &Arena,
    p: Player,
    e: Player,
    episodes: u64,
) -> Result<Cell, vitro_algo::pursuit::PursuitError> {
    let threads = std::thread::available_parallelism().map_or(1, |n| n.get()) as u64;
    let times: Vec<Option<u32>> = std::thread::scope(|scope| {
        let handles: Vec<_> = (0..threads)
            .map(|t| {
                scope.spawn(move || {
                    (t..episodes)
                        .step_by(threads as usize)
                        .map(|seed| {
                            let mut rng = ChaCha8Rng::seed_from_u64(seed);
                            let (p0, e0) = start(arena, &mut rng);
                            play(
                                arena,
                                &p0,
                                e0,
                                p.pursuers().as_mut(),
                                e.evader().as_mut(),
                                HORIZON,
                                &mut rng,
                            )
                            .map(|r| (seed, r.captured_at))
                        })
                        .collect::<Result<Vec<_>, _>>()
                })
            })
            .collect();
        let mut all = Vec::new();
        for h in handles {
            match h.join() {
                Ok(r) => all.extend(r?),
                Err(e) => std::panic::resume_unwind(e),
            }
        }
        all.sort_unstable();
        Ok::<_, vitro_algo::pursuit::PursuitError>(all.into_iter().map(|(_, t)| t).collect())
    })?;
    let caught: Vec<f64> = times.iter().flatten().map(|&t| f64::from(t)).collect();
    Ok(Cell {
        rate: caught.len() as f64 / times.len().max(1) as f64,
        mean_time: (!caught.is_empty()).then(|| caught.iter().sum::<f64>() / caught.len() as f64),
    })
}

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let episodes: u64 = match std::env::args().nth(1) {
        Some(s) => s.parse()?,
        None => 30,
    };
    let graph = Graph::load(format!("{ROOT}/data/town/kotka_walk.edges"))?;
    let vis = VisibilityGraph(Graph::load(format!("{ROOT}/data/town/kotka_walk.vis"))?);
    let arena = Arena::new(graph, &vis)?;
    let seen: usize = (0..arena.node_count())
        .map(|v| arena.visible_from(v).len() - 1)
        .sum();
    println!(
        "Kotka walking graph: {} junctions, {} streets, diameter {} hops, {:.1} junctions in sight on average",
        arena.node_count(),
        arena.graph().edge_count(),
        arena.diameter(),
        seen as f64 / arena.node_count() as f64
    );
    println!("{PURSUERS} pursuers, horizon {HORIZON}, {episodes} episodes per point\n");

    // MCTS throughput on the town (one move from a fixed start, single thread).
    let mut rng = ChaCha8Rng::seed_from_u64(99);
    let (p0, e0) = start(&arena, &mut rng);
    let mut m = mcts(2000);
    let t0 = Instant::now();
    play(&arena, &p0, e0, &mut m, &mut FleeingEvader, 20, &mut rng)?;
    let secs = t0.elapsed().as_secs_f64();
    println!(
        "MCTS (pursuers, 3 pieces, 30-turn simulations): {} iterations in {:.2} s = {:.0} iterations/s\n",
        m.iterations_run,
        secs,
        m.iterations_run as f64 / secs
    );

    let mut curves: Vec<(String, Vec<(u64, f64)>)> = Vec::new();
    let series: [(&str, Matchup); 4] = [
        ("pursuers MCTS vs fleeing evader", |b| {
            (Player::Mcts(b), Player::Greedy)
        }),
        ("pursuers minimax vs fleeing evader", |b| {
            (Player::Minimax(b), Player::Greedy)
        }),
        ("greedy pursuers vs evader MCTS", |b| {
            (Player::Greedy, Player::Mcts(b))
        }),
        ("greedy pursuers vs evader minimax", |b| {
            (Player::Greedy, Player::Minimax(b))
        }),
    ];
    println!(
        "capture rate vs budget B (MCTS: B iterations, minimax: {NODES_PER_ITERATION}·B nodes per move)"
    );
    for (name, make) in series {
        let t0 = Instant::now();
        let mut points = Vec::new();
        for b in BUDGETS {
            let (p, e) = make(b);
            points.push((b, matchup(&arena, p, e, episodes)?.rate));
        }
        let row: Vec<String> = points
            .iter()
            .map(|(b, r)| format!("B={b}: {r:.2}"))
            .collect();
        println!(
            "  {name:36} {}   ({:.0} s)",
            row.join("  "),
            t0.elapsed().as_secs_f64()
        );
        curves.push((name.to_string(), points));
    }

    let players = [
        Player::Random,
        Player::Greedy,
        Player::Mcts(TABLE_BUDGET),
        Player::Minimax(TABLE_BUDGET),
    ];
    println!(
        "\ncapture rate / mean capture turn (rows: pursuers, columns: evader; baselines: greedy evader = fleeing)"
    );
    print!("{:>16}", "");
    for e in players {
        print!(" | {:>18}", e.name());
    }
    println!();
    for p in players {
        print!("{:>16}", p.name());
        for e in players {
            let c = matchup(&arena, p, e, episodes)?;
            let time = c.mean_time.map_or("-".to_string(), |t| format!("{t:.0}"));
            print!(" | {:>11.2} / {:>4}", c.rate, time);
        }
        println!();
    }
    plot(
        Path::new(&format!("{ROOT}/docs/pursuit_anytime.png")),
        &curves,
        episodes,
    )?;
    println!("\nwrote docs/pursuit_anytime.png");
    Ok(())
}

fn plot(
    path: &Path,
    curves: &[(String, Vec<(u64, f64)>)],
    episodes: u64,
) -> Result<(), Box<dyn std::error::Error>> {
    register_font("sans-serif", FontStyle::Normal, FONT)
        .map_err(|_| "the embedded font could not be loaded")?;
    let root = BitMapBackend::new(path, (960, 600)).into_drawing_area();
    root.fill(&WHITE)?;
    let mut chart = ChartBuilder::on(&root)
        .caption(
            format!("Kotka walking graph: capture rate vs search budget ({PURSUERS} pursuers, {HORIZON} turns, {episodes} episodes)"),
            ("sans-serif", 20),
        )
        .margin(20)
        .x_label_area_size(50)
        .y_label_area_size(60)
        .build_cartesian_2d((8f64..1250f64).log_scale(), 0f64..1.05f64)?;
    chart
        .configure_mesh()
        .x_desc(format!(
            "budget B per move (MCTS: B iterations; minimax: {NODES_PER_ITERATION}·B nodes)"
        ))
        .y_desc("capture rate")
        .x_label_formatter(&|v| format!("{v:.0}"))
        .y_label_formatter(&|v| format!("{v:.1}"))
        .label_style(("sans-serif", 15))
        .axis_desc_style(("sans-serif", 17))
        .draw()?;
    let colours = [RED, BLUE, MAGENTA, CYAN];
    for (i, (name, points)) in curves.iter().enumerate() {
        let colour = colours[i % colours.len()];
        let xy: Vec<(f64, f64)> = points.iter().map(|&(b, r)| (b as f64, r)).collect();
        chart
            .draw_series(LineSeries::new(xy.clone(), colour.stroke_width(3)))?
            .label(name.clone())
            .legend(move |(x, y)| {
                PathElement::new(vec![(x, y), (x + 24, y)], colour.stroke_width(3))
            });
        chart.draw_series(xy.iter().map(|&p| Circle::new(p, 5, colour.filled())))?;
    }
    chart
        .configure_series_labels()
        .position(SeriesLabelPosition::LowerRight)
        .label_font(("sans-serif", 16))
        .background_style(WHITE.mix(0.9))
        .border_style(BLACK)
        .draw()?;
    root.present()?;
    Ok(())
}

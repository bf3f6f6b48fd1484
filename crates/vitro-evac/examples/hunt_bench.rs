//! Decisions per second of the pursuit searches on the mission's real board (the town's walk
//! graph with line of sight), for the hunt lead (two pursuers) and the HVT, with the beliefs
//! they hold early in a hunt (wide) and during a chase (narrow).
//!
//! `cargo run --release -p vitro-evac --example hunt_bench -- [DECISIONS] [BUDGET]`
//!
//! Prints one line per case: the board size, decisions per second and the mean iteration
//! cost. The mission's discrete level spends most of its time in these searches, so this is
//! the figure to watch when changing them.

use rand::{Rng, SeedableRng};
use rand_chacha::ChaCha8Rng;
use std::time::Instant;
use vitro_algo::pursuit::{
    Belief, Budget, EvaderStrategy, EvaderView, Mcts, MctsConfig, PursuerStrategy, PursuerView,
};
use vitro_evac::Mission;
use vitro_tactical::scenario::Preset;

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let args: Vec<String> = std::env::args().collect();
    let decisions: usize = args.get(1).and_then(|s| s.parse().ok()).unwrap_or(200);
    let budget: u64 = args.get(2).and_then(|s| s.parse().ok()).unwrap_or(200);
    let path = concat!(
        env!("CARGO_MANIFEST_DIR"),
        "/../../scenarios/evacuation.toml"
    );
    let mission = Mission::at_fidelity(path, Some(1), Preset::Discrete)?;
    let board = mission
        .brief
        .board
        .clone()
        .ok_or("the default scenario has no HVT board")?;
    let n = board.node_count();
    println!(
        "board: {n} walk nodes, diameter {} hops, a turn {:.1} s; budget {budget} iterations",
        board.diameter(),
        mission.brief.turn_s
    );
    let config = MctsConfig {
        budget: Budget::iterations(budget),
        ..MctsConfig::default()
    };
    let mut rng = ChaCha8Rng::seed_from_u64(7);
    // Positions and beliefs drawn once per decision, outside the timed part.
    let cases: Vec<(usize, usize, usize)> = (0..decisions)
        .map(|_| {
            (
                rng.random_range(0..n),
                rng.random_range(0..n),
                rng.random_range(0..n),
            )
        })
        .collect();
    for wide in [true, false] {
        let belief_about = |v: usize| {
            if wide {
                Belief::uniform(n)
            } else {
                // A chase: the piece was seen three turns ago.
                let mut b = Belief::at(n, v);
                for _ in 0..3 {
                    b.predict(&board);
                }
                b
            }
        };
        let label = if wide { "wide" } else { "narrow" };

        let mut search = Mcts::new(config);
        let beliefs: Vec<Belief> = cases.iter().map(|&(_, _, e)| belief_about(e)).collect();
        let t = Instant::now();
        for (&(a, b, _), belief) in cases.iter().zip(&beliefs) {
            let view = PursuerView {
                arena: &board,
                positions: &[a, b],
                belief,
                turn: 0,
            };
            std::hint::black_box(PursuerStrategy::choose(&mut search, &view, &mut rng));
        }
        report(&format!("pursuers, {label} belief"), t, decisions, &search);

        let mut search = Mcts::new(config);
        let beliefs: Vec<[Belief; 2]> = cases
            .iter()
            .map(|&(a, b, _)| [belief_about(a), belief_about(b)])
            .collect();
        let t = Instant::now();
        for (&(_, _, e), pair) in cases.iter().zip(&beliefs) {
            let view = EvaderView {
                arena: &board,
                position: e,
                beliefs: pair,
                turn: 0,
            };
            std::hint::black_box(EvaderStrategy::choose(&mut search, &view, &mut rng));
        }
        report(&format!("evader, {label} beliefs"), t, decisions, &search);
    }
    Ok(())
}

fn report(what: &str, t: Instant, decisions: usize, search: &Mcts) {
    let s = t.elapsed().as_secs_f64();
    println!(
        "{what:26} {:8.0} decisions/s  {:6.2} us/iteration",
        decisions as f64 / s,
        s * 1e6 / search.iterations_run.max(1) as f64
    );
}

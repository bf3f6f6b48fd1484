//! Solves an instance file with each solver: `cargo run --release -p vitro-routing --example
//! solve_file -- data/vrp/A-n32-k5.vrp [BUDGET] [SEED]`.

use vitro_routing::{Options, Solver, parse, solve};

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let mut args = std::env::args().skip(1);
    let path = args
        .next()
        .ok_or("usage: solve_file INSTANCE [BUDGET] [SEED]")?;
    let budget: u64 = args
        .next()
        .map_or(Ok(Options::DEFAULT_BUDGET), |s| s.parse())?;
    let seed: u64 = args.next().map_or(Ok(0), |s| s.parse())?;
    let inst = parse(&std::fs::read_to_string(&path)?)?;
    for solver in [
        Solver::Savings,
        Solver::Auction,
        Solver::LocalSearch { budget },
    ] {
        let sol = solve(&inst, &Options { solver, seed });
        let gap = inst
            .best_known
            .map(|b| format!(", gap {:+.2}%", sol.gap_percent(b)))
            .unwrap_or_default();
        println!(
            "{}: {solver:?}: cost {:.2}, {} routes, {} unassigned{gap}, {:?}",
            inst.name,
            sol.cost,
            sol.routes.len(),
            sol.unassigned.len(),
            sol.stats
        );
    }
    Ok(())
}

//! The LP backends side by side on the patrol instances: the convoy game (certified by branch
//! and bound: LP relaxations) and the village game (team local search: successive LP).
//!
//! `cargo run --release -p vitro-algo --example lp_backends [-- ITERATIONS]`
//!
//! Prints, per instance and backend, the solve time, the value found, the LPs solved and
//! the ones that failed numerically. The village runs `ITERATIONS` LP iterations per local
//! search (default 10) without random restarts, so that it fits a few minutes.

use std::time::Instant;

use vitro_algo::patrol::{self, Instance, LpBackend, SolveOptions};

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let root = concat!(env!("CARGO_MANIFEST_DIR"), "/../..");
    let iterations = match std::env::args().nth(1) {
        Some(s) => s.parse()?,
        None => 10,
    };
    let convoy = Instance::load(format!("{root}/data/patrol/convoy.toml"))?;
    let village = Instance::load(format!("{root}/data/patrol/village.toml"))?;
    let cases: [(&str, &Instance, SolveOptions); 3] = [
        ("convoy, stationary", &convoy, SolveOptions::default()),
        (
            "convoy, time-dependent",
            &convoy,
            SolveOptions {
                time_dependent: true,
                ..SolveOptions::default()
            },
        ),
        (
            "village, phase-locked team",
            &village,
            SolveOptions {
                phase_locked: true,
                local_iterations: iterations,
                restarts: 0,
                ..SolveOptions::default()
            },
        ),
    ];
    println!(
        "{:<28} {:<9} {:>9} {:>10} {:>7} {:>6} {:>6} {:>8}",
        "instance", "backend", "time s", "value", "exact", "LPs", "fails", "B&B LPs"
    );
    for (name, instance, options) in cases {
        for lp in LpBackend::ALL {
            let options = SolveOptions {
                lp,
                ..options.clone()
            };
            let started = Instant::now();
            let solution = patrol::solve_with(instance, &options)?;
            let seconds = started.elapsed().as_secs_f64();
            let s = &solution.stats;
            println!(
                "{name:<28} {:<9} {seconds:>9.3} {:>10.6} {:>7} {:>6} {:>6} {:>8}",
                lp.name(),
                solution.value,
                solution.exact,
                s.lp.solves,
                s.lp.failures + s.bnb_lp.failures,
                s.bnb_lp.solves,
            );
        }
    }
    Ok(())
}

//! The cost of the patrol's receding-horizon re-solve on the default scenario: the game of
//! the rest of the trip re-timed from every step of the mission's timetable, solved once
//! each (wall time of one core; run with and without `--release`):
//!
//! `cargo run -p vitro-evac --release --example patrol_resolve_cost`

use std::time::Instant;
use vitro_evac::Mission;
use vitro_evac::agents::air::Aircraft;
use vitro_tactical::scenario::Preset;

const SCENARIO: &str = concat!(
    env!("CARGO_MANIFEST_DIR"),
    "/../../scenarios/evacuation.toml"
);

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let t0 = Instant::now();
    let m = Mission::at_fidelity(SCENARIO, None, Preset::Discrete)?;
    println!(
        "mission built (with its game): {:.3} s",
        t0.elapsed().as_secs_f64()
    );
    let unit = m
        .members
        .iter()
        .find_map(|mem| {
            let a = m.sim.agent(mem.id)?.as_any().downcast_ref::<Aircraft>()?;
            a.patrol.clone()
        })
        .ok_or("no Skeldar")?;
    let game = &unit.game;
    println!(
        "mission game: {} steps of trip, period {}, capture probability {:.3}",
        game.timetable.len(),
        game.plan.period,
        game.trip_capture_probability
    );
    let (mut total, mut most, mut n) = (0.0, 0.0_f64, 0);
    for from in 1..game.timetable.len() {
        let t = Instant::now();
        let Some(g) = game.retimed(from)? else {
            continue;
        };
        let s = t.elapsed().as_secs_f64();
        (total, most, n) = (total + s, most.max(s), n + 1);
        println!(
            "re-solve from step {from:2}: {:2} steps left, period {:2}, capture probability {:.3}, {s:.3} s",
            g.timetable.len(),
            g.plan.period,
            g.trip_capture_probability
        );
    }
    if n > 0 {
        println!(
            "{n} re-solves: mean {:.3} s, most {most:.3} s",
            total / f64::from(n)
        );
    }
    Ok(())
}

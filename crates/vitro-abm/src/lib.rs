//! The three models of the public ABM frameworks comparison — Flocking, Schelling and
//! WolfSheep — written on Vitro's core as a user would write them: the state in the
//! environment, agents that read it through sensors and change it through actuators, each
//! activation an event of the queue.
//!
//! The rules and the small and large parameter sets are the comparison's `DECLARATION.md`
//! files, copied in `declarations/` with their provenance. `examples/abm_bench.rs` times
//! them (100 seeded runs, the median) and prints the statistics the declarations let one
//! check; `scripts/abm_compare.sh` runs it next to the same models written with krABMaga.
//!
//! # Steps as events
//!
//! The declarations activate every agent once per step, in a new random order each step.
//! Here step `k` is the simulated second `[k, k + 1)`: each agent draws the instant of its
//! next activation uniformly in the next step's window (from its own random stream), so the
//! order within a step is a fresh random permutation every step, and the event queue does
//! the sorting. Where the declaration orders kinds within a step (WolfSheep: all sheep, then
//! all wolves, then the grass) each kind gets its own part of the window.
//!
//! ```
//! use vitro_abm::schelling::{self, Schelling};
//! let out = schelling::run(&Schelling::SMALL, 7);
//! assert_eq!(out.agents, 1000);
//! assert!(out.happy > 500, "most agents are happy after 20 steps: {}", out.happy);
//! ```

pub mod flocking;
pub mod schelling;
pub mod wolfsheep;

use rand::Rng;
use vitro::time::{SimDuration, SimTime};

/// The one random stream purpose every agent (and every actuator acting for it) draws
/// from: one stream per agent keeps each agent's draws independent of the others' and its
/// random state in one place (a stream per purpose would be as deterministic, with more
/// memory touched per activation).
pub const DRAWS: &str = "agent";

/// One step of simulated time.
pub const STEP: SimDuration = SimDuration::from_secs(1);

/// The delay from `now` to an instant drawn uniformly in `[from, to)` of step `step`
/// (fractions of the step), at nanosecond resolution.
pub fn activation_delay(
    now: SimTime,
    step: u64,
    from: f64,
    to: f64,
    rng: &mut impl Rng,
) -> SimDuration {
    let span = STEP.as_nanos() as f64;
    let lo = (from * span) as u64;
    let hi = ((to * span) as u64).max(lo + 1);
    let at = SimTime::from_nanos(step * STEP.as_nanos() + rng.random_range(lo..hi));
    at.saturating_since(now)
}

/// The median of `xs` (the upper one of an even count, as the comparison's scripts take it).
pub fn median(xs: &[f64]) -> f64 {
    let mut v = xs.to_vec();
    v.sort_by(f64::total_cmp);
    v.get(v.len() / 2).copied().unwrap_or(f64::NAN)
}

#[cfg(test)]
mod tests {
    use super::*;
    use rand::SeedableRng;

    #[test]
    fn activations_fall_in_their_window() {
        let mut rng = rand_chacha::ChaCha8Rng::seed_from_u64(1);
        let now = SimTime::from_secs_f64(0.3);
        for _ in 0..1000 {
            let d = activation_delay(now, 1, 0.4, 0.8, &mut rng);
            let at = (now + d).as_secs_f64();
            assert!((1.4..1.8).contains(&at), "{at}");
        }
        assert_eq!(median(&[3.0, 1.0, 2.0]), 2.0);
        assert_eq!(median(&[4.0, 1.0, 2.0, 3.0]), 3.0);
    }
}

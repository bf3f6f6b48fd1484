//! The three models of the public ABM frameworks comparison — Flocking, Schelling and
//! WolfSheep — written on Vitro's core as a user would write them: the state in the
//! environment, agents that read it through sensors and change it through actuators, each
//! activation traced.
//!
//! The rules and the small and large parameter sets are the comparison's `DECLARATION.md`
//! files, copied in `declarations/` with their provenance. `examples/abm_bench.rs` times
//! them (100 seeded runs, the median) and prints the statistics the declarations let one
//! check; `scripts/abm_compare.sh` runs it next to the same models written with krABMaga.
//!
//! # Steps as rounds
//!
//! The declarations activate every agent once per step, in a new random order each step.
//! Here step `k` is the simulated second `[k, k + 1)`, and each kind of agent is a member of
//! a round ([`Simulation::add_round`](vitro::sim::Simulation::add_round)): one event of the
//! queue per step that activates its members in a fresh seeded random order, each
//! activation traced. Where the declaration orders kinds within a step (WolfSheep: all
//! sheep, then all wolves, then the grass) each kind's round fires at its own instant of the
//! step. Each agent draws from its own small random stream
//! ([`Context::small_rng`](vitro::sim::Context::small_rng): SplitMix64, 8 bytes of state),
//! so its draws do not depend on the other agents.
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

use vitro::time::SimDuration;

/// The one small random stream purpose every agent (and every actuator acting for it) draws
/// from: one stream per agent keeps each agent's draws independent of the others' and its
/// random state in one place (a stream per purpose would be as deterministic, with more
/// memory touched per activation).
pub const DRAWS: &str = "agent";

/// One step of simulated time.
pub const STEP: SimDuration = SimDuration::from_secs(1);

/// The median of `xs` (the upper one of an even count, as the comparison's scripts take it).
pub fn median(xs: &[f64]) -> f64 {
    let mut v = xs.to_vec();
    v.sort_by(f64::total_cmp);
    v.get(v.len() / 2).copied().unwrap_or(f64::NAN)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn medians() {
        assert_eq!(median(&[3.0, 1.0, 2.0]), 2.0);
        assert_eq!(median(&[4.0, 1.0, 2.0, 3.0]), 3.0);
    }
}

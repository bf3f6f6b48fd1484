//! The village-scale patrolling game: two patrol UAVs guarding three convoys on the real town's
//! street graph (`data/patrol/village.toml`, built by `patrol_village_data`), solved by the
//! scalable method (team local search over phase-locked tubes with restarts), then played in
//! the simulator against the attacker's best replies.
//!
//! `cargo run --release -p vitro-worlds --example patrol_village [-- ITERATIONS RESTARTS TRIALS]`
//!
//! Prints the instance, the LP sizes and the solve time, the value and where the attacker
//! wins, why (from some of its best starts, no walk of the unit guarding the west and south
//! convoys meets both within one attack), and the Monte-Carlo estimate of the capture
//! probability against the attacker's best reply, with its 99% interval.
//!
//! Measured with the defaults (60 LP iterations, 2 restarts, 20 000 attacks per convoy; one
//! core of the shared 2-core machine, otherwise quiet): solve 120 s, 471 LPs in 9 local
//! searches on 3 of 15 candidate teams, the largest LP 6 980 variables x 3 186 constraints;
//! value 0.500011, capture probability 0.499989 (one unit rides with the north-east convoy,
//! the other guards the west and south ones, which it cannot both keep covered); simulated
//! 0.5000 with 99% interval [0.4874, 0.5126] against the best reply (800 761 steps, 4.8 M
//! events, 0.5 s). The full-phase team search reaches 0.24 (time-dependent) and 0.01
//! (stationary).

use std::time::Instant;

use vitro_algo::patrol::{
    self, Instance, PatrolError, PatrolPlan, Policy, SolveOptions, TargetPosition,
};
use vitro_worlds::patrol::{AttackOrder, SimOptions, best_replies, simulate};

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let root = concat!(env!("CARGO_MANIFEST_DIR"), "/../..");
    let arg = |i: usize, default: u64| -> Result<u64, std::num::ParseIntError> {
        std::env::args().nth(i).map_or(Ok(default), |s| s.parse())
    };
    let iterations = usize::try_from(arg(1, 60)?)?;
    let restarts = usize::try_from(arg(2, 2)?)?;
    let trials = u32::try_from(arg(3, 20_000)?)?;
    let instance = Instance::load(format!("{root}/data/patrol/village.toml"))?;
    let period = instance.period()?;
    println!(
        "village: {} cells, {} links; {} convoys, {} units; period {period} steps, attacks of {} steps",
        instance.graph.node_count(),
        instance.graph.edge_count(),
        instance.targets.len(),
        instance.patrollers.len(),
        instance.targets[0].deadline
    );

    let options = SolveOptions {
        phase_locked: true,
        local_iterations: iterations,
        restarts,
        ..SolveOptions::default()
    };
    let started = Instant::now();
    let solution = patrol::solve_with(&instance, &options)?;
    let seconds = started.elapsed().as_secs_f64();
    let lp = &solution.stats.lp;
    println!(
        "solve: {seconds:.1} s; {} candidate teams ({} searched), {} local searches, {} LPs, largest {} variables x {} constraints",
        solution.stats.supports,
        solution.stats.supports_searched,
        solution.stats.local_searches,
        lp.solves,
        lp.max_variables,
        lp.max_constraints
    );
    println!(
        "value {:.6} (attacker's expected gain), capture probability {:.6} (local optimum, not certified)",
        solution.value, solution.capture_probability
    );
    for (unit, policy) in instance.patrollers.iter().zip(&solution.policies) {
        let states: usize = (0..policy.phases())
            .map(|f| policy.states_at(f).len())
            .sum();
        println!(
            "  {}: {} cells, {states} (cell, phase) states",
            unit.name,
            policy.support().len()
        );
    }
    let binding: Vec<_> = solution
        .threats
        .iter()
        .filter(|t| t.capture_probability <= solution.capture_probability + 1e-6)
        .collect();
    for t in &binding {
        println!(
            "  binding: {} at phase {}, units at {:?}: caught with probability {:.6}",
            instance.targets[t.target].name, t.phase, t.from, t.capture_probability
        );
    }
    explain(&instance, &solution.policies, &binding)?;

    // The attacker's best reply against each convoy, at any phase: strike when the computed
    // capture probability is within SLACK of the least (pooling nearly-worst starts, which
    // the units visit more often than the single worst ones).
    const SLACK: f64 = 0.01;
    let plan = PatrolPlan::from_solution(&instance, &solution)?;
    let choices = best_replies(&instance, &plan, SLACK)?;
    let sim = SimOptions {
        seed: 2024,
        trials,
        order: AttackOrder::InTurn,
        max_wait: 100_000,
        max_steps: 50_000_000,
        ..SimOptions::default()
    };
    let started = Instant::now();
    let report = simulate(&instance, &plan, &choices, &sim)?;
    let seconds = started.elapsed().as_secs_f64();
    println!(
        "simulator: {} best replies x {trials} attacks in turn, {} steps, {} events, {seconds:.1} s, trace {:016x}, {} refused moves, {} attacks given up",
        report.choices.len(),
        report.steps,
        report.events,
        report.trace_hash,
        report.refused_moves,
        report.choices.iter().map(|e| e.abandoned).sum::<u32>()
    );
    for e in &report.choices {
        println!(
            "  {}: {} attacks, caught {:.4}, 99% interval [{:.4}, {:.4}]; computed {:.6} (mean of the attacks made; threshold {:.6})",
            instance.targets[e.choice.target].name,
            e.trials,
            e.capture_probability,
            e.interval.0,
            e.interval.1,
            e.computed,
            e.choice.threshold
        );
    }
    let agree = report
        .choices
        .iter()
        .all(|e| e.trials > 0 && e.interval.0 <= e.computed && e.computed <= e.interval.1);
    let (lo, hi) = report.value_interval;
    println!(
        "  capture probability against the best reply: simulated {:.4}, 99% interval [{:.4}, {:.4}]; computed {:.6} (attacks within {SLACK} of it pooled)",
        1.0 - report.value,
        1.0 - hi,
        1.0 - lo,
        solution.capture_probability
    );
    println!("  every computed capture probability inside its simultaneous 99% interval: {agree}");
    Ok(())
}

/// Why the attacker wins half the time: the unit guarding the west and the south convoy (the
/// other rides with the north-east one) is observed, and at some of the binding starts no walk
/// of it meets both convoys within one attack: its chances of catching one or the other add up
/// to at most 1, so even odds are the best it can do there.
fn explain(
    instance: &Instance,
    policies: &[Policy],
    binding: &[&patrol::Threat],
) -> Result<(), PatrolError> {
    // Each unit's own chance to catch each attack, by (target, phase, vertex).
    let mut own: Vec<Vec<(usize, usize, usize, f64)>> = Vec::new();
    for policy in policies {
        own.push(
            policy
                .attacks(instance)?
                .iter()
                .map(|a| (a.target, a.phase, a.from, a.capture_probability))
                .collect(),
        );
    }
    let chance = |unit: usize, t: usize, phase: usize, h: usize| {
        own[unit]
            .iter()
            .find(|a| (a.0, a.1, a.2) == (t, phase, h))
            .map_or(0.0, |a| a.3)
    };
    let schedule = |name: &str| {
        instance
            .targets
            .iter()
            .position(|t| t.name == name)
            .and_then(|i| match &instance.targets[i].position {
                TargetPosition::Schedule(s) => Some((i, s.clone(), instance.targets[i].deadline)),
                TargetPosition::Static(_) => None,
            })
    };
    let (Some((w, west, deadline)), Some((s, south, _))) =
        (schedule("convoy west"), schedule("convoy south"))
    else {
        return Ok(());
    };
    let period = west.len().max(1);
    let deadline = deadline as usize;
    let dist = |a: usize, b: usize| instance.graph.distances_from(a)[b];
    let meets_both = |h: usize, phase: usize| {
        let order = [(&west, &south), (&south, &west)];
        order.iter().any(|(x, y)| {
            (1..=deadline).any(|a| {
                let xa = x[(phase + a) % period];
                dist(h, xa).is_some_and(|d| d <= a)
                    && (a..=deadline)
                        .any(|b| dist(xa, y[(phase + b) % period]).is_some_and(|d| d <= b - a))
            })
        })
    };
    // Binding attacks on either where only one unit has a chance (the other keeps to its
    // convoy), and no walk of that unit meets both.
    let (mut exclusive, mut total) = (Vec::new(), 0);
    for t in binding.iter().filter(|t| t.target == w || t.target == s) {
        total += 1;
        let helpers: Vec<usize> = (0..t.from.len())
            .filter(|&i| chance(i, t.target, t.phase, t.from[i]) > 1e-9)
            .map(|i| t.from[i])
            .collect();
        if let [h] = helpers[..]
            && !meets_both(h, t.phase)
        {
            exclusive.push((t.phase, h));
        }
    }
    println!(
        "  {} of the {total} binding attacks on the west and south convoys start where one unit alone has a chance and no walk of it meets both within {deadline} steps, so 1/2 is the best it can do there: (phase, its cell) {exclusive:?}",
        exclusive.len()
    );
    Ok(())
}

//! Patrolling security games (after Basilico, Gatti & Amigoni, AAMAS 2009): one patroller
//! randomises its walk on a graph; an attacker who knows the randomisation and watches the
//! patroller strikes a target at the worst moment.
//!
//! # The game
//!
//! - The patroller follows a stationary Markov [`Policy`]: on its *support* (the vertices it
//!   patrols, closed under its moves) each vertex has a distribution over staying or stepping
//!   to a neighbour. The patroller picks the support too.
//! - The attacker sees the patroller's vertex `h` (any support vertex; he can wait for it),
//!   picks a target `t` and starts the attack at once. The attack takes `deadline_t` steps and
//!   is caught if the patroller stands on `t` at one of the steps `1..=deadline_t`; otherwise
//!   the attacker gains `value_t`.
//! - The value of a policy is the attacker's best expected gain,
//!   `max over (t, h) of value_t · (1 − P(t, h))`; the patroller minimises it. With equal values
//!   this is maximising the worst-case capture probability. (With Markov policies the history
//!   tells the attacker nothing more than the current vertex.)
//!
//! # What is exact
//!
//! `P(t, h)` is a polynomial of degree `deadline_t` in the transition probabilities, so the
//! patroller's problem is a non-convex polynomial program; no single LP states it, and its
//! optimum can be irrational. [`solve`] therefore works in two stages:
//!
//! 1. **Local (mathematical programming).** On each candidate support, successive linear
//!    programming (good_lp): linearise every `P(t, h)` at the current policy, solve
//!    the LP `min z s.t. z ≥ value_t · (1 − linearised P(t, h))`, rows stochastic, within a
//!    trust region; repeat. This finds a good policy fast but only a *local* optimum.
//! 2. **Exact (certified).** Branch and bound over boxes of transition probabilities on every
//!    connected support (module `exact`). Lower bounds come from the monotonicity of `P` in
//!    each entry: an interval recursion, and an LP relaxation (good_lp again) whose
//!    error shrinks with the square of the box width. When the search finishes, the returned
//!    policy is within [`SolveOptions::tolerance`] of the best value over **all** stationary
//!    Markov policies on **all** supports: [`Solution::exact`] is then true and
//!    `value − lower_bound ≤ tolerance`. This is practical for small graphs (up to about five
//!    vertices and a few dozen transition entries, certified in milliseconds to seconds);
//!    on larger ones the box budget ([`SolveOptions::max_nodes`]) runs out, `exact` is false,
//!    and the solution is the best policy found with a certified but looser `lower_bound`.
//!
//! The LP solver is [`SolveOptions::lp`]: microlp (default) or Clarabel ([`LpBackend`];
//! example `lp_backends` compares them).
//!
//! The value [`solve`] reports is always the exact value of the returned policy (computed by
//! the recursion above, checked by [`monte_carlo`]); only its optimality is conditional on
//! `exact`. Optima are in general irrational: on a path of four vertices with targets of
//! value 1 and 2 at the ends (deadline 3) the certified optimum is 0.928203… (≈ 4√3 − 6).
//!
//! # Moving targets and time-dependent policies
//!
//! Targets may be convoys on cyclic schedules ([`TargetPosition::Schedule`]); the period `T`
//! is the least common multiple of the schedules' lengths, and the attacker also sees the
//! phase `time mod T`. The chain then runs on the product state `(vertex, phase)`: an attack
//! started at `(h, φ)` on target `t` is caught if the patroller stands on `pos_t(φ + s)` at a
//! step `s ∈ 1..=D`. A *stationary* policy shares one row per vertex across phases; a
//! *time-dependent* one ([`SolveOptions::time_dependent`]) has a row per (vertex, phase).
//! The attack starts are the patroller's *states*, the (vertex, phase) pairs it can be found
//! in: here every support vertex at every phase (a *full-phase* support). Both capture probabilities stay polynomials with non-negative coefficients, so stages 1
//! and 2 apply unchanged and `exact` keeps its meaning over the class searched. Every
//! stationary policy is a time-dependent one, so the time-dependent optimum is never worse.
//!
//! # Phase-locked policies: attacks start only where the patroller can be
//!
//! The classes above give the patroller the same support at every phase, so the attacker may
//! strike from every (support vertex, phase). That is right for static targets, but with
//! convoys it forbids the obvious defence: a patroller riding with a convoy is at the convoy's
//! vertex *at that phase* and nowhere else, yet the full-phase class lets the attacker start
//! while it stands on the far end of the route. On a 10 × 10 grid with three convoys and two
//! patrollers (example `patrol_scale`) that modelling choice made every policy worthless
//! (capture probability 0): some (vertex, phase) of every support is out of reach of some
//! convoy. It is a modelling error, not a property of the game: a Markov patroller is only
//! ever in the states of its policy's recurrent class, and only those are observable starts.
//!
//! [`SolveOptions::phase_locked`] fixes it: time-dependent policies on *phase-locked* supports,
//! a set of product states `(vertex, phase)` closed under the moves, attacked only from those
//! states (see [`Policy`]). The supports searched are *tubes* around the targets each patroller
//! guards (module `tube`): at every phase, the states that keep all its targets within reach
//! of an attack (else any of them), ranked by distance to the targets (best placed first, with
//! a little slack) or by intercept time; states that cannot go on or cannot reach a target in
//! time are pruned. On the grid the team then catches every attack (value 0); on the village
//! instance (`data/patrol/village.toml`, example `patrol_village`) the least capture
//! probability rises from 0.24 (full-phase time-dependent team; 0.01 stationary) to 0.5.
//! (The phase-locked search runs on tubes only; run both to compare.) Found by local search
//! (below), phase-locked policies are never certified: [`Solution::lower_bound`] is 0 and
//! `exact` false unless every attack is surely caught (a single patroller also gets the
//! certified full-phase optimum as a candidate). Every returned policy is restricted to one
//! closed class of its states (where the patroller really ends up; moves of probability below
//! 10⁻⁹ left by the LP are dropped first), so its value counts only starts the attacker can
//! actually see.
//!
//! # Several patrollers: local optimisation with restarts (the scalable method)
//!
//! Independent policies, one per patroller; the attacker sees all of them, so the escape
//! probability of a joint start is the product of the patrollers' ones (module `team`).
//! They are found by the same successive LP (product linearised too) with restarts:
//! - over target-to-patroller assignments (while there are at most 64 of them; idle patrollers
//!   guard everything);
//! - over supports: the connected cover of each patroller's targets (full-phase), or with
//!   [`SolveOptions::phase_locked`] tubes: the tightest by distance and one with one more step
//!   of slack (started from the tighter one's optimum), and the tightest by intercept time;
//! - over starting policies: on tubes, following the nearest guarded target (picking one at
//!   random where targets part), then uniform, then in turn [`SolveOptions::restarts`] random
//!   ones and the best so far shaken.
//!
//! Candidates are searched in order of a certified floor (an attack every patroller surely
//! misses), and skipped once the best found beats it; the search stops at a perfect patrol.
//! LPs drop attack starts no move can affect (constant rows become bounds) and, on large
//! instances, keep an active set of the worst few starts per target and phase (steps are
//! accepted only when the exact value improves). It is anytime and returns a local optimum,
//! never certified (`exact` is false unless every attack is surely caught).
//!
//! # Using and checking a plan
//!
//! [`PatrolPlan`] is the plain-data face for a mission: solve once, then ask each unit's next
//! vertex step by step ([`PatrolPlan::next_vertex`]). `vitro_worlds::patrol` plays a plan in
//! the simulator (`vitro` agents: units sampling their policies, convoys on their timetables,
//! an attacker striking at its computed best replies) and estimates the capture probabilities
//! with 99% intervals; [`monte_carlo`] does the same for one policy without the simulator.
//!
//! Policies with memory (history-dependent patrols) and coordinated teams (joint moves) can
//! beat these; they are outside the optimised classes.
//!
//! ```
//! use vitro_algo::patrol::{self, Instance};
//!
//! let instance = Instance::from_toml_str(r#"
//!     [graph]
//!     edges = [[0, 1], [1, 2]]
//!     [[target]]
//!     node = 0
//!     value = 1
//!     deadline = 2
//!     [[target]]
//!     node = 2
//!     value = 1
//!     deadline = 2
//!     [[patroller]]
//! "#)?;
//! let solution = patrol::solve(&instance)?;
//! assert!(solution.exact);
//! // Bouncing 0 -> 1 -> (0 or 2 at random) -> 1 -> ... catches every attack half the time.
//! assert!((solution.value - 0.5).abs() < 1e-6);
//! # Ok::<(), patrol::PatrolError>(())
//! ```

mod chain;
mod error;
mod exact;
mod instance;
mod local;
mod lp;
mod montecarlo;
mod plan;
mod policy;
mod relax;
mod solution;
mod supports;
mod team;
mod tube;

pub use error::PatrolError;
pub use instance::{Instance, MAX_PERIOD, Patroller, Target, TargetPosition};
pub use local::LpStats;
pub use lp::LpBackend;
pub use montecarlo::{AttackEstimate, MonteCarloOptions, MonteCarloReport, monte_carlo};
pub use plan::{PatrolPlan, PlanParams};
pub use policy::{Attack, Policy, Rows};
pub use solution::{Solution, SolveOptions, SolveStats, Threat};
pub use team::{team_value, threats};

use chain::Chain;

/// Solves a patrolling game with [`SolveOptions::default`].
///
/// # Errors
/// See [`solve_with`].
pub fn solve(instance: &Instance) -> Result<Solution, PatrolError> {
    solve_with(instance, &SolveOptions::default())
}

/// Solves a patrolling game: the best stationary (or, with
/// [`SolveOptions::time_dependent`], time-dependent) Markov policy for a single patroller,
/// certified optimal when [`Solution::exact`]; for several patrollers, independent policies
/// found by local search with restarts (never certified). See the [module docs](self).
///
/// # Errors
/// [`PatrolError::Lp`] if the LP solver fails, [`PatrolError::Unsupported`] for a schedule
/// period above [`MAX_PERIOD`], [`PatrolError::InvalidInstance`] for an inconsistent instance.
pub fn solve_with(instance: &Instance, options: &SolveOptions) -> Result<Solution, PatrolError> {
    let (period, targets) = instance.timeline()?;
    let timed = (options.time_dependent || options.phase_locked) && period > 1;
    if instance.patrollers.len() > 1 {
        return team::solve(instance, options, period, &targets, timed);
    }
    if options.phase_locked && period > 1 && !options.full_phase_candidate {
        return team::solve(instance, options, period, &targets, true);
    }
    if options.phase_locked && period > 1 {
        // The certified full-phase optimum, then the phase-locked local search: the better.
        let full = solve_with(
            instance,
            &SolveOptions {
                time_dependent: true,
                phase_locked: false,
                ..options.clone()
            },
        )?;
        // Where the full-phase patroller really ends up: one closed class of its states.
        let policies = team::recurrent_team(instance, full.policies.clone())?;
        let threats = team::threats(instance, &policies)?;
        let value = threats.iter().map(|a| a.expected_loss).fold(0.0, f64::max);
        // Certified over the full-phase class only: no bound over the phase-locked one.
        let full = Solution {
            value,
            lower_bound: 0.0,
            exact: value <= 0.0,
            capture_probability: threats
                .iter()
                .map(|a| a.capture_probability)
                .fold(1.0, f64::min),
            policies,
            threats,
            ..full
        };
        let mut locked = team::solve(instance, options, period, &targets, true)?;
        if locked.value < full.value - options.tolerance {
            locked.stats.nodes += full.stats.nodes;
            return Ok(locked);
        }
        return Ok(full);
    }
    let graph = &instance.graph;
    let (supports, complete) = match supports::connected(graph, options.max_supports) {
        Some(all) => (all, true),
        None => (graph.components(), false),
    };
    let mut chains: Vec<Chain> = supports
        .iter()
        .map(|s| Chain::new(graph, s, &targets, period, timed))
        .collect();
    let mut quick: Vec<f64> = chains.iter().map(supports::unreachable_loss).collect();
    let mut order: Vec<usize> = (0..chains.len()).collect();
    order.sort_by(|&a, &b| {
        quick[a]
            .total_cmp(&quick[b])
            .then(chains[b].len().cmp(&chains[a].len()))
            .then(a.cmp(&b))
    });
    let mut stats = SolveStats {
        supports: chains.len(),
        ..SolveStats::default()
    };
    stats.lp.backend = options.lp;
    stats.bnb_lp.backend = options.lp;
    // Stage 1: local optimisation on the most promising supports.
    let mut best: Option<(usize, Vec<f64>, f64)> = None;
    for &s in order.iter().take(options.local_searches.max(1)) {
        if best.as_ref().is_some_and(|b| quick[s] >= b.2) {
            break;
        }
        let start = local::uniform(&chains[s]);
        let (alpha, loss) =
            local::improve(&chains[s], start, options.local_iterations, &mut stats.lp);
        stats.local_searches += 1;
        if best.as_ref().is_none_or(|b| loss < b.2) {
            best = Some((s, alpha, loss));
        }
    }
    let Some(mut incumbent) = best else {
        return Err(PatrolError::InvalidInstance(
            "the graph has no vertices".into(),
        ));
    };
    // A stationary policy is a time-dependent one: start from the best stationary policy too,
    // so the time-dependent result is never worse.
    if timed {
        let stationary = solve_with(
            instance,
            &SolveOptions {
                time_dependent: false,
                ..options.clone()
            },
        )?;
        let lifted = &stationary.policies[0];
        let support = lifted.support();
        let s = match chains.iter().position(|c| c.nodes == support) {
            Some(s) => s,
            None => {
                chains.push(Chain::new(graph, support, &targets, period, true));
                quick.push(supports::unreachable_loss(&chains[chains.len() - 1]));
                chains.len() - 1
            }
        };
        let start = lifted.to_chain_entries(&chains[s]);
        let (alpha, loss) =
            local::improve(&chains[s], start, options.local_iterations, &mut stats.lp);
        stats.local_searches += 1;
        stats.supports = chains.len();
        if loss < incumbent.2 {
            incumbent = (s, alpha, loss);
        }
    }
    // Stage 2: certify (or improve) by branch and bound on every support that could beat it.
    let cutoff = incumbent.2 - options.tolerance;
    let searched: Vec<usize> = (0..chains.len()).filter(|&s| quick[s] < cutoff).collect();
    let ruled_out = (0..chains.len())
        .filter(|&s| quick[s] >= cutoff)
        .map(|s| quick[s])
        .fold(f64::INFINITY, f64::min);
    stats.supports_searched = searched.len();
    let subset: Vec<Chain> = searched.iter().map(|&s| chains[s].clone()).collect();
    let start = match searched.iter().position(|&s| s == incumbent.0) {
        Some(i) => (i, incumbent.1.clone(), incumbent.2),
        // The incumbent's support was ruled out only if nothing can beat it: keep it.
        None => (usize::MAX, incumbent.1.clone(), incumbent.2),
    };
    let outcome = exact::branch_and_bound(
        &subset,
        start,
        options.tolerance,
        options.max_nodes,
        &mut stats.bnb_lp,
    );
    stats.nodes = outcome.nodes;
    let (chain, alpha) = if outcome.support == usize::MAX {
        (&chains[incumbent.0], &incumbent.1)
    } else {
        (&subset[outcome.support], &outcome.alpha)
    };
    let policy = best_class(instance, Policy::from_chain(chain, alpha))?;
    let policies = vec![policy];
    let threats = team::threats(instance, &policies)?;
    let value = threats.iter().map(|a| a.expected_loss).fold(0.0, f64::max);
    let capture_probability = threats
        .iter()
        .map(|a| a.capture_probability)
        .fold(1.0, f64::min);
    let lower_bound = outcome.lower_bound.min(ruled_out).min(value);
    Ok(Solution {
        value,
        lower_bound,
        exact: complete && value - lower_bound <= options.tolerance,
        capture_probability,
        policies,
        threats,
        stats,
    })
}

/// The policy restricted to its best recurrent class: where the patroller ends up circling.
/// Fewer vertices to attack from can only lower the value, and transient vertices are never
/// visited again, so the restriction is at least as good and describes what really happens.
fn best_class(instance: &Instance, policy: Policy) -> Result<Policy, PatrolError> {
    let mut best: Option<(f64, Policy)> = None;
    for class in policy.recurrent_classes() {
        let restricted = policy.restricted(&class);
        let value = restricted.value(instance)?;
        if best.as_ref().is_none_or(|b| value < b.0) {
            best = Some((value, restricted));
        }
    }
    Ok(best.map_or(policy, |b| b.1))
}

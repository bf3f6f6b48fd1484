//! The patrol plan a mission drives its units with: solve once, then ask each unit's next
//! vertex step by step.

use rand::Rng;
use serde::Serialize;

use super::{Instance, PatrolError, Patroller, Policy, SolveOptions, Target, Threat, solve_with};
use crate::graph::{Graph, NodeId};

/// Settings for [`PatrolPlan::solve`].
#[derive(Clone, Debug, PartialEq)]
pub struct PlanParams {
    /// Phase-locked time-dependent policies (units may keep near the convoys they guard; see
    /// [`SolveOptions::phase_locked`]). Default true; false gives stationary policies.
    pub phase_locked: bool,
    /// LP iterations per local search. Default 60.
    pub iterations: usize,
    /// Random restarts of each local search besides the planned starts. Default 2.
    pub restarts: usize,
    /// Seed of the restarts. Default 0.
    pub seed: u64,
    /// With [`PlanParams::phase_locked`] and one unit, also try the certified full-phase
    /// policy (see [`SolveOptions::full_phase_candidate`]). Default true.
    pub full_phase_candidate: bool,
    /// The LP solver. Default [`LpBackend::default`](super::LpBackend::default).
    pub lp: super::LpBackend,
}

impl Default for PlanParams {
    fn default() -> Self {
        PlanParams {
            phase_locked: true,
            iterations: 60,
            restarts: 2,
            seed: 0,
            full_phase_candidate: true,
            lp: super::LpBackend::default(),
        }
    }
}

/// Randomised patrols for a team of units guarding convoys on known timetables: one Markov
/// policy per unit over the timetable's phases, with the attacker's best reply against them.
/// Plain data: clone it, serialise it, hand one copy to each unit.
///
/// Time runs in steps; at each step a unit moves to a neighbouring vertex or stays, and the
/// convoys move to their next scheduled vertex. The phase of step `k` is `k % period`.
///
/// ```
/// use rand::SeedableRng;
/// use vitro_algo::graph;
/// use vitro_algo::patrol::{PatrolPlan, PlanParams, Target, TargetPosition};
///
/// // A road of six junctions; a convoy drives out and back, one junction a step.
/// let road = graph::path(6)?;
/// let convoy = Target {
///     name: "convoy".into(),
///     position: TargetPosition::Schedule(vec![0, 1, 2, 3, 4, 5, 4, 3, 2, 1]),
///     value: 1.0,
///     deadline: 3,
/// };
/// let plan = PatrolPlan::solve(&road, &[convoy], 1, &PlanParams::default())?;
/// // One unit can ride with one convoy: every attack is caught.
/// assert!(plan.capture_probability > 0.999);
///
/// // Drive the unit: where to start, then one vertex per step.
/// let mut rng = rand_chacha::ChaCha8Rng::seed_from_u64(1);
/// let mut at = plan.start_vertex(0, 0, &mut rng)?;
/// for step in 0..20 {
///     let next = plan.next_vertex(0, at, plan.phase(step), &mut rng)?;
///     assert!(next == at || road.has_edge(at, next));
///     at = next;
/// }
/// # Ok::<(), Box<dyn std::error::Error>>(())
/// ```
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct PatrolPlan {
    /// Where the units move.
    #[serde(skip)]
    pub graph: Graph,
    /// The timetable's period in steps (1 when every target is static).
    pub period: usize,
    /// One policy per unit.
    pub policies: Vec<Policy>,
    /// The attacker's best expected gain against the plan (lower is better).
    pub value: f64,
    /// The smallest capture probability over every attack the attacker can choose.
    pub capture_probability: f64,
    /// Per target and phase, the attacker's best joint start and its outcome.
    pub threats: Vec<Threat>,
}

impl PatrolPlan {
    /// Plans `units` units guarding `convoys` (moving or static targets) on `graph`.
    ///
    /// # Errors
    /// [`PatrolError::InvalidInstance`] for an empty graph, no convoys or no units, a convoy
    /// off the graph or not moving along its edges; [`PatrolError::Lp`] if the LP solver
    /// fails; [`PatrolError::Unsupported`] for a timetable period above
    /// [`MAX_PERIOD`](super::MAX_PERIOD).
    pub fn solve(
        graph: &Graph,
        convoys: &[Target],
        units: usize,
        params: &PlanParams,
    ) -> Result<PatrolPlan, PatrolError> {
        let patrollers = (0..units)
            .map(|i| Patroller {
                name: format!("unit{i}"),
            })
            .collect();
        let instance = Instance::new(graph.clone(), convoys.to_vec(), patrollers)?;
        let options = SolveOptions {
            time_dependent: params.phase_locked,
            phase_locked: params.phase_locked,
            local_iterations: params.iterations,
            restarts: params.restarts,
            seed: params.seed,
            full_phase_candidate: params.full_phase_candidate,
            lp: params.lp,
            ..SolveOptions::default()
        };
        let solution = solve_with(&instance, &options)?;
        let period = instance.period()?;
        Ok(PatrolPlan {
            graph: instance.graph,
            period,
            policies: solution.policies,
            value: solution.value,
            capture_probability: solution.capture_probability,
            threats: solution.threats,
        })
    }

    /// The plan of an instance already solved (by [`solve_with`]).
    ///
    /// # Errors
    /// As for [`Instance::period`].
    pub fn from_solution(
        instance: &Instance,
        solution: &super::Solution,
    ) -> Result<PatrolPlan, PatrolError> {
        Ok(PatrolPlan {
            graph: instance.graph.clone(),
            period: instance.period()?,
            policies: solution.policies.clone(),
            value: solution.value,
            capture_probability: solution.capture_probability,
            threats: solution.threats.clone(),
        })
    }

    /// Number of units.
    pub fn units(&self) -> usize {
        self.policies.len()
    }

    /// The phase of step `step`.
    pub fn phase(&self, step: u64) -> usize {
        let period = self.period.max(1) as u64;
        // The remainder is below the period, a usize.
        (step % period) as usize
    }

    fn policy(&self, unit: usize) -> Result<&Policy, PatrolError> {
        self.policies.get(unit).ok_or(PatrolError::NoSuchUnit {
            unit,
            units: self.policies.len(),
        })
    }

    /// The vertices where `unit` may be at `phase`, ascending.
    ///
    /// # Errors
    /// [`PatrolError::NoSuchUnit`].
    pub fn vertices_at(&self, unit: usize, phase: usize) -> Result<Vec<NodeId>, PatrolError> {
        Ok(self.policy(unit)?.states_at(phase))
    }

    /// A vertex where `unit` may start its patrol at `phase`, drawn evenly from
    /// [`PatrolPlan::vertices_at`] (the policy keeps the unit in one recurrent class, so any of
    /// them is fine).
    ///
    /// # Errors
    /// [`PatrolError::NoSuchUnit`]; [`PatrolError::InvalidPolicy`] for a policy with no vertex
    /// at that phase (never for a solved plan).
    pub fn start_vertex<R: Rng + ?Sized>(
        &self,
        unit: usize,
        phase: usize,
        rng: &mut R,
    ) -> Result<NodeId, PatrolError> {
        let at = self.vertices_at(unit, phase)?;
        if at.is_empty() {
            return Err(PatrolError::InvalidPolicy(format!(
                "unit {unit} has no vertex at phase {phase}"
            )));
        }
        Ok(at[rng.random_range(0..at.len())])
    }

    /// Where `unit`, at `current` at `phase`, goes next: drawn from its policy with one
    /// uniform number from `rng`. A unit off its patrol (not at one of
    /// [`PatrolPlan::vertices_at`] for that phase, e.g. delayed) takes one step along a
    /// shortest path towards the nearest vertex where it may be at the next phase, staying if
    /// it is already there.
    ///
    /// # Errors
    /// [`PatrolError::NoSuchUnit`], or [`PatrolError::NoSuchVertex`] for a vertex outside the
    /// graph.
    pub fn next_vertex<R: Rng + ?Sized>(
        &self,
        unit: usize,
        current: NodeId,
        phase: usize,
        rng: &mut R,
    ) -> Result<NodeId, PatrolError> {
        let policy = self.policy(unit)?;
        if current >= self.graph.node_count() {
            return Err(PatrolError::NoSuchVertex(current));
        }
        let u: f64 = rng.random();
        if let Some(next) = policy.next_at(current, phase, u) {
            return Ok(next);
        }
        Ok(self.rejoin(policy, current, phase + 1))
    }

    /// One step from `current` along a shortest path towards the nearest vertex of `policy`
    /// at `phase` (`current` itself if it is one, or if none can be reached).
    fn rejoin(&self, policy: &Policy, current: NodeId, phase: usize) -> NodeId {
        let goals = policy.states_at(phase);
        if goals.binary_search(&current).is_ok() {
            return current;
        }
        // Breadth-first search from the current vertex; the first goal found is the nearest
        // (ties to the first reached, neighbours in ascending order).
        let n = self.graph.node_count();
        let mut parent = vec![usize::MAX; n];
        parent[current] = current;
        let mut queue = std::collections::VecDeque::from([current]);
        while let Some(x) = queue.pop_front() {
            if goals.binary_search(&x).is_ok() {
                let mut step = x;
                while parent[step] != current {
                    step = parent[step];
                }
                return step;
            }
            for &y in self.graph.neighbors(x) {
                if parent[y] == usize::MAX {
                    parent[y] = x;
                    queue.push_back(y);
                }
            }
        }
        current
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::graph;
    use crate::patrol::TargetPosition;
    use rand::SeedableRng;
    use rand_chacha::ChaCha8Rng;

    fn shuttle() -> (Graph, Vec<Target>) {
        let g = graph::path(6).unwrap();
        let convoy = Target {
            name: "c".into(),
            position: TargetPosition::Schedule(vec![0, 1, 2, 3, 4, 5, 4, 3, 2, 1]),
            value: 1.0,
            deadline: 2,
        };
        (g, vec![convoy])
    }

    #[test]
    fn units_follow_their_policies_and_rejoin_when_lost() {
        let (g, convoys) = shuttle();
        let plan = PatrolPlan::solve(&g, &convoys, 1, &PlanParams::default()).unwrap();
        assert_eq!(plan.period, 10);
        let mut rng = ChaCha8Rng::seed_from_u64(3);
        // On its patrol, every move is one the policy allows.
        let mut at = plan.start_vertex(0, 0, &mut rng).unwrap();
        for step in 0..50u64 {
            let phase = plan.phase(step);
            let next = plan.next_vertex(0, at, phase, &mut rng).unwrap();
            assert!(
                plan.policies[0]
                    .moves_at(at, phase)
                    .unwrap()
                    .iter()
                    .any(|m| m.0 == next)
            );
            at = next;
        }
        // Off it, one step at a time towards where it should be next.
        let phase = 0;
        let allowed = plan.vertices_at(0, phase + 1).unwrap();
        let lost = (0..6).find(|v| {
            !allowed.contains(v)
                && plan
                    .vertices_at(0, phase)
                    .unwrap()
                    .binary_search(v)
                    .is_err()
        });
        if let Some(lost) = lost {
            let next = plan.next_vertex(0, lost, phase, &mut rng).unwrap();
            let gap = |v: usize| allowed.iter().map(|&w| v.abs_diff(w)).min().unwrap();
            assert_eq!(gap(next) + 1, gap(lost));
        }
        // Bad input is an error, not a panic.
        assert!(matches!(
            plan.next_vertex(1, 0, 0, &mut rng),
            Err(PatrolError::NoSuchUnit { unit: 1, units: 1 })
        ));
        assert!(matches!(
            plan.next_vertex(0, 9, 0, &mut rng),
            Err(PatrolError::NoSuchVertex(9))
        ));
    }

    #[test]
    fn plans_are_deterministic_and_match_the_solver() {
        let (g, convoys) = shuttle();
        let params = PlanParams {
            phase_locked: false,
            ..PlanParams::default()
        };
        let a = PatrolPlan::solve(&g, &convoys, 1, &params).unwrap();
        let b = PatrolPlan::solve(&g, &convoys, 1, &params).unwrap();
        assert_eq!(a, b);
        assert_eq!(a.policies[0].phases(), 1);
        let instance = Instance::new(
            g,
            convoys,
            vec![Patroller {
                name: "unit0".into(),
            }],
        )
        .unwrap();
        let solution = solve_with(
            &instance,
            &SolveOptions {
                local_iterations: 60,
                ..SolveOptions::default()
            },
        )
        .unwrap();
        assert_eq!(PatrolPlan::from_solution(&instance, &solution).unwrap(), a);
    }
}

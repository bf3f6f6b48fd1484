//! A multi-agent planning scenario: the ground task, which agent owns which action, what
//! each agent observes, and the joint plan the team starts with.

use std::collections::BTreeMap;
use std::sync::Arc;

use crate::planning::heuristic::FfHeuristic;
use crate::planning::pddl::{Domain, Problem, parse_domain, parse_problem};
use crate::planning::search::greedy_best_first;
use crate::planning::{ActionId, FactId, PddlSource, PlanError, Task, ground};

use super::RepairError;

/// Which parameter of a ground action names the agent that owns (executes) it.
///
/// By default the first parameter: in the dock-worker domain `(move r1 l1 l2)` belongs to
/// robot `r1` and `(take k1 l1 cc cb p1)` to crane `k1`; in Depots `(drive truck0 ...)` to
/// the truck and `(lift hoist0 ...)` to the hoist. An action schema can name another
/// parameter (counted from 0).
///
/// ```
/// use vitro_algo::repair::Ownership;
/// let own = Ownership::first_parameter().with("load", 3);
/// assert_eq!(own.parameter("load"), 3);
/// assert_eq!(own.parameter("move"), 0);
/// ```
#[derive(Debug, Clone, Default, PartialEq, Eq)]
pub struct Ownership {
    by_action: BTreeMap<String, usize>,
}

impl Ownership {
    /// Every action belongs to the object of its first parameter.
    pub fn first_parameter() -> Self {
        Self::default()
    }
    /// Actions of schema `action` (lower-case) belong to their parameter `index` instead.
    pub fn with(mut self, action: &str, index: usize) -> Self {
        self.by_action.insert(action.to_lowercase(), index);
        self
    }
    /// The schemas that name another owning parameter, with it.
    pub fn overrides(&self) -> Vec<(String, usize)> {
        self.by_action
            .iter()
            .map(|(a, &i)| (a.clone(), i))
            .collect()
    }
    /// The owning parameter of schema `action`.
    pub fn parameter(&self, action: &str) -> usize {
        self.by_action.get(action).copied().unwrap_or(0)
    }
}

/// Everything the agents of a run share: the task, the team and the initial joint plan.
#[derive(Debug)]
pub struct Team {
    /// The ground task.
    pub task: Task,
    /// Agent names (objects that own at least one action), in problem object order.
    pub agents: Vec<String>,
    /// Per action: the index of its owner in `agents`.
    pub owner: Vec<usize>,
    /// Per agent: its actions, in id order.
    pub actions_of: Vec<Vec<ActionId>>,
    /// Per agent: the facts it observes (those its own actions read or write), sorted.
    pub views: Vec<Vec<FactId>>,
    /// Facts no agent observes, true initially: no action changes them.
    pub unobserved: Vec<FactId>,
    /// The joint plan the team starts with.
    pub plan: Vec<ActionId>,
}

impl Team {
    /// The name of `action`.
    pub fn action_name(&self, action: ActionId) -> &str {
        &self.task.actions[action as usize].name
    }
    /// The state after applying `action` in `state` (unchecked).
    pub fn apply(&self, action: ActionId, state: &[u64]) -> Vec<u64> {
        let mut out = Vec::with_capacity(state.len());
        self.task.apply_into(action, state, &mut out);
        out
    }
}

/// A multi-agent planning problem ready to be executed: parsed PDDL, the ground task, the
/// agents and their actions, and an initial joint plan (greedy best-first search with FF).
///
/// ```
/// use vitro_algo::planning::PddlSource;
/// use vitro_algo::repair::{Ownership, Scenario};
///
/// let domain = "(define (domain lift) (:predicates (at ?w ?f) (adj ?a ?b))
///   (:action go :parameters (?w ?a ?b) :precondition (and (at ?w ?a) (adj ?a ?b))
///    :effect (and (at ?w ?b) (not (at ?w ?a)))))";
/// let problem = "(define (problem p) (:domain lift) (:objects ann bob f0 f1)
///   (:init (at ann f0) (at bob f1) (adj f0 f1) (adj f1 f0))
///   (:goal (and (at ann f1) (at bob f0))))";
/// let s = Scenario::from_pddl(
///     PddlSource::new("lift.pddl", domain),
///     PddlSource::new("p.pddl", problem),
///     &Ownership::first_parameter(),
/// )?;
/// assert_eq!(s.agents(), ["ann", "bob"]);
/// assert_eq!(s.plan().len(), 2);
/// # Ok::<(), vitro_algo::repair::RepairError>(())
/// ```
#[derive(Debug, Clone)]
pub struct Scenario {
    domain: Domain,
    problem: Problem,
    /// The PDDL texts and the ownership it was made from (to rebuild a saved repairer).
    pub(crate) domain_text: String,
    pub(crate) problem_text: String,
    pub(crate) ownership: Vec<(String, usize)>,
    pub(crate) team: Arc<Team>,
}

impl Scenario {
    /// Parses and grounds a problem, assigns each ground action to its owner and plans.
    ///
    /// # Errors
    /// [`RepairError::Plan`] when the PDDL does not parse or has no plan,
    /// [`RepairError::NoOwner`] when an action has no parameter at the owning position.
    pub fn from_pddl(
        domain: PddlSource<'_>,
        problem: PddlSource<'_>,
        ownership: &Ownership,
    ) -> Result<Self, RepairError> {
        let d = parse_domain(domain.text, domain.name).map_err(PlanError::from)?;
        let p = parse_problem(&d, problem.text, problem.name).map_err(PlanError::from)?;
        let task = ground(&d, &p).map_err(PlanError::from)?;
        let team = Self::build_team(&p, task, ownership)?;
        Ok(Scenario {
            domain_text: domain.text.to_string(),
            problem_text: problem.text.to_string(),
            ownership: ownership.overrides(),
            domain: d,
            problem: p,
            team: Arc::new(team),
        })
    }

    /// [`from_pddl`](Self::from_pddl) on two files.
    ///
    /// # Errors
    /// [`RepairError::Io`] when a file cannot be read, otherwise as `from_pddl`.
    pub fn from_files(
        domain: &std::path::Path,
        problem: &std::path::Path,
        ownership: &Ownership,
    ) -> Result<Self, RepairError> {
        let read = |path: &std::path::Path| {
            std::fs::read_to_string(path).map_err(|source| RepairError::Io {
                path: path.display().to_string(),
                source,
            })
        };
        let (dt, pt) = (read(domain)?, read(problem)?);
        let (dn, pn) = (domain.display().to_string(), problem.display().to_string());
        Self::from_pddl(
            PddlSource::new(&dn, &dt),
            PddlSource::new(&pn, &pt),
            ownership,
        )
    }

    fn build_team(
        problem: &Problem,
        task: Task,
        ownership: &Ownership,
    ) -> Result<Team, RepairError> {
        // Owner object of each action, by name.
        let mut owner_name = Vec::with_capacity(task.actions.len());
        for a in &task.actions {
            let words: Vec<&str> = a
                .name
                .trim_start_matches('(')
                .trim_end_matches(')')
                .split_whitespace()
                .collect();
            let schema = words.first().copied().unwrap_or_default();
            let index = ownership.parameter(schema);
            let owner = words.get(index + 1).ok_or_else(|| RepairError::NoOwner {
                action: a.name.clone(),
                parameter: index,
            })?;
            owner_name.push(owner.to_string());
        }
        // Agents in problem object order.
        let agents: Vec<String> = problem
            .objects
            .iter()
            .map(|o| o.name.clone())
            .filter(|n| owner_name.contains(n))
            .collect();
        let index_of: BTreeMap<&str, usize> = agents
            .iter()
            .enumerate()
            .map(|(i, n)| (n.as_str(), i))
            .collect();
        let owner: Vec<usize> = owner_name.iter().map(|n| index_of[n.as_str()]).collect();
        let mut actions_of = vec![Vec::new(); agents.len()];
        let mut observed = vec![vec![false; task.facts.len()]; agents.len()];
        for (id, a) in task.actions.iter().enumerate() {
            let who = owner[id];
            actions_of[who].push(id as ActionId);
            for &f in a.pre.iter().chain(&a.add).chain(&a.del) {
                observed[who][f as usize] = true;
            }
        }
        let views: Vec<Vec<FactId>> = observed
            .iter()
            .map(|o| (0..o.len() as FactId).filter(|&f| o[f as usize]).collect())
            .collect();
        let unobserved: Vec<FactId> = task
            .init
            .iter()
            .copied()
            .filter(|&f| observed.iter().all(|o| !o[f as usize]))
            .collect();
        let outcome = greedy_best_first(&task, &mut FfHeuristic::new(&task));
        let plan = outcome
            .plan
            .ok_or(RepairError::Plan(PlanError::Unsolvable {
                expanded: outcome.stats.expanded,
            }))?;
        Ok(Team {
            task,
            agents,
            owner,
            actions_of,
            views,
            unobserved,
            plan,
        })
    }

    /// The parsed domain (for validating executed traces).
    pub fn domain(&self) -> &Domain {
        &self.domain
    }
    /// The parsed problem.
    pub fn problem(&self) -> &Problem {
        &self.problem
    }
    /// The ground task.
    pub fn task(&self) -> &Task {
        &self.team.task
    }
    /// The team: agents, their actions and views, the initial plan (shared by every agent
    /// of a run).
    pub fn team(&self) -> &Arc<Team> {
        &self.team
    }
    /// The agents (owning objects), in problem object order.
    pub fn agents(&self) -> &[String] {
        &self.team.agents
    }
    /// The initial joint plan, as ground actions.
    pub fn plan(&self) -> Vec<&str> {
        self.team
            .plan
            .iter()
            .map(|&a| self.team.task.actions[a as usize].name.as_str())
            .collect()
    }
    /// The agent that owns ground action `action` (by its PDDL form).
    pub fn owner_of(&self, action: &str) -> Option<&str> {
        let id = self
            .team
            .task
            .actions
            .iter()
            .position(|a| a.name == action)?;
        Some(self.team.agents[self.team.owner[id]].as_str())
    }
    /// The facts agent `agent` observes, in PDDL form.
    pub fn view_of(&self, agent: &str) -> Option<Vec<&str>> {
        let i = self.team.agents.iter().position(|a| a == agent)?;
        Some(
            self.team.views[i]
                .iter()
                .map(|&f| self.team.task.facts[f as usize].as_str())
                .collect(),
        )
    }
}

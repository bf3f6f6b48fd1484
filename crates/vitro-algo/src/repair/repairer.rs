//! The repair framework for plans executed in the caller's world: [`Repairer`].

use std::collections::{BTreeMap, BTreeSet};
use std::sync::Arc;

use serde::{Deserialize, Serialize};

use super::planner::RepairKind;
use super::scenario::Team;
use super::{RepairError, Scenario, Strategy, bits};
use crate::planning::heuristic::FfHeuristic;
use crate::planning::search::greedy_best_first_bounded;
use crate::planning::{ActionId, FactId, Task};

/// A step of a plan: the plan version that introduced it and its position there.
#[derive(Debug, Clone, Copy, PartialEq, Eq, PartialOrd, Ord, Hash, Serialize, Deserialize)]
pub struct StepRef {
    /// 0 for the first plan, then one more per repair.
    pub version: u32,
    /// Position in the plan of that version.
    pub index: u32,
}

/// A pending step, as the caller sees it.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct PlanStep {
    /// Its identity.
    pub id: StepRef,
    /// Its owner (index into [`Scenario::agents`]).
    pub agent: usize,
    /// The ground action, in PDDL form, e.g. `(fly v0 c1 c2)`.
    pub action: String,
}

/// What made the caller ask for a repair.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize)]
pub enum Cause {
    /// This step was carried out but did not make its effects true.
    Failed(StepRef),
    /// This agent can no longer act (lost, recalled): its pending steps will not happen.
    Lost(usize),
    /// Every step is done (or abandoned) and the goal does not hold.
    PlanEnd,
}

/// The settings of a repairer.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct RepairSettings {
    /// How failures are repaired.
    pub strategy: Strategy,
    /// Bound on the states one search may expand (none: no bound).
    pub max_expansions: Option<u64>,
    /// A repair plan longer than this is cut to its first `max_depth` steps (none: no cut).
    pub max_depth: Option<usize>,
}

impl Default for RepairSettings {
    /// Replanning, no bounds.
    fn default() -> Self {
        RepairSettings {
            strategy: Strategy::Replan,
            max_expansions: None,
            max_depth: None,
        }
    }
}

/// What one call of [`Repairer::repair`] did.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct Revision {
    /// The kind of plan made.
    pub kind: RepairKind,
    /// Back-on-track found no plan and replanned.
    pub fell_back: bool,
    /// `max_depth` cut the new plan.
    pub cut: bool,
    /// A search stopped at `max_expansions`.
    pub truncated: bool,
    /// States expanded.
    pub expanded: u64,
    /// A plan was found (if not, the plan keeps only the steps still valid, if any).
    pub found: bool,
    /// Agents that own steps of the new plan they were not told: each needs a message.
    pub tell: Vec<usize>,
}

/// Counts over a repairer's life.
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq, Serialize, Deserialize)]
pub struct RepairTally {
    /// Repairs made (plans after the first).
    pub repairs: u64,
    /// Repairs that `max_depth` cut.
    pub cuts: u64,
    /// Back-on-track repairs that fell back to replanning.
    pub fallbacks: u64,
    /// Searches stopped at `max_expansions`.
    pub truncated: u64,
    /// Repairs that found no plan.
    pub unsolved: u64,
    /// Failures reported while the plan was executed lazily (left for the plan's end).
    pub deferred: u64,
    /// States expanded by every repair.
    pub expanded: u64,
}

/// The repair framework for plans executed elsewhere: a [`Repairer`] holds a team's joint
/// plan and repairs it by a [`Strategy`] when the agents that execute it, in a world of
/// their own (a mission), report a failure, a lost teammate or the end of the plan.
///
/// The stand-alone `vitro_worlds::repair::run` executes a plan turn by turn in a world of its own;
/// here the caller owns the world and the radio. Each agent executes its own steps in
/// order, in parallel with the others; the caller tells the repairer which steps were done
/// ([`Repairer::done`]), what it believes is true ([`Repairer::repair`]'s `belief`) and
/// what the goal is now (a goal may shrink as the mission moves on). The repairer answers
/// with a new plan and the agents that must be told their new steps: counting those
/// messages is the point of comparing strategies.
///
/// Strategies, for parallel execution:
/// - [`Replan`](Strategy::Replan): at every failure, a plan from the belief to the goal;
///   every agent with a step it was not told gets a message.
/// - [`BackOnTrack`](Strategy::BackOnTrack): a plan from the belief to a *target*: what the
///   failed step should have made true, what each working agent's next pending step needs,
///   and the goal facts a lost agent's pending steps would have made true; then the pending
///   steps of the working agents, unchanged (their owners need no message). No such plan
///   (or the end of the plan short of the goal): it falls back to replanning.
/// - [`Lazy`](Strategy::Lazy): failures of the first plan are left alone (the agents go on);
///   when the plan ends short of the goal, one repair to the goal, whose own failures are
///   replanned. [`RepeatedLazy`](Strategy::RepeatedLazy): every plan is executed lazily.
///
/// `max_depth` cuts a repair plan to its first steps (the rest is planned when the cut plan
/// ends); each cut is counted. `max_expansions` bounds each search.
///
/// ```
/// use vitro_algo::planning::PddlSource;
/// use vitro_algo::repair::{Cause, Ownership, RepairSettings, Repairer, Scenario, Strategy};
///
/// let domain = "(define (domain lift) (:predicates (at ?w ?f) (adj ?a ?b) (seen ?f))
///   (:action go :parameters (?w ?a ?b) :precondition (and (at ?w ?a) (adj ?a ?b))
///    :effect (and (at ?w ?b) (not (at ?w ?a)) (seen ?b))))";
/// let problem = "(define (problem p) (:domain lift) (:objects ann bob f0 f1 f2)
///   (:init (at ann f0) (at bob f2) (adj f0 f1) (adj f1 f0) (adj f1 f2) (adj f2 f1))
///   (:goal (and (seen f1) (seen f0))))";
/// let s = Scenario::from_pddl(PddlSource::new("d", domain), PddlSource::new("p", problem),
///                             &Ownership::first_parameter())?;
/// let settings = RepairSettings { strategy: Strategy::Replan, ..RepairSettings::default() };
/// let mut r = Repairer::new(&s, settings);
/// let told = r.start();                 // the first plan goes to its owners
/// assert!(!told.is_empty());
/// // The first step ran but its effect did not come true: replan from what is believed.
/// let first = r.pending()[0].id;
/// r.done(first);
/// let belief = ["(at ann f0)", "(at bob f2)"];
/// let rev = r.repair(Cause::Failed(first), &belief, &["(seen f1)", "(seen f0)"])?.unwrap();
/// assert!(rev.found);
/// # Ok::<(), vitro_algo::repair::RepairError>(())
/// ```
#[derive(Debug, Clone, Serialize, Deserialize)]
#[serde(into = "Saved", try_from = "Saved")]
pub struct Repairer {
    team: Arc<Team>,
    saved: Saved,
    index: BTreeMap<String, FactId>,
}

/// The repairer's state, and how it is saved: the PDDL it was made from and its plan.
#[derive(Debug, Clone, Serialize, Deserialize)]
struct Saved {
    domain: String,
    problem: String,
    ownership: Vec<(String, usize)>,
    settings: RepairSettings,
    /// Pending steps of the current plan, in order.
    steps: Vec<(StepRef, ActionId)>,
    /// The current plan is executed lazily.
    deferred: bool,
    version: u32,
    /// Per agent: the steps it was told.
    told: Vec<BTreeSet<StepRef>>,
    /// Agents lost: their actions are out of every search.
    lost: BTreeSet<usize>,
    /// Steps over (done or abandoned), with their actions.
    past: BTreeMap<StepRef, ActionId>,
    tally: RepairTally,
}

impl From<Repairer> for Saved {
    fn from(r: Repairer) -> Saved {
        r.saved
    }
}

impl TryFrom<Saved> for Repairer {
    type Error = RepairError;
    fn try_from(saved: Saved) -> Result<Self, RepairError> {
        let scenario = saved.scenario()?;
        let mut r = Repairer::build(&scenario, saved.settings);
        r.saved = saved;
        Ok(r)
    }
}

impl Saved {
    fn scenario(&self) -> Result<Scenario, RepairError> {
        let mut own = super::Ownership::first_parameter();
        for (a, i) in &self.ownership {
            own = own.with(a, *i);
        }
        Scenario::from_pddl(
            crate::planning::PddlSource::new("domain", &self.domain),
            crate::planning::PddlSource::new("problem", &self.problem),
            &own,
        )
    }
}

impl Repairer {
    /// A repairer of `scenario`'s first plan (executed lazily for the lazy strategies).
    pub fn new(scenario: &Scenario, settings: RepairSettings) -> Self {
        Repairer::build(scenario, settings)
    }

    fn build(scenario: &Scenario, settings: RepairSettings) -> Self {
        let team = scenario.team.clone();
        let task = &team.task;
        let index = task
            .facts
            .iter()
            .enumerate()
            .map(|(i, f)| (f.clone(), i as FactId))
            .collect();
        let steps = team
            .plan
            .iter()
            .enumerate()
            .map(|(i, &a)| {
                let id = StepRef {
                    version: 0,
                    index: i as u32,
                };
                (id, a)
            })
            .collect();
        let saved = Saved {
            domain: scenario.domain_text.clone(),
            problem: scenario.problem_text.clone(),
            ownership: scenario.ownership.clone(),
            settings,
            steps,
            deferred: matches!(settings.strategy, Strategy::Lazy | Strategy::RepeatedLazy),
            version: 0,
            told: vec![BTreeSet::new(); team.agents.len()],
            lost: BTreeSet::new(),
            past: BTreeMap::new(),
            tally: RepairTally::default(),
        };
        Repairer { team, saved, index }
    }

    /// The agents that own steps of the first plan (each needs a message with its steps),
    /// marked as told.
    pub fn start(&mut self) -> Vec<usize> {
        self.tell_new()
    }

    /// The team's agents, in problem object order.
    pub fn agents(&self) -> &[String] {
        &self.team.agents
    }

    /// The pending steps, in plan order.
    pub fn pending(&self) -> Vec<PlanStep> {
        self.saved
            .steps
            .iter()
            .map(|&(id, a)| self.step(id, a))
            .collect()
    }

    /// The pending steps of `agent`, in order.
    pub fn steps_of(&self, agent: usize) -> Vec<PlanStep> {
        self.saved
            .steps
            .iter()
            .filter(|&&(_, a)| self.team.owner[a as usize] == agent)
            .map(|&(id, a)| self.step(id, a))
            .collect()
    }

    fn step(&self, id: StepRef, action: ActionId) -> PlanStep {
        PlanStep {
            id,
            agent: self.team.owner[action as usize],
            action: self.team.action_name(action).to_string(),
        }
    }

    /// The current plan is executed lazily (failures wait for the plan's end).
    pub fn is_deferred(&self) -> bool {
        self.saved.deferred
    }

    /// Step `id` is over (done, or abandoned): it is no longer pending.
    pub fn done(&mut self, id: StepRef) {
        if let Some(i) = self.saved.steps.iter().position(|(s, _)| *s == id) {
            let (s, a) = self.saved.steps.remove(i);
            self.saved.past.insert(s, a);
        }
    }

    /// No step of an agent still able to act is pending.
    pub fn is_finished(&self) -> bool {
        let owner = &self.team.owner;
        self.saved
            .steps
            .iter()
            .all(|&(_, a)| self.saved.lost.contains(&owner[a as usize]))
    }

    /// The counts so far.
    pub fn tally(&self) -> RepairTally {
        self.saved.tally
    }

    /// The settings.
    pub fn settings(&self) -> RepairSettings {
        self.saved.settings
    }

    /// The ids of facts named in PDDL form, sorted.
    fn facts(&self, names: &[&str]) -> Result<Vec<FactId>, RepairError> {
        let mut out: Vec<FactId> = Vec::with_capacity(names.len());
        for n in names {
            let f = self
                .index
                .get(*n)
                .ok_or_else(|| RepairError::UnknownFact(n.to_string()))?;
            out.push(*f);
        }
        out.sort_unstable();
        out.dedup();
        Ok(out)
    }

    /// Repairs the plan for `cause`, from the facts believed true now (`belief`: the facts
    /// that actions change; grounding compiles the static ones away) to `goal`. `None`: nothing to do now
    /// (a failure of a lazily executed plan, or a plan end with the goal believed reached).
    ///
    /// # Errors
    /// [`RepairError::UnknownFact`] for a fact the task does not have.
    pub fn repair(
        &mut self,
        cause: Cause,
        belief: &[&str],
        goal: &[&str],
    ) -> Result<Option<Revision>, RepairError> {
        if let Cause::Lost(a) = cause {
            self.saved.lost.insert(a);
        }
        let task = &self.team.task;
        let belief = bits::state(task.words(), &self.facts(belief)?);
        let goal = self.facts(goal)?;
        if cause == Cause::PlanEnd && goal.iter().all(|&f| holds(&belief, f)) {
            return Ok(None);
        }
        let strategy = self.saved.settings.strategy;
        if self.saved.deferred && cause != Cause::PlanEnd {
            self.saved.tally.deferred += 1;
            return Ok(None);
        }
        let mut rev = match (strategy, cause) {
            (Strategy::BackOnTrack, Cause::Failed(_) | Cause::Lost(_)) => {
                self.back_on_track(cause, &belief, &goal)
            }
            (Strategy::Lazy | Strategy::RepeatedLazy, Cause::PlanEnd) if self.saved.deferred => {
                self.plan_to_goal(
                    RepairKind::Lazy,
                    &belief,
                    goal,
                    strategy == Strategy::RepeatedLazy,
                )
            }
            _ => self.plan_to_goal(RepairKind::Replan, &belief, goal, false),
        };
        let t = &mut self.saved.tally;
        t.repairs += 1;
        t.cuts += u64::from(rev.cut);
        t.fallbacks += u64::from(rev.fell_back);
        t.truncated += u64::from(rev.truncated);
        t.unsolved += u64::from(!rev.found);
        t.expanded += rev.expanded;
        rev.tell = self.tell_new();
        Ok(Some(rev))
    }

    /// A plan from `belief` to `goal` replaces the plan.
    fn plan_to_goal(
        &mut self,
        kind: RepairKind,
        belief: &[u64],
        goal: Vec<FactId>,
        deferred: bool,
    ) -> Revision {
        let (plan, expanded, truncated) = self.search(belief, goal);
        let found = plan.is_some();
        let (steps, cut) = self.cut(plan.unwrap_or_default());
        self.saved.version += 1;
        let v = self.saved.version;
        self.saved.steps = numbered(v, &steps);
        self.saved.deferred = deferred;
        Revision {
            kind,
            fell_back: false,
            cut,
            truncated,
            expanded,
            found,
            tell: Vec::new(),
        }
    }

    fn back_on_track(&mut self, cause: Cause, belief: &[u64], goal: &[FactId]) -> Revision {
        let task = &self.team.task;
        let owner = &self.team.owner;
        let goal_set: BTreeSet<FactId> = goal.iter().copied().collect();
        let mut target: BTreeSet<FactId> = BTreeSet::new();
        let failed = match cause {
            Cause::Failed(id) => Some(id),
            _ => None,
        };
        // What the failed step should have made true.
        let failed_action = failed.and_then(|id| {
            let pending = self.saved.steps.iter().find(|(s, _)| *s == id).map(|p| p.1);
            pending.or_else(|| self.saved.past.get(&id).copied())
        });
        if let Some(a) = failed_action {
            target.extend(task.actions[a as usize].add.iter().copied());
        }
        // The steps that go on: pending, not the failed one, not a lost agent's.
        let rest: Vec<(StepRef, ActionId)> = self
            .saved
            .steps
            .iter()
            .copied()
            .filter(|&(s, a)| Some(s) != failed && !self.saved.lost.contains(&owner[a as usize]))
            .collect();
        // The goal facts lost agents' pending steps would have made true.
        for &(_, a) in &self.saved.steps {
            if self.saved.lost.contains(&owner[a as usize]) {
                let adds = task.actions[a as usize].add.iter();
                target.extend(adds.filter(|f| goal_set.contains(f)));
            }
        }
        let mut seen = BTreeSet::new();
        for &(_, a) in &rest {
            if seen.insert(owner[a as usize]) {
                target.extend(task.actions[a as usize].pre.iter().copied());
            }
        }
        let (back, e1, t1) = self.search(belief, target.into_iter().collect());
        let Some(prefix) = back else {
            let mut r = self.plan_to_goal(RepairKind::BackOnTrack, belief, goal.to_vec(), false);
            r.fell_back = true;
            r.expanded += e1;
            r.truncated |= t1;
            return r;
        };
        let (prefix, cut) = self.cut(prefix);
        self.saved.version += 1;
        let mut steps = numbered(self.saved.version, &prefix);
        steps.extend(rest);
        self.saved.steps = steps;
        self.saved.deferred = false;
        Revision {
            kind: RepairKind::BackOnTrack,
            fell_back: false,
            cut,
            truncated: t1,
            expanded: e1,
            found: true,
            tell: Vec::new(),
        }
    }

    /// Greedy best-first search with FF from `from` to `goal`: the plan, states expanded,
    /// and whether the bound stopped it.
    fn search(&self, from: &[u64], goal: Vec<FactId>) -> (Option<Vec<ActionId>>, u64, bool) {
        let team = &self.team;
        // A lost agent's actions can be neither planned nor applied: they need a fact that
        // no state has (the last id, so the preconditions stay sorted).
        let never = team.task.facts.len() as FactId;
        let mut facts = team.task.facts.clone();
        facts.push("(lost)".into());
        let actions = team
            .task
            .actions
            .iter()
            .enumerate()
            .map(|(i, a)| {
                let mut a = a.clone();
                if self.saved.lost.contains(&team.owner[i]) {
                    a.pre.push(never);
                }
                a
            })
            .collect();
        let task = Task {
            facts,
            actions,
            init: bits::facts(from),
            goal,
        };
        let out = greedy_best_first_bounded(
            &task,
            &mut FfHeuristic::new(&task),
            self.saved.settings.max_expansions,
        );
        (out.plan, out.stats.expanded, out.stats.truncated)
    }

    fn cut(&self, mut plan: Vec<ActionId>) -> (Vec<ActionId>, bool) {
        match self.saved.settings.max_depth {
            Some(d) if plan.len() > d => {
                plan.truncate(d);
                (plan, true)
            }
            _ => (plan, false),
        }
    }

    /// Marks every pending step as told to its owner; the agents that were told something
    /// new, in order.
    fn tell_new(&mut self) -> Vec<usize> {
        let mut out = BTreeSet::new();
        for &(id, a) in &self.saved.steps {
            let who = self.team.owner[a as usize];
            if self.saved.told[who].insert(id) {
                out.insert(who);
            }
        }
        out.into_iter().collect()
    }
}

/// Whether fact `f` is set in state `s`.
fn holds(s: &[u64], f: FactId) -> bool {
    s.get((f / 64) as usize)
        .is_some_and(|w| w & (1 << (f % 64)) != 0)
}

fn numbered(version: u32, actions: &[ActionId]) -> Vec<(StepRef, ActionId)> {
    actions
        .iter()
        .enumerate()
        .map(|(i, &a)| {
            let id = StepRef {
                version,
                index: i as u32,
            };
            (id, a)
        })
        .collect()
}

#[cfg(test)]
#[path = "repairer_tests.rs"]
mod tests;

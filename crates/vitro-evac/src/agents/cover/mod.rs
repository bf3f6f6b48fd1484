//! The Vidars' cover plan: the helicopters watch the checkpoints of the route ahead of the
//! team, by a multi-agent plan that the lead Vidar makes and repairs with the repair
//! framework of [`vitro_algo::repair`].
//!
//! **The domain.** The route is cut into checkpoints about [`SPACING_M`] apart. A Vidar
//! `hop`s from a checkpoint to a neighbour (one or two ahead, one back) and watches the one
//! it reaches, or `look`s again at the one it is over; the goal is every checkpoint ahead of
//! the team watched and each working Vidar at its station over the extraction end of the
//! route ([`station`]: the escort goes all the way), so every Vidar moves with the team and
//! the planner shares the looks out (on the default route it leapfrogs them: one Vidar the
//! odd checkpoints, the other the even ones). Which Vidar watches which checkpoint is the
//! planner's choice (greedy best-first search with FF on the ground task).
//!
//! **Execution** ([`watch`]): each Vidar flies its own steps in order, paced by the team (a
//! step starts once its checkpoint is at most [`AHEAD`] checkpoints ahead of the truck's last
//! reported place, or at once if it leads back towards the team), and looks at the checkpoint
//! on arrival: the look fails when its camera
//! has no line of sight to the checkpoint's ground (a roof in the way, out of range), or
//! with the scenario's `repair.failure_rate` (glare, smoke, a gust: drawn from its own
//! stream). It reports each look to the lead by radio (the lead's own looks need no
//! message).
//!
//! **Failures the lead detects** (all from what it hears): a failed look; a look not
//! reported within [`OVERDUE_S`] of when it was due (a lost plan or report message, a Vidar
//! stuck); a Vidar lost (it reports its recall, or its position reports go stale: down,
//! out of range); the plan ending with checkpoints ahead still unwatched (a cut plan, a
//! lazily executed one). Each goes to the [`Repairer`] with the scenario's strategy and
//! depth bound; every Vidar that owns steps it was not told gets one plan message. The
//! lead is never recalled (it would take the plan with it).

pub mod watch;

use crate::brief::Brief;
use crate::scenario::RepairStrategy;
use serde::{Deserialize, Serialize};
use std::collections::{BTreeMap, BTreeSet};
use vitro::entity::EntityId;
use vitro_algo::planning::PddlSource;
use vitro_algo::repair::{
    Cause, Ownership, RepairError, RepairSettings, RepairTally, Repairer, Scenario, StepRef,
    Strategy,
};
use vitro_site::map::Mode;

/// States one repair search may expand: a search with no plan within the bound counts as
/// finding none (an unsolvable cover problem would otherwise be searched exhaustively).
pub const MAX_EXPANSIONS: u64 = 4_000;
/// Spacing of the checkpoints along the route, metres.
pub const SPACING_M: f64 = 150.0;
/// A step starts once its checkpoint is at most this many checkpoints ahead of the truck.
pub const AHEAD: usize = 2;
/// A step due (its checkpoint within [`AHEAD`]) and not reported after this long is
/// taken for failed, seconds.
pub const OVERDUE_S: f64 = 60.0;

const DOMAIN: &str = "(define (domain cover) (:requirements :strips :typing)
  (:types uav spot)
  (:predicates (at ?u - uav ?s - spot) (next ?a ?b - spot) (watched ?s - spot))
  (:action hop :parameters (?u - uav ?a ?b - spot)
    :precondition (and (at ?u ?a) (next ?a ?b))
    :effect (and (at ?u ?b) (not (at ?u ?a)) (watched ?b)))
  (:action look :parameters (?u - uav ?s - spot)
    :precondition (at ?u ?s)
    :effect (watched ?s)))";

/// The checkpoints of the route: its drive nodes at least [`SPACING_M`] apart (and the
/// last), world points.
pub fn checkpoints(brief: &Brief) -> Vec<[f64; 3]> {
    let mut out: Vec<[f64; 3]> = Vec::new();
    let pts: Vec<[f64; 3]> = brief
        .route
        .iter()
        .filter_map(|&n| brief.node_point(Mode::Drive, n))
        .collect();
    for (i, p) in pts.iter().enumerate() {
        let far = out
            .last()
            .is_none_or(|q| libm::hypot(p[0] - q[0], p[1] - q[1]) >= SPACING_M);
        if far || i + 1 == pts.len() {
            out.push(*p);
        }
    }
    out
}

/// Index of the checkpoint nearest to `p`.
pub fn nearest(points: &[[f64; 3]], p: [f64; 3]) -> usize {
    (0..points.len())
        .min_by(|&a, &b| {
            let d = |i: usize| libm::hypot(points[i][0] - p[0], points[i][1] - p[1]);
            d(a).total_cmp(&d(b)).then(a.cmp(&b))
        })
        .unwrap_or(0)
}

/// One step of a Vidar: fly to checkpoint `spot` (or stay over it) and watch it.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize, Deserialize)]
pub struct CoverStep {
    /// The plan step it carries out.
    pub step: StepRef,
    /// The checkpoint to watch.
    pub spot: usize,
}

impl CoverStep {
    /// The step as a plan message word: `version.index:spot`.
    pub fn word(&self) -> String {
        format!("{}.{}:{}", self.step.version, self.step.index, self.spot)
    }
    /// A plan message word read back (`None`: not one).
    pub fn parse(word: &str) -> Option<CoverStep> {
        let (step, spot) = word.split_once(':')?;
        let (v, i) = step.split_once('.')?;
        Some(CoverStep {
            step: StepRef {
                version: v.parse().ok()?,
                index: i.parse().ok()?,
            },
            spot: spot.parse().ok()?,
        })
    }
}

/// The checkpoint a ground action `(hop v a b)` / `(look v s)` watches: its last word.
fn spot_of(action: &str) -> Option<usize> {
    let last = action.trim_end_matches(')').split_whitespace().last()?;
    last.strip_prefix('c')?.parse().ok()
}

/// The station of Vidar `i` at the end of a route of `points` checkpoints: the last
/// checkpoint for the lead, one before it for the next, and so on.
pub fn station(points: usize, i: usize) -> usize {
    points.saturating_sub(1).saturating_sub(i)
}

fn strategy(s: RepairStrategy) -> Strategy {
    match s {
        RepairStrategy::Replan => Strategy::Replan,
        RepairStrategy::BackOnTrack => Strategy::BackOnTrack,
        RepairStrategy::Lazy => Strategy::Lazy,
        RepairStrategy::RepeatedLazy => Strategy::RepeatedLazy,
    }
}

/// The lead Vidar's side of the cover plan: what it believes, the repairer, the counts.
#[derive(Clone, Debug, Serialize, Deserialize)]
pub struct CoverPlanner {
    /// The Vidars, in team order (the lead first).
    pub team: Vec<EntityId>,
    /// The checkpoints (world points).
    pub points: Vec<[f64; 3]>,
    settings: RepairSettings,
    repairer: Option<Repairer>,
    /// Checkpoints reported watched.
    watched: BTreeSet<usize>,
    /// Vidars (team indices) taken for lost.
    lost: BTreeSet<usize>,
    /// When each Vidar's current due step became due, or its last report (seconds).
    due_since: BTreeMap<usize, f64>,
    /// The checkpoint the truck was last believed at.
    passed: usize,
    /// The plan as first made (for the viewer: original against repaired).
    pub original: Vec<String>,
    /// The pending steps of the current plan, as PDDL actions.
    pub current: Vec<String>,
    /// Plan messages sent to the other Vidars.
    pub messages: u64,
    /// Failures detected (failed or overdue looks, lost Vidars).
    pub failures: u64,
    /// Checkpoints the truck passed with no look reported.
    pub missed: u64,
    /// Failures heard since the last turn.
    inbox: Vec<Cause>,
    /// Reports heard (looks, recalls, lost Vidars): news for a stuck plan.
    heard: u64,
    /// The truck's checkpoint and the reports heard when the last plan end found no plan.
    stuck: Option<(usize, u64)>,
}

impl CoverPlanner {
    /// A planner for `team` over `brief`'s route.
    pub fn new(brief: &Brief, team: Vec<EntityId>) -> Self {
        CoverPlanner {
            team,
            points: checkpoints(brief),
            settings: RepairSettings {
                strategy: strategy(brief.repair.strategy),
                max_expansions: Some(MAX_EXPANSIONS),
                max_depth: brief.repair.max_depth.map(|d| d as usize),
            },
            repairer: None,
            watched: BTreeSet::new(),
            lost: BTreeSet::new(),
            due_since: BTreeMap::new(),
            passed: 0,
            original: Vec::new(),
            current: Vec::new(),
            messages: 0,
            failures: 0,
            missed: 0,
            inbox: Vec::new(),
            heard: 0,
            stuck: None,
        }
    }

    /// The repairer's counts (repairs, cuts, fallbacks, ...), none before the first plan.
    pub fn tally(&self) -> RepairTally {
        self.repairer
            .as_ref()
            .map(Repairer::tally)
            .unwrap_or_default()
    }

    /// The goal with the truck at checkpoint `k`: every checkpoint ahead watched (nearest
    /// first), then each working Vidar at its station.
    fn goal(&self, k: usize) -> Vec<String> {
        let n = self.points.len();
        let looks = (k + 1..n).map(|c| format!("(watched c{c})"));
        let stations = (0..self.team.len())
            .filter(|i| !self.lost.contains(i))
            .map(|i| format!("(at v{i} c{})", station(n, i)));
        looks.chain(stations).collect()
    }

    /// The PDDL problem from the Vidars at checkpoints `at` to the goal at `k`.
    fn problem(&self, at: &[usize], k: usize) -> String {
        let mut s = String::from("(define (problem cover-now) (:domain cover) (:objects");
        for i in 0..self.team.len() {
            s.push_str(&format!(" v{i}"));
        }
        s.push_str(" - uav");
        for c in 0..self.points.len() {
            s.push_str(&format!(" c{c}"));
        }
        s.push_str(" - spot) (:init");
        for (i, c) in at.iter().enumerate() {
            s.push_str(&format!(" (at v{i} c{c})"));
        }
        for c in 1..self.points.len() {
            s.push_str(&format!(" (next c{} c{c}) (next c{c} c{})", c - 1, c - 1));
            if c >= 2 {
                s.push_str(&format!(" (next c{} c{c})", c - 2));
            }
        }
        s.push_str(") (:goal (and");
        for g in self.goal(k) {
            s.push(' ');
            s.push_str(&g);
        }
        s.push_str(")))");
        s
    }

    /// Makes the first plan, the truck at checkpoint `k`, the Vidars at `at`: the steps to
    /// send (team index, its steps).
    ///
    /// # Errors
    /// When the cover problem has no plan (e.g. a route of one checkpoint).
    pub fn start(
        &mut self,
        k: usize,
        at: &[usize],
        now_s: f64,
    ) -> Result<Vec<(usize, Vec<CoverStep>)>, RepairError> {
        let text = self.problem(at, k);
        let scenario = Scenario::from_pddl(
            PddlSource::new("cover.pddl", DOMAIN),
            PddlSource::new("cover-now.pddl", &text),
            &Ownership::first_parameter(),
        )?;
        let mut r = Repairer::new(&scenario, self.settings);
        let tell = r.start();
        self.original = r.pending().into_iter().map(|s| s.action).collect();
        self.repairer = Some(r);
        self.passed = k;
        for i in 0..self.team.len() {
            self.due_since.insert(i, now_s);
        }
        Ok(self.orders(&tell))
    }

    /// The steps of each agent of `tell`, to send.
    fn orders(&mut self, tell: &[usize]) -> Vec<(usize, Vec<CoverStep>)> {
        let Some(r) = &self.repairer else {
            return Vec::new();
        };
        self.current = r.pending().into_iter().map(|s| s.action).collect();
        tell.iter()
            .map(|&i| {
                let steps = r
                    .steps_of(i)
                    .into_iter()
                    .filter_map(|s| {
                        Some(CoverStep {
                            step: s.id,
                            spot: spot_of(&s.action)?,
                        })
                    })
                    .collect();
                (i, steps)
            })
            .collect()
    }

    /// The index of `id` in the team.
    pub fn index_of(&self, id: EntityId) -> Option<usize> {
        self.team.iter().position(|&t| t == id)
    }

    /// A look reported by Vidar `i`: the step is over; a failed look is a failure (for the
    /// next turn).
    pub fn report(&mut self, i: usize, step: CoverStep, ok: bool, now_s: f64) {
        self.heard += 1;
        let Some(r) = self.repairer.as_mut() else {
            return;
        };
        r.done(step.step);
        self.due_since.insert(i, now_s);
        if ok {
            self.watched.insert(step.spot);
        } else {
            self.failures += 1;
            self.inbox.push(Cause::Failed(step.step));
        }
    }

    /// Vidar `i` is lost (recalled, or no fresh report): a failure, once (the lead is never
    /// taken for lost).
    pub fn lost(&mut self, i: usize) {
        if i != 0 && self.repairer.is_some() && self.lost.insert(i) {
            self.heard += 1;
            self.failures += 1;
            self.inbox.push(Cause::Lost(i));
        }
    }

    /// Whether Vidar `i` is taken for lost.
    pub fn is_lost(&self, i: usize) -> bool {
        self.lost.contains(&i)
    }

    /// Whether the first plan is made.
    pub fn started(&self) -> bool {
        self.repairer.is_some()
    }

    /// One turn of the lead: the truck at checkpoint `k`, the Vidars believed at `at`
    /// (none: no fresh report). Takes the failures heard since the last turn, finds overdue
    /// looks and the plan's end, repairs, and returns the steps to send.
    ///
    /// # Errors
    /// [`RepairError`] only for a fact the task lacks (a bug, not an input).
    pub fn turn(
        &mut self,
        k: usize,
        at: &[Option<usize>],
        now_s: f64,
    ) -> Result<Vec<(usize, Vec<CoverStep>)>, RepairError> {
        let goal = self.goal(k);
        let mut causes = std::mem::take(&mut self.inbox);
        let Some(r) = self.repairer.as_mut() else {
            return Ok(Vec::new());
        };
        // Checkpoints the truck passed unwatched.
        for c in self.passed + 1..=k.min(self.points.len().saturating_sub(1)) {
            if !self.watched.contains(&c) {
                self.missed += 1;
            }
        }
        self.passed = self.passed.max(k);
        // Overdue looks: the first pending step of a working Vidar, due, unreported.
        for i in 0..self.team.len() {
            if self.lost.contains(&i) {
                continue;
            }
            let first = r.steps_of(i).into_iter().next();
            let Some(s) = first else {
                self.due_since.insert(i, now_s);
                continue;
            };
            let Some(spot) = spot_of(&s.action) else {
                continue;
            };
            let back = at.get(i).copied().flatten().is_some_and(|h| spot < h);
            if spot > k + AHEAD && !back {
                self.due_since.insert(i, now_s);
                continue;
            }
            let since = *self.due_since.entry(i).or_insert(now_s);
            if i != 0 && now_s - since > OVERDUE_S {
                // Taken for done, and failed.
                r.done(s.id);
                self.failures += 1;
                self.due_since.insert(i, now_s);
                causes.push(Cause::Failed(s.id));
            }
        }
        if r.is_finished() {
            causes.push(Cause::PlanEnd);
        }
        // What the lead believes: where each working Vidar is, what was watched.
        let mut belief: Vec<String> = Vec::new();
        for (i, a) in at.iter().enumerate() {
            if let Some(c) = a
                && !self.lost.contains(&i)
            {
                belief.push(format!("(at v{i} c{c})"));
            }
        }
        belief.extend(self.watched.iter().map(|c| format!("(watched c{c})")));
        let belief: Vec<&str> = belief.iter().map(String::as_str).collect();
        let goal: Vec<&str> = goal.iter().map(String::as_str).collect();
        let mut tell: BTreeSet<usize> = BTreeSet::new();
        let mut replaced = false;
        let news = (k, self.heard);
        for cause in causes {
            if replaced && matches!(cause, Cause::Failed(_) | Cause::PlanEnd) {
                // The plan was made again from the belief: the failure is in it.
                continue;
            }
            if cause == Cause::PlanEnd && self.stuck == Some(news) {
                // Nothing new since the last plan end found no plan.
                continue;
            }
            // No plan to the whole goal (a Vidar lost, budgets spent): the nearer half.
            let mut to = goal.len();
            let mut cause = cause;
            let rev = loop {
                let Some(rev) = r.repair(cause, &belief, &goal[..to])? else {
                    break None;
                };
                if rev.found || to <= 1 {
                    break Some(rev);
                }
                to /= 2;
                cause = Cause::PlanEnd;
            };
            let Some(rev) = rev else { continue };
            self.stuck = (!rev.found).then_some(news);
            replaced |= rev.kind != vitro_algo::repair::RepairKind::BackOnTrack || rev.fell_back;
            tell.extend(rev.tell);
        }
        let tell: Vec<usize> = tell.into_iter().collect();
        Ok(self.orders(&tell))
    }
}

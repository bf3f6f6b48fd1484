//! The Vidars' cover plan: the helicopters keep checkpoints ahead of the team, by a plan
//! that the lead Vidar makes with the PDDL planner ([`vitro_algo::planning`]) and repairs
//! as the team moves.
//!
//! The route is cut into checkpoints about [`SPACING_M`] apart, joined in a chain. The goal
//! while the team is at checkpoint `k` puts Vidar `i` at checkpoint `k + 1 + 2i`. A plan is a
//! sequence of `(fly ?uav ?from ?to)` actions between neighbouring checkpoints; each Vidar
//! flies its own steps. When the team reaches a new checkpoint the goal moves and the lead
//! repairs the plan by the scenario's strategy:
//!
//! - `replan`: a new plan from where the Vidars are now to the new goal; every Vidar with
//!   steps gets its whole new part (it drops what it had).
//! - `lazy` and `repeated_lazy`: the current plan is kept; the lead plans from the state at
//!   its end (the old goal) to the new goal and sends each Vidar only its new steps, which it
//!   appends. (In the mission every plan is executed lazily, so the two coincide here.)
//! - `back_on_track`: as lazy, but first a plan from where the Vidars are now back to the
//!   state the old plan leads to, for any Vidar off its plan (e.g. blown off by the
//!   dynamics), then the extension.
//!
//! `max_depth` bounds a repair plan's length: a longer one is cut to its first `max_depth`
//! steps (the rest is planned at the next repair), and the cut is counted.

use crate::brief::Brief;
use serde::{Deserialize, Serialize};
use vitro::entity::EntityId;
use vitro_algo::planning::{PddlSource, Planner, solve};
use vitro_site::map::Mode;
use vitro_tactical::scenario::RepairStrategy;

/// Spacing of the checkpoints along the route, metres.
pub const SPACING_M: f64 = 150.0;

const DOMAIN: &str = "(define (domain cover) (:requirements :strips :typing)
  (:types uav spot)
  (:predicates (at ?u - uav ?s - spot) (next ?a ?b - spot))
  (:action fly :parameters (?u - uav ?a ?b - spot)
    :precondition (and (at ?u ?a) (next ?a ?b))
    :effect (and (at ?u ?b) (not (at ?u ?a)))))";

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

/// What a repair produced: each Vidar's new steps (checkpoint indices) and whether they
/// replace its current steps.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct Repair {
    /// Per Vidar (in team order): the checkpoints to fly to, in order.
    pub steps: Vec<Vec<usize>>,
    /// True: the steps replace the old ones; false: they are appended.
    pub replace: bool,
    /// States the planner expanded.
    pub expanded: u64,
    /// True if `max_depth` cut the plan.
    pub cut: bool,
}

/// The lead Vidar's planner state.
#[derive(Clone, Debug, Serialize, Deserialize)]
pub struct CoverPlanner {
    /// The Vidars, in team order (the lead first).
    pub team: Vec<EntityId>,
    /// The checkpoints (world points).
    pub points: Vec<[f64; 3]>,
    strategy: RepairStrategy,
    max_depth: Option<u32>,
    /// The goal of the current plan (a checkpoint per Vidar), if there is a plan.
    pub goal: Option<Vec<usize>>,
    /// The plan as first made (for the viewer: original against repaired).
    pub original: Vec<String>,
    /// The steps of the current plan, as PDDL actions.
    pub current: Vec<String>,
    /// Repairs made (plans after the first).
    pub repairs: u64,
    /// Repairs whose plan `max_depth` cut.
    pub cuts: u64,
    /// Plan messages sent to the other Vidars.
    pub messages: u64,
    /// The last plan was cut: the next one starts from where the Vidars are.
    from_now: bool,
}

impl CoverPlanner {
    /// A planner for `team` over `brief`'s route.
    pub fn new(brief: &Brief, team: Vec<EntityId>) -> Self {
        CoverPlanner {
            team,
            points: checkpoints(brief),
            strategy: brief.repair.strategy,
            max_depth: brief.repair.max_depth,
            goal: None,
            original: Vec::new(),
            current: Vec::new(),
            repairs: 0,
            cuts: 0,
            messages: 0,
            from_now: false,
        }
    }

    /// The goal while the team is at checkpoint `k`.
    pub fn goal_for(&self, k: usize) -> Vec<usize> {
        let last = self.points.len().saturating_sub(1);
        (0..self.team.len())
            .map(|i| (k + 1 + 2 * i).min(last))
            .collect()
    }

    fn problem(&self, from: &[usize], to: &[usize]) -> String {
        let mut s = String::from("(define (problem cover-now) (:domain cover) (:objects");
        for i in 0..self.team.len() {
            s.push_str(&format!(" v{i}"));
        }
        s.push_str(" - uav");
        for c in 0..self.points.len() {
            s.push_str(&format!(" c{c}"));
        }
        s.push_str(" - spot) (:init");
        for (i, c) in from.iter().enumerate() {
            s.push_str(&format!(" (at v{i} c{c})"));
        }
        for c in 1..self.points.len() {
            s.push_str(&format!(" (next c{} c{c}) (next c{c} c{})", c - 1, c - 1));
        }
        s.push_str(") (:goal (and");
        for (i, c) in to.iter().enumerate() {
            s.push_str(&format!(" (at v{i} c{c})"));
        }
        s.push_str(")))");
        s
    }

    /// Plans from `from` to `to`: the PDDL actions, cut to `max_depth` if set.
    fn plan(&mut self, from: &[usize], to: &[usize]) -> Option<(Vec<String>, u64, bool)> {
        if from == to {
            return Some((Vec::new(), 0, false));
        }
        let text = self.problem(from, to);
        let r = solve(
            PddlSource::new("cover.pddl", DOMAIN),
            PddlSource::new("cover-now.pddl", &text),
            Planner::Satisficing,
        )
        .ok()?;
        let mut plan = r.plan;
        let mut cut = false;
        if let Some(d) = self.max_depth
            && plan.len() > d as usize
        {
            plan.truncate(d as usize);
            cut = true;
        }
        Some((plan, r.expanded, cut))
    }

    /// Makes or repairs the plan for the team at checkpoint `k`, the Vidars now nearest to
    /// checkpoints `now`. `None` if the goal did not move (or no plan exists).
    pub fn update(&mut self, k: usize, now: &[usize]) -> Option<Repair> {
        let goal = self.goal_for(k);
        if self.goal.as_ref() == Some(&goal) {
            return None;
        }
        let first = self.goal.is_none();
        let (actions, expanded, cut, replace) = match (&self.goal, self.strategy) {
            (None, _) | (_, RepairStrategy::Replan) => {
                let (p, e, c) = self.plan(now, &goal)?;
                (p, e, c, true)
            }
            (Some(old), RepairStrategy::Lazy | RepairStrategy::RepeatedLazy) => {
                let old = if self.from_now {
                    now.to_vec()
                } else {
                    old.clone()
                };
                let (p, e, c) = self.plan(&old, &goal)?;
                (p, e, c, false)
            }
            (Some(old), RepairStrategy::BackOnTrack) => {
                let old = if self.from_now {
                    now.to_vec()
                } else {
                    old.clone()
                };
                // Back to where the old plan leads, from where the Vidars are (only those
                // off their plan need steps), then on to the new goal.
                let (mut p, e1, c1) = self.plan(now, &old)?;
                let (q, e2, c2) = self.plan(&old, &goal)?;
                p.extend(q);
                (p, e1 + e2, c1 || c2, true)
            }
        };
        let mut steps = vec![Vec::new(); self.team.len()];
        for a in &actions {
            // "(fly v<i> c<a> c<b>)"
            let words: Vec<&str> = a
                .trim_matches(|c| c == '(' || c == ')')
                .split_whitespace()
                .collect();
            let i = words
                .get(1)
                .and_then(|w| w.strip_prefix('v')?.parse::<usize>().ok());
            let c = words
                .get(3)
                .and_then(|w| w.strip_prefix('c')?.parse::<usize>().ok());
            if let (Some(i), Some(c)) = (i, c)
                && i < steps.len()
            {
                steps[i].push(c);
            }
        }
        if first {
            self.original = actions.clone();
        } else {
            self.repairs += 1;
        }
        if cut {
            self.cuts += 1;
        }
        if replace {
            self.current = actions;
        } else {
            self.current.extend(actions);
        }
        self.from_now = cut;
        self.goal = Some(goal);
        Some(Repair {
            steps,
            replace,
            expanded,
            cut,
        })
    }
}

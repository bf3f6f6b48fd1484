//! The Skeldars' randomised patrol around the convoy: a patrolling security game
//! ([`vitro_algo::patrol`]) made and solved once when the mission is built
//! ([`PatrolGame::build`]), then played one step at a time by each Skeldar, phase-locked to
//! the truck's actual progress ([`PatrolGame::lock`]).
//!
//! # The game
//!
//! - **Vertices**: checkpoints of the route, its drive nodes about [`SPACING_M`] apart (as
//!   the Vidars' checkpoints); where the route comes back within half a spacing of a
//!   checkpoint already taken, that one is reused. **Edges**: checkpoints a Skeldar flies
//!   between within one patrol step (`patrol.step_s`; straight-line distance at most
//!   [`REACH_SHARE`] of its cruise speed times the step), and consecutive checkpoints along
//!   the route.
//! - **The convoy's timetable**: where the truck is expected at each step — the discrete
//!   level's speed profile of each drive leg (the truck stops at the end of every leg), the
//!   pickup at the safehouse (the troopers walk to the VIP, `mission.pickup_s`, and walk
//!   back), then the legs to the extraction point — as its nearest checkpoint. A game's
//!   timetable repeats, so after the extraction point the convoy "returns" to the start along
//!   a shortest path of the patrol graph; the mission never plays those phases (the phase
//!   stops at the extraction point).
//! - **Targets**: the convoy, and the route ahead of it: the convoy's own timetable
//!   `patrol.horizon` steps later (where an ambush laid now meets it). Each is worth 1; an
//!   attack takes `patrol.attack_steps` steps and is caught if a Skeldar stands on its
//!   target's checkpoint at one of them.
//! - **Solved** by [`PatrolPlan::solve`] (phase-locked time-dependent policies, one per
//!   Skeldar), with restarts seeded from the mission's seed.
//!
//! With the convoy alone, the game is trivial: a Skeldar (25 m/s) outruns the truck and
//! catches every attack by riding with it, a deterministic patrol. The route ahead is what
//! makes it spread out, at random, between the convoy and the road it is about to drive.

use crate::entity::route::Track;
use crate::evac::MissionError;
use crate::evac::brief::Brief;
use crate::geo::{P2, dist};
use crate::map::Mode;
use crate::types::{GroundKind, TroopKind, TypeBook, VtolKind};
use rand::Rng;
use std::sync::{Arc, Mutex};
use vitro::env::NodeId as StreetNode;
use vitro_algo::graph::{Graph, NodeId};
use vitro_algo::patrol::{PatrolPlan, PlanParams, Target, TargetPosition};

/// Spacing of the patrol checkpoints along the route, metres.
pub const SPACING_M: f64 = super::cover::SPACING_M;
/// Share of the distance a Skeldar cruises in one patrol step that an edge may span (the
/// rest is left for turns and acceleration).
pub const REACH_SHARE: f64 = 0.8;
/// LP iterations of each local search of the solver: the mission's games settle within a
/// handful, and the mission is built thousands of times in a batch.
pub const SOLVER_ITERATIONS: usize = 10;
/// How far (metres along the route) the truck may be from where the timetable expects it
/// before the patrol holds (late) or skips ahead (early): half a checkpoint spacing, the
/// game's own resolution.
pub const LOCK_TOLERANCE_M: f64 = SPACING_M / 2.0;
/// Periods of the timetable the occupancy iteration runs before it averages (burn-in), and
/// then averages over.
const OCCUPANCY_PERIODS: usize = 64;

/// The patrol game of a mission, solved: what every Skeldar flies by.
#[derive(Clone, Debug)]
pub struct PatrolGame {
    /// The checkpoints (the game's vertices): world points on the ground.
    pub points: Vec<[f64; 3]>,
    /// The convoy's expected distance along the route at each step of its trip, metres
    /// (step 0 at the start, the last at the extraction point).
    pub timetable: Vec<f64>,
    /// The convoy's vertex at each step of the trip.
    pub trip: Vec<NodeId>,
    /// The solved plan.
    pub plan: PatrolPlan,
    /// The least capture probability over the attacks that start during the trip (the
    /// plan's own least capture probability also counts the fictional return).
    pub trip_capture_probability: f64,
    /// Seconds per step.
    pub step_s: f64,
    /// The longest edge, metres.
    pub reach_m: f64,
    /// The route's nodes, town metres.
    route: Vec<P2>,
    /// Distance along the route at each route node, metres.
    along: Vec<f64>,
    /// Per unit, per phase: where the unit is in the long run, `(vertex, probability)`.
    occupancy: Vec<Vec<Vec<(NodeId, f64)>>>,
}

impl PatrolGame {
    /// Makes and solves the patrol game of `brief`'s route for `units` Skeldars, the
    /// restarts seeded from `seed`.
    ///
    /// # Errors
    /// [`MissionError::Setup`] if the route has no drive profile, the timetable's period is
    /// too long for the solver (a very short `patrol.step_s`), or the solver fails.
    pub fn build(
        brief: &Brief,
        types: &TypeBook,
        units: usize,
        seed: u64,
    ) -> Result<PatrolGame, MissionError> {
        let setup = |e: String| MissionError::Setup(format!("patrol game: {e}"));
        let Layout {
            graph,
            town,
            trip,
            timetable,
            route,
            along,
            reach_m,
        } = Layout::new(brief, types)?;
        let p = &brief.patrol;
        let targets = targets(&graph, &trip, p.horizon as usize, p.attack_steps).map_err(setup)?;
        let plan = solve(graph, targets, units.max(1), seed).map_err(setup)?;
        let trip_capture_probability = plan
            .threats
            .iter()
            .filter(|t| t.phase < timetable.len())
            .map(|t| t.capture_probability)
            .fold(1.0, f64::min);
        let occupancy = (0..plan.units())
            .map(|u| occupancy(&plan, u))
            .collect::<Result<_, _>>()
            .map_err(setup)?;
        let points = town.iter().map(|&p| brief.site.on_ground(p)).collect();
        Ok(PatrolGame {
            points,
            timetable,
            trip,
            plan,
            trip_capture_probability,
            step_s: brief.patrol.step_s,
            reach_m,
            route,
            along,
            occupancy,
        })
    }

    /// The last phase of the trip (the convoy at the extraction point).
    pub fn last_phase(&self) -> usize {
        self.timetable.len().saturating_sub(1)
    }

    /// How far along the route a truck at world point `pos` is, metres, searching forward
    /// from `from` metres (a truck does not drive back; where the route passes near itself,
    /// the stretch ahead wins) within two steps' reach.
    pub fn progress(&self, brief: &Brief, pos: [f64; 3], from: f64) -> f64 {
        let p = brief.site.to_town([pos[0], pos[1]]);
        let first = self.along.partition_point(|&s| s <= from).saturating_sub(1);
        let limit = from + 2.0 * self.reach_m;
        let mut best = (f64::INFINITY, from);
        for i in first..self.route.len() {
            if self.along[i] > limit {
                break;
            }
            let (a, b) = (
                self.route[i],
                self.route.get(i + 1).copied().unwrap_or(self.route[i]),
            );
            let (d, t) = project(p, a, b);
            let s = self.along[i] + t * dist(a, b);
            if d < best.0 {
                best = (d, s.max(from));
            }
        }
        best.1
    }

    /// The phase of the next vertex of a Skeldar whose vertex is of `phase` (where the
    /// convoy should be now), given the truck's progress `s` (metres along the route), or
    /// `None` to hold (stay): the truck is late (not moving yet, or the pickup takes longer
    /// than planned), or the trip is over. On time: `phase + 1`. Early: one more for every
    /// moving step of the timetable the truck is already past (never past the end of the
    /// trip; the waits of the timetable are never skipped, they take their time).
    ///
    /// A truck seen at a drive node (the discrete level moves it node to node) may be
    /// anywhere up to the next node of the route, or one step's drive further at most: it
    /// counts as late only if even that is behind the timetable.
    pub fn lock(&self, phase: usize, s: f64) -> Option<usize> {
        let last = self.last_phase();
        let expected = |k: usize| self.timetable.get(k).copied().unwrap_or(f64::INFINITY);
        let step = self
            .timetable
            .windows(2)
            .map(|w| w[1] - w[0])
            .fold(0.0, f64::max);
        let next_node = self.along.iter().copied().find(|&x| x > s).unwrap_or(s);
        let at_most = next_node.min(s + step);
        if phase >= last || at_most < expected(phase) - LOCK_TOLERANCE_M {
            return None;
        }
        let mut now = phase;
        while now + 1 < last
            && expected(now + 1) > expected(now) + 1e-6
            && s >= expected(now + 1) - LOCK_TOLERANCE_M
        {
            now += 1;
        }
        Some(now + 1)
    }

    /// Where `unit` is in the long run at `phase` of its policy: world points with their
    /// probabilities (the heat map of its patrol).
    pub fn heat(&self, unit: usize, phase: usize) -> Vec<([f64; 3], f64)> {
        let Some(per_phase) = self.occupancy.get(unit) else {
            return Vec::new();
        };
        let Some(at) = per_phase.get(phase % per_phase.len().max(1)) else {
            return Vec::new();
        };
        at.iter()
            .filter_map(|&(v, p)| Some((*self.points.get(v)?, p)))
            .collect()
    }

    /// The world point of vertex `v` on the ground.
    pub fn point(&self, v: NodeId) -> Option<[f64; 3]> {
        self.points.get(v).copied()
    }
}

/// One Skeldar's place in the patrol game: a small state machine, stepped every
/// `patrol.step_s` by its aircraft ([`PatrolUnit::step`]).
#[derive(Clone, Debug)]
pub struct PatrolUnit {
    /// The solved game (shared by every Skeldar).
    pub game: Arc<PatrolGame>,
    /// Its unit in the plan.
    pub unit: usize,
    /// The vertex it flies to or hovers over, once it has one.
    pub at: Option<NodeId>,
    /// The phase of `at`: where the convoy should be when the Skeldar is there.
    pub phase: usize,
    /// The truck's progress along the route, metres.
    pub progress: f64,
    /// Steps it stayed put (the truck late, gone, or at the end of its trip).
    pub holds: u64,
    /// Steps off its policy: towards the patrol again after the truck ran early.
    pub rejoins: u64,
}

impl PatrolUnit {
    /// Unit `unit` of `game`, not started.
    pub fn new(game: Arc<PatrolGame>, unit: usize) -> Self {
        PatrolUnit {
            game,
            unit,
            at: None,
            phase: 0,
            progress: 0.0,
            holds: 0,
            rejoins: 0,
        }
    }

    /// One patrol step, the truck at `truck` (`None`: no track of it): the vertex to fly to
    /// next, or `None` to stay where it is. The first step draws where to start; the next
    /// ones draw from the policy at the phase the truck's progress gives ([`PatrolGame::lock`]).
    pub fn step<R: Rng + ?Sized>(
        &mut self,
        brief: &Brief,
        truck: Option<[f64; 3]>,
        rng: &mut R,
    ) -> Option<NodeId> {
        let Some(pos) = truck else {
            self.holds += 1;
            return None;
        };
        self.progress = self.game.progress(brief, pos, self.progress);
        let plan = &self.game.plan;
        let Some(at) = self.at else {
            let phase = self.game.lock(0, self.progress).unwrap_or(0);
            let fallback = self.game.trip.get(phase).copied().unwrap_or(0);
            let v = plan.start_vertex(self.unit, phase, rng).unwrap_or(fallback);
            (self.at, self.phase) = (Some(v), phase);
            return Some(v);
        };
        let Some(phase) = self.game.lock(self.phase, self.progress) else {
            self.holds += 1;
            return None;
        };
        let from = phase - 1;
        let on_policy = plan
            .policies
            .get(self.unit)
            .is_some_and(|p| p.moves_at(at, from).is_some());
        let Ok(next) = plan.next_vertex(self.unit, at, from, rng) else {
            self.holds += 1;
            return None;
        };
        if !on_policy {
            self.rejoins += 1;
        }
        (self.at, self.phase) = (Some(next), phase);
        Some(next)
    }
}

/// The game's board and timetable, before solving.
struct Layout {
    graph: Graph,
    /// The vertices' town points.
    town: Vec<P2>,
    /// The convoy's vertex at each step of the trip.
    trip: Vec<NodeId>,
    timetable: Vec<f64>,
    route: Vec<P2>,
    along: Vec<f64>,
    reach_m: f64,
}

impl Layout {
    fn new(brief: &Brief, types: &TypeBook) -> Result<Layout, MissionError> {
        let setup = |e: String| MissionError::Setup(format!("patrol game: {e}"));
        let cruise = types.vtol(VtolKind::Skeldar).cruise_speed;
        let reach_m = (REACH_SHARE * cruise * brief.patrol.step_s).max(1.0);
        let drive = brief.roads.of(Mode::Drive);
        let route: Vec<P2> = brief
            .route
            .iter()
            .map(|&n| drive.graph.node(n).map_or([0.0, 0.0], |s| s.pos))
            .collect();
        let along = cumulative(&route);
        let (checkpoints, vertex_of, town) = checkpoints(&route, &along);
        let graph = patrol_graph(&town, &vertex_of, reach_m).map_err(|e| setup(e.to_string()))?;
        let timetable = timetable(brief, types, &along)?;
        let trip: Vec<NodeId> = timetable
            .iter()
            .map(|&s| vertex_of[nearest_checkpoint(&checkpoints, s)])
            .collect();
        Ok(Layout {
            graph,
            town,
            trip,
            timetable,
            route,
            along,
            reach_m,
        })
    }
}

/// The game's targets: the convoy, and the route `ahead` steps ahead of it (where the
/// convoy will be then; at the extraction point near the end). Their timetables are the trip,
/// then the fictional return that closes the cycle: both go back from the extraction point
/// together, along a shortest path of the patrol graph, each to its own vertex at phase 0
/// (the first one there waits), so the return asks nothing of the patrol that the trip
/// does not.
fn targets(
    graph: &Graph,
    trip: &[NodeId],
    ahead: usize,
    deadline: u32,
) -> Result<Vec<Target>, String> {
    let last = trip.len().checked_sub(1).ok_or("empty timetable")?;
    let mut tracks = vec![("convoy", 0)];
    if ahead > 0 {
        tracks.push(("route ahead", ahead));
    }
    let mut schedules: Vec<(&str, Vec<NodeId>)> = Vec::new();
    for (name, shift) in tracks {
        let there: Vec<NodeId> = (0..=last).map(|k| trip[(k + shift).min(last)]).collect();
        let back = between(graph, trip[last], there[0])?;
        schedules.push((name, [there, back].concat()));
    }
    let period = schedules.iter().map(|s| s.1.len()).max().unwrap_or(0);
    Ok(schedules
        .into_iter()
        .map(|(name, mut schedule)| {
            let home = schedule[0];
            schedule.resize(period, home);
            Target {
                name: name.into(),
                position: TargetPosition::Schedule(schedule),
                value: 1.0,
                deadline,
            }
        })
        .collect())
}

/// The inner vertices of a shortest path of `graph` from `from` to `to` (none if they are
/// equal or adjacent), then `to` (unless equal to `from`).
fn between(graph: &Graph, from: NodeId, to: NodeId) -> Result<Vec<NodeId>, String> {
    let distance = graph.distances_from(to);
    let mut out = Vec::new();
    let mut at = from;
    while at != to {
        let d = distance
            .get(at)
            .copied()
            .flatten()
            .ok_or("the route's ends are not connected")?;
        at = graph
            .neighbors(at)
            .iter()
            .copied()
            .find(|&w| distance[w] == Some(d - 1))
            .ok_or("no shortest path back")?;
        out.push(at);
    }
    Ok(out)
}

/// What a game is solved from.
#[derive(Clone, Debug, PartialEq)]
struct GameKey {
    graph: Graph,
    targets: Vec<Target>,
    units: usize,
    seed: u64,
}

/// Plans solved in this process, most recent last: the runs of a batch share their games.
static SOLVED: Mutex<Vec<(GameKey, PatrolPlan)>> = Mutex::new(Vec::new());
/// Most plans kept in [`SOLVED`].
const SOLVED_KEPT: usize = 8;

/// Solves the game of `targets` on `graph` for `units` units with [`SOLVER_ITERATIONS`],
/// no restarts and no full-phase candidate, or returns the plan this process already solved
/// for the same game (the solver is deterministic: the same plan).
fn solve(
    graph: Graph,
    targets: Vec<Target>,
    units: usize,
    seed: u64,
) -> Result<PatrolPlan, String> {
    let key = GameKey {
        graph,
        targets,
        units,
        seed,
    };
    if let Ok(solved) = SOLVED.lock()
        && let Some((_, plan)) = solved.iter().find(|(k, _)| *k == key)
    {
        return Ok(plan.clone());
    }
    let params = PlanParams {
        phase_locked: true,
        iterations: SOLVER_ITERATIONS,
        restarts: 0,
        seed,
        full_phase_candidate: false,
    };
    let plan =
        PatrolPlan::solve(&key.graph, &key.targets, units, &params).map_err(|e| e.to_string())?;
    if let Ok(mut solved) = SOLVED.lock() {
        if solved.len() >= SOLVED_KEPT {
            solved.remove(0);
        }
        solved.push((key, plan.clone()));
    }
    Ok(plan)
}

/// Cumulative distance along a polyline at each of its points.
fn cumulative(pts: &[P2]) -> Vec<f64> {
    let mut out = Vec::with_capacity(pts.len());
    let mut run = 0.0;
    for (i, &p) in pts.iter().enumerate() {
        if i > 0 {
            run += dist(pts[i - 1], p);
        }
        out.push(run);
    }
    out
}

/// Distance from `p` to segment `a`–`b` and the position of the nearest point on it (0 at
/// `a`, 1 at `b`).
fn project(p: P2, a: P2, b: P2) -> (f64, f64) {
    let (dx, dy) = (b[0] - a[0], b[1] - a[1]);
    let len2 = dx * dx + dy * dy;
    let t = if len2 > 0.0 {
        (((p[0] - a[0]) * dx + (p[1] - a[1]) * dy) / len2).clamp(0.0, 1.0)
    } else {
        0.0
    };
    let q = [a[0] + t * dx, a[1] + t * dy];
    (dist(p, q), t)
}

/// The route's checkpoints, every [`SPACING_M`] along it (and its end): their distances
/// along the route, the vertex of each (a checkpoint within half a spacing of an earlier
/// vertex reuses it, where the route comes back), and the vertices' town points.
fn checkpoints(route: &[P2], along: &[f64]) -> (Vec<f64>, Vec<NodeId>, Vec<P2>) {
    let total = along.last().copied().unwrap_or(0.0);
    let sp = SPACING_M;
    let count = (total / sp).ceil() as usize;
    let (mut at, mut vertex_of, mut town) = (Vec::new(), Vec::new(), Vec::<P2>::new());
    for k in 0..=count {
        let s = (k as f64 * sp).min(total);
        let p = point_at(route, along, s);
        let near = (0..town.len())
            .filter(|&v| dist(town[v], p) < sp / 2.0)
            .min_by(|&a, &b| {
                dist(town[a], p)
                    .total_cmp(&dist(town[b], p))
                    .then(a.cmp(&b))
            });
        let v = near.unwrap_or_else(|| {
            town.push(p);
            town.len() - 1
        });
        at.push(s);
        vertex_of.push(v);
    }
    (at, vertex_of, town)
}

/// The point `s` metres along a polyline (clamped to its ends).
fn point_at(pts: &[P2], along: &[f64], s: f64) -> P2 {
    let i = along.partition_point(|&x| x <= s).saturating_sub(1);
    let (Some(&a), Some(&sa)) = (pts.get(i), along.get(i)) else {
        return [0.0, 0.0];
    };
    let (Some(&b), Some(&sb)) = (pts.get(i + 1), along.get(i + 1)) else {
        return a;
    };
    let t = if sb > sa {
        ((s - sa) / (sb - sa)).clamp(0.0, 1.0)
    } else {
        0.0
    };
    [a[0] + t * (b[0] - a[0]), a[1] + t * (b[1] - a[1])]
}

/// The patrol graph: vertices within `reach` metres of each other, and consecutive
/// checkpoints along the route.
fn patrol_graph(
    town: &[P2],
    vertex_of: &[NodeId],
    reach: f64,
) -> Result<Graph, vitro_algo::graph::GraphError> {
    let mut edges = Vec::new();
    for u in 0..town.len() {
        for v in u + 1..town.len() {
            if dist(town[u], town[v]) <= reach {
                edges.push((u, v));
            }
        }
    }
    edges.extend(vertex_of.windows(2).map(|w| (w[0], w[1])));
    Graph::from_edges(town.len(), &edges)
}

/// Index of the checkpoint whose distance along the route (`at`, ascending) is nearest `s`.
fn nearest_checkpoint(at: &[f64], s: f64) -> usize {
    let i = at.partition_point(|&x| x < s);
    match (i.checked_sub(1), at.get(i)) {
        (Some(a), Some(&b)) if s - at[a] <= b - s => a,
        (_, Some(_)) => i,
        (Some(a), None) => a,
        (None, None) => 0,
    }
}

/// The convoy's expected distance along the route at every step of its trip (metres): the
/// drive legs at the discrete level's speed profile, and the pickup at the safehouse.
fn timetable(brief: &Brief, types: &TypeBook, along: &[f64]) -> Result<Vec<f64>, MissionError> {
    let drive = brief.roads.of(Mode::Drive);
    let truck = types.ground(GroundKind::CargoTruck);
    // (time, distance along the route) at every route node reached, and the waits.
    let mut knots: Vec<(f64, f64)> = vec![(0.0, 0.0)];
    let (mut t0, mut from) = (0.0, 0usize);
    let ends = brief.legs_out.iter().map(|&n| (n, false));
    let ends = ends.chain(brief.legs_back.iter().map(|&n| (n, true)));
    let mut picked_up = false;
    for (end, back) in ends {
        if back && !picked_up {
            picked_up = true;
            t0 += pickup_seconds(brief, types, brief.route.get(from).copied());
            knots.push((t0, along.get(from).copied().unwrap_or(0.0)));
        }
        let Some(to) = (from..brief.route.len()).find(|&i| brief.route[i] == end) else {
            continue;
        };
        let path = &brief.route[from..=to];
        if path.len() > 1 {
            let track = Track::plan_vehicle(&brief.site, drive, path, truck, &types.speed_limits)
                .map_err(|e| MissionError::Setup(format!("patrol game: {e}")))?;
            for (j, &(p, _)) in track.nodes.iter().enumerate().take(path.len()) {
                let t = track.t.get(p).copied().unwrap_or(0.0);
                knots.push((t0 + t, along[from + j]));
            }
            t0 += track.duration();
        }
        from = to;
    }
    let steps = (t0 / brief.patrol.step_s).ceil() as usize;
    Ok((0..=steps)
        .map(|k| interpolate(&knots, k as f64 * brief.patrol.step_s))
        .collect())
}

/// The truck's wait at the safehouse, seconds: the troopers walk from it to the VIP and
/// back, and `mission.pickup_s`.
fn pickup_seconds(brief: &Brief, types: &TypeBook, safehouse: Option<StreetNode>) -> f64 {
    let walk = brief.roads.of(Mode::Walk);
    let from = safehouse
        .and_then(|n| brief.node_point(Mode::Drive, n))
        .and_then(|p| brief.walk_node(p));
    let load = types.troops.of(TroopKind::Blue).load;
    let there = from
        .and_then(|f| walk.path(f, brief.vip_node).ok())
        .and_then(|path| Track::plan_walk(&brief.site, walk, &path, &types.troops, load).ok())
        .map_or(0.0, |t| t.duration());
    2.0 * there + brief.mission.pickup_s
}

/// Piecewise-linear interpolation of `(time, value)` knots (time non-decreasing) at `t`,
/// clamped at the ends.
fn interpolate(knots: &[(f64, f64)], t: f64) -> f64 {
    let i = knots.partition_point(|k| k.0 <= t);
    match (i.checked_sub(1).map(|j| knots[j]), knots.get(i)) {
        (Some((ta, a)), Some(&(tb, b))) if tb > ta => a + (b - a) * (t - ta) / (tb - ta),
        (Some((_, a)), _) => a,
        (None, Some(&(_, b))) => b,
        (None, None) => 0.0,
    }
}

/// Where `unit` is in the long run at each phase of its policy: the distribution over its
/// states, propagated through the timetable from an even start, then averaged over
/// [`OCCUPANCY_PERIODS`] periods after as many of burn-in.
fn occupancy(plan: &PatrolPlan, unit: usize) -> Result<Vec<Vec<(NodeId, f64)>>, String> {
    let n = plan.graph.node_count();
    let period = plan.period.max(1);
    let policy = plan.policies.get(unit).ok_or("no such unit")?;
    let start = plan.vertices_at(unit, 0).map_err(|e| e.to_string())?;
    let mut d = vec![0.0; n];
    for &v in &start {
        d[v] = 1.0 / start.len() as f64;
    }
    let mut sum = vec![vec![0.0; n]; period];
    for round in 0..2 * OCCUPANCY_PERIODS {
        for (phase, acc) in sum.iter_mut().enumerate() {
            if round >= OCCUPANCY_PERIODS {
                for (a, x) in acc.iter_mut().zip(&d) {
                    *a += x;
                }
            }
            let mut next = vec![0.0; n];
            for (v, &p) in d.iter().enumerate() {
                if p > 0.0
                    && let Some(moves) = policy.moves_at(v, phase)
                {
                    for &(w, q) in moves {
                        next[w] += p * q;
                    }
                }
            }
            d = next;
        }
    }
    Ok(sum
        .into_iter()
        .map(|acc| {
            let total: f64 = acc.iter().sum();
            acc.into_iter()
                .enumerate()
                .filter(|&(_, x)| x > 1e-9 * total.max(1e-300))
                .map(|(v, x)| (v, x / total))
                .collect()
        })
        .collect())
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::evac::Mission;

    const SCENARIO: &str = concat!(
        env!("CARGO_MANIFEST_DIR"),
        "/../../scenarios/evacuation.toml"
    );

    #[test]
    #[ignore]
    fn dump_instance() {
        let m = Mission::from_file(SCENARIO, None).unwrap();
        let l = Layout::new(&m.brief, TypeBook::builtin()).unwrap();
        let mut out = String::from("[graph]\nedges = [");
        let e: Vec<String> = l
            .graph
            .edges()
            .map(|(u, v)| format!("[{u}, {v}]"))
            .collect();
        out += &e.join(", ");
        out += "]\n";
        let ahead = std::env::var("AHEAD")
            .ok()
            .and_then(|a| a.parse().ok())
            .unwrap_or(2);
        for t in targets(&l.graph, &l.trip, ahead, 3).unwrap() {
            let TargetPosition::Schedule(s) = &t.position else {
                continue;
            };
            out += &format!(
                "\n[[target]]\nname = \"{}\"\nschedule = {:?}\nvalue = 1\ndeadline = {}\n",
                t.name, s, t.deadline
            );
        }
        out += "\n[[patroller]]\n";
        eprintln!(
            "vertices {}, edges {}, trip {:?}",
            l.graph.node_count(),
            l.graph.edge_count(),
            l.timetable
        );
        std::fs::write("/work/scratch/patrol/game.toml", out).unwrap();
    }
}

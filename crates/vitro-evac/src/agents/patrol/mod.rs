//! The Skeldars' randomised patrol around the convoy: a patrolling security game
//! ([`vitro_algo::patrol`]) made and solved once when the mission is built
//! ([`PatrolGame::build`]), then played one step at a time by each Skeldar
//! ([`PatrolUnit::step`]), phase-locked to the truck's actual progress
//! ([`PatrolGame::lock`]).
//!
//! # The game
//!
//! - **Vertices**: checkpoints every [`SPACING_M`] along the route (the Vidars' spacing);
//!   where the route comes back within half a spacing of a checkpoint already taken, that
//!   one is reused. **Edges**: checkpoints a Skeldar flies between within one patrol step
//!   (`patrol.step_s`; straight-line distance at most [`REACH_SHARE`] of its cruise speed
//!   times the step), and consecutive checkpoints along the route.
//! - **The convoy's timetable**: where the truck is expected at each step — the discrete
//!   level's speed profile of each drive leg (the truck stops at the end of every leg), the
//!   pickup at the safehouse (the troopers walk to the VIP and back, `mission.pickup_s`),
//!   then the legs to the extraction point — as its nearest checkpoint.
//! - **Targets**: the convoy, and the route ahead of it: the convoy's own timetable
//!   `patrol.horizon` steps later (where an ambush laid now meets it; at the extraction
//!   point near the end). Each is worth 1; an attack takes `patrol.attack_steps` steps and
//!   is caught if a Skeldar stands on its target's checkpoint at one of them.
//! - A game's timetable repeats: after the extraction point both targets "return" together
//!   along a shortest path of the patrol graph, each to where it starts (the first there
//!   waits). The return asks no more of the patrol than the trip; the mission never plays it
//!   (the phase stops at the extraction point), and
//!   [`PatrolGame::trip_capture_probability`] leaves it out.
//! - **Solved** by [`PatrolPlan::solve`]: phase-locked time-dependent policies (one per
//!   Skeldar, independent), the local search only (`patrol.iterations` LP iterations per
//!   search, no random restarts, no full-phase candidate: on a route timetable no full-phase
//!   policy guards a convoy). The plan depends on the scenario only (its seed seeds the
//!   solver), so every run of a scenario flies the same plan, drawing its moves from its own
//!   seed; a process solves each game once ([`PatrolGame::build`] keeps the last few).
//!
//! With the convoy alone (`patrol.horizon = 0`) the game is trivial: a Skeldar (25 m/s)
//! outruns the truck and catches every attack by riding with it, a deterministic patrol. The
//! route ahead is what makes it spread out, at random, between the convoy and the road it
//! is about to drive. On the default scenario (19 checkpoints, 45 edges, a 17-step trip in a
//! 24-step period, attacks of 3 steps, the route 2 steps ahead) the least capture
//! probability is 0.5: some attack starts leave the Skeldar a coin flip between the convoy
//! and the road ahead. Solving it takes about 0.3 s of one core (release build, 5
//! iterations); the mission's setup took 0.1 s before.
//!
//! # Playing it
//!
//! Every step each Skeldar reads the truck's position (the blue-force tracker), turns it
//! into progress along the route, and compares it with the timetable: on time it draws its
//! next checkpoint from its policy at the current phase (one uniform number from its own
//! `"patrol"` stream); when the truck is late (not moving yet, a longer pickup) it stays
//! where it is, the phase held; when the truck is early the phase skips ahead and the
//! Skeldar steps towards the checkpoints of that phase ([`PatrolPlan::next_vertex`]
//! rejoins). With the truck at the extraction point, or out of track, it stays. Its heat
//! map is where its policy puts it in the long run at the current phase
//! ([`PatrolGame::heat`]).
//!
//! # The game's attacker, and when the guarantee holds
//!
//! The first `patrol.attackers` red troopers play the game's attacker ([`attack`]): briefed
//! with the policies, they watch the Skeldars and the truck and strike once, where the game
//! says. The computed capture probability of an attack is exact — the realised stop rate
//! agrees with it over many runs (`experiments/mission_patrol.toml`,
//! `scripts/patrol_table.py`) — under these conditions: (1) the attacker read the state
//! right (each Skeldar at the vertex and phase it believed); (2) through the attack's
//! `attack_steps` steps every Skeldar drew its moves from its policy, i.e. the truck kept
//! its timetable within [`LOCK_TOLERANCE_M`] (no hold, no skip, no rejoin) and the Skeldar
//! was not sent hunting; (3) the attack ends by the extraction point (the mission never
//! plays the timetable's fictional return). The report counts the attacks for which (1) and
//! (2) held (`patrol_attacks_on_schedule`). Outside them the patrol still runs (holding or
//! skipping ahead, as above, or re-solving, below) but the number is not a guarantee.
//!
//! When the truck runs off its timetable beyond the tolerance, the Skeldar re-solves the
//! game of the rest of the trip from where the truck is ([`resolve`], which also states when
//! the guarantee holds after a re-solve: the attacker is not told the new policy).
use crate::brief::Brief;
use crate::error::MissionError;
use board::{Board, project};
use rand::Rng;
pub use resolve::{MAX_RESOLVES, RESOLVE_GAP_STEPS};
use serde::{Deserialize, Serialize};
use solved::{Frame, Solved, Spec, solve_game};
use std::sync::Arc;
use steps::{CaptureTable, StepKind, StepLog};
use vitro_algo::graph::NodeId;
use vitro_algo::patrol::{PatrolPlan, Target};
use vitro_site::geo::{P2, dist};
use vitro_tactical::types::TypeBook;

pub mod attack;
mod board;
pub mod resolve;
mod solved;
pub mod steps;

pub use board::REACH_SHARE;

/// Spacing of the patrol checkpoints along the route, metres.
pub const SPACING_M: f64 = super::cover::SPACING_M;
/// How far (metres along the route) the truck may be from where the timetable expects it
/// before the patrol holds (late) or skips ahead (early): half a checkpoint spacing, the
/// game's own resolution.
pub const LOCK_TOLERANCE_M: f64 = SPACING_M / 2.0;

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
    /// The game's targets (the convoy, the route ahead).
    targets: Vec<Target>,
    /// Per unit, target and phase: the capture probability from each of its states.
    capture: CaptureTable,
    /// What it was solved with (a re-solve uses the same).
    spec: Spec,
}

impl PatrolGame {
    /// Makes and solves the patrol game of `brief`'s route for `units` Skeldars, the solver
    /// seeded from `seed`; a game this process solved already is not solved again.
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
        let Board {
            graph,
            town,
            trip,
            timetable,
            route,
            along,
            reach_m,
        } = Board::new(brief, types)?;
        let p = &brief.patrol;
        let spec = Spec {
            ahead: p.horizon as usize,
            attack_steps: p.attack_steps,
            units: units.max(1),
            iterations: p.iterations as usize,
            seed,
        };
        let points = town.iter().map(|&p| brief.site.on_ground(p)).collect();
        let frame = Frame {
            points,
            graph,
            step_s: brief.patrol.step_s,
            reach_m,
            route,
            along,
        };
        assemble(frame, timetable, trip, spec).map_err(setup)
    }

    /// The last phase of the trip (the convoy at the extraction point).
    pub fn last_phase(&self) -> usize {
        self.timetable.len().saturating_sub(1)
    }

    /// How far along the route a truck at town point `p` is, metres, searching forward from
    /// `from` metres (a truck does not drive back; where the route passes near itself, the
    /// stretch ahead wins) within two steps' reach.
    pub fn progress(&self, p: P2, from: f64) -> f64 {
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
    /// step of the timetable the truck is already past (never past the end of the trip); a
    /// wait of the timetable takes its time, unless the truck has left already.
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
        // The truck is past phase `now + 1` if it reached where the timetable then has it, or,
        // for a wait there, if it has left.
        let mut now = phase;
        while now + 1 < last {
            let (here, next) = (expected(now), expected(now + 1));
            let past = if next > here + 1e-6 {
                s >= next - LOCK_TOLERANCE_M
            } else {
                s > here + LOCK_TOLERANCE_M
            };
            if !past {
                break;
            }
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
#[derive(Clone, Debug, Serialize, Deserialize)]
pub struct PatrolUnit {
    /// The solved game (shared by every Skeldar).
    #[serde(with = "vitro_mission::snapshot::briefed")]
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
    /// Every step it took (the umpire's record, for the attacks' verdicts).
    pub log: Vec<StepLog>,
    /// Times it re-solved the game ([`PatrolUnit::resolve`]).
    #[serde(default)]
    pub resolves: u64,
    /// The step of the mission's timetable its game starts at: 0, or where its last
    /// re-solve re-timed the trip from.
    #[serde(default)]
    pub offset: usize,
    /// Its step count ([`PatrolUnit::log`]'s length) at its last re-solve.
    #[serde(default)]
    last_resolve: Option<usize>,
    /// The game it plays after a re-solve (rebuilt from `game` and `offset` after a
    /// snapshot is restored).
    #[serde(skip)]
    current: Option<Arc<PatrolGame>>,
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
            log: Vec::new(),
            resolves: 0,
            offset: 0,
            last_resolve: None,
            current: None,
        }
    }

    /// One patrol step at `now_s` seconds, the truck at town point `truck` (`None`: no
    /// track of it): the vertex to fly to next, or `None` to stay where it is. The first
    /// step draws where to start; the next ones draw from the policy at the phase the
    /// truck's progress gives ([`PatrolGame::lock`]). Every step goes to [`PatrolUnit::log`].
    pub fn step<R: Rng + ?Sized>(
        &mut self,
        truck: Option<P2>,
        now_s: f64,
        rng: &mut R,
    ) -> Option<NodeId> {
        let (next, kind) = match self.draw(truck, rng) {
            Some((v, kind)) => (Some(v), kind),
            None => (None, StepKind::Hold),
        };
        if kind == StepKind::Hold {
            self.holds += 1;
        }
        self.log.push(StepLog {
            t: now_s,
            at: self.at,
            phase: self.phase,
            kind,
            plan: self.offset,
        });
        next
    }

    /// The step's move and what kind it is (`None`: hold).
    fn draw<R: Rng + ?Sized>(
        &mut self,
        truck: Option<P2>,
        rng: &mut R,
    ) -> Option<(NodeId, StepKind)> {
        let pos = truck?;
        let game = self.playing();
        self.progress = game.progress(pos, self.progress);
        let Some(at) = self.at else {
            let phase = game.lock(0, self.progress).unwrap_or(0);
            let fallback = game.trip.get(phase).copied().unwrap_or(0);
            let v = game
                .plan
                .start_vertex(self.unit, phase, rng)
                .unwrap_or(fallback);
            (self.at, self.phase) = (Some(v), phase);
            return Some((v, StepKind::Policy));
        };
        let game = self.resolve(game);
        let plan = &game.plan;
        let phase = game.lock(self.phase, self.progress)?;
        let from = phase - 1;
        let on_policy = plan
            .policies
            .get(self.unit)
            .is_some_and(|p| p.moves_at(at, from).is_some());
        let next = plan.next_vertex(self.unit, at, from, rng).ok()?;
        let kind = if on_policy {
            StepKind::Policy
        } else {
            self.rejoins += 1;
            StepKind::Rejoin
        };
        (self.at, self.phase) = (Some(next), phase);
        Some((next, kind))
    }
}

/// Makes and solves the game of the convoy's `timetable` (its vertex at each step: `trip`)
/// on `frame`.
fn assemble(
    frame: Frame,
    timetable: Vec<f64>,
    trip: Vec<NodeId>,
    spec: Spec,
) -> Result<PatrolGame, String> {
    let Frame {
        points,
        graph,
        step_s,
        reach_m,
        route,
        along,
    } = frame;
    let Solved {
        plan,
        targets,
        capture,
        occupancy,
        trip_capture_probability,
    } = solve_game(graph, &trip, timetable.len(), spec)?;
    Ok(PatrolGame {
        points,
        timetable,
        trip,
        plan,
        trip_capture_probability,
        step_s,
        reach_m,
        route,
        along,
        occupancy,
        targets,
        capture,
        spec,
    })
}

#[cfg(test)]
mod tests {
    use super::*;
    use rand::SeedableRng;
    use rand_chacha::ChaCha8Rng;
    use vitro_algo::graph::Graph;

    /// A straight route of 8 nodes 100 m apart; checkpoints on the nodes, edges up to 200 m.
    /// The convoy waits three steps at 300 m.
    pub(super) fn game() -> PatrolGame {
        let edges: Vec<(usize, usize)> = (0..7)
            .map(|i| (i, i + 1))
            .chain((0..6).map(|i| (i, i + 2)))
            .collect();
        let graph = Graph::from_edges(8, &edges).unwrap();
        let timetable = vec![0.0, 100.0, 300.0, 300.0, 300.0, 500.0, 700.0];
        let trip: Vec<NodeId> = timetable.iter().map(|s| (s / 100.0) as usize).collect();
        let route: Vec<P2> = (0..8).map(|i| [100.0 * f64::from(i), 0.0]).collect();
        let frame = Frame {
            points: route.iter().map(|p| [p[0], p[1], 0.0]).collect(),
            graph,
            step_s: 20.0,
            reach_m: 200.0,
            along: route.iter().map(|p| p[0]).collect(),
            route,
        };
        let spec = Spec {
            ahead: 1,
            attack_steps: 2,
            units: 1,
            iterations: 5,
            seed: 0,
        };
        assemble(frame, timetable, trip, spec).unwrap()
    }

    #[test]
    fn the_phase_follows_the_truck() {
        let g = game();
        // On time, and a truck seen at a node may be up to the next one.
        assert_eq!(g.lock(0, 0.0), Some(1));
        assert_eq!(g.lock(1, 100.0), Some(2));
        assert_eq!(g.lock(1, 0.0), Some(2));
        // Late: hold.
        assert_eq!(g.lock(2, 0.0), None);
        // The wait takes its time; a pickup longer than planned holds.
        assert_eq!(g.lock(2, 300.0), Some(3));
        assert_eq!(g.lock(4, 300.0), Some(5));
        assert_eq!(g.lock(5, 300.0), None);
        // Early: ahead to the wait, not through it; through it once the truck has left.
        assert_eq!(g.lock(1, 300.0), Some(3));
        assert_eq!(g.lock(1, 500.0), Some(6));
        // The end of the trip.
        assert_eq!(g.lock(5, 700.0), Some(6));
        assert_eq!(g.lock(6, 700.0), None);
        // Progress along the route, forward only.
        assert!((g.progress([250.0, 30.0], 0.0) - 250.0).abs() < 1e-9);
        assert!((g.progress([50.0, 0.0], 250.0) - 250.0).abs() < 1e-9);
    }

    #[test]
    fn a_unit_moves_along_edges_and_its_heat_is_a_distribution() {
        let g = Arc::new(game());
        for phase in 0..g.plan.period {
            let total: f64 = g.heat(0, phase).iter().map(|h| h.1).sum();
            assert!((total - 1.0).abs() < 1e-6, "phase {phase}: {total}");
        }
        // A truck late at the start, on time, then early.
        let truck = [
            0.0, 0.0, 100.0, 300.0, 300.0, 300.0, 300.0, 500.0, 700.0, 700.0, 700.0,
        ];
        let mut rng = ChaCha8Rng::seed_from_u64(1);
        let mut unit = PatrolUnit::new(g.clone(), 0);
        let mut at = None;
        for &x in &truck {
            let (before, resolves) = (unit.phase, unit.resolves);
            if let Some(next) = unit.step(Some([x, 0.0]), 0.0, &mut rng) {
                if let Some(a) = at {
                    assert!(a == next || g.plan.graph.has_edge(a, next), "{a} -> {next}");
                }
                at = Some(next);
            }
            // The phase goes forward, or starts again with a re-solve.
            assert!(unit.phase >= before || unit.resolves > resolves);
            assert_eq!(unit.at, at);
        }
        assert_eq!(unit.phase, unit.game_now().last_phase());
        assert!(
            unit.holds + unit.resolves >= 2,
            "held {} times, re-solved {} times",
            unit.holds,
            unit.resolves
        );
        // No track of the truck: stay.
        assert_eq!(unit.step(None, 0.0, &mut rng), None);
    }
}

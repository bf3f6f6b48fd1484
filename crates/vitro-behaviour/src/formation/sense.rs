//! The sensors a squad reads the map and its surroundings through (each a
//! [`Sensor<Arena>`]: the controllers never see the arena itself).
//!
//! - [`ClearWay`]: whether a straight way keeps out of every forbidden zone;
//! - [`FreeSlot`]: a slot moved out of forbidden zones, on the leader's side of obstacles;
//! - [`SideClearance`]: free distance to the left and right across a direction (how the
//!   leader tells a street from open ground);
//! - [`WalkRoute`]: a route on the free walk graph between two points, with its Pandolf
//!   walking speeds (the squad's map and compass);
//! - [`NearestNode`]: the walk-graph node nearest to a point;
//! - [`NextNode`]: the walk-graph node a body on a node is heading for;
//! - [`Gait`]: the body's own walking speed on the level;
//! - [`Hostiles`]: red troopers in range and in line of sight.

use serde::{Deserialize, Serialize};
use vitro::entity::EntityId;
use vitro::env::{NodeId, Probe, Sensor};
use vitro_site::geo::{P2, dist};
use vitro_tactical::arena::Arena;
use vitro_tactical::entity::discrete::NodeKind;
use vitro_tactical::entity::route::Track;
use vitro_tactical::types::TroopKind;

/// Spacing of the probes along a straight way, metres. A way that clips the rounded corner
/// of a zone's buffer (radius ≥ 1 m) between two probes enters it by at most
/// `0.1² / 8` m ≈ 1.3 mm; within [`WAY_END`] of either end, where ways start and stop by
/// zone edges, probes are [`WAY_END_PROBE`] apart (at most 0.02 mm).
pub const WAY_PROBE: f64 = 0.1;
/// The stretch at each end of a way probed finely, metres.
pub const WAY_END: f64 = 0.3;
/// Spacing of the probes near the ends of a way, metres.
pub const WAY_END_PROBE: f64 = 0.01;
/// Spacing of the probes on the way from a slot's base to the slot ([`FreeSlot`]: a test of
/// which side of an obstacle the slot is on, not a way anyone walks), metres.
pub const SLOT_PROBE: f64 = 0.25;
/// How far a slot is kept from the edge of a forbidden zone where there is room, metres.
pub const SLOT_MARGIN: f64 = 0.3;

/// Spacing of the probes across a route, metres.
pub const SIDE_PROBE: f64 = 0.5;

/// Whether the straight way from `from` to `to` (world x, y) keeps out of every forbidden
/// zone, probed every [`WAY_PROBE`] metres (every [`WAY_END_PROBE`] within [`WAY_END`] of
/// either end), both ends included.
#[derive(Copy, Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct ClearWay {
    /// Start, world metres.
    pub from: P2,
    /// End, world metres.
    pub to: P2,
}

impl Sensor<Arena> for ClearWay {
    type Reading = bool;
    fn read(&self, env: &Arena, _: EntityId, _: &mut Probe<'_>) -> bool {
        clear_way(env, self.from, self.to, true)
    }
}

/// Whether the way from `a` to `b` is clear: for a way a body walks (`walked`), probed every
/// [`WAY_PROBE`] metres and finely near its ends; otherwise every [`SLOT_PROBE`] metres.
fn clear_way(env: &Arena, a: P2, b: P2, walked: bool) -> bool {
    let len = dist(a, b);
    let free = |t: f64| {
        !env.site
            .is_forbidden([a[0] + t * (b[0] - a[0]), a[1] + t * (b[1] - a[1])])
    };
    let step = if walked { WAY_PROBE } else { SLOT_PROBE };
    let n = (len / step).ceil().max(1.0) as usize;
    if !(0..=n).all(|i| free(i as f64 / n as f64)) {
        return false;
    }
    if len < 1e-9 || !walked {
        return true;
    }
    let end = WAY_END.min(len / 2.0);
    let m = (end / WAY_END_PROBE).ceil() as usize;
    (1..m).all(|i| {
        let d = i as f64 * WAY_END_PROBE / len;
        free(d) && free(1.0 - d)
    })
}

/// A slot made safe to stand in: `slot` itself if the straight way to it from `base` (the
/// point of the leader's way it is measured from) is clear; else the free point nearest to
/// it, if the way from `base` to that is clear; else the last free point of the way from
/// `base` towards `slot` (so that a slot behind a house is pulled in to the leader's side).
#[derive(Copy, Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct FreeSlot {
    /// Where the slot is measured from, world metres.
    pub base: P2,
    /// The slot before obstacles, world metres.
    pub slot: P2,
}

impl Sensor<Arena> for FreeSlot {
    type Reading = P2;
    fn read(&self, env: &Arena, _: EntityId, _: &mut Probe<'_>) -> P2 {
        let (a, b) = (self.base, self.slot);
        if clear_way(env, a, b, false) {
            return off_edge(env, a, b);
        }
        let nearest = env.site.nearest_free(b);
        if clear_way(env, a, nearest, false) {
            return off_edge(env, a, nearest);
        }
        let n = (dist(a, b) / WAY_PROBE).ceil().max(1.0) as usize;
        let at = |i: usize| {
            let t = i as f64 / n as f64;
            [a[0] + t * (b[0] - a[0]), a[1] + t * (b[1] - a[1])]
        };
        let first_blocked = (0..=n)
            .find(|&i| env.site.is_forbidden(at(i)))
            .unwrap_or(n + 1);
        if first_blocked == 0 {
            // The base itself is forbidden (the leader's way cut a corner): nearest free.
            return env.site.nearest_free(a);
        }
        at(first_blocked.saturating_sub(2))
    }
}

/// `p` moved [`SLOT_MARGIN`] away from the forbidden ground around it (probed in eight
/// directions at that distance), if the moved point is free and in a straight line from
/// `base`; `p` itself otherwise.
fn off_edge(env: &Arena, base: P2, p: P2) -> P2 {
    let mut push = [0.0, 0.0];
    for k in 0..8 {
        let a = f64::from(k) * std::f64::consts::FRAC_PI_4;
        let (s, c) = (libm::sin(a), libm::cos(a));
        if env
            .site
            .is_forbidden([p[0] + SLOT_MARGIN * c, p[1] + SLOT_MARGIN * s])
        {
            push = [push[0] - c, push[1] - s];
        }
    }
    let n = libm::hypot(push[0], push[1]);
    if n < 1e-9 {
        return p;
    }
    let q = [
        p[0] + SLOT_MARGIN * push[0] / n,
        p[1] + SLOT_MARGIN * push[1] / n,
    ];
    if clear_way(env, base, q, false) { q } else { p }
}

/// Free distance from a world point to the left and to the right of a direction, up to
/// `reach` metres: the distance to the first forbidden probe ([`SIDE_PROBE`] apart), or
/// `reach` if there is none.
#[derive(Copy, Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct SideClearance {
    /// Where, world metres.
    pub at: P2,
    /// The direction across which to look, radians from east.
    pub heading: f64,
    /// How far to look each side, metres.
    pub reach: f64,
}

impl Sensor<Arena> for SideClearance {
    /// `[left, right]`, metres.
    type Reading = [f64; 2];
    fn read(&self, env: &Arena, _: EntityId, _: &mut Probe<'_>) -> [f64; 2] {
        let (s, c) = (libm::sin(self.heading), libm::cos(self.heading));
        let steps = (self.reach / SIDE_PROBE).ceil().max(1.0) as usize;
        let side = |sign: f64| {
            (1..=steps)
                .map(|i| (i as f64 * SIDE_PROBE).min(self.reach))
                .find(|&r| {
                    env.site
                        .is_forbidden([self.at[0] - sign * r * s, self.at[1] + sign * r * c])
                })
                .unwrap_or(self.reach)
        };
        [side(1.0), side(-1.0)]
    }
}

/// A route on the walk graph.
#[derive(Clone, Debug, Default, PartialEq, Serialize, Deserialize)]
pub struct Leg {
    /// World points (on the ground), at most a metre apart; the first is where the route
    /// was asked from.
    pub pts: Vec<[f64; 3]>,
    /// Walking speed on the piece ending at each point, m/s (the body's Pandolf speed for
    /// its load and the grade).
    pub v: Vec<f64>,
    /// The walk-graph nodes passed, with the index of their point, in order.
    pub nodes: Vec<(usize, NodeId)>,
}

/// How many nearest nodes [`WalkRoute`] tries as a start.
const START_CANDIDATES: usize = 8;

/// The route on the free walk graph from a world point to the node nearest another: it
/// starts at the nearest node (of the graph's main part, among the eight nearest) that the
/// body can reach in a straight line from `from` without entering a forbidden zone, and ends
/// at the main node nearest to `to`. Speeds are those of the reading body's type (a blue
/// trooper's if it has no trooper body). `None` if no near node is in a straight line or
/// there is no route.
#[derive(Copy, Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct WalkRoute {
    /// From, world metres.
    pub from: P2,
    /// To, world metres.
    pub to: P2,
}

impl Sensor<Arena> for WalkRoute {
    type Reading = Option<Leg>;
    fn read(&self, env: &Arena, me: EntityId, _: &mut Probe<'_>) -> Option<Leg> {
        let walk = &env.roads.walk;
        let site = &env.site;
        let near = nearest_nodes(env, self.from, START_CANDIDATES);
        let start = near
            .iter()
            .copied()
            .find(|&(_, p)| clear_way(env, self.from, p, true))?
            .0;
        let goal = walk.nearest_connected(site.to_town(self.to))?;
        let path = walk.path(start, goal).ok()?;
        let kind = troop_kind(env, me).unwrap_or(TroopKind::Blue);
        let troops = &env.types.troops;
        let track = Track::plan_walk(site, walk, &path, troops, troops.of(kind).load).ok()?;
        let mut leg = Leg::default();
        let first = track.pts.first().copied()?;
        if dist(self.from, [first[0], first[1]]) > 1e-6 {
            let z = site.ground(self.from).unwrap_or(first[2]);
            leg.pts.push([self.from[0], self.from[1], z]);
            leg.v
                .push(track.v.first().copied().unwrap_or(troops.min_speed));
        }
        let shift = leg.pts.len();
        leg.pts.extend(&track.pts);
        leg.v.extend(
            track
                .v
                .iter()
                .map(|&v| if v > 0.0 { v } else { troops.min_speed }),
        );
        leg.nodes = track.nodes.iter().map(|&(i, n)| (i + shift, n)).collect();
        Some(leg)
    }
}

/// The `k` nodes of the walk graph's main part nearest to world point `p`, nearest first
/// (ties to the lower id), with their world positions.
fn nearest_nodes(env: &Arena, p: P2, k: usize) -> Vec<(NodeId, P2)> {
    let walk = &env.roads.walk;
    let town = env.site.to_town(p);
    let mut all: Vec<(f64, NodeId, P2)> = (0..walk.graph.node_count() as u32)
        .map(NodeId)
        .filter(|n| walk.main.get(n.0 as usize).copied().unwrap_or(false))
        .filter_map(|n| walk.graph.node(n).map(|s| (dist(town, s.pos), n, s.pos)))
        .collect();
    let k = k.min(all.len());
    if k == 0 {
        return Vec::new();
    }
    let cmp =
        |a: &(f64, NodeId, P2), b: &(f64, NodeId, P2)| a.0.total_cmp(&b.0).then(a.1.cmp(&b.1));
    all.select_nth_unstable_by(k - 1, cmp);
    all.truncate(k);
    all.sort_by(cmp);
    all.into_iter()
        .map(|(_, n, q)| (n, env.site.to_world(q)))
        .collect()
}

/// The node of the walk graph's main part nearest to a world point, with its world
/// position.
#[derive(Copy, Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct NearestNode(pub P2);

impl Sensor<Arena> for NearestNode {
    type Reading = Option<(NodeId, P2)>;
    fn read(&self, env: &Arena, _: EntityId, _: &mut Probe<'_>) -> Option<(NodeId, P2)> {
        let walk = &env.roads.walk;
        let n = walk.nearest_connected(env.site.to_town(self.0))?;
        let p = walk.graph.node(n)?.pos;
        Some((n, env.site.to_world(p)))
    }
}

/// The walk-graph node next to the node at world point `from` whose bearing from it is
/// `heading` (within 0.05 rad), with its world position: where a body hopping from that
/// node along that heading is going (a walk-graph hop is a straight piece between nodes).
/// `None` if no neighbour lies that way.
#[derive(Copy, Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct NextNode {
    /// The node the body hops from, world metres.
    pub from: P2,
    /// Its heading, radians from east.
    pub heading: f64,
}

impl Sensor<Arena> for NextNode {
    type Reading = Option<(NodeId, P2)>;
    fn read(&self, env: &Arena, _: EntityId, _: &mut Probe<'_>) -> Option<(NodeId, P2)> {
        let walk = &env.roads.walk;
        let at = env.site.to_town(self.from);
        let n = walk.nearest_connected(at)?;
        let p = walk.graph.node(n)?.pos;
        walk.graph
            .neighbors(n)
            .filter_map(|(v, _, _)| {
                let q = walk.graph.node(v)?.pos;
                let bearing = libm::atan2(q[1] - p[1], q[0] - p[0]);
                let off = vitro_tactical::entity::route::wrap_angle(bearing - self.heading).abs();
                (off < 0.05).then_some((off, v, q))
            })
            .min_by(|a, b| a.0.total_cmp(&b.0).then(a.1.cmp(&b.1)))
            .map(|(_, v, q)| (v, env.site.to_world(q)))
    }
}

fn troop_kind(env: &Arena, id: EntityId) -> Option<TroopKind> {
    if let Some(w) = env.walkers.get(id) {
        return Some(w.kind);
    }
    match env.at_node.get(id)?.kind {
        NodeKind::Troop(k) => Some(k),
        NodeKind::Ground(_) => None,
    }
}

/// The body's own walking speed on the level, m/s (Pandolf, for its type's load); `None`
/// without a trooper body.
#[derive(Copy, Clone, Debug, Default, PartialEq, Serialize, Deserialize)]
pub struct Gait;

impl Sensor<Arena> for Gait {
    type Reading = Option<f64>;
    fn read(&self, env: &Arena, me: EntityId, _: &mut Probe<'_>) -> Option<f64> {
        let t = &env.types.troops;
        Some(t.walking_speed(t.of(troop_kind(env, me)?).load, 0.0))
    }
}

/// A red trooper seen.
#[derive(Copy, Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct Hostile {
    /// Who.
    pub id: EntityId,
    /// Where, world metres.
    pub pos: [f64; 3],
}

/// Red troopers (either level) within `range` metres (3D) whose centre is in line of sight
/// from the observer's eye (terrain and buildings), in id order. Deterministic: no
/// detection draw.
#[derive(Copy, Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct Hostiles {
    /// Range, metres.
    pub range: f64,
}

impl Sensor<Arena> for Hostiles {
    type Reading = Vec<Hostile>;
    fn read(&self, env: &Arena, me: EntityId, _: &mut Probe<'_>) -> Vec<Hostile> {
        let Some(mine) = env.pose(me) else {
            return Vec::new();
        };
        let h = env.types.troops.height;
        let eye = [mine.pos[0], mine.pos[1], mine.pos[2] + h];
        let reds = env
            .walkers
            .iter()
            .filter(|(_, b)| b.kind == TroopKind::Red)
            .map(|(id, _)| id)
            .chain(
                env.at_node
                    .iter()
                    .filter(|(_, b)| b.kind == NodeKind::Troop(TroopKind::Red))
                    .map(|(id, _)| id),
            );
        let mut out: Vec<Hostile> = reds
            .filter(|&id| id != me)
            .filter_map(|id| env.pose(id).map(|p| (id, p.pos)))
            .filter(|&(_, p)| {
                let d = [p[0] - eye[0], p[1] - eye[1], p[2] + h / 2.0 - eye[2]];
                libm::sqrt(d[0] * d[0] + d[1] * d[1] + d[2] * d[2]) <= self.range
                    && env.site.los.visible(eye, [p[0], p[1], p[2] + h / 2.0])
            })
            .map(|(id, pos)| Hostile { id, pos })
            .collect();
        out.sort_by_key(|h| h.id);
        out
    }
}

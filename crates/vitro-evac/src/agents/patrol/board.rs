//! The patrol game's board: the route's checkpoints and the patrol graph, the convoy's
//! timetable, and the targets.

use crate::agents::cover::SPACING_M;
use crate::brief::Brief;
use crate::error::MissionError;
use vitro::env::NodeId as StreetNode;
use vitro_algo::graph::{Graph, NodeId};
use vitro_algo::patrol::{Target, TargetPosition};
use vitro_site::geo::{P2, dist};
use vitro_site::map::Mode;
use vitro_tactical::entity::route::Track;
use vitro_tactical::types::{GroundKind, TroopKind, TypeBook, VtolKind};

/// Share of the distance a Skeldar cruises in one patrol step that an edge may span (the
/// rest is left for turns and acceleration).
pub const REACH_SHARE: f64 = 0.8;

/// The game's board and timetable, before solving.
pub(super) struct Board {
    /// The patrol graph (vertices: the checkpoints).
    pub graph: Graph,
    /// The vertices' town points.
    pub town: Vec<P2>,
    /// The convoy's vertex at each step of the trip.
    pub trip: Vec<NodeId>,
    /// The convoy's expected distance along the route at each step of the trip, metres.
    pub timetable: Vec<f64>,
    /// The route's nodes, town metres.
    pub route: Vec<P2>,
    /// Distance along the route at each of its nodes, metres.
    pub along: Vec<f64>,
    /// The longest edge, metres.
    pub reach_m: f64,
}

impl Board {
    /// The board of `brief`'s route for a Skeldar of `types`.
    pub fn new(brief: &Brief, types: &TypeBook) -> Result<Board, MissionError> {
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
        Ok(Board {
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
pub(super) fn targets(
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
pub(super) fn project(p: P2, a: P2, b: P2) -> (f64, f64) {
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

#[cfg(test)]
mod tests {
    use super::*;
    use vitro_algo::patrol::{Instance, Patroller};

    #[test]
    fn timetables_interpolate_and_map_to_checkpoints() {
        let knots = [(0.0, 0.0), (10.0, 100.0), (20.0, 100.0), (30.0, 200.0)];
        let at = |t| interpolate(&knots, t);
        assert_eq!(
            [at(-1.0), at(5.0), at(15.0), at(25.0), at(40.0)],
            [0.0, 50.0, 100.0, 150.0, 200.0]
        );
        let marks = [0.0, 150.0, 300.0];
        let near = |s| nearest_checkpoint(&marks, s);
        assert_eq!(
            [near(-5.0), near(70.0), near(80.0), near(290.0), near(400.0)],
            [0, 0, 1, 2, 2]
        );
    }

    #[test]
    fn checkpoints_are_spaced_and_reused_where_the_route_comes_back() {
        // Out 600 m east and back along the same street.
        let route = [[0.0, 0.0], [600.0, 0.0], [0.0, 0.0]];
        let along = cumulative(&route);
        assert_eq!(along, [0.0, 600.0, 1200.0]);
        let (at, vertex_of, town) = checkpoints(&route, &along);
        assert_eq!(at.len(), 9);
        assert_eq!(vertex_of, [0, 1, 2, 3, 4, 3, 2, 1, 0]);
        assert_eq!(town.len(), 5);
        assert_eq!(point_at(&route, &along, 750.0), [450.0, 0.0]);
        let g = patrol_graph(&town, &vertex_of, 300.0).unwrap();
        assert!(g.has_edge(0, 2) && !g.has_edge(0, 3));
    }

    #[test]
    fn targets_are_cyclic_walks_with_a_common_period() {
        let g = vitro_algo::graph::path(6).unwrap();
        let trip = [0, 1, 2, 3, 4, 5];
        let targets = targets(&g, &trip, 2, 3).unwrap();
        let schedules: Vec<&Vec<NodeId>> = targets
            .iter()
            .filter_map(|t| match &t.position {
                TargetPosition::Schedule(s) => Some(s),
                TargetPosition::Static(_) => None,
            })
            .collect();
        assert_eq!(schedules[0], &vec![0, 1, 2, 3, 4, 5, 4, 3, 2, 1, 0]);
        assert_eq!(schedules[1], &vec![2, 3, 4, 5, 5, 5, 4, 3, 2, 2, 2]);
        // The solver accepts them: walks of the graph, cyclically.
        let unit = Patroller { name: "p".into() };
        assert!(Instance::new(g.clone(), targets, vec![unit]).is_ok());
        assert_eq!(super::targets(&g, &trip, 0, 3).unwrap().len(), 1);
    }
}

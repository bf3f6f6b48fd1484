//! Planning on the lattice, apart from the event loop: the fixed-wing aircraft's A* over
//! (cell, heading), one maneuver's cell and heading, and the whole maneuver sequence a
//! lattice aircraft flies for a waypoint command ([`maneuvers`], which a calibration uses to
//! time a command in advance).

use crate::entity::air::{AirKind, DIRS, Lattice, LatticeBody, Maneuver, dir_of};
use std::cmp::Ordering;
use std::collections::{BTreeMap, BinaryHeap};

/// Most A* expansions for one waypoint (a bound that a lattice trip across a town never
/// reaches).
const MAX_EXPANSIONS: usize = 500_000;

/// −1, 0 or +1.
pub(crate) fn sign(x: i32) -> i32 {
    x.signum()
}

/// The cell and heading after a fixed-wing maneuver.
pub(crate) fn ctol_move(b: &LatticeBody, turn: i32, climb: i32) -> ([i32; 3], u8) {
    let dir = (i32::from(b.dir) + turn).rem_euclid(8) as u8;
    let s = DIRS[dir as usize];
    ([b.cell[0] + s[0], b.cell[1] + s[1], b.cell[2] + climb], dir)
}

/// The cell and heading of a lattice aircraft's next maneuver towards waypoint cell `g`:
/// a fixed-wing aircraft (`ctol`) flies the next maneuver of its A* plan (planned afresh
/// when `plan` is empty) and climbs one cell towards `g`; a helicopter steps one cell
/// towards `g` on each axis. The autopilot and [`maneuvers`] share it, so a calibration
/// times the very cells the autopilot flies.
pub(crate) fn waypoint_step(
    b: &LatticeBody,
    g: [i32; 3],
    ctol: bool,
    plan: &mut Vec<Maneuver>,
) -> ([i32; 3], u8) {
    if ctol {
        if plan.is_empty() {
            *plan = plan_ctol([b.cell[0], b.cell[1]], b.dir, [g[0], g[1]]);
        }
        let m = plan.pop().unwrap_or(Maneuver { turn: 0, climb: 0 });
        ctol_move(b, i32::from(m.turn), sign(g[2] - b.cell[2]))
    } else {
        let d = [g[0] - b.cell[0], g[1] - b.cell[1], g[2] - b.cell[2]];
        let to = [
            b.cell[0] + sign(d[0]),
            b.cell[1] + sign(d[1]),
            b.cell[2] + sign(d[2]),
        ];
        let dir = if d[0] != 0 || d[1] != 0 {
            dir_of(libm::atan2(f64::from(sign(d[1])), f64::from(sign(d[0]))))
        } else {
            b.dir
        };
        (to, dir)
    }
}

#[derive(PartialEq)]
struct Open(f64, [i32; 3]);
impl Eq for Open {}
impl Ord for Open {
    fn cmp(&self, o: &Self) -> Ordering {
        // Min-heap on f, ties by state: deterministic.
        o.0.total_cmp(&self.0).then(o.1.cmp(&self.1))
    }
}
impl PartialOrd for Open {
    fn partial_cmp(&self, o: &Self) -> Option<Ordering> {
        Some(self.cmp(o))
    }
}

fn octile(a: [i32; 2], b: [i32; 2]) -> f64 {
    let (dx, dy) = ((a[0] - b[0]).abs(), (a[1] - b[1]).abs());
    let (lo, hi) = (dx.min(dy), dx.max(dy));
    f64::from(hi - lo) + std::f64::consts::SQRT_2 * f64::from(lo)
}

/// The shortest fixed-wing maneuver sequence (in cells flown) from `start` heading `dir` to
/// the cell `goal`, any final heading; returned last maneuver first. Empty if none is found
/// within the search window.
pub fn plan_ctol(start: [i32; 2], dir: u8, goal: [i32; 2]) -> Vec<Maneuver> {
    if start == goal {
        return Vec::new();
    }
    let margin = 8;
    let lo = [
        start[0].min(goal[0]) - margin,
        start[1].min(goal[1]) - margin,
    ];
    let hi = [
        start[0].max(goal[0]) + margin,
        start[1].max(goal[1]) + margin,
    ];
    let s0 = [start[0], start[1], i32::from(dir)];
    let mut g: BTreeMap<[i32; 3], f64> = BTreeMap::new();
    let mut prev: BTreeMap<[i32; 3], ([i32; 3], i8)> = BTreeMap::new();
    let mut open = BinaryHeap::new();
    g.insert(s0, 0.0);
    open.push(Open(octile(start, goal), s0));
    let mut expansions = 0;
    while let Some(Open(_, s)) = open.pop() {
        if [s[0], s[1]] == goal {
            let mut out = Vec::new();
            let mut cur = s;
            while let Some(&(p, turn)) = prev.get(&cur) {
                out.push(Maneuver { turn, climb: 0 });
                cur = p;
            }
            return out;
        }
        expansions += 1;
        if expansions > MAX_EXPANSIONS {
            break;
        }
        let gs = g.get(&s).copied().unwrap_or(f64::INFINITY);
        for turn in [-1i8, 0, 1] {
            let nd = (s[2] + i32::from(turn)).rem_euclid(8);
            let step = DIRS[nd as usize];
            let n = [s[0] + step[0], s[1] + step[1], nd];
            if n[0] < lo[0] || n[1] < lo[1] || n[0] > hi[0] || n[1] > hi[1] {
                continue;
            }
            let cost = if step[0] != 0 && step[1] != 0 {
                std::f64::consts::SQRT_2
            } else {
                1.0
            };
            let ng = gs + cost;
            if ng < g.get(&n).copied().unwrap_or(f64::INFINITY) {
                g.insert(n, ng);
                prev.insert(n, (s, turn));
                open.push(Open(ng + octile([n[0], n[1]], goal), n));
            }
        }
    }
    Vec::new()
}

/// Most maneuvers [`maneuvers`] follows for one command.
const MAX_MANEUVERS: usize = 100_000;

/// The maneuvers a lattice aircraft (`ctol`: fixed-wing, else helicopter) in cell `cell`
/// heading `dir` flies to reach every one of `points` in order, as the autopilot decides
/// them (the cells do not depend on the speed): each maneuver's horizontal and vertical
/// length, metres. `None` if the last waypoint is not reached within a bound.
pub fn maneuvers(
    l: &Lattice,
    ctol: bool,
    cell: [i32; 3],
    dir: u8,
    points: &[[f64; 3]],
) -> Option<Vec<[f64; 2]>> {
    let mut b = LatticeBody {
        kind: AirKind::Ctol(crate::types::CtolKind::Procerus),
        lattice: *l,
        cell,
        dir,
        speed: 0.0,
        moving_to: None,
        pending: None,
    };
    let mut plan: Vec<Maneuver> = Vec::new();
    let mut out = Vec::new();
    let mut next = 0;
    while out.len() < MAX_MANEUVERS {
        // Waypoints reached in this cell, as in `start_next`.
        while let Some(&p) = points.get(next) {
            let g = l.cell_of(p);
            if !(b.cell[0] == g[0] && b.cell[1] == g[1] && (ctol || b.cell[2] == g[2])) {
                break;
            }
            next += 1;
            plan.clear();
        }
        let Some(&p) = points.get(next) else {
            return Some(out);
        };
        let g = l.cell_of(p);
        let (to, d) = waypoint_step(&b, g, ctol, &mut plan);
        let (p0, p1) = (l.point(b.cell), l.point(to));
        out.push([
            libm::hypot(p1[0] - p0[0], p1[1] - p0[1]),
            (p1[2] - p0[2]).abs(),
        ]);
        b.cell = to;
        b.dir = d;
    }
    None
}

#[cfg(test)]
mod tests {
    use super::*;

    fn fly(start: [i32; 2], dir: u8, plan: &[Maneuver]) -> ([i32; 2], u8) {
        let (mut c, mut d) = (start, dir);
        for m in plan.iter().rev() {
            d = (i32::from(d) + i32::from(m.turn)).rem_euclid(8) as u8;
            let s = DIRS[d as usize];
            c = [c[0] + s[0], c[1] + s[1]];
        }
        (c, d)
    }

    #[test]
    fn a_star_reaches_a_goal_behind_the_aircraft() {
        // Heading east, the goal two cells west: it must turn around.
        let plan = plan_ctol([0, 0], 0, [-2, 0]);
        assert!(!plan.is_empty());
        assert_eq!(fly([0, 0], 0, &plan).0, [-2, 0]);
        // Straight ahead: straight maneuvers only.
        let plan = plan_ctol([0, 0], 0, [5, 0]);
        assert_eq!(plan.len(), 5);
        assert!(plan.iter().all(|m| m.turn == 0));
        // A diagonal goal.
        let plan = plan_ctol([3, 3], 2, [10, -4]);
        assert_eq!(fly([3, 3], 2, &plan).0, [10, -4]);
        assert!(plan_ctol([1, 1], 5, [1, 1]).is_empty());
    }
}

//! Deterministic local search: 2-opt within a route, relocate, swap, and 2-opt* between routes
//! (Potvin & Rousseau, "An exchange heuristic for routeing problems with time windows", *J. Oper.
//! Res. Soc.* 46, 1995), first improvement in a fixed scan order, until no move improves.

use crate::Instance;

/// Improvements smaller than this are not taken (they would let rounding loop forever).
const EPS: f64 = 1e-9;

/// Runs the four neighbourhoods until none improves; empty routes are dropped. Returns the
/// number of moves taken.
pub(crate) fn improve(inst: &Instance, routes: &mut Vec<Vec<usize>>) -> u64 {
    let mut moves = 0;
    let mut buf = Vec::new();
    loop {
        let improved = two_opt(inst, routes, &mut buf)
            || relocate(inst, routes, &mut buf)
            || swap(inst, routes, &mut buf)
            || two_opt_star(inst, routes, &mut buf);
        routes.retain(|r| !r.is_empty());
        if !improved {
            return moves;
        }
        moves += 1;
    }
}

fn at(route: &[usize], i: isize) -> usize {
    if i < 0 {
        0
    } else {
        route.get(i as usize).copied().unwrap_or(0)
    }
}

/// Reverses a segment of one route.
fn two_opt(inst: &Instance, routes: &mut [Vec<usize>], buf: &mut Vec<usize>) -> bool {
    for r in routes.iter_mut() {
        let n = r.len();
        for i in 0..n {
            for j in i + 1..n {
                let a = at(r, i as isize - 1);
                let b = at(r, j as isize + 1);
                let delta = inst.dist(a, r[j]) + inst.dist(r[i], b)
                    - inst.dist(a, r[i])
                    - inst.dist(r[j], b);
                if delta < -EPS {
                    buf.clear();
                    buf.extend_from_slice(r);
                    buf[i..=j].reverse();
                    if inst.route_on_time(buf) {
                        r.copy_from_slice(buf);
                        return true;
                    }
                }
            }
        }
    }
    false
}

/// Moves one customer to its cheapest feasible place in another (or the same) route.
fn relocate(inst: &Instance, routes: &mut [Vec<usize>], buf: &mut Vec<usize>) -> bool {
    let loads: Vec<u64> = routes.iter().map(|r| inst.route_load(r)).collect();
    let mut rest = Vec::new();
    for ra in 0..routes.len() {
        for i in 0..routes[ra].len() {
            let r = &routes[ra];
            let c = r[i];
            let (p, q) = (at(r, i as isize - 1), at(r, i as isize + 1));
            let gain = inst.dist(p, c) + inst.dist(c, q) - inst.dist(p, q);
            for rb in 0..routes.len() {
                let found = if rb == ra {
                    rest.clear();
                    rest.extend(routes[ra].iter().copied().filter(|&x| x != c));
                    let load = loads[ra] - inst.nodes[c].demand;
                    crate::solution::best_insertion(inst, &rest, load, c, buf)
                } else {
                    crate::solution::best_insertion(inst, &routes[rb], loads[rb], c, buf)
                };
                if let Some((cost, pos)) = found
                    && cost < gain - EPS
                {
                    routes[ra].remove(i);
                    routes[rb].insert(pos, c);
                    return true;
                }
            }
        }
    }
    false
}

/// Exchanges two customers of different routes.
fn swap(inst: &Instance, routes: &mut [Vec<usize>], buf: &mut Vec<usize>) -> bool {
    let loads: Vec<u64> = routes.iter().map(|r| inst.route_load(r)).collect();
    let mut other = Vec::new();
    for ra in 0..routes.len() {
        for rb in ra + 1..routes.len() {
            for i in 0..routes[ra].len() {
                for j in 0..routes[rb].len() {
                    let (a, b) = (&routes[ra], &routes[rb]);
                    let (x, y) = (a[i], b[j]);
                    let (dx, dy) = (inst.nodes[x].demand, inst.nodes[y].demand);
                    if loads[ra] - dx + dy > inst.capacity || loads[rb] - dy + dx > inst.capacity {
                        continue;
                    }
                    let (ap, an) = (at(a, i as isize - 1), at(a, i as isize + 1));
                    let (bp, bn) = (at(b, j as isize - 1), at(b, j as isize + 1));
                    let delta =
                        inst.dist(ap, y) + inst.dist(y, an) - inst.dist(ap, x) - inst.dist(x, an)
                            + inst.dist(bp, x)
                            + inst.dist(x, bn)
                            - inst.dist(bp, y)
                            - inst.dist(y, bn);
                    if delta >= -EPS {
                        continue;
                    }
                    buf.clear();
                    buf.extend_from_slice(a);
                    buf[i] = y;
                    other.clear();
                    other.extend_from_slice(b);
                    other[j] = x;
                    if inst.route_on_time(buf) && inst.route_on_time(&other) {
                        routes[ra][i] = y;
                        routes[rb][j] = x;
                        return true;
                    }
                }
            }
        }
    }
    false
}

/// Exchanges the tails of two routes: `a[..i] + b[j..]` and `b[..j] + a[i..]`.
fn two_opt_star(inst: &Instance, routes: &mut [Vec<usize>], buf: &mut Vec<usize>) -> bool {
    let mut other = Vec::new();
    for ra in 0..routes.len() {
        for rb in ra + 1..routes.len() {
            let (a, b) = (&routes[ra], &routes[rb]);
            let prefix = |r: &[usize]| -> Vec<u64> {
                let mut p = vec![0];
                for &c in r {
                    p.push(p[p.len() - 1] + inst.nodes[c].demand);
                }
                p
            };
            let (pa, pb) = (prefix(a), prefix(b));
            let (la, lb) = (pa[a.len()], pb[b.len()]);
            for i in 0..=a.len() {
                for j in 0..=b.len() {
                    if (i == 0 && j == 0) || (i == a.len() && j == b.len()) {
                        continue;
                    }
                    if pa[i] + (lb - pb[j]) > inst.capacity || pb[j] + (la - pa[i]) > inst.capacity
                    {
                        continue;
                    }
                    let (a0, a1) = (at(a, i as isize - 1), at(a, i as isize));
                    let (b0, b1) = (at(b, j as isize - 1), at(b, j as isize));
                    let delta = inst.dist(a0, b1) + inst.dist(b0, a1)
                        - inst.dist(a0, a1)
                        - inst.dist(b0, b1);
                    if delta >= -EPS {
                        continue;
                    }
                    buf.clear();
                    buf.extend_from_slice(&a[..i]);
                    buf.extend_from_slice(&b[j..]);
                    other.clear();
                    other.extend_from_slice(&b[..j]);
                    other.extend_from_slice(&a[i..]);
                    if inst.route_on_time(buf) && inst.route_on_time(&other) {
                        routes[ra] = buf.clone();
                        routes[rb] = other.clone();
                        return true;
                    }
                }
            }
        }
    }
    false
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::{Metric, Node};

    #[test]
    fn a_crossed_route_is_uncrossed() {
        let nodes = vec![
            Node::untimed(0.0, 0.0, 0),
            Node::untimed(0.0, 10.0, 1),
            Node::untimed(10.0, 0.0, 1),
            Node::untimed(10.0, 10.0, 1),
        ];
        let inst = Instance::new("sq", nodes, 10, None, Metric::Euclidean);
        let mut routes = vec![vec![1, 2, 3]];
        assert!(improve(&inst, &mut routes) > 0);
        assert!((inst.cost(&routes) - 40.0).abs() < 1e-9, "{routes:?}");
    }
}

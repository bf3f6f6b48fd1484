//! Moving a trooper through its actuators at whatever level its body is: `MoveAndTurn` at
//! the directed level, `WalkToNode` hops at the discrete level; and following a route.

use super::sense::{ClearWay, Leg, NearestNode};
use serde::{Deserialize, Serialize};
use vitro::env::NodeId;
use vitro::sim::Context;
use vitro_site::geo::{P2, dist};
use vitro_tactical::actuate::MoveError;
use vitro_tactical::actuate::troop::directed::MoveAndTurn;
use vitro_tactical::actuate::troop::discrete::{PacedHop, PacedWalkToNode, WalkToNode};
use vitro_tactical::entity::troop::StepCmd;
use vitro_tactical::entity::{Level, Pose};
use vitro_tactical::model::Tactical;
use vitro_tactical::radio::Message;

/// The (x, y) of a pose.
pub(crate) fn xy(p: &Pose) -> P2 {
    [p.pos[0], p.pos[1]]
}

/// A body's motion commands, remembered between cycles.
#[derive(Clone, Debug, Default, Serialize, Deserialize)]
pub(crate) struct Mover {
    /// A discrete hop (trip) is under way: no new one until it arrives.
    hopping: bool,
    /// The last command asked for motion (a stop is then due).
    moving: bool,
}

impl Mover {
    /// Walks straight towards `to` at `speed` m/s (directed), or hops to the walk-graph
    /// node nearest `to` unless a hop is under way (discrete).
    pub fn toward<M: Message>(
        &mut self,
        cx: &mut Context<'_, Tactical<M>>,
        pose: &Pose,
        to: P2,
        speed: f64,
    ) -> Result<(), MoveError> {
        match pose.level {
            Level::Discrete => {
                if self.hopping {
                    return Ok(());
                }
                let Some((node, at)) = cx.sense(&NearestNode(to)) else {
                    return Ok(());
                };
                if dist(at, xy(pose)) < 0.5 {
                    return Ok(());
                }
                self.hop(cx, node)
            }
            _ => {
                if dist(to, xy(pose)) < 1e-6 {
                    return self.stop(cx, pose);
                }
                self.moving = true;
                cx.act(
                    &MoveAndTurn,
                    StepCmd {
                        toward: [to[0], to[1], pose.pos[2]],
                        speed: speed.max(0.0),
                    },
                )
            }
        }
    }

    /// Hops to `node` (discrete level) unless a hop is under way.
    pub fn hop<M: Message>(
        &mut self,
        cx: &mut Context<'_, Tactical<M>>,
        node: NodeId,
    ) -> Result<(), MoveError> {
        if self.hopping {
            return Ok(());
        }
        match cx.act(&WalkToNode, node) {
            Ok(()) | Err(MoveError::UnderWay(_)) => {
                self.hopping = true;
                Ok(())
            }
            Err(e) => Err(e),
        }
    }

    /// A squad leader's hop to `node` at its pace (discrete level; the pace counts where
    /// the arena is calibrated, [`PacedWalkToNode`]) unless a hop is under way.
    pub fn paced_hop<M: Message>(
        &mut self,
        cx: &mut Context<'_, Tactical<M>>,
        node: NodeId,
        slow: bool,
    ) -> Result<(), MoveError> {
        if self.hopping {
            return Ok(());
        }
        match cx.act(&PacedWalkToNode, PacedHop { node, slow }) {
            Ok(()) | Err(MoveError::UnderWay(_)) => {
                self.hopping = true;
                Ok(())
            }
            Err(e) => Err(e),
        }
    }

    /// Stops where it stands (directed; a discrete hop always ends at its node).
    pub fn stop<M: Message>(
        &mut self,
        cx: &mut Context<'_, Tactical<M>>,
        pose: &Pose,
    ) -> Result<(), MoveError> {
        if pose.level == Level::Discrete || !self.moving {
            return Ok(());
        }
        self.moving = false;
        cx.act(
            &MoveAndTurn,
            StepCmd {
                toward: pose.pos,
                speed: 0.0,
            },
        )
    }

    /// The body reached the goal of its hop.
    pub fn arrived(&mut self) {
        self.hopping = false;
    }
}

/// How far past the nearest point a follower looks for its next target, in points.
const WINDOW: usize = 40;

/// Following a [`Leg`] at the directed level: the index of the next point to reach, and a
/// target ahead on the route that the body can walk to in a straight line.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub(crate) struct Follow {
    /// The route.
    pub leg: Leg,
    /// Index of the next point to reach.
    pub next: usize,
    /// Index of the next node (of `leg.nodes`) to reach, at the discrete level.
    pub next_node: usize,
}

impl Follow {
    pub fn new(leg: Leg) -> Self {
        Follow {
            leg,
            next: 0,
            next_node: 0,
        }
    }

    /// Marks as reached the points before the one nearest `pos` (among the next few), that
    /// one too once the body is past it (or, for the last point, on it).
    pub fn advance(&mut self, pos: P2) {
        let pts = &self.leg.pts;
        let n = pts.len();
        let end = (self.next + WINDOW).min(n);
        let nearest = (self.next..end)
            .min_by(|&a, &b| dist(pos, p2(pts[a])).total_cmp(&dist(pos, p2(pts[b]))));
        let Some(i) = nearest else {
            return;
        };
        let (p, a) = (pos, p2(pts[i]));
        let passed = match pts.get(i + 1) {
            Some(&b) => {
                let b = p2(b);
                (p[0] - a[0]) * (b[0] - a[0]) + (p[1] - a[1]) * (b[1] - a[1]) > 0.0
                    || dist(p, a) < 0.05
            }
            None => dist(p, a) < 0.05,
        };
        self.next = self.next.max(if passed { i + 1 } else { i });
    }

    /// True once the body stands on the last point (directed) or reached the last node
    /// (discrete).
    pub fn done(&self, level: Level) -> bool {
        match level {
            Level::Discrete => self.next_node >= self.leg.nodes.len(),
            _ => self.next >= self.leg.pts.len(),
        }
    }

    /// The farthest point at most `look` metres ahead along the route (from the next point
    /// on) to which the way from `pos` is clear, and the walking speed there; `None` if the
    /// way to none of them (the next point included) is clear.
    pub fn target<M: Message>(
        &self,
        cx: &mut Context<'_, Tactical<M>>,
        pos: P2,
        look: f64,
    ) -> Option<(P2, f64)> {
        let pts = &self.leg.pts;
        let first = *pts.get(self.next)?;
        let mut along = dist(pos, p2(first));
        let mut last = self.next;
        while last + 1 < pts.len() && last + 1 < self.next + WINDOW {
            along += dist(p2(pts[last]), p2(pts[last + 1]));
            if along > look {
                break;
            }
            last += 1;
        }
        let pick = (self.next..=last).rev().find(|&i| {
            cx.sense(&ClearWay {
                from: pos,
                to: p2(pts[i]),
            })
        })?;
        let v = self.leg.v.get(self.next).copied().unwrap_or(0.0);
        Some((p2(pts[pick]), v))
    }

    /// The next point to reach and the walking speed there.
    pub fn next_point(&self) -> Option<(P2, f64)> {
        let p = self.leg.pts.get(self.next)?;
        Some((p2(*p), self.leg.v.get(self.next).copied().unwrap_or(0.0)))
    }

    /// The next node to hop to (discrete level), past nodes already reached.
    pub fn next_hop(&self) -> Option<NodeId> {
        self.leg.nodes.get(self.next_node).map(|&(_, n)| n)
    }

    /// A hop reached `node` (discrete level).
    pub fn hopped(&mut self, node: NodeId) {
        if let Some(k) = self.leg.nodes[self.next_node..]
            .iter()
            .position(|&(_, n)| n == node)
        {
            self.next_node += k + 1;
        }
    }
}

fn p2(p: [f64; 3]) -> P2 {
    [p[0], p[1]]
}

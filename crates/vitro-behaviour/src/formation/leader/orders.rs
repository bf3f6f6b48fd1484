//! Orders and roster changes heard on the radio: planning the walk to an ordered point
//! (spliced onto the route under way when no node is in a straight line), and the
//! entity numbers of `join` / `leave`.

use super::state::{Route, State};
use crate::formation::motion::{Follow, xy};
use crate::formation::sense::{Leg, WalkRoute};
use vitro::comm::{Address, Outgoing};
use vitro::entity::EntityId;
use vitro::sim::Context;
use vitro_site::geo::P2;
use vitro_tactical::arena::OwnPose;
use vitro_tactical::entity::Level;
use vitro_tactical::model::Tactical;
use vitro_tactical::radio::{Signal, SquadTalk};

/// Tells `id` it is no longer in the squad.
pub(super) fn dismiss<M: SquadTalk>(cx: &mut Context<'_, Tactical<M>>, id: EntityId) {
    let msg = M::from(Signal::new("formation", "none"));
    cx.send(Outgoing::new(Address::Agent(id), msg));
}

/// The rest of `old` up to its next node, then the walk route from that node to `goal`.
fn splice<M: SquadTalk>(cx: &mut Context<'_, Tactical<M>>, old: &Follow, goal: P2) -> Option<Leg> {
    let &(end, _) = old.leg.nodes.iter().find(|&&(i, _)| i >= old.next)?;
    let node = old.leg.pts.get(end)?;
    let tail = cx.sense(&WalkRoute {
        from: [node[0], node[1]],
        to: goal,
    })?;
    let mut leg = Leg {
        pts: old.leg.pts[old.next..=end].to_vec(),
        v: old.leg.v[old.next..=end].to_vec(),
        nodes: Vec::new(),
    };
    let shift = leg.pts.len() - 1;
    leg.pts.extend(tail.pts.iter().skip(1));
    leg.v.extend(tail.v.iter().skip(1));
    leg.nodes = tail.nodes.iter().map(|&(i, n)| (i + shift, n)).collect();
    Some(leg)
}

/// An entity number as written in `join` / `leave`: `7` or `#7`.
pub(super) fn parse_id(s: &str) -> Option<EntityId> {
    let s = s.trim();
    s.strip_prefix('#').unwrap_or(s).parse().ok().map(EntityId)
}

impl State {
    /// Plans the walk to `goal` for `requester`.
    pub(super) fn go_to<M: SquadTalk>(
        &mut self,
        cx: &mut Context<'_, Tactical<M>>,
        requester: EntityId,
        goal: P2,
    ) {
        let pose = cx.sense(&OwnPose);
        let mut leg = pose.and_then(|p| {
            cx.sense(&WalkRoute {
                from: xy(&p),
                to: goal,
            })
        });
        if leg.is_none() && pose.is_some_and(|p| p.level != Level::Discrete) {
            // No node in a straight line from here (held on a bend): on along the route
            // walked so far to its next node, and from there.
            let old = self
                .route
                .as_ref()
                .map(|r| &r.follow)
                .or(self.held.as_ref());
            leg = old.and_then(|f| splice(cx, f, goal));
        }
        self.at_goal_since = None;
        self.held = None;
        match leg {
            Some(leg) => {
                self.route = Some(Route {
                    follow: Follow::new(leg),
                    requester,
                    goal,
                })
            }
            None => {
                self.route = None;
                let msg = M::from(Signal::new(
                    "unreachable",
                    format!("{} {}", goal[0], goal[1]),
                ));
                cx.send(Outgoing::new(Address::Agent(requester), msg));
                self.problem(format!("no walk route to {goal:?}"));
            }
        }
    }
}

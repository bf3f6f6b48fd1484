//! Troopers' actuators: `WalkToNode` at the [`discrete`] and [`directed`] levels, and
//! `MoveAndTurn` under it at the directed level. Walking speeds come from the carried load
//! and the grade (Pandolf; [`TroopParams::walking_speed`](crate::types::TroopParams)).

/// The discrete level.
pub mod discrete {
    use crate::actuate::{MoveError, start_paced_trip, start_trip};
    use crate::arena::{Arena, Ev};
    use crate::entity::discrete::NodeKind;
    use vitro::entity::EntityId;
    use vitro::env::{Actuator, Effects, NodeId};

    /// WalkToNode at the discrete level: the trooper hops from node to node of the walk
    /// graph, each hop taking the edge's length at the Pandolf speed of its load and grade.
    #[derive(Copy, Clone, Debug, Default)]
    pub struct WalkToNode;

    impl Actuator<Arena, Ev> for WalkToNode {
        type Command = NodeId;
        type Error = MoveError;
        fn actuate(
            &self,
            w: &mut Arena,
            me: EntityId,
            goal: NodeId,
            fx: &mut Effects<'_, Ev>,
        ) -> Result<(), MoveError> {
            start_trip(w, me, goal, |k| matches!(k, NodeKind::Troop(_)), fx)
        }
    }

    /// A squad leader's hop at the discrete level at its pace: [`WalkToNode`], the hop's
    /// profile stretched by the pace's factor where the arena has a calibration with a
    /// squad fit (`vitro_calibrate::squad`); as [`WalkToNode`] without one.
    #[derive(Copy, Clone, Debug, Default)]
    pub struct PacedWalkToNode;

    /// A [`PacedWalkToNode`] command: the node, and whether the pace is slow.
    #[derive(Copy, Clone, Debug, PartialEq, Eq)]
    pub struct PacedHop {
        /// The node to walk to.
        pub node: NodeId,
        /// True at the slow pace, false at the normal one.
        pub slow: bool,
    }

    impl Actuator<Arena, Ev> for PacedWalkToNode {
        type Command = PacedHop;
        type Error = MoveError;
        fn actuate(
            &self,
            w: &mut Arena,
            me: EntityId,
            cmd: PacedHop,
            fx: &mut Effects<'_, Ev>,
        ) -> Result<(), MoveError> {
            let pace = w
                .calibration
                .as_ref()
                .and_then(|c| c.pace_stretch(crate::entity::Level::Discrete, cmd.slow));
            let troop = |k| matches!(k, NodeKind::Troop(_));
            start_paced_trip(w, me, cmd.node, troop, pace, fx)
        }
    }
}

/// The directed level.
pub mod directed {
    use crate::actuate::{MoveError, arrived, plan};
    use crate::arena::{Arena, Clock, Ev};
    use crate::entity::discrete::NodeKind;
    use crate::entity::route::Follow;
    use crate::entity::troop::{StepCmd, Walker};
    use vitro::entity::EntityId;
    use vitro::env::{Actuator, Effects, NodeId};
    use vitro_site::geo::dist;
    use vitro_site::map::Mode;

    /// MoveAndTurn: face a point (at the type's turn rate) and walk towards it.
    #[derive(Copy, Clone, Debug, Default)]
    pub struct MoveAndTurn;

    impl Actuator<Arena, Ev> for MoveAndTurn {
        type Command = StepCmd;
        type Error = MoveError;
        fn actuate(
            &self,
            w: &mut Arena,
            me: EntityId,
            cmd: StepCmd,
            fx: &mut Effects<'_, Ev>,
        ) -> Result<(), MoveError> {
            if !w.walkers.update(me, |b| b.cmd = Some(cmd)) {
                return Err(MoveError::NoBody(me));
            }
            w.wake(Clock::Kinematic, fx);
            Ok(())
        }
    }

    /// WalkToNode at the directed level: plans on the free walk graph, then at every
    /// kinematic step drives [`MoveAndTurn`] to the next point of the path at the piece's
    /// walking speed.
    #[derive(Copy, Clone, Debug, Default)]
    pub struct WalkToNode;

    impl Actuator<Arena, Ev> for WalkToNode {
        type Command = NodeId;
        type Error = MoveError;
        fn actuate(
            &self,
            w: &mut Arena,
            me: EntityId,
            goal: NodeId,
            fx: &mut Effects<'_, Ev>,
        ) -> Result<(), MoveError> {
            let b = w.walkers.get(me).ok_or(MoveError::NoBody(me))?;
            if w.follow.contains(me) {
                return Err(MoveError::UnderWay(me));
            }
            let from = start_node(w, b);
            if from == goal {
                arrived(me, goal, fx);
                return Ok(());
            }
            let kind = NodeKind::Troop(b.kind);
            let track = plan(w, kind, crate::entity::Level::Directed, from, goal, 0.0)?;
            w.follow.insert(
                me,
                Follow {
                    goal,
                    s: 0.0,
                    next: 1,
                    track,
                },
            );
            w.wake(Clock::Kinematic, fx);
            Ok(())
        }
    }

    /// How far a body may stand from its last node before a new trip starts from the node
    /// nearest it instead, metres.
    const OFF_NODE_M: f64 = 3.0;

    /// The node a new trip starts from: the last node the body passed, or — if
    /// [`MoveAndTurn`] alone has steered it away since (a formation slot) — the connected
    /// walk node nearest it.
    fn start_node(w: &Arena, b: &Walker) -> NodeId {
        let here = [b.pos[0], b.pos[1]];
        let at = w.site.street_point(Mode::Walk, b.node);
        if at.is_some_and(|p| dist([p[0], p[1]], here) <= OFF_NODE_M) {
            return b.node;
        }
        (w.roads.of(Mode::Walk))
            .nearest_connected(w.site.to_town(here))
            .unwrap_or(b.node)
    }

    /// One kinematic step of every directed trooper on a trip, and of every one driven by
    /// [`MoveAndTurn`] alone (no trip: it walks straight towards the commanded point, and the
    /// command ends there); true if any is still under way.
    pub(crate) fn step_all(w: &mut Arena, dt: f64, fx: &mut Effects<'_, Ev>) -> bool {
        let ids: Vec<EntityId> = w
            .walkers
            .iter()
            .filter(|(id, _)| w.follow.contains(*id))
            .map(|(id, _)| id)
            .collect();
        let mut busy = false;
        for id in ids {
            busy |= step_one(w, id, dt, fx);
        }
        busy | step_free(w, dt)
    }

    /// One step of the troopers [`MoveAndTurn`] drives without a trip; true if any still has
    /// a command.
    fn step_free(w: &mut Arena, dt: f64) -> bool {
        let ids: Vec<EntityId> = w
            .walkers
            .iter()
            .filter(|(id, b)| b.cmd.is_some() && !w.follow.contains(*id))
            .map(|(id, _)| id)
            .collect();
        let rate = w.types.troops.turn_rate();
        let site = w.site.clone();
        let mut busy = false;
        for id in ids {
            w.walkers.update(id, |b| {
                if b.step(rate * dt, dt, |p| site.ground(p)).is_some() {
                    b.cmd = None;
                    b.speed = 0.0;
                }
                busy |= b.cmd.is_some();
            });
        }
        busy
    }

    fn step_one(w: &mut Arena, id: EntityId, dt: f64, fx: &mut Effects<'_, Ev>) -> bool {
        let (Some(f), Some(mut b)) = (w.follow.get(id).cloned(), w.walkers.get(id).cloned()) else {
            return false;
        };
        let tr = f.track.clone();
        let rate = w.types.troops.turn_rate();
        let mut next = f.next.max(1);
        let mut budget = dt;
        let mut node = b.node;
        let mut done = false;
        loop {
            // The walking speed is along the ground; the body moves in plan.
            let (a, c) = (tr.pts[next - 1], tr.pts[next]);
            let len = tr.s[next] - tr.s[next - 1];
            let run = vitro_site::geo::dist([a[0], a[1]], [c[0], c[1]]);
            let plan = if len > 1e-9 { run / len } else { 1.0 };
            let cmd = StepCmd {
                toward: c,
                speed: tr.v[next] * plan,
            };
            let Ok(()) = MoveAndTurn.actuate(w, id, cmd, fx) else {
                return false;
            };
            b.cmd = Some(cmd);
            match b.step(rate * budget, budget, |_| None) {
                Some(rest) => {
                    if let Some(&(_, n)) = tr.nodes.iter().find(|&&(k, _)| k == next) {
                        node = n;
                    }
                    next += 1;
                    if next >= tr.pts.len() {
                        done = true;
                        break;
                    }
                    budget = rest;
                    if budget <= 0.0 {
                        break;
                    }
                }
                None => break,
            }
        }
        let s = if done {
            tr.length()
        } else {
            let (a, c) = (tr.pts[next - 1], tr.pts[next]);
            let run = vitro_site::geo::dist([a[0], a[1]], [c[0], c[1]]);
            let gone = vitro_site::geo::dist([a[0], a[1]], [b.pos[0], b.pos[1]]);
            let frac = if run > 1e-9 {
                (gone / run).min(1.0)
            } else {
                0.0
            };
            tr.s[next - 1] + frac * (tr.s[next] - tr.s[next - 1])
        };
        b.pos[2] = tr.point_at(s)[2];
        b.node = node;
        if done {
            b.speed = 0.0;
            b.cmd = None;
        }
        w.walkers.insert(id, b);
        if done {
            w.follow.remove(id);
            arrived(id, f.goal, fx);
            false
        } else {
            w.follow.update(id, |f| {
                f.s = s;
                f.next = next;
            });
            true
        }
    }
}

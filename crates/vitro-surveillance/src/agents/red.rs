//! The red units: each goes from junction to junction of its street graph, a destination
//! drawn at random at a distance in `leg_m`, pauses for a time drawn in `dwell_s`, and goes
//! on. Every draw comes from the unit's own `"route"` stream, so a run is the same for a
//! seed whatever else the scenario holds. They sense nothing but their own position.

use crate::act::{Drive, Walk};
use crate::brief::{Gait, RedBrief};
use crate::model::Field;
use rand::Rng;
use serde::{Deserialize, Serialize};
use std::sync::Arc;
use vitro::env::NodeId;
use vitro::sim::{Context, Input};
use vitro::time::SimDuration;
use vitro_site::map::Mode;
use vitro_tactical::arena::{Ev, OwnPose};
use vitro_tactical::model::{Controller, Intention};

/// Timer key: the pause is over.
const GO: u64 = 1;
/// A refused move is tried again after this long.
const RETRY: SimDuration = SimDuration::from_secs(10);

/// A red unit on the move.
#[derive(Debug, Serialize, Deserialize)]
pub struct Prowler {
    #[serde(with = "vitro_mission::snapshot::briefed")]
    brief: Arc<RedBrief>,
    gait: Gait,
    /// Where it is going.
    pub goal: Option<NodeId>,
    /// Destinations reached.
    pub legs: u32,
}

impl Prowler {
    /// Its briefing.
    pub(crate) fn brief(&self) -> &Arc<RedBrief> {
        &self.brief
    }

    /// A red unit of `brief` moving with `gait`.
    pub fn new(brief: Arc<RedBrief>, gait: Gait) -> Self {
        Prowler {
            brief,
            gait,
            goal: None,
            legs: 0,
        }
    }

    /// Draws the next destination and sets off (or tries again later).
    fn set_off(&mut self, cx: &mut Context<'_, Field>) {
        let Some(pose) = cx.sense(&OwnPose) else {
            return;
        };
        let here = self.brief.site.to_town([pose.pos[0], pose.pos[1]]);
        let g = self.brief.roads.of(self.gait.mode);
        let [near, far] = self.brief.leg_m;
        let candidates: Vec<NodeId> = (0..g.graph.node_count() as u32)
            .map(NodeId)
            .filter(|&n| g.main.get(n.0 as usize).copied().unwrap_or(false))
            .filter(|&n| {
                g.graph.node(n).is_some_and(|s| {
                    let d = crate::sector::dist(s.pos, here);
                    (near..=far).contains(&d)
                })
            })
            .collect();
        if candidates.is_empty() {
            cx.set_timer(RETRY, GO);
            return;
        }
        let goal = candidates[cx.rng("route").random_range(0..candidates.len())];
        let moved = match self.gait.mode {
            Mode::Walk => cx.act(&Walk(self.gait.level), goal).is_ok(),
            Mode::Drive => cx.act(&Drive(self.gait.level), goal).is_ok(),
        };
        if moved {
            self.goal = Some(goal);
        } else {
            self.goal = None;
            cx.set_timer(RETRY, GO);
        }
    }

    /// Arrived: pauses.
    fn pause(&mut self, cx: &mut Context<'_, Field>) {
        self.legs += 1;
        self.goal = None;
        let [lo, hi] = self.brief.dwell_s;
        let s = if hi > lo {
            cx.rng("route").random_range(lo..=hi)
        } else {
            lo
        };
        cx.set_timer(SimDuration::from_secs_f64(s), GO);
    }
}

impl Controller<Field> for Prowler {
    fn handle(&mut self, input: Input<'_, Field>, cx: &mut Context<'_, Field>) {
        match input {
            Input::Event(Ev::Start) | Input::Timer(GO) => self.set_off(cx),
            Input::Event(Ev::Arrived(n)) if Some(*n) == self.goal => self.pause(cx),
            _ => {}
        }
    }

    fn intention(&self) -> Option<Intention> {
        let text = match self.goal {
            Some(n) => format!("move to junction {}", n.0),
            None => "wait".to_owned(),
        };
        Some(Intention {
            text,
            ..Intention::default()
        })
    }
}

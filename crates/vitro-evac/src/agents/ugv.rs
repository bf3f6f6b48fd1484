//! The unmanned ground vehicle (MDARS): drives to the route junctions ahead of the truck
//! and reports hostile contacts to the blue group.

use super::air::progress;
use super::{Reporter, SENSE, last_known, note_friends};
use crate::act::Drive;
use crate::brief::{BLUE, Brief};
use crate::radio::Evac;
use crate::sense::VisionOf;
use serde::{Deserialize, Serialize};
use std::sync::Arc;
use vitro::env::NodeId;
use vitro::sim::{Context, Input};
use vitro::time::SimDuration;
use vitro_behaviour::belief::{Beacon, Whereabouts};
use vitro_site::map::Mode;
use vitro_tactical::arena::Ev;
use vitro_tactical::model::{Controller, Intention};

/// Timer key of the next goal.
const PLAN: u64 = 40;

/// The unmanned ground vehicle: drives to the route junctions ahead of the truck.
#[derive(Debug, Serialize, Deserialize)]
pub struct Ugv {
    #[serde(with = "vitro_mission::snapshot::briefed")]
    brief: Arc<Brief>,
    drive: Drive,
    reporter: Reporter,
    goal: Option<NodeId>,
    known: Whereabouts,
    beacon: Beacon,
}

impl Ugv {
    /// The UGV of `brief`, driving at `drive`'s level.
    pub fn new(brief: Arc<Brief>, drive: Drive) -> Self {
        Ugv {
            known: super::whereabouts(&brief),
            beacon: super::beacon(&brief),
            brief,
            drive,
            reporter: Reporter::default(),
            goal: None,
        }
    }
    fn next(&mut self, cx: &mut Context<'_, Evac>) {
        let Some(truck) = last_known(&self.known, self.brief.truck, cx.now()) else {
            // No report of the truck yet: it waits and asks again.
            cx.set_timer(SimDuration::from_secs(10), PLAN);
            return;
        };
        let r = &self.brief.route;
        let k = (progress(&self.brief, truck) + 6).min(r.len().saturating_sub(1));
        let Some(&goal) = r.get(k) else { return };
        if self.goal != Some(goal) && cx.act(&self.drive, goal).is_ok() {
            self.goal = Some(goal);
        } else {
            self.goal = None;
            cx.set_timer(SimDuration::from_secs(10), PLAN);
        }
    }
}

impl Controller<Evac> for Ugv {
    fn handle(&mut self, input: Input<'_, Evac>, cx: &mut Context<'_, Evac>) {
        match input {
            Input::Event(Ev::Start) => {
                cx.join(BLUE);
                self.beacon.start(cx);
                cx.set_timer(SimDuration::from_secs(1), SENSE);
                // The first goal once the first position reports are in.
                cx.set_timer(SimDuration::from_secs(1), PLAN);
            }
            Input::Timer(Beacon::TIMER) => self.beacon.tick(cx),
            Input::Message(env) => {
                self.known.hear(env);
            }
            Input::Event(Ev::Arrived(_)) | Input::Timer(PLAN) => self.next(cx),
            // Stuck on the way: a new goal later, planned from where it stands.
            Input::Event(Ev::Stalled(..)) => {
                self.goal = None;
                cx.set_timer(SimDuration::from_secs(10), PLAN);
            }
            Input::Timer(SENSE) => {
                // Only the blue and red sightings are noted or reported.
                let seen = cx.sense(&VisionOf::armed(self.brief.sensors.ground.vision()));
                note_friends(&mut self.known, &seen, cx.now());
                self.reporter.report(&seen, cx);
                cx.set_timer(
                    SimDuration::from_secs_f64(self.brief.sensors.period_s),
                    SENSE,
                );
            }
            _ => {}
        }
    }
    fn intention(&self) -> Option<Intention> {
        Some(Intention {
            text: "scout the junctions ahead".into(),
            path: self
                .goal
                .and_then(|g| self.brief.node_point(Mode::Drive, g))
                .into_iter()
                .collect(),
            ..Intention::default()
        })
    }
}

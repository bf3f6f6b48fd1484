//! The perimeter watch's agents: a guard patrols the ring round the depot, looks with its own
//! camera and radios each walker it sees to the other guards; a walker walks to the depot
//! (the stock `VisitNodes` through the walking actuator: no code of its own).

use serde::{Deserialize, Serialize};
use std::collections::BTreeSet;
use vitro::prelude::*;
use vitro_behaviour::route::VisitNodes;
use vitro_tactical::actuate::by_level::Drive;
use vitro_tactical::arena::Ev;
use vitro_tactical::model::{Controller, Tactical};
use vitro_tactical::radio::{Basic, Contact, Message};
use vitro_tactical::sensor::FriendFoeVision;
use vitro_tactical::sensor::track::Look;
use vitro_tactical::world::Side;

/// The model of the mission: the tactical arena, speaking the stock radio vocabulary.
pub type Watch = Tactical<Basic>;

/// The radio group of the guards.
pub const GUARDS: GroupId = GroupId(1);
/// The key of a guard's look timer.
const LOOK: u64 = 1;

// ANCHOR: guard
/// A guard: patrols its ring of junctions, looks every `look`, radios new walkers.
#[derive(Clone, Debug, Serialize, Deserialize)]
pub struct Guard {
    /// The patrol, driven at the guard's level (`Drive(level)`).
    pub patrol: VisitNodes<Drive>,
    /// Its camera (range, field of view, detection and identification draws).
    pub camera: FriendFoeVision,
    /// Time between two looks.
    pub look: SimDuration,
    /// Walkers its own camera saw, each with when it first did.
    pub seen: Vec<(SimTime, EntityId)>,
    /// Walkers it knows of, seen or heard of on the radio.
    pub known: BTreeSet<EntityId>,
    /// Walkers it heard of before it saw them itself.
    pub heard_first: u32,
    /// Trips its body gave up.
    pub stalls: u32,
}

impl Controller<Watch> for Guard {
    fn handle(&mut self, input: Input<'_, Watch>, cx: &mut Context<'_, Watch>) {
        match input {
            Input::Event(Ev::Start) => {
                cx.join(GUARDS);
                cx.set_timer(self.look, LOOK);
                self.patrol.handle(input, cx);
            }
            // Look: a reading of its own camera; every new red walker is radioed.
            Input::Timer(LOOK) => {
                for s in cx.sense(&Look(self.camera)) {
                    if s.seen_as != Side::Red || self.seen.iter().any(|x| x.1 == s.id) {
                        continue;
                    }
                    self.seen.push((cx.now(), s.id));
                    if self.known.insert(s.id) {
                        let contact = Contact {
                            target: s.id,
                            pos: s.pos,
                            seen_as: Side::Red,
                        };
                        cx.send(Outgoing::new(Address::Group(GUARDS), contact.into()));
                    }
                }
                cx.set_timer(self.look, LOOK);
            }
            // Hear: another guard's sighting.
            Input::Message(m) => {
                if let Some(c) = m.body.read::<Contact>()
                    && self.known.insert(c.target)
                {
                    self.heard_first += 1;
                }
            }
            // Stuck on the way (a rigid body against a kerb): on to the next junction.
            Input::Event(Ev::Stalled(..)) => {
                self.stalls += 1;
                let ring = &self.patrol.route;
                let next = ring[self.patrol.next % ring.len()];
                self.patrol.next += 1;
                self.patrol.error = cx.act(&self.patrol.goto, next).err();
            }
            // Move: arrivals go to the patrol.
            _ => self.patrol.handle(input, cx),
        }
    }
}
// ANCHOR_END: guard

impl Guard {
    /// A guard patrolling `ring` in a loop at `drive`'s level, looking with `camera` every
    /// `look`.
    pub fn new(
        ring: Vec<NodeId>,
        drive: Drive,
        camera: FriendFoeVision,
        look: SimDuration,
    ) -> Self {
        let mut patrol = VisitNodes::new(ring, drive);
        patrol.repeat = true;
        Guard {
            patrol,
            camera,
            look,
            seen: Vec::new(),
            known: BTreeSet::new(),
            heard_first: 0,
            stalls: 0,
        }
    }
}

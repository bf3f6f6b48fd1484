//! The escort's squad: a trooper's part in the squad that fetches the VIP in formation.
//!
//! When the truck reaches the safehouse, the commander makes a squad of the troopers it
//! lets out: it orders the last of them to the VIP (`Order::GoTo`; pursuers of the
//! high-value target are taken from the first troopers) and tells the others to follow that
//! one (`Order::Follow`). Each mission [`Trooper`](super::trooper::Trooper)
//! then embeds a formation controller ([`vitro_behaviour::formation`]): a [`Leader`] in the one
//! ordered to go, a [`Member`] in each one told to follow. The trooper forwards its inputs
//! to that controller while the squad walks (the formation's own radio protocol, its
//! timers, the ends of its hops) and takes control back for boarding and the hunt. The
//! squad keeps the formation its leader's rule program chooses (file, column, line,
//! wedge). When the squad reaches the VIP, the VIP is told to follow the leader and joins
//! the squad; after the pickup time the squad walks back to the truck with the VIP in its
//! last slot, and on `arrived` the commander orders everybody on board.
//!
//! | message | from → to | effect |
//! |---|---|---|
//! | `Order::GoTo([x, y])` | truck → trooper | lead the squad to (x, y): the trooper becomes the leader if it was not; its [`Leader`] answers `Signal("arrived", "")` (or `"unreachable"`) to the truck. The same order again while under way changes nothing |
//! | `Order::Follow(l)`, `l` a person | truck → trooper or VIP | keep a slot in `l`'s squad: it becomes a [`Member`] of `l` and tells `l` `Signal("join", me)` (again at every such order, in case it was lost) |
//! | `Signal("join" / "leave", id)` | member → leader | `id` joins (last slot) or leaves the squad; a trooper on foot that is told `join` starts leading |
//! | `Signal("squad", "3 5")` | truck → leader | with every `GoTo`: the members the truck counts on; the leader drops any other (one sent after the high-value target whose `leave` was lost) |
//! | `Signal("formation", ..)` | leader → member | the leader's briefing (pattern, slot, spacing, facing) |
//! | `Radio::Contact` of a red body | member → leader | contact: a line facing the threat, slow pace (the leader's own eyes count too; reports from outside the squad do not) |
//! | `Order::Follow(truck)`, `Order::Pursue` | truck → trooper | it leaves the squad; leaving for the hunt, a member tells its leader `leave` and a leader tells its members `Signal("formation", "none")` (they stand still until the truck names a new leader) |
//! | `Signal("down", id)` | trooper → truck | squad mate `id` lies down ([`Fallen`]); told at most every 30 s. A leader also drops the fallen member from its squad |
//!
//! The truck promotes another trooper of the squad when its leader falls or is sent after
//! the high-value target (the new leader gets the `GoTo`, the others a `Follow` of it),
//! and gives up the squad (everyone back to the truck on their own) when no trooper is left
//! to lead it or the leader reports the goal unreachable.
//!
//! Every new controller a trooper embeds deliberates on its own timer index, so that a tick
//! its predecessor left pending is not taken for its own. A trooper that is down drops its
//! controller at its next tick. At the directed level a trooper whose body a formation
//! controller has steered walks any later way back to the truck as a squad of one (a
//! [`Leader`] with no members): the walk actuator plans from the last walk-graph node its
//! body passed, which free steering leaves behind.

use crate::brief::Brief;
use crate::radio::{Evac, Radio};
use crate::sense::Fallen;
use serde::{Deserialize, Serialize};
use std::collections::BTreeMap;
use vitro::comm::{Address, Envelope, Outgoing, Performative, Protocol};
use vitro::entity::EntityId;
use vitro::protocol::TimerTag;
use vitro::sim::{Context, Input};
use vitro::time::{SimDuration, SimTime};
use vitro_behaviour::formation::{Leader, Member};
use vitro_tactical::model::{Controller, Intention};

/// The formation controllers' timer tags (leader "FL", member "FM").
const TICKS: [TimerTag; 2] = [TimerTag(0x464c), TimerTag(0x464d)];
/// A fallen squad mate is reported to the truck again after this long.
const TELL_AGAIN: SimDuration = SimDuration::from_secs(30);

/// True if timer `key` belongs to a formation controller.
pub(crate) fn is_tick(key: u64) -> bool {
    TICKS.iter().any(|t| t.index(key).is_some())
}

/// What the trooper does in the squad.
#[derive(Serialize, Deserialize)]
pub(crate) enum Part {
    /// Leads it, walking to `goal` (world x, y) if it was given one.
    Lead {
        /// The formation controller.
        leader: Box<Leader>,
        /// The latest point ordered.
        goal: Option<[f64; 2]>,
    },
    /// Keeps a slot in another trooper's squad.
    Follow(Box<Member>),
}

/// A trooper's part in the squad, with the formation controller it embeds.
#[derive(Serialize, Deserialize)]
pub(crate) struct Squad {
    /// Leader or member.
    pub part: Part,
    /// When each fallen squad mate was last reported to the truck.
    told: BTreeMap<EntityId, SimTime>,
}

impl Squad {
    /// A squad leader (with nobody yet) deliberating on timer index `index`; `None` if the
    /// briefed program does not load (it was checked when the mission was built).
    pub fn lead(brief: &Brief, index: u64) -> Option<Squad> {
        let f = &brief.formation;
        let leader = Leader::new(&f.program, Vec::new(), f.params.clone()).ok()?;
        let part = Part::Lead {
            leader: Box::new(leader.with_timer_index(index)),
            goal: None,
        };
        Some(Squad::new(part))
    }

    /// A member of `leader`'s squad deliberating on timer index `index`.
    pub fn follow(brief: &Brief, leader: EntityId, index: u64) -> Squad {
        let params = &brief.formation.params;
        let m = Member::new(leader, params.clone()).with_timer_index(index);
        Squad::new(Part::Follow(Box::new(m)))
    }

    fn new(part: Part) -> Squad {
        Squad {
            part,
            told: BTreeMap::new(),
        }
    }

    /// The leader followed, for a member.
    pub fn leader(&self) -> Option<EntityId> {
        match &self.part {
            Part::Follow(m) => Some(m.leader()),
            Part::Lead { .. } => None,
        }
    }

    /// True for a leader still walking to its goal.
    pub fn under_way(&self) -> bool {
        matches!(&self.part, Part::Lead { leader, .. } if leader.under_way())
    }

    /// Hands one input to the embedded controller.
    pub fn forward(&mut self, input: Input<'_, Evac>, cx: &mut Context<'_, Evac>) {
        match &mut self.part {
            Part::Lead { leader, .. } => leader.handle(input, cx),
            Part::Follow(member) => member.handle(input, cx),
        }
    }

    /// Hands a message to the embedded controller if it is one for it: briefings to a
    /// member; `join`, `leave` and the contacts its members report to a leader (what the
    /// squad sees itself: reports from farther away, e.g. from the drones, are not a
    /// contact for the squad).
    pub fn hear(&mut self, env: &Envelope<Radio>, cx: &mut Context<'_, Evac>) {
        let relevant = match (&self.part, &env.body) {
            (Part::Follow(_), Radio::Signal(s, _)) => s == "formation",
            (Part::Lead { .. }, Radio::Signal(s, _)) => s == "join" || s == "leave",
            (Part::Lead { leader, .. }, Radio::Contact { .. } | Radio::Position(_)) => {
                leader.roster().contains(&env.from)
            }
            // The formation link: where the leader is.
            (Part::Follow(m), Radio::Position(_)) => env.from == m.leader(),
            _ => false,
        };
        if relevant {
            self.forward(Input::Message(env), cx);
        }
    }

    /// A leader drops the members that are not in `roster` (the truck's `Signal("squad",
    /// "3 5")`: the members it counts on, e.g. not those sent after the high-value target,
    /// whose own `leave` may have been lost).
    pub fn keep_only(&mut self, roster: &str, cx: &mut Context<'_, Evac>) {
        let Part::Lead { leader, .. } = &mut self.part else {
            return;
        };
        let keep: Vec<&str> = roster.split_whitespace().collect();
        let gone: Vec<EntityId> = leader
            .roster()
            .iter()
            .copied()
            .filter(|m| !keep.contains(&m.0.to_string().as_str()))
            .collect();
        for m in gone {
            let leave = note(cx, Radio::Signal("leave".into(), m.0.to_string()));
            leader.handle(Input::Message(&leave), cx);
        }
    }

    /// Looks at the squad mates: a leader drops each member it sees down from its squad,
    /// a member watches its leader; either tells `truck` who is down (each at most every
    /// 30 s).
    pub fn watch(&mut self, brief: &Brief, cx: &mut Context<'_, Evac>) {
        let range = brief.formation.params.sight_range;
        let mates: Vec<EntityId> = match &self.part {
            Part::Lead { leader, .. } => leader.roster().to_vec(),
            Part::Follow(m) => vec![m.leader()],
        };
        let now = cx.now();
        for who in mates {
            if !cx.sense(&Fallen { who, range }) {
                continue;
            }
            if let Part::Lead { leader, .. } = &mut self.part {
                let leave = note(cx, Radio::Signal("leave".into(), who.0.to_string()));
                leader.handle(Input::Message(&leave), cx);
            }
            let fresh = self
                .told
                .get(&who)
                .is_none_or(|&t| now.saturating_since(t) >= TELL_AGAIN);
            if fresh {
                self.told.insert(who, now);
                let msg = Radio::Signal("down".into(), who.0.to_string());
                cx.send(Outgoing::new(Address::Agent(brief.truck), msg));
            }
        }
    }

    /// What the trooper does in the squad, for the viewer: the pattern and its slot (a
    /// member; its path the slot), or the pattern, the ground, the members and the route
    /// ahead (the leader); `what` says where the squad is going.
    pub fn intention(&self, brief: &Brief, what: &str) -> Intention {
        match &self.part {
            Part::Lead { leader, .. } => {
                let members: Vec<String> = leader.roster().iter().map(|m| m.to_string()).collect();
                Intention {
                    text: format!("lead the squad in {} ({what})", leader.formation()),
                    plan: vec![
                        format!("formation {}", leader.formation()),
                        format!("ground {}", leader.ground().name()),
                        format!("members {}", members.join(" ")),
                    ],
                    path: leader.route_ahead(),
                    ..Intention::default()
                }
            }
            Part::Follow(m) => {
                let text = match (m.pattern(), m.slot()) {
                    (Some(p), Some(k)) => {
                        format!(
                            "in formation: {}, slot {k} behind {} ({what})",
                            p.name(),
                            m.leader()
                        )
                    }
                    _ => format!("join the squad of {} ({what})", m.leader()),
                };
                let path = m
                    .slot_point()
                    .map(|s| vec![brief.site.on_ground(brief.site.to_town(s))])
                    .unwrap_or_default();
                Intention {
                    text,
                    plan: m.doing().split(", ").map(String::from).collect(),
                    path,
                    ..Intention::default()
                }
            }
        }
    }
}

impl std::fmt::Debug for Squad {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match &self.part {
            Part::Lead { leader, goal } => f
                .debug_struct("Lead")
                .field("formation", &leader.formation())
                .field("roster", &leader.roster())
                .field("goal", goal)
                .finish(),
            Part::Follow(m) => f
                .debug_struct("Follow")
                .field("leader", &m.leader())
                .finish(),
        }
    }
}

/// A message from the trooper to itself, handed straight to its controller (not sent).
pub(crate) fn note(cx: &Context<'_, Evac>, body: Radio) -> Envelope<Radio> {
    Envelope {
        from: cx.me(),
        to: Address::Agent(cx.me()),
        receiver: cx.me(),
        protocol: Protocol::Plain,
        performative: Performative::Inform,
        conversation: 0,
        sent_at: cx.now(),
        size_bytes: 0,
        body,
    }
}

//! The red side: adversaries hiding in the village who fire at blue units they can see and
//! that no drone watches over (the first `patrol.attackers` of them also play the patrol
//! game's attacker: [`Attacker`]), and the high-value target, hidden until it shows up,
//! then evading its pursuers with the configured anytime search.

use super::SENSE;
use super::hunt::Search;
use super::hunt::TurnClock;
use super::patrol::attack::{Attacker, PatrolWatch};
use super::trooper::{DECIDED, TURN};
use crate::act::{Fire, SetStatus, Walk};
use crate::brief::Brief;
use crate::radio::Evac;
use crate::sense::{Myself, Vision, VisionOf, Watched};
use serde::{Deserialize, Serialize};
use std::sync::Arc;
use vitro::entity::EntityId;
use vitro::env::NodeId;
use vitro::sim::{Context, Input};
use vitro::time::{SimDuration, SimTime};
use vitro_algo::pursuit::{Belief, EvaderView};
use vitro_site::map::Mode;
use vitro_tactical::arena::Ev;
use vitro_tactical::condition::Status;
use vitro_tactical::model::{Controller, Intention};
use vitro_tactical::world::Side;

/// A red adversary hiding at a node.
#[derive(Debug, Serialize, Deserialize)]
pub struct Adversary {
    #[serde(with = "vitro_mission::snapshot::briefed")]
    brief: Arc<Brief>,
    /// Since when it has aimed at each blue unit in range: a handful, sorted by id (a
    /// binary search, where a tree's walk and rebalancing cost more), kept as a map.
    #[serde(with = "aim_map")]
    aim: Vec<(EntityId, SimTime)>,
    /// Shots fired.
    pub shots: u32,
    /// Its part as the patrol game's attacker, if it plays it.
    pub attacker: Option<Attacker>,
}

/// Timer key: half a second after a patrol step, follow the truck (the attacker's phase).
const FOLLOW: u64 = 40;
/// Timer key: half a second before a patrol step, watch the Skeldars (and maybe strike).
const WATCH: u64 = 41;

impl Adversary {
    /// An adversary of `brief`.
    pub fn new(brief: Arc<Brief>) -> Self {
        Adversary {
            brief,
            aim: Vec::new(),
            shots: 0,
            attacker: None,
        }
    }

    /// An adversary of `brief` that also plays the patrol game's attacker.
    pub fn attacking(brief: Arc<Brief>, attacker: Attacker) -> Self {
        Adversary {
            attacker: Some(attacker),
            ..Adversary::new(brief)
        }
    }

    /// The attacker's two looks per patrol step (Skeldars step at 1 s + k · `step_s`): the
    /// truck just after a step, the Skeldars just before the next. Stops once it attacked.
    fn on_patrol(&mut self, key: u64, cx: &mut Context<'_, Evac>) {
        let active = cx
            .sense(&Myself)
            .is_some_and(|(c, _)| c.status == Status::Active);
        let watch = PatrolWatch {
            range: self.brief.patrol.watch_range_m,
        };
        let Some(attacker) = self.attacker.as_mut() else {
            return;
        };
        if !active || attacker.attack.is_some() {
            return;
        }
        let seen = cx.sense(&watch);
        if key == FOLLOW {
            let truck = seen.truck.map(|p| self.brief.site.to_town([p[0], p[1]]));
            attacker.follow(truck);
        } else if attacker
            .watch(cx.now().as_secs_f64(), &seen.skeldars)
            .is_some()
        {
            return;
        }
        cx.set_timer(SimDuration::from_secs_f64(attacker.game.step_s), key);
    }

    fn on_sense(&mut self, cx: &mut Context<'_, Evac>) {
        let active = cx
            .sense(&Myself)
            .is_some_and(|(c, _)| c.status == Status::Active);
        if !active {
            return;
        }
        let m = &self.brief.mission;
        // The blue ones within reach (the look draws for every body it can see).
        let seen = cx.sense(&VisionOf {
            vision: self.brief.sensors.ground.vision(),
            sides: &[Side::Blue],
            within: m.attack_range_m,
        });
        let now = cx.now();
        let blue: Vec<EntityId> = seen.iter().map(|s| s.id).collect();
        if !self.aim.is_empty() {
            self.aim.retain(|(id, _)| blue.contains(id));
        }
        for id in blue {
            let since = match self.aim.binary_search_by_key(&id, |&(k, _)| k) {
                Ok(i) => self.aim[i].1,
                Err(i) => {
                    self.aim.insert(i, (id, now));
                    now
                }
            };
            let aimed = now.saturating_since(since).as_secs_f64() >= m.attack_aim_s;
            let watched = cx.sense(&Watched {
                target: id,
                radius: m.cover_radius_m,
            });
            if aimed && !watched {
                let fire = Fire {
                    range: m.attack_range_m,
                    p_hit: m.hit_probability,
                };
                if cx.act(&fire, id).is_ok() {
                    self.shots += 1;
                }
                // Aiming anew: `id` is in the list (entered above).
                if let Ok(i) = self.aim.binary_search_by_key(&id, |&(k, _)| k) {
                    self.aim[i].1 = now;
                }
                break;
            }
        }
        cx.set_timer(
            SimDuration::from_secs_f64(self.brief.sensors.period_s),
            SENSE,
        );
    }
}

impl Controller<Evac> for Adversary {
    fn handle(&mut self, input: Input<'_, Evac>, cx: &mut Context<'_, Evac>) {
        match input {
            Input::Event(Ev::Start) => {
                cx.set_timer(SimDuration::from_secs(1), SENSE);
                if let Some(a) = &self.attacker {
                    let step = a.game.step_s;
                    cx.set_timer(SimDuration::from_secs_f64(1.5), FOLLOW);
                    cx.set_timer(SimDuration::from_secs_f64(0.5 + step), WATCH);
                }
            }
            Input::Timer(SENSE) => self.on_sense(cx),
            Input::Timer(key @ (FOLLOW | WATCH)) => self.on_patrol(key, cx),
            _ => {}
        }
    }
    fn intention(&self) -> Option<Intention> {
        if let Some(a) = self.attacker.as_ref().and_then(|a| a.attack.as_ref()) {
            return Some(Intention {
                text: format!(
                    "attack target {} (computed capture probability {:.2})",
                    a.target, a.capture
                ),
                ..Intention::default()
            });
        }
        let text = if self.aim.is_empty() {
            "hide and watch".to_string()
        } else {
            format!("aim at {} blue unit(s)", self.aim.len())
        };
        Some(Intention {
            text,
            ..Intention::default()
        })
    }
}

/// Timer key: the HVT shows up.
const APPEAR: u64 = 30;

/// The high-value target: hidden, then evading.
#[derive(Debug, Serialize, Deserialize)]
pub struct Hvt {
    #[serde(with = "vitro_mission::snapshot::briefed")]
    brief: Arc<Brief>,
    walk: Walk,
    search: Search,
    tracked: Vec<EntityId>,
    beliefs: Vec<Belief>,
    next: Option<NodeId>,
    under_way: bool,
    /// Turns played.
    pub turns: u32,
    clock: TurnClock,
}

impl Hvt {
    /// The target of `brief`, walking at `walk`'s level; it keeps a belief about each of
    /// the first `hvt_pursuers` blue troopers (the ones the team sends after it).
    pub fn new(brief: Arc<Brief>, walk: Walk) -> Self {
        let k = brief.mission.hvt_pursuers as usize;
        let tracked: Vec<EntityId> = brief.team.iter().copied().take(k.max(1)).collect();
        Hvt {
            search: Search::new(&brief.pursuit),
            brief,
            walk,
            tracked,
            beliefs: Vec::new(),
            next: None,
            under_way: false,
            turns: 0,
            clock: TurnClock::default(),
        }
    }

    fn on_turn(&mut self, cx: &mut Context<'_, Evac>) {
        let Some((me, Some(pose))) = cx.sense(&Myself) else {
            return;
        };
        if me.status != Status::Active {
            return;
        }
        self.clock.begin(cx);
        let Some(board) = self.brief.board.clone() else {
            return;
        };
        let Some(here) = self.brief.walk_node(pose.pos) else {
            return;
        };
        let here = here.0 as usize;
        let n = board.node_count();
        if self.beliefs.len() != self.tracked.len() {
            self.beliefs = vec![Belief::uniform(n); self.tracked.len()];
        }
        let seen = cx.sense(&Vision(self.brief.sensors.ground.vision()));
        for (id, belief) in self.tracked.iter().zip(&mut self.beliefs) {
            belief.predict(&board);
            match seen
                .iter()
                .find(|s| s.id == *id)
                .and_then(|s| self.brief.walk_node(s.pos))
            {
                Some(v) => belief.collapse(v.0 as usize),
                None => belief.exclude_seen_by(&board, &[here]),
            }
            if belief.size() == 0 {
                *belief = Belief::uniform(n);
            }
        }
        let view = EvaderView {
            arena: &board,
            position: here,
            beliefs: &self.beliefs,
            turn: self.turns,
        };
        let v = self.search.evade(&view, cx.rng("evade"));
        self.turns += 1;
        self.next = Some(NodeId(v as u32));
        let us = self.brief.pursuit.think_us_per_iteration * f64::from(self.brief.pursuit.budget);
        cx.set_timer(SimDuration::from_secs_f64(us * 1e-6), DECIDED);
    }

    fn on_decided(&mut self, cx: &mut Context<'_, Evac>) {
        if let Some(node) = self.next
            && !self.under_way
        {
            self.under_way = cx.act(&self.walk, node).is_ok();
        }
        // The next turn starts on arrival (no sooner than MIN_TURN after this one began), or
        // after a long turn at the latest.
        let fallback = SimDuration::from_secs_f64(2.0 * self.brief.turn_s);
        self.clock.next_in(fallback, TURN, cx);
    }

    fn on_arrived(&mut self, cx: &mut Context<'_, Evac>) {
        self.under_way = false;
        if self.turns > 0 {
            self.clock.after_move(TURN, cx);
        }
    }
}

impl Controller<Evac> for Hvt {
    fn handle(&mut self, input: Input<'_, Evac>, cx: &mut Context<'_, Evac>) {
        match input {
            Input::Event(Ev::Start) => {
                let at = SimDuration::from_secs_f64(self.brief.mission.hvt_appear_s);
                cx.set_timer(at, APPEAR);
            }
            Input::Timer(APPEAR) if cx.act(&SetStatus, Status::Active).is_ok() => {
                cx.set_timer(SimDuration::ZERO, TURN);
            }
            Input::Timer(TURN) => self.on_turn(cx),
            Input::Timer(DECIDED) => self.on_decided(cx),
            Input::Event(Ev::Arrived(_)) => self.on_arrived(cx),
            _ => {}
        }
    }
    fn intention(&self) -> Option<Intention> {
        if self.turns == 0 {
            return None;
        }
        let path = self
            .next
            .and_then(|n| self.brief.node_point(Mode::Walk, n))
            .into_iter()
            .collect();
        Some(Intention {
            text: format!("evade ({}, turn {})", self.search.name(), self.turns),
            path,
            ..Intention::default()
        })
    }
}

/// The aim list serialized as a map from blue unit to time (as the `BTreeMap` it replaced).
mod aim_map {
    use serde::{Deserialize, Deserializer, Serializer};
    use std::collections::BTreeMap;
    use vitro::entity::EntityId;
    use vitro::time::SimTime;

    pub(super) fn serialize<S: Serializer>(
        v: &[(EntityId, SimTime)],
        s: S,
    ) -> Result<S::Ok, S::Error> {
        s.collect_map(v.iter().map(|(k, t)| (k, t)))
    }

    pub(super) fn deserialize<'de, D: Deserializer<'de>>(
        d: D,
    ) -> Result<Vec<(EntityId, SimTime)>, D::Error> {
        Ok(BTreeMap::<EntityId, SimTime>::deserialize(d)?
            .into_iter()
            .collect())
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::collections::BTreeMap;

    #[derive(Serialize, Deserialize, PartialEq, Debug)]
    struct Aims(#[serde(with = "aim_map")] Vec<(EntityId, SimTime)>);

    #[test]
    fn the_aim_list_serializes_as_the_map_it_replaced() {
        let list = vec![
            (EntityId(2), SimTime::from_secs(5)),
            (EntityId(9), SimTime::from_secs(1)),
        ];
        let map: BTreeMap<EntityId, SimTime> = list.iter().copied().collect();
        let bytes = postcard::to_allocvec(&Aims(list.clone())).unwrap();
        assert_eq!(bytes, postcard::to_allocvec(&map).unwrap());
        assert_eq!(postcard::from_bytes::<Aims>(&bytes).unwrap(), Aims(list));
    }
}

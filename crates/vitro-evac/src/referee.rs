//! The referee: measures the mission from outside (it is not an agent and changes nothing):
//! every sample it looks at the conditions and poses; every fired event it sees through a
//! listener (contact reports, messages).

use crate::sense::covered;
use serde::{Deserialize, Serialize};
use std::collections::BTreeMap;
use vitro::entity::{EntityId, EntityMap};
use vitro::time::SimTime;
use vitro_tactical::arena::Arena;
use vitro_tactical::condition::{Role, Status};
use vitro_tactical::world::Side;

/// The mission's metrics.
#[derive(Clone, Debug, Default, PartialEq, Serialize, Deserialize)]
pub struct Metrics {
    /// The VIP reached the extraction point.
    pub success: bool,
    /// When, seconds (absent if it did not).
    pub time_to_extraction_s: Option<f64>,
    /// Blue people (troopers and VIP) down.
    pub casualties: u32,
    /// The VIP is down.
    pub vip_down: bool,
    /// Red adversaries in the scenario (the HVT not counted).
    pub adversaries: u32,
    /// Adversaries reported at least once by a blue unit.
    pub adversaries_detected: u32,
    /// Time of the first report of each detected adversary, seconds, by name.
    pub first_detection_s: BTreeMap<String, f64>,
    /// Mean time to the first report over the detected adversaries, seconds.
    pub mean_time_to_detection_s: Option<f64>,
    /// Time some team member on foot or the truck had no drone within the cover radius,
    /// until the VIP was out, seconds.
    pub time_uncovered_s: f64,
    /// When a blue unit first reported the HVT, seconds.
    pub hvt_first_report_s: Option<f64>,
    /// The HVT was captured.
    pub hvt_captured: bool,
    /// When, seconds.
    pub hvt_capture_s: Option<f64>,
    /// Messages sent (each copy counts).
    pub messages_sent: u64,
    /// Messages lost on the channel.
    pub messages_lost: u64,
    /// Repairs of the Vidars' cover plan.
    pub plan_repairs: u64,
    /// Trips the truck gave up because it was stuck (physical level: no progress for the
    /// arena's stall time).
    pub vehicle_stalls: u64,
    /// UAVs that crashed (flew into the ground at a continuous level).
    pub aircraft_down: u64,
    /// Cover-plan repairs cut by the depth bound (`repair.max_depth`).
    pub plan_cuts: u64,
    /// Cover-plan messages sent by the lead Vidar.
    pub plan_messages: u64,
    /// Cover-plan failures the lead detected (failed or overdue looks, Vidars lost).
    pub plan_failures: u64,
    /// Back-on-track repairs of the cover plan that fell back to replanning.
    pub plan_fallbacks: u64,
    /// Checkpoints the truck passed with no look at them reported to the lead.
    pub checkpoints_missed: u64,
    /// Shots fired by the adversaries.
    pub shots: u64,
    /// Calls for proposals the truck made for the hunt's pursuer slots (contract net).
    pub cnet_calls: u64,
    /// Pursuer slots awarded (contracts renewed included).
    pub cnet_awards: u64,
    /// Pursuer slots called again because a hunter was lost (down, silent, or its
    /// contract failed).
    pub cnet_reallocations: u64,
    /// The patrol game's least capture probability over the attacks of the trip, as
    /// computed when the mission was built, and after a re-solve the least of that and the
    /// last re-solved game's over the rest of the trip (absent without a Skeldar).
    pub patrol_capture_probability: Option<f64>,
    /// Share of the escort (the truck on its way, until the VIP is out) during which a
    /// Skeldar was within the cover radius of the truck (horizontally; absent without a
    /// Skeldar).
    pub patrol_cover_fraction: Option<f64>,
    /// Share of the escort during which a Skeldar was within its sensors' range of the truck
    /// (horizontally, line of sight not checked).
    pub patrol_sight_fraction: Option<f64>,
    /// Attacks the patrol game's attackers started (`patrol.attackers`, one each at most).
    pub patrol_attacks: u64,
    /// Of those, the ones a Skeldar stopped: it stood on the target's checkpoint at one of
    /// the attack's steps (the game's definition; the umpire's verdict from the Skeldars'
    /// step logs).
    pub patrol_attacks_stopped: u64,
    /// Mean over the attacks of the capture probability the solved game gives the state and
    /// target each attacker chose (absent without attacks): the realised stop rate should
    /// agree with it where the game's assumptions held.
    pub patrol_capture_computed: Option<f64>,
    /// Attacks through which every Skeldar played its policy from the state the attacker
    /// saw (the truck on its timetable: no hold, skip or rejoin): where the guarantee holds.
    pub patrol_attacks_on_schedule: u64,
    /// Of those, the ones stopped.
    pub patrol_stopped_on_schedule: u64,
    /// Mean computed capture probability of the attacks on schedule (absent without any).
    pub patrol_capture_on_schedule: Option<f64>,
    /// Attacks started on a misread state: some Skeldar was not at the vertex and phase the
    /// attacker believed (its phase from its own sightings of the truck).
    pub patrol_attacks_misread: u64,
    /// Re-solves of the patrol game, over the Skeldars: the truck ran off its timetable and
    /// the game of the rest of the trip was solved again from where it was.
    pub patrol_resolves: u64,
    /// Events fired.
    pub events: u64,
    /// Simulated time at the end, seconds.
    pub sim_time_s: f64,
}

/// The referee's running state.
#[derive(Clone, Debug, Default, Serialize, Deserialize)]
pub struct Referee {
    /// The metrics so far.
    pub metrics: Metrics,
    last: Option<SimTime>,
    /// Log lines of what changed (time, text), drained by the frames.
    pub log: Vec<(SimTime, String)>,
    statuses: EntityMap<Status>,
    /// Range of the aircraft's sensors, metres (for [`Metrics::patrol_sight_fraction`]).
    pub sensor_range_m: f64,
    /// Escort time so far, and how much of it a Skeldar was within the cover radius and
    /// within sensor range of the truck, seconds.
    escort: [f64; 3],
}

impl Referee {
    /// Looks at the arena at `now` (call at every sample).
    pub fn sample(
        &mut self,
        w: &Arena,
        now: SimTime,
        cover_radius: f64,
        names: &BTreeMap<EntityId, String>,
    ) {
        let dt = self
            .last
            .map_or(0.0, |t| now.saturating_since(t).as_secs_f64());
        self.last = Some(now);
        let m = &mut self.metrics;
        let mut uncovered = false;
        let mut casualties = 0;
        for (id, c) in w.conditions.iter() {
            let before = self.statuses.insert(id, c.status);
            if before.is_some() && before != Some(c.status) {
                let who = names.get(&id).map_or("?", |s| s.as_str());
                self.log.push((now, format!("{who}: {}", c.status.name())));
            }
            if c.side != Side::Blue {
                if c.role == Role::Hvt && c.status == Status::Captured && !m.hvt_captured {
                    m.hvt_captured = true;
                    m.hvt_capture_s = Some(now.as_secs_f64());
                }
                continue;
            }
            let person = c.role.is_person();
            if person && c.status == Status::Down {
                casualties += 1;
            }
            let in_team = matches!(c.role, Role::Truck | Role::Trooper | Role::Vip);
            if in_team && c.status == Status::Active && !covered(w, id, cover_radius) {
                uncovered = true;
            }
            if c.role == Role::Vip {
                match c.status {
                    Status::Extracted if !m.success => {
                        m.success = true;
                        m.time_to_extraction_s = Some(now.as_secs_f64());
                    }
                    Status::Down => m.vip_down = true,
                    _ => {}
                }
            }
        }
        m.casualties = casualties;
        // The escort is over once the VIP is out (the hunt may go on).
        if uncovered && !m.success {
            m.time_uncovered_s += dt;
        }
        let escorting = !m.success;
        m.sim_time_s = now.as_secs_f64();
        if escorting {
            self.watch_truck(w, dt, cover_radius);
        }
    }

    /// Counts `dt` of escort, and whether a Skeldar was near the truck (patrol metrics).
    fn watch_truck(&mut self, w: &Arena, dt: f64, cover_radius: f64) {
        let active = |role: Role| {
            w.conditions
                .iter()
                .filter(move |(_, c)| c.role == role && c.status == Status::Active)
                .filter_map(|(id, _)| w.pose(id))
        };
        let Some(truck) = active(Role::Truck).next() else {
            return;
        };
        let mut skeldars = active(Role::Skeldar).peekable();
        if skeldars.peek().is_none() && self.escort[0] == 0.0 {
            return;
        }
        let nearest = skeldars
            .map(|p| libm::hypot(p.pos[0] - truck.pos[0], p.pos[1] - truck.pos[1]))
            .fold(f64::INFINITY, f64::min);
        self.escort[0] += dt;
        if nearest <= cover_radius {
            self.escort[1] += dt;
        }
        if nearest <= self.sensor_range_m {
            self.escort[2] += dt;
        }
        let m = &mut self.metrics;
        if self.escort[0] > 0.0 {
            m.patrol_cover_fraction = Some(self.escort[1] / self.escort[0]);
            m.patrol_sight_fraction = Some(self.escort[2] / self.escort[0]);
        }
    }

    /// Notes a contact report about `target` at `now` (from the listener).
    pub fn contact(&mut self, target: &str, now: SimTime) {
        let m = &mut self.metrics;
        if !m.first_detection_s.contains_key(target) {
            m.first_detection_s
                .insert(target.to_string(), now.as_secs_f64());
            self.log.push((now, format!("{target} detected")));
            m.adversaries_detected = m.first_detection_s.len() as u32;
            let n = m.first_detection_s.len() as f64;
            m.mean_time_to_detection_s = Some(m.first_detection_s.values().sum::<f64>() / n);
        }
    }

    /// True once the mission is decided: the VIP extracted or down.
    pub fn decided(&self) -> bool {
        self.metrics.success || self.metrics.vip_down
    }
}

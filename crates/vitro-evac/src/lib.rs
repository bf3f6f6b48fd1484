//! # The evacuation mission
//!
//! A truck with blue troopers drives from the start to a safehouse; the troopers fetch the
//! VIP on foot and bring it on board; the truck drives to the extraction point. Red
//! adversaries, placed at random from the seed, hide in the village and fire at team members
//! they can see and that no drone watches over. A high-value target shows up at a set time;
//! when a blue unit reports it, the commander sends pursuers after it, who hunt it with an
//! anytime pursuit–evasion search while it evades with the same kind of search. Drones and
//! the UGV watch the team and the route and report contacts.
//!
//! Every agent acts only through sensors ([`sense`]), actuators ([`act`]) and the radio
//! ([`Radio`]); what each knows beforehand is the [`brief`]. The
//! [`referee`] measures the mission from outside; [`view`] turns the state into
//! [`vitro_record`] scenes and frames for recordings and the viewer.
//!
//! ```no_run
//! use vitro_evac::Mission;
//! let mut mission = Mission::from_file("scenarios/evacuation.toml", None)?;
//! let metrics = mission.run();
//! println!("success: {}, trace {:016x}", metrics.success, mission.sim.trace_hash());
//! # Ok::<(), vitro_evac::MissionError>(())
//! ```

pub mod act;
pub mod agents;
pub mod brief;
mod error;
pub mod external;
mod member;
mod plugin;
pub mod radio;
pub mod referee;
pub mod sense;
mod setup;
mod snapshot;
pub mod view;

use crate::radio::{Evac, Radio};
use brief::Brief;
pub use error::MissionError;
pub use member::Member;
pub use plugin::{Evacuation, mission_error, validated};
use referee::{Metrics, Referee};
use std::collections::BTreeMap;
use std::path::Path;
use std::sync::{Arc, Mutex};
use vitro::entity::EntityId;
use vitro::sim::{Input, Simulation, StopReason};
use vitro::time::{SimDuration, SimTime};
use vitro_tactical::condition::{Role, Status};
use vitro_tactical::scenario::{FidelitySpec, Preset, ScenarioFile, Validated};
use vitro_tactical::world::Side;

/// What the listener collects between samples: the contacts (for the metrics, taken at
/// every sample) and, once the scene was asked for ([`Mission::scene`]: a recorder or a
/// viewer asks for it before it asks for frames), the radio messages for the frames. A run
/// nobody watches keeps no message, so its memory does not grow with the messages sent.
#[derive(Clone, Debug, Default, serde::Serialize, serde::Deserialize)]
struct Heard {
    contacts: Vec<(SimTime, EntityId)>,
    messages: Vec<vitro_record::MessageEvent>,
    /// Whether messages are kept (not part of a snapshot: a restored run keeps them once
    /// its scene is asked for).
    #[serde(skip)]
    watched: bool,
}

/// A mission ready to run: the simulation, the briefing and the referee.
pub struct Mission {
    /// The simulation (its `control()` drives pacing from another thread).
    pub sim: Simulation<Evac>,
    /// The briefing.
    pub brief: Arc<Brief>,
    /// The entities, in id order.
    pub members: Vec<Member>,
    /// The scenario's name.
    pub name: String,
    /// When simulated time 0 is on the calendar (the scenario's `start`).
    pub start: vitro::time::UtcTime,
    /// The referee.
    pub referee: Referee,
    /// When the mission ends at the latest.
    pub end: SimTime,
    /// Sampling period of the metrics and the frames.
    pub sample: SimDuration,
    /// The master seed the mission was built with.
    pub seed: u64,
    names: BTreeMap<EntityId, String>,
    heard: Arc<Mutex<Heard>>,
    next_sample: SimTime,
    finished: bool,
}

impl Mission {
    /// Validates the scenario at `path` and builds its mission with its seed, or `seed`.
    pub fn from_file(path: impl AsRef<Path>, seed: Option<u64>) -> Result<Mission, MissionError> {
        let v = ScenarioFile::validate(path)?;
        Mission::build(v, seed)
    }

    /// [`from_file`](Self::from_file) with every entity type at the levels of `preset`
    /// (the file's per-type overrides dropped): the same mission at another fidelity.
    pub fn at_fidelity(
        path: impl AsRef<Path>,
        seed: Option<u64>,
        preset: Preset,
    ) -> Result<Mission, MissionError> {
        let mut v = ScenarioFile::validate(path)?;
        v.loaded.file.fidelity = FidelitySpec {
            level: preset,
            ..FidelitySpec::default()
        };
        Mission::build(v, seed)
    }

    /// Builds the mission of a validated scenario with its seed, or `seed`.
    pub fn build(v: Validated, seed: Option<u64>) -> Result<Mission, MissionError> {
        Mission::build_with(v, seed, None)
    }

    /// Builds the mission of `v` with its seed, or `seed`, the units named in `units` driven
    /// from outside ([`external`]): each must be a [`controllable`](external::controllable)
    /// unit of the scenario ([`Mission::controllable`] lists them). Returns the mission and
    /// the desk where the units' knowledge is read and their commands left.
    pub fn build_external(
        v: Validated,
        seed: Option<u64>,
        units: &[String],
    ) -> Result<(Mission, external::SharedDesk), MissionError> {
        let can = Mission::controllable(&v);
        if let Some(bad) = units.iter().find(|u| !can.contains(u)) {
            return Err(MissionError::Setup(format!(
                "{bad:?} cannot be driven from outside (the scenario's controllable units: {})",
                can.join(", ")
            )));
        }
        let desk = external::SharedDesk::default();
        let mission = Mission::build_with(v, seed, Some((units, &desk)))?;
        Ok((mission, desk))
    }

    /// The names of the scenario's units that may be driven from outside, in id order.
    pub fn controllable(v: &Validated) -> Vec<String> {
        setup::roster(&v.loaded.file)
            .into_iter()
            .filter(external::controllable)
            .map(|m| m.name)
            .collect()
    }

    fn build_with(
        v: Validated,
        seed: Option<u64>,
        external: Option<(&[String], &external::SharedDesk)>,
    ) -> Result<Mission, MissionError> {
        let name = v.loaded.file.name.clone();
        let start = v
            .loaded
            .file
            .start
            .unwrap_or(vitro::time::UtcTime::DEFAULT_START);
        let seed = seed.unwrap_or(v.loaded.file.seed);
        let end = SimTime::from_secs_f64(v.loaded.file.end.time_s);
        let sample = SimDuration::from_secs_f64(v.loaded.file.record.sample_s.max(0.01));
        let built = setup::build(v, seed, external)?;
        let names: BTreeMap<EntityId, String> = built
            .members
            .iter()
            .map(|m| (m.id, m.name.clone()))
            .collect();
        let heard = Arc::new(Mutex::new(Heard::default()));
        let mut sim = built.sim;
        listen(&mut sim, &heard);
        let adversaries = built
            .members
            .iter()
            .filter(|m| m.side == Side::Red && m.role == Role::Trooper)
            .count() as u32;
        let mut referee = Referee::default();
        referee.metrics.adversaries = adversaries;
        referee.sensor_range_m = built.brief.sensors.air.range_m;
        Ok(Mission {
            sim,
            brief: built.brief,
            members: built.members,
            name,
            start,
            referee,
            end,
            sample,
            seed,
            names,
            heard,
            next_sample: SimTime::ZERO,
            finished: false,
        })
    }

    /// True once the mission is over: decided, out of time or out of events.
    pub fn finished(&self) -> bool {
        self.finished
    }

    /// Runs until simulated time `until` (or the end of the mission), sampling the metrics
    /// every sample period; returns false once the mission is over.
    pub fn advance(&mut self, until: SimTime) -> bool {
        let brief = self.brief.clone();
        while !self.finished {
            let next = self.next_sample.min(self.end).min(until);
            let reason = self.sim.run(next, |s| over(s.env(), &brief));
            match reason {
                StopReason::Condition | StopReason::Requested => {
                    self.take_sample(self.sim.now());
                    self.finished = true;
                }
                StopReason::Control => break,
                StopReason::Time | StopReason::QueueEmpty => {
                    if next == self.next_sample {
                        self.take_sample(next);
                        self.next_sample += self.sample;
                    }
                    if reason == StopReason::QueueEmpty || next >= self.end {
                        self.take_sample(next);
                        self.finished = true;
                    } else if next >= until {
                        break;
                    }
                }
            }
        }
        !self.finished
    }

    /// Runs the mission to its end and returns its metrics.
    pub fn run(&mut self) -> Metrics {
        while self.advance(self.end) {}
        self.metrics()
    }

    fn take_sample(&mut self, now: SimTime) {
        let contacts = match self.heard.lock() {
            Ok(mut h) => std::mem::take(&mut h.contacts),
            Err(_) => Vec::new(),
        };
        for (t, target) in contacts {
            // Members are listed in id order (a look-up, not a scan per contact).
            let member = match self.members.get(target.index()) {
                Some(m) if m.id == target => Some(m),
                _ => self.members.iter().find(|m| m.id == target),
            };
            let red = member.is_some_and(|m| m.side == Side::Red && m.role == Role::Trooper);
            if red && let Some(name) = self.names.get(&target) {
                self.referee.contact(name, t);
            }
            if Some(target) == self.brief.hvt && self.referee.metrics.hvt_first_report_s.is_none() {
                self.referee.metrics.hvt_first_report_s = Some(t.as_secs_f64());
                self.referee.log.push((t, "HVT reported".into()));
            }
        }
        let radius = self.brief.mission.cover_radius_m;
        self.referee
            .sample(self.sim.env(), now, radius, &self.names);
    }

    /// The metrics so far.
    pub fn metrics(&self) -> Metrics {
        let mut m = self.referee.metrics.clone();
        let (mut sent, mut lost) = (0, 0);
        for (_, _, c) in self.sim.network().all_counts() {
            sent += c.sent;
            lost += c.lost;
        }
        m.messages_sent = sent;
        m.messages_lost = lost;
        m.events = self.sim.events_fired();
        m.sim_time_s = self.sim.now().as_secs_f64();
        self.patrol_attacks(&mut m);
        for mem in &self.members {
            let condition = self.sim.env().conditions.get(mem.id);
            if condition.is_some_and(|c| {
                matches!(c.role, Role::Procerus | Role::Vidar | Role::Skeldar)
                    && c.status == Status::Down
            }) {
                m.aircraft_down += 1;
            }
            let agent = self.sim.agent(mem.id).map(|a| a.as_any());
            if let Some(a) = agent.and_then(|a| a.downcast_ref::<agents::red::Adversary>()) {
                m.shots += u64::from(a.shots);
            }
            let aircraft = agent.and_then(|a| a.downcast_ref::<agents::air::Aircraft>());
            if let Some(unit) = aircraft.and_then(|a| a.patrol.as_ref()) {
                let p = unit
                    .game
                    .trip_capture_probability
                    .min(unit.game_now().trip_capture_probability);
                m.patrol_resolves += unit.resolves;
                m.patrol_capture_probability =
                    Some(m.patrol_capture_probability.map_or(p, |q| q.min(p)));
            }
            if let Some(c) = agent.and_then(|a| a.downcast_ref::<agents::commander::Commander>()) {
                m.vehicle_stalls += u64::from(c.stalls);
                m.cnet_calls += c.tender.calls;
                m.cnet_awards += c.tender.awards;
                m.cnet_reallocations += c.tender.reallocations;
            }
            let cover = aircraft.and_then(|a| a.cover.as_ref());
            if let Some(c) = cover {
                let t = c.tally();
                m.plan_repairs += t.repairs;
                m.plan_cuts += t.cuts;
                m.plan_fallbacks += t.fallbacks;
                m.plan_messages += c.messages;
                m.plan_failures += c.failures;
                m.checkpoints_missed += c.missed;
            }
        }
        m
    }
}

impl Mission {
    /// The patrol attacks and the umpire's verdicts: each attacker's attack against the
    /// Skeldars' step logs (plan unit order).
    fn patrol_attacks(&self, m: &mut Metrics) {
        let mut logs: Vec<(usize, &[agents::patrol::steps::StepLog])> = Vec::new();
        let mut attacks = Vec::new();
        for mem in &self.members {
            let agent = self.sim.agent(mem.id).map(|a| a.as_any());
            let aircraft = agent.and_then(|a| a.downcast_ref::<agents::air::Aircraft>());
            if let Some(unit) = aircraft.and_then(|a| a.patrol.as_ref()) {
                logs.push((unit.unit, &unit.log));
            }
            let red = agent.and_then(|a| a.downcast_ref::<agents::red::Adversary>());
            if let Some(attack) = red.and_then(|r| r.attacker.as_ref()?.attack.as_ref()) {
                attacks.push(attack);
            }
        }
        logs.sort_by_key(|l| l.0);
        let logs: Vec<&[agents::patrol::steps::StepLog]> = logs.into_iter().map(|l| l.1).collect();
        let (mut all, mut on) = (0.0, 0.0);
        for a in attacks {
            let v = a.verdict(&logs);
            m.patrol_attacks += 1;
            m.patrol_attacks_stopped += u64::from(v.stopped);
            m.patrol_attacks_misread += u64::from(v.misread);
            all += a.capture;
            if v.on_schedule {
                m.patrol_attacks_on_schedule += 1;
                m.patrol_stopped_on_schedule += u64::from(v.stopped);
                on += a.capture;
            }
        }
        if m.patrol_attacks > 0 {
            m.patrol_capture_computed = Some(all / m.patrol_attacks as f64);
        }
        if m.patrol_attacks_on_schedule > 0 {
            m.patrol_capture_on_schedule = Some(on / m.patrol_attacks_on_schedule as f64);
        }
    }
}

/// Collects the contacts and (when watched) the messages of `sim` into `heard` between
/// samples.
fn listen(sim: &mut Simulation<Evac>, heard: &Arc<Mutex<Heard>>) {
    let sink = heard.clone();
    sim.add_listener(move |f| {
        let Ok(mut h) = sink.lock() else { return };
        if let Input::Message(env) = &f.input
            && let Radio::Contact { target, .. } = &env.body
        {
            h.contacts.push((f.time, *target));
        }
        if !h.watched {
            return;
        }
        match &f.input {
            Input::Message(env) => {
                h.messages.push(vitro_record::MessageEvent {
                    t_ns: f.time.as_nanos(),
                    from: env.from.0,
                    to: Some(env.receiver.0),
                    kind: radio_kind(&env.body).into(),
                    delivered: true,
                });
            }
            Input::Undeliverable(env, _) => h.messages.push(vitro_record::MessageEvent {
                t_ns: f.time.as_nanos(),
                from: env.from.0,
                to: None,
                kind: radio_kind(&env.body).into(),
                delivered: false,
            }),
            _ => {}
        }
    });
}

/// True once the mission is over: the VIP is down, or it is out and no hunt goes on (the
/// high-value target hidden, captured, or no pursuer left on its feet).
fn over(w: &vitro_tactical::arena::Arena, brief: &Brief) -> bool {
    let status = |id| w.conditions.get(id).map(|c| c.status);
    match status(brief.vip) {
        Some(Status::Down) => true,
        Some(Status::Extracted) => {
            let hunted = brief.hvt.is_some_and(|h| status(h) == Some(Status::Active));
            // Blue troopers still on their feet once the VIP is out are the hunt's.
            let hunting = (brief.team.iter()).any(|&id| status(id) == Some(Status::Active));
            !(hunted && hunting)
        }
        _ => false,
    }
}

/// The name of a radio message's kind, for recordings.
fn radio_kind(r: &Radio) -> &'static str {
    match r {
        Radio::Contact { .. } => "contact",
        Radio::Position(_) => "position",
        Radio::Order(_) => "order",
        Radio::Plan(_) => "plan",
        Radio::Signal(..) => "signal",
        Radio::Tender { .. } => "tender",
    }
}

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
pub mod scenario;
pub mod sense;
mod setup;
mod snapshot;
pub mod view;

use crate::radio::Radio;
use crate::scenario::{ScenarioFile, Validated};
use brief::Brief;
pub use error::MissionError;
pub use member::Member;
pub use plugin::{Evacuation, mission_error, validated};
use referee::{Metrics, Referee};
use std::collections::BTreeMap;
use std::path::Path;
use std::sync::Arc;
use vitro::entity::EntityId;
use vitro::time::SimTime;
use vitro_mission::session::{Session, Setup};
use vitro_tactical::condition::{Role, Status};
use vitro_tactical::scenario::Preset;
use vitro_tactical::world::Side;

/// A run of the evacuation: the generic run with the mission's own part, [`Mission`].
pub type EvacRun = Session<Mission>;

/// The evacuation's own part of a run: the briefing, the entities and the referee (the
/// simulation, the settings and the advance loop are the [`Session`]'s, whose fields it
/// reads as its own: `run.sim`, `run.end`, `run.referee`).
pub struct Mission {
    /// The briefing.
    pub brief: Arc<Brief>,
    /// The entities, in id order.
    pub members: Vec<Member>,
    /// The referee.
    pub referee: Referee,
    names: BTreeMap<EntityId, String>,
}

impl Mission {
    /// Validates the scenario at `path` and builds its mission with its seed, or `seed`.
    pub fn from_file(path: impl AsRef<Path>, seed: Option<u64>) -> Result<EvacRun, MissionError> {
        let v = ScenarioFile::validate(path)?;
        Mission::build(v, seed)
    }

    /// [`from_file`](Self::from_file) with every entity type at the levels of `preset`
    /// (the file's per-type overrides dropped): the same mission at another fidelity.
    pub fn at_fidelity(
        path: impl AsRef<Path>,
        seed: Option<u64>,
        preset: Preset,
    ) -> Result<EvacRun, MissionError> {
        let mut v = ScenarioFile::validate(path)?;
        v.loaded.file.fidelity.set_preset(preset);
        Mission::build(v, seed)
    }

    /// Builds the mission of a validated scenario with its seed, or `seed`.
    pub fn build(v: Validated, seed: Option<u64>) -> Result<EvacRun, MissionError> {
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
    ) -> Result<(EvacRun, external::SharedDesk), MissionError> {
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
    ) -> Result<EvacRun, MissionError> {
        let f = &v.loaded.file;
        let seed = seed.unwrap_or(f.seed);
        let (end_s, sample_s) = (f.end.time_s, f.record.sample_s);
        let setup = Setup::from_secs(f.name.clone(), seed, end_s, sample_s, f.start);
        let built = setup::build(v, seed, external)?;
        let names = (built.members.iter())
            .map(|m| (m.id, m.name.clone()))
            .collect();
        let adversaries = (built.members.iter())
            .filter(|m| m.side == Side::Red && m.role == Role::Trooper)
            .count() as u32;
        let mut referee = Referee::default();
        referee.metrics.adversaries = adversaries;
        referee.sensor_range_m = built.brief.sensors.air.range_m;
        let mission = Mission {
            brief: built.brief,
            members: built.members,
            referee,
            names,
        };
        Ok(Session::new(setup, built.sim, mission))
    }

    /// Takes the contacts reported since the last sample to the referee, and its sample.
    fn take_sample(run: &mut EvacRun, now: SimTime) {
        let contacts = std::mem::take(&mut run.heard().own);
        let m = &mut run.play;
        for (t, target) in contacts {
            // Members are listed in id order (a look-up, not a scan per contact).
            let member = match m.members.get(target.index()) {
                Some(x) if x.id == target => Some(x),
                _ => m.members.iter().find(|x| x.id == target),
            };
            let red = member.is_some_and(|x| x.side == Side::Red && x.role == Role::Trooper);
            if red && let Some(name) = m.names.get(&target) {
                m.referee.contact(name, t);
            }
            if Some(target) == m.brief.hvt && m.referee.metrics.hvt_first_report_s.is_none() {
                m.referee.metrics.hvt_first_report_s = Some(t.as_secs_f64());
                m.referee.log.push((t, "HVT reported".into()));
            }
        }
        let radius = m.brief.mission.cover_radius_m;
        (m.referee).sample(run.sim.env(), now, radius, &m.names);
    }

    /// The metrics of `run` so far.
    fn measure(run: &EvacRun) -> Metrics {
        let mut m = run.referee.metrics.clone();
        let (mut sent, mut lost) = (0, 0);
        for (_, _, c) in run.sim.network().all_counts() {
            sent += c.sent;
            lost += c.lost;
        }
        m.messages_sent = sent;
        m.messages_lost = lost;
        m.events = run.sim.events_fired();
        m.sim_time_s = run.sim.now().as_secs_f64();
        Mission::patrol_attacks(run, &mut m);
        for mem in &run.members {
            let condition = run.sim.env().conditions.get(mem.id);
            if condition.is_some_and(|c| {
                matches!(c.role, Role::Procerus | Role::Vidar | Role::Skeldar)
                    && c.status == Status::Down
            }) {
                m.aircraft_down += 1;
            }
            let agent = run.sim.agent(mem.id).map(|a| a.as_any());
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
    fn patrol_attacks(run: &EvacRun, m: &mut Metrics) {
        let mut logs: Vec<(usize, &[agents::patrol::steps::StepLog])> = Vec::new();
        let mut attacks = Vec::new();
        for mem in &run.members {
            let agent = run.sim.agent(mem.id).map(|a| a.as_any());
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

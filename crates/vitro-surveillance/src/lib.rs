//! # The wide-area surveillance mission
//!
//! A team of UAVs must find red units moving in a town and keep track of them. A ground
//! control station shares the search area out among the UAVs, sector by sector, by
//! **contract net** over the simulated radio; each UAV sweeps the sectors it won and looks
//! through its own camera; once its **tracking sensor** holds a lock on a red unit that no
//! teammate follows, it follows it until the lock is lost, searches round the target's
//! dead-reckoned position for a while, and goes back to its sectors. UAVs can be lost
//! (at set times, or failing at random); the station notices only when their status
//! reports stop, and shares their sectors out again. Areas tasked during the run are cut
//! into sectors and called too.
//!
//! This crate is an application of the toolkit, and shows how one is put together:
//!
//! | part | from |
//! |---|---|
//! | the town, its terrain, line of sight | `vitro_site` (the same map as the evacuation) |
//! | bodies at each level of fidelity, their actuators and autopilots | `vitro_tactical` ([`act`] picks the level's own) |
//! | the camera and its locks | `vitro_tactical::sensor::track` ([`Look`](vitro_tactical::sensor::track::Look), [`Tracker`](vitro_tactical::sensor::track::Tracker)) |
//! | the radio: delay, jitter, loss, range | `vitro::comm`, with the mission's own vocabulary [`net::Net`] |
//! | task allocation | `vitro::protocol::contract_net`, bids read through [`Bid`](vitro::protocol::Bid) |
//! | the model | [`model::Field`]: the tactical arena and events, the mission's messages and agents |
//! | the scenario tables | the shared ones of `vitro_tactical::scenario`, and the mission's own ([`scenario`]) |
//! | plugging into the tools | [`Surveillance`] implements `vitro_mission::Mission`; a run is a `vitro_mission::Run` |
//!
//! The agents ([`agents`]) know only what their [`brief`] says, what their own sensors
//! read and what the radio brings. The [`referee`] measures from outside (time to first
//! detection and tracked share of each red unit, messages, re-allocations, losses), and
//! [`view`] draws the run for recordings and the viewer.
//!
//! ```no_run
//! use vitro_surveillance::Operation;
//!
//! let mut run = Operation::from_file("scenarios/surveillance.toml", Some(7))?;
//! let m = run.run();
//! println!(
//!     "{} of {} red units found, mean time to detection {:?} s, tracked {:.0} % of the time",
//!     m.red_detected, m.red_units, m.mean_time_to_detection_s, 100.0 * m.mean_tracked_share,
//! );
//! println!("trace {:016x}", run.sim.trace_hash());
//! # Ok::<(), vitro_surveillance::SurveillanceError>(())
//! ```
//!
//! From the command line: `vitro run scenarios/surveillance.toml --json`, `vitro batch
//! experiments/surveillance_uavs.toml --out DIR`, `vitro run ... --record run.mcap` and
//! `vitro view run.mcap`.

pub mod act;
pub mod agents;
pub mod brief;
pub mod model;
pub mod net;
mod plugin;
pub mod referee;
pub mod scenario;
pub mod sector;
pub mod sense;
pub mod setup;
mod snapshot;
pub mod view;

pub use plugin::Surveillance;
pub use setup::{Member, SetupError};

use model::Field;
use referee::Metrics;
use std::collections::BTreeMap;
use std::path::Path;
use std::sync::{Arc, Mutex};
use vitro::entity::EntityId;
use vitro::sim::{Input, Simulation, StopReason};
use vitro::time::{SimDuration, SimTime};
use vitro_tactical::condition::Status;
use vitro_tactical::scenario::{Diagnostics, Preset};

/// Why a surveillance run could not be made.
#[derive(Debug, thiserror::Error)]
pub enum SurveillanceError {
    /// The scenario has problems (bad input).
    #[error("{} problem(s)\n{}", .0.len(), .0.render())]
    Scenario(Diagnostics),
    /// The scenario is valid but the run cannot be set up.
    #[error(transparent)]
    Setup(#[from] SetupError),
    /// The scenario file cannot be read.
    #[error("cannot read {file}: {source}")]
    Read {
        /// The file.
        file: String,
        /// Why.
        source: std::io::Error,
    },
}

/// Messages heard on the radio, for the frames (collected once a frame was asked for).
#[derive(Clone, Debug, Default, serde::Serialize, serde::Deserialize)]
struct Heard {
    on: bool,
    messages: Vec<vitro_record::MessageEvent>,
}

/// A surveillance run: the simulation, its entities, and what the referee needs.
pub struct Operation {
    /// The simulation (its `control()` drives pacing from another thread).
    pub sim: Simulation<Field>,
    /// The entities, in id order (the station first).
    pub members: Vec<Member>,
    /// The scenario's name.
    pub name: String,
    /// When simulated time 0 is on the calendar (the scenario's `start`).
    pub start: vitro::time::UtcTime,
    /// The master seed.
    pub seed: u64,
    /// When the run ends.
    pub end: SimTime,
    /// Sampling period of the frames.
    pub sample: SimDuration,
    /// The UAVs lost so far, with when.
    pub lost: BTreeMap<EntityId, SimTime>,
    /// The team's briefing (the map and the operation area, for drawings).
    pub team: Arc<brief::TeamBrief>,
    /// The station's briefing (the sectors and the tasking timetable, for drawings).
    pub tasks: Arc<brief::StationBrief>,
    losses: Vec<(SimTime, EntityId)>,
    next_loss: usize,
    next_sample: SimTime,
    finished: bool,
    heard: Arc<Mutex<Heard>>,
    log: Vec<(SimTime, String)>,
    station_log: usize,
}

impl Operation {
    /// Reads, validates and builds the scenario at `path`, with its seed or `seed`.
    ///
    /// # Errors
    /// [`SurveillanceError`]: unreadable file, bad scenario, or a setup failure.
    pub fn from_file(path: impl AsRef<Path>, seed: Option<u64>) -> Result<Self, SurveillanceError> {
        let path = path.as_ref();
        let text = std::fs::read_to_string(path).map_err(|source| SurveillanceError::Read {
            file: path.display().to_string(),
            source,
        })?;
        Self::from_text(path, &text, seed, None)
    }

    /// Builds the scenario `text` read from `path`, with its seed or `seed`, every entity
    /// at the levels of `preset` if given.
    ///
    /// # Errors
    /// [`SurveillanceError::Scenario`] or [`SurveillanceError::Setup`].
    pub fn from_text(
        path: &Path,
        text: &str,
        seed: Option<u64>,
        preset: Option<Preset>,
    ) -> Result<Self, SurveillanceError> {
        let mut v = scenario::validate_text(path, text).map_err(SurveillanceError::Scenario)?;
        if let Some(level) = preset {
            v.file.fidelity = vitro_tactical::scenario::FidelitySpec {
                level,
                ..Default::default()
            };
        }
        let name = v.file.name.clone();
        let start = v.file.start.unwrap_or(vitro::time::UtcTime::DEFAULT_START);
        let seed = seed.unwrap_or(v.file.seed);
        let end = SimTime::from_secs_f64(v.file.end.time_s);
        let sample = SimDuration::from_secs_f64(v.file.record.sample_s.max(0.01));
        let built = setup::build(v, seed)?;
        let heard = Arc::new(Mutex::new(Heard::default()));
        let mut sim = built.sim;
        listen(&mut sim, &heard);
        Ok(Operation {
            sim,
            members: built.members,
            name,
            start,
            seed,
            end,
            sample,
            lost: BTreeMap::new(),
            team: built.team,
            tasks: built.station,
            losses: built.losses,
            next_loss: 0,
            next_sample: SimTime::ZERO,
            finished: false,
            heard,
            log: Vec::new(),
            station_log: 0,
        })
    }

    /// True once the run is over.
    pub fn finished(&self) -> bool {
        self.finished
    }

    /// Runs until `until` (or the end), applying the UAV losses as their times come;
    /// returns false once the run is over.
    pub fn advance(&mut self, until: SimTime) -> bool {
        while !self.finished {
            let loss = self
                .losses
                .get(self.next_loss)
                .map_or(SimTime::MAX, |l| l.0);
            let next = self.next_sample.min(self.end).min(until).min(loss);
            match self.sim.run(next, |_| false) {
                StopReason::Control => break,
                StopReason::Condition | StopReason::Requested => self.finished = true,
                reason @ (StopReason::Time | StopReason::QueueEmpty) => {
                    self.apply_losses(next);
                    if next == self.next_sample {
                        self.next_sample += self.sample;
                    }
                    if reason == StopReason::QueueEmpty || next >= self.end {
                        self.finished = true;
                    } else if next >= until {
                        break;
                    }
                }
            }
        }
        !self.finished
    }

    /// The losses due by `now`: the UAV is down (it stops sensing, flying on its own and
    /// talking); nobody is told.
    fn apply_losses(&mut self, now: SimTime) {
        while let Some(&(t, id)) = self.losses.get(self.next_loss) {
            if t > now {
                break;
            }
            self.next_loss += 1;
            let w = self.sim.env_mut();
            let active = w
                .conditions
                .get(id)
                .is_some_and(|c| c.status == Status::Active);
            if active && !self.lost.contains_key(&id) {
                w.conditions.update(id, |c| c.status = Status::Down);
                self.lost.insert(id, t);
                let name = self.sim.entities().name(id).unwrap_or("a UAV").to_owned();
                self.log.push((t, format!("{name} lost")));
            }
        }
    }

    /// Runs to the end and returns the metrics.
    pub fn run(&mut self) -> Metrics {
        while self.advance(self.end) {}
        self.metrics()
    }

    /// The metrics so far.
    pub fn metrics(&self) -> Metrics {
        referee::measure(&self.sim, &self.members, &self.lost)
    }

    /// What happened since the last call: losses, awards, presumptions, in time order.
    pub fn drain_log(&mut self) -> Vec<(SimTime, String)> {
        let mut out = std::mem::take(&mut self.log);
        let station = self.sim.agent(EntityId(0)).map(|a| a.as_any());
        if let Some(s) = station.and_then(|a| a.downcast_ref::<agents::station::Station>()) {
            out.extend(s.log.iter().skip(self.station_log).cloned());
            self.station_log = s.log.len();
        }
        out.sort_by_key(|(t, _)| *t);
        out
    }

    /// The messages heard since the last call (collection starts at the first call).
    fn drain_messages(&mut self) -> Vec<vitro_record::MessageEvent> {
        match self.heard.lock() {
            Ok(mut h) => {
                h.on = true;
                std::mem::take(&mut h.messages)
            }
            Err(_) => Vec::new(),
        }
    }
}

/// Collects the messages of `sim` into `heard` for the frames (once a frame was asked for).
fn listen(sim: &mut Simulation<Field>, heard: &Arc<Mutex<Heard>>) {
    let sink = heard.clone();
    sim.add_listener(move |f| {
        let Ok(mut h) = sink.lock() else { return };
        if !h.on {
            return;
        }
        let (env, delivered) = match &f.input {
            Input::Message(env) => (*env, true),
            Input::Undeliverable(env, _) => (*env, false),
            _ => return,
        };
        h.messages.push(vitro_record::MessageEvent {
            t_ns: f.time.as_nanos(),
            from: env.from.0,
            to: delivered.then_some(env.receiver.0),
            kind: env.body.kind().into(),
            delivered,
        });
    });
}

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
//! | task allocation | `vitro::protocol::contract_net`, bids read through [`Bid`](vitro::protocol::Bid); or, by the scenario's `[allocation] method`, sequential auctions over the radio or a central plan solved with `vitro_routing` (the station's `allot` module) |
//! | the model | [`model::Field`]: the tactical arena and events, the mission's messages and agents |
//! | the scenario tables | the shared ones of `vitro_tactical::scenario`, and the mission's own ([`scenario`]) |
//! | plugging into the tools | [`Surveillance`] implements `vitro_mission::Mission`; [`Operation`] is the mission's `vitro_mission::session::Play`, and a run ([`SurveillanceRun`]) the generic session over it |
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

use std::collections::BTreeMap;
use std::path::Path;
use std::sync::Arc;
use vitro::entity::EntityId;
use vitro::time::SimTime;
use vitro_mission::session::{Session, Setup};
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

/// A surveillance run: the generic run with the mission's own part, [`Operation`].
pub type SurveillanceRun = Session<Operation>;

/// The surveillance's own part of a run: its entities, the losses and what the referee needs
/// (the simulation, the settings and the advance loop are the [`Session`]'s, whose fields it
/// reads as its own: `run.sim`, `run.end`, `run.lost`).
pub struct Operation {
    /// The entities, in id order (the station first).
    pub members: Vec<Member>,
    /// The UAVs lost so far, with when.
    pub lost: BTreeMap<EntityId, SimTime>,
    /// The team's briefing (the map and the operation area, for drawings).
    pub team: Arc<brief::TeamBrief>,
    /// The station's briefing (the sectors and the tasking timetable, for drawings).
    pub tasks: Arc<brief::StationBrief>,
    losses: Vec<(SimTime, EntityId)>,
    next_loss: usize,
    log: Vec<(SimTime, String)>,
    station_log: usize,
}

impl Operation {
    /// Reads, validates and builds the scenario at `path`, with its seed or `seed`.
    ///
    /// # Errors
    /// [`SurveillanceError`]: unreadable file, bad scenario, or a setup failure.
    pub fn from_file(
        path: impl AsRef<Path>,
        seed: Option<u64>,
    ) -> Result<SurveillanceRun, SurveillanceError> {
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
    ) -> Result<SurveillanceRun, SurveillanceError> {
        let mut v = scenario::validate_text(path, text).map_err(SurveillanceError::Scenario)?;
        if let Some(level) = preset {
            v.file.fidelity.set_preset(level);
        }
        let f = &v.file;
        let seed = seed.unwrap_or(f.seed);
        let (end_s, sample_s) = (f.end.time_s, f.record.sample_s);
        let setup = Setup::from_secs(f.name.clone(), seed, end_s, sample_s, f.start);
        let built = setup::build(v, seed)?;
        let operation = Operation {
            members: built.members,
            lost: BTreeMap::new(),
            team: built.team,
            tasks: built.station,
            losses: built.losses,
            next_loss: 0,
            log: Vec::new(),
            station_log: 0,
        };
        Ok(Session::new(setup, built.sim, operation))
    }

    /// The losses due by `now`: the UAV is down (it stops sensing, flying on its own and
    /// talking); nobody is told.
    fn apply_losses(run: &mut SurveillanceRun, now: SimTime) {
        let (sim, op) = (&mut run.sim, &mut run.play);
        while let Some(&(t, id)) = op.losses.get(op.next_loss) {
            if t > now {
                break;
            }
            op.next_loss += 1;
            let w = sim.env_mut();
            let active = w
                .conditions
                .get(id)
                .is_some_and(|c| c.status == Status::Active);
            if active && !op.lost.contains_key(&id) {
                w.conditions.update(id, |c| c.status = Status::Down);
                op.lost.insert(id, t);
                let name = sim.entities().name(id).unwrap_or("a UAV").to_owned();
                op.log.push((t, format!("{name} lost")));
            }
        }
    }

    /// What happened since the last call: losses, awards, presumptions, in time order.
    fn drain_log(run: &mut SurveillanceRun) -> Vec<(SimTime, String)> {
        let (sim, op) = (&run.sim, &mut run.play);
        let mut out = std::mem::take(&mut op.log);
        let station = sim.agent(EntityId(0)).map(|a| a.as_any());
        if let Some(s) = station.and_then(|a| a.downcast_ref::<agents::station::Station>()) {
            out.extend(s.log.iter().skip(op.station_log).cloned());
            op.station_log = s.log.len();
        }
        out.sort_by_key(|(t, _)| *t);
        out
    }
}

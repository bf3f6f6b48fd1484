//! # A mission in a few lines: the generic run
//!
//! Every run of every mission holds the same things: the simulation, the scenario's name,
//! the seed, the end time, the sample period, a listener that keeps the radio messages for
//! the frames, and an advance loop that stops at each sample. A [`Session`] holds them, and is
//! a [`Run`](crate::Run) for the tools, once the mission says what is its own in a [`Play`]:
//!
//! - its model and its metrics ([`Play::Metrics`], a [`MetricTable`]);
//! - the human summary ([`Play::summary`]) and the static world ([`Play::scene`], e.g. the site
//!   drawn by [`crate::scene::site_scene`] with the mission's places);
//! - what each frame shows ([`Play::frame`]: entities, detections, intentions; the session
//!   fills in the time, the events, the messages and the metrics);
//! - where it may: its end condition ([`Play::over`], checked after every event), what it does
//!   at each sample ([`Play::at_sample`]) or at a time of its own ([`Play::next_stop`],
//!   [`Play::at_stop`]), its verdict, its log, and its state beside the simulation for
//!   snapshots ([`Play::save`], [`Play::restore`], [`Play::world`]).
//!
//! A session dereferences to its play, so a mission's fields read as the run's
//! (`run.referee`, `run.members`), and the play's hooks are given the whole session.
//! Everything is generic: the loop costs what a hand-written one does, event for event.
//!
//! ```
//! use vitro::prelude::*;
//! use vitro_mission::session::{Play, Session, Setup};
//! use vitro_mission::{Metric, MetricTable, Run, metric_table};
//! use vitro_record::{Frame, Scene};
//!
//! // A model: a counter that ticks every second.
//! struct Tick;
//! struct Ticks;
//! impl Model for Ticks {
//!     type Env = u64;
//!     type Event = ();
//!     type Msg = ();
//!     type Agent = Tick;
//!     fn state_digest(n: &u64) -> u64 {
//!         *n
//!     }
//! }
//! impl Agent<Ticks> for Tick {
//!     fn handle(&mut self, _: Input<'_, Ticks>, cx: &mut Context<'_, Ticks>) {
//!         cx.schedule_in(SimDuration::from_secs(1), ());
//!     }
//! }
//!
//! // The mission's own part: its metrics, its summary, its pictures.
//! #[derive(Default)]
//! struct Count {
//!     events: u64,
//!     samples: u32,
//! }
//! impl MetricTable for Count {
//!     fn table(&self) -> Vec<(&'static str, Metric)> {
//!         metric_table!(self; events, samples)
//!     }
//! }
//! #[derive(Default)]
//! struct Counting {
//!     samples: u32,
//! }
//! impl Play for Counting {
//!     type Model = Ticks;
//!     type Metrics = Count;
//!     type Heard = ();
//!     fn metrics(run: &Session<Self>) -> Count {
//!         Count { events: run.sim.events_fired(), samples: run.samples }
//!     }
//!     fn summary(_: &Session<Self>, m: &Count) -> Vec<(String, String)> {
//!         vec![("ticks".into(), format!("{} events", m.events))]
//!     }
//!     fn at_sample(run: &mut Session<Self>, _: SimTime) {
//!         run.samples += 1;
//!     }
//!     fn scene(run: &Session<Self>) -> Scene {
//!         Scene::flat(run.name.clone(), 0, [0.0, 0.0, 10.0, 10.0])
//!     }
//!     fn frame(_: &mut Session<Self>, _: &mut Frame) {}
//! }
//!
//! let mut sim = Simulation::<Ticks>::new(0, 7);
//! let id = sim.add_agent("tick", Tick).unwrap();
//! sim.schedule(SimTime::ZERO, Target::Entity(id), ()).unwrap();
//! let setup = Setup::new("ticks", 7, SimTime::from_secs(60), SimDuration::from_secs(10));
//! let mut run = Session::new(setup, sim, Counting::default());
//! while run.advance(run.end) {}
//! assert_eq!(run.metrics().events, 61);
//! assert_eq!(run.samples, 8); // at 0, 10, ..., 60 s, and once more at the end
//! // The tools see a `Run`: the table and the trace hash.
//! assert_eq!(Session::<Counting>::metric_names(), ["events", "samples", "trace_hash"]);
//! assert_eq!(Run::metrics(&run)[0], ("events", Metric::Int(61)));
//! ```

mod heard;
mod run;

pub use heard::Heard;

use crate::{MetricTable, RunFailed, SnapshotError};
use std::ops::{Deref, DerefMut};
use std::sync::{Arc, Mutex, MutexGuard};
use vitro::sim::{Fired, Model, Simulation, StopReason};
use vitro::time::{SimDuration, SimTime, UtcTime};
use vitro_record::{Frame, Scene};

/// A mission's own part of a run: what the generic [`Session`] cannot decide for it.
///
/// The hooks are given the whole session (the simulation, the settings, and the play itself
/// through [`Deref`]). Only the metrics, the summary, the scene and the frame must be written.
pub trait Play: Sized + 'static {
    /// The simulation's model.
    type Model: Model;
    /// What the mission measures.
    type Metrics: MetricTable;
    /// What the listener keeps of the fired events beside the messages (`()`: nothing);
    /// saved with the run.
    type Heard: Default + Clone + Send + serde::Serialize + serde::de::DeserializeOwned + 'static;

    /// The metrics so far.
    fn metrics(run: &Session<Self>) -> Self::Metrics;
    /// The human summary's lines, e.g. `("outcome", "SUCCESS: ...")`.
    fn summary(run: &Session<Self>, m: &Self::Metrics) -> Vec<(String, String)>;
    /// The static world, drawn once.
    fn scene(run: &Session<Self>) -> Scene;
    /// Draws the state now into `frame`, whose time, event count, messages and metrics the
    /// session filled in (entities, detections, intentions, sensors, log are the play's).
    fn frame(run: &mut Session<Self>, frame: &mut Frame);

    /// True once the mission is decided (checked before the first event of each stretch and
    /// after every event: keep it cheap). By default never: the run goes to its end.
    #[inline]
    fn over(&self, sim: &Simulation<Self::Model>) -> bool {
        let _ = sim;
        false
    }
    /// What the listener keeps of each fired event (called after every event: keep it cheap).
    /// By default the messages, once watched, of kind [`message_kind`](Self::message_kind).
    #[inline]
    fn hear(heard: &mut Heard<Self::Heard>, f: &Fired<'_, Self::Model>) {
        heard.keep(f, Self::message_kind);
    }
    /// The name of a message's kind in recordings (e.g. `"contact"`). By default `"message"`.
    fn message_kind(msg: &<Self::Model as Model>::Msg) -> &'static str {
        let _ = msg;
        "message"
    }
    /// The next time the run must stop for the mission (e.g. a loss due then); by default
    /// none.
    fn next_stop(&self) -> SimTime {
        SimTime::MAX
    }
    /// Called at every stop in time (a sample, the mission's own [`next_stop`](Self::next_stop),
    /// the time a caller advanced to, the end), before the sample if one is due.
    fn at_stop(run: &mut Session<Self>, now: SimTime) {
        let _ = (run, now);
    }
    /// Called every sample period, once more when the run ends, and when the mission is
    /// decided ([`over`](Self::over)).
    fn at_sample(run: &mut Session<Self>, now: SimTime) {
        let _ = (run, now);
    }
    /// The simulated time reached, as [`Run::now`](crate::Run::now) says it: by default the
    /// time of the last event.
    fn now(run: &Session<Self>) -> SimTime {
        run.sim.now()
    }
    /// Whether the run broke (an agent failed), checked after each advance.
    ///
    /// # Errors
    /// [`RunFailed`] with why.
    fn check(run: &Session<Self>) -> Result<(), RunFailed> {
        let _ = run;
        Ok(())
    }
    /// The verdict on the run so far ([`Run::verdict`](crate::Run::verdict)); by default `Ok`.
    ///
    /// # Errors
    /// Why the mission failed.
    fn verdict(run: &Session<Self>, m: &Self::Metrics) -> Result<(), String> {
        let _ = (run, m);
        Ok(())
    }
    /// The run's own fields of `vitro run --json`; by default the metrics' table.
    fn report(
        run: &Session<Self>,
        m: &Self::Metrics,
    ) -> serde_json::Map<String, serde_json::Value> {
        let _ = run;
        m.json()
    }
    /// What happened since the last call, for `--verbose`; by default nothing.
    fn drain_log(run: &mut Session<Self>) -> Vec<(SimTime, String)> {
        let _ = run;
        Vec::new()
    }
    /// A digest of what a run rebuilds from its scenario rather than saves (its site, its
    /// programs, its town): a snapshot restores only onto a build with the same. By default
    /// 0 (nothing checked).
    fn world(run: &Session<Self>) -> u64 {
        let _ = run;
        0
    }
    /// The mission's state as bytes: the simulation (without the static world) and the
    /// play's own fields; the session saves its own beside. By default the mission cannot
    /// save.
    ///
    /// # Errors
    /// [`SnapshotError::Unsupported`] if it cannot.
    fn save(run: &Session<Self>) -> Result<Vec<u8>, SnapshotError> {
        Err(SnapshotError::Unsupported(run.name.clone()))
    }
    /// Puts the play's own fields of a state [`save`](Self::save) made into this run (a
    /// fresh build of the same scenario) and returns the simulation it holds; the session
    /// listens to it and takes it.
    ///
    /// # Errors
    /// [`SnapshotError::Corrupt`] if the state does not decode,
    /// [`SnapshotError::Unsupported`] by default.
    fn restore(
        run: &mut Session<Self>,
        state: &[u8],
    ) -> Result<Simulation<Self::Model>, SnapshotError> {
        let _ = state;
        Err(SnapshotError::Unsupported(run.name.clone()))
    }
}

/// A run's settings, as its scenario and build options give them.
#[derive(Clone, Debug, PartialEq)]
pub struct Setup {
    /// The scenario's name.
    pub name: String,
    /// The master seed.
    pub seed: u64,
    /// When simulated time 0 is on the calendar.
    pub start: UtcTime,
    /// When the run ends at the latest.
    pub end: SimTime,
    /// Simulated time between samples (frames, series rows, the play's samples).
    pub sample: SimDuration,
}

impl Setup {
    /// The settings of a run named `name` with `seed`, ending at `end` and sampled every
    /// `sample` (at least a millisecond), starting at [`UtcTime::DEFAULT_START`].
    pub fn new(name: impl Into<String>, seed: u64, end: SimTime, sample: SimDuration) -> Setup {
        Setup {
            name: name.into(),
            seed,
            start: UtcTime::DEFAULT_START,
            end,
            sample: sample.max(SimDuration::from_millis(1)),
        }
    }

    /// The settings of a scenario that gives its end and sample period in seconds (the
    /// period at least 10 ms) and maybe its start on the calendar.
    pub fn from_secs(
        name: impl Into<String>,
        seed: u64,
        end_s: f64,
        sample_s: f64,
        start: Option<UtcTime>,
    ) -> Setup {
        let end = SimTime::from_secs_f64(end_s);
        let sample = SimDuration::from_secs_f64(sample_s.max(0.01));
        Setup {
            start: start.unwrap_or(UtcTime::DEFAULT_START),
            ..Setup::new(name, seed, end, sample)
        }
    }
}

/// One run of a mission: the simulation, the settings and the mission's [`Play`]; a
/// [`Run`](crate::Run) for the tools.
pub struct Session<P: Play> {
    /// The simulation (its `control()` drives pacing from another thread).
    pub sim: Simulation<P::Model>,
    /// The scenario's name.
    pub name: String,
    /// The master seed.
    pub seed: u64,
    /// When simulated time 0 is on the calendar.
    pub start: UtcTime,
    /// When the run ends at the latest.
    pub end: SimTime,
    /// Simulated time between samples.
    pub sample: SimDuration,
    /// The mission's own part (also reached through [`Deref`]).
    pub play: P,
    heard: Arc<Mutex<Heard<P::Heard>>>,
    next_sample: SimTime,
    reached: SimTime,
    stop: Option<StopReason>,
    finished: bool,
}

impl<P: Play> Deref for Session<P> {
    type Target = P;
    fn deref(&self) -> &P {
        &self.play
    }
}

impl<P: Play> DerefMut for Session<P> {
    fn deref_mut(&mut self) -> &mut P {
        &mut self.play
    }
}

impl<P: Play> Session<P> {
    /// A run of `sim` with `setup`, the mission's part `play`; listens to the simulation.
    pub fn new(setup: Setup, sim: Simulation<P::Model>, play: P) -> Session<P> {
        let mut run = Session {
            sim,
            name: setup.name,
            seed: setup.seed,
            start: setup.start,
            end: setup.end,
            sample: setup.sample,
            play,
            heard: Arc::default(),
            next_sample: SimTime::ZERO,
            reached: SimTime::ZERO,
            stop: None,
            finished: false,
        };
        run.listen();
        run
    }

    /// The names [`Run::metrics`](crate::Run::metrics) gives, in order: the play's table and
    /// `trace_hash` (a mission's `Mission::metric_names`).
    pub fn metric_names() -> Vec<&'static str> {
        let mut names = P::Metrics::names();
        names.push("trace_hash");
        names
    }

    /// Adds the listener that keeps what [`Play::hear`] says.
    fn listen(&mut self) {
        let sink = self.heard.clone();
        self.sim.add_listener(move |f| {
            if let Ok(mut h) = sink.lock() {
                P::hear(&mut h, f);
            }
        });
    }

    /// What the listener kept (messages and the play's own).
    pub fn heard(&self) -> MutexGuard<'_, Heard<P::Heard>> {
        self.heard.lock().unwrap_or_else(|p| p.into_inner())
    }

    /// True once the run is over: decided, out of time or out of events.
    pub fn finished(&self) -> bool {
        self.finished
    }

    /// The time the run was advanced to: the time asked for at a stop in time, the last
    /// event's otherwise.
    pub fn reached(&self) -> SimTime {
        self.reached
    }

    /// Why the simulation last returned (`None` before the first advance).
    pub fn stop(&self) -> Option<StopReason> {
        self.stop
    }

    /// Runs until simulated time `until` (events at that time included) or the end, calling
    /// the play at its stops and samples; false once the run is over.
    pub fn advance(&mut self, until: SimTime) -> bool {
        while !self.finished {
            let next = (self.next_sample.min(self.end).min(until)).min(self.play.next_stop());
            let play = &self.play;
            let reason = self.sim.run(next, |s| play.over(s));
            self.stop = Some(reason);
            self.reached = if reason == StopReason::Time {
                next
            } else {
                self.sim.now()
            };
            match reason {
                StopReason::Control => break,
                StopReason::Condition | StopReason::Requested => {
                    P::at_sample(self, self.sim.now());
                    self.finished = true;
                }
                StopReason::Time | StopReason::QueueEmpty => {
                    P::at_stop(self, next);
                    if next == self.next_sample {
                        P::at_sample(self, next);
                        self.next_sample += self.sample;
                    }
                    if reason == StopReason::QueueEmpty || next >= self.end {
                        P::at_sample(self, next);
                        self.finished = true;
                    } else if next >= until {
                        break;
                    }
                }
            }
        }
        !self.finished
    }

    /// Runs to the end and returns the metrics.
    pub fn run(&mut self) -> P::Metrics {
        while self.advance(self.end) {}
        self.metrics()
    }

    /// The metrics so far.
    pub fn metrics(&self) -> P::Metrics {
        P::metrics(self)
    }

    /// The static world. From the first call on, the messages are kept for the frames.
    pub fn scene(&self) -> Scene {
        self.heard().watched = true;
        P::scene(self)
    }

    /// The state now; the messages since the last frame are moved into it.
    pub fn frame(&mut self) -> Frame {
        let mut frame = Frame {
            t_ns: P::now(self).as_nanos(),
            events: self.sim.events_fired(),
            messages: std::mem::take(&mut self.heard().messages),
            metrics: self.metrics().numbers(),
            ..Frame::default()
        };
        P::frame(self, &mut frame);
        frame
    }
}

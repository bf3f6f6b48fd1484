//! A live view: the simulation runs on its own thread, paced, and publishes frames.
//!
//! The simulation thread never waits for a viewer. It runs in slices (about one frame of wall
//! time each), publishes the latest frame into a [`watch`] channel (each client picks up
//! the newest when it is ready: latest frame wins) and goes on. Viewers act on the run only
//! through its [`Control`] handle, which changes *when* events fire in wall time, never
//! *which*: the trace hash of a watched run is that of the unwatched one.

use crate::ViewError;
use crate::protocol::{Command, CommandError, Hello, History, Mode, ServerMsg, Status};
use std::sync::atomic::{AtomicBool, Ordering};
use std::sync::{Arc, Mutex, MutexGuard};
use std::thread::JoinHandle;
use std::time::{Duration, Instant};
use tokio::sync::watch;
use vitro::prelude::{Model, SimTime, Simulation, StopReason};
use vitro::sim::Control;
use vitro_record::{Frame, Scene};

/// Wall time between published frames while the run goes on.
pub const FRAME_WALL: Duration = Duration::from_millis(40);

/// An error a source reports (its controller failed, its state is inconsistent).
pub type SourceError = Box<dyn std::error::Error + Send + Sync>;

/// How far [`LiveSource::advance`] got.
#[derive(Copy, Clone, Debug, PartialEq, Eq)]
pub enum Advance {
    /// It reached the requested time.
    Reached,
    /// It returned early: the interrupt held after an event, or the control handle's `stop`.
    Interrupted,
    /// The run is over (end time or end condition reached, nothing left to happen).
    Finished,
}

/// A simulation the viewer can run and show: what a scenario implements to be watched.
pub trait LiveSource: Send + 'static {
    /// What is shown (the scenario's name).
    fn title(&self) -> String;
    /// The static world.
    fn scene(&self) -> Scene;
    /// The simulation's control handle.
    fn control(&self) -> Control;
    /// When the run ends, if it has an end time, simulated nanoseconds.
    fn end_ns(&self) -> Option<u64>;
    /// Simulated time between frames when the run is not paced, nanoseconds.
    fn sample_ns(&self) -> u64 {
        1_000_000_000
    }
    /// Runs up to `until_ns` (events at that time included), returning early when
    /// `interrupt` holds after an event or when the control handle's `stop` is called.
    /// [`advance_sim`] does it for a [`Simulation`].
    fn advance(
        &mut self,
        until_ns: u64,
        interrupt: &mut dyn FnMut() -> bool,
    ) -> Result<Advance, SourceError>;
    /// The state now, shown as of `t_ns` (the time reached). Must not change the run.
    fn frame(&mut self, t_ns: u64) -> Frame;
    /// The trace hash so far.
    fn trace_hash(&self) -> u64;
}

/// Runs `sim` up to `until_ns` for [`LiveSource::advance`]: an early return is
/// [`Advance::Interrupted`]; an empty queue or a stop requested by an agent is
/// [`Advance::Finished`]. (An end time is the source's to check.)
pub fn advance_sim<M: Model>(
    sim: &mut Simulation<M>,
    until_ns: u64,
    interrupt: &mut dyn FnMut() -> bool,
) -> Advance {
    match sim.run(SimTime::from_nanos(until_ns), |_| interrupt()) {
        StopReason::Time => Advance::Reached,
        StopReason::Condition | StopReason::Control => Advance::Interrupted,
        StopReason::QueueEmpty | StopReason::Requested => Advance::Finished,
    }
}

/// How a live run ended.
#[derive(Clone, Debug, PartialEq)]
pub struct Outcome {
    /// Simulated time reached, nanoseconds.
    pub t_ns: u64,
    /// Events fired.
    pub events: u64,
    /// The trace hash.
    pub trace_hash: u64,
    /// Why it stopped early, if the source failed.
    pub failure: Option<String>,
    /// True if it was stopped from outside ([`LiveRun::stop`]) before its end.
    pub stopped: bool,
}

/// What the simulation thread shares with the server.
struct Shared {
    control: Control,
    hello: Hello,
    scene_json: Arc<str>,
    history: Mutex<History>,
    frames: watch::Sender<Option<Arc<str>>>,
    outcome: watch::Sender<Option<Outcome>>,
    quit: AtomicBool,
}

fn lock<T>(m: &Mutex<T>) -> MutexGuard<'_, T> {
    // The data behind these locks stays consistent even if a holder panicked.
    m.lock().unwrap_or_else(|e| e.into_inner())
}

/// A running live view: the simulation thread and what clients read from it.
///
/// Clones share the same run.
#[derive(Clone)]
pub struct LiveRun {
    shared: Arc<Shared>,
    thread: Arc<Mutex<Option<JoinHandle<()>>>>,
}

impl LiveRun {
    /// Starts `source` on a new thread, paced at `speed` simulated seconds per wall second
    /// (`None`: as fast as possible), paused first if `paused`.
    pub fn start(
        source: impl LiveSource,
        speed: Option<f64>,
        paused: bool,
    ) -> Result<LiveRun, ViewError> {
        let control = source.control();
        match speed {
            Some(s) => control.set_speed(s)?,
            None => control.unpaced(),
        }
        if paused {
            control.pause();
        }
        let scene = source.scene();
        let hello = Hello {
            mode: Mode::Live,
            title: source.title(),
            start_ns: control.sim_time().as_nanos(),
            end_ns: source.end_ns(),
        };
        let scene_json = ServerMsg::Scene {
            scene: Box::new(scene),
        }
        .to_json();
        let shared = Arc::new(Shared {
            control,
            hello,
            scene_json: scene_json.into(),
            history: Mutex::new(History::default()),
            frames: watch::Sender::new(None),
            outcome: watch::Sender::new(None),
            quit: AtomicBool::new(false),
        });
        let inner = shared.clone();
        let thread = std::thread::Builder::new()
            .name("vitro-sim".into())
            .spawn(move || run_loop(source, &inner))
            .map_err(ViewError::Thread)?;
        Ok(LiveRun {
            shared,
            thread: Arc::new(Mutex::new(Some(thread))),
        })
    }

    /// The simulation's control handle.
    pub fn control(&self) -> Control {
        self.shared.control.clone()
    }

    /// The first message to a client.
    pub fn hello(&self) -> Hello {
        self.shared.hello.clone()
    }

    /// The scene message, as JSON.
    pub fn scene_json(&self) -> Arc<str> {
        self.shared.scene_json.clone()
    }

    /// The metrics so far.
    pub fn history(&self) -> History {
        lock(&self.shared.history).clone()
    }

    /// The latest frame message (JSON), as it changes.
    pub fn frames(&self) -> watch::Receiver<Option<Arc<str>>> {
        self.shared.frames.subscribe()
    }

    /// How the run ended, once it has.
    pub fn outcome(&self) -> Option<Outcome> {
        self.shared.outcome.borrow().clone()
    }

    /// Waits for the end of the run.
    pub async fn finished(&self) -> Outcome {
        let mut rx = self.shared.outcome.subscribe();
        loop {
            if let Some(o) = rx.borrow_and_update().clone() {
                return o;
            }
            if rx.changed().await.is_err() {
                // The sender lives in `shared`, which we hold: unreachable, but do not spin.
                std::future::pending::<()>().await;
            }
        }
    }

    /// Where the run stands.
    pub fn status(&self) -> Status {
        let c = &self.shared.control;
        let outcome = self.outcome();
        Status {
            paused: c.is_paused(),
            speed: c.speed(),
            t_ns: c.sim_time().as_nanos(),
            events: c.events_fired(),
            finished: outcome.is_some(),
            trace_hash: outcome.as_ref().map(|o| format!("{:016x}", o.trace_hash)),
            failure: outcome.and_then(|o| o.failure),
        }
    }

    /// Applies a client command to the run.
    pub fn apply(&self, cmd: &Command) -> Result<(), CommandError> {
        let c = &self.shared.control;
        match *cmd {
            Command::Pause {} => {
                c.pause();
                // Wakes the simulation thread so it shows the state where it paused.
                c.stop();
            }
            Command::Resume {} => c.resume(),
            Command::Step { n } => {
                if !c.is_paused() {
                    c.pause();
                    c.stop();
                }
                c.step(n);
            }
            Command::Speed { factor } => {
                c.set_speed(factor)
                    .map_err(|e| CommandError::OutOfRange(e.to_string()))?;
                // Wakes the simulation thread so the next frame comes at the new pace.
                c.stop();
            }
            Command::Seek { .. } => return Err(CommandError::Unavailable("seek", Mode::Live)),
        }
        Ok(())
    }

    /// Stops the run (if it is still going) and waits for its thread; the outcome.
    pub fn stop(&self) -> Option<Outcome> {
        self.shared.quit.store(true, Ordering::SeqCst);
        self.shared.control.stop();
        if let Some(t) = lock(&self.thread).take() {
            // A panic on the simulation thread was already reported by the panic hook.
            let _ = t.join();
        }
        self.outcome()
    }
}

/// The simulation thread: run a slice, publish a frame, repeat.
fn run_loop(mut source: impl LiveSource, shared: &Shared) {
    let ctl = shared.control.clone();
    let end = source.end_ns();
    let mut t = ctl.sim_time().as_nanos();
    publish(&mut source, shared, t);
    let mut last_publish = Instant::now();
    let (failure, stopped) = loop {
        if shared.quit.load(Ordering::SeqCst) {
            break (None, true);
        }
        let slice = match ctl.speed() {
            Some(speed) => (speed * FRAME_WALL.as_secs_f64() * 1e9) as u64,
            None => source.sample_ns(),
        };
        let mut until = t.saturating_add(slice.max(1_000_000));
        if let Some(end) = end {
            until = until.min(end);
        }
        let start = ctl.events_fired();
        let step = source.advance(until, &mut || ctl.is_paused() && ctl.events_fired() > start);
        match step {
            Err(e) => {
                t = t.max(ctl.sim_time().as_nanos());
                break (Some(e.to_string()), false);
            }
            Ok(Advance::Reached) if end.is_some_and(|e| until >= e) => {
                t = until;
                break (None, false);
            }
            Ok(Advance::Reached) => t = until,
            Ok(Advance::Interrupted) => {
                t = t.max(ctl.sim_time().as_nanos());
                publish(&mut source, shared, t);
                last_publish = Instant::now();
                continue;
            }
            Ok(Advance::Finished) => {
                t = t.max(ctl.sim_time().as_nanos());
                break (None, false);
            }
        }
        if last_publish.elapsed() >= FRAME_WALL {
            publish(&mut source, shared, t);
            last_publish = Instant::now();
        }
    };
    publish(&mut source, shared, t);
    shared.outcome.send_replace(Some(Outcome {
        t_ns: t,
        events: ctl.events_fired(),
        trace_hash: source.trace_hash(),
        failure,
        stopped,
    }));
}

fn publish(source: &mut impl LiveSource, shared: &Shared, t_ns: u64) {
    let frame = source.frame(t_ns);
    lock(&shared.history).push(&frame);
    let json = ServerMsg::Frame {
        frame: Box::new(frame),
    }
    .to_json();
    shared.frames.send_replace(Some(json.into()));
}

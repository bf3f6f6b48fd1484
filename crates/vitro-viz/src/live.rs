//! A live view: the simulation runs on its own thread, paced, and publishes frames.
//!
//! The simulation thread never waits for a viewer. It runs in slices (about one frame of wall
//! time each), publishes the latest frame into a [`watch`] channel (each client picks up
//! the newest when it is ready: latest frame wins) and goes on. The page's clients and the
//! Foxglove server's read the same channel ([`Published`]: the frame and its page message). Viewers act on the run only
//! through its [`Control`] handle, which changes *when* events fire in wall time, never
//! *which*: the trace hash of a watched run is that of the unwatched one.

pub use crate::error::SourceError;
use crate::error::ViewError;
use crate::protocol::{
    Command, CommandError, Hello, History, Mode, Status, frame_json, scene_json,
};
use std::sync::atomic::{AtomicBool, AtomicU64, Ordering};
use std::sync::{Arc, Mutex, MutexGuard};
use std::thread::JoinHandle;
use std::time::{Duration, Instant};
use tokio::sync::watch;
use vitro::prelude::{Model, SimTime, Simulation, StopReason};
use vitro::sim::Control;
use vitro_record::{Frame, Scene};

/// Wall time between published frames while the run goes on.
pub const FRAME_WALL: Duration = Duration::from_millis(40);

/// A simulation the viewer can run and show: what a scenario implements to be watched.
///
/// It lives on the simulation thread (built there by [`LiveRun::spawn`] if it cannot move
/// between threads).
pub trait LiveSource: 'static {
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
    /// Runs up to `until_ns` (events at that time included), returning early when the
    /// control handle's `stop` is called; `Ok(false)` once the run is over (end time, end
    /// condition, nothing left to happen). [`advance_sim`] does it for a [`Simulation`].
    fn advance(&mut self, until_ns: u64) -> Result<bool, SourceError>;
    /// The state now, shown as of `t_ns` (the time reached). Must not change the run.
    fn frame(&mut self, t_ns: u64) -> Frame;
    /// The trace hash so far.
    fn trace_hash(&self) -> u64;
}

/// Runs `sim` up to `until_ns` for [`LiveSource::advance`]: false once its queue is empty
/// or an agent asked to stop. (An end time is the source's to check.)
pub fn advance_sim<M: Model>(sim: &mut Simulation<M>, until_ns: u64) -> bool {
    match sim.run_until(SimTime::from_nanos(until_ns)) {
        StopReason::Time | StopReason::Control | StopReason::Condition => true,
        StopReason::QueueEmpty | StopReason::Requested => false,
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

/// A frame as the simulation thread publishes it.
#[derive(Clone, Debug)]
pub struct Published {
    /// The frame.
    pub frame: Arc<Frame>,
    /// Its page message ([`ServerMsg::Frame`](crate::protocol::ServerMsg::Frame)), as JSON.
    pub json: Arc<str>,
}

/// What the simulation thread shares with the server.
struct Shared {
    control: Control,
    hello: Hello,
    scene: Arc<Scene>,
    scene_json: Arc<str>,
    history: Mutex<History>,
    frames: watch::Sender<Option<Published>>,
    outcome: watch::Sender<Option<Outcome>>,
    quit: AtomicBool,
    /// How many times the run was interrupted (made to return from `advance`) so far.
    interrupts: AtomicU64,
    /// Steps asked for and not yet handed to the control handle.
    steps: Mutex<u64>,
}

impl Shared {
    /// Makes the simulation thread return from `advance` (before its next event) and show
    /// the state it reached.
    fn interrupt(&self) {
        self.interrupts.fetch_add(1, Ordering::SeqCst);
        self.control.stop();
    }
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
        source: impl LiveSource + Send,
        speed: Option<f64>,
        paused: bool,
    ) -> Result<LiveRun, ViewError> {
        LiveRun::spawn(move || Ok(source), speed, paused)
    }

    /// Builds a source on a new thread with `build` and runs it there (for sources that
    /// cannot move between threads), paced at `speed`, paused first if `paused`.
    pub fn spawn<S: LiveSource>(
        build: impl FnOnce() -> Result<S, SourceError> + Send + 'static,
        speed: Option<f64>,
        paused: bool,
    ) -> Result<LiveRun, ViewError> {
        let (tx, rx) = std::sync::mpsc::sync_channel(1);
        let thread = std::thread::Builder::new()
            .name("vitro-sim".into())
            .spawn(move || {
                let ready = build()
                    .map_err(ViewError::Source)
                    .and_then(|source| prepare(source, speed, paused));
                match ready {
                    Ok((source, shared)) => {
                        // The caller may have given up waiting: then nobody watches this run.
                        if tx.send(Ok(shared.clone())).is_ok() {
                            run_loop(source, shared);
                        }
                    }
                    Err(e) => {
                        let _ = tx.send(Err(e));
                    }
                }
            })
            .map_err(ViewError::Thread)?;
        match rx.recv() {
            Ok(Ok(shared)) => Ok(LiveRun {
                shared,
                thread: Arc::new(Mutex::new(Some(thread))),
            }),
            Ok(Err(e)) => Err(e),
            Err(_) => Err(ViewError::Source(
                "the simulation thread ended while starting".into(),
            )),
        }
    }

    /// The simulation's control handle.
    pub fn control(&self) -> Control {
        self.shared.control.clone()
    }

    /// The first message to a client.
    pub fn hello(&self) -> Hello {
        self.shared.hello.clone()
    }

    /// The static world.
    pub fn scene(&self) -> Arc<Scene> {
        self.shared.scene.clone()
    }

    /// The scene message, as JSON.
    pub fn scene_json(&self) -> Arc<str> {
        self.shared.scene_json.clone()
    }

    /// The metrics so far.
    pub fn history(&self) -> History {
        lock(&self.shared.history).clone()
    }

    /// The latest frame, as it changes.
    pub fn frames(&self) -> watch::Receiver<Option<Published>> {
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
    ///
    /// A step pauses the run and fires exactly `n` more events; the simulation thread hands
    /// the steps to the control handle when it is out of `advance`, so that it knows where
    /// they start and can show the state after the last one.
    pub fn apply(&self, cmd: &Command) -> Result<(), CommandError> {
        let s = &self.shared;
        match *cmd {
            Command::Pause {} => {
                s.control.pause();
                s.interrupt();
            }
            Command::Resume {} => s.control.resume(),
            Command::Step { n } => {
                *lock(&s.steps) += n;
                s.control.pause();
                s.interrupt();
            }
            Command::Speed { factor } => {
                s.control
                    .set_speed(factor)
                    .map_err(|e| CommandError::OutOfRange(e.to_string()))?;
                // The next frame comes at the new pace.
                s.interrupt();
            }
            Command::Seek { .. } => return Err(CommandError::Unavailable("seek", Mode::Live)),
        }
        Ok(())
    }

    /// Stops the run (if it is still going) and waits for its thread; the outcome.
    pub fn stop(&self) -> Option<Outcome> {
        self.shared.quit.store(true, Ordering::SeqCst);
        self.shared.interrupt();
        if let Some(t) = lock(&self.thread).take() {
            // A panic on the simulation thread was already reported by the panic hook.
            let _ = t.join();
        }
        self.outcome()
    }
}

/// Sets the pace of `source` and what its clients get first.
fn prepare<S: LiveSource>(
    source: S,
    speed: Option<f64>,
    paused: bool,
) -> Result<(S, Arc<Shared>), ViewError> {
    let control = source.control();
    match speed {
        Some(s) => control.set_speed(s)?,
        None => control.unpaced(),
    }
    if paused {
        control.pause();
    }
    let hello = Hello {
        mode: Mode::Live,
        title: source.title(),
        start_ns: control.sim_time().as_nanos(),
        end_ns: source.end_ns(),
    };
    let scene = source.scene();
    let scene_json = scene_json(&scene);
    let shared = Arc::new(Shared {
        control,
        hello,
        scene: Arc::new(scene),
        scene_json: scene_json.into(),
        history: Mutex::new(History::default()),
        frames: watch::Sender::new(None),
        outcome: watch::Sender::new(None),
        quit: AtomicBool::new(false),
        interrupts: AtomicU64::new(0),
        steps: Mutex::new(0),
    });
    Ok((source, shared))
}

/// The simulation thread: run a slice, publish a frame, repeat.
fn run_loop(mut source: impl LiveSource, shared: Arc<Shared>) {
    let ctl = shared.control.clone();
    let end = source.end_ns();
    let mut t = ctl.sim_time().as_nanos();
    publish(&mut source, &shared, t);
    let mut last_publish = Instant::now();
    let mut shown_events = ctl.events_fired();
    // Interrupts counted up to the last look: one that came while this thread was between
    // slices (after a publish, before `advance`) still gets its frame.
    let mut seen_interrupts = shared.interrupts.load(Ordering::SeqCst);
    let (failure, stopped) = loop {
        if shared.quit.load(Ordering::SeqCst) {
            break (None, true);
        }
        let steps = std::mem::take(&mut *lock(&shared.steps));
        if steps > 0 {
            watch_steps(&shared, ctl.events_fired() + steps);
            ctl.step(steps);
        }
        let slice = match ctl.speed() {
            Some(speed) => (speed * FRAME_WALL.as_secs_f64() * 1e9) as u64,
            None => source.sample_ns(),
        };
        let mut until = t.saturating_add(slice.max(1_000_000));
        if let Some(end) = end {
            until = until.min(end);
        }
        let going = match source.advance(until) {
            Ok(going) => going,
            Err(e) => {
                t = t.max(ctl.sim_time().as_nanos());
                break (Some(e.to_string()), false);
            }
        };
        let interrupts = shared.interrupts.load(Ordering::SeqCst);
        let interrupted = interrupts != seen_interrupts;
        seen_interrupts = interrupts;
        let at_end = !interrupted && end.is_some_and(|e| until >= e);
        // Up to `until` if it was reached (the run is over at its end time); otherwise up to
        // the last event (interrupted, or over early: its end condition, no event left).
        t = if at_end || (going && !interrupted) {
            until
        } else {
            t.max(ctl.sim_time().as_nanos())
        };
        if !going || at_end {
            break (None, false);
        }
        // A paused run shows where it stopped even when the interrupt that stopped it was
        // counted before this slice began (it then looks like no interrupt at all).
        let unshown_pause = ctl.is_paused() && ctl.events_fired() != shown_events;
        if interrupted || unshown_pause || last_publish.elapsed() >= FRAME_WALL {
            publish(&mut source, &shared, t);
            last_publish = Instant::now();
            shown_events = ctl.events_fired();
        }
    };
    publish(&mut source, &shared, t);
    shared.outcome.send_replace(Some(Outcome {
        t_ns: t,
        events: ctl.events_fired(),
        trace_hash: source.trace_hash(),
        failure,
        stopped,
    }));
}

/// Interrupts the run once `target` events have fired (the last of some steps), so the
/// state after them is shown; gives up if the run resumes or ends first.
fn watch_steps(shared: &Arc<Shared>, target: u64) {
    const GIVE_UP: Duration = Duration::from_secs(60);
    let watcher = shared.clone();
    let spawned = std::thread::Builder::new()
        .name("vitro-steps".into())
        .spawn(move || {
            let started = Instant::now();
            let c = &watcher.control;
            while c.events_fired() < target
                && c.is_paused()
                && watcher.outcome.borrow().is_none()
                && started.elapsed() < GIVE_UP
            {
                std::thread::sleep(Duration::from_millis(1));
            }
            watcher.interrupt();
        });
    if spawned.is_err() {
        // No thread to watch: interrupt now; the steps still fire, shown at the next frame.
        shared.interrupt();
    }
}

fn publish(source: &mut impl LiveSource, shared: &Shared, t_ns: u64) {
    let frame = source.frame(t_ns);
    lock(&shared.history).push(&frame);
    let json = frame_json(&frame);
    shared.frames.send_replace(Some(Published {
        frame: Arc::new(frame),
        json: json.into(),
    }));
}

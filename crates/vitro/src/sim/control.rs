//! Pacing and remote control of a running simulation.
//!
//! A [`Control`] handle is `Clone + Send + Sync`: a viewer thread may pause, resume, step,
//! change the speed or stop the run at any moment. It changes *when* events fire in wall time,
//! never *which* events fire or in what order, so the trace is the same whatever it does.
//! Wall time comes from a [`Clock`], which tests replace by a [`ManualClock`].

use crate::time::SimTime;
use std::sync::atomic::{AtomicU64, Ordering};
use std::sync::{Arc, Condvar, Mutex, MutexGuard};
use std::time::{Duration, Instant};

/// The slowest and fastest real-time speed factors accepted.
pub const SPEED_RANGE: (f64, f64) = (0.1, 1000.0);

/// Source of wall-clock time for pacing.
pub trait Clock: Send {
    /// Time elapsed since some fixed origin.
    fn now(&self) -> Duration;
    /// Waits `d` (may return early).
    fn sleep(&self, d: Duration);
}

/// The real wall clock.
#[derive(Debug)]
pub struct WallClock(Instant);

impl Default for WallClock {
    fn default() -> Self {
        WallClock(Instant::now())
    }
}

impl Clock for WallClock {
    fn now(&self) -> Duration {
        self.0.elapsed()
    }
    fn sleep(&self, d: Duration) {
        std::thread::sleep(d);
    }
}

/// A clock that moves only when slept on (or advanced by hand): for tests of pacing.
#[derive(Clone, Debug, Default)]
pub struct ManualClock(Arc<AtomicU64>);

impl ManualClock {
    /// Moves the clock forward.
    pub fn advance(&self, d: Duration) {
        self.0.fetch_add(d.as_nanos() as u64, Ordering::SeqCst);
    }
}

impl Clock for ManualClock {
    fn now(&self) -> Duration {
        Duration::from_nanos(self.0.load(Ordering::SeqCst))
    }
    fn sleep(&self, d: Duration) {
        self.advance(d);
    }
}

/// Why a control request was refused.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum ControlError {
    /// The speed factor is outside [`SPEED_RANGE`].
    #[error("speed factor {0} outside {min}..={max}", min = SPEED_RANGE.0, max = SPEED_RANGE.1)]
    SpeedOutOfRange(f64),
}

#[derive(Clone, Copy, Debug, PartialEq)]
pub(crate) struct ControlState {
    pub paused: bool,
    /// `None`: as fast as possible; `Some(x)`: x simulated seconds per wall second.
    pub speed: Option<f64>,
    pub steps: u64,
    pub stop: bool,
}

#[derive(Debug)]
pub(crate) struct Shared {
    pub generation: AtomicU64,
    pub state: Mutex<ControlState>,
    pub changed: Condvar,
    pub sim_now: AtomicU64,
    pub fired: AtomicU64,
}

/// Remote control of a simulation run (see the module docs).
#[derive(Clone, Debug)]
pub struct Control(pub(crate) Arc<Shared>);

impl Default for Control {
    fn default() -> Self {
        Control(Arc::new(Shared {
            generation: AtomicU64::new(0),
            state: Mutex::new(ControlState {
                paused: false,
                speed: None,
                steps: 0,
                stop: false,
            }),
            changed: Condvar::new(),
            sim_now: AtomicU64::new(0),
            fired: AtomicU64::new(0),
        }))
    }
}

impl Control {
    pub(crate) fn lock(&self) -> MutexGuard<'_, ControlState> {
        // A poisoned lock only means a controller panicked mid-update of plain flags.
        self.0.state.lock().unwrap_or_else(|e| e.into_inner())
    }
    fn change(&self, f: impl FnOnce(&mut ControlState)) {
        let mut s = self.lock();
        f(&mut s);
        self.0.generation.fetch_add(1, Ordering::Release);
        self.0.changed.notify_all();
    }
    #[inline]
    pub(crate) fn generation(&self) -> u64 {
        self.0.generation.load(Ordering::Acquire)
    }

    /// Pauses the run before its next event.
    pub fn pause(&self) {
        self.change(|s| s.paused = true);
    }
    /// Resumes a paused run.
    pub fn resume(&self) {
        self.change(|s| {
            s.paused = false;
            s.steps = 0;
        });
    }
    /// While paused, fires exactly `n` more events.
    pub fn step(&self, n: u64) {
        self.change(|s| s.steps += n);
    }
    /// Paces the run at `factor` simulated seconds per wall second (0.1 … 1000).
    pub fn set_speed(&self, factor: f64) -> Result<(), ControlError> {
        if !(SPEED_RANGE.0..=SPEED_RANGE.1).contains(&factor) {
            return Err(ControlError::SpeedOutOfRange(factor));
        }
        self.change(|s| s.speed = Some(factor));
        Ok(())
    }
    /// Runs as fast as possible (no pacing): the default.
    pub fn unpaced(&self) {
        self.change(|s| s.speed = None);
    }
    /// Stops the run before its next event.
    pub fn stop(&self) {
        self.change(|s| s.stop = true);
    }
    /// True if paused.
    pub fn is_paused(&self) -> bool {
        self.lock().paused
    }
    /// The speed factor, `None` when unpaced.
    pub fn speed(&self) -> Option<f64> {
        self.lock().speed
    }
    /// The simulated time of the last fired event.
    pub fn sim_time(&self) -> SimTime {
        SimTime::from_nanos(self.0.sim_now.load(Ordering::Acquire))
    }
    /// Number of events fired so far.
    pub fn events_fired(&self) -> u64 {
        self.0.fired.load(Ordering::Acquire)
    }
}

//! A session as the tools see it: the [`Run`] of any [`Play`], and its snapshot framing.

use super::{Heard, Play, Session};
use crate::{Metric, MetricTable, Run, RunFailed, SnapshotError};
use serde::{Deserialize, Serialize};
use vitro::sim::{Control, StopReason};
use vitro::time::{SimDuration, SimTime};
use vitro_record::{Frame, Scene};

/// A session's saved state: the play's bytes ([`Play::save`]) and the session's own fields.
#[derive(Serialize, Deserialize)]
struct Saved<X> {
    world: u64,
    play: Vec<u8>,
    heard: Heard<X>,
    next_sample: SimTime,
    reached: SimTime,
    stop: Option<StopReason>,
    finished: bool,
}

fn corrupt(e: impl std::fmt::Display) -> SnapshotError {
    SnapshotError::Corrupt(e.to_string())
}

impl<P: Play> Run for Session<P> {
    fn name(&self) -> String {
        self.name.clone()
    }

    fn seed(&self) -> u64 {
        self.seed
    }

    fn end(&self) -> SimTime {
        self.end
    }

    fn set_end(&mut self, end: SimTime) {
        self.end = end;
    }

    fn sample(&self) -> SimDuration {
        self.sample
    }

    fn now(&self) -> SimTime {
        P::now(self)
    }

    fn advance(&mut self, until: SimTime) -> Result<bool, RunFailed> {
        let going = Session::advance(self, until);
        P::check(self)?;
        Ok(going)
    }

    fn control(&self) -> Control {
        self.sim.control()
    }

    fn trace_hash(&self) -> u64 {
        self.sim.trace_hash()
    }

    fn metrics(&self) -> Vec<(&'static str, Metric)> {
        let mut table = P::metrics(self).table();
        let hash = format!("{:016x}", self.sim.trace_hash());
        table.push(("trace_hash", Metric::Text(hash)));
        table
    }

    fn report(&self) -> serde_json::Map<String, serde_json::Value> {
        P::report(self, &P::metrics(self))
    }

    fn verdict(&self) -> Result<(), String> {
        P::verdict(self, &P::metrics(self))
    }

    fn summary(&self) -> Vec<(String, String)> {
        P::summary(self, &P::metrics(self))
    }

    fn scene(&self) -> Scene {
        Session::scene(self)
    }

    fn frame(&mut self) -> Frame {
        Session::frame(self)
    }

    fn drain_log(&mut self) -> Vec<(f64, String)> {
        (P::drain_log(self).into_iter())
            .map(|(t, line)| (t.as_secs_f64(), line))
            .collect()
    }

    fn save_state(&self) -> Result<Vec<u8>, SnapshotError> {
        let saved = Saved {
            world: P::world(self),
            play: P::save(self)?,
            heard: self.heard().clone(),
            next_sample: self.next_sample,
            reached: self.reached,
            stop: self.stop,
            finished: self.finished,
        };
        postcard::to_stdvec(&saved).map_err(corrupt)
    }

    fn restore_state(&mut self, state: &[u8]) -> Result<(), SnapshotError> {
        let saved: Saved<P::Heard> = postcard::from_bytes(state).map_err(corrupt)?;
        if saved.world != P::world(self) {
            return Err(SnapshotError::Mismatch(
                "what the scenario builds (its map, terrain, programs or town) changed since the run was saved".into(),
            ));
        }
        self.sim = P::restore(self, &saved.play)?;
        self.listen();
        {
            let mut heard = self.heard();
            let watched = heard.watched;
            *heard = saved.heard;
            heard.watched = watched;
        }
        self.next_sample = saved.next_sample;
        self.reached = saved.reached;
        self.stop = saved.stop;
        self.finished = saved.finished;
        Ok(())
    }
}

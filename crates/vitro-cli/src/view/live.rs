//! Any mission's run as a live source for the viewer.

use vitro::sim::Control;
use vitro::time::SimTime;
use vitro_mission::Run;
use vitro_record::{Frame, Scene};
use vitro_viz::{LiveSource, SourceError};

/// A run the viewer can drive.
pub(crate) struct RunSource(Box<dyn Run>);

impl RunSource {
    pub(crate) fn new(run: Box<dyn Run>) -> Self {
        RunSource(run)
    }
}

impl LiveSource for RunSource {
    fn title(&self) -> String {
        format!("{} (seed {})", self.0.name(), self.0.seed())
    }

    fn scene(&self) -> Scene {
        self.0.scene()
    }

    fn control(&self) -> Control {
        self.0.control()
    }

    fn end_ns(&self) -> Option<u64> {
        Some(self.0.end().as_nanos())
    }

    fn sample_ns(&self) -> u64 {
        self.0.sample().as_nanos()
    }

    fn advance(&mut self, until_ns: u64) -> Result<bool, SourceError> {
        Ok(self.0.advance(SimTime::from_nanos(until_ns))?)
    }

    fn frame(&mut self, t_ns: u64) -> Frame {
        let mut f = self.0.frame();
        f.t_ns = f.t_ns.max(t_ns);
        f
    }

    fn trace_hash(&self) -> u64 {
        self.0.trace_hash()
    }
}

//! The evacuation mission as a live source for the viewer.

use vitro::sim::Control;
use vitro::time::SimTime;
use vitro_evac::Mission;
use vitro_record::{Frame, Scene};
use vitro_viz::{LiveSource, SourceError};

/// A mission run the viewer can drive.
pub(crate) struct MissionSource {
    mission: Mission,
    seed: u64,
}

impl MissionSource {
    pub(crate) fn new(mission: Mission, seed: u64) -> Self {
        MissionSource { mission, seed }
    }
}

impl LiveSource for MissionSource {
    fn title(&self) -> String {
        format!("{} (seed {})", self.mission.name, self.seed)
    }

    fn scene(&self) -> Scene {
        self.mission.scene()
    }

    fn control(&self) -> Control {
        self.mission.sim.control()
    }

    fn end_ns(&self) -> Option<u64> {
        Some(self.mission.end.as_nanos())
    }

    fn sample_ns(&self) -> u64 {
        self.mission.sample.as_nanos()
    }

    fn advance(&mut self, until_ns: u64) -> Result<bool, SourceError> {
        Ok(self.mission.advance(SimTime::from_nanos(until_ns)))
    }

    fn frame(&mut self, t_ns: u64) -> Frame {
        let mut f = self.mission.frame();
        f.t_ns = f.t_ns.max(t_ns);
        f
    }

    fn trace_hash(&self) -> u64 {
        self.mission.sim.trace_hash()
    }
}

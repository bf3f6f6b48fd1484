//! The demo scenario (cars patrolling a generated town) as a live source for the viewer: its
//! pictures are the demo crate's own ([`DemoView`]).

use vitro::sim::Control;
use vitro::time::SimTime;
use vitro_demo::Scenario;
use vitro_demo::view::DemoView;
use vitro_record::{Frame, Scene};
use vitro_viz::{LiveSource, SourceError};

/// A demo run the viewer can drive.
pub(crate) struct DemoSource(DemoView);

impl DemoSource {
    pub(crate) fn new(scenario: Scenario) -> Self {
        DemoSource(DemoView::new(scenario))
    }
}

impl LiveSource for DemoSource {
    fn title(&self) -> String {
        self.0.title()
    }

    fn scene(&self) -> Scene {
        self.0.scene()
    }

    fn control(&self) -> Control {
        self.0.control()
    }

    fn end_ns(&self) -> Option<u64> {
        Some(self.0.scenario().end().as_nanos())
    }

    fn advance(&mut self, until_ns: u64) -> Result<bool, SourceError> {
        Ok(self.0.advance(SimTime::from_nanos(until_ns))?)
    }

    fn frame(&mut self, t_ns: u64) -> Frame {
        self.0.frame(t_ns)
    }

    fn trace_hash(&self) -> u64 {
        self.0.trace_hash()
    }
}

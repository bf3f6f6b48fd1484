//! The demo as a plug-in of the tools: [`PatrollingCars`] is the kind `"demo"`, and a
//! [`DemoView`] is one of its runs.

use crate::config::{ConfigError, DemoConfig};
use crate::view::DemoView;
use crate::{DemoError, Metrics, Scenario};
use std::path::Path;
use vitro::sim::Control;
use vitro::time::{SimDuration, SimTime};
use vitro_mission::{BuildOptions, Metric, MissionError, Run, RunFailed};
use vitro_record::{Frame, Scene};

/// The demo, registered as `kind = "demo"`: cars patrolling a generated town and claiming
/// junctions over a lossy radio.
#[derive(Clone, Copy, Debug, Default)]
pub struct PatrollingCars;

fn config(path: &Path, text: &str) -> Result<DemoConfig, MissionError> {
    DemoConfig::parse(&path.display().to_string(), text).map_err(|e| match e {
        ConfigError::Content(d) => MissionError::Scenario(d.to_string()),
        ConfigError::Read { .. } => MissionError::Scenario(e.to_string()),
    })
}

fn build(cfg: DemoConfig) -> Result<Scenario, MissionError> {
    Scenario::build(cfg).map_err(|e| match e {
        DemoError::Invalid(_) => MissionError::Scenario(e.to_string()),
        _ => MissionError::Setup(format!("cannot build the scenario: {e}")),
    })
}

impl vitro_mission::Mission for PatrollingCars {
    fn kind(&self) -> &'static str {
        "demo"
    }

    fn about(&self) -> &'static str {
        "cars patrolling a generated town over a lossy radio"
    }

    fn validate(&self, path: &Path, text: &str) -> Result<String, MissionError> {
        let scenario = build(config(path, text)?)?;
        let m = scenario.metrics();
        Ok(format!(
            "{} junctions, {} streets, {} cars, {} simulated seconds",
            m.junctions,
            m.streets,
            m.cars,
            scenario.config().end_s
        ))
    }

    fn build(
        &self,
        path: &Path,
        text: &str,
        options: &BuildOptions,
    ) -> Result<Box<dyn Run>, MissionError> {
        let mut cfg = config(path, text)?;
        if let Some(seed) = options.seed {
            cfg.seed = seed;
        }
        if let Some(level) = &options.fidelity {
            return Err(MissionError::Scenario(format!(
                "--fidelity {level}: the demo has one level of fidelity"
            )));
        }
        Ok(Box::new(DemoView::new(build(cfg)?)))
    }

    fn metric_names(&self) -> Vec<&'static str> {
        metrics(&Metrics::default())
            .into_iter()
            .map(|(k, _)| k)
            .collect()
    }

    /// The demo names no files; it ends at `end_s`.
    fn end_key(&self) -> &'static [&'static str] {
        &["end_s"]
    }

    fn file_keys(&self) -> &'static [(&'static str, &'static str)] {
        &[]
    }
}

/// The demo's metrics as named values, in summary-column order.
fn metrics(m: &Metrics) -> Vec<(&'static str, Metric)> {
    vec![
        ("mean_idleness_s", Metric::Float(m.mean_idleness_s)),
        ("max_idleness_s", Metric::Float(m.max_idleness_s)),
        ("visits", Metric::count(m.visits)),
        ("decisions", Metric::count(m.decisions)),
        ("goals_reached", Metric::count(m.goals_reached)),
        ("yielded", Metric::count(m.yielded)),
        ("messages_sent", Metric::count(m.messages_sent)),
        ("messages_received", Metric::count(m.messages_received)),
        ("messages_lost", Metric::count(m.messages_lost)),
        ("messages_bounced", Metric::count(m.messages_bounced)),
        ("events", Metric::count(m.events)),
        ("sim_time_s", Metric::Float(m.sim_time_s)),
        ("junctions", Metric::count(m.junctions as u64)),
        ("streets", Metric::count(m.streets as u64)),
        ("cars", Metric::count(m.cars as u64)),
        ("stop", Metric::Text(m.stop.clone())),
        ("trace_hash", Metric::Text(format!("{:016x}", m.trace_hash))),
    ]
}

impl Run for DemoView {
    fn name(&self) -> String {
        self.scenario().config().name.clone()
    }

    fn seed(&self) -> u64 {
        self.scenario().config().seed
    }

    fn end(&self) -> SimTime {
        self.scenario().end()
    }

    fn set_end(&mut self, end: SimTime) {
        self.scenario_mut().set_end(end);
    }

    fn sample(&self) -> SimDuration {
        SimDuration::from_secs(1)
    }

    fn now(&self) -> SimTime {
        self.scenario().reached()
    }

    fn advance(&mut self, until: SimTime) -> Result<bool, RunFailed> {
        DemoView::advance(self, until).map_err(|e| RunFailed(e.to_string()))
    }

    fn control(&self) -> Control {
        DemoView::control(self)
    }

    fn trace_hash(&self) -> u64 {
        DemoView::trace_hash(self)
    }

    fn metrics(&self) -> Vec<(&'static str, Metric)> {
        metrics(&self.scenario().metrics())
    }

    fn report(&self) -> serde_json::Map<String, serde_json::Value> {
        match serde_json::to_value(self.scenario().metrics()) {
            Ok(serde_json::Value::Object(m)) => m,
            _ => serde_json::Map::new(),
        }
    }

    fn summary(&self) -> Vec<(String, String)> {
        let m = self.scenario().metrics();
        vec![
            (
                "world".into(),
                format!(
                    "{} junctions, {} streets, {} cars",
                    m.junctions, m.streets, m.cars
                ),
            ),
            ("stopped".into(), format!("at {}", m.stop)),
            (
                "idleness".into(),
                format!(
                    "mean {:.1} s, worst {:.1} s ({} visits)",
                    m.mean_idleness_s, m.max_idleness_s, m.visits
                ),
            ),
            (
                "patrol".into(),
                format!(
                    "{} goals chosen, {} reached, {} given up to a better claim",
                    m.decisions, m.goals_reached, m.yielded
                ),
            ),
            (
                "messages".into(),
                format!(
                    "{} sent, {} received, {} lost, {} out of range",
                    m.messages_sent, m.messages_received, m.messages_lost, m.messages_bounced
                ),
            ),
        ]
    }

    fn scene(&self) -> Scene {
        DemoView::scene(self)
    }

    fn frame(&mut self) -> Frame {
        let t = self.now().as_nanos();
        DemoView::frame(self, t)
    }

    fn save_state(&self) -> Result<Vec<u8>, vitro_mission::SnapshotError> {
        DemoView::save_state(self)
    }

    fn restore_state(&mut self, state: &[u8]) -> Result<(), vitro_mission::SnapshotError> {
        DemoView::restore_state(self, state)
    }
}

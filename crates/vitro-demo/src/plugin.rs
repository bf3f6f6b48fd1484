//! The demo as a plug-in of the tools: [`PatrollingCars`] is the kind `"demo"`, and a
//! [`DemoRun`] (the generic run with the demo's [`Scenario`] as its play) is one of its runs.

use crate::config::{ConfigError, DemoConfig};
use crate::patrol::{Demo, PatrolMsg};
use crate::{DemoError, DemoRun, Metrics, Scenario, snapshot, view};
use std::path::Path;
use vitro::sim::Simulation;
use vitro::time::SimTime;
use vitro_mission::session::Play;
use vitro_mission::{
    BuildOptions, Metric, MetricTable, MissionError, Run, RunFailed, SnapshotError, metric_table,
};
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

fn build(cfg: DemoConfig) -> Result<DemoRun, MissionError> {
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
        Ok(Box::new(build(cfg)?))
    }

    fn metric_names(&self) -> Vec<&'static str> {
        DemoRun::metric_names()
    }

    /// The demo names no files; it ends at `end_s`.
    fn end_key(&self) -> &'static [&'static str] {
        &["end_s"]
    }

    fn file_keys(&self) -> &'static [(&'static str, &'static str)] {
        &[]
    }
}

impl MetricTable for Metrics {
    fn table(&self) -> Vec<(&'static str, Metric)> {
        metric_table!(self; mean_idleness_s, max_idleness_s, visits, decisions, goals_reached,
            yielded, messages_sent, messages_received, messages_lost, messages_bounced, events,
            sim_time_s, junctions, streets, cars, stop)
    }
}

impl Play for Scenario {
    type Model = Demo;
    type Metrics = Metrics;
    type Heard = ();

    fn metrics(run: &DemoRun) -> Metrics {
        Scenario::measure(run)
    }

    fn scene(run: &DemoRun) -> Scene {
        view::scene(run)
    }

    fn frame(run: &mut DemoRun, frame: &mut Frame) {
        view::frame(run, frame);
    }

    fn message_kind(msg: &PatrolMsg) -> &'static str {
        match msg {
            PatrolMsg::Claim { .. } => "claim",
        }
    }

    /// The time advanced to: the demo's metrics are observed up to it.
    fn now(run: &DemoRun) -> SimTime {
        run.reached()
    }

    fn check(run: &DemoRun) -> Result<(), RunFailed> {
        Scenario::failure(run).map_err(|e| RunFailed(e.to_string()))
    }

    fn report(_: &DemoRun, m: &Metrics) -> serde_json::Map<String, serde_json::Value> {
        match serde_json::to_value(m) {
            Ok(serde_json::Value::Object(m)) => m,
            _ => serde_json::Map::new(),
        }
    }

    /// The town's size: junctions, streets and cars.
    fn world(run: &DemoRun) -> u64 {
        let streets = run.sim.env().streets();
        let size = [streets.node_count(), streets.edge_count(), run.cars().len()];
        size.iter().fold(0, |h, &n| h.rotate_left(21) ^ n as u64)
    }

    fn save(run: &DemoRun) -> Result<Vec<u8>, SnapshotError> {
        snapshot::save(run)
    }

    fn restore(run: &mut DemoRun, state: &[u8]) -> Result<Simulation<Demo>, SnapshotError> {
        snapshot::restore(run, state)
    }

    fn summary(_: &DemoRun, m: &Metrics) -> Vec<(String, String)> {
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
}

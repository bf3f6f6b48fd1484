//! The surveillance mission as a plug-in of the tools: [`Surveillance`] is the kind
//! `"surveillance"`, and an [`Operation`] is one of its runs.

use crate::referee::Metrics;
use crate::{Operation, SurveillanceError, scenario};
use std::path::Path;
use vitro::sim::Control;
use vitro::time::{SimDuration, SimTime};
use vitro_mission::{BuildOptions, Metric, MissionError, Run, RunFailed};
use vitro_record::{Frame, Scene};
use vitro_tactical::scenario::{Diagnostics, Preset};

/// The surveillance mission, registered as `kind = "surveillance"`.
#[derive(Clone, Copy, Debug, Default)]
pub struct Surveillance;

/// Every problem of a scenario, each with its place and the offending line.
fn diagnostics(d: Diagnostics) -> MissionError {
    let n = d.len();
    let problems = if n == 1 { "problem" } else { "problems" };
    MissionError::Scenario(format!("{n} {problems}\n{}", d.render()))
}

fn mission_error(e: SurveillanceError) -> MissionError {
    match e {
        SurveillanceError::Scenario(d) => diagnostics(d),
        e @ SurveillanceError::Read { .. } => MissionError::Scenario(e.to_string()),
        e @ SurveillanceError::Setup(_) => MissionError::Setup(e.to_string()),
    }
}

impl vitro_mission::Mission for Surveillance {
    fn kind(&self) -> &'static str {
        "surveillance"
    }

    fn about(&self) -> &'static str {
        "a UAV team shares out search sectors by contract net, finds and tracks red units"
    }

    fn fidelity_levels(&self) -> &'static [&'static str] {
        &Preset::NAMES
    }

    fn validate(&self, path: &Path, text: &str) -> Result<String, MissionError> {
        let v = scenario::validate_text(path, text).map_err(diagnostics)?;
        let f = &v.file;
        let count = |red: bool| -> u64 {
            (f.entities.iter())
                .filter(|e| e.kind.is_aircraft() != red)
                .map(|e| u64::from(e.count))
                .sum()
        };
        let area = f.search.area.unwrap_or(v.site.map.extent);
        let sectors = crate::sector::grid_size(area, f.search.sector_m);
        Ok(format!(
            "{:?}: {} UAVs, {} red units, {sectors} sectors (+{} tasked later), {} simulated seconds, fidelity {}",
            f.name,
            count(false),
            count(true),
            f.areas.len(),
            f.end.time_s,
            format!("{:?}", f.fidelity.level).to_lowercase(),
        ))
    }

    fn build(
        &self,
        path: &Path,
        text: &str,
        options: &BuildOptions,
    ) -> Result<Box<dyn Run>, MissionError> {
        let preset = Preset::named(options.fidelity.as_deref())
            .map_err(|e| MissionError::Scenario(e.to_string()))?;
        let run = Operation::from_text(path, text, options.seed, preset).map_err(mission_error)?;
        Ok(Box::new(run))
    }

    fn metric_names(&self) -> Vec<&'static str> {
        metrics(&Metrics::default(), 0)
            .into_iter()
            .map(|(k, _)| k)
            .collect()
    }
}

/// The mission's metrics as named values, in summary-column order.
fn metrics(m: &Metrics, trace: u64) -> Vec<(&'static str, Metric)> {
    let c = Metric::count;
    vec![
        ("red_units", c(u64::from(m.red_units))),
        ("red_detected", c(u64::from(m.red_detected))),
        (
            "mean_time_to_detection_s",
            m.mean_time_to_detection_s.into(),
        ),
        ("max_time_to_detection_s", m.max_time_to_detection_s.into()),
        (
            "restricted_time_to_detection_s",
            Metric::Float(m.restricted_time_to_detection_s),
        ),
        ("mean_tracked_share", Metric::Float(m.mean_tracked_share)),
        ("min_tracked_share", Metric::Float(m.min_tracked_share)),
        ("messages_sent", c(m.messages_sent)),
        ("messages_lost", c(m.messages_lost)),
        ("cnet_messages", c(m.cnet_messages)),
        ("calls", c(m.calls)),
        ("awards", c(m.awards)),
        ("calls_failed", c(m.calls_failed)),
        ("reallocations", c(m.reallocations)),
        ("handovers", c(m.handovers)),
        ("revocations", c(m.revocations)),
        ("uavs", c(u64::from(m.uavs))),
        ("uavs_lost", c(u64::from(m.uavs_lost))),
        ("presumed_lost", c(m.presumed_lost)),
        ("sectors", c(u64::from(m.sectors))),
        ("sectors_held", c(u64::from(m.sectors_held))),
        ("events", c(m.events)),
        ("sim_time_s", Metric::Float(m.sim_time_s)),
        ("trace_hash", Metric::Text(format!("{trace:016x}"))),
    ]
}

impl Run for Operation {
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
        self.sim.now()
    }

    fn advance(&mut self, until: SimTime) -> Result<bool, RunFailed> {
        Ok(Operation::advance(self, until))
    }

    fn control(&self) -> Control {
        self.sim.control()
    }

    fn trace_hash(&self) -> u64 {
        self.sim.trace_hash()
    }

    fn metrics(&self) -> Vec<(&'static str, Metric)> {
        metrics(&Operation::metrics(self), self.sim.trace_hash())
    }

    fn report(&self) -> serde_json::Map<String, serde_json::Value> {
        let mut out: serde_json::Map<String, serde_json::Value> = (Run::metrics(self).into_iter())
            .filter(|(k, _)| *k != "trace_hash")
            .map(|(k, v)| (k.to_owned(), serde_json::to_value(v).unwrap_or_default()))
            .collect();
        let m = Operation::metrics(self);
        if let Ok(red) = serde_json::to_value(&m.red) {
            out.insert("red".into(), red);
        }
        let levels: serde_json::Map<String, serde_json::Value> = (self.members.iter())
            .filter_map(|x| Some((x.kind?.name().to_owned(), x.level.name().into())))
            .collect();
        out.insert("levels".into(), levels.into());
        out
    }

    fn summary(&self) -> Vec<(String, String)> {
        let m = Operation::metrics(self);
        let opt = |x: Option<f64>| x.map_or("-".to_string(), |v| format!("{v:.1} s"));
        vec![
            (
                "red units".into(),
                format!(
                    "{} of {} detected, mean time to first detection {}, tracked {:.0} % of the time on average (least {:.0} %)",
                    m.red_detected,
                    m.red_units,
                    opt(m.mean_time_to_detection_s),
                    100.0 * m.mean_tracked_share,
                    100.0 * m.min_tracked_share
                ),
            ),
            (
                "allocation".into(),
                format!(
                    "{} calls, {} awards, {} failed, {} re-allocations ({} to another UAV), {} revocations; {}/{} sectors held",
                    m.calls,
                    m.awards,
                    m.calls_failed,
                    m.reallocations,
                    m.handovers,
                    m.revocations,
                    m.sectors_held,
                    m.sectors
                ),
            ),
            (
                "team".into(),
                format!(
                    "{} UAVs, {} lost, presumed lost {} time(s)",
                    m.uavs, m.uavs_lost, m.presumed_lost
                ),
            ),
            (
                "messages".into(),
                format!(
                    "{} sent, {} lost, {} of the contract net",
                    m.messages_sent, m.messages_lost, m.cnet_messages
                ),
            ),
        ]
    }

    fn scene(&self) -> Scene {
        Operation::scene(self)
    }

    fn frame(&mut self) -> Frame {
        Operation::frame(self)
    }

    fn drain_log(&mut self) -> Vec<(f64, String)> {
        Operation::drain_log(self)
            .into_iter()
            .map(|(t, line)| (t.as_secs_f64(), line))
            .collect()
    }

    fn save_state(&self) -> Result<Vec<u8>, vitro_mission::SnapshotError> {
        Operation::save_state(self)
    }

    fn restore_state(&mut self, state: &[u8]) -> Result<(), vitro_mission::SnapshotError> {
        Operation::restore_state(self, state)
    }
}

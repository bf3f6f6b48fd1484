//! The surveillance mission as a plug-in of the tools: [`Surveillance`] is the kind
//! `"surveillance"`, and a [`SurveillanceRun`] (the generic run with the mission's
//! [`Operation`] as its play) is one of its runs.

use crate::model::Field;
use crate::net::Net;
use crate::referee::{self, Metrics};
use crate::{Operation, SurveillanceError, SurveillanceRun, scenario, snapshot, view};
use std::path::Path;
use vitro::sim::Simulation;
use vitro::time::SimTime;
use vitro_mission::session::Play;
use vitro_mission::{
    BuildOptions, Metric, MetricTable, MissionError, Run, SnapshotError, metric_table,
};
use vitro_record::{Frame, Scene};
use vitro_tactical::arena::site_digest;
use vitro_tactical::scenario::Preset;

/// The surveillance mission, registered as `kind = "surveillance"`.
#[derive(Clone, Copy, Debug, Default)]
pub struct Surveillance;

fn mission_error(e: SurveillanceError) -> MissionError {
    match e {
        SurveillanceError::Scenario(d) => MissionError::Scenario(d.report()),
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

    fn validate(&self, path: &Path, text: &str) -> Result<String, MissionError> {
        let v =
            scenario::validate_text(path, text).map_err(|d| MissionError::Scenario(d.report()))?;
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

    fn fidelity_levels(&self) -> &'static [&'static str] {
        &Preset::NAMES
    }

    fn metric_names(&self) -> Vec<&'static str> {
        SurveillanceRun::metric_names()
    }
}

impl MetricTable for Metrics {
    fn table(&self) -> Vec<(&'static str, Metric)> {
        metric_table!(self; red_units, red_detected, mean_time_to_detection_s,
            max_time_to_detection_s, restricted_time_to_detection_s, mean_tracked_share,
            min_tracked_share, messages_sent, messages_lost, cnet_messages, allocation_messages,
            calls, awards, calls_failed, reallocations, handovers, revocations, uavs, uavs_lost,
            presumed_lost, sectors, sectors_held, events, sim_time_s)
    }
}

impl Play for Operation {
    type Model = Field;
    type Metrics = Metrics;
    type Heard = ();

    fn metrics(run: &SurveillanceRun) -> Metrics {
        referee::measure(&run.sim, &run.members, &run.lost)
    }

    fn scene(run: &SurveillanceRun) -> Scene {
        view::scene(run)
    }

    fn frame(run: &mut SurveillanceRun, frame: &mut Frame) {
        view::frame(run, frame);
    }

    fn message_kind(msg: &Net) -> &'static str {
        msg.kind()
    }

    fn next_stop(&self) -> SimTime {
        self.losses
            .get(self.next_loss)
            .map_or(SimTime::MAX, |l| l.0)
    }

    fn at_stop(run: &mut SurveillanceRun, now: SimTime) {
        Operation::apply_losses(run, now);
    }

    fn drain_log(run: &mut SurveillanceRun) -> Vec<(SimTime, String)> {
        Operation::drain_log(run)
    }

    fn report(run: &SurveillanceRun, m: &Metrics) -> serde_json::Map<String, serde_json::Value> {
        let mut out = m.json();
        if let Ok(red) = serde_json::to_value(&m.red) {
            out.insert("red".into(), red);
        }
        let levels: serde_json::Map<String, serde_json::Value> = (run.members.iter())
            .filter_map(|x| Some((x.kind?.name().to_owned(), x.level.name().into())))
            .collect();
        out.insert("levels".into(), levels.into());
        out
    }

    fn world(run: &SurveillanceRun) -> u64 {
        site_digest(&run.team.site)
    }

    fn save(run: &SurveillanceRun) -> Result<Vec<u8>, SnapshotError> {
        snapshot::save(run)
    }

    fn restore(
        run: &mut SurveillanceRun,
        state: &[u8],
    ) -> Result<Simulation<Field>, SnapshotError> {
        snapshot::restore(run, state)
    }

    fn summary(_: &SurveillanceRun, m: &Metrics) -> Vec<(String, String)> {
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
                    "{} sent, {} lost, {} of the allocation method",
                    m.messages_sent, m.messages_lost, m.allocation_messages
                ),
            ),
        ]
    }
}

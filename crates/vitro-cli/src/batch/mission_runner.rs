//! The batch runner of mission scenarios (the evacuation mission): each run validates the
//! varied scenario as if it were the scenario file (paths resolve from its directory), builds
//! the mission with the run's seed and runs it, sampling the kept series.

use std::collections::BTreeMap;
use std::path::PathBuf;
use vitro::time::SimTime;
use vitro_batch::{RunOutput, RunSettings, Runner, SeriesRow, Value};
use vitro_evac::Mission;
use vitro_evac::referee::Metrics;
use vitro_tactical::scenario::{ScenarioFile, Validated};

/// Runs mission scenarios for `vitro batch`.
pub(crate) struct MissionRunner {
    /// The scenario file the experiment names (relative paths in it resolve from its
    /// directory).
    pub(crate) path: PathBuf,
}

/// The mission's metrics as named values, in summary-column order.
fn metric_values(m: &Metrics, trace: u64) -> Vec<(&'static str, Value)> {
    let int = |x: u64| Value::Int(i64::try_from(x).unwrap_or(i64::MAX));
    let opt = |x: Option<f64>| Value::Float(x.unwrap_or(f64::NAN));
    vec![
        ("success", Value::Bool(m.success)),
        ("time_to_extraction_s", opt(m.time_to_extraction_s)),
        ("casualties", int(u64::from(m.casualties))),
        ("vip_down", Value::Bool(m.vip_down)),
        (
            "adversaries_detected",
            int(u64::from(m.adversaries_detected)),
        ),
        ("mean_time_to_detection_s", opt(m.mean_time_to_detection_s)),
        ("time_uncovered_s", Value::Float(m.time_uncovered_s)),
        ("hvt_captured", Value::Bool(m.hvt_captured)),
        ("hvt_capture_s", opt(m.hvt_capture_s)),
        ("messages_sent", int(m.messages_sent)),
        ("messages_lost", int(m.messages_lost)),
        ("plan_repairs", int(m.plan_repairs)),
        ("plan_cuts", int(m.plan_cuts)),
        ("plan_messages", int(m.plan_messages)),
        ("shots", int(m.shots)),
        (
            "patrol_capture_probability",
            opt(m.patrol_capture_probability),
        ),
        ("patrol_cover_fraction", opt(m.patrol_cover_fraction)),
        ("patrol_sight_fraction", opt(m.patrol_sight_fraction)),
        ("events", int(m.events)),
        ("sim_time_s", Value::Float(m.sim_time_s)),
        ("trace_hash", Value::Text(format!("{trace:016x}"))),
    ]
}

impl MissionRunner {
    fn validated(&self, scenario: &toml::Table) -> Result<Validated, String> {
        let text = toml::to_string(scenario).map_err(|e| e.to_string())?;
        ScenarioFile::validate_text(&self.path, &text).map_err(|d| d.to_string())
    }
}

impl Runner for MissionRunner {
    fn metric_names(&self, scenario: &toml::Table) -> Result<Vec<String>, String> {
        self.validated(scenario)?;
        Ok(metric_values(&Metrics::default(), 0)
            .into_iter()
            .map(|(k, _)| k.to_owned())
            .collect())
    }

    fn run(
        &self,
        scenario: &toml::Table,
        seed: u64,
        settings: &RunSettings<'_>,
    ) -> Result<RunOutput, String> {
        let v = self.validated(scenario)?;
        let mut m = Mission::build(v, Some(seed)).map_err(|e| e.to_string())?;
        if let Some(end) = settings.end_s {
            m.end = m.end.min(SimTime::from_secs_f64(end));
        }
        let keep = settings.keep;
        let mut series = Vec::new();
        match keep.every_s.filter(|_| !keep.series.is_empty()) {
            None => {
                m.run();
            }
            Some(every) => {
                for k in 1u64.. {
                    let t = SimTime::from_secs_f64(k as f64 * every).min(m.end);
                    let going = m.advance(t);
                    let values: BTreeMap<String, Value> =
                        metric_values(&m.metrics(), m.sim.trace_hash())
                            .into_iter()
                            .filter(|(name, _)| keep.series.iter().any(|k| k == name))
                            .map(|(name, v)| (name.to_owned(), v))
                            .collect();
                    series.push(SeriesRow {
                        t_s: m.sim.now().as_secs_f64(),
                        values,
                    });
                    if !going || t >= m.end {
                        break;
                    }
                }
            }
        }
        let metrics = metric_values(&m.metrics(), m.sim.trace_hash())
            .into_iter()
            .map(|(k, v)| (k.to_owned(), v))
            .collect();
        Ok(RunOutput { metrics, series })
    }
}

//! The batch runner of mission scenarios (the evacuation mission): each run validates the
//! varied scenario as if it were the scenario file (paths resolve from its directory), builds
//! the mission with the run's seed and runs it, sampling the kept series.

use std::collections::BTreeMap;
use std::path::{Component, Path, PathBuf};
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

    fn scenario_file(
        &self,
        scenario: &toml::Table,
        seed: u64,
        end_s: Option<f64>,
        dir: &Path,
    ) -> Result<String, String> {
        let mut t = scenario.clone();
        let seed =
            i64::try_from(seed).map_err(|_| format!("seed {seed} does not fit a TOML integer"))?;
        t.insert("seed".into(), toml::Value::Integer(seed));
        if let Some(end) = end_s {
            let table = t
                .entry("end")
                .or_insert_with(|| toml::Value::Table(toml::Table::new()));
            if let toml::Value::Table(e) = table {
                let old = e.get("time_s").and_then(toml::Value::as_float);
                let time = old.map_or(end, |o| o.min(end));
                e.insert("time_s".into(), toml::Value::Float(time));
            }
        }
        // Files the scenario names resolve from its own directory: rewrite them for `dir`.
        let from = self.path.parent().unwrap_or(Path::new(""));
        for (table, key) in [
            ("site", "map"),
            ("site", "terrain"),
            ("formation", "program"),
        ] {
            let Some(toml::Value::Table(sub)) = t.get_mut(table) else {
                continue;
            };
            let Some(toml::Value::String(p)) = sub.get(key) else {
                continue;
            };
            if Path::new(p).is_absolute() {
                continue;
            }
            let moved = relative(&from.join(p), dir)?;
            sub.insert(key.into(), toml::Value::String(moved));
        }
        toml::to_string(&t).map_err(|e| e.to_string())
    }
}

/// `target` as a path relative to directory `dir` (both must exist).
fn relative(target: &Path, dir: &Path) -> Result<String, String> {
    let abs = |p: &Path| {
        p.canonicalize()
            .map_err(|e| format!("{}: {e}", p.display()))
    };
    let (target, dir) = (abs(target)?, abs(dir)?);
    let t: Vec<Component> = target.components().collect();
    let d: Vec<Component> = dir.components().collect();
    let common = t.iter().zip(&d).take_while(|(a, b)| a == b).count();
    let mut out = PathBuf::new();
    for _ in common..d.len() {
        out.push("..");
    }
    for c in &t[common..] {
        out.push(c.as_os_str());
    }
    Ok(out.to_string_lossy().replace('\\', "/"))
}

//! The evacuation as a plug-in of the tools: [`Evacuation`] is the kind `"evacuation"`, and a
//! [`Mission`] is one of its runs.

use crate::referee::Metrics;
use crate::{Mission, MissionError};
use std::path::Path;
use vitro::sim::Control;
use vitro::time::{SimDuration, SimTime};
use vitro_mission::{BuildOptions, Metric, Run, RunFailed};
use vitro_record::{Frame, Scene};
use vitro_tactical::scenario::{Diagnostics, FidelitySpec, Preset, ScenarioFile, Validated};

/// The evacuation mission, registered as `kind = "evacuation"`.
#[derive(Clone, Copy, Debug, Default)]
pub struct Evacuation;

/// Every problem of a scenario, each with its place and the offending line.
fn diagnostics(d: Diagnostics) -> vitro_mission::MissionError {
    let n = d.len();
    let problems = if n == 1 { "problem" } else { "problems" };
    vitro_mission::MissionError::Scenario(format!("{n} {problems}\n{}", d.render()))
}

/// The scenario text read from `path`, validated, every entity type at the levels of the
/// `fidelity` preset if one is named (one of `discrete`, `interpolated`, `physical`).
///
/// # Errors
/// Every problem of the scenario (file, line, column), or an unknown preset.
pub fn validated(
    path: &Path,
    text: &str,
    fidelity: Option<&str>,
) -> Result<Validated, vitro_mission::MissionError> {
    let mut v = ScenarioFile::validate_text(path, text).map_err(diagnostics)?;
    let preset = Preset::named(fidelity)
        .map_err(|e| vitro_mission::MissionError::Scenario(e.to_string()))?;
    if let Some(level) = preset {
        v.loaded.file.fidelity = FidelitySpec {
            level,
            ..FidelitySpec::default()
        };
    }
    Ok(v)
}

/// A mission that could not be built as the plug-in's error.
pub fn mission_error(e: MissionError) -> vitro_mission::MissionError {
    match e {
        MissionError::Scenario(d) => diagnostics(d),
        MissionError::Setup(_) => vitro_mission::MissionError::Setup(e.to_string()),
    }
}

impl vitro_mission::Mission for Evacuation {
    fn kind(&self) -> &'static str {
        "evacuation"
    }

    fn about(&self) -> &'static str {
        "a convoy fetches a VIP through a town held by red units"
    }

    fn fidelity_levels(&self) -> &'static [&'static str] {
        &Preset::NAMES
    }

    fn validate(&self, path: &Path, text: &str) -> Result<String, vitro_mission::MissionError> {
        let v = ScenarioFile::validate_text(path, text).map_err(diagnostics)?;
        let f = &v.loaded.file;
        let entities: u64 = f.entities.iter().map(|e| u64::from(e.count)).sum();
        let name = |p: &Path| {
            p.file_name()
                .map_or_else(|| p.display().to_string(), |n| n.to_string_lossy().into())
        };
        Ok(format!(
            "{:?}: {entities} entities in {} groups, {} on {}, {} simulated seconds, fidelity {}",
            f.name,
            f.entities.len(),
            name(&v.loaded.map),
            name(&v.loaded.terrain),
            f.end.time_s,
            format!("{:?}", f.fidelity.level).to_lowercase(),
        ))
    }

    fn build(
        &self,
        path: &Path,
        text: &str,
        options: &BuildOptions,
    ) -> Result<Box<dyn Run>, vitro_mission::MissionError> {
        let v = validated(path, text, options.fidelity.as_deref())?;
        let mission = Mission::build(v, options.seed).map_err(mission_error)?;
        Ok(Box::new(mission))
    }

    fn metric_names(&self) -> Vec<&'static str> {
        metrics(&Metrics::default(), 0)
            .into_iter()
            .map(|(k, _)| k)
            .collect()
    }

    fn file_keys(&self) -> &'static [(&'static str, &'static str)] {
        &[
            ("site", "map"),
            ("site", "terrain"),
            ("fidelity", "calibration"),
            ("formation", "program"),
        ]
    }
}

/// The mission's metrics as named values, in summary-column order.
fn metrics(m: &Metrics, trace: u64) -> Vec<(&'static str, Metric)> {
    vec![
        ("success", Metric::Bool(m.success)),
        ("time_to_extraction_s", m.time_to_extraction_s.into()),
        ("casualties", Metric::count(u64::from(m.casualties))),
        ("vip_down", Metric::Bool(m.vip_down)),
        (
            "adversaries_detected",
            Metric::count(u64::from(m.adversaries_detected)),
        ),
        (
            "mean_time_to_detection_s",
            m.mean_time_to_detection_s.into(),
        ),
        ("time_uncovered_s", Metric::Float(m.time_uncovered_s)),
        ("hvt_captured", Metric::Bool(m.hvt_captured)),
        ("hvt_capture_s", m.hvt_capture_s.into()),
        ("messages_sent", Metric::count(m.messages_sent)),
        ("messages_lost", Metric::count(m.messages_lost)),
        ("plan_repairs", Metric::count(m.plan_repairs)),
        ("vehicle_stalls", Metric::count(m.vehicle_stalls)),
        ("aircraft_down", Metric::count(m.aircraft_down)),
        ("plan_cuts", Metric::count(m.plan_cuts)),
        ("plan_messages", Metric::count(m.plan_messages)),
        ("plan_failures", Metric::count(m.plan_failures)),
        ("plan_fallbacks", Metric::count(m.plan_fallbacks)),
        ("checkpoints_missed", Metric::count(m.checkpoints_missed)),
        ("shots", Metric::count(m.shots)),
        ("cnet_calls", Metric::count(m.cnet_calls)),
        ("cnet_awards", Metric::count(m.cnet_awards)),
        ("cnet_reallocations", Metric::count(m.cnet_reallocations)),
        (
            "patrol_capture_probability",
            m.patrol_capture_probability.into(),
        ),
        ("patrol_cover_fraction", m.patrol_cover_fraction.into()),
        ("patrol_sight_fraction", m.patrol_sight_fraction.into()),
        ("patrol_attacks", Metric::count(m.patrol_attacks)),
        (
            "patrol_attacks_stopped",
            Metric::count(m.patrol_attacks_stopped),
        ),
        ("patrol_capture_computed", m.patrol_capture_computed.into()),
        (
            "patrol_attacks_on_schedule",
            Metric::count(m.patrol_attacks_on_schedule),
        ),
        (
            "patrol_stopped_on_schedule",
            Metric::count(m.patrol_stopped_on_schedule),
        ),
        (
            "patrol_capture_on_schedule",
            m.patrol_capture_on_schedule.into(),
        ),
        (
            "patrol_attacks_misread",
            Metric::count(m.patrol_attacks_misread),
        ),
        ("patrol_resolves", Metric::count(m.patrol_resolves)),
        ("events", Metric::count(m.events)),
        ("sim_time_s", Metric::Float(m.sim_time_s)),
        ("trace_hash", Metric::Text(format!("{trace:016x}"))),
    ]
}

impl Run for Mission {
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
        Ok(Mission::advance(self, until))
    }

    fn control(&self) -> Control {
        self.sim.control()
    }

    fn trace_hash(&self) -> u64 {
        self.sim.trace_hash()
    }

    fn metrics(&self) -> Vec<(&'static str, Metric)> {
        metrics(&Mission::metrics(self), self.sim.trace_hash())
    }

    fn report(&self) -> serde_json::Map<String, serde_json::Value> {
        let mut out = match serde_json::to_value(Mission::metrics(self)) {
            Ok(serde_json::Value::Object(m)) => m,
            _ => serde_json::Map::new(),
        };
        let levels: serde_json::Map<String, serde_json::Value> = self
            .members
            .iter()
            .map(|x| (x.kind.name().to_owned(), x.level.name().into()))
            .collect();
        out.insert("levels".into(), levels.into());
        out
    }

    fn verdict(&self) -> Result<(), String> {
        let m = &self.referee.metrics;
        if m.success {
            Ok(())
        } else if m.vip_down {
            Err("mission failed: the VIP was hit".into())
        } else {
            Err("mission failed: the VIP was not extracted in time".into())
        }
    }

    fn summary(&self) -> Vec<(String, String)> {
        summary(self, &Mission::metrics(self))
    }

    fn scene(&self) -> Scene {
        Mission::scene(self)
    }

    fn frame(&mut self) -> Frame {
        Mission::frame(self)
    }

    fn save_state(&self) -> Result<Vec<u8>, vitro_mission::SnapshotError> {
        Mission::save_state(self)
    }

    fn restore_state(&mut self, state: &[u8]) -> Result<(), vitro_mission::SnapshotError> {
        Mission::restore_state(self, state)
    }

    fn drain_log(&mut self) -> Vec<(f64, String)> {
        std::mem::take(&mut self.referee.log)
            .into_iter()
            .map(|(t, line)| (t.as_secs_f64(), line))
            .collect()
    }
}

/// The human summary's lines, between the scenario line and the time line.
fn summary(mission: &Mission, m: &Metrics) -> Vec<(String, String)> {
    let opt = |x: Option<f64>| x.map_or("-".to_string(), |v| format!("{v:.1} s"));
    let mut levels: Vec<(String, String)> = mission
        .members
        .iter()
        .map(|x| (x.kind.name().to_owned(), x.level.name().to_owned()))
        .collect();
    levels.sort();
    levels.dedup();
    let levels: Vec<String> = levels.iter().map(|(k, v)| format!("{k} {v}")).collect();
    let mut out = vec![
        ("levels".to_owned(), levels.join(", ")),
        (
            "outcome".to_owned(),
            format!(
                "{}, time to extraction {}",
                if m.success {
                    "SUCCESS: the VIP is out"
                } else {
                    "FAILURE"
                },
                opt(m.time_to_extraction_s)
            ),
        ),
        (
            "team".to_owned(),
            format!(
                "{} casualties, uncovered {:.1} s, {} shots taken at it{}",
                m.casualties,
                m.time_uncovered_s,
                m.shots,
                match m.vehicle_stalls {
                    0 => String::new(),
                    n => format!(", the truck stuck {n} times"),
                }
            ),
        ),
        (
            "adversaries".to_owned(),
            format!(
                "{} of {} detected, mean time to first report {}",
                m.adversaries_detected,
                m.adversaries,
                opt(m.mean_time_to_detection_s)
            ),
        ),
        (
            "HVT".to_owned(),
            format!(
                "{}; hunt slots by contract net: {} calls, {} awards, {} reallocations",
                if m.hvt_captured {
                    format!("captured at {}", opt(m.hvt_capture_s))
                } else {
                    "not captured".into()
                },
                m.cnet_calls,
                m.cnet_awards,
                m.cnet_reallocations
            ),
        ),
        (
            "messages".to_owned(),
            format!("{} sent, {} lost", m.messages_sent, m.messages_lost),
        ),
        (
            "cover plan".to_owned(),
            format!(
                "{} failures, {} repairs, {} plan messages, {} checkpoints missed{}",
                m.plan_failures,
                m.plan_repairs,
                m.plan_messages,
                m.checkpoints_missed,
                if m.plan_cuts > 0 {
                    format!(", {} cut by the depth bound", m.plan_cuts)
                } else {
                    String::new()
                }
            ),
        ),
    ];
    if let Some(p) = m.patrol_capture_probability {
        let pct = |x: Option<f64>| x.map_or("-".into(), |x| format!("{:.0} %", 100.0 * x));
        out.push((
            "patrol".to_owned(),
            format!(
                "capture probability {p:.2} (computed); truck within cover radius {}, within sensor range {} of the escort",
                pct(m.patrol_cover_fraction),
                pct(m.patrol_sight_fraction)
            ),
        ));
    }
    if let Some(p) = m.patrol_capture_computed {
        out.push((
            "patrol attacks".to_owned(),
            format!(
                "{} started, {} stopped (computed capture probability {p:.2}); {} with the patrol on schedule, {} of them stopped",
                m.patrol_attacks,
                m.patrol_attacks_stopped,
                m.patrol_attacks_on_schedule,
                m.patrol_stopped_on_schedule
            ),
        ));
    }
    out
}

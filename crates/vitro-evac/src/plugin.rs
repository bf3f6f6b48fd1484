//! The evacuation as a plug-in of the tools: [`Evacuation`] is the kind `"evacuation"`, and an
//! [`EvacRun`] (the generic run with the evacuation's [`Mission`] as its play) is one of its
//! runs.

use crate::radio::{Evac, Radio};
use crate::referee::Metrics;
use crate::scenario::{ScenarioFile, Validated};
use crate::{EvacRun, Mission, MissionError, over, radio_kind, snapshot, view};
use std::path::Path;
use vitro::entity::EntityId;
use vitro::sim::{Fired, Input, Simulation};
use vitro::time::SimTime;
use vitro_mission::session::{Heard, Play};
use vitro_mission::{BuildOptions, Metric, MetricTable, Run, SnapshotError, metric_table};
use vitro_record::{Frame, Scene};
use vitro_tactical::scenario::Preset;

/// The evacuation mission, registered as `kind = "evacuation"`.
#[derive(Clone, Copy, Debug, Default)]
pub struct Evacuation;

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
    let scenario = |e: String| vitro_mission::MissionError::Scenario(e);
    let mut v = ScenarioFile::validate_text(path, text).map_err(|d| scenario(d.report()))?;
    if let Some(level) = Preset::named(fidelity).map_err(|e| scenario(e.to_string()))? {
        v.loaded.file.fidelity.set_preset(level);
    }
    Ok(v)
}

/// A mission that could not be built as the plug-in's error.
pub fn mission_error(e: MissionError) -> vitro_mission::MissionError {
    match e {
        MissionError::Scenario(d) => vitro_mission::MissionError::Scenario(d.report()),
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

    fn validate(&self, path: &Path, text: &str) -> Result<String, vitro_mission::MissionError> {
        let v = validated(path, text, None)?;
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

    fn fidelity_levels(&self) -> &'static [&'static str] {
        &Preset::NAMES
    }

    fn metric_names(&self) -> Vec<&'static str> {
        EvacRun::metric_names()
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

impl MetricTable for Metrics {
    fn table(&self) -> Vec<(&'static str, Metric)> {
        metric_table!(self; success, time_to_extraction_s, casualties, vip_down,
            adversaries_detected, mean_time_to_detection_s, time_uncovered_s, hvt_captured,
            hvt_capture_s, messages_sent, messages_lost, plan_repairs, vehicle_stalls,
            aircraft_down, plan_cuts, plan_messages, plan_failures, plan_fallbacks,
            checkpoints_missed, shots, cnet_calls, cnet_awards, cnet_reallocations,
            patrol_capture_probability, patrol_cover_fraction, patrol_sight_fraction,
            patrol_attacks, patrol_attacks_stopped, patrol_capture_computed,
            patrol_attacks_on_schedule, patrol_stopped_on_schedule, patrol_capture_on_schedule,
            patrol_attacks_misread, patrol_resolves, events, sim_time_s)
    }
}

impl Play for Mission {
    type Model = Evac;
    type Metrics = Metrics;
    /// The contacts reported since the last sample, for the referee.
    type Heard = Vec<(SimTime, EntityId)>;

    fn metrics(run: &EvacRun) -> Metrics {
        Mission::measure(run)
    }

    fn summary(run: &EvacRun, m: &Metrics) -> Vec<(String, String)> {
        summary(run, m)
    }

    fn scene(run: &EvacRun) -> Scene {
        view::scene(run)
    }

    fn frame(run: &mut EvacRun, frame: &mut Frame) {
        view::frame(run, frame);
    }

    fn over(&self, sim: &Simulation<Evac>) -> bool {
        over(sim.env(), &self.brief)
    }

    fn hear(heard: &mut Heard<Self::Heard>, f: &Fired<'_, Evac>) {
        if let Input::Message(env) = &f.input
            && let Radio::Contact { target, .. } = &env.body
        {
            heard.own.push((f.time, *target));
        }
        heard.keep(f, radio_kind);
    }

    fn at_sample(run: &mut EvacRun, now: SimTime) {
        Mission::take_sample(run, now);
    }

    fn verdict(_: &EvacRun, m: &Metrics) -> Result<(), String> {
        match (m.success, m.vip_down) {
            (true, _) => Ok(()),
            (false, true) => Err("mission failed: the VIP was hit".into()),
            (false, false) => Err("mission failed: the VIP was not extracted in time".into()),
        }
    }

    fn report(run: &EvacRun, m: &Metrics) -> serde_json::Map<String, serde_json::Value> {
        let mut out = match serde_json::to_value(m) {
            Ok(serde_json::Value::Object(m)) => m,
            _ => serde_json::Map::new(),
        };
        let levels: serde_json::Map<String, serde_json::Value> = (run.members.iter())
            .map(|x| (x.kind.name().to_owned(), x.level.name().into()))
            .collect();
        out.insert("levels".into(), levels.into());
        out
    }

    fn drain_log(run: &mut EvacRun) -> Vec<(SimTime, String)> {
        std::mem::take(&mut run.referee.log)
    }

    fn world(run: &EvacRun) -> u64 {
        snapshot::world(&run.brief)
    }

    fn save(run: &EvacRun) -> Result<Vec<u8>, SnapshotError> {
        snapshot::save(run)
    }

    fn restore(run: &mut EvacRun, state: &[u8]) -> Result<Simulation<Evac>, SnapshotError> {
        snapshot::restore(run, state)
    }
}

/// The human summary's lines, between the scenario line and the time line.
fn summary(mission: &EvacRun, m: &Metrics) -> Vec<(String, String)> {
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

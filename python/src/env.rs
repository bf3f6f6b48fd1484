//! `EvacSim`: an evacuation run some of whose blue units are driven from Python
//! (`vitro_evac::external`), the engine of `vitro.env.parallel_env`.

use crate::{guarded, py_error};
use pyo3::prelude::*;
use std::cell::RefCell;
use std::path::{Path, PathBuf};
use vitro::entity::EntityId;
use vitro::time::{SimDuration, SimTime};
use vitro_evac::EvacRun;
use vitro_evac::Mission;
use vitro_evac::external::{Command, SharedDesk, lock, target_points};
use vitro_evac::scenario::{EnvSpec, Validated};
use vitro_mission::{BuildOptions, Mission as _, RegistryError, Run};
use vitro_tactical::condition::{Role, Status};
use vitro_tactical::world::Side;
use vitro_tools::ToolError;

/// Simulated time between two checks for news while advancing, seconds (the sensors'
/// period in the shipped scenarios).
const SLICE_S: f64 = 1.0;

/// An evacuation run with externally driven units.
#[pyclass(unsendable, module = "vitro._vitro")]
pub struct EvacSim {
    mission: EvacRun,
    desk: SharedDesk,
    agents: Vec<(String, EntityId)>,
    targets: Vec<[f64; 3]>,
    /// The scenario's `[env]` table.
    env: EnvSpec,
    /// Seconds each agent (in `agents` order) covered a team member so far.
    cover_s: Vec<f64>,
}

fn side_code(s: Side) -> i64 {
    match s {
        Side::Blue => 1,
        Side::Red => 2,
        _ => 0,
    }
}

/// The scenario last validated in this thread: its path, text and fidelity preset, and
/// what validating it gave (the site, and the street graphs once a run was built on it).
type Kept = (PathBuf, String, Option<String>, Validated);

thread_local! {
    static LAST: RefCell<Option<Kept>> = const { RefCell::new(None) };
}

/// The scenario at `path` (its `text`) validated at the `fidelity` preset; a clone of the
/// last one when the path, the text and the preset are the same (a new episode of the same
/// task: the site and its street graphs are built once, not on every reset).
fn validated(path: &Path, text: &str, fidelity: Option<&str>) -> Result<Validated, ToolError> {
    let same = |k: &Kept| k.0 == path && k.1 == text && k.2.as_deref() == fidelity;
    if let Some(v) = LAST.with_borrow(|k| k.as_ref().filter(|k| same(k)).map(|k| k.3.clone())) {
        return Ok(v);
    }
    let v = vitro_evac::validated(path, text, fidelity)
        .map_err(|e| vitro_tools::scenario_error(path, RegistryError::Mission(e)))?;
    // Built now, so that every clone shares them.
    v.roads();
    let kept = (
        path.to_path_buf(),
        text.to_string(),
        fidelity.map(str::to_string),
        v.clone(),
    );
    LAST.with_borrow_mut(|k| *k = Some(kept));
    Ok(v)
}

/// Builds the run: the scenario checked as `vitro run` checks it (same messages), then the
/// mission with `units` (default: every controllable unit) driven from outside.
fn build(
    path: PathBuf,
    options: BuildOptions,
    units: Option<Vec<String>>,
) -> Result<EvacSim, ToolError> {
    let (mission, text) = vitro_tools::registry()
        .read(&path)
        .map_err(|e| vitro_tools::scenario_error(&path, e))?;
    if mission.kind() != vitro_evac::Evacuation.kind() {
        return Err(ToolError::Input(format!(
            "{}: a {:?} scenario; the environment runs evacuation scenarios",
            path.display(),
            mission.kind()
        )));
    }
    let v = validated(&path, &text, options.fidelity.as_deref())?;
    let env = v.loaded.file.env.clone();
    let can = Mission::controllable(&v);
    let units = units.unwrap_or_else(|| can.clone());
    if units.is_empty() {
        return Err(ToolError::Input(format!(
            "{}: no unit to drive from outside",
            path.display()
        )));
    }
    if let Some(bad) = units.iter().find(|u| !can.contains(u)) {
        return Err(ToolError::Input(format!(
            "{bad:?} cannot be driven from outside (the controllable units of {}: {})",
            path.display(),
            can.join(", ")
        )));
    }
    let (mission, desk) = Mission::build_external(v, options.seed, &units).map_err(|e| {
        vitro_tools::scenario_error(&path, RegistryError::Mission(vitro_evac::mission_error(e)))
    })?;
    let agents = units
        .iter()
        .filter_map(|u| {
            let m = mission.members.iter().find(|m| &m.name == u)?;
            Some((u.clone(), m.id))
        })
        .collect();
    let points = target_points(&mission.brief);
    let cover_s = vec![0.0; units.len()];
    Ok(EvacSim {
        mission,
        desk,
        agents,
        targets: points,
        env,
        cover_s,
    })
}

impl EvacSim {
    /// Credits `dt` seconds of cover to each agent that is an active aircraft within the
    /// cover radius of an active team member (the truck, a trooper, the VIP), while the VIP
    /// is not out yet (the referee's escort).
    fn credit_cover(&mut self, dt: f64) {
        if self.mission.referee.metrics.success {
            return;
        }
        let w = self.mission.sim.env();
        let radius = self.mission.brief.mission.cover_radius_m;
        let team: Vec<[f64; 3]> = w
            .conditions
            .iter()
            .filter(|(_, c)| {
                c.side == Side::Blue
                    && c.status == Status::Active
                    && matches!(c.role, Role::Truck | Role::Trooper | Role::Vip)
            })
            .filter_map(|(id, _)| w.pose(id).map(|p| p.pos))
            .collect();
        for ((_, id), cover) in self.agents.iter().zip(self.cover_s.iter_mut()) {
            let flying = w
                .conditions
                .get(*id)
                .is_some_and(|c| c.role.is_aircraft() && c.status == Status::Active);
            let Some(me) = w.pose(*id).filter(|_| flying) else {
                continue;
            };
            let near = |p: &[f64; 3]| {
                let (dx, dy) = (p[0] - me.pos[0], p[1] - me.pos[1]);
                dx * dx + dy * dy <= radius * radius
            };
            if team.iter().any(near) {
                *cover += dt;
            }
        }
    }

    fn id(&self, agent: &str) -> Result<EntityId, ToolError> {
        self.agents
            .iter()
            .find(|(n, _)| n == agent)
            .map(|(_, id)| *id)
            .ok_or_else(|| ToolError::Input(format!("no agent {agent:?}")))
    }

    fn knowledge_json(&self, agent: &str) -> Result<String, ToolError> {
        let id = self.id(agent)?;
        let desk = lock(&self.desk);
        let k = desk
            .units
            .get(&id)
            .map(|s| s.knowledge.clone())
            .unwrap_or_default();
        let now = self.mission.sim.now();
        let stale = SimDuration::from_secs_f64(self.mission.brief.sensors.stale_s);
        let seen: Vec<serde_json::Value> = k
            .seen
            .iter()
            .map(|(who, p, side)| serde_json::json!([who.0, p[0], p[1], side_code(*side)]))
            .collect();
        let heard: Vec<serde_json::Value> = k
            .heard
            .iter()
            .filter(|(_, h)| now.saturating_since(h.at) <= stale)
            .map(|(who, h)| {
                let age = now.saturating_since(h.at).as_secs_f64();
                let side = side_code(h.seen_as);
                serde_json::json!([who.0, h.pos[0], h.pos[1], side, age, h.from.0])
            })
            .collect();
        let out = serde_json::json!({
            "pos": k.pos.map(|p| [p[0], p[1]]),
            "active": k.active,
            "goal": k.goal,
            "arrived": k.arrived,
            "seen": seen,
            "heard": heard,
            "under_way": k.under_way,
            "refused": k.refused,
        });
        Ok(out.to_string())
    }
}

#[pymethods]
impl EvacSim {
    /// Builds the run of the evacuation scenario at `scenario_path`.
    #[new]
    #[pyo3(signature = (scenario_path, seed=None, fidelity=None, units=None))]
    fn new(
        py: Python<'_>,
        scenario_path: PathBuf,
        seed: Option<u64>,
        fidelity: Option<String>,
        units: Option<Vec<String>>,
    ) -> PyResult<EvacSim> {
        guarded(|| build(scenario_path, BuildOptions { seed, fidelity }, units))
            .map_err(|e| py_error(py, e))
    }

    /// The names of the externally driven units, in id order.
    fn agents(&self) -> Vec<String> {
        self.agents.iter().map(|(n, _)| n.clone()).collect()
    }

    /// The targets commands name: world (x, y, z) points, in order.
    fn targets(&self) -> Vec<(f64, f64, f64)> {
        self.targets.iter().map(|p| (p[0], p[1], p[2])).collect()
    }

    /// The target indices of the start, the safehouse and the extraction point.
    fn places(&self) -> (usize, usize, usize) {
        let [a, b, c] = vitro_evac::external::places(&self.mission.brief);
        (a, b, c)
    }

    /// The simulated time now, seconds.
    fn now(&self) -> f64 {
        self.mission.sim.now().as_secs_f64()
    }

    /// When the run ends at the latest, simulated seconds.
    fn end(&self) -> f64 {
        self.mission.end.as_secs_f64()
    }

    /// Ends the run at `until` simulated seconds at the latest.
    fn set_end(&mut self, py: Python<'_>, until: f64) -> PyResult<()> {
        vitro_tools::set_until(&mut self.mission, until).map_err(|e| py_error(py, e))
    }

    /// True once the mission is over.
    fn finished(&self) -> bool {
        self.mission.finished()
    }

    /// The trace hash so far, as `vitro run` prints it.
    fn trace_hash(&self) -> String {
        format!("{:016x}", self.mission.sim.trace_hash())
    }

    /// Leaves a command for `agent`: 0 holds, `1 + i` goes to target `i`. Carried out at
    /// the unit's next look (within a sensor period).
    fn command(&mut self, py: Python<'_>, agent: &str, action: i64) -> PyResult<()> {
        let run = || {
            let id = self.id(agent)?;
            let command = match usize::try_from(action) {
                Ok(0) => Command::Hold,
                Ok(a) if a <= self.targets.len() => Command::GoTo(a - 1),
                _ => {
                    return Err(ToolError::Input(format!(
                        "action {action} for {agent:?}: expected 0 (hold) to {} (a target)",
                        self.targets.len()
                    )));
                }
            };
            lock(&self.desk).units.entry(id).or_default().pending = Some(command);
            Ok(())
        };
        guarded(run).map_err(|e| py_error(py, e))
    }

    /// Runs at most `max_s` simulated seconds, in slices of a second; with `stop_on_news`
    /// stops after the first slice in which a driven unit reached its goal or saw a new
    /// hostile, with `stop_when_decided` after the slice in which the mission was decided
    /// (the VIP extracted or down). Returns false once the mission is over.
    #[pyo3(signature = (max_s, stop_on_news, stop_when_decided=false))]
    fn advance(
        &mut self,
        py: Python<'_>,
        max_s: f64,
        stop_on_news: bool,
        stop_when_decided: bool,
    ) -> PyResult<bool> {
        let run = || {
            if !(max_s > 0.0 && max_s.is_finite()) {
                return Err(ToolError::Input(format!(
                    "advance {max_s}: expected a positive number of simulated seconds"
                )));
            }
            for slot in lock(&self.desk).units.values_mut() {
                slot.knowledge.arrived = false;
                slot.knowledge.new_contact = false;
            }
            let stop =
                (self.mission.sim.now() + SimDuration::from_secs_f64(max_s)).min(self.mission.end);
            let slice = SimDuration::from_secs_f64(SLICE_S);
            loop {
                let before = self.mission.sim.now();
                let t: SimTime = (before + slice).min(stop);
                let going = self.mission.advance(t);
                self.credit_cover(
                    self.mission
                        .sim
                        .now()
                        .saturating_since(before)
                        .as_secs_f64(),
                );
                if !going {
                    return Ok(false);
                }
                if stop_when_decided && self.mission.referee.decided() {
                    return Ok(true);
                }
                let news = lock(&self.desk)
                    .units
                    .values()
                    .any(|s| s.knowledge.arrived || s.knowledge.new_contact);
                if t >= stop || (stop_on_news && news) {
                    return Ok(true);
                }
            }
        };
        guarded(run).map_err(|e| py_error(py, e))
    }

    /// What `agent` knows, as JSON text: `pos` [x, y] (world metres) or null, `active`,
    /// `goal` (target index or null), `arrived`, `seen` [[id, x, y, side]] nearest first,
    /// `heard` [[target id, x, y, side, age_s, sender id]] (side: 0 neutral, 1 blue, 2
    /// red; reports from other units no older than `sensors.stale_s`), `under_way` (a UGV
    /// on a trip: it takes a new goal only once there), `refused`.
    fn knowledge(&self, py: Python<'_>, agent: &str) -> PyResult<String> {
        guarded(|| self.knowledge_json(agent)).map_err(|e| py_error(py, e))
    }

    /// The scenario's `sensors.stale_s`: how long a heard report is kept, seconds.
    fn stale_s(&self) -> f64 {
        self.mission.brief.sensors.stale_s
    }

    /// The master seed the run was built with.
    fn seed(&self) -> u64 {
        self.mission.seed
    }

    /// The entities' ids, names and sides (1 blue, 2 red, 0 neutral), in id order.
    fn members(&self) -> Vec<(u32, String, i64)> {
        self.mission
            .members
            .iter()
            .map(|m| (m.id.0, m.name.clone(), side_code(m.side)))
            .collect()
    }

    /// The referee's ground truth (never given to an agent), in id order: one row per
    /// entity `[x, y, z, status]`, world metres (a body's own pose; a rider's is its
    /// vehicle's, none gives zeros), status 0 hidden, 1 active, 2 aboard, 3 down, 4
    /// captured, 5 extracted.
    fn state(&self) -> Vec<[f64; 4]> {
        let w = self.mission.sim.env();
        self.mission
            .members
            .iter()
            .map(|m| {
                let status = w.conditions.get(m.id).map(|c| c.status);
                let body = match status {
                    Some(Status::Aboard(v)) => v,
                    _ => m.id,
                };
                let p = w.pose(body).map_or([0.0; 3], |p| p.pos);
                let code = match status {
                    None | Some(Status::Hidden) => 0.0,
                    Some(Status::Active) => 1.0,
                    Some(Status::Aboard(_)) => 2.0,
                    Some(Status::Down) => 3.0,
                    Some(Status::Captured) => 4.0,
                    Some(Status::Extracted) => 5.0,
                };
                [p[0], p[1], p[2], code]
            })
            .collect()
    }

    /// The scenario's `[env]` table as JSON text: `hunt` and `reward` (every weight).
    fn env_settings(&self) -> String {
        serde_json::to_string(&self.env).unwrap_or_default()
    }

    /// Seconds each agent (in `agents()` order) was an active aircraft within the cover
    /// radius of an active team member (the truck, a trooper, the VIP) while the VIP was not
    /// out yet, so far (the referee's measure, never given to an agent).
    fn cover_s(&self) -> Vec<f64> {
        self.cover_s.clone()
    }

    /// True once the mission is decided: the VIP extracted or down.
    fn decided(&self) -> bool {
        self.mission.referee.decided()
    }

    /// The mission's metrics so far (the referee's, never given to an agent), as JSON text.
    fn metrics(&self) -> String {
        serde_json::Value::Object(self.mission.report()).to_string()
    }
}

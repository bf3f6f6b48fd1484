//! The perimeter watch as a mission of the tools: its metrics, its part of a run (a [`Play`]
//! of the generic [`Session`]) and its kind (a [`Mission`]).

use super::agents::Watch;
use super::scenario::{self, Validated};
use super::setup::{self, Cast};
use std::path::Path;
use std::sync::Arc;
use vitro_mission::session::{Play, Session, Setup};
use vitro_mission::{BuildOptions, Metric, MetricTable, Mission, MissionError, Run, metric_table};
use vitro_record::{Frame, Scene};
use vitro_site::site::Site;
use vitro_tactical::scenario::Preset;

// ANCHOR: metrics
/// What the referee measures, from the ground truth and the guards' own records.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Metrics {
    /// Walkers in the scenario.
    pub walkers: usize,
    /// Walkers a guard's own camera saw.
    pub walkers_seen: usize,
    /// Walkers within `reach_m` of the depot now.
    pub walkers_at_depot: usize,
    /// When a guard first saw a walker, seconds.
    pub first_sighting_s: Option<f64>,
    /// Walkers a guard heard of on the radio before it saw them.
    pub heard_first: u32,
    /// Trips the guards' bodies gave up (stuck on the way).
    pub stalls: u32,
}

impl MetricTable for Metrics {
    fn table(&self) -> Vec<(&'static str, Metric)> {
        metric_table!(self; walkers, walkers_seen, walkers_at_depot, first_sighting_s, heard_first, stalls)
    }
}
// ANCHOR_END: metrics

/// The mission's part of a run: the cast and the depot.
pub struct Perimeter {
    /// Who is who.
    pub cast: Cast,
    /// The depot, world metres.
    pub depot: [f64; 3],
    /// How close is "at the depot", metres.
    pub reach_m: f64,
    /// The site, for the scene.
    pub site: Arc<Site>,
}

/// A run of the perimeter watch.
pub type WatchRun = Session<Perimeter>;

// ANCHOR: play
impl Play for Perimeter {
    type Model = Watch;
    type Metrics = Metrics;
    type Heard = ();

    fn metrics(run: &WatchRun) -> Metrics {
        let guards = run.cast.guards.iter().filter_map(|g| run.sim.agent(g));
        let mut seen: Vec<_> = guards
            .clone()
            .flat_map(|g| g.seen.iter().copied())
            .collect();
        seen.sort();
        let first_sighting_s = seen.first().map(|s| s.0.as_secs_f64());
        seen.sort_by_key(|s| s.1);
        seen.dedup_by_key(|s| s.1);
        let at_depot = |id| {
            run.sim.env().pose(id).is_some_and(|p| {
                libm::hypot(p.pos[0] - run.depot[0], p.pos[1] - run.depot[1]) <= run.reach_m
            })
        };
        Metrics {
            walkers: run.cast.walkers.len(),
            walkers_seen: seen.len(),
            walkers_at_depot: run.cast.walkers.iter().filter(|&&id| at_depot(id)).count(),
            first_sighting_s,
            heard_first: guards.clone().map(|g| g.heard_first).sum(),
            stalls: guards.map(|g| g.stalls).sum(),
        }
    }

    fn summary(_: &WatchRun, m: &Metrics) -> Vec<(String, String)> {
        let first = m
            .first_sighting_s
            .map_or("-".into(), |t| format!("{t:.0} s"));
        vec![(
            "walkers".into(),
            format!(
                "{} of {} seen (first at {first}), {} at the depot, {} heard of first; {} stalls",
                m.walkers_seen, m.walkers, m.walkers_at_depot, m.heard_first, m.stalls
            ),
        )]
    }

    fn scene(run: &WatchRun) -> Scene {
        let mut scene =
            vitro_mission::scene::site_scene(&run.site, run.name.clone(), run.start.unix_millis());
        scene.places.insert("depot".into(), run.depot);
        scene
    }

    fn frame(run: &mut WatchRun, frame: &mut Frame) {
        let w = run.sim.env();
        for (k, (name, kind)) in run.cast.kinds.iter().enumerate() {
            let id = vitro::entity::EntityId(k as u32);
            if let (Some(p), Some(c)) = (w.pose(id), w.conditions.get(id)) {
                let status = c.status.name().to_owned();
                let e = vitro_tactical::record::entity(id, name, kind.name(), c.side, &p, status);
                frame.entities.push(e);
            }
        }
    }
}
// ANCHOR_END: play

// ANCHOR: mission
/// The perimeter watch, `kind = "watch"`.
pub struct PerimeterWatch;

impl Mission for PerimeterWatch {
    fn kind(&self) -> &'static str {
        "watch"
    }
    fn about(&self) -> &'static str {
        "two UGVs guard a depot against walkers, seeing with their cameras, telling by radio"
    }
    fn fidelity_levels(&self) -> &'static [&'static str] {
        &Preset::NAMES
    }
    fn validate(&self, path: &Path, text: &str) -> Result<String, MissionError> {
        let v = read(path, text)?;
        let count = |blue: bool| -> u32 {
            let group = v
                .file
                .entities
                .iter()
                .filter(|e| e.kind.is_vehicle() == blue);
            group.map(|e| e.count).sum()
        };
        Ok(format!("{} guards, {} walkers", count(true), count(false)))
    }
    fn build(
        &self,
        path: &Path,
        text: &str,
        options: &BuildOptions,
    ) -> Result<Box<dyn Run>, MissionError> {
        let mut v = read(path, text)?;
        let preset = Preset::named(options.fidelity.as_deref())
            .map_err(|e| MissionError::Scenario(e.to_string()))?;
        if let Some(level) = preset {
            v.file.fidelity.set_preset(level);
        }
        let f = &v.file;
        let seed = options.seed.unwrap_or(f.seed);
        let setup = Setup::from_secs(
            f.name.clone(),
            seed,
            f.end.time_s,
            f.record.sample_s,
            f.start,
        );
        let (sim, cast) = setup::build(&v, seed).map_err(|e| MissionError::Setup(e.to_string()))?;
        let play = Perimeter {
            cast,
            depot: v.site.on_ground(f.watch.depot),
            reach_m: f.watch.reach_m,
            site: v.site,
        };
        Ok(Box::new(Session::new(setup, sim, play)))
    }
    fn metric_names(&self) -> Vec<&'static str> {
        WatchRun::metric_names()
    }
}

/// The scenario `text` read from `path` and checked, or every problem as one report.
fn read(path: &Path, text: &str) -> Result<Validated, MissionError> {
    scenario::validate(path, text).map_err(|d| MissionError::Scenario(d.report()))
}
// ANCHOR_END: mission

//! The registry of scenarios and properties, the run of every scenario at each of its levels,
//! and the report: one row per (entity, level, property).

use super::{CheckError, Family, Property, Run, Scenario, Setup, property, scenario};
use serde::Serialize;
use vitro_tactical::entity::Level;

/// One line of the report.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct Row {
    /// Entity (type) name.
    pub entity: String,
    /// Level.
    pub level: Level,
    /// Property name.
    pub property: String,
    /// Whether it holds.
    pub pass: bool,
    /// The measured value.
    pub value: f64,
    /// The bound, in words.
    pub limit: String,
}

/// How fast one level ran: simulated seconds per wall-clock second over its runs.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct LevelSpeed {
    /// The family.
    pub family: Family,
    /// The level.
    pub level: Level,
    /// Runs at this level.
    pub runs: usize,
    /// Simulated seconds, summed.
    pub sim_seconds: f64,
    /// Wall-clock seconds, summed.
    pub wall_seconds: f64,
    /// Simulated seconds per wall-clock second.
    pub speed: f64,
}

/// The outcome of a check.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct CheckReport {
    /// One row per (entity, level, applicable property).
    pub rows: Vec<Row>,
    /// Each level's speed.
    pub speeds: Vec<LevelSpeed>,
    /// True if every row passes.
    pub pass: bool,
}

impl CheckReport {
    /// The report as a plain-text table.
    pub fn table(&self) -> String {
        let mut out = format!(
            "{:<14} {:<13} {:<22} {:<5} {:>12}  {}\n",
            "entity", "level", "property", "pass", "value", "limit"
        );
        for r in &self.rows {
            out += &format!(
                "{:<14} {:<13} {:<22} {:<5} {:>12.4}  {}\n",
                r.entity,
                r.level.name(),
                r.property,
                if r.pass { "yes" } else { "NO" },
                r.value,
                r.limit
            );
        }
        out += &format!(
            "\n{:<8} {:<13} {:>4} {:>10} {:>9} {:>14}\n",
            "family", "level", "runs", "sim s", "wall s", "sim s / wall s"
        );
        for s in &self.speeds {
            out += &format!(
                "{:<8} {:<13} {:>4} {:>10.1} {:>9.3} {:>14.0}\n",
                format!("{:?}", s.family).to_lowercase(),
                s.level.name(),
                s.runs,
                s.sim_seconds,
                s.wall_seconds,
                s.speed
            );
        }
        out += &format!(
            "\n{}\n",
            if self.pass {
                "all properties hold"
            } else {
                "SOME PROPERTIES FAIL"
            }
        );
        out
    }
}

/// Scenarios and properties.
#[derive(Default)]
pub struct Registry {
    scenarios: Vec<Box<dyn Scenario>>,
    properties: Vec<Box<dyn Property>>,
}

impl Registry {
    /// An empty registry.
    pub fn new() -> Self {
        Self::default()
    }

    /// The standard scenarios on `setup`'s town and the standard properties.
    pub fn standard(setup: &Setup) -> Result<Self, CheckError> {
        let mut r = Registry::new();
        for s in scenario::standard(setup)? {
            r.add_scenario(s);
        }
        for p in property::standard() {
            r.add_property(p);
        }
        Ok(r)
    }

    /// Adds a scenario.
    pub fn add_scenario(&mut self, s: Box<dyn Scenario>) {
        self.scenarios.push(s);
    }
    /// Adds a property.
    pub fn add_property(&mut self, p: Box<dyn Property>) {
        self.properties.push(p);
    }

    /// Runs every scenario at each of its levels (the reference level first) and judges
    /// every run by every property that applies.
    pub fn run(&self, setup: &Setup) -> Result<CheckReport, CheckError> {
        let mut rows = Vec::new();
        let mut runs: Vec<Run> = Vec::new();
        for sc in &self.scenarios {
            let mut reference = None;
            for (i, level) in sc.levels().into_iter().enumerate() {
                let mut run = sc.run(setup, level)?;
                if i == 0 {
                    reference = run.arrival;
                } else {
                    run.reference = reference;
                }
                for p in &self.properties {
                    if let Some(v) = p.evaluate(&run, &setup.site) {
                        rows.push(Row {
                            entity: run.entity.clone(),
                            level: run.level,
                            property: p.name().to_owned(),
                            pass: v.pass,
                            value: v.value,
                            limit: v.limit,
                        });
                    }
                }
                runs.push(run);
            }
        }
        let mut speeds: Vec<LevelSpeed> = Vec::new();
        for run in &runs {
            match speeds
                .iter_mut()
                .find(|s| s.family == run.family && s.level == run.level)
            {
                Some(s) => {
                    s.runs += 1;
                    s.sim_seconds += run.sim_seconds;
                    s.wall_seconds += run.wall_seconds;
                }
                None => speeds.push(LevelSpeed {
                    family: run.family,
                    level: run.level,
                    runs: 1,
                    sim_seconds: run.sim_seconds,
                    wall_seconds: run.wall_seconds,
                    speed: 0.0,
                }),
            }
        }
        for s in &mut speeds {
            s.speed = s.sim_seconds / s.wall_seconds.max(1e-9);
        }
        let pass = rows.iter().all(|r| r.pass);
        Ok(CheckReport { rows, speeds, pass })
    }
}

/// The check the command line runs: the standard registry on the real town on the real
/// terrain ([`DEFAULT_MAP`](vitro_tactical::setup::DEFAULT_MAP), [`DEFAULT_TERRAIN`](vitro_tactical::setup::DEFAULT_TERRAIN)).
pub fn check_levels() -> Result<CheckReport, CheckError> {
    let setup = Setup::default_town()?;
    Registry::standard(&setup)?.run(&setup)
}

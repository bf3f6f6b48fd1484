//! Reading a scenario file: the TOML syntax, then the types, then the checks.
//!
//! Every stage reports every problem it finds: all syntax errors the parser recovers from;
//! then, if the whole document does not fit the types, each top-level key and each
//! `[[entity]]` on its own; then the semantic checks of [`check`](super::check).

use super::check::{check_file, check_site};
use super::loaded::Loaded;
use super::{
    EnvSpec, FormationSpec, MissionSpec, PatrolSpec, Places, PursuitSpec, RepairSpec, ScenarioFile,
    SensorsSpec, TieOrder,
};
use std::path::Path;
use std::sync::{Arc, OnceLock};
use vitro_site::site::Site;
use vitro_tactical::entity::roads::Roads;
use vitro_tactical::scenario::checker::resolve;
use vitro_tactical::scenario::tables::{self, Layout, one};
use vitro_tactical::scenario::{Diagnostic, Diagnostics, SourceMap};

/// The keys of a scenario file's top level, in the order of [`ScenarioFile`]'s fields.
pub const TOP_LEVEL_KEYS: [&str; 19] = [
    "kind",
    "name",
    "seed",
    "start",
    "tie_order",
    "end",
    "site",
    "fidelity",
    "places",
    "entity",
    "mission",
    "sensors",
    "channel",
    "patrol",
    "pursuit",
    "repair",
    "formation",
    "record",
    "env",
];

/// A scenario file read and checked against its site, with the site built.
///
/// A clone shares the site, the calibration and, once built, the free street graphs
/// ([`roads`](Self::roads)): runs built from clones of one `Validated` (the episodes of a
/// learning environment, say) build them once.
#[derive(Clone, Debug)]
pub struct Validated {
    /// The file.
    pub loaded: Loaded,
    /// The town on its terrain at the scenario's offset.
    pub site: Arc<Site>,
    /// The calibration the scenario names, checked against its site and types.
    pub calibration: Option<Arc<vitro_tactical::calibration::Calibration>>,
    /// The free street graphs of `site`, built the first time they are asked for.
    roads: OnceLock<Arc<Roads>>,
}

impl Validated {
    /// The free street graphs of the site: built on the first call, then shared by this
    /// value and every clone made after.
    pub fn roads(&self) -> Arc<Roads> {
        (self.roads)
            .get_or_init(|| Arc::new(Roads::new(&self.site)))
            .clone()
    }
}

impl ScenarioFile {
    /// Reads the scenario at `path` and checks everything that does not need the site:
    /// syntax, types, ranges, files, fidelity levels, entity names and altitudes, and the
    /// entities the mission needs. Paths in the file are relative to its directory.
    ///
    /// ```
    /// use vitro_evac::scenario::ScenarioFile;
    /// let path = concat!(env!("CARGO_MANIFEST_DIR"), "/../../scenarios/evacuation.toml");
    /// let loaded = ScenarioFile::load(path).unwrap();
    /// assert!(loaded.map.ends_with("data/maps/kotka.osm.pbf"));
    /// assert!(loaded.map.is_absolute());
    /// ```
    pub fn load(path: impl AsRef<Path>) -> Result<Loaded, Diagnostics> {
        let (loaded, problems) = read(path.as_ref())?;
        if problems.is_empty() {
            Ok(loaded)
        } else {
            Err(Diagnostics::new(problems))
        }
    }

    /// [`load`](Self::load), then builds the site and checks the places and the entities'
    /// starts against it (inside the town, not in a building or forbidden zone). Reports
    /// every problem of both stages together.
    pub fn validate(path: impl AsRef<Path>) -> Result<Validated, Diagnostics> {
        let (loaded, problems) = read(path.as_ref())?;
        Self::validate_loaded(loaded, problems)
    }

    /// [`validate`](Self::validate) of `text` as if it were the file at `path`: its paths
    /// resolve from `path`'s directory and its problems name `path` (a scenario varied by
    /// an experiment, for instance).
    pub fn validate_text(path: impl AsRef<Path>, text: &str) -> Result<Validated, Diagnostics> {
        let (loaded, problems) = read_text(path.as_ref(), text.to_owned())?;
        Self::validate_loaded(loaded, problems)
    }

    fn validate_loaded(
        loaded: Loaded,
        mut problems: Vec<Diagnostic>,
    ) -> Result<Validated, Diagnostics> {
        if loaded.map.is_file() && loaded.terrain.is_file() {
            match loaded.site() {
                Ok(site) => {
                    let map = SourceMap::new(&loaded.path, &loaded.source);
                    problems.extend(check_site(&loaded.file, &site, &map));
                    // (A missing file is reported by the file checks.)
                    let named = loaded.calibration.as_ref().is_some_and(|p| p.is_file());
                    let calibration = match named.then(|| loaded.calibration()).transpose() {
                        Ok(c) => c.flatten().map(Arc::new),
                        Err(d) => {
                            problems.extend(d.0);
                            None
                        }
                    };
                    if problems.is_empty() {
                        return Ok(Validated {
                            loaded,
                            site: Arc::new(site),
                            calibration,
                            roads: OnceLock::new(),
                        });
                    }
                }
                Err(d) => problems.extend(d.0),
            }
        }
        Err(Diagnostics::new(problems))
    }
}

fn single(d: Diagnostic) -> Diagnostics {
    Diagnostics(vec![d])
}

/// Reads, parses and checks the file: the scenario with the problems found, or the problems
/// that stopped the parse.
fn read(path: &Path) -> Result<(Loaded, Vec<Diagnostic>), Diagnostics> {
    let source = std::fs::read_to_string(path).map_err(|e| {
        single(Diagnostic::new(
            path,
            "",
            None,
            format!("cannot read the scenario: {e}"),
            Some("a readable TOML file".into()),
        ))
    })?;
    read_text(path, source)
}

/// [`read`] of `source` as if it were the file at `path` (paths resolve from its directory).
fn read_text(path: &Path, source: String) -> Result<(Loaded, Vec<Diagnostic>), Diagnostics> {
    let file = parse(path, &source).map_err(Diagnostics::new)?;
    let resolve = |p: &Path| resolve(path, p);
    let loaded = Loaded {
        map: resolve(&file.site.map),
        terrain: resolve(&file.site.terrain),
        program: file.formation.program.as_deref().map(resolve),
        calibration: file.fidelity.calibration.as_deref().map(resolve),
        file,
        path: path.to_path_buf(),
        source,
    };
    let problems = {
        let map = SourceMap::new(&loaded.path, &loaded.source);
        check_file(&loaded, &map)
    };
    Ok((loaded, problems))
}

/// The evacuation's own top-level keys (beside the shared ones), each with the check of its
/// value, and those a file must have.
const LAYOUT: Layout<'static> = Layout {
    keys: &[
        ("tie_order", one::<TieOrder>),
        ("places", one::<Places>),
        ("mission", one::<MissionSpec>),
        ("sensors", one::<SensorsSpec>),
        ("patrol", one::<PatrolSpec>),
        ("pursuit", one::<PursuitSpec>),
        ("repair", one::<RepairSpec>),
        ("formation", one::<FormationSpec>),
        ("env", one::<EnvSpec>),
    ],
    required: &[("places", "a top-level `places`")],
};

/// Parses `text` into a scenario, or every syntax or type error found.
pub(crate) fn parse(file: &Path, text: &str) -> Result<ScenarioFile, Vec<Diagnostic>> {
    tables::parse(file, text, &LAYOUT)
}

#[cfg(test)]
mod layout_tests {
    use super::*;

    #[test]
    fn the_layout_lists_the_top_level_keys() {
        let mut keys = LAYOUT.key_names();
        keys.sort_unstable();
        let mut want = TOP_LEVEL_KEYS;
        want.sort_unstable();
        assert_eq!(keys, want);
    }
}

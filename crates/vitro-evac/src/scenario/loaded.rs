//! A scenario file read and checked, with its paths resolved: what building its site needs.

use super::ScenarioFile;
use std::path::PathBuf;
use vitro_site::site::Site;
use vitro_tactical::calibration::{Calibration, site_fingerprint, types_fingerprint};
use vitro_tactical::scenario::checker::SiteFiles;
use vitro_tactical::scenario::{Diagnostics, SourceMap};
use vitro_tactical::types::TypeBook;

/// A scenario file read and checked, with its paths resolved.
#[derive(Clone, Debug)]
pub struct Loaded {
    /// The scenario.
    pub file: ScenarioFile,
    /// The scenario file's path, as it was named.
    pub path: PathBuf,
    /// The map, absolute.
    pub map: PathBuf,
    /// The terrain, absolute.
    pub terrain: PathBuf,
    /// The formation rule file, absolute (none: the built-in rules).
    pub program: Option<PathBuf>,
    /// The calibration file, absolute (none: uncalibrated abstract levels).
    pub calibration: Option<PathBuf>,
    /// The file's text.
    pub source: String,
}

impl Loaded {
    /// Reads the calibration the scenario names, if any, and checks that it was made for
    /// this scenario's map, terrain and the built-in type set; problems point at
    /// `[fidelity] calibration`.
    pub fn calibration(&self) -> Result<Option<Calibration>, Diagnostics> {
        let Some(path) = &self.calibration else {
            return Ok(None);
        };
        let map = SourceMap::new(&self.path, &self.source);
        let fail = |e: String| {
            Diagnostics(vec![map.at(
                "fidelity.calibration",
                e,
                "a calibration made by `vitro calibrate` on this scenario's map and types",
            )])
        };
        let cal = Calibration::read(path).map_err(|e| fail(e.to_string()))?;
        let site = site_fingerprint(&self.map, &self.terrain, self.file.site.offset)
            .map_err(|e| fail(e.to_string()))?;
        cal.check(&site, &types_fingerprint(TypeBook::builtin()))
            .map_err(|e| fail(e.to_string()))?;
        Ok(Some(cal))
    }

    /// The scenario's `[site]` files.
    pub fn site_files(&self) -> SiteFiles {
        SiteFiles {
            map: self.map.clone(),
            terrain: self.terrain.clone(),
        }
    }

    /// Builds the town on its terrain at the scenario's offset; problems point at `[site]`.
    pub fn site(&self) -> Result<Site, Diagnostics> {
        let map = SourceMap::new(&self.path, &self.source);
        (self.site_files())
            .load(&self.file.site, &map)
            .map_err(|d| Diagnostics(vec![*d]))
    }
}

//! Checking any mission's scenario: the shared tables (`[end]`, `[site]`, `[fidelity]`,
//! `[[entity]]`, `[channel]`, `[record]`, a camera's [`VisionSpec`]) and the building blocks
//! a mission checks its own tables with.
//!
//! A [`Checker`] collects problems, each at the place of the key it names (file, line,
//! column, what was expected), and goes on, so one pass reports them all. [`SiteFiles`]
//! resolves a `[site]` table's files and builds the town on its terrain, and
//! [`Checker::place`] checks a point against it.
//!
//! ```
//! use std::path::Path;
//! use vitro_tactical::scenario::checker::Checker;
//! use vitro_tactical::scenario::{ChannelSpec, EntitySpec, SourceMap};
//!
//! let text = "[channel]\nloss = 1.5\n\n[[entity]]\nname = \"ugv\"\ntype = \"ugv\"\nside = \"blue\"\ncount = 0\n";
//! #[derive(serde::Deserialize)]
//! struct File { channel: ChannelSpec, entity: Vec<EntitySpec> }
//! let file: File = toml::from_str(text).unwrap();
//! let map = SourceMap::new(Path::new("watch.toml"), text);
//! let mut c = Checker::new(&map, &file.entity);
//! c.channel(&file.channel);
//! c.entities();
//! c.num("channel.range_m", -1.0, true, 0.0, 1e6, "metres"); // a mission's own check
//! let lines: Vec<String> = c.finish().iter().map(|d| d.to_string()).collect();
//! assert_eq!(lines, [
//!     "watch.toml:2:8: invalid value 1.5 for `channel.loss` (expected a probability in [0, 1])",
//!     "watch.toml:8:9: invalid value 0 for `count` of entity `ugv` (expected a count in 1..=20000)",
//!     "watch.toml:1:1: invalid value -1 for `channel.range_m` (expected metres in (0, 1000000])",
//! ]);
//! ```

use super::span::{Capped, Diagnostic, SourceMap};
use super::{
    ChannelSpec, EndSpec, EntitySpec, EntityType, FidelitySpec, RecordSpec, SiteSpec, VisionSpec,
};
use std::collections::BTreeMap;
use std::path::{Path, PathBuf};
use vitro_site::map::{MapConfig, TownMap};
use vitro_site::site::{Site, SiteConfig};
use vitro_site::terrain::Terrain;

/// Largest end time, seconds.
pub const MAX_END_S: f64 = 1e6;
/// Most entities in one `[[entity]]` group (a scenario may have many groups: swarms of
/// tens of thousands run, see the scaling tables in docs/benchmarks.md).
pub const MAX_COUNT: u32 = 20_000;
/// Flight altitudes above the ground, metres.
pub const ALTITUDE_M: (f64, f64) = (20.0, 3000.0);

/// What a town point is, in words.
pub const TOWN_XY: &str = "town metres [x, y]";

/// Collects the problems of one scenario file, each at the place of the key it names.
pub struct Checker<'a> {
    map: &'a SourceMap<'a>,
    entities: &'a [EntitySpec],
    out: Capped<'a>,
}

impl<'a> Checker<'a> {
    /// A checker of the file `map` reads, whose `[[entity]]` tables are `entities` (they
    /// name the keys of entities in messages: "`count` of entity `scouts`").
    pub fn new(map: &'a SourceMap<'a>, entities: &'a [EntitySpec]) -> Self {
        Checker {
            map,
            entities,
            out: Capped::new(map.file()),
        }
    }

    /// The problems found, in the order they were found (at most
    /// [`MAX_PROBLEMS`](super::MAX_PROBLEMS), then a count of the rest).
    pub fn finish(self) -> Vec<Diagnostic> {
        self.out.finish()
    }

    /// Adds a problem: `message` at the key `path` (`"channel.loss"`, `"entity.0.count"`),
    /// with what was expected.
    pub fn push(&mut self, path: &str, message: String, expected: &str) {
        let map = self.map;
        self.out.push(|| map.at(path, message, expected));
    }

    /// Adds problems found elsewhere (a program the scenario names, a site that did not
    /// build).
    pub fn extend(&mut self, problems: impl IntoIterator<Item = Diagnostic>) {
        for d in problems {
            self.out.push(|| d);
        }
    }

    /// The key at `path` for a message: `` `channel.loss` ``, or `` `count` of entity
    /// `scouts` ``.
    pub fn label(&self, path: &str) -> String {
        let mut parts = path.splitn(3, '.');
        if let (Some("entity"), Some(i), Some(rest)) = (parts.next(), parts.next(), parts.next())
            && let Some(e) = i.parse::<usize>().ok().and_then(|i| self.entities.get(i))
        {
            return format!("`{rest}` of entity `{}`", e.name);
        }
        format!("`{path}`")
    }

    /// Reports `value` at `path` unless `ok`.
    pub fn value(&mut self, path: &str, value: impl std::fmt::Display, ok: bool, expected: &str) {
        if !ok {
            let message = format!("invalid value {value} for {}", self.label(path));
            self.push(path, message, expected);
        }
    }

    /// A number in `[lo, hi]` (or `(lo, hi]` when `open_lo`), `what` in words
    /// (`"seconds"`).
    pub fn num(&mut self, path: &str, v: f64, open_lo: bool, lo: f64, hi: f64, what: &str) {
        let ok = if open_lo { v > lo } else { v >= lo } && v <= hi;
        let bracket = if open_lo { '(' } else { '[' };
        let expected = format!("{what} in {bracket}{lo}, {hi}]");
        self.value(path, v, ok, &expected);
    }

    /// A whole number in `lo..=hi`.
    pub fn count(&mut self, path: &str, v: u64, lo: u64, hi: u64, what: &str) {
        let expected = format!("{what} in {lo}..={hi}");
        self.value(path, v, (lo..=hi).contains(&v), &expected);
    }

    /// A point `[x, y]`: finite, and two numbers in the file (toml reads the first two of
    /// a longer array without a word).
    pub fn point(&mut self, path: &str, p: [f64; 2], what: &str) {
        if let Some(n) = self.map.array_len(path).filter(|&n| n != 2) {
            let message = format!("{n} numbers for {}", self.label(path));
            self.push(path, message, &format!("an array of 2 numbers, {what}"));
        }
        let ok = p.iter().all(|c| c.is_finite());
        self.value(path, format!("{p:?}"), ok, &format!("finite {what}"));
    }

    /// An area `[x_min, y_min, x_max, y_max]`: finite, not empty.
    pub fn area(&mut self, path: &str, a: [f64; 4]) {
        let ok = a.iter().all(|v| v.is_finite()) && a[0] < a[2] && a[1] < a[3];
        let expected = "town metres [x_min, y_min, x_max, y_max], min < max";
        self.value(path, format!("{a:?}"), ok, expected);
    }

    /// A range `[min, max]` of numbers, `0 <= min <= max`.
    pub fn range(&mut self, path: &str, r: [f64; 2], what: &str) {
        let ok = r.iter().all(|v| v.is_finite()) && 0.0 <= r[0] && r[0] <= r[1];
        let expected = format!("[min, max] {what}, 0 <= min <= max");
        self.value(path, format!("{r:?}"), ok, &expected);
    }

    /// A file the scenario names (`given`, found at `resolved`) exists.
    pub fn file_exists(&mut self, path: &str, given: &Path, resolved: &Path, what: &str) {
        if !resolved.is_file() {
            let message = format!(
                "file `{}` not found for {} (looked at {})",
                given.display(),
                self.label(path),
                resolved.display()
            );
            let expected = format!("{what}, relative to the scenario file's directory");
            self.push(path, message, &expected);
        }
    }

    /// A camera's range, field of view, detection probabilities and misidentification.
    pub fn vision(&mut self, path: &str, v: &VisionSpec) {
        let p = |k: &str| format!("{path}.{k}");
        self.num(&p("range_m"), v.range_m, true, 0.0, 1e5, "metres");
        self.num(&p("fov_deg"), v.fov_deg, true, 0.0, 360.0, "degrees");
        self.num(&p("p0"), v.p0, false, 0.0, 1.0, "a probability");
        self.num(&p("falloff"), v.falloff, false, 0.0, 100.0, "an exponent");
        let m = v.misidentification;
        self.num(&p("misidentification"), m, false, 0.0, 1.0, "a probability");
    }

    /// `[end]`: a positive time, at most [`MAX_END_S`].
    pub fn end(&mut self, end: &EndSpec) {
        let what = "simulated seconds";
        self.num("end.time_s", end.time_s, true, 0.0, MAX_END_S, what);
    }

    /// `[site]`: the map and terrain files exist, the offset is a finite point.
    pub fn site(&mut self, spec: &SiteSpec, files: &SiteFiles) {
        let map_what = "an .osm.pbf file";
        self.file_exists("site.map", &spec.map, &files.map, map_what);
        let terrain_what = "a terrain grid";
        self.file_exists("site.terrain", &spec.terrain, &files.terrain, terrain_what);
        if let Some(o) = spec.offset {
            self.point("site.offset", o, "metres [east, north]");
        }
    }

    /// `[fidelity]`: every override is a level its type has.
    pub fn fidelity(&mut self, f: &FidelitySpec) {
        // One type per key (the VIP and the HVT are troopers).
        for t in EntityType::ALL
            .into_iter()
            .filter(|t| t.fidelity_key() == t.name())
        {
            if let Some(level) = f.override_of(t)
                && !t.levels().contains(&level)
            {
                let names: Vec<String> = t.levels().iter().map(|l| format!("`{l}`")).collect();
                let key = t.fidelity_key();
                let message = format!("unknown fidelity level `{level}` for `{key}`");
                let expected = format!("one of {}", names.join(", "));
                self.push(&format!("fidelity.{key}"), message, &expected);
            }
        }
    }

    /// `[[entity]]`: names not empty and unique (a group's own name included), counts in
    /// range, starts finite, an altitude for aircraft and for them only.
    pub fn entities(&mut self) {
        let mut seen: BTreeMap<String, usize> = BTreeMap::new();
        for (i, e) in self.entities.iter().enumerate() {
            let at = |k: &str| format!("entity.{i}.{k}");
            if e.name.trim().is_empty() {
                self.push(&at("name"), "empty entity name".into(), "a non-empty name");
            }
            let mut names = e.names();
            if e.count > 1 {
                names.insert(0, e.name.clone());
            }
            for name in names {
                if let Some(&first) = seen.get(&name) {
                    let line = self
                        .map
                        .at(&format!("entity.{first}.name"), "", "")
                        .position;
                    let line = line.map_or(String::new(), |(l, _)| format!(" (first at line {l})"));
                    let message = format!("duplicate entity name `{name}`{line}");
                    self.push(&at("name"), message, "a name used by one entity only");
                    break;
                }
                seen.insert(name, i);
            }
            let n = u64::from(e.count);
            self.count(&at("count"), n, 1, u64::from(MAX_COUNT), "a count");
            if let Some(p) = e.start {
                self.point(&at("start"), p, TOWN_XY);
            }
            let (lo, hi) = ALTITUDE_M;
            match (e.kind.is_aircraft(), e.altitude_m) {
                (true, None) => {
                    let message =
                        format!("entity `{}` is a {} without `altitude_m`", e.name, e.kind);
                    let expected = format!("`altitude_m` for an aircraft, metres in [{lo}, {hi}]");
                    self.push(&at("type"), message, &expected);
                }
                (true, Some(a)) => self.num(&at("altitude_m"), a, false, lo, hi, "metres"),
                (false, Some(_)) => {
                    let message = format!("entity `{}` is a {} with `altitude_m`", e.name, e.kind);
                    let expected =
                        "no `altitude_m` for a ground entity (only procerus, vidar, skeldar fly)";
                    self.push(&at("altitude_m"), message, expected);
                }
                (false, None) => {}
            }
        }
    }

    /// `[channel]`: delays, loss and range.
    pub fn channel(&mut self, ch: &ChannelSpec) {
        let ms = "milliseconds";
        self.num("channel.delay_ms", ch.delay_ms, false, 0.0, 1e6, ms);
        self.num("channel.jitter_ms", ch.jitter_ms, false, 0.0, 1e6, ms);
        self.num("channel.loss", ch.loss, false, 0.0, 1.0, "a probability");
        self.num("channel.range_m", ch.range_m, true, 0.0, 1e6, "metres");
    }

    /// `[record]`: a positive sample period.
    pub fn record(&mut self, r: &RecordSpec) {
        self.num("record.sample_s", r.sample_s, true, 0.0, 3600.0, "seconds");
    }

    /// A point of the file (town metres) against the site: in the town's extent and, when
    /// `on_ground`, outside buildings and forbidden zones (the expected value names the
    /// nearest free point). A point that is not finite is left to [`point`](Self::point).
    pub fn place(&mut self, site: &Site, path: &str, p: [f64; 2], on_ground: bool) {
        if !p.iter().all(|x| x.is_finite()) {
            return;
        }
        let [x0, y0, x1, y1] = site.map.extent;
        if !(x0..=x1).contains(&p[0]) || !(y0..=y1).contains(&p[1]) {
            let message = format!("{} {p:?} lies outside the town", self.label(path));
            let expected =
                format!("town metres with x in [{x0:.0}, {x1:.0}] and y in [{y0:.0}, {y1:.0}]");
            self.push(path, message, &expected);
            return;
        }
        if !on_ground || !site.zones.is_forbidden(p) {
            return;
        }
        let inside = site.map.buildings.iter().position(|b| {
            let [bx0, by0, bx1, by1] = b.footprint.bbox();
            (bx0..=bx1).contains(&p[0]) && (by0..=by1).contains(&p[1]) && b.footprint.contains(p)
        });
        let what = match inside {
            Some(b) => format!("inside building #{b}"),
            None => "in a forbidden zone (too close to a building or water)".to_owned(),
        };
        let free = site.zones.nearest_free(p);
        let message = format!("{} {p:?} lies {what}", self.label(path));
        let expected = format!(
            "a free point outside buildings and forbidden zones, e.g. [{:.1}, {:.1}]",
            free[0], free[1]
        );
        self.push(path, message, &expected);
    }

    /// The entities' starts against the site (on the ground for all but aircraft).
    pub fn starts(&mut self, site: &Site) {
        for (i, e) in self.entities.iter().enumerate() {
            if let Some(p) = e.start {
                self.place(site, &format!("entity.{i}.start"), p, !e.kind.is_aircraft());
            }
        }
    }
}

/// A `[site]` table's files, resolved from the scenario file's directory.
#[derive(Clone, Debug, PartialEq)]
pub struct SiteFiles {
    /// The map, absolute.
    pub map: PathBuf,
    /// The terrain, absolute.
    pub terrain: PathBuf,
}

impl SiteFiles {
    /// Resolves `spec`'s files from the directory of the scenario at `scenario`.
    pub fn resolve(scenario: &Path, spec: &SiteSpec) -> Self {
        SiteFiles {
            map: resolve(scenario, &spec.map),
            terrain: resolve(scenario, &spec.terrain),
        }
    }

    /// True when both files exist (else [`Checker::site`] has said which is missing).
    pub fn exist(&self) -> bool {
        self.map.is_file() && self.terrain.is_file()
    }

    /// Builds the town on its terrain at `spec`'s offset; a problem points at `[site]`.
    ///
    /// # Errors
    /// The map or terrain cannot be read, or the town does not fit on the terrain.
    pub fn load(&self, spec: &SiteSpec, map: &SourceMap<'_>) -> Result<Site, Box<Diagnostic>> {
        let town = TownMap::load(&self.map, &MapConfig::default()).map_err(|e| {
            Box::new(map.at(
                "site.map",
                format!("cannot load the map: {e}"),
                "an OpenStreetMap .osm.pbf file",
            ))
        })?;
        let ground = Terrain::load(&self.terrain).map_err(|e| {
            Box::new(map.at(
                "site.terrain",
                format!("cannot load the terrain: {e}"),
                "an ESRI ASCII grid (.asc) or a GeoTIFF",
            ))
        })?;
        let config = SiteConfig {
            offset: spec.offset,
            ..SiteConfig::default()
        };
        Site::new(town, ground, &config).map_err(|e| {
            let key = if spec.offset.is_some() {
                "site.offset"
            } else {
                "site.terrain"
            };
            Box::new(map.at(
                key,
                format!("cannot set the town on the terrain: {e}"),
                "an offset that keeps the whole town on the terrain",
            ))
        })
    }
}

/// `p` as named in the scenario at `scenario`: relative to its directory, made absolute.
pub fn resolve(scenario: &Path, p: &Path) -> PathBuf {
    let joined = scenario.parent().unwrap_or(Path::new("")).join(p);
    joined
        .canonicalize()
        .or_else(|_| std::path::absolute(&joined))
        .unwrap_or(joined)
}

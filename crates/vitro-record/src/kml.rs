//! KML 2.2 for Google Earth: one `gx:Track` per entity, styled by side, and the scene's named
//! places.
//!
//! Positions go through the scene's [`Geo`](crate::Geo) (latitude, longitude, altitude above
//! sea level; `altitudeMode` absolute). Times are calendar times in UTC, to the
//! millisecond: simulated time 0 is the scene's start (the scenario's `start`), so Google
//! Earth's time slider shows the mission's date. Every element is in the order the OGC KML
//! 2.2 schema (and Google's `gx` extension schema) wants: `scripts/check_kml.py` validates
//! a file against them.
//!
//! ```
//! use vitro_record::{kml, synthetic};
//! let mut scene = synthetic::scene();
//! scene.start_unix_ms = 1_717_221_600_000; // 2024-06-01T06:00:00Z
//! let frames = (0..3).map(|i| synthetic::frame(&scene, i, 2));
//! let doc = kml::export(&scene, frames);
//! assert_eq!(doc.matches("<gx:Track>").count(), 2);
//! assert!(doc.contains("<when>2024-06-01T06:00:02Z</when>"));
//! ```

use crate::draw::{side_color, side_name};
use crate::foxglove::Color;
use crate::frame::{Frame, Scene, Side};
use std::borrow::Borrow;
use std::collections::BTreeMap;
use std::io::{self, Write};

/// One entity's track.
#[derive(Clone, Debug)]
struct Track {
    name: String,
    kind: String,
    side: Side,
    /// (time, world position) per frame the entity is in.
    samples: Vec<(u64, [f64; 3])>,
}

/// Entity tracks gathered frame by frame, then written as KML.
///
/// A track's times must all come before its coordinates in a `gx:Track`, so the positions
/// are kept (32 bytes per entity and frame: 4.6 MB for 40 entities over an hour at 1 Hz).
#[derive(Clone, Debug, Default)]
pub struct Tracks {
    tracks: BTreeMap<u32, Track>,
}

impl Tracks {
    /// No tracks yet.
    pub fn new() -> Self {
        Self::default()
    }

    /// Adds one frame's entity positions.
    pub fn add(&mut self, frame: &Frame) {
        for e in &frame.entities {
            let track = self.tracks.entry(e.id).or_insert_with(|| Track {
                name: e.name.clone(),
                kind: e.kind.clone(),
                side: e.side,
                samples: Vec::new(),
            });
            // The latest name and side win (an unknown contact may be identified later).
            if track.name != e.name {
                track.name.clone_from(&e.name);
            }
            track.side = e.side;
            track.samples.push((frame.t_ns, e.pos));
        }
    }

    /// Number of tracks (entities seen).
    pub fn len(&self) -> usize {
        self.tracks.len()
    }

    /// Whether no entity was seen.
    pub fn is_empty(&self) -> bool {
        self.tracks.is_empty()
    }

    /// Writes the KML document: styles, the scene's places, then the tracks.
    pub fn write<W: Write>(&self, scene: &Scene, mut out: W) -> io::Result<()> {
        writeln!(out, r#"<?xml version="1.0" encoding="UTF-8"?>"#)?;
        writeln!(
            out,
            r#"<kml xmlns="http://www.opengis.net/kml/2.2" xmlns:gx="http://www.google.com/kml/ext/2.2">"#
        )?;
        writeln!(out, "<Document>")?;
        writeln!(out, "<name>{}</name>", escape(&scene.name))?;
        let styles = [Side::Friendly, Side::Hostile, Side::Neutral, Side::Unknown]
            .map(|s| (side_name(s), side_color(s)));
        for (id, color) in styles
            .into_iter()
            .chain([("place", Color::rgb(1.0, 0.8, 0.1))])
        {
            let c = kml_color(color);
            writeln!(
                out,
                "<Style id=\"{id}\"><IconStyle><color>{c}</color><scale>0.8</scale></IconStyle>\
                 <LabelStyle><scale>0.8</scale></LabelStyle>\
                 <LineStyle><color>{c}</color><width>2</width></LineStyle></Style>"
            )?;
        }
        writeln!(out, "<Folder><name>Places</name>")?;
        for (name, &p) in &scene.places {
            let [lat, lon, alt] = scene.geo.to_wgs84(p);
            writeln!(
                out,
                "<Placemark><name>{}</name><styleUrl>#place</styleUrl><Point>\
                 <altitudeMode>absolute</altitudeMode>\
                 <coordinates>{lon:.7},{lat:.7},{alt:.2}</coordinates></Point></Placemark>",
                escape(name)
            )?;
        }
        writeln!(out, "</Folder>")?;
        writeln!(out, "<Folder><name>Entities</name>")?;
        for track in self.tracks.values() {
            writeln!(
                out,
                "<Placemark><name>{}</name><description>{}, {}</description>\
                 <styleUrl>#{}</styleUrl>",
                escape(&track.name),
                escape(&track.kind),
                side_name(track.side),
                side_name(track.side)
            )?;
            writeln!(out, "<gx:Track><altitudeMode>absolute</altitudeMode>")?;
            for &(t, _) in &track.samples {
                writeln!(out, "<when>{}</when>", utc_time(scene.start_unix_ms, t))?;
            }
            for &(_, p) in &track.samples {
                let [lat, lon, alt] = scene.geo.to_wgs84(p);
                writeln!(out, "<gx:coord>{lon:.7} {lat:.7} {alt:.2}</gx:coord>")?;
            }
            writeln!(out, "</gx:Track></Placemark>")?;
        }
        writeln!(out, "</Folder>")?;
        writeln!(out, "</Document>")?;
        writeln!(out, "</kml>")?;
        Ok(())
    }
}

/// The KML document of `scene` and `frames`: one track per entity, the scene's places.
pub fn export<F: Borrow<Frame>>(scene: &Scene, frames: impl IntoIterator<Item = F>) -> String {
    let mut tracks = Tracks::new();
    for f in frames {
        tracks.add(f.borrow());
    }
    let mut out = Vec::new();
    // Writing to a Vec cannot fail, and everything written is UTF-8.
    let _ = tracks.write(scene, &mut out);
    String::from_utf8_lossy(&out).into_owned()
}

/// A KML colour: `aabbggrr` in hex.
fn kml_color(c: Color) -> String {
    // Clamped to [0, 255] before the cast.
    let b = |x: f64| (x.clamp(0.0, 1.0) * 255.0).round() as u8;
    format!("{:02x}{:02x}{:02x}{:02x}", b(c.a), b(c.b), b(c.g), b(c.r))
}

/// Text made safe inside an XML element.
fn escape(s: &str) -> String {
    let mut out = String::with_capacity(s.len());
    for c in s.chars() {
        match c {
            '&' => out.push_str("&amp;"),
            '<' => out.push_str("&lt;"),
            '>' => out.push_str("&gt;"),
            '"' => out.push_str("&quot;"),
            '\'' => out.push_str("&apos;"),
            // Control characters other than tab and newlines are not allowed in XML 1.0.
            c if c.is_control() && !matches!(c, '\t' | '\n' | '\r') => out.push(' '),
            c => out.push(c),
        }
    }
    out
}

/// Simulated nanoseconds `t_ns` after the start (milliseconds since the Unix epoch) as an
/// ISO 8601 (RFC 3339) UTC time, to the millisecond.
pub(crate) fn utc_time(start_unix_ms: i64, t_ns: u64) -> String {
    vitro::time::UtcTime::from_unix_millis(start_unix_ms)
        .plus_nanos(t_ns)
        .to_string()
}

#[cfg(test)]
mod tests {
    use super::*;

    fn iso_time(t_ns: u64) -> String {
        utc_time(0, t_ns)
    }

    #[test]
    fn times_are_iso_8601_calendar_times() {
        assert_eq!(iso_time(0), "1970-01-01T00:00:00Z");
        assert_eq!(iso_time(86_400_500_000_000), "1970-01-02T00:00:00.500Z");
        assert_eq!(iso_time(3_723_000_000_000), "1970-01-01T01:02:03Z");
        // 2000-02-29 (a leap day in a century year) and 2024-12-31.
        assert_eq!(
            iso_time(951_782_400 * 1_000_000_000),
            "2000-02-29T00:00:00Z"
        );
        assert_eq!(
            iso_time(1_735_603_200 * 1_000_000_000),
            "2024-12-31T00:00:00Z"
        );
        // From a start: 2024-06-01T06:00:00Z plus 90.25 s; a start before 1970.
        assert_eq!(
            utc_time(1_717_221_600_000, 90_250_000_000),
            "2024-06-01T06:01:30.250Z"
        );
        assert_eq!(utc_time(-1000, 0), "1969-12-31T23:59:59Z");
    }

    #[test]
    fn styles_follow_the_schema_order() {
        let doc = export(&crate::synthetic::scene(), std::iter::empty::<Frame>());
        let style = &doc[doc.find("<Style ").expect("a style")..];
        let at = |e: &str| style.find(e).expect(e);
        assert!(at("<IconStyle>") < at("<LabelStyle>"));
        assert!(at("<LabelStyle>") < at("<LineStyle>"));
    }

    #[test]
    fn colours_are_alpha_blue_green_red() {
        assert_eq!(kml_color(Color::rgb(1.0, 0.0, 0.0)), "ff0000ff");
        assert_eq!(kml_color(Color::rgb(0.0, 0.0, 1.0).alpha(0.5)), "80ff0000");
    }

    #[test]
    fn names_are_escaped() {
        assert_eq!(escape("a<b & 'c'\u{1}"), "a&lt;b &amp; &apos;c&apos; ");
    }
}

//! The channels of a run, as a recording writes them and a live Foxglove server serves them.
//!
//! One definition for both: [`Channel`] names each channel (topic and schema), and
//! [`scene_messages`] and [`frame_messages`] encode what a scene and a frame put on them, as
//! JSON, through a caller's `put` (the [`Recorder`](crate::Recorder) writes MCAP messages,
//! a live server sends WebSocket messages). Times are simulated nanoseconds.

use crate::draw;
use crate::foxglove::SceneUpdate;
use crate::frame::{EntityState, Frame, Geo, Scene};
use crate::schema;
use serde::Serialize;
use std::borrow::Cow;
use std::collections::BTreeMap;

/// Topic names of a recording.
pub mod topic {
    /// The lossless [`Scene`](crate::Scene).
    pub const SCENE: &str = "/vitro/scene";
    /// The lossless [`Frame`](crate::Frame)s.
    pub const FRAME: &str = "/vitro/frame";
    /// The static map (`foxglove.SceneUpdate`).
    pub const MAP: &str = "/map";
    /// Entities (`foxglove.SceneUpdate`).
    pub const ENTITIES: &str = "/entities";
    /// Detections (`foxglove.SceneUpdate`).
    pub const DETECTIONS: &str = "/detections";
    /// Intentions and paths (`foxglove.SceneUpdate`).
    pub const INTENTIONS: &str = "/intentions";
    /// Sensor footprints (`foxglove.SceneUpdate`).
    pub const SENSORS: &str = "/sensors";
    /// Entity poses (`foxglove.FrameTransforms`).
    pub const TF: &str = "/tf";
    /// Messages and log lines (`foxglove.Log`).
    pub const LOG: &str = "/log";
    /// Metrics (`vitro.Metrics`).
    pub const METRICS: &str = "/metrics";
    /// Prefix of the per-entity GNSS channels (`foxglove.LocationFix`): `/gps/NAME`.
    pub const GPS_PREFIX: &str = "/gps/";
}

/// One channel of a run.
#[derive(Clone, Debug, PartialEq, Eq, PartialOrd, Ord, Hash)]
pub enum Channel {
    /// `/vitro/scene`: the lossless scene, once.
    Scene,
    /// `/vitro/frame`: each lossless frame.
    Frame,
    /// `/map`: terrain, streets, buildings, zones and places, once.
    Map,
    /// `/entities`: a body, heading arrow and label per entity.
    Entities,
    /// `/detections`: lines from observers to what they see.
    Detections,
    /// `/intentions`: each agent's path and intention.
    Intentions,
    /// `/sensors`: sensor footprints.
    Sensors,
    /// `/tf`: world → each entity.
    Tf,
    /// `/log`: messages sent and the mission's log lines.
    Log,
    /// `/metrics`: `events` and the mission metrics, by name.
    Metrics,
    /// `/gps/NAME`: one entity's GNSS fixes, named by its [`gps_topic`].
    Gps {
        /// The entity's id.
        id: u32,
        /// Its topic.
        topic: String,
    },
}

impl Channel {
    /// The channels that exist from the start, in the order a recording adds them (the
    /// `/gps/NAME` channels come as their entities first appear).
    pub const FIXED: [Channel; 10] = [
        Channel::Scene,
        Channel::Frame,
        Channel::Map,
        Channel::Entities,
        Channel::Detections,
        Channel::Intentions,
        Channel::Sensors,
        Channel::Tf,
        Channel::Log,
        Channel::Metrics,
    ];

    /// The GNSS channel of entity `e`.
    pub fn gps(e: &EntityState) -> Self {
        Channel::Gps {
            id: e.id,
            topic: gps_topic(&e.name),
        }
    }

    /// The topic name.
    pub fn topic(&self) -> Cow<'_, str> {
        Cow::Borrowed(match self {
            Channel::Scene => topic::SCENE,
            Channel::Frame => topic::FRAME,
            Channel::Map => topic::MAP,
            Channel::Entities => topic::ENTITIES,
            Channel::Detections => topic::DETECTIONS,
            Channel::Intentions => topic::INTENTIONS,
            Channel::Sensors => topic::SENSORS,
            Channel::Tf => topic::TF,
            Channel::Log => topic::LOG,
            Channel::Metrics => topic::METRICS,
            Channel::Gps { topic, .. } => return Cow::Borrowed(topic),
        })
    }

    /// The schema name (its text is [`schema::schema_text`]).
    pub fn schema(&self) -> &'static str {
        match self {
            Channel::Scene => schema::VITRO_SCENE,
            Channel::Frame => schema::VITRO_FRAME,
            Channel::Map
            | Channel::Entities
            | Channel::Detections
            | Channel::Intentions
            | Channel::Sensors => schema::SCENE_UPDATE,
            Channel::Tf => schema::FRAME_TRANSFORMS,
            Channel::Log => schema::LOG,
            Channel::Metrics => schema::VITRO_METRICS,
            Channel::Gps { .. } => schema::LOCATION_FIX,
        }
    }

    /// True for the lossless `/vitro/*` channels (the others are drawn for Foxglove).
    pub fn is_lossless(&self) -> bool {
        matches!(self, Channel::Scene | Channel::Frame)
    }

    /// True for the channels written once, from the scene (`/vitro/scene`, `/map`).
    pub fn is_static(&self) -> bool {
        matches!(self, Channel::Scene | Channel::Map)
    }
}

/// The topic of an entity's GNSS channel: `/gps/` and its name made safe (letters, digits,
/// `_`, `-` and `.` kept, the rest `_`).
pub fn gps_topic(name: &str) -> String {
    let safe: String = name
        .chars()
        .map(|c| {
            if c.is_ascii_alphanumeric() || matches!(c, '_' | '-' | '.') {
                c
            } else {
                '_'
            }
        })
        .collect();
    let safe = if safe.is_empty() { "_" } else { &safe };
    format!("{}{safe}", topic::GPS_PREFIX)
}

/// How a frame's scene update is drawn.
type DrawFn = fn(&Frame) -> SceneUpdate;

/// Encodes `value` as JSON into `buf` and hands it to `put`.
fn emit<E: From<serde_json::Error>>(
    buf: &mut Vec<u8>,
    channel: &Channel,
    t_ns: u64,
    value: &impl Serialize,
    put: &mut impl FnMut(&Channel, u64, &[u8]) -> Result<(), E>,
) -> Result<(), E> {
    buf.clear();
    serde_json::to_writer(&mut *buf, value)?;
    put(channel, t_ns, buf)
}

/// Encodes the messages of `scene` (at t = 0) on the static channels `wants` picks, into
/// `buf`, handing each to `put` (`/vitro/scene`, then `/map`).
pub fn scene_messages<E: From<serde_json::Error>>(
    scene: &Scene,
    wants: impl Fn(&Channel) -> bool,
    buf: &mut Vec<u8>,
    mut put: impl FnMut(&Channel, u64, &[u8]) -> Result<(), E>,
) -> Result<(), E> {
    if wants(&Channel::Scene) {
        emit(buf, &Channel::Scene, 0, scene, &mut put)?;
    }
    if wants(&Channel::Map) {
        emit(buf, &Channel::Map, 0, &draw::map_update(scene), &mut put)?;
    }
    Ok(())
}

/// Encodes the messages of `frame` on the channels `wants` picks, into `buf`, handing each
/// to `put` in a fixed order: `/vitro/frame`, the scene updates, `/tf`, a `/gps/NAME` per
/// entity, the `/log` lines (each at its own time), `/metrics`.
pub fn frame_messages<E: From<serde_json::Error>>(
    geo: &Geo,
    frame: &Frame,
    wants: impl Fn(&Channel) -> bool,
    buf: &mut Vec<u8>,
    mut put: impl FnMut(&Channel, u64, &[u8]) -> Result<(), E>,
) -> Result<(), E> {
    let t = frame.t_ns;
    let put = &mut put;
    if wants(&Channel::Frame) {
        emit(buf, &Channel::Frame, t, frame, put)?;
    }
    let updates: [(Channel, DrawFn); 4] = [
        (Channel::Entities, draw::entities_update),
        (Channel::Detections, draw::detections_update),
        (Channel::Intentions, draw::intentions_update),
        (Channel::Sensors, draw::sensors_update),
    ];
    for (channel, draw) in updates {
        if wants(&channel) {
            emit(buf, &channel, t, &draw(frame), put)?;
        }
    }
    if wants(&Channel::Tf) {
        emit(buf, &Channel::Tf, t, &draw::transforms(frame), put)?;
    }
    for e in &frame.entities {
        let channel = Channel::gps(e);
        if wants(&channel) {
            emit(buf, &channel, t, &draw::location_fix(geo, t, e), put)?;
        }
    }
    if wants(&Channel::Log) {
        for (at, line) in draw::logs(frame) {
            emit(buf, &Channel::Log, at, &line, put)?;
        }
    }
    if wants(&Channel::Metrics) {
        let mut values: BTreeMap<&str, f64> = BTreeMap::new();
        values.insert("events", frame.events as f64);
        values.extend(frame.metrics.iter().map(|(k, &v)| (k.as_str(), v)));
        emit(buf, &Channel::Metrics, t, &values, put)?;
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::synthetic;

    #[test]
    fn topics_keep_safe_names_only() {
        assert_eq!(gps_topic("blue-1"), "/gps/blue-1");
        assert_eq!(gps_topic("red 2/ä"), "/gps/red_2__");
        assert_eq!(gps_topic(""), "/gps/_");
    }

    #[test]
    fn every_channel_has_a_schema_text() {
        let scene = synthetic::scene();
        let frame = synthetic::frame(&scene, 1, 3);
        let mut seen = Vec::new();
        let mut buf = Vec::new();
        let mut put = |c: &Channel, _t: u64, json: &[u8]| -> Result<(), serde_json::Error> {
            serde_json::from_slice::<serde_json::Value>(json)?;
            seen.push(c.clone());
            Ok(())
        };
        scene_messages(&scene, |_| true, &mut buf, &mut put).unwrap();
        frame_messages(&scene.geo, &frame, |_| true, &mut buf, &mut put).unwrap();
        for c in &seen {
            assert!(schema::schema_text(c.schema()).is_some(), "{c:?}");
        }
        for c in Channel::FIXED.iter().filter(|c| **c != Channel::Log) {
            assert!(seen.contains(c), "{c:?}");
        }
        assert_eq!(
            seen.iter()
                .filter(|c| c.topic().starts_with("/gps/"))
                .count(),
            3
        );
    }
}

//! Writing a run to MCAP, frame by frame.
//!
//! A recording holds two kinds of channel (all JSON, schemas in [`crate::schema`]):
//!
//! | topic | schema | messages |
//! |---|---|---|
//! | `/vitro/scene` | `vitro.Scene` | the [`Scene`], once, at t = 0 |
//! | `/vitro/frame` | `vitro.Frame` | each [`Frame`], whole |
//! | `/map` | `foxglove.SceneUpdate` | terrain, streets, buildings, zones, places, once |
//! | `/entities` | `foxglove.SceneUpdate` | a body, heading arrow and label per entity |
//! | `/detections` | `foxglove.SceneUpdate` | lines from observers to what they see |
//! | `/intentions` | `foxglove.SceneUpdate` | each agent's path (and original path) and intention |
//! | `/sensors` | `foxglove.SceneUpdate` | sensor footprints (sector outlines) |
//! | `/tf` | `foxglove.FrameTransforms` | world → each entity (frame named after it) |
//! | `/gps/NAME` | `foxglove.LocationFix` | one channel per entity, for the Map panel |
//! | `/log` | `foxglove.Log` | messages sent (at their send time) and the frame's log lines |
//! | `/metrics` | `vitro.Metrics` | `events` and the mission metrics, by name (Plot panel) |
//!
//! The two `/vitro/*` channels are lossless: [`crate::Replay`] reads back exactly what was
//! written. The others are for Foxglove (coordinates rounded to the millimetre) and can be
//! left out ([`RecordOptions::foxglove`]). Log and publish times are simulated nanoseconds
//! since the start of the run (MCAP leaves the epoch to the writer; [`crate::Replay`] seeks
//! by them): the calendar time of t = 0, the scenario's `start`, is the `start` entry of
//! the `vitro` metadata record (RFC 3339, UTC) and the scene's `start_unix_ms`.
//!
//! # Streaming, and a run killed midway
//!
//! Nothing is kept per frame: each frame is encoded into the open MCAP chunk, and a chunk is
//! compressed and written out whole when it reaches [`RecordOptions::chunk_bytes`]
//! (uncompressed). The scene is written in a chunk of its own, closed at once.
//! [`Recorder::finish`] closes the last chunk and writes MCAP's summary (indexes, statistics)
//! and footer. Dropping a `Recorder` without `finish` also finishes the file (ignoring errors).
//! A process *killed* midway (no destructor runs) leaves the header, the scene and every closed
//! chunk, then a partial chunk and no summary: [`crate::Replay::open`] recovers the frames of
//! the closed chunks (those of the open chunk, at most `chunk_bytes` of messages, are lost),
//! and `mcap recover` (the MCAP CLI) rewrites such a file with its summary. Call
//! [`Recorder::flush`] to close the chunk early at a point that must survive.

use crate::draw;
pub use crate::error::RecordError;
use crate::frame::{Frame, Geo, Scene};
use crate::schema;
use mcap::records::{MessageHeader, Metadata};
use serde::Serialize;
use std::collections::BTreeMap;
use std::fs::File;
use std::io::{BufWriter, Seek, Write};
use std::path::Path;

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

/// How a recording is written.
#[derive(Clone, Debug, PartialEq)]
pub struct RecordOptions {
    /// Write the Foxglove channels besides the lossless `/vitro/*` ones (default: yes).
    pub foxglove: bool,
    /// Target uncompressed size of an MCAP chunk, bytes (default 1 MiB): larger compresses
    /// better, smaller loses less when the process is killed.
    pub chunk_bytes: u64,
    /// Compress chunks with zstd (default: yes).
    pub compress: bool,
}

impl Default for RecordOptions {
    fn default() -> Self {
        Self {
            foxglove: true,
            chunk_bytes: 1 << 20,
            compress: true,
        }
    }
}

/// Counts of what a [`Recorder`] has written so far.
#[derive(Copy, Clone, Debug, Default, PartialEq, Eq)]
pub struct RecordStats {
    /// Frames recorded.
    pub frames: u64,
    /// MCAP messages written, every channel.
    pub messages: u64,
    /// Bytes of message payload before compression.
    pub payload_bytes: u64,
}

/// Channel ids of an open recording.
#[derive(Debug)]
struct Channels {
    frame: u16,
    foxglove: Option<FoxgloveChannels>,
}

#[derive(Debug)]
struct FoxgloveChannels {
    entities: u16,
    detections: u16,
    intentions: u16,
    sensors: u16,
    tf: u16,
    log: u16,
    metrics: u16,
    location_schema: u16,
    /// Entity id → its `/gps/NAME` channel, added when the entity first appears.
    gps: BTreeMap<u32, u16>,
}

/// Writes a run to an MCAP file: the scene once, then a frame at a time.
///
/// ```
/// use vitro_record::{synthetic, Recorder, Replay};
/// let path = std::env::temp_dir().join(format!("doc-{}.mcap", std::process::id()));
/// let scene = synthetic::scene();
/// let mut rec = Recorder::create(&path, &scene)?;
/// for i in 0..3 {
///     rec.frame(&synthetic::frame(&scene, i, 4))?;
/// }
/// rec.finish()?;
/// let replay = Replay::open(&path)?;
/// assert_eq!(replay.len(), 3);
/// # std::fs::remove_file(&path)?;
/// # Ok::<(), Box<dyn std::error::Error>>(())
/// ```
pub struct Recorder<W: Write + Seek> {
    mcap: mcap::Writer<W>,
    channels: Channels,
    geo: Geo,
    last_t: Option<u64>,
    sequence: u32,
    stats: RecordStats,
    buf: Vec<u8>,
}

impl Recorder<BufWriter<File>> {
    /// Creates the file `path` and writes `scene` to it, with the default options.
    pub fn create(path: impl AsRef<Path>, scene: &Scene) -> Result<Self, RecordError> {
        Self::create_with(path, scene, &RecordOptions::default())
    }

    /// Creates the file `path` and writes `scene` to it.
    pub fn create_with(
        path: impl AsRef<Path>,
        scene: &Scene,
        options: &RecordOptions,
    ) -> Result<Self, RecordError> {
        let path = path.as_ref();
        let file = File::create(path).map_err(|source| RecordError::Create {
            path: path.to_owned(),
            source,
        })?;
        Self::new(BufWriter::new(file), scene, options)
    }
}

impl<W: Write + Seek> Recorder<W> {
    /// Starts a recording on `out` and writes `scene` (and the Foxglove map) at t = 0.
    pub fn new(out: W, scene: &Scene, options: &RecordOptions) -> Result<Self, RecordError> {
        crate::finite::check_scene(scene)?;
        let mcap_options = mcap::WriteOptions::new()
            .compression(options.compress.then_some(mcap::Compression::Zstd))
            .chunk_size(Some(options.chunk_bytes.max(1)))
            .compression_threads(0)
            .library(format!("vitro-record {}", env!("CARGO_PKG_VERSION")));
        let mut mcap = mcap_options.create(out)?;
        let mut add = |topic: &str, schema_name: &str| -> Result<u16, RecordError> {
            let text = schema::schema_text(schema_name).unwrap_or_default();
            let schema = mcap.add_schema(schema_name, "jsonschema", text.as_bytes())?;
            Ok(mcap.add_channel(schema, topic, "json", &BTreeMap::new())?)
        };
        let scene_channel = add(topic::SCENE, schema::VITRO_SCENE)?;
        let frame = add(topic::FRAME, schema::VITRO_FRAME)?;
        let (map, foxglove) = if options.foxglove {
            let map = add(topic::MAP, schema::SCENE_UPDATE)?;
            let channels = FoxgloveChannels {
                entities: add(topic::ENTITIES, schema::SCENE_UPDATE)?,
                detections: add(topic::DETECTIONS, schema::SCENE_UPDATE)?,
                intentions: add(topic::INTENTIONS, schema::SCENE_UPDATE)?,
                sensors: add(topic::SENSORS, schema::SCENE_UPDATE)?,
                tf: add(topic::TF, schema::FRAME_TRANSFORMS)?,
                log: add(topic::LOG, schema::LOG)?,
                metrics: add(topic::METRICS, schema::VITRO_METRICS)?,
                location_schema: {
                    let text = schema::schema_text(schema::LOCATION_FIX).unwrap_or_default();
                    mcap.add_schema(schema::LOCATION_FIX, "jsonschema", text.as_bytes())?
                },
                gps: BTreeMap::new(),
            };
            (Some(map), Some(channels))
        } else {
            (None, None)
        };
        mcap.write_metadata(&Metadata {
            name: "vitro".to_owned(),
            metadata: BTreeMap::from([
                ("scene".to_owned(), scene.name.clone()),
                (
                    "start".to_owned(),
                    crate::kml::utc_time(scene.start_unix_ms, 0),
                ),
                (
                    "writer".to_owned(),
                    format!("vitro-record {}", env!("CARGO_PKG_VERSION")),
                ),
            ]),
        })?;
        let mut rec = Self {
            mcap,
            channels: Channels { frame, foxglove },
            geo: scene.geo,
            last_t: None,
            sequence: 0,
            stats: RecordStats::default(),
            buf: Vec::with_capacity(64 << 10),
        };
        rec.put(scene_channel, 0, scene)?;
        if let Some(map) = map {
            rec.put(map, 0, &draw::map_update(scene))?;
        }
        // The scene in a closed chunk of its own: a run killed at any point keeps it.
        rec.mcap.flush()?;
        Ok(rec)
    }

    /// Encodes `value` as JSON and writes it on `channel` at simulated time `t_ns`.
    fn put(&mut self, channel: u16, t_ns: u64, value: &impl Serialize) -> Result<(), RecordError> {
        self.buf.clear();
        serde_json::to_writer(&mut self.buf, value)?;
        self.sequence = self.sequence.wrapping_add(1);
        let header = MessageHeader {
            channel_id: channel,
            sequence: self.sequence,
            log_time: t_ns,
            publish_time: t_ns,
        };
        self.mcap.write_to_known_channel(&header, &self.buf)?;
        self.stats.messages += 1;
        self.stats.payload_bytes += self.buf.len() as u64;
        Ok(())
    }

    /// Records one frame. Frames come in time order; a rejected frame writes nothing.
    pub fn frame(&mut self, frame: &Frame) -> Result<(), RecordError> {
        if let Some(last_ns) = self.last_t.filter(|&last| frame.t_ns < last) {
            return Err(RecordError::TimeWentBack {
                t_ns: frame.t_ns,
                last_ns,
            });
        }
        crate::finite::check_frame(frame)?;
        let t = frame.t_ns;
        self.put(self.channels.frame, t, frame)?;
        if self.channels.foxglove.is_some() {
            self.foxglove(frame)?;
        }
        self.last_t = Some(t);
        self.stats.frames += 1;
        Ok(())
    }

    /// Writes a frame's Foxglove channels.
    fn foxglove(&mut self, frame: &Frame) -> Result<(), RecordError> {
        let Some(fx) = self.channels.foxglove.as_mut() else {
            return Ok(());
        };
        for e in &frame.entities {
            if !fx.gps.contains_key(&e.id) {
                let topic = format!("{}{}", topic::GPS_PREFIX, topic_safe(&e.name));
                let id =
                    self.mcap
                        .add_channel(fx.location_schema, &topic, "json", &BTreeMap::new())?;
                fx.gps.insert(e.id, id);
            }
        }
        let (entities, detections, intentions, sensors) =
            (fx.entities, fx.detections, fx.intentions, fx.sensors);
        let (tf, log, metrics) = (fx.tf, fx.log, fx.metrics);
        let gps: Vec<u16> = frame.entities.iter().map(|e| fx.gps[&e.id]).collect();
        let t = frame.t_ns;
        self.put(entities, t, &draw::entities_update(frame))?;
        self.put(detections, t, &draw::detections_update(frame))?;
        self.put(intentions, t, &draw::intentions_update(frame))?;
        self.put(sensors, t, &draw::sensors_update(frame))?;
        self.put(tf, t, &draw::transforms(frame))?;
        for (e, channel) in frame.entities.iter().zip(gps) {
            let fix = draw::location_fix(&self.geo, t, e);
            self.put(channel, t, &fix)?;
        }
        for (at, line) in draw::logs(frame) {
            self.put(log, at, &line)?;
        }
        let mut values: BTreeMap<&str, f64> = BTreeMap::new();
        values.insert("events", frame.events as f64);
        values.extend(frame.metrics.iter().map(|(k, &v)| (k.as_str(), v)));
        self.put(metrics, t, &values)
    }

    /// Closes the open chunk and flushes the output: what was recorded so far survives a kill.
    pub fn flush(&mut self) -> Result<(), RecordError> {
        Ok(self.mcap.flush()?)
    }

    /// What has been written so far.
    pub fn stats(&self) -> RecordStats {
        self.stats
    }

    /// Closes the last chunk, writes the summary and footer, flushes, and gives the output back.
    pub fn finish(self) -> Result<W, RecordError> {
        let Self { mut mcap, .. } = self;
        mcap.finish()?;
        let mut out = mcap.into_inner();
        out.flush()?;
        Ok(out)
    }
}

/// A name made safe for a topic: letters, digits, `_`, `-` and `.` kept, the rest `_`.
fn topic_safe(name: &str) -> String {
    let s: String = name
        .chars()
        .map(|c| {
            if c.is_ascii_alphanumeric() || matches!(c, '_' | '-' | '.') {
                c
            } else {
                '_'
            }
        })
        .collect();
    if s.is_empty() { "_".to_owned() } else { s }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::synthetic;
    use std::io::Cursor;

    #[test]
    fn topics_keep_safe_names_only() {
        assert_eq!(topic_safe("blue-1"), "blue-1");
        assert_eq!(topic_safe("red 2/ä"), "red_2__");
        assert_eq!(topic_safe(""), "_");
    }

    #[test]
    fn frames_out_of_order_or_not_finite_are_rejected_and_write_nothing() {
        let scene = synthetic::scene();
        let mut rec =
            Recorder::new(Cursor::new(Vec::new()), &scene, &RecordOptions::default()).unwrap();
        rec.frame(&synthetic::frame(&scene, 5, 3)).unwrap();
        let before = rec.stats();
        let err = rec.frame(&synthetic::frame(&scene, 4, 3)).unwrap_err();
        assert!(matches!(err, RecordError::TimeWentBack { .. }), "{err}");
        let mut bad = synthetic::frame(&scene, 6, 3);
        bad.metrics.insert("time_to_extraction_s".into(), f64::NAN);
        let err = rec.frame(&bad).unwrap_err();
        assert!(err.to_string().contains("time_to_extraction_s"), "{err}");
        assert_eq!(rec.stats(), before);
        // Equal times are fine.
        rec.frame(&synthetic::frame(&scene, 5, 3)).unwrap();
        assert_eq!(rec.stats().frames, 2);
    }

    #[test]
    fn without_foxglove_only_the_vitro_channels_are_written() {
        let scene = synthetic::scene();
        let options = RecordOptions {
            foxglove: false,
            ..RecordOptions::default()
        };
        let mut rec = Recorder::new(Cursor::new(Vec::new()), &scene, &options).unwrap();
        for i in 0..4 {
            rec.frame(&synthetic::frame(&scene, i, 5)).unwrap();
        }
        // The scene and one message per frame.
        assert_eq!(rec.stats().messages, 5);
        let bytes = rec.finish().unwrap().into_inner();
        let summary = mcap::Summary::read(&bytes).unwrap().unwrap();
        let mut topics: Vec<&str> = summary
            .channels
            .values()
            .map(|c| c.topic.as_str())
            .collect();
        topics.sort();
        assert_eq!(topics, [topic::FRAME, topic::SCENE]);
    }
}

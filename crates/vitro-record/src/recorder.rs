//! Writing a run to MCAP, frame by frame.
//!
//! A recording holds two kinds of channel (all JSON, schemas in [`crate::schema`]; the
//! channels and their messages are [`crate::channels`]'s, which a live Foxglove server shares):
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

pub use crate::channels::topic;
use crate::channels::{Channel, frame_messages, scene_messages};
pub use crate::error::RecordError;
use crate::frame::{Frame, Geo, Scene};
use crate::schema;
use mcap::records::{MessageHeader, Metadata};
use std::collections::BTreeMap;
use std::fs::File;
use std::io::{BufWriter, Seek, Write};
use std::path::Path;

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

/// MCAP channel ids of an open recording, by channel (a `/gps/NAME` added when its entity
/// first appears).
#[derive(Debug, Default)]
struct Channels {
    ids: BTreeMap<Channel, u16>,
    /// The `foxglove.LocationFix` schema, for the `/gps/NAME` channels.
    location_schema: u16,
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
    foxglove: bool,
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
        let mut channels = Channels::default();
        for channel in Channel::FIXED {
            if !(options.foxglove || channel.is_lossless()) {
                continue;
            }
            let id = add_channel(&mut mcap, &channel)?;
            channels.ids.insert(channel, id);
        }
        if options.foxglove {
            let text = schema::schema_text(schema::LOCATION_FIX).unwrap_or_default();
            channels.location_schema =
                mcap.add_schema(schema::LOCATION_FIX, "jsonschema", text.as_bytes())?;
        }
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
            channels,
            foxglove: options.foxglove,
            geo: scene.geo,
            last_t: None,
            sequence: 0,
            stats: RecordStats::default(),
            buf: Vec::with_capacity(64 << 10),
        };
        let Self {
            mcap,
            channels,
            sequence,
            stats,
            buf,
            ..
        } = &mut rec;
        scene_messages(
            scene,
            |c| channels.ids.contains_key(c),
            buf,
            |c, t, json| {
                let id = channels.ids[c];
                put(mcap, sequence, stats, id, t, json)
            },
        )?;
        // The scene in a closed chunk of its own: a run killed at any point keeps it.
        rec.mcap.flush()?;
        Ok(rec)
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
        let Self {
            mcap,
            channels,
            foxglove,
            geo,
            sequence,
            stats,
            buf,
            ..
        } = self;
        let foxglove = *foxglove;
        frame_messages(
            geo,
            frame,
            |c| foxglove || c.is_lossless(),
            buf,
            |c, t, json| {
                let id = match channels.ids.get(c) {
                    Some(&id) => id,
                    None => {
                        let id = mcap.add_channel(
                            channels.location_schema,
                            &c.topic(),
                            "json",
                            &BTreeMap::new(),
                        )?;
                        channels.ids.insert(c.clone(), id);
                        id
                    }
                };
                put(mcap, sequence, stats, id, t, json)
            },
        )?;
        self.last_t = Some(frame.t_ns);
        self.stats.frames += 1;
        Ok(())
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

/// Adds `channel` (and its schema) to a recording.
fn add_channel<W: Write + Seek>(
    mcap: &mut mcap::Writer<W>,
    channel: &Channel,
) -> Result<u16, RecordError> {
    let name = channel.schema();
    let text = schema::schema_text(name).unwrap_or_default();
    let schema = mcap.add_schema(name, "jsonschema", text.as_bytes())?;
    Ok(mcap.add_channel(schema, &channel.topic(), "json", &BTreeMap::new())?)
}

/// Writes one JSON message on MCAP channel `id` at simulated time `t_ns`.
fn put<W: Write + Seek>(
    mcap: &mut mcap::Writer<W>,
    sequence: &mut u32,
    stats: &mut RecordStats,
    id: u16,
    t_ns: u64,
    json: &[u8],
) -> Result<(), RecordError> {
    *sequence = sequence.wrapping_add(1);
    let header = MessageHeader {
        channel_id: id,
        sequence: *sequence,
        log_time: t_ns,
        publish_time: t_ns,
    };
    mcap.write_to_known_channel(&header, json)?;
    stats.messages += 1;
    stats.payload_bytes += json.len() as u64;
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::synthetic;
    use std::io::Cursor;

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

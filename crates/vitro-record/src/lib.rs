//! # vitro-record: what a run shows, recorded and replayed
//!
//! The plain-data vocabulary shared by the mission (which produces it), the recorder (which
//! writes it to MCAP with Foxglove schemas), the KML exporter and the viewer (which streams it
//! live or replays it): a static [`Scene`] (map layers, terrain, geo-reference) and a
//! [`Frame`] per sample time (entities with poses, detections, messages, intentions,
//! metrics). Nothing here depends on the simulator, so a viewer or a converter builds without
//! physics or maps.
//!
//! - [`Recorder`] writes a run to MCAP frame by frame: lossless `/vitro/scene` and
//!   `/vitro/frame` channels, and Foxglove channels (3D scene, transforms, GNSS fixes for the
//!   Map panel, logs, metrics) that Foxglove Studio opens as they are ([`recorder`] lists them).
//! - [`channels`] defines those channels and encodes a scene's and a frame's messages for
//!   them, for the recorder and for a live Foxglove server alike.
//! - [`Replay`] reads a recording back: the scene, the frame count and time range, any frame
//!   by index or simulated time.
//! - [`kml`] writes entity tracks for Google Earth.
//! - [`synthetic`] makes a scene and frames for tests, examples and benchmarks.
//!
//! ```
//! use vitro_record::{synthetic, kml, Recorder, Replay};
//! let path = std::env::temp_dir().join(format!("vitro-lib-doc-{}.mcap", std::process::id()));
//! let scene = synthetic::scene();
//! let mut rec = Recorder::create(&path, &scene)?;
//! for i in 0..60 {
//!     rec.frame(&synthetic::frame(&scene, i, 8))?;
//! }
//! rec.finish()?;
//!
//! let mut replay = Replay::open(&path)?;
//! assert_eq!(replay.len(), 60);
//! let frame = replay.frame_at(30_500_000_000)?.unwrap();   // at or just before 30.5 s
//! assert_eq!(frame.t_ns, 30_000_000_000);
//! let frames: Vec<_> = replay.frames().collect::<Result<_, _>>()?;
//! let doc = kml::export(replay.scene(), &frames);
//! assert_eq!(doc.matches("<gx:Track>").count(), 8);
//! # std::fs::remove_file(&path)?;
//! # Ok::<(), Box<dyn std::error::Error>>(())
//! ```

pub mod channels;
pub mod draw;
mod error;
mod finite;
pub mod foxglove;
pub mod frame;
pub mod geometry;
mod index;
pub mod kml;
pub mod recorder;
pub mod replay;
pub mod schema;
pub mod synthetic;

pub use channels::Channel;
pub use frame::{
    Building, Detection, EntityState, Frame, Geo, Heightmap, Intention, MessageEvent, Scene,
    SensorFootprint, Side,
};
pub use recorder::{RecordError, RecordOptions, RecordStats, Recorder, topic};
pub use replay::{Frames, Replay, ReplayError};

//! # vitro-record: what a run shows, recorded and replayed
//!
//! The plain-data vocabulary shared by the mission (which produces it), the recorder (which
//! writes it to MCAP with Foxglove schemas), the KML exporter and the viewer (which streams it
//! live or replays it): a static [`Scene`] (map layers, terrain, geo-reference) and a
//! [`Frame`] per sample time (entities with poses, detections, messages, intentions,
//! metrics). Nothing here depends on the simulator, so a viewer or a converter builds without
//! physics or maps.

pub mod frame;

pub use frame::{
    Building, Detection, EntityState, Frame, Geo, Heightmap, Intention, MessageEvent, Scene, Side,
};

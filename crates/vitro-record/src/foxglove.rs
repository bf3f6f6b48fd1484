//! Foxglove's well-known message types, as written in JSON.
//!
//! Only what a recording writes, field for field as Foxglove's schemas name them
//! (<https://docs.foxglove.dev/docs/visualization/message-schemas/introduction>): times are
//! `{sec, nsec}`, enums are integers, every required field is present (empty arrays included),
//! so Foxglove Studio and other readers of the well-known schemas take the messages as they are.

use serde::Serialize;

/// The fixed frame everything is drawn in.
pub const WORLD_FRAME: &str = "world";

/// A timestamp: seconds and nanoseconds.
#[derive(Copy, Clone, Debug, Default, PartialEq, Eq, Serialize)]
pub struct Time {
    /// Whole seconds.
    pub sec: u64,
    /// Nanoseconds past `sec`, below 10⁹.
    pub nsec: u32,
}

impl Time {
    /// The time `t_ns` nanoseconds after the epoch.
    ///
    /// ```
    /// use vitro_record::foxglove::Time;
    /// assert_eq!(Time::from_ns(1_500_000_000), Time { sec: 1, nsec: 500_000_000 });
    /// ```
    pub fn from_ns(t_ns: u64) -> Self {
        Self {
            sec: t_ns / 1_000_000_000,
            // Below 10⁹: fits.
            nsec: (t_ns % 1_000_000_000) as u32,
        }
    }
}

/// A length of time; zero for "forever" in a [`SceneEntity`]'s lifetime.
#[derive(Copy, Clone, Debug, Default, PartialEq, Eq, Serialize)]
pub struct Duration {
    /// Whole seconds.
    pub sec: i64,
    /// Nanoseconds past `sec`.
    pub nsec: u32,
}

/// A vector or a point, metres.
#[derive(Copy, Clone, Debug, Default, PartialEq, Serialize)]
pub struct Vector3 {
    /// East.
    pub x: f64,
    /// North.
    pub y: f64,
    /// Up.
    pub z: f64,
}

impl Vector3 {
    /// A vector from an `[x, y, z]` array, rounded to the millimetre (shorter JSON).
    pub fn mm(p: [f64; 3]) -> Self {
        Self {
            x: round_to(p[0], 1e3),
            y: round_to(p[1], 1e3),
            z: round_to(p[2], 1e3),
        }
    }
}

/// `x` rounded to `1/scale` (non-finite values become 0: JSON has no NaN).
pub(crate) fn round_to(x: f64, scale: f64) -> f64 {
    if x.is_finite() {
        (x * scale).round() / scale
    } else {
        0.0
    }
}

/// A rotation.
#[derive(Copy, Clone, Debug, PartialEq, Serialize)]
pub struct Quaternion {
    /// x.
    pub x: f64,
    /// y.
    pub y: f64,
    /// z.
    pub z: f64,
    /// w.
    pub w: f64,
}

impl Quaternion {
    /// No rotation.
    pub const IDENTITY: Self = Self {
        x: 0.0,
        y: 0.0,
        z: 0.0,
        w: 1.0,
    };

    /// A rotation about the vertical axis by `yaw` radians, counter-clockwise from east.
    pub fn yaw(yaw: f64) -> Self {
        let half = if yaw.is_finite() { yaw / 2.0 } else { 0.0 };
        Self {
            x: 0.0,
            y: 0.0,
            z: round_to(half.sin(), 1e6),
            w: round_to(half.cos(), 1e6),
        }
    }
}

/// A position and an orientation.
#[derive(Copy, Clone, Debug, PartialEq, Serialize)]
pub struct Pose {
    /// Position.
    pub position: Vector3,
    /// Orientation.
    pub orientation: Quaternion,
}

impl Pose {
    /// At `p` (rounded to the millimetre), turned `yaw` radians from east.
    pub fn at(p: [f64; 3], yaw: f64) -> Self {
        Self {
            position: Vector3::mm(p),
            orientation: Quaternion::yaw(yaw),
        }
    }
}

/// A colour, each channel in `[0, 1]`.
#[derive(Copy, Clone, Debug, PartialEq, Serialize)]
pub struct Color {
    /// Red.
    pub r: f64,
    /// Green.
    pub g: f64,
    /// Blue.
    pub b: f64,
    /// Opacity.
    pub a: f64,
}

impl Color {
    /// An opaque colour.
    pub const fn rgb(r: f64, g: f64, b: f64) -> Self {
        Self { r, g, b, a: 1.0 }
    }

    /// This colour with opacity `a`.
    pub const fn alpha(self, a: f64) -> Self {
        Self { a, ..self }
    }
}

/// A key and its value.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct KeyValuePair {
    /// Key.
    pub key: String,
    /// Value.
    pub value: String,
}

/// An arrow: tail at the pose, pointing along its x axis.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct ArrowPrimitive {
    /// Tail and direction.
    pub pose: Pose,
    /// Shaft length, metres.
    pub shaft_length: f64,
    /// Shaft diameter, metres.
    pub shaft_diameter: f64,
    /// Head length, metres.
    pub head_length: f64,
    /// Head diameter, metres.
    pub head_diameter: f64,
    /// Colour.
    pub color: Color,
}

/// A box centred on its pose.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct CubePrimitive {
    /// Centre and orientation.
    pub pose: Pose,
    /// Size along each axis, metres.
    pub size: Vector3,
    /// Colour.
    pub color: Color,
}

/// A sphere or ellipsoid centred on its pose.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct SpherePrimitive {
    /// Centre and orientation.
    pub pose: Pose,
    /// Diameter along each axis, metres.
    pub size: Vector3,
    /// Colour.
    pub color: Color,
}

/// A cylinder (or cone) centred on its pose, flat faces perpendicular to z.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct CylinderPrimitive {
    /// Centre and orientation.
    pub pose: Pose,
    /// Bounding box, metres.
    pub size: Vector3,
    /// Bottom face scale (1: full size).
    pub bottom_scale: f64,
    /// Top face scale (1: full size).
    pub top_scale: f64,
    /// Colour.
    pub color: Color,
}

/// How a [`LinePrimitive`]'s points connect.
#[derive(Copy, Clone, Debug, PartialEq, Eq)]
pub enum LineType {
    /// 0-1, 1-2, ..., (n-1)-n.
    Strip = 0,
    /// A closed strip.
    Loop = 1,
    /// Separate segments 0-1, 2-3, ...
    List = 2,
}

impl Serialize for LineType {
    fn serialize<S: serde::Serializer>(&self, s: S) -> Result<S::Ok, S::Error> {
        s.serialize_u8(*self as u8)
    }
}

/// Lines through points.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct LinePrimitive {
    /// How the points connect.
    #[serde(rename = "type")]
    pub kind: LineType,
    /// Origin of the points.
    pub pose: Pose,
    /// Thickness: metres, or pixels when `scale_invariant`.
    pub thickness: f64,
    /// Whether `thickness` is in screen pixels.
    pub scale_invariant: bool,
    /// Points.
    pub points: Vec<Vector3>,
    /// Colour of the whole line (when `colors` is empty).
    pub color: Color,
    /// One colour per point, or none.
    pub colors: Vec<Color>,
    /// Indices into `points`, or none (all points in order).
    pub indices: Vec<u32>,
}

/// Triangles: each three points (or three indices) make one.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct TriangleListPrimitive {
    /// Origin of the points.
    pub pose: Pose,
    /// Vertices.
    pub points: Vec<Vector3>,
    /// Colour of the whole mesh (when `colors` is empty).
    pub color: Color,
    /// One colour per vertex, or none.
    pub colors: Vec<Color>,
    /// Indices into `points`, three per triangle, or none.
    pub indices: Vec<u32>,
}

/// A text label.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct TextPrimitive {
    /// Centre of the text.
    pub pose: Pose,
    /// Whether the text always faces the camera.
    pub billboard: bool,
    /// Height of a line: metres, or pixels when `scale_invariant`.
    pub font_size: f64,
    /// Whether `font_size` is in screen pixels.
    pub scale_invariant: bool,
    /// Colour.
    pub color: Color,
    /// The text.
    pub text: String,
}

/// A 3D model (unused, present because the schema requires the array).
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct ModelPrimitive {}

/// One thing drawn in a 3D scene: primitives sharing a frame of reference.
#[derive(Clone, Debug, Default, PartialEq, Serialize)]
pub struct SceneEntity {
    /// When.
    pub timestamp: Time,
    /// Frame of reference of the primitives.
    pub frame_id: String,
    /// Identifier: replaces an earlier entity with the same id on the same topic.
    pub id: String,
    /// How long it stays (zero: until replaced or deleted).
    pub lifetime: Duration,
    /// Whether it moves with `frame_id`.
    pub frame_locked: bool,
    /// Key-value pairs shown by the inspector.
    pub metadata: Vec<KeyValuePair>,
    /// Arrows.
    pub arrows: Vec<ArrowPrimitive>,
    /// Boxes.
    pub cubes: Vec<CubePrimitive>,
    /// Spheres.
    pub spheres: Vec<SpherePrimitive>,
    /// Cylinders.
    pub cylinders: Vec<CylinderPrimitive>,
    /// Lines.
    pub lines: Vec<LinePrimitive>,
    /// Triangle meshes.
    pub triangles: Vec<TriangleListPrimitive>,
    /// Text labels.
    pub texts: Vec<TextPrimitive>,
    /// Models (none).
    pub models: Vec<ModelPrimitive>,
}

impl SceneEntity {
    /// An empty entity `id` in the world frame at `t_ns`, lasting until replaced.
    pub fn new(t_ns: u64, id: impl Into<String>) -> Self {
        Self {
            timestamp: Time::from_ns(t_ns),
            frame_id: WORLD_FRAME.to_owned(),
            id: id.into(),
            ..Self::default()
        }
    }
}

/// Removes earlier entities of a topic: all of them (`type` 1) or one by id (`type` 0).
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct SceneEntityDeletion {
    /// Entities at or before this time are removed.
    pub timestamp: Time,
    /// 0: the entity `id`; 1: all.
    #[serde(rename = "type")]
    pub kind: u8,
    /// The entity to remove when `type` is 0.
    pub id: String,
}

impl SceneEntityDeletion {
    /// Removes every entity of the topic stamped at or before `t_ns`.
    pub fn all(t_ns: u64) -> Self {
        Self {
            timestamp: Time::from_ns(t_ns),
            kind: 1,
            id: String::new(),
        }
    }
}

/// `foxglove.SceneUpdate`: deletions first, then entities added or replaced.
#[derive(Clone, Debug, Default, PartialEq, Serialize)]
pub struct SceneUpdate {
    /// Removals, applied first.
    pub deletions: Vec<SceneEntityDeletion>,
    /// Entities added or replaced.
    pub entities: Vec<SceneEntity>,
}

/// Where a child frame sits in its parent.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct FrameTransform {
    /// When.
    pub timestamp: Time,
    /// Parent frame.
    pub parent_frame_id: String,
    /// Child frame.
    pub child_frame_id: String,
    /// The child's origin in the parent.
    pub translation: Vector3,
    /// The child's orientation in the parent.
    pub rotation: Quaternion,
}

/// `foxglove.FrameTransforms`: several transforms at once.
#[derive(Clone, Debug, Default, PartialEq, Serialize)]
pub struct FrameTransforms {
    /// The transforms.
    pub transforms: Vec<FrameTransform>,
}

/// `foxglove.LocationFix`: a position on the globe (what Foxglove's Map panel shows).
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct LocationFix {
    /// When.
    pub timestamp: Time,
    /// The frame at the fix (the entity's).
    pub frame_id: String,
    /// Latitude, degrees.
    pub latitude: f64,
    /// Longitude, degrees.
    pub longitude: f64,
    /// Altitude above sea level, metres.
    pub altitude: f64,
    /// Covariance, m², east-north-up, row-major (zero: exact).
    pub position_covariance: [f64; 9],
    /// 0: unknown, 1: approximated, 2: diagonal known, 3: known.
    pub position_covariance_type: u8,
    /// Heading, radians clockwise from north.
    pub heading: f64,
    /// Velocity east-north-up, m/s.
    pub velocity: Vector3,
    /// Colour of the track.
    pub color: Color,
}

/// Severity of a [`Log`] line.
#[derive(Copy, Clone, Debug, PartialEq, Eq)]
pub enum LogLevel {
    /// Debug.
    Debug = 1,
    /// Information.
    Info = 2,
    /// Warning.
    Warning = 3,
}

impl Serialize for LogLevel {
    fn serialize<S: serde::Serializer>(&self, s: S) -> Result<S::Ok, S::Error> {
        s.serialize_u8(*self as u8)
    }
}

/// `foxglove.Log`: one line of a log.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct Log {
    /// When.
    pub timestamp: Time,
    /// Severity.
    pub level: LogLevel,
    /// The line.
    pub message: String,
    /// Who says it.
    pub name: String,
    /// Source file (empty).
    pub file: String,
    /// Source line (0).
    pub line: u32,
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn enums_and_times_serialize_as_foxglove_expects() {
        let line = LinePrimitive {
            kind: LineType::List,
            pose: Pose::at([1.23456, 0.0, -0.0004], 0.0),
            thickness: 1.0,
            scale_invariant: true,
            points: vec![],
            color: Color::rgb(1.0, 0.0, 0.0),
            colors: vec![],
            indices: vec![],
        };
        let v = serde_json::to_value(&line).unwrap();
        assert_eq!(v["type"], 2);
        assert_eq!(v["pose"]["position"]["x"], 1.235);
        assert_eq!(v["pose"]["orientation"]["w"], 1.0);
        let del = serde_json::to_value(SceneEntityDeletion::all(2_000_000_001)).unwrap();
        assert_eq!(del["type"], 1);
        assert_eq!(del["timestamp"]["sec"], 2);
        assert_eq!(del["timestamp"]["nsec"], 1);
    }

    #[test]
    fn yaw_quaternion_turns_east_to_north() {
        let q = Quaternion::yaw(std::f64::consts::FRAC_PI_2);
        assert!((q.z - 0.5f64.sqrt()).abs() < 1e-6 && (q.w - 0.5f64.sqrt()).abs() < 1e-6);
        assert_eq!(Quaternion::yaw(f64::NAN), Quaternion::IDENTITY);
    }

    #[test]
    fn every_required_scene_entity_array_is_written() {
        let v = serde_json::to_value(SceneEntity::new(5, "a")).unwrap();
        for key in [
            "metadata",
            "arrows",
            "cubes",
            "spheres",
            "cylinders",
            "lines",
            "triangles",
            "texts",
            "models",
        ] {
            assert!(v[key].is_array(), "{key}");
        }
        assert_eq!(v["frame_id"], "world");
        assert_eq!(v["lifetime"]["sec"], 0);
    }
}

//! What travels over the WebSocket: JSON text messages.
//!
//! The server sends, in order: one [`Hello`], the [`Scene`] (once), the metric history so far,
//! then frames and statuses as they come. The client sends [`Command`]s, each a small JSON
//! object such as `{"cmd":"step","n":1}`; anything else (unknown command or field, binary
//! message, more than [`MAX_COMMAND_BYTES`]) is rejected.

use serde::{Deserialize, Serialize};
use std::collections::BTreeMap;
use vitro::sim::control::SPEED_RANGE;
use vitro_record::{Frame, Scene};

/// The longest client message accepted, in bytes.
pub const MAX_COMMAND_BYTES: usize = 1024;

/// The most events one `step` command may ask for.
pub const MAX_STEP: u64 = 10_000;

/// Whether the view shows a running simulation or a recording.
#[derive(Copy, Clone, Debug, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "lowercase")]
pub enum Mode {
    /// A simulation running now, paced in wall-clock time.
    Live,
    /// A recording, played back (seekable).
    Replay,
}

/// The first message of a connection.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct Hello {
    /// Live or replay.
    pub mode: Mode,
    /// What is shown (scenario or file name).
    pub title: String,
    /// First simulated time, nanoseconds.
    pub start_ns: u64,
    /// Last simulated time if known (a recording's end, a scenario's end time), nanoseconds.
    pub end_ns: Option<u64>,
}

/// Where playback stands, sent a few times a second and after each command.
#[derive(Clone, Debug, Default, PartialEq, Serialize, Deserialize)]
pub struct Status {
    /// Paused (live: the simulation; replay: this connection's playback).
    pub paused: bool,
    /// Simulated seconds per wall second; `None`: as fast as possible.
    pub speed: Option<f64>,
    /// Simulated time of the last fired event (live) or of the playhead (replay), ns.
    pub t_ns: u64,
    /// Events fired so far (live) or in the frame at the playhead (replay).
    pub events: u64,
    /// The run is over (live) or the playhead is at the end (replay).
    pub finished: bool,
    /// The run's trace hash once it is over (live), hex.
    pub trace_hash: Option<String>,
    /// Why the run stopped early, if it failed.
    pub failure: Option<String>,
}

/// Metric values over time, for the charts: `t_ns[i]` goes with `values[name][i]`
/// (`NaN`, sent as `null`, where a metric has no value yet).
#[derive(Clone, Debug, Default, PartialEq, Serialize, Deserialize)]
pub struct History {
    /// Sample times, nanoseconds.
    pub t_ns: Vec<u64>,
    /// Metric name → value per sample.
    pub values: BTreeMap<String, Vec<Option<f64>>>,
}

/// The most samples a [`History`] keeps; beyond it every other sample is dropped.
pub const HISTORY_CAP: usize = 2048;

impl History {
    /// Appends the metrics of `frame` (thinning the history when it is full).
    pub fn push(&mut self, frame: &Frame) {
        if self.t_ns.last().is_some_and(|&t| t >= frame.t_ns) {
            return;
        }
        if self.t_ns.len() >= HISTORY_CAP {
            self.thin();
        }
        let n = self.t_ns.len();
        self.t_ns.push(frame.t_ns);
        for (name, &v) in &frame.metrics {
            let col = self
                .values
                .entry(name.clone())
                .or_insert_with(|| vec![None; n]);
            col.push(v.is_finite().then_some(v));
        }
        for col in self.values.values_mut() {
            col.resize(n + 1, None);
        }
    }

    fn thin(&mut self) {
        fn every_other<T>(v: &mut Vec<T>) {
            let mut i = 0;
            v.retain(|_| {
                i += 1;
                i % 2 == 1
            });
        }
        every_other(&mut self.t_ns);
        self.values.values_mut().for_each(every_other);
    }
}

/// A message from the server.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(tag = "type", rename_all = "lowercase")]
pub enum ServerMsg {
    /// The first message.
    Hello(Hello),
    /// The static world, once.
    Scene {
        /// The scene.
        scene: Box<Scene>,
    },
    /// Metrics so far, once after the scene.
    History(History),
    /// The state at one instant.
    Frame {
        /// The frame.
        frame: Box<Frame>,
    },
    /// Playback state.
    Status(Status),
    /// A client message was rejected (the connection stays open).
    Error {
        /// Why.
        message: String,
    },
}

impl ServerMsg {
    /// The message as JSON text.
    pub fn to_json(&self) -> String {
        to_json(self)
    }
}

/// The frame message for `frame`, as JSON text: what [`ServerMsg::Frame`] encodes to, without
/// a copy of the frame.
pub fn frame_json(frame: &Frame) -> String {
    #[derive(Serialize)]
    #[serde(tag = "type", rename = "frame")]
    struct FrameMsg<'a> {
        frame: &'a Frame,
    }
    to_json(&FrameMsg { frame })
}

/// The scene message for `scene`, as JSON text: what [`ServerMsg::Scene`] encodes to, without
/// a copy of the scene.
pub fn scene_json(scene: &Scene) -> String {
    #[derive(Serialize)]
    #[serde(tag = "type", rename = "scene")]
    struct SceneMsg<'a> {
        scene: &'a Scene,
    }
    to_json(&SceneMsg { scene })
}

fn to_json(msg: &impl Serialize) -> String {
    // Plain data with string keys: serialising it cannot fail.
    serde_json::to_string(msg).unwrap_or_else(|e| {
        format!(r#"{{"type":"error","message":"cannot encode a message: {e}"}}"#)
    })
}

/// A command from the client.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(tag = "cmd", rename_all = "lowercase", deny_unknown_fields)]
pub enum Command {
    /// Pause (live: the simulation itself; replay: this connection's playback).
    Pause {},
    /// Resume.
    Resume {},
    /// Pause if running, then fire exactly `n` events (live) or show the next `n` frames
    /// (replay).
    Step {
        /// How many (1 to [`MAX_STEP`]).
        n: u64,
    },
    /// Set the speed factor (simulated seconds per wall second).
    Speed {
        /// The factor, within [`SPEED_RANGE`].
        factor: f64,
    },
    /// Move the playhead (replay only), simulated nanoseconds.
    Seek {
        /// Where to.
        t_ns: u64,
    },
}

/// Why a client message was rejected.
#[derive(Debug, thiserror::Error, PartialEq)]
pub enum CommandError {
    /// Longer than [`MAX_COMMAND_BYTES`].
    #[error("message of {0} bytes is over the limit of {MAX_COMMAND_BYTES}")]
    TooLong(usize),
    /// Not a known command.
    #[error("not a command: {0}")]
    Malformed(String),
    /// A value out of range.
    #[error("{0}")]
    OutOfRange(String),
    /// Not available in this mode.
    #[error("{0} is not available in a {1:?} view")]
    Unavailable(&'static str, Mode),
}

impl Command {
    /// Parses and checks a client message.
    ///
    /// ```
    /// use vitro_viz::protocol::Command;
    /// assert_eq!(Command::parse(r#"{"cmd":"step","n":1}"#), Ok(Command::Step { n: 1 }));
    /// assert!(Command::parse(r#"{"cmd":"step","n":0}"#).is_err());
    /// assert!(Command::parse(r#"{"cmd":"jump"}"#).is_err());
    /// ```
    pub fn parse(text: &str) -> Result<Command, CommandError> {
        if text.len() > MAX_COMMAND_BYTES {
            return Err(CommandError::TooLong(text.len()));
        }
        let cmd: Command =
            serde_json::from_str(text).map_err(|e| CommandError::Malformed(e.to_string()))?;
        cmd.check()
    }

    /// This command if its values are in range (a step of 1 to [`MAX_STEP`] events, a speed
    /// within [`SPEED_RANGE`]).
    pub fn check(self) -> Result<Command, CommandError> {
        match self {
            Command::Step { n } if !(1..=MAX_STEP).contains(&n) => Err(CommandError::OutOfRange(
                format!("step n = {n}: expected 1 to {MAX_STEP}"),
            )),
            Command::Speed { factor } if !(SPEED_RANGE.0..=SPEED_RANGE.1).contains(&factor) => {
                Err(CommandError::OutOfRange(format!(
                    "speed {factor}: expected {} to {}",
                    SPEED_RANGE.0, SPEED_RANGE.1
                )))
            }
            cmd => Ok(cmd),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn commands_parse_and_reject() {
        assert_eq!(Command::parse(r#"{"cmd":"pause"}"#), Ok(Command::Pause {}));
        assert_eq!(
            Command::parse(r#"{"cmd":"speed","factor":2.5}"#),
            Ok(Command::Speed { factor: 2.5 })
        );
        assert_eq!(
            Command::parse(r#"{"cmd":"seek","t_ns":5}"#),
            Ok(Command::Seek { t_ns: 5 })
        );
        for bad in [
            "",
            "null",
            "[]",
            r#"{"cmd":"pause","extra":1}"#,
            r#"{"cmd":"speed","factor":1e9}"#,
            r#"{"cmd":"speed","factor":-1}"#,
            r#"{"cmd":"speed"}"#,
            r#"{"cmd":"step","n":-1}"#,
            r#"{"cmd":"step","n":100000}"#,
            r#"{"cmd":"seek","t_ns":"soon"}"#,
        ] {
            assert!(Command::parse(bad).is_err(), "{bad}");
        }
        let long = format!(r#"{{"cmd":"pause","pad":"{}"}}"#, "x".repeat(2000));
        assert!(matches!(
            Command::parse(&long),
            Err(CommandError::TooLong(_))
        ));
    }

    #[test]
    fn frame_and_scene_json_are_their_messages() {
        let frame = Frame {
            t_ns: 7,
            ..Frame::default()
        };
        let msg = ServerMsg::Frame {
            frame: Box::new(frame.clone()),
        };
        assert_eq!(frame_json(&frame), msg.to_json());
        let scene = vitro_record::synthetic::scene();
        let msg = ServerMsg::Scene {
            scene: Box::new(scene.clone()),
        };
        assert_eq!(scene_json(&scene), msg.to_json());
    }

    #[test]
    fn history_aligns_columns_and_thins() {
        let mut h = History::default();
        let mut f = Frame::default();
        for i in 0..(HISTORY_CAP as u64 + 10) {
            f.t_ns = i + 1;
            f.metrics.insert("a".into(), i as f64);
            if i == 5 {
                f.metrics.insert("b".into(), 1.0);
            }
            h.push(&f);
        }
        assert!(h.t_ns.len() <= HISTORY_CAP);
        assert!(h.values.values().all(|c| c.len() == h.t_ns.len()));
        assert_eq!(h.values["b"][0], None);
        assert!(h.t_ns.windows(2).all(|w| w[0] < w[1]));
        // Frames out of order or repeated are ignored.
        let n = h.t_ns.len();
        h.push(&f);
        assert_eq!(h.t_ns.len(), n);
    }
}

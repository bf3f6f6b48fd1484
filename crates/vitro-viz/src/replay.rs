//! A replay: frames read back from a recording, each connection with its own playhead.

use crate::ViewError;
use crate::live::SourceError;
use crate::protocol::{
    Command, CommandError, HISTORY_CAP, Hello, History, Mode, ServerMsg, Status,
};
use std::path::Path;
use std::sync::{Arc, Mutex};
use vitro_record::{Frame, Replay, ReplayError, Scene};

/// A recording the viewer can play: a scene and frames in time order, read by index.
pub trait Recording: Send + 'static {
    /// What is shown (scenario or file name).
    fn title(&self) -> String;
    /// The static world.
    fn scene(&self) -> Scene;
    /// The time of every frame, in order, simulated nanoseconds.
    fn times(&self) -> Vec<u64>;
    /// Frame `i` (`None` past the end).
    fn frame(&mut self, i: usize) -> Result<Option<Frame>, SourceError>;
}

/// A recording held in memory (tests, small runs).
#[derive(Clone, Debug)]
pub struct MemoryRecording {
    title: String,
    scene: Scene,
    frames: Vec<Frame>,
}

impl MemoryRecording {
    /// A recording of `frames` (sorted by time here).
    pub fn new(title: impl Into<String>, scene: Scene, mut frames: Vec<Frame>) -> Self {
        frames.sort_by_key(|f| f.t_ns);
        MemoryRecording {
            title: title.into(),
            scene,
            frames,
        }
    }
}

impl Recording for MemoryRecording {
    fn title(&self) -> String {
        self.title.clone()
    }
    fn scene(&self) -> Scene {
        self.scene.clone()
    }
    fn times(&self) -> Vec<u64> {
        self.frames.iter().map(|f| f.t_ns).collect()
    }
    fn frame(&mut self, i: usize) -> Result<Option<Frame>, SourceError> {
        Ok(self.frames.get(i).cloned())
    }
}

/// A Vitro recording file (MCAP), read with [`vitro_record::Replay`].
pub struct McapRecording {
    title: String,
    replay: Replay,
}

impl McapRecording {
    /// Opens the recording at `path` (indexing it; frames are read on demand).
    pub fn open(path: &Path) -> Result<McapRecording, ReplayError> {
        let replay = Replay::open(path)?;
        let file = path.file_name().map_or_else(
            || path.display().to_string(),
            |f| f.to_string_lossy().into_owned(),
        );
        let title = format!("{} ({file})", replay.scene().name);
        Ok(McapRecording { title, replay })
    }
}

impl Recording for McapRecording {
    fn title(&self) -> String {
        self.title.clone()
    }
    fn scene(&self) -> Scene {
        self.replay.scene().clone()
    }
    fn times(&self) -> Vec<u64> {
        self.replay.times().collect()
    }
    fn frame(&mut self, i: usize) -> Result<Option<Frame>, SourceError> {
        Ok(self.replay.frame(i)?)
    }
}

/// A recording shared by every connection, with what each needs first.
#[derive(Clone)]
pub struct ReplayFeed {
    recording: Arc<Mutex<Box<dyn Recording>>>,
    times: Arc<Vec<u64>>,
    hello: Hello,
    scene_json: Arc<str>,
    history: Arc<History>,
}

impl ReplayFeed {
    /// Opens `recording`: reads its scene, and the metrics of up to [`HISTORY_CAP`] frames
    /// spread over the run (for the charts).
    pub fn new(mut recording: impl Recording) -> Result<ReplayFeed, ViewError> {
        let mut times = recording.times();
        if times.windows(2).any(|w| w[0] > w[1]) {
            times.sort_unstable();
        }
        let (start_ns, end_ns) = match (times.first(), times.last()) {
            (Some(&a), Some(&b)) => (a, b),
            _ => (0, 0),
        };
        let mut history = History::default();
        let every = times.len().div_ceil(HISTORY_CAP).max(1);
        let last = times.len().saturating_sub(1);
        for i in (0..times.len()).filter(|&i| i % every == 0 || i == last) {
            if let Some(f) = recording.frame(i).map_err(ViewError::Source)? {
                history.push(&f);
            }
        }
        let scene_json = ServerMsg::Scene {
            scene: Box::new(recording.scene()),
        }
        .to_json();
        Ok(ReplayFeed {
            hello: Hello {
                mode: Mode::Replay,
                title: recording.title(),
                start_ns,
                end_ns: Some(end_ns),
            },
            scene_json: scene_json.into(),
            history: Arc::new(history),
            times: Arc::new(times),
            recording: Arc::new(Mutex::new(Box::new(recording))),
        })
    }

    /// The first message to a client.
    pub fn hello(&self) -> Hello {
        self.hello.clone()
    }
    /// The scene message, as JSON.
    pub fn scene_json(&self) -> Arc<str> {
        self.scene_json.clone()
    }
    /// The metrics over the recording.
    pub fn history(&self) -> History {
        (*self.history).clone()
    }

    /// A playhead at the start, playing at 1×.
    pub fn player(&self) -> Player {
        Player {
            feed: self.clone(),
            t_ns: self.hello.start_ns,
            paused: false,
            speed: 1.0,
            events: 0,
            shown: None,
        }
    }

    /// The last frame at or before `t_ns`.
    fn frame_at(&self, t_ns: u64) -> Result<Option<Frame>, SourceError> {
        match self.times.partition_point(|&t| t <= t_ns).checked_sub(1) {
            Some(i) => self.frame(i),
            None => Ok(None),
        }
    }

    /// The first frame after `t_ns`.
    fn frame_after(&self, t_ns: u64) -> Result<Option<Frame>, SourceError> {
        self.frame(self.times.partition_point(|&t| t <= t_ns))
    }

    fn frame(&self, i: usize) -> Result<Option<Frame>, SourceError> {
        if i >= self.times.len() {
            return Ok(None);
        }
        let mut r = self.recording.lock().unwrap_or_else(|e| e.into_inner());
        r.frame(i)
    }
}

/// One connection's playhead over a [`ReplayFeed`].
pub struct Player {
    feed: ReplayFeed,
    t_ns: u64,
    paused: bool,
    speed: f64,
    events: u64,
    shown: Option<u64>,
}

impl Player {
    fn end(&self) -> u64 {
        self.feed.hello.end_ns.unwrap_or(self.feed.hello.start_ns)
    }

    /// Moves the playhead by `wall_s` of wall time (if playing); the frame to show if it
    /// changed, as a message.
    pub fn advance(&mut self, wall_s: f64) -> Result<Option<String>, SourceError> {
        if !self.paused {
            let dt = (wall_s * self.speed * 1e9) as u64;
            self.t_ns = self.t_ns.saturating_add(dt).min(self.end());
            if self.t_ns >= self.end() {
                self.paused = true;
            }
        }
        let frame = self.feed.frame_at(self.t_ns)?;
        Ok(self.show(frame, false))
    }

    fn show(&mut self, frame: Option<Frame>, force: bool) -> Option<String> {
        let frame = frame?;
        if !force && self.shown == Some(frame.t_ns) {
            return None;
        }
        self.shown = Some(frame.t_ns);
        self.events = frame.events;
        Some(
            ServerMsg::Frame {
                frame: Box::new(frame),
            }
            .to_json(),
        )
    }

    /// Applies a client command; the frames to show now, as messages.
    pub fn apply(&mut self, cmd: &Command) -> Result<Vec<String>, CommandError> {
        let failed = |e: SourceError| CommandError::OutOfRange(format!("cannot read: {e}"));
        match *cmd {
            Command::Pause {} => self.paused = true,
            Command::Resume {} => {
                if self.t_ns >= self.end() {
                    self.t_ns = self.feed.hello.start_ns;
                }
                self.paused = false;
            }
            Command::Speed { factor } => self.speed = factor,
            Command::Step { n } => {
                self.paused = true;
                let mut out = Vec::new();
                for _ in 0..n {
                    let Some(f) = self.feed.frame_after(self.t_ns).map_err(failed)? else {
                        break;
                    };
                    self.t_ns = f.t_ns;
                    out.extend(self.show(Some(f), true));
                }
                return Ok(out);
            }
            Command::Seek { t_ns } => {
                self.t_ns = t_ns.clamp(self.feed.hello.start_ns, self.end());
                let f = self.feed.frame_at(self.t_ns).map_err(failed)?;
                return Ok(self.show(f, true).into_iter().collect());
            }
        }
        Ok(Vec::new())
    }

    /// Where the playhead stands.
    pub fn status(&self) -> Status {
        Status {
            paused: self.paused,
            speed: Some(self.speed),
            t_ns: self.t_ns,
            events: self.events,
            finished: self.t_ns >= self.end(),
            trace_hash: None,
            failure: None,
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use vitro_record::{Geo, Heightmap};

    pub(crate) fn scene() -> Scene {
        Scene {
            name: "empty".into(),
            start_unix_ms: 0,
            geo: Geo {
                lat0: 0.0,
                lon0: 0.0,
                m_per_deg_lat: 111_000.0,
                m_per_deg_lon: 111_000.0,
                offset: [0.0, 0.0],
                z0: 0.0,
            },
            extent: [0.0, 0.0, 100.0, 100.0],
            streets: vec![],
            paths: vec![],
            buildings: vec![],
            bridges: vec![],
            forbidden: vec![],
            places: Default::default(),
            terrain: Heightmap {
                nx: 1,
                ny: 1,
                origin: [0.0, 0.0],
                cell: 1.0,
                z: vec![0.0],
            },
        }
    }

    fn frames() -> Vec<Frame> {
        (1..=10)
            .map(|i| Frame {
                t_ns: i * 1_000_000_000,
                events: i * 3,
                ..Frame::default()
            })
            .collect()
    }

    #[test]
    fn playhead_plays_steps_and_seeks() {
        let feed = ReplayFeed::new(MemoryRecording::new("t", scene(), frames())).unwrap();
        assert_eq!(feed.history().t_ns.len(), 10);
        let mut p = feed.player();
        assert!(p.advance(0.0).unwrap().is_some());
        assert!(p.advance(0.0).unwrap().is_none(), "same frame twice");
        p.apply(&Command::Speed { factor: 4.0 }).unwrap();
        p.advance(1.0).unwrap();
        assert_eq!(p.status().t_ns, 5_000_000_000);
        let shown = p.apply(&Command::Step { n: 2 }).unwrap();
        assert_eq!(shown.len(), 2);
        assert!(p.status().paused);
        assert_eq!(p.status().events, 21);
        p.apply(&Command::Seek {
            t_ns: 2_500_000_000,
        })
        .unwrap();
        assert_eq!(p.status().events, 6);
        p.apply(&Command::Seek { t_ns: u64::MAX }).unwrap();
        assert!(p.status().finished);
        assert_eq!(p.status().events, 30);
        p.apply(&Command::Resume {}).unwrap();
        assert_eq!(p.status().t_ns, 1_000_000_000, "resume at the end restarts");
    }
}

//! Reading a recording back: the scene, and any frame by index or simulated time.
//!
//! Opening builds an index of every frame — its time and where its message lies (chunk,
//! offset) — from the MCAP summary, without decompressing anything; a frame is read on demand
//! by decompressing its chunk (the last chunk read is kept, so reading in order decompresses
//! each chunk once). Memory is the index (24 bytes a frame) plus one chunk, whatever the
//! length of the run. A file without a summary (a run killed midway) is scanned instead, up
//! to its last complete chunk ([`Replay::is_complete`] tells which).

pub use crate::error::ReplayError;
use crate::frame::{Frame, Scene};
use crate::index::{Index, MessageLoc, chunk_record};
use mcap::records::{Record, op};
use std::fs::File;
use std::io::{BufReader, Read, Seek, SeekFrom};
use std::path::Path;

/// A recording opened for replay.
///
/// ```
/// use vitro_record::{synthetic, RecordOptions, Recorder, Replay};
/// let scene = synthetic::scene();
/// let mut rec = Recorder::new(std::io::Cursor::new(Vec::new()), &scene, &RecordOptions::default())?;
/// for i in 0..10 {
///     rec.frame(&synthetic::frame(&scene, i, 4))?;    // one a second
/// }
/// let bytes = rec.finish()?.into_inner();
/// let mut replay = Replay::from_reader(std::io::Cursor::new(bytes))?;
/// assert_eq!(replay.scene(), &scene);
/// assert_eq!(replay.time_range(), Some((0, 9_000_000_000)));
/// let f = replay.frame_at(4_500_000_000)?.expect("a frame at or before 4.5 s");
/// assert_eq!(f.t_ns, 4_000_000_000);
/// # Ok::<(), Box<dyn std::error::Error>>(())
/// ```
pub struct Replay<R: Read + Seek = BufReader<File>> {
    messages: Messages<R>,
    scene: Scene,
    complete: bool,
}

/// The source, its index, and the last chunk read.
struct Messages<R> {
    source: R,
    index: Index,
    cache: Option<(u32, Vec<u8>)>,
    zstd: Option<zstd::bulk::Decompressor<'static>>,
}

impl<R: Read + Seek> Messages<R> {
    /// Reads the message at `at` and decodes its JSON.
    fn decode<T: serde::de::DeserializeOwned>(
        &mut self,
        at: MessageLoc,
        what: &'static str,
    ) -> Result<T, ReplayError> {
        if self.cache.as_ref().is_none_or(|(k, _)| *k != at.chunk) {
            let records = self
                .index
                .load_chunk(&mut self.source, at.chunk, &mut self.zstd)?;
            self.cache = Some((at.chunk, records));
        }
        let records = self.cache.as_ref().map_or(&[][..], |(_, r)| r.as_slice());
        let bad = || ReplayError::Corrupt(format!("no {what} message at its indexed offset"));
        let (opcode, body, _) = chunk_record(records, at.offset).ok_or_else(bad)?;
        if opcode != op::MESSAGE {
            return Err(bad());
        }
        let Record::Message { header, data } = mcap::parse_record(opcode, body)? else {
            return Err(bad());
        };
        let channel = if what == "scene" {
            self.index.scene_channel
        } else {
            self.index.frame_channel
        };
        if header.log_time != at.t_ns || header.channel_id != channel {
            return Err(bad());
        }
        serde_json::from_slice(&data).map_err(|source| ReplayError::Decode {
            what,
            t_ns: at.t_ns,
            source,
        })
    }
}

impl<R: Read + Seek> std::fmt::Debug for Replay<R> {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("Replay")
            .field("scene", &self.scene.name)
            .field("frames", &self.len())
            .field("complete", &self.complete)
            .finish()
    }
}

fn open_file(path: &Path) -> Result<BufReader<File>, ReplayError> {
    match File::open(path) {
        Ok(f) => Ok(BufReader::new(f)),
        Err(e) if e.kind() == std::io::ErrorKind::NotFound => Err(ReplayError::Missing {
            path: path.to_owned(),
        }),
        Err(source) => Err(ReplayError::Open {
            path: path.to_owned(),
            source,
        }),
    }
}

impl Replay<BufReader<File>> {
    /// Opens the recording at `path`.
    pub fn open(path: impl AsRef<Path>) -> Result<Self, ReplayError> {
        Self::from_reader(open_file(path.as_ref())?)
    }

    /// Opens the recording at `path` ignoring its summary: reads every chunk, as [`open`]
    /// does for a file without a summary.
    ///
    /// [`open`]: Self::open
    pub fn scan(path: impl AsRef<Path>) -> Result<Self, ReplayError> {
        Self::with(open_file(path.as_ref())?, true)
    }
}

impl<R: Read + Seek> Replay<R> {
    /// Opens a recording held by `source` (a file, a `Cursor` over bytes).
    pub fn from_reader(source: R) -> Result<Self, ReplayError> {
        Self::with(source, false)
    }

    fn with(mut source: R, scan: bool) -> Result<Self, ReplayError> {
        let mut magic = [0; 8];
        source.seek(SeekFrom::Start(0))?;
        match source.read_exact(&mut magic) {
            Ok(()) if magic == *mcap::MAGIC => {}
            Ok(()) => return Err(ReplayError::NotMcap),
            Err(e) if e.kind() == std::io::ErrorKind::UnexpectedEof => {
                return Err(ReplayError::NotMcap);
            }
            Err(e) => return Err(e.into()),
        }
        let file_len = source.seek(SeekFrom::End(0))?;
        let (index, complete) = if scan {
            (Index::scan(&mut source, file_len)?, false)
        } else {
            Index::build(&mut source, file_len)?
        };
        let scene_at = index.scene.ok_or(ReplayError::NoScene)?;
        let mut messages = Messages {
            source,
            index,
            cache: None,
            zstd: None,
        };
        let scene = messages.decode(scene_at, "scene")?;
        // The scene's chunk is not needed again.
        messages.cache = None;
        Ok(Self {
            messages,
            scene,
            complete,
        })
    }

    /// The static world of the run.
    pub fn scene(&self) -> &Scene {
        &self.scene
    }

    /// Number of frames.
    pub fn len(&self) -> usize {
        self.messages.index.frames.len()
    }

    /// Whether there are no frames.
    pub fn is_empty(&self) -> bool {
        self.messages.index.frames.is_empty()
    }

    /// Whether the file was finished (it has MCAP's summary); `false` for a file recovered by
    /// a scan, such as that of a run killed midway.
    pub fn is_complete(&self) -> bool {
        self.complete
    }

    /// Times of the first and last frames, simulated nanoseconds.
    pub fn time_range(&self) -> Option<(u64, u64)> {
        let f = &self.messages.index.frames;
        Some((f.first()?.t_ns, f.last()?.t_ns))
    }

    /// Time of frame `i`.
    pub fn time_of(&self, i: usize) -> Option<u64> {
        self.messages.index.frames.get(i).map(|f| f.t_ns)
    }

    /// Times of every frame, in order.
    pub fn times(&self) -> impl ExactSizeIterator<Item = u64> + '_ {
        self.messages.index.frames.iter().map(|f| f.t_ns)
    }

    /// Index of the frame at `t_ns`, or the last one before it (`None` before the first).
    /// Among frames at equal times, the last written.
    pub fn index_at(&self, t_ns: u64) -> Option<usize> {
        self.messages
            .index
            .frames
            .partition_point(|f| f.t_ns <= t_ns)
            .checked_sub(1)
    }

    /// Frame `i` (`None` past the end).
    pub fn frame(&mut self, i: usize) -> Result<Option<Frame>, ReplayError> {
        match self.messages.index.frames.get(i).copied() {
            Some(at) => self.messages.decode(at, "frame").map(Some),
            None => Ok(None),
        }
    }

    /// The frame at `t_ns`, or the last one before it (`None` before the first frame).
    pub fn frame_at(&mut self, t_ns: u64) -> Result<Option<Frame>, ReplayError> {
        match self.index_at(t_ns) {
            Some(i) => self.frame(i),
            None => Ok(None),
        }
    }

    /// Every frame in order, read one at a time.
    pub fn frames(&mut self) -> Frames<'_, R> {
        Frames {
            replay: self,
            next: 0,
        }
    }
}

/// The frames of a [`Replay`], in order ([`Replay::frames`]).
pub struct Frames<'a, R: Read + Seek> {
    replay: &'a mut Replay<R>,
    next: usize,
}

impl<R: Read + Seek> Iterator for Frames<'_, R> {
    type Item = Result<Frame, ReplayError>;

    fn next(&mut self) -> Option<Self::Item> {
        let i = self.next;
        self.next += 1;
        self.replay.frame(i).transpose()
    }

    fn size_hint(&self) -> (usize, Option<usize>) {
        let left = self.replay.len().saturating_sub(self.next);
        (left, Some(left))
    }
}

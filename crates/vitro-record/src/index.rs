//! Where each frame of a recording lies: built from MCAP's summary, or by scanning the chunks.
//!
//! A frame is found by (chunk, offset of its message record in the decompressed chunk), the
//! addressing of MCAP's own message indexes. A finished recording's summary gives the chunks
//! and its message indexes give the offsets without decompressing anything; a file without a
//! summary (a run killed midway) is scanned chunk by chunk up to its last complete chunk.

use crate::error::ReplayError;
use crate::recorder::topic;
use mcap::records::{self, Record, op};
use mcap::sans_io::{SummaryReadEvent, SummaryReader, SummaryReaderOptions};
use std::io::{Read, Seek, SeekFrom};

/// Length of a record's opcode and length prefix.
const PREFIX: u64 = 9;

/// Largest chunk this reader decompresses (a corrupt size must not allocate without bound).
const MAX_CHUNK: u64 = 4 << 30;

/// A chunk record in the file.
#[derive(Copy, Clone, Debug, PartialEq, Eq)]
pub(crate) struct ChunkLoc {
    /// File offset of the chunk record (its opcode).
    pub offset: u64,
    /// Length of the record's body.
    pub length: u64,
}

/// A message: its time, its chunk and its record's offset in the decompressed chunk.
#[derive(Copy, Clone, Debug, PartialEq, Eq)]
pub(crate) struct MessageLoc {
    /// Log time, simulated nanoseconds.
    pub t_ns: u64,
    /// Index into [`Index::chunks`].
    pub chunk: u32,
    /// Offset of the message record in the decompressed chunk.
    pub offset: u64,
}

/// The chunks of a recording and where its scene and frames are.
#[derive(Debug, Default)]
pub(crate) struct Index {
    /// Chunks, in file order.
    pub chunks: Vec<ChunkLoc>,
    /// The scene message, if any.
    pub scene: Option<MessageLoc>,
    /// Frame messages, in time order (write order among equal times).
    pub frames: Vec<MessageLoc>,
    /// The `/vitro/scene` channel id.
    pub scene_channel: u16,
    /// The `/vitro/frame` channel id.
    pub frame_channel: u16,
}

/// Reads `len` bytes at `offset`.
fn read_at<R: Read + Seek>(r: &mut R, offset: u64, len: u64) -> Result<Vec<u8>, ReplayError> {
    let len = usize::try_from(len).map_err(|_| ReplayError::Corrupt("record too long".into()))?;
    r.seek(SeekFrom::Start(offset))?;
    let mut buf = vec![0; len];
    r.read_exact(&mut buf)?;
    Ok(buf)
}

/// The opcode and body length of the record at `offset`, if the file holds all of it.
fn record_head<R: Read + Seek>(r: &mut R, offset: u64, file_len: u64) -> Option<(u8, u64)> {
    let head = read_at(r, offset, PREFIX).ok()?;
    let len = u64::from_le_bytes(head[1..9].try_into().ok()?);
    let end = offset.checked_add(PREFIX)?.checked_add(len)?;
    (end <= file_len).then_some((head[0], len))
}

/// Length of the footer record (opcode, length, summary start, summary offset start, CRC).
const FOOTER: u64 = PREFIX + 20;

/// True when the summary section holds only the records a summary may have (schemas, channels,
/// chunk, attachment and metadata indexes, statistics, summary offsets), each within the
/// section. mcap's summary reader mishandles others: it reads a chunk's records past the
/// chunk's end, and its attachment parser slices past a malformed body. A file without a
/// summary passes.
fn summary_section_is_plain<R: Read + Seek>(r: &mut R, file_len: u64) -> bool {
    let magic = mcap::MAGIC.len() as u64;
    let Some(footer) = file_len.checked_sub(magic + FOOTER) else {
        return true; // too short for a footer: the summary reader says so
    };
    let Some(start) = read_at(r, footer + PREFIX, 8)
        .ok()
        .and_then(|b| Some(u64::from_le_bytes(b.try_into().ok()?)))
    else {
        return true;
    };
    if start == 0 {
        return true;
    }
    let mut at = start;
    while at < footer {
        match record_head(r, at, footer) {
            Some((
                op::SCHEMA
                | op::CHANNEL
                | op::CHUNK_INDEX
                | op::ATTACHMENT_INDEX
                | op::METADATA_INDEX
                | op::STATISTICS
                | op::SUMMARY_OFFSET,
                len,
            )) => at += PREFIX + len,
            _ => return false,
        }
    }
    true
}

/// The summary section, if the file has a readable one.
fn read_summary<R: Read + Seek>(r: &mut R, file_len: u64) -> Option<mcap::Summary> {
    if !summary_section_is_plain(r, file_len) {
        return None;
    }
    let mut reader =
        SummaryReader::new_with_options(SummaryReaderOptions::default().with_file_size(file_len));
    while let Some(event) = reader.next_event() {
        match event.ok()? {
            SummaryReadEvent::ReadRequest(n) => {
                let read = r.read(reader.insert(n)).ok()?;
                reader.notify_read(read);
            }
            SummaryReadEvent::SeekRequest(to) => {
                let pos = r.seek(to).ok()?;
                reader.notify_seeked(pos);
            }
        }
    }
    reader.finish()
}

/// Decompresses a chunk record's body into its records.
pub(crate) fn decompress_chunk(
    body: &[u8],
    zstd: &mut Option<zstd::bulk::Decompressor<'static>>,
) -> Result<Vec<u8>, ReplayError> {
    let Record::Chunk { header, data } = mcap::parse_record(op::CHUNK, body)? else {
        return Err(ReplayError::Corrupt(
            "a chunk index points at a non-chunk record".into(),
        ));
    };
    if header.uncompressed_size > MAX_CHUNK {
        return Err(ReplayError::Corrupt(format!(
            "a chunk claims {} bytes uncompressed",
            header.uncompressed_size
        )));
    }
    match header.compression.as_str() {
        "" => Ok(data.into_owned()),
        "zstd" => {
            if zstd.is_none() {
                *zstd = Some(zstd::bulk::Decompressor::new()?);
            }
            let z = zstd
                .as_mut()
                .ok_or_else(|| ReplayError::Corrupt("zstd".into()))?;
            // Bounded by MAX_CHUNK above.
            let out = z.decompress(&data, header.uncompressed_size as usize)?;
            if out.len() as u64 != header.uncompressed_size {
                return Err(ReplayError::Corrupt(
                    "a chunk decompresses to the wrong size".into(),
                ));
            }
            Ok(out)
        }
        other => Err(ReplayError::Compression(other.to_owned())),
    }
}

/// The record at `offset` in a decompressed chunk: opcode, body and the next record's offset.
pub(crate) fn chunk_record(records: &[u8], offset: u64) -> Option<(u8, &[u8], u64)> {
    let start = usize::try_from(offset).ok()?;
    let head = records.get(start..start.checked_add(9)?)?;
    let len = usize::try_from(u64::from_le_bytes(head[1..9].try_into().ok()?)).ok()?;
    let body_start = start + 9;
    let body = records.get(body_start..body_start.checked_add(len)?)?;
    Some((head[0], body, (body_start + len) as u64))
}

/// Channel ids of the Vitro topics, found so far.
#[derive(Default)]
struct VitroChannels {
    scene: Option<u16>,
    frame: Option<u16>,
}

impl VitroChannels {
    fn add(&mut self, c: &records::Channel) {
        if c.topic == topic::SCENE {
            self.scene = Some(c.id);
        } else if c.topic == topic::FRAME {
            self.frame = Some(c.id);
        }
    }
}

impl Index {
    /// Builds the index of a recording: from its summary when it has one, else by a scan.
    /// Returns it and whether the summary was used.
    pub fn build<R: Read + Seek>(r: &mut R, file_len: u64) -> Result<(Self, bool), ReplayError> {
        if let Some(summary) = read_summary(r, file_len) {
            let mut vitro = VitroChannels::default();
            for c in summary.channels.values() {
                if c.topic == topic::SCENE {
                    vitro.scene = Some(c.id);
                } else if c.topic == topic::FRAME {
                    vitro.frame = Some(c.id);
                }
            }
            let (Some(scene), Some(frame)) = (vitro.scene, vitro.frame) else {
                return Err(ReplayError::NotVitro);
            };
            if let Some(index) = Self::from_summary(r, file_len, &summary, scene, frame)? {
                return Ok((index, true));
            }
        }
        Ok((Self::scan(r, file_len)?, false))
    }

    /// The index from the summary's chunk indexes and the chunks' message indexes, or `None`
    /// when they do not account for every frame the statistics count.
    fn from_summary<R: Read + Seek>(
        r: &mut R,
        file_len: u64,
        summary: &mcap::Summary,
        scene_channel: u16,
        frame_channel: u16,
    ) -> Result<Option<Self>, ReplayError> {
        let mut chunk_indexes: Vec<&records::ChunkIndex> = summary.chunk_indexes.iter().collect();
        chunk_indexes.sort_by_key(|c| c.chunk_start_offset);
        let mut index = Self {
            scene_channel,
            frame_channel,
            ..Self::default()
        };
        for (k, ci) in chunk_indexes.iter().enumerate() {
            let Some(length) = ci.chunk_length.checked_sub(PREFIX) else {
                return Ok(None);
            };
            let chunk =
                u32::try_from(k).map_err(|_| ReplayError::Corrupt("too many chunks".into()))?;
            index.chunks.push(ChunkLoc {
                offset: ci.chunk_start_offset,
                length,
            });
            for (channel, &at) in &ci.message_index_offsets {
                if *channel != scene_channel && *channel != frame_channel {
                    continue;
                }
                let Some((op::MESSAGE_INDEX, len)) = record_head(r, at, file_len) else {
                    return Ok(None);
                };
                let body = read_at(r, at + PREFIX, len)?;
                let Record::MessageIndex(mi) = mcap::parse_record(op::MESSAGE_INDEX, &body)? else {
                    return Ok(None);
                };
                let mut entries: Vec<_> = mi
                    .records
                    .iter()
                    .map(|e| MessageLoc {
                        t_ns: e.log_time,
                        chunk,
                        offset: e.offset,
                    })
                    .collect();
                entries.sort_by_key(|m| m.offset);
                if *channel == frame_channel {
                    index.frames.extend(entries);
                } else if index.scene.is_none() {
                    index.scene = entries.first().copied();
                }
            }
        }
        let counted = summary
            .stats
            .as_ref()
            .and_then(|s| s.channel_message_counts.get(&frame_channel).copied());
        if counted.is_some_and(|n| n != index.frames.len() as u64) {
            return Ok(None);
        }
        index.sort();
        Ok(Some(index))
    }

    /// The index by reading every complete record from the start, decompressing each chunk;
    /// stops at the first incomplete or unreadable record (the end of a killed run's file).
    pub fn scan<R: Read + Seek>(r: &mut R, file_len: u64) -> Result<Self, ReplayError> {
        let mut vitro = VitroChannels::default();
        let mut chunks = Vec::new();
        let mut scene = None;
        let mut frames = Vec::new();
        let mut zstd = None;
        let mut pos = mcap::MAGIC.len() as u64;
        while let Some((opcode, len)) = record_head(r, pos, file_len) {
            let next = pos + PREFIX + len;
            match opcode {
                op::CHANNEL => {
                    let body = read_at(r, pos + PREFIX, len)?;
                    match mcap::parse_record(op::CHANNEL, &body) {
                        Ok(Record::Channel(c)) => vitro.add(&c),
                        _ => break,
                    }
                }
                op::CHUNK => {
                    let body = read_at(r, pos + PREFIX, len)?;
                    let Ok(records) = decompress_chunk(&body, &mut zstd) else {
                        break;
                    };
                    let chunk = u32::try_from(chunks.len())
                        .map_err(|_| ReplayError::Corrupt("too many chunks".into()))?;
                    chunks.push(ChunkLoc {
                        offset: pos,
                        length: len,
                    });
                    let mut at = 0;
                    while let Some((opcode, body, after)) = chunk_record(&records, at) {
                        // Only channels and messages are read: a chunk holds nothing else
                        // a replay needs (and mcap's parser of other records, attachments
                        // among them, panics on some malformed bodies).
                        let record = match opcode {
                            op::CHANNEL | op::MESSAGE => mcap::parse_record(opcode, body).ok(),
                            _ => None,
                        };
                        match record {
                            Some(Record::Channel(c)) => vitro.add(&c),
                            Some(Record::Message { header, .. }) => {
                                let loc = MessageLoc {
                                    t_ns: header.log_time,
                                    chunk,
                                    offset: at,
                                };
                                if Some(header.channel_id) == vitro.frame {
                                    frames.push(loc);
                                } else if Some(header.channel_id) == vitro.scene && scene.is_none()
                                {
                                    scene = Some(loc);
                                }
                            }
                            _ => {}
                        }
                        at = after;
                    }
                }
                op::DATA_END | op::FOOTER => break,
                _ => {}
            }
            pos = next;
        }
        let (Some(scene_channel), Some(frame_channel)) = (vitro.scene, vitro.frame) else {
            return Err(ReplayError::NotVitro);
        };
        let mut index = Self {
            chunks,
            scene,
            frames,
            scene_channel,
            frame_channel,
        };
        index.sort();
        Ok(index)
    }

    /// Frames in time order; a stable sort keeps the write order of equal times.
    fn sort(&mut self) {
        if !self.frames.windows(2).all(|w| w[0].t_ns <= w[1].t_ns) {
            self.frames.sort_by_key(|f| f.t_ns);
        }
    }

    /// Reads and decompresses chunk `k`.
    pub fn load_chunk<R: Read + Seek>(
        &self,
        r: &mut R,
        k: u32,
        zstd: &mut Option<zstd::bulk::Decompressor<'static>>,
    ) -> Result<Vec<u8>, ReplayError> {
        let c = self
            .chunks
            .get(k as usize)
            .ok_or_else(|| ReplayError::Corrupt("a message in a chunk that is not there".into()))?;
        let body = read_at(r, c.offset + PREFIX, c.length)?;
        decompress_chunk(&body, zstd)
    }
}

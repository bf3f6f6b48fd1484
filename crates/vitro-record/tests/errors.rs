//! Typed errors for files that are missing, not MCAP, or MCAP without a Vitro recording.

mod common;

use common::temp;
use std::collections::BTreeMap;
use std::io::Cursor;
use vitro_record::{Replay, ReplayError};

#[test]
fn a_missing_file_says_so_with_its_path() {
    let path = temp("does-not-exist.mcap");
    let err = Replay::open(&path).unwrap_err();
    assert!(matches!(err, ReplayError::Missing { .. }), "{err:?}");
    assert!(err.to_string().contains("does-not-exist.mcap"), "{err}");
}

#[test]
fn files_that_are_not_mcap_are_refused() {
    for bytes in [
        &b""[..],
        b"\x89MCAP0",
        b"name,value\n1,2\n3,4\n",
        &[0u8; 4096],
    ] {
        let err = Replay::from_reader(Cursor::new(bytes)).unwrap_err();
        assert!(matches!(err, ReplayError::NotMcap), "{err:?}");
    }
    let path = temp("text.mcap");
    std::fs::write(&path, "hello, not a recording\n").unwrap();
    let err = Replay::open(&path).unwrap_err();
    assert!(matches!(err, ReplayError::NotMcap), "{err:?}");
    std::fs::remove_file(&path).unwrap();
}

/// An MCAP file with one JSON channel, `topic`, and `n` messages.
fn other_mcap(topic: &str, n: u64, finish: bool) -> Vec<u8> {
    let mut w = mcap::Writer::new(Cursor::new(Vec::new())).unwrap();
    let schema = w.add_schema("Thing", "jsonschema", b"{}").unwrap();
    let channel = w
        .add_channel(schema, topic, "json", &BTreeMap::new())
        .unwrap();
    for t in 0..n {
        let header = mcap::records::MessageHeader {
            channel_id: channel,
            sequence: t as u32,
            log_time: t,
            publish_time: t,
        };
        w.write_to_known_channel(&header, b"{\"x\": 1}").unwrap();
    }
    if finish {
        w.finish().unwrap();
        w.into_inner().into_inner()
    } else {
        w.flush().unwrap();
        w.into_inner().into_inner()
    }
}

#[test]
fn mcap_without_vitro_channels_is_not_a_recording() {
    for finish in [true, false] {
        let bytes = other_mcap("/camera/info", 10, finish);
        let err = Replay::from_reader(Cursor::new(bytes)).unwrap_err();
        assert!(matches!(err, ReplayError::NotVitro), "{err:?}");
        assert!(err.to_string().contains("/vitro/frame"), "{err}");
    }
    // Only the magic bytes.
    let err = Replay::from_reader(Cursor::new(mcap::MAGIC.to_vec())).unwrap_err();
    assert!(matches!(err, ReplayError::NotVitro), "{err:?}");
}

#[test]
fn a_frame_that_does_not_decode_names_its_time() {
    // A /vitro/frame channel whose message is not a Frame, beside a valid scene.
    let mut w = mcap::Writer::new(Cursor::new(Vec::new())).unwrap();
    let mut put = |topic: &str, t: u64, data: &[u8]| {
        let schema = w.add_schema("x", "jsonschema", b"{}").unwrap();
        let channel = w
            .add_channel(schema, topic, "json", &BTreeMap::new())
            .unwrap();
        let header = mcap::records::MessageHeader {
            channel_id: channel,
            sequence: 0,
            log_time: t,
            publish_time: t,
        };
        w.write_to_known_channel(&header, data).unwrap();
    };
    let scene = serde_json::to_vec(&vitro_record::synthetic::scene()).unwrap();
    put("/vitro/scene", 0, &scene);
    put("/vitro/frame", 42, b"{\"t_ns\": \"soon\"}");
    w.finish().unwrap();
    let bytes = w.into_inner().into_inner();
    let mut replay = Replay::from_reader(Cursor::new(bytes)).unwrap();
    assert_eq!(replay.len(), 1);
    let err = replay.frame(0).unwrap_err();
    assert!(
        matches!(
            err,
            ReplayError::Decode {
                what: "frame",
                t_ns: 42,
                ..
            }
        ),
        "{err:?}"
    );
}

/// Files whose footer points their summary section at a chunk (mcap's summary reader once
/// read the chunk's records past its end and overflowed) or at a malformed attachment (its
/// parser sliced past the body): a summary holding records a summary never has is not
/// trusted, and the file is scanned, which finds no recording.
#[test]
fn a_summary_section_holding_data_records_is_not_trusted() {
    for bytes in [
        &include_bytes!("fuzz/summary_with_chunk.mcap")[..],
        &include_bytes!("fuzz/summary_with_attachment.mcap")[..],
    ] {
        assert!(Replay::from_reader(Cursor::new(bytes)).is_err());
    }
}

/// A file without a summary whose chunk holds a malformed attachment record (mcap's
/// attachment parser once sliced past its end): the scan reads only channels and messages.
#[test]
fn a_malformed_attachment_inside_a_chunk_is_skipped() {
    let bytes = include_bytes!("fuzz/chunk_with_attachment.mcap");
    assert!(Replay::from_reader(Cursor::new(&bytes[..])).is_err());
}

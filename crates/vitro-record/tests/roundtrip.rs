//! Scene and frames → MCAP → Replay give back exactly what was written, and seeking finds the
//! frame at or just before any time.

mod common;

use common::{frames, record, temp};
use std::io::Cursor;
use vitro_record::{RecordOptions, Recorder, Replay, synthetic};

#[test]
fn replay_reads_back_exactly_what_was_recorded() {
    let path = temp("roundtrip.mcap");
    let scene = synthetic::scene();
    let mut input = frames(&scene, 90, 12);
    // Values JSON must carry exactly: awkward floats, big times, unicode text.
    input[3].entities[0].pos = [0.1 + 0.2, 1e-300, -123_456.0 - 1.0 / 7.0];
    input[3].metrics.insert("ratio".into(), 1.0 / 3.0);
    input[4].log.push("Ünïcode \"quoted\" <tag> & tab\t".into());
    let written = record(&path, &input, &RecordOptions::default());
    assert_eq!(written, scene);

    for replay in [Replay::open(&path).unwrap(), Replay::scan(&path).unwrap()] {
        let mut replay = replay;
        assert_eq!(replay.scene(), &scene);
        assert_eq!(replay.len(), input.len());
        assert_eq!(replay.time_range(), Some((0, 89 * synthetic::PERIOD_NS)));
        let back: Vec<_> = replay.frames().collect::<Result<_, _>>().unwrap();
        assert_eq!(back, input);
        // Random access in any order.
        for i in [57usize, 2, 89, 0, 31] {
            assert_eq!(replay.frame(i).unwrap().as_ref(), Some(&input[i]));
        }
        assert_eq!(replay.frame(90).unwrap(), None);
    }
    assert!(Replay::open(&path).unwrap().is_complete());
    assert!(!Replay::scan(&path).unwrap().is_complete());
    std::fs::remove_file(&path).unwrap();
}

#[test]
fn every_option_reads_back_the_same() {
    let scene = synthetic::scene();
    let input = frames(&scene, 40, 6);
    let choices = [
        RecordOptions::default(),
        RecordOptions {
            foxglove: false,
            ..RecordOptions::default()
        },
        RecordOptions {
            compress: false,
            ..RecordOptions::default()
        },
        RecordOptions {
            chunk_bytes: 4096,
            ..RecordOptions::default()
        },
    ];
    for options in choices {
        let mut rec = Recorder::new(Cursor::new(Vec::new()), &scene, &options).unwrap();
        for f in &input {
            rec.frame(f).unwrap();
        }
        let bytes = rec.finish().unwrap().into_inner();
        let mut replay = Replay::from_reader(Cursor::new(bytes)).unwrap();
        let back: Vec<_> = replay.frames().collect::<Result<_, _>>().unwrap();
        assert_eq!(back, input, "{options:?}");
    }
}

#[test]
fn the_same_frames_give_the_same_bytes() {
    let scene = synthetic::scene();
    let input = frames(&scene, 30, 8);
    let write = || {
        let mut rec =
            Recorder::new(Cursor::new(Vec::new()), &scene, &RecordOptions::default()).unwrap();
        for f in &input {
            rec.frame(f).unwrap();
        }
        rec.finish().unwrap().into_inner()
    };
    assert_eq!(write(), write());
}

#[test]
fn seek_finds_the_frame_at_or_just_before_a_time() {
    let scene = synthetic::scene();
    // Irregular times, two frames at the same time.
    let times = [5u64, 10, 10, 250, 1_000, 1_001, 7_000_000_000];
    let input: Vec<_> = times
        .iter()
        .enumerate()
        .map(|(i, &t)| {
            let mut f = synthetic::frame(&scene, i as u64, 3);
            f.t_ns = t;
            f
        })
        .collect();
    let mut rec = Recorder::new(
        Cursor::new(Vec::new()),
        &scene,
        &RecordOptions {
            chunk_bytes: 2048,
            ..RecordOptions::default()
        },
    )
    .unwrap();
    for f in &input {
        rec.frame(f).unwrap();
    }
    let mut replay = Replay::from_reader(Cursor::new(rec.finish().unwrap().into_inner())).unwrap();
    assert_eq!(replay.time_range(), Some((5, 7_000_000_000)));
    assert!(replay.times().eq(times.iter().copied()));
    let cases = [
        (0, None),
        (4, None),
        (5, Some(0)),
        (9, Some(0)),
        (10, Some(2)), // the last written of two at 10
        (249, Some(2)),
        (250, Some(3)),
        (1_000, Some(4)),
        (1_000_000, Some(5)),
        (7_000_000_000, Some(6)),
        (u64::MAX, Some(6)),
    ];
    for (t, want) in cases {
        assert_eq!(replay.index_at(t), want, "t = {t}");
        let got = replay.frame_at(t).unwrap();
        assert_eq!(got.as_ref(), want.map(|i| &input[i]), "t = {t}");
    }
}

#[test]
fn a_recording_without_frames_opens_empty() {
    let scene = synthetic::scene();
    let rec = Recorder::new(Cursor::new(Vec::new()), &scene, &RecordOptions::default()).unwrap();
    let mut replay = Replay::from_reader(Cursor::new(rec.finish().unwrap().into_inner())).unwrap();
    assert_eq!(replay.scene(), &scene);
    assert!(replay.is_empty());
    assert_eq!(replay.time_range(), None);
    assert_eq!(replay.frame_at(u64::MAX).unwrap(), None);
    assert_eq!(replay.frames().count(), 0);
}

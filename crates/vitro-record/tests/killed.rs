//! A run killed midway leaves a readable prefix: the scene and every closed chunk.

mod common;

use common::{frames, temp};
use vitro_record::{RecordOptions, Recorder, Replay, synthetic};

fn small_chunks() -> RecordOptions {
    RecordOptions {
        chunk_bytes: 32 << 10,
        ..RecordOptions::default()
    }
}

#[test]
fn a_recorder_that_never_finishes_leaves_its_closed_chunks() {
    let path = temp("killed.mcap");
    let scene = synthetic::scene();
    let input = frames(&scene, 300, 10);
    let mut rec = Recorder::create_with(&path, &scene, &small_chunks()).unwrap();
    for f in &input {
        rec.frame(f).unwrap();
    }
    // No destructor runs, as when the process is killed: the buffered tail never reaches
    // the file, the open chunk stays unfinished, no summary is written.
    std::mem::forget(rec);

    let mut replay = Replay::open(&path).unwrap();
    assert!(!replay.is_complete());
    assert_eq!(replay.scene(), &scene);
    // Lost: at most the frames of the open chunk (32 KiB of messages, a few frames).
    let n = replay.len();
    assert!(n > 250, "{n} of 300 frames recovered");
    let back: Vec<_> = replay.frames().collect::<Result<_, _>>().unwrap();
    assert_eq!(back, input[..n]);
    std::fs::remove_file(&path).unwrap();
}

#[test]
fn a_file_cut_anywhere_after_the_scene_gives_a_prefix() {
    let path = temp("cut.mcap");
    let scene = synthetic::scene();
    let input = frames(&scene, 120, 10);
    let mut rec = Recorder::create_with(&path, &scene, &small_chunks()).unwrap();
    for f in &input {
        rec.frame(f).unwrap();
    }
    rec.finish().unwrap();
    let bytes = std::fs::read(&path).unwrap();
    let scene_end = {
        // The shortest prefix that still holds the scene.
        let mut lo = 8;
        let mut hi = bytes.len();
        while lo < hi {
            let mid = (lo + hi) / 2;
            let ok = Replay::from_reader(std::io::Cursor::new(&bytes[..mid])).is_ok();
            if ok { hi = mid } else { lo = mid + 1 }
        }
        lo
    };
    let mut last = 0;
    let step = (bytes.len() - scene_end) / 25;
    for cut in (scene_end..bytes.len())
        .step_by(step)
        .chain([bytes.len() - 1])
    {
        let mut replay = Replay::from_reader(std::io::Cursor::new(&bytes[..cut])).unwrap();
        assert!(!replay.is_complete());
        assert_eq!(replay.scene(), &scene);
        let n = replay.len();
        assert!(n >= last, "a longer prefix never holds fewer frames");
        last = n;
        let back: Vec<_> = replay.frames().collect::<Result<_, _>>().unwrap();
        assert_eq!(back, input[..n], "cut at {cut}");
    }
    // Cut just before the summary, everything is there.
    assert_eq!(last, input.len());
    std::fs::remove_file(&path).unwrap();
}

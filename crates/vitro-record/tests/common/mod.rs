//! Shared helpers of the recording tests: temporary files and synthetic recordings.

#![allow(dead_code)]

use std::path::PathBuf;
use vitro_record::{Frame, RecordOptions, Recorder, Scene, synthetic};

/// A path in the temporary directory, unique to this process and `name`.
pub fn temp(name: &str) -> PathBuf {
    std::env::temp_dir().join(format!("vitro-record-{}-{name}", std::process::id()))
}

/// Synthetic frames `0..n` with `entities` entities.
pub fn frames(scene: &Scene, n: u64, entities: usize) -> Vec<Frame> {
    (0..n)
        .map(|i| synthetic::frame(scene, i, entities))
        .collect()
}

/// Records `frames` of the synthetic scene to `path`; returns the scene.
pub fn record(path: &PathBuf, frames: &[Frame], options: &RecordOptions) -> Scene {
    let scene = synthetic::scene();
    let mut rec = Recorder::create_with(path, &scene, options).expect("create");
    for f in frames {
        rec.frame(f).expect("frame");
    }
    rec.finish().expect("finish");
    scene
}

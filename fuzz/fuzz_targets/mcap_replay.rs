#![no_main]

use libfuzzer_sys::fuzz_target;
use std::io::Cursor;

fuzz_target!(|data: &[u8]| {
    if let Ok(mut replay) = vitro_record::Replay::from_reader(Cursor::new(data)) {
        let _ = replay.scene();
        for frame in replay.frames().take(10_000) {
            if frame.is_err() {
                break;
            }
        }
    }
});

#![no_main]

use libfuzzer_sys::fuzz_target;
use vitro_mission::Mission;

fuzz_target!(|data: &[u8]| {
    if let Ok(text) = std::str::from_utf8(data) {
        // A path in no directory: the files a scenario names are not found (and not loaded).
        let path = std::path::Path::new("/nonexistent/vitro-fuzz/scenario.toml");
        let _ = vitro_evac::Evacuation.validate(path, text);
    }
});

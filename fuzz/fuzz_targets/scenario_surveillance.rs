#![no_main]

use libfuzzer_sys::fuzz_target;
use vitro_mission::Mission;

fuzz_target!(|data: &[u8]| {
    if let Ok(text) = std::str::from_utf8(data) {
        let path = std::path::Path::new("/nonexistent/vitro-fuzz/scenario.toml");
        let _ = vitro_surveillance::Surveillance.validate(path, text);
    }
});

#![no_main]

use libfuzzer_sys::fuzz_target;
fuzz_target!(|data: &[u8]| {
    if let Ok(text) = std::str::from_utf8(data) {
        if let Ok(instance) = vitro_algo::patrol::Instance::from_toml_str(text) {
            let _ = instance.period();
        }
    }
});

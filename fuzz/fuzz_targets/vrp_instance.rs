#![no_main]

use libfuzzer_sys::fuzz_target;
fuzz_target!(|data: &[u8]| {
    if let Ok(text) = std::str::from_utf8(data) {
        if let Ok(instance) = vitro_routing::parse::parse(text) {
            // A parsed instance is solvable: the construction heuristic takes it, whatever
            // its numbers (small ones only, so a run stays fast).
            if instance.customers() <= 64 {
                let _ = vitro_routing::savings(&instance);
            }
        }
    }
});

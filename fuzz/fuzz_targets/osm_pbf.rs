#![no_main]

use libfuzzer_sys::fuzz_target;
use vitro_site::map::{MapConfig, TownMap};

fuzz_target!(|data: &[u8]| {
    let _ = TownMap::from_bytes(data, &MapConfig::default());
});

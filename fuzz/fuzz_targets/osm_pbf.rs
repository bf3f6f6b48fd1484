#![no_main]

use libfuzzer_sys::fuzz_target;
use std::sync::Once;
use vitro_site::map::{MapConfig, TownMap};

static HOOK: Once = Once::new();

fuzz_target!(|data: &[u8]| {
    // osmpbf's decoder panics on an arithmetic overflow with hostile coordinates, before any
    // element reaches the reader; the reader (vitro-site map/osm.rs) catches that panic and
    // returns malformed data. libfuzzer-sys's panic hook aborts on every panic, caught or not:
    // here a panic raised inside osmpbf is let unwind to the reader's catch, and every other
    // panic aborts as before (and one that escapes the reader aborts in libfuzzer-sys anyway).
    HOOK.call_once(|| {
        let abort = std::panic::take_hook();
        std::panic::set_hook(Box::new(move |info| {
            let in_osmpbf = info
                .location()
                .is_some_and(|l| l.file().contains("osmpbf-"));
            if !in_osmpbf {
                abort(info);
            }
        }));
    });
    let _ = TownMap::from_bytes(data, &MapConfig::default());
});

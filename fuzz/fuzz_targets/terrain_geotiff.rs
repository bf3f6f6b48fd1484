#![no_main]

use libfuzzer_sys::fuzz_target;
use std::io::Write;
use std::sync::OnceLock;

/// One file per process, rewritten each run: GeoTIFF is read through a path.
fn file() -> &'static std::path::Path {
    static FILE: OnceLock<std::path::PathBuf> = OnceLock::new();
    FILE.get_or_init(|| std::env::temp_dir().join(format!("vitro-fuzz-{}.tif", std::process::id())))
}

fuzz_target!(|data: &[u8]| {
    let Ok(mut f) = std::fs::File::create(file()) else {
        return;
    };
    if f.write_all(data).is_ok() {
        drop(f);
        let _ = vitro_site::terrain::Terrain::load(file());
    }
});

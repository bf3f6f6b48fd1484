//! Terrain viewshed from the command line (what `vitro terrain viewshed` will run).
//!
//! `cargo run --release -p vitro-site --example viewshed -- FILE X,Y H T OUT.asc`
//!
//! `FILE` is an ESRI ASCII grid or a GeoTIFF; `X,Y` the observer in the file's own
//! coordinates; `H` and `T` the observer and target heights above the ground, metres.

use std::time::Instant;
use vitro_site::viewshed::viewshed_file;

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let args: Vec<String> = std::env::args().skip(1).collect();
    let [file, xy, h, t, out] = &args[..] else {
        return Err("usage: viewshed FILE X,Y OBSERVER_HEIGHT TARGET_HEIGHT OUT.asc".into());
    };
    let (x, y) = xy.split_once(',').ok_or("observer must be X,Y")?;
    let observer = [x.trim().parse()?, y.trim().parse()?];
    let t0 = Instant::now();
    let sum = viewshed_file(file, observer, h.parse()?, t.parse()?, out)?;
    println!(
        "{out}: {} of {} cells visible ({:.1} %), {:.3} s",
        sum.visible,
        sum.cells,
        100.0 * sum.visible as f64 / sum.cells as f64,
        t0.elapsed().as_secs_f64()
    );
    Ok(())
}

//! Prints the summary of an `.osm.pbf` file as JSON (what `vitro map info` will print).
//!
//! `cargo run --release -p vitro-site --example map_info [FILE.osm.pbf]`

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let path = std::env::args().nth(1).unwrap_or_else(|| {
        concat!(env!("CARGO_MANIFEST_DIR"), "/../../data/maps/kotka.osm.pbf").to_string()
    });
    let info = vitro_site::info::map_info(&path)?;
    println!("{}", serde_json::to_string_pretty(&info)?);
    Ok(())
}

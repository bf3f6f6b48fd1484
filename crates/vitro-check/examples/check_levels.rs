//! The cross-level check on the real town: every standard scenario at every level, every
//! standard property, as a table (or JSON with `--json`). Exits with status 1 if a property
//! fails.
//!
//! `cargo run --release -p vitro-check --example check_levels [--json]`

use vitro_check::check_levels;

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let report = check_levels()?;
    if std::env::args().any(|a| a == "--json") {
        println!("{}", serde_json::to_string_pretty(&report)?);
    } else {
        print!("{}", report.table());
    }
    if !report.pass {
        std::process::exit(1);
    }
    Ok(())
}

//! Runs the default mission at a fidelity preset for some simulated seconds and prints each
//! agent's stated intention: a quick look inside a run.
//!
//! `cargo run -p vitro-tactical --example evac_peek -- [discrete|interpolated|physical] [SECONDS]`

use vitro::time::SimTime;
use vitro_tactical::evac::Mission;
use vitro_tactical::scenario::Preset;

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let args: Vec<String> = std::env::args().collect();
    let preset = match args.get(1).map(String::as_str) {
        Some("interpolated") => Preset::Interpolated,
        Some("physical") => Preset::Physical,
        _ => Preset::Discrete,
    };
    let secs: f64 = args.get(2).and_then(|s| s.parse().ok()).unwrap_or(10.0);
    let path = concat!(
        env!("CARGO_MANIFEST_DIR"),
        "/../../scenarios/evacuation.toml"
    );
    let mut m = Mission::at_fidelity(path, None, preset)?;
    m.advance(SimTime::from_secs_f64(secs));
    let f = m.frame();
    for e in &f.entities {
        let i = f.intentions.iter().find(|i| i.id == e.id);
        println!(
            "{:10} {:9} {:12} ({:7.1}, {:7.1}, {:5.1}) {:5.1} m/s  {}  {:?}",
            e.name,
            e.level,
            e.status,
            e.pos[0],
            e.pos[1],
            e.pos[2],
            e.speed,
            i.map_or("", |i| i.text.as_str()),
            i.map(|i| &i.plan)
        );
    }
    Ok(())
}

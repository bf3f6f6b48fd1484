//! Runs the default mission at a fidelity preset for some simulated seconds and prints each
//! agent's stated intention: a quick look inside a run.
//!
//! `cargo run -p vitro-evac --example evac_peek -- [discrete|interpolated|physical] [SECONDS] [SEED] [SCENARIO]`

use vitro::time::SimTime;
use vitro_evac::Mission;
use vitro_tactical::scenario::Preset;

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let args: Vec<String> = std::env::args().collect();
    let preset = match args.get(1).map(String::as_str) {
        Some("interpolated") => Preset::Interpolated,
        Some("physical") => Preset::Physical,
        _ => Preset::Discrete,
    };
    let secs: f64 = args.get(2).and_then(|s| s.parse().ok()).unwrap_or(10.0);
    let seed: Option<u64> = args.get(3).and_then(|s| s.parse().ok());
    let default = concat!(
        env!("CARGO_MANIFEST_DIR"),
        "/../../scenarios/evacuation.toml"
    );
    let path = args.get(4).map_or(default, String::as_str);
    let mut m = Mission::at_fidelity(path, seed, preset)?;
    if std::env::var_os("END").is_some() {
        m.end = SimTime::from_secs_f64(secs);
    }
    if std::env::var_os("CHUNKED").is_some() {
        let mut t = SimTime::ZERO;
        while t < SimTime::from_secs_f64(secs) {
            t += m.sample;
            m.advance(t);
        }
    } else {
        m.advance(SimTime::from_secs_f64(secs));
    }
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
    let commander = m.sim.agent(m.brief.truck).and_then(|a| {
        a.as_any()
            .downcast_ref::<vitro_evac::agents::commander::Commander>()
    });
    if let Some(c) = commander {
        let log: Vec<String> = c
            .log
            .iter()
            .map(|(t, p)| format!("{:.0} s {p:?}", t.as_secs_f64()))
            .collect();
        println!("phases: {}", log.join(", "));
    }
    for mem in &m.members {
        let c = m.sim.env().conditions.get(mem.id);
        println!("{:10} {:?}", mem.name, c.map(|c| c.status));
    }
    println!(
        "t = {:.1} s, {} events, trace {:016x}",
        m.sim.now().as_secs_f64(),
        m.sim.events_fired(),
        m.sim.trace_hash()
    );
    Ok(())
}

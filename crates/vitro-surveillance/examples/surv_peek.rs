//! Prints the state of a surveillance run every minute: each UAV's mode, position, sectors
//! and locks, the station's picture, and the referee's metrics at the end.
//!
//! `cargo run --release -p vitro-surveillance --example surv_peek -- [SCENARIO] [SEED] [END_S]`

use vitro::time::SimTime;
use vitro_mission::Run;
use vitro_surveillance::Operation;
use vitro_surveillance::agents::station::Station;
use vitro_surveillance::agents::uav::Uav;

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let args: Vec<String> = std::env::args().collect();
    let path = args
        .get(1)
        .map_or("scenarios/surveillance.toml", String::as_str);
    let seed = args.get(2).map(|s| s.parse()).transpose()?;
    let mut op = Operation::from_file(path, seed)?;
    if let Some(end) = args.get(3) {
        op.end = SimTime::from_secs_f64(end.parse()?);
    }
    let mut t = 0;
    loop {
        t += 60;
        let going = op.advance(SimTime::from_secs(t));
        println!("t = {:.0} s", op.sim.now().as_secs_f64());
        for m in &op.members {
            let Some(a) = op.sim.agent(m.id) else {
                continue;
            };
            let pos = op.sim.env().pose(m.id).map(|p| p.pos).unwrap_or_default();
            if let Some(u) = a.as_any().downcast_ref::<Uav>() {
                let locks: Vec<String> = u
                    .locks()
                    .map(|l| format!("#{} (misses {})", l.target.0, l.misses))
                    .collect();
                println!(
                    "  {:8} {:?} at ({:.0}, {:.0}, {:.0}) sectors {:?} locks [{}] route {} pts",
                    m.name,
                    u.mode,
                    pos[0],
                    pos[1],
                    pos[2],
                    u.sectors.keys().collect::<Vec<_>>(),
                    locks.join(", "),
                    u.route.len()
                );
            } else if let Some(s) = a.as_any().downcast_ref::<Station>() {
                let held = s.sectors.values().filter(|x| x.holder.is_some()).count();
                println!("  station: {held}/{} held, {:?}", s.sectors.len(), s.stats);
            } else if m.is_red() {
                println!("  {:8} at ({:.0}, {:.0})", m.name, pos[0], pos[1]);
            }
        }
        for (t, line) in Run::drain_log(&mut op) {
            println!("  {t:7.1} s  {line}");
        }
        if !going {
            break;
        }
    }
    println!("{:#?}", op.metrics());
    Ok(())
}

//! Looks at each stall of the traffic scenario at the physical level: which vehicle gave its
//! trip up, where, facing which way, how much room it had ahead and behind (straight and
//! along its steering), and which vehicles and buildings were near. With `TRACE=NAME,FROM,TO`
//! it also prints that vehicle's state every 0.2 s between the two times (position, pitch,
//! heading, speed, controls, recovery, the bearing of its track, its progress).
//!
//! `cargo run --release -p vitro-traffic --example stall_probe -- [SEED] [UNTIL_S]`
//! (`SCEN=FILE` reads another traffic scenario than `scenarios/traffic.toml`).

use std::collections::HashMap;
use std::path::Path;
use vitro::entity::EntityId;
use vitro::env::NodeId;
use vitro::time::SimTime;
use vitro_mission::Run;
use vitro_tactical::arena::Arena;
use vitro_tactical::entity::ground::physical::Chassis;
use vitro_tactical::entity::route::wrap_angle;
use vitro_tactical::scenario::Preset;

/// Which vehicle to trace, from when to when (simulated seconds).
struct Trace {
    name: String,
    from: f64,
    to: f64,
}

fn trace_from_env() -> Option<Trace> {
    let v = std::env::var("TRACE").ok()?;
    let mut p = v.split(',');
    Some(Trace {
        name: p.next()?.to_string(),
        from: p.next()?.parse().ok()?,
        to: p.next()?.parse().ok()?,
    })
}

/// What surrounds vehicle `id` (its last row under way: `prev`) when it gave its trip up.
fn report_stall(
    w: &Arena,
    names: &HashMap<EntityId, String>,
    id: EntityId,
    prev: &Chassis,
    t: f64,
) {
    let g = prev.ground_point();
    println!(
        "t={t:.1} {} ({:?}) stalled at ({:.1},{:.1}) heading {:.0}° pitch {:.1}° recoveries {} no progress since {:.0} s",
        names[&id],
        prev.kind,
        g[0],
        g[1],
        prev.heading().to_degrees(),
        prev.attitude[1].to_degrees(),
        prev.recoveries,
        prev.progress.1.as_secs_f64()
    );
    if let Some(p) = w.physics.as_ref() {
        let room = |back, steer| {
            p.clearance_steered(id, back, steer, 8.0, false)
                .unwrap_or(-1.0)
        };
        let steer = prev.controls.steer;
        println!(
            "   room ahead {:.2} m (along its steering {:.2}), behind {:.2} m (along its steering {:.2})",
            room(false, 0.0),
            room(false, steer),
            room(true, 0.0),
            room(true, steer)
        );
    }
    for (oid, o) in w.chassis.iter() {
        let p = o.ground_point();
        let d = libm::hypot(p[0] - g[0], p[1] - g[1]);
        if oid != id && d < 25.0 {
            let b = wrap_angle(libm::atan2(p[1] - g[1], p[0] - g[0]) - prev.heading());
            println!(
                "   {} ({:?}) {:.1} m away at {:.0}°, heading {:+.0}° to it, speed {:.2}, under way {}",
                names[&oid],
                o.kind,
                d,
                b.to_degrees(),
                wrap_angle(o.heading() - prev.heading()).to_degrees(),
                o.speed,
                w.follow.contains(oid)
            );
        }
    }
    let here = [g[0], g[1]];
    for b in &w.site.buildings {
        let d = b.footprint.boundary_distance(here);
        if d < 0.5 * w.types.ground(prev.kind).length + 3.0 {
            println!("   building {} {:.1} m from its centre", b.index, d);
        }
    }
    for b in &w.site.bridges {
        let near = (b.deck.iter()).any(|q| libm::hypot(q[0] - g[0], q[1] - g[1]) < 15.0);
        if near {
            println!("   bridge {} ends within 15 m (deck {:?})", b.index, b.deck);
        }
    }
}

/// One line of the traced vehicle's state.
fn report_trace(w: &Arena, id: EntityId, t: f64) {
    let Some(row) = w.chassis.get(id) else {
        return;
    };
    let g = row.ground_point();
    let (alpha, s) = match w.follow.get(id) {
        Some(f) => {
            let r = w.types.ground(row.kind).turning_radius.max(6.0);
            let a = f.track.point_at(f.s + r);
            let bearing = wrap_angle(libm::atan2(a[1] - g[1], a[0] - g[0]) - row.heading());
            (bearing.to_degrees(), f.s)
        }
        None => (f64::NAN, f64::NAN),
    };
    let room = |back| {
        (w.physics.as_ref())
            .and_then(|p| p.clearance_steered(id, back, row.controls.steer, 8.0, false))
            .unwrap_or(-1.0)
    };
    println!(
        "  {t:.1} ({:.2},{:.2}) pitch {:.1}° heading {:.1}° speed {:.2} steer {:.2} drive {:.0} brake {:.0} recoveries {} manoeuvre {:?} track at {:.0}° s {:.1} room {:.2}/{:.2}",
        g[0],
        g[1],
        row.attitude[1].to_degrees(),
        row.heading().to_degrees(),
        row.speed,
        row.controls.steer,
        row.controls.drive,
        row.controls.brake,
        row.recoveries,
        row.manoeuvre.map(|m| (m.reverse, m.moves)),
        alpha,
        s,
        room(false),
        room(true)
    );
}

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let mut args = std::env::args().skip(1);
    let seed: u64 = args.next().map(|s| s.parse()).transpose()?.unwrap_or(1);
    let until: f64 = args
        .next()
        .map(|s| s.parse())
        .transpose()?
        .unwrap_or(3600.0);
    let scenario = std::env::var("SCEN").unwrap_or_else(|_| "scenarios/traffic.toml".into());
    let path = Path::new(&scenario);
    let text = std::fs::read_to_string(path)?;
    let mut run =
        vitro_traffic::Streets::from_text(path, &text, Some(seed), Some(Preset::Physical))?;
    let names: HashMap<_, _> = (run.play.members.iter())
        .map(|m| (m.id, m.name.clone()))
        .collect();
    let trace = trace_from_env();
    let traced = (trace.as_ref())
        .and_then(|tr| names.iter().find(|(_, n)| **n == tr.name))
        .map(|(id, _)| *id);
    // Each vehicle under way: its goal and its last row.
    let mut under_way: HashMap<EntityId, (NodeId, Chassis)> = HashMap::new();
    let (mut t, mut stalls) = (0.0, 0);
    while t < until {
        t += 0.2;
        Run::advance(&mut run, SimTime::from_secs_f64(t))?;
        let w = run.sim.env();
        let now: HashMap<_, _> = (w.chassis.iter())
            .filter_map(|(id, row)| Some((id, (w.follow.get(id)?.goal, row.clone()))))
            .collect();
        for (id, (goal, prev)) in &under_way {
            let same_trip = now.get(id).is_some_and(|n| n.0 == *goal);
            let arrived = w.chassis.get(*id).is_some_and(|r| r.node == *goal);
            if !same_trip && !arrived {
                stalls += 1;
                report_stall(w, &names, *id, prev, t);
            }
        }
        if let (Some(tr), Some(id)) = (&trace, traced)
            && (tr.from..=tr.to).contains(&t)
        {
            report_trace(w, id, t);
        }
        under_way = now;
    }
    println!("{stalls} stalls");
    Ok(())
}

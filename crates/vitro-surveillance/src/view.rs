//! The run as [`vitro_record`] data: the static [`Scene`] (the town, its terrain, the
//! station and the sector centres as named places) and a [`Frame`] of the state now (the
//! UAVs, the red units, their status; each UAV's locks as detections, its camera as a
//! sensor footprint, its route, sectors and locks as its intention; messages, metrics and
//! log). Reading only: making a frame never changes the run.

use crate::SurveillanceRun;
use crate::agents::uav::Uav;
use std::collections::BTreeMap;
use vitro::entity::EntityId;
use vitro_mission::scene::site_scene;
use vitro_record::{Detection, Frame, Intention, Scene, SensorFootprint};
use vitro_tactical::record::{entity, side};

/// The static scene: the town, the station, and each sector's centre as a place `sector N`
/// (the sectors of areas tasked later too).
pub fn scene(run: &SurveillanceRun) -> Scene {
    let site = &run.team.site;
    let mut places = BTreeMap::new();
    if let Some(p) = run.sim.env().pose(EntityId(0)) {
        places.insert("station".to_string(), p.pos);
    }
    let b = &run.tasks;
    let later = b.tasking.iter().flat_map(|(_, s)| s.iter());
    for s in b.sectors.iter().chain(later) {
        let c = crate::sector::centre(s.area);
        places.insert(format!("sector {}", s.id), site.on_ground(c));
    }
    let mut scene = site_scene(site, run.name.clone(), run.start.unix_millis());
    scene.places = places;
    scene
}

/// Draws the run now into `frame`: the entities, locks, cameras and intentions; the log lines
/// since the previous frame are moved into it.
pub fn frame(run: &mut SurveillanceRun, frame: &mut Frame) {
    let metrics = run.metrics();
    frame.log = (crate::Operation::drain_log(run).into_iter())
        .map(|(t, s)| format!("{:7.1} s  {s}", t.as_secs_f64()))
        .collect();
    let w = run.sim.env();
    let mut entities = Vec::new();
    let mut detections = Vec::new();
    let mut sensors = Vec::new();
    let mut intentions = Vec::new();
    let locked: Vec<EntityId> = (run.members.iter())
        .filter_map(|m| run.sim.agent(m.id)?.as_any().downcast_ref::<Uav>())
        .flat_map(|u| u.locks().map(|l| l.target).collect::<Vec<_>>())
        .collect();
    for m in &run.members {
        let (Some(c), Some(p)) = (w.conditions.get(m.id), w.pose(m.id)) else {
            continue;
        };
        let status = if m.is_red() {
            match metrics.red.get(&m.name) {
                _ if locked.contains(&m.id) => "tracked",
                Some(r) if r.first_detection_s.is_some() => "lost track",
                _ => "undetected",
            }
            .to_owned()
        } else if m.kind.is_none() {
            "station".to_owned()
        } else {
            c.status.name().to_owned()
        };
        let kind = m.kind.map_or("station", |k| k.name());
        entities.push(entity(m.id, &m.name, kind, m.side, &p, status));
        let agent = run.sim.agent(m.id);
        if let Some(i) = agent.and_then(|a| a.intention()) {
            intentions.push(Intention {
                id: m.id.0,
                text: i.text,
                plan: i.plan,
                path: i.path,
                heat: i.heat,
                belief: i.belief,
                ..Intention::default()
            });
        }
        let Some(u) = agent.and_then(|a| a.as_any().downcast_ref::<Uav>()) else {
            continue;
        };
        if !u.alive {
            continue;
        }
        let v = run.team.tracking.vision;
        sensors.push(SensorFootprint {
            id: m.id.0,
            kind: "camera".into(),
            range: v.range,
            heading: p.heading,
            fov: 2.0 * v.half_fov,
        });
        for l in u.locks().filter(|l| l.misses == 0) {
            detections.push(Detection {
                observer: m.id.0,
                target: l.target.0,
                from: p.pos,
                to: l.pos,
                seen_as: side(l.seen_as),
            });
        }
    }
    frame.entities = entities;
    frame.detections = detections;
    frame.sensors = sensors;
    frame.intentions = intentions;
}

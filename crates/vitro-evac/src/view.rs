//! The mission as [`vitro_record`] data: the static [`Scene`] (map layers, terrain,
//! geo-reference, named places) and a [`Frame`] of the current state (entities,
//! lines of sight, intentions, sensor sectors, log; the session adds the messages and the
//! metrics). Reading only: making a frame never changes the simulation.

use crate::EvacRun;
use vitro_mission::scene::site_scene;
use vitro_record::{Detection, Frame, Intention, Scene, SensorFootprint};
use vitro_tactical::condition::Status;
use vitro_tactical::record::entity;
use vitro_tactical::sensor::FriendFoeVision;
use vitro_tactical::world::{Body, Side};

/// The static scene of the run: the site and the mission's places.
pub fn scene(run: &EvacRun) -> Scene {
    let mut scene = site_scene(&run.brief.site, run.name.clone(), run.start.unix_millis());
    let names = ["start", "safehouse", "extraction"];
    scene.places = (names.into_iter().zip(run.brief.places))
        .map(|(k, p)| (k.to_string(), p))
        .collect();
    scene
}

/// Draws the run now into `frame`: entities, lines of sight, cameras, intentions; the
/// referee's log lines since the previous frame are moved into it.
pub fn frame(run: &mut EvacRun, frame: &mut Frame) {
    let (sim, mission) = (&run.sim, &mut run.play);
    let w = sim.env();
    let mut entities = Vec::new();
    let mut bodies: Vec<(u32, Body, bool)> = Vec::new();
    for m in &mission.members {
        let Some(c) = w.conditions.get(m.id) else {
            continue;
        };
        let pose = match c.status {
            Status::Aboard(v) => w.pose(v),
            Status::Hidden => None,
            _ => w.pose(m.id),
        };
        let Some(p) = pose else { continue };
        let metrics = &mission.referee.metrics;
        let detected = m.side != Side::Red
            || metrics.first_detection_s.contains_key(&m.name)
            || (Some(m.id) == mission.brief.hvt && metrics.hvt_first_report_s.is_some());
        let status = if detected || c.status != Status::Active {
            c.status.name().to_string()
        } else {
            "undetected".to_string()
        };
        entities.push(entity(m.id, &m.name, c.role.name(), m.side, &p, status));
        if c.status == Status::Active {
            let b = Body::new(p.pos, p.heading, c.side, c.height);
            bodies.push((m.id.0, b, c.role.is_aircraft()));
        }
    }
    let ground = mission.brief.sensors.ground.vision();
    let air = mission.brief.sensors.air.vision();
    let mut detections = Vec::new();
    let mut sensors = Vec::new();
    for (id, b, flies) in &bodies {
        if b.side != Side::Blue {
            continue;
        }
        let v: &FriendFoeVision = if *flies { &air } else { &ground };
        sensors.push(SensorFootprint {
            id: *id,
            kind: "camera".into(),
            range: v.range,
            heading: b.heading,
            fov: 2.0 * v.half_fov,
        });
        for (tid, t, _) in &bodies {
            if t.side == Side::Red && v.can_see(&w.site, b, t) {
                detections.push(Detection {
                    observer: *id,
                    target: *tid,
                    from: b.eye(),
                    to: t.centre(),
                    seen_as: vitro_record::Side::Hostile,
                });
            }
        }
    }
    let intentions = (mission.members.iter())
        .filter_map(|m| {
            let i = sim.agent(m.id)?.intention()?;
            Some(Intention {
                id: m.id.0,
                text: i.text,
                plan: i.plan,
                path: i.path,
                original_plan: i.original_plan,
                belief: i.belief,
                heat: i.heat,
                ..Intention::default()
            })
        })
        .collect();
    frame.entities = entities;
    frame.detections = detections;
    frame.sensors = sensors;
    frame.intentions = intentions;
    frame.log = (mission.referee.log.drain(..))
        .map(|(t, s)| format!("{:7.1} s  {s}", t.as_secs_f64()))
        .collect();
}

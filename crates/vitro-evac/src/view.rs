//! The mission as [`vitro_record`] data: the static [`Scene`] (map layers, terrain,
//! geo-reference, named places) and a [`Frame`] of the current state (entities,
//! lines of sight, messages, intentions, sensor sectors, metrics, log). Reading only: making
//! a frame never changes the simulation.

use super::Mission;
use std::collections::BTreeMap;
use vitro_mission::scene::site_scene;
use vitro_record::{Detection, EntityState, Frame, Intention, Scene, SensorFootprint};
use vitro_tactical::condition::Status;
use vitro_tactical::sensor::FriendFoeVision;
use vitro_tactical::world::{Body, Side};

fn side(s: Side) -> vitro_record::Side {
    match s {
        Side::Blue => vitro_record::Side::Friendly,
        Side::Red => vitro_record::Side::Hostile,
        Side::Neutral => vitro_record::Side::Neutral,
    }
}

impl Mission {
    /// The static scene of the mission. From the first call on, the radio messages are kept
    /// for the frames ([`frame`](Self::frame) hands over those since the last frame): a
    /// recorder or a viewer asks for the scene before it runs, and a run nobody watches keeps
    /// none.
    pub fn scene(&self) -> Scene {
        if let Ok(mut h) = self.heard.lock() {
            h.watched = true;
        }
        let site = &self.brief.site;
        let places = ["start", "safehouse", "extraction"]
            .into_iter()
            .zip(self.brief.places)
            .map(|(k, p)| (k.to_string(), p))
            .collect();
        let mut scene = site_scene(site, self.name.clone(), self.start.unix_millis());
        scene.places = places;
        scene
    }

    /// The state now, as a frame; the messages (kept once the [scene](Self::scene) was asked
    /// for) and log lines since the previous frame are moved into it.
    pub fn frame(&mut self) -> Frame {
        let w = self.sim.env();
        let mut entities = Vec::new();
        let mut bodies: Vec<(u32, Body, bool)> = Vec::new();
        for m in &self.members {
            let Some(c) = w.conditions.get(m.id) else {
                continue;
            };
            let pose = match c.status {
                Status::Aboard(v) => w.pose(v),
                Status::Hidden => None,
                _ => w.pose(m.id),
            };
            let Some(p) = pose else { continue };
            let metrics = &self.referee.metrics;
            let detected = m.side != Side::Red
                || metrics.first_detection_s.contains_key(&m.name)
                || (Some(m.id) == self.brief.hvt && metrics.hvt_first_report_s.is_some());
            let status = if detected || c.status != Status::Active {
                c.status.name().to_string()
            } else {
                "undetected".to_string()
            };
            entities.push(EntityState {
                id: m.id.0,
                name: m.name.clone(),
                kind: c.role.name().into(),
                side: side(m.side),
                level: p.level.name().into(),
                pos: p.pos,
                heading: p.heading,
                speed: p.speed,
                status,
            });
            if c.status == Status::Active {
                let b = Body::new(p.pos, p.heading, c.side, c.height);
                bodies.push((m.id.0, b, c.role.is_aircraft()));
            }
        }
        let ground = self.brief.sensors.ground.vision();
        let air = self.brief.sensors.air.vision();
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
        let intentions = self
            .members
            .iter()
            .filter_map(|m| {
                let i = self.sim.agent(m.id)?.intention()?;
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
        let messages = match self.heard.lock() {
            Ok(mut h) => std::mem::take(&mut h.messages),
            Err(_) => Vec::new(),
        };
        let log = self
            .referee
            .log
            .drain(..)
            .map(|(t, s)| format!("{:7.1} s  {s}", t.as_secs_f64()))
            .collect();
        Frame {
            t_ns: self.sim.now().as_nanos(),
            events: self.sim.events_fired(),
            entities,
            detections,
            messages,
            intentions,
            sensors,
            metrics: metric_map(&self.metrics()),
            log,
        }
    }
}

/// The numeric metrics by name (absent values left out).
pub fn metric_map(m: &super::Metrics) -> BTreeMap<String, f64> {
    let mut out = BTreeMap::new();
    let b = |x: bool| if x { 1.0 } else { 0.0 };
    out.insert("success".into(), b(m.success));
    if let Some(t) = m.time_to_extraction_s {
        out.insert("time_to_extraction_s".into(), t);
    }
    out.insert("casualties".into(), f64::from(m.casualties));
    out.insert(
        "adversaries_detected".into(),
        f64::from(m.adversaries_detected),
    );
    out.insert("time_uncovered_s".into(), m.time_uncovered_s);
    out.insert("hvt_captured".into(), b(m.hvt_captured));
    out.insert("messages_sent".into(), m.messages_sent as f64);
    out.insert("plan_repairs".into(), m.plan_repairs as f64);
    out.insert("vehicle_stalls".into(), m.vehicle_stalls as f64);
    out.insert("aircraft_down".into(), m.aircraft_down as f64);
    out.insert("shots".into(), m.shots as f64);
    out.insert("cnet_calls".into(), m.cnet_calls as f64);
    out.insert("cnet_awards".into(), m.cnet_awards as f64);
    out.insert("cnet_reallocations".into(), m.cnet_reallocations as f64);
    out.insert("patrol_attacks".into(), m.patrol_attacks as f64);
    out.insert(
        "patrol_attacks_stopped".into(),
        m.patrol_attacks_stopped as f64,
    );
    let patrol = [
        ("patrol_capture_computed", m.patrol_capture_computed),
        ("patrol_capture_probability", m.patrol_capture_probability),
        ("patrol_cover_fraction", m.patrol_cover_fraction),
        ("patrol_sight_fraction", m.patrol_sight_fraction),
    ];
    for (name, value) in patrol {
        if let Some(x) = value {
            out.insert(name.into(), x);
        }
    }
    out
}

//! The run as [`vitro_record`] data: the static [`Scene`] (the town, its terrain, the
//! station and the sector centres as named places) and a [`Frame`] of the state now (the
//! UAVs, the red units, their status; each UAV's locks as detections, its camera as a
//! sensor footprint, its route, sectors and locks as its intention; messages, metrics and
//! log). Reading only: making a frame never changes the run.

use crate::Operation;
use crate::agents::uav::Uav;
use crate::referee::Metrics;
use std::collections::BTreeMap;
use vitro::entity::EntityId;
use vitro_mission::scene::site_scene;
use vitro_record::{Detection, EntityState, Frame, Intention, Scene, SensorFootprint};
use vitro_tactical::world::Side;

fn side(s: Side) -> vitro_record::Side {
    match s {
        Side::Blue => vitro_record::Side::Friendly,
        Side::Red => vitro_record::Side::Hostile,
        Side::Neutral => vitro_record::Side::Neutral,
    }
}

impl Operation {
    /// The static scene: the town, the station, and each sector's centre as a place
    /// `sector N` (the sectors of areas tasked later too).
    pub fn scene(&self) -> Scene {
        let site = &self.team.site;
        let mut places = BTreeMap::new();
        if let Some(p) = self.sim.env().pose(EntityId(0)) {
            places.insert("station".to_string(), p.pos);
        }
        let b = &self.tasks;
        let later = b.tasking.iter().flat_map(|(_, s)| s.iter());
        for s in b.sectors.iter().chain(later) {
            let c = crate::sector::centre(s.area);
            places.insert(format!("sector {}", s.id), site.on_ground(c));
        }
        let mut scene = site_scene(site, self.name.clone(), self.start.unix_millis());
        scene.places = places;
        scene
    }

    /// The state now, as a frame; the messages and log lines since the previous frame are
    /// moved into it.
    pub fn frame(&mut self) -> Frame {
        let metrics = self.metrics();
        let messages = self.drain_messages();
        let log = (self.drain_log().into_iter())
            .map(|(t, s)| format!("{:7.1} s  {s}", t.as_secs_f64()))
            .collect();
        let w = self.sim.env();
        let mut entities = Vec::new();
        let mut detections = Vec::new();
        let mut sensors = Vec::new();
        let mut intentions = Vec::new();
        let locked: Vec<EntityId> = (self.members.iter())
            .filter_map(|m| self.sim.agent(m.id)?.as_any().downcast_ref::<Uav>())
            .flat_map(|u| u.locks().map(|l| l.target).collect::<Vec<_>>())
            .collect();
        for m in &self.members {
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
            entities.push(EntityState {
                id: m.id.0,
                name: m.name.clone(),
                kind: m.kind.map_or("station", |k| k.name()).into(),
                side: side(m.side),
                level: p.level.name().into(),
                pos: p.pos,
                heading: p.heading,
                speed: p.speed,
                status,
            });
            let agent = self.sim.agent(m.id);
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
            let v = self.team.tracking.vision;
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
        Frame {
            t_ns: self.sim.now().as_nanos(),
            events: self.sim.events_fired(),
            entities,
            detections,
            messages,
            intentions,
            sensors,
            metrics: metric_map(&metrics),
            log,
        }
    }
}

/// The numeric metrics by name (absent values left out).
pub fn metric_map(m: &Metrics) -> BTreeMap<String, f64> {
    let mut out = BTreeMap::new();
    let mut put = |k: &str, v: f64| {
        out.insert(k.to_owned(), v);
    };
    put("red_detected", f64::from(m.red_detected));
    put("mean_tracked_share", m.mean_tracked_share);
    put("messages_sent", m.messages_sent as f64);
    put("messages_lost", m.messages_lost as f64);
    put("awards", m.awards as f64);
    put("reallocations", m.reallocations as f64);
    put("uavs_lost", f64::from(m.uavs_lost));
    put("sectors_held", f64::from(m.sectors_held));
    if let Some(t) = m.mean_time_to_detection_s {
        put("mean_time_to_detection_s", t);
    }
    out
}

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
use vitro_record::{
    Building, Detection, EntityState, Frame, Geo, Heightmap, Intention, Scene, SensorFootprint,
};
use vitro_site::map::Mode;
use vitro_site::site::Site;
use vitro_tactical::world::Side;

/// Terrain samples per side of the scene's heightmap (at most).
const TERRAIN_SAMPLES: usize = 96;

fn side(s: Side) -> vitro_record::Side {
    match s {
        Side::Blue => vitro_record::Side::Friendly,
        Side::Red => vitro_record::Side::Hostile,
        Side::Neutral => vitro_record::Side::Neutral,
    }
}

fn geo(site: &Site) -> Geo {
    let p = site.map.projection;
    let [lat1, lon1] = p.unproject([1000.0, 1000.0]);
    Geo {
        lat0: p.lat0,
        lon0: p.lon0,
        m_per_deg_lat: 1000.0 / (lat1 - p.lat0),
        m_per_deg_lon: 1000.0 / (lon1 - p.lon0),
        offset: site.offset,
        z0: 0.0,
    }
}

fn heightmap(site: &Site) -> Heightmap {
    let e = site.terrain.extent();
    let span = (e[2] - e[0]).max(e[3] - e[1]);
    let cell = span / (TERRAIN_SAMPLES - 1) as f64;
    let nx = (((e[2] - e[0]) / cell) as usize + 1).min(TERRAIN_SAMPLES);
    let ny = (((e[3] - e[1]) / cell) as usize + 1).min(TERRAIN_SAMPLES);
    let mut z = Vec::with_capacity(nx * ny);
    for j in 0..ny {
        for i in 0..nx {
            let x = (e[0] + i as f64 * cell).min(e[2]);
            let y = (e[1] + j as f64 * cell).min(e[3]);
            z.push(site.ground([x, y]).unwrap_or(0.0) as f32);
        }
    }
    Heightmap {
        nx,
        ny,
        origin: [e[0], e[1]],
        cell,
        z,
    }
}

fn lines(site: &Site, mode: Mode) -> Vec<Vec<[f64; 3]>> {
    (0..site.map.streets(mode).segments.len())
        .filter_map(|i| site.segment_path(mode, i))
        .collect()
}

impl Operation {
    /// The static scene: the town, the station, and each sector's centre as a place
    /// `sector N` (the sectors of areas tasked later too).
    pub fn scene(&self) -> Scene {
        let site = &self.team.site;
        let e = site.map.extent;
        let [ox, oy] = site.offset;
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
        Scene {
            name: self.name.clone(),
            start_unix_ms: self.start.unix_millis(),
            geo: geo(site),
            extent: [e[0] + ox, e[1] + oy, e[2] + ox, e[3] + oy],
            streets: lines(site, Mode::Drive),
            paths: lines(site, Mode::Walk),
            buildings: (site.buildings.iter())
                .map(|b| Building {
                    footprint: b.footprint.outer.clone(),
                    base: b.base,
                    height: b.roof - b.base,
                })
                .collect(),
            bridges: site.bridges.iter().map(|b| b.deck.clone()).collect(),
            forbidden: (site.map.water.iter())
                .map(|w| w.area.outer.iter().map(|&p| site.to_world(p)).collect())
                .collect(),
            places,
            terrain: heightmap(site),
        }
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

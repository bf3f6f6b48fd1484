//! The demo's pictures: its street graph as a [`Scene`] and each instant as a [`Frame`], for
//! recordings and the viewer.

use crate::patrol::{PatrolMsg, Patroller};
use crate::{Demo, DemoError, Scenario};
use std::collections::BTreeMap;
use std::sync::{Arc, Mutex};
use vitro::entity::EntityId;
use vitro::env::NodeId;
use vitro::prelude::*;
use vitro::sim::Control;
use vitro_record::frame::SensorFootprint;
use vitro_record::{EntityState, Frame, Geo, Heightmap, Intention, MessageEvent, Scene, Side};

/// Margin around the town on the map, metres.
const MARGIN_M: f64 = 60.0;

/// A demo run with what its pictures need: the messages heard since the last frame and each
/// car's last shown pose.
pub struct DemoView {
    pub(crate) scenario: Scenario,
    /// Messages delivered or bounced since the last frame (filled by a listener).
    pub(crate) heard: Arc<Mutex<Vec<MessageEvent>>>,
    /// Each car's last shown position and time, for its heading and speed.
    pub(crate) last: BTreeMap<u32, ([f64; 2], u64, f64)>,
}

impl DemoView {
    /// Wraps a built scenario (adds a listener that collects the messages for the frames).
    pub fn new(mut scenario: Scenario) -> Self {
        let heard = Arc::new(Mutex::new(Vec::new()));
        listen(&mut scenario, &heard);
        DemoView {
            scenario,
            heard,
            last: BTreeMap::new(),
        }
    }

    fn junction(&self, n: NodeId) -> Option<[f64; 3]> {
        let j = self.scenario.simulation().env().streets().node(n)?;
        Some([j.x, j.y, 0.0])
    }

    /// The junction nearest to `p`.
    fn nearest(&self, p: [f64; 2]) -> Option<NodeId> {
        let streets = self.scenario.simulation().env().streets();
        (0..streets.node_count() as u32)
            .map(NodeId)
            .filter_map(|n| {
                streets
                    .node(n)
                    .map(|j| (n, libm::hypot(j.x - p[0], j.y - p[1])))
            })
            .min_by(|a, b| a.1.total_cmp(&b.1))
            .map(|(n, _)| n)
    }

    fn car(&mut self, id: EntityId, t_ns: u64) -> Option<EntityState> {
        let sim = self.scenario.simulation();
        let (x, y) = sim.env().position(id)?;
        let failed = sim.agent(id).and_then(Patroller::failure).is_some();
        let (heading, speed) = match self.last.get(&id.0) {
            Some(&([px, py], pt, h)) if t_ns > pt => {
                let d = libm::hypot(x - px, y - py);
                let h = if d > 1e-6 {
                    libm::atan2(y - py, x - px)
                } else {
                    h
                };
                (h, d / ((t_ns - pt) as f64 / 1e9))
            }
            Some(&(_, _, h)) => (h, 0.0),
            None => (0.0, 0.0),
        };
        self.last.insert(id.0, ([x, y], t_ns, heading));
        Some(EntityState {
            id: id.0,
            name: sim.entities().name(id).unwrap_or("car").to_owned(),
            kind: "car".to_owned(),
            side: Side::Friendly,
            level: "interpolated".to_owned(),
            pos: [x, y, 0.0],
            heading,
            speed,
            status: if failed { "failed" } else { "active" }.to_owned(),
        })
    }

    fn intention(&self, id: EntityId, at: [f64; 3]) -> Option<Intention> {
        let sim = self.scenario.simulation();
        let goal = sim.agent(id)?.goal()?;
        let streets = sim.env().streets();
        let path = self
            .nearest([at[0], at[1]])
            .and_then(|from| streets.shortest_path(from, goal))
            .map(|(_, nodes)| nodes.iter().filter_map(|&n| self.junction(n)).collect())
            .unwrap_or_default();
        Some(Intention {
            id: id.0,
            text: format!(
                "patrol: drive to junction {} (least recently visited, claimed over the radio)",
                goal.0
            ),
            plan: vec![
                format!("drive to junction {}", goal.0),
                "broadcast visits and the next claim".to_owned(),
            ],
            path,
            ..Intention::default()
        })
    }

    fn metrics(&self, t_ns: u64) -> BTreeMap<String, f64> {
        let sim = self.scenario.simulation();
        let env = sim.env();
        let n = env.streets().node_count();
        let now = SimTime::from_nanos(t_ns);
        let (mut gap_sq, mut worst, mut visits) = (0u128, 0u64, 0u64);
        for i in 0..n {
            let log = env.visit_log(NodeId(i as u32));
            let open = now.saturating_since(log.last).as_nanos();
            gap_sq += log.gap_sq + u128::from(open).pow(2);
            worst = worst.max(log.max_gap.as_nanos()).max(open);
            visits += log.visits;
        }
        let mean_s = if n == 0 || t_ns == 0 {
            0.0
        } else {
            gap_sq as f64 / 2.0 / n as f64 / t_ns as f64 / 1e9
        };
        let (mut sent, mut received, mut lost) = (0, 0, 0);
        for (_, _, c) in sim.network().all_counts() {
            sent += c.sent;
            received += c.received;
            lost += c.lost;
        }
        let reached: u64 = self
            .scenario
            .cars()
            .iter()
            .filter_map(|&c| sim.agent(c))
            .map(|p| p.stats().goals_reached)
            .sum();
        BTreeMap::from([
            ("mean_idleness_s".to_owned(), mean_s),
            ("max_idleness_s".to_owned(), worst as f64 / 1e9),
            ("visits".to_owned(), visits as f64),
            ("goals_reached".to_owned(), reached as f64),
            ("messages_sent".to_owned(), sent as f64),
            ("messages_received".to_owned(), received as f64),
            ("messages_lost".to_owned(), lost as f64),
        ])
    }
}

impl DemoView {
    /// The scenario, as built.
    pub fn scenario(&self) -> &Scenario {
        &self.scenario
    }

    /// `name (seed N)`.
    pub fn title(&self) -> String {
        format!(
            "{} (seed {})",
            self.scenario.config().name,
            self.scenario.config().seed
        )
    }

    /// The static world: the street graph on flat ground.
    pub fn scene(&self) -> Scene {
        let streets = self.scenario.simulation().env().streets();
        let nodes: Vec<NodeId> = (0..streets.node_count() as u32).map(NodeId).collect();
        let mut lines = Vec::new();
        for &a in &nodes {
            for (b, _, _) in streets.neighbors(a) {
                if a < b
                    && let (Some(p), Some(q)) = (self.junction(a), self.junction(b))
                {
                    lines.push(vec![p, q]);
                }
            }
        }
        let mut ext = [f64::MAX, f64::MAX, f64::MIN, f64::MIN];
        for p in nodes.iter().filter_map(|&n| self.junction(n)) {
            ext = [
                ext[0].min(p[0]),
                ext[1].min(p[1]),
                ext[2].max(p[0]),
                ext[3].max(p[1]),
            ];
        }
        if ext[0] > ext[2] {
            ext = [0.0, 0.0, 1.0, 1.0];
        }
        let extent = [
            ext[0] - MARGIN_M,
            ext[1] - MARGIN_M,
            ext[2] + MARGIN_M,
            ext[3] + MARGIN_M,
        ];
        Scene {
            name: self.scenario.config().name.clone(),
            start_unix_ms: (self.scenario.config().start)
                .unwrap_or(vitro::time::UtcTime::DEFAULT_START)
                .unix_millis(),
            // The generated town is on no map: an arbitrary reference, for tools that want one.
            geo: Geo {
                lat0: 0.0,
                lon0: 0.0,
                m_per_deg_lat: 110_574.0,
                m_per_deg_lon: 111_320.0,
                offset: [0.0, 0.0],
                z0: 0.0,
            },
            extent,
            streets: lines,
            paths: Vec::new(),
            buildings: Vec::new(),
            bridges: Vec::new(),
            forbidden: Vec::new(),
            places: BTreeMap::new(),
            // Flat ground.
            terrain: Heightmap {
                nx: 2,
                ny: 2,
                origin: [extent[0], extent[1]],
                cell: (extent[2] - extent[0]).max(extent[3] - extent[1]),
                z: vec![0.0; 4],
            },
        }
    }

    /// The simulation's control handle.
    pub fn control(&self) -> Control {
        self.scenario.simulation().control()
    }

    /// Runs up to `until`; `Ok(false)` once the run is over (its end time or nothing left
    /// to happen).
    ///
    /// # Errors
    /// [`DemoError::AgentFailed`] if a car's controller failed.
    pub fn advance(&mut self, until: SimTime) -> Result<bool, DemoError> {
        let end = self.scenario.end();
        let until = until.min(end);
        Ok(match self.scenario.run_to(until)? {
            StopReason::Time => until < end,
            StopReason::Control | StopReason::Condition => true,
            StopReason::QueueEmpty | StopReason::Requested => false,
        })
    }

    /// The scenario, mutable (to move its end time).
    pub fn scenario_mut(&mut self) -> &mut Scenario {
        &mut self.scenario
    }

    /// The state now, shown as of `t_ns`.
    pub fn frame(&mut self, t_ns: u64) -> Frame {
        let cars = self.scenario.cars().to_vec();
        let entities: Vec<EntityState> = cars.iter().filter_map(|&c| self.car(c, t_ns)).collect();
        let intentions = entities
            .iter()
            .filter_map(|e| self.intention(EntityId(e.id), e.pos))
            .collect();
        let sensors = match self.scenario.config().channel.range_m {
            Some(range) => entities
                .iter()
                .map(|e| SensorFootprint {
                    id: e.id,
                    kind: "radio range".to_owned(),
                    range,
                    heading: 0.0,
                    fov: core::f64::consts::TAU,
                })
                .collect(),
            None => Vec::new(),
        };
        let messages = std::mem::take(&mut *self.heard.lock().unwrap_or_else(|p| p.into_inner()));
        let sim = self.scenario.simulation();
        Frame {
            t_ns,
            events: sim.events_fired(),
            metrics: self.metrics(t_ns),
            entities,
            detections: Vec::new(),
            messages,
            intentions,
            sensors,
            log: Vec::new(),
        }
    }

    /// The trace hash so far.
    pub fn trace_hash(&self) -> u64 {
        self.scenario.simulation().trace_hash()
    }
}

/// Collects the messages of `scenario`'s run into `heard` for the frames.
pub(crate) fn listen(scenario: &mut Scenario, heard: &Arc<Mutex<Vec<MessageEvent>>>) {
    let sink = heard.clone();
    scenario
        .simulation_mut()
        .add_listener(move |fired: &vitro::sim::Fired<'_, Demo>| {
            let (e, delivered) = match fired.input {
                Input::Message(e) => (e, true),
                Input::Undeliverable(e, _) => (e, false),
                _ => return,
            };
            let kind = match e.body {
                PatrolMsg::Claim { .. } => "claim",
            };
            let m = MessageEvent {
                t_ns: e.sent_at.as_nanos(),
                from: e.from.0,
                to: Some(e.receiver.0),
                kind: kind.to_owned(),
                delivered,
            };
            sink.lock().unwrap_or_else(|p| p.into_inner()).push(m);
        });
}

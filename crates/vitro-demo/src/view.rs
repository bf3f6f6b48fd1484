//! The demo's pictures: its street graph as a [`Scene`] and each instant drawn into a
//! [`Frame`], for recordings and the viewer.

use crate::DemoRun;
use crate::patrol::{Demo, Patroller};
use vitro::entity::EntityId;
use vitro::env::NodeId;
use vitro::sim::Simulation;
use vitro_record::frame::SensorFootprint;
use vitro_record::{EntityState, Frame, Intention, Scene, Side};

/// Margin around the town on the map, metres.
const MARGIN_M: f64 = 60.0;

fn junction(sim: &Simulation<Demo>, n: NodeId) -> Option<[f64; 3]> {
    let j = sim.env().streets().node(n)?;
    Some([j.x, j.y, 0.0])
}

/// The junction nearest to `p`.
fn nearest(sim: &Simulation<Demo>, p: [f64; 2]) -> Option<NodeId> {
    let streets = sim.env().streets();
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

fn car(run: &mut DemoRun, id: EntityId, t_ns: u64) -> Option<EntityState> {
    let (sim, play) = (&run.sim, &mut run.play);
    let (x, y) = sim.env().position(id)?;
    let failed = sim.agent(id).and_then(Patroller::failure).is_some();
    let (heading, speed) = match play.last.get(&id.0) {
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
    play.last.insert(id.0, ([x, y], t_ns, heading));
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

fn intention(sim: &Simulation<Demo>, id: EntityId, at: [f64; 3]) -> Option<Intention> {
    let goal = sim.agent(id)?.goal()?;
    let streets = sim.env().streets();
    let path = nearest(sim, [at[0], at[1]])
        .and_then(|from| streets.shortest_path(from, goal))
        .map(|(_, nodes)| nodes.iter().filter_map(|&n| junction(sim, n)).collect())
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

/// The static world: the street graph on flat ground.
pub fn scene(run: &DemoRun) -> Scene {
    let sim = &run.sim;
    let streets = sim.env().streets();
    let nodes: Vec<NodeId> = (0..streets.node_count() as u32).map(NodeId).collect();
    let mut lines = Vec::new();
    for &a in &nodes {
        for (b, _, _) in streets.neighbors(a) {
            if a < b
                && let (Some(p), Some(q)) = (junction(sim, a), junction(sim, b))
            {
                lines.push(vec![p, q]);
            }
        }
    }
    let mut ext = [f64::MAX, f64::MAX, f64::MIN, f64::MIN];
    for p in nodes.iter().filter_map(|&n| junction(sim, n)) {
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
    let m = MARGIN_M;
    let extent = [ext[0] - m, ext[1] - m, ext[2] + m, ext[3] + m];
    let mut scene = Scene::flat(run.name.clone(), run.start.unix_millis(), extent);
    scene.streets = lines;
    scene
}

/// Draws the cars now into `frame`: their poses, their goals, their radio ranges.
pub fn frame(run: &mut DemoRun, frame: &mut Frame) {
    let cars = run.cars().to_vec();
    let entities: Vec<EntityState> = (cars.iter())
        .filter_map(|&c| car(run, c, frame.t_ns))
        .collect();
    frame.intentions = (entities.iter())
        .filter_map(|e| intention(&run.sim, EntityId(e.id), e.pos))
        .collect();
    if let Some(range) = run.config().channel.range_m {
        frame.sensors = (entities.iter())
            .map(|e| SensorFootprint {
                id: e.id,
                kind: "radio range".to_owned(),
                range,
                heading: 0.0,
                fov: core::f64::consts::TAU,
            })
            .collect();
    }
    frame.entities = entities;
}

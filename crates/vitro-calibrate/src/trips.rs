//! The sample trips of a calibration: drawn over the town's own streets and footpaths (one
//! start on each street class in turn, a share over bridges, lengths spread over a range),
//! and run at any level, with or without a calibration.

use rand::{Rng, SeedableRng};
use rand_chacha::ChaCha8Rng;
use std::sync::Arc;
use std::sync::atomic::{AtomicUsize, Ordering};
use vitro::env::NodeId;
use vitro_check::CheckError;
use vitro_check::scenario::visit;
use vitro_tactical::actuate;
use vitro_tactical::calibration::{Calibration, Features, entity_key};
use vitro_tactical::entity::Level;
use vitro_tactical::entity::discrete::NodeKind;
use vitro_tactical::entity::roads::FreeGraph;
use vitro_tactical::entity::route::Track;
use vitro_tactical::setup::Setup;
use vitro_tactical::types::{GroundKind, TroopKind};

/// Largest start heading off the way a sample trip is given, radians: 120°, past the right
/// angle of a turn onto the next street at a junction where a leg ended, so that the
/// start-turn terms are fitted over the whole range a mission's legs need (a U-turn is
/// another manoeuvre, which the model does not describe).
pub const MAX_START_OFF: f64 = 2.0 * std::f64::consts::FRAC_PI_3;

/// One sample trip.
#[derive(Copy, Clone, Debug, PartialEq)]
pub struct Trip {
    /// What drives or walks it.
    pub kind: NodeKind,
    /// Start node.
    pub from: NodeId,
    /// Goal node.
    pub to: NodeId,
    /// True if the fit may use it (else it is held out for evaluation).
    pub fit: bool,
    /// The body's start heading off the path's first piece, radians (every other trip
    /// starts turned by an angle drawn up to [`MAX_START_OFF`]: a start off the way, as at
    /// a leg's end).
    pub start_off: f64,
}

/// How many trips to draw, and how long.
#[derive(Clone, Debug, PartialEq)]
pub struct Sampling {
    /// Trips per entity type used by the fit.
    pub fit_per_type: usize,
    /// Trips per entity type held out.
    pub held_out_per_type: usize,
    /// Path length range of vehicle trips, metres.
    pub drive_m: (f64, f64),
    /// Path length range of trooper trips, metres.
    pub walk_m: (f64, f64),
    /// The entity types (default: every vehicle and trooper type).
    pub kinds: Vec<NodeKind>,
    /// Seed of the draw.
    pub seed: u64,
}

impl Default for Sampling {
    fn default() -> Self {
        Sampling {
            fit_per_type: 16,
            held_out_per_type: 8,
            drive_m: (150.0, 1600.0),
            walk_m: (60.0, 500.0),
            kinds: GroundKind::ALL
                .iter()
                .map(|&k| NodeKind::Ground(k))
                .chain(TroopKind::ALL.iter().map(|&k| NodeKind::Troop(k)))
                .collect(),
            seed: 1,
        }
    }
}

/// The two end nodes of a street segment.
type Ends = (NodeId, NodeId);

/// The main-part nodes of `g` at the ends of a segment of each street class (classes in
/// name order), and of bridge segments.
fn starts(setup: &Setup, g: &FreeGraph) -> (Vec<Vec<Ends>>, Vec<Ends>) {
    let sg = setup.site.map.streets(g.mode);
    let mut by_class: std::collections::BTreeMap<&str, Vec<(NodeId, NodeId)>> =
        std::collections::BTreeMap::new();
    let mut bridges = Vec::new();
    for (i, seg) in sg.segments.iter().enumerate() {
        let main = |n: NodeId| g.main.get(n.0 as usize).copied().unwrap_or(false);
        if g.blocked.get(i).copied().unwrap_or(true) || !main(seg.from) || !main(seg.to) {
            continue;
        }
        by_class
            .entry(seg.class.as_str())
            .or_default()
            .push((seg.from, seg.to));
        if seg.bridge {
            bridges.push((seg.from, seg.to));
        }
    }
    (by_class.into_values().collect(), bridges)
}

/// Draws the sample trips: per entity type, starts taken on each street class in turn
/// (every fourth over a bridge, where the mode has one), goals drawn until the path's length
/// is in range. The first `fit_per_type` trips of a type are fitted, the rest held out.
pub fn sample(setup: &Setup, s: &Sampling) -> Vec<Trip> {
    let mut out = Vec::new();
    for (ki, &kind) in s.kinds.iter().enumerate() {
        let g = setup.roads.of(kind.mode());
        let (classes, bridges) = starts(setup, g);
        let mains: Vec<NodeId> = (0..g.graph.node_count() as u32)
            .map(NodeId)
            .filter(|n| g.main[n.0 as usize])
            .collect();
        if mains.len() < 2 || classes.is_empty() {
            continue;
        }
        let (lo, hi) = match kind {
            NodeKind::Ground(_) => s.drive_m,
            NodeKind::Troop(_) => s.walk_m,
        };
        let mut rng = ChaCha8Rng::seed_from_u64(s.seed);
        rng.set_stream(ki as u64 + 1);
        let total = s.fit_per_type + s.held_out_per_type;
        let mut made = 0;
        let mut tries = 0;
        while made < total && tries < 200 * total {
            tries += 1;
            let over_bridge = made % 4 == 3 && !bridges.is_empty();
            let (from, first) = if over_bridge {
                bridges[rng.random_range(0..bridges.len())]
            } else {
                let c = &classes[made % classes.len()];
                let (a, b) = c[rng.random_range(0..c.len())];
                if rng.random_bool(0.5) { (a, b) } else { (b, a) }
            };
            // Goals whose straight-line distance could give a path length in range.
            let Some(at) = g.graph.node(from).map(|n| n.pos) else {
                continue;
            };
            let near: Vec<NodeId> = mains
                .iter()
                .copied()
                .filter(|&n| {
                    g.graph.node(n).is_some_and(|q| {
                        let d = vitro_site::geo::dist(at, q.pos);
                        d >= 0.5 * lo && d <= hi
                    })
                })
                .collect();
            if near.is_empty() {
                continue;
            }
            let to = near[rng.random_range(0..near.len())];
            let Ok(path) = g.path(from, to) else { continue };
            if over_bridge && path.get(1) != Some(&first) {
                continue;
            }
            let len: f64 = path
                .windows(2)
                .filter_map(|w| {
                    g.graph
                        .neighbors(w[0])
                        .filter(|(t, _, _)| *t == w[1])
                        .map(|(_, l, _)| l)
                        .min_by(f64::total_cmp)
                })
                .sum();
            if len < lo || len > hi {
                continue;
            }
            let start_off = if made % 2 == 1 {
                rng.random_range(-MAX_START_OFF..MAX_START_OFF)
            } else {
                0.0
            };
            out.push(Trip {
                kind,
                from,
                to,
                fit: made < s.fit_per_type,
                start_off,
            });
            made += 1;
        }
    }
    out
}

/// The planned (uncalibrated) track of a trip.
pub fn track(setup: &Setup, t: &Trip) -> Result<Track, CheckError> {
    let name = entity_key(t.kind);
    let err = |e: vitro_tactical::entity::roads::RouteError| CheckError::Scenario {
        scenario: name.clone(),
        message: e.to_string(),
    };
    let g = setup.roads.of(t.kind.mode());
    let path = g.path(t.from, t.to).map_err(err)?;
    match t.kind {
        NodeKind::Ground(k) => Track::plan_vehicle(
            &setup.site,
            g,
            &path,
            setup.types.ground(k),
            &setup.types.speed_limits,
        ),
        NodeKind::Troop(k) => Track::plan_walk(
            &setup.site,
            g,
            &path,
            &setup.types.troops,
            setup.types.troops.of(k).load,
        ),
    }
    .map_err(err)
}

/// The street classes a trip's path uses (sorted, `+` separated) and whether it crosses a
/// bridge.
pub fn coverage(setup: &Setup, t: &Trip) -> (String, bool) {
    let g = setup.roads.of(t.kind.mode());
    let sg = setup.site.map.streets(g.mode);
    let Ok(path) = g.path(t.from, t.to) else {
        return (String::new(), false);
    };
    let mut classes = std::collections::BTreeSet::new();
    let mut bridge = false;
    for w in path.windows(2) {
        if let Some((_, _, e)) = g.graph.neighbors(w[0]).find(|(n, _, _)| *n == w[1])
            && let Some(seg) = sg.segments.get(e.segment as usize)
        {
            classes.insert(seg.class.clone());
            bridge |= seg.bridge;
        }
    }
    (classes.into_iter().collect::<Vec<_>>().join("+"), bridge)
}

/// The body's heading at a trip's start.
fn start_heading(tr: &Track, t: &Trip) -> f64 {
    vitro_tactical::entity::route::wrap_angle(tr.heading_at(0.0) + t.start_off)
}

/// The features of a trip's uncalibrated track, started at the trip's heading.
pub fn features(setup: &Setup, t: &Trip) -> Result<Features, CheckError> {
    track(setup, t).map(|tr| Features::starting(&tr, start_heading(&tr, t)))
}

/// Runs `t` at `level` (with `calibration` on the arena if given) and returns its arrival
/// time, seconds (`None`: it did not arrive within three times its profile time + 300 s).
pub fn run(
    setup: &Setup,
    t: &Trip,
    level: Level,
    calibration: Option<Arc<Calibration>>,
) -> Result<Option<f64>, CheckError> {
    let tr = track(setup, t)?;
    let heading = start_heading(&tr, t);
    let limit = 3.0 * tr.duration() + 300.0;
    let name = entity_key(t.kind);
    let setup = Setup {
        calibration,
        ..setup.clone()
    };
    let (from, to) = (t.from, t.to);
    let r = match t.kind {
        NodeKind::Ground(kind) => {
            let place = move |a: &mut vitro_tactical::arena::Arena, id| {
                a.add_vehicle(id, kind, level, from, heading)
            };
            match level {
                Level::Discrete => visit(
                    &setup,
                    &name,
                    to,
                    actuate::ground::discrete::GoToNode,
                    place,
                    limit,
                )?,
                Level::Interpolated => visit(
                    &setup,
                    &name,
                    to,
                    actuate::ground::interpolated::GoToNode,
                    place,
                    limit,
                )?,
                _ => visit(
                    &setup,
                    &name,
                    to,
                    actuate::ground::physical::GoToNode,
                    place,
                    limit,
                )?,
            }
        }
        NodeKind::Troop(kind) => {
            let place = move |a: &mut vitro_tactical::arena::Arena, id| {
                a.add_trooper(id, kind, level, from, heading)
            };
            match level {
                Level::Discrete => visit(
                    &setup,
                    &name,
                    to,
                    actuate::troop::discrete::WalkToNode,
                    place,
                    limit,
                )?,
                _ => visit(
                    &setup,
                    &name,
                    to,
                    actuate::troop::directed::WalkToNode,
                    place,
                    limit,
                )?,
            }
        }
    };
    Ok(r.arrival)
}

/// The levels of a kind: its concrete one and its abstract ones (the interpolated level
/// only for vehicles).
pub fn levels(kind: NodeKind) -> (Level, Vec<Level>) {
    match kind {
        NodeKind::Ground(_) => (Level::Physical, vec![Level::Discrete, Level::Interpolated]),
        NodeKind::Troop(_) => (Level::Directed, vec![Level::Discrete]),
    }
}

/// Maps `f` over `items` on `threads` threads; results in the items' order whatever the
/// thread count (each item is computed alone). `tick` is called after each item.
pub fn par_map<T: Sync, R: Send>(
    items: &[T],
    threads: usize,
    f: impl Fn(&T) -> R + Sync,
    tick: &(dyn Fn() + Sync),
) -> Vec<R> {
    let next = AtomicUsize::new(0);
    let mut slots: Vec<Option<R>> = (0..items.len()).map(|_| None).collect();
    let threads = threads.clamp(1, items.len().max(1));
    std::thread::scope(|sc| {
        let handles: Vec<_> = (0..threads)
            .map(|_| {
                sc.spawn(|| {
                    let mut got = Vec::new();
                    loop {
                        let i = next.fetch_add(1, Ordering::Relaxed);
                        let Some(item) = items.get(i) else { break };
                        got.push((i, f(item)));
                        tick();
                    }
                    got
                })
            })
            .collect();
        for h in handles {
            if let Ok(got) = h.join() {
                for (i, r) in got {
                    slots[i] = Some(r);
                }
            }
        }
    });
    slots.into_iter().flatten().collect()
}

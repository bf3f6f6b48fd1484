//! Builds the village-scale patrolling instance `data/patrol/village.{toml,edges,pos}` from the
//! real town's walking graph (`data/town/kotka_walk.{edges,pos}`, exported from the
//! OpenStreetMap extract `data/maps/kotka.osm.pbf`).
//!
//! `cargo run --release -p vitro-algo --example patrol_village_data [-- OUT_DIR]`
//!
//! - **Graph**: the town coarsened into square cells of [`CELL`] metres. Every street (a
//!   straight segment between two junctions) is walked in short steps; each cell it passes
//!   through is a vertex and consecutive cells along it are joined. So one step of the game
//!   is one cell (about 200 m: some 10 s for a patrol UAV at 20 m/s), and cells a street only
//!   crosses are vertices too. Vertices are numbered by cell row (south first), then column
//!   (west first); `village.pos` gives each cell's centre.
//! - **Convoys**: three convoys shuttle between the depot (the junction with the least mean
//!   walking distance to all others, the town's graph median) and three districts (junctions
//!   [`DESTINATIONS`], about 1 km away to the north-east, west and south), along the shortest
//!   walking route in metres (the walking graph is the street graph exported to `data/town`;
//!   the west and south routes share their first six cells), mapped to cells. A convoy takes
//!   two steps per cell (half the patrol units' speed), waits at the district, drives back and
//!   waits at the depot; all three keep one timetable of [`PERIOD`] steps, leaving the depot
//!   [`PERIOD`]` / 3` steps apart.
//! - **Attacks** take [`DEADLINE`] steps (with 6, the solver finds no two-unit patrol that
//!   keeps every convoy within reach: some attack always escapes); every convoy is worth 1.
//!
//! The test `tests/patrol_village.rs` rebuilds the files and checks they match the committed
//! ones.

use std::collections::{BTreeMap, BTreeSet, BinaryHeap};
use std::fmt::Write as _;
use std::path::Path;

/// Side of a cell, metres.
const CELL: f64 = 200.0;
/// The districts' junctions (ids of `kotka_walk`): north-east, west, south.
const DESTINATIONS: [(usize, &str); 3] = [(212, "north-east"), (196, "west"), (89, "south")];
/// Steps of the common timetable.
const PERIOD: usize = 48;
/// Steps an attack takes.
const DEADLINE: u32 = 8;
/// Steps a convoy waits at its district.
const DWELL: usize = 4;

#[allow(dead_code)] // The test `tests/patrol_village.rs` includes this file for `build`.
fn main() -> Result<(), Box<dyn std::error::Error>> {
    let root = concat!(env!("CARGO_MANIFEST_DIR"), "/../..");
    let out = std::env::args()
        .nth(1)
        .unwrap_or_else(|| format!("{root}/data/patrol"));
    let files = build(Path::new(&format!("{root}/data/town")))?;
    for (name, text) in &files {
        std::fs::write(Path::new(&out).join(name), text)?;
    }
    println!("wrote {} files to {out}", files.len());
    Ok(())
}

/// The three files `(name, text)`: `village.edges`, `village.pos`, `village.toml`.
pub fn build(town: &Path) -> Result<Vec<(String, String)>, Box<dyn std::error::Error>> {
    let pos = read_positions(&town.join("kotka_walk.pos"))?;
    let streets = read_edges(&town.join("kotka_walk.edges"))?;
    // Cells along every street, and the cell graph.
    let cell = |p: [f64; 2]| ((p[1] / CELL).floor() as i64, (p[0] / CELL).floor() as i64);
    let along = |a: usize, b: usize| -> Vec<(i64, i64)> {
        let (pa, pb) = (pos[a], pos[b]);
        let length = ((pa[0] - pb[0]).powi(2) + (pa[1] - pb[1]).powi(2)).sqrt();
        let pieces = ((length / (CELL / 20.0)).ceil() as usize).max(1);
        let mut cells: Vec<(i64, i64)> = Vec::new();
        for i in 0..=pieces {
            let f = i as f64 / pieces as f64;
            let c = cell([pa[0] + f * (pb[0] - pa[0]), pa[1] + f * (pb[1] - pa[1])]);
            if cells.last() != Some(&c) {
                cells.push(c);
            }
        }
        cells
    };
    let mut cells = BTreeSet::new();
    let mut links = BTreeSet::new();
    for &(a, b) in &streets {
        let line = along(a, b);
        cells.extend(line.iter().copied());
        for w in line.windows(2) {
            links.insert((w[0].min(w[1]), w[0].max(w[1])));
        }
    }
    let id: BTreeMap<(i64, i64), usize> = cells.iter().enumerate().map(|(i, &c)| (c, i)).collect();
    // Junction graph with lengths, for routes.
    let mut adjacent: Vec<Vec<(usize, f64)>> = vec![Vec::new(); pos.len()];
    for &(a, b) in &streets {
        let d = ((pos[a][0] - pos[b][0]).powi(2) + (pos[a][1] - pos[b][1]).powi(2)).sqrt();
        adjacent[a].push((b, d));
        adjacent[b].push((a, d));
    }
    let depot = (0..pos.len())
        .map(|j| (dijkstra(&adjacent, j).0.iter().sum::<f64>(), j))
        .min_by(|a, b| a.0.total_cmp(&b.0).then(a.1.cmp(&b.1)))
        .map(|(_, j)| j)
        .ok_or("empty town")?;
    let (distance, previous) = dijkstra(&adjacent, depot);
    let mut convoys = Vec::new();
    for (k, &(destination, district)) in DESTINATIONS.iter().enumerate() {
        let mut junctions = vec![destination];
        while let Some(&j) = junctions.last().filter(|&&j| j != depot) {
            junctions.push(previous[j].ok_or("district unreachable from the depot")?);
        }
        junctions.reverse();
        let mut route: Vec<usize> = Vec::new();
        for w in junctions.windows(2) {
            for c in along(w[0], w[1]) {
                let v = id[&c];
                if route.last() != Some(&v) {
                    route.push(v);
                }
            }
        }
        let schedule = timetable(&route, k * PERIOD / DESTINATIONS.len())?;
        convoys.push((
            district,
            destination,
            distance[destination],
            route,
            schedule,
        ));
    }
    let header = format!(
        "# The village: data/town/kotka_walk (the walking graph of data/maps/kotka.osm.pbf,\n\
         # (c) OpenStreetMap contributors, ODbL 1.0) coarsened into {CELL} m cells by\n\
         # crates/vitro-algo/examples/patrol_village_data.rs: {} cells, {} links.\n",
        cells.len(),
        links.len()
    );
    let mut edges = header.clone();
    for (a, b) in &links {
        writeln!(edges, "{} {}", id[a], id[b])?;
    }
    let mut positions = header.clone();
    positions
        .push_str("# id x y: the cell's centre, town metres east / north of the map's centre\n");
    for (i, &(row, col)) in cells.iter().enumerate() {
        let (x, y) = ((col as f64 + 0.5) * CELL, (row as f64 + 0.5) * CELL);
        writeln!(positions, "{i} {x:.1} {y:.1}")?;
    }
    let mut toml = header;
    write!(
        toml,
        "# One step: a patrol unit moves one cell (or stays). Three convoys shuttle between the\n\
         # depot (junction {depot}, cell {}) and three districts along the shortest walking\n\
         # routes, two steps per cell, waiting {DWELL} steps at the district and the rest of a\n\
         # {PERIOD}-step timetable at the depot, leaving {} steps apart. Attacks take {DEADLINE} steps.\n\
         # Two patrol units. Solve with `vitro solve patrol data/patrol/village.toml --phase-locked`.\n\n\
         [graph]\nfile = \"village.edges\"\n",
        id[&cell(pos[depot])],
        PERIOD / DESTINATIONS.len()
    )?;
    for (district, destination, metres, route, schedule) in &convoys {
        let cells: Vec<String> = route.iter().map(usize::to_string).collect();
        let steps: Vec<String> = schedule.iter().map(usize::to_string).collect();
        write!(
            toml,
            "\n# To the {district} district (junction {destination}), {metres:.0} m: cells {}.\n\
             [[target]]\nname = \"convoy {district}\"\nschedule = [{}]\nvalue = 1\ndeadline = {DEADLINE}\n",
            cells.join(" "),
            steps.join(", ")
        )?;
    }
    toml.push_str("\n[[patroller]]\nname = \"uav 1\"\n\n[[patroller]]\nname = \"uav 2\"\n");
    Ok(vec![
        ("village.edges".into(), edges),
        ("village.pos".into(), positions),
        ("village.toml".into(), toml),
    ])
}

/// The convoy's cell at every step of the timetable: out along `route` (two steps per cell),
/// [`DWELL`] steps at the end, back, and waiting at the depot for the rest of the period;
/// shifted to leave the depot at step `departure`.
fn timetable(route: &[usize], departure: usize) -> Result<Vec<usize>, String> {
    let mut trip: Vec<usize> = Vec::new();
    for &v in route {
        trip.extend([v, v]);
    }
    let last = *route.last().ok_or("empty route")?;
    trip.extend(std::iter::repeat_n(last, DWELL));
    for &v in route[..route.len() - 1].iter().rev() {
        trip.extend([v, v]);
    }
    if trip.len() > PERIOD {
        return Err(format!(
            "a round trip of {} steps exceeds the period",
            trip.len()
        ));
    }
    trip.resize(PERIOD, route[0]);
    trip.rotate_right(departure);
    Ok(trip)
}

/// Shortest distances and predecessors from `source`.
fn dijkstra(adjacent: &[Vec<(usize, f64)>], source: usize) -> (Vec<f64>, Vec<Option<usize>>) {
    let mut distance = vec![f64::INFINITY; adjacent.len()];
    let mut previous = vec![None; adjacent.len()];
    let mut heap = BinaryHeap::new();
    distance[source] = 0.0;
    heap.push((std::cmp::Reverse(Metres(0.0)), source));
    while let Some((std::cmp::Reverse(Metres(d)), u)) = heap.pop() {
        if d > distance[u] {
            continue;
        }
        for &(v, w) in &adjacent[u] {
            if d + w < distance[v] {
                distance[v] = d + w;
                previous[v] = Some(u);
                heap.push((std::cmp::Reverse(Metres(d + w)), v));
            }
        }
    }
    (distance, previous)
}

/// A totally ordered distance for the heap.
struct Metres(f64);
impl PartialEq for Metres {
    fn eq(&self, other: &Self) -> bool {
        self.cmp(other).is_eq()
    }
}
impl Eq for Metres {}
impl PartialOrd for Metres {
    fn partial_cmp(&self, other: &Self) -> Option<std::cmp::Ordering> {
        Some(self.cmp(other))
    }
}
impl Ord for Metres {
    fn cmp(&self, other: &Self) -> std::cmp::Ordering {
        self.0.total_cmp(&other.0)
    }
}

fn read_positions(path: &Path) -> Result<Vec<[f64; 2]>, Box<dyn std::error::Error>> {
    let mut pos = Vec::new();
    for line in std::fs::read_to_string(path)?.lines() {
        let fields: Vec<&str> = line.split_whitespace().collect();
        if line.starts_with('#') || fields.len() < 3 {
            continue;
        }
        if fields[0].parse::<usize>()? != pos.len() {
            return Err(format!("{}: ids out of order at {line}", path.display()).into());
        }
        pos.push([fields[1].parse()?, fields[2].parse()?]);
    }
    Ok(pos)
}

fn read_edges(path: &Path) -> Result<Vec<(usize, usize)>, Box<dyn std::error::Error>> {
    let mut edges = Vec::new();
    for line in std::fs::read_to_string(path)?.lines() {
        let fields: Vec<&str> = line.split_whitespace().collect();
        if line.starts_with('#') || fields.len() < 2 {
            continue;
        }
        edges.push((fields[0].parse()?, fields[1].parse()?));
    }
    Ok(edges)
}

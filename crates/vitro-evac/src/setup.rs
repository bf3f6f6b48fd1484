//! Building a mission from a validated scenario: the arena, the briefing, every entity's
//! body, condition and agent, the channel and the start events.

use super::act::{Dismount, Drive, Pilot, Walk};
use super::agents::air::{AirRole, Aircraft};
use super::agents::commander::Commander;
use super::agents::hunt::Board;
use super::agents::patrol::attack::Attacker;
use super::agents::patrol::{PatrolGame, PatrolUnit};
use super::agents::red::{Adversary, Hvt};
use super::agents::trooper::Trooper;
use super::agents::ugv::Ugv;
use super::brief::{Brief, FormationBrief};
use crate::error::MissionError;
use crate::external::{External, SharedDesk};
use crate::member::Member;
use crate::radio::Evac;
use crate::scenario::{ScenarioFile, Validated};
use rand::{Rng, SeedableRng};
use rand_chacha::ChaCha8Rng;
use std::collections::BTreeSet;
use std::sync::Arc;
use vitro::entity::EntityId;
use vitro::env::NodeId;
use vitro::event::Target;
use vitro::sim::Simulation;
use vitro::time::{SimDuration, SimTime};
use vitro_algo::graph::Graph;
use vitro_algo::pursuit::VisibilityGraph;
use vitro_behaviour::formation::{FormationParams, LEADER_PROGRAM, Leader};
use vitro_behaviour::route::VisitNodes;
use vitro_site::geo::{P2, dist};
use vitro_site::map::Mode;
use vitro_site::site::Site;
use vitro_tactical::arena::{Arena, Ev};
use vitro_tactical::condition::{Condition, Role, Status};
use vitro_tactical::entity::roads::FreeGraph;
use vitro_tactical::model::Controller;
use vitro_tactical::scenario::{EntityType, TieOrder};
use vitro_tactical::types::{CtolKind, GroundKind, TroopKind, TypeBook, VtolKind};
use vitro_tactical::world::Side;

/// Length of a drive leg (the commander stops at the end of each), metres.
const LEG_M: f64 = 400.0;
/// Range of the line-of-sight visibility between walk nodes on the pursuit board, metres.
const BOARD_SIGHT_M: f64 = 150.0;
/// Eye height of a person, metres.
const EYE_M: f64 = 1.7;
/// The formation's deliberation period at the discrete level, where a trooper hops whole
/// walk-graph edges (tens of seconds each) and a half-second cycle would only repeat itself.
const DISCRETE_PERIOD: SimDuration = SimDuration::from_secs(2);

/// Every entity the file asks for, in file order (counts expanded), with its id.
pub(crate) fn roster(file: &ScenarioFile) -> Vec<Member> {
    let mut out = Vec::new();
    for e in &file.entities {
        for i in 0..e.count.max(1) {
            let name = if e.count > 1 {
                format!("{}-{}", e.name, i + 1)
            } else {
                e.name.clone()
            };
            out.push(Member {
                id: EntityId(out.len() as u32),
                name,
                kind: e.kind,
                role: e.kind.into(),
                side: e.side.side(),
                level: file.fidelity.level_of(e.kind),
                start: e.start,
                altitude: e.altitude_m,
            });
        }
    }
    out
}

fn node_pos(g: &FreeGraph, n: NodeId) -> P2 {
    g.graph.node(n).map_or([0.0, 0.0], |s| s.pos)
}

/// Splits a path into legs of about [`LEG_M`]: the last node of each.
fn legs(g: &FreeGraph, path: &[NodeId]) -> Vec<NodeId> {
    let mut out = Vec::new();
    let mut run = 0.0;
    for w in path.windows(2) {
        run += dist(node_pos(g, w[0]), node_pos(g, w[1]));
        if run >= LEG_M {
            out.push(w[1]);
            run = 0.0;
        }
    }
    if let Some(&last) = path.last()
        && out.last() != Some(&last)
    {
        out.push(last);
    }
    out
}

/// The walk graph as a pursuit board: undirected street edges, and visibility between
/// nodes within [`BOARD_SIGHT_M`] that see each other over terrain and buildings.
fn board(site: &Site, walk: &FreeGraph) -> Result<Board, MissionError> {
    let n = walk.graph.node_count();
    let mut edges = Vec::new();
    for u in 0..n as u32 {
        for (v, _, _) in walk.graph.neighbors(NodeId(u)) {
            if u < v.0 {
                edges.push((u as usize, v.0 as usize));
            }
        }
    }
    edges.sort_unstable();
    edges.dedup();
    let graph = Graph::from_edges(n, &edges).map_err(|e| MissionError::Setup(e.to_string()))?;
    let pts: Vec<[f64; 3]> = (0..n as u32)
        .map(|u| site.on_ground(node_pos(walk, NodeId(u))))
        .collect();
    let mut sight = Vec::new();
    for u in 0..n {
        for v in u + 1..n {
            let (a, b) = (pts[u], pts[v]);
            if libm::hypot(a[0] - b[0], a[1] - b[1]) > BOARD_SIGHT_M {
                continue;
            }
            let eye = [a[0], a[1], a[2] + EYE_M];
            let target = [b[0], b[1], b[2] + EYE_M / 2.0];
            if site.los.visible(eye, target) {
                sight.push((u, v));
            }
        }
    }
    let vis = Graph::from_edges(n, &sight).map_err(|e| MissionError::Setup(e.to_string()))?;
    Board::new(graph, &VisibilityGraph(vis)).map_err(|e| MissionError::Setup(e.to_string()))
}

/// A random main-part node of `g` between `near` and `far` metres from `from` (town
/// metres), or the nearest one to `from` if none is.
fn random_node(g: &FreeGraph, rng: &mut ChaCha8Rng, from: P2, near: f64, far: f64) -> NodeId {
    random_free_node(g, rng, from, near, far, &BTreeSet::new())
}

/// [`random_node`] avoiding the nodes in `taken`.
fn random_free_node(
    g: &FreeGraph,
    rng: &mut ChaCha8Rng,
    from: P2,
    near: f64,
    far: f64,
    taken: &BTreeSet<NodeId>,
) -> NodeId {
    let candidates: Vec<NodeId> = (0..g.graph.node_count() as u32)
        .map(NodeId)
        .filter(|&n| g.main[n.0 as usize] && !taken.contains(&n))
        .filter(|&n| (near..=far).contains(&dist(node_pos(g, n), from)))
        .collect();
    if candidates.is_empty() {
        // The free main-part node nearest to `from`.
        return (0..g.graph.node_count() as u32)
            .map(NodeId)
            .filter(|&n| g.main[n.0 as usize] && !taken.contains(&n))
            .min_by(|&a, &b| {
                dist(node_pos(g, a), from)
                    .total_cmp(&dist(node_pos(g, b), from))
                    .then(a.cmp(&b))
            })
            .unwrap_or(NodeId(0));
    }
    candidates[rng.random_range(0..candidates.len())]
}

/// What [`build`] returns.
pub(crate) struct Built {
    pub sim: Simulation<Evac>,
    pub brief: Arc<Brief>,
    pub members: Vec<Member>,
}

/// Builds the simulation of `v` with `seed`; the units `external` names get an external
/// controller meeting at its desk instead of their own.
pub(crate) fn build(
    v: Validated,
    seed: u64,
    external: Option<(&[String], &SharedDesk)>,
) -> Result<Built, MissionError> {
    let file = &v.loaded.file;
    let (site, roads) = (v.site.clone(), v.roads());
    let members = roster(file);
    let find = |r: Role| members.iter().filter(move |m| m.role == r);
    let one = |r: Role| {
        find(r)
            .map(|m| m.id)
            .next()
            .ok_or_else(|| MissionError::Setup(format!("the scenario has no {}", r.name())))
    };
    let truck = one(Role::Truck)?;
    let vip = one(Role::Vip)?;
    let hvt = find(Role::Hvt).map(|m| m.id).next();
    let team: Vec<EntityId> = find(Role::Trooper)
        .filter(|m| m.side == Side::Blue)
        .map(|m| m.id)
        .collect();

    let drive = roads.of(Mode::Drive);
    let walk = roads.of(Mode::Walk);
    let p = &file.places;
    let node = |g: &FreeGraph, at: P2, what: &str| {
        g.nearest_connected(at)
            .ok_or_else(|| MissionError::Setup(format!("no street near the {what}")))
    };
    let (start, safe, extr) = (
        node(drive, p.start, "start")?,
        node(drive, p.safehouse, "safehouse")?,
        node(drive, p.extraction, "extraction point")?,
    );
    let route_err =
        |e: vitro_tactical::entity::roads::RouteError| MissionError::Setup(e.to_string());
    let out_path = drive.path(start, safe).map_err(route_err)?;
    let back_path = drive.path(safe, extr).map_err(route_err)?;
    let mut route = out_path.clone();
    route.extend(back_path.iter().skip(1));
    // The VIP waits where the file puts it (the escort fetches it on foot from the
    // safehouse's crossroads), else at the safehouse.
    let vip_at = find(Role::Vip).find_map(|m| m.start).unwrap_or(p.safehouse);
    let vip_node = node(walk, vip_at, "VIP")?;
    let trooper_level = file.fidelity.level_of(EntityType::Trooper);
    let ty = TypeBook::builtin();
    let board = match hvt {
        Some(_) => Some(Arc::new(board(&site, walk)?)),
        None => None,
    };
    let formation = formation_brief(&v.loaded, trooper_level)?;
    let brief = Arc::new(Brief {
        site: site.clone(),
        roads: roads.clone(),
        truck,
        team: team.clone(),
        vip,
        hvt,
        legs_out: legs(drive, &out_path),
        legs_back: legs(drive, &back_path),
        route,
        vip_node,
        places: [
            site.on_ground(p.start),
            site.on_ground(p.safehouse),
            site.on_ground(p.extraction),
        ],
        trooper_level,
        mission: file.mission.clone(),
        sensors: file.sensors.clone(),
        patrol: file.patrol.clone(),
        pursuit: file.pursuit.clone(),
        repair: file.repair.clone(),
        board,
        turn_s: turn_seconds(walk),
        formation,
    });

    let mut arena = Arena::with(site.clone(), roads.clone(), Arc::new(ty.clone()));
    arena.calibration = v.calibration.clone();
    let mut sim = Simulation::<Evac>::new(arena, seed);
    if file.tie_order == TieOrder::Shuffled {
        sim.shuffle_ties();
    }
    sim.network_mut().set_default_link(file.channel.link());
    // The Skeldars' patrol game, solved once (from the scenario's own seed: every run of a
    // scenario flies the same plan, drawing its moves from its own seed).
    let skeldars: Vec<EntityId> = find(Role::Skeldar).map(|m| m.id).collect();
    let patrol = match skeldars.len() {
        0 => None,
        units => Some(Arc::new(PatrolGame::build(&brief, ty, units, file.seed)?)),
    };
    let mut rng = ChaCha8Rng::seed_from_u64(seed ^ 0x5ce1_a410);
    let mut aircraft_slot = 0;
    // The first red troopers play the patrol game's attacker.
    let mut attackers = file.patrol.attackers;
    // Drive-graph nodes holding a vehicle: two rigid bodies must not start in one place.
    let mut taken = BTreeSet::new();
    for m in &members {
        let agent: Box<dyn Controller<Evac>> = match m.role {
            Role::Truck => Box::new(Commander::new(
                brief.clone(),
                Drive(m.level),
                Dismount {
                    level: trooper_level,
                },
            )),
            Role::Trooper if m.side == Side::Blue => {
                Box::new(Trooper::new(brief.clone(), Walk(m.level)))
            }
            Role::Vip => Box::new(Trooper::new(brief.clone(), Walk(m.level))),
            Role::Trooper => match &patrol {
                Some(game) if attackers > 0 => {
                    attackers -= 1;
                    let attacker = Attacker::new(game.clone(), skeldars.clone());
                    Box::new(Adversary::attacking(brief.clone(), attacker))
                }
                _ => Box::new(Adversary::new(brief.clone())),
            },
            Role::Hvt => Box::new(Hvt::new(brief.clone(), Walk(m.level))),
            Role::Car => {
                let stops = (0..6)
                    .map(|_| random_node(drive, &mut rng, [0.0, 0.0], 0.0, 1.0e9))
                    .collect();
                let mut v = VisitNodes::new(stops, Drive(m.level));
                v.repeat = true;
                Box::new(v)
            }
            Role::Ugv => Box::new(Ugv::new(brief.clone(), Drive(m.level))),
            Role::Procerus | Role::Vidar | Role::Skeldar => {
                let role = match m.role {
                    Role::Skeldar => AirRole::Patrol,
                    Role::Vidar => {
                        aircraft_slot += 1;
                        AirRole::Cover {
                            slot: aircraft_slot - 1,
                        }
                    }
                    _ => AirRole::Scout,
                };
                let height = m.altitude.unwrap_or(100.0);
                let pilot = Pilot(m.level);
                let unit = skeldars.iter().position(|&id| id == m.id);
                match (role, &patrol, unit) {
                    (AirRole::Cover { slot }, _, _) => {
                        let team = find(Role::Vidar).map(|v| v.id).collect();
                        Box::new(Aircraft::cover(brief.clone(), pilot, team, slot, height))
                    }
                    (AirRole::Patrol, Some(game), Some(unit)) => {
                        let unit = PatrolUnit::new(game.clone(), unit);
                        Box::new(Aircraft::patrol(brief.clone(), pilot, unit, height))
                    }
                    _ => Box::new(Aircraft::new(brief.clone(), pilot, role, height)),
                }
            }
        };
        let agent = match external.filter(|(names, _)| names.contains(&m.name)) {
            Some((_, desk)) => match External::for_member(m, brief.clone(), desk.clone()) {
                Some(e) => Box::new(e),
                None => agent,
            },
            None => agent,
        };
        let id = sim
            .add_agent(m.name.clone(), agent)
            .map_err(|e| MissionError::Setup(e.to_string()))?;
        if id != m.id {
            return Err(MissionError::Setup(format!(
                "entity {} got id {id:?}",
                m.name
            )));
        }
        place(&mut sim, m, &brief, &mut rng, &mut taken)?;
    }
    for m in &members {
        sim.schedule(SimTime::ZERO, Target::Entity(m.id), Ev::Start)
            .map_err(|e| MissionError::Setup(e.to_string()))?;
    }
    Ok(Built {
        sim,
        brief,
        members,
    })
}

/// Places `m`'s body (if it has one at the start) and its condition.
fn place(
    sim: &mut Simulation<Evac>,
    m: &Member,
    brief: &Brief,
    rng: &mut ChaCha8Rng,
    taken: &mut BTreeSet<NodeId>,
) -> Result<(), MissionError> {
    let roads = brief.roads.clone();
    let (drive, walk) = (roads.of(Mode::Drive), roads.of(Mode::Walk));
    let start_town = brief.site.to_town([brief.places[0][0], brief.places[0][1]]);
    let safe_town = brief.site.to_town([brief.places[1][0], brief.places[1][1]]);
    let at = |g: &FreeGraph, p: Option<[f64; 2]>, default: P2| {
        g.nearest_connected(p.unwrap_or(default))
            .unwrap_or(NodeId(0))
    };
    let w: &mut Arena = sim.env_mut();
    let mut cond = Condition::new(m.role, m.side, m.role.height());
    let err =
        |e: vitro_tactical::arena::PlaceError| MissionError::Setup(format!("{}: {e}", m.name));
    let heading = 0.0;
    match m.role {
        Role::Truck => {
            let n = at(drive, m.start, start_town);
            taken.insert(n);
            w.add_vehicle(m.id, GroundKind::CargoTruck, m.level, n, heading)
                .map_err(err)?;
        }
        Role::Car | Role::Ugv => {
            let n = match (m.role, m.start) {
                // The junction nearest the start that no other vehicle holds.
                (_, Some(p)) => random_free_node(drive, rng, p, 0.0, 0.0, taken),
                // The UGV starts a few junctions ahead of the truck on its route.
                (Role::Ugv, None) => brief
                    .route
                    .iter()
                    .copied()
                    .skip(2)
                    .find(|n| !taken.contains(n))
                    .unwrap_or_else(|| random_free_node(drive, rng, start_town, 0.0, 1.0e9, taken)),
                _ => random_free_node(drive, rng, [0.0, 0.0], 0.0, 1.0e9, taken),
            };
            taken.insert(n);
            let kind = if m.role == Role::Car {
                GroundKind::Car
            } else {
                GroundKind::Mdars
            };
            w.add_vehicle(m.id, kind, m.level, n, heading)
                .map_err(err)?;
        }
        Role::Trooper if m.side == Side::Blue => {
            cond.status = Status::Aboard(brief.truck);
        }
        Role::Vip => {
            w.add_trooper(m.id, TroopKind::Vip, m.level, brief.vip_node, heading)
                .map_err(err)?;
        }
        Role::Trooper | Role::Hvt => {
            let n = match m.start {
                Some(p) => at(walk, Some(p), p),
                None if m.role == Role::Hvt => random_node(walk, rng, safe_town, 150.0, 450.0),
                None => random_node(walk, rng, start_town, 250.0, 1.0e9),
            };
            w.add_trooper(m.id, TroopKind::Red, m.level, n, heading)
                .map_err(err)?;
            if m.role == Role::Hvt {
                cond.status = Status::Hidden;
            }
        }
        Role::Procerus | Role::Vidar | Role::Skeldar => {
            let p = m.start.unwrap_or(start_town);
            let g = brief.site.on_ground(p);
            let pos = [g[0], g[1], g[2] + m.altitude.unwrap_or(100.0)];
            match m.role {
                Role::Procerus => w.add_ctol(m.id, CtolKind::Procerus, m.level, pos, heading),
                Role::Vidar => w.add_vtol(m.id, VtolKind::Vidar, m.level, pos, heading),
                _ => w.add_vtol(m.id, VtolKind::Skeldar, m.level, pos, heading),
            }
            .map_err(err)?;
        }
    }
    w.conditions.insert(m.id, cond);
    Ok(())
}

/// The squad's formation settings: the scenario's leader program (or the built-in one),
/// checked by building a leader with it, and its spacing.
fn formation_brief(
    loaded: &crate::scenario::Loaded,
    level: vitro_tactical::entity::Level,
) -> Result<FormationBrief, MissionError> {
    let (name, program) = match &loaded.program {
        Some(path) => {
            let text = std::fs::read_to_string(path).map_err(|e| {
                MissionError::Setup(format!("formation program {}: {e}", path.display()))
            })?;
            (path.display().to_string(), text)
        }
        None => ("leader.jz".to_string(), LEADER_PROGRAM.to_string()),
    };
    let mut params = FormationParams {
        spacing: loaded.file.formation.spacing_m,
        ..FormationParams::default()
    };
    if level == vitro_tactical::entity::Level::Discrete {
        params.period = DISCRETE_PERIOD;
    }
    Leader::named(&name, &program, Vec::new(), params.clone())
        .map_err(|e| MissionError::Setup(format!("formation: {e}")))?;
    Ok(FormationBrief { program, params })
}

/// A pursuit turn: the time to walk a mean walk-graph edge at a patrol pace (1.3 m/s),
/// at least 10 s.
fn turn_seconds(walk: &FreeGraph) -> f64 {
    let (mut total, mut count) = (0.0, 0usize);
    for u in 0..walk.graph.node_count() as u32 {
        for (_, len, _) in walk.graph.neighbors(NodeId(u)) {
            total += len;
            count += 1;
        }
    }
    let mean = if count == 0 {
        0.0
    } else {
        total / count as f64
    };
    (mean / 1.3).max(10.0)
}

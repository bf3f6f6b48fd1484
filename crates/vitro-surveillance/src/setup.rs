//! Building a run from a validated scenario: the arena, the briefings, every entity's body,
//! condition and agent, the channel, the losses and the start events.

use crate::agents::red::Prowler;
use crate::agents::station::Station;
use crate::agents::uav::Uav;
use crate::brief::{Airframe, Discipline, Gait, RedBrief, StationBrief, TeamBrief};
use crate::model::Field;
use crate::scenario::Validated;
use crate::sector::grid;
use rand::{Rng, SeedableRng};
use rand_chacha::ChaCha8Rng;
use std::collections::BTreeSet;
use std::sync::Arc;
use vitro::entity::EntityId;
use vitro::env::NodeId;
use vitro::event::Target;
use vitro::protocol::CnetConfig;
use vitro::sim::{CostModel, Simulation};
use vitro::time::{SimDuration, SimTime};
use vitro_site::map::Mode;
use vitro_tactical::arena::{Arena, Ev};
use vitro_tactical::condition::{Condition, Role};
use vitro_tactical::entity::Level;
use vitro_tactical::entity::roads::{FreeGraph, Roads};
use vitro_tactical::model::Controller;
use vitro_tactical::scenario::EntityType;
use vitro_tactical::sensor::track::TrackConfig;
use vitro_tactical::types::{CtolKind, GroundKind, TroopKind, TypeBook, VtolKind};
use vitro_tactical::world::Side;

/// Why a valid scenario could not be set up.
#[derive(Clone, Debug, PartialEq, thiserror::Error)]
pub enum SetupError {
    /// No street junction near a point the scenario names.
    #[error("no street junction near the {0}")]
    NoJunction(String),
    /// A body could not be placed.
    #[error("cannot place {0}: {1}")]
    Place(String, String),
    /// An entity did not get the id the roster gave it.
    #[error("entity {0} got another id")]
    Id(String),
}

/// One entity of the run.
#[derive(Clone, Debug, PartialEq)]
pub struct Member {
    /// Its id.
    pub id: EntityId,
    /// Its name.
    pub name: String,
    /// Its type (`None`: the station).
    pub kind: Option<EntityType>,
    /// Its side.
    pub side: Side,
    /// Its level of fidelity.
    pub level: Level,
}

impl Member {
    /// True for a UAV.
    pub fn is_uav(&self) -> bool {
        self.kind.is_some_and(EntityType::is_aircraft)
    }
    /// True for a red unit.
    pub fn is_red(&self) -> bool {
        self.side == Side::Red
    }
}

/// What [`build`] returns.
pub(crate) struct Built {
    pub sim: Simulation<Field>,
    pub members: Vec<Member>,
    /// UAV losses, in time order.
    pub losses: Vec<(SimTime, EntityId)>,
    pub team: Arc<TeamBrief>,
    pub station: Arc<StationBrief>,
}

/// A main-part node of `g` not in `taken`, at random (from `rng`), or the one nearest to
/// `at` when given.
fn node(
    g: &FreeGraph,
    rng: &mut ChaCha8Rng,
    at: Option<[f64; 2]>,
    taken: &BTreeSet<NodeId>,
) -> Option<NodeId> {
    let free: Vec<NodeId> = (0..g.graph.node_count() as u32)
        .map(NodeId)
        .filter(|n| g.main.get(n.0 as usize).copied().unwrap_or(false) && !taken.contains(n))
        .collect();
    match at {
        Some(p) => free.into_iter().min_by(|&a, &b| {
            let d = |n: NodeId| {
                g.graph
                    .node(n)
                    .map_or(f64::INFINITY, |s| crate::sector::dist(s.pos, p))
            };
            d(a).total_cmp(&d(b)).then(a.cmp(&b))
        }),
        None if free.is_empty() => None,
        None => Some(free[rng.random_range(0..free.len())]),
    }
}

/// Builds the simulation of `v` with `seed`.
pub(crate) fn build(v: Validated, seed: u64) -> Result<Built, SetupError> {
    let f = &v.file;
    let site = Arc::new(v.site);
    let roads = Arc::new(Roads::new(&site));
    let types = TypeBook::builtin();
    // The roster: the station, then the entities in file order.
    let mut members = vec![Member {
        id: EntityId(0),
        name: "station".into(),
        kind: None,
        side: Side::Blue,
        level: Level::Discrete,
    }];
    for e in &f.entities {
        for name in e.names() {
            members.push(Member {
                id: EntityId(members.len() as u32),
                name,
                kind: Some(e.kind),
                side: e.side.side(),
                level: f.fidelity.level_of(e.kind),
            });
        }
    }
    let uavs: Vec<EntityId> = members
        .iter()
        .filter(|m| m.is_uav())
        .map(|m| m.id)
        .collect();
    let ch = &f.channel;
    let al = &f.allocation;
    let secs = SimDuration::from_secs_f64;
    let discipline = Discipline {
        heartbeat: secs(f.team.heartbeat_s),
        lost_after: secs(f.team.lost_after_s),
        report: secs(f.team.report_s),
        report_fresh: secs(f.team.report_fresh_s),
        cnet: CnetConfig {
            proposal_deadline: secs(al.proposal_deadline_s),
            report_deadline: secs(al.report_deadline_s),
            proposal_expiry: secs(al.proposal_expiry_s),
        },
    };
    let area = f.search.area.unwrap_or(site.map.extent);
    let sectors = grid(area, f.search.sector_m, 0);
    let mut next = sectors.len() as u32;
    let mut tasking = Vec::new();
    for a in &f.areas {
        let s = grid(a.area, f.search.sector_m, next);
        next += s.len() as u32;
        tasking.push((SimTime::from_secs_f64(a.appear_s), s));
    }
    tasking.sort_by_key(|(t, _)| *t);
    let station_brief = Arc::new(StationBrief {
        home: f.station.start,
        site: site.clone(),
        method: al.method,
        budget: al.budget,
        search_cost: CostModel {
            base: SimDuration::ZERO,
            per_unit: secs(al.iteration_ms / 1e3),
        },
        team: uavs.clone(),
        sectors,
        tasking,
        retry: secs(al.retry_s),
        discipline,
    });
    let team = Arc::new(TeamBrief {
        site: site.clone(),
        station: EntityId(0),
        team: uavs.clone(),
        area,
        spacing_m: f.search.spacing_m,
        tracking: TrackConfig {
            vision: f.sensors.camera.vision(),
            misses_to_lose: f.tracking.misses_to_lose,
            side: Side::Red,
            confirm_looks: f.tracking.confirm_looks,
            max_locks: f.tracking.max_locks as usize,
        },
        period: secs(f.sensors.period_s),
        orbit_m: f.team.orbit_m,
        reacquire: secs(f.team.reacquire_s),
        cue_m: f.team.cue_m,
        discipline,
    });
    let red = Arc::new(RedBrief {
        roads: roads.clone(),
        site: site.clone(),
        leg_m: f.red.leg_m,
        dwell_s: f.red.dwell_s,
    });

    let arena = Arena::with(site.clone(), roads.clone(), Arc::new(types.clone()));
    let mut sim = Simulation::<Field>::new(arena, seed);
    sim.network_mut().set_default_link(ch.link());
    let mut rng = ChaCha8Rng::seed_from_u64(seed ^ 0x5e7e_111a);
    let mut taken = BTreeSet::new();
    // Each member's entity table (the station has none).
    let specs: Vec<&vitro_tactical::scenario::EntitySpec> = (f.entities.iter())
        .flat_map(|e| std::iter::repeat_n(e, e.names().len()))
        .collect();
    let starts: Vec<Option<[f64; 2]>> = specs.iter().map(|e| e.start).collect();
    let altitudes: Vec<f64> = specs
        .iter()
        .map(|e| e.altitude_m.unwrap_or(100.0))
        .collect();
    for (k, m) in members.iter().enumerate() {
        let err = |e: String| SetupError::Place(m.name.clone(), e);
        let agent: Box<dyn Controller<Field>> = match m.kind {
            None => Box::new(Station::new(station_brief.clone())),
            Some(t) if t.is_aircraft() => {
                let fixed_wing = t == EntityType::Procerus;
                let cruise_mps = if fixed_wing {
                    types.ctol(CtolKind::Procerus).cruise_speed
                } else if t == EntityType::Vidar {
                    types.vtol(VtolKind::Vidar).cruise_speed
                } else {
                    types.vtol(VtolKind::Skeldar).cruise_speed
                };
                let frame = Airframe {
                    level: m.level,
                    fixed_wing,
                    altitude_m: altitudes[k - 1],
                    cruise_mps,
                };
                Box::new(Uav::new(team.clone(), frame))
            }
            Some(t) => {
                let mode = if t == EntityType::Trooper {
                    Mode::Walk
                } else {
                    Mode::Drive
                };
                Box::new(Prowler::new(
                    red.clone(),
                    Gait {
                        mode,
                        level: m.level,
                    },
                ))
            }
        };
        let id = sim
            .add_agent(m.name.clone(), agent)
            .map_err(|e| err(e.to_string()))?;
        if id != m.id {
            return Err(SetupError::Id(m.name.clone()));
        }
        let w = sim.env_mut();
        let drive = roads.of(Mode::Drive);
        match m.kind {
            None => {
                let n = node(drive, &mut rng, Some(f.station.start), &taken)
                    .ok_or_else(|| SetupError::NoJunction("station".into()))?;
                taken.insert(n);
                w.add_vehicle(m.id, GroundKind::CargoTruck, Level::Discrete, n, 0.0)
                    .map_err(|e| err(e.to_string()))?;
                w.conditions
                    .insert(m.id, Condition::new(Role::Truck, Side::Blue, 3.2));
                continue;
            }
            Some(t) if t.is_aircraft() => {
                let p = starts[k - 1].unwrap_or(f.station.start);
                let g = site.on_ground(p);
                let pos = [g[0], g[1], g[2] + altitudes[k - 1]];
                match t {
                    EntityType::Procerus => w.add_ctol(m.id, CtolKind::Procerus, m.level, pos, 0.0),
                    EntityType::Vidar => w.add_vtol(m.id, VtolKind::Vidar, m.level, pos, 0.0),
                    _ => w.add_vtol(m.id, VtolKind::Skeldar, m.level, pos, 0.0),
                }
                .map_err(|e| err(e.to_string()))?;
            }
            Some(EntityType::Trooper) => {
                let walk = roads.of(Mode::Walk);
                let n = node(walk, &mut rng, starts[k - 1], &BTreeSet::new())
                    .ok_or_else(|| SetupError::NoJunction(m.name.clone()))?;
                w.add_trooper(m.id, TroopKind::Red, m.level, n, 0.0)
                    .map_err(|e| err(e.to_string()))?;
            }
            Some(t) => {
                let n = node(drive, &mut rng, starts[k - 1], &taken)
                    .ok_or_else(|| SetupError::NoJunction(m.name.clone()))?;
                taken.insert(n);
                let kind = match t {
                    EntityType::Truck => GroundKind::CargoTruck,
                    EntityType::Ugv => GroundKind::Mdars,
                    _ => GroundKind::Car,
                };
                w.add_vehicle(m.id, kind, m.level, n, 0.0)
                    .map_err(|e| err(e.to_string()))?;
            }
        }
        if let Some(t) = m.kind {
            w.conditions.insert(
                m.id,
                Condition::new(t.into(), m.side, Role::from(t).height()),
            );
        }
    }
    for m in &members {
        sim.schedule(SimTime::ZERO, Target::Entity(m.id), Ev::Start)
            .map_err(|e| SetupError::Place(m.name.clone(), e.to_string()))?;
    }
    let losses = losses(&v.file, &members, seed);
    Ok(Built {
        sim,
        members,
        losses,
        team,
        station: station_brief,
    })
}

/// The UAV losses: those the scenario sets, and a failure time per UAV drawn from the
/// failure rate (exponential, from the seed's own `failures` stream), in time order.
fn losses(
    f: &crate::scenario::SurveillanceFile,
    members: &[Member],
    seed: u64,
) -> Vec<(SimTime, EntityId)> {
    let mut out: Vec<(SimTime, EntityId)> = (f.losses.iter())
        .filter_map(|l| {
            let m = members.iter().find(|m| m.name == l.uav)?;
            Some((SimTime::from_secs_f64(l.at_s), m.id))
        })
        .collect();
    let rate = f.failures.rate_per_h / 3600.0;
    if rate > 0.0 {
        let mut rng = ChaCha8Rng::seed_from_u64(seed ^ 0xfa11_0e55);
        for m in members.iter().filter(|m| m.is_uav()) {
            let u: f64 = 1.0 - rng.random::<f64>();
            let t = -libm::log(u) / rate;
            if t < vitro_tactical::scenario::MAX_END_S {
                out.push((SimTime::from_secs_f64(t), m.id));
            }
        }
    }
    out.sort();
    out
}

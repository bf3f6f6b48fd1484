//! External controllers: blue units whose decisions come from outside the simulation (a
//! Python policy, a learning agent) between slices of the run.
//!
//! [`Mission::build_external`](crate::Mission::build_external) gives the named units an
//! [`External`] controller instead of their own. Such a unit still acts only through its
//! actuators and knows only what its own sensors and the radio tell it: every sensor period
//! it reads its own position and condition ([`Myself`]) and its friend-or-foe vision
//! ([`Vision`]), keeps the latest contact report heard on the radio for each target, reports
//! what it sees to the blue group as the unit it replaces would, and carries out the
//! [`Command`] left for it on the [`Desk`]. Whoever drives the run reads each unit's
//! [`Knowledge`] from the desk and leaves the next commands there between `advance` calls.
//!
//! Commands name [`targets`]: the briefed places and route junctions, the same list for
//! every unit. Runs without external units are built exactly as if none could be (the same
//! trace hash).

use crate::act::{Drive, Pilot};
use crate::agents::{Reporter, SENSE};
use crate::brief::{BLUE, Brief};
use crate::member::Member;
use crate::radio::{Evac, Radio};
use crate::sense::{Myself, Vision};
use std::collections::{BTreeMap, BTreeSet};
use std::sync::{Arc, Mutex, MutexGuard};
use vitro::entity::EntityId;
use vitro::env::NodeId;
use vitro::sim::{Context, Input};
use vitro::time::{SimDuration, SimTime};
use vitro_site::map::Mode;
use vitro_tactical::arena::Ev;
use vitro_tactical::condition::{Role, Status};
use vitro_tactical::entity::air::FlightCommand;
use vitro_tactical::model::{Controller, Intention};
use vitro_tactical::world::Side;

/// The roles an external controller can drive: the UGV (on the drive graph) and the
/// helicopters (Vidar, Skeldar), which can hold where they are. The truck, the troopers and
/// the fixed-wing Procerus keep their own controllers.
pub const CONTROLLABLE: [Role; 3] = [Role::Ugv, Role::Vidar, Role::Skeldar];

/// Altitude of an external helicopter above the ground when the scenario gives none, metres.
const DEFAULT_HEIGHT_M: f64 = 100.0;

/// True if `m` may be driven from outside: a blue unit of a [`CONTROLLABLE`] role.
pub fn controllable(m: &Member) -> bool {
    m.side == Side::Blue && CONTROLLABLE.contains(&m.role)
}

/// What an external unit is told to do.
#[derive(Copy, Clone, Debug, PartialEq, Eq)]
pub enum Command {
    /// Stop: the UGV at the junction nearest to it, a helicopter hovering where it is.
    Hold,
    /// Go to target `i` of [`targets`] (a helicopter flies over it).
    GoTo(usize),
}

/// A contact heard on the radio: the latest report about one target from another unit
/// (its own reports do not come back to it).
#[derive(Copy, Clone, Debug, PartialEq)]
pub struct Heard {
    /// Who sent the report.
    pub from: EntityId,
    /// Where the reporter saw it, world metres.
    pub pos: [f64; 3],
    /// The side the reporter took it for.
    pub seen_as: Side,
    /// When the report arrived.
    pub at: SimTime,
}

/// What an external unit knows: its own sensors' latest readings and the radio.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Knowledge {
    /// Its own position (GPS), world metres; `None` before the first look.
    pub pos: Option<[f64; 3]>,
    /// Whether it is active (not down).
    pub active: bool,
    /// What its vision saw at its last look: (who, where, side taken for), nearest first.
    pub seen: Vec<(EntityId, [f64; 3], Side)>,
    /// The latest radio contact report per target, from other units; a report older than
    /// `sensors.stale_s` is dropped at the next look.
    pub heard: BTreeMap<EntityId, Heard>,
    /// The target it goes to, if any.
    pub goal: Option<usize>,
    /// Whether it reached its goal since the desk last cleared the flag.
    pub arrived: bool,
    /// Whether it saw a hostile it had never seen before (since the flag was cleared).
    pub new_contact: bool,
    /// Whether it is on a trip it cannot leave before the trip's end (a UGV driving to
    /// its goal: its actuator takes a new goal only at rest).
    pub under_way: bool,
    /// Commands its actuator refused.
    pub refused: u32,
}

/// One unit's place on the desk.
#[derive(Clone, Debug, Default)]
pub struct Slot {
    /// The command waiting to be carried out at the unit's next look.
    pub pending: Option<Command>,
    /// What the unit knows.
    pub knowledge: Knowledge,
}

/// Where the driver of a run and the external controllers meet: one slot per unit.
#[derive(Clone, Debug, Default)]
pub struct Desk {
    /// The units' slots, by entity id.
    pub units: BTreeMap<EntityId, Slot>,
}

/// The desk, shared by the driver and the controllers.
pub type SharedDesk = Arc<Mutex<Desk>>;

/// Locks the desk (a poisoned lock still holds plain data).
pub fn lock(desk: &SharedDesk) -> MutexGuard<'_, Desk> {
    desk.lock().unwrap_or_else(|e| e.into_inner())
}

/// The drive-graph nodes commands name, in order: the start of the route, then the end of
/// each leg out (the last is the safehouse) and back (the last is the extraction point),
/// each once. Briefed knowledge: every blue unit has the route.
pub fn targets(brief: &Brief) -> Vec<NodeId> {
    let mut out: Vec<NodeId> = Vec::new();
    let all = brief.route.first().into_iter();
    for &n in all.chain(&brief.legs_out).chain(&brief.legs_back) {
        if !out.contains(&n) {
            out.push(n);
        }
    }
    out
}

/// The indices in [`targets`] of the briefed places: the start, the safehouse (the end of
/// the last leg out) and the extraction point (the end of the last leg back).
pub fn places(brief: &Brief) -> [usize; 3] {
    let t = targets(brief);
    let at = |n: Option<&NodeId>| n.and_then(|n| t.iter().position(|m| m == n)).unwrap_or(0);
    [
        at(brief.route.first()),
        at(brief.legs_out.last()),
        at(brief.legs_back.last()),
    ]
}

/// The world points of [`targets`] (on the ground), in the same order.
pub fn target_points(brief: &Brief) -> Vec<[f64; 3]> {
    targets(brief)
        .into_iter()
        .map(|n| brief.node_point(Mode::Drive, n).unwrap_or([0.0; 3]))
        .collect()
}

/// How the unit moves.
#[derive(Copy, Clone, Debug)]
enum Mover {
    Drive(Drive),
    Fly { pilot: Pilot, height: f64 },
}

/// The controller of a unit driven from outside.
#[derive(Debug)]
pub struct External {
    brief: Arc<Brief>,
    desk: SharedDesk,
    mover: Mover,
    targets: Vec<NodeId>,
    reporter: Reporter,
    /// The last command carried out (the same command again is not repeated).
    last: Option<Command>,
    /// The hostiles its vision ever saw.
    known: BTreeSet<EntityId>,
}

impl External {
    /// The external controller of `m` (a [`controllable`] unit), meeting its driver at
    /// `desk`; `None` for any other unit.
    pub fn for_member(m: &Member, brief: Arc<Brief>, desk: SharedDesk) -> Option<External> {
        if !controllable(m) {
            return None;
        }
        let mover = match m.role {
            Role::Ugv => Mover::Drive(Drive(m.level)),
            _ => Mover::Fly {
                pilot: Pilot(m.level),
                height: m.altitude.unwrap_or(DEFAULT_HEIGHT_M),
            },
        };
        lock(&desk).units.entry(m.id).or_default();
        Some(External {
            targets: targets(&brief),
            brief,
            desk,
            mover,
            reporter: Reporter::default(),
            last: None,
            known: BTreeSet::new(),
        })
    }

    fn vision(&self) -> Vision {
        match self.mover {
            Mover::Drive(_) => Vision(self.brief.sensors.ground.vision()),
            Mover::Fly { .. } => Vision(self.brief.sensors.air.vision()),
        }
    }

    /// Looks (own position and condition, vision), reports hostiles, carries out a pending
    /// command.
    fn look(&mut self, cx: &mut Context<'_, Evac>) {
        let me = cx.me();
        let mine = cx.sense(&Myself);
        let active = mine.is_some_and(|(c, _)| c.status == Status::Active);
        let pos = mine.and_then(|(_, p)| p).map(|p| p.pos);
        let mut seen = if active {
            cx.sense(&self.vision())
        } else {
            Vec::new()
        };
        seen.sort_by(|a, b| a.distance.total_cmp(&b.distance).then(a.id.cmp(&b.id)));
        self.reporter.report(&seen, cx);
        let mut new_contact = false;
        for s in seen.iter().filter(|s| s.seen_as == Side::Red) {
            new_contact |= self.known.insert(s.id);
        }
        let stale = SimDuration::from_secs_f64(self.brief.sensors.stale_s);
        let now = cx.now();
        let pending = {
            let mut desk = lock(&self.desk);
            let slot = desk.units.entry(me).or_default();
            let k = &mut slot.knowledge;
            k.heard.retain(|_, h| now.saturating_since(h.at) <= stale);
            k.seen = seen.iter().map(|s| (s.id, s.pos, s.seen_as)).collect();
            k.new_contact |= new_contact;
            k.pos = pos;
            k.active = active;
            if active { slot.pending.take() } else { None }
        };
        let pending = pending.filter(|c| Some(*c) != self.last);
        if let (Some(command), Some(pos)) = (pending, pos) {
            self.carry_out(command, pos, cx);
        }
    }

    fn carry_out(&mut self, command: Command, pos: [f64; 3], cx: &mut Context<'_, Evac>) {
        let me = cx.me();
        let goal = match command {
            Command::Hold => None,
            Command::GoTo(i) => self.targets.get(i).copied().map(|n| (i, n)),
        };
        let ok = match (self.mover, goal) {
            (Mover::Drive(drive), Some((_, n))) => cx.act(&drive, n).is_ok(),
            (Mover::Drive(drive), None) => {
                let here = self.brief.site.to_town([pos[0], pos[1]]);
                let node = self.brief.roads.of(Mode::Drive).nearest_connected(here);
                node.is_some_and(|n| cx.act(&drive, n).is_ok())
            }
            (Mover::Fly { pilot, height }, goal) => {
                let point = match goal {
                    Some((_, n)) => self.brief.node_point(Mode::Drive, n),
                    None => Some(pos),
                };
                point.is_some_and(|p| {
                    let g = self.brief.site.ground([p[0], p[1]]).unwrap_or(p[2]);
                    let points = vec![[p[0], p[1], g + height]];
                    cx.act(
                        &pilot,
                        FlightCommand::Waypoints {
                            points,
                            speed: None,
                        },
                    )
                    .is_ok()
                })
            }
        };
        let mut desk = lock(&self.desk);
        let k = &mut desk.units.entry(me).or_default().knowledge;
        if ok {
            self.last = Some(command);
            k.goal = goal.map(|(i, _)| i);
            k.under_way = matches!(self.mover, Mover::Drive(_));
        } else {
            k.refused += 1;
        }
    }
}

impl Controller<Evac> for External {
    fn handle(&mut self, input: Input<'_, Evac>, cx: &mut Context<'_, Evac>) {
        match input {
            Input::Event(Ev::Start) => {
                cx.join(BLUE);
                self.look(cx);
                let period = SimDuration::from_secs_f64(self.brief.sensors.period_s);
                cx.set_timer(period, SENSE);
            }
            Input::Timer(SENSE) => {
                self.look(cx);
                let period = SimDuration::from_secs_f64(self.brief.sensors.period_s);
                cx.set_timer(period, SENSE);
            }
            Input::Event(Ev::Arrived(_) | Ev::Waypoint(_)) => {
                let me = cx.me();
                let mut desk = lock(&self.desk);
                let k = &mut desk.units.entry(me).or_default().knowledge;
                k.arrived = true;
                k.under_way = false;
            }
            Input::Event(Ev::Stalled(..)) => {
                let me = cx.me();
                let mut desk = lock(&self.desk);
                desk.units.entry(me).or_default().knowledge.under_way = false;
                // The trip was given up: the same command may be given again.
                self.last = None;
            }
            Input::Message(env) => {
                if let Radio::Contact {
                    target,
                    pos,
                    seen_as,
                } = &env.body
                {
                    let me = cx.me();
                    if env.from == me {
                        return; // its own report, back from the group
                    }
                    let heard = Heard {
                        from: env.from,
                        pos: *pos,
                        seen_as: *seen_as,
                        at: cx.now(),
                    };
                    let mut desk = lock(&self.desk);
                    let k = &mut desk.units.entry(me).or_default().knowledge;
                    k.heard.insert(*target, heard);
                }
            }
            _ => {}
        }
    }

    fn intention(&self) -> Option<Intention> {
        Some(Intention {
            text: "driven from outside".into(),
            ..Intention::default()
        })
    }
}

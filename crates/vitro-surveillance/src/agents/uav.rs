//! A UAV of the team. It bids for the sectors the station calls, sweeps the sectors it holds
//! (the whole operation area while it holds none), looks through its camera every sensor
//! period, and follows a target it has locked that no teammate reports following:
//!
//! - **search**: fly the route over its sectors, again and again;
//! - **track**: hover over the target's predicted position (a helicopter) or orbit it (a
//!   fixed-wing aircraft), while its own lock holds;
//! - **re-acquire**: the lock is lost; circle the target's dead-reckoned position for
//!   `reacquire_s`, then go back to searching.
//!
//! A searching UAV that hears a teammate's fresh sighting within `cue_m` of a target nobody
//! follows goes to look for it there (a cue). Two UAVs following one target settle it by id: the higher gives way when it hears the
//! other's report. Every UAV reports its status (position, sectors, what it follows) every
//! `heartbeat_s` and its fresh fixes every `report_s`, over the radio only.

use super::plan::{cost, search_route, watch};
use crate::act::Pilot;
use crate::brief::{Airframe, TeamBrief};
use crate::model::Field;
use crate::net::{ALLOCATION, Net, TEAM};
use crate::sector::{Rect, centre, dist};
use serde::{Deserialize, Serialize};
use std::collections::BTreeMap;
use std::sync::Arc;
use vitro::comm::{Address, Outgoing};
use vitro::entity::EntityId;
use vitro::protocol::{CnetEvent, ContractNet, Handled, Reply, TimerTag};
use vitro::sim::{Context, Input};
use vitro::time::{SimDuration, SimTime};
use vitro_tactical::arena::{Ev, OwnPose};
use vitro_tactical::entity::air::FlightCommand;
use vitro_tactical::model::{Controller, Intention};
use vitro_tactical::sensor::track::{Lock, TrackEvent, Tracker};

/// Timer key: look through the camera.
const SENSE: u64 = 1;
/// Timer key: report status.
const HEARTBEAT: u64 = 2;
/// The contract net's timer tag.
const CNET: TimerTag = TimerTag(1);
/// A followed target is flown to again once it is this far from the last point, metres.
const REFLY_M: f64 = 25.0;

/// What a UAV is doing.
#[derive(Copy, Clone, Debug, PartialEq, Serialize, Deserialize)]
pub enum Mode {
    /// Sweeping its sectors.
    Search,
    /// Following a target it holds a lock on.
    Track(EntityId),
    /// Looking for a target whose lock it lost, round `at` (town metres), until `until`.
    Reacquire {
        /// The target.
        target: EntityId,
        /// Its dead-reckoned position when the lock was lost.
        at: [f64; 2],
        /// When it gives up.
        until: SimTime,
    },
}

/// A stretch of time a UAV's tracker held a lock on a target.
#[derive(Copy, Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct LockSpan {
    /// The target.
    pub target: EntityId,
    /// When the lock was taken.
    pub from: SimTime,
    /// When it was lost (none: still held).
    pub to: Option<SimTime>,
}

/// A UAV of the team.
#[derive(Debug, Serialize, Deserialize)]
pub struct Uav {
    #[serde(with = "vitro_mission::snapshot::briefed")]
    brief: Arc<TeamBrief>,
    frame: Airframe,
    cnet: ContractNet<Net>,
    tracker: Tracker,
    /// The sectors it holds, by id.
    pub sectors: BTreeMap<u32, Rect>,
    /// The sectors it learnt of from calls.
    known: BTreeMap<u32, Rect>,
    /// Proposals awaiting an answer.
    pending: BTreeMap<Reply, u32>,
    /// What it is doing.
    pub mode: Mode,
    /// The points of its last flight command, world metres.
    pub route: Vec<[f64; 3]>,
    /// Where it last flew to watch a target, town metres.
    watching: Option<[f64; 2]>,
    /// Teammates' tracks heard: target → (teammate, when).
    heard: BTreeMap<EntityId, (EntityId, SimTime)>,
    /// When each target was last reported.
    reported: BTreeMap<EntityId, SimTime>,
    /// Teammates' sightings heard: target → (where, town metres, when seen).
    cues: BTreeMap<EntityId, ([f64; 2], SimTime)>,
    /// The last fix of each lock (kept when the lock is lost, for re-acquisition).
    fixes: BTreeMap<EntityId, Lock>,
    /// Every lock it held, in the order taken.
    pub spans: Vec<LockSpan>,
    /// False once it found itself down.
    pub alive: bool,
    /// Flight commands refused by the autopilot.
    pub refused: u32,
}

impl Uav {
    /// A UAV of `brief` with airframe `frame`.
    pub fn new(brief: Arc<TeamBrief>, frame: Airframe) -> Self {
        Uav {
            cnet: ContractNet::new(CNET, brief.discipline.cnet),
            tracker: Tracker::new(brief.tracking),
            brief,
            frame,
            sectors: BTreeMap::new(),
            known: BTreeMap::new(),
            pending: BTreeMap::new(),
            mode: Mode::Search,
            route: Vec::new(),
            watching: None,
            heard: BTreeMap::new(),
            reported: BTreeMap::new(),
            cues: BTreeMap::new(),
            fixes: BTreeMap::new(),
            spans: Vec::new(),
            alive: true,
            refused: 0,
        }
    }

    /// The locks it holds now.
    pub fn locks(&self) -> impl Iterator<Item = &Lock> + '_ {
        self.tracker.locks()
    }

    /// Its own position in town metres (GPS), if it has a body.
    fn here(&self, cx: &mut Context<'_, Field>) -> Option<[f64; 2]> {
        let p = cx.sense(&OwnPose)?.pos;
        Some(self.brief.site.to_town([p[0], p[1]]))
    }

    fn fly(&mut self, points: Vec<[f64; 3]>, cx: &mut Context<'_, Field>) {
        if points.is_empty() {
            return;
        }
        let cmd = FlightCommand::Waypoints {
            points: points.clone(),
            speed: None,
        };
        match cx.act(&Pilot(self.frame.level), cmd) {
            Ok(()) => self.route = points,
            Err(_) => self.refused += 1,
        }
    }

    /// Flies the search route over its sectors from where it is.
    fn search(&mut self, cx: &mut Context<'_, Field>) {
        self.mode = Mode::Search;
        self.watching = None;
        let Some(here) = self.here(cx) else { return };
        // Without sectors it searches the whole area, entering it at the corner its place
        // in the roster gives it (so that UAVs cut off from the station spread out).
        let from = if self.sectors.is_empty() {
            let a = self.brief.area;
            let k = (self.brief.team.iter())
                .position(|&u| u == cx.me())
                .unwrap_or(0);
            [[a[0], a[1]], [a[2], a[3]], [a[2], a[1]], [a[0], a[3]]][k % 4]
        } else {
            here
        };
        let route = search_route(&self.brief, &self.frame, &self.sectors, from);
        self.fly(route, cx);
    }

    /// Flies to watch town point `p` (again only if it moved).
    fn watch(&mut self, p: [f64; 2], wide: bool, cx: &mut Context<'_, Field>) {
        if self.watching.is_some_and(|w| dist(w, p) < REFLY_M) {
            return;
        }
        self.watching = Some(p);
        let points = watch(&self.brief, &self.frame, p, wide);
        self.fly(points, cx);
    }

    fn start(&mut self, cx: &mut Context<'_, Field>) {
        cx.join(TEAM);
        let b = &self.brief;
        cx.set_timer(b.period, SENSE);
        // Status reports staggered by id over a heartbeat, so they do not all go at once.
        let n = b.team.len().max(1) as u64;
        let k = b.team.iter().position(|&u| u == cx.me()).unwrap_or(0) as u64;
        let offset = b.discipline.heartbeat.as_nanos() * (k + 1) / n;
        cx.set_timer(SimDuration::from_nanos(offset), HEARTBEAT);
        self.search(cx);
    }

    /// One look through the camera, then what to do.
    fn sense(&mut self, cx: &mut Context<'_, Field>) {
        let now = cx.now();
        if !cx.sense(&crate::sense::Alive) {
            self.go_down(now);
            return;
        }
        for lock in self.tracker.locks() {
            self.fixes.insert(lock.target, *lock);
        }
        for e in self.tracker.sense(cx) {
            match e {
                TrackEvent::Acquired(target) => self.spans.push(LockSpan {
                    target,
                    from: now,
                    to: None,
                }),
                TrackEvent::Lost(target) => {
                    if let Some(s) =
                        (self.spans.iter_mut().rev()).find(|s| s.target == target && s.to.is_none())
                    {
                        s.to = Some(now);
                    }
                }
            }
        }
        self.decide(cx);
        self.report(cx);
        cx.set_timer(self.brief.period, SENSE);
    }

    /// Whether a teammate reported following `target` lately.
    fn followed_by_other(&self, target: EntityId, now: SimTime, me: EntityId) -> Option<EntityId> {
        let (who, at) = *self.heard.get(&target)?;
        (who != me && now.saturating_since(at) <= self.brief.discipline.report_fresh).then_some(who)
    }

    fn decide(&mut self, cx: &mut Context<'_, Field>) {
        let (now, me) = (cx.now(), cx.me());
        let site = self.brief.site.clone();
        let town = |p: [f64; 3]| site.to_town([p[0], p[1]]);
        match self.mode {
            Mode::Track(t) => {
                let other = self.followed_by_other(t, now, me);
                match self.tracker.get(t).copied() {
                    _ if other.is_some_and(|o| o < me) => self.search(cx),
                    Some(lock) => {
                        let p = town(lock.predicted(now));
                        self.watch(p, false, cx);
                    }
                    None => {
                        let at = self
                            .fixes
                            .get(&t)
                            .map_or([0.0, 0.0], |l| town(l.predicted(now)));
                        self.mode = Mode::Reacquire {
                            target: t,
                            at,
                            until: now + self.brief.reacquire,
                        };
                        self.watching = None;
                        self.watch(at, true, cx);
                    }
                }
                return;
            }
            Mode::Reacquire { target, until, at } => {
                if self.tracker.get(target).is_some() {
                    self.mode = Mode::Track(target);
                    self.watching = None;
                } else if now >= until {
                    self.search(cx);
                } else {
                    self.watch(at, true, cx);
                }
                return;
            }
            Mode::Search => {}
        }
        // Searching: follow the nearest locked target nobody else follows.
        let Some(here) = self.here(cx) else { return };
        let pick = (self.tracker.locks())
            .filter(|l| l.misses == 0 && self.followed_by_other(l.target, now, me).is_none())
            .min_by(|a, b| {
                dist(here, town(a.pos))
                    .total_cmp(&dist(here, town(b.pos)))
                    .then(a.target.cmp(&b.target))
            })
            .map(|l| (l.target, town(l.predicted(now))));
        if let Some((t, p)) = pick {
            self.mode = Mode::Track(t);
            self.watching = None;
            self.watch(p, false, cx);
            return;
        }
        // Else a teammate's fresh sighting nearby of a target nobody follows: go and look.
        let fresh = self.brief.discipline.report_fresh;
        let reach = self.brief.cue_m;
        let cue = (self.cues.iter())
            .filter(|(t, (p, seen))| {
                now.saturating_since(*seen) <= fresh
                    && dist(here, *p) <= reach
                    && self.followed_by_other(**t, now, me).is_none()
            })
            .min_by(|a, b| {
                dist(here, a.1.0)
                    .total_cmp(&dist(here, b.1.0))
                    .then(a.0.cmp(b.0))
            })
            .map(|(t, (p, _))| (*t, *p));
        if let Some((target, at)) = cue {
            self.cues.remove(&target);
            self.mode = Mode::Reacquire {
                target,
                at,
                until: now + self.brief.reacquire,
            };
            self.watching = None;
            self.watch(at, true, cx);
        }
    }

    /// Reports fresh fixes not reported for `report_s`.
    fn report(&mut self, cx: &mut Context<'_, Field>) {
        let now = cx.now();
        let every = self.brief.discipline.report;
        let due: Vec<Lock> = (self.tracker.locks())
            .filter(|l| l.misses == 0)
            .filter(|l| {
                (self.reported.get(&l.target)).is_none_or(|&t| now.saturating_since(t) >= every)
            })
            .copied()
            .collect();
        for l in due {
            self.reported.insert(l.target, now);
            let body = Net::Sighting {
                target: l.target,
                pos: l.pos,
                seen_ns: l.seen_at.as_nanos(),
                following: self.mode == Mode::Track(l.target),
            };
            cx.send(Outgoing::new(Address::Group(TEAM), body));
        }
    }

    fn heartbeat(&mut self, cx: &mut Context<'_, Field>) {
        if self.status(cx) {
            cx.set_timer(self.brief.discipline.heartbeat, HEARTBEAT);
        }
    }

    /// Sends its status report; false if it has no body to report from.
    fn status(&mut self, cx: &mut Context<'_, Field>) -> bool {
        let Some(pos) = cx.sense(&OwnPose).map(|p| p.pos) else {
            return false;
        };
        let tracking = match self.mode {
            Mode::Track(t) => vec![t],
            _ => Vec::new(),
        };
        let body = Net::Status {
            pos,
            sectors: self.sectors.keys().copied().collect(),
            tracking,
        };
        cx.send(Outgoing::new(Address::Group(TEAM), body));
        true
    }

    /// Sectors the station allotted it (an auction's award or the central plan): taken,
    /// and claimed at once in a status report.
    fn take(&mut self, sectors: &[(u32, Rect)], cx: &mut Context<'_, Field>) {
        for &(s, area) in sectors {
            self.known.insert(s, area);
            self.sectors.insert(s, area);
        }
        self.status(cx);
        if self.mode == Mode::Search {
            self.search(cx);
        }
    }

    /// An auction round: its award if it is this UAV's, then its bid for the waiting
    /// sector it adds most cheaply (none if it has no position to bid from).
    fn on_round(
        &mut self,
        round: u64,
        award: Option<(EntityId, u32, Rect)>,
        sectors: &[(u32, Rect)],
        cx: &mut Context<'_, Field>,
    ) {
        if let Some((u, s, area)) = award
            && u == cx.me()
        {
            self.take(&[(s, area)], cx);
        }
        if sectors.is_empty() {
            return;
        }
        let Some(here) = self.here(cx) else {
            return;
        };
        let load: Vec<Rect> = self.sectors.values().copied().collect();
        let mut best: Option<(f64, u32)> = None;
        for &(s, area) in sectors {
            self.known.insert(s, area);
            let bid = if self.sectors.contains_key(&s) {
                0.0
            } else {
                cost(&self.brief, &self.frame, &load, area, here)
            };
            if best.is_none_or(|(b, _)| bid < b) {
                best = Some((bid, s));
            }
        }
        if let Some((bid, sector)) = best {
            let body = Net::Bid {
                round,
                sector,
                cost: bid,
            };
            let to = Address::Agent(self.brief.station);
            cx.send(Outgoing::new(to, body).protocol(ALLOCATION, round));
        }
    }

    /// Found itself down: its camera and radio are gone.
    fn go_down(&mut self, now: SimTime) {
        self.alive = false;
        self.tracker.clear();
        for s in self.spans.iter_mut().filter(|s| s.to.is_none()) {
            s.to = Some(now);
        }
    }

    fn on_cnet(&mut self, event: CnetEvent<'_, Net>, cx: &mut Context<'_, Field>) {
        match event {
            CnetEvent::CallForProposals { reply, cfp } => {
                let Net::Call { sector, area } = cfp.body else {
                    return;
                };
                self.known.insert(sector, area);
                let Some(here) = self.here(cx) else {
                    self.cnet.refuse(cx, reply, Net::Decline { sector });
                    return;
                };
                // A sector it holds already (its confirmation was lost): keeping it costs
                // nothing.
                let bid = if self.sectors.contains_key(&sector) {
                    0.0
                } else {
                    let load: Vec<Rect> = (self.sectors.values().copied())
                        .chain(
                            self.pending
                                .values()
                                .filter_map(|s| self.known.get(s).copied()),
                        )
                        .collect();
                    cost(&self.brief, &self.frame, &load, area, here)
                };
                self.cnet
                    .propose(cx, reply, Net::Offer { sector, cost: bid });
                self.pending.insert(reply, sector);
            }
            CnetEvent::Accepted { reply, accept, .. } => {
                self.pending.remove(&reply);
                let Net::Offer { sector, .. } = accept.body else {
                    return;
                };
                let Some(&area) = self.known.get(&sector) else {
                    self.cnet.report_failure(cx, reply, Net::Decline { sector });
                    return;
                };
                self.sectors.insert(sector, area);
                self.cnet.report_done(cx, reply, Net::Holding { sector });
                if self.mode == Mode::Search {
                    self.search(cx);
                }
            }
            CnetEvent::Rejected { reply } | CnetEvent::Expired { reply } => {
                self.pending.remove(&reply);
            }
            _ => {}
        }
    }

    fn on_message(&mut self, from: EntityId, body: &Net, cx: &mut Context<'_, Field>) {
        let now = cx.now();
        match body {
            Net::Status { tracking, .. } => {
                for &t in tracking {
                    self.heard.insert(t, (from, now));
                }
            }
            Net::Sighting {
                target,
                pos,
                seen_ns,
                following,
            } => {
                if *following {
                    self.heard.insert(*target, (from, now));
                }
                let at = self.brief.site.to_town([pos[0], pos[1]]);
                self.cues
                    .insert(*target, (at, SimTime::from_nanos(*seen_ns)));
            }
            Net::Round {
                round,
                award,
                sectors,
            } if from == self.brief.station => self.on_round(*round, *award, sectors, cx),
            Net::Assign { sectors } if from == self.brief.station => self.take(sectors, cx),
            Net::Revoke { sectors } if from == self.brief.station => {
                let before = self.sectors.len();
                self.sectors.retain(|s, _| !sectors.contains(s));
                if self.sectors.len() != before && self.mode == Mode::Search {
                    self.search(cx);
                }
            }
            _ => {}
        }
    }
}

impl Controller<Field> for Uav {
    fn handle(&mut self, input: Input<'_, Field>, cx: &mut Context<'_, Field>) {
        if !self.alive {
            return;
        }
        match self.cnet.handle(input, cx) {
            Handled::Event(e) => return self.on_cnet(e, cx),
            Handled::Consumed => return,
            Handled::NotMine => {}
        }
        match input {
            Input::Event(Ev::Start) => self.start(cx),
            Input::Event(Ev::Waypoint(i)) if *i as usize + 1 == self.route.len() => {
                match self.mode {
                    Mode::Search => self.search(cx),
                    // Orbits go round again; a hovering helicopter stays.
                    _ if self.route.len() > 1 => self.fly(self.route.clone(), cx),
                    _ => {}
                }
            }
            Input::Timer(SENSE) => self.sense(cx),
            Input::Timer(HEARTBEAT) => self.heartbeat(cx),
            Input::Message(env) => self.on_message(env.from, &env.body, cx),
            _ => {}
        }
    }

    fn intention(&self) -> Option<Intention> {
        let ids: Vec<String> = self.sectors.keys().map(|s| s.to_string()).collect();
        let doing = match self.mode {
            Mode::Search if ids.is_empty() => "search the whole area".to_owned(),
            Mode::Search => format!("search sector(s) {}", ids.join(", ")),
            Mode::Track(t) => format!("follow #{}", t.0),
            Mode::Reacquire { target, .. } => format!("look for #{}", target.0),
        };
        let text = if self.alive { doing } else { "down".to_owned() };
        let heat = (self.sectors.values())
            .map(|r| (above_plain(&self.brief, centre(*r)), 1.0))
            .collect();
        let belief = (self.tracker.locks())
            .map(|l| (l.pos, 1.0 / f64::from(1 + l.misses)))
            .collect();
        Some(Intention {
            text,
            plan: self.sectors.keys().map(|s| format!("sector {s}")).collect(),
            path: self.route.clone(),
            heat,
            belief,
            ..Intention::default()
        })
    }
}

/// A town point on the ground, in world metres (for drawings).
fn above_plain(brief: &TeamBrief, p: [f64; 2]) -> [f64; 3] {
    brief.site.on_ground(p)
}

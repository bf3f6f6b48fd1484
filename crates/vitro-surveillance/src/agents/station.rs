//! The ground control station: the contract net's manager. It calls for proposals for one
//! sector at a time (a sequential auction, so that each bid counts the sectors already
//! won), awards each to the lowest bid, and keeps its picture of who holds what from the
//! UAVs' confirmations and status reports only:
//!
//! - a call that fails (no proposal by the deadline, no confirmation from the winner) is
//!   made again after `retry_s`;
//! - a UAV not heard from for `lost_after_s` is presumed lost and its sectors are called
//!   again (a re-allocation);
//! - a UAV heard again claims its sectors back where nobody else holds them, and is told to
//!   drop ([`Net::Revoke`]) those another UAV holds meanwhile;
//! - an area tasked during the run is cut into sectors and called.
//!
//! The scenario may choose another allocation method (the `allot` module): sequential
//! single-item auctions over the radio, or a central plan (a vehicle routing problem solved
//! by the station); the picture, the presumptions and the revocations are the same.

mod allot;

use crate::brief::StationBrief;
use crate::model::Field;
use crate::net::{Net, TEAM};
use crate::scenario::AllocationMethod;
use crate::sector::Rect;
use serde::{Deserialize, Serialize};
use std::collections::{BTreeMap, BTreeSet, VecDeque};
use std::sync::Arc;
use vitro::comm::{Address, Envelope, Outgoing};
use vitro::entity::EntityId;
use vitro::protocol::{CallFailure, CnetEvent, ContractNet, Handled, Participants, TimerTag};
use vitro::sim::{Context, Input};
use vitro::time::SimTime;
use vitro_tactical::arena::Ev;
use vitro_tactical::model::{Controller, Intention};

/// Timer key: look for silent UAVs.
const CHECK: u64 = 1;
/// Timer keys from here: area `k` is tasked.
const TASKING: u64 = 1 << 20;
/// Timer key: the central search is over.
const PLANNED: u64 = 2;
/// Timer keys from here: sector `s` is called again.
const RETRY: u64 = 1 << 32;
/// Timer keys from here: auction round `r` is decided (below the contract net's tag, the
/// top 16 bits).
const ROUND: u64 = 1 << 40;
/// The contract net's timer tag.
const CNET: TimerTag = TimerTag(1);

/// An auction round waiting for its bids.
#[derive(Clone, Debug, Default, PartialEq, Serialize, Deserialize)]
struct Round {
    id: u64,
    sectors: Vec<u32>,
    /// (cost, bidder, sector).
    bids: Vec<(f64, EntityId, u32)>,
}

/// What the auction and the central plan keep between inputs.
#[derive(Clone, Debug, Default, PartialEq, Serialize, Deserialize)]
struct Allot {
    /// The round open, if any.
    round: Option<Round>,
    /// Rounds announced so far.
    rounds: u64,
    /// The last award, not announced yet.
    award: Option<(EntityId, u32, Rect)>,
    /// The central plan being searched: each UAV's sectors.
    plan: Option<Vec<(EntityId, Vec<u32>)>>,
    /// Central plans made.
    plans: u64,
    /// Each UAV's last reported position, town metres (the central plan).
    positions: BTreeMap<EntityId, [f64; 2]>,
}

/// The station's picture of one sector.
#[derive(Copy, Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct SectorState {
    /// Its area, town metres.
    pub area: Rect,
    /// Who holds it, as far as the station knows.
    pub holder: Option<EntityId>,
    /// When the holder confirmed it (its report, or a status that claims it).
    pub confirmed: Option<SimTime>,
    /// Whether it was ever awarded (a later call is a re-allocation).
    pub awarded_before: bool,
    /// The UAV it was last awarded to.
    pub last_winner: Option<EntityId>,
    /// When it was assigned without the contract net (an auction or the central plan): the
    /// holder's status report must claim it in time.
    #[serde(default)]
    pub assigned: Option<SimTime>,
}

/// What the station counts.
#[derive(Copy, Clone, Debug, Default, PartialEq, Eq, Serialize, Deserialize)]
pub struct StationStats {
    /// Calls for proposals made.
    pub calls: u64,
    /// Calls awarded.
    pub awards: u64,
    /// Calls that ended without a confirmed holder (no proposal, no report, unreachable).
    pub failed: u64,
    /// Calls for sectors that had been awarded before.
    pub reallocations: u64,
    /// Awards of a sector to another UAV than the one it was last awarded to.
    pub handovers: u64,
    /// Times a UAV was presumed lost (rightly or not).
    pub presumed_lost: u64,
    /// Revocations sent.
    pub revocations: u64,
}

/// The ground control station.
#[derive(Debug, Serialize, Deserialize)]
pub struct Station {
    #[serde(with = "vitro_mission::snapshot::briefed")]
    brief: Arc<StationBrief>,
    cnet: ContractNet<Net>,
    /// Its picture of the sectors, by id.
    pub sectors: BTreeMap<u32, SectorState>,
    queue: VecDeque<u32>,
    /// The call being collected: (conversation, sector).
    open: Option<(u64, u32)>,
    heard: BTreeMap<EntityId, SimTime>,
    /// The UAVs presumed lost.
    pub presumed_lost: BTreeSet<EntityId>,
    /// Its counts.
    pub stats: StationStats,
    /// What happened, for the log: (time, line).
    pub log: Vec<(SimTime, String)>,
    /// The auction's or the central plan's state.
    #[serde(default)]
    allot: Allot,
}

impl Station {
    /// The station of `brief`.
    pub fn new(brief: Arc<StationBrief>) -> Self {
        let cnet = ContractNet::new(CNET, brief.discipline.cnet);
        Station {
            brief,
            cnet,
            sectors: BTreeMap::new(),
            queue: VecDeque::new(),
            open: None,
            heard: BTreeMap::new(),
            presumed_lost: BTreeSet::new(),
            stats: StationStats::default(),
            log: Vec::new(),
            allot: Allot::default(),
        }
    }

    fn add_sectors(&mut self, sectors: &[crate::sector::Sector]) {
        for s in sectors {
            self.sectors.insert(
                s.id,
                SectorState {
                    area: s.area,
                    holder: None,
                    confirmed: None,
                    awarded_before: false,
                    last_winner: None,
                    assigned: None,
                },
            );
            self.queue.push_back(s.id);
        }
    }

    fn start(&mut self, cx: &mut Context<'_, Field>) {
        cx.join(TEAM);
        let brief = self.brief.clone();
        self.add_sectors(&brief.sectors);
        for (k, (at, _)) in brief.tasking.iter().enumerate() {
            cx.set_timer(at.saturating_since(cx.now()), TASKING + k as u64);
        }
        cx.set_timer(brief.discipline.heartbeat, CHECK);
        self.call_next(cx);
    }

    /// Calls for proposals for the next sector waiting, if no call is open (or the next
    /// auction round, or the next central plan).
    fn call_next(&mut self, cx: &mut Context<'_, Field>) {
        match self.brief.method {
            AllocationMethod::ContractNet => {}
            AllocationMethod::Auction => return self.next_round(cx),
            AllocationMethod::Central => return self.next_plan(cx),
        }
        if self.open.is_some() {
            return;
        }
        let alive: Vec<EntityId> = (self.brief.team.iter())
            .copied()
            .filter(|u| !self.presumed_lost.contains(u))
            .collect();
        if alive.is_empty() {
            return;
        }
        while let Some(s) = self.queue.pop_front() {
            let Some(state) = self.sectors.get(&s) else {
                continue;
            };
            if state.holder.is_some() {
                continue;
            }
            let body = Net::Call {
                sector: s,
                area: state.area,
            };
            self.stats.calls += 1;
            if state.awarded_before {
                self.stats.reallocations += 1;
            }
            let c = self
                .cnet
                .announce(cx, Participants::Agents(&alive), u64::from(s), body);
            self.open = Some((c, s));
            return;
        }
    }

    fn on_cnet(&mut self, event: CnetEvent<'_, Net>, cx: &mut Context<'_, Field>) {
        let now = cx.now();
        match event {
            CnetEvent::Awarded {
                conversation,
                task,
                winner,
                ..
            } => {
                let s = task as u32;
                if let Some(state) = self.sectors.get_mut(&s) {
                    if state.last_winner.is_some_and(|w| w != winner) {
                        self.stats.handovers += 1;
                    }
                    state.last_winner = Some(winner);
                    state.holder = Some(winner);
                    state.confirmed = None;
                    state.awarded_before = true;
                }
                self.stats.awards += 1;
                self.log
                    .push((now, format!("sector {s} awarded to {}", name(cx, winner))));
                self.close(conversation, cx);
            }
            CnetEvent::Done { task, winner, .. } => {
                let s = task as u32;
                if let Some(state) = self.sectors.get_mut(&s)
                    && state.holder == Some(winner)
                {
                    state.confirmed = Some(now);
                }
            }
            CnetEvent::Failed {
                conversation,
                task,
                reason,
                ..
            } => {
                let s = task as u32;
                self.stats.failed += 1;
                let winner = match reason {
                    CallFailure::NoProposals => None,
                    CallFailure::WinnerFailed { winner }
                    | CallFailure::ReportTimedOut { winner }
                    | CallFailure::WinnerUnreachable { winner, .. } => Some(winner),
                };
                if let Some(state) = self.sectors.get_mut(&s)
                    && (state.holder.is_none()
                        || (state.holder == winner && state.confirmed.is_none()))
                {
                    state.holder = None;
                    cx.set_timer(self.brief.retry, RETRY + u64::from(s));
                }
                self.close(conversation, cx);
            }
            _ => {}
        }
    }

    /// The open call is over: the next one.
    fn close(&mut self, conversation: u64, cx: &mut Context<'_, Field>) {
        if self.open.is_some_and(|(c, _)| c == conversation) {
            self.open = None;
        }
        self.call_next(cx);
    }

    /// A UAV's status: it is alive; its claims are checked against the picture.
    fn on_status(&mut self, env: &Envelope<Net>, claims: &[u32], cx: &mut Context<'_, Field>) {
        let (u, now) = (env.from, cx.now());
        self.heard.insert(u, now);
        if let Net::Status { pos, .. } = &env.body
            && self.brief.method == AllocationMethod::Central
        {
            let at = self.brief.site.to_town([pos[0], pos[1]]);
            self.allot.positions.insert(u, at);
        }
        if self.presumed_lost.remove(&u) {
            self.log.push((now, format!("{} heard again", name(cx, u))));
        }
        let open = self.open.map(|(_, s)| s);
        let mut revoke = Vec::new();
        for &s in claims {
            let Some(state) = self.sectors.get_mut(&s) else {
                continue;
            };
            match state.holder {
                Some(h) if h == u => {
                    state.confirmed.get_or_insert(now);
                }
                Some(_) => revoke.push(s),
                None if open == Some(s) => revoke.push(s),
                None => {
                    state.holder = Some(u);
                    state.confirmed = Some(now);
                    self.queue.retain(|&q| q != s);
                }
            }
        }
        // Sectors it confirmed before this report was sent but no longer claims: free.
        let dropped: Vec<u32> = (self.sectors.iter())
            .filter(|(s, st)| {
                st.holder == Some(u)
                    && st.confirmed.is_some_and(|t| t < env.sent_at)
                    && !claims.contains(s)
            })
            .map(|(s, _)| *s)
            .collect();
        for s in dropped {
            self.release(s);
        }
        if !revoke.is_empty() {
            self.stats.revocations += 1;
            cx.send(Outgoing::new(
                Address::Agent(u),
                Net::Revoke { sectors: revoke },
            ));
        }
        self.call_next(cx);
    }

    /// Sector `s` has no holder any more: it is called again.
    fn release(&mut self, s: u32) {
        if let Some(state) = self.sectors.get_mut(&s) {
            state.holder = None;
            state.confirmed = None;
            if !self.queue.contains(&s) {
                self.queue.push_back(s);
            }
        }
    }

    /// UAVs silent for too long are presumed lost; their sectors are called again.
    fn check(&mut self, cx: &mut Context<'_, Field>) {
        let now = cx.now();
        let brief = self.brief.clone();
        let d = brief.discipline;
        for &u in &brief.team {
            let last = self.heard.get(&u).copied().unwrap_or(SimTime::ZERO);
            if self.presumed_lost.contains(&u) || now.saturating_since(last) <= d.lost_after {
                continue;
            }
            self.presumed_lost.insert(u);
            self.stats.presumed_lost += 1;
            self.allot.positions.remove(&u);
            let held: Vec<u32> = (self.sectors.iter())
                .filter(|(_, st)| st.holder == Some(u))
                .map(|(s, _)| *s)
                .collect();
            self.log.push((
                now,
                format!(
                    "{} presumed lost: {} sector(s) called again",
                    name(cx, u),
                    held.len()
                ),
            ));
            for s in held {
                self.release(s);
            }
        }
        self.unconfirmed(now);
        cx.set_timer(d.heartbeat, CHECK);
        self.call_next(cx);
    }
}

fn name(cx: &Context<'_, Field>, id: EntityId) -> String {
    cx.name_of(id)
        .map_or_else(|| format!("#{}", id.0), str::to_owned)
}

impl Controller<Field> for Station {
    fn handle(&mut self, input: Input<'_, Field>, cx: &mut Context<'_, Field>) {
        match self.cnet.handle(input, cx) {
            Handled::Event(e) => return self.on_cnet(e, cx),
            Handled::Consumed => return,
            Handled::NotMine => {}
        }
        match input {
            Input::Event(Ev::Start) => self.start(cx),
            Input::Timer(CHECK) => self.check(cx),
            Input::Timer(PLANNED) => self.planned(cx),
            Input::Timer(k) if k >= ROUND => self.round_over(k - ROUND, cx),
            Input::Timer(k) if (TASKING..RETRY).contains(&k) => {
                let brief = self.brief.clone();
                if let Some((_, sectors)) = brief.tasking.get((k - TASKING) as usize) {
                    self.add_sectors(sectors);
                    let line = format!("tasked with a new area: {} sector(s)", sectors.len());
                    self.log.push((cx.now(), line));
                }
                self.call_next(cx);
            }
            Input::Timer(k) if k >= RETRY => {
                let s = (k - RETRY) as u32;
                if self.sectors.get(&s).is_some_and(|st| st.holder.is_none()) {
                    self.release(s);
                }
                self.call_next(cx);
            }
            Input::Message(env) => match &env.body {
                Net::Status { sectors, .. } => self.on_status(env, sectors, cx),
                &Net::Bid {
                    round,
                    sector,
                    cost,
                } => self.on_bid(env.from, round, sector, cost),
                _ => {}
            },
            _ => {}
        }
    }

    fn intention(&self) -> Option<Intention> {
        let held = self.sectors.values().filter(|s| s.holder.is_some()).count();
        let text = format!(
            "{held}/{} sectors held, {} waiting, {} UAV(s) presumed lost",
            self.sectors.len(),
            self.queue.len(),
            self.presumed_lost.len()
        );
        Some(Intention {
            text,
            plan: self
                .open
                .map(|(_, s)| format!("calling sector {s}"))
                .into_iter()
                .collect(),
            ..Intention::default()
        })
    }
}

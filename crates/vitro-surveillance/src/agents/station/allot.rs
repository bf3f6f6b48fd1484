//! The station's other two ways of sharing the sectors out, chosen by the scenario
//! (`[allocation] method`):
//!
//! - **auction**: sequential single-item auctions over the radio (Koenig et al., "The power
//!   of sequential single-item auctions for agent coordination", AAAI 2006). Each round the
//!   station announces every sector waiting ([`Net::Round`], to each UAV it believes
//!   flying); each UAV bids for the one it adds most cheaply to what it holds ([`Net::Bid`],
//!   the same cost as its contract-net proposal); after the proposal deadline the lowest
//!   bid wins, and the award rides on the next round's announcement. A round without bids
//!   fails, its sectors called again after `retry_s`.
//! - **central**: the station poses the waiting sectors as a capacitated vehicle routing
//!   problem — its own position the depot, the sectors' centres the customers (one unit of
//!   demand each), one vehicle per UAV it believes flying, of capacity the sectors shared
//!   evenly — and solves it with `vitro_routing`'s large neighbourhood search. The search
//!   takes simulated time (`budget` iterations at `iteration_ms` each); then each tour goes
//!   ([`Net::Assign`]) to the UAV last reported nearest it, the tours matched greedily.
//!
//! Either way the station's picture is what the UAVs report: an assigned sector that no
//! status report of its holder claims within the report deadline plus a heartbeat is
//! released and allotted again (a failed call).

use super::{PLANNED, RETRY, ROUND, Round, Station, name};
use crate::model::Field;
use crate::net::{ALLOCATION, Net};
use crate::sector::{Rect, centre, dist};
use vitro::comm::{Address, Outgoing};
use vitro::entity::EntityId;
use vitro::sim::Context;
use vitro::time::SimTime;
use vitro_routing::{Instance, Metric, Node, Options, Solver, solve};

impl Station {
    /// The UAVs it believes flying.
    fn alive(&self) -> Vec<EntityId> {
        (self.brief.team.iter())
            .copied()
            .filter(|u| !self.presumed_lost.contains(u))
            .collect()
    }

    /// The sectors waiting for a holder, in queue order, each once.
    fn waiting(&self) -> Vec<u32> {
        let mut out: Vec<u32> = Vec::new();
        for &s in &self.queue {
            if self.sectors.get(&s).is_some_and(|st| st.holder.is_none()) && !out.contains(&s) {
                out.push(s);
            }
        }
        out
    }

    /// Sector `s` is `u`'s now, as far as the station knows (to be confirmed).
    fn assign(&mut self, s: u32, u: EntityId, now: SimTime) {
        let Some(state) = self.sectors.get_mut(&s) else {
            return;
        };
        if state.awarded_before {
            self.stats.reallocations += 1;
        }
        if state.last_winner.is_some_and(|w| w != u) {
            self.stats.handovers += 1;
        }
        state.last_winner = Some(u);
        state.holder = Some(u);
        state.confirmed = None;
        state.awarded_before = true;
        state.assigned = Some(now);
        self.stats.awards += 1;
        self.queue.retain(|&q| q != s);
    }

    /// Sectors assigned but not claimed in time are released (failed calls).
    pub(super) fn unconfirmed(&mut self, now: SimTime) {
        let d = self.brief.discipline;
        let late: Vec<u32> = (self.sectors.iter())
            .filter(|(_, st)| {
                st.holder.is_some()
                    && st.confirmed.is_none()
                    && st.assigned.is_some_and(|t| {
                        now.saturating_since(t) > d.cnet.report_deadline + d.heartbeat
                    })
            })
            .map(|(s, _)| *s)
            .collect();
        for s in late {
            self.stats.failed += 1;
            if let Some(st) = self.sectors.get_mut(&s) {
                st.assigned = None;
            }
            self.release(s);
        }
    }

    /// Opens the next auction round if sectors are waiting (announcing the last award
    /// either way).
    pub(super) fn next_round(&mut self, cx: &mut Context<'_, Field>) {
        if self.allot.round.is_some() || self.alive().is_empty() {
            return;
        }
        let waiting = self.waiting();
        if waiting.is_empty() && self.allot.award.is_none() {
            return;
        }
        self.allot.rounds += 1;
        let id = self.allot.rounds;
        let sectors: Vec<(u32, Rect)> = (waiting.iter())
            .filter_map(|s| self.sectors.get(s).map(|st| (*s, st.area)))
            .collect();
        let body = Net::Round {
            round: id,
            award: self.allot.award.take(),
            sectors,
        };
        // One copy to each UAV it believes flying (as the contract net's calls: a UAV
        // that has not joined the team's group yet still hears it).
        for u in self.alive() {
            cx.send(Outgoing::new(Address::Agent(u), body.clone()).protocol(ALLOCATION, id));
        }
        if waiting.is_empty() {
            return;
        }
        self.stats.calls += 1;
        let deadline = self.brief.discipline.cnet.proposal_deadline;
        cx.set_timer(deadline, ROUND + id);
        self.allot.round = Some(Round {
            id,
            sectors: waiting,
            bids: Vec::new(),
        });
    }

    /// A UAV's bid in an auction round.
    pub(super) fn on_bid(&mut self, from: EntityId, round: u64, sector: u32, cost: f64) {
        if let Some(r) = self.allot.round.as_mut()
            && r.id == round
            && r.sectors.contains(&sector)
            && cost.is_finite()
        {
            r.bids.push((cost, from, sector));
        }
    }

    /// Auction round `id`'s deadline: the lowest bid wins.
    pub(super) fn round_over(&mut self, id: u64, cx: &mut Context<'_, Field>) {
        let Some(r) = self.allot.round.take_if(|r| r.id == id) else {
            return;
        };
        let now = cx.now();
        let best = (r.bids.iter())
            .filter(|(_, u, s)| {
                !self.presumed_lost.contains(u)
                    && self.sectors.get(s).is_some_and(|st| st.holder.is_none())
            })
            .min_by(|a, b| a.0.total_cmp(&b.0).then(a.1.cmp(&b.1)).then(a.2.cmp(&b.2)));
        match best {
            Some(&(_, u, s)) => {
                self.assign(s, u, now);
                if let Some(area) = self.sectors.get(&s).map(|st| st.area) {
                    self.allot.award = Some((u, s, area));
                }
                self.log
                    .push((now, format!("sector {s} auctioned to {}", name(cx, u))));
            }
            None => {
                self.stats.failed += 1;
                for s in r.sectors {
                    self.queue.retain(|&q| q != s);
                    cx.set_timer(self.brief.retry, RETRY + u64::from(s));
                }
            }
        }
        self.next_round(cx);
    }

    /// Starts the central search over the waiting sectors, if there are any and no search
    /// is running.
    pub(super) fn next_plan(&mut self, cx: &mut Context<'_, Field>) {
        if self.allot.plan.is_some() {
            return;
        }
        let alive = self.alive();
        let waiting = self.waiting();
        if alive.is_empty() || waiting.is_empty() {
            return;
        }
        let home = self.brief.home;
        let mut nodes = vec![Node::untimed(home[0], home[1], 0)];
        for s in &waiting {
            let c = self.sectors.get(s).map_or(home, |st| centre(st.area));
            nodes.push(Node::untimed(c[0], c[1], 1));
        }
        let capacity = waiting.len().div_ceil(alive.len()) as u64;
        let inst = Instance::new(
            "sectors",
            nodes,
            capacity,
            Some(alive.len()),
            Metric::Euclidean,
        );
        let budget = self.brief.budget;
        let options = Options {
            solver: Solver::LocalSearch { budget },
            seed: self.allot.plans,
        };
        let solution = solve(&inst, &options);
        self.allot.plans += 1;
        self.stats.calls += 1;
        // Each tour to the UAV last reported nearest one of its sectors, nearest pair first.
        let tours: Vec<Vec<u32>> = (solution.routes.iter())
            .filter(|r| !r.is_empty())
            .map(|r| r.iter().map(|&c| waiting[c - 1]).collect())
            .collect();
        let mut pairs = Vec::new();
        for (t, tour) in tours.iter().enumerate() {
            for (k, u) in alive.iter().enumerate() {
                let at = self.allot.positions.get(u).copied().unwrap_or(home);
                let d = (tour.iter())
                    .filter_map(|s| self.sectors.get(s))
                    .map(|st| dist(at, centre(st.area)))
                    .fold(f64::INFINITY, f64::min);
                pairs.push((d, t, k));
            }
        }
        pairs.sort_by(|a, b| a.0.total_cmp(&b.0).then(a.1.cmp(&b.1)).then(a.2.cmp(&b.2)));
        let (mut tour_done, mut uav_done) = (vec![false; tours.len()], vec![false; alive.len()]);
        let mut plan = Vec::new();
        for (_, t, k) in pairs {
            if !tour_done[t] && !uav_done[k] {
                (tour_done[t], uav_done[k]) = (true, true);
                plan.push((alive[k], tours[t].clone()));
            }
        }
        for s in &waiting {
            self.queue.retain(|q| q != s);
        }
        // Sectors no tour took (none, with one unit of demand each and room for all).
        for &c in &solution.unassigned {
            cx.set_timer(self.brief.retry, RETRY + u64::from(waiting[c - 1]));
        }
        self.allot.plan = Some(plan);
        cx.set_timer(self.brief.search_cost.cost(budget), PLANNED);
    }

    /// The central search is over: each UAV is sent its tour.
    pub(super) fn planned(&mut self, cx: &mut Context<'_, Field>) {
        let Some(plan) = self.allot.plan.take() else {
            return;
        };
        let now = cx.now();
        for (u, tour) in plan {
            let mut sent = Vec::new();
            for s in tour {
                let free = self.sectors.get(&s).is_some_and(|st| st.holder.is_none());
                if !free {
                    continue;
                }
                if self.presumed_lost.contains(&u) {
                    self.release(s);
                    continue;
                }
                self.assign(s, u, now);
                if let Some(st) = self.sectors.get(&s) {
                    sent.push((s, st.area));
                }
            }
            if !sent.is_empty() {
                let line = format!("{} sector(s) planned for {}", sent.len(), name(cx, u));
                self.log.push((now, line));
                let body = Net::Assign { sectors: sent };
                cx.send(
                    Outgoing::new(Address::Agent(u), body).protocol(ALLOCATION, self.allot.plans),
                );
            }
        }
        self.next_plan(cx);
    }
}

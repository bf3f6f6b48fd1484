//! The referee: measures the mission from outside, with the ground truth no agent has
//! (which red units exist, which UAVs were lost and when) and the agents' own records
//! (each UAV's lock spans, the station's counts), read after the fact.
//!
//! - **time to first detection** of a red unit: when a UAV's tracker first took a lock on
//!   it (its own camera identified it as red); its mean over the units detected, and its
//!   restricted mean over all units (an undetected one counted at the time run);
//! - **tracked share**: the share of the run during which some UAV held a lock on it (the
//!   union of every UAV's lock spans, each ended at the UAV's loss);
//! - messages sent and lost on the radio, contract-net messages, the allocation method's
//!   messages, calls, awards, failed calls, re-allocations (calls for sectors awarded
//!   before) and handovers (awards of a sector to another UAV than its last winner),
//!   revocations, UAVs lost and presumed lost.

use crate::agents::station::Station;
use crate::agents::uav::Uav;
use crate::model::Field;
use crate::net::ALLOCATION;
use crate::setup::Member;
use serde::Serialize;
use std::collections::BTreeMap;
use vitro::comm::Protocol;
use vitro::entity::EntityId;
use vitro::sim::Simulation;
use vitro::time::SimTime;

/// What the referee measures of one red unit.
#[derive(Clone, Debug, Default, PartialEq, Serialize)]
pub struct RedRecord {
    /// When it was first locked, seconds (none: never).
    pub first_detection_s: Option<f64>,
    /// How long some UAV held a lock on it, seconds.
    pub tracked_s: f64,
    /// `tracked_s` over the time run.
    pub tracked_share: f64,
}

/// The mission's metrics.
#[derive(Clone, Debug, Default, PartialEq, Serialize)]
pub struct Metrics {
    /// Red units in the run.
    pub red_units: u32,
    /// Red units locked at least once.
    pub red_detected: u32,
    /// Mean time to first detection over the red units detected, seconds.
    pub mean_time_to_detection_s: Option<f64>,
    /// Longest time to first detection, seconds.
    pub max_time_to_detection_s: Option<f64>,
    /// Mean time to first detection over every red unit, an undetected one counted at the
    /// time run (a restricted mean: comparable between runs that detect more or fewer),
    /// seconds.
    pub restricted_time_to_detection_s: f64,
    /// Mean share of the run each red unit was tracked.
    pub mean_tracked_share: f64,
    /// Smallest share of the run a red unit was tracked.
    pub min_tracked_share: f64,
    /// Messages sent (every copy).
    pub messages_sent: u64,
    /// Messages lost on the channel.
    pub messages_lost: u64,
    /// Contract-net messages sent.
    pub cnet_messages: u64,
    /// Messages of the allocation method sent (the contract net's, or the auction's rounds
    /// and bids, or the central plan's assignments; status reports not counted).
    pub allocation_messages: u64,
    /// Calls for proposals the station made.
    pub calls: u64,
    /// Calls awarded.
    pub awards: u64,
    /// Calls that ended without a confirmed holder.
    pub calls_failed: u64,
    /// Calls for sectors awarded before.
    pub reallocations: u64,
    /// Awards of a sector to another UAV than its last winner.
    pub handovers: u64,
    /// Revocations the station sent.
    pub revocations: u64,
    /// UAVs in the run.
    pub uavs: u32,
    /// UAVs lost (scheduled or failed).
    pub uavs_lost: u32,
    /// Times the station presumed a UAV lost.
    pub presumed_lost: u64,
    /// Sectors the station knows of.
    pub sectors: u32,
    /// Sectors with a holder in the station's picture.
    pub sectors_held: u32,
    /// Events fired.
    pub events: u64,
    /// Simulated time reached, seconds.
    pub sim_time_s: f64,
    /// Per red unit, by name.
    pub red: BTreeMap<String, RedRecord>,
}

/// The length of the union of intervals.
fn union_length(mut spans: Vec<(f64, f64)>) -> f64 {
    spans.sort_by(|a, b| a.0.total_cmp(&b.0).then(a.1.total_cmp(&b.1)));
    let mut total = 0.0;
    let mut cur: Option<(f64, f64)> = None;
    for (a, b) in spans.into_iter().filter(|(a, b)| b > a) {
        cur = match cur {
            Some((s, e)) if a <= e => Some((s, e.max(b))),
            Some((s, e)) => {
                total += e - s;
                Some((a, b))
            }
            None => Some((a, b)),
        };
    }
    total + cur.map_or(0.0, |(s, e)| e - s)
}

/// Measures the run so far; `lost` holds each lost UAV's loss time.
pub fn measure(
    sim: &Simulation<Field>,
    members: &[Member],
    lost: &BTreeMap<EntityId, SimTime>,
) -> Metrics {
    let now = sim.now();
    let now_s = now.as_secs_f64();
    let mut spans: BTreeMap<EntityId, Vec<(f64, f64)>> = BTreeMap::new();
    let mut first: BTreeMap<EntityId, f64> = BTreeMap::new();
    let mut m = Metrics::default();
    for mem in members {
        let agent = sim.agent(mem.id).map(|a| a.as_any());
        if let Some(u) = agent.and_then(|a| a.downcast_ref::<Uav>()) {
            m.uavs += 1;
            let cap = lost.get(&mem.id).copied().unwrap_or(now).min(now);
            for s in &u.spans {
                let from = s.from.min(cap).as_secs_f64();
                let to = s.to.unwrap_or(now).min(cap).as_secs_f64();
                spans.entry(s.target).or_default().push((from, to));
                let f = first.entry(s.target).or_insert(f64::INFINITY);
                *f = f.min(s.from.as_secs_f64());
            }
        }
        if let Some(st) = agent.and_then(|a| a.downcast_ref::<Station>()) {
            let s = st.stats;
            (m.calls, m.awards, m.calls_failed) = (s.calls, s.awards, s.failed);
            (m.reallocations, m.revocations, m.presumed_lost) =
                (s.reallocations, s.revocations, s.presumed_lost);
            m.handovers = s.handovers;
            m.sectors = st.sectors.len() as u32;
            m.sectors_held = st.sectors.values().filter(|x| x.holder.is_some()).count() as u32;
        }
    }
    let mut delays = Vec::new();
    let mut shares = Vec::new();
    let mut restricted = 0.0;
    for mem in members.iter().filter(|x| x.is_red()) {
        let first_s = first.get(&mem.id).copied().filter(|t| t.is_finite());
        let tracked_s = union_length(spans.remove(&mem.id).unwrap_or_default());
        let share = if now_s > 0.0 { tracked_s / now_s } else { 0.0 };
        delays.extend(first_s);
        restricted += first_s.unwrap_or(now_s);
        shares.push(share);
        m.red.insert(
            mem.name.clone(),
            RedRecord {
                first_detection_s: first_s,
                tracked_s,
                tracked_share: share,
            },
        );
    }
    m.red_units = shares.len() as u32;
    m.red_detected = delays.len() as u32;
    if !delays.is_empty() {
        m.mean_time_to_detection_s = Some(delays.iter().sum::<f64>() / delays.len() as f64);
        m.max_time_to_detection_s = delays.iter().copied().reduce(f64::max);
    }
    if !shares.is_empty() {
        m.restricted_time_to_detection_s = restricted / shares.len() as f64;
        m.mean_tracked_share = shares.iter().sum::<f64>() / shares.len() as f64;
        m.min_tracked_share = shares.iter().copied().fold(f64::INFINITY, f64::min);
    }
    for (_, protocol, c) in sim.network().all_counts() {
        m.messages_sent += c.sent;
        m.messages_lost += c.lost;
        if protocol == Protocol::ContractNet {
            m.cnet_messages += c.sent;
        }
        if protocol == Protocol::ContractNet || protocol == ALLOCATION {
            m.allocation_messages += c.sent;
        }
    }
    m.uavs_lost = lost.len() as u32;
    m.events = sim.events_fired();
    m.sim_time_s = now_s;
    m
}

#[cfg(test)]
mod tests {
    use super::union_length;

    #[test]
    fn overlapping_spans_count_once() {
        assert_eq!(union_length(vec![]), 0.0);
        assert_eq!(
            union_length(vec![(0.0, 10.0), (5.0, 15.0), (20.0, 25.0)]),
            20.0
        );
        assert_eq!(union_length(vec![(3.0, 3.0), (1.0, 2.0), (0.0, 4.0)]), 4.0);
    }
}

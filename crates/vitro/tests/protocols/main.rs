//! Interaction protocols over the simulated network: request/inform, query, subscribe/notify,
//! contract net and token ring, each on a perfect channel and with lost messages.

use serde::Serialize;
use std::sync::{Arc, Mutex};
use vitro::comm::MessageCounts;
use vitro::prelude::*;
use vitro::protocol::{Handled, Reply, TimerTag};

const TAG: TimerTag = TimerTag(1);

fn ms(n: u64) -> SimDuration {
    SimDuration::from_millis(n)
}
fn secs(n: u64) -> SimDuration {
    SimDuration::from_secs(n)
}
fn at(d: SimDuration) -> SimTime {
    SimTime::ZERO + d
}

/// Sets the loss of the directed link `from -> to`, the rest as the default link.
fn set_loss<M: Model>(sim: &mut Simulation<M>, from: EntityId, to: EntityId, loss: f64) {
    let p = LinkParams {
        loss,
        ..*sim.network().default_link()
    };
    sim.network_mut().set_link(from, to, p);
}

/// Every copy sent under `p` was received, lost or bounced.
fn assert_balanced<M: Model>(sim: &Simulation<M>, p: Protocol) {
    let t = sim.network().all_counts().filter(|&(_, q, _)| q == p).fold(
        MessageCounts::default(),
        |mut t, (_, _, c)| {
            t.sent += c.sent;
            t.received += c.received;
            t.lost += c.lost;
            t.bounced += c.bounced;
            t
        },
    );
    assert_eq!(t.sent, t.received + t.lost + t.bounced, "{p:?}: {t:?}");
}

mod contract_net;
mod query;
mod request_inform;
mod subscribe_notify;
mod token_ring;

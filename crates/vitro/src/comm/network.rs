//! Addresses, envelopes, link parameters and the routing decision of the simulated network.

use crate::entity::EntityId;
use crate::time::{SimDuration, SimTime};
use rand::Rng;
use serde::{Deserialize, Serialize};
use std::collections::{BTreeMap, BTreeSet};

/// A multicast group.
#[derive(Copy, Clone, Debug, PartialEq, Eq, PartialOrd, Ord, Hash, Serialize, Deserialize)]
pub struct GroupId(pub u32);

/// Where a message goes.
#[derive(Copy, Clone, Debug, PartialEq, Eq, PartialOrd, Ord, Hash, Serialize, Deserialize)]
pub enum Address {
    /// One agent (direct).
    Agent(EntityId),
    /// Every member of a group but the sender (multicast).
    Group(GroupId),
    /// Every agent but the sender.
    Broadcast,
}

/// The interaction protocol a message belongs to (message counts are kept per protocol).
#[derive(Copy, Clone, Debug, PartialEq, Eq, PartialOrd, Ord, Hash, Serialize, Deserialize)]
pub enum Protocol {
    /// No protocol: a plain message.
    Plain,
    /// Request / inform.
    Request,
    /// Query (query-if / query-ref, answered by inform).
    Query,
    /// Subscribe / notify.
    Subscribe,
    /// Contract net (call for proposals).
    ContractNet,
    /// Token ring.
    TokenRing,
    /// A protocol of the model's own.
    Custom(u16),
}

/// The communicative act of a message (FIPA-style).
#[derive(Copy, Clone, Debug, PartialEq, Eq, PartialOrd, Ord, Hash, Serialize, Deserialize)]
pub enum Performative {
    /// Telling a fact.
    Inform,
    /// Asking for an action.
    Request,
    /// Agreeing to a request.
    Agree,
    /// Refusing a request or a call for proposals.
    Refuse,
    /// An action failed.
    Failure,
    /// An action is done.
    Done,
    /// Asking whether something holds.
    QueryIf,
    /// Asking for a value.
    QueryRef,
    /// Asking to be notified of changes.
    Subscribe,
    /// A notification to a subscriber.
    Notify,
    /// Ending a subscription or a conversation.
    Cancel,
    /// Call for proposals.
    Cfp,
    /// A proposal (bid).
    Propose,
    /// A proposal is accepted.
    AcceptProposal,
    /// A proposal is rejected.
    RejectProposal,
    /// A token handed on (token ring).
    Token,
}

/// A message as delivered.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct Envelope<Msg> {
    /// The sender.
    pub from: EntityId,
    /// The address it was sent to.
    pub to: Address,
    /// The agent this copy is for.
    pub receiver: EntityId,
    /// Its protocol.
    pub protocol: Protocol,
    /// Its communicative act.
    pub performative: Performative,
    /// Conversation id chosen by the initiator (0 if none).
    pub conversation: u64,
    /// When it was sent.
    pub sent_at: SimTime,
    /// Its size on the channel, in bytes.
    pub size_bytes: u32,
    /// The content.
    pub body: Msg,
}

/// A message to send: built with [`Outgoing::new`] and the setters.
#[derive(Clone, Debug, PartialEq)]
pub struct Outgoing<Msg> {
    /// Destination.
    pub to: Address,
    /// Protocol (default [`Protocol::Plain`]).
    pub protocol: Protocol,
    /// Act (default [`Performative::Inform`]).
    pub performative: Performative,
    /// Conversation id (default 0).
    pub conversation: u64,
    /// Size in bytes (default 64).
    pub size_bytes: u32,
    /// Content.
    pub body: Msg,
}

impl<Msg> Outgoing<Msg> {
    /// An `Inform` of `body` to `to`, 64 bytes, no protocol.
    pub fn new(to: Address, body: Msg) -> Self {
        Outgoing {
            to,
            protocol: Protocol::Plain,
            performative: Performative::Inform,
            conversation: 0,
            size_bytes: 64,
            body,
        }
    }
    /// Sets the protocol and conversation id.
    pub fn protocol(mut self, protocol: Protocol, conversation: u64) -> Self {
        self.protocol = protocol;
        self.conversation = conversation;
        self
    }
    /// Sets the communicative act.
    pub fn performative(mut self, p: Performative) -> Self {
        self.performative = p;
        self
    }
    /// Sets the size on the channel.
    pub fn size(mut self, bytes: u32) -> Self {
        self.size_bytes = bytes;
        self
    }
}

/// Why a message came back to its sender.
#[derive(Copy, Clone, Debug, PartialEq, Serialize, Deserialize, thiserror::Error)]
pub enum DeliveryError {
    /// No agent has that id.
    #[error("no agent {0} to deliver to")]
    UnknownReceiver(EntityId),
    /// The group does not exist or has no member but the sender.
    #[error("multicast group {0:?} has no receiver")]
    EmptyGroup(GroupId),
    /// The receiver is beyond the channel's range.
    #[error("receiver {receiver} is {distance_m:.1} m away, beyond the {range_m:.1} m range")]
    OutOfRange {
        /// The intended receiver.
        receiver: EntityId,
        /// Its distance.
        distance_m: f64,
        /// The link's range.
        range_m: f64,
    },
    /// The channel has a range limit but a position is unknown.
    #[error("position of {0} unknown on a range-limited channel")]
    NoPosition(EntityId),
}

impl DeliveryError {
    /// The agent the returned copy was meant for, where the error names it (not for
    /// [`EmptyGroup`](Self::EmptyGroup), nor for a [`NoPosition`](Self::NoPosition) of the
    /// sender itself, which it cannot tell apart).
    ///
    /// Useful for multicast and broadcast bounces, whose envelope is addressed to the group.
    pub fn receiver(&self) -> Option<EntityId> {
        match *self {
            DeliveryError::UnknownReceiver(r) => Some(r),
            DeliveryError::OutOfRange { receiver, .. } => Some(receiver),
            DeliveryError::EmptyGroup(_) | DeliveryError::NoPosition(_) => None,
        }
    }
}

/// Parameters of a link (or of the default channel).
#[derive(Copy, Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct LinkParams {
    /// Fixed propagation delay.
    pub delay: SimDuration,
    /// Extra delay drawn uniformly in `[0, jitter]`.
    pub jitter: SimDuration,
    /// Probability that a message is lost silently, in `[0, 1]`.
    pub loss: f64,
    /// Range limit in metres (needs positions), `None` for unlimited.
    pub range_m: Option<f64>,
    /// Bandwidth in bits per second (the sender's transmitter serialises its messages), `None`
    /// for unlimited.
    pub bandwidth_bps: Option<f64>,
}

impl Default for LinkParams {
    /// A perfect channel: 1 ms delay, no jitter, no loss, unlimited range and bandwidth.
    fn default() -> Self {
        LinkParams {
            delay: SimDuration::from_millis(1),
            jitter: SimDuration::ZERO,
            loss: 0.0,
            range_m: None,
            bandwidth_bps: None,
        }
    }
}

/// Messages counted for one (agent, protocol).
#[derive(Copy, Clone, Debug, Default, PartialEq, Eq, Serialize, Deserialize)]
pub struct MessageCounts {
    /// Copies sent (a broadcast to n agents counts n).
    pub sent: u64,
    /// Copies delivered to this agent.
    pub received: u64,
    /// Copies this agent sent that were lost.
    pub lost: u64,
    /// Copies this agent sent that came back undeliverable.
    pub bounced: u64,
}

/// What happens to one copy of a message.
#[derive(Copy, Clone, Debug, PartialEq, Serialize, Deserialize)]
pub enum Route {
    /// Delivered to `receiver` at `at`.
    Deliver {
        /// The receiver.
        receiver: EntityId,
        /// Arrival time.
        at: SimTime,
    },
    /// Lost on the way to `receiver`.
    Lost {
        /// The receiver it was meant for.
        receiver: EntityId,
    },
    /// Returned to the sender at `at`.
    Bounce {
        /// The receiver this copy was meant for (`None` for an empty group).
        receiver: Option<EntityId>,
        /// Why.
        error: DeliveryError,
        /// When the sender learns it.
        at: SimTime,
    },
}

/// The simulated network: link parameters, groups, transmitter state and message counts.
#[derive(Clone, Debug, Default, Serialize, Deserialize)]
pub struct Network {
    default: LinkParams,
    links: BTreeMap<(EntityId, EntityId), LinkParams>,
    groups: BTreeMap<GroupId, BTreeSet<EntityId>>,
    tx_busy_until: BTreeMap<EntityId, SimTime>,
    counts: BTreeMap<(EntityId, Protocol), MessageCounts>,
}

impl Network {
    /// A network whose links all have `default` parameters.
    pub fn new(default: LinkParams) -> Self {
        Network {
            default,
            ..Default::default()
        }
    }
    /// The default link parameters.
    pub fn default_link(&self) -> &LinkParams {
        &self.default
    }
    /// Replaces the default link parameters.
    pub fn set_default_link(&mut self, p: LinkParams) {
        self.default = p;
    }
    /// Sets the parameters of the directed link `from -> to`.
    pub fn set_link(&mut self, from: EntityId, to: EntityId, p: LinkParams) {
        self.links.insert((from, to), p);
    }
    /// The parameters of `from -> to`.
    pub fn link(&self, from: EntityId, to: EntityId) -> &LinkParams {
        self.links.get(&(from, to)).unwrap_or(&self.default)
    }
    /// Adds `who` to `group`.
    pub fn join(&mut self, group: GroupId, who: EntityId) {
        self.groups.entry(group).or_default().insert(who);
    }
    /// Removes `who` from `group`.
    pub fn leave(&mut self, group: GroupId, who: EntityId) {
        if let Some(g) = self.groups.get_mut(&group) {
            g.remove(&who);
        }
    }
    /// Members of `group`, in id order.
    pub fn members(&self, group: GroupId) -> impl Iterator<Item = EntityId> + '_ {
        self.groups.get(&group).into_iter().flatten().copied()
    }
    /// Message counts of (agent, protocol).
    pub fn counts(&self, who: EntityId, protocol: Protocol) -> MessageCounts {
        self.counts
            .get(&(who, protocol))
            .copied()
            .unwrap_or_default()
    }
    /// All message counts, in (agent, protocol) order.
    pub fn all_counts(&self) -> impl Iterator<Item = (EntityId, Protocol, MessageCounts)> + '_ {
        self.counts.iter().map(|(&(e, p), &c)| (e, p, c))
    }
    /// Total copies sent by everyone.
    pub fn total_sent(&self) -> u64 {
        self.counts.values().map(|c| c.sent).sum()
    }

    /// Counts one delivery to `receiver` (called by the driver when the copy arrives).
    pub fn count_received(&mut self, receiver: EntityId, protocol: Protocol) {
        self.counts
            .entry((receiver, protocol))
            .or_default()
            .received += 1;
    }

    /// Decides the fate of each copy of a message sent at `now`.
    ///
    /// `is_agent` says whether an entity has an agent to receive; `agents` lists all agents in
    /// registration order (for broadcast); `locate` is the position sensor for range limits;
    /// `rng` is the sender's channel stream.
    ///
    /// Every copy is counted once as `sent` for (sender, protocol), then as `lost` or `bounced`
    /// if so (its `received` is counted on arrival, by [`count_received`](Self::count_received)).
    /// A multicast to a group with no member but the sender is one copy, bounced with
    /// [`DeliveryError::EmptyGroup`]; a broadcast with no other agent sends nothing.
    /// Multicast copies go out in member id order, broadcast copies in registration order.
    #[allow(clippy::too_many_arguments)]
    pub fn route<R: Rng>(
        &mut self,
        from: EntityId,
        to: Address,
        protocol: Protocol,
        size_bytes: u32,
        now: SimTime,
        agents: &[EntityId],
        is_agent: impl Fn(EntityId) -> bool,
        locate: impl Fn(EntityId) -> Option<[f64; 3]>,
        rng: &mut R,
    ) -> Vec<Route> {
        let receivers: Vec<EntityId> = match to {
            Address::Agent(r) => vec![r],
            Address::Group(g) => self.members(g).filter(|&r| r != from).collect(),
            Address::Broadcast => agents.iter().copied().filter(|&r| r != from).collect(),
        };
        let mut routes = Vec::with_capacity(receivers.len().max(1));
        if receivers.is_empty() {
            if let Address::Group(g) = to {
                // One copy went out and came back: counted as sent and bounced, so that
                // `sent = received by others + lost + bounced` always holds.
                let at = now + self.default.delay;
                let c = self.counts.entry((from, protocol)).or_default();
                c.sent += 1;
                c.bounced += 1;
                routes.push(Route::Bounce {
                    receiver: None,
                    error: DeliveryError::EmptyGroup(g),
                    at,
                });
            }
            return routes;
        }
        // One transmission serves every receiver (a radio): the transmitter is busy for
        // size / bandwidth of the default link (or of the direct link).
        let tx_link = match to {
            Address::Agent(r) => *self.link(from, r),
            _ => self.default,
        };
        let start = now.max(self.tx_busy_until.get(&from).copied().unwrap_or(now));
        let tx_end = match tx_link.bandwidth_bps {
            Some(bps) if bps > 0.0 => {
                // Rounded up to the next nanosecond: n messages never take less than
                // n · size · 8 / bandwidth, however the division rounds.
                let nanos = (size_bytes as f64 * 8.0 * 1e9 / bps).ceil();
                let end = start + SimDuration::from_nanos(nanos as u64);
                self.tx_busy_until.insert(from, end);
                end
            }
            _ => start,
        };
        let sender_pos = locate(from);
        for r in receivers {
            let link = *self.link(from, r);
            let c = self.counts.entry((from, protocol)).or_default();
            c.sent += 1;
            let bounce = |error| Route::Bounce {
                receiver: Some(r),
                error,
                at: now + link.delay,
            };
            if !is_agent(r) {
                c.bounced += 1;
                routes.push(bounce(DeliveryError::UnknownReceiver(r)));
                continue;
            }
            if let Some(range_m) = link.range_m {
                match (sender_pos, locate(r)) {
                    (Some(a), Some(b)) => {
                        let d =
                            ((a[0] - b[0]).powi(2) + (a[1] - b[1]).powi(2) + (a[2] - b[2]).powi(2))
                                .sqrt();
                        if d > range_m {
                            c.bounced += 1;
                            routes.push(bounce(DeliveryError::OutOfRange {
                                receiver: r,
                                distance_m: d,
                                range_m,
                            }));
                            continue;
                        }
                    }
                    (None, _) => {
                        c.bounced += 1;
                        routes.push(bounce(DeliveryError::NoPosition(from)));
                        continue;
                    }
                    (_, None) => {
                        c.bounced += 1;
                        routes.push(bounce(DeliveryError::NoPosition(r)));
                        continue;
                    }
                }
            }
            // Draw loss and jitter every time, in this order, so the stream's use does not
            // depend on the outcome.
            let u: f64 = rng.random();
            let j = if link.jitter.as_nanos() > 0 {
                rng.random_range(0..=link.jitter.as_nanos())
            } else {
                0
            };
            if u < link.loss {
                c.lost += 1;
                routes.push(Route::Lost { receiver: r });
                continue;
            }
            routes.push(Route::Deliver {
                receiver: r,
                at: tx_end + link.delay + SimDuration::from_nanos(j),
            });
        }
        routes
    }
}

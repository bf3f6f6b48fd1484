//! Interaction protocols over the simulated network: [`request`]/inform, [`query`],
//! [`subscribe`]/notify, [`contract_net`] task allocation and [`token_ring`].
//!
//! Each protocol is a plain state machine that an agent keeps in its own state and drives from
//! its [`Agent::handle`](crate::sim::Agent::handle): the agent hands every input to the
//! machine, which answers
//! - [`Handled::NotMine`]: not this machine's message or timer, the agent goes on with it;
//! - [`Handled::Consumed`]: handled inside the machine (a late reply, an automatic answer);
//! - [`Handled::Event`]: something the agent reacts to (a request came in, a reply, a timeout).
//!
//! The machines send through [`Context::send`] and wake themselves through
//! [`Context::set_timer`]: no threads, no boxing, ordered maps only, so a run stays
//! deterministic. They derive `Serialize`, so agents holding them can be snapshotted.
//!
//! Conventions shared by all machines:
//! - **Bodies** are the model's own `Msg`; a machine never invents one. The agent gives the body
//!   of every message it starts or answers; the few automatic messages (a reject to a late
//!   bidder, a cancel for an unwanted notification, a token passed on past a dead member) echo
//!   the body of the message they answer.
//! - **Timers**: each machine is given a [`TimerTag`]; every timer key it sets carries the tag in
//!   its top 16 bits, and it claims only those. Give each machine of an agent its own tag, and
//!   keep the agent's own timer keys below 2^48 (tag 0) or under a tag of its own.
//! - **Conversations**: an initiator numbers its conversations `(its id << 32) | sequence`, so
//!   ids are unique per protocol in a run; replies carry the id back.
//! - **Deadlines** are timers: a reply that never comes (lost, or never sent) ends the
//!   conversation in an explicit timed-out state, never in a hang.
//! - **Counts**: every message a machine sends is tagged with its [`Protocol`], so
//!   [`Network::counts`](crate::comm::Network::counts) tells the messages per agent and
//!   protocol.
//!
//! ```
//! use vitro::prelude::*;
//! use vitro::protocol::{Handled, TimerTag, request::{RequestEvent, RequestInform}};
//!
//! #[derive(Clone, serde::Serialize)]
//! enum Msg { Double(u32), Ok, Result(u32) }
//!
//! struct Demo;
//! impl Model for Demo { type Env = (); type Event = (); type Msg = Msg; type Agent = Node; }
//!
//! struct Node { rq: RequestInform, server: Option<EntityId>, answer: Option<u32> }
//! impl Agent<Demo> for Node {
//!     fn handle(&mut self, input: Input<'_, Demo>, cx: &mut Context<'_, Demo>) {
//!         if let (Input::Event(()), Some(server)) = (input, self.server) {
//!             self.rq.request(cx, server, Msg::Double(21), Some(SimDuration::from_secs(1)));
//!             return;
//!         }
//!         match self.rq.handle(input, cx) {
//!             Handled::Event(RequestEvent::Requested { reply, request }) => {
//!                 if let Msg::Double(x) = request.body {
//!                     self.rq.agree(cx, reply, Msg::Ok);
//!                     self.rq.done(cx, reply, Msg::Result(2 * x));
//!                 }
//!             }
//!             Handled::Event(RequestEvent::Done { reply, .. }) => {
//!                 if let Msg::Result(y) = reply.body { self.answer = Some(y) }
//!             }
//!             _ => {}
//!         }
//!     }
//! }
//!
//! let mut sim = Simulation::<Demo>::new((), 1);
//! let node = |server| Node { rq: RequestInform::new(TimerTag(1)), server, answer: None };
//! let s = sim.add_agent("server", node(None)).unwrap();
//! let c = sim.add_agent("client", node(Some(s))).unwrap();
//! sim.schedule(SimTime::ZERO, Target::Entity(c), ()).unwrap();
//! sim.run_until(SimTime::MAX);
//! assert_eq!(sim.agent(c).unwrap().answer, Some(42));
//! assert_eq!(sim.network().counts(s, Protocol::Request).sent, 2); // agree + done
//! ```

pub mod contract_net;
mod exchange;
pub mod query;
pub mod request;
pub mod subscribe;
pub mod token_ring;

use crate::comm::{Address, Envelope, Outgoing, Performative, Protocol};
use crate::entity::EntityId;
use crate::sim::{Context, Model};
use serde::{Deserialize, Serialize};

pub use contract_net::{Bid, CallFailure, CnetConfig, CnetEvent, ContractNet, Participants};
pub use query::{Query, QueryEvent, QueryKind};
pub use request::{RequestEvent, RequestInform};
pub use subscribe::{SubscribeEvent, SubscribeNotify};
pub use token_ring::{RingError, TokenEvent, TokenRing};

/// What a protocol machine made of one input.
#[derive(Clone, Debug, PartialEq)]
pub enum Handled<E> {
    /// Not this machine's message or timer: the agent handles the input itself.
    NotMine,
    /// Handled inside the machine; nothing for the agent to do.
    Consumed,
    /// Something the agent must react to.
    Event(E),
}

impl<E> Handled<E> {
    /// True unless [`NotMine`](Self::NotMine).
    pub fn is_mine(&self) -> bool {
        !matches!(self, Handled::NotMine)
    }
    /// The event, if any.
    pub fn event(self) -> Option<E> {
        match self {
            Handled::Event(e) => Some(e),
            _ => None,
        }
    }
}

/// The 16-bit tag that marks a machine's timer keys (see the module documentation).
///
/// ```
/// use vitro::protocol::TimerTag;
/// let tag = TimerTag(3);
/// assert_eq!(tag.index(tag.key(42)), Some(42));
/// assert_eq!(TimerTag(4).index(tag.key(42)), None);
/// ```
#[derive(Copy, Clone, Debug, PartialEq, Eq, PartialOrd, Ord, Hash, Serialize, Deserialize)]
pub struct TimerTag(pub u16);

const TAG_SHIFT: u32 = 48;
const INDEX_MASK: u64 = (1 << TAG_SHIFT) - 1;

impl TimerTag {
    /// The timer key for `index` (its low 48 bits) under this tag.
    pub fn key(self, index: u64) -> u64 {
        (u64::from(self.0) << TAG_SHIFT) | (index & INDEX_MASK)
    }
    /// The index of `key` if it carries this tag.
    pub fn index(self, key: u64) -> Option<u64> {
        (key >> TAG_SHIFT == u64::from(self.0)).then_some(key & INDEX_MASK)
    }
}

/// Where an answer goes: the other party and the conversation (kept by a responder that
/// answers later, e.g. after an agree).
#[derive(Copy, Clone, Debug, PartialEq, Eq, PartialOrd, Ord, Hash, Serialize, Deserialize)]
pub struct Reply {
    /// The party to answer.
    pub to: EntityId,
    /// The conversation the answer belongs to.
    pub conversation: u64,
}

impl Reply {
    /// The answer to `env`: to its sender, in its conversation.
    pub fn to<Msg>(env: &Envelope<Msg>) -> Self {
        Reply {
            to: env.from,
            conversation: env.conversation,
        }
    }
}

/// The conversation id of an initiator's `seq`-th conversation.
fn conversation_id(me: EntityId, seq: u32) -> u64 {
    (u64::from(me.0) << 32) | u64::from(seq)
}

/// Sends one protocol message.
fn send<M: Model>(
    cx: &mut Context<'_, M>,
    to: Address,
    protocol: Protocol,
    performative: Performative,
    conversation: u64,
    size_bytes: u32,
    body: M::Msg,
) {
    cx.send(
        Outgoing::new(to, body)
            .protocol(protocol, conversation)
            .performative(performative)
            .size(size_bytes),
    );
}

/// Sends one answer within a conversation.
fn answer<M: Model>(
    cx: &mut Context<'_, M>,
    reply: Reply,
    protocol: Protocol,
    performative: Performative,
    size_bytes: u32,
    body: M::Msg,
) {
    send(
        cx,
        Address::Agent(reply.to),
        protocol,
        performative,
        reply.conversation,
        size_bytes,
        body,
    );
}

/// Default size of a protocol message on the channel, in bytes.
pub const DEFAULT_MESSAGE_SIZE: u32 = 64;

//! Query (FIPA query): `query-if` (does it hold?) or `query-ref` (what is it?), answered by
//! `inform`, or by `refuse` / `failure`.
//!
//! The initiator calls [`Query::query_if`] or [`Query::query_ref`] with an optional deadline;
//! the conversation ends in exactly one of [`Answered`](QueryEvent::Answered),
//! [`Refused`](QueryEvent::Refused), [`Failed`](QueryEvent::Failed),
//! [`TimedOut`](QueryEvent::TimedOut) or [`Undeliverable`](QueryEvent::Undeliverable). The
//! responder gets [`Asked`](QueryEvent::Asked) and answers through [`Query::inform`],
//! [`Query::refuse`] or [`Query::fail`]. One machine serves both roles.

use super::exchange::{Exchanges, Spec, Step};
use super::{DEFAULT_MESSAGE_SIZE, Handled, Reply, TimerTag, answer};
use crate::comm::{DeliveryError, Envelope, Performative, Protocol};
use crate::entity::EntityId;
use crate::sim::{Context, Input, Model};
use crate::time::SimDuration;
use serde::{Deserialize, Serialize};

/// The kind of question.
#[derive(Copy, Clone, Debug, PartialEq, Eq, Serialize, Deserialize)]
pub enum QueryKind {
    /// Whether a proposition holds (`query-if`).
    If,
    /// The value of an expression (`query-ref`).
    Ref,
}

/// What happened in a query conversation.
#[derive(Debug, PartialEq)]
pub enum QueryEvent<'a, Msg> {
    /// (Responder) a question came in.
    Asked {
        /// Where to answer.
        reply: Reply,
        /// Its kind.
        kind: QueryKind,
        /// The question.
        query: &'a Envelope<Msg>,
    },
    /// (Initiator) the answer. Closed.
    Answered {
        /// The inform message.
        answer: &'a Envelope<Msg>,
    },
    /// (Initiator) the responder refused to answer. Closed.
    Refused {
        /// The refusal.
        reply: &'a Envelope<Msg>,
    },
    /// (Initiator) the responder could not answer. Closed.
    Failed {
        /// The failure message.
        reply: &'a Envelope<Msg>,
    },
    /// (Initiator) no answer by the deadline. Closed; a later answer is dropped.
    TimedOut {
        /// The conversation.
        conversation: u64,
        /// The party asked.
        peer: EntityId,
    },
    /// (Initiator) the question came back undelivered. Closed.
    Undeliverable {
        /// The conversation.
        conversation: u64,
        /// The party asked.
        peer: EntityId,
        /// Why.
        error: DeliveryError,
    },
}

/// The query machine (both roles).
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct Query {
    tag: TimerTag,
    size_bytes: u32,
    ex: Exchanges,
}

const OPENING: &[Performative] = &[Performative::QueryIf, Performative::QueryRef];
const REPLIES: &[Performative] = &[
    Performative::Inform,
    Performative::Refuse,
    Performative::Failure,
];

impl Query {
    /// A machine whose timers carry `tag`.
    pub fn new(tag: TimerTag) -> Self {
        Query {
            tag,
            size_bytes: DEFAULT_MESSAGE_SIZE,
            ex: Exchanges::default(),
        }
    }

    /// Sets the size of its messages on the channel (default [`DEFAULT_MESSAGE_SIZE`]).
    pub fn with_message_size(mut self, bytes: u32) -> Self {
        self.size_bytes = bytes;
        self
    }

    fn spec(&self) -> Spec<'static> {
        Spec {
            tag: self.tag,
            protocol: Protocol::Query,
            opening: OPENING,
            replies: REPLIES,
        }
    }

    /// (Initiator) asks `to` whether `body` holds. Returns the conversation id.
    pub fn query_if<M: Model>(
        &mut self,
        cx: &mut Context<'_, M>,
        to: EntityId,
        body: M::Msg,
        deadline: Option<SimDuration>,
    ) -> u64 {
        self.ask(cx, Performative::QueryIf, to, body, deadline)
    }

    /// (Initiator) asks `to` for the value `body` names. Returns the conversation id.
    pub fn query_ref<M: Model>(
        &mut self,
        cx: &mut Context<'_, M>,
        to: EntityId,
        body: M::Msg,
        deadline: Option<SimDuration>,
    ) -> u64 {
        self.ask(cx, Performative::QueryRef, to, body, deadline)
    }

    fn ask<M: Model>(
        &mut self,
        cx: &mut Context<'_, M>,
        p: Performative,
        to: EntityId,
        body: M::Msg,
        deadline: Option<SimDuration>,
    ) -> u64 {
        let spec = self.spec();
        self.ex
            .start(cx, &spec, p, self.size_bytes, to, body, deadline)
    }

    /// (Initiator) whether `conversation` still awaits its answer.
    pub fn is_open(&self, conversation: u64) -> bool {
        self.ex.is_open(conversation)
    }

    /// (Initiator) the open conversations and the parties asked, in id order.
    pub fn open(&self) -> impl Iterator<Item = (u64, EntityId)> + '_ {
        self.ex.open()
    }

    /// (Responder) answers.
    pub fn inform<M: Model>(&self, cx: &mut Context<'_, M>, reply: Reply, body: M::Msg) {
        answer(
            cx,
            reply,
            Protocol::Query,
            Performative::Inform,
            self.size_bytes,
            body,
        );
    }
    /// (Responder) refuses to answer.
    pub fn refuse<M: Model>(&self, cx: &mut Context<'_, M>, reply: Reply, body: M::Msg) {
        answer(
            cx,
            reply,
            Protocol::Query,
            Performative::Refuse,
            self.size_bytes,
            body,
        );
    }
    /// (Responder) reports it cannot answer.
    pub fn fail<M: Model>(&self, cx: &mut Context<'_, M>, reply: Reply, body: M::Msg) {
        answer(
            cx,
            reply,
            Protocol::Query,
            Performative::Failure,
            self.size_bytes,
            body,
        );
    }

    /// Handles one input (see [`Handled`]).
    pub fn handle<'a, M: Model>(
        &mut self,
        input: Input<'a, M>,
        cx: &mut Context<'_, M>,
    ) -> Handled<QueryEvent<'a, M::Msg>> {
        let spec = self.spec();
        let ev = match self.ex.classify(input, cx, &spec) {
            Step::NotMine => return Handled::NotMine,
            Step::Consumed => return Handled::Consumed,
            Step::Incoming(query) => QueryEvent::Asked {
                reply: Reply::to(query),
                kind: if query.performative == Performative::QueryIf {
                    QueryKind::If
                } else {
                    QueryKind::Ref
                },
                query,
            },
            Step::Reply(reply) => {
                self.ex.close(cx, reply.conversation);
                match reply.performative {
                    Performative::Inform => QueryEvent::Answered { answer: reply },
                    Performative::Refuse => QueryEvent::Refused { reply },
                    _ => QueryEvent::Failed { reply },
                }
            }
            Step::TimedOut(conversation, o) => QueryEvent::TimedOut {
                conversation,
                peer: o.peer,
            },
            Step::Undeliverable(conversation, o, error) => QueryEvent::Undeliverable {
                conversation,
                peer: o.peer,
                error,
            },
        };
        Handled::Event(ev)
    }
}

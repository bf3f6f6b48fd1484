//! Request / inform (FIPA request): `request → agree | refuse`, then `done | failure`.
//!
//! The initiator calls [`RequestInform::request`] with an optional deadline for the outcome;
//! the conversation ends in exactly one of [`Refused`](RequestEvent::Refused),
//! [`Done`](RequestEvent::Done), [`Failed`](RequestEvent::Failed),
//! [`TimedOut`](RequestEvent::TimedOut) (no outcome by the deadline, e.g. a lost message) or
//! [`Undeliverable`](RequestEvent::Undeliverable). The responder gets
//! [`Requested`](RequestEvent::Requested) and answers through [`agree`](RequestInform::agree),
//! [`refuse`](RequestInform::refuse), then [`done`](RequestInform::done) or
//! [`fail`](RequestInform::fail), at once or later (keep the [`Reply`]). Agreeing is optional:
//! a responder may answer `done` straight away. An `inform` is accepted as `done` (FIPA's
//! inform-done). One machine serves both roles. See the [module](super) example.

use super::exchange::{Exchanges, Spec, Step};
use super::{DEFAULT_MESSAGE_SIZE, Handled, Reply, TimerTag, answer};
use crate::comm::{DeliveryError, Envelope, Performative, Protocol};
use crate::entity::EntityId;
use crate::sim::{Context, Input, Model};
use crate::time::SimDuration;
use serde::{Deserialize, Serialize};

/// What happened in a request conversation.
#[derive(Debug, PartialEq)]
pub enum RequestEvent<'a, Msg> {
    /// (Responder) a request came in; answer through [`Reply::to`]`(request)` = `reply`.
    Requested {
        /// Where to answer.
        reply: Reply,
        /// The request.
        request: &'a Envelope<Msg>,
    },
    /// (Initiator) the responder agreed; the outcome follows.
    Agreed {
        /// The conversation.
        conversation: u64,
        /// The responder.
        from: EntityId,
    },
    /// (Initiator) the responder refused. Closed.
    Refused {
        /// The refusal.
        reply: &'a Envelope<Msg>,
    },
    /// (Initiator) the action is done. Closed.
    Done {
        /// The done (or inform) message.
        reply: &'a Envelope<Msg>,
    },
    /// (Initiator) the action failed. Closed.
    Failed {
        /// The failure message.
        reply: &'a Envelope<Msg>,
    },
    /// (Initiator) no outcome by the deadline. Closed; later replies are dropped.
    TimedOut {
        /// The conversation.
        conversation: u64,
        /// The responder.
        peer: EntityId,
        /// Whether it had agreed.
        agreed: bool,
    },
    /// (Initiator) the request came back undelivered. Closed.
    Undeliverable {
        /// The conversation.
        conversation: u64,
        /// The responder.
        peer: EntityId,
        /// Why.
        error: DeliveryError,
    },
}

/// The request/inform machine (both roles).
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct RequestInform {
    tag: TimerTag,
    size_bytes: u32,
    ex: Exchanges,
}

const OPENING: &[Performative] = &[Performative::Request];
const REPLIES: &[Performative] = &[
    Performative::Agree,
    Performative::Refuse,
    Performative::Done,
    Performative::Inform,
    Performative::Failure,
];

impl RequestInform {
    /// A machine whose timers carry `tag`.
    pub fn new(tag: TimerTag) -> Self {
        RequestInform {
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
            protocol: Protocol::Request,
            opening: OPENING,
            replies: REPLIES,
        }
    }

    /// (Initiator) asks `to` to act on `body`; the outcome must come within `deadline`.
    /// Returns the conversation id.
    pub fn request<M: Model>(
        &mut self,
        cx: &mut Context<'_, M>,
        to: EntityId,
        body: M::Msg,
        deadline: Option<SimDuration>,
    ) -> u64 {
        let spec = self.spec();
        self.ex.start(
            cx,
            &spec,
            Performative::Request,
            self.size_bytes,
            to,
            body,
            deadline,
        )
    }

    /// (Initiator) whether `conversation` still awaits its outcome.
    pub fn is_open(&self, conversation: u64) -> bool {
        self.ex.is_open(conversation)
    }

    /// (Initiator) the open conversations and their responders, in id order.
    pub fn open(&self) -> impl Iterator<Item = (u64, EntityId)> + '_ {
        self.ex.open()
    }

    /// (Initiator) gives up `conversation` without a message; later replies are dropped.
    pub fn abandon<M: Model>(&mut self, cx: &mut Context<'_, M>, conversation: u64) -> bool {
        self.ex.close(cx, conversation).is_some()
    }

    /// (Responder) agrees to act.
    pub fn agree<M: Model>(&self, cx: &mut Context<'_, M>, reply: Reply, body: M::Msg) {
        self.answer(cx, reply, Performative::Agree, body);
    }
    /// (Responder) refuses to act.
    pub fn refuse<M: Model>(&self, cx: &mut Context<'_, M>, reply: Reply, body: M::Msg) {
        self.answer(cx, reply, Performative::Refuse, body);
    }
    /// (Responder) reports the action done (inform-done).
    pub fn done<M: Model>(&self, cx: &mut Context<'_, M>, reply: Reply, body: M::Msg) {
        self.answer(cx, reply, Performative::Done, body);
    }
    /// (Responder) reports the action failed.
    pub fn fail<M: Model>(&self, cx: &mut Context<'_, M>, reply: Reply, body: M::Msg) {
        self.answer(cx, reply, Performative::Failure, body);
    }

    fn answer<M: Model>(&self, cx: &mut Context<'_, M>, reply: Reply, p: Performative, b: M::Msg) {
        answer(cx, reply, Protocol::Request, p, self.size_bytes, b);
    }

    /// Handles one input (see [`Handled`]).
    pub fn handle<'a, M: Model>(
        &mut self,
        input: Input<'a, M>,
        cx: &mut Context<'_, M>,
    ) -> Handled<RequestEvent<'a, M::Msg>> {
        let spec = self.spec();
        let ev = match self.ex.classify(input, cx, &spec) {
            Step::NotMine => return Handled::NotMine,
            Step::Consumed => return Handled::Consumed,
            Step::Incoming(request) => RequestEvent::Requested {
                reply: Reply::to(request),
                request,
            },
            Step::Reply(reply) => match reply.performative {
                Performative::Agree => {
                    self.ex.agree(reply.conversation);
                    RequestEvent::Agreed {
                        conversation: reply.conversation,
                        from: reply.from,
                    }
                }
                p => {
                    self.ex.close(cx, reply.conversation);
                    match p {
                        Performative::Refuse => RequestEvent::Refused { reply },
                        Performative::Failure => RequestEvent::Failed { reply },
                        _ => RequestEvent::Done { reply },
                    }
                }
            },
            Step::TimedOut(conversation, o) => RequestEvent::TimedOut {
                conversation,
                peer: o.peer,
                agreed: o.agreed,
            },
            Step::Undeliverable(conversation, o, error) => RequestEvent::Undeliverable {
                conversation,
                peer: o.peer,
                error,
            },
        };
        Handled::Event(ev)
    }
}

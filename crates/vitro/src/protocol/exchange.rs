//! The core shared by the one-shot protocols (request, query): the initiator's open
//! conversations with their peer and deadline timer, and the sorting of inputs.

use super::{TimerTag, conversation_id, send};
use crate::comm::{Address, DeliveryError, Envelope, Performative, Protocol};
use crate::entity::EntityId;
use crate::event::OwnEventId;
use crate::sim::{Context, Input, Model};
use crate::time::SimDuration;
use serde::{Deserialize, Serialize};
use std::collections::BTreeMap;

/// One open conversation of the initiator.
#[derive(Copy, Clone, Debug, PartialEq, Eq, Serialize, Deserialize)]
pub(super) struct Open {
    /// The party asked.
    pub peer: EntityId,
    /// Whether the peer agreed (request only).
    pub agreed: bool,
    timer: Option<OwnEventId>,
}

/// The initiator's open conversations.
#[derive(Clone, Debug, Default, PartialEq, Serialize, Deserialize)]
pub(super) struct Exchanges {
    next: u32,
    open: BTreeMap<u64, Open>,
}

/// The protocol-level meaning of one input.
pub(super) enum Step<'a, Msg> {
    NotMine,
    Consumed,
    /// A message opening a conversation (this agent is the responder).
    Incoming(&'a Envelope<Msg>),
    /// A reply from the peer of an open conversation (still open: the caller closes it).
    Reply(&'a Envelope<Msg>),
    /// The deadline of a conversation passed (closed).
    TimedOut(u64, Open),
    /// The opening message could not be delivered (closed).
    Undeliverable(u64, Open, DeliveryError),
}

/// What sets a protocol apart: its tag, its performatives.
pub(super) struct Spec<'s> {
    pub tag: TimerTag,
    pub protocol: Protocol,
    /// Performatives that open a conversation.
    pub opening: &'s [Performative],
    /// Performatives that answer one.
    pub replies: &'s [Performative],
}

impl Exchanges {
    /// Opens a conversation: sends `body` to `to` and sets the deadline timer.
    #[allow(clippy::too_many_arguments)]
    pub fn start<M: Model>(
        &mut self,
        cx: &mut Context<'_, M>,
        spec: &Spec<'_>,
        performative: Performative,
        size_bytes: u32,
        to: EntityId,
        body: M::Msg,
        deadline: Option<SimDuration>,
    ) -> u64 {
        let seq = self.next;
        self.next = self.next.wrapping_add(1);
        let conversation = conversation_id(cx.me(), seq);
        send(
            cx,
            Address::Agent(to),
            spec.protocol,
            performative,
            conversation,
            size_bytes,
            body,
        );
        let timer = deadline.map(|d| cx.set_timer(d, spec.tag.key(u64::from(seq))));
        self.open.insert(
            conversation,
            Open {
                peer: to,
                agreed: false,
                timer,
            },
        );
        conversation
    }

    /// Marks `conversation` as agreed.
    pub fn agree(&mut self, conversation: u64) {
        if let Some(o) = self.open.get_mut(&conversation) {
            o.agreed = true;
        }
    }

    /// Closes `conversation` (cancelling its deadline).
    pub fn close<M: Model>(&mut self, cx: &mut Context<'_, M>, conversation: u64) -> Option<Open> {
        let o = self.open.remove(&conversation)?;
        if let Some(t) = o.timer {
            cx.cancel(t);
        }
        Some(o)
    }

    /// The open conversations and their peers, in id order.
    pub fn open(&self) -> impl Iterator<Item = (u64, EntityId)> + '_ {
        self.open.iter().map(|(&c, o)| (c, o.peer))
    }

    /// Whether `conversation` is open.
    pub fn is_open(&self, conversation: u64) -> bool {
        self.open.contains_key(&conversation)
    }

    /// Sorts one input.
    pub fn classify<'a, M: Model>(
        &mut self,
        input: Input<'a, M>,
        cx: &mut Context<'_, M>,
        spec: &Spec<'_>,
    ) -> Step<'a, M::Msg> {
        match input {
            Input::Message(env) if env.protocol == spec.protocol => {
                if spec.opening.contains(&env.performative) {
                    Step::Incoming(env)
                } else if spec.replies.contains(&env.performative) {
                    match self.open.get(&env.conversation) {
                        Some(o) if o.peer == env.from => Step::Reply(env),
                        // A late reply (after the deadline) or a stray one.
                        _ => Step::Consumed,
                    }
                } else {
                    Step::NotMine
                }
            }
            Input::Undeliverable(env, error) if env.protocol == spec.protocol => {
                if spec.opening.contains(&env.performative) {
                    match self.close(cx, env.conversation) {
                        Some(o) => Step::Undeliverable(env.conversation, o, error),
                        None => Step::Consumed,
                    }
                } else {
                    // An answer of ours came back: the initiator's deadline covers it.
                    Step::Consumed
                }
            }
            Input::Timer(key) => match spec.tag.index(key) {
                None => Step::NotMine,
                Some(index) => {
                    let Ok(seq) = u32::try_from(index) else {
                        return Step::Consumed;
                    };
                    let conversation = conversation_id(cx.me(), seq);
                    match self.open.remove(&conversation) {
                        Some(o) => Step::TimedOut(conversation, o),
                        None => Step::Consumed,
                    }
                }
            },
            _ => Step::NotMine,
        }
    }
}

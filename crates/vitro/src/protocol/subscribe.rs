//! Subscribe / notify (FIPA subscribe): a subscriber asks a publisher to be told of changes;
//! the publisher keeps its subscriber list and notifies each subscriber on every change, until
//! the subscriber cancels.
//!
//! **Subscriber**: [`SubscribeNotify::subscribe`] (optionally with a deadline for the
//! publisher's agree), then [`Confirmed`](SubscribeEvent::Confirmed) or
//! [`Refused`](SubscribeEvent::Refused) or [`TimedOut`](SubscribeEvent::TimedOut) (subscribe
//! again if it matters), then [`Notified`](SubscribeEvent::Notified) per change;
//! [`SubscribeNotify::cancel`] ends it.
//!
//! **Publisher**: [`SubscribeRequested`](SubscribeEvent::SubscribeRequested), answered by
//! [`SubscribeNotify::accept`] (adds the subscriber, sends agree) or
//! [`SubscribeNotify::refuse`]; [`SubscribeNotify::notify_all`] on each change;
//! [`Unsubscribed`](SubscribeEvent::Unsubscribed) when a subscriber cancels.
//!
//! **Lost messages.** A lost subscribe or agree is covered by the subscriber's deadline; a
//! notification arriving for a subscription still awaiting its agree confirms it. A lost cancel
//! is repaired by the subscriber: a notification (or a late agree) for a subscription it no
//! longer holds is answered by a fresh cancel, echoing its body. A lost notification cannot be
//! noticed: notify the whole current state, not a difference, so the next one repairs it.

use super::{DEFAULT_MESSAGE_SIZE, Handled, Reply, TimerTag, answer, conversation_id, send};
use crate::comm::{Address, DeliveryError, Envelope, Performative, Protocol};
use crate::entity::EntityId;
use crate::event::OwnEventId;
use crate::sim::{Context, Input, Model};
use crate::time::SimDuration;
use serde::{Deserialize, Serialize};
use std::collections::BTreeMap;

/// What happened in a subscription.
#[derive(Debug, PartialEq)]
pub enum SubscribeEvent<'a, Msg> {
    /// (Publisher) a subscription is asked for: [`accept`](SubscribeNotify::accept) or
    /// [`refuse`](SubscribeNotify::refuse) it.
    SubscribeRequested {
        /// The subscriber and its subscription.
        reply: Reply,
        /// The request.
        request: &'a Envelope<Msg>,
    },
    /// (Publisher) a subscriber cancelled; it is off the list.
    Unsubscribed {
        /// The subscriber and its subscription.
        subscriber: Reply,
    },
    /// (Publisher) a notification could not be delivered (the subscriber stays on the list;
    /// [`remove`](SubscribeNotify::remove) it if it is gone for good).
    NotifyUndeliverable {
        /// The subscriber and its subscription.
        subscriber: Reply,
        /// Why.
        error: DeliveryError,
    },
    /// (Subscriber) the publisher agreed.
    Confirmed {
        /// The subscription.
        conversation: u64,
        /// The publisher.
        publisher: EntityId,
    },
    /// (Subscriber) the publisher refused. Ended.
    Refused {
        /// The refusal.
        reply: &'a Envelope<Msg>,
    },
    /// (Subscriber) a change.
    Notified {
        /// The notification.
        notification: &'a Envelope<Msg>,
    },
    /// (Subscriber) no agree by the deadline. Ended (a late agree is answered by a cancel).
    TimedOut {
        /// The subscription.
        conversation: u64,
        /// The publisher.
        publisher: EntityId,
    },
    /// (Subscriber) the subscribe came back undelivered. Ended.
    Undeliverable {
        /// The subscription.
        conversation: u64,
        /// The publisher.
        publisher: EntityId,
        /// Why.
        error: DeliveryError,
    },
}

/// One subscription held by a subscriber.
#[derive(Copy, Clone, Debug, PartialEq, Eq, Serialize, Deserialize)]
struct Held {
    publisher: EntityId,
    confirmed: bool,
    timer: Option<OwnEventId>,
}

/// The subscribe/notify machine (both roles).
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct SubscribeNotify {
    tag: TimerTag,
    size_bytes: u32,
    next: u32,
    /// Subscriber role: subscriptions held, by conversation.
    held: BTreeMap<u64, Held>,
    /// Publisher role: subscribers, in acceptance order.
    subscribers: Vec<Reply>,
}

const P: Protocol = Protocol::Subscribe;

impl SubscribeNotify {
    /// A machine whose timers carry `tag`.
    pub fn new(tag: TimerTag) -> Self {
        SubscribeNotify {
            tag,
            size_bytes: DEFAULT_MESSAGE_SIZE,
            next: 0,
            held: BTreeMap::new(),
            subscribers: Vec::new(),
        }
    }

    /// Sets the size of its messages on the channel (default [`DEFAULT_MESSAGE_SIZE`]).
    pub fn with_message_size(mut self, bytes: u32) -> Self {
        self.size_bytes = bytes;
        self
    }

    /// (Subscriber) subscribes to `publisher` with `body` (what to watch). Without an agree
    /// within `deadline` it ends in [`TimedOut`](SubscribeEvent::TimedOut). Returns the
    /// subscription's conversation id.
    pub fn subscribe<M: Model>(
        &mut self,
        cx: &mut Context<'_, M>,
        publisher: EntityId,
        body: M::Msg,
        deadline: Option<SimDuration>,
    ) -> u64 {
        let seq = self.next;
        self.next = self.next.wrapping_add(1);
        let conversation = conversation_id(cx.me(), seq);
        send(
            cx,
            Address::Agent(publisher),
            P,
            Performative::Subscribe,
            conversation,
            self.size_bytes,
            body,
        );
        let timer = deadline.map(|d| cx.set_timer(d, self.tag.key(u64::from(seq))));
        self.held.insert(
            conversation,
            Held {
                publisher,
                confirmed: false,
                timer,
            },
        );
        conversation
    }

    /// (Subscriber) cancels a subscription, telling the publisher with `body`. False if it is
    /// not held.
    pub fn cancel<M: Model>(
        &mut self,
        cx: &mut Context<'_, M>,
        conversation: u64,
        body: M::Msg,
    ) -> bool {
        let Some(h) = self.drop_held(cx, conversation) else {
            return false;
        };
        let reply = Reply {
            to: h.publisher,
            conversation,
        };
        answer(cx, reply, P, Performative::Cancel, self.size_bytes, body);
        true
    }

    /// (Subscriber) whether the subscription is held (confirmed or awaiting its agree).
    pub fn is_subscribed(&self, conversation: u64) -> bool {
        self.held.contains_key(&conversation)
    }

    /// (Subscriber) whether the publisher confirmed the subscription.
    pub fn is_confirmed(&self, conversation: u64) -> bool {
        self.held.get(&conversation).is_some_and(|h| h.confirmed)
    }

    /// (Publisher) accepts a subscription: adds it to the list (once) and sends an agree.
    pub fn accept<M: Model>(&mut self, cx: &mut Context<'_, M>, reply: Reply, body: M::Msg) {
        if !self.subscribers.contains(&reply) {
            self.subscribers.push(reply);
        }
        answer(cx, reply, P, Performative::Agree, self.size_bytes, body);
    }

    /// (Publisher) refuses a subscription.
    pub fn refuse<M: Model>(&self, cx: &mut Context<'_, M>, reply: Reply, body: M::Msg) {
        answer(cx, reply, P, Performative::Refuse, self.size_bytes, body);
    }

    /// (Publisher) notifies every subscriber of `body`, in acceptance order. Returns how many.
    pub fn notify_all<M: Model>(&self, cx: &mut Context<'_, M>, body: M::Msg) -> usize {
        let n = self.subscribers.len();
        let mut body = Some(body);
        for (i, &s) in self.subscribers.iter().enumerate() {
            let b = if i + 1 == n {
                body.take()
            } else {
                body.clone()
            };
            if let Some(b) = b {
                answer(cx, s, P, Performative::Notify, self.size_bytes, b);
            }
        }
        n
    }

    /// (Publisher) notifies one subscriber.
    pub fn notify<M: Model>(&self, cx: &mut Context<'_, M>, subscriber: Reply, body: M::Msg) {
        answer(
            cx,
            subscriber,
            P,
            Performative::Notify,
            self.size_bytes,
            body,
        );
    }

    /// (Publisher) the subscribers, in acceptance order.
    pub fn subscribers(&self) -> &[Reply] {
        &self.subscribers
    }

    /// (Publisher) drops a subscriber without a message. False if it was not on the list.
    pub fn remove(&mut self, subscriber: Reply) -> bool {
        let before = self.subscribers.len();
        self.subscribers.retain(|&s| s != subscriber);
        self.subscribers.len() != before
    }

    fn drop_held<M: Model>(&mut self, cx: &mut Context<'_, M>, conversation: u64) -> Option<Held> {
        let h = self.held.remove(&conversation)?;
        if let Some(t) = h.timer {
            cx.cancel(t);
        }
        Some(h)
    }

    /// Handles one input (see [`Handled`]).
    pub fn handle<'a, M: Model>(
        &mut self,
        input: Input<'a, M>,
        cx: &mut Context<'_, M>,
    ) -> Handled<SubscribeEvent<'a, M::Msg>> {
        let ev = match input {
            Input::Message(env) if env.protocol == P => match env.performative {
                Performative::Subscribe => SubscribeEvent::SubscribeRequested {
                    reply: Reply::to(env),
                    request: env,
                },
                Performative::Cancel => {
                    let subscriber = Reply::to(env);
                    if !self.remove(subscriber) {
                        return Handled::Consumed;
                    }
                    SubscribeEvent::Unsubscribed { subscriber }
                }
                Performative::Agree | Performative::Notify => {
                    let held = self
                        .held
                        .get_mut(&env.conversation)
                        .filter(|h| h.publisher == env.from);
                    let Some(h) = held else {
                        // Not (or no longer) subscribed: say so again (a lost cancel, a late
                        // agree after the deadline).
                        let body = env.body.clone();
                        answer(
                            cx,
                            Reply::to(env),
                            P,
                            Performative::Cancel,
                            self.size_bytes,
                            body,
                        );
                        return Handled::Consumed;
                    };
                    let newly = !h.confirmed;
                    h.confirmed = true;
                    if let Some(t) = h.timer.take() {
                        cx.cancel(t);
                    }
                    if env.performative == Performative::Notify {
                        SubscribeEvent::Notified { notification: env }
                    } else if newly {
                        SubscribeEvent::Confirmed {
                            conversation: env.conversation,
                            publisher: env.from,
                        }
                    } else {
                        return Handled::Consumed;
                    }
                }
                Performative::Refuse => {
                    let is_pending = self
                        .held
                        .get(&env.conversation)
                        .is_some_and(|h| h.publisher == env.from);
                    if !is_pending {
                        return Handled::Consumed;
                    }
                    self.drop_held(cx, env.conversation);
                    SubscribeEvent::Refused { reply: env }
                }
                _ => return Handled::NotMine,
            },
            Input::Undeliverable(env, error) if env.protocol == P => match env.performative {
                Performative::Subscribe => match self.drop_held(cx, env.conversation) {
                    Some(h) => SubscribeEvent::Undeliverable {
                        conversation: env.conversation,
                        publisher: h.publisher,
                        error,
                    },
                    None => return Handled::Consumed,
                },
                Performative::Notify => SubscribeEvent::NotifyUndeliverable {
                    subscriber: Reply {
                        to: env.receiver,
                        conversation: env.conversation,
                    },
                    error,
                },
                _ => return Handled::Consumed,
            },
            Input::Timer(key) => {
                let Some(index) = self.tag.index(key) else {
                    return Handled::NotMine;
                };
                let Ok(seq) = u32::try_from(index) else {
                    return Handled::Consumed;
                };
                let conversation = conversation_id(cx.me(), seq);
                match self.held.get(&conversation) {
                    Some(h) if !h.confirmed => {
                        let publisher = h.publisher;
                        self.held.remove(&conversation);
                        SubscribeEvent::TimedOut {
                            conversation,
                            publisher,
                        }
                    }
                    _ => return Handled::Consumed,
                }
            }
            _ => return Handled::NotMine,
        };
        Handled::Event(ev)
    }
}

//! Token ring: one token handed around an ordered ring of agents, with loss detection and
//! regeneration by timeout.
//!
//! Every member builds the same [`TokenRing`] (same member order) and calls
//! [`start`](TokenRing::start) once; the first member then holds the token. The holder does its
//! work and calls [`pass`](TokenRing::pass) with the token's body; the next member gets
//! [`Acquired`](TokenEvent::Acquired). The body is the model's `Msg` (shared state may ride on
//! it); the token's *generation* travels in the conversation id.
//!
//! **Loss.** The first member is the ring's *monitor* (as in IEEE 802.5): when it has not seen
//! the token for `timeout` since it last passed it, it presumes the token lost and regenerates
//! it ([`Regenerated`](TokenEvent::Regenerated)). The member at ring index `i` stands by: it
//! regenerates after `(i + 1) × timeout`, which only happens if every member before it is
//! gone. Regeneration by one member at a time is what keeps a ring with regular timing from
//! a cascade of simultaneous regenerations. Choose `timeout` above twice the longest rotation
//! (members × (holding time + channel delay and jitter)), so that a standby member always
//! sees the monitor's new token before its own longer wait runs out.
//!
//! **Duplicates.** A regenerated token gets a generation above every one its maker has seen
//! (`(round << 16) | its ring index`; the generation travels in the conversation id). A member
//! drops a token older than the newest generation it has seen, and a holder that receives a
//! second token keeps one, so a duplicate (a slow token presumed lost) dies out within a
//! rotation. A pass that bounces (the next member is gone or out of range) skips that member
//! ([`Skipped`](TokenEvent::Skipped)), echoing the token's body.

use super::{DEFAULT_MESSAGE_SIZE, Handled, TimerTag, send};
use crate::comm::{Address, DeliveryError, Envelope, Performative, Protocol};
use crate::entity::EntityId;
use crate::event::OwnEventId;
use crate::sim::{Context, Input, Model};
use crate::time::SimDuration;
use serde::{Deserialize, Serialize};

/// Why a ring cannot be built or the token not passed.
#[derive(Clone, Debug, PartialEq, Eq, thiserror::Error)]
pub enum RingError {
    /// A ring needs at least one member.
    #[error("a token ring needs at least one member")]
    Empty,
    /// The agent building the machine is not in the ring.
    #[error("{0} is not a member of the ring")]
    NotAMember(EntityId),
    /// A member appears twice.
    #[error("{0} appears twice in the ring")]
    Duplicate(EntityId),
    /// More members than generations can tell apart (2^16).
    #[error("a ring of {0} members is too large (at most 65536)")]
    TooLarge(usize),
    /// Only the holder can pass the token.
    #[error("this member does not hold the token")]
    NotHolder,
}

/// What happened to the token. All but [`Skipped`](Self::Skipped) mean: this member holds it
/// now, and passes it on with [`TokenRing::pass`].
#[derive(Debug, PartialEq)]
pub enum TokenEvent<'a, Msg> {
    /// The token arrived.
    Acquired {
        /// The token message (its body is the token's content).
        token: &'a Envelope<Msg>,
    },
    /// The token was presumed lost and this member made a new one (no body: the agent gives
    /// one when it passes).
    Regenerated {
        /// The new generation.
        generation: u64,
    },
    /// The pass bounced and no other member is left to try: the token is back.
    Returned {
        /// The last member tried.
        member: EntityId,
        /// Why it was unreachable.
        error: DeliveryError,
    },
    /// The pass to `member` bounced; the token went on to `next`.
    Skipped {
        /// The unreachable member.
        member: EntityId,
        /// The member it was passed to instead.
        next: EntityId,
        /// Why.
        error: DeliveryError,
    },
}

impl<Msg> TokenEvent<'_, Msg> {
    /// Whether this member holds the token after the event.
    pub fn holds(&self) -> bool {
        !matches!(self, TokenEvent::Skipped { .. })
    }
}

const P: Protocol = Protocol::TokenRing;
const INDEX_BITS: u32 = 16;
const MAX_MEMBERS: usize = 1 << INDEX_BITS;

/// One member's view of a token ring.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct TokenRing {
    tag: TimerTag,
    size_bytes: u32,
    members: Vec<EntityId>,
    index: usize,
    timeout: SimDuration,
    /// The generation of the token held, if any.
    holding: Option<u64>,
    /// The newest generation seen.
    newest: u64,
    watchdog: Option<OwnEventId>,
    watch_seq: u64,
    regenerations: u64,
}

impl TokenRing {
    /// The machine of `me` in the ring `members` (in passing order; the first is the monitor),
    /// whose timers carry `tag`; the monitor regenerates the token after `timeout` without
    /// seeing it (see the [module](self) documentation).
    pub fn new(
        tag: TimerTag,
        members: Vec<EntityId>,
        me: EntityId,
        timeout: SimDuration,
    ) -> Result<Self, RingError> {
        if members.is_empty() {
            return Err(RingError::Empty);
        }
        if members.len() > MAX_MEMBERS {
            return Err(RingError::TooLarge(members.len()));
        }
        let mut sorted = members.clone();
        sorted.sort_unstable();
        if let Some(w) = sorted.windows(2).find(|w| w[0] == w[1]) {
            return Err(RingError::Duplicate(w[0]));
        }
        let index = members
            .iter()
            .position(|&m| m == me)
            .ok_or(RingError::NotAMember(me))?;
        Ok(TokenRing {
            tag,
            size_bytes: DEFAULT_MESSAGE_SIZE,
            members,
            index,
            timeout,
            holding: None,
            newest: 0,
            watchdog: None,
            watch_seq: 0,
            regenerations: 0,
        })
    }

    /// Sets the size of the token on the channel (default [`DEFAULT_MESSAGE_SIZE`]).
    pub fn with_message_size(mut self, bytes: u32) -> Self {
        self.size_bytes = bytes;
        self
    }

    /// Starts this member: the first member of the ring creates the token and holds it
    /// (returns true); the others start watching for it.
    pub fn start<M: Model>(&mut self, cx: &mut Context<'_, M>) -> bool {
        if self.index == 0 && self.newest == 0 && self.holding.is_none() {
            self.newest = 1 << INDEX_BITS;
            self.holding = Some(self.newest);
            self.disarm(cx);
            true
        } else {
            if self.holding.is_none() {
                self.arm(cx);
            }
            false
        }
    }

    /// Passes the token, with `body`, to the next member. Returns that member.
    pub fn pass<M: Model>(
        &mut self,
        cx: &mut Context<'_, M>,
        body: M::Msg,
    ) -> Result<EntityId, RingError> {
        let generation = self.holding.take().ok_or(RingError::NotHolder)?;
        let next = self.after(self.index);
        self.send_token(cx, next, generation, body);
        Ok(next)
    }

    /// Whether this member holds the token.
    pub fn holding(&self) -> bool {
        self.holding.is_some()
    }
    /// The newest token generation this member has seen.
    pub fn generation(&self) -> u64 {
        self.newest
    }
    /// How many times this member regenerated the token.
    pub fn regenerations(&self) -> u64 {
        self.regenerations
    }
    /// The ring, in passing order.
    pub fn members(&self) -> &[EntityId] {
        &self.members
    }
    /// The member this one passes to.
    pub fn next(&self) -> EntityId {
        self.after(self.index)
    }

    fn after(&self, i: usize) -> EntityId {
        self.members[(i + 1) % self.members.len()]
    }

    fn send_token<M: Model>(
        &mut self,
        cx: &mut Context<'_, M>,
        to: EntityId,
        generation: u64,
        body: M::Msg,
    ) {
        send(
            cx,
            Address::Agent(to),
            P,
            Performative::Token,
            generation,
            self.size_bytes,
            body,
        );
        self.arm(cx);
    }

    /// Starts waiting for the token: `(index + 1) × timeout` (the monitor first).
    fn arm<M: Model>(&mut self, cx: &mut Context<'_, M>) {
        self.disarm(cx);
        self.watch_seq = self.watch_seq.wrapping_add(1);
        let key = self.tag.key(self.watch_seq);
        let wait = self.timeout * (self.index as u64 + 1);
        self.watchdog = Some(cx.set_timer(wait, key));
    }

    fn disarm<M: Model>(&mut self, cx: &mut Context<'_, M>) {
        if let Some(t) = self.watchdog.take() {
            cx.cancel(t);
        }
    }

    fn take<M: Model>(&mut self, cx: &mut Context<'_, M>, generation: u64) {
        self.holding = Some(generation);
        self.disarm(cx);
    }

    /// Handles one input (see [`Handled`]).
    pub fn handle<'a, M: Model>(
        &mut self,
        input: Input<'a, M>,
        cx: &mut Context<'_, M>,
    ) -> Handled<TokenEvent<'a, M::Msg>> {
        match input {
            Input::Message(token)
                if token.protocol == P && token.performative == Performative::Token =>
            {
                let generation = token.conversation;
                if generation < self.newest {
                    // A stale duplicate: a newer token is about.
                    return Handled::Consumed;
                }
                self.newest = generation;
                if let Some(held) = self.holding {
                    // Two tokens met: keep one.
                    self.holding = Some(held.max(generation));
                    return Handled::Consumed;
                }
                self.take(cx, generation);
                Handled::Event(TokenEvent::Acquired { token })
            }
            Input::Undeliverable(token, error)
                if token.protocol == P && token.performative == Performative::Token =>
            {
                let generation = token.conversation;
                if self.holding.is_some() || generation < self.newest {
                    return Handled::Consumed;
                }
                let member = token.receiver;
                let Some(pos) = self.members.iter().position(|&m| m == member) else {
                    return Handled::Consumed;
                };
                let next = self.after(pos);
                if next == self.members[self.index] {
                    self.take(cx, generation);
                    return Handled::Event(TokenEvent::Returned { member, error });
                }
                self.send_token(cx, next, generation, token.body.clone());
                Handled::Event(TokenEvent::Skipped {
                    member,
                    next,
                    error,
                })
            }
            Input::Timer(key) if self.tag.index(key).is_some() => {
                if self.watchdog.is_none() || key != self.tag.key(self.watch_seq) {
                    return Handled::Consumed;
                }
                self.watchdog = None;
                if self.holding.is_some() {
                    return Handled::Consumed;
                }
                let round = (self.newest >> INDEX_BITS) + 1;
                let generation = (round << INDEX_BITS) | self.index as u64;
                self.newest = generation;
                self.regenerations += 1;
                self.take(cx, generation);
                Handled::Event(TokenEvent::Regenerated { generation })
            }
            _ => Handled::NotMine,
        }
    }
}

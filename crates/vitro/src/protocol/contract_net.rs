//! Contract net (FIPA contract net): task allocation by call for proposals.
//!
//! **Initiator.** [`ContractNet::announce`] sends a call for proposals (`cfp`) for one task to a
//! set of participants (a list of agents, a multicast group, or everyone) and collects answers
//! until the proposal deadline, or until every copy of the call is answered (a proposal, a
//! refusal, or the call bounced back). It then accepts the best proposal and rejects the
//! others ([`Awarded`](CnetEvent::Awarded)), or fails with
//! [`NoProposals`](CallFailure::NoProposals). The winner must report `done` or `failure`
//! within the report deadline; the call ends in [`Done`](CnetEvent::Done) or
//! [`Failed`](CnetEvent::Failed) (the winner failed, never reported, or was unreachable).
//! A failed call hands its `cfp` body back, so the agent can re-announce it. Several calls
//! (tasks) may be open at once; each is its own conversation.
//!
//! **Participant.** [`CallForProposals`](CnetEvent::CallForProposals), answered by
//! [`ContractNet::propose`] or [`ContractNet::refuse`]; then
//! [`Accepted`](CnetEvent::Accepted) (do the task, then [`ContractNet::report_done`] or
//! [`ContractNet::report_failure`]), [`Rejected`](CnetEvent::Rejected), or
//! [`Expired`](CnetEvent::Expired) when neither came within the proposal expiry (a lost
//! answer): release what the proposal reserved.
//!
//! **Bids.** A bid travels in the model's own message body: the model's `Msg` implements
//! [`Bid`], which reads the bid of a proposal. Bids are costs: the lowest wins, ties go to the
//! lowest entity id; a proposal whose body has no bid, or a NaN one, counts as a refusal. (To
//! maximise a utility, bid its negation.)
//!
//! **Lost messages** end in deadlines, never in hangs: a lost call or answer leaves a copy
//! unanswered, so the initiator decides at the proposal deadline with what it has; a lost
//! accept or report ends the call at the report deadline ([`CallFailure::ReportTimedOut`]);
//! a lost accept or reject ends the participant's wait at its expiry. A late proposal is
//! rejected at once (echoing its body), a late report dropped. A task may thus be done twice
//! when a `done` report is lost and the task re-announced: contract net is at-least-once.

use super::{DEFAULT_MESSAGE_SIZE, Handled, Reply, TimerTag, answer, conversation_id, send};
use crate::comm::{Address, DeliveryError, Envelope, Performative, Protocol};
use crate::entity::EntityId;
use crate::event::OwnEventId;
use crate::sim::{Context, Input, Model};
use serde::{Deserialize, Serialize};
use std::collections::{BTreeMap, BTreeSet};

mod terms;
pub use terms::{Bid, CallFailure, CnetConfig, CnetEvent, Participants};

/// A valid proposal received.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
struct Offer<Msg> {
    from: EntityId,
    bid: f64,
    body: Msg,
}

#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
enum Phase<Msg> {
    Collecting {
        /// Copies of the call sent.
        expected: u64,
        /// Participants that answered.
        answered: BTreeSet<EntityId>,
        /// Copies that came back undelivered (from unnamed receivers).
        bounced: u64,
        offers: Vec<Offer<Msg>>,
    },
    Awarded {
        winner: EntityId,
    },
}

/// One open call of the initiator.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
struct Call<Msg> {
    task: u64,
    cfp: Msg,
    timer: OwnEventId,
    phase: Phase<Msg>,
}

/// Timer indices with this bit are participants' proposal expiries; without, calls' deadlines.
const EXPIRY_BIT: u64 = 1 << 47;
const P: Protocol = Protocol::ContractNet;

/// The contract-net machine (both roles). `Msg` is the model's message type.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct ContractNet<Msg> {
    tag: TimerTag,
    cfg: CnetConfig,
    size_bytes: u32,
    next: u32,
    /// Initiator: open calls by conversation.
    calls: BTreeMap<u64, Call<Msg>>,
    next_expiry: u64,
    /// Participant: proposals awaiting an answer, with their expiry index and timer.
    proposals: BTreeMap<Reply, (u64, OwnEventId)>,
    /// Participant: expiry index → proposal.
    expiries: BTreeMap<u64, Reply>,
}

impl<Msg: Clone> ContractNet<Msg> {
    /// A machine whose timers carry `tag`, with deadlines `cfg`.
    pub fn new(tag: TimerTag, cfg: CnetConfig) -> Self {
        ContractNet {
            tag,
            cfg,
            size_bytes: DEFAULT_MESSAGE_SIZE,
            next: 0,
            calls: BTreeMap::new(),
            next_expiry: 0,
            proposals: BTreeMap::new(),
            expiries: BTreeMap::new(),
        }
    }

    /// Sets the size of its messages on the channel (default [`DEFAULT_MESSAGE_SIZE`]).
    pub fn with_message_size(mut self, bytes: u32) -> Self {
        self.size_bytes = bytes;
        self
    }

    /// The deadlines.
    pub fn config(&self) -> &CnetConfig {
        &self.cfg
    }

    /// (Initiator) calls for proposals for `task` (a label of the agent's choosing, handed
    /// back in the events) with body `cfp`. Returns the call's conversation id.
    ///
    /// The call is decided once every copy sent is answered or bounced, or at the proposal
    /// deadline (a call that reached nobody fails there with
    /// [`NoProposals`](CallFailure::NoProposals)).
    pub fn announce<M: Model<Msg = Msg>>(
        &mut self,
        cx: &mut Context<'_, M>,
        to: Participants<'_>,
        task: u64,
        cfp: Msg,
    ) -> u64 {
        let seq = self.next;
        self.next = self.next.wrapping_add(1);
        let conversation = conversation_id(cx.me(), seq);
        // The network counts one `sent` per copy: the difference is the number of answers
        // (proposal, refusal or bounce) that would complete the call.
        let before = cx.network().counts(cx.me(), P).sent;
        let size = self.size_bytes;
        let call = |cx: &mut Context<'_, M>, a: Address| {
            send(cx, a, P, Performative::Cfp, conversation, size, cfp.clone());
        };
        match to {
            Participants::Agents(list) => {
                for &a in list {
                    call(cx, Address::Agent(a));
                }
            }
            Participants::Group(g) => call(cx, Address::Group(g)),
            Participants::Broadcast => call(cx, Address::Broadcast),
        }
        let expected = cx.network().counts(cx.me(), P).sent - before;
        let timer = cx.set_timer(self.cfg.proposal_deadline, self.tag.key(u64::from(seq)));
        self.calls.insert(
            conversation,
            Call {
                task,
                cfp,
                timer,
                phase: Phase::Collecting {
                    expected,
                    answered: BTreeSet::new(),
                    bounced: 0,
                    offers: Vec::new(),
                },
            },
        );
        conversation
    }

    /// (Initiator) the open calls as (conversation, task), in conversation order.
    pub fn open_calls(&self) -> impl Iterator<Item = (u64, u64)> + '_ {
        self.calls.iter().map(|(&c, call)| (c, call.task))
    }

    /// (Initiator) whether the call is still open.
    pub fn is_open(&self, conversation: u64) -> bool {
        self.calls.contains_key(&conversation)
    }

    /// (Initiator) the winner of an open call, once awarded.
    pub fn winner(&self, conversation: u64) -> Option<EntityId> {
        match self.calls.get(&conversation)?.phase {
            Phase::Awarded { winner } => Some(winner),
            Phase::Collecting { .. } => None,
        }
    }

    /// (Participant) proposes `body` (its bid inside, see [`Bid`]); binds until accepted,
    /// rejected or expired.
    pub fn propose<M: Model<Msg = Msg>>(
        &mut self,
        cx: &mut Context<'_, M>,
        reply: Reply,
        body: Msg,
    ) {
        answer(cx, reply, P, Performative::Propose, self.size_bytes, body);
        let index = EXPIRY_BIT | (self.next_expiry % EXPIRY_BIT);
        self.next_expiry = self.next_expiry.wrapping_add(1);
        let timer = cx.set_timer(self.cfg.proposal_expiry, self.tag.key(index));
        if let Some((old, t)) = self.proposals.insert(reply, (index, timer)) {
            cx.cancel(t);
            self.expiries.remove(&old);
        }
        self.expiries.insert(index, reply);
    }

    /// (Participant) declines a call.
    pub fn refuse<M: Model<Msg = Msg>>(&self, cx: &mut Context<'_, M>, reply: Reply, body: Msg) {
        answer(cx, reply, P, Performative::Refuse, self.size_bytes, body);
    }

    /// (Participant) reports an accepted task done.
    pub fn report_done<M: Model<Msg = Msg>>(
        &self,
        cx: &mut Context<'_, M>,
        reply: Reply,
        body: Msg,
    ) {
        answer(cx, reply, P, Performative::Done, self.size_bytes, body);
    }

    /// (Participant) reports an accepted task failed.
    pub fn report_failure<M: Model<Msg = Msg>>(
        &self,
        cx: &mut Context<'_, M>,
        reply: Reply,
        body: Msg,
    ) {
        answer(cx, reply, P, Performative::Failure, self.size_bytes, body);
    }

    /// (Participant) the calls it proposed to and awaits an answer from, in order.
    pub fn pending_proposals(&self) -> impl Iterator<Item = Reply> + '_ {
        self.proposals.keys().copied()
    }

    fn forget_proposal<M: Model<Msg = Msg>>(
        &mut self,
        cx: &mut Context<'_, M>,
        reply: Reply,
    ) -> bool {
        match self.proposals.remove(&reply) {
            Some((index, timer)) => {
                cx.cancel(timer);
                self.expiries.remove(&index);
                true
            }
            None => false,
        }
    }

    /// Ends a call's collection: accepts the best proposal and rejects the others, or fails.
    fn decide<'a, M: Model<Msg = Msg>>(
        &mut self,
        cx: &mut Context<'_, M>,
        conversation: u64,
    ) -> Handled<CnetEvent<'a, Msg>> {
        let size = self.size_bytes;
        let report_deadline = self.cfg.report_deadline;
        let tag = self.tag;
        let Some(call) = self.calls.get_mut(&conversation) else {
            return Handled::Consumed;
        };
        let Phase::Collecting { offers, .. } = &mut call.phase else {
            return Handled::Consumed;
        };
        let mut offers = std::mem::take(offers);
        cx.cancel(call.timer);
        let best = offers
            .iter()
            .enumerate()
            .min_by(|(_, a), (_, b)| a.bid.total_cmp(&b.bid).then(a.from.cmp(&b.from)))
            .map(|(i, _)| i);
        let Some(best) = best else {
            return match self.calls.remove(&conversation) {
                Some(call) => Handled::Event(CnetEvent::Failed {
                    conversation,
                    task: call.task,
                    reason: CallFailure::NoProposals,
                    report: None,
                    cfp: call.cfp,
                }),
                None => Handled::Consumed,
            };
        };
        let proposals = offers.len();
        let win = offers.swap_remove(best);
        offers.sort_by_key(|o| o.from);
        let (winner, bid) = (win.from, win.bid);
        let to = |who| Reply {
            to: who,
            conversation,
        };
        answer(
            cx,
            to(winner),
            P,
            Performative::AcceptProposal,
            size,
            win.body,
        );
        for o in offers {
            answer(
                cx,
                to(o.from),
                P,
                Performative::RejectProposal,
                size,
                o.body,
            );
        }
        let index = u64::from(conversation as u32);
        call.timer = cx.set_timer(report_deadline, tag.key(index));
        call.phase = Phase::Awarded { winner };
        Handled::Event(CnetEvent::Awarded {
            conversation,
            task: call.task,
            winner,
            bid,
            proposals,
        })
    }

    /// Counts one answer (or bounce) to a call being collected; decides once all are in.
    fn on_answer<'a, M: Model<Msg = Msg>>(
        &mut self,
        cx: &mut Context<'_, M>,
        conversation: u64,
        from: Option<EntityId>,
        offer: Option<Offer<Msg>>,
    ) -> Handled<CnetEvent<'a, Msg>> {
        let Some(Call {
            phase:
                Phase::Collecting {
                    expected,
                    answered,
                    bounced,
                    offers,
                },
            ..
        }) = self.calls.get_mut(&conversation)
        else {
            return Handled::Consumed;
        };
        match from {
            // A second answer from the same participant changes nothing.
            Some(f) if !answered.insert(f) => return Handled::Consumed,
            Some(_) => {}
            None => *bounced += 1,
        }
        offers.extend(offer);
        if answered.len() as u64 + *bounced >= *expected {
            self.decide(cx, conversation)
        } else {
            Handled::Consumed
        }
    }

    /// Ends an awarded call if `from` won it.
    fn close_awarded<M: Model<Msg = Msg>>(
        &mut self,
        cx: &mut Context<'_, M>,
        conversation: u64,
        from: EntityId,
    ) -> Option<(EntityId, Call<Msg>)> {
        let winner = match self.calls.get(&conversation)?.phase {
            Phase::Awarded { winner } if winner == from => winner,
            _ => return None,
        };
        let call = self.calls.remove(&conversation)?;
        cx.cancel(call.timer);
        Some((winner, call))
    }

    /// Handles one input (see [`Handled`]).
    pub fn handle<'a, M: Model<Msg = Msg>>(
        &mut self,
        input: Input<'a, M>,
        cx: &mut Context<'_, M>,
    ) -> Handled<CnetEvent<'a, Msg>>
    where
        Msg: Bid,
    {
        match input {
            Input::Message(env) if env.protocol == P => self.on_message(env, cx),
            Input::Undeliverable(env, error) if env.protocol == P => self.on_bounce(env, error, cx),
            Input::Timer(key) => match self.tag.index(key) {
                None => Handled::NotMine,
                Some(index) if index & EXPIRY_BIT != 0 => {
                    let Some(reply) = self.expiries.remove(&index) else {
                        return Handled::Consumed;
                    };
                    self.proposals.remove(&reply);
                    Handled::Event(CnetEvent::Expired { reply })
                }
                Some(index) => {
                    let Ok(seq) = u32::try_from(index) else {
                        return Handled::Consumed;
                    };
                    let conversation = conversation_id(cx.me(), seq);
                    match self.calls.get(&conversation).map(|c| &c.phase) {
                        Some(Phase::Collecting { .. }) => self.decide(cx, conversation),
                        Some(Phase::Awarded { .. }) => match self.calls.remove(&conversation) {
                            Some(Call {
                                task,
                                cfp,
                                phase: Phase::Awarded { winner },
                                ..
                            }) => Handled::Event(CnetEvent::Failed {
                                conversation,
                                task,
                                reason: CallFailure::ReportTimedOut { winner },
                                report: None,
                                cfp,
                            }),
                            _ => Handled::Consumed,
                        },
                        None => Handled::Consumed,
                    }
                }
            },
            _ => Handled::NotMine,
        }
    }

    fn on_message<'a, M: Model<Msg = Msg>>(
        &mut self,
        env: &'a Envelope<Msg>,
        cx: &mut Context<'_, M>,
    ) -> Handled<CnetEvent<'a, Msg>>
    where
        Msg: Bid,
    {
        let reply = Reply::to(env);
        let conversation = env.conversation;
        match env.performative {
            Performative::Cfp => Handled::Event(CnetEvent::CallForProposals { reply, cfp: env }),
            Performative::Propose => {
                let late = match self.calls.get(&conversation).map(|c| &c.phase) {
                    Some(Phase::Collecting { .. }) => false,
                    Some(Phase::Awarded { winner }) => *winner != env.from,
                    None => true,
                };
                if late {
                    // Too late to compete: release the bidder at once.
                    let body = env.body.clone();
                    answer(
                        cx,
                        reply,
                        P,
                        Performative::RejectProposal,
                        self.size_bytes,
                        body,
                    );
                    return Handled::Consumed;
                }
                let offer = env.body.bid().filter(|b| !b.is_nan()).map(|bid| Offer {
                    from: env.from,
                    bid,
                    body: env.body.clone(),
                });
                self.on_answer(cx, conversation, Some(env.from), offer)
            }
            Performative::Refuse => self.on_answer(cx, conversation, Some(env.from), None),
            Performative::AcceptProposal => {
                let late = !self.forget_proposal(cx, reply);
                Handled::Event(CnetEvent::Accepted {
                    reply,
                    accept: env,
                    late,
                })
            }
            Performative::RejectProposal => {
                if self.forget_proposal(cx, reply) {
                    Handled::Event(CnetEvent::Rejected { reply })
                } else {
                    Handled::Consumed
                }
            }
            Performative::Done | Performative::Inform => {
                match self.close_awarded(cx, conversation, env.from) {
                    Some((winner, call)) => Handled::Event(CnetEvent::Done {
                        conversation,
                        task: call.task,
                        winner,
                        report: env,
                    }),
                    None => Handled::Consumed,
                }
            }
            Performative::Failure => match self.close_awarded(cx, conversation, env.from) {
                Some((winner, call)) => Handled::Event(CnetEvent::Failed {
                    conversation,
                    task: call.task,
                    reason: CallFailure::WinnerFailed { winner },
                    report: Some(env),
                    cfp: call.cfp,
                }),
                None => Handled::Consumed,
            },
            _ => Handled::NotMine,
        }
    }

    fn on_bounce<'a, M: Model<Msg = Msg>>(
        &mut self,
        env: &'a Envelope<Msg>,
        error: DeliveryError,
        cx: &mut Context<'_, M>,
    ) -> Handled<CnetEvent<'a, Msg>> {
        let conversation = env.conversation;
        match env.performative {
            Performative::Cfp => {
                // The receiver, when known, counts as having answered (no proposal).
                let from = match env.to {
                    Address::Agent(r) => Some(r),
                    _ => error.receiver(),
                };
                self.on_answer(cx, conversation, from, None)
            }
            Performative::AcceptProposal => {
                match self.close_awarded(cx, conversation, env.receiver) {
                    Some((winner, call)) => Handled::Event(CnetEvent::Failed {
                        conversation,
                        task: call.task,
                        reason: CallFailure::WinnerUnreachable { winner, error },
                        report: None,
                        cfp: call.cfp,
                    }),
                    None => Handled::Consumed,
                }
            }
            Performative::Propose => {
                let reply = Reply {
                    to: env.receiver,
                    conversation,
                };
                if self.forget_proposal(cx, reply) {
                    Handled::Event(CnetEvent::Expired { reply })
                } else {
                    Handled::Consumed
                }
            }
            _ => Handled::Consumed,
        }
    }
}

//! What an agent is: the [`Model`] it belongs to, the [`Input`]s it receives and the
//! [`Context`] it acts through (sensors, actuators, scheduling of its own events, messages,
//! random streams; never the environment itself). The three name each other, so they live
//! in one file.

use super::kernel::{Kernel, Queued};
use super::round::RoundId;
use crate::comm::{DeliveryError, Envelope, GroupId, Network, Outgoing, Route};
use crate::entity::{CapabilityRegister, EntityId};
use crate::env::{Actuator, Effects, Probe, Sensor};
use crate::event::{EventId, OwnEventId, Schedule, ScheduleError, Target};
use crate::rng::Owner;
use crate::time::{SimDuration, SimTime};
use rand_chacha::ChaCha8Rng;
use serde::{Deserialize, Serialize};

/// The types of one simulation model, and its environment's behaviour.
pub trait Model: Sized + 'static {
    /// The environment: every storage of the world.
    type Env;
    /// Event payloads (typed; stored inline in the queue, no box per event).
    type Event: Serialize;
    /// Message contents.
    type Msg: Clone + Serialize;
    /// The agents (a single type, or an enum of agent kinds: dispatch stays static).
    type Agent: Agent<Self>;

    /// Handles an event targeted at the environment ([`Target::Env`](crate::event::Target)):
    /// physics steps, delayed actuator effects. Does nothing by default.
    fn on_env_event(env: &mut Self::Env, event: &Self::Event, fx: &mut Effects<'_, Self::Event>) {
        let _ = (env, event, fx);
    }

    /// The position sensor used by range-limited channels: where `who` is at `now` (models
    /// that move bodies by events may interpolate). `None` by default (no position).
    fn locate(env: &Self::Env, who: EntityId, now: SimTime) -> Option<[f64; 3]> {
        let _ = (env, who, now);
        None
    }

    /// A digest of the environment's state changes so far (combine the storages'
    /// `digest()`s). Part of the trace hash. Zero by default.
    fn state_digest(env: &Self::Env) -> u64 {
        let _ = env;
        0
    }
}

/// What an agent is woken by.
pub enum Input<'a, M: Model> {
    /// An event targeted at this agent, or broadcast.
    Event(&'a M::Event),
    /// A message delivered to this agent.
    Message(&'a Envelope<M::Msg>),
    /// A message this agent sent that could not be delivered.
    Undeliverable(&'a Envelope<M::Msg>, DeliveryError),
    /// A timer this agent set ([`Context::set_timer`]) with its key.
    Timer(u64),
}

impl<M: Model> Clone for Input<'_, M> {
    fn clone(&self) -> Self {
        *self
    }
}
impl<M: Model> Copy for Input<'_, M> {}

/// An agent: the brain of an entity. It reaches the world only through its [`Context`].
pub trait Agent<M: Model> {
    /// Reacts to one input.
    fn handle(&mut self, input: Input<'_, M>, cx: &mut Context<'_, M>);
}

/// The simulated cost of thinking: `base + per_unit × units` (e.g. per search node expanded).
///
/// Deliberation is charged simulated time from this declared model, never host time, so the
/// scenario, not the CPU, sets how fast agents reason.
#[derive(Copy, Clone, Debug, Default, PartialEq, Eq, Serialize, Deserialize)]
pub struct CostModel {
    /// Fixed cost of any deliberation.
    pub base: SimDuration,
    /// Cost of one unit of work.
    pub per_unit: SimDuration,
}

impl CostModel {
    /// The simulated duration of `units` units of work.
    pub fn cost(&self, units: u64) -> SimDuration {
        self.base + self.per_unit * units
    }
}

/// What an agent may do while it handles an input. It holds no way to reach the environment
/// but [`sense`](Self::sense) and [`act`](Self::act).
///
/// The compiler enforces that rule: an agent that tries to touch a storage directly does not
/// build.
///
/// ```compile_fail,E0616
/// use vitro::prelude::*;
/// struct World { fuel: EntityStorage<f64> }
/// struct M;
/// impl Model for M { type Env = World; type Event = (); type Msg = (); type Agent = Cheat; }
/// struct Cheat;
/// impl Agent<M> for Cheat {
///     fn handle(&mut self, _: Input<'_, M>, cx: &mut Context<'_, M>) {
///         cx.env.fuel.insert(cx.me(), 1e9); // error[E0616]: field `env` is private
///     }
/// }
/// ```
///
/// The same agent written through an actuator builds:
///
/// ```
/// use vitro::prelude::*;
/// struct World { fuel: EntityStorage<f64> }
/// struct Refuel;
/// impl Actuator<World, ()> for Refuel {
///     type Command = f64;
///     type Error = std::convert::Infallible;
///     fn actuate(&self, w: &mut World, me: EntityId, litres: f64, _: &mut Effects<()>)
///         -> Result<(), Self::Error> {
///         w.fuel.insert(me, litres);
///         Ok(())
///     }
/// }
/// struct M;
/// impl Model for M { type Env = World; type Event = (); type Msg = (); type Agent = Honest; }
/// struct Honest;
/// impl Agent<M> for Honest {
///     fn handle(&mut self, _: Input<'_, M>, cx: &mut Context<'_, M>) {
///         let Ok(()) = cx.act(&Refuel, 40.0);
///     }
/// }
/// ```
pub struct Context<'a, M: Model> {
    pub(crate) me: EntityId,
    pub(crate) env: &'a mut M::Env,
    pub(crate) k: &'a mut Kernel<M::Event, M::Msg>,
}

impl<'a, M: Model> Context<'a, M> {
    /// The entity this agent is.
    pub fn me(&self) -> EntityId {
        self.me
    }
    /// The current simulated time.
    pub fn now(&self) -> SimTime {
        self.k.queue.now()
    }
    /// The name of an entity.
    pub fn name_of(&self, id: EntityId) -> Option<&str> {
        self.k.entities.name(id)
    }
    /// The entity called `name`.
    pub fn lookup(&self, name: &str) -> Option<EntityId> {
        self.k.entities.lookup(name)
    }

    /// Reads a sensor now.
    pub fn sense<S: Sensor<M::Env>>(&mut self, sensor: &S) -> S::Reading {
        let mut probe = Probe {
            now: self.k.queue.now(),
            owner: self.me,
            rngs: &mut self.k.rngs,
        };
        sensor.read(self.env, self.me, &mut probe)
    }

    /// Reads a sensor now and delivers the reading to this agent after `latency`, as the event
    /// `wrap(reading)` (a sensor acting with a delay).
    pub fn sense_later<S: Sensor<M::Env>>(
        &mut self,
        sensor: &S,
        latency: SimDuration,
        wrap: impl FnOnce(S::Reading) -> M::Event,
    ) -> OwnEventId {
        let reading = self.sense(sensor);
        self.schedule_in(latency, wrap(reading))
    }

    /// Commands an actuator.
    pub fn act<A: Actuator<M::Env, M::Event>>(
        &mut self,
        actuator: &A,
        cmd: A::Command,
    ) -> Result<(), A::Error> {
        let mut fx = Effects {
            owner: Owner::Entity(self.me),
            rngs: &mut self.k.rngs,
            sched: &mut EventOnly(&mut self.k.queue),
            fired: None,
        };
        actuator.actuate(self.env, self.me, cmd, &mut fx)
    }

    /// Schedules `event` for this agent itself after `delay`.
    ///
    /// An agent schedules only its own events: the environment's and other agents' are
    /// changed through actuators and messages. There is no target to name:
    ///
    /// ```compile_fail,E0061
    /// # use vitro::prelude::*;
    /// # struct M;
    /// # impl Model for M { type Env = (); type Event = (); type Msg = (); type Agent = A; }
    /// # struct A;
    /// impl Agent<M> for A {
    ///     fn handle(&mut self, _: Input<'_, M>, cx: &mut Context<'_, M>) {
    ///         cx.schedule_in(SimDuration::from_secs(1), Target::Env, ()); // does not build
    ///     }
    /// }
    /// ```
    ///
    /// Its own event, the same agent otherwise, builds:
    ///
    /// ```
    /// # use vitro::prelude::*;
    /// # struct M;
    /// # impl Model for M { type Env = (); type Event = (); type Msg = (); type Agent = A; }
    /// # struct A;
    /// impl Agent<M> for A {
    ///     fn handle(&mut self, _: Input<'_, M>, cx: &mut Context<'_, M>) {
    ///         let _mine: OwnEventId = cx.schedule_in(SimDuration::from_secs(1), ());
    ///     }
    /// }
    /// ```
    pub fn schedule_in(&mut self, delay: SimDuration, event: M::Event) -> OwnEventId {
        let at = self.now() + delay;
        self.schedule_at(at, event)
            .expect("now + delay is never in the past")
    }
    /// Schedules `event` for this agent itself at `at`; an error if `at` is in the past.
    pub fn schedule_at(
        &mut self,
        at: SimTime,
        event: M::Event,
    ) -> Result<OwnEventId, ScheduleError> {
        let id = self.k.queue.push(at, Queued::Own(self.me, event))?;
        Ok(OwnEventId::new(id))
    }
    /// Cancels one of this agent's own pending events or timers; false if it already fired,
    /// was cancelled, or is not this agent's.
    ///
    /// Only ids this agent's scheduling returned are accepted; an [`EventId`] of the
    /// environment's does not build:
    ///
    /// ```compile_fail,E0308
    /// # use vitro::prelude::*;
    /// # struct M;
    /// # impl Model for M { type Env = (); type Event = vitro::event::EventId; type Msg = (); type Agent = A; }
    /// # struct A;
    /// impl Agent<M> for A {
    ///     fn handle(&mut self, input: Input<'_, M>, cx: &mut Context<'_, M>) {
    ///         if let Input::Event(id) = input {
    ///             cx.cancel(*id); // an EventId, not an OwnEventId: does not build
    ///         }
    ///     }
    /// }
    /// ```
    ///
    /// An id of its own scheduling builds (and cancels, once):
    ///
    /// ```
    /// # use vitro::prelude::*;
    /// # struct M;
    /// # impl Model for M { type Env = (); type Event = vitro::event::EventId; type Msg = (); type Agent = A; }
    /// # struct A;
    /// impl Agent<M> for A {
    ///     fn handle(&mut self, input: Input<'_, M>, cx: &mut Context<'_, M>) {
    ///         if let Input::Event(id) = input {
    ///             let mine = cx.schedule_in(SimDuration::from_secs(1), *id);
    ///             assert!(cx.cancel(mine));
    ///             assert!(!cx.cancel(mine));
    ///         }
    ///     }
    /// }
    /// ```
    pub fn cancel(&mut self, id: OwnEventId) -> bool {
        let me = self.me;
        let mine = matches!(
            self.k.queue.get(id.id()),
            Some(Queued::Own(who, _) | Queued::Timer(who, _)) if *who == me
        );
        mine && self.k.queue.cancel(id.id())
    }
    /// Wakes this agent with [`Input::Timer(key)`](super::Input::Timer) after `delay`.
    pub fn set_timer(&mut self, delay: SimDuration, key: u64) -> OwnEventId {
        let at = self.now() + delay;
        let id = self
            .k
            .queue
            .push(at, Queued::Timer(self.me, key))
            .expect("now + delay is never in the past");
        OwnEventId::new(id)
    }
    /// Delivers `event` to this agent once `units` of thinking, priced by `cost`, are done:
    /// the way to make a decision take simulated time.
    pub fn decide_after(&mut self, cost: &CostModel, units: u64, event: M::Event) -> OwnEventId {
        self.schedule_in(cost.cost(units), event)
    }

    /// This agent's random stream for `purpose`.
    #[inline]
    pub fn rng(&mut self, purpose: &str) -> &mut ChaCha8Rng {
        self.k.rngs.stream(Owner::Entity(self.me), purpose)
    }

    /// Joins `round` ([`Simulation::add_round`](super::Simulation::add_round)): from its next
    /// firing on, this agent is activated once per firing; false if it was a member already.
    pub fn join_round(&mut self, round: RoundId) -> bool {
        self.k.join_round(round, self.me)
    }
    /// Leaves `round`; false if this agent was not a member.
    pub fn leave_round(&mut self, round: RoundId) -> bool {
        self.k.leave_round(round, self.me)
    }

    /// This agent's small random stream for `purpose`
    /// ([`RngStreams::small`](crate::rng::RngStreams::small): SplitMix64, 8 bytes of state):
    /// for agents by the thousand that draw a few numbers per activation.
    #[inline]
    pub fn small_rng(&mut self, purpose: &str) -> &mut crate::rng::SplitMix64 {
        self.k.rngs.small(Owner::Entity(self.me), purpose)
    }

    /// Sends a message through the simulated network. Each copy is delivered later, lost, or
    /// comes back as [`Input::Undeliverable`](super::Input::Undeliverable).
    pub fn send(&mut self, msg: Outgoing<M::Msg>) {
        let now = self.now();
        let me = self.me;
        let env: &M::Env = self.env;
        let k = &mut *self.k;
        let rng = k.rngs.stream(Owner::Entity(me), "comm");
        let has_agent = &k.has_agent;
        let routes = k.network.route(
            me,
            msg.to,
            msg.protocol,
            msg.size_bytes,
            now,
            &k.agent_order,
            |id| has_agent.get(id.index()).copied().unwrap_or(false),
            |id| M::locate(env, id, now),
            rng,
        );
        let n = routes.len();
        let mut body = Some(msg.body);
        for (i, route) in routes.into_iter().enumerate() {
            let b = if i + 1 == n {
                body.take().expect("body used once")
            } else {
                body.clone().expect("body kept until last")
            };
            let mut env = Envelope {
                from: me,
                to: msg.to,
                receiver: me,
                protocol: msg.protocol,
                performative: msg.performative,
                conversation: msg.conversation,
                sent_at: now,
                size_bytes: msg.size_bytes,
                body: b,
            };
            let pushed = match route {
                Route::Deliver { receiver, at } => {
                    env.receiver = receiver;
                    k.queue.push(at, Queued::Message(Box::new(env)))
                }
                Route::Bounce {
                    receiver,
                    error,
                    at,
                } => {
                    // The copy's intended receiver; the sender itself for an empty group.
                    env.receiver = receiver.unwrap_or(me);
                    k.queue.push(at, Queued::Bounce(Box::new((env, error))))
                }
                Route::Lost { .. } => continue,
            };
            pushed.expect("deliveries are never in the past");
        }
    }

    /// The network (read-only: link parameters, groups, message counts).
    pub fn network(&self) -> &Network {
        &self.k.network
    }
    /// Joins a multicast group.
    pub fn join(&mut self, group: GroupId) {
        self.k.network.join(group, self.me);
    }
    /// Leaves a multicast group.
    pub fn leave(&mut self, group: GroupId) {
        self.k.network.leave(group, self.me);
    }

    /// The capability register (who offers what).
    pub fn register(&self) -> &CapabilityRegister {
        &self.k.register
    }
    /// Offers a capability in the register.
    pub fn offer(&mut self, capability: &str) -> bool {
        self.k.register.offer(self.me, capability)
    }
    /// Withdraws a capability from the register.
    pub fn withdraw(&mut self, capability: &str) -> bool {
        self.k.register.withdraw(self.me, capability)
    }

    /// Asks the driver to stop after this event.
    pub fn request_stop(&mut self) {
        self.k.stop_requested = true;
    }
}

/// Adapts the raw queue to [`Schedule`] for actuators and the environment.
pub(crate) struct EventOnly<'q, E, Msg>(pub &'q mut crate::event::EventQueue<Queued<E, Msg>>);

impl<E, Msg> Schedule<E> for EventOnly<'_, E, Msg> {
    fn now(&self) -> SimTime {
        self.0.now()
    }
    fn schedule_at(
        &mut self,
        at: SimTime,
        target: Target,
        event: E,
    ) -> Result<EventId, ScheduleError> {
        self.0.push(at, Queued::Event(target, event))
    }
    fn cancel(&mut self, id: EventId) -> bool {
        self.0.cancel(id)
    }
}

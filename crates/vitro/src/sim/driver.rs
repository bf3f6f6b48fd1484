//! The simulation driver: fires events, paces them, obeys the control handle.

use super::agent::{Agent, Input, Model};
use super::agent::{Context, EventOnly};
use super::control::{Clock, Control, ControlState, WallClock};
use super::handle::{AgentHandle, AgentKey, Holds};
use super::kernel::{Kernel, Queued};
use super::round::{Round, RoundId};
use crate::comm::Network;
use crate::entity::{CapabilityRegister, Entities, EntityError, EntityId};
use crate::env::Effects;
use crate::event::{EventId, Popped, ScheduleError, Target};
use crate::rng::{Owner, RngStreams};
use crate::time::{SimDuration, SimTime};
use crate::trace::TraceHasher;
use std::sync::atomic::Ordering;
use std::time::Duration;

/// One fired event, as shown to listeners (after the agents handled it).
pub struct Fired<'a, M: Model> {
    /// When it fired.
    pub time: SimTime,
    /// Its handle.
    pub id: EventId,
    /// Who received it (for messages: the receiver; for bounces: the sender).
    pub target: Target,
    /// What was received.
    pub input: Input<'a, M>,
}

/// Why a run returned.
#[derive(Copy, Clone, Debug, PartialEq, Eq, serde::Serialize, serde::Deserialize)]
pub enum StopReason {
    /// The next event is after the requested end time.
    Time,
    /// No event is left.
    QueueEmpty,
    /// The stop condition became true.
    Condition,
    /// An agent asked to stop ([`Context::request_stop`]).
    Requested,
    /// The control handle asked to stop.
    Control,
}

type Listener<M> = Box<dyn for<'a> FnMut(&Fired<'a, M>) + Send>;

/// A running model: environment, agents, event queue, random streams, network, trace.
///
/// ```
/// use vitro::prelude::*;
///
/// struct Ping;
/// impl Model for Ping {
///     type Env = ();
///     type Event = u32;
///     type Msg = ();
///     type Agent = Counter;
/// }
/// struct Counter(u32);
/// impl Agent<Ping> for Counter {
///     fn handle(&mut self, input: Input<'_, Ping>, cx: &mut Context<'_, Ping>) {
///         if let Input::Event(&n) = input {
///             self.0 += 1;
///             if n > 0 {
///                 cx.schedule_in(SimDuration::from_secs(1), n - 1);
///             }
///         }
///     }
/// }
/// let mut sim = Simulation::<Ping>::new((), 7);
/// let a = sim.add_agent("counter", Counter(0)).unwrap();
/// sim.schedule(SimTime::ZERO, Target::Entity(a), 9).unwrap();
/// assert_eq!(sim.run_until(SimTime::MAX), StopReason::QueueEmpty);
/// assert_eq!(sim.agent(a).unwrap().0, 10);
/// assert_eq!(sim.now(), SimTime::from_secs(9));
/// ```
pub struct Simulation<M: Model> {
    pub(crate) env: M::Env,
    pub(crate) agents: Vec<Option<M::Agent>>,
    pub(crate) k: Kernel<M::Event, M::Msg>,
    listeners: Vec<Listener<M>>,
    control: Control,
    clock: Box<dyn Clock>,
}

/// Longest single sleep while pacing, so control changes are seen promptly.
const MAX_SLEEP: Duration = Duration::from_millis(20);

impl<M: Model> Simulation<M> {
    /// A simulation of `env` whose random streams derive from `seed`.
    pub fn new(env: M::Env, seed: u64) -> Self {
        Self::from_parts(env, Vec::new(), Kernel::new(seed))
    }

    pub(crate) fn from_parts(
        env: M::Env,
        agents: Vec<Option<M::Agent>>,
        k: Kernel<M::Event, M::Msg>,
    ) -> Self {
        let control = Control::default();
        control
            .0
            .sim_now
            .store(k.queue.now().as_nanos(), Ordering::Release);
        control.0.fired.store(k.fired, Ordering::Release);
        Simulation {
            env,
            agents,
            k,
            listeners: Vec::new(),
            control,
            clock: Box::new(WallClock::default()),
        }
    }

    /// Creates an entity without an agent (a passive body).
    pub fn add_entity(&mut self, name: impl Into<String>) -> Result<EntityId, EntityError> {
        let id = self.k.entities.create(name)?;
        self.agents.push(None);
        self.k.has_agent.push(false);
        Ok(id)
    }

    /// Creates an entity driven by `agent`. Broadcasts reach agents in this order. An empty
    /// `name` makes an unnamed entity ([`Entities`]: known by its id only).
    pub fn add_agent(
        &mut self,
        name: impl Into<String>,
        agent: M::Agent,
    ) -> Result<EntityId, EntityError> {
        let id = self.add_entity(name)?;
        self.agents[id.index()] = Some(agent);
        self.k.has_agent[id.index()] = true;
        self.k.agent_order.push(id);
        Ok(id)
    }

    /// Creates an entity driven by `agent` (as [`add_agent`](Self::add_agent)) and returns
    /// its typed handle: [`agent`](Self::agent) given the handle returns the `A`.
    pub fn add<A>(
        &mut self,
        name: impl Into<String>,
        agent: A,
    ) -> Result<AgentHandle<A>, EntityError>
    where
        M::Agent: Holds<A>,
    {
        let id = self.add_agent(name, M::Agent::hold(agent))?;
        Ok(AgentHandle::new(id))
    }

    /// The environment, for set-up and for the experimenter (agents never get it).
    pub fn env(&self) -> &M::Env {
        &self.env
    }
    /// The environment, mutable, for set-up between runs.
    pub fn env_mut(&mut self) -> &mut M::Env {
        &mut self.env
    }
    /// The agent of `key`: of an [`EntityId`], the model's agent; of a handle
    /// ([`add`](Self::add)), the agent of the handle's type.
    pub fn agent<K: AgentKey<M>>(&self, key: K) -> Option<&K::Agent> {
        self.agents
            .get(key.entity().index())
            .and_then(Option::as_ref)
            .and_then(K::pick)
    }
    /// The entity directory.
    pub fn entities(&self) -> &Entities {
        &self.k.entities
    }
    /// The capability register.
    pub fn register_mut(&mut self) -> &mut CapabilityRegister {
        &mut self.k.register
    }
    /// The capability register.
    pub fn register(&self) -> &CapabilityRegister {
        &self.k.register
    }
    /// The simulated network.
    pub fn network(&self) -> &Network {
        &self.k.network
    }
    /// The simulated network, for configuration.
    pub fn network_mut(&mut self) -> &mut Network {
        &mut self.k.network
    }
    /// The random streams (set-up code may draw from its own named streams).
    pub fn rngs_mut(&mut self) -> &mut RngStreams {
        &mut self.k.rngs
    }
    /// Whether event payloads are hashed into the trace (default true; times, sequence numbers
    /// and targets always are).
    pub fn set_trace_payloads(&mut self, on: bool) {
        self.k.trace_payloads = on;
    }
    /// From now on, events due at the same time fire in a seeded random order instead of
    /// first scheduled, first fired ([`EventQueue::shuffle_ties`](crate::event::EventQueue::shuffle_ties);
    /// the generator is seeded from the run's own `"tie_order"` stream, so the same seed
    /// gives the same order): a check that an outcome is not an artefact of the order in
    /// which agents were added or woke.
    pub fn shuffle_ties(&mut self) {
        use rand::Rng;
        let seed = self.k.rngs.stream(Owner::Global, "tie_order").random();
        self.k.queue.shuffle_ties(seed);
    }

    /// Schedules an event from outside (set-up, experimenter).
    pub fn schedule(
        &mut self,
        at: SimTime,
        target: Target,
        event: M::Event,
    ) -> Result<EventId, ScheduleError> {
        self.k.queue.push(at, Queued::Event(target, event))
    }
    /// Cancels a pending event.
    pub fn cancel(&mut self, id: EventId) -> bool {
        self.k.queue.cancel(id)
    }

    /// A new round: from `first` on, every `period` (at least a nanosecond), it activates
    /// each of its members once with [`Input::Timer(key)`](Input::Timer), in a fresh random
    /// order each time (drawn from the run's small stream `"round_order"`), as one event of
    /// the queue. Members join with [`join_round`](Self::join_round) or
    /// [`Context::join_round`]; a round without members is idle (no event) until one joins.
    /// An agent joining during a firing is activated from the next one on; a stop request
    /// takes effect once the firing is done.
    ///
    /// ```
    /// use vitro::prelude::*;
    /// struct M;
    /// impl Model for M { type Env = (); type Event = (); type Msg = (); type Agent = Walker; }
    /// struct Walker(Vec<SimTime>);
    /// impl Agent<M> for Walker {
    ///     fn handle(&mut self, input: Input<'_, M>, cx: &mut Context<'_, M>) {
    ///         if let Input::Timer(7) = input {
    ///             self.0.push(cx.now());
    ///         }
    ///     }
    /// }
    /// let mut sim = Simulation::<M>::new((), 1);
    /// let step = sim.add_round(SimTime::ZERO, SimDuration::from_secs(1), 7).unwrap();
    /// for i in 0..3 {
    ///     let a = sim.add_agent(format!("w{i}"), Walker(Vec::new())).unwrap();
    ///     sim.join_round(step, a);
    /// }
    /// sim.run_until(SimTime::from_secs(2));
    /// let a = sim.entities().lookup("w0").unwrap();
    /// assert_eq!(sim.agent(a).unwrap().0.len(), 3); // at 0, 1 and 2 s
    /// assert_eq!(sim.events_fired(), 3); // one event per firing
    /// ```
    pub fn add_round(
        &mut self,
        first: SimTime,
        period: SimDuration,
        key: u64,
    ) -> Result<RoundId, ScheduleError> {
        let now = self.k.queue.now();
        if first < now {
            return Err(ScheduleError::InThePast { at: first, now });
        }
        let id = RoundId(u32::try_from(self.k.rounds.len()).expect("more than 2^32 rounds"));
        self.k.rounds.push(Round {
            key,
            period: SimDuration::from_nanos(period.as_nanos().max(1)),
            next_at: first,
            ..Round::default()
        });
        Ok(id)
    }
    /// Makes `agent` a member of `round`; false if it was one or there is no such round.
    pub fn join_round(&mut self, round: RoundId, agent: EntityId) -> bool {
        self.k.join_round(round, agent)
    }
    /// Ends `agent`'s membership of `round`; false if it was not a member.
    pub fn leave_round(&mut self, round: RoundId, agent: EntityId) -> bool {
        self.k.leave_round(round, agent)
    }
    /// Number of members of `round` (0 if there is no such round).
    pub fn round_len(&self, round: RoundId) -> usize {
        self.k.rounds.get(round.0 as usize).map_or(0, Round::len)
    }

    /// The simulated time of the last fired event.
    pub fn now(&self) -> SimTime {
        self.k.queue.now()
    }
    /// Number of pending events.
    pub fn pending(&self) -> usize {
        self.k.queue.len()
    }
    /// Number of events fired so far.
    pub fn events_fired(&self) -> u64 {
        self.k.fired
    }
    /// The trace hash so far: every fired event (time, sequence, target, payload) and the
    /// environment's state changes ([`Model::state_digest`]).
    pub fn trace_hash(&self) -> u64 {
        let mut h = self.k.trace;
        h.write_u64(M::state_digest(&self.env));
        h.finish()
    }

    /// Registers a listener called after every fired event.
    pub fn add_listener(&mut self, f: impl for<'a> FnMut(&Fired<'a, M>) + Send + 'static) {
        self.listeners.push(Box::new(f));
    }
    /// A handle to control this simulation from another thread.
    pub fn control(&self) -> Control {
        self.control.clone()
    }
    /// Replaces the wall clock used for pacing (tests use a [`ManualClock`](super::ManualClock)).
    pub fn set_clock(&mut self, clock: impl Clock + 'static) {
        self.clock = Box::new(clock);
    }

    /// Fires the next event, ignoring pacing and control. Returns its time, `None` if empty.
    pub fn step(&mut self) -> Option<SimTime> {
        let p = self.k.queue.pop()?;
        Some(self.fire(p))
    }

    /// Fires a popped event: traces it, hands it to its receivers and the listeners.
    #[inline]
    fn fire(&mut self, p: Popped<Queued<M::Event, M::Msg>>) -> SimTime {
        let t = p.time;
        self.k.fired += 1;
        let tr = &mut self.k.trace;
        tr.write_u64(t.as_nanos());
        tr.write_u64(p.id.seq());
        let payloads = self.k.trace_payloads;
        let (target, input) = match &p.payload {
            Queued::Event(target, ev) => traced_event(tr, *target, ev, payloads),
            // Traced as an event targeted at `who` (the same bits as before the split).
            Queued::Own(who, ev) => traced_event(tr, Target::Entity(*who), ev, payloads),
            Queued::Message(e) => {
                tr.write_u64(1 << 62);
                tr.digest(e);
                self.k.network.count_received(e.receiver, e.protocol);
                (Target::Entity(e.receiver), Input::Message(e))
            }
            Queued::Bounce(b) => {
                let (e, err) = &**b;
                tr.write_u64(2 << 62);
                tr.digest(e);
                tr.digest(err);
                (Target::Entity(e.from), Input::Undeliverable(e, *err))
            }
            Queued::Timer(who, key) => {
                tr.write_u64((3 << 62) | who.0 as u64);
                tr.write_u64(*key);
                (Target::Entity(*who), Input::Timer(*key))
            }
            Queued::Round(r) => {
                tr.write_u64((1 << 61) | u64::from(*r));
                self.fire_round(t, p.id, *r);
                self.control
                    .0
                    .sim_now
                    .store(t.as_nanos(), Ordering::Release);
                self.control.0.fired.store(self.k.fired, Ordering::Release);
                return t;
            }
        };
        match target {
            Target::Entity(e) => self.deliver(e, input),
            Target::Broadcast => {
                for i in 0..self.k.agent_order.len() {
                    let e = self.k.agent_order[i];
                    self.deliver(e, input);
                }
            }
            Target::Env => {
                if let Input::Event(ev) = input {
                    let mut fx = Effects {
                        owner: Owner::Global,
                        rngs: &mut self.k.rngs,
                        sched: &mut EventOnly(&mut self.k.queue),
                        fired: Some(p.id),
                    };
                    M::on_env_event(&mut self.env, ev, &mut fx);
                }
            }
        }
        if !self.listeners.is_empty() {
            let fired = Fired {
                time: t,
                id: p.id,
                target,
                input,
            };
            for l in &mut self.listeners {
                l(&fired);
            }
        }
        self.control
            .0
            .sim_now
            .store(t.as_nanos(), Ordering::Release);
        self.control.0.fired.store(self.k.fired, Ordering::Release);
        t
    }

    /// Fires round `r`: its members in a fresh random order, each traced and activated.
    fn fire_round(&mut self, t: SimTime, id: EventId, r: u32) {
        use rand::Rng;
        let Some(round) = self.k.rounds.get_mut(r as usize) else {
            return;
        };
        round.pending = false;
        let (key, period) = (round.key, round.period);
        let mut order = std::mem::take(&mut round.members);
        let rng = self.k.rngs.small(Owner::Global, "round_order");
        for i in (1..order.len()).rev() {
            order.swap(i, rng.random_range(0..=i));
        }
        for &e in &order {
            if !self.k.rounds[r as usize].is_active(e) {
                continue;
            }
            self.k.trace.write_u64(u64::from(e.0));
            self.deliver(e, Input::Timer(key));
            if !self.listeners.is_empty() {
                let fired = Fired {
                    time: t,
                    id,
                    target: Target::Entity(e),
                    input: Input::Timer(key),
                };
                for l in &mut self.listeners {
                    l(&fired);
                }
            }
        }
        let round = &mut self.k.rounds[r as usize];
        round.settle(order);
        round.next_at = t + period;
        if !round.members.is_empty() {
            round.pending = true;
            // Later than now: the period is at least a nanosecond.
            let _ = self.k.queue.push(round.next_at, Queued::Round(r));
        }
    }

    fn deliver(&mut self, e: EntityId, input: Input<'_, M>) {
        if let Some(Some(agent)) = self.agents.get_mut(e.index()) {
            let mut cx = Context {
                me: e,
                env: &mut self.env,
                k: &mut self.k,
            };
            agent.handle(input, &mut cx);
        }
    }

    /// Runs until the next event is after `until` or the queue is empty (or a stop request).
    pub fn run_until(&mut self, until: SimTime) -> StopReason {
        self.run(until, |_| false)
    }

    /// Runs until `stop_if` holds (checked before the first event and after each), the next
    /// event is after `until`, the queue empties, an agent or the control handle stops it.
    ///
    /// Pacing and pausing follow the [`Control`] handle; they change only wall-clock timing.
    pub fn run(&mut self, until: SimTime, mut stop_if: impl FnMut(&Self) -> bool) -> StopReason {
        let control = self.control.clone();
        let mut seen = u64::MAX;
        let mut st = ControlState {
            paused: false,
            speed: None,
            steps: 0,
            stop: false,
        };
        // Pacing anchor: (wall, sim) at the last (re)start of paced running.
        let mut anchor: Option<(Duration, SimTime)> = None;
        if stop_if(self) {
            return StopReason::Condition;
        }
        loop {
            let generation = control.generation();
            if generation != seen {
                seen = generation;
                let mut s = control.lock();
                if s.stop {
                    s.stop = false;
                    return StopReason::Control;
                }
                if s.speed != st.speed || s.paused != st.paused {
                    anchor = None;
                }
                st = *s;
            }
            if st.paused && st.steps == 0 {
                let s = control.lock();
                if control.generation() == seen {
                    let _unused = control
                        .0
                        .changed
                        .wait_timeout(s, Duration::from_millis(50))
                        .unwrap_or_else(|e| e.into_inner());
                }
                continue;
            }
            let Some(t) = self.k.queue.peek_time() else {
                return StopReason::QueueEmpty;
            };
            if t > until {
                return StopReason::Time;
            }
            if let (Some(speed), false) = (st.speed, st.paused) {
                let (w0, s0) = *anchor.get_or_insert((self.clock.now(), self.now()));
                let due = w0 + Duration::from_secs_f64((t - s0).as_secs_f64() / speed);
                let wall = self.clock.now();
                if wall < due {
                    self.clock.sleep((due - wall).min(MAX_SLEEP));
                    continue;
                }
            }
            if st.paused {
                let mut s = control.lock();
                if s.steps == 0 || !s.paused {
                    continue;
                }
                s.steps -= 1;
                st.steps = s.steps;
            }
            // The event just peeked at: nothing touched the queue since.
            if let Some(p) = self.k.queue.pop_peeked() {
                self.fire(p);
            }
            if self.k.stop_requested {
                self.k.stop_requested = false;
                return StopReason::Requested;
            }
            if stop_if(self) {
                return StopReason::Condition;
            }
        }
    }
}

/// Traces an event for `target` (its payload too when `payloads`) and gives the receiver's
/// input: the one path of plain and own events, so the payload's digest is one call site.
#[inline]
fn traced_event<'a, M: Model>(
    tr: &mut TraceHasher,
    target: Target,
    ev: &'a M::Event,
    payloads: bool,
) -> (Target, Input<'a, M>) {
    tr.write_u64(target_code(target));
    if payloads {
        tr.digest(ev);
    }
    (target, Input::Event(ev))
}

fn target_code(t: Target) -> u64 {
    match t {
        Target::Entity(e) => e.0 as u64,
        Target::Broadcast => 1 << 40,
        Target::Env => 1 << 41,
    }
}

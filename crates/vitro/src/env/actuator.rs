//! Actuators: the only way an agent changes the environment.
//!
//! An actuator may write storages directly or drive lower actuators (layering):
//! `GoToNode -> MoveInDirection -> SteerAndAccelerate`. It may also act with a delay by
//! scheduling an event for the environment through [`Effects`].

use crate::entity::EntityId;
use crate::event::{EventId, Schedule, ScheduleError, Target};
use crate::rng::{Owner, RngStreams};
use crate::time::{SimDuration, SimTime};
use rand_chacha::ChaCha8Rng;

/// What an actuator (or the environment's own event handler) may do besides writing storages:
/// schedule and cancel events, draw random numbers.
pub struct Effects<'a, Ev> {
    pub(crate) owner: Owner,
    pub(crate) rngs: &'a mut RngStreams,
    pub(crate) sched: &'a mut dyn Schedule<Ev>,
    pub(crate) fired: Option<EventId>,
}

impl<'a, Ev> Effects<'a, Ev> {
    /// Effects on behalf of `owner` (for tests and harnesses that drive actuators directly).
    pub fn new(owner: Owner, rngs: &'a mut RngStreams, sched: &'a mut dyn Schedule<Ev>) -> Self {
        Effects {
            owner,
            rngs,
            sched,
            fired: None,
        }
    }
    /// Effects of the environment handling the event `fired` (for harnesses that forward the
    /// environment's events themselves).
    pub fn handling(mut self, fired: EventId) -> Self {
        self.fired = Some(fired);
        self
    }
    /// The environment event being handled, if this runs in the environment's event handler
    /// (`None` for an actuator commanded by an agent).
    ///
    /// Handlers compare it with the id they scheduled, so a stale or forged event is ignored:
    /// a hop of a trip that was replaced, a second tick of a clock.
    pub fn fired(&self) -> Option<EventId> {
        self.fired
    }
    /// The current simulated time.
    pub fn now(&self) -> SimTime {
        self.sched.now()
    }
    /// On whose behalf this runs.
    pub fn owner(&self) -> Owner {
        self.owner
    }
    /// The owner's random stream for `purpose`.
    #[inline]
    pub fn rng(&mut self, purpose: &str) -> &mut ChaCha8Rng {
        self.rngs.stream(self.owner, purpose)
    }
    /// The owner's small random stream for `purpose` ([`RngStreams::small`]).
    #[inline]
    pub fn small_rng(&mut self, purpose: &str) -> &mut crate::rng::SplitMix64 {
        self.rngs.small(self.owner, purpose)
    }
    /// Schedules `event` for `target` after `delay`.
    pub fn schedule_in(&mut self, delay: SimDuration, target: Target, event: Ev) -> EventId {
        let at = self.now() + delay;
        self.sched
            .schedule_at(at, target, event)
            .expect("now + delay is never in the past")
    }
    /// Schedules `event` for `target` at `at`; fails if `at` is in the past.
    pub fn schedule_at(
        &mut self,
        at: SimTime,
        target: Target,
        event: Ev,
    ) -> Result<EventId, ScheduleError> {
        self.sched.schedule_at(at, target, event)
    }
    /// Cancels a pending event; false if it already fired or was cancelled.
    pub fn cancel(&mut self, id: EventId) -> bool {
        self.sched.cancel(id)
    }
}

/// Changes the environment `Env` on behalf of one entity, on command.
///
/// `Ev` is the model's event type, for actuators that act over time (they schedule events).
pub trait Actuator<Env, Ev> {
    /// The command it takes.
    type Command;
    /// Why a command can be refused.
    type Error;
    /// Carries out `cmd` for `me`.
    fn actuate(
        &self,
        env: &mut Env,
        me: EntityId,
        cmd: Self::Command,
        fx: &mut Effects<'_, Ev>,
    ) -> Result<(), Self::Error>;
}

impl<Env, Ev, A: Actuator<Env, Ev> + ?Sized> Actuator<Env, Ev> for &A {
    type Command = A::Command;
    type Error = A::Error;
    fn actuate(
        &self,
        env: &mut Env,
        me: EntityId,
        cmd: Self::Command,
        fx: &mut Effects<'_, Ev>,
    ) -> Result<(), Self::Error> {
        (**self).actuate(env, me, cmd, fx)
    }
}

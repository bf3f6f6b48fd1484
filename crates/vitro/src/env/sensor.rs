//! Sensors: the only way an agent reads the environment.

use crate::entity::EntityId;
use crate::rng::{Owner, RngStreams};
use crate::time::SimTime;
use rand_chacha::ChaCha8Rng;

/// What a sensor may use besides the environment: the time and its owner's random streams.
pub struct Probe<'a> {
    pub(crate) now: SimTime,
    pub(crate) owner: EntityId,
    pub(crate) rngs: &'a mut RngStreams,
}

impl<'a> Probe<'a> {
    /// A probe for `owner` at `now` (for tests and harnesses that drive sensors directly).
    pub fn new(now: SimTime, owner: EntityId, rngs: &'a mut RngStreams) -> Self {
        Probe { now, owner, rngs }
    }
    /// The current simulated time.
    pub fn now(&self) -> SimTime {
        self.now
    }
    /// The sensing entity.
    pub fn me(&self) -> EntityId {
        self.owner
    }
    /// The owner's random stream for `purpose` (e.g. measurement noise).
    #[inline]
    pub fn rng(&mut self, purpose: &str) -> &mut ChaCha8Rng {
        self.rngs.stream(Owner::Entity(self.owner), purpose)
    }
    /// The owner's small random stream for `purpose` ([`RngStreams::small`]).
    #[inline]
    pub fn small_rng(&mut self, purpose: &str) -> &mut crate::rng::SplitMix64 {
        self.rngs.small(Owner::Entity(self.owner), purpose)
    }
}

/// Reads part of the environment `Env` on behalf of one entity.
///
/// ```
/// use vitro::entity::EntityId;
/// use vitro::env::{EntityStorage, Probe, Sensor};
/// use vitro::rng::RngStreams;
/// use vitro::time::SimTime;
///
/// struct World { fuel: EntityStorage<f64> }
/// struct FuelGauge;
/// impl Sensor<World> for FuelGauge {
///     type Reading = Option<f64>;
///     fn read(&self, w: &World, me: EntityId, _: &mut Probe) -> Option<f64> {
///         w.fuel.get(me).copied()
///     }
/// }
/// let mut w = World { fuel: EntityStorage::default() };
/// w.fuel.insert(EntityId(0), 40.0);
/// let mut rngs = RngStreams::new(0);
/// let mut probe = Probe::new(SimTime::ZERO, EntityId(0), &mut rngs);
/// assert_eq!(FuelGauge.read(&w, EntityId(0), &mut probe), Some(40.0));
/// ```
pub trait Sensor<Env> {
    /// What the sensor reports.
    type Reading;
    /// Takes one reading for `me`.
    fn read(&self, env: &Env, me: EntityId, probe: &mut Probe<'_>) -> Self::Reading;
}

impl<Env, S: Sensor<Env> + ?Sized> Sensor<Env> for &S {
    type Reading = S::Reading;
    fn read(&self, env: &Env, me: EntityId, probe: &mut Probe<'_>) -> Self::Reading {
        (**self).read(env, me, probe)
    }
}

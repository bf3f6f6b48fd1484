//! # Vitro: in vitro multi-agent simulation
//!
//! The toolkit core: simulated [`time`], the [`event`] queue, [`entity`] identities and the
//! capability register, the [environment](mod@env) (storages read by sensors and written by
//! actuators), simulated [`comm`]unication, deterministic [`rng`] streams and [`trace`]
//! hashes, and the [`sim`]ulation driver that ties them together. Interaction [`protocol`]s
//! (request/inform, query, subscribe/notify, contract net, token ring) sit on top.
//!
//! Layers, lowest first (a module only imports those below it):
//! `time`, `trace`, `hint` → `entity`, `rng` → `event` → `env`, `comm` → `sim` → `protocol`.
//!
//! ## The loop: sensor → controller → actuator → storage → sensor
//!
//! ```
//! use vitro::prelude::*;
//!
//! // The world: one storage of positions on a line.
//! #[derive(Default)]
//! struct World { pos: EntityStorage<i64> }
//!
//! // A sensor reads the storage...
//! struct Odometer;
//! impl Sensor<World> for Odometer {
//!     type Reading = i64;
//!     fn read(&self, w: &World, me: EntityId, _: &mut Probe) -> i64 {
//!         w.pos.get(me).copied().unwrap_or(0)
//!     }
//! }
//! // ...an actuator writes it.
//! struct Wheel;
//! impl Actuator<World, Tick> for Wheel {
//!     type Command = i64;
//!     type Error = std::convert::Infallible;
//!     fn actuate(&self, w: &mut World, me: EntityId, step: i64, _: &mut Effects<Tick>)
//!         -> Result<(), Self::Error> {
//!         w.pos.update(me, |p| *p += step);
//!         Ok(())
//!     }
//! }
//!
//! #[derive(serde::Serialize)]
//! struct Tick;
//! struct Walk;
//! impl Model for Walk { type Env = World; type Event = Tick; type Msg = (); type Agent = GoTo; }
//!
//! // The controller sees only its context: it senses, decides, acts, and waits.
//! struct GoTo { goal: i64 }
//! impl Agent<Walk> for GoTo {
//!     fn handle(&mut self, _: Input<'_, Walk>, cx: &mut Context<'_, Walk>) {
//!         let here = cx.sense(&Odometer);
//!         if here != self.goal {
//!             cx.act(&Wheel, (self.goal - here).signum()).unwrap();
//!             cx.schedule_in(SimDuration::from_secs(1), Tick);
//!         }
//!     }
//! }
//!
//! let mut sim = Simulation::<Walk>::new(World::default(), 1);
//! let walker = sim.add_agent("walker", GoTo { goal: 5 }).unwrap();
//! sim.env_mut().pos.insert(walker, 0);
//! sim.schedule(SimTime::ZERO, Target::Entity(walker), Tick).unwrap();
//! sim.run_until(SimTime::MAX);
//! assert_eq!(sim.env().pos.get(walker), Some(&5));
//! assert_eq!(sim.now(), SimTime::from_secs(5));
//! ```

pub mod comm;
pub mod entity;
pub mod env;
pub mod event;
pub mod hint;
pub mod protocol;
pub mod rng;
pub mod sim;
pub mod time;
pub mod trace;

/// The names most models need.
pub mod prelude {
    pub use crate::comm::{
        Address, Envelope, GroupId, LinkParams, Outgoing, Performative, Protocol,
    };
    pub use crate::entity::EntityId;
    pub use crate::env::{
        Actuator, Effects, EntityStorage, GraphStorage, KeyValueStorage, NodeId, Probe, Sensor,
    };
    pub use crate::event::{EventId, OwnEventId, Target};
    pub use crate::sim::{
        Agent, AgentHandle, Context, CostModel, Holds, Input, Model, RoundId, Simulation,
        StopReason,
    };
    pub use crate::time::{SimDuration, SimTime};
}

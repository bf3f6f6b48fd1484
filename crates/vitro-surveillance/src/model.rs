//! The mission's model: the tactical [`Arena`] as environment, its events [`Ev`], the
//! mission's own radio vocabulary [`Net`], and agents that are any [`Unit`].
//!
//! The arena's events (discrete hops and maneuvers, the fixed-step clocks of the continuous
//! levels) are run by `vitro_tactical::model::run_env_event`, so every entity moves as it
//! does in any other tactical mission; only the messages differ.

use crate::net::Net;
use vitro::entity::EntityId;
use vitro::env::Effects;
use vitro::sim::{Agent, Context, Input, Model};
use vitro::time::SimTime;
use vitro_tactical::arena::{Arena, Ev};
use vitro_tactical::model::{AsAny, Intention, run_env_event};

/// The surveillance model over the [`Arena`].
pub struct Field;

/// An agent of the surveillance model: it senses, acts and talks through its context only.
pub trait Unit: AsAny {
    /// Reacts to one input.
    fn handle(&mut self, input: Input<'_, Field>, cx: &mut Context<'_, Field>);
    /// What the agent says it is doing, for viewers and recordings (never read by the
    /// simulation itself).
    fn intention(&self) -> Option<Intention> {
        None
    }
}

impl Agent<Field> for Box<dyn Unit> {
    fn handle(&mut self, input: Input<'_, Field>, cx: &mut Context<'_, Field>) {
        (**self).handle(input, cx);
    }
}

impl Model for Field {
    type Env = Arena;
    type Event = Ev;
    type Msg = Net;
    type Agent = Box<dyn Unit>;

    fn on_env_event(env: &mut Arena, event: &Ev, fx: &mut Effects<'_, Ev>) {
        run_env_event(env, event, fx);
    }

    /// Where a radio is: its entity's body.
    fn locate(env: &Arena, who: EntityId, _: SimTime) -> Option<[f64; 3]> {
        env.pose(who).map(|p| p.pos)
    }

    fn state_digest(env: &Arena) -> u64 {
        env.digest()
    }
}

//! The evacuation's radio: what its agents say to each other through the simulated network
//! (`vitro::comm`), and the [`Evac`] model that carries it.
//!
//! One vocabulary for every agent of the mission, so that messages are plain data
//! (serialised into the trace hash) and any agent can read any report. It carries the
//! shared words of [`vitro_tactical::radio`] (fixes, contacts, commands, signals), so the
//! stock behaviours (formations, tracking, routes) run in the mission unchanged, and adds
//! its own: plans, pursuit orders and the contract net's tenders.
//!
//! ```
//! use vitro_evac::radio::Radio;
//! use vitro_tactical::radio::{Command, Message, Signal};
//!
//! let order = Radio::from(Command::GoTo([10.0, 20.0]));
//! assert_eq!(order.read::<Command>(), Some(Command::GoTo([10.0, 20.0])));
//! assert_eq!(Radio::Plan(vec![]).read::<Signal>(), None);
//! ```

use serde::{Deserialize, Serialize};
use vitro::entity::EntityId;
use vitro_tactical::model::Tactical;
use vitro_tactical::radio::{Carries, Command, Contact, Fix, Signal};
use vitro_tactical::world::Side;

/// The evacuation's model: the tactical arena, its messages [`Radio`].
pub type Evac = Tactical<Radio>;

/// A message of the evacuation.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub enum Radio {
    /// "I see `target` at `pos`, and I take it for `seen_as`."
    Contact {
        /// Who was seen.
        target: EntityId,
        /// Where, world metres.
        pos: [f64; 3],
        /// The side the observer believes it is on.
        seen_as: Side,
    },
    /// The sender's own fix (blue-force tracking: its GPS position, heading and speed, and
    /// when it was taken).
    Position(Fix),
    /// An order to the receiver: what to do next.
    Order(Order),
    /// The sender's plan, step by step (e.g. the actions of a repaired plan).
    Plan(Vec<String>),
    /// A named signal with a short argument (e.g. `("formation", "wedge")`).
    Signal(String, String),
    /// Task allocation by contract net ([`vitro::protocol::contract_net`]): a call for
    /// proposals for `task` at `at` (no `cost`), or a proposal for it bidding `cost`
    /// (lower wins).
    Tender {
        /// What is allocated (e.g. `"hunt"`, a pursuer slot of the HVT hunt).
        task: String,
        /// Where the task is, world (x, y), as far as the caller knows.
        at: [f64; 2],
        /// The bid, in a proposal.
        cost: Option<f64>,
    },
}

impl vitro::protocol::Bid for Radio {
    /// The cost a [`Radio::Tender`] proposal bids; no other message bids.
    fn bid(&self) -> Option<f64> {
        match self {
            Radio::Tender { cost, .. } => *cost,
            _ => None,
        }
    }
}

/// What an [`Radio::Order`] tells the receiver to do.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub enum Order {
    /// Go to a world point (x, y).
    GoTo([f64; 2]),
    /// Follow an entity, keeping near it.
    Follow(EntityId),
    /// Pursue `target` (a high-value target) together with `team` (the pursuers, the first
    /// of them leading).
    Pursue {
        /// Who to catch.
        target: EntityId,
        /// The pursuers; the first coordinates the others.
        team: Vec<EntityId>,
    },
    /// Stop and hold position.
    Hold,
}

impl From<Fix> for Radio {
    fn from(fix: Fix) -> Radio {
        Radio::Position(fix)
    }
}

impl Carries<Fix> for Radio {
    fn carried(&self) -> Option<Fix> {
        match self {
            Radio::Position(fix) => Some(*fix),
            _ => None,
        }
    }
}

impl From<Contact> for Radio {
    fn from(c: Contact) -> Radio {
        Radio::Contact {
            target: c.target,
            pos: c.pos,
            seen_as: c.seen_as,
        }
    }
}

impl Carries<Contact> for Radio {
    fn carried(&self) -> Option<Contact> {
        match *self {
            Radio::Contact {
                target,
                pos,
                seen_as,
            } => Some(Contact {
                target,
                pos,
                seen_as,
            }),
            _ => None,
        }
    }
}

impl From<Command> for Radio {
    fn from(c: Command) -> Radio {
        Radio::Order(match c {
            Command::GoTo(p) => Order::GoTo(p),
            Command::Follow(id) => Order::Follow(id),
            Command::Hold => Order::Hold,
        })
    }
}

impl Carries<Command> for Radio {
    /// The shared command an order is ([`Order::Pursue`] is the mission's own: none).
    fn carried(&self) -> Option<Command> {
        match self {
            Radio::Order(Order::GoTo(p)) => Some(Command::GoTo(*p)),
            Radio::Order(Order::Follow(id)) => Some(Command::Follow(*id)),
            Radio::Order(Order::Hold) => Some(Command::Hold),
            _ => None,
        }
    }
}

impl From<Signal> for Radio {
    fn from(s: Signal) -> Radio {
        Radio::Signal(s.name, s.arg)
    }
}

impl Carries<Signal> for Radio {
    fn carried(&self) -> Option<Signal> {
        match self {
            Radio::Signal(name, arg) => Some(Signal::new(name.clone(), arg.clone())),
            _ => None,
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use vitro::time::SimTime;
    use vitro_tactical::radio::Message;

    /// Each shared word goes in and comes back out unchanged, and no other word is read
    /// out of it.
    #[test]
    fn shared_words_round_trip() {
        let fix = Fix {
            pos: [1.0, 2.0, 3.0],
            heading: 0.5,
            course: 0.25,
            speed: 4.0,
            at: SimTime::from_secs(9),
        };
        let contact = Contact {
            target: EntityId(4),
            pos: [5.0, 6.0, 7.0],
            seen_as: Side::Red,
        };
        let command = Command::Follow(EntityId(8));
        let signal = Signal::new("formation", "wedge 2 5 -");
        let m = Radio::from(fix);
        assert_eq!(m.read::<Fix>(), Some(fix));
        assert_eq!(m.read::<Contact>(), None);
        let m = Radio::from(contact);
        assert_eq!(m.read::<Contact>(), Some(contact));
        assert_eq!(m.read::<Fix>(), None);
        let m = Radio::from(command.clone());
        assert_eq!(m.read::<Command>(), Some(command));
        assert_eq!(m.read::<Signal>(), None);
        let m = Radio::from(signal.clone());
        assert_eq!(m.read::<Signal>(), Some(signal));
        assert_eq!(m.read::<Command>(), None);
        let pursue = Radio::Order(Order::Pursue {
            target: EntityId(1),
            team: vec![EntityId(2)],
        });
        assert_eq!(pursue.read::<Command>(), None);
    }
}

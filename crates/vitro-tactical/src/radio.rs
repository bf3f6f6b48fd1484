//! The tactical radio: the words the shared behaviours say to each other through the
//! simulated network (`vitro::comm`), and how a mission's own messages carry them.
//!
//! The vocabulary is open: a mission chooses its message type `M` (the `Msg` of
//! [`Tactical<M>`](crate::model::Tactical)), and a shared behaviour asks of it only the
//! words it speaks, each a small type of this module: a position report ([`Fix`]), a
//! sighting ([`Contact`]), an order to move ([`Command`]) and a named signal ([`Signal`]).
//! `M: Carries<Fix>` says that `M` is made from a fix (`From`) and read back as one
//! ([`Message::read`]); a tracker asks for [`Reports`] (fixes and contacts), a formation
//! leader for [`SquadTalk`], the four words of its protocol. Messages stay plain data, serialised into the trace hash as the mission's own
//! type. [`Basic`] is a ready vocabulary holding the four words and nothing else, for
//! tests, examples and missions that need no words of their own.
//!
//! ```
//! use vitro_tactical::radio::{Basic, Carries, Command, Message, Signal};
//!
//! // A mission's own vocabulary: its words, and the shared ones it carries.
//! #[derive(Clone, Debug, PartialEq, serde::Serialize, serde::Deserialize)]
//! enum Net { Alarm(u32), Move(Command) }
//! impl From<Command> for Net {
//!     fn from(c: Command) -> Net { Net::Move(c) }
//! }
//! impl Carries<Command> for Net {
//!     fn carried(&self) -> Option<Command> {
//!         match self { Net::Move(c) => Some(c.clone()), _ => None }
//!     }
//! }
//! let order = Net::from(Command::GoTo([10.0, 20.0]));
//! assert_eq!(order.read::<Command>(), Some(Command::GoTo([10.0, 20.0])));
//! assert_eq!(Net::Alarm(3).read::<Command>(), None);
//! // The stock vocabulary carries all four words.
//! let arrived = Basic::from(Signal::new("arrived", ""));
//! assert_eq!(arrived.read::<Signal>().map(|s| s.name), Some("arrived".to_string()));
//! ```

use crate::entity::{Level, Pose};
use crate::world::Side;
use serde::{Deserialize, Serialize};
use vitro::entity::EntityId;
use vitro::time::{SimDuration, SimTime};

/// A message type of a tactical model: plain data (cloned into the network, serialised
/// into the trace hash). Every such type has it; [`read`](Message::read) takes a shared
/// word back out of one.
pub trait Message: Clone + Serialize + 'static {
    /// The `T` this message carries, if it is one (e.g. `env.body.read::<Fix>()`).
    fn read<T>(&self) -> Option<T>
    where
        Self: Carries<T>,
    {
        self.carried()
    }
}

impl<M: Clone + Serialize + 'static> Message for M {}

/// A message type that carries the shared word `T`: made from one (`From<T>`), and read
/// back as one (the same `T`, for a message made from it).
pub trait Carries<T>: From<T> {
    /// The `T` this message carries, if it is one.
    fn carried(&self) -> Option<T>;
}

/// The words of tracking (see `vitro_behaviour::belief`): position reports and contacts.
/// Every message type carrying the two has it.
pub trait Reports: Message + Carries<Fix> + Carries<Contact> {}

impl<M: Message + Carries<Fix> + Carries<Contact>> Reports for M {}

/// The words of a formation squad's protocol (see
/// `vitro_behaviour::formation`): position reports, contacts,
/// orders to move and named signals. Every message type carrying the four has it.
pub trait SquadTalk: Reports + Carries<Command> + Carries<Signal> {}

impl<M: Reports + Carries<Command> + Carries<Signal>> SquadTalk for M {}

/// "I see `target` at `pos`, and I take it for `seen_as`."
#[derive(Copy, Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct Contact {
    /// Who was seen.
    pub target: EntityId,
    /// Where, world metres.
    pub pos: [f64; 3],
    /// The side the observer believes it is on.
    pub seen_as: Side,
}

/// An order to the receiver to move: where to go next, or to stop.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub enum Command {
    /// Go to a world point (x, y).
    GoTo([f64; 2]),
    /// Follow an entity, keeping near it.
    Follow(EntityId),
    /// Stop and hold position.
    Hold,
}

/// A named signal with a short argument (e.g. `formation` with `wedge 2 5 -`): the
/// formations' protocol words and the signals their rule programs raise.
#[derive(Clone, Debug, PartialEq, Eq, Serialize, Deserialize)]
pub struct Signal {
    /// Its name, e.g. `"formation"`.
    pub name: String,
    /// Its argument, e.g. `"wedge 2 5 -"` (may be empty).
    pub arg: String,
}

impl Signal {
    /// The signal `name` with argument `arg`.
    pub fn new(name: impl Into<String>, arg: impl Into<String>) -> Signal {
        Signal {
            name: name.into(),
            arg: arg.into(),
        }
    }

    /// Whether it is named `name`.
    pub fn is(&self, name: &str) -> bool {
        self.name == name
    }
}

/// The stock vocabulary: the shared words and nothing else.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub enum Basic {
    /// A sighting.
    Contact(Contact),
    /// The sender's own fix (blue-force tracking).
    Position(Fix),
    /// An order to move.
    Order(Command),
    /// A named signal.
    Signal(Signal),
}

macro_rules! basic_carries {
    ($($word:ident => $variant:ident),*) => {$(
        impl From<$word> for Basic {
            fn from(w: $word) -> Basic {
                Basic::$variant(w)
            }
        }
        impl Carries<$word> for Basic {
            fn carried(&self) -> Option<$word> {
                match self {
                    Basic::$variant(w) => Some(w.clone()),
                    _ => None,
                }
            }
        }
    )*};
}

basic_carries!(Contact => Contact, Fix => Position, Command => Order, Signal => Signal);

/// One fix of an entity: where it was, which way it faced and moved, and when.
#[derive(Copy, Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct Fix {
    /// Position, world metres.
    pub pos: [f64; 3],
    /// Heading (where it faces), radians counter-clockwise from east (0 if unknown).
    pub heading: f64,
    /// Course over the ground (where it moves), radians counter-clockwise from east.
    pub course: f64,
    /// Speed over the ground along the course, m/s (0 if unknown).
    pub speed: f64,
    /// When it was taken.
    pub at: SimTime,
}

impl Fix {
    /// The fix of a pose taken at `at`, moving the way it faces (vehicles, aircraft).
    pub fn of(pose: &Pose, at: SimTime) -> Fix {
        Fix {
            pos: pose.pos,
            heading: pose.heading,
            course: pose.heading,
            speed: pose.speed,
            at,
        }
    }

    /// The fix a GPS gives of `pose` at `at` after its fix `prev`: a trooper at the
    /// directed level may walk one way and face another, so its course and speed are those
    /// over the ground since `prev` (if that is at most 10 s old); anything else moves the
    /// way it faces ([`Fix::of`]).
    pub fn after(pose: &Pose, at: SimTime, prev: Option<&Fix>) -> Fix {
        let mut fix = Fix::of(pose, at);
        if pose.level == Level::Directed
            && let Some(p) = prev
        {
            let dt = at.saturating_since(p.at).as_secs_f64();
            if dt > 0.0 && dt <= 10.0 {
                let (dx, dy) = (pose.pos[0] - p.pos[0], pose.pos[1] - p.pos[1]);
                fix.course = libm::atan2(dy, dx);
                fix.speed = libm::hypot(dx, dy) / dt;
            }
        }
        fix
    }

    /// How old the fix is at `now`.
    pub fn age(&self, now: SimTime) -> SimDuration {
        now.saturating_since(self.at)
    }

    /// Where the entity is at `now` if it kept its course and speed since the fix (dead
    /// reckoning; the height is kept).
    pub fn predicted(&self, now: SimTime) -> [f64; 3] {
        let d = self.speed * self.age(now).as_secs_f64();
        [
            self.pos[0] + d * libm::cos(self.course),
            self.pos[1] + d * libm::sin(self.course),
            self.pos[2],
        ]
    }

    /// The fix as a pose at `now`: the dead-reckoned position, the reported heading and
    /// speed, at `level`.
    pub fn pose(&self, now: SimTime, level: Level) -> Pose {
        Pose {
            pos: self.predicted(now),
            heading: self.heading,
            speed: self.speed,
            level,
        }
    }
}

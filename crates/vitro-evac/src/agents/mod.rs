//! The mission's agents. Each acts only through its `Context`: the sensors of
//! [`sense`](super::sense), the actuators of [`act`](super::act) and the radio.

pub mod air;
pub mod commander;
pub mod cover;
pub mod hunt;
pub mod overwatch;
pub mod patrol;
pub mod red;
pub mod squad;
pub mod tender;
pub mod trooper;
pub mod ugv;

use super::brief::{BLUE, Brief};
use crate::radio::{Evac, Radio};
use serde::{Deserialize, Serialize};
use vitro::comm::{Address, Outgoing};
use vitro::entity::{EntityId, EntityMap};
use vitro::sim::Context;
use vitro::time::{SimDuration, SimTime};
use vitro_behaviour::belief::{Beacon, Whereabouts};
use vitro_tactical::sensor::Sighting;
use vitro_tactical::world::Side;

/// Timer key of the periodic sensing.
pub(crate) const SENSE: u64 = 1;

/// A contact is reported again only after this long.
const REPORT_AGAIN: SimDuration = SimDuration::from_secs(30);

/// Reports hostile sightings to the blue group, each target at most once per 30 s.
#[derive(Clone, Debug, Default, Serialize, Deserialize)]
pub struct Reporter {
    last: EntityMap<SimTime>,
    /// Contact reports sent.
    pub sent: u32,
}

impl Reporter {
    /// Sends a [`Radio::Contact`] for every sighting taken for hostile not reported lately.
    pub fn report(&mut self, sightings: &[Sighting], cx: &mut Context<'_, Evac>) {
        let now = cx.now();
        for s in sightings.iter().filter(|s| s.seen_as == Side::Red) {
            let fresh = self
                .last
                .get(s.id)
                .is_none_or(|&t| now.saturating_since(t) >= REPORT_AGAIN);
            if fresh {
                self.last.insert(s.id, now);
                self.sent += 1;
                cx.send(Outgoing::new(
                    Address::Group(BLUE),
                    Radio::Contact {
                        target: s.id,
                        pos: s.pos,
                        seen_as: s.seen_as,
                    },
                ));
            }
        }
    }
}

/// Sends `body` to one agent.
pub(crate) fn tell(cx: &mut Context<'_, Evac>, to: EntityId, body: Radio) {
    cx.send(Outgoing::new(Address::Agent(to), body));
}

/// The blue-force beacon of a unit of `brief`: its own GPS fix to the blue group every
/// `sensors.report_period_s`.
pub(crate) fn beacon(brief: &Brief) -> Beacon {
    let period = SimDuration::from_secs_f64(brief.sensors.report_period_s);
    Beacon::new(period, Address::Group(BLUE))
}

/// What a unit of `brief` knows of where the others are: nothing yet; fixes go stale after
/// `sensors.stale_s`.
pub(crate) fn whereabouts(brief: &Brief) -> Whereabouts {
    Whereabouts::new(SimDuration::from_secs_f64(brief.sensors.stale_s))
}

/// Takes the friends an own look identified as blue into `known` (the look's own fixes).
pub(crate) fn note_friends(known: &mut Whereabouts, seen: &[Sighting], now: SimTime) {
    for s in seen.iter().filter(|s| s.seen_as == Side::Blue) {
        known.saw(s, now);
    }
}

/// Where `id` is as far as `known` goes at `now`: its fresh fix dead-reckoned, else the
/// place it was last reported at (an agent goes there and looks), else nothing.
pub(crate) fn last_known(known: &Whereabouts, id: EntityId, now: SimTime) -> Option<[f64; 3]> {
    known
        .estimate(id, now)
        .or_else(|| known.last(id).map(|f| f.pos))
}

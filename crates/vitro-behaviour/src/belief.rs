//! What an agent believes about where the others are: the last fix it got of each, from its
//! own camera or from a position report over the radio, with its age.
//!
//! No agent reads another entity's state from the world. It learns where a friend is from
//! that friend's own position reports ([`Fix`], blue-force tracking: every unit
//! sends its GPS fix every few seconds, see [`Beacon`]), which the simulated radio delays,
//! loses or bounces out of range; and where anyone is from its own camera
//! ([`Sighting`], see [`Whereabouts::saw`]) or a friend's contact
//! report ([`Contact`]). [`Whereabouts`] keeps
//! the newest fix of each entity and dead-reckons it forward ([`Fix::predicted`]) for at
//! most [`Whereabouts::stale_after`]; older than that, the agent does not know where that
//! entity is, and must hold, search, or go to the last place it was reported at.
//!
//! ```
//! use vitro::entity::{EntityId, EntityMap};
//! use vitro::time::{SimDuration, SimTime};
//! use vitro_behaviour::belief::{Fix, Whereabouts};
//!
//! let truck = EntityId(3);
//! let mut known = Whereabouts::new(SimDuration::from_secs(30));
//! let t = SimTime::from_secs;
//! // Nothing heard yet: the truck is nowhere as far as this agent knows.
//! assert!(known.estimate(truck, t(0)).is_none());
//! // A report: at the origin at t = 10 s, heading east (0 rad) at 5 m/s.
//! known.note(truck, Fix { pos: [0.0, 0.0, 0.0], heading: 0.0, course: 0.0, speed: 5.0, at: t(10) });
//! // Two seconds later it is believed 10 m east (dead reckoning)...
//! assert_eq!(known.estimate(truck, t(12)).unwrap()[0], 10.0);
//! // ...an older report changes nothing...
//! known.note(truck, Fix { pos: [99.0, 0.0, 0.0], heading: 0.0, course: 0.0, speed: 0.0, at: t(5) });
//! assert_eq!(known.estimate(truck, t(12)).unwrap()[0], 10.0);
//! // ...and 30 s after the last report the agent no longer claims to know.
//! assert!(known.estimate(truck, t(41)).is_none());
//! assert_eq!(known.last(truck).unwrap().pos, [0.0, 0.0, 0.0]); // where it was last reported
//! ```

use serde::{Deserialize, Serialize};
use vitro::comm::{Address, Envelope, Outgoing};
use vitro::entity::{EntityId, EntityMap};
use vitro::sim::Context;
use vitro::time::{SimDuration, SimTime};
use vitro_tactical::arena::OwnPose;
use vitro_tactical::model::Tactical;
pub use vitro_tactical::radio::Fix;
use vitro_tactical::radio::{Carries, Contact, Message, Reports};
use vitro_tactical::sensor::Sighting;

/// Where each other entity was last known to be, from reports and own sightings.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct Whereabouts {
    fixes: EntityMap<Fix>,
    /// A fix older than this is not used for an estimate.
    pub stale_after: SimDuration,
    /// Position reports heard.
    pub reports: u64,
}

impl Default for Whereabouts {
    /// Fixes older than a minute are stale.
    fn default() -> Self {
        Whereabouts::new(SimDuration::from_secs(60))
    }
}

impl Whereabouts {
    /// Nothing known yet; fixes go stale after `stale_after`.
    pub fn new(stale_after: SimDuration) -> Self {
        Whereabouts {
            fixes: EntityMap::new(),
            stale_after,
            reports: 0,
        }
    }

    /// Keeps `fix` of `id` if it is newer than the one held.
    pub fn note(&mut self, id: EntityId, fix: Fix) {
        match self.fixes.get(id) {
            Some(old) if old.at > fix.at => {}
            _ => {
                self.fixes.insert(id, fix);
            }
        }
    }

    /// Takes in a received message: a position report updates its sender's fix, a contact
    /// report the fix of the entity it names (where it was seen, when the report was sent).
    /// True if it was either.
    pub fn hear<M: Reports>(&mut self, env: &Envelope<M>) -> bool {
        if let Some(fix) = env.body.read::<Fix>() {
            self.reports += 1;
            self.note(env.from, fix);
            true
        } else if let Some(Contact { target, pos, .. }) = env.body.read::<Contact>() {
            let fix = Fix {
                pos,
                heading: 0.0,
                course: 0.0,
                speed: 0.0,
                at: env.sent_at,
            };
            self.note(target, fix);
            true
        } else {
            false
        }
    }

    /// Takes in an own camera's sighting at `now` (position only: heading and speed are
    /// estimated from the previous fix when there is one, a few seconds old at most).
    pub fn saw(&mut self, s: &Sighting, now: SimTime) {
        let (mut course, mut speed) = (0.0, 0.0);
        if let Some(old) = self.fixes.get(s.id) {
            let dt = now.saturating_since(old.at).as_secs_f64();
            if dt > 0.0 && dt <= 10.0 {
                let (dx, dy) = (s.pos[0] - old.pos[0], s.pos[1] - old.pos[1]);
                course = libm::atan2(dy, dx);
                speed = libm::hypot(dx, dy) / dt;
            }
        }
        self.note(
            s.id,
            Fix {
                pos: s.pos,
                heading: course,
                course,
                speed,
                at: now,
            },
        );
    }

    /// The newest fix of `id`, however old.
    pub fn last(&self, id: EntityId) -> Option<&Fix> {
        self.fixes.get(id)
    }

    /// The newest fix of `id` if it is not stale at `now`.
    pub fn fresh(&self, id: EntityId, now: SimTime) -> Option<&Fix> {
        self.fixes
            .get(id)
            .filter(|f| f.age(now) <= self.stale_after)
    }

    /// Where `id` is believed to be at `now`: its fresh fix, dead-reckoned; `None` if none
    /// is fresh.
    pub fn estimate(&self, id: EntityId, now: SimTime) -> Option<[f64; 3]> {
        self.fresh(id, now).map(|f| f.predicted(now))
    }

    /// Forgets `id` (e.g. reported down).
    pub fn forget(&mut self, id: EntityId) {
        self.fixes.remove(id);
    }
}

/// Blue-force tracking: sends the owner's own GPS fix ([`OwnPose`]) as a
/// position report ([`Fix`]) every `period`.
///
/// The owner's controller starts it once ([`Beacon::start`]) and passes the timer back
/// ([`Beacon::is_timer`], [`Beacon::tick`]).
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct Beacon {
    /// Time between two reports.
    pub period: SimDuration,
    /// Where the reports go.
    pub to: Address,
    /// Reports sent.
    pub sent: u64,
    /// The last fix sent.
    pub last: Option<Fix>,
}

impl Beacon {
    /// The timer key a beacon uses (controllers must not use it for anything else).
    pub const TIMER: u64 = 0xB1F0_0000_0000_0001;

    /// A beacon reporting to `to` every `period`.
    pub fn new(period: SimDuration, to: Address) -> Self {
        Beacon {
            period,
            to,
            sent: 0,
            last: None,
        }
    }

    /// Sends the first report now and sets the timer for the next.
    pub fn start<M: Message + Carries<Fix>>(&mut self, cx: &mut Context<'_, Tactical<M>>) {
        self.tick(cx);
    }

    /// Whether a timer key is the beacon's.
    pub fn is_timer(key: u64) -> bool {
        key == Self::TIMER
    }

    /// Sends the owner's fix, if it has a body, and sets the timer for the next report (a
    /// zero period sends nothing: no blue-force tracking).
    pub fn tick<M: Message + Carries<Fix>>(&mut self, cx: &mut Context<'_, Tactical<M>>) {
        if self.period == SimDuration::ZERO {
            return;
        }
        if let Some(pose) = cx.sense(&OwnPose) {
            let fix = Fix::after(&pose, cx.now(), self.last.as_ref());
            cx.send(Outgoing::new(self.to, M::from(fix)));
            self.last = Some(fix);
            self.sent += 1;
        }
        cx.set_timer(self.period, Self::TIMER);
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn fix(x: f64, at: u64) -> Fix {
        Fix {
            pos: [x, 0.0, 0.0],
            heading: 0.0,
            course: 0.0,
            speed: 0.0,
            at: SimTime::from_secs(at),
        }
    }

    #[test]
    fn the_newest_fix_wins_whatever_the_order_reports_arrive_in() {
        let mut w = Whereabouts::default();
        let id = EntityId(1);
        w.note(id, fix(2.0, 20));
        w.note(id, fix(1.0, 10));
        assert_eq!(w.last(id).unwrap().pos[0], 2.0);
        w.note(id, fix(3.0, 30));
        assert_eq!(w.last(id).unwrap().pos[0], 3.0);
    }

    #[test]
    fn own_sightings_estimate_heading_and_speed() {
        let mut w = Whereabouts::default();
        let id = EntityId(4);
        let s = |x: f64, y: f64| Sighting {
            id,
            pos: [x, y, 0.0],
            distance: 50.0,
            bearing: 0.0,
            seen_as: vitro_tactical::world::Side::Blue,
        };
        w.saw(&s(0.0, 0.0), SimTime::from_secs(1));
        w.saw(&s(0.0, 8.0), SimTime::from_secs(3));
        let f = w.last(id).unwrap();
        assert_eq!(f.speed, 4.0);
        assert!((f.course - std::f64::consts::FRAC_PI_2).abs() < 1e-12);
        let ahead = w.estimate(id, SimTime::from_secs(5)).unwrap();
        assert!((ahead[1] - 16.0).abs() < 1e-9 && ahead[0].abs() < 1e-9);
    }

    #[test]
    fn a_stale_fix_gives_no_estimate_but_is_still_the_last_known_place() {
        let mut w = Whereabouts::new(SimDuration::from_secs(10));
        let id = EntityId(2);
        w.note(id, fix(7.0, 0));
        assert!(w.estimate(id, SimTime::from_secs(10)).is_some());
        assert!(w.estimate(id, SimTime::from_secs(11)).is_none());
        assert_eq!(w.last(id).unwrap().pos[0], 7.0);
        w.forget(id);
        assert!(w.last(id).is_none());
    }
}

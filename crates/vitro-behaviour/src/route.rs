//! Route following: controllers written against the top actuators only, so each runs unchanged at
//! every level of fidelity (the pattern of `vitro`'s `examples/layered.rs`).
//!
//! - [`VisitNodes`]: visits a list of nodes in order (once or in a loop) through any actuator
//!   whose command is a goal node: `GoToNode` for vehicles, `WalkToNode` for troopers.
//! - [`FlightMission`]: flies a list of [`Leg`]s (waypoints, straight flight, loiter around a
//!   moving ground target, loops over it) through any autopilot: either aircraft type at
//!   either level.

use crate::belief::Whereabouts;
use serde::{Deserialize, Serialize};
use vitro::entity::EntityId;
use vitro::env::{Actuator, NodeId};
use vitro::sim::{Context, Input};
use vitro::time::{SimDuration, SimTime};
use vitro_tactical::actuate::MoveError;
use vitro_tactical::arena::{Arena, Ev, OwnPose};
use vitro_tactical::autopilot::FlyError;
use vitro_tactical::entity::air::FlightCommand;
use vitro_tactical::model::{Controller, Tactical};
use vitro_tactical::radio::{Message, Reports};
use vitro_tactical::sensor::FriendFoeVision;
use vitro_tactical::sensor::track::Look;

/// The default camera of a [`FlightMission`]: a gimballed electro-optical camera that looks
/// all round and follows a designated vehicle out to 1.5 km (p0 = 0.95, falling linearly
/// with distance; 10 % misidentification, which does not break a lock on a designated id).
pub const GIMBAL: FriendFoeVision = FriendFoeVision {
    range: 1500.0,
    half_fov: std::f64::consts::PI,
    p0: 0.95,
    k: 1.0,
    misidentification: 0.1,
};

/// Visits `route` node by node through the goal-node actuator `A`; logs each arrival.
#[derive(Clone, Debug, Serialize, Deserialize)]
pub struct VisitNodes<A> {
    /// The nodes to visit, in order.
    pub route: Vec<NodeId>,
    /// Start over after the last node.
    pub repeat: bool,
    /// The top actuator.
    pub goto: A,
    /// Index of the next node to visit.
    pub next: usize,
    /// Arrivals: time and node.
    pub log: Vec<(SimTime, NodeId)>,
    /// The last refusal from the actuator, if any (the controller then stops).
    pub error: Option<MoveError>,
}

impl<A> VisitNodes<A> {
    /// Visits `route` once through `goto`.
    pub fn new(route: Vec<NodeId>, goto: A) -> Self {
        VisitNodes {
            route,
            repeat: false,
            goto,
            next: 0,
            log: Vec::new(),
            error: None,
        }
    }
    /// True once the last node of a one-pass route was reached.
    pub fn finished(&self) -> bool {
        !self.repeat && !self.route.is_empty() && self.log.len() >= self.route.len()
    }
}

impl<M, A> Controller<Tactical<M>> for VisitNodes<A>
where
    M: Message,
    A: Actuator<Arena, Ev, Command = NodeId, Error = MoveError> + 'static,
{
    fn handle(&mut self, input: Input<'_, Tactical<M>>, cx: &mut Context<'_, Tactical<M>>) {
        match input {
            Input::Event(Ev::Start) => {}
            Input::Event(Ev::Arrived(n)) => self.log.push((cx.now(), *n)),
            // The body gave the trip up: the controller stops and says why.
            Input::Event(Ev::Stalled(n, why)) => {
                self.error = Some(MoveError::Stalled(cx.me(), *n, *why));
                return;
            }
            _ => return,
        }
        if self.route.is_empty() || (!self.repeat && self.next >= self.route.len()) {
            return;
        }
        let goal = self.route[self.next % self.route.len()];
        self.next += 1;
        if let Err(e) = cx.act(&self.goto, goal) {
            self.error = Some(e);
        }
    }
}

/// How often a loiter leg re-aims at its moving target.
const REAIM: SimDuration = SimDuration::from_secs(2);
/// Timer keys of re-aiming carry this bit (leg timers do not).
const REAIM_KEY: u64 = 1 << 32;

/// One leg of a flight mission.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub enum Leg {
    /// Fly through these world points in order.
    Waypoints(Vec<[f64; 3]>),
    /// Fly a course (radians from east) at an altitude (world metres) for `secs` seconds.
    Straight {
        /// Course, radians from east.
        heading: f64,
        /// Altitude, world metres.
        altitude: f64,
        /// Duration, seconds.
        secs: f64,
    },
    /// Circle a ground target, counter-clockwise, `radius` metres around it and `height`
    /// metres above it, for `secs` seconds; the circle follows the target as it moves (where
    /// the aircraft's own camera, [`FlightMission::camera`], or the target's position reports
    /// put it, dead-reckoned; the last place it was seen once that is stale), aiming 45°
    /// ahead around it at every waypoint and every two seconds. Until the target is first
    /// seen or reported, the aircraft keeps its course and looks again every two seconds.
    Loiter {
        /// The entity to circle.
        target: EntityId,
        /// Circle radius, metres.
        radius: f64,
        /// Height above the target, metres.
        height: f64,
        /// Duration, seconds.
        secs: f64,
    },
    /// Fly back and forth over a ground target along `axis` (radians from east), turning
    /// `half_length` metres beyond it on either side, `passes` times; each end is placed
    /// around where the target is believed to be (as for `Loiter`).
    Loop {
        /// The entity to fly over.
        target: EntityId,
        /// Distance from the target to each turn point, metres.
        half_length: f64,
        /// Direction of the passes, radians from east.
        axis: f64,
        /// Height above the target, metres.
        height: f64,
        /// Number of passes.
        passes: u32,
    },
}

/// Flies `legs` in order through the autopilot `P`; logs every waypoint reached.
#[derive(Clone, Debug, Serialize, Deserialize)]
pub struct FlightMission<P> {
    /// The legs.
    pub legs: Vec<Leg>,
    /// Airspeed to ask for; `None` for the type's cruise speed.
    pub speed: Option<f64>,
    /// The top actuator (an autopilot).
    pub pilot: P,
    /// Index of the leg being flown (`legs.len()` once all are done).
    pub leg: usize,
    /// Waypoints reached: time, leg, waypoint index within the leg's last command.
    pub log: Vec<(SimTime, usize, u32)>,
    /// When each leg ended.
    pub legs_done: Vec<SimTime>,
    /// The last refusal from the autopilot, if any.
    pub error: Option<FlyError>,
    /// The camera that finds and follows the targets of `Loiter` and `Loop` legs (looked
    /// through at every aim).
    pub camera: FriendFoeVision,
    /// Where it believes the targets are: its camera's fixes and the position and contact
    /// reports it hears.
    pub known: Whereabouts,
    ends_at: Option<SimTime>,
    passes: u32,
    /// True once the current leg has had its first aim.
    aimed: bool,
}

impl<P> FlightMission<P> {
    /// A mission of `legs` flown through `pilot` at cruise speed.
    pub fn new(legs: Vec<Leg>, pilot: P) -> Self {
        FlightMission {
            legs,
            speed: None,
            pilot,
            leg: 0,
            log: Vec::new(),
            legs_done: Vec::new(),
            error: None,
            camera: GIMBAL,
            known: Whereabouts::default(),
            ends_at: None,
            passes: 0,
            aimed: false,
        }
    }
    /// True once every leg is flown.
    pub fn finished(&self) -> bool {
        self.leg >= self.legs.len()
    }
}

impl<P> FlightMission<P>
where
    P: Actuator<Arena, Ev, Command = FlightCommand, Error = FlyError> + 'static,
{
    fn command<M: Message>(&mut self, cmd: FlightCommand, cx: &mut Context<'_, Tactical<M>>) {
        if let Err(e) = cx.act(&self.pilot, cmd) {
            self.error = Some(e);
        }
    }

    fn begin<M: Message>(&mut self, i: usize, cx: &mut Context<'_, Tactical<M>>) {
        if i > 0 && i <= self.legs.len() && self.legs_done.len() < i {
            self.legs_done.push(cx.now());
        }
        self.leg = i;
        self.passes = 0;
        self.ends_at = None;
        self.aimed = false;
        let Some(leg) = self.legs.get(i).cloned() else {
            return;
        };
        match leg {
            Leg::Waypoints(points) => self.command(
                FlightCommand::Waypoints {
                    points,
                    speed: self.speed,
                },
                cx,
            ),
            Leg::Straight {
                heading,
                altitude,
                secs,
            } => {
                self.command(
                    FlightCommand::Straight {
                        heading,
                        altitude,
                        speed: self.speed,
                    },
                    cx,
                );
                cx.set_timer(SimDuration::from_secs_f64(secs.max(0.0)), i as u64);
            }
            Leg::Loiter { secs, .. } => {
                self.ends_at = Some(cx.now() + SimDuration::from_secs_f64(secs.max(0.0)));
                self.aim(cx);
                cx.set_timer(REAIM, REAIM_KEY | i as u64);
            }
            Leg::Loop { .. } => {
                if !self.aim(cx) {
                    cx.set_timer(REAIM, REAIM_KEY | i as u64);
                }
            }
        }
    }

    /// Where the leg's target is believed to be now: one look of the camera first, then the
    /// fresh fix dead-reckoned, else the last place it was seen or reported at.
    fn locate<M: Message>(
        &mut self,
        target: EntityId,
        cx: &mut Context<'_, Tactical<M>>,
    ) -> Option<[f64; 3]> {
        let now = cx.now();
        for s in cx.sense(&Look(self.camera)) {
            if s.id == target {
                self.known.saw(&s, now);
            }
        }
        self.known
            .estimate(target, now)
            .or_else(|| self.known.last(target).map(|f| f.pos))
    }

    /// The next waypoints of a loiter or loop leg, from where the target is believed to be
    /// now: the next point and the one after it (so the autopilot carries its speed through
    /// the first; the leg aims again as soon as the first is reached). False if the target
    /// has not been seen or reported yet (nothing is commanded).
    fn aim<M: Message>(&mut self, cx: &mut Context<'_, Tactical<M>>) -> bool {
        let Some(leg) = self.legs.get(self.leg).cloned() else {
            return false;
        };
        let points = match leg {
            Leg::Loiter {
                target,
                radius,
                height,
                ..
            } => {
                let Some(me) = cx.sense(&OwnPose) else {
                    return false;
                };
                let Some(t) = self.locate(target, cx) else {
                    return false;
                };
                let a = libm::atan2(me.pos[1] - t[1], me.pos[0] - t[0]);
                let at = |k: f64| {
                    let b = a + k * std::f64::consts::FRAC_PI_4;
                    [
                        t[0] + radius * libm::cos(b),
                        t[1] + radius * libm::sin(b),
                        t[2] + height,
                    ]
                };
                vec![at(1.0), at(2.0)]
            }
            Leg::Loop {
                target,
                half_length,
                axis,
                height,
                ..
            } => {
                let Some(t) = self.locate(target, cx) else {
                    return false;
                };
                let side = if self.passes.is_multiple_of(2) {
                    1.0
                } else {
                    -1.0
                };
                let end = |s: f64| {
                    [
                        t[0] + s * half_length * libm::cos(axis),
                        t[1] + s * half_length * libm::sin(axis),
                        t[2] + height,
                    ]
                };
                vec![end(side), end(-side)]
            }
            _ => return false,
        };
        self.command(
            FlightCommand::Waypoints {
                points,
                speed: self.speed,
            },
            cx,
        );
        self.aimed = true;
        true
    }
}

impl<M, P> Controller<Tactical<M>> for FlightMission<P>
where
    M: Reports,
    P: Actuator<Arena, Ev, Command = FlightCommand, Error = FlyError> + 'static,
{
    fn handle(&mut self, input: Input<'_, Tactical<M>>, cx: &mut Context<'_, Tactical<M>>) {
        match input {
            Input::Event(Ev::Start) => self.begin(0, cx),
            Input::Message(env) => {
                self.known.hear(env);
            }
            Input::Event(Ev::Waypoint(k)) => {
                self.log.push((cx.now(), self.leg, *k));
                match self.legs.get(self.leg) {
                    Some(Leg::Waypoints(points)) if *k as usize + 1 >= points.len() => {
                        self.begin(self.leg + 1, cx);
                    }
                    Some(Leg::Loiter { .. }) => {
                        if self.ends_at.is_some_and(|t| cx.now() >= t) {
                            self.begin(self.leg + 1, cx);
                        } else {
                            self.aim(cx);
                        }
                    }
                    Some(Leg::Loop { passes, .. }) => {
                        self.passes += 1;
                        if self.passes >= *passes {
                            self.begin(self.leg + 1, cx);
                        } else {
                            self.aim(cx);
                        }
                    }
                    _ => {}
                }
            }
            Input::Timer(key) if key == REAIM_KEY | self.leg as u64 => {
                if self.ends_at.is_some_and(|t| cx.now() >= t) {
                    self.begin(self.leg + 1, cx);
                } else if matches!(self.legs.get(self.leg), Some(Leg::Loiter { .. })) {
                    self.aim(cx);
                    cx.set_timer(REAIM, key);
                } else if matches!(self.legs.get(self.leg), Some(Leg::Loop { .. }))
                    && !self.aimed
                    && !self.aim(cx)
                {
                    // The target not found yet: look again.
                    cx.set_timer(REAIM, key);
                }
            }
            Input::Timer(key) if key == self.leg as u64 => {
                if matches!(self.legs.get(self.leg), Some(Leg::Straight { .. })) {
                    self.begin(self.leg + 1, cx);
                }
            }
            _ => {}
        }
    }
}

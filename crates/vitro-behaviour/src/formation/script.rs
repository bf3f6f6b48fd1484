//! A scripted radio operator: sends given messages at given times and logs what it hears
//! (a stand-in commander for tests, examples and documentation).

use serde::{Deserialize, Serialize};
use vitro::comm::{Address, Outgoing};
use vitro::entity::EntityId;
use vitro::protocol::TimerTag;
use vitro::sim::{Context, Input};
use vitro::time::{SimDuration, SimTime};
use vitro_tactical::model::{Controller, Tactical};
use vitro_tactical::radio::{Basic, Carries, Message, Signal};

/// Timer tag of the script's sends ("SC").
const SEND: TimerTag = TimerTag(0x5343);

/// Sends each `(time, to, message)` of its plan at its time (times already past when the
/// script starts are sent at once), then one message of [`on_arrival`](Self::on_arrival)
/// each time it hears `Signal("arrived", _)` (a list of waypoints for a leader), and logs
/// every message it receives. It starts at its first input (e.g.
/// [`Ev::Start`](vitro_tactical::arena::Ev::Start)).
#[derive(Clone, Debug, Serialize, Deserialize)]
pub struct Script<M = Basic> {
    /// What to send: when, to whom, what.
    pub plan: Vec<(SimTime, EntityId, M)>,
    /// What to send next each time an `arrived` signal comes in, in order.
    pub on_arrival: Vec<(EntityId, M)>,
    /// What it heard: when, from whom, what.
    pub heard: Vec<(SimTime, EntityId, M)>,
    started: bool,
    arrivals: usize,
}

impl<M> Default for Script<M> {
    fn default() -> Self {
        Script {
            plan: Vec::new(),
            on_arrival: Vec::new(),
            heard: Vec::new(),
            started: false,
            arrivals: 0,
        }
    }
}

impl<M> Script<M> {
    /// A script sending `plan`.
    pub fn new(plan: Vec<(SimTime, EntityId, M)>) -> Self {
        Script {
            plan,
            ..Script::default()
        }
    }

    /// The same script, sending `orders` one by one as `arrived` signals come in.
    pub fn then_on_arrival(mut self, orders: Vec<(EntityId, M)>) -> Self {
        self.on_arrival = orders;
        self
    }
}

impl<M: PartialEq> Script<M> {
    /// Every time it heard `msg`.
    pub fn heard_all(&self, msg: &M) -> Vec<SimTime> {
        self.heard
            .iter()
            .filter(|(_, _, m)| m == msg)
            .map(|&(t, _, _)| t)
            .collect()
    }

    /// When it first heard `msg`, if it did.
    pub fn heard_at(&self, msg: &M) -> Option<SimTime> {
        self.heard
            .iter()
            .find(|(_, _, m)| m == msg)
            .map(|&(t, _, _)| t)
    }
}

impl<M: Message + Carries<Signal>> Controller<Tactical<M>> for Script<M> {
    fn handle(&mut self, input: Input<'_, Tactical<M>>, cx: &mut Context<'_, Tactical<M>>) {
        match input {
            Input::Timer(key) => {
                if let Some(i) = SEND.index(key)
                    && let Some((_, to, msg)) =
                        usize::try_from(i).ok().and_then(|i| self.plan.get(i))
                {
                    cx.send(Outgoing::new(Address::Agent(*to), msg.clone()));
                }
                return;
            }
            Input::Message(env) => {
                self.heard.push((cx.now(), env.from, env.body.clone()));
                if env.body.read::<Signal>().is_some_and(|s| s.is("arrived")) {
                    if let Some((to, msg)) = self.on_arrival.get(self.arrivals) {
                        cx.send(Outgoing::new(Address::Agent(*to), msg.clone()));
                    }
                    self.arrivals += 1;
                }
            }
            _ => {}
        }
        if !self.started {
            self.started = true;
            let now = cx.now();
            for (i, (t, _, _)) in self.plan.iter().enumerate() {
                let wait = if *t > now {
                    *t - now
                } else {
                    SimDuration::ZERO
                };
                cx.set_timer(wait, SEND.key(i as u64));
            }
        }
    }
}

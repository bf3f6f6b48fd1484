//! The traffic's controller: to a random junction, then another, for the whole run.

use rand::Rng;
use rand_chacha::ChaCha8Rng;
use std::sync::Arc;
use vitro::env::{Actuator, NodeId};
use vitro::sim::{Context, Input};
use vitro::time::SimTime;
use vitro_tactical::actuate::MoveError;
use vitro_tactical::arena::{Arena, Ev, StallReason};
use vitro_tactical::model::{Controller, Intention, Tactical};

/// Refusals in a row (no route to the drawn junction) after which a tour stops.
const MAX_REFUSALS: u32 = 8;

/// Tours random junctions of `nodes` through the goal-node actuator `A` (`Drive` or
/// `Walk` at the body's level); its own random stream draws each destination.
#[derive(Clone, Debug)]
pub struct Tour<A> {
    /// The junctions it may go to.
    nodes: Arc<Vec<NodeId>>,
    /// The top actuator.
    goto: A,
    /// Its own random stream.
    rng: ChaCha8Rng,
    /// The junction it is going to, and since when; none once the tour stopped.
    pub goal: Option<NodeId>,
    /// When the current trip began.
    pub since: SimTime,
    /// Trips completed: start, arrival.
    pub trips: Vec<(SimTime, SimTime)>,
    /// Trips given up: when, and why.
    pub stalls: Vec<(SimTime, StallReason)>,
    /// The actuator's last refusal, if the tour stopped on it.
    pub error: Option<MoveError>,
}

impl<A> Tour<A> {
    /// A tour of `nodes` through `goto`, drawing destinations from `rng`.
    pub fn new(nodes: Arc<Vec<NodeId>>, goto: A, rng: ChaCha8Rng) -> Self {
        Tour {
            nodes,
            goto,
            rng,
            goal: None,
            since: SimTime::ZERO,
            trips: Vec::new(),
            stalls: Vec::new(),
            error: None,
        }
    }
}

impl<A> Controller<Tactical> for Tour<A>
where
    A: Actuator<Arena, Ev, Command = NodeId, Error = MoveError> + 'static,
{
    fn handle(&mut self, input: Input<'_, Tactical>, cx: &mut Context<'_, Tactical>) {
        let here = match input {
            Input::Event(Ev::Start) => None,
            Input::Event(Ev::Arrived(n)) => {
                self.trips.push((self.since, cx.now()));
                Some(*n)
            }
            Input::Event(Ev::Stalled(_, why)) => {
                self.stalls.push((cx.now(), *why));
                None
            }
            _ => return,
        };
        self.goal = None;
        if self.nodes.len() < 2 {
            return;
        }
        for _ in 0..MAX_REFUSALS {
            let next = self.nodes[self.rng.random_range(0..self.nodes.len())];
            if Some(next) == here {
                continue;
            }
            match cx.act(&self.goto, next) {
                Ok(()) => {
                    self.goal = Some(next);
                    self.since = cx.now();
                    self.error = None;
                    return;
                }
                Err(e) => self.error = Some(e),
            }
        }
    }

    fn intention(&self) -> Option<Intention> {
        let goal = self.goal?;
        Some(Intention {
            text: format!("to junction {} (trip {})", goal.0, self.trips.len() + 1),
            ..Intention::default()
        })
    }
}

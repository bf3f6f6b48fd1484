//! Controllers: agents written against the top actuators only, so each runs unchanged at
//! every level of fidelity (the pattern of `vitro`'s `examples/layered.rs`).
//!
//! - [`VisitNodes`]: visits a list of nodes in order (once or in a loop) through any actuator
//!   whose command is a goal node: `GoToNode` for vehicles, `WalkToNode` for troopers.

use crate::actuate::MoveError;
use crate::arena::{Arena, Ev};
use crate::model::{Controller, Tactical};
use vitro::env::{Actuator, NodeId};
use vitro::sim::{Context, Input};
use vitro::time::SimTime;

/// Visits `route` node by node through the goal-node actuator `A`; logs each arrival.
#[derive(Clone, Debug)]
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

impl<A> Controller for VisitNodes<A>
where
    A: Actuator<Arena, Ev, Command = NodeId, Error = MoveError> + 'static,
{
    fn handle(&mut self, input: Input<'_, Tactical>, cx: &mut Context<'_, Tactical>) {
        match input {
            Input::Event(Ev::Start) => {}
            Input::Event(Ev::Arrived(n)) => self.log.push((cx.now(), *n)),
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

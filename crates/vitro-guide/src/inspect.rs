//! The inspection controller of the tutorial ([Part 1](crate::tutorial_1_graph) writes it),
//! kept here once so that the later parts use it as it is: `use vitro_guide::inspect::Inspect;`.
//! A test checks that this file holds the code the page shows, character for character.

use vitro::prelude::*;
use vitro_tactical::actuate::MoveError;
use vitro_tactical::arena::{Arena, Ev, OwnPose};
use vitro_tactical::model::{Controller, Tactical};

/// Inspects every checkpoint once, nearest first.
pub struct Inspect<A> {
    /// Briefed: the checkpoints not yet inspected, with where they are (world x, y).
    pub todo: Vec<(NodeId, [f64; 2])>,
    /// The top actuator: any actuator whose command is "go to this node".
    pub goto: A,
    /// What it did: when it reached each checkpoint.
    pub done: Vec<(SimTime, NodeId)>,
    /// The actuator's refusal, if any (the controller then stops).
    pub error: Option<MoveError>,
}

impl<A> Inspect<A> {
    /// Inspects `todo` through `goto`; nothing done yet.
    pub fn new(todo: Vec<(NodeId, [f64; 2])>, goto: A) -> Self {
        Inspect {
            todo,
            goto,
            done: Vec::new(),
            error: None,
        }
    }
}

impl<A> Controller for Inspect<A>
where
    A: Actuator<Arena, Ev, Command = NodeId, Error = MoveError> + 'static,
{
    fn handle(&mut self, input: Input<'_, Tactical>, cx: &mut Context<'_, Tactical>) {
        match input {
            Input::Event(Ev::Start) => {}
            Input::Event(Ev::Arrived(node)) => self.done.push((cx.now(), *node)),
            _ => return,
        }
        // Sense: where am I? (A sensor reading, not the storage.)
        let Some(me) = cx.sense(&OwnPose) else { return };
        // Decide: the nearest checkpoint left (squared distance: exact, the same on
        // every machine; ties go to the first in the list).
        let d2 = |p: [f64; 2]| (p[0] - me.pos[0]).powi(2) + (p[1] - me.pos[1]).powi(2);
        let next =
            (0..self.todo.len()).min_by(|&a, &b| d2(self.todo[a].1).total_cmp(&d2(self.todo[b].1)));
        let Some(i) = next else { return }; // all inspected
        let (goal, _) = self.todo.remove(i);
        // Act: the actuator moves the body over time and answers with Ev::Arrived.
        if let Err(e) = cx.act(&self.goto, goal) {
            self.error = Some(e);
        }
    }
}

#[cfg(test)]
mod tests {
    #[test]
    fn this_is_the_code_part_1_shows() {
        let page = include_str!("../../../docs/guide/src/tutorial-1-graph.md");
        let start = page.find("```rust\nuse vitro::prelude::*;").unwrap() + "```rust\n".len();
        let len = page[start..].find("# fn main() {}").unwrap();
        let shown = &page[start..start + len];
        assert!(include_str!("inspect.rs").contains(shown));
    }
}

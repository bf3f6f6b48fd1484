//! A Vidar's side of the cover plan: the steps it was told, flown in order, paced by the
//! team, and the reports of its looks (see the [parent](super) module).

use super::{AHEAD, CoverStep};
use crate::radio::Radio;
use serde::{Deserialize, Serialize};
use std::collections::VecDeque;
use vitro::entity::EntityId;

/// The signal name of a look report and of a recall.
pub const WATCH: &str = "watch";
/// A recall's signal argument.
pub const RECALLED: &str = "recalled";

/// What a Vidar heard of the cover plan, in a look report to the lead.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Heard {
    /// A look at `step`'s checkpoint, done (`true`) or failed.
    Look(CoverStep, bool),
    /// The sender was recalled: it leaves the team.
    Recalled,
}

impl Heard {
    /// The report as a radio message.
    pub fn message(&self) -> Radio {
        let arg = match self {
            Heard::Look(s, ok) => format!("{} {}", s.word(), if *ok { "ok" } else { "fail" }),
            Heard::Recalled => RECALLED.into(),
        };
        Radio::Signal(WATCH.into(), arg)
    }
    /// A report read from a radio message (`None`: not one).
    pub fn read(body: &Radio) -> Option<Heard> {
        let Radio::Signal(name, arg) = body else {
            return None;
        };
        if name != WATCH {
            return None;
        }
        if arg == RECALLED {
            return Some(Heard::Recalled);
        }
        let (word, outcome) = arg.split_once(' ')?;
        Some(Heard::Look(CoverStep::parse(word)?, outcome == "ok"))
    }
}

/// The plan message that gives a Vidar its steps (they replace what it had).
pub fn plan_message(steps: &[CoverStep]) -> Radio {
    Radio::Plan(steps.iter().map(CoverStep::word).collect())
}

/// The steps of a plan message (words that are not steps are skipped).
pub fn read_plan(body: &[String]) -> Vec<CoverStep> {
    body.iter().filter_map(|w| CoverStep::parse(w)).collect()
}

/// A Vidar's cover steps and the one under way.
#[derive(Clone, Debug, Serialize, Deserialize)]
pub struct Watcher {
    /// The lead Vidar (it makes the plan; looks are reported to it).
    pub lead: EntityId,
    queue: VecDeque<CoverStep>,
    flying: Option<CoverStep>,
    /// Recalled: it no longer takes part.
    pub recalled: bool,
}

impl Watcher {
    /// A Vidar of the team led by `lead`, with no steps yet.
    pub fn new(lead: EntityId) -> Self {
        Watcher {
            lead,
            queue: VecDeque::new(),
            flying: None,
            recalled: false,
        }
    }

    /// New steps: they replace the old ones (the step under way goes on only if it is
    /// still among them).
    pub fn take(&mut self, steps: Vec<CoverStep>) {
        let keep = self.flying.filter(|f| steps.contains(f));
        self.queue = steps.into_iter().filter(|s| Some(*s) != keep).collect();
        self.flying = keep;
    }

    /// The step to start now, the truck at checkpoint `k`, the Vidar over checkpoint `here`
    /// (none: one is under way, none is left, or the next is too far ahead of the team and
    /// not on the way back to it).
    pub fn next(&mut self, k: usize, here: usize) -> Option<CoverStep> {
        if self.recalled || self.flying.is_some() {
            return None;
        }
        let s = *self.queue.front()?;
        if s.spot > k + AHEAD && s.spot >= here {
            return None;
        }
        self.queue.pop_front();
        self.flying = Some(s);
        Some(s)
    }

    /// The step under way has reached its checkpoint: it is over.
    pub fn arrived(&mut self) -> Option<CoverStep> {
        self.flying.take()
    }

    /// The steps not yet done, the one under way first (for the viewer).
    pub fn steps(&self) -> Vec<CoverStep> {
        self.flying.iter().chain(&self.queue).copied().collect()
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use vitro_algo::repair::StepRef;

    fn step(index: u32, spot: usize) -> CoverStep {
        CoverStep {
            step: StepRef { version: 1, index },
            spot,
        }
    }

    #[test]
    fn reports_and_plans_travel_as_radio_messages() {
        for h in [
            Heard::Look(step(3, 7), true),
            Heard::Look(step(4, 8), false),
            Heard::Recalled,
        ] {
            assert_eq!(Heard::read(&h.message()), Some(h));
        }
        let steps = vec![step(0, 1), step(1, 3)];
        let Radio::Plan(body) = plan_message(&steps) else {
            panic!("a plan message")
        };
        assert_eq!(read_plan(&body), steps);
        assert_eq!(
            Heard::read(&Radio::Signal("formation".into(), "wedge".into())),
            None
        );
    }

    #[test]
    fn steps_wait_for_the_team_and_new_plans_replace_old() {
        let mut w = Watcher::new(EntityId(1));
        w.take(vec![step(0, 1), step(1, 5)]);
        assert_eq!(w.next(0, 0), Some(step(0, 1)));
        assert_eq!(w.next(0, 1), None, "one step at a time");
        assert_eq!(w.arrived(), Some(step(0, 1)));
        assert_eq!(
            w.next(0, 1),
            None,
            "checkpoint 5 is too far ahead of the truck at 0"
        );
        assert_eq!(w.next(3, 1), Some(step(1, 5)));
        w.take(vec![step(2, 6)]);
        assert_eq!(w.arrived(), None, "the step under way was dropped");
        assert_eq!(w.steps(), vec![step(2, 6)]);
        // Far ahead of the team, a step back towards it starts at once.
        w.take(vec![step(3, 9)]);
        assert_eq!(w.next(0, 10), Some(step(3, 9)));
    }
}

//! Schelling with krABMaga: one agent per household in its `Schedule`. The occupancy grid
//! lives in the state, updated in place: krABMaga's grids are double-buffered (a read sees
//! the last step), which cannot keep the declaration's one household a cell while the
//! households of one step move one after another.

use crate::{Outcome, Size};
use krabmaga::engine::agent::Agent;
use krabmaga::engine::schedule::Schedule;
use krabmaga::engine::state::State;
use krabmaga::rand::{Rng, SeedableRng};
use krabmaga::rand_pcg::Pcg64;
use std::any::Any;

#[derive(Copy, Clone)]
struct Home {
    x: i32,
    y: i32,
    group: u8,
    happy: bool,
}

struct Town {
    side: i32,
    radius: i32,
    min_happy: u32,
    agents: u32,
    cells: Vec<Option<u32>>,
    homes: Vec<Home>,
    rng: Pcg64,
}

impl Town {
    fn cell(&self, x: i32, y: i32) -> usize {
        (y * self.side + x) as usize
    }
    fn empty_cell(&mut self) -> (i32, i32) {
        loop {
            let (x, y) = (self.rng.random_range(0..self.side), self.rng.random_range(0..self.side));
            if self.cells[self.cell(x, y)].is_none() {
                return (x, y);
            }
        }
    }
}

#[derive(Copy, Clone)]
struct Household {
    id: u32,
}

impl Agent for Household {
    fn step(&mut self, state: &mut dyn State) {
        let t = state.as_any_mut().downcast_mut::<Town>().expect("the Schelling state");
        let h = t.homes[self.id as usize];
        let r = t.radius;
        let mut same = 0;
        for y in (h.y - r).max(0)..=(h.y + r).min(t.side - 1) {
            for x in (h.x - r).max(0)..=(h.x + r).min(t.side - 1) {
                if let Some(o) = t.cells[t.cell(x, y)] {
                    if o != self.id && t.homes[o as usize].group == h.group {
                        same += 1;
                    }
                }
            }
        }
        if same >= t.min_happy {
            t.homes[self.id as usize].happy = true;
            return;
        }
        let (x, y) = t.empty_cell();
        let (from, to) = (t.cell(h.x, h.y), t.cell(x, y));
        t.cells[from] = None;
        t.cells[to] = Some(self.id);
        t.homes[self.id as usize] = Home { x, y, happy: false, ..h };
    }
}

impl State for Town {
    fn init(&mut self, schedule: &mut Schedule) {
        for id in 0..self.agents {
            let (x, y) = self.empty_cell();
            let c = self.cell(x, y);
            self.cells[c] = Some(id);
            self.homes.push(Home { x, y, group: (id % 2) as u8, happy: false });
            schedule.schedule_repeating(Box::new(Household { id }), 0.0, 0);
        }
    }
    fn as_any_mut(&mut self) -> &mut dyn Any {
        self
    }
    fn as_any(&self) -> &dyn Any {
        self
    }
    fn as_state_mut(&mut self) -> &mut dyn State {
        self
    }
    fn as_state(&self) -> &dyn State {
        self
    }
    fn reset(&mut self) {}
    fn update(&mut self, _step: u64) {}
}

/// Runs the model of `size` with `seed` for 20 steps.
pub fn run(size: Size, seed: u64) -> Outcome {
    let (side, agents, radius, min_happy) = match size {
        Size::Small => (40, 1000, 1, 3),
        Size::Large => (100, 8000, 2, 8),
    };
    let mut town = Town {
        side,
        radius,
        min_happy,
        agents,
        cells: vec![None; (side * side) as usize],
        homes: Vec::with_capacity(agents as usize),
        rng: Pcg64::seed_from_u64(seed),
    };
    let mut schedule = Schedule::new();
    town.init(&mut schedule);
    for _ in 0..20 {
        schedule.step(&mut town);
    }
    let happy = town.homes.iter().filter(|h| h.happy).count();
    Outcome::Schelling { happy: happy as f64 / f64::from(agents) }
}

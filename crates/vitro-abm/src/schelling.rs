//! Schelling's segregation model (`declarations/Schelling.md`).
//!
//! `K` households of two groups on an `X × X` grid (not periodic, one household a cell).
//! At each activation a household counts the households of its own group within Chebyshev
//! radius `r`; with at least `min_happy` of them it is happy and stays, otherwise it moves to
//! a random empty cell. 20 steps.

use crate::{DRAWS, STEP, activation_delay};
use rand::{Rng, SeedableRng};
use rand_chacha::ChaCha8Rng;
use serde::Serialize;
use vitro::prelude::*;

/// A parameter set of the declaration.
#[derive(Copy, Clone, Debug, PartialEq)]
pub struct Schelling {
    /// Side of the grid, cells.
    pub side: i32,
    /// Households.
    pub agents: u32,
    /// Neighbourhood radius (Chebyshev), cells.
    pub radius: i32,
    /// Same-group neighbours a household needs to be happy.
    pub min_happy: u32,
    /// Steps simulated.
    pub steps: u64,
}

impl Schelling {
    /// The small set: 40 × 40, 1000 households, r = 1, 3 to be happy.
    pub const SMALL: Schelling = Schelling {
        side: 40,
        agents: 1000,
        radius: 1,
        min_happy: 3,
        steps: 20,
    };
    /// The large set: 100 × 100, 8000 households, r = 2, 8 to be happy.
    pub const LARGE: Schelling = Schelling {
        side: 100,
        agents: 8000,
        radius: 2,
        min_happy: 8,
        steps: 20,
    };
}

/// A household's state.
#[derive(Copy, Clone, Debug, PartialEq, Eq, Serialize)]
pub struct Home {
    /// Cell column.
    pub x: i32,
    /// Cell row.
    pub y: i32,
    /// Group, 0 or 1.
    pub group: u8,
    /// Happy after its last activation.
    pub happy: bool,
}

/// The environment: the occupancy grid and the households.
pub struct Town {
    side: i32,
    radius: i32,
    min_happy: u32,
    /// Who occupies each cell, row-major.
    cells: Vec<Option<EntityId>>,
    /// The households.
    pub homes: EntityStorage<Home>,
}

impl Town {
    fn cell(&self, x: i32, y: i32) -> usize {
        (y * self.side + x) as usize
    }
}

/// What a household sees: how many of its own group live within the radius, and the
/// model's threshold (read from the model, as the declaration asks).
pub struct Neighbours;

impl Sensor<Town> for Neighbours {
    type Reading = (u32, u32);
    fn read(&self, w: &Town, me: EntityId, _: &mut Probe<'_>) -> (u32, u32) {
        let Some(h) = w.homes.get(me) else {
            return (0, w.min_happy);
        };
        let r = w.radius;
        let mut same = 0;
        for y in (h.y - r).max(0)..=(h.y + r).min(w.side - 1) {
            for x in (h.x - r).max(0)..=(h.x + r).min(w.side - 1) {
                let Some(other) = w.cells[w.cell(x, y)] else {
                    continue;
                };
                if other != me && w.homes.get(other).is_some_and(|o| o.group == h.group) {
                    same += 1;
                }
            }
        }
        (same, w.min_happy)
    }
}

/// Stays (happy) or moves to a random empty cell (unhappy), drawing from the household's
/// `"move"` stream.
pub struct Settle;

impl Actuator<Town, Wake> for Settle {
    type Command = bool;
    type Error = std::convert::Infallible;
    fn actuate(
        &self,
        w: &mut Town,
        me: EntityId,
        happy: bool,
        fx: &mut Effects<'_, Wake>,
    ) -> Result<(), Self::Error> {
        let Some(h) = w.homes.get(me).copied() else {
            return Ok(());
        };
        if happy {
            if !h.happy {
                w.homes.update(me, |h| h.happy = true);
            }
            return Ok(());
        }
        let rng = fx.rng(DRAWS);
        let (x, y) = loop {
            let (x, y) = (rng.random_range(0..w.side), rng.random_range(0..w.side));
            if w.cells[w.cell(x, y)].is_none() {
                break (x, y);
            }
        };
        let (from, to) = (w.cell(h.x, h.y), w.cell(x, y));
        w.cells[from] = None;
        w.cells[to] = Some(me);
        w.homes.update(me, |h| {
            h.x = x;
            h.y = y;
            h.happy = false;
        });
        Ok(())
    }
}

/// The event that starts a household.
#[derive(Copy, Clone, Debug, Serialize)]
pub struct Wake;

/// A household: counts, then stays or moves; next activation in the next step's window.
pub struct Household {
    step: u64,
}

/// The model's types.
pub struct Model;

impl vitro::sim::Model for Model {
    type Env = Town;
    type Event = Wake;
    type Msg = ();
    type Agent = Household;
}

impl Agent<Model> for Household {
    fn handle(&mut self, _: Input<'_, Model>, cx: &mut Context<'_, Model>) {
        let (same, min_happy) = cx.sense(&Neighbours);
        let Ok(()) = cx.act(&Settle, same >= min_happy);
        self.step += 1;
        let delay = activation_delay(cx.now(), self.step, 0.0, 1.0, cx.rng(DRAWS));
        cx.set_timer(delay, 0);
    }
}

/// A model built and ready to run.
pub fn build(p: &Schelling, seed: u64) -> Simulation<Model> {
    let town = Town {
        side: p.side,
        radius: p.radius,
        min_happy: p.min_happy,
        cells: vec![None; (p.side * p.side) as usize],
        homes: EntityStorage::default(),
    };
    let mut sim = Simulation::<Model>::new(town, seed);
    let mut rng = ChaCha8Rng::seed_from_u64(seed);
    let cells = (p.side * p.side) as u32;
    for i in 0..p.agents.min(cells) {
        let Ok(id) = sim.add_agent(format!("home-{i}"), Household { step: 0 }) else {
            break;
        };
        let w = sim.env_mut();
        let (x, y) = loop {
            let (x, y) = (rng.random_range(0..p.side), rng.random_range(0..p.side));
            if w.cells[w.cell(x, y)].is_none() {
                break (x, y);
            }
        };
        let c = w.cell(x, y);
        w.cells[c] = Some(id);
        let group = (i % 2) as u8;
        w.homes.insert(
            id,
            Home {
                x,
                y,
                group,
                happy: false,
            },
        );
        let first = SimTime::from_nanos(rng.random_range(0..STEP.as_nanos()));
        // Scheduling at a time not in the past cannot fail on a fresh simulation.
        let _ = sim.schedule(first, Target::Entity(id), Wake);
    }
    sim
}

/// What a run ends with.
#[derive(Copy, Clone, Debug, PartialEq)]
pub struct Outcome {
    /// Households.
    pub agents: u32,
    /// Happy households after the last step.
    pub happy: u32,
    /// Events fired.
    pub events: u64,
}

/// Runs a model of `p` with `seed` for its steps.
pub fn run(p: &Schelling, seed: u64) -> Outcome {
    let mut sim = build(p, seed);
    sim.run_until(SimTime::ZERO + STEP * p.steps);
    let homes = &sim.env().homes;
    Outcome {
        agents: homes.len() as u32,
        happy: homes.iter().filter(|(_, h)| h.happy).count() as u32,
        events: sim.events_fired(),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn one_household_a_cell_and_most_end_happy() {
        let p = Schelling::SMALL;
        let out = run(&p, 3);
        assert_eq!(out.agents, p.agents);
        assert_eq!(out.events, u64::from(p.agents) * p.steps);
        let sim = {
            let mut s = build(&p, 3);
            s.run_until(SimTime::ZERO + STEP * p.steps);
            s
        };
        let w = sim.env();
        let mut seen = std::collections::BTreeSet::new();
        for (id, h) in w.homes.iter() {
            assert!(seen.insert((h.x, h.y)), "two households in one cell");
            assert_eq!(w.cells[w.cell(h.x, h.y)], Some(id));
        }
        // Segregation: far more happy households than at the random start.
        assert!(out.happy as f64 > 0.8 * p.agents as f64, "{out:?}");
    }
}

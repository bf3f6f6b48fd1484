//! Schelling's segregation model (`declarations/Schelling.md`).
//!
//! `K` households of two groups on an `X × X` grid (not periodic, one household a cell).
//! At each activation a household counts the households of its own group within Chebyshev
//! radius `r`; with at least `min_happy` of them it is happy and stays, otherwise it moves to
//! a random empty cell. 20 steps.

use crate::{DRAWS, STEP};
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
/// own small stream.
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
        let rng = fx.small_rng(DRAWS);
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

/// A household: counts, then stays or moves; a member of the model's round (activated once a
/// step, in a fresh random order).
pub struct Household;

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
    // One firing at the start of each step: every household once, in a fresh random order.
    let Ok(steps) = sim.add_round(SimTime::ZERO, STEP, 0) else {
        return sim;
    };
    let cells = (p.side * p.side) as u32;
    for i in 0..p.agents.min(cells) {
        let Ok(id) = sim.add_agent(format!("home-{i}"), Household) else {
            break;
        };
        sim.join_round(steps, id);
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
    /// Events fired (one a step: the round's firing).
    pub events: u64,
}

/// The end of a run of `p`: the last step's firing is at `steps - 1`.
fn end(p: &Schelling) -> SimTime {
    SimTime::ZERO + STEP * p.steps.saturating_sub(1)
}

/// Runs a model of `p` with `seed` for its steps.
pub fn run(p: &Schelling, seed: u64) -> Outcome {
    let mut sim = build(p, seed);
    sim.run_until(end(p));
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
        assert_eq!(out.events, p.steps);
        let activations = std::sync::Arc::new(std::sync::atomic::AtomicU64::new(0));
        let sim = {
            let mut s = build(&p, 3);
            let a = activations.clone();
            s.add_listener(move |_| {
                a.fetch_add(1, std::sync::atomic::Ordering::Relaxed);
            });
            s.run_until(end(&p));
            s
        };
        // Every household once a step.
        let activations = activations.load(std::sync::atomic::Ordering::Relaxed);
        assert_eq!(activations, u64::from(p.agents) * p.steps);
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

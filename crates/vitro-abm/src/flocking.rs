//! The flocking model (`declarations/Flocking.md`).
//!
//! Birds in a periodic 2D continuous space. At each activation a bird finds its neighbours
//! within its visual distance, steers by cohesion, separation and alignment (the
//! declaration's update rule; headings to neighbours are the shortest periodic differences)
//! and moves `speed` along its unit velocity. 100 steps.
//!
//! Neighbour search goes through a bucket grid of cells at least the visual distance wide,
//! kept by the flight actuator.

use crate::STEP;
use rand::{Rng, SeedableRng};
use rand_chacha::ChaCha8Rng;
use serde::Serialize;
use vitro::prelude::*;

/// A parameter set of the declaration.
#[derive(Copy, Clone, Debug, PartialEq)]
pub struct Flocking {
    /// Extent of the (square, periodic) space.
    pub extent: f64,
    /// Birds.
    pub birds: u32,
    /// Visual distance.
    pub visual_distance: f64,
    /// Speed (distance per step).
    pub speed: f64,
    /// Cohere factor.
    pub cohere: f64,
    /// Separation distance.
    pub separation: f64,
    /// Separate factor.
    pub separate: f64,
    /// Match factor.
    pub match_factor: f64,
    /// Steps simulated.
    pub steps: u64,
}

impl Flocking {
    /// The small set: 100 × 100, 200 birds, visual distance 5.
    pub const SMALL: Flocking = Flocking {
        extent: 100.0,
        birds: 200,
        visual_distance: 5.0,
        speed: 1.0,
        cohere: 0.03,
        separation: 1.0,
        separate: 0.015,
        match_factor: 0.05,
        steps: 100,
    };
    /// The large set: 150 × 150, 400 birds, visual distance 15.
    pub const LARGE: Flocking = Flocking {
        extent: 150.0,
        birds: 400,
        visual_distance: 15.0,
        ..Flocking::SMALL
    };
}

/// A bird's state.
#[derive(Copy, Clone, Debug, PartialEq, Serialize)]
pub struct Bird {
    /// Position.
    pub pos: [f64; 2],
    /// Unit velocity.
    pub vel: [f64; 2],
}

/// The environment: the birds and their bucket grid.
pub struct Sky {
    p: Flocking,
    /// Cells along each axis.
    n: usize,
    /// Bird ids per cell.
    cells: Vec<Vec<EntityId>>,
    /// The birds.
    pub birds: EntityStorage<Bird>,
}

impl Sky {
    fn cell_of(&self, pos: [f64; 2]) -> (usize, usize) {
        let f = |v: f64| ((v / self.p.extent * self.n as f64) as usize).min(self.n - 1);
        (f(pos[0]), f(pos[1]))
    }
    /// The shortest periodic difference `b - a`.
    fn delta(&self, a: [f64; 2], b: [f64; 2]) -> [f64; 2] {
        let e = self.p.extent;
        let d = |x: f64| x - e * libm::round(x / e);
        [d(b[0] - a[0]), d(b[1] - a[1])]
    }
}

/// A neighbour as a bird sees it: the heading to it and its velocity.
#[derive(Copy, Clone, Debug)]
pub struct Seen {
    /// Shortest periodic difference from the observer to it.
    pub heading: [f64; 2],
    /// Its velocity.
    pub vel: [f64; 2],
}

/// The birds within the visual distance (Euclidean, periodic), and the bird's own state.
pub struct Eyes;

impl Sensor<Sky> for Eyes {
    type Reading = (Option<Bird>, Vec<Seen>);
    fn read(&self, w: &Sky, me: EntityId, _: &mut Probe<'_>) -> Self::Reading {
        let Some(b) = w.birds.get(me).copied() else {
            return (None, Vec::new());
        };
        let r = w.p.visual_distance;
        let (cx, cy) = w.cell_of(b.pos);
        let n = w.n as isize;
        // With fewer than three cells a side, every cell is a neighbour cell.
        let span: Vec<isize> = if n < 3 {
            (0..n).collect()
        } else {
            vec![-1, 0, 1]
        };
        let mut out = Vec::new();
        for &dy in &span {
            for &dx in &span {
                let (x, y) = if n < 3 {
                    (dx as usize, dy as usize)
                } else {
                    (
                        (cx as isize + dx).rem_euclid(n) as usize,
                        (cy as isize + dy).rem_euclid(n) as usize,
                    )
                };
                for &other in &w.cells[y * w.n + x] {
                    let Some(o) = w.birds.get(other).filter(|_| other != me) else {
                        continue;
                    };
                    let h = w.delta(b.pos, o.pos);
                    if h[0] * h[0] + h[1] * h[1] <= r * r {
                        out.push(Seen {
                            heading: h,
                            vel: o.vel,
                        });
                    }
                }
            }
        }
        (Some(b), out)
    }
}

/// Sets a bird's unit velocity and moves it `speed` along it (wrapping around).
pub struct Fly;

impl Actuator<Sky, Wake> for Fly {
    type Command = [f64; 2];
    type Error = std::convert::Infallible;
    fn actuate(
        &self,
        w: &mut Sky,
        me: EntityId,
        vel: [f64; 2],
        _: &mut Effects<'_, Wake>,
    ) -> Result<(), Self::Error> {
        let Some(b) = w.birds.get(me).copied() else {
            return Ok(());
        };
        let e = w.p.extent;
        let wrap = |v: f64| {
            let r = v - e * libm::floor(v / e);
            if r >= e { 0.0 } else { r }
        };
        let pos = [
            wrap(b.pos[0] + vel[0] * w.p.speed),
            wrap(b.pos[1] + vel[1] * w.p.speed),
        ];
        let (from, to) = (w.cell_of(b.pos), w.cell_of(pos));
        if from != to {
            let cell = &mut w.cells[from.1 * w.n + from.0];
            if let Some(i) = cell.iter().position(|&x| x == me) {
                cell.swap_remove(i);
            }
            w.cells[to.1 * w.n + to.0].push(me);
        }
        w.birds.insert(me, Bird { pos, vel });
        Ok(())
    }
}

/// The event that starts a bird.
#[derive(Copy, Clone, Debug, Serialize)]
pub struct Wake;

/// A bird: looks, steers, flies; a member of the model's round (activated once a step, in a
/// fresh random order). It carries its own flocking properties, as in the declaration.
pub struct Boid {
    p: Flocking,
}

/// The model's types.
pub struct Model;

impl vitro::sim::Model for Model {
    type Env = Sky;
    type Event = Wake;
    type Msg = ();
    type Agent = Boid;
}

/// The declaration's update rule: the new unit velocity of a bird with velocity `vel` that
/// sees `seen`.
pub fn steer(p: &Flocking, vel: [f64; 2], seen: &[Seen]) -> [f64; 2] {
    let (mut cohere, mut separate, mut matching) = ([0.0; 2], [0.0; 2], [0.0; 2]);
    for s in seen {
        let h = s.heading;
        for k in 0..2 {
            cohere[k] += h[k];
            matching[k] += s.vel[k];
        }
        if libm::sqrt(h[0] * h[0] + h[1] * h[1]) < p.separation {
            for k in 0..2 {
                separate[k] -= h[k];
            }
        }
    }
    let n = seen.len().max(1) as f64;
    let mut v = [0.0; 2];
    for k in 0..2 {
        v[k] = (vel[k]
            + cohere[k] / n * p.cohere
            + separate[k] / n * p.separate
            + matching[k] / n * p.match_factor)
            / 2.0;
    }
    let norm = libm::sqrt(v[0] * v[0] + v[1] * v[1]);
    if norm > 0.0 {
        [v[0] / norm, v[1] / norm]
    } else {
        vel
    }
}

impl Agent<Model> for Boid {
    fn handle(&mut self, _: Input<'_, Model>, cx: &mut Context<'_, Model>) {
        let (Some(me), seen) = cx.sense(&Eyes) else {
            return;
        };
        let Ok(()) = cx.act(&Fly, steer(&self.p, me.vel, &seen));
    }
}

/// A model built and ready to run.
pub fn build(p: &Flocking, seed: u64) -> Simulation<Model> {
    let n = ((p.extent / p.visual_distance) as usize).max(1);
    let sky = Sky {
        p: *p,
        n,
        cells: vec![Vec::new(); n * n],
        birds: EntityStorage::default(),
    };
    let mut sim = Simulation::<Model>::new(sky, seed);
    let mut rng = ChaCha8Rng::seed_from_u64(seed);
    // One firing at the start of each step: every bird once, in a fresh random order.
    let Ok(steps) = sim.add_round(SimTime::ZERO, STEP, 0) else {
        return sim;
    };
    for i in 0..p.birds {
        let Ok(id) = sim.add_agent(format!("bird-{i}"), Boid { p: *p }) else {
            break;
        };
        sim.join_round(steps, id);
        let pos = [
            rng.random::<f64>() * p.extent,
            rng.random::<f64>() * p.extent,
        ];
        let v = loop {
            let v = [
                rng.random::<f64>() * 2.0 - 1.0,
                rng.random::<f64>() * 2.0 - 1.0,
            ];
            let norm = libm::sqrt(v[0] * v[0] + v[1] * v[1]);
            if norm > 1e-9 {
                break [v[0] / norm, v[1] / norm];
            }
        };
        let w = sim.env_mut();
        let (cx, cy) = w.cell_of(pos);
        w.cells[cy * w.n + cx].push(id);
        w.birds.insert(id, Bird { pos, vel: v });
    }
    sim
}

/// What a run ends with.
#[derive(Copy, Clone, Debug, PartialEq)]
pub struct Outcome {
    /// Birds.
    pub birds: u32,
    /// Polarisation: the length of the mean unit velocity (0: disordered, 1: one flock
    /// heading one way).
    pub polarisation: f64,
    /// Mean number of neighbours within the visual distance.
    pub neighbours: f64,
    /// Events fired (one a step: the round's firing).
    pub events: u64,
}

/// The polarisation and mean neighbour count of `sky`.
fn order(sky: &Sky) -> (f64, f64) {
    let (mut v, mut pairs, mut n) = ([0.0; 2], 0usize, 0usize);
    let r = sky.p.visual_distance;
    let all: Vec<Bird> = sky.birds.iter().map(|(_, b)| *b).collect();
    for (i, a) in all.iter().enumerate() {
        v[0] += a.vel[0];
        v[1] += a.vel[1];
        n += 1;
        for b in &all[i + 1..] {
            let h = sky.delta(a.pos, b.pos);
            if h[0] * h[0] + h[1] * h[1] <= r * r {
                pairs += 2;
            }
        }
    }
    let n = n.max(1) as f64;
    (libm::sqrt(v[0] * v[0] + v[1] * v[1]) / n, pairs as f64 / n)
}

/// Runs a model of `p` with `seed` for its steps.
pub fn run(p: &Flocking, seed: u64) -> Outcome {
    let mut sim = build(p, seed);
    // The last step's firing is at `steps - 1`.
    sim.run_until(SimTime::ZERO + STEP * p.steps.saturating_sub(1));
    let (polarisation, neighbours) = order(sim.env());
    Outcome {
        birds: sim.env().birds.len() as u32,
        polarisation,
        neighbours,
        events: sim.events_fired(),
    }
}

/// The polarisation and mean neighbour count of a freshly built model of `p` (the
/// disordered start).
pub fn initial_order(p: &Flocking, seed: u64) -> (f64, f64) {
    order(build(p, seed).env())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn birds_flock() {
        let p = Flocking::SMALL;
        let (_, before) = initial_order(&p, 5);
        let out = run(&p, 5);
        assert_eq!(out.events, p.steps);
        // Uniformly scattered birds have ~200 × π 5² / 100² ≈ 1.6 neighbours; flocks gather.
        assert!(before < 2.5, "{before}");
        assert!(out.neighbours > 2.0 * before, "{out:?} from {before}");
    }

    #[test]
    fn headings_are_periodic() {
        let sky = build(&Flocking::SMALL, 1);
        let d = sky.env().delta([99.0, 1.0], [1.0, 99.0]);
        assert!((d[0] - 2.0).abs() < 1e-12 && (d[1] + 2.0).abs() < 1e-12);
    }
}

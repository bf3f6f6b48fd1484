//! The wolf-sheep-grass model (`declarations/WolfSheep.md`).
//!
//! Sheep and wolves (two agent kinds) walk a periodic grid one of the eight neighbouring
//! cells at a time, lose energy, eat (sheep: the grass of their cell; wolves: a sheep of
//! their cell), die when out of energy and otherwise reproduce with their probability,
//! halving their energy for the newborn. Each step activates all sheep, then all wolves
//! (each in a fresh random order), then regrows the grass. 100 steps.
//!
//! Three rounds ([`Simulation::add_round`]) make a step: the sheep's at its start, the
//! wolves' 0.4 s in, the meadow's 0.9 s in. A newborn is an entity of its own: the breeding
//! actuator leaves it in the field's nursery, and the run loop adds it to the simulation
//! after the step (Vitro adds agents between runs) and to its kind's round, to be activated
//! from the next step on. An eaten or starved animal loses its body; its agent leaves its
//! round (the eaten one at its next activation).

use crate::{DRAWS, STEP};
use rand::{Rng, SeedableRng};
use rand_chacha::ChaCha8Rng;
use serde::Serialize;
use vitro::prelude::*;

/// A parameter set of the declaration.
#[derive(Copy, Clone, Debug, PartialEq)]
pub struct WolfSheep {
    /// Side of the (square, periodic) grid.
    pub side: i32,
    /// Sheep at the start.
    pub sheep: u32,
    /// Wolves at the start.
    pub wolves: u32,
    /// Steps for eaten grass to grow back.
    pub regrowth: u32,
    /// Reproduction probability of a sheep per step.
    pub sheep_reproduce: f64,
    /// Reproduction probability of a wolf per step.
    pub wolf_reproduce: f64,
    /// Energy a sheep gains from grass.
    pub sheep_gain: f64,
    /// Energy a wolf gains from a sheep.
    pub wolf_gain: f64,
    /// Steps simulated.
    pub steps: u64,
}

impl WolfSheep {
    /// The small set: 25 × 25, 60 sheep, 40 wolves, regrowth 20, reproduction 0.2 / 0.1.
    pub const SMALL: WolfSheep = WolfSheep {
        side: 25,
        sheep: 60,
        wolves: 40,
        regrowth: 20,
        sheep_reproduce: 0.2,
        wolf_reproduce: 0.1,
        sheep_gain: 5.0,
        wolf_gain: 13.0,
        steps: 100,
    };
    /// The large set: 100 × 100, 1000 sheep, 500 wolves, regrowth 10, reproduction 0.4 / 0.2.
    pub const LARGE: WolfSheep = WolfSheep {
        side: 100,
        sheep: 1000,
        wolves: 500,
        regrowth: 10,
        sheep_reproduce: 0.4,
        wolf_reproduce: 0.2,
        ..WolfSheep::SMALL
    };
}

/// The two animal kinds.
#[derive(Copy, Clone, Debug, PartialEq, Eq, Serialize)]
pub enum Kind {
    /// Eats grass.
    Sheep,
    /// Eats sheep.
    Wolf,
}

/// An animal's body.
#[derive(Copy, Clone, Debug, PartialEq, Serialize)]
pub struct Animal {
    /// Cell column.
    pub x: i32,
    /// Cell row.
    pub y: i32,
    /// Energy.
    pub energy: f64,
}

/// The grass of one cell.
#[derive(Copy, Clone, Debug, PartialEq, Eq)]
struct Grass {
    grown: bool,
    countdown: u32,
}

/// The environment: grass, the animals' bodies, who stands where, and the nursery.
pub struct Field {
    p: WolfSheep,
    grass: Vec<Grass>,
    /// Sheep per cell (wolves look for their prey here).
    flock: Vec<Vec<EntityId>>,
    /// Sheep bodies.
    pub sheep: EntityStorage<Animal>,
    /// Wolf bodies.
    pub wolves: EntityStorage<Animal>,
    /// Newborns waiting to be added after the step.
    nursery: Vec<(Kind, Animal)>,
}

impl Field {
    fn cell(&self, x: i32, y: i32) -> usize {
        (y * self.p.side + x) as usize
    }
    fn bodies(&self, k: Kind) -> &EntityStorage<Animal> {
        match k {
            Kind::Sheep => &self.sheep,
            Kind::Wolf => &self.wolves,
        }
    }
    fn bodies_mut(&mut self, k: Kind) -> &mut EntityStorage<Animal> {
        match k {
            Kind::Sheep => &mut self.sheep,
            Kind::Wolf => &mut self.wolves,
        }
    }
    /// Removes the sheep `id` from its cell's flock.
    fn leave(&mut self, id: EntityId, x: i32, y: i32) {
        let c = self.cell(x, y);
        if let Some(i) = self.flock[c].iter().position(|&s| s == id) {
            self.flock[c].swap_remove(i);
        }
    }
}

/// An animal's own body, and its kind's parameters (energy to survive, reproduction
/// probability).
pub struct Body(pub Kind);

impl Sensor<Field> for Body {
    type Reading = Option<Animal>;
    fn read(&self, w: &Field, me: EntityId, _: &mut Probe<'_>) -> Option<Animal> {
        w.bodies(self.0).get(me).copied()
    }
}

/// What an animal does with its body: walk to a neighbouring cell (losing one energy), eat,
/// die, or breed.
#[derive(Copy, Clone, Debug)]
pub enum Deed {
    /// Walk by `(dx, dy)`, each in -1..=1, wrapping around; costs one energy.
    Walk(i32, i32),
    /// Eat what the cell offers the kind (grass; a sheep chosen at random).
    Eat,
    /// Leave the field.
    Die,
    /// Halve the energy; the newborn gets the other half.
    Breed,
}

/// Carries out an animal's [`Deed`].
pub struct Act(pub Kind);

impl Actuator<Field, Wake> for Act {
    type Command = Deed;
    type Error = std::convert::Infallible;
    fn actuate(
        &self,
        w: &mut Field,
        me: EntityId,
        deed: Deed,
        fx: &mut Effects<'_, Wake>,
    ) -> Result<(), Self::Error> {
        let k = self.0;
        let Some(a) = w.bodies(k).get(me).copied() else {
            return Ok(());
        };
        match deed {
            Deed::Walk(dx, dy) => {
                let s = w.p.side;
                let (x, y) = ((a.x + dx).rem_euclid(s), (a.y + dy).rem_euclid(s));
                if k == Kind::Sheep {
                    w.leave(me, a.x, a.y);
                    let c = w.cell(x, y);
                    w.flock[c].push(me);
                }
                let energy = a.energy - 1.0;
                w.bodies_mut(k).insert(me, Animal { x, y, energy });
            }
            Deed::Eat if k == Kind::Sheep => {
                let c = w.cell(a.x, a.y);
                if w.grass[c].grown {
                    w.grass[c] = Grass {
                        grown: false,
                        countdown: w.p.regrowth,
                    };
                    let gain = w.p.sheep_gain;
                    w.sheep.update(me, |s| s.energy += gain);
                }
            }
            Deed::Eat => {
                let c = w.cell(a.x, a.y);
                let n = w.flock[c].len();
                if n > 0 {
                    let prey = w.flock[c].swap_remove(fx.small_rng(DRAWS).random_range(0..n));
                    w.sheep.remove(prey);
                    let gain = w.p.wolf_gain;
                    w.wolves.update(me, |s| s.energy += gain);
                }
            }
            Deed::Die => {
                if k == Kind::Sheep {
                    w.leave(me, a.x, a.y);
                }
                w.bodies_mut(k).remove(me);
            }
            Deed::Breed => {
                let half = a.energy / 2.0;
                w.bodies_mut(k).update(me, |s| s.energy = half);
                w.nursery.push((k, Animal { energy: half, ..a }));
            }
        }
        Ok(())
    }
}

/// Regrows the grass: every cell's countdown falls by one; at zero the grass is grown.
pub struct Grow;

impl Actuator<Field, Wake> for Grow {
    type Command = ();
    type Error = std::convert::Infallible;
    fn actuate(
        &self,
        w: &mut Field,
        _: EntityId,
        _: (),
        _: &mut Effects<'_, Wake>,
    ) -> Result<(), Self::Error> {
        for g in w.grass.iter_mut().filter(|g| !g.grown) {
            g.countdown = g.countdown.saturating_sub(1);
            if g.countdown == 0 {
                g.grown = true;
            }
        }
        Ok(())
    }
}

/// The event that starts an agent.
#[derive(Copy, Clone, Debug, Serialize)]
pub struct Wake;

/// The agents: animals of either kind, and the meadow (the grass's clock).
pub enum Beast {
    /// An animal: its kind, its kind's round and its reproduction probability.
    Animal(Kind, RoundId, f64),
    /// The meadow.
    Meadow,
}

/// The model's types.
pub struct Model;

impl vitro::sim::Model for Model {
    type Env = Field;
    type Event = Wake;
    type Msg = ();
    type Agent = Beast;
}

impl Agent<Model> for Beast {
    fn handle(&mut self, _: Input<'_, Model>, cx: &mut Context<'_, Model>) {
        let Beast::Animal(k, round, p_breed) = *self else {
            let Ok(()) = cx.act(&Grow, ());
            return;
        };
        if cx.sense(&Body(k)).is_none() {
            cx.leave_round(round); // eaten
            return;
        }
        let rng = cx.small_rng(DRAWS);
        let (dx, dy) = loop {
            let d = (rng.random_range(-1..=1), rng.random_range(-1..=1));
            if d != (0, 0) {
                break d;
            }
        };
        let Ok(()) = cx.act(&Act(k), Deed::Walk(dx, dy));
        let Ok(()) = cx.act(&Act(k), Deed::Eat);
        let energy = cx.sense(&Body(k)).map_or(0.0, |a| a.energy);
        let dies = match k {
            Kind::Sheep => energy < 1.0,
            Kind::Wolf => energy < 0.0,
        };
        if dies {
            let Ok(()) = cx.act(&Act(k), Deed::Die);
            cx.leave_round(round);
            return;
        }
        if cx.small_rng(DRAWS).random::<f64>() < p_breed {
            let Ok(()) = cx.act(&Act(k), Deed::Breed);
        }
    }
}

/// The rounds of a model: the sheep's and the wolves'.
#[derive(Copy, Clone, Debug)]
pub struct Rounds {
    /// Activates the sheep at the start of each step.
    pub sheep: RoundId,
    /// Activates the wolves 0.4 s into each step.
    pub wolves: RoundId,
}

/// Adds an animal with body `a`, activated from the next firing of its kind's round.
fn add(sim: &mut Simulation<Model>, rounds: Rounds, k: Kind, a: Animal) {
    let p = sim.env().p;
    let (round, p_breed) = match k {
        Kind::Sheep => (rounds.sheep, p.sheep_reproduce),
        Kind::Wolf => (rounds.wolves, p.wolf_reproduce),
    };
    // Unnamed: an animal is known by its id (as in the other frameworks), and a run adds
    // tens of thousands of them.
    let Ok(id) = sim.add_agent("", Beast::Animal(k, round, p_breed)) else {
        return;
    };
    let w = sim.env_mut();
    if k == Kind::Sheep {
        let c = w.cell(a.x, a.y);
        w.flock[c].push(id);
    }
    w.bodies_mut(k).insert(id, a);
    sim.join_round(round, id);
}

/// A model built and ready to run, and its rounds.
pub fn build(p: &WolfSheep, seed: u64) -> (Simulation<Model>, Rounds) {
    let cells = (p.side * p.side) as usize;
    let mut rng = ChaCha8Rng::seed_from_u64(seed);
    let grass = (0..cells)
        .map(|_| {
            if rng.random::<bool>() {
                Grass {
                    grown: true,
                    countdown: 0,
                }
            } else {
                Grass {
                    grown: false,
                    countdown: rng.random_range(1..=p.regrowth.max(1)),
                }
            }
        })
        .collect();
    let field = Field {
        p: *p,
        grass,
        flock: vec![Vec::new(); cells],
        sheep: EntityStorage::default(),
        wolves: EntityStorage::default(),
        nursery: Vec::new(),
    };
    let mut sim = Simulation::<Model>::new(field, seed);
    let mut round = |at: f64| {
        sim.add_round(SimTime::from_secs_f64(at), STEP, 0)
            .expect("at time zero every instant is ahead")
    };
    let rounds = Rounds {
        sheep: round(0.0),
        wolves: round(0.4),
    };
    let meadow = round(0.9);
    if let Ok(id) = sim.add_agent("meadow", Beast::Meadow) {
        sim.join_round(meadow, id);
    }
    for (k, n, gain) in [
        (Kind::Sheep, p.sheep, p.sheep_gain),
        (Kind::Wolf, p.wolves, p.wolf_gain),
    ] {
        for _ in 0..n {
            let a = Animal {
                x: rng.random_range(0..p.side),
                y: rng.random_range(0..p.side),
                energy: f64::from(rng.random_range(1..=(2.0 * gain) as u32)),
            };
            add(&mut sim, rounds, k, a);
        }
    }
    (sim, rounds)
}

/// What a run ends with.
#[derive(Clone, Debug, PartialEq)]
pub struct Outcome {
    /// Sheep and wolves alive after each step.
    pub counts: Vec<(u32, u32)>,
    /// Events fired (three a step: the rounds' firings).
    pub events: u64,
}

/// Runs a model of `p` with `seed` for its steps.
pub fn run(p: &WolfSheep, seed: u64) -> Outcome {
    let (mut sim, rounds) = build(p, seed);
    let mut counts = Vec::with_capacity(p.steps as usize);
    for k in 1..=p.steps {
        // Step k - 1, up to (not including) the start of step k.
        sim.run_until(SimTime::from_nanos((STEP * k).as_nanos() - 1));
        let born = std::mem::take(&mut sim.env_mut().nursery);
        for (kind, a) in born {
            add(&mut sim, rounds, kind, a);
        }
        let w = sim.env();
        counts.push((w.sheep.len() as u32, w.wolves.len() as u32));
    }
    Outcome {
        counts,
        events: sim.events_fired(),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn populations_live_and_the_flock_index_matches_the_bodies() {
        let p = WolfSheep::SMALL;
        let out = run(&p, 11);
        assert_eq!(out.counts.len(), 100);
        assert_eq!(out.events, 300);
        // Sheep breed fast enough to stay; the counts move (births and deaths happen).
        assert!(out.counts.iter().any(|&(s, _)| s != p.sheep));
        let (mut sim, _) = build(&p, 11);
        sim.run_until(SimTime::ZERO + STEP * 10);
        let w = sim.env();
        let indexed: usize = w.flock.iter().map(Vec::len).sum();
        assert_eq!(indexed, w.sheep.len());
        for (id, s) in w.sheep.iter() {
            assert!(w.flock[w.cell(s.x, s.y)].contains(&id));
        }
    }
}

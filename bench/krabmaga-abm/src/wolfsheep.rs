//! WolfSheep with krABMaga: sheep and wolves are two agent types in its `Schedule` (sheep at
//! ordering 0 run before wolves at ordering 1 each step), the grass and who stands where
//! live in the state. Newborns are scheduled by the state after the step; an eaten or
//! starved animal stops (`is_stopped`) and leaves the schedule.

use crate::{Outcome, Size};
use krabmaga::engine::agent::Agent;
use krabmaga::engine::schedule::Schedule;
use krabmaga::engine::state::State;
use krabmaga::rand::{Rng, SeedableRng};
use krabmaga::rand_pcg::Pcg64;
use std::any::Any;

#[derive(Copy, Clone)]
struct P {
    side: i32,
    sheep: u32,
    wolves: u32,
    regrowth: u32,
    sheep_reproduce: f64,
    wolf_reproduce: f64,
}

#[derive(Copy, Clone)]
struct Animal {
    x: i32,
    y: i32,
    energy: f64,
}

struct Field {
    p: P,
    grass: Vec<(bool, u32)>,
    flock: Vec<Vec<u32>>,
    /// Bodies by id (sheep and wolves share the id space); `None`: dead.
    bodies: Vec<Option<Animal>>,
    /// Newborns: (is a wolf, body).
    nursery: Vec<(bool, Animal)>,
    sheep: u32,
    wolves: u32,
    rng: Pcg64,
}

impl Field {
    fn cell(&self, x: i32, y: i32) -> usize {
        (y * self.p.side + x) as usize
    }
    fn leave(&mut self, id: u32, a: Animal) {
        let c = self.cell(a.x, a.y);
        if let Some(i) = self.flock[c].iter().position(|&s| s == id) {
            self.flock[c].swap_remove(i);
        }
    }
    fn walk(&mut self, a: Animal) -> Animal {
        let (dx, dy) = loop {
            let d = (self.rng.random_range(-1..=1), self.rng.random_range(-1..=1));
            if d != (0, 0) {
                break d;
            }
        };
        let s = self.p.side;
        Animal { x: (a.x + dx).rem_euclid(s), y: (a.y + dy).rem_euclid(s), energy: a.energy - 1.0 }
    }
    fn add(&mut self, wolf: bool, a: Animal, schedule: &mut Schedule, time: f32) {
        let id = self.bodies.len() as u32;
        self.bodies.push(Some(a));
        if wolf {
            self.wolves += 1;
            schedule.schedule_repeating(Box::new(Wolf { id }), time, 1);
        } else {
            self.sheep += 1;
            let c = self.cell(a.x, a.y);
            self.flock[c].push(id);
            schedule.schedule_repeating(Box::new(Sheep { id }), time, 0);
        }
    }
}

fn field(state: &mut dyn State) -> &mut Field {
    state.as_any_mut().downcast_mut::<Field>().expect("the WolfSheep state")
}

#[derive(Copy, Clone)]
struct Sheep {
    id: u32,
}

#[derive(Copy, Clone)]
struct Wolf {
    id: u32,
}

impl Agent for Sheep {
    fn step(&mut self, state: &mut dyn State) {
        let f = field(state);
        let Some(a) = f.bodies[self.id as usize] else { return };
        f.leave(self.id, a);
        let mut a = f.walk(a);
        let c = f.cell(a.x, a.y);
        if f.grass[c].0 {
            f.grass[c] = (false, f.p.regrowth);
            a.energy += 5.0;
        }
        if a.energy < 1.0 {
            f.bodies[self.id as usize] = None;
            f.sheep -= 1;
            return;
        }
        f.flock[c].push(self.id);
        if f.rng.random::<f64>() < f.p.sheep_reproduce {
            a.energy /= 2.0;
            f.nursery.push((false, a));
        }
        f.bodies[self.id as usize] = Some(a);
    }
    fn is_stopped(&mut self, state: &mut dyn State) -> bool {
        field(state).bodies[self.id as usize].is_none()
    }
}

impl Agent for Wolf {
    fn step(&mut self, state: &mut dyn State) {
        let f = field(state);
        let Some(a) = f.bodies[self.id as usize] else { return };
        let mut a = f.walk(a);
        let c = f.cell(a.x, a.y);
        let n = f.flock[c].len();
        if n > 0 {
            let prey = f.flock[c].swap_remove(f.rng.random_range(0..n));
            f.bodies[prey as usize] = None;
            f.sheep -= 1;
            a.energy += 13.0;
        }
        if a.energy < 0.0 {
            f.bodies[self.id as usize] = None;
            f.wolves -= 1;
            return;
        }
        if f.rng.random::<f64>() < f.p.wolf_reproduce {
            a.energy /= 2.0;
            f.nursery.push((true, a));
        }
        f.bodies[self.id as usize] = Some(a);
    }
    fn is_stopped(&mut self, state: &mut dyn State) -> bool {
        field(state).bodies[self.id as usize].is_none()
    }
}

impl State for Field {
    fn init(&mut self, schedule: &mut Schedule) {
        let p = self.p;
        for (wolf, n, gain) in [(false, p.sheep, 5.0), (true, p.wolves, 13.0)] {
            for _ in 0..n {
                let a = Animal {
                    x: self.rng.random_range(0..p.side),
                    y: self.rng.random_range(0..p.side),
                    energy: f64::from(self.rng.random_range(1..=(2.0 * gain) as u32)),
                };
                self.add(wolf, a, schedule, 0.0);
            }
        }
    }
    fn after_step(&mut self, schedule: &mut Schedule) {
        for g in self.grass.iter_mut().filter(|g| !g.0) {
            g.1 = g.1.saturating_sub(1);
            if g.1 == 0 {
                g.0 = true;
            }
        }
        let next = schedule.time + 1.0;
        for (wolf, a) in std::mem::take(&mut self.nursery) {
            self.add(wolf, a, schedule, next);
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

/// Runs the model of `size` with `seed` for 100 steps.
pub fn run(size: Size, seed: u64) -> Outcome {
    let p = match size {
        Size::Small => P { side: 25, sheep: 60, wolves: 40, regrowth: 20, sheep_reproduce: 0.2, wolf_reproduce: 0.1 },
        Size::Large => P { side: 100, sheep: 1000, wolves: 500, regrowth: 10, sheep_reproduce: 0.4, wolf_reproduce: 0.2 },
    };
    let cells = (p.side * p.side) as usize;
    let mut rng = Pcg64::seed_from_u64(seed);
    let grass = (0..cells)
        .map(|_| if rng.random::<bool>() { (true, 0) } else { (false, rng.random_range(1..=p.regrowth)) })
        .collect();
    let mut f = Field {
        p,
        grass,
        flock: vec![Vec::new(); cells],
        bodies: Vec::new(),
        nursery: Vec::new(),
        sheep: 0,
        wolves: 0,
        rng,
    };
    let mut schedule = Schedule::new();
    f.init(&mut schedule);
    let mut peak = f.sheep;
    for _ in 0..100 {
        schedule.step(&mut f);
        peak = peak.max(f.sheep);
    }
    Outcome::WolfSheep { sheep: f.sheep, wolves: f.wolves, peak }
}

//! Flocking with krABMaga: birds in its `Field2D` (double-buffered: a bird sees where its
//! neighbours were at the end of the last step; positions there are f32, so each bird keeps
//! its f64 position and velocity in the object it stores), scheduled by its `Schedule`.

use crate::{Outcome, Size};
use krabmaga::engine::agent::Agent;
use krabmaga::engine::fields::field::Field;
use krabmaga::engine::fields::field_2d::{Field2D, Location2D};
use krabmaga::engine::location::Real2D;
use krabmaga::engine::schedule::Schedule;
use krabmaga::engine::state::State;
use krabmaga::rand::{Rng, SeedableRng};
use krabmaga::rand_pcg::Pcg64;
use std::any::Any;
use std::fmt;
use std::hash::{Hash, Hasher};

#[derive(Copy, Clone)]
struct Params {
    extent: f64,
    birds: u32,
    visual: f64,
    speed: f64,
    cohere: f64,
    separation: f64,
    separate: f64,
    matching: f64,
}

fn params(size: Size) -> Params {
    let small = Params {
        extent: 100.0,
        birds: 200,
        visual: 5.0,
        speed: 1.0,
        cohere: 0.03,
        separation: 1.0,
        separate: 0.015,
        matching: 0.05,
    };
    match size {
        Size::Small => small,
        Size::Large => Params {
            extent: 150.0,
            birds: 400,
            visual: 15.0,
            ..small
        },
    }
}

#[derive(Copy, Clone)]
struct Bird {
    id: u32,
    pos: [f64; 2],
    vel: [f64; 2],
}

impl Hash for Bird {
    fn hash<H: Hasher>(&self, state: &mut H) {
        self.id.hash(state);
    }
}
impl PartialEq for Bird {
    fn eq(&self, o: &Bird) -> bool {
        self.id == o.id
    }
}
impl Eq for Bird {}
impl fmt::Display for Bird {
    fn fmt(&self, f: &mut fmt::Formatter) -> fmt::Result {
        write!(f, "bird {}", self.id)
    }
}
impl Location2D<Real2D> for Bird {
    fn get_location(self) -> Real2D {
        Real2D { x: self.pos[0] as f32, y: self.pos[1] as f32 }
    }
    fn set_location(&mut self, loc: Real2D) {
        self.pos = [f64::from(loc.x), f64::from(loc.y)];
    }
}

struct Sky {
    p: Params,
    field: Field2D<Bird>,
    seed: u64,
}

fn delta(e: f64, a: [f64; 2], b: [f64; 2]) -> [f64; 2] {
    let d = |x: f64| x - e * (x / e).round();
    [d(b[0] - a[0]), d(b[1] - a[1])]
}

impl Agent for Bird {
    fn step(&mut self, state: &mut dyn State) {
        let sky = state.as_any_mut().downcast_mut::<Sky>().expect("the flocking state");
        let p = sky.p;
        let near = sky
            .field
            .get_neighbors_within_relax_distance(self.get_location(), p.visual as f32);
        let (mut n, mut cohere, mut separate, mut matching) = (0.0, [0.0; 2], [0.0; 2], [0.0; 2]);
        for o in near.iter().filter(|o| o.id != self.id) {
            let h = delta(p.extent, self.pos, o.pos);
            let d = (h[0] * h[0] + h[1] * h[1]).sqrt();
            if d > p.visual {
                continue;
            }
            n += 1.0;
            for k in 0..2 {
                cohere[k] += h[k];
                matching[k] += o.vel[k];
                if d < p.separation {
                    separate[k] -= h[k];
                }
            }
        }
        let n = f64::max(n, 1.0);
        let mut v = [0.0; 2];
        for k in 0..2 {
            v[k] = (self.vel[k] + cohere[k] / n * p.cohere + separate[k] / n * p.separate
                + matching[k] / n * p.matching)
                / 2.0;
        }
        let norm = (v[0] * v[0] + v[1] * v[1]).sqrt();
        if norm > 0.0 {
            self.vel = [v[0] / norm, v[1] / norm];
        }
        let e = p.extent;
        let wrap = |x: f64| {
            let r = x - e * (x / e).floor();
            if r >= e { 0.0 } else { r }
        };
        self.pos = [wrap(self.pos[0] + self.vel[0] * p.speed), wrap(self.pos[1] + self.vel[1] * p.speed)];
        sky.field.set_object_location(*self, self.get_location());
    }
}

impl State for Sky {
    fn init(&mut self, schedule: &mut Schedule) {
        let mut rng = Pcg64::seed_from_u64(self.seed);
        let p = self.p;
        for id in 0..p.birds {
            let pos = [rng.random::<f64>() * p.extent, rng.random::<f64>() * p.extent];
            let vel = loop {
                let v = [rng.random::<f64>() * 2.0 - 1.0, rng.random::<f64>() * 2.0 - 1.0];
                let norm = (v[0] * v[0] + v[1] * v[1]).sqrt();
                if norm > 1e-9 {
                    break [v[0] / norm, v[1] / norm];
                }
            };
            let b = Bird { id, pos, vel };
            self.field.set_object_location(b, b.get_location());
            schedule.schedule_repeating(Box::new(b), 0.0, 0);
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
    fn update(&mut self, _step: u64) {
        self.field.lazy_update();
    }
}

/// Runs the model of `size` with `seed` for 100 steps.
pub fn run(size: Size, seed: u64) -> Outcome {
    let p = params(size);
    // Bags as wide as the visual distance; `false`: the bag search wraps around (krABMaga's
    // `toroidal = true` clamps it at the border instead).
    let field = Field2D::new(p.extent as f32, p.extent as f32, p.visual as f32, false);
    let mut sky = Sky { p, field, seed };
    let mut schedule = Schedule::new();
    sky.init(&mut schedule);
    for _ in 0..100 {
        schedule.step(&mut sky);
    }
    // Statistics from the birds as they are after the last step.
    let birds: Vec<Bird> = schedule
        .get_all_events()
        .into_iter()
        .filter_map(|a| a.downcast::<Bird>().ok().map(|b| *b))
        .collect();
    let (mut v, mut pairs) = ([0.0; 2], 0usize);
    for (i, a) in birds.iter().enumerate() {
        v[0] += a.vel[0];
        v[1] += a.vel[1];
        for b in &birds[i + 1..] {
            let h = delta(p.extent, a.pos, b.pos);
            if h[0] * h[0] + h[1] * h[1] <= p.visual * p.visual {
                pairs += 2;
            }
        }
    }
    let n = birds.len().max(1) as f64;
    Outcome::Flocking {
        polarisation: (v[0] * v[0] + v[1] * v[1]).sqrt() / n,
        neighbours: pairs as f64 / n,
    }
}

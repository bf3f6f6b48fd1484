//! Monte-Carlo evaluation of a patrol plan in the simulator: a `vitro` model with patrol units
//! that move by sampling their policies from their own random streams, convoys that follow
//! their timetables, and an attacker who watches the units and strikes.
//!
//! Time runs in steps of one simulated second. At step `k` (time `k` s) every unit moves from
//! its vertex by its policy's row for phase `k − 1` and every convoy moves to its scheduled
//! vertex; half a second later the attacker looks: the phase `k mod period` and where every
//! unit and convoy is ([`Watch`]), through sensors only. It knows the plan, so for what it sees
//! it knows the computed probability that an attack on each target started now is caught
//! (`1 − Π over units of (1 − unit's capture probability from its vertex)`). It plays its
//! [`AttackChoice`]s one at a time, in turn or at random ([`AttackOrder`]): for a choice
//! (target, phase or any phase, threshold) it waits until it sees that phase with the computed
//! capture probability at most the threshold, starts the attack, and watches the next
//! `deadline` steps: the attack is caught if a unit stands on the target's vertex at one of
//! them. Attacks change nothing in the world; the units do not know about them.
//!
//! [`worst_choices`] are the attacker's best replies per target and phase, [`best_replies`]
//! per target at any phase; a small slack on the threshold pools starts that are nearly as
//! good (each attack's computed probability is recorded, and the estimate is compared with
//! their mean). The estimates come with Hoeffding intervals, Bonferroni-split over the choices:
//! with probability at least `confidence`, every choice's mean computed capture probability
//! lies in its interval. Successive attacks are not independent draws (each starts where the
//! units happen to be), but given its start an attack's outcome is independent of the past
//! (the units are Markov), so the centred outcomes are martingale differences in `[−1, 1]`
//! of range 1 and the Azuma–Hoeffding bound is the same.

mod world;

use std::sync::Arc;

use serde::Serialize;
use vitro::prelude::*;
use vitro::rng::Owner;

use vitro_algo::graph::NodeId;
use vitro_algo::patrol::{Instance, PatrolError, PatrolPlan};

pub use world::{AttackChoice, AttackOrder, best_replies, worst_choices};
use world::{Attacker, STEP, tables};
pub use world::{PatrolAgent, PatrolEvent, PatrolModel, PatrolWorld, Sighting, Watch};

/// When the attacker looks, after the step's moves.
const LOOK: SimDuration = SimDuration::from_millis(500);

/// Settings for [`simulate`].
#[derive(Clone, Debug, PartialEq)]
pub struct SimOptions {
    /// Master seed of the simulation.
    pub seed: u64,
    /// Attacks per choice. Default 2 000.
    pub trials: u32,
    /// Simultaneous confidence level of all the intervals. Default 0.99.
    pub confidence: f64,
    /// The attacker's order. Default [`AttackOrder::InTurn`].
    pub order: AttackOrder,
    /// Steps an attacker waits for a choice's start before giving that attack up. Default
    /// 100 000.
    pub max_wait: u64,
    /// Steps simulated at most. Default 100 000 000.
    pub max_steps: u64,
}

impl Default for SimOptions {
    fn default() -> Self {
        SimOptions {
            seed: 0,
            trials: 2_000,
            confidence: 0.99,
            order: AttackOrder::InTurn,
            max_wait: 100_000,
            max_steps: 100_000_000,
        }
    }
}

/// The simulated outcome of one attack choice.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct ChoiceEstimate {
    /// The choice.
    pub choice: AttackChoice,
    /// Attacks made.
    pub trials: u32,
    /// Attacks caught.
    pub captures: u32,
    /// Attacks given up after waiting [`SimOptions::max_wait`] steps for the start.
    pub abandoned: u32,
    /// `captures / trials` (0 without trials).
    pub capture_probability: f64,
    /// The mean computed capture probability of the attacks made (0 without trials).
    pub computed: f64,
    /// Confidence interval for the capture probability.
    pub interval: (f64, f64),
}

/// The result of [`simulate`].
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct SimReport {
    /// One estimate per choice, in the order given.
    pub choices: Vec<ChoiceEstimate>,
    /// The attacker's best estimated gain: the largest `value_t · (1 − estimate)`.
    pub value: f64,
    /// Confidence interval for the mean computed value of the attacks made, choice by choice
    /// (holds together with the choices' intervals).
    pub value_interval: (f64, f64),
    /// Steps simulated.
    pub steps: u64,
    /// Events fired.
    pub events: u64,
    /// The run's trace hash (same seed, same hash).
    pub trace_hash: u64,
    /// Moves the world refused (a unit or convoy jumping): always 0 for valid plans.
    pub refused_moves: u64,
}

/// Plays `choices` against `plan` in the simulator (see the module docs).
///
/// # Errors
/// [`PatrolError::InvalidPolicy`] if the plan does not fit the instance (units, period),
/// [`PatrolError::InvalidInstance`] for bad options or choices.
pub fn simulate(
    instance: &Instance,
    plan: &PatrolPlan,
    choices: &[AttackChoice],
    options: &SimOptions,
) -> Result<SimReport, PatrolError> {
    let period = instance.period()?;
    if plan.units() != instance.patrollers.len() || plan.period != period {
        return Err(PatrolError::InvalidPolicy(
            "the plan was made for another instance".into(),
        ));
    }
    check(instance, plan, choices, options)?;
    let plan = Arc::new(plan.clone());
    let world = PatrolWorld {
        graph: plan.graph.clone(),
        at: EntityStorage::default(),
        units: Vec::new(),
        convoys: Vec::new(),
        period,
        refused: 0,
    };
    let mut sim = Simulation::<PatrolModel>::new(world, options.seed);
    let entity = |e: vitro::entity::EntityError| PatrolError::InvalidInstance(e.to_string());
    for unit in 0..plan.units() {
        let agent = PatrolAgent::Unit {
            plan: Arc::clone(&plan),
            unit,
        };
        let id = sim
            .add_agent(format!("unit{unit}"), agent)
            .map_err(entity)?;
        let mut rng = sim.rngs_mut().fresh(Owner::Entity(id), "start");
        let start = plan.start_vertex(unit, 0, &mut rng)?;
        sim.env_mut().at.insert(id, start);
        sim.env_mut().units.push(id);
    }
    for (t, target) in instance.targets.iter().enumerate() {
        let schedule: Vec<NodeId> = (0..period)
            .map(|step| target.position.at(step).unwrap_or(0))
            .collect();
        let start = schedule[0];
        let id = sim
            .add_agent(format!("convoy{t}"), PatrolAgent::Convoy { schedule })
            .map_err(entity)?;
        sim.env_mut().at.insert(id, start);
        sim.env_mut().convoys.push(id);
    }
    let attacker = Attacker {
        table: tables(instance, plan.as_ref())?,
        choices: choices.to_vec(),
        deadlines: instance
            .targets
            .iter()
            .map(|t| u64::from(t.deadline))
            .collect(),
        order: options.order,
        trials: options.trials,
        max_wait: options.max_wait,
        tally: vec![(0, 0, 0); choices.len()],
        computed: vec![0.0; choices.len()],
        waiting: None,
        open: None,
        turn: 0,
    };
    let attacker = sim
        .add_agent("attacker", PatrolAgent::Attacker(Box::new(attacker)))
        .map_err(entity)?;
    let schedule = |sim: &mut Simulation<PatrolModel>, at: SimTime, who: EntityId, e| {
        sim.schedule(at, Target::Entity(who), e)
            .map_err(|e| PatrolError::InvalidInstance(e.to_string()))
    };
    let movers: Vec<EntityId> = sim
        .env()
        .units
        .iter()
        .chain(&sim.env().convoys)
        .copied()
        .collect();
    for id in movers {
        schedule(&mut sim, SimTime::ZERO + STEP, id, PatrolEvent::Step)?;
    }
    schedule(&mut sim, SimTime::ZERO + LOOK, attacker, PatrolEvent::Look)?;
    let end =
        SimTime::ZERO + SimDuration::from_nanos(STEP.as_nanos().saturating_mul(options.max_steps));
    sim.run_until(end);
    let Some(PatrolAgent::Attacker(attacker)) = sim.agent(attacker) else {
        return Err(PatrolError::InvalidInstance("the attacker is gone".into()));
    };
    Ok(report(instance, attacker, &sim, options))
}

fn check(
    instance: &Instance,
    plan: &PatrolPlan,
    choices: &[AttackChoice],
    options: &SimOptions,
) -> Result<(), PatrolError> {
    let bad = |m: String| Err(PatrolError::InvalidInstance(m));
    if options.trials == 0 || !(options.confidence > 0.0 && options.confidence < 1.0) {
        return bad("simulation needs at least one trial and a confidence in (0, 1)".into());
    }
    if choices.is_empty() {
        return bad("no attack choices to play".into());
    }
    for (i, c) in choices.iter().enumerate() {
        if c.target >= instance.targets.len() || c.phase.is_some_and(|p| p >= plan.period.max(1)) {
            return bad(format!(
                "choice {i} names no target or phase of the instance"
            ));
        }
    }
    Ok(())
}

fn report(
    instance: &Instance,
    attacker: &Attacker,
    sim: &Simulation<PatrolModel>,
    options: &SimOptions,
) -> SimReport {
    let delta = (1.0 - options.confidence) / attacker.choices.len() as f64;
    let (mut value, mut lo, mut hi) = (0.0f64, 0.0f64, 0.0f64);
    let choices = attacker
        .choices
        .iter()
        .zip(&attacker.tally)
        .zip(&attacker.computed)
        .map(|((choice, &(trials, captures, abandoned)), &sum)| {
            let (p, computed, interval) = if trials == 0 {
                (0.0, 0.0, (0.0, 1.0))
            } else {
                let n = f64::from(trials);
                let p = f64::from(captures) / n;
                let half = libm::sqrt(libm::log(2.0 / delta) / (2.0 * n));
                (p, sum / n, ((p - half).max(0.0), (p + half).min(1.0)))
            };
            let worth = instance.targets[choice.target].value;
            value = value.max(worth * (1.0 - p));
            lo = lo.max(worth * (1.0 - interval.1));
            hi = hi.max(worth * (1.0 - interval.0));
            ChoiceEstimate {
                choice: choice.clone(),
                trials,
                captures,
                abandoned,
                capture_probability: p,
                computed,
                interval,
            }
        })
        .collect();
    SimReport {
        choices,
        value,
        value_interval: (lo, hi),
        steps: sim.now().as_nanos() / STEP.as_nanos(),
        events: sim.events_fired(),
        trace_hash: sim.trace_hash(),
        refused_moves: sim.env().refused,
    }
}

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

use std::sync::Arc;

use rand::Rng;
use serde::Serialize;
use vitro::prelude::*;
use vitro::rng::Owner;

use super::{Instance, PatrolError, PatrolPlan};
use crate::graph::{Graph, NodeId};

/// One step of the game in simulated time.
const STEP: SimDuration = SimDuration::from_secs(1);
/// When the attacker looks, after the step's moves.
const LOOK: SimDuration = SimDuration::from_millis(500);

/// What the attacker does: strike `target` when the phase is `phase` (any phase if `None`)
/// and the computed capture probability of an attack started now is at most `threshold`.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct AttackChoice {
    /// Index of the target in [`Instance::targets`].
    pub target: usize,
    /// The phase at which the attack starts, or any.
    pub phase: Option<usize>,
    /// The largest computed capture probability the attacker accepts.
    pub threshold: f64,
}

/// In which order the attacker plays its choices (one attack at a time).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize)]
pub enum AttackOrder {
    /// Choice 0, 1, 2, … and round again.
    InTurn,
    /// A choice drawn evenly from the attacker's own random stream each time.
    Random,
}

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

/// What the attacker knows: `table[t][i][φ]`, the vertices where unit `i` may be at phase
/// `φ`, ascending, with the computed probability that it catches an attack on target `t`
/// started then.
type Tables = Vec<Vec<Vec<Vec<(NodeId, f64)>>>>;

fn tables(instance: &Instance, plan: &PatrolPlan) -> Result<Tables, PatrolError> {
    let period = plan.period.max(1);
    let mut table = vec![vec![vec![Vec::new(); period]; plan.units()]; instance.targets.len()];
    for (i, policy) in plan.policies.iter().enumerate() {
        for a in policy.attacks(instance)? {
            table[a.target][i][a.phase % period].push((a.from, a.capture_probability));
        }
    }
    for per_unit in &mut table {
        for per_phase in per_unit {
            for row in per_phase {
                row.sort_by_key(|&(v, _)| v);
            }
        }
    }
    Ok(table)
}

/// The least computed capture probability of an attack on `t` at `phase` over every joint
/// start (each unit at its worst vertex).
fn least(table: &Tables, t: usize, phase: usize) -> f64 {
    let escape: f64 = table[t]
        .iter()
        .map(|unit| {
            unit[phase]
                .iter()
                .map(|&(_, p)| 1.0 - p.min(1.0))
                .fold(0.0, f64::max)
        })
        .product();
    1.0 - escape
}

/// The attacker's computed best replies for every target and phase: strike when the computed
/// capture probability is within `slack` of the least at that phase (by target, then phase).
///
/// # Errors
/// As for [`super::Policy::attacks`].
pub fn worst_choices(
    instance: &Instance,
    plan: &PatrolPlan,
    slack: f64,
) -> Result<Vec<AttackChoice>, PatrolError> {
    let table = tables(instance, plan)?;
    let period = plan.period.max(1);
    Ok((0..instance.targets.len() * period)
        .map(|k| {
            let (target, phase) = (k / period, k % period);
            AttackChoice {
                target,
                phase: Some(phase),
                threshold: least(&table, target, phase) + slack,
            }
        })
        .collect())
}

/// The attacker's computed best reply against each target at any phase: strike when the
/// computed capture probability is within `slack` of the least over every phase.
///
/// # Errors
/// As for [`super::Policy::attacks`].
pub fn best_replies(
    instance: &Instance,
    plan: &PatrolPlan,
    slack: f64,
) -> Result<Vec<AttackChoice>, PatrolError> {
    let table = tables(instance, plan)?;
    Ok((0..instance.targets.len())
        .map(|target| AttackChoice {
            target,
            phase: None,
            threshold: (0..plan.period.max(1))
                .map(|phase| least(&table, target, phase))
                .fold(1.0, f64::min)
                + slack,
        })
        .collect())
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
                let half = ((2.0 / delta).ln() / (2.0 * n)).sqrt();
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

/// The simulated world: where every unit and convoy is.
pub struct PatrolWorld {
    graph: Graph,
    /// Every mover's vertex.
    at: EntityStorage<NodeId>,
    units: Vec<EntityId>,
    convoys: Vec<EntityId>,
    period: usize,
    refused: u64,
}

/// The patrol model's events.
#[derive(Clone, Copy, Debug, Serialize)]
pub enum PatrolEvent {
    /// A unit or convoy moves.
    Step,
    /// The attacker looks.
    Look,
}

/// The patrol model (see the module docs).
pub struct PatrolModel;

impl Model for PatrolModel {
    type Env = PatrolWorld;
    type Event = PatrolEvent;
    type Msg = ();
    type Agent = PatrolAgent;

    fn state_digest(env: &PatrolWorld) -> u64 {
        env.at.digest()
    }
}

/// The step being played (at a step's moves) or looked at (half a step later).
fn step_of(now: SimTime) -> u64 {
    now.as_nanos() / STEP.as_nanos()
}

/// A mover's own vertex.
struct Here;
impl Sensor<PatrolWorld> for Here {
    type Reading = Option<NodeId>;
    fn read(&self, w: &PatrolWorld, me: EntityId, _: &mut Probe) -> Option<NodeId> {
        w.at.get(me).copied()
    }
}

/// What the attacker sees: the phase, every unit's vertex, every convoy's vertex.
pub struct Watch;

/// A [`Watch`] reading.
pub struct Sighting {
    /// The step's phase.
    pub phase: usize,
    /// Every unit's vertex, in unit order.
    pub units: Vec<NodeId>,
    /// Every convoy's vertex, in target order.
    pub convoys: Vec<NodeId>,
}

impl Sensor<PatrolWorld> for Watch {
    type Reading = Sighting;
    fn read(&self, w: &PatrolWorld, _: EntityId, probe: &mut Probe) -> Sighting {
        let where_ = |ids: &[EntityId]| -> Vec<NodeId> {
            ids.iter()
                .map(|&id| w.at.get(id).copied().unwrap_or(NodeId::MAX))
                .collect()
        };
        let period = w.period.max(1) as u64;
        Sighting {
            // Below the period, a usize.
            phase: (step_of(probe.now()) % period) as usize,
            units: where_(&w.units),
            convoys: where_(&w.convoys),
        }
    }
}

/// Why a move was refused.
#[derive(Debug, thiserror::Error)]
enum MoveError {
    #[error("no body")]
    NoBody,
    #[error("{from} -> {to} is not an edge")]
    NotAdjacent { from: NodeId, to: NodeId },
}

/// Moves a unit or convoy to a vertex: its own or a neighbour.
struct Drive;
impl Actuator<PatrolWorld, PatrolEvent> for Drive {
    type Command = NodeId;
    type Error = MoveError;
    fn actuate(
        &self,
        w: &mut PatrolWorld,
        me: EntityId,
        to: NodeId,
        _: &mut Effects<PatrolEvent>,
    ) -> Result<(), MoveError> {
        let Some(&from) = w.at.get(me) else {
            w.refused += 1;
            return Err(MoveError::NoBody);
        };
        if from != to && !w.graph.has_edge(from, to) {
            w.refused += 1;
            return Err(MoveError::NotAdjacent { from, to });
        }
        if from != to {
            w.at.insert(me, to);
        }
        Ok(())
    }
}

/// The agents of the patrol model.
pub enum PatrolAgent {
    /// A patrol unit following its plan.
    Unit {
        /// The plan.
        plan: Arc<PatrolPlan>,
        /// Which unit of the plan.
        unit: usize,
    },
    /// A convoy on its timetable.
    Convoy {
        /// Its vertex at every step of the period.
        schedule: Vec<NodeId>,
    },
    /// The attacker.
    Attacker(Box<Attacker>),
}

/// The attacker's state (see the module docs).
pub struct Attacker {
    /// What it knows of the plan.
    table: Tables,
    choices: Vec<AttackChoice>,
    deadlines: Vec<u64>,
    order: AttackOrder,
    trials: u32,
    max_wait: u64,
    /// Per choice: attacks made, caught, given up.
    tally: Vec<(u32, u32, u32)>,
    /// Per choice: the sum of the attacks' computed capture probabilities.
    computed: Vec<f64>,
    /// The choice waited for, and since which step.
    waiting: Option<(usize, u64)>,
    /// The attack under way: choice, start step, computed capture probability.
    open: Option<(usize, u64, f64)>,
    /// The next choice in turn.
    turn: usize,
}

impl Agent<PatrolModel> for PatrolAgent {
    fn handle(&mut self, input: Input<'_, PatrolModel>, cx: &mut Context<'_, PatrolModel>) {
        let Input::Event(event) = input else {
            return;
        };
        match (self, event) {
            (PatrolAgent::Unit { plan, unit }, PatrolEvent::Step) => {
                if let Some(here) = cx.sense(&Here) {
                    let phase = plan.phase(step_of(cx.now()).saturating_sub(1));
                    let next = plan.next_vertex(*unit, here, phase, cx.rng("patrol"));
                    // A refused move is counted by the world; the unit stays.
                    let _ = cx.act(&Drive, next.unwrap_or(here));
                }
                cx.schedule_in(STEP, Target::Entity(cx.me()), PatrolEvent::Step);
            }
            (PatrolAgent::Convoy { schedule }, PatrolEvent::Step) => {
                let len = schedule.len().max(1) as u64;
                // Below the schedule's length, a usize.
                let i = (step_of(cx.now()) % len) as usize;
                if let Some(&to) = schedule.get(i) {
                    let _ = cx.act(&Drive, to);
                }
                cx.schedule_in(STEP, Target::Entity(cx.me()), PatrolEvent::Step);
            }
            (PatrolAgent::Attacker(attacker), PatrolEvent::Look) => {
                if attacker.look(cx) {
                    cx.schedule_in(STEP, Target::Entity(cx.me()), PatrolEvent::Look);
                } else {
                    cx.request_stop();
                }
            }
            _ => {}
        }
    }
}

impl Attacker {
    /// One look at the world; false once every choice has its trials.
    fn look(&mut self, cx: &mut Context<'_, PatrolModel>) -> bool {
        let step = step_of(cx.now());
        let seen = cx.sense(&Watch);
        if let Some((c, start, computed)) = self.open {
            let t = self.choices[c].target;
            let caught = seen.units.contains(&seen.convoys[t]);
            if caught || step - start >= self.deadlines[t] {
                self.tally[c].0 += 1;
                self.tally[c].1 += u32::from(caught);
                self.computed[c] += computed;
                self.open = None;
            }
        }
        if self.open.is_some() {
            return true;
        }
        if self.waiting.is_none() {
            let Some(c) = self.pick(cx) else {
                return false;
            };
            self.waiting = Some((c, step));
        }
        let Some((c, since)) = self.waiting else {
            return true;
        };
        let choice = &self.choices[c];
        let computed = self.computed_capture(choice.target, seen.phase, &seen.units);
        let ready = choice.phase.is_none_or(|p| p == seen.phase)
            && computed.is_some_and(|p| p <= choice.threshold);
        if let (true, Some(p)) = (ready, computed) {
            self.open = Some((c, step, p));
            self.waiting = None;
        } else if step - since >= self.max_wait {
            self.tally[c].2 += 1;
            self.waiting = None;
        }
        true
    }

    /// The computed probability that an attack on `t` started now is caught, with the units
    /// at `units` at `phase` (`None` if a unit is off its plan's states).
    fn computed_capture(&self, t: usize, phase: usize, units: &[NodeId]) -> Option<f64> {
        let mut escape = 1.0;
        for (i, &at) in units.iter().enumerate() {
            let row = self.table.get(t)?.get(i)?.get(phase)?;
            let k = row.binary_search_by_key(&at, |&(v, _)| v).ok()?;
            escape *= 1.0 - row[k].1.min(1.0);
        }
        Some(1.0 - escape)
    }

    /// The next choice to play, if any still needs trials.
    fn pick(&mut self, cx: &mut Context<'_, PatrolModel>) -> Option<usize> {
        let k = self.choices.len();
        let needs = |tally: &(u32, u32, u32)| tally.0 + tally.2 < self.trials;
        let open: Vec<usize> = (0..k).filter(|&c| needs(&self.tally[c])).collect();
        if open.is_empty() {
            return None;
        }
        match self.order {
            AttackOrder::InTurn => {
                let c = (0..k)
                    .map(|i| (self.turn + i) % k)
                    .find(|&c| needs(&self.tally[c]))?;
                self.turn = c + 1;
                Some(c)
            }
            AttackOrder::Random => Some(open[cx.rng("attack").random_range(0..open.len())]),
        }
    }
}

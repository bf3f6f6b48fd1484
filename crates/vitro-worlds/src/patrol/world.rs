//! The simulated world: where every unit and convoy is, the sensors and the actuator that
//! reach it, and the agents.
//!
//! The attacker lives here too: the model names it as one of its agents, and it plays against
//! the model's sensors, so the two cannot be split without an import circle.

use rand::Rng;
use serde::Serialize;
use std::sync::Arc;
use vitro::prelude::*;
use vitro_algo::graph::{Graph, NodeId};
use vitro_algo::patrol::{Instance, PatrolError, PatrolPlan};

/// One step of the patrol clock.
pub(super) const STEP: SimDuration = SimDuration::from_secs(1);

/// The simulated world: where every unit and convoy is.
pub struct PatrolWorld {
    pub(super) graph: Graph,
    /// Every mover's vertex.
    pub(super) at: EntityStorage<NodeId>,
    pub(super) units: Vec<EntityId>,
    pub(super) convoys: Vec<EntityId>,
    pub(super) period: usize,
    pub(super) refused: u64,
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
pub(super) fn step_of(now: SimTime) -> u64 {
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
                cx.schedule_in(STEP, PatrolEvent::Step);
            }
            (PatrolAgent::Convoy { schedule }, PatrolEvent::Step) => {
                let len = schedule.len().max(1) as u64;
                // Below the schedule's length, a usize.
                let i = (step_of(cx.now()) % len) as usize;
                if let Some(&to) = schedule.get(i) {
                    let _ = cx.act(&Drive, to);
                }
                cx.schedule_in(STEP, PatrolEvent::Step);
            }
            (PatrolAgent::Attacker(attacker), PatrolEvent::Look) => {
                if attacker.look(cx) {
                    cx.schedule_in(STEP, PatrolEvent::Look);
                } else {
                    cx.request_stop();
                }
            }
            _ => {}
        }
    }
}

/// What the attacker does: strike `target` when the phase is `phase` (any phase if `None`)
/// and the computed capture probability of an attack started now is at most `threshold`.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct AttackChoice {
    /// Index of the target in [`Instance::targets`](vitro_algo::patrol::Instance::targets).
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

/// What the attacker knows: `table[t][i][φ]`, the vertices where unit `i` may be at phase
/// `φ`, ascending, with the computed probability that it catches an attack on target `t`
/// started then.
pub(super) type Tables = Vec<Vec<Vec<Vec<(NodeId, f64)>>>>;

pub(super) fn tables(instance: &Instance, plan: &PatrolPlan) -> Result<Tables, PatrolError> {
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
/// As for [`Policy::attacks`](vitro_algo::patrol::Policy::attacks).
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
/// As for [`Policy::attacks`](vitro_algo::patrol::Policy::attacks).
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

/// The attacker's state (see the module docs).
pub struct Attacker {
    /// What it knows of the plan.
    pub(super) table: Tables,
    pub(super) choices: Vec<AttackChoice>,
    pub(super) deadlines: Vec<u64>,
    pub(super) order: AttackOrder,
    pub(super) trials: u32,
    pub(super) max_wait: u64,
    /// Per choice: attacks made, caught, given up.
    pub(super) tally: Vec<(u32, u32, u32)>,
    /// Per choice: the sum of the attacks' computed capture probabilities.
    pub(super) computed: Vec<f64>,
    /// The choice waited for, and since which step.
    pub(super) waiting: Option<(usize, u64)>,
    /// The attack under way: choice, start step, computed capture probability.
    pub(super) open: Option<(usize, u64, f64)>,
    /// The next choice in turn.
    pub(super) turn: usize,
}

impl Attacker {
    /// One look at the world; false once every choice has its trials.
    pub(super) fn look(&mut self, cx: &mut Context<'_, PatrolModel>) -> bool {
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

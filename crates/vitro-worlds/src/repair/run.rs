//! One run: builds the simulation, executes the plan, and reports what happened.

use std::fmt;
use std::sync::Arc;

use vitro::comm::Protocol;
use vitro::entity::EntityId;
use vitro::event::Target;
use vitro::sim::Simulation;
use vitro::time::{SimDuration, SimTime};

use super::record::{Applied, RepairRecord, RunFailure};

use super::agent::RepairModel;
use super::agent::{Settings, Worker};
use super::world::{Ev, World};
use super::{PLAN_PROTOCOL, RepairConfig, RunError, TURN_PROTOCOL};
use vitro_algo::repair::Scenario;

/// Messages sent in a run, per protocol (a message to n agents counts n).
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq)]
pub struct MessageTally {
    /// Turn passing ([`TURN_PROTOCOL`]).
    pub turns: u64,
    /// State queries and their answers (the core's query protocol).
    pub queries: u64,
    /// Repaired plans ([`PLAN_PROTOCOL`]).
    pub plans: u64,
}

impl MessageTally {
    /// All messages.
    pub fn total(&self) -> u64 {
        self.turns + self.queries + self.plans
    }
}

/// What happened in one run.
#[derive(Debug, Clone)]
pub struct RunReport {
    /// Reached the goal, or why not.
    pub outcome: Result<(), RunFailure>,
    /// Every change of the world, in order.
    pub log: Vec<Applied>,
    /// Actions the agents executed (failed ones included).
    pub executed: usize,
    /// Failures the agents detected.
    pub detected: usize,
    /// Steps skipped because a precondition was false (lazy execution).
    pub skipped: usize,
    /// The repairs, in order.
    pub repairs: Vec<RepairRecord>,
    /// Messages sent.
    pub messages: MessageTally,
    /// States expanded by all repairs.
    pub expanded: u64,
    /// Simulated planning time of all repairs.
    pub planning_time: SimDuration,
    /// When the run ended.
    pub end_time: SimTime,
    /// The trace hash of the run.
    pub trace_hash: u64,
}

impl RunReport {
    /// Whether the goal was reached.
    pub fn succeeded(&self) -> bool {
        self.outcome.is_ok()
    }
    /// The ground actions that changed the world, in order (slips and disturbances
    /// included): a valid plan from the initial state whenever the run succeeded.
    pub fn applied(&self) -> Vec<&str> {
        self.log.iter().filter_map(Applied::applied).collect()
    }
    /// Executions that failed.
    pub fn failures(&self) -> usize {
        self.log.iter().filter(|a| a.is_failure()).count()
    }
    /// Repair searches cut by the expansion bound.
    pub fn truncated_searches(&self) -> usize {
        self.repairs.iter().filter(|r| r.truncated).count()
    }
}

impl fmt::Display for RunReport {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match &self.outcome {
            Ok(()) => write!(f, "goal reached")?,
            Err(e) => write!(f, "failed: {e}")?,
        }
        write!(
            f,
            " at {:.1} s: {} actions executed ({} failed, {} skipped), {} repairs, {} messages, \
             {} states expanded",
            self.end_time.as_secs_f64(),
            self.executed,
            self.failures(),
            self.skipped,
            self.repairs.len(),
            self.messages.total(),
            self.expanded
        )?;
        let cut = self.truncated_searches();
        if cut > 0 {
            write!(f, "; the expansion bound cut {cut} repair search(es)")?;
        }
        Ok(())
    }
}

/// Executes the scenario's joint plan once with `config`, from master seed `seed`.
///
/// # Errors
/// [`RunError::Probability`] or [`RunError::ZeroPeriod`] for an invalid configuration.
pub fn run(scenario: &Scenario, config: &RepairConfig, seed: u64) -> Result<RunReport, RunError> {
    let probability = |what, value: f64| {
        if (0.0..=1.0).contains(&value) {
            Ok(())
        } else {
            Err(RunError::Probability { what, value })
        }
    };
    probability("failure_probability", config.failure_probability)?;
    if let Some(d) = config.disturbance {
        probability("disturbance probability", d.probability)?;
        if d.period == SimDuration::ZERO {
            return Err(RunError::ZeroPeriod);
        }
    }
    let team = Arc::clone(scenario.team());
    let world = World::new(
        Arc::clone(&team),
        config.failure_probability,
        config.disturbance,
    );
    let mut sim = Simulation::<RepairModel>::new(world, seed);
    sim.network_mut().set_default_link(config.link);
    // Entities are numbered in creation order: agent i is entity i of this fresh simulation.
    let peers: Vec<EntityId> = (0..team.agents.len() as u32).map(EntityId).collect();
    let settings = Arc::new(Settings {
        strategy: config.strategy,
        action_time: config.action_time,
        cost: config.cost,
        max_expansions: config.max_expansions,
        max_repairs: config.max_repairs,
        answer_deadline: config.answer_deadline,
        peers: peers.clone(),
    });
    for (i, name) in team.agents.iter().enumerate() {
        let worker = Worker::new(i, Arc::clone(&team), Arc::clone(&settings));
        let id = sim
            .add_agent(name.clone(), worker)
            .map_err(|_| RunError::DuplicateAgent(name.clone()))?;
        debug_assert_eq!(id, peers[i]);
        sim.env_mut().embody(id, i);
    }
    let first = team.plan.first().map_or(0, |&a| team.owner[a as usize]);
    let start = Target::Entity(peers[first]);
    sim.schedule(SimTime::ZERO, start, Ev::Start)?;
    if let Some(d) = config.disturbance {
        sim.schedule(SimTime::ZERO + d.period, Target::Env, Ev::Disturb)?;
    }
    sim.run_until(config.time_limit);
    Ok(report(&sim, &peers))
}

fn report(sim: &Simulation<RepairModel>, peers: &[EntityId]) -> RunReport {
    let workers: Vec<&Worker> = peers.iter().filter_map(|&p| sim.agent(p)).collect();
    let outcome = workers
        .iter()
        .find_map(|w| w.tally.outcome.clone())
        .unwrap_or(Err(RunFailure::TimeLimit));
    let mut repairs: Vec<RepairRecord> = workers
        .iter()
        .flat_map(|w| w.tally.repairs.iter().cloned())
        .collect();
    repairs.sort_by_key(|r| r.time);
    let mut messages = MessageTally::default();
    for (_, protocol, counts) in sim.network().all_counts() {
        match protocol {
            p if p == TURN_PROTOCOL => messages.turns += counts.sent,
            p if p == PLAN_PROTOCOL => messages.plans += counts.sent,
            Protocol::Query => messages.queries += counts.sent,
            _ => {}
        }
    }
    RunReport {
        outcome,
        log: sim.env().log().to_vec(),
        executed: workers.iter().map(|w| w.tally.executed).sum(),
        detected: workers.iter().map(|w| w.tally.detected).sum(),
        skipped: workers.iter().map(|w| w.tally.skipped).sum(),
        expanded: repairs.iter().map(|r| r.expanded).sum(),
        planning_time: repairs
            .iter()
            .fold(SimDuration::ZERO, |t, r| t + r.planning_time),
        repairs,
        messages,
        end_time: sim.now(),
        trace_hash: sim.trace_hash(),
    }
}

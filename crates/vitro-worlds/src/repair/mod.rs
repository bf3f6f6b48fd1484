//! Multi-agent plans executed in the simulator, and their decentralized repair: the
//! dock-worker world where the repair strategies of `vitro_algo::repair` are compared.
//!
//! A [`Scenario`](vitro_algo::repair::Scenario) is a PDDL problem whose ground actions each
//! belong to an agent (by default the object of the action's first parameter: in the
//! dock-worker domain each robot and each crane is an agent, see
//! [`Ownership`](vitro_algo::repair::Ownership)), and a joint plan. [`run`] executes the
//! plan in a vitro [`Simulation`](vitro::sim::Simulation):
//!
//! - **World.** The environment holds the ground state in a storage. Agents read it only
//!   through a sensor that shows each agent its *view*: the facts its own actions read or
//!   write. Nobody sees the whole state. They change it only through an actuator that
//!   executes one of their own actions.
//! - **Execution.** Steps run in plan order. The owner of a step checks its preconditions
//!   (all within its view), acts, waits the action's duration, checks the effects, and
//!   passes the turn to the next step's owner with a message (protocol
//!   [`TURN_PROTOCOL`]). Consecutive steps of one agent need no message.
//! - **Failures.** With probability `p` (drawn from the acting agent's random stream
//!   `"failure"`) an action *slips*: instead of the intended action, the agent carries out
//!   another of its own actions applicable at that moment, drawn uniformly from the same
//!   stream (a crane puts the container on the wrong pile, a robot drives to the wrong
//!   place). If it has no other applicable action, the action has no effect. Optionally the
//!   world also changes under the agents: every `period`, with probability `q`, the
//!   environment applies an applicable action of any agent, drawn from its own stream
//!   ([`Disturbance`]).
//! - **Detection.** The acting agent notices a failure when its view after the action
//!   differs from its view before plus the action's effects, or when a precondition of its
//!   next step is false; at the end of the plan, the last agent checks the goal.
//! - **Repair.** The agent that detects the failure becomes the repairer. It asks every
//!   other agent for its view (the core's query protocol, one question and one answer per
//!   agent), plans (charged as simulated time through a [`CostModel`] per state expanded:
//!   greedy best-first search with FF, optionally bounded, see
//!   [`RepairConfig::max_expansions`]), sends the new plan to the agents that own steps of
//!   it they do not know yet (protocol [`PLAN_PROTOCOL`]), and resumes execution.
//!
//! The strategies ([`Strategy`]) differ in what the repairer plans for and when:
//! - [`Replan`](Strategy::Replan): at every failure, a new plan from the current state to
//!   the goal, sent to every agent that owns a step of it.
//! - [`BackOnTrack`](Strategy::BackOnTrack): at every failure, a plan from the current state
//!   back to the state the plan expected after the failed step (its true facts), followed by
//!   the rest of the old plan. Only the owners of the new prefix are told: the others keep
//!   the rest of the plan they already know. If no such plan is found (none exists, or the
//!   bound cut the search), it falls back to replanning.
//! - [`Lazy`](Strategy::Lazy): failures of the original plan are not repaired at once: the
//!   agents go on with every step that still applies and skip the others; at the end of the
//!   plan, one repair plans from the state reached to the goal. Failures of that repair plan
//!   are handled by replanning (the lazy repair is made once).
//! - [`RepeatedLazy`](Strategy::RepeatedLazy): every plan, repair plans included, is
//!   executed lazily, and a lazy repair is made each time a plan ends short of the goal.
//!
//! Every run is reproducible: same scenario, configuration and seed give the same trace hash.
//!
//! ```
//! use vitro_algo::planning::PddlSource;
//! use vitro_algo::repair::{Ownership, Scenario, Strategy};
//! use vitro_worlds::repair::{RepairConfig, run};
//!
//! let domain = "(define (domain lift) (:predicates (at ?w ?f) (adj ?a ?b))
//!   (:action go :parameters (?w ?a ?b) :precondition (and (at ?w ?a) (adj ?a ?b))
//!    :effect (and (at ?w ?b) (not (at ?w ?a)))))";
//! let problem = "(define (problem p) (:domain lift) (:objects ann bob f0 f1 f2)
//!   (:init (at ann f0) (at bob f2) (adj f0 f1) (adj f1 f0) (adj f1 f2) (adj f2 f1))
//!   (:goal (and (at ann f2) (at bob f0))))";
//! let scenario = Scenario::from_pddl(
//!     PddlSource::new("lift.pddl", domain),
//!     PddlSource::new("p.pddl", problem),
//!     &Ownership::first_parameter(),
//! )?;
//! let config = RepairConfig { strategy: Strategy::BackOnTrack, failure_probability: 0.3,
//!                             ..RepairConfig::default() };
//! let report = run(&scenario, &config, 7)?;
//! assert!(report.succeeded());
//! # Ok::<(), vitro_worlds::repair::RunError>(())
//! ```

mod agent;
mod record;
mod run;
mod world;

use thiserror::Error;
use vitro::comm::{LinkParams, Protocol};
use vitro::sim::CostModel;
use vitro::time::{SimDuration, SimTime};
use vitro_algo::repair::{RepairError, Strategy};

pub use record::{Applied, AppliedKind, RepairRecord, RunFailure, Trigger};
pub use run::{MessageTally, RunReport, run};

/// The protocol of the messages that pass the turn from one step's owner to the next.
pub const TURN_PROTOCOL: Protocol = Protocol::Custom(1);
/// The protocol of the messages that distribute a repaired plan.
pub const PLAN_PROTOCOL: Protocol = Protocol::Custom(2);

/// Changes of the world that no agent made: every `period`, with `probability`, the
/// environment applies an action applicable at that moment, drawn uniformly from all
/// actions of all agents (its own random stream `"disturbance"`).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Disturbance {
    /// Time between two draws.
    pub period: SimDuration,
    /// Probability that a draw changes the world, in `[0, 1]`.
    pub probability: f64,
}

/// The settings of one run.
#[derive(Debug, Clone, PartialEq)]
pub struct RepairConfig {
    /// How failures are repaired.
    pub strategy: Strategy,
    /// Probability that an executed action slips, in `[0, 1]`.
    pub failure_probability: f64,
    /// Optional exogenous changes of the world.
    pub disturbance: Option<Disturbance>,
    /// Simulated duration of one action.
    pub action_time: SimDuration,
    /// Simulated cost of planning, per state expanded.
    pub cost: CostModel,
    /// Bound on the states one repair search may expand (the conservative adaptation that
    /// keeps repairs tractable). A cut search counts as finding no plan, and is reported
    /// ([`RepairRecord::truncated`], [`RunReport::truncated_searches`]).
    pub max_expansions: Option<u64>,
    /// The run fails after this many repairs.
    pub max_repairs: u32,
    /// How long a repairer waits for an answer before the run fails.
    pub answer_deadline: SimDuration,
    /// The run fails if it has not ended by then.
    pub time_limit: SimTime,
    /// Parameters of every link of the network.
    pub link: LinkParams,
}

impl Default for RepairConfig {
    /// Replanning, no failures, 10 s actions, planning at 50 ms + 2 ms per state expanded,
    /// no search bound, at most 100 repairs, 60 s answer deadline, one simulated day, a
    /// perfect 1 ms network.
    fn default() -> Self {
        RepairConfig {
            strategy: Strategy::Replan,
            failure_probability: 0.0,
            disturbance: None,
            action_time: SimDuration::from_secs(10),
            cost: CostModel {
                base: SimDuration::from_millis(50),
                per_unit: SimDuration::from_millis(2),
            },
            max_expansions: None,
            max_repairs: 100,
            answer_deadline: SimDuration::from_secs(60),
            time_limit: SimTime::from_secs(24 * 3600),
            link: LinkParams::default(),
        }
    }
}

/// Why a run could not be started.
#[derive(Debug, Error)]
pub enum RunError {
    /// The scenario could not be built.
    #[error(transparent)]
    Repair(#[from] RepairError),
    /// A probability outside `[0, 1]`.
    #[error("{what} must be a probability in [0, 1], found {value}")]
    Probability {
        /// Which setting.
        what: &'static str,
        /// The value given.
        value: f64,
    },
    /// A disturbance period of zero.
    #[error("the disturbance period must be positive")]
    ZeroPeriod,
    /// Two agents with one name.
    #[error("two agents are named {0}")]
    DuplicateAgent(String),
    /// An event could not be scheduled.
    #[error(transparent)]
    Schedule(#[from] vitro::event::ScheduleError),
}

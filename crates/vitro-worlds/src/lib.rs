//! # vitro-worlds: synthetic worlds where the algorithms run as agents
//!
//! The algorithms of `vitro-algo` know nothing of simulated time, storages or the radio. Here
//! each is put in a small world of its own, a `vitro` simulation whose agents play it through
//! sensors, actuators and messages, so that its claims can be measured where agents see only
//! what they sense and talk with delay and loss:
//!
//! | module | the world | the algorithm it runs |
//! |---|---|---|
//! | [`patrol`] | patrol units that sample their policies, convoys on their timetables, an attacker who watches and strikes | the patrolling game (`vitro_algo::patrol`): capture probabilities with confidence intervals |
//! | [`repair`] | the dock-worker world: each agent owns its actions, sees only its view, and passes the turn by message; actions slip | plan repair (`vitro_algo::repair`): strategies compared on messages and repairs |
//! | [`rules`] | any `vitro` model: a rule-programmed agent with modules bound to its sensors and actuators | the rule language (`vitro_algo::rules`) |
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
//! // Actions slip three times in ten; the team repairs back onto its plan and still arrives.
//! let config = RepairConfig { strategy: Strategy::BackOnTrack, failure_probability: 0.3,
//!                             ..RepairConfig::default() };
//! let report = run(&scenario, &config, 7)?;
//! assert!(report.succeeded());
//! # Ok::<(), vitro_worlds::repair::RunError>(())
//! ```

pub mod patrol;
pub mod repair;
pub mod rules;

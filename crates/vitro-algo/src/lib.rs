//! # vitro-algo: the algorithms agents think with
//!
//! Domain-independent algorithms for Vitro: classical planning and the algorithms the
//! tactical simulator builds on. None of them knows about simulated time, storages or the
//! radio: a controller calls them while it deliberates (and charges the work to simulated
//! time through a `vitro::sim::CostModel`), so each can be tested, benchmarked and reused on
//! its own.
//!
//! | module | what | used in the evacuation mission by |
//! |---|---|---|
//! | [`graph`] | undirected graphs: edge lists, generators (path, cycle, grid, tree, Petersen, ...) | the games below; synthetic worlds |
//! | [`cops`] | exact cops and robber: cop numbers and strategies | (not the mission: `vitro solve cops` and the graphs in `data/graphs`) |
//! | [`planning`] | PDDL: parser, grounder, A* with LM-cut, GBFS with FF, plan validator | the Vidar team's cover plan |
//! | [`repair`] | multi-agent plan repair: replan, back-on-track, lazy, repeated lazy | the lead Vidar, as the team moves |
//! | [`patrol`] | patrolling security games (static and moving targets), solved by linear programming | the Skeldar's randomized patrol |
//! | [`pursuit`] | visibility-based pursuit–evasion: IS-MCTS, iterative-deepening minimax | the HVT hunt, both sides |
//! | [`rules`] | a rule language (`when <query> then <update>`, modules, nested rules) | troop formations |
//!
//! ## Three of them in a few lines
//!
//! ```
//! use rand::SeedableRng;
//! use vitro_algo::cops::{cop_number, CopOptions};
//! use vitro_algo::graph;
//! use vitro_algo::planning::{solve, PddlSource, Planner};
//! use vitro_algo::pursuit::{play, Arena, FleeingEvader, FullVisibility, GreedyPursuers};
//!
//! // How many cops catch a robber on a 3 x 4 grid of streets? Two.
//! let streets = graph::grid(3, 4)?;
//! assert_eq!(cop_number(&streets, &CopOptions::default())?.cop_number, 2);
//!
//! // A plan: switch both lights on, optimally.
//! let domain = "(define (domain lights) (:predicates (on ?l) (off ?l))
//!   (:action switch :parameters (?l) :precondition (off ?l)
//!    :effect (and (on ?l) (not (off ?l)))))";
//! let problem = "(define (problem two) (:domain lights) (:objects a b)
//!   (:init (off a) (off b)) (:goal (and (on a) (on b))))";
//! let plan = solve(
//!     PddlSource::new("lights.pddl", domain),
//!     PddlSource::new("two.pddl", problem),
//!     Planner::Optimal,
//! )?;
//! assert_eq!(plan.plan, ["(switch a)", "(switch b)"]);
//!
//! // A chase on a path of 8 junctions: a greedy pursuer from one end catches a fleeing
//! // evader at the other (randomness only from the caller's seeded generator).
//! let arena = Arena::new(graph::path(8)?, &FullVisibility)?;
//! let mut rng = rand_chacha::ChaCha8Rng::seed_from_u64(1);
//! let chase = play(&arena, &[0], 7, &mut GreedyPursuers, &mut FleeingEvader, 50, &mut rng)?;
//! assert!(chase.captured_at.is_some());
//! # Ok::<(), Box<dyn std::error::Error>>(())
//! ```
//!
//! The synthetic worlds where these algorithms run as agents of a `vitro` simulation (a
//! patrol against an attacker, a team executing and repairing a plan, rule-programmed
//! agents) are the crate above, `vitro-worlds`. The guide (`docs/guide`) shows a controller
//! on the tactical world; its Part 1 uses [`graph::grid`] as the streets of a synthetic town.

pub mod cops;
pub mod graph;
pub mod patrol;
pub mod planning;
pub mod pursuit;
pub mod repair;
pub mod rules;
pub mod scc;

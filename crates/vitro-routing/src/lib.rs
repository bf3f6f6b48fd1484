//! Vehicle routing and task allocation for Vitro: the capacitated vehicle routing problem with
//! time windows (CVRP, CVRPTW), solved centrally or by a simulated distributed auction.
//!
//! An [`Instance`] is a depot (node 0), customers with demands and (Solomon) time windows —
//! ready time, due time, service time: a vehicle arriving early waits, one arriving late is
//! infeasible — and a fleet of vehicles of one capacity. [`solve`] answers it with a
//! [`Solution`]: routes, their total length, and the customers no vehicle could serve. The
//! [`Solver`] is a plain value, so a mission picks one by configuration:
//!
//! - [`Solver::Savings`]: Clarke & Wright's savings construction (1964): fast, a few percent
//!   above the best.
//! - [`Solver::LocalSearch`]: the savings solution improved by a large neighbourhood search
//!   (Shaw 1998; Ropke & Pisinger 2006: random and related removal, regret insertion) with
//!   record-to-record acceptance (Dueck 1993), each step followed by 2-opt, relocate, swap and
//!   2-opt* (Potvin & Rousseau 1995). Anytime: `budget` iterations, the best solution found is
//!   returned.
//! - [`Solver::Auction`]: sequential single-item auctions (Koenig et al., AAAI 2006): each
//!   vehicle bids its marginal insertion cost, the lowest bid wins; the rounds and messages a
//!   radio would carry are counted in [`Stats`].
//!
//! Everything is deterministic: the same instance, solver and seed give the same solution, bit
//! for bit (the random numbers are a seeded ChaCha8 stream; no platform maths is used).
//!
//! [`parse()`] reads the standard text formats: CVRPLIB `.vrp` (TSPLIB `EUC_2D`, with the rounded
//! distances its best-known values assume) and Solomon's VRPTW files.
//!
//! Crates looked at first: `vrp-core`/`vrp-solver` (reinterpreter/vrp) is a rich-VRP framework
//! with its own problem model and a large dependency tree; `routik-solver` 0.1 is a first
//! release; `solverforge-cvrp` is domain helpers for its own constraint-solver framework. None
//! fitted a small, seed-deterministic core crate, so the solvers here are written from the
//! papers cited.
//!
//! ```
//! use vitro_routing::{Options, Solver, parse, solve};
//!
//! let text = "NAME : tiny-n5-k2\nTYPE : CVRP\nDIMENSION : 5\nEDGE_WEIGHT_TYPE : EUC_2D\n\
//!     CAPACITY : 10\nNODE_COORD_SECTION\n1 0 0\n2 0 10\n3 0 11\n4 10 0\n5 11 0\n\
//!     DEMAND_SECTION\n1 0\n2 5\n3 5\n4 5\n5 5\nDEPOT_SECTION\n1\n-1\nEOF\n";
//! let inst = parse(text)?;
//! assert_eq!(inst.customers(), 4);
//!
//! let options = Options { solver: Solver::LocalSearch { budget: 50 }, seed: 7 };
//! let sol = solve(&inst, &options);
//! sol.check(&inst)?; // capacity, windows, fleet, every customer once
//! assert_eq!(sol.routes.len(), 2);
//! assert_eq!(sol.cost, 44.0);
//!
//! let auction = solve(&inst, &Options { solver: Solver::Auction, seed: 0 });
//! assert_eq!(auction.stats.rounds, 4);
//! # Ok::<(), Box<dyn std::error::Error>>(())
//! ```

mod auction;
mod instance;
mod lns;
mod moves;
pub mod parse;
mod savings;
mod solution;

pub use auction::auction;
pub use instance::{Instance, Metric, Node};
pub use parse::{ParseError, parse};
pub use savings::savings;
pub use solution::{Solution, Stats, Violation};

use serde::{Deserialize, Serialize};

/// Which solver answers an instance.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "kebab-case")]
#[non_exhaustive]
pub enum Solver {
    /// Clarke & Wright's savings construction.
    Savings,
    /// The savings solution improved by `budget` large-neighbourhood iterations.
    LocalSearch {
        /// Ruin-and-recreate iterations (each followed by the local search).
        budget: u64,
    },
    /// Sequential single-item auctions among the fleet.
    Auction,
}

impl Default for Solver {
    fn default() -> Solver {
        Solver::LocalSearch {
            budget: Options::DEFAULT_BUDGET,
        }
    }
}

/// A solver and its seed.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default, Serialize, Deserialize)]
pub struct Options {
    /// The solver.
    pub solver: Solver,
    /// Seed of the solver's random stream (the local search only).
    pub seed: u64,
}

impl Options {
    /// The default local-search budget: iterations.
    pub const DEFAULT_BUDGET: u64 = 2000;
}

/// Solves an instance with the chosen solver. Customers that no vehicle can serve on its own
/// (demand over capacity, window out of reach) are returned in [`Solution::unassigned`].
#[must_use]
pub fn solve(inst: &Instance, options: &Options) -> Solution {
    match options.solver {
        Solver::Savings => savings(inst),
        Solver::LocalSearch { budget } => lns::lns(inst, savings(inst), budget, options.seed),
        Solver::Auction => auction(inst),
    }
}

//! `vitro solve vrp INSTANCE`: a CVRPLIB or Solomon instance through `vitro-routing`.

use crate::Failure;
use anyhow::anyhow;
use clap::{Args, ValueEnum};
use serde::Serialize;
use std::path::PathBuf;
use std::time::Instant;
use vitro_routing::{Options, Solver, Stats, parse, solve};

#[derive(Debug, Clone, Copy, ValueEnum)]
pub(crate) enum SolverArg {
    /// Clarke & Wright's savings construction.
    Savings,
    /// The savings solution improved by a large neighbourhood search (--budget iterations).
    LocalSearch,
    /// Sequential single-item auctions among the fleet (messages counted).
    Auction,
}

#[derive(Debug, Args)]
pub(crate) struct VrpArgs {
    /// The instance: CVRPLIB `.vrp` (EUC_2D) or Solomon VRPTW text.
    instance: PathBuf,
    /// The solver.
    #[arg(long, value_enum, default_value = "local-search")]
    solver: SolverArg,
    /// Local-search iterations (ruin, recreate, local search each).
    #[arg(long, default_value_t = Options::DEFAULT_BUDGET)]
    budget: u64,
    /// Seed of the local search's random stream.
    #[arg(long, default_value_t = 0)]
    seed: u64,
    /// Prints one JSON object on stdout.
    #[arg(long)]
    json: bool,
}

#[derive(Serialize)]
struct VrpReport {
    name: String,
    solver: Solver,
    seed: u64,
    customers: usize,
    capacity: u64,
    fleet: Option<usize>,
    cost: f64,
    vehicles_used: usize,
    /// Customer indices per route (the depot is 0, implied at both ends; for CVRPLIB files
    /// customer `k` is the file's node `k + 1`).
    routes: Vec<Vec<usize>>,
    loads: Vec<u64>,
    unassigned: Vec<usize>,
    feasible: bool,
    /// Why not, when not.
    violation: Option<String>,
    best_known: Option<f64>,
    gap_percent: Option<f64>,
    stats: Stats,
    wall_time_s: f64,
}

pub(crate) fn vrp(args: &VrpArgs) -> Result<(), Failure> {
    let path = &args.instance;
    vitro_tools::input_file(path)?;
    let text = std::fs::read_to_string(path)
        .map_err(|e| Failure::Input(anyhow!("cannot read {}: {e}", path.display())))?;
    let inst = parse(&text).map_err(|e| Failure::Input(anyhow!("{}: {e}", path.display())))?;
    let solver = match args.solver {
        SolverArg::Savings => Solver::Savings,
        SolverArg::LocalSearch => Solver::LocalSearch {
            budget: args.budget,
        },
        SolverArg::Auction => Solver::Auction,
    };
    let started = Instant::now();
    let sol = solve(
        &inst,
        &Options {
            solver,
            seed: args.seed,
        },
    );
    let wall_time_s = started.elapsed().as_secs_f64();
    let violation = if sol.unassigned.is_empty() {
        sol.check(&inst).err().map(|e| e.to_string())
    } else {
        Some(format!("{} customer(s) unassigned", sol.unassigned.len()))
    };
    let report = VrpReport {
        name: inst.name.clone(),
        solver,
        seed: args.seed,
        customers: inst.customers(),
        capacity: inst.capacity,
        fleet: inst.vehicles,
        cost: sol.cost,
        vehicles_used: sol.routes.len(),
        loads: sol.routes.iter().map(|r| inst.route_load(r)).collect(),
        routes: sol.routes.clone(),
        unassigned: sol.unassigned.clone(),
        feasible: violation.is_none(),
        violation,
        best_known: inst.best_known,
        gap_percent: inst.best_known.map(|b| sol.gap_percent(b)),
        stats: sol.stats.clone(),
        wall_time_s,
    };
    if args.json {
        let line = serde_json::to_string(&report).map_err(|e| Failure::Runtime(anyhow!(e)))?;
        println!("{line}");
    } else {
        print_text(&report);
    }
    match &report.violation {
        Some(v) => Err(Failure::Check(anyhow!(
            "{}: no feasible solution: {v}",
            path.display()
        ))),
        None => Ok(()),
    }
}

fn print_text(r: &VrpReport) {
    let fleet = r
        .fleet
        .map_or_else(|| "unlimited".to_string(), |v| v.to_string());
    let how = match r.solver {
        Solver::Savings => "savings".to_string(),
        Solver::LocalSearch { budget } => {
            format!("local search, {budget} iterations, seed {}", r.seed)
        }
        Solver::Auction => format!(
            "auction, {} rounds, {} messages",
            r.stats.rounds, r.stats.messages
        ),
        other => format!("{other:?}"),
    };
    println!(
        "{}: cost {:.2} with {} of {fleet} vehicles ({} customers, capacity {}; {how}; {:.3} s)",
        r.name, r.cost, r.vehicles_used, r.customers, r.capacity, r.wall_time_s
    );
    if let (Some(b), Some(g)) = (r.best_known, r.gap_percent) {
        println!("gap to best-known {b}: {g:+.2}%");
    }
    for (k, (route, load)) in r.routes.iter().zip(&r.loads).enumerate() {
        let stops: Vec<String> = route.iter().map(usize::to_string).collect();
        println!("route {}: {} (load {load})", k + 1, stops.join(" "));
    }
    if !r.unassigned.is_empty() {
        let left: Vec<String> = r.unassigned.iter().map(usize::to_string).collect();
        println!("unassigned: {}", left.join(" "));
    }
}

//! Plan repair vs replanning, over the failure probability: a batch of seeded runs per
//! strategy, a table per strategy, and a plot of the messages sent.
//!
//! ```text
//! cargo run --release -p vitro-worlds --example repair_experiment -- \
//!     [--seeds N] [--max-expansions N] [--plot PATH] [DOMAIN.pddl PROBLEM.pddl]
//! ```
//!
//! Defaults: the dock-worker problem `data/planning/dwr/problem-02.pddl`, 30 seeds per
//! probability, no search bound, the plot at `docs/repair_messages.png`. Each cell is the
//! mean over all runs (successful or not); messages are the copies sent, in all protocols.

use std::path::{Path, PathBuf};
use std::process::ExitCode;

use plotters::prelude::*;
use plotters::style::{FontStyle, register_font};
use vitro_algo::repair::{Ownership, Scenario, Strategy};
use vitro_worlds::repair::{RepairConfig, RunReport, run};

/// DejaVu Sans (licence: `assets/fonts/DejaVuSans-LICENSE.txt`).
static FONT: &[u8] = include_bytes!("../../../assets/fonts/DejaVuSans.ttf");
const PROBABILITIES: [f64; 5] = [0.0, 0.05, 0.1, 0.2, 0.3];
/// Okabe–Ito colours.
const COLOURS: [RGBColor; 4] = [
    RGBColor(0, 114, 178),
    RGBColor(230, 159, 0),
    RGBColor(0, 158, 115),
    RGBColor(204, 121, 167),
];

struct Args {
    seeds: u64,
    bound: Option<u64>,
    plot: PathBuf,
    domain: PathBuf,
    problem: PathBuf,
}

fn parse_args() -> Result<Args, String> {
    let root = Path::new(env!("CARGO_MANIFEST_DIR")).join("../..");
    let mut args = Args {
        seeds: 30,
        bound: None,
        plot: root.join("docs/repair_messages.png"),
        domain: root.join("data/planning/dwr/domain.pddl"),
        problem: root.join("data/planning/dwr/problem-02.pddl"),
    };
    let mut files = Vec::new();
    let mut it = std::env::args().skip(1);
    while let Some(a) = it.next() {
        let mut value = |name: &str| it.next().ok_or(format!("{name} needs a value"));
        match a.as_str() {
            "--seeds" => args.seeds = value("--seeds")?.parse().map_err(|e| format!("{e}"))?,
            "--max-expansions" => {
                args.bound = Some(
                    value("--max-expansions")?
                        .parse()
                        .map_err(|e| format!("{e}"))?,
                )
            }
            "--plot" => args.plot = value("--plot")?.into(),
            _ if a.starts_with("--") => return Err(format!("unknown option {a}")),
            _ => files.push(PathBuf::from(a)),
        }
    }
    match files.len() {
        0 => {}
        2 => {
            args.problem = files.remove(1);
            args.domain = files.remove(0);
        }
        _ => return Err("give both DOMAIN.pddl and PROBLEM.pddl, or neither".into()),
    }
    Ok(args)
}

/// Means of one (strategy, probability) cell.
struct Cell {
    p: f64,
    runs: usize,
    success: f64,
    executed: f64,
    repairs: f64,
    turns: f64,
    queries: f64,
    plans: f64,
    messages: f64,
    messages_se: f64,
    expanded: f64,
    planning_s: f64,
    truncated: usize,
    /// Messages of each run, by seed.
    per_seed: Vec<f64>,
}

fn cell(p: f64, reports: &[RunReport]) -> Cell {
    let n = reports.len() as f64;
    let mean = |f: &dyn Fn(&RunReport) -> f64| reports.iter().map(f).sum::<f64>() / n;
    let messages = mean(&|r| r.messages.total() as f64);
    let var = reports
        .iter()
        .map(|r| (r.messages.total() as f64 - messages).powi(2))
        .sum::<f64>()
        / (n - 1.0).max(1.0);
    Cell {
        p,
        runs: reports.len(),
        success: mean(&|r| f64::from(u8::from(r.succeeded()))),
        executed: mean(&|r| r.executed as f64),
        repairs: mean(&|r| r.repairs.len() as f64),
        turns: mean(&|r| r.messages.turns as f64),
        queries: mean(&|r| r.messages.queries as f64),
        plans: mean(&|r| r.messages.plans as f64),
        messages,
        messages_se: (var / n).sqrt(),
        expanded: mean(&|r| r.expanded as f64),
        planning_s: mean(&|r| r.planning_time.as_secs_f64()),
        truncated: reports.iter().map(RunReport::truncated_searches).sum(),
        per_seed: reports.iter().map(|r| r.messages.total() as f64).collect(),
    }
}

fn main() -> ExitCode {
    let args = match parse_args() {
        Ok(a) => a,
        Err(e) => {
            eprintln!("error: {e}");
            return ExitCode::from(2);
        }
    };
    match experiment(&args) {
        Ok(()) => ExitCode::SUCCESS,
        Err(e) => {
            eprintln!("error: {e}");
            ExitCode::FAILURE
        }
    }
}

fn experiment(args: &Args) -> Result<(), Box<dyn std::error::Error>> {
    let scenario =
        Scenario::from_files(&args.domain, &args.problem, &Ownership::first_parameter())?;
    println!(
        "problem {}: agents {}; original plan {} steps; {} seeds per probability",
        args.problem.display(),
        scenario.agents().join(", "),
        scenario.plan().len(),
        args.seeds
    );
    match args.bound {
        Some(b) => println!("repair searches bounded at {b} expansions"),
        None => println!("repair searches unbounded"),
    }
    let mut results = Vec::new();
    for strategy in Strategy::ALL {
        let mut cells = Vec::new();
        for p in PROBABILITIES {
            let config = RepairConfig {
                strategy,
                failure_probability: p,
                max_expansions: args.bound,
                ..RepairConfig::default()
            };
            let reports = (0..args.seeds)
                .map(|seed| run(&scenario, &config, seed))
                .collect::<Result<Vec<_>, _>>()?;
            cells.push(cell(p, &reports));
        }
        print_table(strategy, &cells);
        results.push((strategy, cells));
    }
    print_paired(&results);
    plot(&args.plot, &scenario, args.seeds, &results)?;
    println!("\nplot: {}", args.plot.display());
    Ok(())
}

fn print_table(strategy: Strategy, cells: &[Cell]) {
    println!("\n{strategy}");
    println!(
        "{:>5} {:>5} {:>8} {:>9} {:>8} {:>9} {:>6} {:>8} {:>6} {:>9} {:>10} {:>5}",
        "p",
        "runs",
        "success",
        "executed",
        "repairs",
        "messages",
        "turn",
        "query",
        "plan",
        "expanded",
        "plan time",
        "cut"
    );
    for c in cells {
        println!(
            "{:>5.2} {:>5} {:>7.0}% {:>9.1} {:>8.2} {:>9.1} {:>6.1} {:>8.1} {:>6.1} {:>9.1} {:>9.2}s {:>5}",
            c.p,
            c.runs,
            100.0 * c.success,
            c.executed,
            c.repairs,
            c.messages,
            c.turns,
            c.queries,
            c.plans,
            c.expanded,
            c.planning_s,
            c.truncated
        );
    }
}

/// Messages of each repair strategy minus those of replanning on the same seeds.
fn print_paired(results: &[(Strategy, Vec<Cell>)]) {
    let Some((_, replan)) = results.iter().find(|(s, _)| *s == Strategy::Replan) else {
        return;
    };
    println!("\nmessages minus replanning's, same seeds (mean ± 2 s.e.; fewer/more runs)");
    for (strategy, cells) in results.iter().filter(|(s, _)| *s != Strategy::Replan) {
        let mut line = format!("{:>14}", strategy.to_string());
        for (c, r) in cells.iter().zip(replan).filter(|(c, _)| c.p > 0.0) {
            let d: Vec<f64> = c
                .per_seed
                .iter()
                .zip(&r.per_seed)
                .map(|(a, b)| a - b)
                .collect();
            let n = d.len() as f64;
            let mean = d.iter().sum::<f64>() / n;
            let var = d.iter().map(|x| (x - mean).powi(2)).sum::<f64>() / (n - 1.0).max(1.0);
            let fewer = d.iter().filter(|&&x| x < 0.0).count();
            let more = d.iter().filter(|&&x| x > 0.0).count();
            line += &format!(
                "  p={:.2}: {:+6.1} ± {:4.1} ({fewer}/{more})",
                c.p,
                mean,
                2.0 * (var / n).sqrt()
            );
        }
        println!("{line}");
    }
}

fn plot(
    path: &Path,
    scenario: &Scenario,
    seeds: u64,
    results: &[(Strategy, Vec<Cell>)],
) -> Result<(), Box<dyn std::error::Error>> {
    register_font("sans-serif", FontStyle::Normal, FONT)
        .map_err(|_| "the embedded font could not be loaded")?;
    if let Some(dir) = path.parent() {
        std::fs::create_dir_all(dir)?;
    }
    let root = BitMapBackend::new(path, (960, 600)).into_drawing_area();
    root.fill(&WHITE)?;
    let y_max = results
        .iter()
        .flat_map(|(_, cells)| cells.iter().map(|c| c.messages + 2.0 * c.messages_se))
        .fold(0.0, f64::max)
        * 1.1;
    let title = format!(
        "Messages per run vs action failure probability ({}, {} agents, {} seeds)",
        scenario.problem().name,
        scenario.agents().len(),
        seeds
    );
    let mut chart = ChartBuilder::on(&root)
        .caption(title, ("sans-serif", 22))
        .margin(20)
        .x_label_area_size(50)
        .y_label_area_size(70)
        .build_cartesian_2d(-0.01f64..0.31f64, 0f64..y_max)?;
    chart
        .configure_mesh()
        .x_desc("failure probability p")
        .y_desc("messages sent (mean, ±2 s.e.)")
        .y_label_formatter(&|v| format!("{v:.0}"))
        .label_style(("sans-serif", 15))
        .axis_desc_style(("sans-serif", 17))
        .light_line_style(TRANSPARENT)
        .draw()?;
    for (i, (strategy, cells)) in results.iter().enumerate() {
        let colour = COLOURS[i % COLOURS.len()];
        chart
            .draw_series(LineSeries::new(
                cells.iter().map(|c| (c.p, c.messages)),
                colour.stroke_width(3),
            ))?
            .label(strategy.to_string())
            .legend(move |(x, y)| {
                PathElement::new(vec![(x, y), (x + 24, y)], colour.stroke_width(3))
            });
        chart.draw_series(
            cells
                .iter()
                .map(|c| Circle::new((c.p, c.messages), 5, colour.filled())),
        )?;
        chart.draw_series(cells.iter().map(|c| {
            let (lo, hi) = (
                c.messages - 2.0 * c.messages_se,
                c.messages + 2.0 * c.messages_se,
            );
            PathElement::new(vec![(c.p, lo), (c.p, hi)], colour.stroke_width(2))
        }))?;
    }
    chart
        .configure_series_labels()
        .position(SeriesLabelPosition::UpperLeft)
        .label_font(("sans-serif", 16))
        .background_style(WHITE.mix(0.9))
        .border_style(BLACK)
        .draw()?;
    root.present()?;
    Ok(())
}

//! `vitro search`: looks for failing runs of a scenario over the parameters of an
//! experiment's `[search]` table, adaptively (cross-entropy method) or at random, and shrinks
//! the failures found to minimal scenario files.
//!
//! ```text
//! vitro search EXPERIMENT.toml --out DIR [--budget N] [--strategy adaptive|random]
//!              [--jobs N] [--resume] [--seed N] [--shrink N]
//! ```

use crate::Failure;
use crate::batch::{fail_on_failed_runs, jobs, load, progress_bar, runner_for};
use clap::Args;
use std::path::PathBuf;
use std::sync::OnceLock;
use vitro_batch::Runner;
use vitro_batch::journal::Status;
use vitro_batch::search::{SearchEvent, SearchOptions, Strategy, run_search};

/// Arguments of `vitro search`.
#[derive(Debug, Args)]
pub(crate) struct SearchArgs {
    /// The experiment file, with a [search] table (see experiments/README.md).
    experiment: PathBuf,
    /// Result directory: runs.jsonl, manifest.json, summary tables, found.csv, minimal/.
    #[arg(long, value_name = "DIR")]
    out: PathBuf,
    /// Evaluations (default: the [search] table's `budget`).
    #[arg(long, value_name = "N", value_parser = clap::value_parser!(u64).range(1..=1_000_000))]
    budget: Option<u64>,
    /// `adaptive` (cross-entropy method) or `random` (uniform, the baseline).
    #[arg(long, default_value = "adaptive", value_parser = parse_strategy)]
    strategy: Strategy,
    /// Runs at once (default: the number of CPUs); the results do not depend on it.
    #[arg(long, short = 'j', value_name = "N", value_parser = clap::value_parser!(u32).range(1..=4096))]
    jobs: Option<u32>,
    /// Completes the search in DIR (after a kill or a crash).
    #[arg(long)]
    resume: bool,
    /// Search seed (default: the experiment's `seed`).
    #[arg(long, value_name = "N")]
    seed: Option<u64>,
    /// Distinct failures to shrink (default: the [search] table's `shrink`; 0: none).
    #[arg(long, value_name = "N")]
    shrink: Option<u32>,
}

fn parse_strategy(s: &str) -> Result<Strategy, String> {
    s.parse()
}

pub(crate) fn search(args: &SearchArgs) -> Result<(), Failure> {
    let runner = runner_for(&args.experiment);
    let runner: &dyn Runner = runner.as_ref();
    let exp = load(&args.experiment, runner)?;
    let Some(spec) = &exp.search else {
        return Err(Failure::Input(anyhow::anyhow!(
            "{} has no [search] table: nothing to search (see experiments/README.md)",
            args.experiment.display()
        )));
    };
    let jobs = jobs(args.jobs);
    let budget = args.budget.unwrap_or(spec.budget);
    let seed = args.seed.unwrap_or(exp.design.base_seed);
    eprintln!(
        "search {:?}: {} over {} parameters, {budget} runs in generations of {}, seed {seed}, {jobs} jobs -> {}\n  objective: {}",
        exp.name,
        args.strategy.as_str(),
        spec.dims.len(),
        spec.population,
        args.out.display(),
        spec.objective.describe()
    );
    let opts = SearchOptions {
        out: args.out.clone(),
        jobs,
        resume: args.resume,
        budget: args.budget,
        strategy: args.strategy,
        seed: args.seed,
        shrink: args.shrink,
    };
    let bar = progress_bar();
    let started = OnceLock::new();
    let report = run_search(&exp, runner, &opts, &|e| match e {
        SearchEvent::Run(p) => {
            let bar = started.get_or_init(|| {
                bar.set_length(p.total - p.before);
                if p.before > 0 {
                    bar.set_prefix(format!("({} done before) ", p.before));
                }
                &bar
            });
            if p.record.status == Status::Failed {
                bar.println(format!(
                    "run {} failed: {}",
                    p.record.run,
                    p.record.error.as_deref().unwrap_or("")
                ));
            } else if spec.objective.fails(&p.record.metrics) {
                bar.println(format!("run {} fails", p.record.run));
            }
            bar.inc(1);
        }
        SearchEvent::Shrink {
            run,
            index,
            count,
            budget,
        } => {
            bar.println(format!(
                "shrinking failure {} of {count}: run {run} (at most {budget} runs)",
                index + 1
            ));
            bar.set_prefix(format!("shrink {}/{count} ", index + 1));
            bar.set_position(0);
            bar.set_length(u64::from(budget));
        }
        SearchEvent::ShrinkRun => bar.inc(1),
    })
    .map_err(|e| {
        if e.is_input() {
            Failure::Input(e.into())
        } else {
            Failure::Runtime(e.into())
        }
    })?;
    bar.finish_and_clear();

    if report.torn_dropped {
        eprintln!(
            "dropped a torn last line of runs.jsonl (a run cut off by the kill); it ran again"
        );
    }
    let found = report.failures.len() as u64;
    eprintln!(
        "{} runs made in {:.2} s, {} done before; {found} of {} runs fail ({:.1} %)",
        report.ran,
        report.wall_s,
        report.skipped,
        report.planned,
        100.0 * found as f64 / report.planned.max(1) as f64
    );
    for m in &report.minimal {
        eprintln!(
            "minimal failure {} (from run {}, {} shrink runs, trace hash {}):",
            m.file, m.run, m.runs, m.trace_hash
        );
        for c in &m.changes {
            eprintln!("    {c}");
        }
        if !m.also.is_empty() {
            let runs: Vec<String> = m.also.iter().map(u64::to_string).collect();
            eprintln!("  runs {} shrank to the same failure", runs.join(", "));
        }
    }
    for f in &report.files {
        eprintln!("wrote {}", f.display());
    }
    println!("{found} failing runs of {}", report.planned);
    fail_on_failed_runs(&report.errors, report.planned)
}

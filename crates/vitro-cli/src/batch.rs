//! `vitro batch`, `vitro merge` and `vitro plot`: experiment suites over the scenario an
//! experiment names, run by the mission its `kind` names (`vitro_mission::batch::MissionRunner`).
//!
//! ```text
//! vitro batch EXPERIMENT.toml --out DIR [--jobs N] [--shard I/N] [--resume] [--slurm [--tasks N] [--time T]]
//! vitro batch --print-schema
//! vitro merge DIR... --out DIR
//! vitro plot DIR --out PLOTS [--metric M]... [--hist M]... [--success M]
//! ```

mod slurm;

use crate::Failure;
use anyhow::anyhow;
use clap::Args;
use indicatif::{ProgressBar, ProgressDrawTarget, ProgressStyle};
use std::io::IsTerminal;
use std::path::{Path, PathBuf};
use vitro_batch::Runner;
use vitro_batch::design::Shard;
use vitro_batch::journal::Status;
use vitro_batch::plot::{PlotOptions, plot_dir};
use vitro_batch::{BatchOptions, Experiment, experiment_schema, merge, run_batch};
pub(crate) use vitro_tools::runner_for;

/// Arguments of `vitro batch`.
#[derive(Debug, Args)]
pub(crate) struct BatchArgs {
    /// The experiment file (TOML; see experiments/ and `--print-schema`).
    #[arg(required_unless_present = "print_schema")]
    experiment: Option<PathBuf>,
    /// Result directory: runs.jsonl, manifest.json, summary and series tables.
    #[arg(long, value_name = "DIR", required_unless_present = "print_schema")]
    out: Option<PathBuf>,
    /// Runs at once (default: the number of CPUs).
    #[arg(long, short = 'j', value_name = "N", value_parser = clap::value_parser!(u32).range(1..=4096))]
    jobs: Option<u32>,
    /// Makes only shard I of N: the runs whose number k has k mod N = I. Without it, a task
    /// of a Slurm job array (SLURM_ARRAY_TASK_ID / _COUNT / _MIN) or of a Kubernetes Indexed
    /// Job (JOB_COMPLETION_INDEX with VITRO_SHARD_COUNT) makes its own shard.
    #[arg(long, value_name = "I/N")]
    shard: Option<Shard>,
    /// Completes the runs missing from DIR (after a kill or a crash).
    #[arg(long)]
    resume: bool,
    /// Prints the sbatch script of a Slurm job array that makes the experiment in shards
    /// (CPUs per task: --jobs, default 2), then merges them into DIR; runs nothing.
    #[arg(long, conflicts_with_all = ["shard", "resume"])]
    slurm: bool,
    /// Tasks of the --slurm job array.
    #[arg(long, value_name = "N", default_value_t = 4, requires = "slurm", value_parser = clap::value_parser!(u64).range(1..=100_000))]
    tasks: u64,
    /// Wall-time limit of each --slurm task (MM, HH:MM:SS or D-HH:MM:SS).
    #[arg(
        long,
        value_name = "TIME",
        default_value = "01:00:00",
        requires = "slurm"
    )]
    time: String,
    /// Prints the JSON Schema of experiment files and exits.
    #[arg(long, exclusive = true)]
    print_schema: bool,
}

/// Arguments of `vitro merge`.
#[derive(Debug, Args)]
pub(crate) struct MergeArgs {
    /// Result directories of one experiment (e.g. its shards).
    #[arg(required = true, num_args = 1..)]
    dirs: Vec<PathBuf>,
    /// The merged result directory (new).
    #[arg(long, value_name = "DIR")]
    out: PathBuf,
}

/// Arguments of `vitro plot`.
#[derive(Debug, Args)]
pub(crate) struct PlotArgs {
    /// A result directory.
    dir: PathBuf,
    /// Where to write the PNG and SVG files.
    #[arg(long, value_name = "DIR")]
    out: PathBuf,
    /// A metric to plot against the parameters (repeatable; default: every numeric one).
    #[arg(long = "metric", value_name = "M")]
    metrics: Vec<String>,
    /// A metric to draw the histogram of (repeatable; default: those plotted).
    #[arg(long = "hist", value_name = "M")]
    histograms: Vec<String>,
    /// Boolean metric saying a run succeeded (default: `success` if kept, else no error).
    #[arg(long, value_name = "M")]
    success: Option<String>,
}

pub(crate) fn batch(args: &BatchArgs) -> Result<(), Failure> {
    if args.print_schema {
        print!("{}", experiment_schema());
        return Ok(());
    }
    let (Some(path), Some(out)) = (&args.experiment, &args.out) else {
        return Err(Failure::Input(anyhow!(
            "an experiment and --out DIR are needed"
        )));
    };
    if args.slurm {
        return slurm_script(args, path, out);
    }
    // Without --shard, a task of a Slurm job array or a Kubernetes Indexed Job makes its share.
    let (shard, shard_from) = vitro_tools::shard_for(args.shard)?.unzip();
    let runner = runner_for(path);
    let runner: &dyn Runner = runner.as_ref();
    let exp = load(path, runner)?;
    let jobs = jobs(args.jobs);
    let total = exp.design.runs().unwrap_or(0);
    let points = exp.design.points().unwrap_or(0);
    eprintln!(
        "experiment {:?}: {total} runs ({points} points x {} replicates{}){}, {jobs} jobs -> {}",
        exp.name,
        exp.design.replicates,
        if let Some(s) = &exp.stop {
            format!(
                " at most, fewer once the 95% CI of {} is within ±{}",
                s.metric, s.half_width
            )
        } else {
            String::new()
        },
        shard
            .zip(shard_from.as_ref())
            .map(|(s, from)| format!(", shard {s} (from {from})"))
            .unwrap_or_default(),
        out.display()
    );

    let bar = progress_bar();
    let opts = BatchOptions {
        out: out.clone(),
        jobs,
        shard,
        shard_from,
        resume: args.resume,
    };
    let started = std::sync::OnceLock::new();
    let report = run_batch(&exp, runner, &opts, &|p| {
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
        }
        bar.inc(1);
    })
    .map_err(vitro_tools::batch_error)?;
    bar.finish_and_clear();

    if report.torn_dropped {
        eprintln!(
            "dropped a torn last line of runs.jsonl (a run cut off by the kill); it ran again"
        );
    }
    let rate = if report.wall_s > 0.0 {
        report.ran as f64 / report.wall_s
    } else {
        0.0
    };
    eprintln!(
        "{} runs made in {:.2} s ({:.2} runs/s, {:.0} runs/hour), {} done before; {} of {} runs failed",
        report.ran,
        report.wall_s,
        rate,
        rate * 3600.0,
        report.skipped,
        report.failed.len(),
        report.planned
    );
    if let Some(stop) = &report.stop {
        let met = stop.points.iter().filter(|p| p.met).count();
        let runs: u32 = stop.points.iter().map(|p| p.replicates).sum();
        eprintln!(
            "conditioned: {met} of {} points reached a 95% CI of {} within ±{} ({runs} runs of {} at most; see manifest.json)",
            stop.points.len(),
            stop.rule.metric,
            stop.rule.half_width,
            report.planned
        );
    }
    for t in &report.tables {
        eprintln!("wrote {}", t.display());
    }
    fail_on_failed_runs(&report.failed, report.planned)
}

/// Loads the experiment at `path`; any problem is bad input.
pub(crate) fn load(path: &std::path::Path, runner: &dyn Runner) -> Result<Experiment, Failure> {
    Ok(vitro_tools::load_experiment(path, runner)?)
}

/// Worker threads: `--jobs`, else the number of CPUs.
/// `--slurm`: checks the experiment, then prints the job array's script.
fn slurm_script(args: &BatchArgs, path: &Path, out: &Path) -> Result<(), Failure> {
    if !slurm::is_slurm_time(&args.time) {
        return Err(Failure::Input(anyhow!(
            "--time {:?}: expected MM, HH:MM:SS or D-HH:MM:SS",
            args.time
        )));
    }
    let runner = runner_for(path);
    let exp = load(path, runner.as_ref())?;
    let vitro = std::env::current_exe()
        .map_err(|e| Failure::Runtime(anyhow!("cannot find the vitro binary: {e}")))?;
    print!(
        "{}",
        slurm::script(&slurm::ArrayPlan {
            name: &exp.name,
            vitro: &vitro,
            experiment: path,
            out,
            tasks: args.tasks,
            cpus: args.jobs.unwrap_or(2),
            time: &args.time,
            runs: exp.design.runs().unwrap_or(0),
        })
    );
    Ok(())
}

pub(crate) fn jobs(arg: Option<u32>) -> usize {
    arg.map_or_else(
        || std::thread::available_parallelism().map_or(1, |n| n.get()),
        |j| j as usize,
    )
}

/// Exit 1 naming the failed runs, if any.
pub(crate) fn fail_on_failed_runs(failed: &[(u64, String)], total: u64) -> Result<(), Failure> {
    if failed.is_empty() {
        return Ok(());
    }
    for (run, err) in failed.iter().take(20) {
        eprintln!("  run {run}: {err}");
    }
    if failed.len() > 20 {
        eprintln!(
            "  ... and {} more (see the summary table)",
            failed.len() - 20
        );
    }
    vitro_tools::failed_runs(failed, total).map_or(Ok(()), |e| Err(e.into()))
}

/// A bar on stderr when it is a terminal, else a hidden one.
pub(crate) fn progress_bar() -> ProgressBar {
    if !std::io::stderr().is_terminal() {
        return ProgressBar::hidden();
    }
    let bar = ProgressBar::with_draw_target(Some(0), ProgressDrawTarget::stderr());
    let style = ProgressStyle::with_template(
        "{prefix}[{elapsed_precise}] {wide_bar} {pos}/{len} runs  {per_sec}  ETA {eta}",
    )
    .unwrap_or_else(|_| ProgressStyle::default_bar());
    bar.set_style(style);
    bar
}

pub(crate) fn merge_dirs(args: &MergeArgs) -> Result<(), Failure> {
    let report = merge(&args.dirs, &args.out).map_err(|e| {
        if e.is_input() {
            Failure::Input(e.into())
        } else {
            Failure::Runtime(e.into())
        }
    })?;
    for dir in &report.torn {
        eprintln!(
            "note: {} ends with a torn run record (left out); resume it to complete",
            dir.display()
        );
    }
    eprintln!(
        "merged {} of {} runs from {} directories into {} ({} failed runs)",
        report.runs,
        report.total,
        args.dirs.len(),
        args.out.display(),
        report.failed.len()
    );
    if report.runs < report.total {
        eprintln!(
            "note: {} runs are missing; `vitro batch EXPERIMENT --out {} --resume` makes them",
            report.total - report.runs,
            args.out.display()
        );
    }
    for t in &report.tables {
        eprintln!("wrote {}", t.display());
    }
    Ok(())
}

pub(crate) fn plot(args: &PlotArgs) -> Result<(), Failure> {
    let opts = PlotOptions {
        metrics: args.metrics.clone(),
        histograms: args.histograms.clone(),
        success: args.success.clone(),
    };
    let files = plot_dir(&args.dir, &args.out, &opts).map_err(|e| {
        if e.is_input() {
            Failure::Input(e.into())
        } else {
            Failure::Runtime(e.into())
        }
    })?;
    eprintln!("wrote {} files to {}", files.len(), args.out.display());
    Ok(())
}

//! `vitro resume FILE`: continues a run saved by `vitro run --save-at SECONDS --save FILE`
//! to the same end (and the same trace hash) as the uninterrupted run.

use crate::Failure;
use crate::missions::registry;
use crate::run::{Output, check_until, drive};
use clap::Args;
use std::path::{Path, PathBuf};
use vitro_mission::{Snapshot, SnapshotError};

/// The arguments of `vitro resume`.
#[derive(Debug, Args)]
pub(crate) struct ResumeArgs {
    /// The snapshot file (`vitro run ... --save-at SECONDS --save FILE`).
    pub(crate) snapshot: PathBuf,
    /// Simulated seconds to run to at most (default: the saved run's end).
    #[arg(long, value_name = "SECONDS")]
    pub(crate) until: Option<f64>,
    /// Paces the run at X simulated seconds per wall second; pacing never changes the outcome.
    #[arg(long, value_name = "X")]
    pub(crate) speed: Option<f64>,
    /// Records the run from the resume point on to an MCAP file.
    #[arg(long, value_name = "FILE.mcap")]
    pub(crate) record: Option<PathBuf>,
    /// Prints one JSON object on stdout instead of the summary.
    #[arg(long)]
    pub(crate) json: bool,
    /// Prints only the trace hash (or only the JSON object with --json).
    #[arg(long)]
    pub(crate) quiet: bool,
    /// Tells more on stderr (mission log lines as they happen).
    #[arg(short, long)]
    pub(crate) verbose: bool,
}

/// A snapshot problem as a failure naming the file: bad input (exit 2) or a failure of the
/// machine (exit 1).
fn failure(file: &Path, e: SnapshotError) -> Failure {
    let bad = e.is_bad_input();
    let e = anyhow::Error::new(e).context(format!("cannot resume {}", file.display()));
    if bad {
        Failure::Input(e)
    } else {
        Failure::Runtime(e)
    }
}

pub(crate) fn resume(args: &ResumeArgs) -> Result<(), Failure> {
    let file = &args.snapshot;
    vitro_tools::input_file(file)?;
    let reader = std::fs::File::open(file).map_err(|e| {
        Failure::Input(anyhow::anyhow!(
            "cannot read snapshot {}: {e}",
            file.display()
        ))
    })?;
    let snap = Snapshot::read(std::io::BufReader::new(reader)).map_err(|e| failure(file, e))?;
    let until = args.until.map(check_until).transpose()?;
    if let Some(until) = until
        && until.as_nanos() < snap.saved_at_ns
    {
        return Err(Failure::Input(anyhow::anyhow!(
            "--until {:.1}: the snapshot is at {:.1} s already",
            until.as_secs_f64(),
            snap.saved_at_ns as f64 / 1e9
        )));
    }
    let mut run = registry()
        .resume(&snap, until)
        .map_err(|e| failure(file, e))?;
    let output = Output {
        resumed: true,
        speed: args.speed,
        record: args.record.as_deref(),
        json: args.json,
        quiet: args.quiet,
        verbose: args.verbose,
    };
    if !args.quiet && !args.json {
        eprintln!(
            "resuming {:?} ({}, seed {}) at {:.1} s simulated, to at most {:.0} s",
            run.name(),
            snap.scenario,
            run.seed(),
            run.now().as_secs_f64(),
            run.end().as_secs_f64()
        );
    }
    drive(run.as_mut(), file, &output, None)
}

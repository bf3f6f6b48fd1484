//! The arguments of `vitro run`, shared by every kind of scenario.

use clap::Args;
use std::path::PathBuf;

#[derive(Debug, Args)]
pub(crate) struct RunArgs {
    /// The scenario file (TOML): a mission scenario (e.g. scenarios/evacuation.toml) or the
    /// patrolling-cars demo (scenarios/demo.toml).
    pub(crate) scenario: PathBuf,
    /// Master seed (overrides the scenario's).
    #[arg(long)]
    pub(crate) seed: Option<u64>,
    /// Simulated seconds to run at most (overrides the scenario's end time).
    #[arg(long, value_name = "SECONDS")]
    pub(crate) until: Option<f64>,
    /// Paces the run at X simulated seconds per wall second (0.1 to 1000); default: as fast
    /// as possible. Pacing never changes the outcome.
    #[arg(long, value_name = "X")]
    pub(crate) speed: Option<f64>,
    /// Runs every entity type at the levels of this preset (discrete, interpolated,
    /// physical) instead of the file's — mission scenarios only.
    #[arg(long, value_name = "PRESET", value_parser = ["discrete", "interpolated", "physical"])]
    pub(crate) fidelity: Option<String>,
    /// Records the run to an MCAP file (Foxglove schemas) — mission scenarios only.
    #[arg(long, value_name = "FILE.mcap")]
    pub(crate) record: Option<PathBuf>,
    /// Saves the run's state at this simulated time to the file --save names (the run goes
    /// on to its end); `vitro resume FILE` continues it.
    #[arg(long, value_name = "SECONDS", requires = "save")]
    pub(crate) save_at: Option<f64>,
    /// The snapshot file --save-at writes.
    #[arg(long, value_name = "FILE", requires = "save_at")]
    pub(crate) save: Option<PathBuf>,
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

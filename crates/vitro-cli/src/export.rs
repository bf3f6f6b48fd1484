//! `vitro export kml RUN.mcap [--out FILE.kml]`: a recording's entity tracks for Google Earth.

use crate::Failure;
use anyhow::anyhow;
use clap::Subcommand;
use std::fs::File;
use std::io::{BufWriter, Write};
use std::path::{Path, PathBuf};
use vitro_record::{Replay, ReplayError, kml};

/// What to export a recording to.
#[derive(Debug, Subcommand)]
pub(crate) enum ExportCommand {
    /// KML 2.2 for Google Earth: one track per entity, styled by side, and the named places.
    Kml {
        /// The recording (MCAP, as `vitro run --record` writes it).
        recording: PathBuf,
        /// Where to write the KML (default: standard output).
        #[arg(long)]
        out: Option<PathBuf>,
    },
}

/// Runs an export command.
pub(crate) fn export(cmd: &ExportCommand) -> Result<(), Failure> {
    match cmd {
        ExportCommand::Kml { recording, out } => export_kml(recording, out.as_deref()),
    }
}

/// A recording that cannot be read is bad input (exit 2), unless reading itself failed.
fn reading(path: &Path, e: ReplayError) -> Failure {
    match e {
        ReplayError::Missing { .. } | ReplayError::Open { .. } => Failure::Input(e.into()),
        ReplayError::Io(_) => Failure::Runtime(anyhow!("{}: {e}", path.display())),
        other => Failure::Input(anyhow!("{}: {other}", path.display())),
    }
}

fn export_kml(recording: &Path, out: Option<&Path>) -> Result<(), Failure> {
    vitro_tools::input_file(recording)?;
    let mut replay = Replay::open(recording).map_err(|e| reading(recording, e))?;
    let mut tracks = kml::Tracks::new();
    for frame in replay.frames() {
        tracks.add(&frame.map_err(|e| reading(recording, e))?);
    }
    let written = match out {
        Some(path) => File::create(path)
            .and_then(|f| {
                let mut w = BufWriter::new(f);
                tracks.write(replay.scene(), &mut w)?;
                w.flush()
            })
            .map_err(|e| anyhow!("writing {}: {e}", path.display())),
        None => {
            let mut w = BufWriter::new(std::io::stdout().lock());
            tracks
                .write(replay.scene(), &mut w)
                .and_then(|()| w.flush())
                .map_err(|e| anyhow!("writing the KML: {e}"))
        }
    };
    written.map_err(Failure::Runtime)?;
    if let Some(path) = out {
        eprintln!(
            "{}: {} tracks over {} frames{}",
            path.display(),
            tracks.len(),
            replay.len(),
            if replay.is_complete() {
                ""
            } else {
                " (an unfinished recording: its readable part)"
            }
        );
    }
    Ok(())
}

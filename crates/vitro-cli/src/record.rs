//! `--record`: writes the run's frames to a file as they are sampled.

use anyhow::Context as _;
use std::path::Path;
use vitro_tactical::evac::Mission;

/// A recording under way.
pub(crate) struct Recording {
    out: std::io::BufWriter<std::fs::File>,
}

impl Recording {
    /// Starts a recording of `mission` at `path` (writes the scene).
    pub(crate) fn create(path: &Path, mission: &Mission) -> anyhow::Result<Recording> {
        use std::io::Write as _;
        let file = std::fs::File::create(path)
            .with_context(|| format!("cannot create {}", path.display()))?;
        let mut out = std::io::BufWriter::new(file);
        serde_json::to_writer(&mut out, &mission.scene())?;
        writeln!(out)?;
        Ok(Recording { out })
    }
    /// Records the mission's current frame.
    pub(crate) fn frame(&mut self, mission: &mut Mission) -> anyhow::Result<()> {
        use std::io::Write as _;
        serde_json::to_writer(&mut self.out, &mission.frame())?;
        writeln!(self.out)?;
        Ok(())
    }
    /// Ends the recording.
    pub(crate) fn finish(mut self) -> anyhow::Result<()> {
        use std::io::Write as _;
        self.out.flush()?;
        Ok(())
    }
}

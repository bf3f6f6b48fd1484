//! `--record`: writes the run to MCAP (Foxglove schemas plus Vitro's lossless channels) as
//! frames are sampled; see [`vitro_record::Recorder`].

use anyhow::Context as _;
use std::path::Path;
use vitro_mission::Run;

/// A recording under way.
pub(crate) struct Recording {
    rec: vitro_record::Recorder<std::io::BufWriter<std::fs::File>>,
}

impl Recording {
    /// Starts a recording of `run` at `path` (writes the scene).
    pub(crate) fn create(path: &Path, run: &dyn Run) -> anyhow::Result<Recording> {
        let rec = vitro_record::Recorder::create(path, &run.scene())
            .with_context(|| format!("cannot record to {}", path.display()))?;
        Ok(Recording { rec })
    }
    /// Records the run's current frame.
    pub(crate) fn frame(&mut self, run: &mut dyn Run) -> anyhow::Result<()> {
        self.rec.frame(&run.frame()).context("writing a frame")?;
        Ok(())
    }
    /// Ends the recording (writes the MCAP summary).
    pub(crate) fn finish(self) -> anyhow::Result<()> {
        self.rec.finish().context("closing the recording")?;
        Ok(())
    }
}

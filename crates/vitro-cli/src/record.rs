//! `--record`: writes the run to MCAP (Foxglove schemas plus Vitro's lossless channels) as
//! frames are sampled; see [`vitro_record::Recorder`].

use anyhow::Context as _;
use std::path::Path;
use vitro_evac::Mission;

/// A recording under way.
pub(crate) struct Recording {
    rec: vitro_record::Recorder<std::io::BufWriter<std::fs::File>>,
}

impl Recording {
    /// Starts a recording of `mission` at `path` (writes the scene).
    pub(crate) fn create(path: &Path, mission: &Mission) -> anyhow::Result<Recording> {
        let rec = vitro_record::Recorder::create(path, &mission.scene())
            .with_context(|| format!("cannot record to {}", path.display()))?;
        Ok(Recording { rec })
    }
    /// Records the mission's current frame.
    pub(crate) fn frame(&mut self, mission: &mut Mission) -> anyhow::Result<()> {
        self.rec
            .frame(&mission.frame())
            .context("writing a frame")?;
        Ok(())
    }
    /// Ends the recording (writes the MCAP summary).
    pub(crate) fn finish(self) -> anyhow::Result<()> {
        self.rec.finish().context("closing the recording")?;
        Ok(())
    }
}

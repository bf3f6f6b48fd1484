//! The registry: every mission a tool knows, by kind.

use crate::kind::{KindError, kind_of};
use crate::snapshot::{Snapshot, SnapshotError};
use crate::{BuildOptions, Mission, MissionError, Run};
use std::path::{Path, PathBuf};
use vitro::time::SimTime;

/// Why a scenario file could not be given to its mission.
///
/// Fatal to the run asked for; [`RegistryError::is_bad_input`] says whose fault. New variants
/// may be added.
#[derive(Debug, thiserror::Error)]
#[non_exhaustive]
pub enum RegistryError {
    /// The file could not be read.
    #[error("cannot read {}: {source}", .file.display())]
    Read {
        /// The file.
        file: PathBuf,
        /// Why.
        source: std::io::Error,
    },
    /// The file names no kind, or one nobody registered.
    #[error(transparent)]
    Kind(#[from] KindError),
    /// The mission refused the file or could not build it.
    #[error(transparent)]
    Mission(#[from] MissionError),
}

impl RegistryError {
    /// True if the problem is the input's (exit code 2), false if a run failed to set up.
    pub fn is_bad_input(&self) -> bool {
        match self {
            RegistryError::Mission(e) => e.is_bad_input(),
            RegistryError::Read { .. } | RegistryError::Kind(_) => true,
        }
    }
}

/// The missions a tool knows, looked up by the `kind` a scenario file names.
///
/// ```
/// use vitro_mission::Registry;
/// let registry = Registry::new(Vec::new());
/// assert!(registry.kinds().is_empty());
/// ```
pub struct Registry {
    missions: Vec<&'static dyn Mission>,
}

impl Registry {
    /// A registry of `missions` (kinds must differ).
    ///
    /// # Panics
    /// If two missions share a kind: a programming error of the tool that builds it.
    pub fn new(missions: Vec<&'static dyn Mission>) -> Registry {
        for (i, m) in missions.iter().enumerate() {
            assert!(
                missions[..i].iter().all(|o| o.kind() != m.kind()),
                "two missions registered as {:?}",
                m.kind()
            );
        }
        Registry { missions }
    }

    /// The registered kinds, in registration order.
    pub fn kinds(&self) -> Vec<&'static str> {
        self.missions.iter().map(|m| m.kind()).collect()
    }

    /// The missions, in registration order.
    pub fn missions(&self) -> &[&'static dyn Mission] {
        &self.missions
    }

    /// The mission registered as `kind`.
    pub fn get(&self, kind: &str) -> Option<&'static dyn Mission> {
        self.missions.iter().copied().find(|m| m.kind() == kind)
    }

    /// The mission a scenario text is for.
    ///
    /// # Errors
    /// [`RegistryError::Kind`] if the text names no registered kind.
    pub fn mission_of(
        &self,
        file: &Path,
        text: &str,
    ) -> Result<&'static dyn Mission, RegistryError> {
        let kind = kind_of(file, text, &self.kinds())?;
        // kind_of accepts registered kinds only.
        Ok(self
            .get(&kind)
            .ok_or_else(|| MissionError::Scenario(format!("no mission registered as {kind}")))?)
    }

    /// Reads a scenario file: its mission and its text.
    ///
    /// # Errors
    /// [`RegistryError::Read`] or [`RegistryError::Kind`].
    pub fn read(&self, file: &Path) -> Result<(&'static dyn Mission, String), RegistryError> {
        let text = std::fs::read_to_string(file).map_err(|source| RegistryError::Read {
            file: file.to_path_buf(),
            source,
        })?;
        Ok((self.mission_of(file, &text)?, text))
    }

    /// Validates a scenario file with its mission: the mission and its summary line.
    ///
    /// # Errors
    /// Any [`RegistryError`].
    pub fn validate(&self, file: &Path) -> Result<(&'static dyn Mission, String), RegistryError> {
        let (mission, text) = self.read(file)?;
        Ok((mission, mission.validate(file, &text)?))
    }

    /// Builds a run of a scenario file.
    ///
    /// # Errors
    /// Any [`RegistryError`].
    pub fn build(
        &self,
        file: &Path,
        options: &BuildOptions,
    ) -> Result<Box<dyn Run>, RegistryError> {
        let (mission, text) = self.read(file)?;
        Ok(mission.build(file, &text, options)?)
    }

    /// The run a snapshot holds, ready to go on: its scenario built again with its options,
    /// its state restored, and its time and trace hash checked against the snapshot's. It
    /// ends where the saved run would have, or at `until` (no later than the scenario's own
    /// end).
    ///
    /// # Errors
    /// [`SnapshotError::UnknownKind`], [`SnapshotError::Build`], or the mission's
    /// [`Run::restore_state`] errors.
    pub fn resume(
        &self,
        snap: &Snapshot,
        until: Option<SimTime>,
    ) -> Result<Box<dyn Run>, SnapshotError> {
        let mission = self
            .get(&snap.kind)
            .ok_or_else(|| SnapshotError::UnknownKind(snap.kind.clone()))?;
        let path = Path::new(&snap.scenario);
        let mut run = mission
            .build(path, &snap.text, &snap.options())
            .map_err(|e| SnapshotError::Build(e.to_string()))?;
        let end = until.map_or(SimTime::from_nanos(snap.end_ns), |u| u.min(run.end()));
        run.set_end(end);
        run.restore_state(&snap.state)?;
        if run.now().as_nanos() != snap.saved_at_ns || run.trace_hash() != snap.trace_hash {
            return Err(SnapshotError::Mismatch(format!(
                "the restored run is at {:.3} s with trace hash {:016x}, the snapshot says {:.3} s and {:016x}",
                run.now().as_secs_f64(),
                run.trace_hash(),
                snap.saved_at_ns as f64 / 1e9,
                snap.trace_hash
            )));
        }
        Ok(run)
    }
}

//! Snapshot and restore of a whole simulation (environment, agents, queue, streams, trace).
//!
//! A restored run continues exactly as the uninterrupted one would have: same events, same
//! random numbers, same trace hash. Listeners, the control handle and the clock are not part of
//! the state and must be set again.

use super::agent::Model;
use super::driver::Simulation;
use super::kernel::Kernel;
use serde::Serialize;
use serde::de::DeserializeOwned;
use std::io::{Read, Write};

/// Everything a snapshot holds, in order.
type State<M> = (
    <M as Model>::Env,
    Vec<Option<<M as Model>::Agent>>,
    Kernel<<M as Model>::Event, <M as Model>::Msg>,
);

const MAGIC: &[u8; 8] = b"VITROSN1";

/// Why a snapshot could not be written or read.
#[derive(Debug, thiserror::Error)]
pub enum SnapshotError {
    /// Reading or writing failed.
    #[error("snapshot I/O: {0}")]
    Io(#[from] std::io::Error),
    /// The bytes are not a snapshot of this format.
    #[error("not a Vitro snapshot (bad header)")]
    BadHeader,
    /// The state could not be encoded or decoded.
    #[error("snapshot encoding: {0}")]
    Encoding(#[from] postcard::Error),
}

impl<M: Model> Simulation<M>
where
    M::Env: Serialize + DeserializeOwned,
    M::Agent: Serialize + DeserializeOwned,
    M::Event: DeserializeOwned,
    M::Msg: DeserializeOwned,
{
    /// Writes the whole state of the simulation.
    pub fn save_snapshot(&self, mut w: impl Write) -> Result<(), SnapshotError> {
        let bytes = postcard::to_stdvec(&(&self.env, &self.agents, &self.k))?;
        w.write_all(MAGIC)?;
        w.write_all(&(bytes.len() as u64).to_le_bytes())?;
        w.write_all(&bytes)?;
        Ok(())
    }

    /// Rebuilds a simulation from [`save_snapshot`](Self::save_snapshot)'s bytes.
    pub fn load_snapshot(mut r: impl Read) -> Result<Self, SnapshotError> {
        let mut head = [0u8; 16];
        r.read_exact(&mut head)?;
        if &head[..8] != MAGIC {
            return Err(SnapshotError::BadHeader);
        }
        let len = u64::from_le_bytes(head[8..].try_into().expect("8 bytes"));
        let mut bytes = Vec::new();
        r.take(len).read_to_end(&mut bytes)?;
        let (env, agents, k): State<M> = postcard::from_bytes(&bytes)?;
        Ok(Simulation::from_parts(env, agents, k))
    }
}

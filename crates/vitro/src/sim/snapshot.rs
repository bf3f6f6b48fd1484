//! Snapshot and restore of a whole simulation (environment, agents, queue, streams, trace).
//!
//! A restored run continues exactly as the uninterrupted one would have: same events, same
//! random numbers, same trace hash. Listeners, the control handle and the clock are not part of
//! the state and must be set again.

use super::agent::Model;
use super::driver::Simulation;
use super::kernel::Kernel;
use crate::time::SimTime;
use serde::de::DeserializeOwned;
use serde::{Deserialize, Serialize};
use std::io::{Read, Write};

/// Everything a snapshot holds, in order.
type State<M> = (
    <M as Model>::Env,
    Vec<Option<<M as Model>::Agent>>,
    Kernel<<M as Model>::Event, <M as Model>::Msg>,
);

/// The header; its number changes with the layout (2: rounds, small random streams, entity
/// names without their index), so that an older snapshot is refused as such.
const MAGIC: &[u8; 8] = b"VITROSN2";

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

/// A simulation's state for saving, borrowed: the environment's and the agents' saved forms
/// (`E`, `A`, chosen by the model: e.g. without the static world, or an enum of agent kinds
/// where agents are trait objects) and the kernel (queue, random streams, entities, register,
/// network, trace). Serialize it with any serde format; read it back as a [`SimState`].
#[derive(Serialize)]
pub struct SimStateRef<'a, E, A, Ev, Msg> {
    env: E,
    agents: Vec<Option<A>>,
    kernel: &'a Kernel<Ev, Msg>,
}

/// A simulation's saved state, owned: what [`SimStateRef`] wrote, read back.
#[derive(Deserialize)]
#[serde(bound(
    deserialize = "E: Deserialize<'de>, A: Deserialize<'de>, Ev: Deserialize<'de>, Msg: Deserialize<'de>"
))]
pub struct SimState<E, A, Ev, Msg> {
    env: E,
    agents: Vec<Option<A>>,
    kernel: Kernel<Ev, Msg>,
}

impl<E, A, Ev, Msg> SimState<E, A, Ev, Msg> {
    /// The simulated time the state was saved at.
    pub fn now(&self) -> SimTime {
        self.kernel.queue.now()
    }
}

impl<M: Model> Simulation<M> {
    /// The state of the simulation for saving, with the environment given as `env` (its
    /// saved form) and each agent turned into its saved form by `agent`. Nothing is cloned:
    /// the result borrows the simulation.
    ///
    /// # Errors
    /// The first error of `agent` (e.g. an agent of a kind that cannot be saved).
    pub fn save_state<'a, E, A, X>(
        &'a self,
        env: E,
        mut agent: impl FnMut(&'a M::Agent) -> Result<A, X>,
    ) -> Result<SimStateRef<'a, E, A, M::Event, M::Msg>, X> {
        let agents = self
            .agents
            .iter()
            .map(|a| a.as_ref().map(&mut agent).transpose())
            .collect::<Result<_, X>>()?;
        Ok(SimStateRef {
            env,
            agents,
            kernel: &self.k,
        })
    }

    /// Rebuilds a simulation from a [`SimState`]: `env` makes the environment of its saved
    /// form, `agent` each agent of its saved form. Listeners, the control handle's settings
    /// and the clock are not part of the state and must be set again.
    ///
    /// # Errors
    /// The first error of `env` or `agent`.
    pub fn restore_state<E, A, X>(
        state: SimState<E, A, M::Event, M::Msg>,
        env: impl FnOnce(E) -> Result<M::Env, X>,
        mut agent: impl FnMut(A) -> Result<M::Agent, X>,
    ) -> Result<Self, X> {
        let env = env(state.env)?;
        let agents = state
            .agents
            .into_iter()
            .map(|a| a.map(&mut agent).transpose())
            .collect::<Result<_, X>>()?;
        Ok(Simulation::from_parts(env, agents, state.kernel))
    }
}

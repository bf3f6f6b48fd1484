//! Serde for an agent's shared, briefed part (`Arc<T>`: a briefing, a solved game) that the
//! scenario rebuilds: nothing is written, and reading takes the value of the run being
//! restored, put in place by a [`Restoring`] guard for the time the agents are read.
//!
//! ```
//! use serde::{Deserialize, Serialize};
//! use std::sync::Arc;
//! use vitro_mission::snapshot::briefed::Restoring;
//!
//! struct Brief(u32);
//!
//! #[derive(Serialize, Deserialize)]
//! struct Agent {
//!     #[serde(with = "vitro_mission::snapshot::briefed")]
//!     brief: Arc<Brief>,
//!     fuel: u32,
//! }
//!
//! let bytes = postcard::to_stdvec(&Agent { brief: Arc::new(Brief(1)), fuel: 9 }).unwrap();
//! let agent: Agent = {
//!     let _shared = Restoring::new().with(Arc::new(Brief(2)));
//!     postcard::from_bytes(&bytes).unwrap()
//! };
//! assert_eq!((agent.brief.0, agent.fuel), (2, 9));
//! // Outside a `Restoring`, there is nothing to read it from.
//! assert!(postcard::from_bytes::<Agent>(&bytes).is_err());
//! ```

use serde::de::Error as _;
use serde::{Deserialize, Deserializer, Serializer};
use std::any::Any;
use std::cell::RefCell;
use std::marker::PhantomData;
use std::sync::Arc;

thread_local! {
    /// The shared values (each an `Arc<T>`, one per type) while a [`Restoring`] lives.
    static SHARED: RefCell<Vec<Box<dyn Any>>> = const { RefCell::new(Vec::new()) };
}

/// Holds the shared values that agents read on this thread take, until dropped.
#[must_use = "the values are shared only while the guard lives"]
pub struct Restoring {
    /// The values live in this thread's storage: the guard stays on it.
    _thread: PhantomData<*const ()>,
}

impl Restoring {
    /// A guard sharing nothing yet (whatever an earlier guard left is cleared).
    pub fn new() -> Restoring {
        SHARED.with(|s| s.borrow_mut().clear());
        Restoring {
            _thread: PhantomData,
        }
    }

    /// Shares `value` with the agents read while the guard lives, in place of any value of
    /// the same type shared before.
    pub fn with<T: 'static>(self, value: Arc<T>) -> Restoring {
        SHARED.with(|s| {
            let mut s = s.borrow_mut();
            s.retain(|v| !v.is::<Arc<T>>());
            s.push(Box::new(value));
        });
        self
    }

    /// Shares `value` if there is one (see [`with`](Self::with)).
    pub fn with_some<T: 'static>(self, value: Option<Arc<T>>) -> Restoring {
        match value {
            Some(v) => self.with(v),
            None => self,
        }
    }
}

impl Default for Restoring {
    fn default() -> Restoring {
        Restoring::new()
    }
}

impl Drop for Restoring {
    fn drop(&mut self) {
        SHARED.with(|s| s.borrow_mut().clear());
    }
}

/// Writes nothing (a unit).
///
/// # Errors
/// The serializer's, if it cannot write a unit.
pub fn serialize<T, S: Serializer>(_: &Arc<T>, s: S) -> Result<S::Ok, S::Error> {
    s.serialize_unit()
}

/// The value of type `T` shared by the [`Restoring`] guard of this thread.
///
/// # Errors
/// The deserializer's, if the input holds no unit; a custom error if no guard shares a `T`.
pub fn deserialize<'de, T: 'static, D: Deserializer<'de>>(d: D) -> Result<Arc<T>, D::Error> {
    <()>::deserialize(d)?;
    SHARED
        .with(|s| {
            s.borrow()
                .iter()
                .find_map(|v| v.downcast_ref::<Arc<T>>().cloned())
        })
        .ok_or_else(|| {
            D::Error::custom(format!(
                "no {} to restore the agents with",
                std::any::type_name::<T>()
            ))
        })
}

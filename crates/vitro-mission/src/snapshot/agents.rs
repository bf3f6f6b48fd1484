//! Boxed agents saved as an enum of their kinds: [`agent_kinds!`](crate::agent_kinds).

/// Declares the agent kinds of a model whose agents are boxed trait objects (each kind with
/// its own serde derives), for [`Simulation::save_state`](vitro::sim::Simulation::save_state)
/// and `restore_state`: an enum `AgentRef` (borrowed, written), an enum `AgentOwned` (read
/// back, boxed: the same encoding), `agent_ref` (a boxed agent to its kind, by its trait's
/// `as_any`) and `agent_box` (back to the box).
///
/// ```
/// use serde::{Deserialize, Serialize};
/// use std::any::Any;
/// use vitro_mission::SnapshotError;
///
/// trait Unit {
///     fn as_any(&self) -> &dyn Any;
/// }
/// #[derive(Serialize, Deserialize)]
/// struct Scout(u32);
/// impl Unit for Scout {
///     fn as_any(&self) -> &dyn Any {
///         self
///     }
/// }
///
/// vitro_mission::agent_kinds! { Box<dyn Unit>: Scout(Scout), }
///
/// let agent: Box<dyn Unit> = Box::new(Scout(4));
/// let bytes = postcard::to_stdvec(&agent_ref(&agent).unwrap()).unwrap();
/// let back = agent_box(postcard::from_bytes(&bytes).unwrap()).unwrap();
/// assert_eq!(back.as_any().downcast_ref::<Scout>().unwrap().0, 4);
/// ```
#[macro_export]
macro_rules! agent_kinds {
    ($agent:ty: $($kind:ident($ty:ty),)*) => {
        /// An agent, borrowed, for saving.
        #[derive(serde::Serialize)]
        enum AgentRef<'a> {
            $($kind(&'a $ty),)*
        }
        /// An agent read back (boxed, as it will live: the same encoding as the borrowed
        /// form).
        #[derive(serde::Deserialize)]
        enum AgentOwned {
            $($kind(Box<$ty>),)*
        }
        /// The kind of a boxed agent, borrowed.
        #[allow(clippy::borrowed_box)] // the model's agent type is the box
        fn agent_ref(c: &$agent) -> Result<AgentRef<'_>, $crate::SnapshotError> {
            let any = (**c).as_any();
            $(if let Some(a) = any.downcast_ref::<$ty>() {
                return Ok(AgentRef::$kind(a));
            })*
            Err($crate::SnapshotError::Unsupported(format!(
                "a run with an agent of another kind ({:?})",
                any.type_id()
            )))
        }
        /// A kind read back, boxed.
        fn agent_box(a: AgentOwned) -> Result<$agent, $crate::SnapshotError> {
            Ok(match a {
                $(AgentOwned::$kind(a) => a as $agent,)*
            })
        }
    };
}

//! Ground vehicles' actuators at each level: `GoToNode` on top of each, then
//! `MoveInDirection` ([`interpolated`], [`physical`]) and `SteerAndAccelerate`
//! ([`physical`]).

pub mod interpolated;
pub mod physical;
mod recover;
mod traffic;
mod wheels;

/// The discrete level.
pub mod discrete {
    use crate::actuate::{MoveError, start_trip};
    use crate::arena::{Arena, Ev};
    use crate::entity::discrete::NodeKind;
    use vitro::entity::EntityId;
    use vitro::env::{Actuator, Effects, NodeId};

    /// GoToNode at the discrete level: the vehicle hops from node to node along the route,
    /// each hop at the time the route's speed profile (its type's power, mass, speed and
    /// acceleration limits, corner speeds, street limits) reaches the node.
    #[derive(Copy, Clone, Debug, Default)]
    pub struct GoToNode;

    impl Actuator<Arena, Ev> for GoToNode {
        type Command = NodeId;
        type Error = MoveError;
        fn actuate(
            &self,
            w: &mut Arena,
            me: EntityId,
            goal: NodeId,
            fx: &mut Effects<'_, Ev>,
        ) -> Result<(), MoveError> {
            start_trip(w, me, goal, |k| matches!(k, NodeKind::Ground(_)), fx)
        }
    }
}

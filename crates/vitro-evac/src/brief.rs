//! The briefing: what every agent of the mission knows before it starts — who is on the
//! team, the map, the planned route, the places, the rules of engagement and the
//! algorithms' settings. Static, shared (`Arc`), never written during a run.

use crate::scenario::{MissionSpec, PatrolSpec, PursuitSpec, RepairSpec, SensorsSpec};
use std::sync::Arc;
use vitro::comm::GroupId;
use vitro::entity::EntityId;
use vitro::env::NodeId;
use vitro_behaviour::formation::FormationParams;
use vitro_site::geo::P2;
use vitro_site::map::Mode;
use vitro_site::site::Site;
use vitro_tactical::entity::Level;
use vitro_tactical::entity::roads::Roads;
use vitro_tactical::types::TroopKind;

/// The radio group of the blue side (contact reports go to it).
pub const BLUE: GroupId = GroupId(1);

/// The mission briefing.
#[derive(Debug)]
pub struct Brief {
    /// The town and terrain (every soldier has the map).
    pub site: Arc<Site>,
    /// The free street graphs.
    pub roads: Arc<Roads>,
    /// The truck (it also commands the team).
    pub truck: EntityId,
    /// The blue troopers, in id order.
    pub team: Vec<EntityId>,
    /// The VIP.
    pub vip: EntityId,
    /// The high-value target, if the scenario has one.
    pub hvt: Option<EntityId>,
    /// The drive-graph legs from the start to the safehouse (each leg's last node).
    pub legs_out: Vec<NodeId>,
    /// The drive-graph legs from the safehouse to the extraction point.
    pub legs_back: Vec<NodeId>,
    /// The drive-graph nodes of the whole route, in order (for the scouts).
    pub route: Vec<NodeId>,
    /// Where the VIP waits: the walk-graph node nearest its start in the scenario (the
    /// safehouse if it has none).
    pub vip_node: NodeId,
    /// World points of the start, the safehouse and the extraction point.
    pub places: [[f64; 3]; 3],
    /// The troopers' level.
    pub trooper_level: Level,
    /// Mission rules.
    pub mission: MissionSpec,
    /// Sensor settings.
    pub sensors: SensorsSpec,
    /// Patrol settings (the Skeldars).
    pub patrol: PatrolSpec,
    /// Pursuit settings (the HVT hunt and the HVT itself).
    pub pursuit: PursuitSpec,
    /// Cover-plan settings (the Vidars).
    pub repair: RepairSpec,
    /// The pursuit board (the walk graph with line of sight), if there is a target to hunt.
    pub board: Option<Arc<vitro_algo::pursuit::Arena>>,
    /// Length of a pursuit turn: the time to walk a typical walk-graph edge, seconds.
    pub turn_s: f64,
    /// How the escort walks in formation.
    pub formation: FormationBrief,
}

/// The squad's formation settings: the leader's rule program and the parameters of every
/// member (the scenario's `[formation]` table).
#[derive(Clone, Debug)]
pub struct FormationBrief {
    /// The leader's rule program, source text (the scenario's file or the built-in
    /// [`LEADER_PROGRAM`](vitro_behaviour::formation::LEADER_PROGRAM)); checked when the mission is
    /// built.
    pub program: String,
    /// The squad's parameters (spacing from the scenario).
    pub params: FormationParams,
}

impl Brief {
    /// The walk-graph node nearest a world point.
    pub fn walk_node(&self, world: [f64; 3]) -> Option<NodeId> {
        let p = self.site.to_town([world[0], world[1]]);
        self.roads.of(Mode::Walk).nearest_connected(p)
    }
    /// World point of a node of `mode`'s graph.
    pub fn node_point(&self, mode: Mode, n: NodeId) -> Option<[f64; 3]> {
        let p: P2 = self.roads.of(mode).graph.node(n)?.pos;
        Some(self.site.on_ground(p))
    }
    /// The trooper kind of a person of the team.
    pub fn troop_kind(&self, id: EntityId) -> TroopKind {
        if id == self.vip {
            TroopKind::Vip
        } else {
            TroopKind::Blue
        }
    }
}

//! Troop formations programmed in the rule language, on the [`Tactical`] model.
//!
//! A squad is a [`Leader`] and its [`Member`]s, each a [`Controller`] that reaches the world
//! only through its context: its own pose ([`OwnPose`](vitro_tactical::arena::OwnPose)), a tracking
//! sensor on the leader (members) or on the members (leader), the map sensors of [`sense`],
//! the troopers' actuators (`MoveAndTurn` at the directed level, `WalkToNode` at the
//! discrete level) and the radio. They work in any mission whose messages carry the
//! squad's four words ([`SquadTalk`]): fixes, contacts, commands and signals.
//!
//! # Patterns and slots
//!
//! [`Pattern`]s (file, column, line, wedge) give each member `k` (1, 2, ...) a slot offset
//! `(forward, left)` in the leader's frame, scaled by [`FormationParams::spacing`]. A slot
//! behind the leader is measured **along the leader's trail** (the way it walked), then
//! across it, so that a file turns corners the way the leader did; a slot abreast is
//! measured from the leader's heading, or from the bearing to the threat in contact
//! ([`slot_point`]). Obstacles ([`sense::FreeSlot`]): a slot in a forbidden zone moves to the
//! nearest free point ([`Site::nearest_free`](vitro_site::site::Site::nearest_free)); a slot that
//! is behind an obstacle as seen from the point of the leader's way it is measured from
//! (moved or not) is pulled in to the last free point before the obstacle, so that members
//! stay on the leader's side of houses; where there is room, a slot is kept 0.3 m off zone
//! edges.
//!
//! A member walks straight to its slot when that way is clear ([`sense::ClearWay`]);
//! otherwise it goes round by the leader's way (the slot's base point, or the nearest point
//! of the leader's trail in a straight line), else along the walk graph
//! ([`sense::WalkRoute`]), and one with no walk-graph node in a straight line backs out the
//! way it came. Ways are probed every 0.1 m (1 cm near their ends), so a body never enters a
//! zone by more than about a millimetre between probes (none was seen in the tests).
//!
//! # The programs
//!
//! Both controllers run a rule program ([`vitro_algo::rules`]) once per
//! [`FormationParams::period`]. The leader's program ([`LEADER_PROGRAM`],
//! `data/rules/formation/leader.jz`) chooses the formation and the pace and says when the
//! squad has arrived; the members' ([`MEMBER_PROGRAM`], `data/rules/formation/member.jz`)
//! choose how to reach their slots and report what they see. The modules (what a program
//! can ask and do) are listed at the top of each file.
//!
//! **Street or open ground.** Every second the leader probes the map
//! ([`sense::SideClearance`]) at four points of its route ([`PROBES`]): where it stands and
//! 5, 10 and 15 m ahead. At each it measures the free distance to the left and to the right,
//! across the route, up to [`FormationParams::street_reach`]. A point with forbidden ground
//! (a building and its buffer, or water) within that reach on **both** sides is in a street;
//! in a narrow one if the free width (left + right) is at most
//! [`FormationParams::narrow_width`]. The ground ahead ([`Ground`]) is *narrow* if two or
//! more probes are narrow, else a *street* if two or more are in a street, else *open* if
//! none is; with exactly one walled probe the previous reading stands. Looking ahead makes
//! the squad close up before it enters a street; asking for two probes (and none to leave)
//! ignores a single gap between houses or a lone house by the way. The program maps narrow
//! → file, street → column, open → wedge, once the last change is
//! [`FormationParams::settle`] old; contact → line, at once.
//!
//! **Contact.** A [`Contact`] report of a red body (from anyone), or a red trooper
//! the leader or a member sees ([`sense::Hostiles`]: within
//! [`FormationParams::sight_range`] and in line of sight). Members report what they see to
//! the leader as a `Contact`. Contact lasts [`FormationParams::contact_hold`] after the
//! latest report; the line faces the threat's bearing (briefed again when the bearing has
//! turned 10°), and the leader walks at its slow pace.
//!
//! **Stragglers.** The leader measures each member's distance to its slot. Beyond
//! [`FormationParams::lag_slow`] it slows down, beyond [`FormationParams::lag_wait`] it
//! halts, but never for longer than [`FormationParams::straggler_timeout`] in a row: after
//! that it walks on at its normal pace until the squad is in order again, so it cannot
//! deadlock. At the goal it reports arrival once every member is within
//! [`FormationParams::gather`] of its slot, or after the same timeout. A member whose body
//! is gone is dropped from the squad at the next cycle (the others are briefed again).
//!
//! # Radio protocol
//!
//! Each word goes inside the mission's own message type (`M::from(word)`).
//!
//! | message | from → to | effect |
//! |---|---|---|
//! | `Command::GoTo([x, y])` | anyone → leader | walk to the walk-graph node nearest to world point (x, y) with the squad; then `Signal::new("arrived", "")` back to the sender. A new `GoTo` replaces the one under way (its sender is not told) |
//! | `Command::Hold` | anyone → leader | stop where it stands (the squad keeps its slots); the `GoTo` under way is dropped |
//! | `Signal::new("join", "7")` | anyone → leader | entity 7 joins the squad (last slot) |
//! | `Signal::new("leave", "7")` | anyone → leader | entity 7 leaves the squad (and is told `formation none`) |
//! | `Signal::new("unreachable", "x y")` | leader → sender of a `GoTo` | no walk route there |
//! | `Signal::new("formation", "wedge 2 5 -")` | leader → member | pattern, slot number, spacing in metres, and the facing in radians (`-`: along the leader's way); sent on every change and every 10 s |
//! | `Signal::new("formation", "none")` | leader → member | dismissed: stand still until briefed again |
//! | `Contact { .. }` | member (or anyone) → leader | contact (if `seen_as` is red) |
//!
//! The id in `join` / `leave` is the decimal number inside the [`EntityId`]
//! (`id.0.to_string()`, e.g. `"7"`); `EntityId`'s `Display` writes `"#7"`, which is accepted
//! too. A member listens to briefings from its own leader only.
//!
//! # Levels
//!
//! At the **directed** level (x, y, heading) the leader follows its walk route with
//! `MoveAndTurn` at the route's Pandolf walking speed (halved to slow), and members steer to
//! their slots with `MoveAndTurn` at the speed that reaches the slot's position one period
//! ahead, capped at 1.25 × their walking speed, or at their running speed
//! ([`FormationParams::run_factor`]) when far.
//!
//! At the **discrete** level (walk-graph nodes) there is no `MoveAndTurn`: the leader hops
//! node by node with `WalkToNode` (it cannot slow down; it waits at each node for the
//! stragglers, the timeout counted afresh at every node and lengthened by the time to walk
//! the worst gap, since an edge can take minutes), and each member hops to the node nearest
//! its slot whenever it is at rest (every way being a walk on the graph, members probe no
//! straight ways: `clear` always holds). While the leader is on a hop, a member takes its slot
//! from the node the leader is hopping to ([`sense::NextNode`]: a hop is a straight piece
//! between nodes, so the leader's heading names it), so that the squad hops together
//! rather than a hop behind. The formation is then only as fine as the graph: slots snap to
//! nodes (often the leader's own), members bunch on them, and the leader measures lag
//! against the node nearest each slot. The squad still arrives gathered and still changes
//! formation (the tests: about 1.1 times the time a trooper alone takes; members on the
//! node nearest their slot at the median, within 10 to 16 m of it at the 95th percentile).
//!
//! # Example
//!
//! ```
//! use std::sync::Arc;
//! use vitro::prelude::*;
//! use vitro_tactical::arena::{Arena, Ev};
//! use vitro_tactical::entity::Level;
//! use vitro_behaviour::formation::{FormationParams, LEADER_PROGRAM, Leader, Member, Script};
//! use vitro_tactical::model::Tactical;
//! use vitro_tactical::radio::{Basic, Command, Signal};
//! use vitro_tactical::types::TroopKind;
//! # use vitro_site::{map::{MapConfig, TownMap}, site::{Site, SiteConfig}, terrain::Terrain};
//! # let root = concat!(env!("CARGO_MANIFEST_DIR"), "/../..");
//! # let map = TownMap::load(format!("{root}/data/maps/kotka.osm.pbf"), &MapConfig::default()).unwrap();
//! # let terrain = Terrain::load(format!("{root}/data/terrain/valley_64x64_90m.asc")).unwrap();
//! # let site = Arc::new(Site::new(map, terrain, &SiteConfig::default()).unwrap());
//! let arena = Arena::new(site);
//! let walk = &arena.roads.walk;
//! // Two walk-graph nodes in the town's south-west (town coordinates), 130 m apart.
//! let start = walk.nearest_connected([-608.6, -790.9]).unwrap();
//! let goal = arena.site.to_world(walk.graph.node(walk.nearest_connected([-484.1, -758.1]).unwrap()).unwrap().pos);
//! let mut sim = Simulation::<Tactical>::new(arena, 7);
//! let params = FormationParams::default();
//! // Ids are given in creation order: the leader will be entity 2.
//! let leader_id = EntityId(2);
//! let mut members = Vec::new();
//! for name in ["alpha", "bravo"] {
//!     let m = sim.add_agent(name, Box::new(Member::new(leader_id, params.clone()))).unwrap();
//!     members.push(m);
//! }
//! let leader = Leader::new(LEADER_PROGRAM, members.clone(), params.clone()).unwrap();
//! let leader = sim.add("leader", leader).unwrap();
//! assert_eq!(leader.id(), leader_id);
//! // The caller places the bodies.
//! for &id in members.iter().chain([&leader_id]) {
//!     sim.env_mut().add_trooper(id, TroopKind::Blue, Level::Directed, start, 0.0).unwrap();
//! }
//! // A commander orders the squad to the goal at t = 1 s.
//! let order = Basic::from(Command::GoTo(goal));
//! let hq = sim.add("hq", Script::new(vec![(SimTime::from_secs(1), leader_id, order)])).unwrap();
//! for id in [members[0], members[1], leader_id, hq.id()] {
//!     sim.schedule(SimTime::ZERO, Target::Entity(id), Ev::Start).unwrap();
//! }
//! sim.run_until(SimTime::from_secs(600));
//! let hq: &Script = sim.agent(&hq).unwrap();
//! assert!(hq.heard.iter().any(|(_, _, m)| *m == Basic::from(Signal::new("arrived", ""))));
//! let leader: &Leader = sim.agent(&leader).unwrap();
//! println!("formation {}, {} track points", leader.formation(), leader.trajectory().len());
//! ```
//!
//! [`Tactical`]: vitro_tactical::model::Tactical
//! [`Controller`]: vitro_tactical::model::Controller
//! [`SquadTalk`]: vitro_tactical::radio::SquadTalk
//! [`Contact`]: vitro_tactical::radio::Contact
//! [`EntityId`]: vitro::entity::EntityId

mod ground;
mod kb;
mod leader;
mod member;
mod motion;
mod pattern;
mod record;
mod script;
pub mod sense;

pub use ground::{Ground, PROBES};
pub use leader::Leader;
pub use member::Member;
pub use pattern::{Pattern, Trail, slot_point};
pub use record::{Arrival, Switch, TrackPoint};
pub use script::Script;

use serde::{Deserialize, Serialize};
use vitro::time::SimDuration;
use vitro_algo::rules::RuleError;

/// The leader's rule program (`data/rules/formation/leader.jz`).
/// How long a squad trusts the last position report of a member (at the leader) or of the
/// leader (at a member): every cycle the leader radios its fix to its members and each
/// member its own to the leader; older than this, a member counts as gone and the leader as
/// not seen.
pub const LINK_STALE: SimDuration = SimDuration::from_secs(10);

/// The time a squad-mate's fix is taken to at `level`: now (dead reckoning) on continuous
/// ground; the fix's own time at the discrete level, where a body stands on its node until
/// its hop ends (the fix's speed and heading then say which node it hops to).
fn at_level(
    fix: &crate::belief::Fix,
    now: vitro::time::SimTime,
    level: vitro_tactical::entity::Level,
) -> vitro::time::SimTime {
    if level == vitro_tactical::entity::Level::Discrete {
        fix.at
    } else {
        now
    }
}

/// The built-in leader program.
pub const LEADER_PROGRAM: &str = include_str!("../../../../data/rules/formation/leader.jz");
/// The members' rule program (`data/rules/formation/member.jz`).
pub const MEMBER_PROGRAM: &str = include_str!("../../../../data/rules/formation/member.jz");

/// Why a formation controller could not be built.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum FormationError {
    /// The rule program does not parse, or names a module or operation the controller
    /// lacks (with the program's line and column).
    #[error(transparent)]
    Program(#[from] RuleError),
    /// A parameter is out of its range.
    #[error("invalid formation parameter {name} = {value}: {why}")]
    Param {
        /// The parameter.
        name: &'static str,
        /// Its value.
        value: f64,
        /// What it must be.
        why: &'static str,
    },
}

/// The parameters of a squad (the leader's and the members' must agree on
/// [`spacing`](Self::spacing); the leader's is sent with each briefing and wins).
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct FormationParams {
    /// Distance between neighbours in a pattern, metres.
    pub spacing: f64,
    /// Deliberation period of every controller.
    pub period: SimDuration,
    /// A member farther than this from its slot runs (`far` in the member program), metres.
    pub far: f64,
    /// The squad is gathered at the goal when every member is this close to its slot, metres.
    pub gather: f64,
    /// The leader slows down while a member is farther than this from its slot, metres.
    pub lag_slow: f64,
    /// The leader halts while a member is farther than this from its slot, metres.
    pub lag_wait: f64,
    /// The longest the leader slows or waits for stragglers in a row (and waits at the goal
    /// for the squad to gather).
    pub straggler_timeout: SimDuration,
    /// The leader's speed when slowing, as a fraction of its walking speed.
    pub slow_factor: f64,
    /// A member's running speed as a multiple of its walking speed.
    pub run_factor: f64,
    /// The least time between two changes of formation driven by the ground.
    pub settle: SimDuration,
    /// How far across its route the leader looks for walls, each side, metres.
    pub street_reach: f64,
    /// A street whose free width is at most this is narrow, metres.
    pub narrow_width: f64,
    /// How long a contact lasts after its latest report or sighting.
    pub contact_hold: SimDuration,
    /// How far the squad sees red troopers (in line of sight), metres.
    pub sight_range: f64,
    /// How often the leader logs the squad's positions.
    pub log_every: SimDuration,
}

impl Default for FormationParams {
    /// 5 m spacing, 0.5 s period; members run beyond 4 m; gathered within 3 m; the leader
    /// slows beyond 6 m, halts beyond 12 m, for at most 45 s, slows to half its speed;
    /// running is 1.6 × walking; 20 s between ground-driven changes; walls looked for 15 m
    /// each side, narrow at 14 m free width or less (the town's houses stand back from the
    /// street behind yards; widths are between the 2 m buffers round the buildings); contact
    /// held 30 s, seen up to 150 m; positions logged every second.
    fn default() -> Self {
        FormationParams {
            spacing: 5.0,
            period: SimDuration::from_millis(500),
            far: 4.0,
            gather: 3.0,
            lag_slow: 6.0,
            lag_wait: 12.0,
            straggler_timeout: SimDuration::from_secs(45),
            slow_factor: 0.5,
            run_factor: 1.6,
            settle: SimDuration::from_secs(20),
            street_reach: 15.0,
            narrow_width: 14.0,
            contact_hold: SimDuration::from_secs(30),
            sight_range: 150.0,
            log_every: SimDuration::from_secs(1),
        }
    }
}

impl FormationParams {
    /// Checks every parameter's range.
    ///
    /// # Errors
    /// [`FormationError::Param`] for the first one out of range.
    pub fn validate(&self) -> Result<(), FormationError> {
        let positive = [
            ("spacing", self.spacing),
            ("period", self.period.as_secs_f64()),
            ("far", self.far),
            ("gather", self.gather),
            ("lag_slow", self.lag_slow),
            ("lag_wait", self.lag_wait),
            ("run_factor", self.run_factor),
            ("street_reach", self.street_reach),
            ("narrow_width", self.narrow_width),
            ("sight_range", self.sight_range),
            ("log_every", self.log_every.as_secs_f64()),
        ];
        for (name, value) in positive {
            if !(value.is_finite() && value > 0.0) {
                return Err(FormationError::Param {
                    name,
                    value,
                    why: "must be a positive number",
                });
            }
        }
        if !(self.slow_factor > 0.0 && self.slow_factor <= 1.0) {
            return Err(FormationError::Param {
                name: "slow_factor",
                value: self.slow_factor,
                why: "must be in (0, 1]",
            });
        }
        if self.lag_wait < self.lag_slow {
            return Err(FormationError::Param {
                name: "lag_wait",
                value: self.lag_wait,
                why: "must be at least lag_slow",
            });
        }
        Ok(())
    }
}

//! Aircraft: fixed-wing ([`ctol`]) and helicopter ([`vtol`]) UAVs, and the discrete level both
//! share: maneuvers between the cells of a tessellated grid ([`Lattice`]).
//!
//! The autopilots ([`crate::autopilot`]) take a [`FlightCommand`] at every level and keep
//! their progress in a [`Pilot`] row.

pub mod ctol;
pub mod vtol;

use crate::types::{CtolKind, CtolType, VtolKind, VtolType};
use serde::{Deserialize, Serialize};
use vitro::event::EventId;

/// What an autopilot is told to do.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub enum FlightCommand {
    /// Fly straight along `heading` (radians from east) at `altitude` (world metres), for ever.
    Straight {
        /// Course, radians from east.
        heading: f64,
        /// Altitude, world metres.
        altitude: f64,
        /// Airspeed, m/s; `None` for the type's cruise speed.
        speed: Option<f64>,
    },
    /// Fly through `points` in order; the agent hears [`Ev::Waypoint`](crate::arena::Ev) at
    /// each. Afterwards a helicopter hovers at the last point; a fixed-wing aircraft, which
    /// cannot stop, flies on straight.
    Waypoints {
        /// World points, metres.
        points: Vec<[f64; 3]>,
        /// Airspeed, m/s; `None` for the type's cruise speed.
        speed: Option<f64>,
    },
}

/// A turn and a climb of one lattice maneuver: each −1, 0 or +1 (45° left/right turn, one
/// layer down/up).
#[derive(Copy, Clone, Debug, PartialEq, Eq, PartialOrd, Ord, Hash, Serialize, Deserialize)]
pub struct Maneuver {
    /// Heading change in steps of 45° (+1 left).
    pub turn: i8,
    /// Layer change (+1 up).
    pub climb: i8,
}

/// An autopilot's progress on its command.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct Pilot {
    /// The command.
    pub cmd: FlightCommand,
    /// Index of the next waypoint (for [`FlightCommand::Waypoints`]).
    pub next: usize,
    /// Lattice fixed-wing only: the planned maneuvers to the next waypoint, last first.
    pub plan: Vec<Maneuver>,
}

/// The airframe of an aircraft.
#[derive(Copy, Clone, Debug, PartialEq, Eq, PartialOrd, Ord, Hash, Serialize, Deserialize)]
pub enum AirKind {
    /// Fixed-wing.
    Ctol(CtolKind),
    /// Helicopter.
    Vtol(VtolKind),
}

/// A tessellated grid of the air: square cells of `cell` metres in plan, layers of `layer`
/// metres in height.
#[derive(Copy, Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct Lattice {
    /// Cell side, metres.
    pub cell: f64,
    /// Layer height, metres.
    pub layer: f64,
    /// World point of cell (0, 0, 0).
    pub origin: [f64; 3],
}

/// The eight headings of the lattice, as cell steps: 0 = east, counter-clockwise.
pub const DIRS: [[i32; 2]; 8] = [
    [1, 0],
    [1, 1],
    [0, 1],
    [-1, 1],
    [-1, 0],
    [-1, -1],
    [0, -1],
    [1, -1],
];

impl Lattice {
    /// The fixed-wing lattice: cells as wide as the tightest turn at cruise speed (so a 45°
    /// heading change between neighbouring cells is within the turn performance: its chord
    /// is 0.77 turn radii), layers as high as the steepest climb over one cell allows.
    pub fn for_ctol(ty: &CtolType) -> Self {
        let cell = (ty.min_turn_radius() / 10.0).ceil().max(1.0) * 10.0;
        let layer = (cell * libm::tan(ty.max_flight_path_deg.to_radians()))
            .floor()
            .max(1.0);
        Lattice {
            cell,
            layer,
            origin: [0.0; 3],
        }
    }
    /// The helicopter lattice: 20 m cells, 5 m layers (so a commanded altitude is held
    /// within 2.5 m).
    pub fn for_vtol(_: &VtolType) -> Self {
        Lattice {
            cell: 20.0,
            layer: 5.0,
            origin: [0.0; 3],
        }
    }
    /// The world point at the centre of `c`.
    pub fn point(&self, c: [i32; 3]) -> [f64; 3] {
        [
            self.origin[0] + f64::from(c[0]) * self.cell,
            self.origin[1] + f64::from(c[1]) * self.cell,
            self.origin[2] + f64::from(c[2]) * self.layer,
        ]
    }
    /// The cell whose centre is nearest to world point `p`.
    pub fn cell_of(&self, p: [f64; 3]) -> [i32; 3] {
        [
            libm::round((p[0] - self.origin[0]) / self.cell) as i32,
            libm::round((p[1] - self.origin[1]) / self.cell) as i32,
            libm::round((p[2] - self.origin[2]) / self.layer) as i32,
        ]
    }
}

/// The lattice heading (0..8) nearest to `heading` radians.
pub fn dir_of(heading: f64) -> u8 {
    let k = libm::round(heading / std::f64::consts::FRAC_PI_4) as i64;
    k.rem_euclid(8) as u8
}

/// An aircraft on its lattice (discrete level).
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct LatticeBody {
    /// The airframe.
    pub kind: AirKind,
    /// Its grid.
    pub lattice: Lattice,
    /// The cell it is in (the last one reached).
    pub cell: [i32; 3],
    /// Lattice heading 0..8 (45° steps from east).
    pub dir: u8,
    /// Speed of the maneuver under way, m/s (0 when a helicopter hovers).
    pub speed: f64,
    /// The maneuver under way: the cell it leads to and the heading there.
    pub moving_to: Option<([i32; 3], u8)>,
    /// The pending end-of-maneuver event.
    pub pending: Option<EventId>,
}

impl LatticeBody {
    /// Heading, radians from east.
    pub fn heading(&self) -> f64 {
        f64::from(self.dir) * std::f64::consts::FRAC_PI_4
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::types::TypeBook;

    #[test]
    fn lattice_cells_round_trip_and_fit_the_turn() {
        let b = TypeBook::builtin();
        let ty = b.ctol(CtolKind::Procerus);
        let l = Lattice::for_ctol(ty);
        assert!(l.cell >= ty.min_turn_radius());
        assert!(l.layer <= l.cell * libm::tan(ty.max_flight_path_deg.to_radians()));
        for c in [[0, 0, 0], [3, -7, 12], [-40, 2, 1]] {
            assert_eq!(l.cell_of(l.point(c)), c);
        }
        assert_eq!(dir_of(0.1), 0);
        assert_eq!(dir_of(std::f64::consts::PI), 4);
        assert_eq!(dir_of(-std::f64::consts::FRAC_PI_4), 7);
    }
}

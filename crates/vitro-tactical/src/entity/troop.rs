//! The directed level of troopers: a position on the ground and a heading. MoveAndTurn turns
//! the body towards a point at the type's turn rate while walking at a commanded speed; the
//! body only makes way in the direction it faces (`speed × cos(heading error)`, none while
//! facing more than 90° away), so corners cost the time of the turn.

use super::route::wrap_angle;
use crate::types::TroopKind;
use serde::{Deserialize, Serialize};
use vitro::env::NodeId;
use vitro_site::geo::dist;

/// What MoveAndTurn asks: face `toward` and walk at `speed`.
#[derive(Copy, Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct StepCmd {
    /// The point to walk to, world metres (height ignored).
    pub toward: [f64; 3],
    /// Walking speed, m/s.
    pub speed: f64,
}

/// A trooper on the ground.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct Walker {
    /// Its type.
    pub kind: TroopKind,
    /// The last walk-graph node it passed (or started at).
    pub node: NodeId,
    /// World position on the ground, metres.
    pub pos: [f64; 3],
    /// Heading, radians from east.
    pub heading: f64,
    /// Speed over the ground in the last step, m/s.
    pub speed: f64,
    /// The command being followed.
    pub cmd: Option<StepCmd>,
}

impl Walker {
    /// Turns for up to `turn` radians towards the command's point, then walks up to
    /// `budget_s` seconds' worth of way; returns the seconds left over if the point was
    /// reached. The height comes from `ground`.
    pub fn step(
        &mut self,
        turn: f64,
        budget_s: f64,
        ground: impl Fn([f64; 2]) -> Option<f64>,
    ) -> Option<f64> {
        let Some(cmd) = self.cmd else {
            self.speed = 0.0;
            return None;
        };
        let (p, q) = ([self.pos[0], self.pos[1]], [cmd.toward[0], cmd.toward[1]]);
        let d = dist(p, q);
        if d < 1e-9 {
            return Some(budget_s);
        }
        let want = libm::atan2(q[1] - p[1], q[0] - p[0]);
        let err = wrap_angle(want - self.heading);
        self.heading = wrap_angle(self.heading + err.clamp(-turn, turn));
        let err = wrap_angle(want - self.heading);
        let facing = libm::cos(err);
        let way = if facing > 1e-9 {
            cmd.speed * facing
        } else {
            0.0
        };
        self.speed = way;
        if way <= 0.0 {
            return None;
        }
        let reach = way * budget_s;
        if reach >= d {
            self.pos = [q[0], q[1], ground(q).unwrap_or(self.pos[2])];
            return Some(budget_s - d / way);
        }
        let f = reach / d;
        let r = [p[0] + f * (q[0] - p[0]), p[1] + f * (q[1] - p[1])];
        self.pos = [r[0], r[1], ground(r).unwrap_or(self.pos[2])];
        None
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn turns_before_making_way() {
        let mut w = Walker {
            kind: TroopKind::Blue,
            node: NodeId(0),
            pos: [0.0; 3],
            heading: std::f64::consts::PI,
            speed: 0.0,
            cmd: Some(StepCmd {
                toward: [10.0, 0.0, 0.0],
                speed: 1.0,
            }),
        };
        // Facing away: a quarter turn makes no way yet.
        assert_eq!(
            w.step(std::f64::consts::FRAC_PI_2, 1.0, |_| Some(0.0)),
            None
        );
        assert_eq!(w.pos, [0.0; 3]);
        // Facing the point: walks 1 m in 1 s.
        w.step(std::f64::consts::FRAC_PI_2, 1.0, |_| Some(0.0));
        assert!(w.heading.abs() < 1e-12 && (w.pos[0] - 1.0).abs() < 1e-12);
        // Reaching the point leaves the rest of the second.
        w.pos = [9.5, 0.0, 0.0];
        let left = w.step(1.0, 1.0, |_| Some(2.0));
        assert!(left.is_some_and(|l| (l - 0.5).abs() < 1e-12) && w.pos == [10.0, 0.0, 2.0]);
    }
}

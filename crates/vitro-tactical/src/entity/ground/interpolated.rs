//! The interpolated level: a vehicle at a point of the ground mesh, moving straight towards
//! a commanded point at a commanded speed, reached under its type's acceleration limits
//! (traction, engine power, resistances and grade through
//! [`GroundType::accel_limit`](crate::types::GroundType::accel_limit); braking at
//! `max_decel`). GoToNode feeds it the street polyline point by point.

use crate::types::{G, GroundKind, GroundType};
use serde::{Deserialize, Serialize};
use vitro::env::NodeId;
use vitro_site::geo::dist;

/// What MoveInDirection asks: head for `toward` and reach `speed` (negative: backing
/// towards it, the vehicle's rear first, at most the type's reverse speed).
#[derive(Copy, Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct MoveCmd {
    /// The point to move towards (world metres; its height is ignored, the body stays on the
    /// ground it is placed on).
    pub toward: [f64; 3],
    /// The speed to reach, m/s; negative in reverse.
    pub speed: f64,
}

/// A vehicle on the ground mesh.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct OnGround {
    /// Its type.
    pub kind: GroundKind,
    /// The last street node it passed (or started at).
    pub node: NodeId,
    /// World position on the ground, metres.
    pub pos: [f64; 3],
    /// Heading, radians from east.
    pub heading: f64,
    /// Speed, m/s; negative in reverse.
    pub speed: f64,
    /// The command being followed.
    pub cmd: Option<MoveCmd>,
}

impl OnGround {
    /// Changes the speed towards the command for `dt` seconds on a grade of `slope`:
    /// accelerating at most [`GroundType::accel_limit`], braking at most `max_decel`; in
    /// reverse, speeding up with the type's `reverse_force` (less rolling resistance), no
    /// harder than `max_accel` as forwards, to at most its
    /// [`reverse_speed`](GroundType::reverse_speed). A change of direction brakes to
    /// rest first.
    pub fn update_speed(&mut self, ty: &GroundType, slope: f64, dt: f64) {
        let target = self.cmd.map_or(0.0, |c| c.speed.max(-ty.reverse_speed()));
        if target < self.speed {
            if self.speed > 0.0 {
                self.speed = (self.speed - ty.max_decel * dt).max(target.max(0.0));
            } else {
                let a = (ty.reverse_force / ty.mass - ty.rolling_resistance * G)
                    .min(ty.max_accel)
                    .max(0.0);
                self.speed = (self.speed - a * dt).max(target);
            }
        } else if target > self.speed {
            if self.speed < 0.0 {
                self.speed = (self.speed + ty.max_decel * dt).min(target.min(0.0));
            } else {
                let a = ty.accel_limit(self.speed, slope).max(0.0);
                self.speed = (self.speed + a * dt).min(target);
            }
        }
    }

    /// Moves at most `budget` metres straight towards the command's point (x, y), with the
    /// height from `ground`; returns the distance left unused if the point was reached. In
    /// reverse (negative speed) the vehicle keeps facing away from the point.
    pub fn advance(
        &mut self,
        budget: f64,
        ground: impl Fn([f64; 2]) -> Option<f64>,
    ) -> Option<f64> {
        let cmd = self.cmd?;
        let (p, q) = ([self.pos[0], self.pos[1]], [cmd.toward[0], cmd.toward[1]]);
        let d = dist(p, q);
        if d > 0.0 {
            self.heading = if self.speed < 0.0 {
                libm::atan2(p[1] - q[1], p[0] - q[0])
            } else {
                libm::atan2(q[1] - p[1], q[0] - p[0])
            };
        }
        if d <= budget {
            self.pos = [q[0], q[1], ground(q).unwrap_or(cmd.toward[2])];
            return Some(budget - d);
        }
        let f = budget / d;
        let r = [p[0] + f * (q[0] - p[0]), p[1] + f * (q[1] - p[1])];
        self.pos = [r[0], r[1], ground(r).unwrap_or(self.pos[2])];
        None
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::types::TypeBook;

    fn body() -> OnGround {
        OnGround {
            kind: GroundKind::Car,
            node: NodeId(0),
            pos: [0.0; 3],
            heading: 0.0,
            speed: 0.0,
            cmd: Some(MoveCmd {
                toward: [10.0, 0.0, 0.0],
                speed: 5.0,
            }),
        }
    }

    #[test]
    fn speeds_up_at_the_traction_limit_and_brakes_at_max_decel() {
        let ty = TypeBook::builtin().ground(GroundKind::Car);
        let mut b = body();
        b.update_speed(ty, 0.0, 0.5);
        let a = ty.accel_limit(0.0, 0.0);
        assert!((b.speed - a * 0.5).abs() < 1e-12);
        for _ in 0..20 {
            b.update_speed(ty, 0.0, 0.5);
        }
        assert_eq!(b.speed, 5.0);
        b.cmd = Some(MoveCmd {
            toward: [10.0, 0.0, 0.0],
            speed: 0.0,
        });
        b.update_speed(ty, 0.0, 0.5);
        assert!((b.speed - (5.0 - 3.5)).abs() < 1e-12);
    }

    #[test]
    fn reverses_up_to_the_reverse_speed_and_faces_away_while_backing() {
        let ty = TypeBook::builtin().ground(GroundKind::Car);
        let mut b = body();
        b.speed = 2.0;
        b.cmd = Some(MoveCmd {
            toward: [-10.0, 0.0, 0.0],
            speed: -20.0,
        });
        // Brakes to rest before engaging reverse.
        b.update_speed(ty, 0.0, 0.5);
        assert_eq!(b.speed, 0.0);
        b.update_speed(ty, 0.0, 0.5);
        let a = (ty.reverse_force / ty.mass - ty.rolling_resistance * G).min(ty.max_accel);
        assert!((b.speed + a * 0.5).abs() < 1e-12, "{}", b.speed);
        for _ in 0..40 {
            b.update_speed(ty, 0.0, 0.5);
        }
        assert_eq!(b.speed, -ty.reverse_speed());
        assert_eq!(b.advance(3.0, |_| Some(0.0)), None);
        assert!((b.pos[0] + 3.0).abs() < 1e-12);
        // Backing west, it still faces east.
        assert!(b.heading.abs() < 1e-12, "{}", b.heading);
        // Asked forward again, it brakes out of reverse first.
        b.cmd = Some(MoveCmd {
            toward: [10.0, 0.0, 0.0],
            speed: 5.0,
        });
        b.update_speed(ty, 0.0, 0.1);
        assert!((b.speed - (-ty.reverse_speed() + 0.7)).abs() < 1e-12);
    }

    #[test]
    fn moves_on_the_ground_and_reports_leftover_distance() {
        let mut b = body();
        let left = b.advance(4.0, |p| Some(p[0] * 0.1));
        assert_eq!(left, None);
        assert!((b.pos[0] - 4.0).abs() < 1e-12 && (b.pos[2] - 0.4).abs() < 1e-12);
        let left = b.advance(10.0, |p| Some(p[0] * 0.1));
        assert!(left.is_some_and(|l| (l - 4.0).abs() < 1e-12));
        assert_eq!(b.pos, [10.0, 0.0, 1.0]);
    }
}

//! The fixed-wing kinematic level: position, heading, flight-path angle, airspeed and bank,
//! driven by a commanded yaw rate, flight-path (pitch) angle and airspeed, each reached
//! under the type's limits.
//!
//! - Airspeed stays within `[min_speed, max_speed]` (the aircraft cannot stop or hover) and
//!   changes at most `max_accel`.
//! - Turns are coordinated: the bank that gives the commanded yaw rate,
//!   `φ = atan(ψ̇ V / g)`, clamped to the bank limit and reached at the roll rate; the yaw rate
//!   is then `g tan φ / V`, so a level turn has radius `V² / (g tan φ)`.
//! - The flight-path angle stays within the limit and changes at most at the pitch rate.
//!
//! Integration is explicit with the heading at mid-step, in `libm` arithmetic.

use crate::entity::route::wrap_angle;
use crate::types::{CtolKind, CtolType, G};
use serde::{Deserialize, Serialize};

/// What the kinematic autopilot layer commands.
#[derive(Copy, Clone, Debug, Default, PartialEq, Serialize, Deserialize)]
pub struct FlyCmd {
    /// Yaw rate, rad/s (positive to the left).
    pub yaw_rate: f64,
    /// Flight-path angle, radians (positive up).
    pub flight_path: f64,
    /// Airspeed, m/s.
    pub airspeed: f64,
}

/// A fixed-wing aircraft at the kinematic level.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct CtolBody {
    /// Its type.
    pub kind: CtolKind,
    /// World position, metres.
    pub pos: [f64; 3],
    /// Heading, radians from east.
    pub heading: f64,
    /// Flight-path angle, radians.
    pub gamma: f64,
    /// Airspeed, m/s.
    pub speed: f64,
    /// Bank angle, radians (positive: left wing down, turning left).
    pub bank: f64,
    /// The command being followed.
    pub cmd: FlyCmd,
}

fn approach(x: f64, target: f64, max_step: f64) -> f64 {
    x + (target - x).clamp(-max_step, max_step)
}

impl CtolBody {
    /// A level aircraft at `pos` flying `heading` at `speed` (clamped to the type's envelope).
    pub fn new(kind: CtolKind, ty: &CtolType, pos: [f64; 3], heading: f64, speed: f64) -> Self {
        let speed = speed.clamp(ty.min_speed, ty.max_speed);
        CtolBody {
            kind,
            pos,
            heading,
            gamma: 0.0,
            speed,
            bank: 0.0,
            cmd: FlyCmd {
                yaw_rate: 0.0,
                flight_path: 0.0,
                airspeed: speed,
            },
        }
    }

    /// The yaw rate of the bank limit at the current speed, rad/s.
    pub fn max_yaw_rate(&self, ty: &CtolType) -> f64 {
        G * libm::tan(ty.max_bank_deg.to_radians()) / self.speed
    }

    /// Advances `dt` seconds under the type's limits.
    pub fn step(&mut self, ty: &CtolType, dt: f64) {
        let c = self.cmd;
        let v_target = c.airspeed.clamp(ty.min_speed, ty.max_speed);
        self.speed =
            approach(self.speed, v_target, ty.max_accel * dt).clamp(ty.min_speed, ty.max_speed);
        let bank_max = ty.max_bank_deg.to_radians();
        let bank_cmd = libm::atan(c.yaw_rate * self.speed / G).clamp(-bank_max, bank_max);
        self.bank = approach(self.bank, bank_cmd, ty.roll_rate_deg_s.to_radians() * dt);
        let gmax = ty.max_flight_path_deg.to_radians();
        self.gamma = approach(
            self.gamma,
            c.flight_path.clamp(-gmax, gmax),
            ty.pitch_rate_deg_s.to_radians() * dt,
        );
        let rate = G * libm::tan(self.bank) / self.speed;
        let mid = self.heading + rate * dt / 2.0;
        let (cg, sg) = (libm::cos(self.gamma), libm::sin(self.gamma));
        self.pos[0] += self.speed * cg * libm::cos(mid) * dt;
        self.pos[1] += self.speed * cg * libm::sin(mid) * dt;
        self.pos[2] += self.speed * sg * dt;
        self.heading = wrap_angle(self.heading + rate * dt);
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::types::TypeBook;

    #[test]
    fn cannot_stop_and_banks_at_the_roll_rate() {
        let ty = TypeBook::builtin().ctol(CtolKind::Procerus);
        let mut b = CtolBody::new(CtolKind::Procerus, ty, [0.0; 3], 0.0, 15.0);
        b.cmd = FlyCmd {
            yaw_rate: 10.0,
            flight_path: 1.0,
            airspeed: 0.0,
        };
        b.step(ty, 0.1);
        assert!((b.bank - 9f64.to_radians()).abs() < 1e-9, "{}", b.bank);
        assert!((b.speed - 14.8).abs() < 1e-9);
        for _ in 0..200 {
            b.step(ty, 0.1);
        }
        assert_eq!(b.speed, ty.min_speed);
        assert!((b.bank - 45f64.to_radians()).abs() < 1e-9);
        assert!((b.gamma - 15f64.to_radians()).abs() < 1e-9);
    }
}

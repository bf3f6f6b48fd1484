//! The helicopter dynamic level: a rigid body driven by its rotor controls.
//!
//! Frames: world x east, y north, z up; body x forward, y left, z up. Attitude is the Z-Y-X
//! Euler triple `[φ, θ, ψ]` (roll about the forward axis, positive right side down; pitch
//! about the left axis, positive nose down; yaw, the heading from east).
//!
//! Forces and moments:
//! - main rotor thrust `T = collective × T_max` along the rotor axis, the body's up axis
//!   tilted forward by `lon × cyclic_tilt` and to the right by `lat × cyclic_tilt`; it acts at
//!   the hub, `hub_height` above the centre of mass, and a stiff hub adds `K (tilt)` with
//!   `K = m g hub_height`;
//! - main rotor reaction torque `−torque_fraction × R × T` about the body's up axis;
//! - tail rotor thrust `tail × T_tail,max` along the body's left axis, `tail_arm` behind the
//!   centre of mass (a yaw moment and a small side force); `T_tail,max` balances 1.5 times the
//!   reaction torque at full thrust;
//! - drag `−½ ρ CdA |v| v` (CdA from the type's top speed) and a rotor-induced linear drag,
//!   and rotor damping of the body rates;
//! - gravity.
//!
//! Integration: semi-implicit Euler at a fixed step, `libm` trigonometry.

use crate::types::{G, RHO_AIR, VtolKind, VtolType};
use serde::{Deserialize, Serialize};

/// Linear drag of the rotor wake per unit mass, 1/s (an estimate).
const INDUCED_DRAG: f64 = 0.05;
/// Rotor damping of the body rates, per unit inertia, 1/s: roll, pitch, yaw (estimates).
const RATE_DAMPING: [f64; 3] = [2.0, 2.0, 1.0];

/// The rotor controls.
#[derive(Copy, Clone, Debug, Default, PartialEq, Serialize, Deserialize)]
pub struct Rotor {
    /// Main rotor collective, 0..1 (fraction of the largest thrust).
    pub collective: f64,
    /// Longitudinal cyclic, −1..1 (positive tilts the disc forward).
    pub lon: f64,
    /// Lateral cyclic, −1..1 (positive tilts the disc to the right).
    pub lat: f64,
    /// Tail rotor pitch, −1..1 (positive pushes the tail to the left: nose right).
    pub tail: f64,
}

impl Rotor {
    /// The controls clamped to their ranges.
    pub fn clamped(self) -> Self {
        Rotor {
            collective: self.collective.clamp(0.0, 1.0),
            lon: self.lon.clamp(-1.0, 1.0),
            lat: self.lat.clamp(-1.0, 1.0),
            tail: self.tail.clamp(-1.0, 1.0),
        }
    }
}

/// What the velocity-hold loop of the autopilot aims at.
#[derive(Copy, Clone, Debug, Default, PartialEq, Serialize, Deserialize)]
pub struct HoldTarget {
    /// Horizontal velocity, world m/s.
    pub vel: [f64; 2],
    /// Altitude, world metres.
    pub altitude: f64,
    /// Heading, radians from east.
    pub heading: f64,
}

/// Integrator states of the hold loop.
#[derive(Copy, Clone, Debug, Default, PartialEq, Serialize, Deserialize)]
pub struct HoldState {
    /// Horizontal acceleration integrators, world m/s².
    pub ixy: [f64; 2],
    /// Vertical acceleration integrator, m/s².
    pub iz: f64,
}

/// A helicopter at the dynamic level.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct VtolBody {
    /// Its type.
    pub kind: VtolKind,
    /// World position of the centre of mass, metres.
    pub pos: [f64; 3],
    /// World velocity, m/s.
    pub vel: [f64; 3],
    /// Euler angles `[φ, θ, ψ]`, radians.
    pub att: [f64; 3],
    /// Body rates `[p, q, r]` about forward, left, up, rad/s.
    pub rates: [f64; 3],
    /// The controls applied.
    pub rotor: Rotor,
    /// What the hold loop aims at.
    pub target: HoldTarget,
    /// The hold loop's integrators.
    pub hold: HoldState,
}

/// Rows of the body-to-world rotation `Rz(ψ) Ry(θ) Rx(φ)`.
pub fn rotation(att: [f64; 3]) -> [[f64; 3]; 3] {
    let (sf, cf) = (libm::sin(att[0]), libm::cos(att[0]));
    let (st, ct) = (libm::sin(att[1]), libm::cos(att[1]));
    let (sp, cp) = (libm::sin(att[2]), libm::cos(att[2]));
    [
        [cp * ct, cp * st * sf - sp * cf, cp * st * cf + sp * sf],
        [sp * ct, sp * st * sf + cp * cf, sp * st * cf - cp * sf],
        [-st, ct * sf, ct * cf],
    ]
}

fn mul(r: &[[f64; 3]; 3], v: [f64; 3]) -> [f64; 3] {
    std::array::from_fn(|i| r[i][0] * v[0] + r[i][1] * v[1] + r[i][2] * v[2])
}

/// The constants of a type's model.
#[derive(Copy, Clone, Debug, PartialEq)]
pub struct Airframe {
    /// Mass, kg.
    pub mass: f64,
    /// Principal inertias, kg·m².
    pub inertia: [f64; 3],
    /// Largest main-rotor thrust, N.
    pub max_thrust: f64,
    /// Largest tail-rotor thrust, N.
    pub max_tail: f64,
    /// Disc tilt at full cyclic, radians.
    pub cyclic_tilt: f64,
    /// Hub height, m.
    pub hub: f64,
    /// Hub stiffness, N·m per radian of tilt.
    pub hub_stiffness: f64,
    /// Reaction torque per newton of thrust, m.
    pub torque_arm: f64,
    /// Tail arm, m.
    pub tail_arm: f64,
    /// Drag area, m².
    pub drag_area: f64,
}

impl Airframe {
    /// The model constants of `ty`.
    pub fn of(ty: &VtolType) -> Self {
        let torque_arm = ty.torque_fraction * ty.rotor_radius();
        Airframe {
            mass: ty.mass,
            inertia: ty.inertia(),
            max_thrust: ty.max_thrust(),
            max_tail: 1.5 * torque_arm * ty.max_thrust() / ty.tail_arm,
            cyclic_tilt: ty.cyclic_tilt_deg.to_radians(),
            hub: ty.hub_height,
            hub_stiffness: ty.mass * G * ty.hub_height,
            torque_arm,
            tail_arm: ty.tail_arm,
            drag_area: ty.drag_area(),
        }
    }

    /// Body-frame force of the rotors (without gravity and drag) and body moments, for
    /// controls `c`.
    pub fn rotor_wrench(&self, c: Rotor, rates: [f64; 3]) -> ([f64; 3], [f64; 3]) {
        let c = c.clamped();
        let t = c.collective * self.max_thrust;
        let (a, b) = (c.lon * self.cyclic_tilt, c.lat * self.cyclic_tilt);
        let tail = c.tail * self.max_tail;
        let f = [
            t * libm::sin(a) * libm::cos(b),
            -t * libm::sin(b) + tail,
            t * libm::cos(a) * libm::cos(b),
        ];
        // r_hub × F_main + hub stiffness, tail moment, reaction torque, rotor damping.
        let m = [
            -self.hub * (f[1] - tail) + self.hub_stiffness * b
                - RATE_DAMPING[0] * self.inertia[0] * rates[0],
            self.hub * f[0] + self.hub_stiffness * a - RATE_DAMPING[1] * self.inertia[1] * rates[1],
            -self.torque_arm * t
                - self.tail_arm * tail
                - RATE_DAMPING[2] * self.inertia[2] * rates[2],
        ];
        (f, m)
    }
}

impl VtolBody {
    /// A helicopter hovering at `pos` facing `heading`, controls trimmed for hover.
    pub fn hovering(kind: VtolKind, ty: &VtolType, pos: [f64; 3], heading: f64) -> Self {
        let af = Airframe::of(ty);
        let collective = af.mass * G / af.max_thrust;
        VtolBody {
            kind,
            pos,
            vel: [0.0; 3],
            att: [0.0, 0.0, heading],
            rates: [0.0; 3],
            rotor: Rotor {
                collective,
                lon: 0.0,
                lat: 0.0,
                tail: -af.torque_arm * collective * af.max_thrust / (af.tail_arm * af.max_tail),
            },
            target: HoldTarget {
                vel: [0.0; 2],
                altitude: pos[2],
                heading,
            },
            hold: HoldState::default(),
        }
    }

    /// Advances `dt` seconds with the current rotor controls.
    pub fn step(&mut self, af: &Airframe, dt: f64) {
        let (fb, mb) = af.rotor_wrench(self.rotor, self.rates);
        let r = rotation(self.att);
        let fw = mul(&r, fb);
        let v = self.vel;
        let speed = libm::sqrt(v[0] * v[0] + v[1] * v[1] + v[2] * v[2]);
        let drag = 0.5 * RHO_AIR * af.drag_area * speed;
        let acc: [f64; 3] = std::array::from_fn(|k| {
            let g = if k == 2 { -G } else { 0.0 };
            (fw[k] - drag * v[k]) / af.mass - INDUCED_DRAG * v[k] + g
        });
        // Euler's equations, principal axes: I ω̇ = M − ω × I ω.
        let w = self.rates;
        let i = af.inertia;
        let iw = [i[0] * w[0], i[1] * w[1], i[2] * w[2]];
        let gyro = [
            w[1] * iw[2] - w[2] * iw[1],
            w[2] * iw[0] - w[0] * iw[2],
            w[0] * iw[1] - w[1] * iw[0],
        ];
        for k in 0..3 {
            self.rates[k] += (mb[k] - gyro[k]) / i[k] * dt;
            self.vel[k] += acc[k] * dt;
            self.pos[k] += self.vel[k] * dt;
        }
        let [p, q, rr] = self.rates;
        let (sf, cf) = (libm::sin(self.att[0]), libm::cos(self.att[0]));
        let (ct, tt) = (libm::cos(self.att[1]), libm::tan(self.att[1]));
        let d = [
            p + sf * tt * q + cf * tt * rr,
            cf * q - sf * rr,
            (sf * q + cf * rr) / ct,
        ];
        for (a, da) in self.att.iter_mut().zip(d) {
            *a += da * dt;
        }
        self.att[2] = crate::entity::route::wrap_angle(self.att[2]);
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::types::TypeBook;

    #[test]
    fn trimmed_hover_is_an_equilibrium() {
        let ty = TypeBook::builtin().vtol(VtolKind::Skeldar);
        let af = Airframe::of(ty);
        let mut b = VtolBody::hovering(VtolKind::Skeldar, ty, [0.0, 0.0, 100.0], 0.5);
        for _ in 0..100 {
            b.step(&af, 0.01);
        }
        // Only the tail rotor's side force is unbalanced: it drifts slowly sideways.
        assert!((b.pos[2] - 100.0).abs() < 1e-6, "{:?}", b.pos);
        assert!(b.rates[2].abs() < 1e-9 && (b.att[2] - 0.5).abs() < 1e-9);
        assert!(libm::hypot(b.vel[0], b.vel[1]) < 0.5);
    }

    #[test]
    fn forward_cyclic_pitches_the_nose_down_and_accelerates_forward() {
        let ty = TypeBook::builtin().vtol(VtolKind::Vidar);
        let af = Airframe::of(ty);
        let mut b = VtolBody::hovering(VtolKind::Vidar, ty, [0.0; 3], 0.0);
        b.rotor.lon = 0.3;
        for _ in 0..50 {
            b.step(&af, 0.01);
        }
        assert!(b.att[1] > 0.0 && b.rates[1] > 0.0);
        assert!(b.vel[0] > 0.0);
        // Right cyclic rolls right side down and drifts right (−y).
        let mut b = VtolBody::hovering(VtolKind::Vidar, ty, [0.0; 3], 0.0);
        b.rotor.lat = 0.3;
        for _ in 0..50 {
            b.step(&af, 0.01);
        }
        assert!(b.att[0] > 0.0 && b.vel[1] < 0.0);
    }
}

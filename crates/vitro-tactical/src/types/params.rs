//! The parameter records of each entity family, with the physics they imply: tractive force
//! and acceleration limits of vehicles, corner speeds, the Pandolf load-speed relation of
//! troopers, turn radii of fixed-wing aircraft, rotor and inertia figures of helicopters.

use super::kinds::{G, RHO_AIR, TRACTION, TroopKind};
use serde::{Deserialize, Serialize};

/// Parameters of a ground vehicle type.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct GroundType {
    /// What it is.
    pub name: String,
    /// Where the figures come from.
    pub source: String,
    /// Which figures are estimates.
    pub notes: String,
    /// Mass, kg.
    pub mass: f64,
    /// Engine power, kW.
    pub power_kw: f64,
    /// Top speed, km/h.
    pub max_speed_kmh: f64,
    /// Largest acceleration (traction/gearing limit at low speed), m/s².
    pub max_accel: f64,
    /// Braking deceleration used in driving, m/s².
    pub max_decel: f64,
    /// Largest lateral acceleration the planner allows in corners, m/s².
    pub max_lateral_accel: f64,
    /// Radius of the tightest circle it can drive, m.
    pub turning_radius: f64,
    /// Body length, m.
    pub length: f64,
    /// Body width, m.
    pub width: f64,
    /// Body height, m.
    pub height: f64,
    /// Distance between axles, m.
    pub wheelbase: f64,
    /// Wheel radius, m.
    pub wheel_radius: f64,
    /// Drag coefficient × frontal area, m².
    pub drag_area: f64,
    /// Rolling resistance coefficient.
    pub rolling_resistance: f64,
    /// Fastest a driver backs the vehicle, km/h.
    pub reverse_speed_kmh: f64,
    /// Largest engine force at the wheels in reverse, N.
    pub reverse_force: f64,
}

impl GroundType {
    /// Top speed, m/s.
    pub fn max_speed(&self) -> f64 {
        self.max_speed_kmh / 3.6
    }

    /// Engine power, W.
    pub fn power(&self) -> f64 {
        self.power_kw * 1000.0
    }

    /// Fastest a driver backs the vehicle, m/s.
    pub fn reverse_speed(&self) -> f64 {
        self.reverse_speed_kmh / 3.6
    }

    /// The range of signed engine force at the wheels at speed `v`, N: backwards at most
    /// `reverse_force` (and never more than the tyres' grip), forwards at most
    /// [`drive_limit`](Self::drive_limit).
    ///
    /// ```
    /// use vitro_tactical::types::{GroundKind, TypeBook};
    /// let car = TypeBook::builtin().ground(GroundKind::Car);
    /// let (back, ahead) = car.drive_range(0.0);
    /// assert!(back < 0.0 && ahead > 0.0 && -back <= car.reverse_force);
    /// ```
    pub fn drive_range(&self, v: f64) -> (f64, f64) {
        let ahead = self.drive_limit(v);
        (-self.reverse_force.min(TRACTION * self.mass * G), ahead)
    }

    /// The largest tractive force at speed `v`, N: the tyres' grip when slow
    /// ([`TRACTION`] × weight), the engine's power `P / v` when fast.
    pub fn drive_limit(&self, v: f64) -> f64 {
        (TRACTION * self.mass * G).min(self.power() / v.abs().max(0.5))
    }

    /// The largest acceleration at speed `v` on a grade of `slope` (rise over run): the
    /// tractive force ([`drive_limit`](Self::drive_limit)) less rolling resistance,
    /// aerodynamic drag and the grade, capped by `max_accel` (gearing and comfort on the
    /// level). May be negative (the grade is too steep at this speed).
    pub fn accel_limit(&self, v: f64, slope: f64) -> f64 {
        let m = self.mass;
        let cos = 1.0 / libm::sqrt(1.0 + slope * slope);
        let net = self.drive_limit(v) / m
            - self.rolling_resistance * G * cos
            - 0.5 * RHO_AIR * self.drag_area * v * v / m
            - G * slope * cos;
        net.min(self.max_accel)
    }

    /// The speed a corner of deflection `turn` (radians) allows when the path may bend on a
    /// circle no wider than `room` metres of tangent on either side: the lateral-acceleration
    /// limit on the widest fillet that fits, never a radius below the turning radius.
    pub fn corner_speed(&self, turn: f64, room: f64) -> f64 {
        let half = (turn.abs() / 2.0).min(1.55);
        if half < 1e-6 {
            return f64::INFINITY;
        }
        let radius = (room / libm::tan(half)).max(self.turning_radius);
        libm::sqrt(self.max_lateral_accel * radius)
    }

    /// The steering angle of the tightest turn (bicycle model), radians.
    pub fn max_steer(&self) -> f64 {
        libm::atan(self.wheelbase / self.turning_radius)
    }
}

/// Parameters shared by every trooper type: the body and the Pandolf load-speed relation.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct TroopParams {
    /// Where the figures come from.
    pub source: String,
    /// Which figures are estimates.
    pub notes: String,
    /// Body mass W, kg.
    pub body_mass: f64,
    /// Standing height, m.
    pub height: f64,
    /// Walking speed with no load on the level, m/s (sets the metabolic budget).
    pub unloaded_speed: f64,
    /// Slowest walking speed however heavy the load, m/s.
    pub min_speed: f64,
    /// How fast a trooper turns, degrees per second.
    pub turn_rate_deg_s: f64,
    /// Pandolf terrain factor η (1.0 on a paved road).
    pub terrain_factor: f64,
    /// Blue troopers.
    pub blue: TroopType,
    /// Red adversaries.
    pub red: TroopType,
    /// The VIP.
    pub vip: TroopType,
}

/// One trooper type: what it carries.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct TroopType {
    /// What it is.
    pub name: String,
    /// Carried load L, kg.
    pub load: f64,
}

impl TroopParams {
    /// Pandolf (1977) metabolic power, W, of walking at `v` m/s with `load` kg on a grade of
    /// `grade_percent` (negative grades count as level).
    pub fn metabolic_power(&self, load: f64, v: f64, grade_percent: f64) -> f64 {
        let w = self.body_mass;
        let g = grade_percent.max(0.0);
        1.5 * w
            + 2.0 * (w + load) * (load / w) * (load / w)
            + self.terrain_factor * (w + load) * (1.5 * v * v + 0.35 * v * g)
    }

    /// Walking speed, m/s, with `load` kg on a grade of `grade_percent`: the speed whose
    /// Pandolf power equals the unloaded walk's on the level, clamped to
    /// `[min_speed, unloaded_speed]`.
    ///
    /// ```
    /// use vitro_tactical::types::TypeBook;
    /// let t = &TypeBook::builtin().troops;
    /// assert!((t.walking_speed(0.0, 0.0) - t.unloaded_speed).abs() < 1e-9);
    /// let loaded = t.walking_speed(33.0, 0.0);
    /// assert!(loaded < 1.2 && loaded > 1.0, "{loaded}");
    /// assert!(t.walking_speed(33.0, 5.0) < loaded);
    /// ```
    pub fn walking_speed(&self, load: f64, grade_percent: f64) -> f64 {
        let budget = self.metabolic_power(0.0, self.unloaded_speed, 0.0);
        let w = self.body_mass;
        let g = grade_percent.max(0.0);
        let base = 1.5 * w + 2.0 * (w + load) * (load / w) * (load / w);
        // a v² + b v - c = 0 with a = 1.5 η (W+L), b = 0.35 η (W+L) G, c = budget - base.
        let a = 1.5 * self.terrain_factor * (w + load);
        let b = 0.35 * self.terrain_factor * (w + load) * g;
        let c = budget - base;
        let v = if c <= 0.0 || a <= 0.0 {
            0.0
        } else {
            (-b + libm::sqrt(b * b + 4.0 * a * c)) / (2.0 * a)
        };
        v.clamp(self.min_speed, self.unloaded_speed)
    }

    /// The type of `kind`.
    pub fn of(&self, kind: TroopKind) -> &TroopType {
        match kind {
            TroopKind::Blue => &self.blue,
            TroopKind::Red => &self.red,
            TroopKind::Vip => &self.vip,
        }
    }

    /// Turn rate, rad/s.
    pub fn turn_rate(&self) -> f64 {
        self.turn_rate_deg_s.to_radians()
    }
}

/// Parameters of a fixed-wing UAV type (kinematic limits).
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct CtolType {
    /// What it is.
    pub name: String,
    /// Where the figures come from.
    pub source: String,
    /// Which figures are estimates.
    pub notes: String,
    /// Mass, kg.
    pub mass: f64,
    /// Wing span, m.
    pub span: f64,
    /// Slowest airspeed (it cannot stop or hover), m/s.
    pub min_speed: f64,
    /// Cruise airspeed, m/s.
    pub cruise_speed: f64,
    /// Fastest airspeed, m/s.
    pub max_speed: f64,
    /// Bank limit, degrees.
    pub max_bank_deg: f64,
    /// Roll rate limit, degrees per second.
    pub roll_rate_deg_s: f64,
    /// Flight-path (pitch) angle limit, degrees.
    pub max_flight_path_deg: f64,
    /// Pitch rate limit, degrees per second.
    pub pitch_rate_deg_s: f64,
    /// Airspeed change limit, m/s².
    pub max_accel: f64,
}

impl CtolType {
    /// Radius of a coordinated level turn at airspeed `v` and bank `bank` (radians):
    /// `v² / (g tan bank)`.
    pub fn turn_radius(v: f64, bank: f64) -> f64 {
        v * v / (G * libm::tan(bank))
    }
    /// The tightest turn radius at cruise speed, m.
    pub fn min_turn_radius(&self) -> f64 {
        Self::turn_radius(self.cruise_speed, self.max_bank_deg.to_radians())
    }
}

/// Parameters of a helicopter UAV type.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct VtolType {
    /// What it is.
    pub name: String,
    /// Where the figures come from.
    pub source: String,
    /// Which figures are estimates.
    pub notes: String,
    /// Mass, kg.
    pub mass: f64,
    /// Main rotor diameter, m.
    pub rotor_diameter: f64,
    /// Engine power, kW.
    pub power_kw: f64,
    /// Fastest level flight, m/s.
    pub max_speed: f64,
    /// Cruise speed the autopilots use, m/s.
    pub cruise_speed: f64,
    /// Fastest climb or descent the autopilots command, m/s.
    pub max_climb: f64,
    /// Full-collective thrust over weight.
    pub thrust_to_weight: f64,
    /// Largest body tilt the autopilots command, degrees.
    pub max_tilt_deg: f64,
    /// Rotor disc tilt at full cyclic, degrees.
    pub cyclic_tilt_deg: f64,
    /// Radius of gyration in roll over rotor radius.
    pub gyration_roll: f64,
    /// Radius of gyration in pitch over rotor radius.
    pub gyration_pitch: f64,
    /// Radius of gyration in yaw over rotor radius.
    pub gyration_yaw: f64,
    /// Rotor hub height above the centre of mass, m.
    pub hub_height: f64,
    /// Tail rotor distance behind the centre of mass, m.
    pub tail_arm: f64,
    /// Main-rotor reaction torque per newton of thrust, in rotor radii (N·m per N / R).
    pub torque_fraction: f64,
}

impl VtolType {
    /// Main rotor radius, m.
    pub fn rotor_radius(&self) -> f64 {
        self.rotor_diameter / 2.0
    }
    /// Largest main-rotor thrust, N.
    pub fn max_thrust(&self) -> f64 {
        self.thrust_to_weight * self.mass * G
    }
    /// Principal moments of inertia (roll, pitch, yaw), kg·m².
    pub fn inertia(&self) -> [f64; 3] {
        let r = self.rotor_radius();
        let i = |k: f64| self.mass * (k * r) * (k * r);
        [
            i(self.gyration_roll),
            i(self.gyration_pitch),
            i(self.gyration_yaw),
        ]
    }
    /// Drag area Cd·A, m², such that at `max_speed` the thrust tilted by `max_tilt_deg`
    /// balances drag in level flight.
    pub fn drag_area(&self) -> f64 {
        let tilt = self.max_tilt_deg.to_radians();
        self.mass * G * libm::tan(tilt) / (0.5 * RHO_AIR * self.max_speed * self.max_speed)
    }
}

#[cfg(test)]
mod tests {
    use super::super::{GroundKind, TypeBook};

    #[test]
    fn power_limits_acceleration_at_speed() {
        let b = TypeBook::builtin();
        let truck = b.ground(GroundKind::CargoTruck);
        // Gearing-limited when slow, power-limited when fast.
        assert_eq!(truck.accel_limit(1.0, 0.0), truck.max_accel);
        let p = truck.power() / (truck.mass * 20.0);
        assert!(truck.accel_limit(20.0, 0.0) < p && truck.accel_limit(20.0, 0.0) < 1.0);
        // A 10 % grade costs about 1 m/s² at speed, nothing when slow (low gear).
        let d = truck.accel_limit(20.0, 0.0) - truck.accel_limit(20.0, 0.1);
        assert!((d - 0.98).abs() < 0.05, "{d}");
        assert_eq!(truck.accel_limit(2.0, 0.1), truck.max_accel);
        // The steepest grade it climbs from rest: traction-limited (sin θ < 0.7).
        assert!(truck.accel_limit(0.5, 0.8) > 0.0);
        assert!(truck.accel_limit(0.5, 1.0) < 0.0);
        // The car out-accelerates the truck.
        assert!(b.ground(GroundKind::Car).accel_limit(10.0, 0.0) > truck.accel_limit(10.0, 0.0));
    }

    #[test]
    fn corners_slow_vehicles_down() {
        let car = TypeBook::builtin().ground(GroundKind::Car);
        assert!(car.corner_speed(0.0, 10.0).is_infinite());
        // A right angle with 10 m of room: a 10 m fillet, sqrt(3 * 10) m/s.
        let v = car.corner_speed(std::f64::consts::FRAC_PI_2, 10.0);
        assert!((v - 30f64.sqrt()).abs() < 1e-9, "{v}");
        // A hairpin with no room: the turning radius bounds it from below.
        let v = car.corner_speed(3.1, 0.1);
        assert!((v - (3.0 * 5.45f64).sqrt()).abs() < 1e-9, "{v}");
    }
}

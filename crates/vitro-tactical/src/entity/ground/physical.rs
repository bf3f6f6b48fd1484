//! The physical level: a ground vehicle as a rigid body on the terrain (rapier3d 0.36 with
//! `enhanced-determinism`).
//!
//! The chassis is a dynamic box of the type's mass and size carried by four ray-cast wheels
//! (rapier's [`DynamicRayCastVehicleController`]: spring-damper suspension, tyre friction
//! limited by the load on each wheel). It drives on the site's line-of-sight mesh: the ground,
//! the building prisms (solid walls) and the bridge decks. The front wheels steer; the engine
//! force is shared by all four wheels (the MDARS and the truck are all-wheel drive; for the
//! car the difference does not matter at town speeds). A fixed step, a fixed insertion order
//! and ordered iteration keep runs identical.
//!
//! The engine is limited to `min(grip, P / v)` at the wheels forwards (grip: 0.7 of the weight) and to the
//! type's `reverse_force` backwards, braking to `m · max_decel`; rolling resistance and drag are applied as forces, so travel times follow
//! from each type's own parameters.
//!
//! [`Chassis`] is the storage row: a copy of the body's state after each step (position,
//! velocity, acceleration, attitude and rates), which sensors read and the trace digests.

use crate::types::{G, GroundKind, GroundType, RHO_AIR};
use rapier3d::control::{DynamicRayCastVehicleController, WheelTuning};
use rapier3d::prelude::*;
use serde::{Deserialize, Serialize};
use std::collections::BTreeMap;
use vitro::entity::EntityId;
use vitro::env::NodeId;
use vitro_site::site::Site;

/// Suspension travel at rest, metres.
const REST_LENGTH: f32 = 0.3;
/// Suspension stiffness per unit chassis mass (rapier's units: the force is this × the
/// compression × the chassis mass): 4 wheels sag g / (4 k) = 8 cm at rest.
const STIFFNESS: f32 = 30.0;
/// Tyre friction coefficient on asphalt.
const TYRE_MU: f32 = 0.9;

/// Why the physics world could not be built.
#[derive(Debug, thiserror::Error)]
pub enum PhysicsError {
    /// The vehicle is off the terrain.
    #[error("vehicle position ({0}, {1}) is off the terrain")]
    OffTerrain(f64, f64),
}

/// What SteerAndAccelerate sets: the front-wheel angle and the wheel forces.
#[derive(Copy, Clone, Debug, Default, PartialEq, Serialize, Deserialize)]
pub struct Controls {
    /// Front-wheel steering angle, radians, positive to the left.
    pub steer: f64,
    /// Total engine force at the wheels, N: positive forwards, negative in reverse.
    pub drive: f64,
    /// Total braking force, N.
    pub brake: f64,
}

/// A vehicle's state after the last physics step (the storage row).
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct Chassis {
    /// Its type.
    pub kind: GroundKind,
    /// The last street node it passed (or started at).
    pub node: NodeId,
    /// Centre of the chassis, world metres.
    pub pos: [f64; 3],
    /// Velocity, m/s.
    pub vel: [f64; 3],
    /// Acceleration over the last step, m/s².
    pub acc: [f64; 3],
    /// Roll (right side down positive), pitch (nose up positive), yaw (heading from east),
    /// radians.
    pub attitude: [f64; 3],
    /// Body rates about the chassis' forward, left and up axes, rad/s.
    pub rates: [f64; 3],
    /// Forward speed (negative when rolling backwards), m/s.
    pub speed: f64,
    /// The controls applied.
    pub controls: Controls,
    /// Height of the chassis centre above the ground under it at rest, metres.
    pub ride_height: f64,
    /// Integral term of MoveInDirection's speed controller, m/s.
    pub integral: f64,
    /// Parked: held in place (a fixed body) until the next trip.
    pub parked: bool,
    /// The farthest distance along the current trip reached, metres, and when (the
    /// physical GoToNode recovers, then gives the trip up, when it stops growing).
    pub progress: (f64, vitro::time::SimTime),
    /// The smallest bearing of its track ahead since the last progress, radians: turning
    /// towards the track counts as progress too (a vehicle swinging round onto its way).
    pub facing: f64,
    /// The recovery manoeuvre under way (backing out, turning in several moves), if any.
    pub manoeuvre: Option<Manoeuvre>,
    /// Recoveries started on the current trip.
    pub recoveries: u32,
}

/// A recovery manoeuvre as a driver makes it: moves alternately backwards and forwards at
/// full steering lock (a K-turn when the street is narrow), each ended by the room left
/// behind or ahead, until the vehicle faces its track.
#[derive(Copy, Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct Manoeuvre {
    /// The current move backs the vehicle.
    pub reverse: bool,
    /// Moves finished so far.
    pub moves: u32,
    /// Where the current move started (ground point, world x y).
    pub from: [f64; 2],
    /// When the current move started.
    pub since: vitro::time::SimTime,
    /// The side the nose is turned to: +1 left, −1 right.
    pub side: f64,
}

impl Chassis {
    /// Heading, radians from east.
    pub fn heading(&self) -> f64 {
        self.attitude[2]
    }
    /// The ground point under the chassis centre (its reference point on the map).
    pub fn ground_point(&self) -> [f64; 3] {
        [self.pos[0], self.pos[1], self.pos[2] - self.ride_height]
    }
}

#[derive(Serialize, Deserialize)]
struct Vehicle {
    body: RigidBodyHandle,
    ctrl: DynamicRayCastVehicleController,
    ty: GroundType,
    last_vel: [f64; 3],
}

/// The rigid-body world of the physical level: the site's mesh and the vehicles on it.
///
/// It serializes whole (rapier's `serde-serialize`: bodies, colliders, contacts, islands,
/// broad phase, the vehicle controllers), so a restored world steps on exactly as the saved
/// one would have.
#[derive(Serialize, Deserialize)]
pub struct Physics {
    world: PhysicsWorld,
    vehicles: BTreeMap<EntityId, Vehicle>,
    dt: f64,
}

impl std::fmt::Debug for Physics {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("Physics")
            .field("vehicles", &self.vehicles.len())
            .field("dt", &self.dt)
            .finish()
    }
}

fn v3(v: Vector) -> [f64; 3] {
    [f64::from(v.x), f64::from(v.y), f64::from(v.z)]
}

impl Physics {
    /// A world of the site's line-of-sight mesh (ground, buildings, bridge decks) under
    /// gravity, stepped every `dt` seconds.
    pub fn new(site: &Site, dt: f64) -> Self {
        let mut world = PhysicsWorld::new();
        world.gravity = Vector::new(0.0, 0.0, -G as f32);
        world.integration_parameters.dt = dt as f32;
        let ground = ColliderBuilder::new(SharedShape::new(site.los.trimesh().clone()))
            .friction(TYRE_MU)
            .build();
        world.insert_collider(ground, None);
        Physics {
            world,
            vehicles: BTreeMap::new(),
            dt,
        }
    }

    /// The fixed step, seconds.
    pub fn dt(&self) -> f64 {
        self.dt
    }

    /// Number of vehicles.
    pub fn len(&self) -> usize {
        self.vehicles.len()
    }
    /// True if there is no vehicle.
    pub fn is_empty(&self) -> bool {
        self.vehicles.is_empty()
    }

    /// Puts a vehicle of type `ty` at rest on the ground at world (x, y), facing `heading`;
    /// returns its first state row (its node is left at 0 for the caller to set).
    pub fn add_vehicle(
        &mut self,
        site: &Site,
        id: EntityId,
        kind: GroundKind,
        ty: &GroundType,
        xy: [f64; 2],
        heading: f64,
    ) -> Result<Chassis, PhysicsError> {
        let ground = site
            .ground(xy)
            .ok_or(PhysicsError::OffTerrain(xy[0], xy[1]))?;
        let r = ty.wheel_radius as f32;
        // The box spans from the wheel centres' height up to the roof.
        let hx = ty.length as f32 / 2.0;
        let hy = ty.width as f32 / 2.0;
        let hz = ((ty.height as f32 - r) / 2.0).max(0.2);
        let sag = (G as f32) / (4.0 * STIFFNESS);
        let ride = hz + REST_LENGTH - sag + r;
        let body = RigidBodyBuilder::dynamic()
            .translation(Vector::new(
                xy[0] as f32,
                xy[1] as f32,
                ground as f32 + ride + 0.02,
            ))
            .rotation(Vector::new(0.0, 0.0, heading as f32))
            .can_sleep(false)
            .build();
        let collider = ColliderBuilder::cuboid(hx, hy, hz)
            .mass(ty.mass as f32)
            .friction(0.5)
            .build();
        let (handle, _) = self.world.insert(body, collider);
        let mut ctrl = DynamicRayCastVehicleController::new(handle);
        ctrl.index_up_axis = 2;
        ctrl.index_forward_axis = 0;
        let damping = 2.0 * STIFFNESS.sqrt();
        let tuning = WheelTuning {
            suspension_stiffness: STIFFNESS,
            suspension_compression: 0.35 * damping,
            suspension_damping: 0.5 * damping,
            max_suspension_travel: 0.2,
            side_friction_stiffness: 1.0,
            friction_slip: TYRE_MU,
            max_suspension_force: (3.0 * ty.mass * G) as f32,
        };
        let (ax, ay) = (ty.wheelbase as f32 / 2.0, hy * 0.85);
        for (x, y) in [(ax, ay), (ax, -ay), (-ax, ay), (-ax, -ay)] {
            ctrl.add_wheel(
                Vector::new(x, y, -hz),
                -Vector::Z,
                -Vector::Y,
                REST_LENGTH,
                r,
                &tuning,
            );
        }
        self.vehicles.insert(
            id,
            Vehicle {
                body: handle,
                ctrl,
                ty: ty.clone(),
                last_vel: [0.0; 3],
            },
        );
        // Parked: brakes on until a command says otherwise.
        let parked = Controls {
            steer: 0.0,
            drive: 0.0,
            brake: ty.mass * ty.max_decel,
        };
        self.set_controls(id, parked);
        let mut row = Chassis {
            kind,
            node: NodeId(0),
            pos: [0.0; 3],
            vel: [0.0; 3],
            acc: [0.0; 3],
            attitude: [0.0; 3],
            rates: [0.0; 3],
            speed: 0.0,
            controls: parked,
            ride_height: f64::from(ride),
            integral: 0.0,
            parked: false,
            progress: (0.0, vitro::time::SimTime::ZERO),
            facing: std::f64::consts::PI,
            manoeuvre: None,
            recoveries: 0,
        };
        self.read(id, &mut row);
        Ok(row)
    }

    /// Removes a vehicle.
    pub fn remove_vehicle(&mut self, id: EntityId) {
        if let Some(v) = self.vehicles.remove(&id) {
            self.world.remove_body(v.body);
        }
    }

    /// Applies controls to a vehicle's wheels (they act from the next step on).
    pub fn set_controls(&mut self, id: EntityId, c: Controls) {
        let Some(v) = self.vehicles.get_mut(&id) else {
            return;
        };
        let n = v.ctrl.wheels().len().max(1) as f64;
        let dt = self.dt;
        for (i, w) in v.ctrl.wheels_mut().iter_mut().enumerate() {
            w.steering = if i < 2 { c.steer as f32 } else { 0.0 };
            w.engine_force = (c.drive / n) as f32;
            // rapier's brake is the largest rolling-friction impulse per step.
            w.brake = (c.brake.max(0.0) / n * dt) as f32;
        }
    }

    /// Parks a vehicle (holds it in place as a fixed body: the parking brake) or releases it.
    pub fn park(&mut self, id: EntityId, on: bool) {
        let Some(v) = self.vehicles.get_mut(&id) else {
            return;
        };
        if let Some(b) = self.world.bodies.get_mut(v.body) {
            if on {
                b.set_linvel(Vector::ZERO, false);
                b.set_angvel(Vector::ZERO, false);
                b.set_body_type(RigidBodyType::Fixed, false);
            } else {
                b.set_body_type(RigidBodyType::Dynamic, true);
            }
        }
        v.last_vel = [0.0; 3];
    }

    /// Advances every vehicle by one step: wheel forces, rolling resistance and drag, then the
    /// rigid-body step.
    pub fn step(&mut self) {
        let dt = self.dt as f32;
        for v in self.vehicles.values_mut() {
            let body = &self.world.bodies[v.body];
            if body.is_fixed() {
                continue;
            }
            let vel = body.linvel();
            let speed = vel.length();
            if speed > 1e-3 {
                // Rolling resistance and aerodynamic drag against the motion.
                let f = v.ty.rolling_resistance * v.ty.mass * G
                    + 0.5 * RHO_AIR * v.ty.drag_area * f64::from(speed * speed);
                let imp =
                    -vel / speed * (f.min(v.ty.mass * f64::from(speed) / self.dt) as f32) * dt;
                if let Some(b) = self.world.bodies.get_mut(v.body) {
                    b.apply_impulse(imp, true);
                }
            }
            let q = self.world.broad_phase.as_query_pipeline_mut(
                self.world.narrow_phase.query_dispatcher(),
                &mut self.world.bodies,
                &mut self.world.colliders,
                QueryFilter::exclude_dynamic(),
            );
            v.ctrl.update_vehicle(dt, q);
        }
        self.world.step();
    }

    /// The free distance ahead of the vehicle's front (or, `backwards`, behind its rear),
    /// metres, up to `range`: three horizontal rays in the chassis' frame, from its two
    /// corners and its middle at half its height, against walls, the ground and other
    /// vehicles (`vehicles_only`: other vehicles alone). `None` if there is no such vehicle.
    pub fn clearance(
        &self,
        id: EntityId,
        backwards: bool,
        range: f64,
        vehicles_only: bool,
    ) -> Option<f64> {
        self.clearance_steered(id, backwards, 0.0, range, vehicles_only)
    }

    /// As [`clearance`](Self::clearance), with the front wheels at `steer` (radians, positive
    /// to the left): each ray leaves its corner in the direction that corner moves when the
    /// vehicle turns about its rear axle's centre of turn (the bicycle model), so the outer
    /// front corner of a vehicle swinging at full lock sees the wall it would scrape.
    pub fn clearance_steered(
        &self,
        id: EntityId,
        backwards: bool,
        steer: f64,
        range: f64,
        vehicles_only: bool,
    ) -> Option<f64> {
        let v = self.vehicles.get(&id)?;
        let b = self.world.bodies.get(v.body)?;
        let (hx, hy) = (v.ty.length as f32 / 2.0, v.ty.width as f32 / 2.0);
        let dir: f32 = if backwards { -1.0 } else { 1.0 };
        let rot = *b.rotation();
        let own = |c: &Collider| c.parent() == Some(v.body);
        let pred =
            |_: ColliderHandle, c: &Collider| !own(c) && (!vehicles_only || c.parent().is_some());
        let filter = QueryFilter::default().predicate(&pred);
        let q = self.world.broad_phase.as_query_pipeline(
            self.world.narrow_phase.query_dispatcher(),
            &self.world.bodies,
            &self.world.colliders,
            filter,
        );
        // The centre of turn in the chassis frame: beside the rear axle, at the signed
        // radius L / tan(steer) (none when the wheels are straight).
        let tan = libm::tan(steer);
        let rear = -(v.ty.wheelbase as f32) / 2.0;
        let mut free = range;
        for y in [-hy, 0.0, hy] {
            let (px, py) = (dir * (hx + 0.01), y);
            let (dx, dy) = if tan.abs() < 1e-6 {
                (dir, 0.0)
            } else {
                let r = (v.ty.wheelbase / tan) as f32;
                // The corner's velocity turning forwards: ω ẑ × (p − c), ω of the sign of r.
                let (vx, vy) = (r - py, px - rear);
                let (vx, vy) = (vx * r.signum() * dir, vy * r.signum() * dir);
                let n = (vx * vx + vy * vy).sqrt().max(1e-6);
                (vx / n, vy / n)
            };
            let origin = b.position() * Vector::new(px, py, 0.0);
            let ray = Ray::new(origin, rot * Vector::new(dx, dy, 0.0));
            if let Some((_, toi)) = q.cast_ray(&ray, range as f32, true) {
                free = free.min(f64::from(toi));
            }
        }
        Some(free)
    }

    /// Copies a vehicle's rigid-body state into its row; false if there is no such vehicle.
    pub fn read(&mut self, id: EntityId, row: &mut Chassis) -> bool {
        let Some(v) = self.vehicles.get_mut(&id) else {
            return false;
        };
        let Some(b) = self.world.bodies.get(v.body) else {
            return false;
        };
        let rot = *b.rotation();
        let fwd = rot * Vector::X;
        let left = rot * Vector::Y;
        let up = rot * Vector::Z;
        let vel = v3(b.linvel());
        row.pos = v3(b.translation());
        row.acc = std::array::from_fn(|k| (vel[k] - v.last_vel[k]) / self.dt);
        row.vel = vel;
        v.last_vel = vel;
        let (f, l, u) = (v3(fwd), v3(left), v3(up));
        row.attitude = [
            libm::atan2(l[2], u[2]),
            libm::asin(f[2].clamp(-1.0, 1.0)),
            libm::atan2(f[1], f[0]),
        ];
        let w = rot.inverse() * b.angvel();
        row.rates = v3(w);
        row.speed = vel[0] * f[0] + vel[1] * f[1] + vel[2] * f[2];
        true
    }
}

//! Sensors over the tactical [`World`]: GPS, proximity vision, friend-or-foe vision; and
//! [`track`]ing, a lock held only while the owner's own friend-or-foe vision detects the
//! target.
//!
//! Randomness comes from the sensing entity's own streams (`probe.rng(..)`): `"gps"` for GPS
//! noise, `"fof"` for detection and identification draws. Candidates are examined in entity-id
//! order, so a reading depends only on the world and the stream, never on a hasher.

pub mod track;

use crate::world::{Body, Side, World};
use rand::Rng;
use serde::{Deserialize, Serialize};
use vitro::entity::EntityId;
use vitro::env::{Probe, Sensor};
use vitro_site::site::Site;

fn dist3(a: [f64; 3], b: [f64; 3]) -> f64 {
    let d = [b[0] - a[0], b[1] - a[1], b[2] - a[2]];
    libm::sqrt(d[0] * d[0] + d[1] * d[1] + d[2] * d[2])
}

/// A standard normal draw (Box–Muller through `libm`, identical on every machine).
fn normal(rng: &mut impl Rng) -> f64 {
    let u1 = 1.0 - rng.random::<f64>(); // (0, 1]
    let u2 = rng.random::<f64>();
    libm::sqrt(-2.0 * libm::log(u1)) * libm::cos(std::f64::consts::TAU * u2)
}

/// GPS: the entity's own position, with optional Gaussian noise.
///
/// ```
/// use vitro_tactical::sensor::Gps;
/// let exact = Gps::default();
/// assert_eq!(exact.sigma, 0.0);
/// ```
#[derive(Copy, Clone, Debug, Default, PartialEq, Serialize, Deserialize)]
pub struct Gps {
    /// Standard deviation of the error on each axis, metres (0: exact).
    pub sigma: f64,
}

impl Sensor<World> for Gps {
    /// The measured position; `None` if the entity has no body.
    type Reading = Option<[f64; 3]>;
    fn read(&self, w: &World, me: EntityId, probe: &mut Probe<'_>) -> Self::Reading {
        let mut p = w.body(me)?.pos;
        if self.sigma > 0.0 {
            let rng = probe.rng("gps");
            for c in &mut p {
                *c += self.sigma * normal(rng);
            }
        }
        Some(p)
    }
}

/// An entity within range (proximity vision).
#[derive(Copy, Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct Contact {
    /// Who.
    pub id: EntityId,
    /// Where.
    pub pos: [f64; 3],
    /// How far, metres.
    pub distance: f64,
}

/// Proximity vision: every other entity within `range` metres (3D), nearest first (ties by
/// id), regardless of walls. A linear scan over the bodies.
#[derive(Copy, Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct ProximityVision {
    /// Range, metres.
    pub range: f64,
}

impl Sensor<World> for ProximityVision {
    type Reading = Vec<Contact>;
    fn read(&self, w: &World, me: EntityId, _: &mut Probe<'_>) -> Vec<Contact> {
        let Some(mine) = w.body(me) else {
            return Vec::new();
        };
        let mut out: Vec<Contact> = w
            .bodies
            .iter()
            .filter(|(id, _)| *id != me)
            .map(|(id, b)| Contact {
                id,
                pos: b.pos,
                distance: dist3(mine.pos, b.pos),
            })
            .filter(|c| c.distance <= self.range)
            .collect();
        out.sort_by(|a, b| a.distance.total_cmp(&b.distance).then(a.id.cmp(&b.id)));
        out
    }
}

/// What friend-or-foe vision reports about one entity it detected.
#[derive(Copy, Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct Sighting {
    /// Who was seen.
    pub id: EntityId,
    /// Where (true position of its base).
    pub pos: [f64; 3],
    /// How far, metres.
    pub distance: f64,
    /// Direction, radians counter-clockwise from east.
    pub bearing: f64,
    /// The side the observer believes it is on (may be wrong).
    pub seen_as: Side,
}

/// Friend-or-foe vision: range, field of view, line of sight, a detection probability that
/// falls with distance, and identification errors.
///
/// A body is examined if it is within `range` (3D), within `half_fov` of the observer's
/// heading (horizontal angle), and its centre is in line of sight from the observer's eye.
/// It is then detected with probability
///
/// `p(d) = p0 · (1 − d / range)^k`
///
/// (`k = 0`: constant `p0`; `k = 1`: linear fall to 0 at the range; larger `k` falls faster).
/// A detected body is identified correctly with probability `1 − misidentification`;
/// otherwise it is reported as one of the two other sides, each equally likely.
#[derive(Copy, Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct FriendFoeVision {
    /// Range, metres.
    pub range: f64,
    /// Half the field of view, radians (π or more: all around).
    pub half_fov: f64,
    /// Detection probability at distance 0.
    pub p0: f64,
    /// Fall-off exponent of the detection curve.
    pub k: f64,
    /// Probability of reporting the wrong side.
    pub misidentification: f64,
}

impl Default for FriendFoeVision {
    /// 300 m, 120° field of view, p0 = 0.95, k = 1, 5 % misidentification.
    fn default() -> Self {
        FriendFoeVision {
            range: 300.0,
            half_fov: 60f64.to_radians(),
            p0: 0.95,
            k: 1.0,
            misidentification: 0.05,
        }
    }
}

/// The angle `a` brought into `(-π, π]`.
fn wrap(a: f64) -> f64 {
    let t = std::f64::consts::TAU;
    let r = a - t * libm::floor(a / t);
    if r > std::f64::consts::PI { r - t } else { r }
}

/// Largest error of [`atan2_approx`], radians, with a wide margin (the polynomial's own is
/// about 1e-5).
const ATAN_SLACK: f64 = 1e-3;

/// `atan2(y, x)` by a polynomial, within [`ATAN_SLACK`] (finite arguments, not both 0).
fn atan2_approx(y: f64, x: f64) -> f64 {
    let (ax, ay) = (x.abs(), y.abs());
    let a = ax.min(ay) / ax.max(ay);
    let s = a * a;
    let mut r = (((((-0.011_721_2 * s + 0.052_653_32) * s - 0.116_432_87) * s + 0.193_543_46) * s
        - 0.332_623_47)
        * s
        + 0.999_977_26)
        * a;
    if ay > ax {
        r = std::f64::consts::FRAC_PI_2 - r;
    }
    if x < 0.0 {
        r = std::f64::consts::PI - r;
    }
    if y < 0.0 { -r } else { r }
}

/// `|wrap(atan2(dy, dx) − heading)| <= half_fov`, the same answer as computing it with
/// `libm::atan2`, which it calls only when a cheap polynomial lands within [`ATAN_SLACK`]
/// of the edge of the field of view (a target almost never does).
fn within_fov(dx: f64, dy: f64, heading: f64, half_fov: f64) -> bool {
    if dx.is_finite() && dy.is_finite() && heading.is_finite() {
        let off = wrap(atan2_approx(dy, dx) - heading).abs();
        if off < half_fov - ATAN_SLACK {
            return true;
        }
        if off > half_fov + ATAN_SLACK {
            return false;
        }
    }
    wrap(libm::atan2(dy, dx) - heading).abs() <= half_fov
}

impl FriendFoeVision {
    /// Detection probability at distance `d` (0 beyond the range).
    pub fn detection_probability(&self, d: f64) -> f64 {
        if !(0.0..=self.range).contains(&d) || self.range <= 0.0 {
            return 0.0;
        }
        (self.p0 * libm::pow(1.0 - d / self.range, self.k)).clamp(0.0, 1.0)
    }

    /// True if `target` is in range, in the field of view and in line of sight of `me`
    /// (no randomness).
    pub fn can_see(&self, site: &Site, me: &Body, target: &Body) -> bool {
        self.can_see_by(me, target, |a, b| site.los.visible(a, b))
    }

    /// [`can_see`](Self::can_see) with line of sight from eye to centre answered by
    /// `visible` (asked only for a target in range and in the field of view).
    pub fn can_see_by(
        &self,
        me: &Body,
        target: &Body,
        visible: impl FnOnce([f64; 3], [f64; 3]) -> bool,
    ) -> bool {
        let d = dist3(me.pos, target.pos);
        if d > self.range {
            return false;
        }
        let dx = target.pos[0] - me.pos[0];
        let dy = target.pos[1] - me.pos[1];
        let in_fov = self.half_fov >= std::f64::consts::PI
            || (dx == 0.0 && dy == 0.0)
            || within_fov(dx, dy, me.heading, self.half_fov);
        in_fov && visible(me.eye(), target.centre())
    }
}

impl FriendFoeVision {
    /// One look from `me` at body `b` of entity `id`: `None` if it cannot be seen or the
    /// detection draw fails; otherwise the sighting, its side drawn with the
    /// misidentification probability. Draws from `rng` only for bodies it can see.
    pub fn look(
        &self,
        site: &Site,
        me: &Body,
        id: EntityId,
        b: &Body,
        rng: &mut impl Rng,
    ) -> Option<Sighting> {
        self.look_by(me, id, b, rng, |p, q| site.los.visible(p, q))
    }

    /// [`look`](Self::look) with line of sight answered by `visible` (the arena's memo of
    /// answers, say: [`Arena::visible`](crate::arena::Arena::visible)).
    pub fn look_by(
        &self,
        me: &Body,
        id: EntityId,
        b: &Body,
        rng: &mut impl Rng,
        visible: impl FnOnce([f64; 3], [f64; 3]) -> bool,
    ) -> Option<Sighting> {
        if !self.can_see_by(me, b, visible) {
            return None;
        }
        self.sighting(me, id, b, rng)
    }

    /// The draws of a look from `me` at body `b` of entity `id` that it can see
    /// ([`can_see`](Self::can_see)): detection with its probability at the distance, then
    /// identification. A sensor that first finds the bodies it can see, then draws for them
    /// in id order, draws exactly as [`look`](Self::look) at every body in id order does.
    pub fn sighting(
        &self,
        me: &Body,
        id: EntityId,
        b: &Body,
        rng: &mut impl Rng,
    ) -> Option<Sighting> {
        self.draw(&self.in_sight(me, id, b), rng)
    }

    /// What a look from `me` knows, before any draw, of body `b` of entity `id` that it can
    /// see: its distance, detection probability and bearing.
    pub fn in_sight(&self, me: &Body, id: EntityId, b: &Body) -> InSight {
        let distance = dist3(me.pos, b.pos);
        InSight {
            id,
            pos: b.pos,
            side: b.side,
            distance,
            p_detect: self.detection_probability(distance),
            bearing: libm::atan2(b.pos[1] - me.pos[1], b.pos[0] - me.pos[0]),
        }
    }

    /// The draws of a look at a body it can see ([`sighting`](Self::sighting), from what
    /// [`in_sight`](Self::in_sight) knew of it): detection, then identification.
    pub fn draw(&self, s: &InSight, rng: &mut impl Rng) -> Option<Sighting> {
        let seen_as = self.identify(s.p_detect, s.side, rng)?;
        Some(Sighting {
            id: s.id,
            pos: s.pos,
            distance: s.distance,
            bearing: s.bearing,
            seen_as,
        })
    }

    /// The draws of [`draw`](Self::draw) for a body of side `side` detected with
    /// probability `p_detect`: `None` if the detection draw fails, else the side it is
    /// taken for (the identification draws).
    #[inline]
    pub fn identify(&self, p_detect: f64, side: Side, rng: &mut impl Rng) -> Option<Side> {
        if rng.random::<f64>() >= p_detect {
            return None;
        }
        Some(if rng.random::<f64>() < self.misidentification {
            // One of the other sides, uniformly (no list made: a look draws many times).
            let others = || Side::ALL.into_iter().filter(|o| *o != side);
            let k = rng.random_range(0..others().count());
            others().nth(k).unwrap_or(side)
        } else {
            side
        })
    }
}

/// A body a look can see (in range, in the field of view, in line of sight), with what the
/// look knows of it before drawing ([`FriendFoeVision::in_sight`]).
#[derive(Copy, Clone, Debug, PartialEq)]
pub struct InSight {
    /// The entity.
    pub id: EntityId,
    /// Its true position.
    pub pos: [f64; 3],
    /// Its true side.
    pub side: Side,
    /// How far, metres.
    pub distance: f64,
    /// Its detection probability at that distance.
    pub p_detect: f64,
    /// Direction, radians counter-clockwise from east.
    pub bearing: f64,
}

impl Sensor<World> for FriendFoeVision {
    type Reading = Vec<Sighting>;
    fn read(&self, w: &World, me: EntityId, probe: &mut Probe<'_>) -> Vec<Sighting> {
        let Some(mine) = w.body(me).copied() else {
            return Vec::new();
        };
        w.bodies
            .iter()
            .filter(|(id, _)| *id != me)
            .filter_map(|(id, b)| self.look(&w.site, &mine, id, b, probe.rng("fof")))
            .collect()
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_polynomial_atan2_stays_well_within_its_slack() {
        let mut worst: f64 = 0.0;
        for i in 0..20_000 {
            let t = i as f64 * std::f64::consts::TAU / 20_000.0 - std::f64::consts::PI;
            for r in [1e-6, 1.0, 3e3] {
                let (y, x) = (r * libm::sin(t), r * libm::cos(t));
                worst = worst.max((atan2_approx(y, x) - libm::atan2(y, x)).abs());
            }
        }
        assert!(worst < ATAN_SLACK / 20.0, "{worst}");
        // And the field-of-view test it speeds up gives the exact answer, edges included.
        for i in 0..2000 {
            let h = i as f64 * 0.0137 - 10.0;
            for k in -50..=50 {
                let a = h + 1.0 + f64::from(k) * 1e-5;
                let (dx, dy) = (libm::cos(a), libm::sin(a));
                let exact = wrap(libm::atan2(dy, dx) - h).abs() <= 1.0;
                assert_eq!(within_fov(dx, dy, h, 1.0), exact);
            }
        }
    }

    #[test]
    fn a_misidentified_side_is_drawn_as_from_the_list_of_the_others() {
        use rand::SeedableRng;
        let v = FriendFoeVision {
            misidentification: 0.5,
            ..FriendFoeVision::default()
        };
        let (mut fast, mut slow) = (
            rand_chacha::ChaCha8Rng::seed_from_u64(3),
            rand_chacha::ChaCha8Rng::seed_from_u64(3),
        );
        let mut wrong = 0;
        for i in 0..3000 {
            let side = Side::ALL[i % 3];
            let s = InSight {
                id: EntityId(7),
                pos: [1.0, 2.0, 0.0],
                side,
                distance: 10.0,
                p_detect: 0.9,
                bearing: 0.3,
            };
            // The draws as made before: the other sides collected in a list.
            let want = (slow.random::<f64>() < s.p_detect).then(|| {
                if slow.random::<f64>() < v.misidentification {
                    let others: Vec<Side> = Side::ALL.into_iter().filter(|o| *o != side).collect();
                    others[slow.random_range(0..others.len())]
                } else {
                    side
                }
            });
            let got = v.draw(&s, &mut fast).map(|x| x.seen_as);
            assert_eq!(got, want, "draw {i}");
            wrong += usize::from(got.is_some_and(|g| g != side));
        }
        assert!(wrong > 1000, "{wrong}");
        assert_eq!(
            fast.random::<u64>(),
            slow.random::<u64>(),
            "same draws used"
        );
    }

    #[test]
    fn angles_wrap_and_curve_shape() {
        assert!((wrap(3.0 * std::f64::consts::PI) - std::f64::consts::PI).abs() < 1e-12);
        assert!((wrap(-0.5) + 0.5).abs() < 1e-12);
        let v = FriendFoeVision {
            range: 100.0,
            half_fov: 1.0,
            p0: 0.8,
            k: 2.0,
            misidentification: 0.0,
        };
        assert_eq!(v.detection_probability(0.0), 0.8);
        assert!((v.detection_probability(50.0) - 0.2).abs() < 1e-12);
        assert_eq!(v.detection_probability(100.0), 0.0);
        assert_eq!(v.detection_probability(101.0), 0.0);
    }
}

//! Line of sight against terrain and buildings: ray casts over a BVH of triangles.
//!
//! The scene is one parry3d [`TriMesh`] (its BVH built once): the ground mesh, every building
//! as an extruded prism (walls from its base to its roof, a flat roof), and every bridge deck
//! as a 1 m thick slab. Coordinates are the terrain's local metres (`f32` inside parry: at
//! 30 km from the origin that is still 2 mm).
//!
//! A sight line `a -> b` is clear if no triangle crosses the segment, ignoring its first and
//! last [`END_TOLERANCE`] metres so that points lying on a surface (a target standing on the
//! ground) do not hide themselves. Triangles are two-sided.

use crate::terrain::{Mesh, Terrain};
use parry3d::math::Vector;
use parry3d::query::{Ray, RayCast};
use parry3d::shape::{TriMesh, Triangle};

/// Metres ignored at both ends of a sight line.
pub const END_TOLERANCE: f64 = 0.05;

/// Why a scene could not be built.
#[derive(Debug, thiserror::Error)]
pub enum LosError {
    /// The scene has no triangle at all.
    #[error("the scene has no triangles")]
    Empty,
    /// parry3d refused the mesh.
    #[error("cannot build the triangle mesh: {0:?}")]
    Mesh(parry3d::shape::TriMeshBuilderError),
}

/// A prism occluder: a footprint (outer ring, counter-clockwise, with holes) between two
/// heights.
#[derive(Clone, Debug, PartialEq)]
pub struct Prism<'a> {
    /// Footprint.
    pub footprint: &'a crate::geo::Polygon,
    /// Bottom height, metres.
    pub base: f64,
    /// Top height, metres.
    pub top: f64,
}

/// Triangles for line-of-sight queries, with their BVH.
pub struct LosScene {
    mesh: TriMesh,
    terrain_triangles: usize,
}

impl std::fmt::Debug for LosScene {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("LosScene")
            .field("triangles", &self.triangle_count())
            .field("terrain_triangles", &self.terrain_triangles)
            .finish()
    }
}

/// Collects triangles before the mesh is built.
#[derive(Default)]
struct Soup {
    v: Vec<Vector>,
    t: Vec<[u32; 3]>,
}

impl Soup {
    fn vertex(&mut self, p: [f64; 3]) -> u32 {
        self.v
            .push(Vector::new(p[0] as f32, p[1] as f32, p[2] as f32));
        (self.v.len() - 1) as u32
    }
    fn quad(&mut self, a: [f64; 3], b: [f64; 3], c: [f64; 3], d: [f64; 3]) {
        let ids = [
            self.vertex(a),
            self.vertex(b),
            self.vertex(c),
            self.vertex(d),
        ];
        self.t.push([ids[0], ids[1], ids[2]]);
        self.t.push([ids[0], ids[2], ids[3]]);
    }
    fn mesh(&mut self, m: &Mesh) {
        let base = self.v.len() as u32;
        for &p in &m.vertices {
            self.vertex(p);
        }
        self.t.extend(
            m.triangles
                .iter()
                .map(|t| [t[0] + base, t[1] + base, t[2] + base]),
        );
    }
    fn prism(&mut self, p: &Prism<'_>) {
        for (a, b) in p.footprint.edges() {
            self.quad(
                [a[0], a[1], p.base],
                [b[0], b[1], p.base],
                [b[0], b[1], p.top],
                [a[0], a[1], p.top],
            );
        }
        let ring = &p.footprint.outer;
        let base = self.v.len() as u32;
        for q in ring {
            self.vertex([q[0], q[1], p.top]);
        }
        for t in p.footprint.triangulate_outer() {
            self.t
                .push([base + t[0] as u32, base + t[1] as u32, base + t[2] as u32]);
        }
    }
}

/// A bridge deck slab: centre line with the deck height at each point, and its width.
#[derive(Clone, Debug, PartialEq)]
pub struct Deck<'a> {
    /// Centre line, `[x, y, deck height]`.
    pub line: &'a [[f64; 3]],
    /// Width, metres.
    pub width: f64,
}

/// Thickness of a bridge deck slab, metres.
pub const DECK_THICKNESS: f64 = 1.0;

impl Soup {
    fn deck(&mut self, d: &Deck<'_>) {
        for w in d.line.windows(2) {
            let (a, b) = (w[0], w[1]);
            let l = libm::hypot(b[0] - a[0], b[1] - a[1]);
            if l == 0.0 {
                continue;
            }
            let n = [
                -(b[1] - a[1]) / l * d.width / 2.0,
                (b[0] - a[0]) / l * d.width / 2.0,
            ];
            let at = |p: [f64; 3], s: f64, dz: f64| [p[0] + s * n[0], p[1] + s * n[1], p[2] + dz];
            for dz in [0.0, -DECK_THICKNESS] {
                self.quad(
                    at(a, -1.0, dz),
                    at(b, -1.0, dz),
                    at(b, 1.0, dz),
                    at(a, 1.0, dz),
                );
            }
            for s in [-1.0, 1.0] {
                let t = -DECK_THICKNESS;
                self.quad(at(a, s, t), at(b, s, t), at(b, s, 0.0), at(a, s, 0.0));
            }
        }
    }
}

impl LosScene {
    /// A scene of the ground of `terrain`, the `prisms` (buildings) and `decks` (bridges).
    pub fn new(
        terrain: &Terrain,
        prisms: &[Prism<'_>],
        decks: &[Deck<'_>],
    ) -> Result<Self, LosError> {
        let mut soup = Soup::default();
        soup.mesh(&terrain.mesh());
        let terrain_triangles = soup.t.len();
        for p in prisms {
            soup.prism(p);
        }
        for d in decks {
            soup.deck(d);
        }
        if soup.t.is_empty() {
            return Err(LosError::Empty);
        }
        let mesh = TriMesh::new(soup.v, soup.t).map_err(LosError::Mesh)?;
        Ok(LosScene {
            mesh,
            terrain_triangles,
        })
    }

    /// A scene of the ground only.
    pub fn terrain_only(terrain: &Terrain) -> Result<Self, LosError> {
        Self::new(terrain, &[], &[])
    }

    /// The triangle mesh (also usable as a static collider for rigid-body physics: ground,
    /// buildings and bridge decks in one).
    pub fn trimesh(&self) -> &TriMesh {
        &self.mesh
    }
    /// Number of triangles.
    pub fn triangle_count(&self) -> usize {
        self.mesh.indices().len()
    }
    /// Number of triangles that belong to the ground (they come first).
    pub fn terrain_triangle_count(&self) -> usize {
        self.terrain_triangles
    }

    /// The ray and its length for the sight line `a -> b`, ends trimmed; `None` if shorter
    /// than both tolerances.
    fn ray(a: [f64; 3], b: [f64; 3]) -> Option<(Ray, f32)> {
        let d = [b[0] - a[0], b[1] - a[1], b[2] - a[2]];
        let len = libm::sqrt(d[0] * d[0] + d[1] * d[1] + d[2] * d[2]);
        if len <= 2.0 * END_TOLERANCE {
            return None;
        }
        let u = [d[0] / len, d[1] / len, d[2] / len];
        let o = [
            a[0] + u[0] * END_TOLERANCE,
            a[1] + u[1] * END_TOLERANCE,
            a[2] + u[2] * END_TOLERANCE,
        ];
        let ray = Ray::new(
            Vector::new(o[0] as f32, o[1] as f32, o[2] as f32),
            Vector::new(u[0] as f32, u[1] as f32, u[2] as f32),
        );
        Some((ray, (len - 2.0 * END_TOLERANCE) as f32))
    }

    /// True if nothing blocks the segment from `a` to `b` (a ray cast through the BVH).
    ///
    /// ```
    /// use vitro_site::los::LosScene;
    /// use vitro_site::terrain::Terrain;
    /// // A ridge 50 m high across x = 500 on a 1 km flat.
    /// let t = Terrain::from_fn(21, 21, 50.0, |x, _| if (x - 525.0).abs() < 30.0 { 50.0 } else { 0.0 }).unwrap();
    /// let los = LosScene::terrain_only(&t).unwrap();
    /// assert!(!los.visible([200.0, 500.0, 2.0], [800.0, 500.0, 2.0]));
    /// assert!(los.visible([200.0, 500.0, 80.0], [800.0, 500.0, 80.0]));
    /// ```
    pub fn visible(&self, a: [f64; 3], b: [f64; 3]) -> bool {
        match Self::ray(a, b) {
            Some((ray, max)) => self.mesh.cast_local_ray(&ray, max, false).is_none(),
            None => true,
        }
    }

    /// Distance from `a` to the first surface on the way to `b`, if any.
    pub fn first_hit(&self, a: [f64; 3], b: [f64; 3]) -> Option<f64> {
        let (ray, max) = Self::ray(a, b)?;
        self.mesh
            .cast_local_ray(&ray, max, false)
            .map(|t| f64::from(t) + END_TOLERANCE)
    }

    /// [`visible`](Self::visible) for many pairs; results in the pairs' order.
    pub fn visible_pairs(&self, pairs: &[([f64; 3], [f64; 3])]) -> Vec<bool> {
        pairs.iter().map(|&(a, b)| self.visible(a, b)).collect()
    }

    /// [`visible`](Self::visible) from one point to many; results in the targets' order.
    pub fn visible_from(&self, from: [f64; 3], targets: &[[f64; 3]]) -> Vec<bool> {
        targets.iter().map(|&b| self.visible(from, b)).collect()
    }

    /// The same answer as [`visible`](Self::visible) by testing every triangle, without the
    /// BVH: a reference for tests and benchmarks.
    pub fn visible_brute_force(&self, a: [f64; 3], b: [f64; 3]) -> bool {
        let Some((ray, max)) = Self::ray(a, b) else {
            return true;
        };
        !self
            .mesh
            .triangles()
            .any(|t: Triangle| t.cast_local_ray(&ray, max, false).is_some())
    }
}

//! A uniform grid of the bodies vision looks at, kept in step with the arena's storages.
//!
//! Vision used to examine every entity of the arena at every look: a look cost grew with the
//! number of entities, a second of simulation with its square. The grid answers "the active
//! bodies within `r` metres (horizontally) of a point" from the cells that box covers.
//!
//! It is derived state, never a source of truth: before a query it catches up with the
//! storages a body depends on ([`Bodies`]: for the arena, the seven pose storages and the
//! conditions) through their write logs ([`EntityStorage::written_since`]): the entities
//! written since its last query are looked up again; a storage that was written more than
//! its log holds, or replaced, makes it rebuild from scratch. A query returns exactly the
//! bodies [`Bodies::body`] gives for those entities, in id order, so a sensor that filters
//! them with the same tests as a scan of every entity sees the same things in the same order
//! (and draws the same random numbers).

use crate::world::Body;
use vitro::entity::EntityId;
use vitro::env::EntityStorage;

/// Side of a cell, metres.
const CELL_M: f64 = 64.0;
/// Cells added around the bodies' extent at a rebuild (bodies that later leave the extent
/// are kept in the border cells: a query still finds them).
const MARGIN_CELLS: i64 = 8;
/// Storages a body depends on.
pub(crate) const SOURCES: usize = 8;

/// Where the grid stood with one storage when it last caught up.
#[derive(Copy, Clone, Debug, Default, PartialEq, Eq)]
pub(crate) struct Mark {
    writes: u64,
    digest: u64,
}

/// What the grid indexes: bodies kept in [`SOURCES`] entity storages.
pub(crate) trait Bodies {
    /// The marks of the source storages, in a fixed order.
    fn marks(&self) -> [Mark; SOURCES];
    /// The entities written in source `i` since it had made `since` writes, if its log
    /// still holds them all ([`EntityStorage::written_since`]).
    fn written(&self, i: usize, since: u64) -> Option<Vec<EntityId>>;
    /// The body of `id`, if it has one that can be seen.
    fn body(&self, id: EntityId) -> Option<Body>;
    /// Every body that can be seen.
    fn all(&self) -> Vec<(EntityId, Body)>;
}

impl Mark {
    /// The mark of storage `s` now.
    pub(crate) fn of<T>(s: &EntityStorage<T>) -> Mark {
        Mark {
            writes: s.writes(),
            digest: s.digest(),
        }
    }
}

/// The grid (see the module documentation).
#[derive(Debug, Default)]
pub(crate) struct BodyGrid {
    /// Marks of the source storages at the last catch-up; `None` before the first build.
    marks: Option<[Mark; SOURCES]>,
    /// Lower-left corner of cell (0, 0), metres.
    origin: [f64; 2],
    /// Cells along x and y.
    dims: [i64; 2],
    /// Entity indices per cell, row-major (unordered within a cell).
    cells: Vec<Vec<u32>>,
    /// Per entity index: its body and cell ([`STRAY`]: off every cell), if it has an
    /// active body.
    bodies: Vec<Option<(Body, usize)>>,
    /// Entity indices whose position is not finite: every query returns them.
    strays: Vec<u32>,
}

/// The cell of a body whose position is not finite.
const STRAY: usize = usize::MAX;

impl BodyGrid {
    fn cell_of(&self, x: f64, y: f64) -> usize {
        if !(x.is_finite() && y.is_finite()) {
            return STRAY;
        }
        let cx = self.axis(x, 0);
        let cy = self.axis(y, 1);
        (cy * self.dims[0] + cx) as usize
    }

    /// The cell column (`k = 0`) or row (`k = 1`) of coordinate `v`, clamped to the grid.
    fn axis(&self, v: f64, k: usize) -> i64 {
        let c = libm::floor((v - self.origin[k]) / CELL_M);
        // NaN and infinities land in a border cell too.
        let c = if c.is_nan() { 0.0 } else { c };
        (c.clamp(0.0, (self.dims[k] - 1) as f64)) as i64
    }

    /// Rebuilds the grid from every entity with a condition.
    fn rebuild(&mut self, w: &impl Bodies) {
        let bodies = w.all();
        let (mut lo, mut hi) = ([f64::INFINITY; 2], [f64::NEG_INFINITY; 2]);
        for (_, b) in bodies
            .iter()
            .filter(|(_, b)| b.pos[0].is_finite() && b.pos[1].is_finite())
        {
            for k in 0..2 {
                lo[k] = lo[k].min(b.pos[k]);
                hi[k] = hi[k].max(b.pos[k]);
            }
        }
        if lo[0] > hi[0] {
            (lo, hi) = ([0.0; 2], [0.0; 2]);
        }
        let margin = MARGIN_CELLS as f64 * CELL_M;
        self.origin = [lo[0] - margin, lo[1] - margin];
        for k in 0..2 {
            let span = hi[k] - lo[k] + 2.0 * margin;
            self.dims[k] = (libm::ceil(span / CELL_M) as i64).clamp(1, 4096);
        }
        self.cells = vec![Vec::new(); (self.dims[0] * self.dims[1]) as usize];
        self.bodies.clear();
        self.strays.clear();
        for (id, b) in bodies {
            self.put(id, Some(b));
        }
        self.marks = Some(w.marks());
    }

    /// Sets the body of `id` (`None`: no active body), moving it between cells.
    fn put(&mut self, id: EntityId, body: Option<Body>) {
        let i = id.index();
        if self.bodies.len() <= i {
            self.bodies.resize(i + 1, None);
        }
        let new_cell = body.map(|b| self.cell_of(b.pos[0], b.pos[1]));
        let old_cell = self.bodies[i].map(|(_, c)| c);
        if old_cell != new_cell {
            if let Some(c) = old_cell {
                let cell = if c == STRAY {
                    &mut self.strays
                } else {
                    &mut self.cells[c]
                };
                if let Some(at) = cell.iter().position(|&e| e == id.0) {
                    cell.swap_remove(at);
                }
            }
            match new_cell {
                Some(STRAY) => self.strays.push(id.0),
                Some(c) => self.cells[c].push(id.0),
                None => {}
            }
        }
        self.bodies[i] = body.zip(new_cell);
    }

    /// Catches up with the storages of `w`.
    fn sync(&mut self, w: &impl Bodies) {
        let now = w.marks();
        let Some(then) = self.marks else {
            self.rebuild(w);
            return;
        };
        if now == then {
            return;
        }
        let mut changed: Vec<EntityId> = Vec::new();
        for (i, (a, b)) in then.iter().zip(now.iter()).enumerate() {
            if a == b {
                continue;
            }
            // A storage replaced or rewound (a restore) shows as fewer writes or as the same
            // count with another digest: rebuild.
            match (b.writes > a.writes)
                .then(|| w.written(i, a.writes))
                .flatten()
            {
                Some(ids) => changed.extend(ids),
                None => {
                    self.rebuild(w);
                    return;
                }
            }
        }
        changed.sort_unstable();
        changed.dedup();
        for id in changed {
            self.put(id, w.body(id));
        }
        self.marks = Some(now);
    }

    /// The active bodies within `radius` metres of `(x, y)` horizontally (and perhaps a few
    /// more, never fewer: those off the grid's cells), in no particular order.
    pub(crate) fn near(
        &mut self,
        w: &impl Bodies,
        x: f64,
        y: f64,
        radius: f64,
    ) -> Vec<(EntityId, Body)> {
        self.sync(w);
        let r = if radius.is_finite() {
            radius.max(0.0)
        } else {
            f64::INFINITY
        };
        let (x0, x1) = (self.axis(x - r, 0), self.axis(x + r, 0));
        let (y0, y1) = (self.axis(y - r, 1), self.axis(y + r, 1));
        // Horizontally within the radius (with a hair of slack for rounding: a body within
        // the radius in 3D is never left out).
        let r2 = r * r * (1.0 + 1e-9) + 1e-9;
        let within = |b: &Body| {
            let (dx, dy) = (b.pos[0] - x, b.pos[1] - y);
            dx * dx + dy * dy <= r2
        };
        let mut out: Vec<(EntityId, Body)> = Vec::new();
        for &e in &self.strays {
            if let Some(Some((b, _))) = self.bodies.get(e as usize) {
                out.push((EntityId(e), *b));
            }
        }
        for cy in y0..=y1 {
            let row = cy * self.dims[0];
            for cx in x0..=x1 {
                for &e in &self.cells[(row + cx) as usize] {
                    if let Some(Some((b, _))) = self.bodies.get(e as usize)
                        && within(b)
                    {
                        out.push((EntityId(e), *b));
                    }
                }
            }
        }
        out
    }
}

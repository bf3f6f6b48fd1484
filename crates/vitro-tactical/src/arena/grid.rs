//! A uniform grid of the bodies vision looks at, kept in step with the arena's storages.
//!
//! A look that examined every entity of the arena would cost in proportion to the number of
//! entities, a second of simulation with its square. The grid answers "the active bodies
//! within `r` metres (horizontally) of a point" from the cells that box covers.
//!
//! It is derived state, never a source of truth: before a query it catches up with the
//! storages a body depends on ([`Bodies`]: for the arena, the seven pose storages and the
//! conditions) through their write logs ([`EntityStorage::written_since`]): the entities
//! written since its last query are looked up again; a storage that was written more than
//! its log holds, or replaced, makes it look every entity up again (in the cells laid out at
//! its first build: a body beyond them is kept in a border cell). A query returns exactly the
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
    /// Calls `f` with every body that can be seen, in the order of [`all`](Self::all),
    /// without gathering them first.
    fn each(&self, f: &mut dyn FnMut(EntityId, Body)) {
        for (id, b) in self.all() {
            f(id, b);
        }
    }
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
    /// Rebuilds so far: cells and changes of an earlier generation mean nothing now.
    generation: u64,
    /// Changes of a body so far (the grid's clock; a body written again with the same bits
    /// is no change).
    clock: u64,
    /// The latest changes (at least [`LOG`] of them, unless the grid was rebuilt since),
    /// oldest first: `log[k]` is change number `log_start + k` of the clock.
    log: Vec<Change>,
    /// The clock of `log[0]`.
    log_start: u64,
    /// Times every body was looked up again ([`resync`](Self::resync)).
    pub(crate) resyncs: u64,
}

/// Changes the grid remembers at least (the log holds between this and twice as many).
pub(crate) const LOG: usize = 1 << 14;

/// One change of a body: the cells it was in before and after (column and row; [`OFF`]:
/// no active body, [`STRAYED`]: a position that is not finite).
#[derive(Copy, Clone, Debug)]
pub(crate) struct Change {
    /// The entity index.
    pub(crate) id: u32,
    before: [u16; 2],
    after: [u16; 2],
}

/// The cell of a change for no active body.
const OFF: [u16; 2] = [u16::MAX, u16::MAX];
/// The cell of a change for a body whose position is not finite.
const STRAYED: [u16; 2] = [u16::MAX - 1, u16::MAX - 1];

/// True if `b` is horizontally within `r` metres of `(x, y)`, with a hair of slack for
/// rounding (a body within the radius in 3D is never left out).
fn within(x: f64, y: f64, r: f64, b: &Body) -> bool {
    let r2 = r * r * (1.0 + 1e-9) + 1e-9;
    let (dx, dy) = (b.pos[0] - x, b.pos[1] - y);
    dx * dx + dy * dy <= r2
}

/// A body's position, heading and height as exact bits: what a look of it, or from it,
/// depends on besides its side.
pub(super) fn body_bits(b: &Body) -> [u64; 5] {
    [
        b.pos[0].to_bits(),
        b.pos[1].to_bits(),
        b.pos[2].to_bits(),
        b.heading.to_bits(),
        b.height.to_bits(),
    ]
}

/// Whether two arrays of bits are equal, folded with XOR and OR: array equality calls
/// `memcmp` for them (about 1 % of a run at 2,000 entities, over the three places that
/// compare bodies, looks' keys and visions).
#[inline]
pub(super) fn bits_eq(a: &[u64; 5], b: &[u64; 5]) -> bool {
    a.iter().zip(b).fold(0, |d, (x, y)| d | (x ^ y)) == 0
}

/// The same body, bit for bit (what vision sees of it cannot differ).
fn same(a: &Body, b: &Body) -> bool {
    a.side == b.side && bits_eq(&body_bits(a), &body_bits(b))
}

/// The cell of a body whose position is not finite.
const STRAY: usize = usize::MAX;

/// What a query looks at: its centre and radius, and the cells that cover it.
#[derive(Copy, Clone, Debug)]
pub(crate) struct Area {
    x: f64,
    y: f64,
    r: f64,
    /// Columns `x0..=x1` and rows `y0..=y1`: `[x0, x1, y0, y1]`.
    cells: [i64; 4],
}

impl Area {
    fn holds(&self, cx: i64, cy: i64) -> bool {
        let [x0, x1, y0, y1] = self.cells;
        (x0..=x1).contains(&cx) && (y0..=y1).contains(&cy)
    }

    /// True if the query looks at the cell a change put a body in or took it from (a stray:
    /// every query does): whether the body could be in its answer before or after. A look
    /// asks it of every change since its last look, so it is a few compares without
    /// branches: the area's columns and rows are within `0..4096` with `x0 <= x1` and
    /// `y0 <= y1`, so a column `c` is in `x0..=x1` exactly when `c - x0` (wrapping) is at
    /// most `x1 - x0`, and [`OFF`] and [`STRAYED`] are beyond every cell.
    #[inline]
    pub(crate) fn touches(&self, c: &Change) -> bool {
        let [x0, x1, y0, y1] = self.cells;
        let (x0, w, y0, h) = (x0 as u16, (x1 - x0) as u16, y0 as u16, (y1 - y0) as u16);
        let inside = |cr: [u16; 2]| (cr[0].wrapping_sub(x0) <= w) & (cr[1].wrapping_sub(y0) <= h);
        inside(c.before) | inside(c.after) | (c.before == STRAYED) | (c.after == STRAYED)
    }
}

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
        // A new generation: what changed before means nothing in its cells.
        self.generation += 1;
        self.log.clear();
        self.log_start = self.clock + 1;
        self.marks = Some(w.marks());
    }

    /// Sets the body of `id` (`None`: no active body), moving it between cells.
    fn put(&mut self, id: EntityId, body: Option<Body>) {
        let i = id.index();
        if self.bodies.len() <= i {
            self.bodies.resize(i + 1, None);
        }
        let unchanged = match (&self.bodies[i], &body) {
            (Some((a, _)), Some(b)) => same(a, b),
            (None, None) => true,
            _ => false,
        };
        if unchanged {
            return;
        }
        let new_cell = body.map(|b| self.cell_of(b.pos[0], b.pos[1]));
        let old_cell = self.bodies[i].map(|(_, c)| c);
        self.clock += 1;
        let change = Change {
            id: id.0,
            before: self.column_row(old_cell),
            after: self.column_row(new_cell),
        };
        if self.log.len() >= 2 * LOG {
            self.log.drain(..LOG);
            self.log_start += LOG as u64;
        }
        self.log.push(change);
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

    /// Looks every body up again, in the same cells (only what changed goes in the log).
    fn resync(&mut self, w: &impl Bodies) {
        self.resyncs += 1;
        let mut found = vec![false; self.bodies.len()];
        // One body at a time: gathering the bodies of every entity into a list of their
        // own first was most of the cost of a resync (a fresh allocation every time).
        w.each(&mut |id, b| {
            if let Some(f) = found.get_mut(id.index()) {
                *f = true;
            }
            self.put(id, Some(b));
        });
        for (i, f) in found.into_iter().enumerate() {
            if !f && self.bodies[i].is_some() {
                self.put(EntityId(i as u32), None);
            }
        }
    }

    /// Catches up with the storages of `w`.
    pub(crate) fn sync(&mut self, w: &impl Bodies) {
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
            // count with another digest: look everything up again.
            match (b.writes > a.writes)
                .then(|| w.written(i, a.writes))
                .flatten()
            {
                Some(ids) => changed.extend(ids),
                None => {
                    self.resync(w);
                    self.marks = Some(now);
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

    /// The cells a query of `radius` metres around `(x, y)` covers (columns `x0..=x1`, rows
    /// `y0..=y1`), and the radius it uses.
    fn span(&self, x: f64, y: f64, radius: f64) -> ([i64; 4], f64) {
        let r = if radius.is_finite() {
            radius.max(0.0)
        } else {
            f64::INFINITY
        };
        let (x0, x1) = (self.axis(x - r, 0), self.axis(x + r, 0));
        let (y0, y1) = (self.axis(y - r, 1), self.axis(y + r, 1));
        ([x0, x1, y0, y1], r)
    }

    /// Where the grid stands in time: its generation and its clock.
    pub(crate) fn now(&self) -> (u64, u64) {
        (self.generation, self.clock)
    }

    /// The column and row of a cell (see [`Change`]).
    fn column_row(&self, cell: Option<usize>) -> [u16; 2] {
        match cell {
            None => OFF,
            Some(STRAY) => STRAYED,
            // Dimensions are at most 4096 cells.
            Some(c) => {
                let d = self.dims[0] as usize;
                [(c % d) as u16, (c / d) as u16]
            }
        }
    }

    /// The changes after clock `at`, oldest first, if the log still holds them all.
    pub(crate) fn changes_since(&self, at: u64) -> Option<&[Change]> {
        let from = (at + 1).checked_sub(self.log_start)?;
        self.log.get(usize::try_from(from).ok()?..)
    }

    /// The area a query of `radius` metres around `(x, y)` looks at.
    pub(crate) fn area(&self, x: f64, y: f64, radius: f64) -> Area {
        let (cells, r) = self.span(x, y, radius);
        Area { x, y, r, cells }
    }

    /// The body of entity index `e` if a query of `area` returns it now
    /// ([`query`](Self::query)).
    pub(crate) fn returned(&self, area: &Area, e: u32) -> Option<Body> {
        let (b, cell) = (*self.bodies.get(e as usize)?)?;
        if cell == STRAY {
            return Some(b);
        }
        let (cx, cy) = (cell as i64 % self.dims[0], cell as i64 / self.dims[0]);
        (area.holds(cx, cy) && within(area.x, area.y, area.r, &b)).then_some(b)
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
        self.query(x, y, radius)
    }

    /// [`near`](Self::near) without catching up first (the caller just did).
    pub(crate) fn query(&self, x: f64, y: f64, radius: f64) -> Vec<(EntityId, Body)> {
        let ([x0, x1, y0, y1], r) = self.span(x, y, radius);
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
                        && within(x, y, r, b)
                    {
                        out.push((EntityId(e), *b));
                    }
                }
            }
        }
        out
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn touches_answers_as_the_range_tests() {
        // The test as written before: a stray, or a cell (not OFF) in the area's ranges.
        let slow = |a: &Area, c: &Change| {
            let inside = |cr: [u16; 2]| {
                cr == STRAYED || (cr != OFF && a.holds(i64::from(cr[0]), i64::from(cr[1])))
            };
            inside(c.before) || inside(c.after)
        };
        let values = [
            0,
            1,
            2,
            5,
            63,
            64,
            100,
            4094,
            4095,
            4096,
            40000,
            u16::MAX - 1,
            u16::MAX,
        ];
        let areas = [
            [0, 0, 0, 0],
            [0, 4095, 0, 4095],
            [2, 5, 63, 100],
            [4095, 4095, 1, 1],
        ];
        let mut hits = 0;
        for cells in areas {
            let area = Area {
                x: 0.0,
                y: 0.0,
                r: 1.0,
                cells,
            };
            for b0 in values {
                for b1 in values {
                    for after in [OFF, STRAYED, [2, 64], [5, 100], [6, 100]] {
                        let c = Change {
                            id: 0,
                            before: [b0, b1],
                            after,
                        };
                        assert_eq!(area.touches(&c), slow(&area, &c), "{cells:?} {c:?}");
                        hits += usize::from(area.touches(&c));
                    }
                }
            }
        }
        assert!(hits > 100, "{hits}");
    }
}

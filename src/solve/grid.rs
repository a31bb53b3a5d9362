//! A uniform bucket grid over a room's floor holding the footprints placed at a search node, so
//! that "does this rectangle overlap a placed footprint, and which one first" looks only at
//! the footprints near the rectangle instead of every one placed.
//!
//! The search asks that question for every candidate pose of every node (the first blocker of
//! a pose, the sides it touches, whether a dependent's zone or a seat is still free, whether a
//! use-clearance is kept), so with a linear scan a node costs candidates × objects placed and a
//! room of N objects costs about N² per node walked. With the grid a question costs the
//! footprints in the few cells the rectangle covers, which stays flat as the room fills.
//!
//! Answers are exactly those of the linear scan: a cell range is computed by clamping to the
//! grid, which keeps any two overlapping rectangles in a shared cell (clamping is monotone, and
//! [`Rect::overlaps`] needs the interiors to meet), every footprint found is tested with
//! [`Rect::overlaps`] itself, and "first" means the lowest index, as a scan from the start
//! would give.

use super::constraints::Rect;

/// The side of a cell, metres, unless the room is so large that the grid would pass
/// [`MAX_CELLS_PER_SIDE`] cells on a side.
const CELL_M: f64 = 0.5;

/// The most cells on a side.
const MAX_CELLS_PER_SIDE: usize = 64;

/// The footprints placed at a node, bucketed by the cells they cover.
///
/// Made whole with [`FootprintGrid::new`], or kept along a search path with
/// [`FootprintGrid::push`] and [`FootprintGrid::pop`] (last in, first out), which cost only the
/// cells of the one footprint: the search places and takes back one object at a time, so the
/// grid of a node is never built again from every footprint placed.
#[derive(Clone)]
pub(crate) struct FootprintGrid {
    rects: Vec<Rect>,
    at: Cells,
    /// Per cell (row-major, x fastest), the indices of the footprints covering it, ascending.
    cells: Vec<Vec<u32>>,
}

/// Where the cells of a bucket grid over a room lie: square cells of one side from an origin,
/// `nx` by `nz` of them; coordinates outside are clamped into the edge cells.
#[derive(Clone, Copy)]
struct Cells {
    x0: f64,
    z0: f64,
    inv_cell: f64,
    nx: usize,
    nz: usize,
}

impl Cells {
    /// Cells of [`CELL_M`] over `bounds` (the room's bounding box), larger when the room
    /// would pass [`MAX_CELLS_PER_SIDE`] on a side.
    fn over(bounds: &Rect) -> Cells {
        let (w, d) = (bounds.width().max(0.0), bounds.depth().max(0.0));
        let longest = w.max(d);
        let cell = if longest / CELL_M > MAX_CELLS_PER_SIDE as f64 {
            longest / MAX_CELLS_PER_SIDE as f64
        } else {
            CELL_M
        };
        let count = |extent: f64| -> usize {
            let n = (extent / cell).ceil();
            if n.is_finite() && n >= 1.0 {
                (n as usize).min(MAX_CELLS_PER_SIDE)
            } else {
                1
            }
        };
        let (nx, nz) = (count(w), count(d));
        let x0 = if bounds.min_x.is_finite() { bounds.min_x } else { 0.0 };
        let z0 = if bounds.min_z.is_finite() { bounds.min_z } else { 0.0 };
        Cells { x0, z0, inv_cell: 1.0 / cell, nx, nz }
    }

    /// One cell holding everything.
    fn one() -> Cells {
        Cells { x0: 0.0, z0: 0.0, inv_cell: 0.0, nx: 1, nz: 1 }
    }

    fn count(&self) -> usize {
        self.nx * self.nz
    }

    /// The cell index of coordinate `v` along an axis starting at `origin` with `n` cells,
    /// clamped into the grid.
    #[inline]
    fn cell_of(&self, v: f64, origin: f64, n: usize) -> usize {
        // Clamped into the grid first (`max` takes 0 for NaN), then truncated, which is the
        // floor for what is not negative (and no libm call on a hot path).
        let c = ((v - origin) * self.inv_cell).max(0.0).min((n - 1) as f64);
        c as usize
    }

    /// The cell (row-major, x fastest) of a point, clamped into the grid.
    #[inline]
    fn of_point(&self, p: [f64; 2]) -> usize {
        self.cell_of(p[1], self.z0, self.nz) * self.nx + self.cell_of(p[0], self.x0, self.nx)
    }

    /// The inclusive cell ranges along x and z a rectangle covers, clamped into the grid.
    #[inline]
    fn span(&self, r: &Rect) -> ((usize, usize), (usize, usize)) {
        let xs = (self.cell_of(r.min_x, self.x0, self.nx), self.cell_of(r.max_x, self.x0, self.nx));
        let zs = (self.cell_of(r.min_z, self.z0, self.nz), self.cell_of(r.max_z, self.z0, self.nz));
        ((xs.0, xs.1.max(xs.0)), (zs.0, zs.1.max(zs.0)))
    }
}

impl FootprintGrid {
    /// The grid over `bounds` (the room's bounding box) holding `rects`.
    pub(crate) fn new(bounds: &Rect, rects: Vec<Rect>) -> FootprintGrid {
        let at = Cells::over(bounds);
        let mut grid = FootprintGrid {
            rects: Vec::with_capacity(rects.len()),
            at,
            cells: vec![Vec::new(); at.count()],
        };
        for r in rects {
            grid.push(r);
        }
        grid
    }

    /// Adds a footprint after the others (its index is the number held before).
    pub(crate) fn push(&mut self, r: Rect) {
        // More than `u32::MAX` footprints cannot be indexed: such a one is held but never found.
        if let Ok(index) = u32::try_from(self.rects.len()) {
            let (xs, zs) = self.at.span(&r);
            for cz in zs.0..=zs.1 {
                for cx in xs.0..=xs.1 {
                    self.cells[cz * self.at.nx + cx].push(index);
                }
            }
        }
        self.rects.push(r);
    }

    /// Takes back the footprint added last, if any.
    pub(crate) fn pop(&mut self) -> Option<Rect> {
        let r = self.rects.pop()?;
        let Ok(index) = u32::try_from(self.rects.len()) else { return Some(r) };
        let (xs, zs) = self.at.span(&r);
        for cz in zs.0..=zs.1 {
            for cx in xs.0..=xs.1 {
                // Indices in a cell ascend and this one is the largest: it is the cell's last.
                let cell = &mut self.cells[cz * self.at.nx + cx];
                if cell.last() == Some(&index) {
                    cell.pop();
                }
            }
        }
        Some(r)
    }

    /// How many footprints are held.
    #[cfg(test)]
    pub(crate) fn len(&self) -> usize {
        self.rects.len()
    }

    /// Calls `f` with the index of every footprint in a cell `r` covers (a footprint in
    /// several such cells comes several times); stops when `f` returns `false`.
    fn for_each_near(&self, r: &Rect, mut f: impl FnMut(usize) -> bool) {
        let (xs, zs) = self.at.span(r);
        for cz in zs.0..=zs.1 {
            for cx in xs.0..=xs.1 {
                for &i in &self.cells[cz * self.at.nx + cx] {
                    if !f(i as usize) {
                        return;
                    }
                }
            }
        }
    }

    /// The lowest index of a footprint `r` overlaps, if any.
    pub(crate) fn first_overlap(&self, r: &Rect) -> Option<usize> {
        let mut first: Option<usize> = None;
        self.for_each_near(r, |i| {
            if first.is_none_or(|f| i < f) && self.rects[i].overlaps(r) {
                first = Some(i);
            }
            true
        });
        first
    }

    /// Whether `r` overlaps any footprint.
    pub(crate) fn any_overlap(&self, r: &Rect) -> bool {
        let mut found = false;
        self.for_each_near(r, |i| {
            found = self.rects[i].overlaps(r);
            !found
        });
        found
    }

    /// The footprints held, in the order given.
    pub(crate) fn rects(&self) -> &[Rect] {
        &self.rects
    }

    /// Whether `r` overlaps any footprint for which `counts` holds.
    pub(crate) fn any_overlap_where(&self, r: &Rect, counts: impl Fn(usize) -> bool) -> bool {
        let mut found = false;
        self.for_each_near(r, |i| {
            found = counts(i) && self.rects[i].overlaps(r);
            !found
        });
        found
    }

    /// Calls `f` with every footprint index that `r` may overlap (each at least once, in no
    /// particular order; some may not overlap `r`: the caller tests).
    pub(crate) fn near(&self, r: &Rect, mut f: impl FnMut(usize)) {
        self.for_each_near(r, |i| {
            f(i);
            true
        });
    }
}

/// Zones fixed for one node (the use-clearances an object keeps out of), bucketed once in
/// compressed rows: a grid of [`CELL_M`] cells whose footprint lists lie side by side in one
/// array, so that making it costs two passes over the zones and three allocations, where a
/// [`FootprintGrid`] allocates a list per cell a zone covers. It answers only "does this
/// rectangle overlap a zone", as [`FootprintGrid::any_overlap`] does (a few zones are looked
/// through one by one).
pub(crate) struct ZoneGrid {
    rects: Vec<Rect>,
    at: Cells,
    /// Per cell, where its zones begin in `items` (one more entry than cells).
    starts: Vec<u32>,
    /// The zones' indices, cell after cell.
    items: Vec<u32>,
}

impl ZoneGrid {
    /// Up to how many zones are looked through one by one rather than bucketed.
    const FEW: usize = 16;

    /// The zones `rects` over `bounds` (the room's bounding box).
    pub(crate) fn new(bounds: &Rect, rects: Vec<Rect>) -> ZoneGrid {
        if rects.len() <= Self::FEW || u32::try_from(rects.len()).is_err() {
            return ZoneGrid { rects, at: Cells::one(), starts: Vec::new(), items: Vec::new() };
        }
        let at = Cells::over(bounds);
        let mut starts = vec![0u32; at.count() + 1];
        for r in &rects {
            let (xs, zs) = at.span(r);
            for cz in zs.0..=zs.1 {
                for cx in xs.0..=xs.1 {
                    starts[cz * at.nx + cx + 1] += 1;
                }
            }
        }
        for c in 0..at.count() {
            starts[c + 1] += starts[c];
        }
        let mut fill = starts.clone();
        let mut items = vec![0u32; starts[at.count()] as usize];
        for (i, r) in (0u32..).zip(&rects) {
            let (xs, zs) = at.span(r);
            for cz in zs.0..=zs.1 {
                for cx in xs.0..=xs.1 {
                    let cell = &mut fill[cz * at.nx + cx];
                    items[*cell as usize] = i;
                    *cell += 1;
                }
            }
        }
        ZoneGrid { rects, at, starts, items }
    }

    /// Whether `r` overlaps any zone.
    pub(crate) fn any_overlap(&self, r: &Rect) -> bool {
        if self.starts.is_empty() {
            return self.rects.iter().any(|z| z.overlaps(r));
        }
        let (xs, zs) = self.at.span(r);
        for cz in zs.0..=zs.1 {
            for cx in xs.0..=xs.1 {
                let c = cz * self.at.nx + cx;
                let (a, b) = (self.starts[c] as usize, self.starts[c + 1] as usize);
                if self.items[a..b].iter().any(|&i| self.rects[i as usize].overlaps(r)) {
                    return true;
                }
            }
        }
        false
    }
}

/// The candidate poses of one object bucketed by their centres: which of them can stand within
/// a distance of a rectangle is looked up in the cells near it instead of going through all.
///
/// A footprint whose half extents are at most `half` can come within `d` of a rectangle only
/// if its centre lies in the rectangle grown by `d` plus `half` along each axis; the lookup
/// gives every candidate whose centre's cell meets that box (clamping keeps it a superset) and
/// the caller tests each one.
pub(crate) struct CentreIndex {
    at: Cells,
    /// Per cell, where its candidates begin in `items` (one more entry than cells).
    starts: Vec<u32>,
    /// The candidates' indices, cell after cell, ascending within a cell.
    items: Vec<u32>,
    /// The largest half extents along x and z of the footprints indexed.
    half: [f64; 2],
}

impl CentreIndex {
    /// The index over `bounds` (the room's bounding box) of `footprints`, by their centres.
    pub(crate) fn new(bounds: &Rect, footprints: &[Rect]) -> CentreIndex {
        let at = Cells::over(bounds);
        let mut half = [0.0f64; 2];
        let cells: Vec<usize> = footprints
            .iter()
            .map(|fp| {
                half[0] = half[0].max(fp.width() / 2.0);
                half[1] = half[1].max(fp.depth() / 2.0);
                at.of_point(fp.center())
            })
            .collect();
        let mut starts = vec![0u32; at.count() + 1];
        for &c in &cells {
            starts[c + 1] += 1;
        }
        for c in 0..at.count() {
            starts[c + 1] += starts[c];
        }
        let mut fill = starts.clone();
        let mut items = vec![0u32; cells.len()];
        for (i, &c) in (0u32..).zip(&cells) {
            items[fill[c] as usize] = i;
            fill[c] += 1;
        }
        CentreIndex { at, starts, items, half }
    }

    /// Calls `f` with every candidate whose footprint can come within `d` of `r` (each once, in
    /// no particular order; some may be farther: the caller tests).
    pub(crate) fn within(&self, r: &Rect, d: f64, mut f: impl FnMut(u32)) {
        // Beyond any rounding of a footprint's centre and half extents.
        const SLACK: f64 = 1e-6;
        let box_ = Rect {
            min_x: r.min_x - d - self.half[0] - SLACK,
            max_x: r.max_x + d + self.half[0] + SLACK,
            min_z: r.min_z - d - self.half[1] - SLACK,
            max_z: r.max_z + d + self.half[1] + SLACK,
        };
        let (xs, zs) = self.at.span(&box_);
        for cz in zs.0..=zs.1 {
            let row = cz * self.at.nx;
            let (a, b) = (self.starts[row + xs.0] as usize, self.starts[row + xs.1 + 1] as usize);
            for &i in &self.items[a..b] {
                f(i);
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use rand::{Rng as _, SeedableRng as _};

    fn rect(x: f64, z: f64, w: f64, d: f64) -> Rect {
        Rect { min_x: x, min_z: z, max_x: x + w, max_z: z + d }
    }

    /// A rectangle whose corner lies within `margin` of `room` and whose sides are below `most`.
    fn random_rect(rng: &mut rand_chacha::ChaCha8Rng, room: &Rect, margin: f64, most: f64) -> Rect {
        rect(
            rng.gen_range(room.min_x - margin..room.max_x + margin),
            rng.gen_range(room.min_z - margin..room.max_z + margin),
            rng.gen_range(0.0..most),
            rng.gen_range(0.0..most),
        )
    }

    #[test]
    fn answers_as_a_linear_scan_does() {
        let mut rng = rand_chacha::ChaCha8Rng::seed_from_u64(7);
        for room in [rect(0.0, 0.0, 4.0, 3.0), rect(-2.0, 1.0, 40.0, 0.5), rect(0.0, 0.0, 0.1, 0.1)]
        {
            let rects: Vec<Rect> =
                (0..60).map(|_| random_rect(&mut rng, &room, 1.0, 2.0)).collect();
            let grid = FootprintGrid::new(&room, rects.clone());
            let zones = ZoneGrid::new(&room, rects.clone());
            let few = ZoneGrid::new(&room, rects[..10].to_vec());
            for _ in 0..2000 {
                let q = random_rect(&mut rng, &room, 2.0, 3.0);
                let first = rects.iter().position(|r| r.overlaps(&q));
                assert_eq!(grid.first_overlap(&q), first);
                assert_eq!(grid.any_overlap(&q), first.is_some());
                assert_eq!(zones.any_overlap(&q), first.is_some());
                assert_eq!(few.any_overlap(&q), rects[..10].iter().any(|r| r.overlaps(&q)));
                let odd = rects.iter().enumerate().any(|(i, r)| i % 2 == 1 && r.overlaps(&q));
                assert_eq!(grid.any_overlap_where(&q, |i| i % 2 == 1), odd);
                let mut seen = vec![false; rects.len()];
                grid.near(&q, |i| seen[i] = true);
                assert!(rects.iter().enumerate().all(|(i, r)| !r.overlaps(&q) || seen[i]));
            }
        }
    }

    #[test]
    fn the_centre_index_finds_every_footprint_within_a_distance() {
        let mut rng = rand_chacha::ChaCha8Rng::seed_from_u64(5);
        for room in [rect(0.0, 0.0, 7.0, 8.0), rect(-3.0, 2.0, 50.0, 0.6)] {
            let fps: Vec<Rect> = (0..500).map(|_| random_rect(&mut rng, &room, 0.5, 1.5)).collect();
            let index = CentreIndex::new(&room, &fps);
            for _ in 0..500 {
                let q = random_rect(&mut rng, &room, 2.0, 2.0);
                let d = rng.gen_range(0.0..1.5);
                let mut seen = vec![0u32; fps.len()];
                index.within(&q, d, |i| seen[i as usize] += 1);
                assert!(seen.iter().all(|&n| n <= 1), "each candidate at most once");
                for (i, fp) in fps.iter().enumerate() {
                    if fp.gap(&q) <= d {
                        assert_eq!(seen[i], 1, "{fp:?} is within {d} of {q:?}");
                    }
                }
            }
        }
    }

    #[test]
    fn pushing_and_popping_answers_as_building_anew() {
        let mut rng = rand_chacha::ChaCha8Rng::seed_from_u64(11);
        let room = rect(0.0, 0.0, 6.0, 5.0);
        let mut kept = FootprintGrid::new(&room, Vec::new());
        let mut held: Vec<Rect> = Vec::new();
        for _ in 0..400 {
            if held.is_empty() || rng.gen_bool(0.6) {
                let r = rect(
                    rng.gen_range(-1.0..6.5),
                    rng.gen_range(-1.0..5.5),
                    rng.gen_range(0.0..2.5),
                    rng.gen_range(0.0..2.5),
                );
                kept.push(r);
                held.push(r);
            } else {
                assert_eq!(kept.pop(), held.pop());
            }
            assert_eq!(kept.len(), held.len());
            let fresh = FootprintGrid::new(&room, held.clone());
            assert_eq!(kept.cells, fresh.cells);
            for _ in 0..20 {
                let q = rect(
                    rng.gen_range(-1.0..6.5),
                    rng.gen_range(-1.0..5.5),
                    rng.gen_range(0.0..2.0),
                    rng.gen_range(0.0..2.0),
                );
                assert_eq!(kept.first_overlap(&q), fresh.first_overlap(&q));
            }
        }
    }

    #[test]
    fn touching_rectangles_and_edge_cells() {
        // Footprints meeting exactly on a cell line do not overlap; ones crossing it do.
        let rects = [rect(0.0, 0.0, 0.5, 0.5), rect(0.5, 0.0, 0.5, 0.5)];
        let grid = FootprintGrid::new(&rect(0.0, 0.0, 2.0, 2.0), rects.to_vec());
        assert_eq!(grid.first_overlap(&rect(0.5, 0.5, 0.5, 0.5)), None);
        assert_eq!(grid.first_overlap(&rect(0.4, 0.4, 0.2, 0.2)), Some(0));
        // Far outside the grid is clamped into its edge cells.
        assert_eq!(grid.first_overlap(&rect(-10.0, -10.0, 10.3, 10.3)), Some(0));
        assert!(!grid.any_overlap(&rect(f64::NAN, 0.0, 1.0, 1.0)));
    }
}

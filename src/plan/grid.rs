//! A uniform grid over the floor: which of many boxes may meet a given box, without looking
//! at every one.
//!
//! The plan stage asks, for every wall, which corners lie on it and which walls of other rooms
//! run along it; the gap warning asks which rooms are near a room. Asked of every item, those
//! questions cost the square of the plan's size (3,200 rooms at 100,000 lines). The grid keeps
//! each item under the cells its box covers; a query gathers the items of the cells its own box
//! covers. The answer is a superset, in item order: the caller applies its exact test to each
//! item returned, in that order, and so gets what a test of every item would give, as long as
//! every item that passes the test has a box that meets the query's (callers widen both by a
//! margin well above their tolerances). An item or a query whose box is not finite or covers
//! too many cells is not cut up: such an item is returned by every query, and such a query
//! returns every item.

use crate::geometry::Point;
use rustc_hash::FxHashMap;

/// The most cells one box is kept under; a larger box is returned by every query.
const MAX_CELLS: i64 = 1024;

/// Items `0..len` by the cells of the floor their boxes cover.
#[derive(Debug)]
pub(crate) struct Grid {
    /// The side of a cell, metres.
    cell: f64,
    /// The items under each cell, in the order they were added.
    cells: FxHashMap<(i64, i64), Vec<usize>>,
    /// Items whose box could not be cut into cells: met by every query.
    wide: Vec<usize>,
    /// How many items were added.
    len: usize,
}

/// The cells a box covers: the first and last cell on each axis, or `None` when the box is not
/// finite or covers more than [`MAX_CELLS`].
fn cover(cell: f64, min: Point, max: Point) -> Option<[(i64, i64); 2]> {
    let index = |v: f64| {
        let c = (v / cell).floor();
        (c.is_finite() && c.abs() < 1e15).then_some(c as i64)
    };
    let (x0, x1) = (index(min[0])?, index(max[0])?);
    let (z0, z1) = (index(min[1])?, index(max[1])?);
    if x1 < x0 || z1 < z0 {
        return None;
    }
    let count = (x1 - x0 + 1).checked_mul(z1 - z0 + 1)?;
    (count <= MAX_CELLS).then_some([(x0, x1), (z0, z1)])
}

impl Grid {
    /// An empty grid of cells `cell` metres wide.
    pub(crate) fn new(cell: f64) -> Grid {
        Grid { cell, cells: FxHashMap::default(), wide: Vec::new(), len: 0 }
    }

    /// Adds the next item (number [`Grid::len`] before the call) with its box.
    pub(crate) fn push(&mut self, min: Point, max: Point) {
        let item = self.len;
        self.len += 1;
        match cover(self.cell, min, max) {
            Some([(x0, x1), (z0, z1)]) => {
                for x in x0..=x1 {
                    for z in z0..=z1 {
                        self.cells.entry((x, z)).or_default().push(item);
                    }
                }
            }
            None => self.wide.push(item),
        }
    }

    /// Every item whose box may meet the box `min`–`max`, in increasing order, each once.
    pub(crate) fn query(&self, min: Point, max: Point) -> Vec<usize> {
        let Some([(x0, x1), (z0, z1)]) = cover(self.cell, min, max) else {
            return (0..self.len).collect();
        };
        let mut out = self.wide.clone();
        for x in x0..=x1 {
            for z in z0..=z1 {
                if let Some(items) = self.cells.get(&(x, z)) {
                    out.extend_from_slice(items);
                }
            }
        }
        out.sort_unstable();
        out.dedup();
        out
    }
}

/// The bounding box of points, widened by `margin` plus a billionth of the largest coordinate
/// (so that the rounding of a test on large coordinates stays inside it).
pub(crate) fn widened_box(points: &[Point], margin: f64) -> (Point, Point) {
    let mut min = [f64::INFINITY; 2];
    let mut max = [f64::NEG_INFINITY; 2];
    let mut largest: f64 = 0.0;
    for p in points {
        for axis in 0..2 {
            min[axis] = min[axis].min(p[axis]);
            max[axis] = max[axis].max(p[axis]);
            largest = largest.max(p[axis].abs());
        }
        // A NaN coordinate makes the box unusable: the query then returns every item.
        if p[0].is_nan() || p[1].is_nan() {
            return ([f64::NAN; 2], [f64::NAN; 2]);
        }
    }
    let m = margin + largest * 1e-9;
    ([min[0] - m, min[1] - m], [max[0] + m, max[1] + m])
}

#[cfg(test)]
mod tests {
    use super::*;
    use proptest::prelude::*;

    fn boxes_meet(a: (Point, Point), b: (Point, Point)) -> bool {
        a.0[0] <= b.1[0] && b.0[0] <= a.1[0] && a.0[1] <= b.1[1] && b.0[1] <= a.1[1]
    }

    proptest! {
        /// A query returns every item whose box meets the query's, in order, each once.
        #[test]
        fn a_query_finds_every_box_that_meets_it(
            items in proptest::collection::vec((-30.0f64..30.0, -30.0f64..30.0, 0.0f64..8.0, 0.0f64..8.0), 0..60),
            q in (-30.0f64..30.0, -30.0f64..30.0, 0.0f64..70.0, 0.0f64..8.0),
            cell in prop_oneof![Just(0.5), Just(2.0), Just(4.0)],
        ) {
            let mut grid = Grid::new(cell);
            let boxes: Vec<(Point, Point)> =
                items.iter().map(|&(x, z, w, d)| ([x, z], [x + w, z + d])).collect();
            for b in &boxes {
                grid.push(b.0, b.1);
            }
            let query = ([q.0, q.1], [q.0 + q.2, q.1 + q.3]);
            let found = grid.query(query.0, query.1);
            prop_assert!(found.windows(2).all(|w| w[0] < w[1]));
            for (i, b) in boxes.iter().enumerate() {
                if boxes_meet(*b, query) {
                    prop_assert!(found.contains(&i), "box {i} missed");
                }
            }
        }
    }

    #[test]
    fn boxes_that_cannot_be_cut_are_always_found() {
        let mut grid = Grid::new(1.0);
        grid.push([0.0, 0.0], [1.0, 1.0]);
        grid.push([f64::NAN, 0.0], [1.0, 1.0]);
        grid.push([-1e300, 0.0], [1e300, 1.0]);
        grid.push([50.0, 50.0], [51.0, 51.0]);
        assert_eq!(grid.query([10.0, 10.0], [11.0, 11.0]), vec![1, 2]);
        assert_eq!(grid.query([f64::NEG_INFINITY, 0.0], [0.0, 0.0]), vec![0, 1, 2, 3]);
        assert_eq!(grid.query([0.5, 0.5], [0.5, 0.5]), vec![0, 1, 2]);
        let (min, max) = widened_box(&[[0.0, 1.0], [2.0, f64::NAN]], 0.1);
        assert!(min[0].is_nan() && max[1].is_nan());
        let (min, max) = widened_box(&[[0.0, 1.0], [2.0, 3.0]], 0.5);
        assert!(min[0] < -0.5 + 1e-6 && max[1] > 3.5 - 1e-6);
    }
}

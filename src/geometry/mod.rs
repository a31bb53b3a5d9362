//! Plane geometry in the floor plane `(x, z)`, metres.
//!
//! Every comparison of lengths goes through [`EPS_M`]: no two floats are compared for exact
//! equality. Orientation follows the house JSON: x to the right, z up when a plan is drawn, so a
//! *clockwise* polygon has a negative [`signed_area`]. Rotations by multiples of 90° are exact
//! ([`rotate_quarter`]).

/// The tolerance of every length comparison, metres (a micrometre).
pub const EPS_M: f64 = 1e-6;

/// A point or vector `(x, z)` in metres.
pub type Point = [f64; 2];

/// Whether two lengths are equal within [`EPS_M`].
pub fn near(a: f64, b: f64) -> bool {
    (a - b).abs() <= EPS_M
}

/// Whether two points are equal within [`EPS_M`] on both axes.
pub fn near_point(a: Point, b: Point) -> bool {
    near(a[0], b[0]) && near(a[1], b[1])
}

/// `b − a`.
pub fn sub(b: Point, a: Point) -> Point {
    [b[0] - a[0], b[1] - a[1]]
}

/// `a + s·v`.
pub fn add_scaled(a: Point, v: Point, s: f64) -> Point {
    [a[0] + s * v[0], a[1] + s * v[1]]
}

/// Euclidean distance.
pub fn distance(a: Point, b: Point) -> f64 {
    length(b[0] - a[0], b[1] - a[1])
}

/// `dx.hypot(dz)`, to the bit, without calling it when one difference is zero: C's `hypot` of
/// a number and a zero is the number's absolute value (C11 Annex F.10.4.3), as here. A wall
/// parallel to an axis most often gives such a difference.
fn length(dx: f64, dz: f64) -> f64 {
    if dz == 0.0 && !dx.is_nan() {
        dx.abs()
    } else if dx == 0.0 && !dz.is_nan() {
        dz.abs()
    } else {
        dx.hypot(dz)
    }
}

/// The unit vector from `a` to `b` (zero when they coincide).
pub fn unit(a: Point, b: Point) -> Point {
    let d = distance(a, b);
    if d <= EPS_M {
        [0.0, 0.0]
    } else {
        [(b[0] - a[0]) / d, (b[1] - a[1]) / d]
    }
}

/// Rotates a vector by `quarter_turns × 90°` clockwise (x right, z up), exactly: the turn that
/// takes rotation 0 (facing +z) to rotation 90 (facing +x).
pub fn rotate_quarter(v: Point, quarter_turns: i32) -> Point {
    match quarter_turns.rem_euclid(4) {
        0 => v,
        1 => [v[1], -v[0]],
        2 => [-v[0], -v[1]],
        _ => [-v[1], v[0]],
    }
}

/// The unit normal on the right of the direction `a → b` (x right, z up). For a clockwise
/// room outline this points into the room.
pub fn right_normal(a: Point, b: Point) -> Point {
    rotate_quarter(unit(a, b), 1)
}

/// The signed area (shoelace formula): positive for counter-clockwise polygons, negative for
/// clockwise ones.
pub fn signed_area(polygon: &[Point]) -> f64 {
    let n = polygon.len();
    let mut sum = 0.0;
    for i in 0..n {
        let a = polygon[i];
        let b = polygon[(i + 1) % n];
        sum += a[0] * b[1] - b[0] * a[1];
    }
    sum / 2.0
}

/// The area centroid of a simple polygon (the vertex mean when the area is zero).
pub fn area_centroid(polygon: &[Point]) -> Point {
    let n = polygon.len();
    if n == 0 {
        return [0.0, 0.0];
    }
    let area = signed_area(polygon);
    if area.abs() <= EPS_M * EPS_M {
        let sx: f64 = polygon.iter().map(|p| p[0]).sum();
        let sz: f64 = polygon.iter().map(|p| p[1]).sum();
        return [sx / n as f64, sz / n as f64];
    }
    let (mut cx, mut cz) = (0.0, 0.0);
    for i in 0..n {
        let a = polygon[i];
        let b = polygon[(i + 1) % n];
        let cross = a[0] * b[1] - b[0] * a[1];
        cx += (a[0] + b[0]) * cross;
        cz += (a[1] + b[1]) * cross;
    }
    [cx / (6.0 * area), cz / (6.0 * area)]
}

/// Whether `p` lies on the segment `a–b` (within [`EPS_M`]), endpoints included.
pub fn point_on_segment(p: Point, a: Point, b: Point) -> bool {
    within(p, nearest_on_segment(p, a, b), EPS_M)
}

/// The point of the segment `a–b` nearest to `p` (`a` for a segment shorter than [`EPS_M`]).
pub fn nearest_on_segment(p: Point, a: Point, b: Point) -> Point {
    let d = sub(b, a);
    let len2 = d[0] * d[0] + d[1] * d[1];
    if len2 <= EPS_M * EPS_M {
        return a;
    }
    let t = (((p[0] - a[0]) * d[0] + (p[1] - a[1]) * d[1]) / len2).clamp(0.0, 1.0);
    add_scaled(a, d, t)
}

/// The distance from `p` to the segment `a–b`.
pub fn distance_to_segment(p: Point, a: Point, b: Point) -> f64 {
    distance(p, nearest_on_segment(p, a, b))
}

/// `distance(a, b).min(bound)`, to the bit, without the square root when one coordinate
/// difference alone reaches `bound` (the distance is never less than either difference).
pub fn distance_below(a: Point, b: Point, bound: f64) -> f64 {
    let (dx, dz) = (b[0] - a[0], b[1] - a[1]);
    if dx.abs().max(dz.abs()) >= bound {
        bound
    } else {
        length(dx, dz).min(bound)
    }
}

/// `distance(a, b) <= r`, to the bit, without the square root when one coordinate difference
/// alone exceeds `r`.
pub fn within(a: Point, b: Point, r: f64) -> bool {
    let (dx, dz) = (b[0] - a[0], b[1] - a[1]);
    dx.abs().max(dz.abs()) <= r && length(dx, dz) <= r
}

/// Whether `p` is on the boundary of the polygon (within [`EPS_M`]).
pub fn point_on_boundary(p: Point, polygon: &[Point]) -> bool {
    let n = polygon.len();
    (0..n).any(|i| point_on_segment(p, polygon[i], polygon[(i + 1) % n]))
}

/// Whether `p` is strictly inside the polygon (boundary points, within [`EPS_M`], are not).
pub fn point_in_polygon(p: Point, polygon: &[Point]) -> bool {
    if point_on_boundary(p, polygon) {
        return false;
    }
    point_in_polygon_raw(p, polygon)
}

/// Whether `p` is inside or on the boundary of the polygon.
pub fn point_in_or_on_polygon(p: Point, polygon: &[Point]) -> bool {
    point_on_boundary(p, polygon) || point_in_polygon_raw(p, polygon)
}

/// A polygon prepared for many point queries: each edge with its bounding box, so that edges
/// far from the point are passed over. Every query gives, to the bit, what the function of the
/// same name on the bare polygon gives.
#[derive(Clone, Debug)]
pub struct Outline<'a> {
    polygon: &'a [Point],
    edges: Vec<(Point, Point, Aabb)>,
    bounds: Aabb,
}

/// How much farther than a threshold an edge's box must be for the edge to be passed over:
/// the nearest point of an edge is computed in floating point and may stand outside the box by
/// a rounding error, never by this much in a room-sized plan.
const PASS_OVER_M: f64 = 1e-9;

impl<'a> Outline<'a> {
    /// The outline of a polygon.
    pub fn new(polygon: &'a [Point]) -> Outline<'a> {
        let n = polygon.len();
        let edges = (0..n)
            .map(|i| {
                let (a, b) = (polygon[i], polygon[(i + 1) % n]);
                (a, b, Aabb::of(&[a, b]))
            })
            .collect();
        Outline { polygon, edges, bounds: Aabb::of(polygon) }
    }

    /// How far `p` is outside a box along the farther axis (negative inside).
    fn gap(p: Point, b: &Aabb) -> f64 {
        let gx = (b.min[0] - p[0]).max(p[0] - b.max[0]);
        let gz = (b.min[1] - p[1]).max(p[1] - b.max[1]);
        gx.max(gz)
    }

    /// [`point_on_boundary`].
    pub fn on_boundary(&self, p: Point) -> bool {
        self.edges.iter().any(|(a, b, bbox)| {
            Outline::gap(p, bbox) <= EPS_M + PASS_OVER_M && point_on_segment(p, *a, *b)
        })
    }

    /// [`point_in_polygon`].
    pub fn contains(&self, p: Point) -> bool {
        if Outline::gap(p, &self.bounds) > EPS_M + PASS_OVER_M {
            return false;
        }
        !self.on_boundary(p) && point_in_polygon_raw(p, self.polygon)
    }

    /// [`point_in_or_on_polygon`].
    pub fn contains_or_on(&self, p: Point) -> bool {
        if Outline::gap(p, &self.bounds) > EPS_M + PASS_OVER_M {
            return false;
        }
        self.on_boundary(p) || point_in_polygon_raw(p, self.polygon)
    }

    /// The distance from `p` to the nearest edge, or `bound` when that is less (see
    /// [`distance_below`]).
    pub fn distance_below(&self, p: Point, bound: f64) -> f64 {
        let mut nearest = bound;
        for (a, b, bbox) in &self.edges {
            if Outline::gap(p, bbox) >= nearest + PASS_OVER_M {
                continue;
            }
            nearest = distance_below(p, nearest_on_segment(p, *a, *b), nearest);
        }
        nearest
    }
}

impl Outline<'_> {
    /// Whether a point of the row at `z` may be inside or on the outline: when not,
    /// [`OutlineRow::misses_row`] holds for the row, which need not be made.
    pub fn reaches_row(&self, z: f64) -> bool {
        (self.bounds.min[1] - z).max(z - self.bounds.max[1]) <= EPS_M + PASS_OVER_M
    }

    /// The outline seen from the points of one row (every point whose `z` is `z`), for
    /// distances up to `reach`: see [`OutlineRow`].
    pub fn row(&self, z: f64, reach: f64) -> OutlineRow<'_, '_> {
        // How far the row is from a box along z (negative inside its z range).
        let gap_z = |b: &Aabb| (b.min[1] - z).max(z - b.max[1]);
        let touch = EPS_M + PASS_OVER_M;
        let edges = |keep: &dyn Fn(f64) -> bool, t: f64| -> Vec<(usize, [f64; 2])> {
            (0..self.edges.len())
                .filter(|&i| keep(gap_z(&self.edges[i].2)))
                .map(|i| (i, x_window(&self.edges[i].2, t)))
                .collect()
        };
        // The crossings `point_in_polygon_raw` meets on this row, in its order.
        let n = self.polygon.len();
        let mut crossings = Vec::new();
        let mut j = n.wrapping_sub(1);
        for i in 0..n {
            let (a, b) = (self.polygon[i], self.polygon[j]);
            if (a[1] > z) != (b[1] > z) {
                crossings.push((b[0] - a[0]) * (z - a[1]) / (b[1] - a[1]) + a[0]);
            }
            j = i;
        }
        OutlineRow {
            outline: self,
            z,
            in_bounds: self.reaches_row(z),
            touching: edges(&|g| g <= touch, touch),
            crossings,
            reach,
            within_reach: edges(&|g| g < reach + PASS_OVER_M, reach + PASS_OVER_M),
        }
    }
}

/// An [`Outline`] seen from one row of points (the same `z`), for a grid that asks about many
/// points of each row: the edges that can touch the row, the edges within reach of it and
/// where the polygon crosses it are worked out once per row. Each query gives, to the bit, what
/// the outline's own query of the same name gives for a point of the row: the edges left out
/// are those the outline's query would pass over for every point of the row.
pub struct OutlineRow<'o, 'a> {
    outline: &'o Outline<'a>,
    z: f64,
    /// Whether the row passes within [`EPS_M`] (and the pass-over margin) of the bounds.
    in_bounds: bool,
    /// The edges whose boxes the row passes that near, in order, each with its [`x_window`]
    /// for that nearness.
    touching: Vec<(usize, [f64; 2])>,
    /// The x of each edge crossing of the ray test, in its order.
    crossings: Vec<f64>,
    /// The largest bound [`OutlineRow::distance_below`] is asked with.
    reach: f64,
    /// The edges whose boxes are nearer the row than `reach` (and the margin), in order, each
    /// with its [`x_window`] for that nearness.
    within_reach: Vec<(usize, [f64; 2])>,
}

/// The x range `[lo, hi]` outside which a point is farther than `t` from the box along x by
/// more than any rounding error (a relative 1e-12 of the numbers involved): a point of a row
/// outside it is passed over by the tests that ask whether the point is within `t` of the box,
/// with no need to measure.
fn x_window(b: &Aabb, t: f64) -> [f64; 2] {
    let slack = (b.min[0].abs() + b.max[0].abs() + t.abs() + 1.0) * 1e-12;
    [b.min[0] - t - slack, b.max[0] + t + slack]
}

/// Whether `x` is in the window (never for a NaN).
fn in_window(x: f64, [lo, hi]: [f64; 2]) -> bool {
    x >= lo && x <= hi
}

impl OutlineRow<'_, '_> {
    /// [`Outline::on_boundary`].
    fn on_boundary(&self, p: Point) -> bool {
        self.touching.iter().any(|&(i, window)| {
            let (a, b, bbox) = &self.outline.edges[i];
            in_window(p[0], window)
                && Outline::gap(p, bbox) <= EPS_M + PASS_OVER_M
                && point_on_segment(p, *a, *b)
        })
    }

    /// `point_in_polygon_raw` from the row's crossings.
    fn raw_inside(&self, p: Point) -> bool {
        self.crossings.iter().filter(|&&x| p[0] < x).count() % 2 == 1
    }

    /// Whether `p` (a point of the row) is within the outline's bounds by the test of
    /// [`Outline::contains`].
    fn near_bounds(&self, p: Point) -> bool {
        let b = &self.outline.bounds;
        self.in_bounds && (b.min[0] - p[0]).max(p[0] - b.max[0]) <= EPS_M + PASS_OVER_M
    }

    /// [`Outline::contains`] for a point of the row.
    pub fn contains(&self, p: Point) -> bool {
        debug_assert!(p[1].to_bits() == self.z.to_bits(), "a point of another row");
        self.near_bounds(p) && !self.on_boundary(p) && self.raw_inside(p)
    }

    /// [`Outline::contains_or_on`] for a point of the row.
    pub fn contains_or_on(&self, p: Point) -> bool {
        debug_assert!(p[1].to_bits() == self.z.to_bits(), "a point of another row");
        self.near_bounds(p) && (self.on_boundary(p) || self.raw_inside(p))
    }

    /// Whether no point of the row is inside or on the outline (then
    /// [`OutlineRow::contains_or_on`] is false for every one).
    pub fn misses_row(&self) -> bool {
        !self.in_bounds
    }

    /// Whether a point of the row at `x` is farther than `reach` (and the margin) from every
    /// edge along x: then [`OutlineRow::distance_below`] gives back its bound (at most
    /// `reach`), every edge being passed over, without being asked.
    pub fn beyond_reach(&self, x: f64) -> bool {
        self.within_reach.iter().all(|&(_, window)| !in_window(x, window))
    }

    /// [`Outline::distance_below`] for a point of the row.
    pub fn distance_below(&self, p: Point, bound: f64) -> f64 {
        debug_assert!(p[1].to_bits() == self.z.to_bits(), "a point of another row");
        if bound > self.reach {
            return self.outline.distance_below(p, bound);
        }
        // An edge left out is at least `reach` (and the margin) away along z: the outline's
        // query passes over it too, since its nearest distance never exceeds `bound`.
        let mut nearest = bound;
        for &(i, window) in &self.within_reach {
            let (a, b, bbox) = &self.outline.edges[i];
            // Outside the window the gap is at least `reach` (and the margin): passed over.
            if !in_window(p[0], window) || Outline::gap(p, bbox) >= nearest + PASS_OVER_M {
                continue;
            }
            nearest = distance_below(p, nearest_on_segment(p, *a, *b), nearest);
        }
        nearest
    }
}

/// The x coordinates of the points of a grid row, ascending and none a NaN: what the
/// queries of [`OutlineRow`] on a whole row (`…_each`) need to find the points in an edge's
/// x range by halving instead of testing every point.
#[derive(Clone, Copy, Debug)]
pub struct RowXs<'a>(&'a [f64]);

impl<'a> RowXs<'a> {
    /// The row's x coordinates, if they are ascending and none is a NaN.
    pub fn new(xs: &'a [f64]) -> Option<RowXs<'a>> {
        let ascending = xs.windows(2).all(|w| w[0] <= w[1]);
        (ascending && xs.first().is_none_or(|x| !x.is_nan())).then_some(RowXs(xs))
    }

    /// The coordinates.
    pub fn xs(&self) -> &'a [f64] {
        self.0
    }

    /// The indices of the points in the window `[lo, hi]` (`in_window`); a NaN bound leaves
    /// that side open, so the range holds every point the window holds, and then some: callers
    /// test each point of it again.
    pub fn window(&self, [lo, hi]: [f64; 2]) -> std::ops::Range<usize> {
        let xs = self.0;
        let start = if lo.is_nan() { 0 } else { xs.partition_point(|&x| x < lo) };
        let end = if hi.is_nan() { xs.len() } else { xs.partition_point(|&x| x <= hi) };
        start..end.max(start)
    }
}

impl OutlineRow<'_, '_> {
    /// [`OutlineRow::contains`] for every point `(xs[i], z)` of the row, into `inside[i]`
    /// (which must be as long as `xs`): each answer to the bit that of the point's own query,
    /// the work done edge by edge over the points within the edge's x range.
    pub fn contains_each(&self, xs: RowXs<'_>, inside: &mut [bool]) {
        assert_eq!(xs.0.len(), inside.len(), "one answer per point");
        inside.fill(false);
        if !self.in_bounds {
            return;
        }
        // `raw_inside`: an odd number of crossings to the right of the point.
        for &c in &self.crossings {
            let right_of = xs.0.partition_point(|&x| x < c);
            for v in &mut inside[..right_of] {
                *v = !*v;
            }
        }
        // `near_bounds`, then `on_boundary` for the points still inside.
        let b = &self.outline.bounds;
        for (v, &x) in inside.iter_mut().zip(xs.0) {
            *v = *v && (b.min[0] - x).max(x - b.max[0]) <= EPS_M + PASS_OVER_M;
        }
        for &(i, window) in &self.touching {
            let (a, b, bbox) = &self.outline.edges[i];
            for k in xs.window(window) {
                let p = [xs.0[k], self.z];
                if inside[k]
                    && in_window(p[0], window)
                    && Outline::gap(p, bbox) <= EPS_M + PASS_OVER_M
                    && point_on_segment(p, *a, *b)
                {
                    inside[k] = false;
                }
            }
        }
    }

    /// Sets `marks[i]` for every point `(xs[i], z)` of the row for which
    /// [`OutlineRow::contains_or_on`] holds (and leaves the others as they are): only the
    /// points within the outline's x bounds are asked.
    pub fn mark_contains_or_on(&self, xs: RowXs<'_>, marks: &mut [bool]) {
        assert_eq!(xs.0.len(), marks.len(), "one mark per point");
        if !self.in_bounds {
            return;
        }
        for k in xs.window(x_window(&self.outline.bounds, EPS_M + PASS_OVER_M)) {
            if !marks[k] && self.contains_or_on([xs.0[k], self.z]) {
                marks[k] = true;
            }
        }
    }

    /// [`OutlineRow::distance_below`] for every point `(xs[i], z)` of the row, with the bound
    /// `nearest[i]`, into `nearest[i]`: each answer to the bit that of the point's own query.
    /// Each point meets the edges in the order its own query does; the edges are only taken
    /// one at a time over the points within their x range, instead of each point testing
    /// every edge.
    pub fn distance_below_each(&self, xs: RowXs<'_>, nearest: &mut [f64]) {
        assert_eq!(xs.0.len(), nearest.len(), "one bound per point");
        if !nearest.iter().all(|&d| d <= self.reach) {
            // A bound past the row's reach (or a NaN) is the whole outline's question.
            for (d, &x) in nearest.iter_mut().zip(xs.0) {
                *d = self.distance_below([x, self.z], *d);
            }
            return;
        }
        for &(i, window) in &self.within_reach {
            let (a, b, bbox) = &self.outline.edges[i];
            for k in xs.window(window) {
                let p = [xs.0[k], self.z];
                if !in_window(p[0], window) || Outline::gap(p, bbox) >= nearest[k] + PASS_OVER_M {
                    continue;
                }
                nearest[k] = distance_below(p, nearest_on_segment(p, *a, *b), nearest[k]);
            }
        }
    }
}

fn point_in_polygon_raw(p: Point, polygon: &[Point]) -> bool {
    let n = polygon.len();
    let mut inside = false;
    let mut j = n.wrapping_sub(1);
    for i in 0..n {
        let (a, b) = (polygon[i], polygon[j]);
        if (a[1] > p[1]) != (b[1] > p[1]) {
            let x = (b[0] - a[0]) * (p[1] - a[1]) / (b[1] - a[1]) + a[0];
            if p[0] < x {
                inside = !inside;
            }
        }
        j = i;
    }
    inside
}

/// Whether the segment is parallel to an axis (within [`EPS_M`]).
pub fn is_axis_aligned(a: Point, b: Point) -> bool {
    near(a[0], b[0]) || near(a[1], b[1])
}

/// The shared piece of two collinear segments, if it has positive length, in the direction
/// of `a0 → a1`.
pub fn segment_overlap(a0: Point, a1: Point, b0: Point, b1: Point) -> Option<(Point, Point)> {
    let len = distance(a0, a1);
    if len <= EPS_M {
        return None;
    }
    // Both ends of b must lie on the line through a.
    let u = unit(a0, a1);
    let cross = |p: Point| (p[0] - a0[0]) * u[1] - (p[1] - a0[1]) * u[0];
    if cross(b0).abs() > EPS_M || cross(b1).abs() > EPS_M {
        return None;
    }
    let t = |p: Point| (p[0] - a0[0]) * u[0] + (p[1] - a0[1]) * u[1];
    let (tb0, tb1) = (t(b0), t(b1));
    let lo = tb0.min(tb1).max(0.0);
    let hi = tb0.max(tb1).min(len);
    if hi - lo <= EPS_M {
        return None;
    }
    Some((add_scaled(a0, u, lo), add_scaled(a0, u, hi)))
}

/// Whether two segments touch or cross (within [`EPS_M`]).
pub fn segments_touch(a0: Point, a1: Point, b0: Point, b1: Point) -> bool {
    let orient = |p: Point, q: Point, r: Point| {
        let v = (q[0] - p[0]) * (r[1] - p[1]) - (q[1] - p[1]) * (r[0] - p[0]);
        if v.abs() <= EPS_M * EPS_M {
            0
        } else if v > 0.0 {
            1
        } else {
            -1
        }
    };
    let (o1, o2) = (orient(a0, a1, b0), orient(a0, a1, b1));
    let (o3, o4) = (orient(b0, b1, a0), orient(b0, b1, a1));
    if o1 != o2 && o3 != o4 && o1 != 0 && o2 != 0 && o3 != 0 && o4 != 0 {
        return true;
    }
    point_on_segment(b0, a0, a1)
        || point_on_segment(b1, a0, a1)
        || point_on_segment(a0, b0, b1)
        || point_on_segment(a1, b0, b1)
        || (o1 * o2 < 0 && o3 * o4 < 0)
}

/// An axis-aligned box in the floor plane.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Aabb {
    /// Minimum corner.
    pub min: Point,
    /// Maximum corner.
    pub max: Point,
}

impl Aabb {
    /// The box around the points (an empty input gives a degenerate box at the origin).
    pub fn of(points: &[Point]) -> Aabb {
        let mut b = Aabb { min: [f64::INFINITY; 2], max: [f64::NEG_INFINITY; 2] };
        for p in points {
            b.min = [b.min[0].min(p[0]), b.min[1].min(p[1])];
            b.max = [b.max[0].max(p[0]), b.max[1].max(p[1])];
        }
        if points.is_empty() {
            b = Aabb { min: [0.0; 2], max: [0.0; 2] };
        }
        b
    }

    /// Width along x.
    pub fn width(&self) -> f64 {
        self.max[0] - self.min[0]
    }

    /// Depth along z.
    pub fn depth(&self) -> f64 {
        self.max[1] - self.min[1]
    }

    /// Whether the interiors overlap by more than [`EPS_M`] on both axes.
    pub fn overlaps(&self, other: &Aabb) -> bool {
        self.min[0] < other.max[0] - EPS_M
            && other.min[0] < self.max[0] - EPS_M
            && self.min[1] < other.max[1] - EPS_M
            && other.min[1] < self.max[1] - EPS_M
    }
}

/// The area shared by two polygons whose edges are axis-parallel (rectilinear), computed on
/// the grid of their coordinates: exact up to rounding.
///
/// Each cell of the grid counts when its centre is inside both polygons by the even-odd rule
/// of `point_in_polygon_raw`. The centres of one row are tested together: the row's edge
/// crossings are found once and sorted, so the work is the grid's cells plus each row's
/// crossings (about the square of the corners, not its cube: a room of 200 corners beside
/// another is measured in well under a millisecond).
pub fn rectilinear_intersection_area(p: &[Point], q: &[Point]) -> f64 {
    let mut xs: Vec<f64> = p.iter().chain(q).map(|v| v[0]).collect();
    let mut zs: Vec<f64> = p.iter().chain(q).map(|v| v[1]).collect();
    xs.sort_by(f64::total_cmp);
    zs.sort_by(f64::total_cmp);
    xs.dedup_by(|a, b| near(*a, *b));
    zs.dedup_by(|a, b| near(*a, *b));
    if xs.len() < 2 || zs.len() < 2 {
        return 0.0;
    }
    let centres_x: Vec<f64> = xs.windows(2).map(|w| f64::midpoint(w[0], w[1])).collect();
    let (nx, nz) = (centres_x.len(), zs.len() - 1);
    // `both[zi * nx + xi]`: whether the centre of cell (xi, zi) is inside both polygons.
    let mut both = vec![true; nx * nz];
    let mut crossings: Vec<f64> = Vec::new();
    for polygon in [p, q] {
        for (zi, zw) in zs.windows(2).enumerate() {
            let z = f64::midpoint(zw[0], zw[1]);
            row_crossings(polygon, z, &mut crossings);
            // A centre is inside when an odd number of crossings lie strictly east of it
            // (`point_in_polygon_raw` toggles on `x < crossing`).
            let mut at_or_west = 0;
            for (xi, &x) in centres_x.iter().enumerate() {
                while at_or_west < crossings.len() && crossings[at_or_west] <= x {
                    at_or_west += 1;
                }
                if (crossings.len() - at_or_west) % 2 == 0 {
                    both[zi * nx + xi] = false;
                }
            }
        }
    }
    let mut area = 0.0;
    for (xi, xw) in xs.windows(2).enumerate() {
        for (zi, zw) in zs.windows(2).enumerate() {
            if both[zi * nx + xi] {
                area += (xw[1] - xw[0]) * (zw[1] - zw[0]);
            }
        }
    }
    area
}

/// The x of every edge of `polygon` crossing the row `z`, sorted, computed as
/// [`point_in_polygon_raw`] computes them.
fn row_crossings(polygon: &[Point], z: f64, out: &mut Vec<f64>) {
    out.clear();
    let n = polygon.len();
    let mut j = n.wrapping_sub(1);
    for i in 0..n {
        let (a, b) = (polygon[i], polygon[j]);
        if (a[1] > z) != (b[1] > z) {
            out.push((b[0] - a[0]) * (z - a[1]) / (b[1] - a[1]) + a[0]);
        }
        j = i;
    }
    out.sort_by(f64::total_cmp);
}

/// The rectangle of depth `depth` on the side `normal` (a unit vector) of the segment
/// `p1–p2`: `[p1, p2, p2 + depth·n, p1 + depth·n]`.
pub fn box_beside(p1: Point, p2: Point, normal: Point, depth: f64) -> Vec<Point> {
    vec![p1, p2, add_scaled(p2, normal, depth), add_scaled(p1, normal, depth)]
}

/// Rounds to the output precision (1e-6 m or degree) and turns `-0` into `0`.
pub fn round6(v: f64) -> f64 {
    let r = (v * 1e6).round() / 1e6;
    if r == 0.0 {
        0.0
    } else {
        r
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Rectangles, an L, a slanted quadrilateral and a triangle, for points on a grid whose
    /// rows and columns pass on and near their corners and edges.
    fn test_polygons() -> Vec<Vec<Point>> {
        vec![
            vec![[0.0, 0.0], [0.0, 4.0], [5.0, 4.0], [5.0, 0.0]],
            vec![[0.0, 0.0], [0.0, 3.0], [2.0, 3.0], [2.0, 5.0], [6.0, 5.0], [6.0, 0.0]],
            vec![[0.3, 0.1], [1.1, 4.2], [4.7, 3.3], [3.9, -0.4]],
            vec![[0.0, 0.0], [2.5, 4.0], [5.0, 0.0]],
            vec![[1.0, 1.0], [1.0, 1.6], [1.4, 1.6], [1.4, 1.0]],
            // Far from the origin, where a rounding error is larger.
            vec![[1e4, 0.0], [1e4, 4.0], [1e4 + 5.0, 4.0], [1e4 + 5.0, 0.0]],
        ]
    }

    /// The cell-by-cell measure `rectilinear_intersection_area` replaced: each cell's centre
    /// tested against both polygons.
    fn intersection_area_cell_by_cell(p: &[Point], q: &[Point]) -> f64 {
        let mut xs: Vec<f64> = p.iter().chain(q).map(|v| v[0]).collect();
        let mut zs: Vec<f64> = p.iter().chain(q).map(|v| v[1]).collect();
        xs.sort_by(f64::total_cmp);
        zs.sort_by(f64::total_cmp);
        xs.dedup_by(|a, b| near(*a, *b));
        zs.dedup_by(|a, b| near(*a, *b));
        let mut area = 0.0;
        for xw in xs.windows(2) {
            for zw in zs.windows(2) {
                let c = [f64::midpoint(xw[0], xw[1]), f64::midpoint(zw[0], zw[1])];
                if point_in_polygon_raw(c, p) && point_in_polygon_raw(c, q) {
                    area += (xw[1] - xw[0]) * (zw[1] - zw[0]);
                }
            }
        }
        area
    }

    /// A staircase of `steps` steps from (0, 6) down to (6, 1) over a rectangle's corner.
    fn staircase(steps: usize) -> Vec<Point> {
        let (s, t) = (6.0 / steps as f64, 5.0 / steps as f64);
        let mut corners = vec![[0.0, 0.0], [0.0, 6.0]];
        for i in 0..steps {
            corners.push([(i + 1) as f64 * s, 6.0 - i as f64 * t]);
            corners.push([(i + 1) as f64 * s, 6.0 - (i + 1) as f64 * t]);
        }
        corners.push([6.0, 0.0]);
        corners
    }

    /// Issue 50: the row-by-row measure gives the very same figure as testing each cell's
    /// centre (bit for bit: repair's choices depend on it), for rectilinear and slanted
    /// outlines, apart, touching, overlapping and nested.
    #[test]
    fn intersection_area_row_by_row_is_the_cell_by_cell_one() {
        let mut polygons = test_polygons();
        polygons.push(staircase(7));
        polygons.push(staircase(40));
        polygons.push(vec![[0.0, -3.0], [0.0, 0.2], [6.0, 0.2], [6.0, -3.0]]);
        polygons.push(vec![[-1.0, 2.0], [-1.0, 3.0], [3.0, 3.0], [3.0, 2.0]]);
        polygons.push(vec![]);
        for p in &polygons {
            for q in &polygons {
                let (got, want) =
                    (rectilinear_intersection_area(p, q), intersection_area_cell_by_cell(p, q));
                assert_eq!(got.to_bits(), want.to_bits(), "{p:?} {q:?}: {got} {want}");
            }
        }
        assert!(near(rectilinear_intersection_area(&staircase(40), &polygons[8]), 1.2));
    }

    #[test]
    fn outline_rows_answer_as_the_outline() {
        for polygon in &test_polygons() {
            let outline = Outline::new(polygon);
            let x0 = polygon[0][0].floor() - 0.5;
            for step in [0.05, 0.1, 0.5] {
                for j in 0..=((6.0 / step) as usize + 2) {
                    let z = -0.5 + j as f64 * step;
                    for reach in [0.0, 0.3, 0.8] {
                        let row = outline.row(z, reach);
                        for i in 0..=((7.0 / step) as usize + 2) {
                            let p = [x0 + i as f64 * step, z];
                            assert_eq!(row.contains(p), outline.contains(p), "{p:?}");
                            assert_eq!(row.contains_or_on(p), outline.contains_or_on(p));
                            assert!(!row.misses_row() || !outline.contains_or_on(p));
                            assert_eq!(row.misses_row(), !outline.reaches_row(z));
                            if row.beyond_reach(p[0]) {
                                for bound in [reach, reach / 2.0] {
                                    let d = outline.distance_below(p, bound);
                                    assert_eq!(d.to_bits(), bound.to_bits(), "{p:?} {bound}");
                                }
                            }
                            for bound in [reach, reach / 2.0, 1.0] {
                                let (a, b) = (
                                    row.distance_below(p, bound),
                                    outline.distance_below(p, bound),
                                );
                                assert_eq!(a.to_bits(), b.to_bits(), "{p:?} {bound}");
                            }
                        }
                    }
                }
            }
        }
    }

    #[test]
    fn whole_rows_answer_as_their_points() {
        for polygon in &test_polygons() {
            let outline = Outline::new(polygon);
            let x0 = polygon[0][0].floor() - 0.5;
            for step in [0.05, 0.1, 0.5] {
                let xs: Vec<f64> =
                    (0..=((7.0 / step) as usize + 2)).map(|i| x0 + i as f64 * step).collect();
                let row_xs = RowXs::new(&xs).expect("ascending");
                for j in 0..=((6.0 / step) as usize + 2) {
                    let z = -0.5 + j as f64 * step;
                    for reach in [0.0, 0.3, 0.8] {
                        let row = outline.row(z, reach);
                        let mut inside = vec![true; xs.len()];
                        row.contains_each(row_xs, &mut inside);
                        let mut marks: Vec<bool> = (0..xs.len()).map(|i| i % 3 == 0).collect();
                        let before = marks.clone();
                        row.mark_contains_or_on(row_xs, &mut marks);
                        for bound in [reach, reach / 2.0, 1.0] {
                            let mut nearest: Vec<f64> = (0..xs.len())
                                .map(|i| if i % 4 == 1 { bound / 3.0 } else { bound })
                                .collect();
                            let bounds = nearest.clone();
                            row.distance_below_each(row_xs, &mut nearest);
                            for (i, &x) in xs.iter().enumerate() {
                                let d = row.distance_below([x, z], bounds[i]);
                                assert_eq!(nearest[i].to_bits(), d.to_bits(), "{x} {z} {bound}");
                            }
                        }
                        for (i, &x) in xs.iter().enumerate() {
                            let p = [x, z];
                            assert_eq!(inside[i], row.contains(p), "{p:?}");
                            assert_eq!(marks[i], before[i] || row.contains_or_on(p), "{p:?}");
                        }
                    }
                }
            }
        }
        assert!(RowXs::new(&[0.0, f64::NAN]).is_none());
        assert!(RowXs::new(&[f64::NAN]).is_none());
        assert!(RowXs::new(&[1.0, 0.5]).is_none());
        let xs = [0.0, 1.0, 1.0, 2.0];
        let row_xs = RowXs::new(&xs).expect("ascending");
        assert_eq!(row_xs.window([1.0, 1.0]), 1..3);
        assert_eq!(row_xs.window([f64::NAN, 1.5]), 0..3);
        assert_eq!(row_xs.window([0.5, f64::NAN]), 1..4);
        assert_eq!(row_xs.window([3.0, 2.0]), 4..4);
    }

    #[test]
    fn lengths_are_hypots() {
        let values = [
            0.0,
            -0.0,
            1e-300,
            5e-324,
            0.05,
            -0.3,
            0.1 + 0.2,
            4.5,
            -1e4,
            1e300,
            f64::INFINITY,
            f64::NEG_INFINITY,
            f64::NAN,
        ];
        for a in values {
            for b in values {
                let want = a.hypot(b);
                assert!(length(a, b).to_bits() == want.to_bits() || want.is_nan(), "{a} {b}");
                assert_eq!(length(a, b).is_nan(), want.is_nan(), "{a} {b}");
            }
        }
        let mut x = 0.123_456_789_f64;
        for _ in 0..10_000 {
            x = (x * 7.123 + 0.377).fract() * 10.0 - 5.0;
            assert_eq!(length(x, 0.0).to_bits(), x.hypot(0.0).to_bits(), "{x}");
            assert_eq!(length(-0.0, x).to_bits(), (-0.0_f64).hypot(x).to_bits(), "{x}");
        }
    }

    #[test]
    fn clockwise_rectangle_has_negative_area() {
        let r = [[0.0, 0.0], [0.0, 8.0], [5.0, 8.0], [5.0, 0.0]];
        assert!(near(signed_area(&r), -40.0));
        assert!(near_point(area_centroid(&r), [2.5, 4.0]));
        // Inside is on the right of the clockwise west wall.
        assert!(near_point(right_normal(r[0], r[1]), [1.0, 0.0]));
    }

    #[test]
    fn overlap_and_area() {
        let a = [[0.0, 0.0], [0.0, 4.0], [4.0, 4.0], [4.0, 0.0]];
        let b = [[2.0, 2.0], [2.0, 6.0], [6.0, 6.0], [6.0, 2.0]];
        assert!(near(rectilinear_intersection_area(&a, &b), 4.0));
        let s = segment_overlap([4.0, 0.0], [4.0, 4.0], [4.0, 6.0], [4.0, 2.0]);
        assert_eq!(s, Some(([4.0, 2.0], [4.0, 4.0])));
        assert!(point_in_polygon([1.0, 1.0], &a));
        assert!(!point_in_polygon([0.0, 1.0], &a));
    }

    #[test]
    fn quarter_turns_are_exact() {
        assert_eq!(rotate_quarter([0.0, 1.0], 1), [1.0, 0.0]);
        assert_eq!(rotate_quarter([0.0, 1.0], 2), [0.0, -1.0]);
        assert_eq!(rotate_quarter([0.0, 1.0], 3), [-1.0, 0.0]);
    }
}

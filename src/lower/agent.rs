//! Where the agent starts: on free floor of the plan's start room, clear of every wall and
//! footprint by the agent's radius, and reachable from a door of that room.
//!
//! The plan stage picks the room (the one with the first exterior door) before anything stands
//! in it; this runs after the layout, on a 5 cm grid: the free cells are those whose distance to
//! the walls and to every floor footprint is at least the radius plus a margin, outside the
//! doors' keep-out zones; the cells reachable from a door (by a flood through free cells) are
//! the candidates; among them the one with the most room around it (up to 0.8 m) and then the
//! nearest to the room's centre wins. No cell is free: the plan's pose is kept.

use crate::check::scene::RoomId;
use crate::geometry::{self as geo, Aabb, Point};
use crate::plan::{AgentPose, FloorPlan};
use crate::solve::{Layout, Rect};

/// The agent's radius, metres (AI2-THOR's default agent).
pub const AGENT_RADIUS_M: f64 = 0.25;
/// Free floor kept around the agent beyond its radius, metres.
const MARGIN_M: f64 = 0.05;
/// The grid step, metres.
const STEP_M: f64 = 0.05;
/// More clearance than this does not make a start better.
const ENOUGH_CLEARANCE_M: f64 = 0.8;
/// A cell this close to a door's opening is where the agent comes in.
const DOOR_REACH_M: f64 = 0.8;

/// The x range `[lo, hi]` outside which a point is farther than `t` along x from the span
/// `min_x…max_x` by more than any rounding error (a relative 1e-12 of the numbers involved),
/// so that tests of nearness may pass it over without measuring.
fn x_window(min_x: f64, max_x: f64, t: f64) -> [f64; 2] {
    let slack = (min_x.abs() + max_x.abs() + t.abs() + 1.0) * 1e-12;
    [min_x - t - slack, max_x + t + slack]
}

/// Whether `x` is in the window (never for a NaN).
fn in_window(x: f64, [lo, hi]: [f64; 2]) -> bool {
    x >= lo && x <= hi
}

/// The distance from `p` to the rectangle, or `bound` when that is less.
fn distance_to_rect_below(p: Point, r: &Rect, bound: f64) -> f64 {
    let dx = (r.min_x - p[0]).max(0.0).max(p[0] - r.max_x);
    let dz = (r.min_z - p[1]).max(0.0).max(p[1] - r.max_z);
    geo::distance_below([0.0, 0.0], [dx, dz], bound)
}

/// The agent's start on free floor (see the module's description). When the plan's start room
/// has no free cell (furniture fills it), the other rooms are tried in the plan's order; when
/// none has one, the plan's pose is kept.
pub fn agent_start(plan: &FloorPlan, layout: &Layout) -> AgentPose {
    let pose = plan.agent;
    let others = (0..plan.rooms.len()).filter(|&r| r != pose.room.0);
    for r in std::iter::once(pose.room.0).chain(others) {
        if let Some(p) = free_start(plan, layout, RoomId(r)) {
            return AgentPose {
                room: RoomId(r),
                position: [geo::round6(p[0]), geo::round6(p[1])],
                ..pose
            };
        }
    }
    pose
}

/// The best free cell of room `id` reachable from one of its doors, if any.
fn free_start(plan: &FloorPlan, layout: &Layout, id: RoomId) -> Option<Point> {
    let room = plan.rooms.get(id.0)?;
    let poly = &room.polygon;
    if poly.len() < 3 {
        return None;
    }
    let footprints: Vec<Rect> = layout
        .rooms
        .iter()
        .filter(|r| r.room == id)
        .flat_map(|r| r.layout.floor.iter().map(|p| p.footprint))
        .collect();
    let doors: Vec<(Point, Point)> = plan
        .doors
        .iter()
        .filter(|d| d.room0 == room.thor_id || d.room1 == room.thor_id)
        .map(|d| d.segment)
        .collect();
    let bbox = Aabb::of(poly);
    let nx = (bbox.width() / STEP_M).floor() as usize + 1;
    let nz = (bbox.depth() / STEP_M).floor() as usize + 1;
    let point = |i: usize, j: usize| cell_point(&bbox, i, j);
    let need = AGENT_RADIUS_M + MARGIN_M;
    let kept_out: Vec<&[Point]> =
        room.door_keep_out.iter().chain(&room.open_boxes).map(Vec::as_slice).collect();
    let clearance = clearances(poly, &kept_out, &footprints, &bbox, nx, nz);
    let free = |c: usize| clearance[c] >= need;
    // Flood from the free cells next to a door; without a door, every free cell counts.
    let mut reached = vec![false; nx * nz];
    // A first-in first-out queue of cells `(i, j)`: they are taken from `queue[head]` on.
    // (Each cell is pushed at most once.)
    let mut queue: Vec<(usize, usize)> = Vec::with_capacity(nx * nz);
    let door_reach = DOOR_REACH_M + need;
    for j in 0..nz {
        // A door whose z range is farther from the row than the reach (the nearest point of a
        // door is within its z range but for rounding) reaches no cell of it.
        let z = point(0, j)[1];
        // Each with the x range beyond which no cell of the row is within reach of it.
        let near: Vec<(&(Point, Point), [f64; 2])> = doors
            .iter()
            .filter(|(a, b)| (a[1].min(b[1]) - z).max(z - a[1].max(b[1])) <= door_reach + 1e-9)
            .map(|d| (d, x_window(d.0[0].min(d.1[0]), d.0[0].max(d.1[0]), door_reach)))
            .collect();
        if near.is_empty() {
            continue;
        }
        for i in 0..nx {
            let c = j * nx + i;
            let p = point(i, j);
            if free(c)
                && near.iter().any(|&(&(a, b), window)| {
                    in_window(p[0], window)
                        && geo::within(p, geo::nearest_on_segment(p, a, b), door_reach)
                })
            {
                reached[c] = true;
                queue.push((i, j));
            }
        }
    }
    if queue.is_empty() {
        for (c, r) in reached.iter_mut().enumerate() {
            *r = free(c);
        }
    }
    let mut head = 0;
    while let Some(&(i, j)) = queue.get(head) {
        head += 1;
        let mut visit = |i: usize, j: usize| {
            let n = j * nx + i;
            if !reached[n] && free(n) {
                reached[n] = true;
                queue.push((i, j));
            }
        };
        if i > 0 {
            visit(i - 1, j);
        }
        if i + 1 < nx {
            visit(i + 1, j);
        }
        if j > 0 {
            visit(i, j - 1);
        }
        if j + 1 < nz {
            visit(i, j + 1);
        }
    }
    let mut best: Option<(f64, f64, Point)> = None;
    let cells = (0..nz).flat_map(|j| (0..nx).map(move |i| (i, j)));
    for (i, j) in cells.filter(|&(i, j)| reached[j * nx + i]) {
        let (c, p) = (j * nx + i, point(i, j));
        let room_around = clearance[c].min(ENOUGH_CLEARANCE_M);
        match best {
            Some((r, _, _)) if room_around > r + 1e-9 => {
                best = Some((room_around, geo::distance(p, room.centroid), p));
            }
            Some((r, d, _)) => {
                // As much room: better only nearer the centre (by more than 1e-9).
                if (room_around - r).abs() <= 1e-9 {
                    let to_centre = geo::distance_below(p, room.centroid, d - 1e-9);
                    if to_centre < d - 1e-9 {
                        best = Some((room_around, to_centre, p));
                    }
                }
            }
            None => best = Some((room_around, geo::distance(p, room.centroid), p)),
        }
    }
    best.map(|(_, _, p)| p)
}

/// Each cell's clearance, row by row (`clearance[j * nx + i]`): the distance from the cell's
/// centre to the nearest wall of `polygon` or footprint, counted up to `ENOUGH_CLEARANCE_M`,
/// or minus infinity for a cell outside the room or in a `kept_out` box (a door's keep-out
/// box or an open connection's).
///
/// Each row asks the walls and boxes about all its cells at once (`geo::OutlineRow`'s `…_each`
/// queries), and each wall, box and footprint measures only the cells within its x range, in
/// the order a cell-by-cell search would meet them: every value is, to the bit, that search's
/// (`tests::cell_by_cell`, which the tests hold this to).
fn clearances(
    polygon: &[Point],
    kept_out: &[&[Point]],
    footprints: &[Rect],
    bbox: &Aabb,
    nx: usize,
    nz: usize,
) -> Vec<f64> {
    let mut clearance = vec![f64::NEG_INFINITY; nx * nz];
    let xs: Vec<f64> = (0..nx).map(|i| cell_point(bbox, i, 0)[0]).collect();
    let Some(row_xs) = geo::RowXs::new(&xs) else {
        return cells_one_by_one(polygon, kept_out, footprints, bbox, nx, nz);
    };
    let outline = geo::Outline::new(polygon);
    let kept_out: Vec<geo::Outline<'_>> = kept_out.iter().map(|b| geo::Outline::new(b)).collect();
    let mut inside = vec![false; nx];
    let mut blocked = vec![false; nx];
    let mut nearest = vec![ENOUGH_CLEARANCE_M; nx];
    for (j, row) in clearance.chunks_exact_mut(nx).enumerate() {
        let z = cell_point(bbox, 0, j)[1];
        let walls = outline.row(z, ENOUGH_CLEARANCE_M);
        walls.contains_each(row_xs, &mut inside);
        blocked.fill(false);
        for b in kept_out.iter().filter(|b| b.reaches_row(z)) {
            b.row(z, 0.0).mark_contains_or_on(row_xs, &mut blocked);
        }
        nearest.fill(ENOUGH_CLEARANCE_M);
        walls.distance_below_each(row_xs, &mut nearest);
        // A footprint farther than `ENOUGH_CLEARANCE_M` from the row, or from a cell along x,
        // cannot lower a clearance counted no further than that.
        let near = footprints
            .iter()
            .filter(|r| (r.min_z - z).max(0.0).max(z - r.max_z) < ENOUGH_CLEARANCE_M);
        for r in near {
            let window = x_window(r.min_x, r.max_x, ENOUGH_CLEARANCE_M);
            for i in row_xs.window(window) {
                let p = [xs[i], z];
                if in_window(p[0], window) {
                    nearest[i] = distance_to_rect_below(p, r, nearest[i]);
                }
            }
        }
        for (i, c) in row.iter_mut().enumerate() {
            if inside[i] && !blocked[i] {
                *c = nearest[i];
            }
        }
    }
    clearance
}

/// The centre of cell `(i, j)` of the grid over `bbox`.
fn cell_point(bbox: &Aabb, i: usize, j: usize) -> Point {
    [bbox.min[0] + (i as f64 + 0.5) * STEP_M, bbox.min[1] + (j as f64 + 0.5) * STEP_M]
}

/// [`clearances`] measured cell by cell: what a grid whose x coordinates are not in order
/// (a room with a NaN coordinate) gets, and what the tests hold the row-wise search to.
fn cells_one_by_one(
    polygon: &[Point],
    kept_out: &[&[Point]],
    footprints: &[Rect],
    bbox: &Aabb,
    nx: usize,
    nz: usize,
) -> Vec<f64> {
    let outline = geo::Outline::new(polygon);
    let kept_out: Vec<geo::Outline<'_>> = kept_out.iter().map(|b| geo::Outline::new(b)).collect();
    let mut clearance = vec![f64::NEG_INFINITY; nx * nz];
    for j in 0..nz {
        let z = cell_point(bbox, 0, j)[1];
        let walls = outline.row(z, ENOUGH_CLEARANCE_M);
        let boxes: Vec<_> =
            kept_out.iter().map(|b| b.row(z, 0.0)).filter(|b| !b.misses_row()).collect();
        let near: Vec<(&Rect, [f64; 2])> = footprints
            .iter()
            .filter(|r| (r.min_z - z).max(0.0).max(z - r.max_z) < ENOUGH_CLEARANCE_M)
            .map(|r| (r, x_window(r.min_x, r.max_x, ENOUGH_CLEARANCE_M)))
            .collect();
        for i in 0..nx {
            let p = cell_point(bbox, i, j);
            if !walls.contains(p) || boxes.iter().any(|b| b.contains_or_on(p)) {
                continue;
            }
            let mut nearest = if walls.beyond_reach(p[0]) {
                ENOUGH_CLEARANCE_M
            } else {
                walls.distance_below(p, ENOUGH_CLEARANCE_M)
            };
            for (r, window) in &near {
                if in_window(p[0], *window) {
                    nearest = distance_to_rect_below(p, r, nearest);
                }
            }
            clearance[j * nx + i] = nearest;
        }
    }
    clearance
}

#[cfg(test)]
mod tests {
    use super::*;
    use proptest::prelude::*;

    /// The row-wise clearances and the cell-by-cell ones, to the bit.
    fn assert_same(polygon: &[Point], kept_out: &[&[Point]], footprints: &[Rect]) {
        let bbox = Aabb::of(polygon);
        let nx = (bbox.width() / STEP_M).floor() as usize + 1;
        let nz = (bbox.depth() / STEP_M).floor() as usize + 1;
        let fast = clearances(polygon, kept_out, footprints, &bbox, nx, nz);
        let slow = cells_one_by_one(polygon, kept_out, footprints, &bbox, nx, nz);
        assert_eq!(fast.len(), slow.len());
        for (c, (a, b)) in fast.iter().zip(&slow).enumerate() {
            assert_eq!(a.to_bits(), b.to_bits(), "cell {} of row {}", c % nx, c / nx);
        }
    }

    fn rect(x: f64, z: f64, w: f64, d: f64) -> Rect {
        Rect { min_x: x, min_z: z, max_x: x + w, max_z: z + d }
    }

    fn corners(r: &Rect) -> Vec<Point> {
        vec![[r.min_x, r.min_z], [r.min_x, r.max_z], [r.max_x, r.max_z], [r.max_x, r.min_z]]
    }

    #[test]
    fn rooms_of_every_shape_measure_as_cell_by_cell() {
        let rooms: Vec<Vec<Point>> = vec![
            vec![[0.0, 0.0], [0.0, 4.0], [5.0, 4.0], [5.0, 0.0]],
            vec![[0.0, 0.0], [0.0, 3.0], [2.0, 3.0], [2.0, 5.0], [6.0, 5.0], [6.0, 0.0]],
            vec![[0.3, 0.1], [1.1, 4.2], [4.7, 3.3], [3.9, -0.4]],
            vec![[0.0, 0.0], [2.5, 4.0], [5.0, 0.0]],
            // Corners on the cells' centres, and a room far from the origin.
            vec![[0.025, 0.025], [0.025, 2.525], [3.075, 2.525], [3.075, 0.025]],
            vec![[1e4, -7.0], [1e4, -3.0], [1e4 + 5.0, -3.0], [1e4 + 5.0, -7.0]],
        ];
        let furniture =
            [rect(1.0, 1.0, 1.2, 0.6), rect(0.0, 2.0, 0.5, 2.0), rect(2.4, 0.05, 2.0, 1.0)];
        let door = corners(&rect(0.0, 1.0, 1.0, 1.0));
        let open = corners(&rect(4.0, 3.5, 1.0, 0.5));
        for polygon in &rooms {
            assert_same(polygon, &[], &[]);
            let shift = Aabb::of(polygon).min;
            let moved: Vec<Rect> = furniture
                .iter()
                .map(|r| {
                    rect(
                        r.min_x + shift[0],
                        r.min_z + shift[1],
                        r.max_x - r.min_x,
                        r.max_z - r.min_z,
                    )
                })
                .collect();
            assert_same(polygon, &[&door, &open], &moved);
        }
    }

    proptest! {
        #![proptest_config(ProptestConfig::with_cases(64))]

        /// Random rooms (an L or a rectangle, at a random place), keep-out boxes and
        /// footprints: the row-wise search gives every cell the value the cell-by-cell one does.
        #[test]
        fn random_rooms_measure_as_cell_by_cell(
            x0 in -20.0f64..20.0,
            z0 in -20.0f64..20.0,
            w in 0.4f64..7.0,
            d in 0.4f64..7.0,
            notch in proptest::option::of((0.1f64..0.9, 0.1f64..0.9)),
            boxes in proptest::collection::vec((0.0f64..1.0, 0.0f64..1.0, 0.1f64..1.5, 0.1f64..1.5), 0..3),
            things in proptest::collection::vec((0.0f64..1.0, 0.0f64..1.0, 0.05f64..2.5, 0.05f64..2.5), 0..8),
        ) {
            let polygon = match notch {
                None => vec![[x0, z0], [x0, z0 + d], [x0 + w, z0 + d], [x0 + w, z0]],
                Some((a, b)) => vec![
                    [x0, z0],
                    [x0, z0 + d * b],
                    [x0 + w * a, z0 + d * b],
                    [x0 + w * a, z0 + d],
                    [x0 + w, z0 + d],
                    [x0 + w, z0],
                ],
            };
            let at = |(u, v, bw, bd): (f64, f64, f64, f64)| rect(x0 + u * w, z0 + v * d, bw, bd);
            let boxes: Vec<Vec<Point>> = boxes.into_iter().map(|b| corners(&at(b))).collect();
            let kept_out: Vec<&[Point]> = boxes.iter().map(Vec::as_slice).collect();
            let footprints: Vec<Rect> = things.into_iter().map(at).collect();
            assert_same(&polygon, &kept_out, &footprints);
        }
    }
}

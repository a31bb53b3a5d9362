//! Geometric repair of a floor plan: the smallest corner movements that turn a plan the plan
//! stage rejects (rooms that overlap by a little, leave thin gaps, have slanted or doubled
//! edges, or float apart) into one it accepts, before any model is asked again.
//!
//! The repair works on the rooms' corners only and in this order:
//!
//! 1. **Outline clean-up**: repeated corners and corners in the middle of a straight wall are
//!    dropped; an edge that is slanted by at most the movement bound is made straight by
//!    moving its second corner.
//! 2. **Shared walls**: wall coordinates of *different* rooms that face each other across a
//!    gap or an overlap of at most the bound (and whose rooms lie side by side along the wall)
//!    are made one: every room moves to the coordinate of the room declared first, so the
//!    overlap goes to the later room and a gap is closed by the later room. Two walls of one
//!    room are never merged.
//! 3. **Detached rooms**: a room that still touches no other room (and is not alone), or that
//!    does not touch a room declared before it that it has a door to, is moved, whole, onto
//!    the nearest such room (for a room touching nothing and without doors, the nearest room),
//!    when that is at most [`MAX_TRANSLATION_M`] away.
//!
//! A repair is kept only when every room's area changes by at most [`MAX_AREA_CHANGE`] and the
//! plan stage finds fewer errors in the repaired plan than in the plan as written; otherwise the
//! plan is returned as written. Doors and windows are never touched, so a room's connections
//! stay what was declared. A plan that the plan stage already accepts is returned unchanged
//! (repair is idempotent), and what the repair cannot fix within its bounds is left for the
//! plan stage to report.

use std::collections::BTreeMap;

use crate::check::scene::{DoorSide, Scene};
use crate::diag::{Code, Diagnostic, Fix, Outcome};
use crate::resolve::structure::StructureCatalog;

/// The most a corner moves to close a gap, remove an overlap or straighten an edge, metres.
pub const MAX_MOVE_M: f64 = 0.5;
/// The most a detached room is moved, whole, to meet its neighbour, metres.
pub const MAX_TRANSLATION_M: f64 = 1.0;
/// The most a room's floor area changes in a repair, as a share of its area as written.
pub const MAX_AREA_CHANGE: f64 = 0.4;
/// Coordinates closer than this are the same, metres.
const SAME_M: f64 = 1e-6;

/// The repaired outlines, one per room of the scene, and whether anything moved.
#[derive(Clone, Debug, PartialEq)]
pub struct Repair {
    /// Per room, in scene order: the corners after repair, metres.
    pub corners: Vec<Vec<[f64; 2]>>,
    /// Whether any corner moved.
    pub changed: bool,
    /// The largest distance any corner moved, metres.
    pub max_move_m: f64,
    /// The largest distance any wall moved (a corner's larger change of x or z), metres: the
    /// figure the bounds limit.
    pub max_wall_move_m: f64,
}

/// Repairs the scene's floor plan (see the module documentation). Each room that changed gets
/// one warning W0307 listing its moves, with a fix per corner that rewrites it.
pub fn repair(scene: &Scene, catalog: &StructureCatalog) -> Outcome<Repair> {
    let original: Vec<Vec<[f64; 2]>> = scene.rooms.iter().map(|r| r.corners.clone()).collect();
    let unchanged =
        Repair { corners: original.clone(), changed: false, max_move_m: 0.0, max_wall_move_m: 0.0 };
    let errors_as_written =
        if scene.rooms.is_empty() { 0 } else { plan_error_count(scene, catalog) };
    if errors_as_written == 0 {
        return Outcome::new(unchanged, Vec::new());
    }
    let mut rooms = original.clone();
    // For each repaired corner, the index of the corner as written it comes from.
    let mut origins: Vec<Vec<usize>> = rooms.iter().map(|c| (0..c.len()).collect()).collect();
    for (corners, origin) in rooms.iter_mut().zip(&mut origins) {
        clean_outline(corners, origin);
    }
    share_walls(&mut rooms, 0);
    share_walls(&mut rooms, 1);
    for (corners, origin) in rooms.iter_mut().zip(&mut origins) {
        clean_outline(corners, origin);
    }
    attach_detached(scene, &mut rooms);
    // Within the area bound, and better than before: otherwise the plan stays as written and
    // the plan stage reports it.
    let within_area = original.iter().zip(&rooms).all(|(before, after)| {
        let a0 = area(before);
        a0 <= 0.0 || (area(after) - a0).abs() / a0 <= MAX_AREA_CHANGE
    });
    let mut repaired = scene.clone();
    for (room, corners) in repaired.rooms.iter_mut().zip(&rooms) {
        room.corners.clone_from(corners);
    }
    if !within_area || plan_error_count(&repaired, catalog) >= errors_as_written {
        return Outcome::new(unchanged, Vec::new());
    }

    let mut diagnostics = Vec::new();
    let mut max_move: f64 = 0.0;
    let mut max_wall_move: f64 = 0.0;
    let mut changed = false;
    for (i, room) in scene.rooms.iter().enumerate() {
        if same_outline(&original[i], &rooms[i]) {
            continue;
        }
        changed = true;
        let moves = describe_moves(&original[i], &rooms[i], &origins[i]);
        max_move = max_move.max(moves.iter().map(|m| m.distance()).fold(0.0, f64::max));
        for change in &moves {
            if let CornerChange::Moved { from, to, .. } = change {
                max_wall_move =
                    max_wall_move.max((to[0] - from[0]).abs().max((to[1] - from[1]).abs()));
            }
        }
        let mut d = Diagnostic::new(
            Code::W0307,
            format!(
                "the outline of room `{}` was repaired: {}",
                room.name,
                summary(&original[i], &rooms[i], &moves)
            ),
        )
        .with_primary(room.name_span, "its corners were moved to fit the other rooms")
        .with_help("review the new corners; `holoc repair --write` writes them into the file");
        for change in &moves {
            d = d.with_note(match *change {
                CornerChange::Moved { from, to, distance } => format!(
                    "({}, {}) → ({}, {}): {distance:.2} m",
                    num(from[0]),
                    num(from[1]),
                    num(to[0]),
                    num(to[1]),
                ),
                CornerChange::Dropped { at, distance } if distance <= SAME_M => format!(
                    "({}, {}) dropped: it repeats a corner or lies on a straight wall",
                    num(at[0]),
                    num(at[1])
                ),
                CornerChange::Dropped { at, distance } => format!(
                    "({}, {}) dropped: the straightened wall passes {distance:.2} m from it",
                    num(at[0]),
                    num(at[1])
                ),
            });
        }
        if let (Some(first), Some(last)) = (room.corner_spans.first(), room.corner_spans.last()) {
            // `corners in cm (…)` becomes `corners in m (…)`; `corners (x m, z m)` keeps units
            // on every number.
            let (start, replacement) = match room.corners_unit_span {
                Some(unit) => (
                    unit.start,
                    format!(
                        "m {}",
                        rooms[i]
                            .iter()
                            .map(|p| format!("({}, {})", num(p[0]), num(p[1])))
                            .collect::<Vec<_>>()
                            .join(" ")
                    ),
                ),
                None => (
                    first.start,
                    rooms[i]
                        .iter()
                        .map(|p| format!("({} m, {} m)", num(p[0]), num(p[1])))
                        .collect::<Vec<_>>()
                        .join(" "),
                ),
            };
            d = d.with_fix(Fix {
                title: format!("write the repaired corners of `{}`", room.name),
                span: crate::source::Span { file: first.file, start, end: last.end },
                replacement,
            });
        }
        diagnostics.push(d);
    }
    Outcome::new(
        Repair { corners: rooms, changed, max_move_m: max_move, max_wall_move_m: max_wall_move },
        diagnostics,
    )
}

/// The scene with repaired outlines (corner spans kept where a corner survived).
pub fn apply(scene: &Scene, repair: &Repair) -> Scene {
    let mut out = scene.clone();
    for (room, corners) in out.rooms.iter_mut().zip(&repair.corners) {
        if !same_outline(&room.corners, corners) {
            let span = room.corner_spans.first().copied().unwrap_or_default();
            room.corner_spans = vec![span; corners.len()];
            room.corners.clone_from(corners);
        }
    }
    out
}

/// The plan stage's errors that geometry can cause (not a missing exterior door or an unknown
/// asset).
fn plan_error_count(scene: &Scene, catalog: &StructureCatalog) -> usize {
    let options = super::PlanOptions { geometry_only: true, ..super::PlanOptions::default() };
    super::plan_with(scene, catalog, options)
        .diagnostics
        .iter()
        .filter(|d| {
            d.is_error() && !matches!(d.code, Code::E0314 | Code::E0315 | Code::E0313 | Code::E0319)
        })
        .count()
}

/// A number as a plan writes it: metres, at most three decimals, no trailing zeros.
fn num(v: f64) -> String {
    let r = (v * 1000.0).round() / 1000.0;
    let r = if r == 0.0 { 0.0 } else { r };
    let mut s = format!("{r:.3}");
    while s.ends_with('0') {
        s.pop();
    }
    if s.ends_with('.') {
        s.pop();
    }
    s
}

fn same_outline(a: &[[f64; 2]], b: &[[f64; 2]]) -> bool {
    a.len() == b.len()
        && a.iter()
            .zip(b)
            .all(|(p, q)| (p[0] - q[0]).abs() < SAME_M && (p[1] - q[1]).abs() < SAME_M)
}

/// Drops repeated corners and corners in the middle of a straight wall, and straightens
/// edges slanted by at most [`MAX_MOVE_M`]. `origin` holds, for each corner, the index of the
/// corner as written it comes from; it is kept in step.
fn clean_outline(corners: &mut Vec<[f64; 2]>, origin: &mut Vec<usize>) {
    let same =
        |p: [f64; 2], q: [f64; 2]| (p[0] - q[0]).abs() <= SAME_M && (p[1] - q[1]).abs() <= SAME_M;
    let mut pts: Vec<([f64; 2], usize)> = Vec::with_capacity(corners.len());
    for (p, o) in corners.iter().zip(origin.iter()) {
        if pts.last().is_none_or(|q| !same(q.0, *p)) {
            pts.push((*p, *o));
        }
    }
    while pts.len() > 1 && same(pts[0].0, pts[pts.len() - 1].0) {
        pts.pop();
    }
    // Straighten slightly slanted edges: the second corner takes the first's coordinate on
    // the axis where they differ least.
    let n = pts.len();
    if n >= 3 {
        for i in 0..n {
            let a = pts[i].0;
            let j = (i + 1) % n;
            let b = pts[j].0;
            let (dx, dz) = ((b[0] - a[0]).abs(), (b[1] - a[1]).abs());
            if dx > SAME_M && dz > SAME_M && dx.min(dz) <= MAX_MOVE_M {
                if dx <= dz {
                    pts[j].0[0] = a[0];
                } else {
                    pts[j].0[1] = a[1];
                }
            }
        }
    }
    // Drop corners on a straight line between their neighbours.
    let mut changed = true;
    while changed && pts.len() > 3 {
        changed = false;
        let n = pts.len();
        for i in 0..n {
            let (p, c, q) = (pts[(i + n - 1) % n].0, pts[i].0, pts[(i + 1) % n].0);
            let same_x = (p[0] - c[0]).abs() <= SAME_M && (c[0] - q[0]).abs() <= SAME_M;
            let same_z = (p[1] - c[1]).abs() <= SAME_M && (c[1] - q[1]).abs() <= SAME_M;
            if same_x || same_z || same(c, q) {
                pts.remove(i);
                changed = true;
                break;
            }
        }
    }
    *corners = pts.iter().map(|p| p.0).collect();
    *origin = pts.iter().map(|p| p.1).collect();
}

/// The extent of a room along an axis (0: x, 1: z).
fn extent(corners: &[[f64; 2]], axis: usize) -> (f64, f64) {
    corners
        .iter()
        .fold((f64::INFINITY, f64::NEG_INFINITY), |(lo, hi), p| (lo.min(p[axis]), hi.max(p[axis])))
}

/// Makes facing walls of different rooms one, along `axis` (0: walls of constant x, 1: of
/// constant z). See the module documentation.
fn share_walls(rooms: &mut [Vec<[f64; 2]>], axis: usize) {
    let other = 1 - axis;
    // Every distinct coordinate of every room on this axis.
    let mut values: Vec<(f64, usize)> = Vec::new();
    for (r, corners) in rooms.iter().enumerate() {
        let mut vs: Vec<f64> = corners.iter().map(|p| p[axis]).collect();
        vs.sort_by(f64::total_cmp);
        vs.dedup_by(|a, b| (*a - *b).abs() <= SAME_M);
        values.extend(vs.into_iter().map(|v| (v, r)));
    }
    let n = values.len();
    let mut parent: Vec<usize> = (0..n).collect();
    // Candidate pairs: a wall of one room and a wall of another that face each other (their
    // outward sides point at each other), overlap along the other axis, and lie at most the
    // bound apart across a gap or an overlap with no third room's floor between them.
    let walls: Vec<Vec<Wall>> = rooms.iter().map(|c| walls_of(c, axis)).collect();
    let index_of = |v: f64, r: usize| {
        values.iter().position(|&(w, room)| room == r && (w - v).abs() <= SAME_M)
    };
    let mut pairs: Vec<(f64, usize, usize)> = Vec::new();
    for (ra, wa) in walls.iter().enumerate() {
        for (rb, wb) in walls.iter().enumerate() {
            if ra == rb {
                continue;
            }
            for a in wa.iter().filter(|w| w.outward > 0.0) {
                for b in wb.iter().filter(|w| w.outward < 0.0) {
                    let d = (a.at - b.at).abs();
                    let (lo, hi) = (a.from.max(b.from), a.to.min(b.to));
                    // Walls already shared (d = 0) pair too, so that they move together.
                    if d > MAX_MOVE_M + SAME_M || hi - lo <= 0.01 {
                        continue;
                    }
                    let mut mid = [0.0; 2];
                    mid[axis] = f64::midpoint(a.at, b.at);
                    mid[other] = f64::midpoint(lo, hi);
                    let between =
                        rooms.iter().enumerate().any(|(r, c)| r != ra && r != rb && inside(mid, c));
                    if between {
                        continue;
                    }
                    if let (Some(i), Some(j)) = (index_of(a.at, ra), index_of(b.at, rb)) {
                        pairs.push((d, i.min(j), i.max(j)));
                    }
                }
            }
        }
    }
    pairs.sort_by(|x, y| x.0.total_cmp(&y.0).then(x.1.cmp(&y.1)).then(x.2.cmp(&y.2)));
    pairs.dedup();
    // Closest pairs first, so that a wall joins its nearest neighbour's.
    pairs.sort_by(|x, y| x.0.total_cmp(&y.0).then(x.1.cmp(&y.1)).then(x.2.cmp(&y.2)));
    let mut members: Vec<Vec<usize>> = (0..n).map(|i| vec![i]).collect();
    for (_, a, b) in pairs {
        let (ra, rb) = (super::build::find(&mut parent, a), super::build::find(&mut parent, b));
        if ra == rb {
            continue;
        }
        // Never two different coordinates of one room in one group, and never a group wider
        // than the bound.
        let joined: Vec<usize> = members[ra].iter().chain(&members[rb]).copied().collect();
        let same_room_twice = joined.iter().any(|&i| {
            joined.iter().any(|&j| {
                i != j && values[i].1 == values[j].1 && (values[i].0 - values[j].0).abs() > SAME_M
            })
        });
        let (lo, hi) = joined.iter().fold((f64::INFINITY, f64::NEG_INFINITY), |(lo, hi), &i| {
            (lo.min(values[i].0), hi.max(values[i].0))
        });
        if same_room_twice || hi - lo > MAX_MOVE_M + SAME_M {
            continue;
        }
        parent[rb] = ra;
        let moved = std::mem::take(&mut members[rb]);
        members[ra].extend(moved);
    }
    // Each group meets at the coordinate that moves the least length of wall (ties: the
    // coordinate of the room declared first).
    let wall_length = |i: usize| -> f64 {
        let (v, r) = values[i];
        walls[r].iter().filter(|w| (w.at - v).abs() <= SAME_M).map(|w| w.to - w.from).sum()
    };
    let mut target: BTreeMap<(usize, u64), f64> = BTreeMap::new();
    for i in 0..n {
        let root = super::build::find(&mut parent, i);
        let group = &members[root];
        if group.len() < 2 {
            continue;
        }
        let cost = |value: f64| -> f64 {
            group.iter().map(|&j| (values[j].0 - value).abs() * wall_length(j)).sum()
        };
        let keep = group
            .iter()
            .map(|&j| (cost(values[j].0), values[j].1, j))
            .min_by(|a, b| {
                // Costs within a square millimetre of wall are equal.
                let (ca, cb) = ((a.0 * 1e6).round(), (b.0 * 1e6).round());
                ca.total_cmp(&cb).then(a.1.cmp(&b.1)).then(a.2.cmp(&b.2))
            })
            .map(|(_, _, j)| values[j].0);
        if let Some(keep) = keep {
            target.insert((values[i].1, values[i].0.to_bits()), keep);
        }
    }
    for (r, corners) in rooms.iter_mut().enumerate() {
        for p in corners.iter_mut() {
            if let Some(v) = target.get(&(r, p[axis].to_bits())) {
                p[axis] = *v;
            } else {
                // The coordinate may differ by rounding from the one recorded.
                if let Some((_, v)) = target.iter().find(|((room, bits), _)| {
                    *room == r && (f64::from_bits(*bits) - p[axis]).abs() <= SAME_M
                }) {
                    p[axis] = *v;
                }
            }
        }
    }
}

/// One straight wall of a room on an axis: at `at` (its constant coordinate), from `from` to
/// `to` along the other axis, and which way its outside points along the axis (+1 or -1).
#[derive(Clone, Copy, Debug)]
struct Wall {
    at: f64,
    from: f64,
    to: f64,
    outward: f64,
}

/// The walls of an outline that run along `axis`'s constant coordinate (0: walls of constant
/// x), with their outward direction from the outline's winding.
fn walls_of(corners: &[[f64; 2]], axis: usize) -> Vec<Wall> {
    let other = 1 - axis;
    let n = corners.len();
    let signed: f64 = (0..n)
        .map(|i| {
            let (a, b) = (corners[i], corners[(i + 1) % n]);
            a[0] * b[1] - b[0] * a[1]
        })
        .sum();
    let mut out = Vec::new();
    for i in 0..n {
        let (a, b) = (corners[i], corners[(i + 1) % n]);
        if (a[axis] - b[axis]).abs() > SAME_M || (a[other] - b[other]).abs() <= SAME_M {
            continue;
        }
        // For a counter-clockwise outline (positive signed area in x, z), the outside of an
        // edge running along +z lies towards +x; along +x it lies towards -z.
        let along = (b[other] - a[other]).signum();
        let ccw = if signed >= 0.0 { 1.0 } else { -1.0 };
        let outward = if axis == 0 { along * ccw } else { -along * ccw };
        out.push(Wall {
            at: a[axis],
            from: a[other].min(b[other]),
            to: a[other].max(b[other]),
            outward,
        });
    }
    out
}

/// Whether a point lies strictly inside an outline (even-odd rule).
fn inside(p: [f64; 2], corners: &[[f64; 2]]) -> bool {
    let n = corners.len();
    let mut inside = false;
    for i in 0..n {
        let (a, b) = (corners[i], corners[(i + 1) % n]);
        if (a[1] > p[1]) != (b[1] > p[1]) {
            let x = a[0] + (p[1] - a[1]) / (b[1] - a[1]) * (b[0] - a[0]);
            if p[0] < x {
                inside = !inside;
            }
        }
    }
    inside
}

/// The gap between two rooms' bounding boxes along each axis (negative: overlap).
fn box_gap(a: &[[f64; 2]], b: &[[f64; 2]]) -> [f64; 2] {
    let mut out = [0.0; 2];
    for (axis, slot) in out.iter_mut().enumerate() {
        let (la, ha) = extent(a, axis);
        let (lb, hb) = extent(b, axis);
        *slot = (lb - ha).max(la - hb);
    }
    out
}

/// Whether two rooms share a stretch of wall (longer than a centimetre).
fn touch(a: &[[f64; 2]], b: &[[f64; 2]]) -> bool {
    let g = box_gap(a, b);
    (g[0].abs() <= SAME_M && g[1] < -0.01) || (g[1].abs() <= SAME_M && g[0] < -0.01)
}

/// Moves rooms that touch no other room onto their nearest neighbour.
fn attach_detached(scene: &Scene, rooms: &mut [Vec<[f64; 2]>]) {
    if rooms.len() < 2 {
        return;
    }
    for r in 0..rooms.len() {
        let linked: Vec<usize> = scene
            .doors
            .iter()
            .filter_map(|d| match (&d.from, &d.to) {
                (DoorSide::Room(a), DoorSide::Room(b)) if a.0 == r => Some(b.0),
                (DoorSide::Room(a), DoorSide::Room(b)) if b.0 == r => Some(a.0),
                _ => None,
            })
            .filter(|&o| o < rooms.len() && o != r)
            .collect();
        let isolated = !(0..rooms.len()).any(|o| o != r && touch(&rooms[r], &rooms[o]));
        // A room declared after a room it has a door to, but not touching it, moves onto it.
        let apart: Vec<usize> =
            linked.iter().copied().filter(|&o| o < r && !touch(&rooms[r], &rooms[o])).collect();
        let candidates: Vec<usize> = if !apart.is_empty() {
            apart
        } else if !isolated {
            continue;
        } else if linked.is_empty() {
            (0..rooms.len()).filter(|&o| o != r).collect()
        } else {
            linked
        };
        // The move that makes the room touch a candidate: close the gap on one axis, and on
        // the other axis only what keeps the rooms side by side.
        let mut best: Option<(f64, [f64; 2])> = None;
        for o in candidates {
            let g = box_gap(&rooms[r], &rooms[o]);
            for axis in 0..2 {
                let other = 1 - axis;
                if g[axis] <= SAME_M || g[other] > -0.5 {
                    continue;
                }
                let (lr, _) = extent(&rooms[r], axis);
                let (lo, _) = extent(&rooms[o], axis);
                let mut shift = [0.0; 2];
                shift[axis] = if lr > lo { -g[axis] } else { g[axis] };
                let dist = g[axis];
                if dist <= MAX_TRANSLATION_M && best.is_none_or(|(d, _)| dist < d) {
                    best = Some((dist, shift));
                }
            }
        }
        if let Some((_, shift)) = best {
            for p in &mut rooms[r] {
                p[0] += shift[0];
                p[1] += shift[1];
            }
        }
    }
}

/// What happened to one corner as written.
#[derive(Clone, Copy, Debug)]
enum CornerChange {
    /// Moved to a corner of the repaired outline, this far (metres).
    Moved { from: [f64; 2], to: [f64; 2], distance: f64 },
    /// Dropped: it repeated the corner before it, or lay on a straight wall of the repaired
    /// outline (this far from it, metres).
    Dropped { at: [f64; 2], distance: f64 },
}

impl CornerChange {
    fn distance(self) -> f64 {
        match self {
            Self::Moved { distance, .. } | Self::Dropped { distance, .. } => distance,
        }
    }
}

/// The distance from a point to the segment from `a` to `b`.
fn to_segment(p: [f64; 2], a: [f64; 2], b: [f64; 2]) -> f64 {
    let (dx, dz) = (b[0] - a[0], b[1] - a[1]);
    let len2 = dx * dx + dz * dz;
    let t = if len2 <= 0.0 {
        0.0
    } else {
        (((p[0] - a[0]) * dx + (p[1] - a[1]) * dz) / len2).clamp(0.0, 1.0)
    };
    (p[0] - a[0] - t * dx).hypot(p[1] - a[1] - t * dz)
}

/// What happened to each corner as written: the repaired corner that comes from it (`origin`
/// gives, per repaired corner, the index of the corner as written), or, when none does, it was
/// dropped (a repeat, or a corner on what is now a straight wall).
fn describe_moves(before: &[[f64; 2]], after: &[[f64; 2]], origin: &[usize]) -> Vec<CornerChange> {
    let n = after.len();
    let mut out = Vec::new();
    for (b, p) in before.iter().enumerate() {
        match origin.iter().position(|&o| o == b) {
            Some(a) => {
                let d = (after[a][0] - p[0]).hypot(after[a][1] - p[1]);
                if d > SAME_M {
                    out.push(CornerChange::Moved { from: *p, to: after[a], distance: d });
                }
            }
            None => {
                let to_wall = (0..n)
                    .map(|e| to_segment(*p, after[e], after[(e + 1) % n]))
                    .fold(f64::INFINITY, f64::min);
                out.push(CornerChange::Dropped { at: *p, distance: to_wall });
            }
        }
    }
    out
}

fn area(corners: &[[f64; 2]]) -> f64 {
    let n = corners.len();
    (0..n)
        .map(|i| {
            let (a, b) = (corners[i], corners[(i + 1) % n]);
            a[0] * b[1] - b[0] * a[1]
        })
        .sum::<f64>()
        .abs()
        / 2.0
}

fn summary(before: &[[f64; 2]], after: &[[f64; 2]], changes: &[CornerChange]) -> String {
    let far = changes.iter().map(|c| c.distance()).fold(0.0, f64::max);
    let moved = changes.iter().filter(|c| matches!(c, CornerChange::Moved { .. })).count();
    let dropped = changes.len() - moved;
    let plural = |n: usize| if n == 1 { "" } else { "s" };
    let mut what = Vec::new();
    if moved > 0 {
        what.push(format!("{moved} corner{} moved", plural(moved)));
    }
    if dropped > 0 {
        what.push(format!("{dropped} corner{} dropped", plural(dropped)));
    }
    if what.is_empty() {
        what.push("corners reordered".to_string());
    }
    let far = if far > SAME_M { format!(" (at most {far:.2} m)") } else { String::new() };
    format!("{}{far}, area {:.2} m² → {:.2} m²", what.join(", "), area(before), area(after))
}

/// The area change of a repair, as a share of the original area, per room (for the
/// benchmark).
pub fn area_changes(before: &Scene, repair: &Repair) -> Vec<f64> {
    before
        .rooms
        .iter()
        .zip(&repair.corners)
        .map(|(r, c)| {
            let a0 = area(&r.corners);
            if a0 <= 0.0 {
                0.0
            } else {
                (area(c) - a0).abs() / a0
            }
        })
        .collect()
}

/// A plan-stage error of the geometry of rooms, as left after repair, with a note that says
/// why repair did not fix it (it needs more than the bounds allow); other diagnostics are
/// returned as they are.
pub fn explain_unrepaired(d: Diagnostic) -> Diagnostic {
    let geometric = d.is_error()
        && matches!(
            d.code,
            Code::E0301 | Code::E0302 | Code::E0305 | Code::E0306 | Code::E0307 | Code::E0308
        );
    if !geometric {
        return d;
    }
    d.with_note(format!(
        "not repaired: it needs more than repair allows (a corner moves at most {MAX_MOVE_M} m, \
         a detached room at most {MAX_TRANSLATION_M} m, a room's area changes by at most {}%); \
         edit the corners by hand",
        MAX_AREA_CHANGE * 100.0
    ))
}

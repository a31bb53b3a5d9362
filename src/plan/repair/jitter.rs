//! Jitter snapped onto shared lines: a plan whose corners were each moved a little (a model
//! that writes every coordinate slightly off) has slanted edges in several rooms and walls that
//! nearly meet their neighbours'. Before any room moves, every wall is put back on one line:
//! the two ends of a nearly straight edge, the facing walls of two rooms and the walls of two
//! rooms that continue one another (a façade) within [`MAX_JITTER_M`] of each other go onto
//! one coordinate, the roundest one between them nearest their length-weighted mean. Rooms
//! that nearly share a wall in the plan therefore share it after, and no corner moves more than
//! [`MAX_JITTER_M`] along an axis.

use super::{extent, inside, roundness, SAME_M};

/// The most a corner of a jittered plan is taken to be off its line along an axis, metres: two
/// corners meant to be on one line are at most twice this apart.
pub const MAX_JITTER_M: f64 = 0.2;

/// Two groups of walls continuing one another (a façade, or two shared walls in line) are one
/// line when their length-weighted means are at most this apart, metres: jitter of up to 17 cm
/// puts a group's mean within about 0.05 m of its line (four corners), while two lines meant a
/// step apart (a T-junction) stay two. Lines meant closer than this become one.
const MAX_CONTINUE_M: f64 = 0.15;

/// Facing walls of two rooms are one wall when their lengths overlap by more than this, metres:
/// two rooms meant to meet at a corner overlap by up to twice the jitter once it is drawn.
const MIN_FACING_M: f64 = 2.0 * MAX_JITTER_M;

/// Facing or continuing walls whose lengths overlap (or, for walls that continue one another,
/// come) within this of each other are one wall, metres.
const MIN_FACE_M: f64 = 0.1;

/// Whether a plan looks jittered: edges that are not straight in at least two rooms (one
/// slanted edge is a wall drawn wrong, straightened by the outline clean-up).
pub(super) fn jittered(rooms: &[Vec<[f64; 2]>]) -> bool {
    rooms.iter().filter(|corners| slanted(corners)).count() >= 2
}

/// Whether an outline has an edge that is neither along x nor along z.
fn slanted(corners: &[[f64; 2]]) -> bool {
    let n = corners.len();
    (0..n).any(|i| {
        let (a, b) = (corners[i], corners[(i + 1) % n]);
        (b[0] - a[0]).abs() > SAME_M && (b[1] - a[1]).abs() > SAME_M
    })
}

/// One wall of a jittered outline: a group of corner coordinates on one axis.
struct Wall {
    /// The room.
    room: usize,
    /// The group (a node of the union-find).
    node: usize,
    /// The mean coordinate of its corners.
    at: f64,
    /// Its extent along the other axis.
    from: f64,
    to: f64,
    /// Which way its outside points (+1 or -1), or 0 when its edges disagree.
    outward: f64,
}

/// The plan with every wall snapped onto its line (see the module documentation). The outlines
/// keep their corners (count and order); edges made straight may leave corners on a straight
/// wall, which the outline clean-up drops.
pub(super) fn snap(rooms: &[Vec<[f64; 2]>]) -> Vec<Vec<[f64; 2]>> {
    let mut out = rooms.to_vec();
    let start: Vec<usize> = rooms
        .iter()
        .scan(0, |at, corners| {
            let here = *at;
            *at += corners.len();
            Some(here)
        })
        .collect();
    let total: usize = rooms.iter().map(Vec::len).sum();
    let boxes: Vec<[(f64, f64); 2]> =
        rooms.iter().map(|corners| [extent(corners, 0), extent(corners, 1)]).collect();
    let near = |a: usize, b: usize| {
        (0..2).all(|k| {
            let ((la, ha), (lb, hb)) = (boxes[a][k], boxes[b][k]);
            (lb - ha).max(la - hb) <= 2.0 * MAX_JITTER_M
        })
    };
    for axis in 0..2 {
        let other = 1 - axis;
        let value = |node: usize| -> f64 {
            let r = start.partition_point(|&s| s <= node) - 1;
            rooms[r][node - start[r]][axis]
        };
        let mut parent: Vec<usize> = (0..total).collect();
        // The two ends of a nearly straight edge along the other axis are one wall.
        let mut outward_of: Vec<Vec<f64>> = vec![Vec::new(); total];
        for (r, corners) in rooms.iter().enumerate() {
            let n = corners.len();
            let ccw = if signed_area(corners) >= 0.0 { 1.0 } else { -1.0 };
            for i in 0..n {
                let (a, b) = (corners[i], corners[(i + 1) % n]);
                let (d, len) = ((b[axis] - a[axis]).abs(), (b[other] - a[other]).abs());
                if d > 2.0 * MAX_JITTER_M || len <= d {
                    continue;
                }
                let (x, y) = (start[r] + i, start[r] + (i + 1) % n);
                union(&mut parent, x, y);
                let along = (b[other] - a[other]).signum();
                let outward = if axis == 0 { along * ccw } else { -along * ccw };
                outward_of[x].push(outward);
            }
        }
        let walls = walls(rooms, &start, &mut parent, &outward_of, axis, value);
        // Facing walls of two rooms, and walls of two rooms that continue one another, nearest
        // first; never two walls of one room together, never a group wider than twice the
        // jitter.
        let mut pairs: Vec<(bool, f64, usize, usize)> = Vec::new();
        for (i, a) in walls.iter().enumerate() {
            for (j, b) in walls.iter().enumerate().skip(i + 1) {
                if a.room == b.room || a.outward == 0.0 || b.outward == 0.0 {
                    continue;
                }
                if !near(a.room, b.room) {
                    continue;
                }
                let d = (a.at - b.at).abs();
                if d > 2.0 * MAX_JITTER_M {
                    continue;
                }
                let (lo, hi) = (a.from.max(b.from), a.to.min(b.to));
                let facing = a.outward * b.outward < 0.0;
                let joins = if facing {
                    // Facing: they overlap along their length, with no third room between.
                    let mut mid = [0.0; 2];
                    mid[axis] = f64::midpoint(a.at, b.at);
                    mid[other] = f64::midpoint(lo, hi);
                    hi - lo > MIN_FACING_M
                        && !rooms
                            .iter()
                            .enumerate()
                            .any(|(r, c)| r != a.room && r != b.room && inside(mid, c))
                } else {
                    // Continuing: one ends about where the other begins.
                    hi - lo > -2.0 * MAX_JITTER_M && hi - lo < MIN_FACE_M
                };
                if joins {
                    pairs.push((!facing, d, i, j));
                }
            }
        }
        // Facing walls first (two rooms sharing a wall), then walls continuing one another.
        pairs.sort_by(|x, y| {
            x.0.cmp(&y.0).then(x.1.total_cmp(&y.1)).then(x.2.cmp(&y.2)).then(x.3.cmp(&y.3))
        });
        let mut members: Vec<Vec<usize>> = (0..walls.len()).map(|i| vec![i]).collect();
        let mut group: Vec<usize> = (0..walls.len()).collect();
        for (continuing, _, i, j) in pairs {
            let (gi, gj) = (find(&mut group, i), find(&mut group, j));
            if gi == gj {
                continue;
            }
            // Two lines continuing one another are one line only when their walls, each
            // group's weighted together, are about as far apart as jitter puts one line's
            // corners: two shared walls a step apart (a T, not a crossing) stay two.
            if continuing
                && (mean_at(&walls, &members[gi]) - mean_at(&walls, &members[gj])).abs()
                    > MAX_CONTINUE_M
            {
                continue;
            }
            let joined: Vec<usize> = members[gi].iter().chain(&members[gj]).copied().collect();
            let one_room_twice = joined
                .iter()
                .any(|&x| joined.iter().any(|&y| x != y && walls[x].room == walls[y].room));
            let (lo, hi) =
                joined.iter().fold((f64::INFINITY, f64::NEG_INFINITY), |(lo, hi), &x| {
                    (lo.min(walls[x].at), hi.max(walls[x].at))
                });
            if one_room_twice || hi - lo > 2.0 * MAX_JITTER_M {
                continue;
            }
            group[gj] = gi;
            let moved = std::mem::take(&mut members[gj]);
            members[gi].extend(moved);
        }
        // Each group's line: the roundest coordinate within the span of its corners nearest
        // the mean of its walls weighted by their length.
        let mut line_of_node: Vec<Option<f64>> = vec![None; total];
        for (g, ws) in members.iter().enumerate() {
            if find(&mut group, g) != g {
                continue;
            }
            let mut nodes: Vec<usize> = Vec::new();
            for &w in ws {
                let root = walls[w].node;
                nodes.extend((0..total).filter(|&x| find(&mut parent, x) == root));
            }
            let (lo, hi) = nodes.iter().fold((f64::INFINITY, f64::NEG_INFINITY), |(lo, hi), &x| {
                (lo.min(value(x)), hi.max(value(x)))
            });
            let mean = mean_at(&walls, ws);
            let line = line_between(lo, hi, mean);
            for x in nodes {
                line_of_node[x] = Some(line);
            }
        }
        for (r, corners) in out.iter_mut().enumerate() {
            for (i, p) in corners.iter_mut().enumerate() {
                if let Some(v) = line_of_node[start[r] + i] {
                    p[axis] = v;
                }
            }
        }
    }
    out
}

/// The mean coordinate of a group of walls, weighted by their length.
fn mean_at(walls: &[Wall], members: &[usize]) -> f64 {
    let weight: f64 = members.iter().map(|&w| (walls[w].to - walls[w].from).max(1e-3)).sum();
    members.iter().map(|&w| walls[w].at * (walls[w].to - walls[w].from).max(1e-3)).sum::<f64>()
        / weight
}

/// The walls of the rooms on one axis: the groups of corners joined by nearly straight edges.
fn walls(
    rooms: &[Vec<[f64; 2]>],
    start: &[usize],
    parent: &mut [usize],
    outward_of: &[Vec<f64>],
    axis: usize,
    value: impl Fn(usize) -> f64,
) -> Vec<Wall> {
    let other = 1 - axis;
    let mut out: Vec<Wall> = Vec::new();
    for (r, corners) in rooms.iter().enumerate() {
        let mut roots: Vec<usize> = Vec::new();
        for i in 0..corners.len() {
            let root = find(parent, start[r] + i);
            if !roots.contains(&root) {
                roots.push(root);
            }
        }
        for root in roots {
            let nodes: Vec<usize> = (0..corners.len())
                .map(|i| start[r] + i)
                .filter(|&x| find(parent, x) == root)
                .collect();
            if nodes.len() < 2 {
                continue;
            }
            let at = nodes.iter().map(|&x| value(x)).sum::<f64>() / nodes.len() as f64;
            let (from, to) =
                nodes.iter().fold((f64::INFINITY, f64::NEG_INFINITY), |(lo, hi), &x| {
                    let v = corners[x - start[r]][other];
                    (lo.min(v), hi.max(v))
                });
            let sides: Vec<f64> =
                nodes.iter().flat_map(|&x| outward_of[x].iter().copied()).collect();
            let outward = if sides.iter().all(|&s| s > 0.0) {
                1.0
            } else if sides.iter().all(|&s| s < 0.0) {
                -1.0
            } else {
                0.0
            };
            out.push(Wall { room: r, node: root, at, from, to, outward });
        }
    }
    out
}

/// The roundest coordinate in `[lo, hi]` (whole metres, then tenths, hundredths, millimetres)
/// nearest `mean`; the mean to the millimetre when none is.
fn line_between(lo: f64, hi: f64, mean: f64) -> f64 {
    for decimals in 0..=3 {
        let scale = 10f64.powi(decimals);
        let nearest = (mean * scale).round() / scale;
        let candidates = [nearest, nearest - 1.0 / scale, nearest + 1.0 / scale];
        let best = candidates
            .into_iter()
            .filter(|&v| v >= lo - SAME_M && v <= hi + SAME_M)
            .min_by(|a, b| (a - mean).abs().total_cmp(&(b - mean).abs()));
        if let Some(v) = best {
            if roundness(v) <= decimals as u32 {
                return v;
            }
        }
    }
    (mean * 1e3).round() / 1e3
}

fn signed_area(corners: &[[f64; 2]]) -> f64 {
    let n = corners.len();
    (0..n)
        .map(|i| {
            let (a, b) = (corners[i], corners[(i + 1) % n]);
            a[0] * b[1] - b[0] * a[1]
        })
        .sum()
}

fn find(parent: &mut [usize], x: usize) -> usize {
    let mut r = x;
    while parent[r] != r {
        r = parent[r];
    }
    let mut y = x;
    while parent[y] != r {
        let next = parent[y];
        parent[y] = r;
        y = next;
    }
    r
}

fn union(parent: &mut [usize], a: usize, b: usize) {
    let (ra, rb) = (find(parent, a), find(parent, b));
    if ra != rb {
        parent[ra.max(rb)] = ra.min(rb);
    }
}

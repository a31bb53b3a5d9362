//! Wall objects, small objects on receptacles and the ceiling object, placed after the floor.

use super::constraints::{Rect, RoomShape, Rot, WindowZone, WINDOW_ZONE_M};
use super::{PlacedObject, Prepared, RoomLayout, RoomProblem, Unplaced, WallSegment};

/// Height of a wall object's bottom when none is given, metres.
pub const DEFAULT_WALL_HEIGHT_M: f64 = 1.5;
/// The top of a wall object stays at least this far below the ceiling, metres.
pub const CEILING_MARGIN_M: f64 = 0.2;
/// Step of the positions tried along a wall, metres.
pub const WALL_STEP_M: f64 = 0.1;
/// Wall objects stand this far off the wall, metres.
pub const WALL_OFFSET_M: f64 = 0.01;
/// Margin kept free around the top of a receptacle and between small objects, metres.
pub const SMALL_GAP_M: f64 = 0.02;
/// A flat thing (a book, a plate) is at most this tall, metres, and at most a third of its
/// shorter side; only flat things are piled.
pub const FLAT_MAX_M: f64 = 0.08;
/// The top thing of a pile rests at most this far above its receptacle's top, metres: a
/// centimetre under what the house check accepts as resting on the receptacle (10 cm, W0612),
/// so that rounding never makes a pile float.
pub const PILE_MAX_M: f64 = 0.09;

/// Whether a small object of this size may be piled or carry a pile.
fn flat(size: [f64; 3]) -> bool {
    let [w, d, h] = size;
    h <= FLAT_MAX_M && 3.0 * h <= w.min(d)
}

/// A pile of things on a receptacle's top, in the receptacle's frame.
struct Pile<'p> {
    /// What it is a pile of.
    item: &'p str,
    /// The centre, `(u, v)`: right and front of the receptacle's centre.
    centre: [f64; 2],
    /// The top thing's extent along `u` and `v`.
    top: [f64; 2],
    /// How high the pile is.
    height: f64,
}

/// The walls of a problem: as given, or the outline's edges without holes.
pub(crate) fn walls(problem: &RoomProblem) -> Vec<WallSegment> {
    if !problem.walls.is_empty() {
        return problem.walls.clone();
    }
    let n = problem.outline.len();
    (0..n)
        .map(|i| WallSegment {
            a: problem.outline[i],
            b: problem.outline[(i + 1) % n],
            holes: Vec::new(),
        })
        .collect()
}

fn unit(a: [f64; 2], b: [f64; 2]) -> ([f64; 2], f64) {
    let len = (b[0] - a[0]).hypot(b[1] - a[1]);
    if len < 1e-9 {
        return ([1.0, 0.0], 0.0);
    }
    ([(b[0] - a[0]) / len, (b[1] - a[1]) / len], len)
}

/// The inward unit normal of a wall segment of the room.
fn inward(room: &RoomShape, a: [f64; 2], d: [f64; 2], len: f64) -> [f64; 2] {
    let mid = [a[0] + d[0] * len / 2.0, a[1] + d[1] * len / 2.0];
    let left = [-d[1], d[0]];
    let probe = [mid[0] + left[0] * 1e-3, mid[1] + left[1] * 1e-3];
    if super::constraints::point_in_polygon(probe, &room.outline) {
        left
    } else {
        [d[1], -d[0]]
    }
}

/// The floor zones in front of the room's windows.
pub(crate) fn window_zones(problem: &RoomProblem, _room: &RoomShape) -> Vec<WindowZone> {
    let mut out = Vec::new();
    for w in walls(problem) {
        let (d, _) = unit(w.a, w.b);
        for h in w.holes.iter().filter(|h| h.window) {
            let p = [w.a[0] + d[0] * h.from_m, w.a[1] + d[1] * h.from_m];
            let q = [w.a[0] + d[0] * h.to_m, w.a[1] + d[1] * h.to_m];
            let mut r = Rect::from_corners(p, q);
            if d[1].abs() < 1e-9 {
                r.min_z -= WINDOW_ZONE_M;
                r.max_z += WINDOW_ZONE_M;
            } else {
                r.min_x -= WINDOW_ZONE_M;
                r.max_x += WINDOW_ZONE_M;
            }
            out.push(WindowZone { zone: r, sill_m: h.bottom_m });
        }
    }
    out
}

/// A 3-D box: floor rectangle and vertical range.
#[derive(Clone, Copy)]
struct Box3 {
    rect: Rect,
    y0: f64,
    y1: f64,
}

impl Box3 {
    fn overlaps(&self, o: &Box3) -> bool {
        self.rect.overlaps(&o.rect) && self.y0 < o.y1 - 1e-6 && o.y0 < self.y1 - 1e-6
    }
}

/// Places wall, small and ceiling objects and fills the world boxes of floor objects.
pub(crate) fn finish(prep: &Prepared<'_>, layout: &mut RoomLayout) {
    let problem = prep.problem;
    for p in &layout.floor {
        let obj = &problem.objects[p.index];
        layout.floor_world.push(PlacedObject {
            id: obj.id.clone(),
            position_m: [p.pose.x, obj.height / 2.0, p.pose.z],
            rotation_deg: p.pose.rot.deg(),
            on: None,
        });
    }
    place_walls(prep, layout);
    place_small(prep, layout);
    place_ceiling(prep, layout);
}

fn place_walls(prep: &Prepared<'_>, layout: &mut RoomLayout) {
    let problem = prep.problem;
    let segs = walls(problem);
    let floor_boxes: Vec<Box3> = layout
        .floor
        .iter()
        .map(|p| Box3 { rect: p.footprint, y0: 0.0, y1: problem.objects[p.index].height })
        .collect();
    let mut placed: Vec<(Box3, [f64; 2])> = Vec::new();
    for wo in &problem.wall_objects {
        let [w, dd, h] = wo.size;
        let top_limit = problem.wall_height - h - CEILING_MARGIN_M;
        let bottom = wo.height_m.unwrap_or(DEFAULT_WALL_HEIGHT_M).min(top_limit).max(0.0);
        let target = wo
            .above
            .and_then(|t| layout.floor.iter().find(|p| p.index == t))
            .map(|p| [p.pose.x, p.pose.z]);
        let mut best: Option<(f64, Box3, [f64; 2], Rot)> = None;
        let mut reasons = (0usize, 0usize, 0usize);
        for seg in &segs {
            let (d, len) = unit(seg.a, seg.b);
            if len < w {
                continue;
            }
            let n = inward(&prep.room, seg.a, d, len);
            let Some(rot) = Rot::facing([n[0].round(), n[1].round()]) else { continue };
            let mut ss = Vec::new();
            let mut s = w / 2.0;
            while s <= len - w / 2.0 + 1e-9 {
                ss.push(s);
                s += WALL_STEP_M;
            }
            ss.push(len / 2.0);
            if let Some(t) = target {
                let proj = (t[0] - seg.a[0]) * d[0] + (t[1] - seg.a[1]) * d[1];
                ss.push(proj.clamp(w / 2.0, len - w / 2.0));
            }
            for s in ss {
                let c = [seg.a[0] + d[0] * s, seg.a[1] + d[1] * s];
                let p0 = [c[0] - d[0] * w / 2.0, c[1] - d[1] * w / 2.0];
                let p1 = [c[0] + d[0] * w / 2.0 + n[0] * dd, c[1] + d[1] * w / 2.0 + n[1] * dd];
                let rect = Rect::from_corners(p0, p1);
                let bx = Box3 { rect, y0: bottom, y1: bottom + h };
                if !prep.room.contains_rect(&rect) {
                    continue;
                }
                let in_hole = seg.holes.iter().any(|ho| {
                    s - w / 2.0 < ho.to_m - 1e-6
                        && ho.from_m < s + w / 2.0 - 1e-6
                        && bottom < ho.top_m - 1e-6
                        && ho.bottom_m < bottom + h - 1e-6
                });
                if in_hole {
                    reasons.0 += 1;
                    continue;
                }
                if placed.iter().any(|(b, _)| b.overlaps(&bx)) {
                    reasons.1 += 1;
                    continue;
                }
                if floor_boxes.iter().any(|b| b.overlaps(&bx)) {
                    reasons.2 += 1;
                    continue;
                }
                let centre = rect.center();
                let score = if let Some(t) = target {
                    -(centre[0] - t[0]).hypot(centre[1] - t[1])
                } else {
                    let spread = placed
                        .iter()
                        .map(|(_, q)| (centre[0] - q[0]).hypot(centre[1] - q[1]))
                        .fold(3.0_f64, f64::min);
                    spread - 0.01 * (s - len / 2.0).abs()
                };
                if best.as_ref().is_none_or(|(b, ..)| score > b + 1e-9) {
                    best = Some((score, bx, centre, rot));
                }
            }
        }
        if let Some((_, bx, centre, rot)) = best {
            {
                let f = rot.front();
                layout.wall.push(PlacedObject {
                    id: wo.id.clone(),
                    position_m: [
                        centre[0] + f[0] * WALL_OFFSET_M,
                        bottom + h / 2.0,
                        centre[1] + f[1] * WALL_OFFSET_M,
                    ],
                    rotation_deg: rot.deg(),
                    on: None,
                });
                placed.push((bx, centre));
            }
        } else {
            {
                let reason = if reasons == (0, 0, 0) {
                    "no wall of the room is long enough".to_string()
                } else {
                    format!(
                        "every position on the walls is over a door or window ({}), overlaps a wall object ({}) or a floor object ({})",
                        reasons.0, reasons.1, reasons.2
                    )
                };
                layout.unplaced.push(Unplaced {
                    id: wo.id.clone(),
                    kind: "wall",
                    rule: None,
                    reason,
                });
            }
        }
    }
}

fn place_small(prep: &Prepared<'_>, layout: &mut RoomLayout) {
    let problem = prep.problem;
    let mut by_receptacle: Vec<Vec<usize>> = vec![Vec::new(); problem.objects.len()];
    for (i, s) in problem.small_objects.iter().enumerate() {
        match by_receptacle.get_mut(s.on) {
            Some(v) => v.push(i),
            None => layout.unplaced.push(Unplaced {
                id: s.id.clone(),
                kind: "small",
                rule: None,
                reason: "its receptacle is not a floor object of the room".to_string(),
            }),
        }
    }
    let mut results: Vec<Option<PlacedObject>> = vec![None; problem.small_objects.len()];
    let mut reasons: Vec<Option<String>> = vec![None; problem.small_objects.len()];
    for (r, items) in by_receptacle.iter().enumerate() {
        if items.is_empty() {
            continue;
        }
        let Some(rp) = layout.floor.iter().find(|p| p.index == r) else {
            for &i in items {
                reasons[i] =
                    Some(format!("its receptacle `{}` is not placed", problem.objects[r].id));
            }
            continue;
        };
        let rec = &problem.objects[r];
        let (top_w, top_d) = (rec.size[0] - 2.0 * SMALL_GAP_M, rec.size[1] - 2.0 * SMALL_GAP_M);
        // Largest first, stable.
        let mut order = items.clone();
        order.sort_by(|&a, &b| {
            let sa = problem.small_objects[a].size;
            let sb = problem.small_objects[b].size;
            sb[0].max(sb[1]).total_cmp(&sa[0].max(sa[1]))
        });
        // Shelf packing in the receptacle's own frame: u to its right, v to its front.
        let (mut u, mut v, mut row_d) = (0.0_f64, 0.0_f64, 0.0_f64);
        let mut piles: Vec<Pile<'_>> = Vec::new();
        let f = rp.pose.rot.front();
        let rt = rp.pose.rot.right();
        let at = |[lu, lv]: [f64; 2], y: f64, turn: f64, id: &str| PlacedObject {
            id: id.to_string(),
            position_m: [rp.pose.x + rt[0] * lu + f[0] * lv, y, rp.pose.z + rt[1] * lu + f[1] * lv],
            rotation_deg: (rp.pose.rot.deg() + turn).rem_euclid(360.0),
            on: Some(r),
        };
        for i in order {
            let s = &problem.small_objects[i];
            let [w, d, h] = s.size;
            // As it is, or turned a quarter on the top when that is what fits.
            let turns: Vec<(f64, f64, f64)> = [(w, d, 0.0), (d, w, 90.0)]
                .into_iter()
                .filter(|&(sw, sd, _)| sw <= top_w + 1e-9 && sd <= top_d + 1e-9)
                .collect();
            if turns.is_empty() {
                reasons[i] = Some(format!(
                    "it is larger than the top of `{}` ({:.2} m × {:.2} m against {:.2} m × {:.2} m, either way round)",
                    rec.id,
                    w,
                    d,
                    top_w.max(0.0),
                    top_d.max(0.0)
                ));
                continue;
            }
            // In the current row if it fits there either way round, else in a new row.
            let in_row =
                turns.iter().find(|&&(sw, sd, _)| u + sw <= top_w + 1e-9 && v + sd <= top_d + 1e-9);
            let next_v = v + row_d + SMALL_GAP_M;
            let (sw, sd, turn) = match in_row {
                Some(&t) => t,
                None => match turns.iter().find(|&&(_, sd, _)| next_v + sd <= top_d + 1e-9) {
                    Some(&t) => {
                        u = 0.0;
                        v = next_v;
                        row_d = 0.0;
                        t
                    }
                    None => {
                        // No room side by side: on a pile of the same thing it fits on, if it
                        // is flat (a book on a book), else it is left out.
                        let pile = piles.iter().enumerate().find_map(|(n, p)| {
                            let ok =
                                p.item == s.item && flat(s.size) && p.height <= PILE_MAX_M + 1e-9;
                            let fits = |&&(sw, sd, _): &&(f64, f64, f64)| {
                                sw <= p.top[0] + 1e-9 && sd <= p.top[1] + 1e-9
                            };
                            ok.then(|| turns.iter().find(fits).map(|&t| (n, t))).flatten()
                        });
                        let Some((n, (sw, sd, turn))) = pile else {
                            reasons[i] = Some(format!("the top of `{}` is full", rec.id));
                            continue;
                        };
                        let pile = &mut piles[n];
                        let y = rec.height + pile.height + h / 2.0;
                        results[i] = Some(at(pile.centre, y, turn, &s.id));
                        pile.top = [sw, sd];
                        pile.height += h;
                        continue;
                    }
                },
            };
            let centre = [-top_w / 2.0 + u + sw / 2.0, top_d / 2.0 - v - sd / 2.0];
            results[i] = Some(at(centre, rec.height + h / 2.0, turn, &s.id));
            if flat(s.size) {
                piles.push(Pile { item: &s.item, centre, top: [sw, sd], height: h });
            }
            u += sw + SMALL_GAP_M;
            row_d = row_d.max(sd);
        }
    }
    for (i, res) in results.into_iter().enumerate() {
        match res {
            Some(p) => layout.small.push(p),
            None => {
                if let Some(reason) = reasons[i].take() {
                    layout.unplaced.push(Unplaced {
                        id: problem.small_objects[i].id.clone(),
                        kind: "small",
                        rule: None,
                        reason,
                    });
                }
            }
        }
    }
}

fn place_ceiling(prep: &Prepared<'_>, layout: &mut RoomLayout) {
    let problem = prep.problem;
    let Some(c) = &problem.ceiling else { return };
    let over = c
        .above
        .and_then(|t| layout.floor.iter().find(|p| p.index == t))
        .map(|p| [p.pose.x, p.pose.z]);
    let mut at = over.unwrap_or_else(|| prep.room.centroid());
    if !prep.room.contains_point(at) {
        let biggest = prep
            .room
            .rects
            .iter()
            .max_by(|a, b| (a.width() * a.depth()).total_cmp(&(b.width() * b.depth())))
            .copied()
            .unwrap_or(prep.room.bounds);
        at = biggest.center();
    }
    layout.ceiling = Some(PlacedObject {
        id: c.id.clone(),
        position_m: [at[0], problem.wall_height - c.size[2] / 2.0, at[1]],
        rotation_deg: 0.0,
        on: None,
    });
}

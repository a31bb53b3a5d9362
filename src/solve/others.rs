//! Wall objects, small objects on receptacles and the ceiling object, placed after the floor.

use super::constraints::{Rect, RoomShape, Rot, WindowZone, WINDOW_ZONE_M};
use super::surfaces::{carrier, Carrier, Surface};
use super::{Holder, PlacedObject, Prepared, RoomLayout, RoomProblem, Unplaced, WallSegment};
use crate::diag::Code;
use crate::resolve::receptacles::MAX_MOVED_PER_RECEPTACLE;
use std::collections::BTreeMap;

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
            sized_m: None,
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
    // Curtains and blinds holoc made dress the windows first, each the first window free; the
    // other wall objects then keep clear of them.
    let mut dressed = vec![false; problem.wall_objects.len()];
    let mut dressings = Vec::new();
    for (i, wo) in problem.wall_objects.iter().enumerate() {
        if let Some(dressing) = Dressing::of(wo.thor_type.as_deref()).filter(|_| wo.resizable) {
            if let Some(p) = dress_window(prep, &segs, wo, dressing, &mut placed) {
                dressings.push((i, p));
                dressed[i] = true;
            }
        }
    }
    let mut dressings = dressings.into_iter().peekable();
    for (i, wo) in problem.wall_objects.iter().enumerate() {
        if dressed[i] {
            if let Some((_, p)) = dressings.next_if(|(k, _)| *k == i) {
                layout.wall.push(p);
            }
            continue;
        }
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
                    sized_m: None,
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
                    code: crate::diag::Code::W0501,
                });
            }
        }
    }
}

/// What dresses a window: curtains hang from above it to the floor (or, short, to under its
/// sill), blinds cover it.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
enum Dressing {
    Curtains,
    Blinds,
}

/// Curtains reach this far past each side of their window and their rod this far above it,
/// metres (common practice: 15–30 cm each side, 10–15 cm above).
pub const CURTAIN_OVERLAP_M: f64 = 0.25;
/// How far above the window the curtain rod is, metres.
pub const CURTAIN_ROD_ABOVE_M: f64 = 0.15;
/// How far blinds reach past their window on each side and above it, metres.
pub const BLIND_OVERLAP_M: f64 = 0.03;

impl Dressing {
    fn of(thor_type: Option<&str>) -> Option<Dressing> {
        match thor_type? {
            "Curtains" => Some(Dressing::Curtains),
            "Blinds" => Some(Dressing::Blinds),
            _ => None,
        }
    }
}

/// Hangs curtains or blinds over the first window of the room that nothing dresses yet,
/// sized to it (`PlacedObject::sized_m`): curtains from [`CURTAIN_ROD_ABOVE_M`] above the
/// window to the floor, [`CURTAIN_OVERLAP_M`] wider each side (as far as the wall allows);
/// blinds over the window with [`BLIND_OVERLAP_M`] round it. `None` when every window is
/// dressed (the object is then hung as any wall object).
fn dress_window(
    prep: &Prepared<'_>,
    segs: &[WallSegment],
    wo: &super::WallObject,
    dressing: Dressing,
    placed: &mut Vec<(Box3, [f64; 2])>,
) -> Option<PlacedObject> {
    let problem = prep.problem;
    let depth = wo.size[1];
    for seg in segs {
        let (d, len) = unit(seg.a, seg.b);
        let n = inward(&prep.room, seg.a, d, len);
        let Some(rot) = Rot::facing([n[0].round(), n[1].round()]) else { continue };
        for hole in seg.holes.iter().filter(|h| h.window) {
            let (lo, hi, top) = match dressing {
                Dressing::Curtains => (
                    (hole.from_m - CURTAIN_OVERLAP_M).max(0.0),
                    (hole.to_m + CURTAIN_OVERLAP_M).min(len),
                    (hole.top_m + CURTAIN_ROD_ABOVE_M).min(problem.wall_height - 0.02),
                ),
                Dressing::Blinds => (
                    (hole.from_m - BLIND_OVERLAP_M).max(0.0),
                    (hole.to_m + BLIND_OVERLAP_M).min(len),
                    (hole.top_m + BLIND_OVERLAP_M).min(problem.wall_height - 0.02),
                ),
            };
            let bottom = match dressing {
                Dressing::Curtains => 0.0,
                Dressing::Blinds => (hole.bottom_m - BLIND_OVERLAP_M).max(0.0),
            };
            let (w, h) = (hi - lo, top - bottom);
            if w <= 0.05 || h <= 0.05 {
                continue;
            }
            let s = f64::midpoint(lo, hi);
            let c = [seg.a[0] + d[0] * s, seg.a[1] + d[1] * s];
            let p0 = [c[0] - d[0] * w / 2.0, c[1] - d[1] * w / 2.0];
            let p1 = [c[0] + d[0] * w / 2.0 + n[0] * depth, c[1] + d[1] * w / 2.0 + n[1] * depth];
            let rect = Rect::from_corners(p0, p1);
            let bx = Box3 { rect, y0: bottom, y1: top };
            if placed.iter().any(|(b, _)| b.overlaps(&bx)) {
                continue;
            }
            let centre = rect.center();
            placed.push((bx, centre));
            let f = rot.front();
            return Some(PlacedObject {
                id: wo.id.clone(),
                position_m: [
                    centre[0] + f[0] * WALL_OFFSET_M,
                    bottom + h / 2.0,
                    centre[1] + f[1] * WALL_OFFSET_M,
                ],
                rotation_deg: rot.deg(),
                on: None,
                sized_m: Some([w, depth, h]),
            });
        }
    }
    None
}

/// A receptacle as the small objects see it: where its box stands and how it carries things.
struct Receptacle {
    id: String,
    /// The centre of its box on the floor plan.
    centre: [f64; 2],
    rot: Rot,
    /// The height of its bottom above the floor.
    base_y: f64,
    carrier: Carrier,
}

impl Receptacle {
    fn of(prep: &Prepared<'_>, layout: &RoomLayout, on: Holder) -> Result<Receptacle, String> {
        let problem = prep.problem;
        match on {
            Holder::Floor(r) => {
                let rec =
                    problem.objects.get(r).ok_or("its receptacle is not an object of the room")?;
                let p = layout
                    .floor
                    .iter()
                    .find(|p| p.index == r)
                    .ok_or_else(|| format!("its receptacle `{}` is not placed", rec.id))?;
                Ok(Receptacle {
                    id: rec.id.clone(),
                    centre: [p.pose.x, p.pose.z],
                    rot: p.pose.rot,
                    base_y: 0.0,
                    carrier: carrier(
                        rec.thor_type.as_deref(),
                        [rec.size[0], rec.size[1], rec.height],
                        SMALL_GAP_M,
                    ),
                })
            }
            Holder::Wall(w) => {
                let rec = problem
                    .wall_objects
                    .get(w)
                    .ok_or("its receptacle is not an object of the room")?;
                let p = layout
                    .wall
                    .iter()
                    .find(|p| p.id == rec.id)
                    .ok_or_else(|| format!("its receptacle `{}` is not placed", rec.id))?;
                Ok(Receptacle {
                    id: rec.id.clone(),
                    centre: [p.position_m[0], p.position_m[2]],
                    rot: Rot::from_deg(p.rotation_deg),
                    base_y: p.position_m[1] - rec.size[2] / 2.0,
                    carrier: carrier(rec.thor_type.as_deref(), rec.size, SMALL_GAP_M),
                })
            }
        }
    }

    /// The world pose of a point `(u, v)` of its frame (`u` to its right, `v` to its front).
    fn at(&self, [u, v]: [f64; 2], y: f64, turn: f64, id: &str, on: Holder) -> PlacedObject {
        let f = self.rot.front();
        let rt = self.rot.right();
        PlacedObject {
            id: id.to_string(),
            position_m: [
                self.centre[0] + rt[0] * u + f[0] * v,
                self.base_y + y,
                self.centre[1] + rt[1] * u + f[1] * v,
            ],
            rotation_deg: (self.rot.deg() + turn).rem_euclid(360.0),
            on: Some(on),
            sized_m: None,
        }
    }
}

/// One item set in a row of a surface: which, its extent on the surface and its turn.
#[derive(Clone, Copy)]
struct Set {
    item: usize,
    extent: [f64; 2],
    turn: f64,
}

/// The items of one surface, row by row (back to front), and the piles on them.
#[derive(Default)]
struct Rows {
    rows: Vec<Vec<Set>>,
    /// Per pile: the item it stands on (its row and place), what it is a pile of, the top
    /// thing's extent and the things on it with their heights above the surface.
    piles: Vec<PileOn>,
}

struct PileOn {
    row: usize,
    place: usize,
    item: String,
    top: [f64; 2],
    height: f64,
    on_it: Vec<(Set, f64)>,
}

impl Rows {
    fn width(row: &[Set]) -> f64 {
        row.iter().map(|s| s.extent[0]).sum::<f64>()
            + SMALL_GAP_M * row.len().saturating_sub(1) as f64
    }

    fn depth(row: &[Set]) -> f64 {
        row.iter().map(|s| s.extent[1]).fold(0.0, f64::max)
    }

    fn depth_with(&self, extra_row: f64) -> f64 {
        let rows = self.rows.iter().map(|r| Rows::depth(r));
        let n = self.rows.len() + usize::from(extra_row > 0.0);
        rows.sum::<f64>() + extra_row + SMALL_GAP_M * n.saturating_sub(1) as f64
    }

    /// Sets an item of extent `e` in the last row or a new one, if the surface has room.
    fn try_set(&mut self, set: Set, extent: [f64; 2]) -> bool {
        let [w, d] = extent;
        if let Some(last) = self.rows.last() {
            let width = Rows::width(last) + SMALL_GAP_M + set.extent[0];
            let deeper = (set.extent[1] - Rows::depth(last)).max(0.0);
            if width <= w + 1e-9 && self.depth_with(0.0) + deeper <= d + 1e-9 {
                if let Some(last) = self.rows.last_mut() {
                    last.push(set);
                }
                return true;
            }
        }
        if set.extent[0] <= w + 1e-9 && self.depth_with(set.extent[1]) <= d + 1e-9 {
            self.rows.push(vec![set]);
            return true;
        }
        false
    }
}

/// Places the small objects: on the surfaces of their receptacle (a mattress, a seat, the
/// shelves of a bookcase, a table top: [`carrier`]) in the order they are declared,
/// row by row, then spread over each surface so that none hugs its edges; flat things of one
/// name that find no room side by side are piled. Things on a bar (a towel holder) hang from
/// it side by side, in layers when the bar is full.
fn place_small(prep: &Prepared<'_>, layout: &mut RoomLayout) {
    let problem = prep.problem;
    let n = problem.small_objects.len();
    let mut results: Vec<Option<PlacedObject>> = vec![None; n];
    let mut reasons: Vec<Option<(String, Code)>> = vec![None; n];
    // Per small object its receptacles to try, in order: its own, or, when people do not put
    // it there, the placed receptacles of the room that take it, nearest first.
    let mut choices: Vec<Vec<Holder>> = Vec::with_capacity(n);
    for (i, s) in problem.small_objects.iter().enumerate() {
        let Some(elsewhere) = &s.elsewhere else {
            choices.push(vec![s.on]);
            continue;
        };
        // Nearest to where it was declared; when that receptacle is left out, to the objects
        // it was asked to stand by (their mean), else to the room's centre.
        let from = if s.absent.is_some() {
            let centres: Vec<[f64; 2]> = (s.anchor.iter())
                .filter_map(|&h| Receptacle::of(prep, layout, h).ok().map(|r| r.centre))
                .collect();
            if centres.is_empty() {
                Some(prep.room.centroid())
            } else {
                let n = centres.len() as f64;
                Some([
                    centres.iter().map(|c| c[0]).sum::<f64>() / n,
                    centres.iter().map(|c| c[1]).sum::<f64>() / n,
                ])
            }
        } else {
            Receptacle::of(prep, layout, s.on).ok().map(|r| r.centre)
        };
        let d = |c: &[f64; 2]| from.map_or(0.0, |f| (c[0] - f[0]).hypot(c[1] - f[1]));
        let mut near: Vec<(usize, Holder, f64)> = elsewhere
            .iter()
            .enumerate()
            .filter_map(|(k, &h)| {
                Receptacle::of(prep, layout, h).ok().map(|r| (k, h, d(&r.centre)))
            })
            .collect();
        near.sort_by(|a, b| a.2.total_cmp(&b.2).then(a.0.cmp(&b.0)));
        if near.is_empty() {
            let why = if elsewhere.is_empty() {
                no_home(problem, s)
            } else {
                "no receptacle of the room that is a home for it is placed".to_string()
            };
            reasons[i] = Some((format!("{}, and {why}", why_elsewhere(problem, s)), Code::W0506));
        }
        choices.push(near.into_iter().map(|(_, h, _)| h).collect());
    }
    // A moved thing goes to the nearest receptacle that is a home for it; when that one is
    // full, or already carries `MAX_MOVED_PER_RECEPTACLE` moved things, to the next. Each round
    // sets every receptacle's things again (those meant for it first, then the moved ones, each
    // in declaration order), so the outcome does not depend on the order in which receptacles
    // fill; it ends because each round moves some thing one choice on.
    let mut pick = vec![0usize; n];
    // Per moved thing, why each receptacle it was moved on from did not take it.
    let mut passed: Vec<Vec<String>> = vec![Vec::new(); n];
    loop {
        let mut by_holder: BTreeMap<Holder, Vec<usize>> = BTreeMap::new();
        let mut moved_on: BTreeMap<Holder, usize> = BTreeMap::new();
        let mut capped: Vec<(usize, Holder)> = Vec::new();
        for moved in [false, true] {
            for (i, s) in problem.small_objects.iter().enumerate() {
                if s.elsewhere.is_some() == moved {
                    if let Some(&h) = choices[i].get(pick[i]) {
                        if moved {
                            let count = moved_on.entry(h).or_default();
                            if *count >= MAX_MOVED_PER_RECEPTACLE {
                                capped.push((i, h));
                                continue;
                            }
                            *count += 1;
                        }
                        by_holder.entry(h).or_default().push(i);
                    }
                }
            }
        }
        for (i, r) in results.iter_mut().enumerate() {
            *r = None;
            if !choices[i].is_empty() {
                reasons[i] = None;
            }
        }
        for &(i, h) in &capped {
            reasons[i] = Some((
                format!(
                    "`{}` already carries {MAX_MOVED_PER_RECEPTACLE} moved things",
                    super::errors::holder_name(problem, h)
                ),
                Code::W0506,
            ));
        }
        for (&on, items) in &by_holder {
            let rec = match Receptacle::of(prep, layout, on) {
                Ok(r) => r,
                Err(reason) => {
                    for &i in items {
                        reasons[i] = Some((reason.clone(), Code::W0503));
                    }
                    continue;
                }
            };
            match &rec.carrier {
                Carrier::Bar { y, length } => {
                    hang(problem, &rec, on, *y, *length, items, &mut results, &mut reasons);
                }
                Carrier::Surfaces(surfaces) => {
                    set_on_surfaces(problem, &rec, on, surfaces, items, &mut results, &mut reasons);
                }
            }
        }
        let mut next = false;
        for (i, s) in problem.small_objects.iter().enumerate() {
            if s.elsewhere.is_some() && results[i].is_none() && pick[i] + 1 < choices[i].len() {
                let h = super::errors::holder_name(problem, choices[i][pick[i]]);
                passed[i].push(match &reasons[i] {
                    Some((_, Code::W0506)) => {
                        format!("`{h}` already carries {MAX_MOVED_PER_RECEPTACLE} moved things")
                    }
                    _ => format!("`{h}` is full"),
                });
                pick[i] += 1;
                next = true;
            }
        }
        if !next {
            break;
        }
    }
    for (i, s) in problem.small_objects.iter().enumerate() {
        if s.elsewhere.is_none() || choices[i].is_empty() {
            continue;
        }
        if results[i].is_some() {
            let full = choices[i][..pick[i]].to_vec();
            let to = choices[i][pick[i]];
            layout.moved.push(super::Moved {
                small: i,
                from: s.on,
                to,
                full,
                absent: s.absent.clone(),
                p: pair_p(problem, s, to),
            });
        } else if let Some((last, code)) = &reasons[i] {
            if matches!(code, Code::W0501 | Code::W0506) {
                // Every receptacle that is a home for it was tried: say why each did not take
                // it. Only full ones: W0501, as for a thing on its own receptacle.
                let h = super::errors::holder_name(problem, choices[i][pick[i]]);
                let mut why = passed[i].clone();
                why.push(match code {
                    Code::W0506 => last.clone(),
                    _ => format!("`{h}` is full"),
                });
                let code = if *code == Code::W0501 && passed[i].iter().all(|p| p.ends_with("full"))
                {
                    Code::W0501
                } else {
                    Code::W0506
                };
                reasons[i] = Some((
                    format!(
                        "{}, and no receptacle of the room that is a home for it takes it ({})",
                        why_elsewhere(problem, s),
                        why.join("; ")
                    ),
                    code,
                ));
            }
        }
    }
    for (i, res) in results.into_iter().enumerate() {
        match res {
            Some(p) => layout.small.push(p),
            None => {
                if let Some((reason, code)) = reasons[i].take() {
                    layout.unplaced.push(Unplaced {
                        id: problem.small_objects[i].id.clone(),
                        kind: "small",
                        rule: None,
                        reason,
                        code,
                    });
                }
            }
        }
    }
}

/// The `p` of the pair a moved thing makes with the receptacle it was moved to
/// (`resolve::receptacles::move_to`).
fn pair_p(problem: &RoomProblem, s: &super::SmallObject, to: Holder) -> Option<f64> {
    let t = holder_type(problem, to)?;
    crate::resolve::receptacles::move_to(s.thor_type.as_deref()?, &s.item, t).ok().flatten()
}

/// The AI2-THOR type of a receptacle of the problem, when known.
fn holder_type(problem: &RoomProblem, h: Holder) -> Option<&str> {
    problem.holder_type(h)
}

/// Why no receptacle of the room is a home for a thing that must be moved: each receptacle
/// with the rule that refuses it (at most six named).
fn no_home(problem: &RoomProblem, s: &super::SmallObject) -> String {
    let holders = (0..problem.objects.len())
        .map(Holder::Floor)
        .chain((0..problem.wall_objects.len()).map(Holder::Wall));
    let item_type = s.thor_type.as_deref().unwrap_or("");
    let refused: Vec<String> = holders
        .filter(|&h| s.absent.is_some() || h != s.on)
        .filter_map(|h| {
            let t = holder_type(problem, h).filter(|t| crate::resolve::is_receptacle_type(t))?;
            let why = crate::resolve::receptacles::move_to(item_type, &s.item, t).err()?;
            Some(format!("`{}`: {why}", super::errors::holder_name(problem, h)))
        })
        .collect();
    if refused.is_empty() {
        return "the room has no other receptacle".to_string();
    }
    let shown = refused.len().min(6);
    let more = match refused.len() - shown {
        0 => String::new(),
        n => format!("; and {n} more"),
    };
    format!("no receptacle of the room is a home for it ({}{more})", refused[..shown].join("; "))
}

/// Why a small thing is not on the receptacle it is declared on.
fn why_elsewhere(problem: &RoomProblem, s: &super::SmallObject) -> String {
    match &s.absent {
        Some(name) => format!("its receptacle `{name}` is left out (no asset)"),
        None => format!("people do not put it on `{}`", super::errors::holder_name(problem, s.on)),
    }
}

/// The most layers of things hung on one bar (three towels over each other).
const MAX_BAR_LAYERS: usize = 3;

#[allow(clippy::too_many_arguments)]
fn hang(
    problem: &RoomProblem,
    rec: &Receptacle,
    on: Holder,
    bar_y: f64,
    length: f64,
    items: &[usize],
    results: &mut [Option<PlacedObject>],
    reasons: &mut [Option<(String, Code)>],
) {
    // Layers of things side by side along the bar.
    let mut layers: Vec<Vec<usize>> = Vec::new();
    for &i in items {
        let w = problem.small_objects[i].size[0];
        let fits = |layer: &Vec<usize>| {
            let used: f64 = layer.iter().map(|&j| problem.small_objects[j].size[0]).sum();
            layer.is_empty() || used + w <= length + 1e-9
        };
        match layers.iter().position(fits) {
            Some(l) => layers[l].push(i),
            None if layers.len() < MAX_BAR_LAYERS => layers.push(vec![i]),
            None => {
                reasons[i] = Some((
                    format!("the bar of `{}` is full ({MAX_BAR_LAYERS} layers)", rec.id),
                    Code::W0501,
                ));
            }
        }
    }
    let mut v = 0.0;
    for layer in &layers {
        let widths: f64 = layer.iter().map(|&j| problem.small_objects[j].size[0]).sum();
        let gap = ((length - widths) / (layer.len() + 1) as f64).max(0.0);
        let start = if widths > length { -widths / 2.0 } else { -length / 2.0 + gap };
        let mut u = start;
        let mut depth: f64 = 0.0;
        for &j in layer {
            let [w, d, h] = problem.small_objects[j].size;
            // Hung over the bar: its top at the bar, never below the floor.
            let y = (bar_y - h / 2.0).max(h / 2.0 - rec.base_y + 0.01);
            results[j] = Some(rec.at([u + w / 2.0, v], y, 0.0, &problem.small_objects[j].id, on));
            u += w + gap;
            depth = depth.max(d);
        }
        v += depth;
    }
}

#[allow(clippy::too_many_arguments)]
fn set_on_surfaces(
    problem: &RoomProblem,
    rec: &Receptacle,
    on: Holder,
    surfaces: &[Surface],
    items: &[usize],
    results: &mut [Option<PlacedObject>],
    reasons: &mut [Option<(String, Code)>],
) {
    let mut rows: Vec<Rows> = surfaces.iter().map(|_| Rows::default()).collect();
    for &i in items {
        let s = &problem.small_objects[i];
        let [w, d, h] = s.size;
        // The surface it is set on by itself (it may carry a pile), or `usize::MAX` on a pile.
        let mut set: Option<usize> = None;
        let mut too_big = true;
        for (n, surface) in surfaces.iter().enumerate() {
            if h > surface.headroom + 1e-9 {
                continue;
            }
            let extent = surface.extent();
            // As it is, or turned a quarter on the surface when that is what fits.
            let turns: Vec<Set> = [([w, d], 0.0), ([d, w], 90.0)]
                .into_iter()
                .filter(|&([sw, sd], _)| sw <= extent[0] + 1e-9 && sd <= extent[1] + 1e-9)
                .map(|(e, turn)| Set { item: i, extent: e, turn })
                .collect();
            if turns.is_empty() {
                continue;
            }
            too_big = false;
            if turns.iter().any(|&t| rows[n].try_set(t, extent)) {
                set = Some(n);
                break;
            }
            // No room side by side: on a pile of the same thing it fits on, if it is flat (a
            // book on a book).
            let pile = rows[n].piles.iter().position(|p| {
                p.item == s.item
                    && flat(s.size)
                    && p.height <= PILE_MAX_M + 1e-9
                    && p.height + h <= surface.headroom + 1e-9
                    && turns
                        .iter()
                        .any(|t| t.extent[0] <= p.top[0] + 1e-9 && t.extent[1] <= p.top[1] + 1e-9)
            });
            if let Some(k) = pile {
                let p = &mut rows[n].piles[k];
                let Some(&t) = turns
                    .iter()
                    .find(|t| t.extent[0] <= p.top[0] + 1e-9 && t.extent[1] <= p.top[1] + 1e-9)
                else {
                    continue;
                };
                p.on_it.push((t, p.height));
                p.top = t.extent;
                p.height += h;
                set = Some(usize::MAX);
                break;
            }
        }
        let Some(n) = set else {
            let reason = if too_big {
                format!(
                    "it is larger than every surface of `{}` ({w:.2} m × {d:.2} m × {h:.2} m, either way round)",
                    rec.id
                )
            } else {
                format!("the top of `{}` is full", rec.id)
            };
            reasons[i] = Some((reason, Code::W0501));
            continue;
        };
        // A flat thing set on its own, in the last row, may carry a pile later.
        if let Some(r) = rows.get_mut(n).filter(|_| flat(s.size)) {
            let row = r.rows.len() - 1;
            let place = r.rows[row].len() - 1;
            let top = r.rows[row][place].extent;
            r.piles.push(PileOn {
                row,
                place,
                item: s.item.clone(),
                top,
                height: h,
                on_it: Vec::new(),
            });
        }
    }
    // Spread: the rows over the surface's depth from its back (or against its back), the
    // things of a row over its width, the gaps equal.
    for (surface, r) in surfaces.iter().zip(&rows) {
        let [width, depth] = surface.extent();
        let [u0, _, v0, _] = surface.area;
        let used = r.depth_with(0.0);
        let gap_v = if surface.against_back {
            0.0
        } else {
            ((depth - used) / (r.rows.len() + 1) as f64).max(0.0)
        };
        let mut v = v0 + gap_v;
        let mut centres: Vec<Vec<[f64; 2]>> = Vec::with_capacity(r.rows.len());
        for row in &r.rows {
            let row_depth = Rows::depth(row);
            let widths: f64 = row.iter().map(|x| x.extent[0]).sum();
            let gap_u = ((width - widths) / (row.len() + 1) as f64).max(0.0);
            let mut u = u0 + gap_u;
            let mut line = Vec::with_capacity(row.len());
            for x in row {
                // Against the back, things stand at the back of their row; else centred on it.
                let vc =
                    if surface.against_back { v + x.extent[1] / 2.0 } else { v + row_depth / 2.0 };
                line.push([u + x.extent[0] / 2.0, vc]);
                u += x.extent[0] + gap_u;
            }
            centres.push(line);
            v += row_depth + SMALL_GAP_M + gap_v;
        }
        for (row, line) in r.rows.iter().zip(&centres) {
            for (x, &c) in row.iter().zip(line) {
                let s = &problem.small_objects[x.item];
                results[x.item] = Some(rec.at(c, surface.y + s.size[2] / 2.0, x.turn, &s.id, on));
            }
        }
        for p in &r.piles {
            let c = centres[p.row][p.place];
            for (t, below) in &p.on_it {
                let s = &problem.small_objects[t.item];
                let y = surface.y + below + s.size[2] / 2.0;
                results[t.item] = Some(rec.at(c, y, t.turn, &s.id, on));
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
        sized_m: None,
    });
}

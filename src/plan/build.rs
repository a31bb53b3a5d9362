//! The plan algorithm, step by step (see the module documentation for the output).

use std::collections::{BTreeMap, BTreeSet};

use rand::{Rng, SeedableRng};
use rand_chacha::ChaCha8Rng;

use super::errors::{m, pt};
use super::{
    AgentPose, FloorPlan, Hole, HoleKind, OpenConnection, PlacedDoor, PlacedWindow, PlanOptions,
    PlanRoom, Wall, DOOR_BOX_DEPTH_M, DOOR_CORNER_MARGIN_M, MAX_ROOM_SIDE_M, MIN_ROOM_SIDE_M,
    N_LAYERS, OPEN_BOX_DEPTH_M, SNAP_M, WINDOW_BOX_DEPTH_M, WINDOW_MARGIN_M, WINDOW_TOP_MARGIN_M,
};
use crate::check::scene::{Direction, DoorKind, DoorSide, DoorSize, RoomId, Scene};
use crate::diag::{Code, Diagnostic, Outcome};
use crate::geometry::{
    self as geo, add_scaled, area_centroid, box_beside, distance, near, near_point,
    point_on_segment, rectilinear_intersection_area, right_normal, segment_overlap, segments_touch,
    signed_area, Aabb, Point, EPS_M,
};
use crate::resolve::structure::{Material, StructureCatalog, Surface};
use crate::source::Span;

/// Purposes of the seeded random streams, so that adding one choice does not shift the others.
const RNG_DOOR: u64 = 1;
const RNG_SKYBOX: u64 = 2;
const RNG_DOOR_ASSET: u64 = 3;

fn rng(seed: u64, purpose: u64, index: u64) -> ChaCha8Rng {
    // SplitMix64 of (purpose, index) mixed into the seed.
    let mut z =
        purpose.wrapping_mul(0x9E37_79B9_7F4A_7C15) ^ index.wrapping_add(0x632B_E59B_D9B4_E019);
    z = (z ^ (z >> 30)).wrapping_mul(0xBF58_476D_1CE4_E5B9);
    z = (z ^ (z >> 27)).wrapping_mul(0x94D0_49BB_1331_11EB);
    z ^= z >> 31;
    ChaCha8Rng::seed_from_u64(seed ^ z)
}

struct Ctx<'a> {
    scene: &'a Scene,
    catalog: &'a StructureCatalog,
    options: PlanOptions,
    diags: Vec<Diagnostic>,
    rooms: Vec<PlanRoom>,
    walls: Vec<Wall>,
    doors: Vec<PlacedDoor>,
    windows: Vec<PlacedWindow>,
    open: Vec<OpenConnection>,
    /// Where each room's walls are in `walls` (rooms in order, each room's walls together),
    /// until the windows split walls.
    room_walls: Vec<std::ops::Range<usize>>,
    /// Each wall id's first place in `walls`, until the windows split walls.
    wall_ids: rustc_hash::FxHashMap<String, usize>,
}

pub(crate) fn run(
    scene: &Scene,
    catalog: &StructureCatalog,
    options: PlanOptions,
) -> Outcome<FloorPlan> {
    let mut ctx = Ctx {
        scene,
        catalog,
        options,
        diags: Vec::new(),
        rooms: Vec::new(),
        walls: Vec::new(),
        doors: Vec::new(),
        windows: Vec::new(),
        open: Vec::new(),
        room_walls: Vec::new(),
        wall_ids: rustc_hash::FxHashMap::default(),
    };
    let ok = ctx.outlines() && ctx.relations();
    if ok {
        ctx.make_walls();
        ctx.open_connections();
        ctx.place_doors();
        ctx.reachability();
        ctx.place_windows();
        if !options.geometry_only {
            ctx.materials();
        }
        ctx.layers();
    }
    let sky_pick = rng(scene.seed, RNG_SKYBOX, 0).gen::<u64>();
    let sky = catalog.skybox(sky_pick);
    let agent = if ok && !ctx.rooms.is_empty() {
        ctx.agent_pose()
    } else {
        AgentPose { room: RoomId(0), position: [0.0, 0.0], rotation_deg: 0.0 }
    };
    let ceiling_material =
        if options.geometry_only { String::new() } else { ctx.ceiling_material() };
    let plan = FloorPlan {
        seed: scene.seed,
        wall_height_m: scene.wall_height_m,
        rooms: ctx.rooms,
        walls: ctx.walls,
        doors: ctx.doors,
        windows: ctx.windows,
        open_connections: ctx.open,
        skybox: sky.name.to_owned(),
        time_of_day: sky.time_of_day.to_owned(),
        ceiling_material,
        agent,
    };
    Outcome::new(plan, ctx.diags)
}

/// Words of material names no ceiling is made of.
const UNLIKELY_CEILINGS: [&str; 8] =
    ["countertop", "marble", "tile", "carpet", "fabric", "granite", "rug", "grass"];

/// The material every ceiling falls back on: a painted white drywall.
pub const DEFAULT_CEILING_MATERIAL: &str = "EggshellDrywall";
/// The most overlaps counted for one room as the sweep meets them (see `relations`): past it
/// the plan's counts are lower bounds and the work stays linear in the rooms.
const OVERLAPS_COUNTED_PER_ROOM: usize = 64;
/// Once the plan has an overlap, the most rooms whose bounds meet a room's that the sweep of
/// `relations` intersects it with (before, it looks at all of them: it must find the first).
const CANDIDATES_PER_ROOM: usize = 256;
/// Past `PAIR_DETAIL_LIMIT` overlapping pairs, the rooms given a diagnostic of their own; the
/// others get one together ("… and K more rooms overlap others").
pub const OVERLAP_ROOMS_SHOWN: usize = 1000;

/// A key that orders finite and infinite floats as `f64::total_cmp` does.
fn sort_key(v: f64) -> u64 {
    let bits = v.to_bits();
    if bits >> 63 == 1 {
        !bits
    } else {
        bits | (1 << 63)
    }
}

/// Keeps in `list` (sorted, `usize::MAX` for none) the smallest of its numbers and `value`.
fn keep_smallest(list: &mut [usize; 3], value: usize) {
    if list.contains(&value) {
        return;
    }
    let mut v = value;
    for slot in list.iter_mut() {
        if v < *slot {
            std::mem::swap(slot, &mut v);
        }
    }
}

/// The side of the cells the plan finds nearby corners and walls by (`grid.rs`), metres.
const GRID_CELL_M: f64 = 2.0;
/// How far beyond a wall the plan looks for corners on it and walls along it, metres: far
/// more than the tolerance of its tests ([`EPS_M`]), so that nothing they accept is missed.
const GRID_MARGIN_M: f64 = 1e-3;

/// The default ceiling: the first room's wall material when it is a painted finish (drywall or
/// plaster), so ceiling and walls match; otherwise (brick, tile, marble, wood panelling…) a
/// painted white drywall, as real ceilings are.
fn default_ceiling_material(first_wall: Option<&str>) -> String {
    match first_wall {
        Some(m) if ["drywall", "plaster"].iter().any(|w| m.to_lowercase().contains(w)) => {
            m.to_owned()
        }
        _ => DEFAULT_CEILING_MATERIAL.to_owned(),
    }
}

/// Removes repeated and straight-through corners, makes the outline clockwise and starts it at
/// the minimal-x (then minimal-z) corner.
fn normalise(corners: &[Point]) -> Vec<Point> {
    let mut pts: Vec<Point> = Vec::new();
    for &p in corners {
        if pts.last().is_none_or(|&q| !near_point(p, q)) {
            pts.push(p);
        }
    }
    while pts.len() > 1 && near_point(pts[0], pts[pts.len() - 1]) {
        pts.pop();
    }
    // Drop corners where the outline goes straight on.
    let mut changed = true;
    while changed && pts.len() > 3 {
        changed = false;
        let n = pts.len();
        for i in 0..n {
            let (a, b, c) = (pts[(i + n - 1) % n], pts[i], pts[(i + 1) % n]);
            let cross = (b[0] - a[0]) * (c[1] - b[1]) - (b[1] - a[1]) * (c[0] - b[0]);
            let dot = (b[0] - a[0]) * (c[0] - b[0]) + (b[1] - a[1]) * (c[1] - b[1]);
            if cross.abs() <= EPS_M * EPS_M && dot > 0.0 {
                pts.remove(i);
                changed = true;
                break;
            }
        }
    }
    if signed_area(&pts) > 0.0 {
        pts.reverse();
    }
    rotate_to_min(&mut pts);
    pts
}

fn rotate_to_min(pts: &mut [Point]) {
    if pts.is_empty() {
        return;
    }
    let mut best = 0;
    for (i, p) in pts.iter().enumerate() {
        let b = pts[best];
        if p[0] < b[0] - EPS_M || (near(p[0], b[0]) && p[1] < b[1] - EPS_M) {
            best = i;
        }
    }
    pts.rotate_left(best);
}

impl Ctx<'_> {
    fn room_name(&self, id: RoomId) -> &str {
        &self.scene.rooms[id.0].name
    }

    fn thor_name(&self, side: DoorSide) -> String {
        match side {
            DoorSide::Exterior => "exterior".to_owned(),
            DoorSide::Room(r) => self.rooms[r.0].thor_id.clone(),
        }
    }

    /// Snaps, normalises and checks every outline. Returns whether all are usable.
    fn outlines(&mut self) -> bool {
        let scene = self.scene;
        // Snap coordinates, axis by axis, to the first value written within SNAP_M.
        let mut anchors: [Anchors; 2] = [Anchors::default(), Anchors::default()];
        let mut snapped: Vec<Vec<Point>> = Vec::new();
        self.rooms.reserve_exact(scene.rooms.len());
        for room in &scene.rooms {
            let mut corners = Vec::new();
            for (ci, &c) in room.corners.iter().enumerate() {
                let mut p = c;
                for axis in 0..2 {
                    let v = c[axis];
                    if let Some(a) = anchors[axis].find(v) {
                        p[axis] = a;
                    } else {
                        anchors[axis].push(v);
                    }
                }
                // Only corners moved onto another room's value are worth a warning.
                if !near_point(p, c) {
                    let span = room.corner_spans.get(ci).copied().unwrap_or(room.decl_span);
                    self.diags.push(
                        Diagnostic::new(
                            Code::W0301,
                            format!("corner {} of room `{}` moved to {}", pt(c), room.name, pt(p)),
                        )
                        .with_primary(
                            span,
                            format!("within {} of a coordinate written earlier", m(SNAP_M)),
                        )
                        .with_help("write the same coordinate in both places")
                        .with_fixes(room.corner_spans.get(ci).map(
                            |&span| crate::diag::Fix {
                                title: format!("snap the corner to {}", pt(p)),
                                span,
                                replacement: format!(
                                    "({} m, {} m)",
                                    crate::ast::format_number(p[0]),
                                    crate::ast::format_number(p[1])
                                ),
                            },
                        )),
                    );
                }
                corners.push(p);
            }
            snapped.push(corners);
        }

        let mut labels: BTreeMap<String, usize> = BTreeMap::new();
        let mut all_ok = true;
        for (room, corners) in scene.rooms.iter().zip(&snapped) {
            let pts = normalise(corners);
            let mut ok = true;
            let corner_span =
                |i: usize| room.corner_spans.get(i).copied().unwrap_or(room.name_span);
            // Rectilinear: every side parallel to an axis (checked on the corners as written).
            for i in 0..corners.len() {
                let (a, b) = (corners[i], corners[(i + 1) % corners.len()]);
                if !geo::is_axis_aligned(a, b) {
                    self.diags.push(
                        Diagnostic::new(
                            Code::E0301,
                            format!(
                                "the side of room `{}` from {} to {} is not parallel to an axis",
                                room.name,
                                pt(a),
                                pt(b)
                            ),
                        )
                        .with_primary(corner_span(i), "this side runs at an angle")
                        .with_secondary(corner_span((i + 1) % corners.len()), "to here")
                        .with_help(
                            "rooms are rectilinear: make the two corners share their x or their z",
                        ),
                    );
                    ok = false;
                    break;
                }
            }
            if ok && (pts.len() < 4 || signed_area(&pts).abs() <= EPS_M) {
                self.diags.push(
                    Diagnostic::new(
                        Code::E0301,
                        format!("the outline of room `{}` has no area", room.name),
                    )
                    .with_primary(room.name_span, "declared here")
                    .with_help("give the room corners that enclose some floor"),
                );
                ok = false;
            }
            if ok {
                // Simple polygon: non-adjacent sides never touch.
                let n = pts.len();
                'outer: for i in 0..n {
                    for j in i + 2..n {
                        if i == 0 && j == n - 1 {
                            continue;
                        }
                        if segments_touch(pts[i], pts[(i + 1) % n], pts[j], pts[(j + 1) % n]) {
                            self.diags.push(
                                Diagnostic::new(
                                    Code::E0302,
                                    format!("the outline of room `{}` crosses itself", room.name),
                                )
                                .with_primary(
                                    room.name_span,
                                    "its corners are not in order around the room",
                                )
                                .with_note(format!(
                                    "the side {}–{} meets the side {}–{}",
                                    pt(pts[i]),
                                    pt(pts[(i + 1) % n]),
                                    pt(pts[j]),
                                    pt(pts[(j + 1) % n])
                                ))
                                .with_help("list the corners in order around the room"),
                            );
                            ok = false;
                            break 'outer;
                        }
                    }
                }
            }
            let bbox = Aabb::of(&pts);
            let area = signed_area(&pts).abs();
            if ok {
                let narrow = bbox.width().min(bbox.depth());
                let wide = bbox.width().max(bbox.depth());
                if narrow < MIN_ROOM_SIDE_M - EPS_M || area < 1.0 - EPS_M {
                    self.diags.push(
                        Diagnostic::new(
                            Code::E0303,
                            format!(
                                "room `{}` is {} m by {} m, smaller than allowed",
                                room.name,
                                m(bbox.width()),
                                m(bbox.depth())
                            ),
                        )
                        .with_primary(room.name_span, format!("{} m²", m(area)))
                        .with_help(format!(
                            "make every room at least {} m wide and 1 m² in area",
                            m(MIN_ROOM_SIDE_M)
                        )),
                    );
                    ok = false;
                } else if wide > MAX_ROOM_SIDE_M + EPS_M {
                    self.diags.push(
                        Diagnostic::new(
                            Code::E0304,
                            format!(
                                "room `{}` is {} m by {} m, larger than allowed",
                                room.name,
                                m(bbox.width()),
                                m(bbox.depth())
                            ),
                        )
                        .with_primary(room.name_span, "declared here")
                        .with_help(format!(
                            "split it into rooms at most {} m wide",
                            m(MAX_ROOM_SIDE_M)
                        )),
                    );
                    ok = false;
                }
            }
            all_ok &= ok;
            let count = labels.entry(room.label.clone()).or_insert(0);
            let thor_id = if *count == 0 {
                room.label.clone()
            } else {
                format!("{}-{}", room.label, room.id.0)
            };
            *count += 1;
            self.rooms.push(PlanRoom {
                id: room.id,
                thor_id,
                centroid: area_centroid(&pts),
                area_m2: area,
                polygon: pts.clone(),
                corners: pts,
                floor_material: String::new(),
                wall_material: String::new(),
                floor_tint: None,
                wall_tint: None,
                layer: 0,
                door_keep_out: Vec::new(),
                open_boxes: Vec::new(),
                window_segments: Vec::new(),
                name_span: room.name_span,
            });
        }
        all_ok
    }

    fn shared_length(&self, a: usize, b: usize) -> f64 {
        let (p, q) = (&self.rooms[a].corners, &self.rooms[b].corners);
        let mut total = 0.0;
        for i in 0..p.len() {
            for j in 0..q.len() {
                if let Some((s, e)) =
                    segment_overlap(p[i], p[(i + 1) % p.len()], q[j], q[(j + 1) % q.len()])
                {
                    total += distance(s, e);
                }
            }
        }
        total
    }

    /// E0305 or E0306 for two rooms whose floors share `inter` square metres.
    fn overlap_diagnostic(&self, a: usize, b: usize, inter: f64) -> Diagnostic {
        let (ra, rb) = (&self.rooms[a], &self.rooms[b]);
        let (na, nb) = (self.room_name(RoomId(a)), self.room_name(RoomId(b)));
        if near(inter, ra.area_m2) || inter >= ra.area_m2 - 1e-4 {
            Diagnostic::new(Code::E0306, format!("room `{na}` lies inside room `{nb}`"))
                .with_primary(ra.name_span, "this room")
                .with_secondary(rb.name_span, "is inside this one")
                .with_help(format!("cut `{na}` out of the outline of `{nb}`, or move it"))
        } else if inter >= rb.area_m2 - 1e-4 {
            Diagnostic::new(Code::E0306, format!("room `{nb}` lies inside room `{na}`"))
                .with_primary(rb.name_span, "this room")
                .with_secondary(ra.name_span, "is inside this one")
                .with_help(format!("cut `{nb}` out of the outline of `{na}`, or move it"))
        } else {
            Diagnostic::new(
                Code::E0305,
                format!("rooms `{na}` and `{nb}` overlap by {} m²", m(inter)),
            )
            .with_primary(rb.name_span, format!("overlaps `{na}`"))
            .with_secondary(ra.name_span, format!("overlaps `{nb}`"))
            .with_help("move the corners so that the rooms only share walls")
        }
    }

    /// Overlap, containment, isolation and connectivity. Returns whether the plan is valid.
    fn relations(&mut self) -> bool {
        let n = self.rooms.len();
        let mut ok = true;
        let mut adjacent = vec![Vec::new(); n];
        // Pairs whose outlines' bounds meet, by a sweep along x that keeps the rooms it has
        // passed and that still reach the current x ordered by their lowest z: a room meets
        // only those whose lowest z lies between its own bounds widened by the tallest room's
        // depth. Near-linear in the rooms however they are laid out (a column of rooms along z
        // cost the square of their number with a sweep along x alone).
        let boxes: Vec<Aabb> = self.rooms.iter().map(|r| Aabb::of(&r.corners)).collect();
        let tallest = boxes.iter().map(Aabb::depth).fold(0.0, f64::max);
        let mut by_x: Vec<usize> = (0..n).collect();
        by_x.sort_by(|&i, &j| boxes[i].min[0].total_cmp(&boxes[j].min[0]).then(i.cmp(&j)));
        let mut active: BTreeSet<(u64, usize)> = BTreeSet::new();
        let mut ends: std::collections::BinaryHeap<std::cmp::Reverse<(u64, usize)>> =
            std::collections::BinaryHeap::new();
        // A room's overlaps are counted up to `OVERLAPS_COUNTED_PER_ROOM` as the sweep meets
        // them, and once the plan is known to be wrong at most `CANDIDATES_PER_ROOM` rooms are
        // looked at for each, so that thousands of rooms drawn over each other cost a bounded
        // number of exact intersections each (the plan is an error either way; its counts then
        // say "at least"). Past `PAIR_DETAIL_LIMIT` pairs only each room's count and first
        // partners are kept: memory linear in the rooms, not in the pairs.
        let mut overlaps: Vec<(usize, usize, f64)> = Vec::new();
        let mut pairs = 0usize;
        let mut counts = vec![0u32; n];
        let mut partners = vec![[usize::MAX; 3]; n];
        let mut touching: Vec<(usize, usize)> = Vec::new();
        let mut capped = false;
        for &i in &by_x {
            while let Some(&std::cmp::Reverse((end, j))) = ends.peek() {
                if end >= sort_key(boxes[i].min[0] - EPS_M) {
                    break;
                }
                ends.pop();
                active.remove(&(sort_key(boxes[j].min[1]), j));
            }
            let low = sort_key(boxes[i].min[1] - tallest - 2.0 * EPS_M);
            let high = sort_key(boxes[i].max[1] + EPS_M);
            let (mut hits, mut looked) = (0usize, 0usize);
            for &(_, j) in active.range((low, 0)..=(high, usize::MAX)) {
                if boxes[i].min[1] > boxes[j].max[1] + EPS_M {
                    continue;
                }
                if !ok && looked >= CANDIDATES_PER_ROOM {
                    capped = true;
                    break;
                }
                looked += 1;
                let (a, b) = (i.min(j), i.max(j));
                let inter =
                    rectilinear_intersection_area(&self.rooms[a].corners, &self.rooms[b].corners);
                if inter > 1e-4 {
                    ok = false;
                    touching = Vec::new();
                    pairs += 1;
                    if overlaps.len() <= crate::diag::PAIR_DETAIL_LIMIT {
                        overlaps.push((a, b, inter));
                    }
                    for (x, y) in [(a, b), (b, a)] {
                        counts[x] = counts[x].saturating_add(1);
                        keep_smallest(&mut partners[x], y);
                    }
                    hits += 1;
                    if hits >= OVERLAPS_COUNTED_PER_ROOM {
                        capped = true;
                        break;
                    }
                } else if ok && self.shared_length(a, b) > EPS_M {
                    touching.push((a, b));
                }
            }
            active.insert((sort_key(boxes[i].min[1]), i));
            ends.push(std::cmp::Reverse((sort_key(boxes[i].max[0]), i)));
        }
        drop((active, ends));
        overlaps.sort_unstable_by_key(|x| (x.0, x.1));
        touching.sort_unstable();
        for &(a, b) in &touching {
            adjacent[a].push(b);
            adjacent[b].push(a);
        }
        if pairs <= crate::diag::PAIR_DETAIL_LIMIT {
            for &(a, b, inter) in &overlaps {
                let d = self.overlap_diagnostic(a, b, inter);
                self.diags.push(d);
            }
        } else {
            // Many pairs: one diagnostic per room that overlaps others, with their number, for
            // the first `OVERLAP_ROOMS_SHOWN` such rooms; then one for all the others.
            let note = if capped {
                format!(
                    "at least {pairs} pairs of rooms overlap; past {} they are counted per room, and the counts are lower bounds (each room is compared with at most {OVERLAPS_COUNTED_PER_ROOM} of the rooms before it that it overlaps)",
                    crate::diag::PAIR_DETAIL_LIMIT
                )
            } else {
                format!(
                    "{pairs} pairs of rooms overlap; past {} they are counted per room",
                    crate::diag::PAIR_DETAIL_LIMIT
                )
            };
            let mut rooms = (0..n).filter(|&a| counts[a] > 0);
            for a in rooms.by_ref().take(OVERLAP_ROOMS_SHOWN) {
                let name = self.room_name(RoomId(a)).to_owned();
                let count = counts[a];
                let mut d = Diagnostic::new(
                    Code::E0305,
                    format!(
                        "room `{name}` overlaps {}{count} other room{}",
                        if capped { "at least " } else { "" },
                        if count == 1 { "" } else { "s" }
                    ),
                )
                .with_primary(self.rooms[a].name_span, "this room");
                for &b in partners[a].iter().filter(|&&b| b != usize::MAX) {
                    d = d.with_secondary(
                        self.rooms[b].name_span,
                        format!("overlaps `{}`", self.room_name(RoomId(b))),
                    );
                }
                d = d
                    .with_note(note.clone())
                    .with_help("move the corners so that the rooms only share walls");
                self.diags.push(d);
            }
            if let Some(first) = rooms.next() {
                let more = 1 + rooms.count();
                let name = self.room_name(RoomId(first)).to_owned();
                self.diags.push(
                    Diagnostic::new(
                        Code::E0305,
                        format!(
                            "… and {more} more room{} overlap{} others, from `{name}` on",
                            if more == 1 { "" } else { "s" },
                            if more == 1 { "s" } else { "" }
                        ),
                    )
                    .with_primary(self.rooms[first].name_span, "the first of them")
                    .with_note(note)
                    .with_note(format!(
                        "one diagnostic is given for each of the first {OVERLAP_ROOMS_SHOWN} rooms that overlap others"
                    ))
                    .with_help("move the corners so that the rooms only share walls"),
                );
            }
        }
        if !ok || n < 2 {
            return ok;
        }
        self.gaps();
        let mut isolated = BTreeSet::new();
        for (a, neighbours) in adjacent.iter().enumerate() {
            if neighbours.is_empty() {
                isolated.insert(a);
                ok = false;
                self.diags.push(
                    Diagnostic::new(
                        Code::E0307,
                        format!(
                            "room `{}` shares no wall with any other room",
                            self.room_name(RoomId(a))
                        ),
                    )
                    .with_primary(self.rooms[a].name_span, "touches no other room")
                    .with_help("move it so that one of its sides lies against another room"),
                );
            }
        }
        // Components among rooms that have neighbours.
        let mut comp = vec![usize::MAX; n];
        let mut groups: Vec<Vec<usize>> = Vec::new();
        for start in 0..n {
            if comp[start] != usize::MAX || isolated.contains(&start) {
                continue;
            }
            let g = groups.len();
            let mut stack = vec![start];
            let mut members = Vec::new();
            comp[start] = g;
            while let Some(r) = stack.pop() {
                members.push(r);
                for &o in &adjacent[r] {
                    if comp[o] == usize::MAX {
                        comp[o] = g;
                        stack.push(o);
                    }
                }
            }
            members.sort_unstable();
            groups.push(members);
        }
        if groups.len() > 1 {
            ok = false;
            let names = |g: &[usize]| {
                g.iter()
                    .map(|&r| format!("`{}`", self.room_name(RoomId(r))))
                    .collect::<Vec<_>>()
                    .join(", ")
            };
            let mut d = Diagnostic::new(
                Code::E0308,
                format!(
                    "the plan falls apart into {} groups of rooms that share no wall",
                    groups.len()
                ),
            )
            .with_primary(self.rooms[groups[1][0]].name_span, "this group…")
            .with_secondary(self.rooms[groups[0][0]].name_span, "…shares no wall with this one")
            .with_help("move one group so that it shares a wall with the other");
            for g in &groups {
                d = d.with_note(format!("group: {}", names(g)));
            }
            self.diags.push(d);
        }
        ok
    }

    /// Warns (W0308) about rooms whose walls face each other across a gap of at most the
    /// repair's bound, with a fix that moves the shorter wall onto the other.
    fn gaps(&mut self) {
        let corners: Vec<Vec<Point>> = self.rooms.iter().map(|r| r.corners.clone()).collect();
        for gap in super::repair::facing_gaps(&corners) {
            let (moving, staying) = (RoomId(gap.moving), RoomId(gap.staying));
            let (mn, sn) = (self.room_name(moving).to_owned(), self.room_name(staying).to_owned());
            let axis = if gap.axis == 0 { "x" } else { "z" };
            let mut d = Diagnostic::new(
                Code::W0308,
                format!(
                    "rooms `{mn}` and `{sn}` face each other across a gap of {} m",
                    m(gap.width())
                ),
            )
            .with_primary(self.rooms[gap.moving].name_span, format!("{} m from `{sn}`", m(gap.width())))
            .with_secondary(self.rooms[gap.staying].name_span, "across the gap")
            .with_help(format!(
                "move the wall of `{mn}` at {axis} = {} m to {axis} = {} m so that the rooms share it (`holoc repair --write` joins them)",
                m(gap.from),
                m(gap.to)
            ));
            let room = &self.scene.rooms[gap.moving];
            let moved = super::repair::with_wall_moved(&room.corners, gap.axis, gap.from, gap.to);
            if let Some(fix) = super::repair::corner_fix(room, &moved) {
                d = d.with_fix(fix);
            }
            self.diags.push(d);
        }
    }

    /// Splits outlines at neighbours' corners and makes one wall per piece.
    fn make_walls(&mut self) {
        let n = self.rooms.len();
        let all: Vec<Point> = self.rooms.iter().flat_map(|r| r.corners.clone()).collect();
        // The corners by where they are: a wall looks only at those near it (`grid`), in the
        // order of `all`, with the same test.
        let mut corners_at = super::grid::Grid::new(GRID_CELL_M);
        for p in &all {
            corners_at.push(*p, *p);
        }
        for r in 0..n {
            let corners = self.rooms[r].corners.clone();
            let mut full = Vec::new();
            for i in 0..corners.len() {
                let (a, b) = (corners[i], corners[(i + 1) % corners.len()]);
                full.push(a);
                let (min, max) = super::grid::widened_box(&[a, b], GRID_MARGIN_M);
                let mut inner: Vec<Point> = corners_at
                    .query(min, max)
                    .into_iter()
                    .map(|k| all[k])
                    .filter(|&p| {
                        point_on_segment(p, a, b) && !near_point(p, a) && !near_point(p, b)
                    })
                    .collect();
                inner.sort_by(|p, q| distance(a, *p).total_cmp(&distance(a, *q)));
                inner.dedup_by(|p, q| near_point(*p, *q));
                full.extend(inner);
            }
            self.rooms[r].polygon = full;
        }
        // Every side of every polygon by where it is, numbered room by room.
        let mut sides_at = super::grid::Grid::new(GRID_CELL_M);
        let mut side_of: Vec<(usize, usize)> = Vec::new();
        for (o, room) in self.rooms.iter().enumerate() {
            let op = &room.polygon;
            for k in 0..op.len() {
                let (min, max) = super::grid::widened_box(&[op[k], op[(k + 1) % op.len()]], 0.0);
                sides_at.push(min, max);
                side_of.push((o, k));
            }
        }
        let mut walls = Vec::new();
        self.room_walls = Vec::with_capacity(n);
        for r in 0..n {
            let poly = self.rooms[r].polygon.clone();
            self.room_walls.push(walls.len()..walls.len() + poly.len());
            for j in 0..poly.len() {
                let (p, q) = (poly[j], poly[(j + 1) % poly.len()]);
                let d = geo::sub(q, p);
                let direction = if d[0].abs() >= d[1].abs() {
                    if d[0] > 0.0 {
                        Direction::North
                    } else {
                        Direction::South
                    }
                } else if d[1] > 0.0 {
                    Direction::West
                } else {
                    Direction::East
                };
                // The last side of another room (in room order, then side order) that runs
                // along this one: only sides near it can.
                let (min, max) = super::grid::widened_box(&[p, q], GRID_MARGIN_M);
                let neighbour = sides_at
                    .query(min, max)
                    .into_iter()
                    .rev()
                    .map(|s| side_of[s])
                    .find(|&(o, k)| {
                        let op = &self.rooms[o].polygon;
                        o != r && segment_overlap(p, q, op[k], op[(k + 1) % op.len()]).is_some()
                    })
                    .map(|(o, k)| (RoomId(o), k));
                walls.push((r, j, direction, p, q, neighbour));
            }
        }
        // Wall ids are known once every wall exists.
        let id_of = |r: usize, j: usize, dir: Direction| {
            format!("wall|{}|{}|{}", self.rooms[r].thor_id, dir.as_str(), j)
        };
        let dir_of: BTreeMap<(usize, usize), Direction> =
            walls.iter().map(|w| ((w.0, w.1), w.2)).collect();
        for &(r, j, direction, p, q, neighbour) in &walls {
            let neighbour =
                neighbour.and_then(|(o, k)| dir_of.get(&(o.0, k)).map(|&d| (o, id_of(o.0, k, d))));
            self.walls.push(Wall {
                id: id_of(r, j, direction),
                room: RoomId(r),
                direction,
                start: p,
                end: q,
                width_m: distance(p, q),
                exterior: neighbour.is_none(),
                neighbour,
                empty: false,
                hole: None,
            });
        }
        self.wall_ids = rustc_hash::FxHashMap::default();
        for (i, wall) in self.walls.iter().enumerate() {
            self.wall_ids.entry(wall.id.clone()).or_insert(i);
        }
    }

    /// The first wall of this id (looked up by id until the windows split walls).
    fn wall_index(&self, id: &str) -> Option<usize> {
        self.wall_ids.get(id).copied()
    }

    /// Whether two rooms' outlines have a corner in common.
    fn meet_at_a_corner(&self, a: RoomId, b: RoomId) -> bool {
        let (ra, rb) = (&self.rooms[a.0].corners, &self.rooms[b.0].corners);
        ra.iter().any(|p| rb.iter().any(|q| near_point(*p, *q)))
    }

    fn rooms_not_adjacent(&mut self, spans: [Span; 2], a: RoomId, b: RoomId) {
        let (na, nb) = (self.room_name(a).to_owned(), self.room_name(b).to_owned());
        self.diags.push(
            Diagnostic::new(Code::E0309, format!("rooms `{na}` and `{nb}` share no wall"))
                .with_primary(spans[1], format!("`{nb}` shares no wall with `{na}`"))
                .with_secondary(spans[0], "first room")
                .with_secondary(self.rooms[a.0].name_span, format!("`{na}` declared here"))
                .with_secondary(self.rooms[b.0].name_span, format!("`{nb}` declared here"))
                .with_note(if self.meet_at_a_corner(a, b) {
                    "the two rooms meet only at a corner; a door needs a stretch of wall they share"
                } else {
                    "the two rooms do not touch"
                })
                .with_help("connect rooms that share a wall"),
        );
    }

    fn open_connections(&mut self) {
        for door in &self.scene.doors {
            if door.kind != DoorKind::Open {
                continue;
            }
            let (DoorSide::Room(a), DoorSide::Room(b)) = (door.from, door.to) else {
                self.diags.push(
                    Diagnostic::new(Code::E0312, "an open connection cannot lead outside")
                        .with_primary(door.span, "`open` with `exterior`")
                        .with_help("use a doorway or a doorframe to the exterior"),
                );
                continue;
            };
            let shared: Vec<usize> = (0..self.walls.len())
                .filter(|&i| {
                    self.walls[i].room == a
                        && self.walls[i].neighbour.as_ref().is_some_and(|n| n.0 == b)
                })
                .collect();
            if shared.is_empty() {
                self.rooms_not_adjacent(door.side_spans, a, b);
                continue;
            }
            let mut segments = Vec::new();
            for i in shared {
                let w = self.walls[i].clone();
                self.walls[i].empty = true;
                if let Some(other) = w.neighbour.as_ref().and_then(|n| self.wall_index(&n.1)) {
                    self.walls[other].empty = true;
                }
                let nrm = right_normal(w.start, w.end);
                self.rooms[a.0].open_boxes.push(box_beside(w.start, w.end, nrm, OPEN_BOX_DEPTH_M));
                self.rooms[b.0].open_boxes.push(box_beside(
                    w.start,
                    w.end,
                    [-nrm[0], -nrm[1]],
                    OPEN_BOX_DEPTH_M,
                ));
                segments.push((w.start, w.end));
            }
            self.open.push(OpenConnection { rooms: (a, b), segments, span: door.span });
        }
    }

    fn free(&self, i: usize) -> bool {
        let w = &self.walls[i];
        !w.empty
            && w.hole.is_none()
            && w.neighbour
                .as_ref()
                .and_then(|n| self.wall_index(&n.1))
                .is_none_or(|o| self.walls[o].hole.is_none())
    }

    /// Candidate walls for a connection, seen from a real room `a`.
    fn candidates(&self, a: RoomId, other: DoorSide) -> Vec<usize> {
        // Only room `a`'s walls can be `a`'s (they are together, in order).
        self.room_walls
            .get(a.0)
            .cloned()
            .unwrap_or(0..0)
            .filter(|&i| {
                let w = &self.walls[i];
                w.room == a
                    && !w.empty
                    && match other {
                        DoorSide::Exterior => w.exterior,
                        DoorSide::Room(b) => w.neighbour.as_ref().is_some_and(|n| n.0 == b),
                    }
            })
            .collect()
    }

    /// Places one door between `from` and `to`; returns false (with a diagnostic) when it fails.
    fn place_door(
        &mut self,
        index: usize,
        from: DoorSide,
        to: DoorSide,
        kind: DoorKind,
        size: DoorSize,
        style: Option<&str>,
        pinned: Option<&crate::check::scene::Pinned>,
        span: Option<Span>,
        spans: [Span; 2],
    ) -> bool {
        let (room, other) = match (from, to) {
            (DoorSide::Room(a), o) => (a, o),
            (DoorSide::Exterior, DoorSide::Room(b)) => (b, DoorSide::Exterior),
            (DoorSide::Exterior, DoorSide::Exterior) => return false,
        };
        let asset = if let Some(pin) = pinned {
            if let Some(a) = self.catalog.door(&pin.id) {
                a.clone()
            } else {
                let names: Vec<&str> = self.catalog.doors.iter().map(|d| d.asset_id).collect();
                self.diags.push(
                    Diagnostic::new(Code::E0313, format!("`{}` is not a door asset", pin.id))
                        .with_primary(pin.span, "not in the door catalog")
                        .with_quoted_suggestions(pin.span, &pin.id, names)
                        .with_note("door assets are `Doorway_*`, `Doorway_Double_*`, `Doorframe_*` and `Doorframe_Double_*`"),
                );
                return false;
            }
        } else {
            let pick = rng(self.scene.seed, RNG_DOOR_ASSET, index as u64).gen::<u64>();
            let Some(a) = self.catalog.select_door(kind, size, style, pick) else {
                self.diags.push(Diagnostic::internal(
                    "the door catalog has no door of this kind and size",
                ));
                return false;
            };
            a.clone()
        };
        let width = asset.bbox_m[0];
        let need = width + 2.0 * DOOR_CORNER_MARGIN_M;
        let cands = self.candidates(room, other);
        let primary = span.unwrap_or(self.rooms[room.0].name_span);
        if cands.is_empty() {
            if let DoorSide::Room(b) = other {
                self.rooms_not_adjacent(spans, room, b);
            } else {
                self.diags.push(
                    Diagnostic::new(
                        Code::E0310,
                        format!("room `{}` has no outside wall for a door", self.room_name(room)),
                    )
                    .with_primary(primary, "door to the exterior")
                    .with_help("connect the exterior to a room on the outside of the house"),
                );
            }
            return false;
        }
        let free: Vec<usize> = cands.iter().copied().filter(|&i| self.free(i)).collect();
        // Prefer walls on sides that no window row of the room asks for, then the longest.
        let window_sides: Vec<Direction> =
            self.scene.rooms[room.0].windows.iter().map(|w| w.wall).collect();
        let rank =
            |i: usize| (!window_sides.contains(&self.walls[i].direction), self.walls[i].width_m);
        let mut best: Option<usize> = None;
        for &i in &free {
            if self.walls[i].width_m + EPS_M >= need {
                let better = best.is_none_or(|b| {
                    let (ri, rb) = (rank(i), rank(b));
                    (ri.0 && !rb.0) || (ri.0 == rb.0 && ri.1 > rb.1 + EPS_M)
                });
                if better {
                    best = Some(i);
                }
            }
        }
        let Some(wi) = best else {
            let what = match other {
                DoorSide::Exterior => format!("the outside walls of `{}`", self.room_name(room)),
                DoorSide::Room(b) => format!(
                    "the walls between `{}` and `{}`",
                    self.room_name(room),
                    self.room_name(b)
                ),
            };
            if free.is_empty() {
                self.diags.push(
                    Diagnostic::new(
                        Code::E0311,
                        format!("every one of {what} already has a door or window"),
                    )
                    .with_primary(primary, "no free wall for this door")
                    .with_help("AI2-THOR allows one hole per wall; move one of the openings"),
                );
            } else {
                let longest = free.iter().map(|&i| self.walls[i].width_m).fold(0.0, f64::max);
                self.diags.push(
                    Diagnostic::new(
                        Code::E0310,
                        format!(
                            "the door ({} m wide) does not fit on {what} (longest free wall {} m)",
                            m(width),
                            m(longest)
                        ),
                    )
                    .with_primary(primary, format!("needs {} m of wall", m(need)))
                    .with_help("use a single door, or make the shared wall longer"),
                );
            }
            return false;
        };
        let wall = self.walls[wi].clone();
        let l = wall.width_m;
        let u: f64 = rng(self.scene.seed, RNG_DOOR, index as u64).gen();
        let room_span = l - need;
        let s_int = DOOR_CORNER_MARGIN_M + ((u * room_span) * 100.0).floor() / 100.0;
        let s_int = s_int.min(l - DOOR_CORNER_MARGIN_M - width);
        let dir = geo::unit(wall.start, wall.end);
        let p1 = add_scaled(wall.start, dir, s_int);
        let p2 = add_scaled(wall.start, dir, s_int + width);
        // Keep-out boxes on the room side(s).
        let nrm = right_normal(wall.start, wall.end);
        self.rooms[room.0].door_keep_out.push(box_beside(p1, p2, nrm, DOOR_BOX_DEPTH_M));
        let neighbour_idx = wall.neighbour.as_ref().and_then(|n| self.wall_index(&n.1));
        if let DoorSide::Room(b) = other {
            self.rooms[b.0].door_keep_out.push(box_beside(
                p1,
                p2,
                [-nrm[0], -nrm[1]],
                DOOR_BOX_DEPTH_M,
            ));
        }
        let hole_for = |start: f64| Hole {
            kind: HoleKind::Door,
            start_m: start,
            end_m: start + width,
            bottom_m: 0.0,
            top_m: asset.bbox_m[1],
        };
        self.walls[wi].hole = Some(hole_for(s_int));
        let reverse_start = l - s_int - width;
        if let Some(o) = neighbour_idx {
            self.walls[o].hole = Some(hole_for(reverse_start));
        }
        // wall0 is the wall on the `from` side; along it the hole starts at `start0`.
        let room_wall = wall.id.clone();
        let other_wall = match other {
            DoorSide::Exterior => wall.exterior_id(),
            DoorSide::Room(_) => wall.neighbour.as_ref().map(|n| n.1.clone()).unwrap_or_default(),
        };
        // A door to the exterior is written as ProcTHOR writes it: the room on both sides and
        // its own wall first, whichever way the scene named it (AI2-THOR orients the door and
        // its `openFromRoomId` from `wall0`/`room0`).
        let exterior = matches!(from, DoorSide::Exterior) || matches!(to, DoorSide::Exterior);
        let room_first = exterior || matches!(from, DoorSide::Room(r) if r == room);
        let (wall0, wall1, start0, segment) = if room_first {
            (room_wall, other_wall, s_int, (p1, p2))
        } else {
            (other_wall, room_wall, reverse_start, (p2, p1))
        };
        let off = asset.offset_m;
        let hole_min = [start0 - off[0], 0.0];
        let hole_max = [start0 + width - off[0], asset.bbox_m[1] - off[1]];
        let asset_position =
            [hole_min[0] + off[0] + width / 2.0, hole_min[1] + off[1] + asset.bbox_m[1] / 2.0];
        let openable = kind == DoorKind::Doorway && !exterior;
        let (room0, room1) = if exterior {
            (self.thor_name(DoorSide::Room(room)), self.thor_name(DoorSide::Room(room)))
        } else {
            (self.thor_name(from), self.thor_name(to))
        };
        self.doors.push(PlacedDoor {
            id: format!("door|{}|{}|{}", index, self.thor_name(from), self.thor_name(to)),
            kind,
            asset_id: asset.asset_id.to_owned(),
            room0,
            room1,
            exterior,
            wall0,
            wall1,
            hole_min,
            hole_max,
            asset_position,
            segment,
            openable,
            openness: if openable { 1.0 } else { 0.0 },
            span,
        });
        true
    }

    fn place_doors(&mut self) {
        // Doors between two rooms that do not fit (E0310), by their diagnostic's index.
        let mut unfit = Vec::new();
        for door in &self.scene.doors {
            if door.kind == DoorKind::Open {
                continue;
            }
            let before = self.diags.len();
            let placed = self.place_door(
                door.index,
                door.from,
                door.to,
                door.kind,
                door.size.unwrap_or(DoorSize::Single),
                door.style.as_deref(),
                door.asset.as_ref(),
                Some(door.span),
                door.side_spans,
            );
            let between_rooms =
                matches!((door.from, door.to), (DoorSide::Room(_), DoorSide::Room(_)));
            if !placed
                && between_rooms
                && self.diags.len() == before + 1
                && self.diags[before].code == Code::E0310
            {
                unfit.push(before);
            }
        }
        // As the original system does, a door that does not fit is left out when every room
        // can still be reached without it; the error becomes a warning that says so.
        if unfit.is_empty() {
            return;
        }
        let (has_exterior, seen) = self.reached();
        if has_exterior && seen.iter().all(|s| *s) {
            for i in unfit {
                let d = &mut self.diags[i];
                d.code = Code::W0306;
                d.severity = crate::diag::Severity::Warning;
                d.message =
                    format!("{}; it is left out, every room is reached without it", d.message);
                d.help = Some(
                    "use a single door, or make the shared wall longer, to have it".to_owned(),
                );
            }
        }
    }

    /// Whether any door leads outside, and which rooms a chain of doors reaches from outside.
    fn reached(&self) -> (bool, Vec<bool>) {
        let n = self.rooms.len();
        let mut edges: Vec<(Option<usize>, Option<usize>)> = Vec::new();
        // A door names its rooms by their ids (the first room of an id, when two share one).
        let mut by_id: rustc_hash::FxHashMap<&str, usize> = rustc_hash::FxHashMap::default();
        for (i, room) in self.rooms.iter().enumerate() {
            by_id.entry(room.thor_id.as_str()).or_insert(i);
        }
        let side = |s: &str| by_id.get(s).copied();
        for d in &self.doors {
            let outside = if d.exterior { None } else { side(&d.room1) };
            edges.push((side(&d.room0), outside));
        }
        for o in &self.open {
            edges.push((Some(o.rooms.0 .0), Some(o.rooms.1 .0)));
        }
        let has_exterior = edges.iter().any(|e| e.0.is_none() || e.1.is_none());
        let mut next: Vec<Vec<usize>> = vec![Vec::new(); n];
        for e in &edges {
            if let (Some(a), Some(b)) = *e {
                next[a].push(b);
                next[b].push(a);
            }
        }
        let mut seen = vec![false; n];
        let mut stack: Vec<usize> = edges
            .iter()
            .filter_map(|e| match e {
                (None, Some(r)) | (Some(r), None) => Some(*r),
                _ => None,
            })
            .collect();
        while let Some(r) = stack.pop() {
            if seen[r] {
                continue;
            }
            seen[r] = true;
            stack.extend(next[r].iter().copied().filter(|&o| !seen[o]));
        }
        (has_exterior, seen)
    }

    fn reachability(&mut self) {
        if self.diags.iter().any(Diagnostic::is_error) || self.rooms.is_empty() {
            return;
        }
        let mut next_index = self.scene.doors.len();
        let (has_exterior, _) = self.reached();
        if !has_exterior {
            let mut added = false;
            if self.options.add_doors {
                for r in 0..self.rooms.len() {
                    let span = self.rooms[r].name_span;
                    let before = self.diags.len();
                    if self.place_door(
                        next_index,
                        DoorSide::Exterior,
                        DoorSide::Room(RoomId(r)),
                        DoorKind::Doorway,
                        DoorSize::Single,
                        None,
                        None,
                        None,
                        [span, span],
                    ) {
                        self.diags.truncate(before);
                        next_index += 1;
                        self.diags.push(
                            Diagnostic::new(
                                Code::W0302,
                                format!(
                                    "added a doorway from outside into room `{}`",
                                    self.room_name(RoomId(r))
                                ),
                            )
                            .with_primary(span, "now reachable from outside")
                            .with_help("write the door in the scene to choose where it goes"),
                        );
                        added = true;
                        break;
                    }
                    self.diags.truncate(before);
                }
            }
            if !added {
                let span = self.rooms[0].name_span;
                self.diags.push(
                    Diagnostic::new(Code::E0314, "no door leads outside")
                        .with_primary(span, "no room of the house has a door to the exterior")
                        .with_help(format!("add `door exterior -- {} : doorway single`, or build with `--add-doors`", self.room_name(RoomId(0)))),
                );
                return;
            }
        }
        loop {
            let (_, seen) = self.reached();
            if seen.iter().all(|&s| s) {
                return;
            }
            let mut progress = false;
            if self.options.add_doors {
                for r in 0..self.rooms.len() {
                    if seen[r] {
                        continue;
                    }
                    let span = self.rooms[r].name_span;
                    for (o, &reached) in seen.iter().enumerate() {
                        if !reached {
                            continue;
                        }
                        let before = self.diags.len();
                        if self.place_door(
                            next_index,
                            DoorSide::Room(RoomId(o)),
                            DoorSide::Room(RoomId(r)),
                            DoorKind::Doorway,
                            DoorSize::Single,
                            None,
                            None,
                            None,
                            [span, span],
                        ) {
                            self.diags.truncate(before);
                            next_index += 1;
                            self.diags.push(
                                Diagnostic::new(
                                    Code::W0302,
                                    format!(
                                        "added a doorway between `{}` and `{}`",
                                        self.room_name(RoomId(o)),
                                        self.room_name(RoomId(r))
                                    ),
                                )
                                .with_primary(span, "now reachable from outside")
                                .with_help("write the door in the scene to choose where it goes"),
                            );
                            progress = true;
                            break;
                        }
                        self.diags.truncate(before);
                    }
                    if progress {
                        break;
                    }
                }
            }
            if !progress {
                for (r, reached) in seen.iter().enumerate() {
                    if !reached {
                        self.diags.push(
                            Diagnostic::new(
                                Code::E0315,
                                format!(
                                    "room `{}` cannot be reached from outside",
                                    self.room_name(RoomId(r))
                                ),
                            )
                            .with_primary(
                                self.rooms[r].name_span,
                                "no chain of doors leads here from the exterior",
                            )
                            .with_help(
                                "add a door to a reachable neighbour, or build with `--add-doors`",
                            ),
                        );
                    }
                }
                return;
            }
        }
    }

    fn place_windows(&mut self) {
        let h_wall = self.scene.wall_height_m;
        // Each room's walls are taken out together (a window row looks only at its room's
        // walls, `w.room == room.id`), split there, and put back in order.
        let mut rest = std::mem::take(&mut self.walls).into_iter();
        let mut out: Vec<Wall> = Vec::with_capacity(rest.len());
        for (k, room) in self.scene.rooms.iter().enumerate() {
            debug_assert_eq!(room.id, RoomId(k), "a scene's rooms are numbered in order");
            let count = self.room_walls.get(k).map_or(0, ExactSizeIterator::len);
            let mut walls: Vec<Wall> = rest.by_ref().take(count).collect();
            for row in &room.windows {
                let cands: Vec<usize> = (0..walls.len())
                    .filter(|&i| {
                        let w = &walls[i];
                        w.room == room.id && w.direction == row.wall && w.exterior && !w.empty
                    })
                    .collect();
                if cands.is_empty() {
                    self.diags.push(
                        Diagnostic::new(
                            Code::E0316,
                            format!(
                                "room `{}` has no outside wall on its {} side",
                                room.name,
                                row.wall.as_str()
                            ),
                        )
                        .with_primary(row.span, "window on a side without outside wall")
                        .with_help("choose a side of the room that faces outside"),
                    );
                    continue;
                }
                let free: Vec<usize> =
                    cands.iter().copied().filter(|&i| walls[i].hole.is_none()).collect();
                let Some(&wi) = free.iter().max_by(|&&a, &&b| {
                    walls[a].width_m.total_cmp(&walls[b].width_m).then(b.cmp(&a))
                }) else {
                    self.diags.push(
                        Diagnostic::new(
                            Code::E0311,
                            format!(
                                "the {} wall of room `{}` already has a door or window",
                                row.wall.as_str(),
                                room.name
                            ),
                        )
                        .with_primary(row.span, "no free wall for this window")
                        .with_help(
                            "AI2-THOR allows one hole per wall; put the window on another side",
                        ),
                    );
                    continue;
                };
                let mut asset = if let Some(pin) = &row.asset {
                    if let Some(a) = self.catalog.window(&pin.id) {
                        a.clone()
                    } else {
                        let names: Vec<&str> =
                            self.catalog.windows.iter().map(|w| w.asset_id).collect();
                        self.diags.push(
                            Diagnostic::new(
                                Code::E0319,
                                format!("`{}` is not a window asset", pin.id),
                            )
                            .with_primary(pin.span, "not in the window catalog")
                            .with_quoted_suggestions(pin.span, &pin.id, names),
                        );
                        continue;
                    }
                } else if let Some(a) =
                    self.catalog.select_window(row.kind, row.width_m, row.height_m)
                {
                    a.clone()
                } else {
                    self.diags.push(Diagnostic::internal(
                        "the window catalog has no window of this type",
                    ));
                    continue;
                };
                let wall = walls[wi].clone();
                let mut n = row.count.max(1) as usize;
                let room_for = |n: usize| wall.width_m / n as f64 - 2.0 * WINDOW_MARGIN_M;
                let top_room = h_wall - WINDOW_TOP_MARGIN_M;
                // Where the asked windows do not fit, holoc fits them as the original system
                // does, and says what it changed: first a narrower window of the same type (not
                // for a pinned asset), then as many windows as the wall holds.
                if asset.hole_m[0] > room_for(n) + EPS_M {
                    let before = (asset.asset_id.to_owned(), asset.hole_m[0], n);
                    let narrower = (row.asset.is_none())
                        .then(|| {
                            self.catalog
                                .windows
                                .iter()
                                .filter(|w| w.kind == Some(row.kind))
                                .filter(|w| w.hole_m[0] <= room_for(n) + EPS_M)
                                .filter(|w| w.hole_m[1] <= top_room + EPS_M)
                                .max_by(|a, b| {
                                    a.hole_m[0]
                                        .total_cmp(&b.hole_m[0])
                                        .then(b.asset_id.cmp(a.asset_id))
                                })
                                .cloned()
                        })
                        .flatten();
                    if let Some(w) = narrower {
                        asset = w;
                    } else {
                        let fits = (wall.width_m / (asset.hole_m[0] + 2.0 * WINDOW_MARGIN_M)
                            + EPS_M)
                            .floor() as usize;
                        if fits >= 1 {
                            n = fits.min(n);
                        }
                    }
                    if asset.hole_m[0] <= room_for(n) + EPS_M {
                        self.diags.push(
                            Diagnostic::new(
                                Code::W0304,
                                format!(
                                    "{} window{} {} m wide {} not fit on the {} wall of `{}` ({} m long); {} {} m wide {} written instead",
                                    before.2,
                                    if before.2 == 1 { "" } else { "s" },
                                    m(before.1),
                                    if before.2 == 1 { "does" } else { "do" },
                                    row.wall.as_str(),
                                    room.name,
                                    m(wall.width_m),
                                    n,
                                    m(asset.hole_m[0]),
                                    if n == 1 { "is" } else { "are" }
                                ),
                            )
                            .with_primary(row.span, format!("{n} × `{}`", asset.asset_id))
                            .with_note(format!(
                                "each window keeps {} m of wall at both ends of its share of the wall; was `{}`",
                                m(WINDOW_MARGIN_M),
                                before.0
                            ))
                            .with_help("ask for fewer or narrower windows to choose yourself"),
                        );
                    }
                }
                let piece = wall.width_m / n as f64;
                let [hx, hy] = asset.hole_m;
                let mut sill = row.sill_m;
                if sill + hy > top_room + EPS_M && hy <= top_room + EPS_M {
                    // The highest sill that keeps the top under the wall's margin, in whole cm.
                    let lowered = ((top_room - hy) * 100.0 + 1e-6).floor() / 100.0;
                    self.diags.push(
                        Diagnostic::new(
                            Code::W0305,
                            format!(
                                "the window's top at {:.3} m is above the wall height of {} m less {} m; the sill is lowered from {} m to {} m",
                                sill + hy,
                                m(h_wall),
                                m(WINDOW_TOP_MARGIN_M),
                                m(sill),
                                m(lowered)
                            ),
                        )
                        .with_primary(row.span, format!("sill {} m", m(lowered)))
                        .with_help(format!("write `sill {} cm` or less to choose yourself", (lowered * 100.0).round())),
                    );
                    sill = lowered.max(0.0);
                }
                if piece + EPS_M < hx + 2.0 * WINDOW_MARGIN_M {
                    self.diags.push(
                        Diagnostic::new(
                            Code::E0317,
                            format!(
                                "{} window{} {} m wide {} not fit on the {} wall of `{}` ({} m long)",
                                n,
                                if n == 1 { "" } else { "s" },
                                m(hx),
                                if n == 1 { "does" } else { "do" },
                                row.wall.as_str(),
                                room.name,
                                m(wall.width_m)
                            ),
                        )
                        .with_primary(row.span, format!("needs {} m of wall", m(n as f64 * (hx + 2.0 * WINDOW_MARGIN_M))))
                        .with_help("use fewer or narrower windows"),
                    );
                    continue;
                }
                if sill + hy > top_room + EPS_M {
                    // The window itself is taller than the wall allows.
                    self.diags.push(
                        Diagnostic::new(
                            Code::E0318,
                            format!(
                                "the window is {} m high; a {} m wall holds windows up to {} m high (it keeps {} m under the ceiling)",
                                m(hy),
                                m(h_wall),
                                m(top_room),
                                m(WINDOW_TOP_MARGIN_M)
                            ),
                        )
                        .with_primary(row.span, format!("sill {} m + height {} m", m(sill), m(hy)))
                        .with_help(format!(
                            "use a window at most {} cm high, or raise the wall height",
                            ((top_room * 100.0) + 1e-6).floor()
                        )),
                    );
                    continue;
                }
                // Split into n sub-walls (one hole per wall), each with a centred window.
                let dir = geo::unit(wall.start, wall.end);
                let mut pieces = Vec::new();
                for k in 0..n {
                    let a = add_scaled(wall.start, dir, piece * k as f64);
                    let b = if k + 1 == n {
                        wall.end
                    } else {
                        add_scaled(wall.start, dir, piece * (k + 1) as f64)
                    };
                    let mut sub = wall.clone();
                    if n > 1 {
                        sub.id = format!("{}|{}", wall.id, k);
                    }
                    sub.start = a;
                    sub.end = b;
                    sub.width_m = distance(a, b);
                    let start = (sub.width_m - hx) / 2.0;
                    sub.hole = Some(Hole {
                        kind: HoleKind::Window,
                        start_m: start,
                        end_m: start + hx,
                        bottom_m: sill,
                        top_m: sill + hy,
                    });
                    let off = asset.offset_m;
                    let hole_min = [start - off[0], sill];
                    let hole_max = [start + hx - off[0], sill + hy - off[1]];
                    let asset_position = [
                        hole_min[0] + off[0] + asset.bbox_m[0] / 2.0,
                        hole_min[1] + off[1] + asset.bbox_m[1] / 2.0,
                    ];
                    let s1 = add_scaled(a, dir, start);
                    let s2 = add_scaled(a, dir, start + hx);
                    self.rooms[room.id.0].window_segments.push((s1, s2));
                    let _ = WINDOW_BOX_DEPTH_M;
                    self.windows.push(PlacedWindow {
                        id: format!("window|{}|{}", sub.id, k),
                        asset_id: asset.asset_id.to_owned(),
                        room: room.id,
                        wall0: sub.id.clone(),
                        wall1: sub.exterior_id(),
                        hole_min,
                        hole_max,
                        asset_position,
                        segment: (s1, s2),
                        span: row.span,
                    });
                    pieces.push(sub);
                }
                walls.splice(wi..=wi, pieces);
            }
            out.append(&mut walls);
        }
        out.extend(rest);
        // Window rows split walls, so the list grew past what it was given: what it did not
        // fill is given back (the plan is kept while the scene is edited).
        out.shrink_to_fit();
        self.walls = out;
        // Walls are no longer where these say.
        self.room_walls.clear();
        self.wall_ids.clear();
    }

    /// The material of every ceiling: the scene's pinned `ceiling material` (E0320 when it is
    /// unknown), else its `ceiling` design resolved like a wall design, else the default.
    fn ceiling_material(&mut self) -> String {
        let first_wall = self.rooms.first().map(|r| r.wall_material.clone());
        if let Some(pin) = &self.scene.ceiling_material {
            if self.catalog.material(&pin.id).is_some() {
                return pin.id.clone();
            }
            let names: Vec<&str> = self.catalog.materials.iter().map(Material::name).collect();
            self.diags.push(
                Diagnostic::new(Code::E0320, format!("`{}` is not a known material", pin.id))
                    .with_primary(pin.span, "not in the material database")
                    .with_quoted_suggestions(pin.span, &pin.id, names),
            );
        } else if let Some(design) = &self.scene.ceiling_design {
            // The best-ranked wall material that a ceiling can be made of.
            let fits = |name: &str| {
                let lower = name.to_lowercase();
                !UNLIKELY_CEILINGS.iter().any(|w| lower.contains(w))
            };
            if let Some((m, _)) = self
                .catalog
                .rank_materials(design, Surface::Wall)
                .into_iter()
                .find(|(m, score)| *score >= 1.0 && fits(m.name()))
            {
                return m.name().to_owned();
            }
        }
        default_ceiling_material(first_wall.as_deref())
    }

    fn materials(&mut self) {
        let mut used: BTreeSet<String> = BTreeSet::new();
        let mut cache: BTreeMap<(String, bool), String> = BTreeMap::new();
        for room in &self.scene.rooms {
            for surface in [Surface::Floor, Surface::Wall] {
                let (pinned, design, default) = match surface {
                    Surface::Floor => {
                        (&room.floor_material, &room.floor_design, "light oak wood floor")
                    }
                    Surface::Wall => (&room.wall_material, &room.wall_design, "white drywall"),
                };
                let name = if let Some(pin) = pinned {
                    if self.catalog.material(&pin.id).is_some() {
                        pin.id.clone()
                    } else {
                        let names: Vec<&str> =
                            self.catalog.materials.iter().map(Material::name).collect();
                        self.diags.push(
                            Diagnostic::new(
                                Code::E0320,
                                format!("`{}` is not a known material", pin.id),
                            )
                            .with_primary(pin.span, "not in the material database")
                            .with_quoted_suggestions(pin.span, &pin.id, names),
                        );
                        continue;
                    }
                } else {
                    let text = design.clone().unwrap_or_else(|| default.to_owned());
                    let key = (text.clone(), surface == Surface::Floor);
                    if let Some(hit) = cache.get(&key) {
                        hit.clone()
                    } else {
                        let chosen =
                            self.catalog.select_material(&text, surface, &used).map_or_else(
                                || crate::resolve::structure::EXTERIOR_WALL_MATERIAL.to_owned(),
                                |m| m.name().to_owned(),
                            );
                        cache.insert(key, chosen.clone());
                        chosen
                    }
                };
                // A colour the design asks tints the material (`PureWhite` painted deep blue).
                let tint = design.as_deref().and_then(|d| self.catalog.tint(d, &name));
                used.insert(name.clone());
                let planned = &mut self.rooms[room.id.0];
                match surface {
                    Surface::Floor => (planned.floor_material, planned.floor_tint) = (name, tint),
                    Surface::Wall => (planned.wall_material, planned.wall_tint) = (name, tint),
                }
            }
        }
    }

    fn layers(&mut self) {
        let n = self.rooms.len();
        // Rooms joined by open connections form one group.
        let mut group: Vec<usize> = (0..n).collect();
        for o in &self.open {
            let (a, b) = (find(&mut group, o.rooms.0 .0), find(&mut group, o.rooms.1 .0));
            let (lo, hi) = (a.min(b), a.max(b));
            group[hi] = lo;
        }
        let roots: Vec<usize> = (0..n).map(|r| find(&mut group, r)).collect();
        let nodes: Vec<usize> = {
            let mut v = roots.clone();
            v.sort_unstable();
            v.dedup();
            v
        };
        let mut adj: BTreeSet<(usize, usize)> = BTreeSet::new();
        for w in &self.walls {
            if let Some((o, _)) = &w.neighbour {
                let (a, b) = (roots[w.room.0], roots[o.0]);
                if a != b {
                    adj.insert((a.min(b), a.max(b)));
                }
            }
        }
        let mut colour: BTreeMap<usize, u8> = BTreeMap::new();
        if !colour_layers(&nodes, &adj, &mut colour) {
            colour = nodes
                .iter()
                .enumerate()
                .map(|(i, &v)| (v, (i % N_LAYERS as usize) as u8))
                .collect();
            self.diags.push(
                Diagnostic::new(Code::W0303, "four lighting layers are not enough for this plan")
                    .with_primary(self.rooms[0].name_span, "some neighbouring rooms share a layer")
                    .with_help("nothing is required; light may show through to a neighbour"),
            );
        }
        for (room, root) in self.rooms.iter_mut().zip(&roots) {
            room.layer = colour.get(root).copied().unwrap_or(0);
        }
    }

    fn agent_pose(&self) -> AgentPose {
        // The room with the first exterior door, else the first room.
        let start = self
            .doors
            .iter()
            .find_map(|d| {
                d.exterior.then(|| self.rooms.iter().position(|r| r.thor_id == d.room0)).flatten()
            })
            .unwrap_or(0);
        let room = &self.rooms[start];
        let bbox = Aabb::of(&room.polygon);
        let poly = &room.polygon;
        let mut best: Option<(f64, Point)> = None;
        let step = 0.25;
        let nx = (bbox.width() / step).floor() as i64;
        let nz = (bbox.depth() / step).floor() as i64;
        for ix in 0..=nx {
            for iz in 0..=nz {
                let p = [bbox.min[0] + ix as f64 * step, bbox.min[1] + iz as f64 * step];
                if !geo::point_in_polygon(p, poly) {
                    continue;
                }
                let clearance = (0..poly.len())
                    .map(|i| geo::distance_to_segment(p, poly[i], poly[(i + 1) % poly.len()]))
                    .fold(f64::INFINITY, f64::min);
                if clearance < 0.5 - EPS_M {
                    continue;
                }
                let blocked = room
                    .door_keep_out
                    .iter()
                    .chain(&room.open_boxes)
                    .any(|b| geo::point_in_or_on_polygon(p, b));
                if blocked {
                    continue;
                }
                let d = distance(p, room.centroid);
                if best.is_none_or(|(bd, _)| d < bd - EPS_M) {
                    best = Some((d, p));
                }
            }
        }
        AgentPose {
            room: RoomId(start),
            position: best.map_or(room.centroid, |b| b.1),
            rotation_deg: 0.0,
        }
    }
}

/// The coordinates written so far on one axis, each one not within [`SNAP_M`] of an earlier one:
/// a corner's coordinate snaps to the first written (`find`). Kept in order of value, so that
/// only the few near a coordinate are looked at.
#[derive(Debug, Default)]
struct Anchors {
    /// Finite values with the order they were written in, by value ([`ordered`]). (A value
    /// that is not finite is within `SNAP_M` of nothing, so it is not kept.)
    by_value: BTreeMap<u64, (f64, usize)>,
    /// How many were written.
    written: usize,
}

/// A finite float as a key that sorts as the float does.
fn ordered(v: f64) -> u64 {
    let bits = v.to_bits();
    if bits >> 63 == 1 {
        !bits
    } else {
        bits | (1 << 63)
    }
}

impl Anchors {
    /// The first value written within [`SNAP_M`] of `v` (`|a − v| < SNAP_M`).
    fn find(&self, v: f64) -> Option<f64> {
        if !v.is_finite() {
            return None;
        }
        // Every value within SNAP_M lies well inside this window, whatever the rounding.
        let window = ordered(v - 2.0 * SNAP_M)..=ordered(v + 2.0 * SNAP_M);
        self.by_value
            .range(window)
            .map(|(_, &found)| found)
            .filter(|&(a, _)| (a - v).abs() < SNAP_M)
            .min_by_key(|&(_, order)| order)
            .map(|(a, _)| a)
    }

    /// Writes `v` after the others.
    fn push(&mut self, v: f64) {
        if v.is_finite() {
            // Two values within SNAP_M are never both written, so no key is taken twice.
            self.by_value.entry(ordered(v)).or_insert((v, self.written));
        }
        self.written += 1;
    }
}

/// Union-find root.
pub(super) fn find(g: &mut [usize], x: usize) -> usize {
    let mut r = x;
    while g[r] != r {
        r = g[r];
    }
    g[x] = r;
    r
}

/// Backtracking colouring of `nodes` with `N_LAYERS` colours: each node in turn takes the
/// first colour none of the nodes before it that it touches (`adj`, pairs `(low, high)`) has,
/// and when none is left the node before it takes its next colour. `colour` gets the first
/// colouring so found (`false` when there is none). The search keeps its own stack, so that
/// thousands of rooms do not nest thousands of calls, and looks only at each node's neighbours.
fn colour_layers(
    nodes: &[usize],
    adj: &BTreeSet<(usize, usize)>,
    colour: &mut BTreeMap<usize, u8>,
) -> bool {
    let place: BTreeMap<usize, usize> = nodes.iter().enumerate().map(|(i, &v)| (v, i)).collect();
    // Each node's neighbours among the nodes before it, by their place.
    let mut earlier: Vec<Vec<usize>> = vec![Vec::new(); nodes.len()];
    for &(a, b) in adj {
        if let (Some(&i), Some(&j)) = (place.get(&a), place.get(&b)) {
            earlier[i.max(j)].push(i.min(j));
        }
    }
    let mut given: Vec<u8> = vec![0; nodes.len()];
    // The colour node `i` tries next.
    let mut next: Vec<u8> = vec![0; nodes.len()];
    let mut i = 0;
    while i < nodes.len() {
        let free = (next[i]..N_LAYERS).find(|&c| !earlier[i].iter().any(|&u| given[u] == c));
        match free {
            Some(c) => {
                given[i] = c;
                next[i] = c + 1;
                i += 1;
                if let Some(n) = next.get_mut(i) {
                    *n = 0;
                }
            }
            None if i == 0 => return false,
            None => i -= 1,
        }
    }
    colour.extend(nodes.iter().zip(&given).map(|(&v, &c)| (v, c)));
    true
}

#[cfg(test)]
mod tests {
    use super::*;
    use proptest::prelude::*;
    use std::fmt::Write as _;

    /// The recursive search `colour_layers` replaced, looking at every coloured node.
    fn solve(
        i: usize,
        nodes: &[usize],
        adj: &BTreeSet<(usize, usize)>,
        colour: &mut BTreeMap<usize, u8>,
    ) -> bool {
        if i == nodes.len() {
            return true;
        }
        let v = nodes[i];
        for c in 0..N_LAYERS {
            let clash =
                colour.iter().any(|(&u, &cu)| cu == c && adj.contains(&(u.min(v), u.max(v))));
            if !clash {
                colour.insert(v, c);
                if solve(i + 1, nodes, adj, colour) {
                    return true;
                }
                colour.remove(&v);
            }
        }
        false
    }

    /// Rows of rooms on a grid of random column lines: each row's rooms span runs of columns,
    /// so that one row's corners fall inside the next row's walls.
    fn rows_of_rooms(columns: &[u8], rows: &[(u8, Vec<u8>)]) -> String {
        let mut xs = vec![0.0];
        for &w in columns {
            xs.push(xs[xs.len() - 1] + f64::from(w) * 0.5 + 1.0);
        }
        let mut text = String::new();
        let mut z = 0.0;
        let mut k = 0;
        for (depth, runs) in rows {
            let z1 = z + f64::from(*depth) * 0.5 + 1.0;
            let mut c = 0;
            for &run in runs.iter().cycle() {
                if c >= columns.len() {
                    break;
                }
                let c1 = (c + usize::from(run % 3) + 1).min(columns.len());
                let (x0, x1) = (xs[c], xs[c1]);
                let _ = write!(
                    text,
                    "room r{k} \"office\" {{\n  corners in m ({x0}, {z}) ({x0}, {z1}) ({x1}, {z1}) ({x1}, {z})\n}}\n"
                );
                k += 1;
                c = c1;
            }
            z = z1;
        }
        text
    }

    proptest! {
        /// Each room's polygon has every corner of the plan that lies inside one of its sides,
        /// and each wall's neighbour is the last side of another room along it: what a look at
        /// every corner and every side finds.
        #[test]
        fn walls_are_split_and_paired_as_a_look_at_everything_does(
            columns in proptest::collection::vec(0u8..6, 1..7),
            rows in proptest::collection::vec((0u8..6, proptest::collection::vec(0u8..3, 1..4)), 1..5),
        ) {
            let text = rows_of_rooms(&columns, &rows);
            let mut sources = crate::source::SourceMap::new();
            let file = sources.add("rows.holo", &text);
            let scene = crate::compile::check_file(&sources, file).value.expect("a scene");
            let plan = run(&scene, StructureCatalog::builtin(), PlanOptions::default()).value;
            prop_assert_eq!(plan.rooms.len(), scene.rooms.len());
            let all: Vec<Point> = plan.rooms.iter().flat_map(|r| r.corners.clone()).collect();
            for room in &plan.rooms {
                let corners = &room.corners;
                let mut full = Vec::new();
                for i in 0..corners.len() {
                    let (a, b) = (corners[i], corners[(i + 1) % corners.len()]);
                    full.push(a);
                    let mut inner: Vec<Point> = all
                        .iter()
                        .copied()
                        .filter(|&p| point_on_segment(p, a, b) && !near_point(p, a) && !near_point(p, b))
                        .collect();
                    inner.sort_by(|p, q| distance(a, *p).total_cmp(&distance(a, *q)));
                    inner.dedup_by(|p, q| near_point(*p, *q));
                    full.extend(inner);
                }
                prop_assert_eq!(&room.polygon, &full);
            }
            let mut first = vec![0usize; plan.rooms.len()];
            for (i, w) in plan.walls.iter().enumerate().rev() {
                first[w.room.0] = i;
            }
            for w in &plan.walls {
                let mut expected = None;
                for (o, other) in plan.rooms.iter().enumerate() {
                    let op = &other.polygon;
                    for k in 0..op.len() {
                        if o != w.room.0 && segment_overlap(w.start, w.end, op[k], op[(k + 1) % op.len()]).is_some() {
                            expected = Some((RoomId(o), plan.walls[first[o] + k].id.clone()));
                        }
                    }
                }
                prop_assert_eq!(&w.neighbour, &expected);
            }
        }

        /// A coordinate snaps to what a scan of every earlier anchor finds.
        #[test]
        fn anchors_find_what_a_scan_finds(
            values in proptest::collection::vec(
                prop_oneof![
                    (-400i32..400).prop_map(|k| f64::from(k) * 0.025),
                    -10.0f64..10.0,
                    Just(f64::NAN),
                    Just(f64::INFINITY),
                ],
                0..80,
            ),
        ) {
            let (mut scan, mut anchors) = (Vec::<f64>::new(), Anchors::default());
            for v in values {
                let expected = scan.iter().copied().find(|&a| (a - v).abs() < SNAP_M);
                let found = anchors.find(v);
                prop_assert_eq!(found.map(f64::to_bits), expected.map(f64::to_bits));
                if found.is_none() {
                    scan.push(v);
                    anchors.push(v);
                }
            }
        }

        /// The colouring is the one the recursive search finds, on graphs that need
        /// backtracking and on graphs with no colouring (five nodes all touching).
        #[test]
        fn layers_are_coloured_as_the_recursive_search_colours_them(
            n in 1usize..10,
            edges in proptest::collection::vec((0usize..12, 0usize..12), 0..40),
            skip in 0usize..3,
        ) {
            let nodes: Vec<usize> = (0..n).map(|k| k * (skip + 1)).collect();
            let adj: BTreeSet<(usize, usize)> = edges
                .iter()
                .filter(|(a, b)| a != b && *a < n && *b < n)
                .map(|&(a, b)| (nodes[a.min(b)], nodes[a.max(b)]))
                .collect();
            let (mut old, mut new) = (BTreeMap::new(), BTreeMap::new());
            let found = solve(0, &nodes, &adj, &mut old);
            prop_assert_eq!(colour_layers(&nodes, &adj, &mut new), found);
            if found {
                prop_assert_eq!(new, old);
            }
        }
    }
}

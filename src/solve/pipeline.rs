//! The solve stage over a whole scene: builds one [`RoomProblem`] per room from the checked
//! scene, the floor plan and the resolved assets, and solves it; `lower` turns the poses into
//! the objects of the house.
//!
//! Objects whose asset could not be resolved are left out of the problems (the resolve stage has
//! reported them), so they take no space and constraints naming them are dropped.

use super::{room_problem, RoomLayout, RoomProblem, Sizes, SolveOptions, WallHole, WallSegment};
use crate::check::scene::{ObjectId, RelationKind, RoomId, Scene, SmallItem};
use crate::diag::Outcome;
use crate::plan::{FloorPlan, HoleKind};
use crate::resolve::{Resolution, Resolved};

/// The solved layout of every room.
#[derive(Clone, Debug)]
pub struct Layout {
    /// One entry per room, in room order.
    pub rooms: Vec<SolvedRoom>,
}

/// One solved room.
#[derive(Clone, Debug)]
pub struct SolvedRoom {
    /// The room.
    pub room: RoomId,
    /// The problem that was solved.
    pub problem: RoomProblem,
    /// The solution.
    pub layout: RoomLayout,
    /// The scene object of each floor object of the problem, in problem order.
    pub floor_ids: Vec<ObjectId>,
    /// The scene object of each wall object of the problem.
    pub wall_ids: Vec<ObjectId>,
    /// For each small object of the problem: the receptacle, the `on top` line and the copy.
    pub small_keys: Vec<(ObjectId, usize, u32)>,
}

/// Sizes from the resolved assets: `[width, depth, height]` = the bounding box's `(x, z, y)`.
struct ResolvedSizes<'a> {
    scene: &'a Scene,
    resolved: &'a Resolved,
}

fn bbox_to_size(b: [f64; 3]) -> [f64; 3] {
    [b[0], b[2], b[1]]
}

impl Sizes for ResolvedSizes<'_> {
    fn object(&self, object: &crate::check::scene::Object) -> [f64; 3] {
        self.resolved
            .object(object.id)
            .map_or_else(|| object.size_m.unwrap_or([0.5, 0.5, 0.5]), |c| bbox_to_size(c.bbox_m))
    }

    fn small(&self, item: &SmallItem) -> [f64; 3] {
        // The item is identified by address: it lives in the scene the problem is built from.
        for o in &self.scene.objects {
            if let Some(k) = o.on_top.iter().position(|t| std::ptr::eq(t, item)) {
                if let Some(choice) = self
                    .resolved
                    .small
                    .get(&(o.id, k))
                    .and_then(|v| v.iter().find_map(Resolution::choice))
                {
                    return bbox_to_size(choice.bbox_m);
                }
            }
        }
        [0.2, 0.2, 0.2]
    }

    fn ceiling(&self, room: RoomId) -> [f64; 3] {
        self.resolved
            .ceilings
            .get(&room)
            .and_then(Resolution::choice)
            .map_or([0.5, 0.5, 0.3], |c| bbox_to_size(c.bbox_m))
    }
}

/// Solves every room of the scene.
pub fn solve(
    scene: &Scene,
    plan: &FloorPlan,
    resolved: &Resolved,
    options: &SolveOptions,
) -> Outcome<Layout> {
    // The scene without the objects that have no asset.
    let mut kept = scene.clone();
    for room in &mut kept.rooms {
        room.objects.retain(|id| resolved.object(*id).is_some());
    }
    // Objects whose every relation names an object left out follow it out (chairs around a
    // table that has no asset are not placed around nothing); the chain is followed.
    let mut dependents: Vec<(RoomId, String, String)> = Vec::new();
    loop {
        let mut dropped = Vec::new();
        for room in &kept.rooms {
            for &id in &room.objects {
                let crate::check::scene::Placement::Floor { constraints, .. } =
                    &kept.object(id).placement
                else {
                    continue;
                };
                // Only relations that place an object by the target's position make it depend
                // on the target (`around`, `in front of`, `near`…); a sofa that faces a missing
                // piano still stands against its wall.
                let positional = constraints.iter().any(|c| {
                    !matches!(
                        c.kind,
                        RelationKind::Far
                            | RelationKind::FaceTo
                            | RelationKind::FaceSameAs
                            | RelationKind::CenterAligned
                    )
                });
                if positional && constraints.iter().all(|c| !room.objects.contains(&c.target)) {
                    let targets: Vec<String> = constraints
                        .iter()
                        .map(|c| format!("`{}`", scene.object(c.target).name))
                        .collect::<std::collections::BTreeSet<_>>()
                        .into_iter()
                        .collect();
                    dropped.push((room.id, id, targets.join(", ")));
                }
            }
        }
        if dropped.is_empty() {
            break;
        }
        for (room, id, targets) in dropped {
            kept.rooms[room.0].objects.retain(|o| *o != id);
            dependents.push((room, kept.object(id).name.clone(), targets));
        }
    }
    // Floor objects beyond the room limit, in placement order, are left out.
    let mut over_limit: Vec<(RoomId, ObjectId)> = Vec::new();
    for room in &kept.rooms {
        let floor = room.objects.iter().copied().filter(|id| kept.object(*id).is_floor());
        over_limit.extend(floor.skip(super::MAX_FLOOR_OBJECTS_PER_ROOM).map(|id| (room.id, id)));
    }
    for &(room, id) in &over_limit {
        kept.rooms[room.0].objects.retain(|o| *o != id);
    }
    let sizes = ResolvedSizes { scene: &kept, resolved };
    let mut diagnostics = Vec::new();
    let mut rooms = Vec::new();
    for room in &kept.rooms {
        // A cancelled batch job (`crate::cancel`) solves no more rooms; its result is dropped.
        if crate::cancel::requested() {
            break;
        }
        let plan_room = plan.room(room.id);
        let mut keep_out: Vec<Vec<[f64; 2]>> = plan_room.door_keep_out.clone();
        keep_out.extend(plan_room.open_boxes.iter().cloned());
        let walls: Vec<WallSegment> = plan
            .room_walls(room.id)
            .map(|w| {
                let mut holes = Vec::new();
                if let Some(h) = &w.hole {
                    holes.push(WallHole {
                        from_m: h.start_m,
                        to_m: h.end_m,
                        bottom_m: h.bottom_m,
                        top_m: h.top_m,
                        window: h.kind == HoleKind::Window,
                    });
                }
                if w.empty {
                    holes.push(WallHole {
                        from_m: 0.0,
                        to_m: w.width_m,
                        bottom_m: 0.0,
                        top_m: scene.wall_height_m,
                        window: false,
                    });
                }
                WallSegment { a: w.start, b: w.end, holes }
            })
            .collect();
        let mut problem = room_problem(&kept, room.id, &sizes, keep_out, walls);
        problem.outline.clone_from(&plan_room.corners);
        if room.ceiling.is_some()
            && resolved.ceilings.get(&room.id).is_none_or(|r| r.choice().is_none())
        {
            problem.ceiling = None;
        }
        let floor_ids: Vec<ObjectId> =
            room.objects.iter().copied().filter(|id| kept.object(*id).is_floor()).collect();
        let wall_ids: Vec<ObjectId> =
            room.objects.iter().copied().filter(|id| !kept.object(*id).is_floor()).collect();
        let mut small_keys = Vec::new();
        for &id in &floor_ids {
            for (k, item) in kept.object(id).on_top.iter().enumerate() {
                for i in 0..item.count {
                    small_keys.push((id, k, i));
                }
            }
        }
        // Each copy of a small object has its own asset, hence its own size; a copy without an
        // asset (reported by resolve, W0401) takes no room on its receptacle.
        let choice = |&(receptacle, line, copy): &(ObjectId, usize, u32)| {
            resolved
                .small
                .get(&(receptacle, line))
                .and_then(|v| v.get(copy as usize))
                .and_then(Resolution::choice)
        };
        let has_asset: Vec<bool> = small_keys.iter().map(|k| choice(k).is_some()).collect();
        let mut n = 0;
        problem.small_objects.retain(|_| {
            n += 1;
            has_asset.get(n - 1).copied().unwrap_or(false)
        });
        small_keys.retain(|k| choice(k).is_some());
        for (small, key) in problem.small_objects.iter_mut().zip(&small_keys) {
            if let Some(c) = choice(key) {
                small.size = bbox_to_size(c.bbox_m);
            }
        }
        let room_options = SolveOptions {
            seed: options.seed ^ (room.id.0 as u64).wrapping_mul(0x9E37_79B9_7F4A_7C15),
            ..*options
        };
        let mut solved = super::solve_room(&problem, &room_options);
        diagnostics.extend(solved.diagnostics);
        for (_, name, targets) in dependents.iter().filter(|(r, ..)| *r == room.id) {
            let u = super::Unplaced {
                id: name.clone(),
                kind: "floor",
                rule: None,
                reason: format!("every relation of `{name}` names {targets}, which is left out"),
            };
            let object = scene.objects.iter().find(|o| o.name == *name);
            diagnostics.push(super::errors::dependent_left_out(&u, object.map(|o| o.name_span)));
            solved.value.unplaced.push(u);
            // What stands on it goes with it.
            for item in object.map(|o| o.on_top.as_slice()).unwrap_or_default() {
                for i in 0..item.count {
                    solved.value.unplaced.push(super::Unplaced {
                        id: format!("{}-{i}|{name}", item.item),
                        kind: "small",
                        rule: None,
                        reason: format!("its receptacle `{name}` is left out"),
                    });
                }
            }
        }
        let beyond: Vec<ObjectId> =
            over_limit.iter().filter(|(r, _)| *r == room.id).map(|&(_, id)| id).collect();
        if let Some(&first) = beyond.first() {
            let object = scene.object(first);
            diagnostics.push(
                crate::diag::Diagnostic::new(
                    crate::diag::Code::W0504,
                    format!(
                        "room `{}` has {} floor objects; the {} after the first {} are left out",
                        room.name,
                        super::MAX_FLOOR_OBJECTS_PER_ROOM + beyond.len(),
                        beyond.len(),
                        super::MAX_FLOOR_OBJECTS_PER_ROOM
                    ),
                )
                .with_primary(object.name_span, "the first object left out")
                .with_help("split the room, or leave out objects; a real room holds a few dozen"),
            );
            for &id in &beyond {
                let o = scene.object(id);
                solved.value.unplaced.push(super::Unplaced {
                    id: o.name.clone(),
                    kind: "floor",
                    rule: None,
                    reason: format!(
                        "the room holds more than {} floor objects",
                        super::MAX_FLOOR_OBJECTS_PER_ROOM
                    ),
                });
                for item in &o.on_top {
                    for i in 0..item.count {
                        solved.value.unplaced.push(super::Unplaced {
                            id: format!("{}-{i}|{}", item.item, o.name),
                            kind: "small",
                            rule: None,
                            reason: format!("its receptacle `{}` is left out", o.name),
                        });
                    }
                }
            }
        }
        rooms.push(SolvedRoom {
            room: room.id,
            problem,
            layout: solved.value,
            floor_ids,
            wall_ids,
            small_keys,
        });
    }
    Outcome::new(Layout { rooms }, diagnostics)
}

fn round6(v: f64) -> f64 {
    let r = (v * 1e6).round() / 1e6;
    if r == 0.0 {
        0.0
    } else {
        r
    }
}

fn n(v: f64) -> String {
    crate::ast::format_number(round6((v * 1000.0).round() / 1000.0))
}

impl Layout {
    /// A human-readable dump (`holoc build --emit layout`, the layout snapshots).
    pub fn dump(&self, scene: &Scene) -> String {
        use std::fmt::Write as _;
        let mut out = String::new();
        for solved in &self.rooms {
            let room = scene.room(solved.room);
            let (ok, total) = solved.layout.constraint_tally(&solved.problem);
            let _ = writeln!(out, "room {} ({ok}/{total} constraints hold)", room.name);
            for placed in &solved.layout.floor {
                let o = &solved.problem.objects[placed.index];
                let failed: Vec<String> = placed
                    .constraints
                    .iter()
                    .filter(|c| !c.measure.satisfied)
                    .map(|c| format!("{} ({} {})", c.text, n(c.measure.value), c.measure.unit))
                    .collect();
                let _ = writeln!(
                    out,
                    "  floor {} at ({}, {}) facing {} by {}{}",
                    o.id,
                    n(placed.pose.x),
                    n(placed.pose.z),
                    placed.pose.rot.deg(),
                    placed.by,
                    if failed.is_empty() {
                        String::new()
                    } else {
                        format!("; violated: {}", failed.join(", "))
                    }
                );
            }
            for (kind, list) in [("wall", &solved.layout.wall), ("small", &solved.layout.small)] {
                for p in list {
                    let _ = writeln!(
                        out,
                        "  {kind} {} at ({}, {}, {}) facing {}",
                        p.id,
                        n(p.position_m[0]),
                        n(p.position_m[1]),
                        n(p.position_m[2]),
                        n(p.rotation_deg)
                    );
                }
            }
            if let Some(c) = &solved.layout.ceiling {
                let _ = writeln!(
                    out,
                    "  ceiling at ({}, {}, {})",
                    n(c.position_m[0]),
                    n(c.position_m[1]),
                    n(c.position_m[2])
                );
            }
            for u in &solved.layout.unplaced {
                let _ = writeln!(out, "  not placed: {} {}: {}", u.kind, u.id, u.reason);
            }
        }
        out
    }
}

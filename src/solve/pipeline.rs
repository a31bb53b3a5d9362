//! The solve stage over a whole scene: builds one [`RoomProblem`] per room from the checked
//! scene, the floor plan and the resolved assets, and solves it; `lower` turns the poses into
//! the objects of the house.
//!
//! Objects whose asset could not be resolved are left out of the problems (the resolve stage has
//! reported them), so they take no space; an object that exists for one of them (a chair at a
//! missing table) follows it, and any other relation naming one is given up (W0505).

use super::scene::item_ids;
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
    /// Relations of placed objects given up because their target is left out.
    pub given_up: Vec<GivenUp>,
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

    fn thor_type(&self, object: &crate::check::scene::Object) -> Option<String> {
        self.resolved.object(object.id).map(|c| c.object_type.clone())
    }

    fn resizable(&self, object: &crate::check::scene::Object) -> bool {
        self.resolved.object(object.id).is_some_and(|c| c.made.is_some())
    }

    fn ceiling(&self, room: RoomId) -> [f64; 3] {
        self.resolved
            .ceilings
            .get(&room)
            .and_then(Resolution::choice)
            .map_or([0.5, 0.5, 0.3], |c| bbox_to_size(c.bbox_m))
    }
}

/// A relation given up because its target is left out: the object is placed by its other
/// relations and its room (W0505).
#[derive(Clone, Debug, PartialEq)]
pub struct GivenUp {
    /// The object that keeps its place, e.g. `kitchen_island-0`.
    pub object: String,
    /// The relation as written, e.g. `in front of stove-0`.
    pub relation: String,
    /// Why: the target is left out.
    pub reason: String,
}

/// Whether target `t` is the reason `o` is there at all: a seat at a table, desk or anything
/// else one sits at (`around`, `in front of`, `behind` it), but not a seat that only looks at a
/// screen or stands by a sofa or bed. Such an object leaves with its target; any other object
/// stays and gives up the relation.
fn reason_to_be(
    o: &crate::check::scene::Object,
    kind: RelationKind,
    t: &crate::check::scene::Object,
) -> bool {
    use super::Role;
    let seat = Role::of(&o.category) == Role::Seat;
    let at = matches!(kind, RelationKind::Around | RelationKind::InFrontOf | RelationKind::Behind);
    let looked_at =
        matches!(Role::of(&t.category), Role::Screen | Role::Sofa | Role::Bed | Role::Seat);
    seat && at && !looked_at
}

/// Solves every room of the scene.
///
/// Every object the scene asks for ends in the layout (placed) or in its room's
/// [`RoomLayout::unplaced`] with the reason and the code of the diagnostic that says so: no
/// asset (W0401), no pose (W0501), left out with the target it exists for or the receptacle
/// it stands on (W0503), beyond the room's limit (W0504). Ceiling lights that the room's light
/// serves are counted apart.
pub fn solve(
    scene: &Scene,
    plan: &FloorPlan,
    resolved: &Resolved,
    options: &SolveOptions,
) -> Outcome<Layout> {
    solve_by_room(scene, plan, resolved, options, None, &|_| {})
}

/// One room as soon as it is solved, given to the callback of [`solve_by_room`].
#[derive(Clone, Copy, Debug)]
pub struct RoomDone<'a> {
    /// The room's place in the scene's room order (its [`RoomId`]'s number).
    pub index: usize,
    /// The room, solved.
    pub solved: &'a SolvedRoom,
    /// The room's relations given up because their target is left out (W0505). The whole
    /// scene's diagnostics list these for every room, in room order, before the rooms' own.
    pub given_up: &'a [crate::diag::Diagnostic],
    /// The room's own diagnostics (objects that could not be placed, ...), in the order the
    /// whole scene's diagnostics list them.
    pub diagnostics: &'a [crate::diag::Diagnostic],
}

/// Solves every room of the scene as [`solve`] does, calling `on_room` as each room is solved:
/// room `first` before any other (alone, on the calling thread), then the others on rayon's
/// threads in the order they finish. Each room keeps its own seed, so every room's layout and
/// diagnostics, and the result, are those of [`solve`] whatever the order.
///
/// A cancellation token of the calling thread (`crate::cancel`) goes with the rooms: once it is
/// cancelled no room starts, a room being solved stops early, and neither is given to
/// `on_room` (the result is incomplete and is to be thrown away, as with [`solve`]).
pub fn solve_by_room(
    scene: &Scene,
    plan: &FloorPlan,
    resolved: &Resolved,
    options: &SolveOptions,
    first: Option<RoomId>,
    on_room: &(dyn Fn(RoomDone<'_>) + Sync),
) -> Outcome<Layout> {
    use crate::check::scene::Placement;
    use crate::diag::Code;
    // The scene without the objects that have no asset.
    let mut kept = scene.clone();
    let mut no_asset: Vec<(RoomId, ObjectId)> = Vec::new();
    for room in &mut kept.rooms {
        room.objects.retain(|id| {
            let has = resolved.object(*id).is_some();
            if !has {
                no_asset.push((room.id, *id));
            }
            has
        });
    }
    // Objects whose reason to be is left out follow it (chairs around a table that has no
    // asset are not placed around nothing); the chain is followed. Any other relation to an
    // object left out is given up and the object stays.
    let mut dependents: Vec<(RoomId, ObjectId, String)> = Vec::new();
    loop {
        let mut dropped = Vec::new();
        for room in &kept.rooms {
            for &id in &room.objects {
                let o = kept.object(id);
                let Placement::Floor { constraints, .. } = &o.placement else { continue };
                let reasons: Vec<&crate::check::scene::Constraint> = constraints
                    .iter()
                    .filter(|c| reason_to_be(o, c.kind, scene.object(c.target)))
                    .collect();
                if !reasons.is_empty() && reasons.iter().all(|c| !room.objects.contains(&c.target))
                {
                    let targets: Vec<String> = reasons
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
            dependents.push((room, id, targets));
        }
    }
    // Relations of the objects that stay to objects left out: given up, and said.
    let mut given_up: Vec<(RoomId, GivenUp)> = Vec::new();
    let mut given_up_said: Vec<(RoomId, crate::diag::Diagnostic)> = Vec::new();
    let mut diagnostics = Vec::new();
    for room in &kept.rooms {
        for &id in &room.objects {
            let o = kept.object(id);
            let Placement::Floor { constraints, .. } = &o.placement else { continue };
            for c in constraints.iter().filter(|c| !room.objects.contains(&c.target)) {
                let target = &scene.object(c.target).name;
                let relation = format!("{} {target}", c.kind.as_str());
                let reason = format!("`{target}` is left out");
                let said = super::errors::relation_given_up(&o.name, &relation, &reason, c.span);
                diagnostics.push(said.clone());
                given_up_said.push((room.id, said));
                given_up.push((room.id, GivenUp { object: o.name.clone(), relation, reason }));
            }
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
    // Rooms are solved independently (each with its own seed), on as many threads as rayon
    // has (a room alone, or every room when `rooms_in_parallel` is off, on the calling
    // thread), and gathered in room order: the output does not depend on the threads. A batch job's
    // cancellation token goes with its rooms to the threads that solve them.
    let token = crate::cancel::current();
    let solve_one =
        |room: &crate::check::scene::Room| -> Option<(SolvedRoom, Vec<crate::diag::Diagnostic>)> {
            let _token = crate::cancel::scoped(token.clone());
            // A cancelled batch job (`crate::cancel`) solves no more rooms; its result is dropped.
            if crate::cancel::requested() {
                return None;
            }
            let mut diagnostics = Vec::new();
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
            // The items on top, in the problem's order: object by object as the room lists them
            // (floor and wall objects alike), line by line, copy by copy.
            let mut small_keys = Vec::new();
            for &id in &room.objects {
                for (_, k, copy) in item_ids(kept.object(id)) {
                    small_keys.push((id, k, copy));
                }
            }
            // Each copy of a small object has its own asset, hence its own size; a copy without an
            // asset (reported by resolve, W0401) takes no room on its receptacle and is listed as
            // left out.
            let choice = |&(receptacle, line, copy): &(ObjectId, usize, u32)| {
                resolved
                    .small
                    .get(&(receptacle, line))
                    .and_then(|v| v.get(copy as usize))
                    .and_then(Resolution::choice)
            };
            let has_asset: Vec<bool> = small_keys.iter().map(|k| choice(k).is_some()).collect();
            let mut without_asset: Vec<(String, (ObjectId, usize, u32))> = Vec::new();
            let mut n = 0;
            problem.small_objects.retain(|s| {
                n += 1;
                let keep = has_asset.get(n - 1).copied().unwrap_or(false);
                if !keep {
                    if let Some(&key) = small_keys.get(n - 1) {
                        without_asset.push((s.id.clone(), key));
                    }
                }
                keep
            });
            small_keys.retain(|k| choice(k).is_some());
            // The receptacles of the room by AI2-THOR type, for things whose declared receptacle
            // may not carry them (ProcTHOR's receptacle pairs): a desk lamp on an armchair goes to
            // the nearest side table.
            let holders: Vec<(super::Holder, Option<String>)> = (problem.objects.iter())
                .enumerate()
                .map(|(i, o)| (super::Holder::Floor(i), o.thor_type.clone()))
                .chain(
                    problem
                        .wall_objects
                        .iter()
                        .enumerate()
                        .map(|(i, o)| (super::Holder::Wall(i), o.thor_type.clone())),
                )
                .collect();
            let type_of = |h: super::Holder| {
                holders.iter().find(|(x, _)| *x == h).and_then(|(_, t)| t.clone())
            };
            // The receptacles of the room a thing may be moved to (`receptacles::move_to`: a
            // home for it, a pair ProcTHOR's houses hold at least one time in twenty), in the
            // order declared; the layout takes the nearest with room for it.
            let homes_for = |object_type: &str, item: &str, except: Option<super::Holder>| {
                holders
                    .iter()
                    .filter(|(h, t)| {
                        Some(*h) != except
                            && t.as_deref().is_some_and(|t| {
                                crate::resolve::receptacles::move_to(object_type, item, t).is_ok()
                            })
                    })
                    .map(|(h, _)| *h)
                    .collect::<Vec<_>>()
            };
            for (small, key) in problem.small_objects.iter_mut().zip(&small_keys) {
                if let Some(c) = choice(key) {
                    small.size = bbox_to_size(c.bbox_m);
                    small.thor_type = Some(c.object_type.clone());
                    let here = type_of(small.on);
                    let refused = here.as_deref().is_some_and(|t| {
                        crate::resolve::is_receptacle_type(t)
                            && crate::resolve::receptacles::judges(&c.object_type)
                            && !crate::resolve::allowed_on(&c.object_type, t)
                    });
                    if refused && !c.pinned {
                        small.elsewhere =
                            Some(homes_for(&c.object_type, &small.item, Some(small.on)));
                    }
                }
            }
            // The things on a receptacle left out for want of an asset (a floating wall shelf
            // AI2-THOR has no asset for) go to the room's receptacles that are a home for them
            // (`receptacles::move_to`), the nearest to where that receptacle was asked to stand
            // with room for it and fewer than three moved things (W0506 says where); else they
            // are left out with the reason (W0506).
            let mut rehomed: std::collections::BTreeSet<String> = std::collections::BTreeSet::new();
            let index_of = |target: ObjectId| {
                let name = &scene.object(target).name;
                problem.objects.iter().position(|p| &p.id == name).map(super::Holder::Floor)
            };
            for &(_, id) in no_asset.iter().filter(|(r, _)| *r == room.id) {
                let o = scene.object(id);
                let anchor: Vec<super::Holder> = match &o.placement {
                    crate::check::Placement::Floor { constraints, .. } => {
                        constraints.iter().filter_map(|c| index_of(c.target)).collect()
                    }
                    crate::check::Placement::Wall { above, .. } => {
                        above.iter().filter_map(|(t, _)| index_of(*t)).collect()
                    }
                };
                for (item_id, line, copy) in item_ids(o) {
                    let key = (id, line, copy);
                    let Some(c) = choice(&key) else { continue };
                    let item = &o.on_top[line];
                    let takes = homes_for(&c.object_type, &item.item, None);
                    let Some(&first) = holders.first().map(|(h, _)| h) else { continue };
                    problem.small_objects.push(super::SmallObject {
                        id: item_id.clone(),
                        item: item.item.clone(),
                        size: bbox_to_size(c.bbox_m),
                        on: takes.first().copied().unwrap_or(first),
                        elsewhere: Some(takes),
                        absent: Some(o.name.clone()),
                        anchor: anchor.clone(),
                        thor_type: Some(c.object_type.clone()),
                        span: Some(item.span),
                    });
                    small_keys.push(key);
                    rehomed.insert(item_id);
                }
            }
            let room_options = SolveOptions {
                seed: options.seed ^ (room.id.0 as u64).wrapping_mul(0x9E37_79B9_7F4A_7C15),
                ..*options
            };
            let mut solved = super::solve_room(&problem, &room_options);
            diagnostics.extend(solved.diagnostics);
            let unplaced = &mut solved.value.unplaced;
            let left_out = |id: String, kind: &'static str, reason: String, code: Code| {
                super::Unplaced { id, kind, rule: None, reason, code }
            };
            let kind_of =
                |o: &crate::check::scene::Object| if o.is_floor() { "floor" } else { "wall" };
            // What stands on an object that is left out goes with it.
            let items_follow =
                |o: &crate::check::scene::Object, unplaced: &mut Vec<super::Unplaced>| {
                    for (id, ..) in item_ids(o) {
                        unplaced.push(left_out(
                            id,
                            "small",
                            format!("its receptacle `{}` is left out", o.name),
                            Code::W0503,
                        ));
                    }
                };
            // Why resolve found no asset, in its words.
            let why = |r: Option<&Resolution>| match r {
                Some(Resolution::Unresolved(u)) => u.reason.clone(),
                _ => "no catalog asset matches it well enough".to_string(),
            };
            for &(_, id) in no_asset.iter().filter(|(r, _)| *r == room.id) {
                let o = scene.object(id);
                unplaced.push(left_out(
                    o.name.clone(),
                    kind_of(o),
                    why(resolved.objects.get(id.0)),
                    Code::W0401,
                ));
                // Its things that were not taken elsewhere: left out for want of an asset of their
                // own (W0401) or with it (W0503).
                for (item_id, line, copy) in item_ids(o) {
                    if rehomed.contains(&item_id) {
                        continue;
                    }
                    let r = resolved.small.get(&(id, line)).and_then(|v| v.get(copy as usize));
                    unplaced.push(match r.and_then(Resolution::choice) {
                    Some(_) => left_out(
                        item_id,
                        "small",
                        format!(
                            "its receptacle `{}` is left out, and no receptacle of the room takes it",
                            o.name
                        ),
                        Code::W0503,
                    ),
                    None => left_out(item_id, "small", why(r), Code::W0401),
                });
                }
            }
            for (id, (receptacle, line, copy)) in without_asset {
                let r = resolved.small.get(&(receptacle, line)).and_then(|v| v.get(copy as usize));
                unplaced.push(left_out(id, "small", why(r), Code::W0401));
            }
            if room.ceiling.is_some()
                && problem.ceiling.is_none()
                && !resolved.ceiling_lights.contains_key(&room.id)
            {
                unplaced.push(left_out(
                    format!("ceiling ({})", room.name),
                    "ceiling",
                    why(resolved.ceilings.get(&room.id)),
                    Code::W0401,
                ));
            }
            for (_, id, targets) in dependents.iter().filter(|(r, ..)| *r == room.id) {
                let o = scene.object(*id);
                let u = left_out(
                    o.name.clone(),
                    "floor",
                    format!("`{}` is there for {targets}, which is left out", o.name),
                    Code::W0503,
                );
                diagnostics.push(super::errors::dependent_left_out(&u, Some(o.name_span)));
                unplaced.push(u);
                items_follow(o, unplaced);
            }
            let beyond: Vec<ObjectId> =
                over_limit.iter().filter(|(r, _)| *r == room.id).map(|&(_, id)| id).collect();
            if let Some(&first) = beyond.first() {
                let object = scene.object(first);
                diagnostics.push(
                    crate::diag::Diagnostic::new(
                        Code::W0504,
                        format!(
                        "room `{}` has {} floor objects; the {} after the first {} are left out",
                        room.name,
                        super::MAX_FLOOR_OBJECTS_PER_ROOM + beyond.len(),
                        beyond.len(),
                        super::MAX_FLOOR_OBJECTS_PER_ROOM
                    ),
                    )
                    .with_primary(object.name_span, "the first object left out")
                    .with_help(
                        "split the room, or leave out objects; a real room holds a few dozen",
                    ),
                );
                for &id in &beyond {
                    let o = scene.object(id);
                    unplaced.push(left_out(
                        o.name.clone(),
                        "floor",
                        format!(
                            "the room holds more than {} floor objects",
                            super::MAX_FLOOR_OBJECTS_PER_ROOM
                        ),
                        Code::W0504,
                    ));
                    items_follow(o, unplaced);
                }
            }
            let solved_room = SolvedRoom {
                room: room.id,
                problem,
                layout: solved.value,
                floor_ids,
                wall_ids,
                small_keys,
                given_up: given_up
                    .iter()
                    .filter(|(r, _)| *r == room.id)
                    .map(|(_, g)| g.clone())
                    .collect(),
            };
            Some((solved_room, diagnostics))
        };
    // A room is reported as soon as it is solved, unless the work was cancelled meanwhile (a
    // room whose search was cut short is not the room `solve` would give).
    let solve_and_report = |room: &crate::check::scene::Room| {
        let one = solve_one(room);
        let cancelled = token.as_ref().is_some_and(|t| t.is_cancelled());
        if let (Some((solved, room_diagnostics)), false) = (&one, cancelled) {
            let said: Vec<crate::diag::Diagnostic> = given_up_said
                .iter()
                .filter(|(r, _)| *r == room.id)
                .map(|(_, d)| d.clone())
                .collect();
            on_room(RoomDone {
                index: room.id.0,
                solved,
                given_up: &said,
                diagnostics: room_diagnostics,
            });
        }
        one
    };
    let head = first.and_then(|id| kept.rooms.iter().find(|r| r.id == id));
    let head = head.map(|room| (room.id, solve_and_report(room)));
    let rest: Vec<&crate::check::scene::Room> =
        kept.rooms.iter().filter(|r| head.as_ref().is_none_or(|(id, _)| r.id != *id)).collect();
    let mut per_room: Vec<_> = if rest.len() < 2 || !options.rooms_in_parallel {
        // A room alone is solved on the calling thread: a one-room build starts no thread.
        rest.into_iter().map(|room| (room.id, solve_and_report(room))).collect()
    } else {
        use rayon::prelude::*;
        rest.into_par_iter().map(|room| (room.id, solve_and_report(room))).collect()
    };
    // Gathered in room order, whatever order they were solved in.
    per_room.extend(head);
    per_room.sort_by_key(|(id, _)| id.0);
    let per_room = per_room.into_iter().map(|(_, one)| one);
    let mut rooms = Vec::with_capacity(per_room.len());
    for one in per_room {
        let Some((solved_room, room_diagnostics)) = one else { break };
        diagnostics.extend(room_diagnostics);
        rooms.push(solved_room);
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

//! The checker: syntax tree → typed [`Scene`].
//!
//! It resolves every name to an id, converts every quantity to metres or degrees, expands object
//! groups into instances (`chair-0`, `chair-1`, …) and checks what the grammar cannot: units,
//! vocabularies, value ranges, duplicates, references and their kinds, the order of constraints
//! (a constraint may only name an object declared before it, so that constraints never form a
//! cycle). It reports every problem it finds, one diagnostic per cause: a name that does not
//! resolve makes the constraint disappear from the scene, and nothing else complains about it.
//!
//! **Invariant:** the [`Scene`] holds no syntax; later stages see ids, metres and degrees.

mod dump;
pub mod scene;

pub use dump::dump;
mod units;

pub use scene::*;

use crate::ast::{self, Quantity};
use crate::diag::{suggest, Code, Diagnostic, Outcome};
use crate::source::Span;
use std::collections::BTreeMap;
use units::{angle_deg, count, length_m};

/// The allowed wall heights, metres (inclusive).
pub const WALL_HEIGHT_RANGE_M: (f64, f64) = (2.0, 8.0);
/// The largest number of instances in one object group.
pub const MAX_GROUP_COUNT: u32 = 50;
/// The most corners a room outline may have (real rooms have 4 to 20; the plan stage's checks
/// grow with the square of the corners).
pub const MAX_ROOM_CORNERS: usize = 200;
/// The largest number of windows in one window row.
pub const MAX_WINDOW_COUNT: u32 = 20;
/// The largest number of small objects in one `on top` line.
pub const MAX_ON_TOP_COUNT: u32 = 20;
/// The default sill height of a window, metres.
pub const DEFAULT_SILL_M: f64 = 0.9;

/// Checks a parsed file and builds the typed scene.
pub fn check(file: &ast::File) -> Outcome<Scene> {
    let parts = check_parts(file);
    let mut diagnostics = parts.head;
    for room in parts.rooms {
        diagnostics.extend(room.diagnostics);
    }
    diagnostics.extend(parts.tail);
    Outcome::new(parts.scene, diagnostics)
}

/// What [`check`] makes of a file, its diagnostics by where they come from (in that order, they
/// are `check`'s): what the language server keeps to check again only the rooms an edit touched.
#[derive(Debug)]
pub struct CheckParts {
    /// The scene.
    pub scene: Scene,
    /// The diagnostics of the `scene` blocks and of the rooms' names.
    pub head: Vec<Diagnostic>,
    /// Each room of the scene's own, in the scene's order.
    pub rooms: Vec<RoomDiagnostics>,
    /// The doors' and the scene's as a whole (no room).
    pub tail: Vec<Diagnostic>,
}

/// A room's own diagnostics.
#[derive(Clone, Debug)]
pub struct RoomDiagnostics {
    /// The diagnostics, in the order [`check`] gives them.
    pub diagnostics: Vec<Diagnostic>,
    /// Whether they read the other rooms (a name that does not resolve in its room is looked
    /// for in every room): then they hold only as long as no room changes.
    pub reads_other_rooms: bool,
}

/// [`check`], with its diagnostics by where they come from.
pub fn check_parts(file: &ast::File) -> CheckParts {
    let mut checker = Checker::new(file);
    checker.file(file)
}

/// Checks room `room` of `file` alone, as [`check`] checks it when it is the scene's room `id`,
/// its objects numbered from `first_object`, in a scene whose walls are `wall_height_m` high:
/// the room, its objects in order and its diagnostics.
pub fn check_room(
    file: &ast::File,
    room: &ast::Room,
    id: RoomId,
    first_object: usize,
    wall_height_m: f64,
) -> (Room, Vec<Object>, RoomDiagnostics) {
    let mut checker = Checker::new(file);
    let mut scene = Scene::empty(wall_height_m);
    let mut checked = checker.room(room, id, &mut scene);
    let mut objects = scene.objects;
    if first_object != 0 {
        renumber_objects(&mut checked, &mut objects, first_object as isize);
    }
    let diagnostics = RoomDiagnostics {
        diagnostics: checker.diagnostics,
        reads_other_rooms: checker.read_other_rooms,
    };
    (checked, objects, diagnostics)
}

/// Checks the doors of `file` against the rooms of `scene` (its doors made again) and whether it
/// has a room, as [`check`] does after the rooms; their diagnostics.
pub fn check_tail(file: &ast::File, scene: &mut Scene) -> Vec<Diagnostic> {
    let mut checker = Checker::new(file);
    scene.doors.clear();
    checker.tail(file, scene);
    checker.diagnostics
}

/// Moves the ids of a room's objects by `by` (its objects come `by` places later in the scene's
/// list): the room's list, each object's id, its relations' targets and the object it hangs
/// above, and the ceiling object's.
pub fn renumber_objects(room: &mut Room, objects: &mut [Object], by: isize) {
    let moved = |id: &mut ObjectId| id.0 = id.0.wrapping_add_signed(by);
    for id in &mut room.objects {
        moved(id);
    }
    if let Some((id, _)) = room.ceiling.as_mut().and_then(|c| c.above.as_mut()) {
        moved(id);
    }
    renumber(objects, by);
}

/// What the check of one room records to check one of its object groups again alone
/// ([`check_group_again`]): the room's instance names and, for each object group, where its
/// statement starts, what it declares and where its diagnostics are in the room's. Offsets are
/// from the room's start and object ids from its first object, so that the shape holds while
/// the room moves in the text and in the scene's list of objects.
#[derive(Clone, Debug)]
pub struct RoomShape {
    names: RoomNames,
    /// The object groups in the order they are expanded (floor groups, then wall groups).
    groups: Vec<GroupShape>,
    /// Where each statement of the room's body that is not a comment or a blank line starts.
    statements: Vec<u32>,
    /// Whether a constraint named an object declared after its own (the room's objects were
    /// then put in another order, which one group alone cannot be checked against).
    forward: bool,
}

/// One object group of a [`RoomShape`].
#[derive(Clone, Debug)]
struct GroupShape {
    name: String,
    /// Where its statement starts, from the room's start.
    start: u32,
    is_wall: bool,
    count: u32,
    /// Its first object, from the room's first.
    first: usize,
    /// Whether its `count` gave no diagnostic.
    count_clean: bool,
    /// Where the diagnostics of its expansion are in the room's.
    diagnostics: std::ops::Range<usize>,
}

impl RoomShape {
    fn of(
        room: &ast::Room,
        groups: &[Group<'_>],
        names: &RoomNames,
        base: usize,
        expanded: Vec<std::ops::Range<usize>>,
        count_clean: &[bool],
        forward: bool,
    ) -> RoomShape {
        let from = room.span.start;
        let relative = |id: ObjectId| ObjectId(id.0 - base);
        let names = RoomNames {
            instances: names
                .instances
                .iter()
                .map(|(k, &(id, floor))| (k.clone(), (relative(id), floor)))
                .collect(),
            groups: names
                .groups
                .iter()
                .map(|(k, &(n, id))| (k.clone(), (n, relative(id))))
                .collect(),
        };
        // `count_clean` is in declaration order, `groups` floor groups first.
        let mut clean_of: BTreeMap<u32, bool> = BTreeMap::new();
        let mut declared: Vec<&Group<'_>> = groups.iter().collect();
        declared.sort_by_key(|g| g.decl.span.start);
        for (g, clean) in declared.iter().zip(count_clean) {
            clean_of.insert(g.decl.span.start, *clean);
        }
        let groups = groups
            .iter()
            .zip(expanded)
            .map(|(g, diagnostics)| GroupShape {
                name: g.decl.id.name.clone(),
                start: g.decl.span.start - from,
                is_wall: g.is_wall,
                count: g.count,
                first: g.first - base,
                count_clean: clean_of.get(&g.decl.span.start).copied().unwrap_or(false),
                diagnostics,
            })
            .collect();
        let statements = room
            .body
            .iter()
            .filter(|st| !matches!(st, ast::RoomStmt::Comment(_) | ast::RoomStmt::Blank(_)))
            .map(|st| room_stmt_start(st) - from)
            .collect();
        RoomShape { names, groups, statements, forward }
    }
}

/// Where a room statement starts.
fn room_stmt_start(stmt: &ast::RoomStmt) -> u32 {
    match stmt {
        ast::RoomStmt::FloorDesign(_, s)
        | ast::RoomStmt::WallDesign(_, s)
        | ast::RoomStmt::FloorMaterial(_, s)
        | ast::RoomStmt::WallMaterial(_, s)
        | ast::RoomStmt::Blank(s) => s.start,
        ast::RoomStmt::Corners(c) => c.span.start,
        ast::RoomStmt::Window(w) => w.span.start,
        ast::RoomStmt::Object(o) | ast::RoomStmt::WallObject(o) => o.span.start,
        ast::RoomStmt::Ceiling(c) => c.span.start,
        ast::RoomStmt::Comment(c) => c.span.start,
        ast::RoomStmt::Error(e) => e.span.start,
    }
}

/// [`check_room`], with the room's [`RoomShape`] (`None` when a group's name is given twice).
pub fn check_room_shaped(
    file: &ast::File,
    room: &ast::Room,
    id: RoomId,
    first_object: usize,
    wall_height_m: f64,
) -> (Room, Vec<Object>, RoomDiagnostics, Option<RoomShape>) {
    let mut checker = Checker::new(file);
    checker.record_shape = true;
    let mut scene = Scene::empty(wall_height_m);
    let mut checked = checker.room(room, id, &mut scene);
    let mut objects = scene.objects;
    if first_object != 0 {
        renumber_objects(&mut checked, &mut objects, first_object as isize);
    }
    let diagnostics = RoomDiagnostics {
        diagnostics: checker.diagnostics,
        reads_other_rooms: checker.read_other_rooms,
    };
    (checked, objects, diagnostics, checker.shape)
}

/// One object group checked again alone ([`check_group_again`]).
#[derive(Debug)]
pub struct GroupChecked {
    /// The place of the group's objects in the room's (from its first object).
    pub objects: std::ops::Range<usize>,
    /// Its objects checked again, numbered from the scene's first object.
    pub new_objects: Vec<Object>,
    /// The place of the diagnostics of its expansion in the room's.
    pub diagnostics: std::ops::Range<usize>,
    /// Those diagnostics now.
    pub new_diagnostics: Vec<Diagnostic>,
    /// Whether they read the other rooms.
    pub reads_other_rooms: bool,
}

/// Checks again, alone, the one object group an edit inside the body of `room` replaced
/// (`body`, the statement groups the parser replaced, see [`crate::parse::BodySplice`]), as
/// [`check`] checks it in that room: `checked` is the room as checked before the edit, its
/// objects numbered from `first_object`, and `shape` its shape, updated to the edited room.
/// `None` (with `shape` unchanged) when the edit did more than change one object group's
/// statements but its name, kind and count (and the count said nothing), or when the room's
/// objects are placed in an order of their own (a constraint naming a later object): then the
/// room is to be checked whole.
pub fn check_group_again(
    file: &ast::File,
    room: &ast::Room,
    checked: &Room,
    shape: &mut RoomShape,
    body: crate::parse::BodySplice,
    first_object: usize,
    wall_height_m: f64,
) -> Option<GroupChecked> {
    if shape.forward || body.old_groups != 1 || body.new_groups != 1 {
        return None;
    }
    let from = u32::try_from(body.room_start).ok()?;
    if room.span.start != from || body.start < body.room_start {
        return None;
    }
    let relative = |at: usize| u32::try_from(at - body.room_start).ok();
    let (start, old_end, new_end) =
        (relative(body.start)?, relative(body.old_end)?, relative(body.new_end)?);
    // Before the edit: one statement in the groups replaced, an object group's.
    let in_old = |at: u32| (start..old_end).contains(&at);
    if shape.statements.iter().filter(|&&at| in_old(at)).count() != 1 {
        return None;
    }
    let k = shape.groups.iter().position(|g| in_old(g.start))?;
    // After: one statement there, an object group of the same name and kind.
    let in_new = |at: u32| (start..new_end).contains(&at);
    let mut found = room
        .body
        .iter()
        .filter(|st| !matches!(st, ast::RoomStmt::Comment(_) | ast::RoomStmt::Blank(_)))
        .skip_while(|st| room_stmt_start(st) - from < start)
        .take_while(|st| in_new(room_stmt_start(st) - from));
    let (stmt, extra) = (found.next()?, found.next());
    if extra.is_some() {
        return None;
    }
    let (o, is_wall) = match stmt {
        ast::RoomStmt::Object(o) => (o, false),
        ast::RoomStmt::WallObject(o) => (o, true),
        _ => return None,
    };
    let g = &shape.groups[k];
    if o.id.name != g.name || is_wall != g.is_wall || !g.count_clean {
        return None;
    }
    let mut checker = Checker::new(file);
    let count = checker.group_count(o);
    if count != g.count || !checker.diagnostics.is_empty() {
        return None;
    }
    let mut scene = Scene::empty(wall_height_m);
    let group = Group { decl: o, is_wall, count, first: g.first };
    checker.expand_group(&group, checked.id, checked, &shape.names, &mut scene);
    let mut objects = scene.objects;
    // A constraint naming a later object would put the room's objects in another order.
    let forward = objects.iter().any(|obj| match &obj.placement {
        Placement::Floor { constraints, .. } => constraints.iter().any(|c| c.target.0 > obj.id.0),
        Placement::Wall { .. } => false,
    });
    if forward {
        return None;
    }
    renumber(&mut objects, first_object as isize);
    // The shape of the edited room.
    let delta = i64::from(new_end) - i64::from(old_end);
    let moved = |at: &mut u32| {
        if *at >= old_end {
            *at = (i64::from(*at) + delta) as u32;
        }
    };
    for at in &mut shape.statements {
        moved(at);
    }
    let old = shape.groups[k].diagnostics.clone();
    let grown = checker.diagnostics.len() as isize - old.len() as isize;
    for (j, g) in shape.groups.iter_mut().enumerate() {
        if j == k {
            g.start = o.span.start - from;
            g.diagnostics = old.start..old.start + checker.diagnostics.len();
        } else {
            moved(&mut g.start);
            // The groups after it in the room's order (their diagnostics come after its own,
            // an empty range at the same place included).
            if j > k {
                g.diagnostics = g.diagnostics.start.wrapping_add_signed(grown)
                    ..g.diagnostics.end.wrapping_add_signed(grown);
            }
        }
    }
    let g = &shape.groups[k];
    Some(GroupChecked {
        objects: g.first..g.first + g.count as usize,
        new_objects: objects,
        diagnostics: old,
        new_diagnostics: checker.diagnostics,
        reads_other_rooms: checker.read_other_rooms,
    })
}

/// Moves the ids of objects by `by`: each object's id, its relations' targets and the object
/// it hangs above.
fn renumber(objects: &mut [Object], by: isize) {
    let moved = |id: &mut ObjectId| id.0 = id.0.wrapping_add_signed(by);
    for object in objects {
        moved(&mut object.id);
        match &mut object.placement {
            Placement::Floor { global: _, constraints } => {
                for c in constraints {
                    moved(&mut c.target);
                }
            }
            Placement::Wall { above, height_m: _ } => {
                if let Some((id, _)) = above {
                    moved(id);
                }
            }
        }
    }
}

struct Checker<'a> {
    diagnostics: Vec<Diagnostic>,
    /// The file, whose rooms [`Checker::all_instances`] is made from when first needed.
    file: &'a ast::File,
    /// Every object name of every room (instances and groups) → the rooms that declare it, so
    /// that a reference to an object of another room is named as such. Made on first use (a
    /// name that does not resolve in its room), so that a valid scene never makes it.
    all_instances: Option<BTreeMap<String, Vec<String>>>,
    /// Whether the room being checked read [`Checker::all_instances`].
    read_other_rooms: bool,
    /// Whether to record the shape of each room checked ([`check_room_shaped`]).
    record_shape: bool,
    /// The shape of the room checked last, when recorded.
    shape: Option<RoomShape>,
}

/// A declared object group, before expansion.
struct Group<'a> {
    decl: &'a ast::Object,
    is_wall: bool,
    count: u32,
    first: usize,
}

/// The instance names of one room, for reference resolution.
#[derive(Clone, Debug)]
struct RoomNames {
    /// Instance name → object index and whether it stands on the floor.
    instances: BTreeMap<String, (ObjectId, bool)>,
    /// Group id → (count, first object).
    groups: BTreeMap<String, (u32, ObjectId)>,
}

impl<'a> Checker<'a> {
    fn new(file: &'a ast::File) -> Checker<'a> {
        Checker {
            diagnostics: Vec::new(),
            file,
            all_instances: None,
            read_other_rooms: false,
            record_shape: false,
            shape: None,
        }
    }

    fn push(&mut self, d: Diagnostic) {
        self.diagnostics.push(d);
    }

    /// The rooms that declare an object or instance called `name`.
    fn rooms_declaring(&mut self, name: &str) -> &[String] {
        let file = self.file;
        self.read_other_rooms = true;
        let all = self.all_instances.get_or_insert_with(|| {
            // The rooms the scene keeps: not `exterior`, the first of each name.
            let mut seen = std::collections::BTreeSet::new();
            let rooms = file
                .items
                .iter()
                .filter_map(|i| match i {
                    ast::Item::Room(room) => Some(room),
                    _ => None,
                })
                .filter(|room| room.id.name != "exterior" && seen.insert(room.id.name.as_str()));
            let mut all: BTreeMap<String, Vec<String>> = BTreeMap::new();
            for room in rooms {
                for stmt in &room.body {
                    if let ast::RoomStmt::Object(o) | ast::RoomStmt::WallObject(o) = stmt {
                        let n = o
                            .body
                            .iter()
                            .find_map(|s| match s {
                                ast::ObjectStmt::Count(q, _, _)
                                    if q.value >= 1.0 && q.value <= f64::from(MAX_GROUP_COUNT) =>
                                {
                                    Some(q.value as u32)
                                }
                                _ => None,
                            })
                            .unwrap_or(1);
                        let mut names = vec![o.id.name.clone()];
                        names.extend((0..n).map(|i| format!("{}-{i}", o.id.name)));
                        for name in names {
                            all.entry(name).or_default().push(room.id.name.clone());
                        }
                    }
                }
            }
            all
        });
        all.get(name).map_or(&[], Vec::as_slice)
    }

    fn file(&mut self, file: &ast::File) -> CheckParts {
        let mut scene = Scene::empty(DEFAULT_WALL_HEIGHT_M);
        let mut scene_span: Option<Span> = None;
        for item in &file.items {
            if let ast::Item::Scene(block) = item {
                if let Some(first) = scene_span {
                    self.push(
                        Diagnostic::new(Code::E0215, "a file has more than one `scene` block")
                            .with_primary(block.span, "second `scene` block")
                            .with_secondary(first, "first `scene` block")
                            .with_help("merge the two blocks into one"),
                    );
                    continue;
                }
                scene_span = Some(block.span);
                self.scene_block(block, &mut scene);
            }
        }
        // Rooms: first their names, so that doors may name rooms declared anywhere.
        let mut room_ids: BTreeMap<String, (RoomId, Span)> = BTreeMap::new();
        let mut rooms: Vec<&ast::Room> = Vec::new();
        for item in &file.items {
            if let ast::Item::Room(room) = item {
                if room.id.name == "exterior" {
                    self.push(
                        Diagnostic::new(Code::E0203, "`exterior` is reserved for the outside")
                            .with_primary(room.id.span, "cannot name a room")
                            .with_help("give the room another identifier, e.g. `exterior_room`"),
                    );
                    continue;
                }
                if let Some((_, first)) = room_ids.get(&room.id.name) {
                    self.push(
                        Diagnostic::new(
                            Code::E0203,
                            format!("room `{}` is defined twice", room.id.name),
                        )
                        .with_primary(room.id.span, "defined again here")
                        .with_secondary(*first, "first defined here")
                        .with_help("give each room its own identifier"),
                    );
                    continue;
                }
                room_ids.insert(room.id.name.clone(), (RoomId(rooms.len()), room.id.span));
                rooms.push(room);
            }
        }
        let head = std::mem::take(&mut self.diagnostics);
        // Sized once: grown by doubling, the rooms of a large file took twice their memory.
        scene.rooms.reserve_exact(rooms.len());
        let mut room_diagnostics = Vec::with_capacity(rooms.len());
        for (index, room) in rooms.iter().enumerate() {
            self.read_other_rooms = false;
            let checked = self.room(room, RoomId(index), &mut scene);
            scene.rooms.push(checked);
            room_diagnostics.push(RoomDiagnostics {
                diagnostics: std::mem::take(&mut self.diagnostics),
                reads_other_rooms: self.read_other_rooms,
            });
        }
        self.tail(file, &mut scene);
        let tail = std::mem::take(&mut self.diagnostics);
        CheckParts { scene, head, rooms: room_diagnostics, tail }
    }

    /// The doors (cross-room references need every room's names) and whether there is a room.
    fn tail(&mut self, file: &ast::File, scene: &mut Scene) {
        let room_ids: BTreeMap<String, (RoomId, Span)> =
            scene.rooms.iter().map(|r| (r.name.clone(), (r.id, r.name_span))).collect();
        self.doors(file, &room_ids, scene);
        let has_bad_line = file.items.iter().any(|i| matches!(i, ast::Item::Error(_)));
        if scene.rooms.is_empty() && !has_bad_line {
            let span = file.span;
            self.push(
                Diagnostic::new(Code::W0203, "the scene declares no room")
                    .with_primary(Span { end: span.start, ..span }, "no `room` block in this file")
                    .with_help("add a room, e.g. `room bedroom \"bedroom\" { corners in m (0, 0) (0, 4) (4, 4) (4, 0) }`"),
            );
        }
    }

    fn scene_block(&mut self, block: &ast::SceneBlock, scene: &mut Scene) {
        scene.request = block.request.as_ref().map(|s| s.value.clone());
        let mut seen: BTreeMap<&str, Span> = BTreeMap::new();
        for stmt in &block.body {
            let (key, span) = match stmt {
                ast::SceneStmt::WallHeight(_, span) => ("wall height", *span),
                ast::SceneStmt::Seed(_, span) => ("seed", *span),
                // One ceiling setting: a pinned material or a design.
                ast::SceneStmt::CeilingMaterial(_, span)
                | ast::SceneStmt::CeilingDesign(_, span) => ("ceiling", *span),
                _ => continue,
            };
            if !self.first_setting(&mut seen, key, span) {
                continue;
            }
            match stmt {
                ast::SceneStmt::WallHeight(q, _) => {
                    if let Some(h) = length_m(q, None, "the wall height", &mut self.diagnostics) {
                        let (lo, hi) = WALL_HEIGHT_RANGE_M;
                        if (lo..=hi).contains(&h) {
                            scene.wall_height_m = h;
                        } else {
                            self.push(
                                Diagnostic::new(
                                    Code::E0208,
                                    format!(
                                        "wall height {} m is outside {lo} m to {hi} m",
                                        ast::format_number(h)
                                    ),
                                )
                                .with_primary(q.span, "out of range")
                                .with_help("AI2-THOR rooms are usually 2.5 m to 3.5 m high"),
                            );
                        }
                    }
                }
                ast::SceneStmt::Seed(q, _) => {
                    if q.unit.is_some()
                        || q.value < 0.0
                        || q.value.fract() != 0.0
                        || q.value > 9.0e15
                    {
                        self.push(
                            Diagnostic::new(
                                Code::E0208,
                                format!("seed `{}` is not a whole number ≥ 0", q.text),
                            )
                            .with_primary(q.span, "expected a whole number without unit")
                            .with_help("write e.g. `seed 42`"),
                        );
                    } else {
                        scene.seed = q.value as u64;
                    }
                }
                ast::SceneStmt::CeilingMaterial(m, _) => {
                    scene.ceiling_material = Some(Pinned { id: m.value.clone(), span: m.span });
                }
                ast::SceneStmt::CeilingDesign(d, _) => scene.ceiling_design = Some(d.value.clone()),
                _ => {}
            }
        }
    }

    /// Records a setting that a block takes once; reports it (E0213) and returns `false` when the
    /// block already gave it.
    fn first_setting<'k>(
        &mut self,
        seen: &mut BTreeMap<&'k str, Span>,
        key: &'k str,
        span: Span,
    ) -> bool {
        if let Some(first) = seen.get(key) {
            let first = *first;
            self.duplicate_setting(key, span, first);
            return false;
        }
        seen.insert(key, span);
        true
    }

    fn duplicate_setting(&mut self, key: &str, span: Span, first: Span) {
        self.push(
            Diagnostic::new(Code::E0213, format!("`{key}` is given twice"))
                .with_primary(span, "given again here")
                .with_secondary(first, "first given here")
                .with_help("keep one of them"),
        );
    }

    fn room(&mut self, room: &ast::Room, id: RoomId, scene: &mut Scene) -> Room {
        let mut checked = Room {
            id,
            name: room.id.name.clone(),
            label: room.label.as_ref().map_or_else(|| room.id.name.clone(), |l| l.value.clone()),
            floor_design: None,
            wall_design: None,
            floor_material: None,
            wall_material: None,
            corners: Vec::new(),
            corner_spans: Vec::new(),
            corners_unit_span: None,
            windows: Vec::new(),
            objects: Vec::new(),
            ceiling: None,
            name_span: room.id.span,
            decl_span: room.span,
        };
        let mut seen: BTreeMap<&str, Span> = BTreeMap::new();
        let mut groups: Vec<Group<'_>> = Vec::new();
        let mut group_spans: BTreeMap<String, Span> = BTreeMap::new();
        let mut ceiling_decl: Option<&ast::Ceiling> = None;
        // Whether each group's `count` gave no diagnostic (for the room's shape).
        let mut count_clean: Vec<bool> = Vec::new();
        let mut duplicates = false;
        for stmt in &room.body {
            let single = match stmt {
                ast::RoomStmt::FloorDesign(_, s) => Some(("floor", *s)),
                ast::RoomStmt::WallDesign(_, s) => Some(("walls", *s)),
                ast::RoomStmt::FloorMaterial(_, s) => Some(("floor material", *s)),
                ast::RoomStmt::WallMaterial(_, s) => Some(("wall material", *s)),
                ast::RoomStmt::Corners(c) => Some(("corners", c.span)),
                ast::RoomStmt::Ceiling(c) => Some(("ceiling", c.span)),
                _ => None,
            };
            if let Some((key, span)) = single {
                if !self.first_setting(&mut seen, key, span) {
                    continue;
                }
            }
            match stmt {
                ast::RoomStmt::FloorDesign(s, _) => checked.floor_design = Some(s.value.clone()),
                ast::RoomStmt::WallDesign(s, _) => checked.wall_design = Some(s.value.clone()),
                ast::RoomStmt::FloorMaterial(s, _) => {
                    checked.floor_material = Some(Pinned { id: s.value.clone(), span: s.span });
                }
                ast::RoomStmt::WallMaterial(s, _) => {
                    checked.wall_material = Some(Pinned { id: s.value.clone(), span: s.span });
                }
                ast::RoomStmt::Corners(c) => self.corners(c, &mut checked),
                ast::RoomStmt::Window(w) => {
                    if let Some(window) = self.window(w, scene.wall_height_m) {
                        checked.windows.push(window);
                    }
                }
                ast::RoomStmt::Object(o) | ast::RoomStmt::WallObject(o) => {
                    let is_wall = matches!(stmt, ast::RoomStmt::WallObject(_));
                    if let Some(first) = group_spans.get(&o.id.name) {
                        self.push(
                            Diagnostic::new(
                                Code::E0203,
                                format!(
                                    "object `{}` is defined twice in room `{}`",
                                    o.id.name, room.id.name
                                ),
                            )
                            .with_primary(o.id.span, "defined again here")
                            .with_secondary(*first, "first defined here")
                            .with_help("give each object group its own identifier, or use `count`"),
                        );
                        duplicates = true;
                        continue;
                    }
                    group_spans.insert(o.id.name.clone(), o.id.span);
                    let before = self.diagnostics.len();
                    let n = self.group_count(o);
                    count_clean.push(self.diagnostics.len() == before);
                    groups.push(Group { decl: o, is_wall, count: n, first: 0 });
                }
                ast::RoomStmt::Ceiling(c) => ceiling_decl = Some(c),
                ast::RoomStmt::Comment(_) | ast::RoomStmt::Error(_) | ast::RoomStmt::Blank(_) => {}
            }
        }
        if checked.corners.is_empty() && !seen.contains_key("corners") {
            self.push(
                Diagnostic::new(Code::E0214, format!("room `{}` has no corners", room.id.name))
                    .with_primary(room.id.span, "no `corners` statement")
                    .with_help("add its outline, e.g. `corners in m (0, 0) (0, 4) (5, 4) (5, 0)`"),
            );
        }
        // Floor groups first, then wall groups, each in declaration order.
        groups.sort_by_key(|g| g.is_wall);
        let mut names = RoomNames { instances: BTreeMap::new(), groups: BTreeMap::new() };
        let base = scene.objects.len();
        let mut next = base;
        for g in &mut groups {
            g.first = next;
            names.groups.insert(g.decl.id.name.clone(), (g.count, ObjectId(next)));
            for i in 0..g.count {
                names.instances.insert(
                    format!("{}-{i}", g.decl.id.name),
                    (ObjectId(next + i as usize), !g.is_wall),
                );
            }
            next += g.count as usize;
        }
        let mut expanded = Vec::with_capacity(if self.record_shape { groups.len() } else { 0 });
        for g in &groups {
            let before = self.diagnostics.len();
            self.expand_group(g, id, &checked, &names, scene);
            if self.record_shape {
                expanded.push(before..self.diagnostics.len());
            }
        }
        checked.objects = (groups.first().map_or(scene.objects.len(), |g| g.first)
            ..scene.objects.len())
            .map(ObjectId)
            .collect();
        let forward = self.check_constraint_order(&mut checked, scene);
        if self.record_shape {
            self.shape = (!duplicates).then(|| {
                RoomShape::of(room, &groups, &names, base, expanded, &count_clean, forward)
            });
        }
        if let Some(c) = ceiling_decl {
            checked.ceiling = Some(self.ceiling(c, &checked, &names, scene));
        }
        checked
    }

    fn corners(&mut self, c: &ast::Corners, room: &mut Room) {
        let default = c.unit.map(|(u, _)| u);
        if let Some((unit, span)) = c.unit {
            if !matches!(unit, ast::Unit::M | ast::Unit::Cm) {
                self.push(
                    Diagnostic::new(
                        Code::E0106,
                        format!("corners are given in `{}`", unit.as_str()),
                    )
                    .with_primary(span, "expected `m` or `cm`")
                    .with_help("write `corners in m ...` or `corners in cm ...`"),
                );
                return;
            }
        }
        room.corners_unit_span = c.unit.map(|(_, span)| span);
        if c.points.len() > MAX_ROOM_CORNERS {
            self.push(
                Diagnostic::new(
                    Code::E0220,
                    format!(
                        "room `{}` has {} corners; holoc accepts at most {MAX_ROOM_CORNERS}",
                        room.name,
                        c.points.len()
                    ),
                )
                .with_primary(c.span, "too many corners")
                .with_help("a room is a simple outline; split it into several rooms"),
            );
            return;
        }
        let mut ok = true;
        for p in &c.points {
            let x = length_m(&p.x, default, "a corner coordinate", &mut self.diagnostics);
            let z = length_m(&p.z, default, "a corner coordinate", &mut self.diagnostics);
            match (x, z) {
                (Some(x), Some(z)) => {
                    room.corners.push([x, z]);
                    room.corner_spans.push(p.span);
                }
                _ => ok = false,
            }
        }
        if ok && c.points.len() < 4 {
            self.push(
                Diagnostic::new(
                    Code::E0214,
                    format!(
                        "room `{}` has {} corners; an outline needs at least 4",
                        room.name,
                        c.points.len()
                    ),
                )
                .with_primary(c.span, "too few corners")
                .with_help(
                    "rooms are rectilinear polygons: list every corner, e.g. four for a rectangle",
                ),
            );
        }
    }

    fn word<T: Copy>(&mut self, word: &ast::Word, what: &str, table: &[(&str, T)]) -> Option<T> {
        let lower = word.name.to_lowercase();
        if let Some((_, v)) = table.iter().find(|(w, _)| *w == lower) {
            return Some(*v);
        }
        let names: Vec<&str> = table.iter().map(|(w, _)| *w).collect();
        let candidates = suggest::closest(&lower, names.iter().copied());
        let listed: Vec<String> = names.iter().map(|n| format!("`{n}`")).collect();
        self.push(
            Diagnostic::new(Code::E0211, format!("unknown {what} `{}`", word.name))
                .with_primary(word.span, format!("not a {what}"))
                .with_help(
                    suggest::did_you_mean(&candidates)
                        .unwrap_or_else(|| format!("a {what} is one of {}", listed.join(", "))),
                )
                .with_fixes(suggest::replacements(word.span, &candidates)),
        );
        None
    }

    fn window(&mut self, w: &ast::Window, wall_height_m: f64) -> Option<Window> {
        let wall = self.word(
            &w.wall,
            "wall direction",
            &[
                ("north", Direction::North),
                ("south", Direction::South),
                ("east", Direction::East),
                ("west", Direction::West),
            ],
        );
        let kind = self.word(
            &w.kind,
            "window type",
            &[
                ("fixed", WindowKind::Fixed),
                ("hung", WindowKind::Hung),
                ("slider", WindowKind::Slider),
            ],
        );
        let width = self.positive_length(&w.width, "the window width");
        let height = self.positive_length(&w.height, "the window height");
        let n = match &w.count {
            Some(q) => count(q, "the window count", 1, MAX_WINDOW_COUNT, &mut self.diagnostics),
            None => Some(1),
        };
        let sill = match &w.sill {
            Some(q) => {
                let s = length_m(q, None, "the sill height", &mut self.diagnostics);
                if let Some(s) = s {
                    if s < 0.0 {
                        self.push(
                            Diagnostic::new(Code::E0208, "the sill height is negative")
                                .with_primary(q.span, "below the floor")
                                .with_help(
                                    "the sill is the height of the window's bottom above the floor",
                                ),
                        );
                        None
                    } else {
                        Some(s)
                    }
                } else {
                    None
                }
            }
            None => Some(DEFAULT_SILL_M),
        };
        let (wall, kind, width, height, n, sill) = (wall?, kind?, width?, height?, n?, sill?);
        if sill + height > wall_height_m + 1e-9 {
            let span = w.sill.as_ref().map_or(w.span, |q| q.span);
            self.push(
                Diagnostic::new(
                    Code::E0208,
                    format!(
                        "the window's top ({} m) is above the wall ({} m)",
                        ast::format_number(round6(sill + height)),
                        ast::format_number(wall_height_m)
                    ),
                )
                .with_primary(span, "sill + height exceeds the wall height")
                .with_help(format!(
                    "lower the sill to at most {} cm",
                    ast::format_number(round6((wall_height_m - height) * 100.0).max(0.0))
                )),
            );
            return None;
        }
        let offered = kind.offered_sizes_cm();
        let (wc, hc) = (width * 100.0, height * 100.0);
        if !offered.iter().any(|(a, b)| (a - wc).abs() < 0.5 && (b - hc).abs() < 0.5) {
            let nearest = offered
                .iter()
                .min_by(|a, b| {
                    let da = (a.0 - wc).hypot(a.1 - hc);
                    let db = (b.0 - wc).hypot(b.1 - hc);
                    da.total_cmp(&db)
                })
                .copied()
                .unwrap_or((wc, hc));
            self.push(
                Diagnostic::new(
                    Code::W0201,
                    format!(
                        "{} windows come in other sizes; {} cm x {} cm is not one of them",
                        kind.as_str(),
                        ast::format_number(round6(wc)),
                        ast::format_number(round6(hc))
                    ),
                )
                .with_primary(
                    w.width.span.to(w.height.span),
                    "the nearest offered size will be used",
                )
                .with_help(format!(
                    "write `{} cm x {} cm`, the nearest size of a {} window",
                    nearest.0,
                    nearest.1,
                    kind.as_str()
                )),
            );
        }
        Some(Window {
            wall,
            kind,
            width_m: width,
            height_m: height,
            count: n,
            sill_m: sill,
            asset: w.asset.as_ref().map(|s| Pinned { id: s.value.clone(), span: s.span }),
            span: w.span,
        })
    }

    fn positive_length(&mut self, q: &Quantity, what: &str) -> Option<f64> {
        let v = length_m(q, None, what, &mut self.diagnostics)?;
        if v <= 0.0 {
            self.push(
                Diagnostic::new(Code::E0208, format!("{what} must be greater than zero"))
                    .with_primary(q.span, "not a positive length"),
            );
            return None;
        }
        Some(v)
    }

    fn group_count(&mut self, o: &ast::Object) -> u32 {
        let mut n = 1;
        let mut seen: Option<Span> = None;
        for stmt in &o.body {
            if let ast::ObjectStmt::Count(q, _, span) = stmt {
                if let Some(first) = seen {
                    self.duplicate_setting("count", *span, first);
                    continue;
                }
                seen = Some(*span);
                // An out-of-range count is an error; the group still declares as many
                // instances as it can hold, so references to them do not cascade.
                n = count(q, "the object count", 1, MAX_GROUP_COUNT, &mut self.diagnostics)
                    .unwrap_or_else(|| fallback_count(q));
            }
        }
        n
    }

    fn expand_group(
        &mut self,
        g: &Group<'_>,
        room: RoomId,
        checked: &Room,
        names: &RoomNames,
        scene: &mut Scene,
    ) {
        let o = g.decl;
        // Group-level settings.
        let mut base = Object {
            id: ObjectId(g.first),
            room,
            name: String::new(),
            group: o.id.name.clone(),
            index: 0,
            group_count: g.count,
            category: o.category.value.clone(),
            description: None,
            size_m: None,
            variance: Variance::Same,
            asset: None,
            at: None,
            facing_deg: None,
            placement: if g.is_wall {
                Placement::Wall { above: None, height_m: None }
            } else {
                Placement::Floor { global: None, constraints: Vec::new() }
            },
            on_top: Vec::new(),
            name_span: o.id.span,
            decl_span: o.span,
        };
        let mut instances: BTreeMap<u32, &ast::Instance> = BTreeMap::new();
        let mut seen: BTreeMap<&'static str, Span> = BTreeMap::new();
        let shared: Vec<&ast::ObjectStmt> = o.body.iter().collect();
        for stmt in &o.body {
            if let ast::ObjectStmt::Instance(inst) = stmt {
                match parse_instance(&inst.id.name, &o.id.name, g.count) {
                    Some(i) => {
                        if let Some(first) = instances.get(&i) {
                            self.push(
                                Diagnostic::new(
                                    Code::E0203,
                                    format!("instance `{}` has two blocks", inst.id.name),
                                )
                                .with_primary(inst.id.span, "second block")
                                .with_secondary(first.id.span, "first block")
                                .with_help("merge the two blocks"),
                            );
                        } else {
                            instances.insert(i, inst);
                        }
                    }
                    None => {
                        let all: Vec<String> =
                            (0..g.count).map(|i| format!("{}-{i}", o.id.name)).collect();
                        let candidates =
                            suggest::closest(&inst.id.name, all.iter().map(String::as_str));
                        self.push(
                            Diagnostic::new(
                                Code::E0201,
                                format!("`{}` is not an instance of `{}`", inst.id.name, o.id.name),
                            )
                            .with_primary(
                                inst.id.span,
                                format!(
                                    "`{}` has {} instance(s): {}",
                                    o.id.name,
                                    g.count,
                                    all.join(", ")
                                ),
                            )
                            .with_help_opt(suggest::did_you_mean(&candidates).or_else(|| {
                                Some(format!(
                                    "raise `count` to declare more instances of `{}`",
                                    o.id.name
                                ))
                            }))
                            .with_fixes(suggest::replacements(inst.id.span, &candidates)),
                        );
                    }
                }
            }
        }
        let wall_height = scene.wall_height_m;
        self.apply_stmts(
            &shared,
            &mut base,
            g.is_wall,
            true,
            &mut seen,
            checked,
            names,
            wall_height,
        );
        let mut missing_global: Vec<String> = Vec::new();
        for i in 0..g.count {
            let mut obj = base.clone();
            obj.id = ObjectId(g.first + i as usize);
            obj.index = i;
            obj.name = format!("{}-{i}", o.id.name);
            if let Some(inst) = instances.get(&i) {
                let stmts: Vec<&ast::ObjectStmt> = inst.body.iter().collect();
                let mut inst_seen = seen.clone();
                self.apply_stmts(
                    &stmts,
                    &mut obj,
                    g.is_wall,
                    false,
                    &mut inst_seen,
                    checked,
                    names,
                    wall_height,
                );
            }
            if let Placement::Floor { constraints, .. } = &mut obj.placement {
                let own = obj.id;
                let mut k = 0;
                while k < constraints.len() {
                    if constraints[k].target == own {
                        let c = constraints.remove(k);
                        self.diagnostics.push(
                            Diagnostic::new(Code::E0206, format!("`{}-{i}` refers to itself", o.id.name))
                                .with_primary(c.target_span, "the object itself")
                                .with_help("a constraint written for the whole group applies to every instance; put it in the instance blocks of the others"),
                        );
                    } else {
                        k += 1;
                    }
                }
            }
            if matches!(obj.placement, Placement::Floor { global: None, .. }) && obj.at.is_none() {
                missing_global.push(obj.name.clone());
            }
            scene.objects.push(obj);
        }
        let has_bad_line = o.body.iter().any(|s| matches!(s, ast::ObjectStmt::Error(_)))
            || instances
                .values()
                .any(|i| i.body.iter().any(|s| matches!(s, ast::ObjectStmt::Error(_))));
        if !missing_global.is_empty() && !has_bad_line {
            let which = if missing_global.len() == g.count as usize && g.count > 1 {
                format!("every instance of `{}`", o.id.name)
            } else {
                missing_global.iter().map(|n| format!("`{n}`")).collect::<Vec<_>>().join(", ")
            };
            self.push(
                Diagnostic::new(
                    Code::W0202,
                    format!(
                        "{which} has neither `edge` nor `middle`; it will be placed against a wall"
                    ),
                )
                .with_primary(o.id.span, "no global constraint")
                .with_help("add `edge` or `middle` to the object"),
            );
        }
    }

    /// Applies object statements (group or instance level) to an object.
    #[allow(clippy::too_many_arguments, reason = "the checker's context for one block")]
    fn apply_stmts(
        &mut self,
        stmts: &[&ast::ObjectStmt],
        obj: &mut Object,
        is_wall: bool,
        group_level: bool,
        seen: &mut BTreeMap<&'static str, Span>,
        room: &Room,
        names: &RoomNames,
        wall_height_m: f64,
    ) {
        for stmt in stmts {
            let single: Option<(&'static str, Span)> = match stmt {
                ast::ObjectStmt::Describe(_, s) => Some(("describe", *s)),
                ast::ObjectStmt::Size(s) => Some(("size", s.span)),
                ast::ObjectStmt::Asset(_, s) => Some(("asset", *s)),
                ast::ObjectStmt::Above(_, s) => Some(("above", *s)),
                ast::ObjectStmt::Height(_, s) => Some(("height", *s)),
                ast::ObjectStmt::At(_, s) => Some(("at", *s)),
                ast::ObjectStmt::Facing(_, s) => Some(("facing", *s)),
                _ => None,
            };
            if let Some((key, span)) = single {
                if !self.first_setting(seen, key, span) {
                    continue;
                }
            }
            match stmt {
                ast::ObjectStmt::Describe(s, _) => obj.description = Some(s.value.clone()),
                ast::ObjectStmt::Size(s) => {
                    let w = self.positive_length(&s.width, "the width");
                    let d = self.positive_length(&s.depth, "the depth");
                    let h = self.positive_length(&s.height, "the height");
                    if let (Some(w), Some(d), Some(h)) = (w, d, h) {
                        obj.size_m = Some([w, d, h]);
                    }
                }
                ast::ObjectStmt::Count(q, variance, span) => {
                    if !group_level {
                        self.misplaced(
                            "count",
                            *span,
                            "an instance block",
                            "put `count` in the object's own block",
                        );
                        continue;
                    }
                    let _ = q;
                    if let Some(v) = variance {
                        let table = [("same", Variance::Same), ("varied", Variance::Varied)];
                        if let Some(v) = self.word(v, "variance", &table) {
                            obj.variance = v;
                        }
                    }
                }
                ast::ObjectStmt::Asset(s, _) => {
                    obj.asset = Some(Pinned { id: s.value.clone(), span: s.span });
                }
                ast::ObjectStmt::Constraint(c) => {
                    if is_wall {
                        self.misplaced(
                            &c.name.name,
                            c.span,
                            "a wall object",
                            "wall objects take `above` and `height`",
                        );
                        continue;
                    }
                    self.constraint(c, obj, room, names);
                }
                ast::ObjectStmt::Above(target, span) => {
                    if !is_wall {
                        self.misplaced(
                            "above",
                            *span,
                            "a floor object",
                            "`above` places wall and ceiling objects",
                        );
                        continue;
                    }
                    if let Some(id) = self.resolve_target(target, room, names, obj, true) {
                        if let Placement::Wall { above, .. } = &mut obj.placement {
                            *above = Some((id, target.span));
                        }
                    }
                }
                ast::ObjectStmt::Height(q, span) => {
                    if !is_wall {
                        self.misplaced(
                            "height",
                            *span,
                            "a floor object",
                            "the height of a floor object is part of `size`",
                        );
                        continue;
                    }
                    if let Some(h) =
                        length_m(q, None, "the height above the floor", &mut self.diagnostics)
                    {
                        if h < 0.0 || h >= wall_height_m {
                            self.push(
                                Diagnostic::new(
                                    Code::E0208,
                                    format!(
                                        "height {} m is not between the floor and the top of the wall ({} m)",
                                        ast::format_number(round6(h)),
                                        ast::format_number(wall_height_m)
                                    ),
                                )
                                .with_primary(q.span, "out of range"),
                            );
                        } else if let Placement::Wall { height_m, .. } = &mut obj.placement {
                            *height_m = Some(h);
                        }
                    }
                }
                ast::ObjectStmt::At(qs, span) => {
                    if qs.len() != 2 {
                        self.push(
                            Diagnostic::new(
                                Code::E0208,
                                format!("`at` takes 2 coordinates here, not {}", qs.len()),
                            )
                            .with_primary(*span, "expected `at X, Z`")
                            .with_help("write the position of the centre, e.g. `at 2 m, 3.5 m`"),
                        );
                        continue;
                    }
                    let x = length_m(&qs[0], None, "the x coordinate", &mut self.diagnostics);
                    let z = length_m(&qs[1], None, "the z coordinate", &mut self.diagnostics);
                    if let (Some(x), Some(z)) = (x, z) {
                        obj.at = Some([x, z]);
                    }
                }
                ast::ObjectStmt::Facing(q, _) => {
                    obj.facing_deg = angle_deg(q, "the facing angle", &mut self.diagnostics);
                }
                ast::ObjectStmt::OnTop(t) => {
                    if let Some(item) = self.on_top(t) {
                        obj.on_top.push(item);
                    }
                }
                ast::ObjectStmt::Instance(inst) => {
                    if !group_level {
                        self.misplaced(
                            "instance",
                            inst.span,
                            "an instance block",
                            "instance blocks do not nest",
                        );
                    }
                }
                ast::ObjectStmt::Comment(_)
                | ast::ObjectStmt::Error(_)
                | ast::ObjectStmt::Blank(_) => {}
            }
        }
    }

    fn misplaced(&mut self, what: &str, span: Span, place: &str, help: &str) {
        self.push(
            Diagnostic::new(Code::E0217, format!("`{what}` is not allowed in {place}"))
                .with_primary(span, "not allowed here")
                .with_help(help.to_string()),
        );
    }

    fn on_top(&mut self, t: &ast::OnTop) -> Option<SmallItem> {
        let n = match &t.count {
            Some(q) => count(q, "the number of items", 1, MAX_ON_TOP_COUNT, &mut self.diagnostics)?,
            None => 1,
        };
        let variance = match &t.variance {
            Some(v) => {
                self.word(v, "variance", &[("same", Variance::Same), ("varied", Variance::Varied)])?
            }
            None => Variance::Same,
        };
        let mut item = SmallItem {
            item: t.item.value.clone(),
            count: n,
            variance,
            asset: None,
            at: None,
            facing_deg: None,
            span: t.span,
        };
        for stmt in &t.body {
            match stmt {
                ast::ObjectStmt::Asset(s, _) => {
                    item.asset = Some(Pinned { id: s.value.clone(), span: s.span });
                }
                ast::ObjectStmt::At(qs, span) => {
                    if qs.len() != 3 {
                        self.push(
                            Diagnostic::new(Code::E0208, format!("`at` takes 3 coordinates here, not {}", qs.len()))
                                .with_primary(*span, "expected `at X, Y, Z`")
                                .with_help("a small object's pin is the centre of its box, e.g. `at 1 m, 0.8 m, 2 m`"),
                        );
                        continue;
                    }
                    let v: Vec<Option<f64>> = qs
                        .iter()
                        .map(|q| length_m(q, None, "a coordinate", &mut self.diagnostics))
                        .collect();
                    if let [Some(x), Some(y), Some(z)] = v[..] {
                        item.at = Some([x, y, z]);
                    }
                }
                ast::ObjectStmt::Facing(q, _) => {
                    item.facing_deg = angle_deg(q, "the facing angle", &mut self.diagnostics);
                }
                ast::ObjectStmt::Comment(_)
                | ast::ObjectStmt::Error(_)
                | ast::ObjectStmt::Blank(_) => {}
                other => {
                    let span = object_stmt_span(other);
                    self.misplaced(
                        object_stmt_word(other),
                        span,
                        "an `on top` block",
                        "an `on top` block takes `asset`, `at` and `facing`",
                    );
                }
            }
        }
        Some(item)
    }

    fn constraint(
        &mut self,
        c: &ast::Constraint,
        obj: &mut Object,
        room: &Room,
        names: &RoomNames,
    ) {
        let global_kind = match c.name.name.as_str() {
            "edge" => Some(GlobalKind::Edge),
            "middle" => Some(GlobalKind::Middle),
            _ => None,
        };
        if let Some(kind) = global_kind {
            if let Some(t) = &c.target {
                self.push(
                    Diagnostic::new(Code::E0219, format!("`{}` takes no object", c.name.name))
                        .with_primary(t.span, "unexpected name")
                        .with_help(format!(
                            "write `{}` alone; to relate objects use e.g. `near {}`",
                            c.name.name, t.name
                        )),
                );
            }
            let group = obj.group.clone();
            let Placement::Floor { global, .. } = &mut obj.placement else { return };
            if let Some(first) = global {
                let first_span = first.span;
                self.push(
                    Diagnostic::new(
                        Code::E0209,
                        format!("`{group}` has more than one global constraint"),
                    )
                    .with_primary(c.span, format!("`{}` here", c.name.name))
                    .with_secondary(first_span, "the first global constraint")
                    .with_help("keep one of `edge` and `middle`"),
                );
                return;
            }
            *global = Some(GlobalConstraint { kind, span: c.span });
            return;
        }
        let Some(kind) = RelationKind::from_words(&c.name.name) else { return };
        let Some(target) = &c.target else {
            self.push(
                Diagnostic::new(Code::E0218, format!("`{}` needs an object", c.name.name))
                    .with_primary(c.span, "no object named")
                    .with_help(format!("write e.g. `{} sofa-0`", c.name.name)),
            );
            return;
        };
        if let Some(id) = self.resolve_target(target, room, names, obj, false) {
            if let Placement::Floor { constraints, .. } = &mut obj.placement {
                constraints.push(Constraint {
                    kind,
                    target: id,
                    span: c.span,
                    target_span: target.span,
                });
            }
        }
    }

    /// Resolves an object reference within a room. `for_wall`: the reference comes from a wall
    /// or ceiling object (`above`), which may name any floor object of the room.
    fn resolve_target(
        &mut self,
        target: &ast::Ident,
        room: &Room,
        names: &RoomNames,
        obj: &Object,
        for_wall: bool,
    ) -> Option<ObjectId> {
        let name = &target.name;
        let found = names.instances.get(name).copied().or_else(|| match names.groups.get(name) {
            Some((1, first)) => {
                Some((*first, names.instances.get(&format!("{name}-0")).is_some_and(|e| e.1)))
            }
            _ => None,
        });
        if let Some((id, is_floor)) = found {
            if !is_floor {
                self.push(
                    Diagnostic::new(Code::E0207, format!("`{name}` is a wall object"))
                        .with_primary(target.span, "expected a floor object")
                        .with_help(
                            "constraints and `above` relate to objects standing on the floor",
                        ),
                );
                return None;
            }
            if !for_wall
                && !obj.name.is_empty()
                && (id == obj.id || group_instance(name, &obj.group, obj.group_count, obj.index))
            {
                self.push(
                    Diagnostic::new(Code::E0206, format!("`{}` refers to itself", obj.name))
                        .with_primary(target.span, "the object itself")
                        .with_help("a constraint relates an object to another, earlier object"),
                );
                return None;
            }
            return Some(id);
        }
        if let Some((n, _)) = names.groups.get(name) {
            let all: Vec<String> = (0..*n).map(|i| format!("`{name}-{i}`")).collect();
            self.push(
                Diagnostic::new(Code::E0212, format!("`{name}` names {n} instances"))
                    .with_primary(target.span, "which one?")
                    .with_help(format!("name one instance: {}", all.join(", "))),
            );
            return None;
        }
        let elsewhere: Vec<String> =
            self.rooms_declaring(name).iter().filter(|r| **r != room.name).cloned().collect();
        if let Some(other) = elsewhere.first() {
            self.push(
                Diagnostic::new(
                    Code::E0207,
                    format!("`{name}` is in room `{other}`, not in `{}`", room.name),
                )
                .with_primary(target.span, "an object of another room")
                .with_help("constraints relate objects of the same room"),
            );
            return None;
        }
        let mut candidates_pool: Vec<&str> = names.instances.keys().map(String::as_str).collect();
        candidates_pool
            .extend(names.groups.iter().filter(|(_, (n, _))| *n == 1).map(|(g, _)| g.as_str()));
        let candidates = suggest::closest(name, candidates_pool.iter().copied());
        self.push(
            Diagnostic::new(Code::E0201, format!("unknown object `{name}`"))
                .with_primary(target.span, format!("not declared in room `{}`", room.name))
                .with_help_opt(suggest::did_you_mean(&candidates))
                .with_fixes(suggest::replacements(target.span, &candidates)),
        );
        None
    }

    /// Puts the room's objects in placement order and reports circles. A constraint may name an
    /// object declared later (the model's order of lines need not be the order of the object
    /// blocks); the objects are then placed in declaration order except that an object comes
    /// after every object its constraints name (a stable topological order). A constraint that
    /// closes a circle is reported (E0205) and leaves the scene.
    fn check_constraint_order(&mut self, room: &mut Room, scene: &mut Scene) -> bool {
        let ids: Vec<ObjectId> = room.objects.clone();
        let mut forward: Vec<(ObjectId, usize)> = Vec::new();
        for &id in &ids {
            if let Placement::Floor { constraints, .. } = &scene.objects[id.0].placement {
                for (k, c) in constraints.iter().enumerate() {
                    if c.target.0 > id.0 {
                        forward.push((id, k));
                    }
                }
            }
        }
        if forward.is_empty() {
            return false;
        }
        // Edges of the dependency graph: object → target, over every constraint.
        let mut edges: BTreeMap<usize, Vec<(usize, Span)>> = BTreeMap::new();
        for &id in &ids {
            if let Placement::Floor { constraints, .. } = &scene.objects[id.0].placement {
                for c in constraints {
                    edges.entry(id.0).or_default().push((c.target.0, c.span));
                }
            }
        }
        let mut in_cycle_reported: Vec<usize> = Vec::new();
        let mut drop: Vec<(ObjectId, usize)> = Vec::new();
        for &(id, k) in &forward {
            let (target, span) = match &scene.objects[id.0].placement {
                Placement::Floor { constraints, .. } => {
                    (constraints[k].target, constraints[k].span)
                }
                Placement::Wall { .. } => continue,
            };
            // Is there a path target → … → id? Then this constraint closes a circle: it leaves
            // the graph (and the scene), and the circle is reported once.
            let Some(path) = find_path(&edges, target.0, id.0) else { continue };
            drop.push((id, k));
            if let Some(out) = edges.get_mut(&id.0) {
                if let Some(pos) = out.iter().position(|&(t, s)| t == target.0 && s == span) {
                    out.remove(pos);
                }
            }
            if in_cycle_reported.contains(&id.0) || in_cycle_reported.contains(&target.0) {
                continue;
            }
            let mut d = Diagnostic::new(
                Code::E0205,
                format!(
                    "constraints of `{}` and `{}` refer to each other in a circle",
                    scene.objects[id.0].name, scene.objects[target.0].name
                ),
            )
            .with_primary(span, "this constraint closes the circle");
            for (node, s) in &path {
                d = d.with_secondary(
                    *s,
                    format!("`{}` depends on the next object here", scene.objects[*node].name),
                );
                in_cycle_reported.push(*node);
            }
            in_cycle_reported.push(id.0);
            self.push(d.with_help(
                "remove one of these constraints; objects are placed one after another, each \
                 after the objects it names",
            ));
        }
        // One cause, one diagnostic: the reported constraints leave the scene.
        drop.sort_by_key(|&(id, k)| (id.0, k));
        for (id, k) in drop.into_iter().rev() {
            if let Placement::Floor { constraints, .. } = &mut scene.objects[id.0].placement {
                constraints.remove(k);
            }
        }
        // Placement order: declaration order, each object after the objects it names.
        let mut placed: Vec<ObjectId> = Vec::with_capacity(ids.len());
        let mut left: Vec<ObjectId> = ids;
        while !left.is_empty() {
            let ready = left.iter().position(|id| match &scene.objects[id.0].placement {
                Placement::Floor { constraints, .. } => constraints
                    .iter()
                    .all(|c| placed.contains(&c.target) || !left.contains(&c.target)),
                Placement::Wall { .. } => true,
            });
            // The circles are gone, so some object is always ready; the fallback keeps the
            // declaration order should that ever not hold.
            let next = ready.unwrap_or(0);
            placed.push(left.remove(next));
        }
        room.objects = placed;
        true
    }

    fn ceiling(
        &mut self,
        c: &ast::Ceiling,
        room: &Room,
        names: &RoomNames,
        scene: &Scene,
    ) -> Ceiling {
        let mut ceiling = Ceiling {
            description: c.description.value.clone(),
            asset: None,
            above: None,
            at: None,
            span: c.span,
        };
        let probe = Object {
            id: ObjectId(usize::MAX),
            room: room.id,
            name: String::new(),
            group: String::new(),
            index: 0,
            group_count: 1,
            category: String::new(),
            description: None,
            size_m: None,
            variance: Variance::Same,
            asset: None,
            at: None,
            facing_deg: None,
            placement: Placement::Wall { above: None, height_m: None },
            on_top: Vec::new(),
            name_span: c.span,
            decl_span: c.span,
        };
        let _ = scene;
        for stmt in &c.body {
            match stmt {
                ast::ObjectStmt::Asset(s, _) => {
                    ceiling.asset = Some(Pinned { id: s.value.clone(), span: s.span });
                }
                ast::ObjectStmt::Above(t, _) => {
                    if let Some(id) = self.resolve_target(t, room, names, &probe, true) {
                        ceiling.above = Some((id, t.span));
                    }
                }
                ast::ObjectStmt::At(qs, span) => {
                    if qs.len() == 2 {
                        let x = length_m(&qs[0], None, "the x coordinate", &mut self.diagnostics);
                        let z = length_m(&qs[1], None, "the z coordinate", &mut self.diagnostics);
                        if let (Some(x), Some(z)) = (x, z) {
                            ceiling.at = Some([x, z]);
                        }
                    } else {
                        self.push(
                            Diagnostic::new(
                                Code::E0208,
                                format!("`at` takes 2 coordinates here, not {}", qs.len()),
                            )
                            .with_primary(*span, "expected `at X, Z`"),
                        );
                    }
                }
                ast::ObjectStmt::Comment(_)
                | ast::ObjectStmt::Error(_)
                | ast::ObjectStmt::Blank(_) => {}
                other => {
                    let span = object_stmt_span(other);
                    self.misplaced(
                        object_stmt_word(other),
                        span,
                        "a `ceiling` block",
                        "a ceiling block takes `asset`, `above` and `at`",
                    );
                }
            }
        }
        ceiling
    }

    fn doors(
        &mut self,
        file: &ast::File,
        rooms: &BTreeMap<String, (RoomId, Span)>,
        scene: &mut Scene,
    ) {
        let mut pairs: BTreeMap<(DoorSide, DoorSide), Span> = BTreeMap::new();
        for item in &file.items {
            let ast::Item::Door(d) = item else { continue };
            let from = self.door_side(&d.from, rooms);
            let to = self.door_side(&d.to, rooms);
            let kind = self.word(
                &d.kind,
                "connection kind",
                &[
                    ("doorway", DoorKind::Doorway),
                    ("doorframe", DoorKind::Doorframe),
                    ("open", DoorKind::Open),
                ],
            );
            let size = match &d.size {
                Some(w) if w.name.eq_ignore_ascii_case("n/a") => Some(None),
                Some(w) => self
                    .word(
                        w,
                        "door size",
                        &[("single", DoorSize::Single), ("double", DoorSize::Double)],
                    )
                    .map(Some),
                None => Some(None),
            };
            let (Some(from), Some(to), Some(kind), Some(size)) = (from, to, kind, size) else {
                continue;
            };
            if from == to {
                let what = if from == DoorSide::Exterior {
                    "the outside to itself"
                } else {
                    "a room to itself"
                };
                self.push(
                    Diagnostic::new(Code::E0210, format!("a door connects {what}"))
                        .with_primary(d.to.span, format!("`{}` again", d.to.name))
                        .with_secondary(d.from.span, "first side")
                        .with_help("a door joins two different rooms, or a room and `exterior`"),
                );
                continue;
            }
            if kind == DoorKind::Open && (from == DoorSide::Exterior || to == DoorSide::Exterior) {
                self.push(
                    Diagnostic::new(Code::E0207, "an open connection cannot lead outside")
                        .with_primary(d.kind.span, "`open` removes the wall between two rooms")
                        .with_help("use `doorway` for a door to the exterior"),
                );
                continue;
            }
            let key = if from <= to { (from, to) } else { (to, from) };
            if let Some(first) = pairs.get(&key) {
                self.push(
                    Diagnostic::new(
                        Code::E0216,
                        format!("`{}` and `{}` are already connected", d.from.name, d.to.name),
                    )
                    .with_primary(d.span, "second connection")
                    .with_secondary(*first, "first connection")
                    .with_help(
                        "keep one connection per pair of rooms; AI2-THOR allows one hole per wall",
                    ),
                );
                continue;
            }
            pairs.insert(key, d.span);
            let size = match kind {
                DoorKind::Open => None,
                _ => Some(size.unwrap_or(DoorSize::Single)),
            };
            scene.doors.push(Door {
                index: scene.doors.len(),
                from,
                to,
                kind,
                size,
                style: d.style.as_ref().map(|s| s.value.clone()),
                asset: d.asset.as_ref().map(|s| Pinned { id: s.value.clone(), span: s.span }),
                side_spans: [d.from.span, d.to.span],
                span: d.span,
            });
        }
    }

    fn door_side(
        &mut self,
        ident: &ast::Ident,
        rooms: &BTreeMap<String, (RoomId, Span)>,
    ) -> Option<DoorSide> {
        if ident.name == "exterior" {
            return Some(DoorSide::Exterior);
        }
        if let Some((id, _)) = rooms.get(&ident.name) {
            return Some(DoorSide::Room(*id));
        }
        let mut pool: Vec<&str> = rooms.keys().map(String::as_str).collect();
        pool.push("exterior");
        let candidates = suggest::closest(&ident.name, pool.iter().copied());
        self.push(
            Diagnostic::new(Code::E0202, format!("unknown room `{}`", ident.name))
                .with_primary(ident.span, "no room has this identifier")
                .with_help_opt(suggest::did_you_mean(&candidates).or_else(|| {
                    Some("a door names two rooms, or a room and `exterior`".to_string())
                }))
                .with_fixes(suggest::replacements(ident.span, &candidates)),
        );
        None
    }
}

/// The instances a group with an unusable `count` still declares, so that references to them
/// do not cascade: as many as it can hold when the count is too large, the number written when
/// only its unit is wrong (`count 2 cm`), else one.
fn fallback_count(q: &Quantity) -> u32 {
    if q.value > f64::from(MAX_GROUP_COUNT) {
        MAX_GROUP_COUNT
    } else if q.value >= 1.0 && q.value.fract() == 0.0 {
        q.value as u32
    } else {
        1
    }
}

/// The number of instances an object group declares, as the checker counts them (its first
/// `count`, or the fallback of an unusable one): what an editor offers before the file checks.
pub fn declared_count(o: &ast::Object) -> u32 {
    o.body
        .iter()
        .find_map(|s| match s {
            ast::ObjectStmt::Count(q, _, _) => Some(
                count(q, "the object count", 1, MAX_GROUP_COUNT, &mut Vec::new())
                    .unwrap_or_else(|| fallback_count(q)),
            ),
            _ => None,
        })
        .unwrap_or(1)
}

/// Whether `name` is `<group>-<index>` of the given group and instance.
fn group_instance(name: &str, group: &str, count: u32, index: u32) -> bool {
    (count == 1 && name == group) || name == format!("{group}-{index}")
}

/// Reads `group-N` with `N < count`.
fn parse_instance(name: &str, group: &str, count: u32) -> Option<u32> {
    let rest = name.strip_prefix(group)?.strip_prefix('-')?;
    let i: u32 = rest.parse().ok()?;
    (i < count && rest == i.to_string()).then_some(i)
}

/// A path `from → … → to` in the dependency graph, as (node, constraint span) steps.
fn find_path(
    edges: &BTreeMap<usize, Vec<(usize, Span)>>,
    from: usize,
    to: usize,
) -> Option<Vec<(usize, Span)>> {
    let mut stack: Vec<(usize, Vec<(usize, Span)>)> = vec![(from, Vec::new())];
    let mut seen = std::collections::BTreeSet::new();
    while let Some((node, path)) = stack.pop() {
        if node == to {
            return Some(path);
        }
        if !seen.insert(node) {
            continue;
        }
        for &(next, span) in edges.get(&node).map_or(&[][..], Vec::as_slice) {
            let mut p = path.clone();
            p.push((node, span));
            stack.push((next, p));
        }
    }
    None
}

fn round6(v: f64) -> f64 {
    (v * 1e6).round() / 1e6
}

fn object_stmt_span(stmt: &ast::ObjectStmt) -> Span {
    match stmt {
        ast::ObjectStmt::Describe(_, s)
        | ast::ObjectStmt::Asset(_, s)
        | ast::ObjectStmt::Count(_, _, s)
        | ast::ObjectStmt::Above(_, s)
        | ast::ObjectStmt::Height(_, s)
        | ast::ObjectStmt::At(_, s)
        | ast::ObjectStmt::Facing(_, s)
        | ast::ObjectStmt::Blank(s) => *s,
        ast::ObjectStmt::Size(s) => s.span,
        ast::ObjectStmt::Constraint(c) => c.span,
        ast::ObjectStmt::OnTop(t) => t.span,
        ast::ObjectStmt::Instance(i) => i.span,
        ast::ObjectStmt::Comment(c) => c.span,
        ast::ObjectStmt::Error(e) => e.span,
    }
}

fn object_stmt_word(stmt: &ast::ObjectStmt) -> &str {
    match stmt {
        ast::ObjectStmt::Describe(..) => "describe",
        ast::ObjectStmt::Asset(..) => "asset",
        ast::ObjectStmt::Count(..) => "count",
        ast::ObjectStmt::Above(..) => "above",
        ast::ObjectStmt::Height(..) => "height",
        ast::ObjectStmt::At(..) => "at",
        ast::ObjectStmt::Facing(..) => "facing",
        ast::ObjectStmt::Size(..) => "size",
        ast::ObjectStmt::Constraint(c) => &c.name.name,
        ast::ObjectStmt::OnTop(..) => "on top",
        ast::ObjectStmt::Instance(..) => "instance",
        ast::ObjectStmt::Comment(..) => "comment",
        ast::ObjectStmt::Error(..) | ast::ObjectStmt::Blank(..) => "line",
    }
}

//! Incremental analysis: what an edit did not touch is not computed again.
//!
//! The language server analyses every version of a document with the stages before the solver.
//! The parser already reuses every top-level item and room statement group whose text did not
//! change (`parse::ParseCache`). After the checker, the floor plan and the asset choices are
//! reused when their inputs are the same as for the previous version *once the previous spans
//! are moved by the edit*:
//!
//! - the plan reads the scene's settings, rooms (name, label, corners, windows, materials) and
//!   doors, never its objects: it runs again only when one of those changed, so typing in an
//!   object block never plans the floor again;
//! - asset resolution is kept room by room: a room reads its objects (category, description,
//!   size, pins, things on top, placement kind), its ceiling object, its name and box, never its
//!   corners' spans, windows, doors or relations, and of the rooms before it only which assets
//!   they use ([`crate::resolve::Resolver`]). A room's last resolution is reused when its input
//!   is the same and every asset it asked about is used or not by the rooms before it as then;
//!   that is not even asked while every room before it is the same room at the same place with
//!   the same assets. So an edit in a description resolves that room, and the later rooms only
//!   when its choices changed what they were told (new rankings through `resolve::RankCache`).
//!
//! An edit is the text between the common prefix and the common suffix of two versions
//! ([`Shift`]). A span before it stays, a span after it moves by the change in length, a span
//! that starts or ends inside it cannot be moved: its stage runs again. A stage is a pure
//! function of its input and copies spans from it without reading their values (but for their
//! order, which the move keeps), so its output for the moved input is its earlier output with
//! the same spans moved. The property tests hold this module's analysis to
//! [`crate::compile::analyse`] through random edits, byte for byte.

use crate::check::{Ceiling, Constraint, Door, GlobalConstraint, Object, Pinned, Placement, Room};
use crate::check::{Scene, SmallItem, Window};
use crate::compile::{Analysed, AnalysisCache};
use crate::diag::{Diagnostic, Fix, Label};
use crate::plan::{FloorPlan, PlanOptions};
use crate::resolve::structure::StructureCatalog;
use crate::resolve::{Catalog, Resolved, RoomResolution};
use crate::source::{FileId, SourceMap, Span};

/// The text an edit replaced: bytes `start..old_end` of the old version became
/// `start..new_end` of the new one.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Shift {
    /// Where the two versions start to differ.
    pub start: usize,
    /// Where the replaced text ended in the old version.
    pub old_end: usize,
    /// Where the new text ends in the new version.
    pub new_end: usize,
}

impl Shift {
    /// The edit between two versions: their common prefix and suffix are unchanged.
    pub fn between(old: &str, new: &str) -> Shift {
        let (start, old_end, new_end) = crate::source::changed_range(old, new);
        Shift { start, old_end, new_end }
    }

    /// Where an offset of the old version is in the new one; `None` inside the replaced text.
    pub fn offset(&self, offset: u32) -> Option<u32> {
        let o = offset as usize;
        if o <= self.start {
            Some(offset)
        } else if o >= self.old_end {
            u32::try_from(o - self.old_end + self.new_end).ok()
        } else {
            None
        }
    }

    /// A span of the old version moved into the new one.
    pub fn span(&self, span: Span) -> Option<Span> {
        Some(Span { file: span.file, start: self.offset(span.start)?, end: self.offset(span.end)? })
    }

    /// Moves every span of `value`; `false` when one cannot be (then `value` is left part
    /// moved, to be thrown away).
    pub fn move_in_place<T: Spans>(&self, value: &mut T) -> bool {
        let mut ok = true;
        value.spans(&mut |span| match self.span(*span) {
            Some(moved) => *span = moved,
            None => ok = false,
        });
        ok
    }

    /// A copy of `value` with every span moved, or `None` when one cannot be.
    pub fn moved<T: Spans + Clone>(&self, value: &T) -> Option<T> {
        let mut out = value.clone();
        let mut ok = true;
        out.spans(&mut |span| match self.span(*span) {
            Some(moved) => *span = moved,
            None => ok = false,
        });
        ok.then_some(out)
    }
}

/// A value holding spans, each of which a function may rewrite.
pub trait Spans {
    /// Calls `f` on every span.
    fn spans(&mut self, f: &mut dyn FnMut(&mut Span));
}

impl Spans for Span {
    fn spans(&mut self, f: &mut dyn FnMut(&mut Span)) {
        f(self);
    }
}

impl<T: Spans> Spans for Option<T> {
    fn spans(&mut self, f: &mut dyn FnMut(&mut Span)) {
        if let Some(x) = self {
            x.spans(f);
        }
    }
}

impl<T: Spans> Spans for Vec<T> {
    fn spans(&mut self, f: &mut dyn FnMut(&mut Span)) {
        for x in self {
            x.spans(f);
        }
    }
}

impl<T: Spans> Spans for [T; 2] {
    fn spans(&mut self, f: &mut dyn FnMut(&mut Span)) {
        for x in self {
            x.spans(f);
        }
    }
}

impl<T> Spans for (T, Span) {
    fn spans(&mut self, f: &mut dyn FnMut(&mut Span)) {
        f(&mut self.1);
    }
}

// Each impl names every field (no `..`), so that a field added later is a compile error here
// until it says whether it holds a span.

impl Spans for Pinned {
    fn spans(&mut self, f: &mut dyn FnMut(&mut Span)) {
        let Pinned { id: _, span } = self;
        f(span);
    }
}

impl Spans for Window {
    fn spans(&mut self, f: &mut dyn FnMut(&mut Span)) {
        let Window { wall: _, kind: _, width_m: _, height_m: _, count: _, sill_m: _, asset, span } =
            self;
        asset.spans(f);
        f(span);
    }
}

impl Spans for Ceiling {
    fn spans(&mut self, f: &mut dyn FnMut(&mut Span)) {
        let Ceiling { description: _, asset, above, at: _, span } = self;
        asset.spans(f);
        above.spans(f);
        f(span);
    }
}

impl Spans for Room {
    fn spans(&mut self, f: &mut dyn FnMut(&mut Span)) {
        let Room {
            id: _,
            name: _,
            label: _,
            floor_design: _,
            wall_design: _,
            floor_material,
            wall_material,
            corners: _,
            corner_spans,
            corners_unit_span,
            windows,
            objects: _,
            ceiling,
            name_span,
            decl_span,
        } = self;
        floor_material.spans(f);
        wall_material.spans(f);
        corner_spans.spans(f);
        corners_unit_span.spans(f);
        windows.spans(f);
        ceiling.spans(f);
        f(name_span);
        f(decl_span);
    }
}

impl Spans for Door {
    fn spans(&mut self, f: &mut dyn FnMut(&mut Span)) {
        let Door { index: _, from: _, to: _, kind: _, size: _, style: _, asset, side_spans, span } =
            self;
        asset.spans(f);
        side_spans.spans(f);
        f(span);
    }
}

impl Spans for GlobalConstraint {
    fn spans(&mut self, f: &mut dyn FnMut(&mut Span)) {
        let GlobalConstraint { kind: _, span } = self;
        f(span);
    }
}

impl Spans for Constraint {
    fn spans(&mut self, f: &mut dyn FnMut(&mut Span)) {
        let Constraint { kind: _, target: _, span, target_span } = self;
        f(span);
        f(target_span);
    }
}

impl Spans for Placement {
    fn spans(&mut self, f: &mut dyn FnMut(&mut Span)) {
        match self {
            Placement::Floor { global, constraints } => {
                global.spans(f);
                constraints.spans(f);
            }
            Placement::Wall { above, height_m: _ } => above.spans(f),
        }
    }
}

impl Spans for SmallItem {
    fn spans(&mut self, f: &mut dyn FnMut(&mut Span)) {
        let SmallItem { item: _, count: _, variance: _, asset, at: _, facing_deg: _, span } = self;
        asset.spans(f);
        f(span);
    }
}

impl Spans for Object {
    fn spans(&mut self, f: &mut dyn FnMut(&mut Span)) {
        let Object {
            id: _,
            room: _,
            name: _,
            group: _,
            index: _,
            group_count: _,
            category: _,
            description: _,
            size_m: _,
            variance: _,
            asset,
            at: _,
            facing_deg: _,
            placement,
            on_top,
            name_span,
            decl_span,
        } = self;
        asset.spans(f);
        placement.spans(f);
        on_top.spans(f);
        f(name_span);
        f(decl_span);
    }
}

impl Spans for Label {
    fn spans(&mut self, f: &mut dyn FnMut(&mut Span)) {
        let Label { span, text: _ } = self;
        f(span);
    }
}

impl Spans for Fix {
    fn spans(&mut self, f: &mut dyn FnMut(&mut Span)) {
        let Fix { title: _, span, replacement: _ } = self;
        f(span);
    }
}

impl Spans for Diagnostic {
    fn spans(&mut self, f: &mut dyn FnMut(&mut Span)) {
        let Diagnostic {
            code: _,
            severity: _,
            message: _,
            primary,
            secondary,
            help: _,
            notes: _,
            fixes,
        } = self;
        primary.spans(f);
        secondary.spans(f);
        fixes.spans(f);
    }
}

impl Spans for FloorPlan {
    fn spans(&mut self, f: &mut dyn FnMut(&mut Span)) {
        let FloorPlan {
            seed: _,
            wall_height_m: _,
            rooms,
            walls: _,
            doors,
            windows,
            open_connections,
            skybox: _,
            time_of_day: _,
            ceiling_material: _,
            agent: _,
        } = self;
        for room in rooms {
            f(&mut room.name_span);
        }
        for door in doors {
            door.span.spans(f);
        }
        for window in windows {
            f(&mut window.span);
        }
        for open in open_connections {
            f(&mut open.span);
        }
    }
}

impl Spans for Resolved {
    fn spans(&mut self, _: &mut dyn FnMut(&mut Span)) {
        // Asset choices hold no spans (their diagnostics do).
        let Resolved { objects: _, ceilings: _, ceiling_lights: _, small: _ } = self;
    }
}

/// A stage's output with its diagnostics.
#[derive(Clone, Debug)]
struct Output<T> {
    value: T,
    diagnostics: Vec<Diagnostic>,
}

impl<T: Spans> Spans for Output<T> {
    fn spans(&mut self, f: &mut dyn FnMut(&mut Span)) {
        self.value.spans(f);
        self.diagnostics.spans(f);
    }
}

/// What the plan reads of a scene: everything but its objects.
#[derive(Clone, Debug, PartialEq)]
struct PlanInput {
    wall_height_m: f64,
    seed: u64,
    ceiling_material: Option<Pinned>,
    ceiling_design: Option<String>,
    rooms: Vec<Room>,
    doors: Vec<Door>,
}

impl PlanInput {
    fn of(scene: &Scene) -> PlanInput {
        PlanInput {
            wall_height_m: scene.wall_height_m,
            seed: scene.seed,
            ceiling_material: scene.ceiling_material.clone(),
            ceiling_design: scene.ceiling_design.clone(),
            rooms: scene
                .rooms
                .iter()
                .map(|r| Room { objects: Vec::new(), ceiling: None, ..r.clone() })
                .collect(),
            doors: scene.doors.clone(),
        }
    }
}

impl PlanInput {
    /// Whether this input is the one [`PlanInput::of`] makes of `scene` (compared in place).
    fn is_of(&self, scene: &Scene) -> bool {
        self.wall_height_m == scene.wall_height_m
            && self.seed == scene.seed
            && self.ceiling_material == scene.ceiling_material
            && self.ceiling_design == scene.ceiling_design
            && self.doors == scene.doors
            && self.rooms.len() == scene.rooms.len()
            && self.rooms.iter().zip(&scene.rooms).all(|(a, b)| same_room_outline(a, b))
    }
}

/// Whether `kept` (a room of a [`PlanInput`]) is what [`PlanInput::of`] makes of `room`.
fn same_room_outline(kept: &Room, room: &Room) -> bool {
    let Room {
        id,
        name,
        label,
        floor_design,
        wall_design,
        floor_material,
        wall_material,
        corners,
        corner_spans,
        corners_unit_span,
        windows,
        objects: _,
        ceiling: _,
        name_span,
        decl_span,
    } = kept;
    *id == room.id
        && *name == room.name
        && *label == room.label
        && *floor_design == room.floor_design
        && *wall_design == room.wall_design
        && *floor_material == room.floor_material
        && *wall_material == room.wall_material
        && *corners == room.corners
        && *corner_spans == room.corner_spans
        && *corners_unit_span == room.corners_unit_span
        && *windows == room.windows
        && *name_span == room.name_span
        && *decl_span == room.decl_span
}

impl Spans for PlanInput {
    fn spans(&mut self, f: &mut dyn FnMut(&mut Span)) {
        self.ceiling_material.spans(f);
        self.rooms.spans(f);
        self.doors.spans(f);
    }
}

/// What asset resolution reads of one room: its name, its box (for the objathor folder's size
/// filters), its ceiling object and its objects without their relations, ids or placement
/// details. With the same input and the same answers about which assets the rooms before it
/// use, a room resolves to the same choices and diagnostics ([`crate::resolve::Resolver`]).
///
/// It is kept written out ([`write_room`]): every value but the spans in `bytes` (strings with
/// their lengths, numbers by their bits, each optional value with a tag, so that two inputs
/// write the same bytes only when they are the same), the spans in `spans`, in the order
/// written. A room's input is one allocation of about its text's size, not a copy of its
/// objects; two numbers equal but for their bits (0 and −0) count as different, which only
/// makes the room resolve again.
#[derive(Clone, Debug, PartialEq)]
struct RoomInput {
    bytes: Vec<u8>,
    spans: Vec<Span>,
}

/// Where [`write_room`] writes: a new [`RoomInput`], or a comparison with a kept one.
trait Sink {
    fn bytes(&mut self, bytes: &[u8]);
    fn span(&mut self, span: Span);
}

impl Sink for RoomInput {
    fn bytes(&mut self, bytes: &[u8]) {
        self.bytes.extend_from_slice(bytes);
    }

    fn span(&mut self, span: Span) {
        self.spans.push(span);
    }
}

/// A kept input compared with what is written, as it is written (nothing is copied).
struct Compare<'a> {
    bytes: &'a [u8],
    spans: &'a [Span],
    same: bool,
}

impl Sink for Compare<'_> {
    fn bytes(&mut self, bytes: &[u8]) {
        match self.bytes.strip_prefix(bytes) {
            Some(rest) if self.same => self.bytes = rest,
            _ => self.same = false,
        }
    }

    fn span(&mut self, span: Span) {
        match self.spans.split_first() {
            Some((first, rest)) if self.same && *first == span => self.spans = rest,
            _ => self.same = false,
        }
    }
}

/// A number written in 7-bit groups, low first, the high bit of each byte telling whether
/// another follows (LEB128): one way to write each number, each ending where it says.
fn write_count<S: Sink>(sink: &mut S, mut n: u64) {
    let mut out = [0u8; 10];
    let mut k = 0;
    loop {
        let low = (n & 0x7f) as u8;
        n >>= 7;
        if n == 0 {
            out[k] = low;
            k += 1;
            break;
        }
        out[k] = low | 0x80;
        k += 1;
    }
    sink.bytes(&out[..k]);
}

fn write_str<S: Sink>(sink: &mut S, s: &str) {
    write_count(sink, s.len() as u64);
    sink.bytes(s.as_bytes());
}

fn write_f64s<S: Sink>(sink: &mut S, values: &[f64]) {
    for v in values {
        sink.bytes(&v.to_bits().to_le_bytes());
    }
}

fn write_opt_f64s<S: Sink, const N: usize>(sink: &mut S, values: Option<&[f64; N]>) {
    match values {
        None => sink.bytes(&[0]),
        Some(values) => {
            sink.bytes(&[1]);
            write_f64s(sink, values);
        }
    }
}

fn write_pinned<S: Sink>(sink: &mut S, pinned: Option<&Pinned>) {
    match pinned {
        None => sink.bytes(&[0]),
        Some(Pinned { id, span }) => {
            sink.bytes(&[1]);
            write_str(sink, id);
            sink.span(*span);
        }
    }
}

fn write_variance<S: Sink>(sink: &mut S, variance: crate::check::Variance) {
    sink.bytes(&[match variance {
        crate::check::Variance::Same => 0,
        crate::check::Variance::Varied => 1,
    }]);
}

/// Writes what resolution reads of `room`: its name, its box, its ceiling object (without the
/// object it hangs above or its position) and its objects (without ids, relations or
/// placement details, but whether they stand on the floor).
fn write_room<S: Sink>(sink: &mut S, scene: &Scene, room: &Room) {
    write_str(sink, &room.name);
    let room_box = crate::resolve::room_box(room, scene.wall_height_m);
    write_opt_f64s(sink, room_box.as_ref());
    match &room.ceiling {
        None => sink.bytes(&[0]),
        Some(Ceiling { description, asset, above: _, at: _, span }) => {
            sink.bytes(&[1]);
            write_str(sink, description);
            write_pinned(sink, asset.as_ref());
            sink.span(*span);
        }
    }
    write_count(sink, room.objects.len() as u64);
    for &id in &room.objects {
        let Object {
            id: _,
            room: _,
            name,
            group,
            index,
            group_count,
            category,
            description,
            size_m,
            variance,
            asset,
            at,
            facing_deg,
            placement,
            on_top,
            name_span,
            decl_span,
        } = scene.object(id);
        write_str(sink, name);
        write_str(sink, group);
        write_count(sink, u64::from(*index));
        write_count(sink, u64::from(*group_count));
        write_str(sink, category);
        match description {
            None => sink.bytes(&[0]),
            Some(d) => {
                sink.bytes(&[1]);
                write_str(sink, d);
            }
        }
        write_opt_f64s(sink, size_m.as_ref());
        write_variance(sink, *variance);
        write_pinned(sink, asset.as_ref());
        write_opt_f64s(sink, at.as_ref());
        write_opt_f64s(sink, facing_deg.as_ref().map(std::array::from_ref));
        sink.bytes(&[u8::from(matches!(placement, Placement::Floor { .. }))]);
        write_count(sink, on_top.len() as u64);
        for SmallItem { item, count, variance, asset, at, facing_deg, span } in on_top {
            write_str(sink, item);
            write_count(sink, u64::from(*count));
            write_variance(sink, *variance);
            write_pinned(sink, asset.as_ref());
            write_opt_f64s(sink, at.as_ref());
            write_opt_f64s(sink, facing_deg.as_ref().map(std::array::from_ref));
            sink.span(*span);
        }
        sink.span(*name_span);
        sink.span(*decl_span);
    }
}

impl RoomInput {
    fn of(scene: &Scene, room: &Room) -> RoomInput {
        let mut input = RoomInput { bytes: Vec::new(), spans: Vec::new() };
        write_room(&mut input, scene, room);
        input.bytes.shrink_to_fit();
        input.spans.shrink_to_fit();
        input
    }

    /// Whether this input is the one [`RoomInput::of`] makes of `room` (compared as it is
    /// written, with nothing copied).
    fn is_of(&self, scene: &Scene, room: &Room) -> bool {
        let mut compare = Compare { bytes: &self.bytes, spans: &self.spans, same: true };
        write_room(&mut compare, scene, room);
        compare.same && compare.bytes.is_empty() && compare.spans.is_empty()
    }
}

impl Spans for RoomInput {
    fn spans(&mut self, f: &mut dyn FnMut(&mut Span)) {
        let RoomInput { bytes: _, spans } = self;
        spans.spans(f);
    }
}

/// One room's resolution with the input it was made from.
#[derive(Debug)]
struct RoomRun {
    input: RoomInput,
    output: RoomResolution,
    /// The room's objects' ids when it ran ([`crate::check::Room::objects`]).
    ids: Vec<crate::check::ObjectId>,
}

/// The last asset resolution: the text and seed it was made for, and each room's run in the
/// scene's order, with the rooms' names.
#[derive(Debug)]
struct ResolveMemo {
    made_for: std::sync::Arc<String>,
    /// The number of the tree whose scene it was made for.
    tree: Option<u64>,
    seed: u64,
    rooms: Vec<(String, RoomRun)>,
    /// The rooms' results put together (`None` while an analysis holds them).
    resolved: Option<Resolved>,
}

/// What the analyses of earlier versions of a document leave for the next: the parse cache
/// and asset rankings, and the last inputs and outputs of the plan and of asset resolution with
/// the text they were made for.
#[derive(Debug, Default)]
pub struct Memo {
    /// Parsed items and asset rankings.
    pub cache: AnalysisCache,
    /// The last plan: the text it was made for, its input and its output.
    /// (The plan is `None` while an analysis holds it.)
    plan: Option<(std::sync::Arc<String>, PlanInput, Output<Option<FloorPlan>>)>,
    /// The last asset resolution, room by room.
    resolve: Option<ResolveMemo>,
    /// The last check, room by room.
    check: Option<CheckMemo>,
    /// When the last check was made in place from the tree before it: that tree's number, the
    /// new tree's, and for each room whether its check was kept (the room's scene value is the
    /// one before, its spans moved and its objects numbered again).
    kept_checks: Option<(u64, u64, Vec<RoomCheck>)>,
    /// How often each stage ran and was reused (for the tests and the benchmark).
    pub counts: Counts,
}

/// The last check: the tree it checked ([`crate::parse::ParseCache::tree_number`]), its scene
/// (while no analysis holds it), its diagnostics by where they come from, and what tells
/// whether an edit may be checked room by room.
#[derive(Debug)]
struct CheckMemo {
    tree: u64,
    scene: Option<Scene>,
    head: Vec<Diagnostic>,
    rooms: Vec<crate::check::RoomDiagnostics>,
    /// The doors' diagnostics and the scene's as a whole ([`crate::check::check_tail`]).
    tail: Vec<Diagnostic>,
    /// Where the tree's doors are.
    doors: Vec<Span>,
    /// Where the tree's `scene` blocks are.
    scene_blocks: Vec<Span>,
    /// Whether every room of the tree is a room of the scene (none called `exterior`, no name
    /// given twice): then the rooms' names and ids stay while the rooms an edit touched keep
    /// their names.
    every_room_kept: bool,
    /// The shape of each room checked alone since the last whole check (the rooms being
    /// edited), from which an edit inside one object group checks that group alone.
    shapes: Vec<Option<crate::check::RoomShape>>,
}

/// How the last check made a room's check.
#[derive(Clone, Debug, PartialEq, Eq)]
enum RoomCheck {
    /// Kept from the check before (its scene value the one before, its spans moved and its
    /// objects numbered again).
    Kept,
    /// Kept but for one object group checked again alone: the places of its objects in the
    /// room's list.
    Group(std::ops::Range<usize>),
    /// Checked again.
    Again,
}

/// How often the plan ran and its last output was reused, and how many rooms' asset choices
/// were made and reused.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct Counts {
    /// Plans made.
    pub planned: u64,
    /// Plans reused.
    pub plans_reused: u64,
    /// Rooms resolved.
    pub rooms_resolved: u64,
    /// Rooms whose resolution was reused.
    pub rooms_reused: u64,
    /// Rooms checked.
    pub rooms_checked: u64,
    /// Rooms whose check was reused.
    pub rooms_check_reused: u64,
    /// Checks whose doors were kept (not checked again).
    pub doors_kept: u64,
    /// Object groups whose asset choice was taken again in a room resolved again.
    pub groups_kept: u64,
    /// Object groups checked again alone (their room's other groups' checks kept).
    pub groups_checked: u64,
}

impl Memo {
    /// Hands back the analysis of `text` that [`analyse`] made, when the document changes: the
    /// next analysis is made from it in place where the edit did not touch it.
    pub fn give_back(&mut self, analysed: Analysed, text: &str) {
        let Analysed { ast, scene, plan, resolved, diagnostics: _ } = analysed;
        if let Some(last) = &mut self.resolve {
            if last.resolved.is_none() && last.made_for.as_str() == text {
                last.resolved = resolved;
            }
        }
        if let Some((made_for, _, output)) = &mut self.plan {
            if output.value.is_none() && made_for.as_str() == text {
                output.value = plan;
            }
        }
        if self.cache.parse.give_back(ast, text) {
            if let Some(check) = &mut self.check {
                check.scene = check.scene.take().or(scene);
            }
        }
    }

    /// Forgets every output (the catalog changed): the next analysis runs every stage.
    pub fn forget(&mut self) {
        self.plan = None;
        self.resolve = None;
        self.cache.ranks = crate::resolve::RankCache::default();
    }
}

/// Runs every stage before the solver on file `file` of `sources` with `catalog`, as
/// [`crate::compile::analyse`] does (the same products and diagnostics, in the same order),
/// reusing what `memo` kept of the previous version where the edit did not touch it.
pub fn analyse(sources: &SourceMap, file: FileId, catalog: &Catalog, memo: &mut Memo) -> Analysed {
    let parsed = crate::parse::parse_edited(sources, file, &mut memo.cache.parse);
    // The text, shared (not copied) by the document, its analysis and what the memo keeps.
    let text = std::sync::Arc::clone(&sources.get(file).text);
    let mut analysed = Analysed {
        ast: parsed.value,
        scene: None,
        plan: None,
        resolved: None,
        diagnostics: parsed.diagnostics,
    };
    let has_errors = |d: &[Diagnostic]| d.iter().any(Diagnostic::is_error);
    let parse_failed = has_errors(&analysed.diagnostics);
    let checked = check(&analysed.ast, memo);
    analysed.diagnostics.extend(checked.diagnostics);
    if parse_failed || has_errors(&analysed.diagnostics) {
        // Kept for the next version.
        if let Some(check) = &mut memo.check {
            check.scene = Some(checked.value);
        }
        return analysed;
    }
    let scene = checked.value;

    let reused = memo.plan.take().and_then(|(made_for, mut before, mut output)| {
        let shift = Shift::between(&made_for, &text);
        // The plan itself is needed only when it has no error (else the analysis stops there).
        let usable = output.value.is_some() || has_errors(&output.diagnostics);
        (usable
            && shift.move_in_place(&mut before)
            && before.is_of(&scene)
            && shift.move_in_place(&mut output))
        .then_some((before, output))
    });
    let (input, mut planned) = match reused {
        Some((input, output)) => {
            memo.counts.plans_reused += 1;
            debug_assert!(input == PlanInput::of(&scene), "an input compared in place");
            (input, output)
        }
        None => {
            memo.counts.planned += 1;
            let planned =
                crate::plan::plan_with(&scene, StructureCatalog::builtin(), PlanOptions::default());
            (
                PlanInput::of(&scene),
                Output { value: Some(planned.value), diagnostics: planned.diagnostics },
            )
        }
    };
    analysed.diagnostics.extend(planned.diagnostics.iter().cloned());
    if has_errors(&analysed.diagnostics) {
        memo.plan = Some((std::sync::Arc::clone(&text), input, planned));
        analysed.scene = Some(scene);
        return analysed;
    }
    // The analysis holds the plan until it is handed back.
    analysed.plan = planned.value.take();
    memo.plan = Some((std::sync::Arc::clone(&text), input, planned));

    let resolved = resolve_rooms(&scene, &text, catalog, memo);
    analysed.diagnostics.extend(resolved.diagnostics);
    analysed.resolved = Some(resolved.value);
    analysed.scene = Some(scene);
    analysed
}

/// Checks the tree, as [`crate::check::check`] does, room by room: when the tree was edited in
/// place from the one checked last ([`crate::parse::Splice`]), only the rooms of the pieces it
/// replaced are checked again (and the rooms whose diagnostics read other rooms), provided the
/// edit touched no `scene` block and left every room's name; the other rooms' checks are kept,
/// their spans moved and their objects numbered again when a room before them changed how many
/// it has. The doors are checked again.
fn check(ast: &crate::ast::File, memo: &mut Memo) -> crate::diag::Outcome<Scene> {
    let last = memo.check.take();
    let splice = memo.cache.parse.splice();
    let in_place = match (last, splice) {
        (Some(mut last), Some(splice)) if last.tree == splice.from => {
            check_in_place(ast, &mut last, splice, &mut memo.counts)
        }
        _ => None,
    };
    let from = splice.map(|s| s.from);
    let (mut scene, head, rooms, kept_tail, shapes) = match in_place {
        Some(InPlace { scene, head, rooms, tail, kept, shapes }) => {
            memo.kept_checks = from.zip(memo.cache.parse.tree_number()).map(|(a, b)| (a, b, kept));
            (scene, head, rooms, tail, shapes)
        }
        None => {
            memo.kept_checks = None;
            let parts = crate::check::check_parts(ast);
            memo.counts.rooms_checked += parts.rooms.len() as u64;
            let shapes = vec![None; parts.rooms.len()];
            (parts.scene, parts.head, parts.rooms, None, shapes)
        }
    };
    let tail = match kept_tail {
        Some(tail) => {
            memo.counts.doors_kept += 1;
            tail
        }
        None => crate::check::check_tail(ast, &mut scene),
    };
    let mut diagnostics = head.clone();
    for room in &rooms {
        diagnostics.extend(room.diagnostics.iter().cloned());
    }
    diagnostics.extend(tail.iter().cloned());
    let tail_kept = tail;
    if let Some(tree) = memo.cache.parse.tree_number() {
        let scene_blocks = ast
            .items
            .iter()
            .filter_map(|i| match i {
                crate::ast::Item::Scene(block) => Some(block.span),
                _ => None,
            })
            .collect();
        let room_items =
            ast.items.iter().filter(|i| matches!(i, crate::ast::Item::Room(_))).count();
        let doors = ast
            .items
            .iter()
            .filter_map(|i| match i {
                crate::ast::Item::Door(door) => Some(door.span),
                _ => None,
            })
            .collect();
        memo.check = Some(CheckMemo {
            tree,
            scene: None,
            head,
            rooms,
            tail: tail_kept,
            doors,
            scene_blocks,
            every_room_kept: room_items == scene.rooms.len(),
            shapes,
        });
    }
    crate::diag::Outcome::new(scene, diagnostics)
}

/// The check of an edited tree made from the last one in place (see [`check`]), or `None`.
fn check_in_place(
    ast: &crate::ast::File,
    last: &mut CheckMemo,
    splice: crate::parse::Splice,
    counts: &mut Counts,
) -> Option<InPlace> {
    if !last.every_room_kept {
        return None;
    }
    let in_old = |span: Span| (splice.start..splice.old_end).contains(&(span.start as usize));
    let in_new = |span: Span| (splice.start..splice.new_end).contains(&(span.start as usize));
    if last.scene_blocks.iter().any(|&s| in_old(s)) {
        return None;
    }
    let mut rooms: Vec<&crate::ast::Room> = Vec::new();
    for item in &ast.items {
        match item {
            crate::ast::Item::Scene(block) if in_new(block.span) => return None,
            crate::ast::Item::Room(room) => rooms.push(room),
            _ => {}
        }
    }
    let mut scene = last.scene.take()?;
    if rooms.len() != scene.rooms.len() {
        return None;
    }
    for (room, kept) in rooms.iter().zip(&scene.rooms) {
        let touched = in_new(room.span);
        if touched != in_old(kept.decl_span) || touched && room.id.name != kept.name {
            return None;
        }
    }
    let shift = Shift { start: splice.start, old_end: splice.old_end, new_end: splice.new_end };
    let mut head = std::mem::take(&mut last.head);
    if !shift.move_in_place(&mut head) {
        return None;
    }
    let mut diagnostics = std::mem::take(&mut last.rooms);
    let mut shapes = std::mem::take(&mut last.shapes);
    shapes.resize(rooms.len(), None);
    let mut kept_checks = Vec::with_capacity(rooms.len());
    let wall_height_m = scene.wall_height_m;
    // Where the room's objects start in the scene's list now, and where they started.
    let (mut first, mut old_first) = (0usize, 0usize);
    for (r, room) in rooms.iter().enumerate() {
        let old_count = scene.rooms[r].objects.len();
        let touched = in_new(room.span);
        // An edit inside one object group of the room: that group alone is checked again.
        let body = splice.body.filter(|b| touched && b.room_start == room.span.start as usize);
        let group_checked = match (body, shapes[r].as_mut()) {
            (Some(body), Some(shape)) => {
                let moved_by = first as isize - old_first as isize;
                let old_first_object = first;
                crate::check::check_group_again(
                    ast,
                    room,
                    &scene.rooms[r],
                    shape,
                    body,
                    old_first_object,
                    wall_height_m,
                )
                .map(|done| (done, body, moved_by))
            }
            _ => None,
        };
        let mut members = None;
        let group_checked = group_checked.is_some_and(|(done, body, moved_by)| {
            members = Some(done.objects.clone());
            let inner = Shift { start: body.start, old_end: body.old_end, new_end: body.new_end };
            let kept = &mut scene.rooms[r];
            let objects = &mut scene.objects[first..first + old_count];
            if moved_by != 0 {
                crate::check::renumber_objects(kept, objects, moved_by);
            }
            let own = &mut diagnostics[r];
            let ok = done.new_objects.len() == done.objects.len()
                && inner.move_in_place(kept)
                && objects
                    .iter_mut()
                    .enumerate()
                    .filter(|(i, _)| !done.objects.contains(i))
                    .all(|(_, o)| inner.move_in_place(o))
                && own
                    .diagnostics
                    .iter_mut()
                    .enumerate()
                    .filter(|(i, _)| !done.diagnostics.contains(i))
                    .all(|(_, d)| inner.move_in_place(d));
            if ok {
                for (slot, object) in objects[done.objects.clone()].iter_mut().zip(done.new_objects)
                {
                    *slot = object;
                }
                let _ = own.diagnostics.splice(done.diagnostics, done.new_diagnostics);
                own.reads_other_rooms |= done.reads_other_rooms;
            }
            ok
        });
        if let (true, Some(members)) = (group_checked, members) {
            first += old_count;
            counts.groups_checked += 1;
            kept_checks.push(RoomCheck::Group(members));
        } else if touched || diagnostics[r].reads_other_rooms {
            let id = crate::check::RoomId(r);
            let (checked, objects, own, shape) =
                crate::check::check_room_shaped(ast, room, id, first, wall_height_m);
            let count = objects.len();
            let _ = scene.objects.splice(first..first + old_count, objects);
            scene.rooms[r] = checked;
            diagnostics[r] = own;
            shapes[r] = shape;
            first += count;
            counts.rooms_checked += 1;
            kept_checks.push(RoomCheck::Again);
        } else {
            let kept = &mut scene.rooms[r];
            let objects = &mut scene.objects[first..first + old_count];
            if first != old_first {
                crate::check::renumber_objects(kept, objects, first as isize - old_first as isize);
            }
            // A room before the edit does not move; one after it moves unless the length stayed.
            let moves =
                kept.decl_span.start as usize >= splice.old_end && splice.old_end != splice.new_end;
            if moves
                && !(shift.move_in_place(kept)
                    && objects.iter_mut().all(|o| shift.move_in_place(o))
                    && shift.move_in_place(&mut diagnostics[r].diagnostics))
            {
                return None;
            }
            first += old_count;
            counts.rooms_check_reused += 1;
            kept_checks.push(RoomCheck::Kept);
        }
        old_first += old_count;
    }
    // The doors read the rooms' names and ids alone, which stay: when the edit touched no
    // door either, the doors and their diagnostics are the last ones, moved.
    let doors_touched = last.doors.iter().any(|&d| in_old(d))
        || ast.items.iter().any(|i| matches!(i, crate::ast::Item::Door(d) if in_new(d.span)));
    let mut tail = std::mem::take(&mut last.tail);
    let tail = (!doors_touched
        && !scene.rooms.is_empty()
        && shift.move_in_place(&mut tail)
        && scene.doors.iter_mut().all(|d| shift.move_in_place(d)))
    .then_some(tail);
    Some(InPlace { scene, head, rooms: diagnostics, tail, kept: kept_checks, shapes })
}

/// What [`check_in_place`] gives.
struct InPlace {
    scene: Scene,
    /// The head's diagnostics.
    head: Vec<Diagnostic>,
    /// Each room's diagnostics.
    rooms: Vec<crate::check::RoomDiagnostics>,
    /// The doors' diagnostics when the doors were kept (`None`: they are to be checked again).
    tail: Option<Vec<Diagnostic>>,
    /// For each room, how its check was made.
    kept: Vec<RoomCheck>,
    /// The rooms' shapes.
    shapes: Vec<Option<crate::check::RoomShape>>,
}

/// The most asset rankings the open of a document keeps that no room holds (about 12 KB
/// each): a scene that repeats its descriptions asks fewer questions than that, and one whose
/// every object group has a description of its own is held to about this many.
const MAX_RANKINGS: usize = 2048;

/// Resolves the scene's assets room by room, reusing each room's last resolution when its
/// input, moved by the edit, is the same and the rooms before it use the assets it asked about
/// as they did then (a room whose choices changed changes what the rooms after it read).
fn resolve_rooms(
    scene: &Scene,
    text: &std::sync::Arc<String>,
    catalog: &Catalog,
    memo: &mut Memo,
) -> crate::diag::Outcome<Resolved> {
    let (shift, old, last_resolved, last_tree) = match memo.resolve.take() {
        Some(last) if last.seed == scene.seed => {
            (Some(Shift::between(&last.made_for, text)), last.rooms, last.resolved, last.tree)
        }
        _ => (None, Vec::new(), None, None),
    };
    // The rooms whose check the last check kept, when it was made from the tree this
    // resolution's memo was made for: their input is the one before, moved, and is not
    // compared again.
    let kept_checks: &[RoomCheck] = match &memo.kept_checks {
        Some((from, to, kept))
            if last_tree == Some(*from) && memo.cache.parse.tree_number() == Some(*to) =>
        {
            kept
        }
        _ => &[],
    };
    let same_rooms = old.len() == scene.rooms.len();
    // The runs kept hold no resolutions of their own (they are in the last result, moved out
    // of the runs when it was put together): without it, no run can be kept.
    let old = if last_resolved.is_some() { old } else { Vec::new() };
    let (names, mut old): (Vec<String>, Vec<Option<RoomRun>>) =
        old.into_iter().map(|(name, run)| (name, Some(run))).unzip();
    let by_name: rustc_hash::FxHashMap<&str, usize> =
        names.iter().enumerate().map(|(i, name)| (name.as_str(), i)).collect();
    let options = crate::resolve::ResolveOptions::default();
    let mut resolver =
        crate::resolve::Resolver::new(catalog, scene.seed, &options, &mut memo.cache.ranks);
    let mut runs: Vec<(String, RoomRun)> = Vec::with_capacity(scene.rooms.len());
    // The rooms whose entries of the last result must be made again, and the object ids those
    // entries had.
    let mut again: Vec<usize> = Vec::new();
    let mut gone: Vec<Vec<crate::check::ObjectId>> = Vec::new();
    // For each room whose run is kept, the place it had in the last result's rooms.
    let mut kept_from: Vec<Option<usize>> = Vec::with_capacity(scene.rooms.len());
    // While every room so far is the one at its place last time and uses the same assets, the
    // rooms before the next one use what they used then: its answers hold without asking.
    let mut in_step = shift.is_some();
    // The rooms whose assets the resolver counts as used (`runs[..counted]`): counted only
    // when a room is resolved or its answers checked, so that an edit in the last rooms does
    // not go through every earlier room's assets.
    let mut counted = 0;
    // The objects of the groups chosen again alone, with their new resolutions.
    let mut patches: Vec<(Vec<crate::check::ObjectId>, Vec<crate::resolve::Resolution>)> =
        Vec::new();
    for (k, room) in scene.rooms.iter().enumerate() {
        let place = by_name.get(room.name.as_str()).copied();
        let mut run = place.and_then(|i| old.get_mut(i)).and_then(Option::take);
        in_step &= place == Some(k);
        // The run's input and diagnostics moved by the edit (a run that cannot be is thrown
        // away).
        // A room whose check changed in one object group alone: that group is chosen again
        // alone (its other groups' choices kept), when its last run recorded them.
        let group = match kept_checks.get(k) {
            Some(RoomCheck::Group(members)) if place == Some(k) => Some(members.clone()),
            _ => None,
        };
        let reusable = match (&mut run, shift) {
            (Some(_), Some(_)) if group.is_some() => false,
            (Some(run), Some(shift)) => {
                let check_kept = place == Some(k) && kept_checks.get(k) == Some(&RoomCheck::Kept);
                (in_step || {
                    used_up_to(&mut resolver, &runs, &mut counted);
                    resolver.reads_hold(&run.output)
                }) && shift.move_in_place(&mut run.input)
                    && (check_kept || run.input.is_of(scene, room))
                    && shift.move_in_place(&mut run.output.diagnostics)
            }
            _ => false,
        };
        // The group chosen again alone: its results, to be put in the result once it is put
        // together (the run's other entries are kept as a kept run's are).
        let mut spoiled = false;
        if let (Some(members), Some(last), Some(shift), Some(resolved)) =
            (group, run.as_mut(), shift, last_resolved.as_ref())
        {
            let no_small = members.clone().all(|i| {
                room.objects.get(i).is_some_and(|&id| {
                    resolved.small.range((id, 0)..=(id, usize::MAX)).next().is_none()
                })
            });
            if last.ids == room.objects && no_small {
                used_up_to(&mut resolver, &runs, &mut counted);
                let moved = |span: Span| shift.span(span);
                match resolver.group_again(scene, room, &mut last.output, members.clone(), &moved) {
                    Some((results, writes_changed)) => {
                        memo.counts.rooms_resolved += 1;
                        in_step &= !writes_changed;
                        last.input = RoomInput::of(scene, room);
                        let ids: Vec<crate::check::ObjectId> =
                            members.map(|i| room.objects[i]).collect();
                        patches.push((ids, results));
                        kept_from.push(place);
                        let run = run.take().expect("matched above");
                        runs.push((room.name.clone(), run));
                        continue;
                    }
                    None => spoiled = true,
                }
            }
        }
        let run = match run {
            Some(mut run) if reusable => {
                memo.counts.rooms_reused += 1;
                // A room not being edited holds no rankings (see below).
                run.output.release_rankings();
                debug_assert!(
                    run.input == RoomInput::of(scene, room),
                    "an input compared in place"
                );
                // Its entries of the last result hold if its objects and place are the same.
                if place != Some(k) || run.ids != room.objects {
                    gone.push(run.ids.clone());
                    again.push(k);
                }
                kept_from.push(place);
                run
            }
            run => {
                memo.counts.rooms_resolved += 1;
                used_up_to(&mut resolver, &runs, &mut counted);
                // While editing, a room resolved again takes again the choices of its object
                // groups whose input did not change (their spans moved by the edit); the first
                // resolution of a scene records none (`Resolver::room`).
                let mut run = run;
                let output = match (shift, &mut run) {
                    (Some(shift), Some(last)) if !spoiled => {
                        let ok = std::cell::Cell::new(true);
                        last.output.spans_mut(
                            &mut |span| match shift.span(*span) {
                                Some(moved) => *span = moved,
                                None => ok.set(false),
                            },
                            &mut |d| {
                                if !shift.move_in_place(d) {
                                    ok.set(false);
                                }
                            },
                        );
                        resolver.room_again(scene, room, ok.get().then_some(&mut last.output))
                    }
                    (Some(_), _) => resolver.room_again(scene, room, None),
                    (None, _) => {
                        // The open: the rooms share rankings while they are resolved, and
                        // then hold none, so that the cache keeps only the rankings of the
                        // rooms being edited (one ranking per object group with a description
                        // of its own was most of the memory of a large scene).
                        let mut output = resolver.room(scene, room);
                        output.release_rankings();
                        resolver.bound_rankings(MAX_RANKINGS);
                        output
                    }
                };
                if let Some(run) = &run {
                    gone.push(run.ids.clone());
                }
                again.push(k);
                kept_from.push(None);
                in_step &= run.is_some_and(|run| output.writes == run.output.writes);
                RoomRun { input: RoomInput::of(scene, room), output, ids: room.objects.clone() }
            }
        };
        runs.push((room.name.clone(), run));
    }
    // The rooms no longer there let go of their rankings before the cache keeps what rooms hold.
    drop(old);
    memo.counts.groups_kept += resolver.groups_kept();
    resolver.finish(&mut memo.cache.ranks);
    let mut resolved = match last_resolved {
        Some(last) if same_rooms && last.objects.len() == scene.objects.len() => {
            assemble_in_place(last, scene, &mut runs, &again, &gone, &kept_from)
        }
        last => assemble_anew(last, scene, &mut runs, &kept_from),
    };
    for (ids, results) in patches {
        for (id, res) in ids.into_iter().zip(results) {
            if let Some(slot) = resolved.value.objects.get_mut(id.0) {
                *slot = res;
            }
        }
    }
    memo.resolve = Some(ResolveMemo {
        made_for: std::sync::Arc::clone(text),
        tree: memo.cache.parse.tree_number(),
        seed: scene.seed,
        rooms: runs,
        resolved: None,
    });
    resolved
}

/// Counts the assets of the rooms of `runs` not counted yet (from `counted` on) as used by the
/// rooms before the next one.
fn used_up_to(
    resolver: &mut crate::resolve::Resolver<'_>,
    runs: &[(String, RoomRun)],
    counted: &mut usize,
) {
    for (_, run) in runs.get(*counted..).unwrap_or_default() {
        resolver.used_before(&run.output);
    }
    *counted = runs.len();
}

/// What [`crate::resolve::assemble`] makes of the rooms' runs, made from the last result:
/// the entries of the rooms `again` put again (those of the object ids `gone` had removed
/// first), every other room's kept. A run holds no resolutions once they are put (they are
/// moved into the result, not copied): a kept run put again at another place (`kept_from`, the
/// place it had) takes its entries out of the last result first. The diagnostics are every
/// room's, in order.
fn assemble_in_place(
    mut resolved: Resolved,
    scene: &Scene,
    runs: &mut [(String, RoomRun)],
    again: &[usize],
    gone: &[Vec<crate::check::ObjectId>],
    kept_from: &[Option<usize>],
) -> crate::diag::Outcome<Resolved> {
    // Every entry to move is taken out before any is put.
    for &k in again {
        if let Some(place) = kept_from[k] {
            let run = &mut runs[k].1;
            resolved.take_room(crate::check::RoomId(place), &run.ids, &mut run.output);
        }
    }
    let forget = |resolved: &mut Resolved, id: crate::check::ObjectId| {
        let keys: Vec<(crate::check::ObjectId, usize)> =
            resolved.small.range((id, 0)..=(id, usize::MAX)).map(|(key, _)| *key).collect();
        for key in keys {
            resolved.small.remove(&key);
        }
    };
    for ids in gone {
        for &id in ids {
            forget(&mut resolved, id);
        }
    }
    for &k in again {
        let room = &scene.rooms[k];
        resolved.ceilings.remove(&room.id);
        resolved.ceiling_lights.remove(&room.id);
        for &id in &room.objects {
            forget(&mut resolved, id);
        }
    }
    for &k in again {
        let room = &scene.rooms[k];
        let run = &mut runs[k].1;
        resolved.put_room_taken(room, &mut run.output);
        run.ids.clone_from(&room.objects);
    }
    let diagnostics =
        runs.iter().flat_map(|(_, run)| run.output.diagnostics.iter().cloned()).collect();
    crate::diag::Outcome::new(resolved, diagnostics)
}

/// What [`crate::resolve::assemble`] makes of the rooms' runs, put together anew: the kept
/// runs' entries (`kept_from`, the place each had) taken out of the last result, which every
/// kept run needs, every run's moved into the new one.
fn assemble_anew(
    mut last: Option<Resolved>,
    scene: &Scene,
    runs: &mut [(String, RoomRun)],
    kept_from: &[Option<usize>],
) -> crate::diag::Outcome<Resolved> {
    let mut resolved = crate::resolve::assemble(scene, std::iter::empty()).value;
    let mut diagnostics = Vec::new();
    for ((room, (_, run)), from) in scene.rooms.iter().zip(runs.iter_mut()).zip(kept_from) {
        if let (Some(place), Some(last)) = (from, &mut last) {
            last.take_room(crate::check::RoomId(*place), &run.ids, &mut run.output);
        }
        resolved.put_room_taken(room, &mut run.output);
        run.ids.clone_from(&room.objects);
        diagnostics.extend(run.output.diagnostics.iter().cloned());
    }
    crate::diag::Outcome::new(resolved, diagnostics)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_shift_moves_what_follows_the_edit_and_refuses_what_it_cut() {
        let shift = Shift::between("abcdef", "abXYZef");
        assert_eq!(shift, Shift { start: 2, old_end: 4, new_end: 5 });
        assert_eq!(shift.offset(1), Some(1));
        assert_eq!(shift.offset(2), Some(2));
        assert_eq!(shift.offset(3), None);
        assert_eq!(shift.offset(4), Some(5));
        assert_eq!(shift.offset(6), Some(7));
        let same = Shift::between("aaa", "aaaa");
        assert_eq!(same, Shift { start: 3, old_end: 3, new_end: 4 });
        assert_eq!(Shift::between("", "x"), Shift { start: 0, old_end: 0, new_end: 1 });
        // Long texts are compared a block at a time: the same answers.
        let long: String = (0..500).map(|i| char::from(b'a' + (i % 26) as u8)).collect();
        let edited = format!("{}XY{}", &long[..200], &long[201..]);
        assert_eq!(
            Shift::between(&long, &edited),
            Shift { start: 200, old_end: 201, new_end: 202 }
        );
        assert_eq!(Shift::between(&long, &long), Shift { start: 500, old_end: 500, new_end: 500 });
        let doubled = format!("{long}{long}");
        assert_eq!(
            Shift::between(&long, &doubled),
            Shift { start: 500, old_end: 500, new_end: 1000 }
        );
    }
}

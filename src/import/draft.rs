//! The scene being imported, before it becomes a syntax tree, and its printing as one.

use crate::ast::{self, Ident, Quantity, Str, Unit};
use crate::source::Span;

/// The scene assembled from the answers read so far.
#[derive(Clone, Debug, Default)]
pub(crate) struct Draft {
    pub request: Option<String>,
    pub seed: u64,
    pub wall_height: Option<f64>,
    pub rooms: Vec<DRoom>,
    pub doors: Vec<DDoor>,
    /// Raw lines that belong to no room, printed at the end of the file.
    pub comments: Vec<String>,
}

#[derive(Clone, Debug, Default)]
pub(crate) struct DRoom {
    pub id: String,
    pub label: String,
    pub floor: Option<String>,
    pub walls: Option<String>,
    /// Corners in metres, (x, z).
    pub corners: Vec<(f64, f64)>,
    pub windows: Vec<DWindow>,
    pub objects: Vec<DObject>,
    pub ceiling: Option<String>,
    pub comments: Vec<String>,
    /// Whether the room was created by a stage other than the floor plan.
    pub implicit: bool,
    /// Where the floor plan names it (its name on its line), when it does.
    pub span: Option<Span>,
}

#[derive(Clone, Debug)]
pub(crate) struct DWindow {
    pub wall: String,
    pub kind: String,
    pub width_cm: f64,
    pub height_cm: f64,
    pub count: u32,
    pub sill_cm: f64,
}

#[derive(Clone, Debug)]
pub(crate) struct DDoor {
    pub from: String,
    pub to: String,
    pub kind: String,
    pub size: Option<String>,
    pub style: Option<String>,
    pub asset: Option<String>,
    pub comments: Vec<String>,
}

#[derive(Clone, Debug, Default)]
pub(crate) struct DObject {
    pub id: String,
    pub category: String,
    pub wall: bool,
    pub describe: Option<String>,
    /// Width × depth × height, cm.
    pub size: Option<[f64; 3]>,
    pub count: u32,
    pub variance: Option<String>,
    pub on_top: Vec<DOnTop>,
    pub instances: Vec<DInstance>,
    pub comments: Vec<String>,
    /// Position in the constraint answer (None: not mentioned).
    pub order: Option<usize>,
    /// Where the object selection declares it (its key or category), when it does.
    pub span: Option<Span>,
}

#[derive(Clone, Debug, Default)]
pub(crate) struct DInstance {
    pub constraints: Vec<(String, Option<String>)>,
    pub above: Option<String>,
    pub height_cm: Option<f64>,
    pub asset: Option<String>,
    /// `at` values in metres (2 for floor, 3 for wall).
    pub at: Option<Vec<f64>>,
    pub facing: Option<f64>,
    pub on_top: Vec<DOnTop>,
    pub comments: Vec<String>,
    /// Position of this instance's line in the constraint answer.
    pub order: Option<usize>,
}

#[derive(Clone, Debug)]
pub(crate) struct DOnTop {
    pub item: String,
    pub count: u32,
    pub variance: Option<String>,
    pub asset: Option<String>,
    pub at: Option<Vec<f64>>,
    pub facing: Option<f64>,
}

impl DObject {
    /// Makes sure `instances` has `count` entries.
    pub fn fit(&mut self) {
        let n = self.count.max(1) as usize;
        if self.instances.len() < n {
            self.instances.resize_with(n, DInstance::default);
        }
    }

    /// The instance names, `<id>-<n>`.
    pub fn instance_names(&self) -> Vec<String> {
        (0..self.count.max(1)).map(|i| format!("{}-{i}", self.id)).collect()
    }
}

impl Draft {
    pub fn room(&self, id: &str) -> Option<&DRoom> {
        self.rooms.iter().find(|r| r.id == id)
    }

    pub fn room_mut(&mut self, id: &str) -> Option<&mut DRoom> {
        self.rooms.iter_mut().find(|r| r.id == id)
    }

    /// Finds a room by label or id, ignoring case, spacing and `_`/`-`/space differences.
    pub fn find_room(&self, name: &str) -> Option<&DRoom> {
        let key = loose(name);
        self.rooms
            .iter()
            .find(|r| loose(&r.label) == key)
            .or_else(|| self.rooms.iter().find(|r| loose(&r.id) == key))
    }

    /// Room labels and ids, for suggestions.
    pub fn room_names(&self) -> Vec<String> {
        self.rooms.iter().map(|r| r.label.clone()).collect()
    }

    /// A fresh room id for a label (see `room_id`), suffixed `_2`, `_3`, … when taken.
    pub fn fresh_room_id(&self, label: &str) -> (String, bool) {
        let base = room_id(label);
        if self.room(&base).is_none() {
            return (base, false);
        }
        let mut n = 2;
        loop {
            let id = format!("{base}_{n}");
            if self.room(&id).is_none() {
                return (id, true);
            }
            n += 1;
        }
    }

    /// Adds a room created by a later stage (stand-alone import without a floor plan).
    pub fn implicit_room(&mut self, label: &str) -> String {
        if let Some(r) = self.find_room(label) {
            return r.id.clone();
        }
        let (id, _) = self.fresh_room_id(label);
        self.rooms.push(DRoom {
            id: id.clone(),
            label: label.trim().to_string(),
            implicit: true,
            ..DRoom::default()
        });
        id
    }
}

/// A comparison key for names: the same rule as [`room_id`] without its prefix (lower case,
/// accents dropped, apostrophes inside a word dropped, every other run of characters outside
/// `a-z0-9` one `_`).
pub(crate) fn loose(name: &str) -> String {
    slug(name)
}

/// Whether a character is an apostrophe (straight, typographic or modifier letter): it joins
/// the letters around it (`professor's` → `professors`) rather than separating words.
fn is_apostrophe(c: char) -> bool {
    matches!(c, '\'' | '\u{2019}' | '\u{2018}' | '\u{02BC}' | '`' | '\u{00B4}')
}

/// The one rule that turns a name into the letters of an id, shared by every stage (the floor
/// plan's room ids, the rooms a later answer names, object ids): compatibility decomposition
/// with the combining marks dropped (`Café` → `cafe`, `Zoë` → `zoe`), lower case, apostrophes
/// dropped, and every run of other characters outside `a-z0-9` one `_`, trimmed.
fn slug(name: &str) -> String {
    use unicode_normalization::char::is_combining_mark;
    use unicode_normalization::UnicodeNormalization;
    let mut out = String::new();
    let mut gap = false;
    for c in name.nfkd().filter(|c| !is_combining_mark(*c)).flat_map(char::to_lowercase) {
        if c.is_ascii_lowercase() || c.is_ascii_digit() {
            if gap && !out.is_empty() {
                out.push('_');
            }
            gap = false;
            out.push(c);
        } else if !is_apostrophe(c) {
            gap = true;
        }
    }
    out
}

/// Words that cannot be room ids.
const KEYWORDS: &[&str] = &[
    "exterior", "scene", "room", "door", "wall", "walls", "floor", "object", "instance", "ceiling",
    "window", "corners", "material", "seed", "height",
];

/// The id rule: lower-case, every run of characters other than `a-z0-9` becomes `_`, trimmed
/// of `_`; prefixed `r_` when it starts with a digit, is empty or is a keyword.
pub(crate) fn room_id(label: &str) -> String {
    let s = slug(label);
    if s.is_empty() || s.starts_with(|c: char| c.is_ascii_digit()) || KEYWORDS.contains(&s.as_str())
    {
        format!("r_{s}").trim_end_matches('_').to_string()
    } else {
        s
    }
}

/// The id of an object group from its normalised key, by the same rule (prefix `o_`).
pub(crate) fn object_id(key: &str) -> String {
    let s = slug(key);
    if s.is_empty() || s.starts_with(|c: char| c.is_ascii_digit()) || KEYWORDS.contains(&s.as_str())
    {
        format!("o_{s}").trim_end_matches('_').to_string()
    } else {
        s
    }
}

// ---------------------------------------------------------------------------------------------
// Printing as a syntax tree.

struct B {
    span: Span,
}

impl B {
    fn id(&self, name: &str) -> Ident {
        Ident::new(name, self.span)
    }
    fn s(&self, value: &str) -> Str {
        Str { value: value.to_string(), span: self.span }
    }
    fn q(&self, value: f64, unit: Option<Unit>) -> Quantity {
        Quantity::new(round(value), unit, self.span)
    }
    fn comment(&self, text: &str) -> ast::Comment {
        ast::Comment { text: text.to_string(), trailing: false, span: self.span }
    }
}

/// Rounds to 6 decimals so that float noise does not reach the output.
fn round(v: f64) -> f64 {
    let r = (v * 1e6).round() / 1e6;
    if r == 0.0 {
        0.0
    } else {
        r
    }
}

impl Draft {
    /// The draft as a `.holo` syntax tree. `span` is given to every node.
    pub fn to_ast(&self, span: Span) -> ast::File {
        let b = B { span };
        let mut items = Vec::new();
        if self.request.is_some() || self.wall_height.is_some() {
            let mut body = Vec::new();
            if let Some(h) = self.wall_height {
                body.push(ast::SceneStmt::WallHeight(b.q(h, Some(Unit::M)), span));
            }
            body.push(ast::SceneStmt::Seed(b.q(self.seed as f64, None), span));
            items.push(ast::Item::Scene(ast::SceneBlock {
                request: self.request.as_ref().map(|r| b.s(r)),
                body,
                span,
            }));
        }
        for room in &self.rooms {
            items.push(ast::Item::Room(room_ast(&b, room)));
        }
        for door in &self.doors {
            for c in &door.comments {
                items.push(ast::Item::Comment(b.comment(c)));
            }
            items.push(ast::Item::Door(ast::Door {
                from: b.id(&door.from),
                to: b.id(&door.to),
                kind: b.id(&door.kind),
                size: door.size.as_deref().map(|s| b.id(s)),
                style: door.style.as_deref().map(|s| b.s(s)),
                asset: door.asset.as_deref().map(|s| b.s(s)),
                span,
            }));
        }
        for c in &self.comments {
            items.push(ast::Item::Comment(b.comment(c)));
        }
        ast::File { items, span }
    }
}

fn room_ast(b: &B, room: &DRoom) -> ast::Room {
    let mut body = Vec::new();
    if let Some(f) = &room.floor {
        body.push(ast::RoomStmt::FloorDesign(b.s(f), b.span));
    }
    if let Some(w) = &room.walls {
        body.push(ast::RoomStmt::WallDesign(b.s(w), b.span));
    }
    if !room.corners.is_empty() {
        body.push(ast::RoomStmt::Corners(ast::Corners {
            unit: Some((Unit::M, b.span)),
            points: room
                .corners
                .iter()
                .map(|&(x, z)| ast::Point { x: b.q(x, None), z: b.q(z, None), span: b.span })
                .collect(),
            span: b.span,
        }));
    }
    for w in &room.windows {
        body.push(ast::RoomStmt::Window(Box::new(ast::Window {
            wall: b.id(&w.wall),
            kind: b.id(&w.kind),
            width: b.q(w.width_cm, Some(Unit::Cm)),
            height: b.q(w.height_cm, Some(Unit::Cm)),
            count: Some(b.q(f64::from(w.count), None)),
            sill: Some(b.q(w.sill_cm, Some(Unit::Cm))),
            asset: None,
            span: b.span,
        })));
    }
    for c in &room.comments {
        body.push(ast::RoomStmt::Comment(b.comment(c)));
    }
    let mut objects: Vec<&DObject> = room.objects.iter().collect();
    // Objects named by the constraint answer first, in its order; the others after.
    objects.sort_by_key(|o| (o.wall, o.order.is_none(), o.order.unwrap_or(0)));
    for o in objects {
        let obj = object_ast(b, o);
        body.push(if o.wall { ast::RoomStmt::WallObject(obj) } else { ast::RoomStmt::Object(obj) });
    }
    if let Some(c) = &room.ceiling {
        body.push(ast::RoomStmt::Ceiling(ast::Ceiling {
            description: b.s(c),
            body: Vec::new(),
            span: b.span,
        }));
    }
    ast::Room { id: b.id(&room.id), label: Some(b.s(&room.label)), body, span: b.span }
}

fn on_top_ast(b: &B, t: &DOnTop) -> ast::ObjectStmt {
    let mut body = Vec::new();
    if let Some(a) = &t.asset {
        body.push(ast::ObjectStmt::Asset(b.s(a), b.span));
    }
    if let Some(at) = &t.at {
        body.push(ast::ObjectStmt::At(at.iter().map(|&v| b.q(v, Some(Unit::M))).collect(), b.span));
    }
    if let Some(f) = t.facing {
        body.push(ast::ObjectStmt::Facing(b.q(f, Some(Unit::Deg)), b.span));
    }
    ast::ObjectStmt::OnTop(ast::OnTop {
        item: b.s(&t.item),
        count: Some(b.q(f64::from(t.count), None)),
        variance: t.variance.as_deref().map(|v| b.id(v)),
        body,
        span: b.span,
    })
}

fn instance_stmts(b: &B, inst: &DInstance) -> Vec<ast::ObjectStmt> {
    let mut body = Vec::new();
    if let Some(a) = &inst.asset {
        body.push(ast::ObjectStmt::Asset(b.s(a), b.span));
    }
    for (name, target) in &inst.constraints {
        body.push(ast::ObjectStmt::Constraint(ast::Constraint {
            name: b.id(name),
            target: target.as_deref().map(|t| b.id(t)),
            span: b.span,
        }));
    }
    if let Some(t) = &inst.above {
        body.push(ast::ObjectStmt::Above(b.id(t), b.span));
    }
    if let Some(h) = inst.height_cm {
        body.push(ast::ObjectStmt::Height(b.q(h, Some(Unit::Cm)), b.span));
    }
    if let Some(at) = &inst.at {
        body.push(ast::ObjectStmt::At(at.iter().map(|&v| b.q(v, Some(Unit::M))).collect(), b.span));
    }
    if let Some(f) = inst.facing {
        body.push(ast::ObjectStmt::Facing(b.q(f, Some(Unit::Deg)), b.span));
    }
    for t in &inst.on_top {
        body.push(on_top_ast(b, t));
    }
    for c in &inst.comments {
        body.push(ast::ObjectStmt::Comment(b.comment(c)));
    }
    body
}

fn object_ast(b: &B, o: &DObject) -> ast::Object {
    let mut body = Vec::new();
    if let Some(d) = &o.describe {
        body.push(ast::ObjectStmt::Describe(b.s(d), b.span));
    }
    if let Some([w, d, h]) = o.size {
        body.push(ast::ObjectStmt::Size(ast::Size3 {
            width: b.q(w, Some(Unit::Cm)),
            depth: b.q(d, Some(Unit::Cm)),
            height: b.q(h, Some(Unit::Cm)),
            span: b.span,
        }));
    }
    if o.count > 1 || o.variance.is_some() {
        body.push(ast::ObjectStmt::Count(
            b.q(f64::from(o.count.max(1)), None),
            o.variance.as_deref().map(|v| b.id(v)),
            b.span,
        ));
    }
    for t in &o.on_top {
        body.push(on_top_ast(b, t));
    }
    for c in &o.comments {
        body.push(ast::ObjectStmt::Comment(b.comment(c)));
    }
    if o.count <= 1 {
        if let Some(inst) = o.instances.first() {
            body.extend(instance_stmts(b, inst));
        }
    } else {
        let mut order: Vec<(usize, &DInstance)> = o.instances.iter().enumerate().collect();
        order.sort_by_key(|(i, inst)| (inst.order.is_none(), inst.order.unwrap_or(0), *i));
        for (i, inst) in order {
            let stmts = instance_stmts(b, inst);
            if stmts.is_empty() {
                continue;
            }
            body.push(ast::ObjectStmt::Instance(ast::Instance {
                id: b.id(&format!("{}-{i}", o.id)),
                body: stmts,
                span: b.span,
            }));
        }
    }
    ast::Object {
        id: b.id(&o.id),
        category: b.s(&o.category),
        has_block: !body.is_empty(),
        body,
        span: b.span,
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn id_rule() {
        assert_eq!(room_id("Living Room"), "living_room");
        assert_eq!(room_id("  Kid's room #2 "), "kids_room_2");
        assert_eq!(room_id("professor’s office"), "professors_office");
        assert_eq!(room_id("Café Zoë"), "cafe_zoe");
        assert_eq!(loose("professor's office"), loose("Professors office"));
        assert_eq!(room_id("2nd bedroom"), "r_2nd_bedroom");
        assert_eq!(room_id("Exterior"), "r_exterior");
        assert_eq!(room_id("日本"), "r");
    }
}

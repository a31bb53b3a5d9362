//! The syntax tree of a `.holo` file.
//!
//! It mirrors the text: every node has a `span`, names keep their own span, values keep the unit
//! they were written with (or none, which the checker reports), and comments are nodes so that
//! `holoc fmt` and the importer lose nothing. Words whose vocabulary the checker knows (window
//! types, directions, door kinds, constraint names) are kept as written in a [`Word`] so that a
//! misspelling gets a did-you-mean from the checker rather than a syntax error.
//!
//! [`File::shape`] prints a tree without its spans: two trees say the same thing when their
//! shapes are equal, which is what the formatter's round-trip property compares.

use crate::source::Span;

/// A name with its own span. Equality ignores the span.
#[derive(Clone, Debug, Eq)]
pub struct Ident {
    /// The name as written.
    pub name: String,
    /// Where it is written.
    pub span: Span,
}

impl PartialEq for Ident {
    fn eq(&self, other: &Self) -> bool {
        self.name == other.name
    }
}

impl Ident {
    /// Makes an identifier.
    pub fn new(name: impl Into<String>, span: Span) -> Ident {
        Ident { name: name.into(), span }
    }
}

/// A keyword-like word (or several, e.g. `in front of`) kept as written.
pub type Word = Ident;

/// A string literal, unescaped. Equality ignores the span.
#[derive(Clone, Debug, Eq)]
pub struct Str {
    /// The value, escapes resolved.
    pub value: String,
    /// Where it is written, quotes included.
    pub span: Span,
}

impl PartialEq for Str {
    fn eq(&self, other: &Self) -> bool {
        self.value == other.value
    }
}

/// A unit a number may carry.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Unit {
    /// Metres.
    M,
    /// Centimetres.
    Cm,
    /// Degrees.
    Deg,
    /// Millimetres (read so that the checker can suggest the conversion; not accepted).
    Mm,
    /// Feet (not accepted).
    Ft,
    /// Inches (not accepted).
    In,
    /// Radians (not accepted).
    Rad,
}

impl Unit {
    /// The unit as written.
    pub fn as_str(self) -> &'static str {
        match self {
            Unit::M => "m",
            Unit::Cm => "cm",
            Unit::Deg => "deg",
            Unit::Mm => "mm",
            Unit::Ft => "ft",
            Unit::In => "in",
            Unit::Rad => "rad",
        }
    }
}

/// A number with an optional unit: `2.7 m`, `130 cm`, `90 deg`, or a bare `42`.
#[derive(Clone, Debug)]
pub struct Quantity {
    /// The value as read.
    pub value: f64,
    /// The number's text as written (kept so that `fmt` prints `2.50` as it was written).
    pub text: String,
    /// The unit, if any.
    pub unit: Option<Unit>,
    /// The unit's own span, if any.
    pub unit_span: Option<Span>,
    /// The number and its unit.
    pub span: Span,
}

impl PartialEq for Quantity {
    fn eq(&self, other: &Self) -> bool {
        self.value.to_bits() == other.value.to_bits() && self.unit == other.unit
    }
}

impl Quantity {
    /// A quantity with a unit, printed with the shortest text that reads back the same value.
    pub fn new(value: f64, unit: Option<Unit>, span: Span) -> Quantity {
        Quantity { value, text: format_number(value), unit, unit_span: None, span }
    }
}

/// Prints a number with the shortest text that reads back as the same `f64` (no exponent).
pub fn format_number(value: f64) -> String {
    if value == value.trunc() && value.abs() < 1e15 {
        format!("{}", value as i64)
    } else {
        let text = format!("{value}");
        if text.contains('e') {
            format!("{value:.6}").trim_end_matches('0').trim_end_matches('.').to_string()
        } else {
            text
        }
    }
}

/// A whole `.holo` file.
#[derive(Clone, Debug, PartialEq)]
pub struct File {
    /// Top-level items in order.
    pub items: Vec<Item>,
    /// The whole file.
    pub span: Span,
}

impl File {
    /// The tree printed without spans and without empty lines: what the file says,
    /// independent of where and how it is laid out.
    pub fn shape(&self) -> String {
        let debug = format!("{:?}", self.items);
        let mut out = String::with_capacity(debug.len());
        let mut rest = debug.as_str();
        while let Some(at) = rest.find("Span { file: ") {
            out.push_str(&rest[..at]);
            out.push('_');
            let after = &rest[at..];
            let close = after.find('}').map_or(after.len(), |i| i + 1);
            rest = &after[close..];
        }
        out.push_str(rest);
        // Empty lines are layout, not meaning.
        out.replace("Blank(_), ", "").replace(", Blank(_)", "").replace("Blank(_)", "")
    }
}

/// A top-level item.
#[derive(Clone, Debug, PartialEq)]
pub enum Item {
    /// `scene "request" { ... }`.
    Scene(SceneBlock),
    /// `room id "label" { ... }`.
    Room(Room),
    /// `door a -- b : kind size "style"`.
    Door(Door),
    /// A comment line or block.
    Comment(Comment),
    /// An empty line kept between two statements (at most one is kept).
    Blank(Span),
    /// A line that is not a statement of its block (already reported by the parser).
    Error(ErrorNode),
}

/// A comment, kept for the formatter and the importer's raw lines.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct Comment {
    /// The comment text, with its `//` or `/* */` markers.
    pub text: String,
    /// Whether it followed a statement on the same line.
    pub trailing: bool,
    /// Where it is written.
    pub span: Span,
}

/// A line the parser could not read; its text is kept so that nothing is lost.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct ErrorNode {
    /// The raw text of the line.
    pub text: String,
    /// Where it is written.
    pub span: Span,
}

/// `scene "request" { wall height 2.7 m  seed 42 }`.
#[derive(Clone, Debug, PartialEq)]
pub struct SceneBlock {
    /// The English request, if given.
    pub request: Option<Str>,
    /// The statements of the block.
    pub body: Vec<SceneStmt>,
    /// The whole block.
    pub span: Span,
}

/// A statement of a `scene` block.
#[derive(Clone, Debug, PartialEq)]
pub enum SceneStmt {
    /// `wall height 2.7 m`.
    WallHeight(Quantity, Span),
    /// `seed 42`.
    Seed(Quantity, Span),
    /// `ceiling material "EggshellDrywall"`.
    CeilingMaterial(Str, Span),
    /// `ceiling "white plaster"`.
    CeilingDesign(Str, Span),
    /// A comment.
    Comment(Comment),
    /// An empty line kept between two statements (at most one is kept).
    Blank(Span),
    /// A line that could not be read.
    Error(ErrorNode),
}

/// `room id "label" { ... }`.
#[derive(Clone, Debug, PartialEq)]
pub struct Room {
    /// The room's identifier.
    pub id: Ident,
    /// The room's display label (the LLM's name), if given.
    pub label: Option<Str>,
    /// The statements of the block.
    pub body: Vec<RoomStmt>,
    /// The whole block.
    pub span: Span,
}

/// A statement of a `room` block.
#[derive(Clone, Debug, PartialEq)]
pub enum RoomStmt {
    /// `floor "maple hardwood"`.
    FloorDesign(Str, Span),
    /// `walls "light grey drywall"`.
    WallDesign(Str, Span),
    /// `floor material "WoodFloorsCross"`.
    FloorMaterial(Str, Span),
    /// `wall material "Walldrywall4Tiled"`.
    WallMaterial(Str, Span),
    /// `corners (0 m, 0 m) (0 m, 4 m) ...` or `corners in m (0, 0) (0, 4) ...`.
    Corners(Corners),
    /// `window west fixed 130 cm x 130 cm, count 1, sill 50 cm` (boxed: a window is three times
    /// the size of any other statement, and a room has few).
    Window(Box<Window>),
    /// `object id "category" { ... }`.
    Object(Object),
    /// `wall object id "category" { ... }`.
    WallObject(Object),
    /// `ceiling "description"` with an optional block.
    Ceiling(Ceiling),
    /// A comment.
    Comment(Comment),
    /// An empty line kept between two statements (at most one is kept).
    Blank(Span),
    /// A line that could not be read.
    Error(ErrorNode),
}

/// A room outline.
#[derive(Clone, Debug, PartialEq)]
pub struct Corners {
    /// The unit given for the whole list with `in m` / `in cm`, if any.
    pub unit: Option<(Unit, Span)>,
    /// The corners as `(x, z)` pairs.
    pub points: Vec<Point>,
    /// The whole statement.
    pub span: Span,
}

/// A point `(x, z)` of the floor plan.
#[derive(Clone, Debug, PartialEq)]
pub struct Point {
    /// East–west coordinate.
    pub x: Quantity,
    /// South–north coordinate (north = +z).
    pub z: Quantity,
    /// The parenthesized pair.
    pub span: Span,
}

/// A window line.
#[derive(Clone, Debug, PartialEq)]
pub struct Window {
    /// `north`, `south`, `east` or `west`.
    pub wall: Word,
    /// `fixed`, `hung` or `slider`.
    pub kind: Word,
    /// Width of the window.
    pub width: Quantity,
    /// Height of the window.
    pub height: Quantity,
    /// `count N`.
    pub count: Option<Quantity>,
    /// `sill 50 cm`: height of the bottom of the window above the floor.
    pub sill: Option<Quantity>,
    /// `asset "Window_Fixed_36x48"`.
    pub asset: Option<Str>,
    /// The whole statement.
    pub span: Span,
}

/// A floor object or a wall object (`wall object`), with its instances.
#[derive(Clone, Debug, PartialEq)]
pub struct Object {
    /// The group identifier; instances are `<id>-0`, `<id>-1`, ….
    pub id: Ident,
    /// The category, e.g. `"sofa"`.
    pub category: Str,
    /// The statements of the block (empty when written without a block).
    pub body: Vec<ObjectStmt>,
    /// Whether the object was written with a `{ }` block.
    pub has_block: bool,
    /// The whole declaration.
    pub span: Span,
}

/// A statement of an `object`, `wall object` or `instance` block.
#[derive(Clone, Debug, PartialEq)]
pub enum ObjectStmt {
    /// `describe "modern sectional"`.
    Describe(Str, Span),
    /// `size 200 cm x 100 cm x 80 cm` (width × depth × height).
    Size(Size3),
    /// `count 4 varied`.
    Count(Quantity, Option<Word>, Span),
    /// `asset "Sofa_1"`.
    Asset(Str, Span),
    /// A layout constraint: `edge`, `near sofa-0`, `in front of tv_stand`, ….
    Constraint(Constraint),
    /// `above sofa-0` (wall objects).
    Above(Ident, Span),
    /// `height 160 cm` (wall objects: height of the bottom above the floor).
    Height(Quantity, Span),
    /// `at 2 m, 3.5 m` (floor: centre x, z) or `at 2 m, 1.2 m, 0.3 m` (x, y, z).
    At(Vec<Quantity>, Span),
    /// `facing 90 deg`.
    Facing(Quantity, Span),
    /// `on top "book" x2 varied` with an optional block of pins.
    OnTop(OnTop),
    /// `instance chair-1 { ... }`: statements for one instance only.
    Instance(Instance),
    /// A comment.
    Comment(Comment),
    /// An empty line kept between two statements (at most one is kept).
    Blank(Span),
    /// A line that could not be read.
    Error(ErrorNode),
}

/// A size `w x d x h`.
#[derive(Clone, Debug, PartialEq)]
pub struct Size3 {
    /// Width (x at rotation 0).
    pub width: Quantity,
    /// Depth (z at rotation 0).
    pub depth: Quantity,
    /// Height.
    pub height: Quantity,
    /// The whole statement.
    pub span: Span,
}

/// A layout constraint as written.
#[derive(Clone, Debug, PartialEq)]
pub struct Constraint {
    /// The constraint's name as written (`in front of`).
    pub name: Word,
    /// The target object, for constraints that have one.
    pub target: Option<Ident>,
    /// The whole statement.
    pub span: Span,
}

/// `instance chair-1 { ... }`.
#[derive(Clone, Debug, PartialEq)]
pub struct Instance {
    /// The instance name, e.g. `chair-1`.
    pub id: Ident,
    /// Its statements.
    pub body: Vec<ObjectStmt>,
    /// The whole block.
    pub span: Span,
}

/// `on top "book" x2 varied { asset "Book_1" }`.
#[derive(Clone, Debug, PartialEq)]
pub struct OnTop {
    /// What to put there.
    pub item: Str,
    /// `xN`, default 1.
    pub count: Option<Quantity>,
    /// `same` or `varied`.
    pub variance: Option<Word>,
    /// Pins: `asset`, `at`, `facing`, comments.
    pub body: Vec<ObjectStmt>,
    /// The whole statement.
    pub span: Span,
}

/// `ceiling "description" { asset "..."  above sofa-0 }`.
#[derive(Clone, Debug, PartialEq)]
pub struct Ceiling {
    /// The description.
    pub description: Str,
    /// Optional statements: `asset`, `above`, `at`, comments.
    pub body: Vec<ObjectStmt>,
    /// The whole statement.
    pub span: Span,
}

/// `door a -- b : doorway double "style" asset "Doorway_1"`.
#[derive(Clone, Debug, PartialEq)]
pub struct Door {
    /// First side: a room id or `exterior`.
    pub from: Ident,
    /// Second side.
    pub to: Ident,
    /// `doorway`, `doorframe` or `open`.
    pub kind: Word,
    /// `single` or `double`.
    pub size: Option<Word>,
    /// The style description.
    pub style: Option<Str>,
    /// `asset "Doorway_1"`.
    pub asset: Option<Str>,
    /// The whole statement.
    pub span: Span,
}

//! The typed scene: what the checker produces and every later stage reads.
//!
//! Names are resolved to ids, every length is in metres and every angle in degrees, instances
//! are expanded (`chair-0`, `chair-1`, …) and every value keeps the span it came from.

use crate::source::Span;

/// Index of a room in [`Scene::rooms`].
#[derive(Clone, Copy, Debug, PartialEq, Eq, PartialOrd, Ord, Hash)]
pub struct RoomId(pub usize);

/// Index of an object in [`Scene::objects`].
#[derive(Clone, Copy, Debug, PartialEq, Eq, PartialOrd, Ord, Hash)]
pub struct ObjectId(pub usize);

/// The default wall height when the scene does not give one, in metres.
pub const DEFAULT_WALL_HEIGHT_M: f64 = 2.7;

/// A checked scene.
#[derive(Clone, Debug, PartialEq)]
pub struct Scene {
    /// The English request the scene came from.
    pub request: Option<String>,
    /// Height of every wall, metres.
    pub wall_height_m: f64,
    /// The seed of every random choice.
    pub seed: u64,
    /// Rooms in declaration order.
    pub rooms: Vec<Room>,
    /// Doors and open connections in declaration order.
    pub doors: Vec<Door>,
    /// Every object instance (floor and wall), rooms in order, declarations in order.
    pub objects: Vec<Object>,
    /// The material of every ceiling, pinned by name (`ceiling material "…"`).
    pub ceiling_material: Option<Pinned>,
    /// The ceiling design, a material query (`ceiling "…"` in the scene block).
    pub ceiling_design: Option<String>,
}

impl Scene {
    /// A scene with nothing in it yet, its walls `wall_height_m` high (seed 0, no request).
    pub fn empty(wall_height_m: f64) -> Scene {
        Scene {
            request: None,
            wall_height_m,
            seed: 0,
            rooms: Vec::new(),
            doors: Vec::new(),
            objects: Vec::new(),
            ceiling_material: None,
            ceiling_design: None,
        }
    }

    /// The room with this id.
    pub fn room(&self, id: RoomId) -> &Room {
        &self.rooms[id.0]
    }

    /// The object with this id.
    pub fn object(&self, id: ObjectId) -> &Object {
        &self.objects[id.0]
    }

    /// The objects of one room, floor objects first in declaration order, then wall objects.
    pub fn room_objects(&self, room: RoomId) -> impl Iterator<Item = &Object> {
        self.rooms[room.0].objects.iter().map(|id| &self.objects[id.0])
    }
}

/// A room.
#[derive(Clone, Debug, PartialEq)]
pub struct Room {
    /// Its id.
    pub id: RoomId,
    /// The identifier written in the file (`living`).
    pub name: String,
    /// The display label (`living room`); the name when no label is written.
    pub label: String,
    /// Floor design text (material query).
    pub floor_design: Option<String>,
    /// Wall design text.
    pub wall_design: Option<String>,
    /// A pinned floor material.
    pub floor_material: Option<Pinned>,
    /// A pinned wall material.
    pub wall_material: Option<Pinned>,
    /// Corners as written, metres, `(x, z)`.
    pub corners: Vec<[f64; 2]>,
    /// The span of each corner.
    pub corner_spans: Vec<Span>,
    /// The span of the unit of `corners in UNIT ...`, when the corners are written that way.
    pub corners_unit_span: Option<Span>,
    /// Windows in declaration order.
    pub windows: Vec<Window>,
    /// Object instances of the room (floor then wall objects), declaration order.
    pub objects: Vec<ObjectId>,
    /// The ceiling object, if any.
    pub ceiling: Option<Ceiling>,
    /// The room's identifier.
    pub name_span: Span,
    /// The whole declaration.
    pub decl_span: Span,
}

/// An asset or material id pinned by the user.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct Pinned {
    /// The id.
    pub id: String,
    /// Where it is written.
    pub span: Span,
}

/// A compass direction (north = +z, east = +x).
#[derive(Clone, Copy, Debug, PartialEq, Eq, PartialOrd, Ord, Hash)]
pub enum Direction {
    /// +z.
    North,
    /// −z.
    South,
    /// +x.
    East,
    /// −x.
    West,
}

impl Direction {
    /// All four, in the order north, east, south, west.
    pub const ALL: [Direction; 4] =
        [Direction::North, Direction::East, Direction::South, Direction::West];

    /// The lower-case word.
    pub fn as_str(self) -> &'static str {
        match self {
            Direction::North => "north",
            Direction::South => "south",
            Direction::East => "east",
            Direction::West => "west",
        }
    }
}

/// A window type.
#[derive(Clone, Copy, Debug, PartialEq, Eq, PartialOrd, Ord, Hash)]
pub enum WindowKind {
    /// Does not open.
    Fixed,
    /// Sash window.
    Hung,
    /// Sliding window.
    Slider,
}

impl WindowKind {
    /// The lower-case word.
    pub fn as_str(self) -> &'static str {
        match self {
            WindowKind::Fixed => "fixed",
            WindowKind::Hung => "hung",
            WindowKind::Slider => "slider",
        }
    }

    /// The sizes (width, height) in cm that the window prompt offers for this type.
    pub fn offered_sizes_cm(self) -> &'static [(f64, f64)] {
        match self {
            WindowKind::Fixed => &[
                (92.0, 120.0),
                (150.0, 92.0),
                (150.0, 120.0),
                (150.0, 180.0),
                (240.0, 120.0),
                (240.0, 180.0),
            ],
            WindowKind::Hung => &[
                (87.0, 160.0),
                (96.0, 91.0),
                (120.0, 160.0),
                (130.0, 67.0),
                (130.0, 87.0),
                (130.0, 130.0),
            ],
            WindowKind::Slider => &[
                (91.0, 92.0),
                (120.0, 61.0),
                (120.0, 91.0),
                (120.0, 120.0),
                (150.0, 92.0),
                (150.0, 120.0),
            ],
        }
    }
}

/// A window row: `count` windows of one type and size on one wall of a room.
#[derive(Clone, Debug, PartialEq)]
pub struct Window {
    /// The wall.
    pub wall: Direction,
    /// The type.
    pub kind: WindowKind,
    /// Width, metres.
    pub width_m: f64,
    /// Height, metres.
    pub height_m: f64,
    /// How many windows.
    pub count: u32,
    /// Height of the bottom above the floor, metres.
    pub sill_m: f64,
    /// A pinned window asset.
    pub asset: Option<Pinned>,
    /// The whole statement.
    pub span: Span,
}

/// How a door or connection is built.
#[derive(Clone, Copy, Debug, PartialEq, Eq, PartialOrd, Ord, Hash)]
pub enum DoorKind {
    /// A door leaf in a frame.
    Doorway,
    /// A frame without a leaf.
    Doorframe,
    /// No wall between the two rooms.
    Open,
}

impl DoorKind {
    /// The lower-case word.
    pub fn as_str(self) -> &'static str {
        match self {
            DoorKind::Doorway => "doorway",
            DoorKind::Doorframe => "doorframe",
            DoorKind::Open => "open",
        }
    }
}

/// Door width class.
#[derive(Clone, Copy, Debug, PartialEq, Eq, PartialOrd, Ord, Hash)]
pub enum DoorSize {
    /// About 1 m wide.
    Single,
    /// About 2 m wide.
    Double,
}

impl DoorSize {
    /// The lower-case word.
    pub fn as_str(self) -> &'static str {
        match self {
            DoorSize::Single => "single",
            DoorSize::Double => "double",
        }
    }
}

/// One side of a door.
#[derive(Clone, Copy, Debug, PartialEq, Eq, PartialOrd, Ord, Hash)]
pub enum DoorSide {
    /// Outside the house.
    Exterior,
    /// A room.
    Room(RoomId),
}

/// A door or an open connection.
#[derive(Clone, Debug, PartialEq)]
pub struct Door {
    /// Index among the scene's doors.
    pub index: usize,
    /// First side as written.
    pub from: DoorSide,
    /// Second side as written.
    pub to: DoorSide,
    /// Doorway, doorframe or open.
    pub kind: DoorKind,
    /// Single or double (`None` for open connections).
    pub size: Option<DoorSize>,
    /// Style description.
    pub style: Option<String>,
    /// Pinned door asset.
    pub asset: Option<Pinned>,
    /// Spans of the two sides.
    pub side_spans: [Span; 2],
    /// The whole statement.
    pub span: Span,
}

/// Whether copies of an object share one asset.
#[derive(Clone, Copy, Debug, PartialEq, Eq, PartialOrd, Ord, Hash)]
pub enum Variance {
    /// Every copy uses the same asset.
    Same,
    /// Copies use different assets where the catalog has them.
    Varied,
}

impl Variance {
    /// The lower-case word.
    pub fn as_str(self) -> &'static str {
        match self {
            Variance::Same => "same",
            Variance::Varied => "varied",
        }
    }
}

/// Where an object goes.
#[derive(Clone, Debug, PartialEq)]
pub enum Placement {
    /// On the floor, with layout constraints.
    Floor {
        /// `edge` or `middle`; `None` when neither is written (the solver treats it as edge).
        global: Option<GlobalConstraint>,
        /// Every other constraint, in the order written (instance block after group block).
        constraints: Vec<Constraint>,
    },
    /// On a wall.
    Wall {
        /// The floor object it hangs above.
        above: Option<(ObjectId, Span)>,
        /// Height of its bottom above the floor, metres (`None`: the solver decides).
        height_m: Option<f64>,
    },
}

/// The global constraint of a floor object.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct GlobalConstraint {
    /// Edge or middle.
    pub kind: GlobalKind,
    /// Where it is written.
    pub span: Span,
}

/// `edge` or `middle`.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum GlobalKind {
    /// Against a wall.
    Edge,
    /// Away from the walls.
    Middle,
}

/// A relation between two floor objects of one room.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Constraint {
    /// Which relation.
    pub kind: RelationKind,
    /// The object it relates to (always declared earlier in the room).
    pub target: ObjectId,
    /// The whole constraint.
    pub span: Span,
    /// The target's name where it is written.
    pub target_span: Span,
}

/// The relations of the paper and the original code.
#[derive(Clone, Copy, Debug, PartialEq, Eq, PartialOrd, Ord, Hash)]
pub enum RelationKind {
    /// Close to the target.
    Near,
    /// Far from the target.
    Far,
    /// In front of the target, from the target's point of view.
    InFrontOf,
    /// Behind the target.
    Behind,
    /// Beside the target, left or right.
    SideOf,
    /// To the target's left.
    LeftOf,
    /// To the target's right.
    RightOf,
    /// Around the target (near it and facing it), e.g. chairs around a table.
    Around,
    /// Centres aligned on x or z.
    CenterAligned,
    /// Facing the target.
    FaceTo,
    /// Facing the same way as the target.
    FaceSameAs,
}

impl RelationKind {
    /// Every relation, in vocabulary order.
    pub const ALL: [RelationKind; 11] = [
        RelationKind::Near,
        RelationKind::Far,
        RelationKind::InFrontOf,
        RelationKind::Behind,
        RelationKind::SideOf,
        RelationKind::LeftOf,
        RelationKind::RightOf,
        RelationKind::Around,
        RelationKind::CenterAligned,
        RelationKind::FaceTo,
        RelationKind::FaceSameAs,
    ];

    /// The canonical words.
    pub fn as_str(self) -> &'static str {
        match self {
            RelationKind::Near => "near",
            RelationKind::Far => "far",
            RelationKind::InFrontOf => "in front of",
            RelationKind::Behind => "behind",
            RelationKind::SideOf => "side of",
            RelationKind::LeftOf => "left of",
            RelationKind::RightOf => "right of",
            RelationKind::Around => "around",
            RelationKind::CenterAligned => "center aligned",
            RelationKind::FaceTo => "face to",
            RelationKind::FaceSameAs => "face same as",
        }
    }

    /// Parses the canonical words.
    pub fn from_words(words: &str) -> Option<RelationKind> {
        RelationKind::ALL.into_iter().find(|k| k.as_str() == words)
    }
}

/// A small object to put on top of a receptacle.
#[derive(Clone, Debug, PartialEq)]
pub struct SmallItem {
    /// What it is (`book`).
    pub item: String,
    /// How many.
    pub count: u32,
    /// Same or varied assets.
    pub variance: Variance,
    /// A pinned asset.
    pub asset: Option<Pinned>,
    /// A pinned world position `(x, y, z)` in metres (from `--keep-layout` imports).
    pub at: Option<[f64; 3]>,
    /// A pinned rotation about y, degrees.
    pub facing_deg: Option<f64>,
    /// The whole statement.
    pub span: Span,
}

/// One object instance.
#[derive(Clone, Debug, PartialEq)]
pub struct Object {
    /// Its id.
    pub id: ObjectId,
    /// The room it belongs to.
    pub room: RoomId,
    /// The instance name, e.g. `chair-1`.
    pub name: String,
    /// The group identifier, e.g. `chair`.
    pub group: String,
    /// Index within the group.
    pub index: u32,
    /// Number of instances in the group.
    pub group_count: u32,
    /// Category words, e.g. `dining chair`.
    pub category: String,
    /// Description for asset resolution.
    pub description: Option<String>,
    /// Desired size (width, depth, height) in metres.
    pub size_m: Option<[f64; 3]>,
    /// Same or varied among the group.
    pub variance: Variance,
    /// A pinned asset.
    pub asset: Option<Pinned>,
    /// A pinned position: `(x, z)` floor centre for floor objects; for wall objects `(x, z)` of
    /// the centre of the back as well.
    pub at: Option<[f64; 2]>,
    /// A pinned rotation about y, degrees (0 faces +z).
    pub facing_deg: Option<f64>,
    /// Floor or wall placement with its constraints.
    pub placement: Placement,
    /// Small objects on top.
    pub on_top: Vec<SmallItem>,
    /// The group's identifier where it is declared.
    pub name_span: Span,
    /// The whole group declaration.
    pub decl_span: Span,
}

impl Object {
    /// Whether the object stands on the floor.
    pub fn is_floor(&self) -> bool {
        matches!(self.placement, Placement::Floor { .. })
    }
}

/// A ceiling object.
#[derive(Clone, Debug, PartialEq)]
pub struct Ceiling {
    /// The description.
    pub description: String,
    /// A pinned asset.
    pub asset: Option<Pinned>,
    /// The floor object it hangs over (else the room's centre).
    pub above: Option<(ObjectId, Span)>,
    /// A pinned `(x, z)` position.
    pub at: Option<[f64; 2]>,
    /// The whole statement.
    pub span: Span,
}

//! The `plan` stage: a checked [`Scene`] becomes a [`FloorPlan`].
//!
//! Rooms are rectilinear polygons (any number of corners, either winding); the stage snaps
//! corners that nearly meet, checks the plan (overlap, containment, isolated rooms,
//! connectivity, outline shape, size), splits every room side where a neighbour's corner lands
//! on it, makes one [`Wall`] per piece (with an exterior copy on the outer boundary), places
//! doors, open connections and windows, picks materials, layers, the skybox and the agent's
//! start pose. Every random choice comes from the scene seed.
//!
//! What the solver reads (all in metres, floor plane `(x, z)`, north = +z):
//! - [`PlanRoom::polygon`]: the room outline, clockwise (x right, z up), starting at the
//!   minimal-x corner, split at neighbours' corners;
//! - [`PlanRoom::door_keep_out`]: a 1.0 m deep rectangle on the room side of each door;
//! - [`PlanRoom::open_boxes`]: 0.5 m deep rectangles on the room side of each open connection;
//! - [`PlanRoom::window_segments`]: the wall segments covered by windows (for wall objects);
//! - [`FloorPlan::walls`] with [`Wall::room`], [`Wall::start`], [`Wall::end`],
//!   [`Wall::direction`] (the side of the room it bounds) and [`Wall::hole`] (where along the
//!   wall a door or window is, from its start).
//!
//! The tolerances and limits are the constants of this module, documented in the book chapter
//! `design/floor-plan.md`.

mod build;
mod dump;
mod errors;
mod grid;
pub mod repair;

use crate::check::scene::{Direction, DoorKind, RoomId, Scene};
use crate::diag::Outcome;
use crate::geometry::Point;
use crate::resolve::structure::StructureCatalog;
use crate::source::Span;

/// Corners of different rooms closer than this on one axis (but not equal) are snapped together,
/// with a warning, metres.
pub const SNAP_M: f64 = 0.05;
/// The narrowest a room may be, metres.
pub const MIN_ROOM_SIDE_M: f64 = 1.0;
/// The widest a room may be, metres.
pub const MAX_ROOM_SIDE_M: f64 = 50.0;
/// The least distance between a door's hole and either end of its wall, metres.
pub const DOOR_CORNER_MARGIN_M: f64 = 0.15;
/// The least distance between a window's hole and either end of its wall piece, metres.
pub const WINDOW_MARGIN_M: f64 = 0.1;
/// The least wall left above a window, metres.
pub const WINDOW_TOP_MARGIN_M: f64 = 0.05;
/// Depth of a door's keep-out rectangle into each room, metres.
pub const DOOR_BOX_DEPTH_M: f64 = 1.0;
/// Depth of an open connection's keep-out rectangle into each room, metres.
pub const OPEN_BOX_DEPTH_M: f64 = 0.5;
/// Depth of a window's keep-out rectangle (for wall objects), metres.
pub const WINDOW_BOX_DEPTH_M: f64 = 0.1;
/// The number of lighting layers (`Procedural0` … `Procedural3`).
pub const N_LAYERS: u8 = 4;

/// Options of the plan stage.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct PlanOptions {
    /// Add a doorway for every room that cannot be reached from outside (and one to the outside
    /// when the house has none) instead of reporting an error.
    pub add_doors: bool,
    /// Plan the geometry only (outlines, walls, doors, windows, reachability): no materials
    /// are chosen and none is reported. Geometric repair checks its candidates this way.
    pub geometry_only: bool,
}

/// The planned house structure.
#[derive(Clone, Debug, PartialEq)]
pub struct FloorPlan {
    /// The seed of the scene.
    pub seed: u64,
    /// Height of every wall, metres.
    pub wall_height_m: f64,
    /// One entry per scene room, same order.
    pub rooms: Vec<PlanRoom>,
    /// Interior walls, rooms in order, clockwise within a room; each wall with
    /// [`Wall::exterior`] also has an exterior copy (`<id>|exterior`) in the house.
    pub walls: Vec<Wall>,
    /// Doors (not open connections), in scene order, then doors added by `--add-doors`.
    pub doors: Vec<PlacedDoor>,
    /// Windows, rooms in order, rows in order.
    pub windows: Vec<PlacedWindow>,
    /// Open connections, in scene order.
    pub open_connections: Vec<OpenConnection>,
    /// The skybox id.
    pub skybox: String,
    /// The skybox's time of day (`Midday`, `GoldenHour`, `BlueHour`).
    pub time_of_day: String,
    /// The ceiling material (the first room's wall material).
    pub ceiling_material: String,
    /// Where the agent starts.
    pub agent: AgentPose,
}

/// A room of the plan.
#[derive(Clone, Debug, PartialEq)]
pub struct PlanRoom {
    /// The scene room.
    pub id: RoomId,
    /// Its id in the house JSON: the label (`living room`), or `<label>-<n>` when two rooms
    /// share a label.
    pub thor_id: String,
    /// The room's own corners, clockwise from the minimal-x corner, after snapping.
    pub corners: Vec<Point>,
    /// The outline split at neighbours' corners, clockwise from the minimal-x corner.
    pub polygon: Vec<Point>,
    /// Area, square metres.
    pub area_m2: f64,
    /// Area centroid.
    pub centroid: Point,
    /// Floor material name.
    pub floor_material: String,
    /// Wall material name.
    pub wall_material: String,
    /// The colour the floor material is tinted with, when its design asks one.
    pub floor_tint: Option<crate::resolve::colors::Color>,
    /// The colour the wall material is tinted with, when its design asks one.
    pub wall_tint: Option<crate::resolve::colors::Color>,
    /// Lighting layer, 0 … 3.
    pub layer: u8,
    /// Keep-out rectangles of the doors, 1.0 m deep into this room.
    pub door_keep_out: Vec<Vec<Point>>,
    /// Keep-out rectangles of open connections, 0.5 m deep into this room.
    pub open_boxes: Vec<Vec<Point>>,
    /// Wall segments covered by this room's windows.
    pub window_segments: Vec<(Point, Point)>,
    /// The room's name span in the source.
    pub name_span: Span,
}

/// What a hole in a wall is for.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum HoleKind {
    /// A door or doorframe.
    Door,
    /// A window.
    Window,
}

/// A hole in a wall, measured along the wall from its start, metres.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Hole {
    /// Door or window.
    pub kind: HoleKind,
    /// Distance from the wall's start to the hole's near side.
    pub start_m: f64,
    /// Distance from the wall's start to the hole's far side.
    pub end_m: f64,
    /// Bottom of the hole above the floor.
    pub bottom_m: f64,
    /// Top of the hole above the floor.
    pub top_m: f64,
}

/// One interior wall: a piece of one room's outline, running clockwise around the room (the
/// room lies on the right of `start → end`).
#[derive(Clone, Debug, PartialEq)]
pub struct Wall {
    /// `wall|<room>|<direction>|<index>` (plus `|<k>` for window sub-walls).
    pub id: String,
    /// The room it bounds.
    pub room: RoomId,
    /// The side of the room it is on.
    pub direction: Direction,
    /// Start point.
    pub start: Point,
    /// End point.
    pub end: Point,
    /// Length, metres.
    pub width_m: f64,
    /// The room on the other side and that room's wall id, for shared walls.
    pub neighbour: Option<(RoomId, String)>,
    /// Whether the wall is on the outer boundary (it then has an exterior copy).
    pub exterior: bool,
    /// Whether the wall is left out because of an open connection (`empty: true`).
    pub empty: bool,
    /// The door or window hole in it.
    pub hole: Option<Hole>,
}

impl Wall {
    /// The id of the wall's exterior copy.
    pub fn exterior_id(&self) -> String {
        format!("{}|exterior", self.id)
    }
}

/// A placed door or doorframe.
#[derive(Clone, Debug, PartialEq)]
pub struct PlacedDoor {
    /// `door|<n>|<room0>|<room1>`.
    pub id: String,
    /// Doorway or doorframe.
    pub kind: DoorKind,
    /// The asset id.
    pub asset_id: String,
    /// First side: a room's house id or `exterior`.
    pub room0: String,
    /// Second side.
    pub room1: String,
    /// Whether it leads outside (then `room0` and `room1` both name its room, as in ProcTHOR).
    pub exterior: bool,
    /// The wall on the first side (the exterior copy when that side is `exterior`).
    pub wall0: String,
    /// The wall on the second side.
    pub wall1: String,
    /// Hole minimum corner `(along wall0, height)`.
    pub hole_min: [f64; 2],
    /// Hole maximum corner.
    pub hole_max: [f64; 2],
    /// Asset centre `(along wall0, height)`.
    pub asset_position: [f64; 2],
    /// The door's opening in the world, in `wall0`'s direction.
    pub segment: (Point, Point),
    /// Whether the leaf can open (interior doorways).
    pub openable: bool,
    /// How far it is open (0 or 1).
    pub openness: f64,
    /// The statement it comes from (`None` for doors added by `--add-doors`).
    pub span: Option<Span>,
}

/// A placed window.
#[derive(Clone, Debug, PartialEq)]
pub struct PlacedWindow {
    /// `window|<wall0>|<k>`.
    pub id: String,
    /// The asset id.
    pub asset_id: String,
    /// The room.
    pub room: RoomId,
    /// The interior (sub-)wall.
    pub wall0: String,
    /// Its exterior copy.
    pub wall1: String,
    /// Hole minimum corner `(along wall0, height)`.
    pub hole_min: [f64; 2],
    /// Hole maximum corner.
    pub hole_max: [f64; 2],
    /// Asset centre `(along wall0, height)`.
    pub asset_position: [f64; 2],
    /// The window in the world.
    pub segment: (Point, Point),
    /// The window row it comes from.
    pub span: Span,
}

/// An open connection: the shared walls stay in the house, marked empty.
#[derive(Clone, Debug, PartialEq)]
pub struct OpenConnection {
    /// The two rooms.
    pub rooms: (RoomId, RoomId),
    /// The shared wall segments (in the first room's wall direction).
    pub segments: Vec<(Point, Point)>,
    /// The statement.
    pub span: Span,
}

/// The agent's start pose.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct AgentPose {
    /// The room it starts in.
    pub room: RoomId,
    /// Floor position `(x, z)`.
    pub position: Point,
    /// Rotation about y, degrees.
    pub rotation_deg: f64,
}

/// Plans the scene with the default options.
pub fn plan(scene: &Scene, catalog: &StructureCatalog) -> Outcome<FloorPlan> {
    plan_with(scene, catalog, PlanOptions::default())
}

/// Plans the scene.
pub fn plan_with(
    scene: &Scene,
    catalog: &StructureCatalog,
    options: PlanOptions,
) -> Outcome<FloorPlan> {
    build::run(scene, catalog, options)
}

impl FloorPlan {
    /// The human-readable dump that `holoc build --emit plan` prints and the snapshots use.
    pub fn dump(&self, scene: &Scene) -> String {
        dump::dump(self, scene)
    }

    /// The plan room of a scene room.
    pub fn room(&self, id: RoomId) -> &PlanRoom {
        &self.rooms[id.0]
    }

    /// The walls of one room.
    pub fn room_walls(&self, id: RoomId) -> impl Iterator<Item = &Wall> {
        self.walls.iter().filter(move |w| w.room == id)
    }

    /// The layer name of a room, `Procedural<n>`.
    pub fn layer_name(&self, id: RoomId) -> String {
        format!("Procedural{}", self.rooms[id.0].layer)
    }
}

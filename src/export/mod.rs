//! The 3D export: an AI2-THOR house as glTF 2.0 binary (`.glb`), written with `gltf-json`
//! (through the `gltf` crate's re-export), and the self-contained viewer page (`viewer.rs`).
//!
//! Coordinates are AI2-THOR's own numbers: metres, `y` up, the house's `x` and `z`. (glTF is
//! right-handed and Unity left-handed, so a glTF viewer shows the house mirrored north–south;
//! the viewer page mirrors it back, see the book's chapter.) The scene has one node per room,
//! wall, door, window and object (items on top included), named by its id, with `extras`
//! `{kind, assetId, objectType, roomId, …}`; in that order, all at the scene's root:
//! - a room's mesh is its floor polygon (triangulated with earcut) and, unless left out, its
//!   ceiling at the height of its walls, facing down;
//! - a wall is a slab 2 cm thick on its room's side of the wall line (an exterior copy on the
//!   outer side) with the holes of its doors and windows cut out; a wall of an open connection
//!   (`empty`) has no mesh;
//! - a door is a frame around its hole and, for doors that have one, a leaf turned by its
//!   openness; a window is a frame and a glass pane;
//! - an object is its asset's bounding box (from the object catalog): the node's translation is
//!   the house's position (the box's centre), its rotation the house's Euler angles (Unity's
//!   order: z, then x, then y) and its scale the box's size, over a shared unit cube.
//!
//! Colours come from `materials.rs`. Nothing here reads the clock or iterates a hash map, so the
//! same house gives the same bytes.

pub mod defaults;
pub mod materials;
pub mod mesh;
pub mod viewer;

use std::collections::{BTreeMap, BTreeSet};

use gltf::json;
use json::validation::{Checked::Valid, USize64};
use nalgebra::{Isometry3, Translation3, UnitQuaternion, Vector3};

use crate::check::scene::DoorKind;
use crate::geometry::{self as geo, Point};
use crate::lower::thor::{House, Object, Wall};
use crate::resolve::structure::StructureCatalog;
use crate::resolve::Catalog;
use materials::Pbr;
use mesh::{Geometry, Hole};

/// Half the thickness of a wall between two rooms: each room's wall is a slab this thick on
/// its own side of the wall line (metres).
pub const WALL_SLAB_M: f64 = 0.02;
/// The width of door and window frames (metres).
const FRAME_M: f64 = 0.05;
/// How far frames stand out of the wall on each side (metres).
const FRAME_PROUD_M: f64 = 0.01;
/// The thickness of a door leaf (metres).
const LEAF_M: f64 = 0.04;
/// The thickness of a window pane (metres).
const PANE_M: f64 = 0.01;

/// How objects are drawn.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, clap::ValueEnum)]
pub enum ObjectMode {
    /// Each object as its asset's bounding box.
    #[default]
    Boxes,
    /// No object nodes at all (the empty house).
    None,
}

/// What to export.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct ExportOptions {
    /// Whether rooms get their ceiling.
    pub ceiling: bool,
    /// Only these rooms (and their walls, windows, objects and the doors that touch them);
    /// `None`: every room.
    pub rooms: Option<BTreeSet<String>>,
    /// How objects are drawn.
    pub objects: ObjectMode,
    /// The meshes of the assets holoc made, drawn with their parts instead of boxes.
    pub made: std::sync::Arc<MadeMeshes>,
}

impl Default for ExportOptions {
    fn default() -> Self {
        ExportOptions {
            ceiling: true,
            rooms: None,
            objects: ObjectMode::Boxes,
            made: std::sync::Arc::default(),
        }
    }
}

/// The meshes of made assets (`crate::make`) by uid: each a list of parts, one per colour,
/// in the asset's own frame (centred on its box, front to `+z`).
#[derive(Clone, Debug, Default)]
pub struct MadeMeshes {
    by_uid: BTreeMap<String, Vec<(Geometry, Pbr)>>,
}

impl PartialEq for MadeMeshes {
    fn eq(&self, other: &Self) -> bool {
        self.by_uid.keys().eq(other.by_uid.keys())
    }
}

impl Eq for MadeMeshes {}

impl MadeMeshes {
    /// The meshes of a build's made assets.
    pub fn of_made(made: &[std::sync::Arc<crate::make::MadeAsset>]) -> MadeMeshes {
        let mut by_uid = BTreeMap::new();
        for m in made {
            let mut parts: Vec<(Geometry, Pbr)> = m
                .palette
                .iter()
                .map(|s| {
                    let glass = matches!(s.material, crate::make::finish::Material::Glass);
                    (Geometry::default(), materials::made(s.rgb, s.roughness, s.metallic, glass))
                })
                .collect();
            let swatch_of: Vec<usize> = m.parts.iter().map(|(_, s)| *s).collect();
            let mesh = &m.mesh;
            for (t, tri) in mesh.triangles.chunks_exact(3).enumerate() {
                let s = mesh.part_of.get(t).and_then(|p| swatch_of.get(*p)).copied().unwrap_or(0);
                if let Some((g, _)) = parts.get_mut(s) {
                    g.push_triangle(
                        tri.iter().map(|&i| (mesh.vertices[i as usize], mesh.normals[i as usize])),
                    );
                }
            }
            parts.retain(|(g, _)| !g.is_empty());
            by_uid.insert(m.uid.clone(), parts);
        }
        MadeMeshes { by_uid }
    }

    /// The meshes of the made assets among `ids` read from their folders in `dir`
    /// (`make::runtime::read_asset`), one part per colour of the albedo texture; an asset
    /// whose folder cannot be read is left out (it is drawn as its catalog box, if any).
    pub fn read<'a>(dir: &std::path::Path, ids: impl IntoIterator<Item = &'a str>) -> MadeMeshes {
        let mut by_uid = BTreeMap::new();
        for id in ids.into_iter().filter(|id| crate::make::is_made_id(id)) {
            if by_uid.contains_key(id) {
                continue;
            }
            let Ok(read) = crate::make::runtime::read_asset(dir, id) else { continue };
            by_uid.insert(id.to_string(), Self::parts_of(&read));
        }
        MadeMeshes { by_uid }
    }

    /// The meshes of made assets already read from their folders (`make::read_folder_assets`).
    pub fn of_read(reads: &[(String, crate::make::runtime::ReadAsset)]) -> MadeMeshes {
        let by_uid = reads.iter().map(|(uid, read)| (uid.clone(), Self::parts_of(read))).collect();
        MadeMeshes { by_uid }
    }

    /// One part per colour of a read asset's albedo texture.
    fn parts_of(read: &crate::make::runtime::ReadAsset) -> Vec<(Geometry, Pbr)> {
        let mut colours: BTreeMap<[u8; 3], Geometry> = BTreeMap::new();
        for (t, tri) in read.triangles.chunks_exact(3).enumerate() {
            let rgb = read.triangle_rgb.get(t).copied().unwrap_or([0.6; 3]);
            let key = rgb.map(|c| (c * 255.0).round() as u8);
            let [a, b, c] = [tri[0], tri[1], tri[2]].map(|i| read.vertices[i as usize]);
            let n = face_normal(a, b, c);
            colours.entry(key).or_default().push_triangle([(a, n), (b, n), (c, n)].into_iter());
        }
        colours
            .into_iter()
            .map(|(k, g)| (g, materials::made(k.map(|c| f64::from(c) / 255.0), 0.6, 0.0, false)))
            .collect()
    }

    /// Whether it holds no mesh.
    pub fn is_empty(&self) -> bool {
        self.by_uid.is_empty()
    }

    /// The uids it has meshes of.
    pub fn uids(&self) -> impl Iterator<Item = &str> {
        self.by_uid.keys().map(String::as_str)
    }
}

fn face_normal(a: [f64; 3], b: [f64; 3], c: [f64; 3]) -> [f64; 3] {
    let u = [b[0] - a[0], b[1] - a[1], b[2] - a[2]];
    let v = [c[0] - a[0], c[1] - a[1], c[2] - a[2]];
    let n = [u[1] * v[2] - u[2] * v[1], u[2] * v[0] - u[0] * v[2], u[0] * v[1] - u[1] * v[0]];
    let l = (n[0] * n[0] + n[1] * n[1] + n[2] * n[2]).sqrt();
    if l < 1e-12 {
        [0.0, 1.0, 0.0]
    } else {
        n.map(|x| x / l)
    }
}

/// How many nodes of each kind an export holds.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct Counts {
    /// Rooms.
    pub rooms: usize,
    /// Walls (exterior copies included).
    pub walls: usize,
    /// Doors.
    pub doors: usize,
    /// Windows.
    pub windows: usize,
    /// Objects, items on top included.
    pub objects: usize,
}

impl Counts {
    /// All nodes.
    pub fn nodes(&self) -> usize {
        self.rooms + self.walls + self.doors + self.windows + self.objects
    }
}

impl std::fmt::Display for Counts {
    /// `4 rooms, 28 walls, 3 doors, 4 windows, 21 objects`.
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        let n = |count: usize, what: &str| {
            format!("{count} {what}{}", if count == 1 { "" } else { "s" })
        };
        write!(
            f,
            "{}, {}, {}, {}, {}",
            n(self.rooms, "room"),
            n(self.walls, "wall"),
            n(self.doors, "door"),
            n(self.windows, "window"),
            n(self.objects, "object")
        )
    }
}

/// An exported house: the glTF document and its binary buffer.
#[derive(Clone, Debug)]
pub struct Export {
    /// The glTF JSON.
    pub root: json::Root,
    /// The binary chunk.
    pub bin: Vec<u8>,
    /// Its nodes by kind.
    pub counts: Counts,
}

impl Export {
    /// The `.glb` file.
    pub fn to_glb(&self) -> Vec<u8> {
        let json = self.json_compact();
        let glb = gltf::binary::Glb {
            header: gltf::binary::Header {
                magic: *b"glTF",
                version: 2,
                // Written by `to_vec`.
                length: 0,
            },
            json: std::borrow::Cow::Owned(json.into_bytes()),
            bin: Some(std::borrow::Cow::Borrowed(&self.bin)),
        };
        glb.to_vec().unwrap_or_default()
    }

    /// The JSON chunk, compact.
    pub fn json_compact(&self) -> String {
        json::serialize::to_string(&self.root).unwrap_or_default()
    }

    /// The JSON chunk, indented (for people and snapshots).
    pub fn json_pretty(&self) -> String {
        json::serialize::to_string_pretty(&self.root).unwrap_or_default()
    }
}

/// Why a house cannot be exported.
#[derive(Clone, Debug, PartialEq, Eq)]
pub enum ExportError {
    /// `--rooms` names rooms the house does not have (with the house's room ids).
    UnknownRooms {
        /// The names not found.
        unknown: Vec<String>,
        /// The house's rooms.
        known: Vec<String>,
    },
}

/// A wall's frame: where it starts, its direction along the floor and its size.
#[derive(Clone, Copy, Debug)]
struct WallFrame {
    start: Point,
    dir: Point,
    length: f64,
    height: f64,
}

impl WallFrame {
    fn of(wall: &Wall) -> Option<WallFrame> {
        let first = wall.polygon.first()?;
        let last = wall.polygon.last()?;
        let start = [first.x, first.z];
        let end = [last.x, last.z];
        let length = geo::distance(start, end);
        if length < 1e-6 {
            return None;
        }
        let height = wall.polygon.iter().map(|p| p.y).fold(0.0, f64::max);
        Some(WallFrame { start, dir: geo::unit(start, end), length, height })
    }

    /// The rotation that turns the frame's `x` along the wall (`z` is then `x × y`).
    fn rotation(&self) -> UnitQuaternion<f64> {
        UnitQuaternion::from_axis_angle(&Vector3::y_axis(), (-self.dir[1]).atan2(self.dir[0]))
    }

    /// The frame's `z` axis on the floor.
    fn normal(&self) -> Point {
        [-self.dir[1], self.dir[0]]
    }

    /// The pose of the point `along` the wall at height `y`.
    fn pose(&self, along: f64, y: f64) -> Isometry3<f64> {
        let p = geo::add_scaled(self.start, self.dir, along);
        Isometry3::from_parts(Translation3::new(p[0], y, p[1]), self.rotation())
    }

    /// Where the point `p` of the floor lies along the wall.
    fn along(&self, p: Point) -> f64 {
        let d = geo::sub(p, self.start);
        d[0] * self.dir[0] + d[1] * self.dir[1]
    }
}

/// The glTF document under construction.
#[derive(Default)]
struct Builder {
    root: json::Root,
    bin: Vec<u8>,
    materials: BTreeMap<String, json::Index<json::Material>>,
    /// The unit cube's accessors (positions, normals, indices), made once.
    cube: Option<[json::Index<json::Accessor>; 3]>,
    /// One unit-cube mesh per material.
    cube_meshes: BTreeMap<String, json::Index<json::Mesh>>,
}

impl Builder {
    fn view(
        &mut self,
        bytes: &[u8],
        target: json::buffer::Target,
    ) -> json::Index<json::buffer::View> {
        while self.bin.len() % 4 != 0 {
            self.bin.push(0);
        }
        let offset = self.bin.len();
        self.bin.extend_from_slice(bytes);
        self.root.push(json::buffer::View {
            buffer: json::Index::new(0),
            byte_length: USize64::from(bytes.len()),
            byte_offset: Some(USize64::from(offset)),
            byte_stride: None,
            name: None,
            target: Some(Valid(target)),
            extensions: None,
            extras: None,
        })
    }

    fn vec3_accessor(&mut self, values: &[[f32; 3]], bounds: bool) -> json::Index<json::Accessor> {
        let bytes: Vec<u8> = values.iter().flatten().flat_map(|v| v.to_le_bytes()).collect();
        let view = self.view(&bytes, json::buffer::Target::ArrayBuffer);
        let (min, max) = if bounds {
            let g = Geometry { positions: values.to_vec(), ..Geometry::default() };
            match g.bounds() {
                Some((lo, hi)) => {
                    (Some(json::Value::from(lo.to_vec())), Some(json::Value::from(hi.to_vec())))
                }
                None => (None, None),
            }
        } else {
            (None, None)
        };
        self.root.push(json::Accessor {
            buffer_view: Some(view),
            byte_offset: None,
            count: USize64::from(values.len()),
            component_type: Valid(json::accessor::GenericComponentType(
                json::accessor::ComponentType::F32,
            )),
            extensions: None,
            extras: None,
            type_: Valid(json::accessor::Type::Vec3),
            min,
            max,
            name: None,
            normalized: false,
            sparse: None,
        })
    }

    fn index_accessor(&mut self, indices: &[u32]) -> json::Index<json::Accessor> {
        let bytes: Vec<u8> = indices.iter().flat_map(|v| v.to_le_bytes()).collect();
        let view = self.view(&bytes, json::buffer::Target::ElementArrayBuffer);
        self.root.push(json::Accessor {
            buffer_view: Some(view),
            byte_offset: None,
            count: USize64::from(indices.len()),
            component_type: Valid(json::accessor::GenericComponentType(
                json::accessor::ComponentType::U32,
            )),
            extensions: None,
            extras: None,
            type_: Valid(json::accessor::Type::Scalar),
            min: None,
            max: None,
            name: None,
            normalized: false,
            sparse: None,
        })
    }

    fn material(&mut self, pbr: &Pbr) -> json::Index<json::Material> {
        if let Some(&i) = self.materials.get(&pbr.name) {
            return i;
        }
        let i = self.root.push(json::Material {
            alpha_mode: Valid(if pbr.glass {
                json::material::AlphaMode::Blend
            } else {
                json::material::AlphaMode::Opaque
            }),
            double_sided: pbr.glass,
            name: Some(pbr.name.clone()),
            pbr_metallic_roughness: json::material::PbrMetallicRoughness {
                base_color_factor: json::material::PbrBaseColorFactor(pbr.base_color),
                metallic_factor: json::material::StrengthFactor(pbr.metalness),
                roughness_factor: json::material::StrengthFactor(pbr.roughness),
                ..Default::default()
            },
            ..Default::default()
        });
        self.materials.insert(pbr.name.clone(), i);
        i
    }

    fn primitive(
        &mut self,
        geometry: &Geometry,
        material: json::Index<json::Material>,
    ) -> json::mesh::Primitive {
        let positions = self.vec3_accessor(&geometry.positions, true);
        let normals = self.vec3_accessor(&geometry.normals, false);
        let indices = self.index_accessor(&geometry.indices);
        primitive_of([positions, normals, indices], material)
    }

    /// A mesh of the non-empty parts, or `None` when every part is empty.
    fn mesh(&mut self, name: &str, parts: &[(&Geometry, Pbr)]) -> Option<json::Index<json::Mesh>> {
        let mut primitives = Vec::new();
        for (g, pbr) in parts {
            if g.is_empty() {
                continue;
            }
            let m = self.material(pbr);
            primitives.push(self.primitive(g, m));
        }
        if primitives.is_empty() {
            return None;
        }
        Some(self.root.push(json::Mesh {
            extensions: None,
            extras: None,
            name: Some(name.to_string()),
            primitives,
            weights: None,
        }))
    }

    /// The unit cube (centred, size 1) in `pbr`, one mesh per material over shared accessors.
    fn cube_mesh(&mut self, pbr: &Pbr) -> json::Index<json::Mesh> {
        if let Some(&i) = self.cube_meshes.get(&pbr.name) {
            return i;
        }
        let accessors = match self.cube {
            Some(a) => a,
            None => {
                let mut g = Geometry::default();
                g.add_box([-0.5; 3], [0.5; 3], &Isometry3::identity());
                let a = [
                    self.vec3_accessor(&g.positions, true),
                    self.vec3_accessor(&g.normals, false),
                    self.index_accessor(&g.indices),
                ];
                self.cube = Some(a);
                a
            }
        };
        let material = self.material(pbr);
        let i = self.root.push(json::Mesh {
            extensions: None,
            extras: None,
            name: Some(format!("box {}", pbr.name)),
            primitives: vec![primitive_of(accessors, material)],
            weights: None,
        });
        self.cube_meshes.insert(pbr.name.clone(), i);
        i
    }

    fn node(&mut self, node: json::Node) -> json::Index<json::Node> {
        self.root.push(node)
    }
}

fn primitive_of(
    [positions, normals, indices]: [json::Index<json::Accessor>; 3],
    material: json::Index<json::Material>,
) -> json::mesh::Primitive {
    let mut attributes = BTreeMap::new();
    attributes.insert(Valid(json::mesh::Semantic::Positions), positions);
    attributes.insert(Valid(json::mesh::Semantic::Normals), normals);
    json::mesh::Primitive {
        attributes,
        extensions: None,
        extras: None,
        indices: Some(indices),
        material: Some(material),
        mode: Valid(json::mesh::Mode::Triangles),
        targets: None,
    }
}

/// `extras` as glTF holds them: raw JSON.
fn extras(value: &serde_json::Value) -> json::Extras {
    serde_json::value::RawValue::from_string(value.to_string()).ok()
}

fn f32x3(v: [f64; 3]) -> [f32; 3] {
    [v[0] as f32, v[1] as f32, v[2] as f32]
}

/// A rotation as glTF writes it, `None` for none: `w` made non-negative (`q` and `−q` are the
/// same turn) and components rounded to 1e-7, so that the file reads `0` rather than `-0` or
/// `6e-17`.
fn quat(q: UnitQuaternion<f64>) -> Option<json::scene::UnitQuaternion> {
    let c = q.coords;
    let sign = if c.w < 0.0 { -1.0 } else { 1.0 };
    let tidy = |v: f64| ((sign * v * 1e7).round() / 1e7) as f32 + 0.0;
    let [x, y, z, w] = [tidy(c.x), tidy(c.y), tidy(c.z), tidy(c.w)];
    if w == 1.0 {
        return None;
    }
    Some(json::scene::UnitQuaternion([x, y, z, w]))
}

/// A node placed by `pose`, named `name`, with `extras`.
fn placed_node(
    name: &str,
    pose: Option<&Isometry3<f64>>,
    mesh: Option<json::Index<json::Mesh>>,
    extra: &serde_json::Value,
) -> json::Node {
    let (translation, rotation) = match pose {
        Some(p) => {
            let t = p.translation.vector;
            (Some(f32x3([t.x, t.y, t.z])), quat(p.rotation))
        }
        None => (None, None),
    };
    json::Node {
        camera: None,
        children: None,
        extensions: None,
        extras: extras(extra),
        matrix: None,
        mesh,
        name: Some(name.to_string()),
        rotation,
        scale: None,
        translation,
        skin: None,
        weights: None,
    }
}

/// An object's rotation from AI2-THOR's Euler angles (degrees; Unity turns about z, then x,
/// then y).
pub fn euler_rotation(x_deg: f64, y_deg: f64, z_deg: f64) -> UnitQuaternion<f64> {
    let about = |axis, deg: f64| UnitQuaternion::from_axis_angle(&axis, deg.to_radians());
    about(Vector3::y_axis(), y_deg)
        * about(Vector3::x_axis(), x_deg)
        * about(Vector3::z_axis(), z_deg)
}

/// Exports `house`: object sizes come from `catalog`, door kinds from the structure catalog.
pub fn export(
    house: &House,
    catalog: &Catalog,
    options: &ExportOptions,
) -> Result<Export, ExportError> {
    if let Some(wanted) = &options.rooms {
        let known: Vec<String> = house.rooms.iter().map(|r| r.id.clone()).collect();
        let unknown: Vec<String> = wanted.iter().filter(|w| !known.contains(w)).cloned().collect();
        if !unknown.is_empty() {
            return Err(ExportError::UnknownRooms { unknown, known });
        }
    }
    let keep = |room: &str| options.rooms.as_ref().is_none_or(|r| r.contains(room));
    let mut b = Builder::default();
    b.root.asset = json::Asset {
        copyright: None,
        extensions: None,
        extras: None,
        generator: Some(format!("holoc {}", env!("CARGO_PKG_VERSION"))),
        min_version: None,
        version: "2.0".to_string(),
    };
    let mut nodes = Vec::new();
    let mut counts = Counts::default();

    let frames: BTreeMap<&str, WallFrame> =
        house.walls.iter().filter_map(|w| Some((w.id.as_str(), WallFrame::of(w)?))).collect();
    let polygons: BTreeMap<&str, Vec<Point>> = house
        .rooms
        .iter()
        .map(|r| (r.id.as_str(), r.floor_polygon.iter().map(|p| [p.x, p.z]).collect()))
        .collect();

    // Rooms: floor and ceiling.
    let ceiling_material = &house.procedural_parameters.ceiling_material;
    let ceiling_tint =
        rgb(ceiling_material.color).or(Some(house.procedural_parameters.ceiling_color));
    for room in house.rooms.iter().filter(|r| keep(&r.id)) {
        let outline = &polygons[room.id.as_str()];
        let height = house
            .walls
            .iter()
            .filter(|w| w.room_id == room.id)
            .flat_map(|w| w.polygon.iter().map(|p| p.y))
            .fold(0.0, f64::max);
        let mut floor = Geometry::default();
        floor.add_polygon(outline, 0.0, true);
        let mut ceiling = Geometry::default();
        if options.ceiling && height > 0.0 {
            ceiling.add_polygon(outline, height, false);
        }
        let mesh = b.mesh(
            &room.id,
            &[
                (
                    &floor,
                    materials::surface(&room.floor_material.name, rgb(room.floor_material.color)),
                ),
                (&ceiling, materials::surface(&ceiling_material.name, ceiling_tint)),
            ],
        );
        let extra = serde_json::json!({
            "kind": "room",
            "roomId": room.id,
            "roomType": room.room_type,
            "floorMaterial": room.floor_material.name,
            "wallMaterial": room.wall_material.name,
        });
        nodes.push(b.node(placed_node(&room.id, None, mesh, &extra)));
        counts.rooms += 1;
    }

    // The holes of each wall, in its own frame.
    let mut holes: BTreeMap<&str, Vec<Hole>> = BTreeMap::new();
    let openings = house
        .doors
        .iter()
        .map(|d| (&d.wall0, &d.wall1, &d.hole_polygon))
        .chain(house.windows.iter().map(|w| (&w.wall0, &w.wall1, &w.hole_polygon)));
    for (wall0, wall1, hole) in openings {
        let (Some(f0), [lo, hi, ..]) = (frames.get(wall0.as_str()), hole.as_slice()) else {
            continue;
        };
        let a = geo::add_scaled(f0.start, f0.dir, lo.x);
        let z = geo::add_scaled(f0.start, f0.dir, hi.x);
        for wall in [wall0, wall1] {
            if let Some(f) = frames.get(wall.as_str()) {
                let (s, e) = (f.along(a), f.along(z));
                holes
                    .entry(wall.as_str())
                    .or_default()
                    .push(Hole { x: [s.min(e), s.max(e)], y: [lo.y.min(hi.y), lo.y.max(hi.y)] });
            }
        }
    }

    // Walls.
    for wall in house.walls.iter().filter(|w| keep(&w.room_id)) {
        let frame = frames.get(wall.id.as_str());
        let mut mesh = None;
        let mut pose = None;
        if let (Some(f), false) = (frame, wall.empty == Some(true)) {
            // Which side of the line the room lies on: a slab stands on its room's side, an
            // exterior copy on the other.
            let mid = geo::add_scaled(f.start, f.dir, f.length / 2.0);
            let probe = geo::add_scaled(mid, f.normal(), 0.05);
            let room_on_z = polygons
                .get(wall.room_id.as_str())
                .is_some_and(|p| geo::point_in_polygon(probe, p));
            let exterior = wall.id.ends_with("|exterior");
            let z = if room_on_z == exterior { [-WALL_SLAB_M, 0.0] } else { [0.0, WALL_SLAB_M] };
            let mut g = Geometry::default();
            let wall_holes = holes.get(wall.id.as_str()).map_or(&[][..], Vec::as_slice);
            mesh::add_wall_slab(&mut g, f.length, f.height, z, wall_holes);
            mesh = b.mesh(
                &wall.id,
                &[(&g, materials::surface(&wall.material.name, rgb(wall.material.color)))],
            );
            pose = Some(f.pose(0.0, 0.0));
        }
        let extra = serde_json::json!({
            "kind": "wall",
            "roomId": wall.room_id,
            "material": wall.material.name,
        });
        nodes.push(b.node(placed_node(&wall.id, pose.as_ref(), mesh, &extra)));
        counts.walls += 1;
    }

    // Doors: a frame around the hole and the leaf, turned by its openness.
    let structure = StructureCatalog::builtin();
    for door in house.doors.iter().filter(|d| keep(&d.room0) || keep(&d.room1)) {
        let frame = frames.get(door.wall0.as_str());
        let (mesh, pose) = match (frame, door.hole_polygon.as_slice()) {
            (Some(f), [lo, hi, ..]) => {
                let (w, h) = ((hi.x - lo.x).abs(), (hi.y - lo.y).abs());
                let mut g = Geometry::default();
                let id = Isometry3::identity();
                let z = [-WALL_SLAB_M - FRAME_PROUD_M, WALL_SLAB_M + FRAME_PROUD_M];
                g.add_box([0.0, 0.0, z[0]], [FRAME_M, h, z[1]], &id);
                g.add_box([w - FRAME_M, 0.0, z[0]], [w, h, z[1]], &id);
                g.add_box([FRAME_M, h - FRAME_M, z[0]], [w - FRAME_M, h, z[1]], &id);
                let has_leaf = structure.door(&door.asset_id).map_or_else(
                    || door.asset_id.starts_with("Doorway"),
                    |a| a.kind == DoorKind::Doorway,
                );
                let mut leaf = Geometry::default();
                if has_leaf {
                    // Hinged at the frame's left side, swinging towards the frame's +z.
                    let swing = UnitQuaternion::from_axis_angle(
                        &Vector3::y_axis(),
                        -door.openness.clamp(0.0, 1.0) * std::f64::consts::FRAC_PI_2,
                    );
                    let hinge = Isometry3::from_parts(Translation3::new(FRAME_M, 0.0, 0.0), swing);
                    leaf.add_box(
                        [0.0, 0.0, -LEAF_M / 2.0],
                        [w - 2.0 * FRAME_M, h - FRAME_M, LEAF_M / 2.0],
                        &hinge,
                    );
                }
                let mesh =
                    b.mesh(&door.id, &[(&g, materials::frame()), (&leaf, materials::door_leaf())]);
                (mesh, Some(f.pose(lo.x.min(hi.x), lo.y.min(hi.y))))
            }
            _ => (None, None),
        };
        let extra = serde_json::json!({
            "kind": "door",
            "assetId": door.asset_id,
            "roomId": door.room0,
            "rooms": [door.room0, door.room1],
            "openness": door.openness,
        });
        nodes.push(b.node(placed_node(&door.id, pose.as_ref(), mesh, &extra)));
        counts.doors += 1;
    }

    // Windows: a frame and a pane.
    for window in house.windows.iter().filter(|w| keep(&w.room_id)) {
        let frame = frames.get(window.wall0.as_str());
        let (mesh, pose) = match (frame, window.hole_polygon.as_slice()) {
            (Some(f), [lo, hi, ..]) => {
                let (w, h) = ((hi.x - lo.x).abs(), (hi.y - lo.y).abs());
                let mut g = Geometry::default();
                let id = Isometry3::identity();
                let z = [-WALL_SLAB_M - FRAME_PROUD_M, WALL_SLAB_M + FRAME_PROUD_M];
                g.add_box([0.0, 0.0, z[0]], [FRAME_M, h, z[1]], &id);
                g.add_box([w - FRAME_M, 0.0, z[0]], [w, h, z[1]], &id);
                g.add_box([FRAME_M, 0.0, z[0]], [w - FRAME_M, FRAME_M, z[1]], &id);
                g.add_box([FRAME_M, h - FRAME_M, z[0]], [w - FRAME_M, h, z[1]], &id);
                let mut pane = Geometry::default();
                pane.add_box(
                    [FRAME_M, FRAME_M, -PANE_M / 2.0],
                    [w - FRAME_M, h - FRAME_M, PANE_M / 2.0],
                    &id,
                );
                let mesh =
                    b.mesh(&window.id, &[(&g, materials::frame()), (&pane, materials::glass())]);
                (mesh, Some(f.pose(lo.x.min(hi.x), lo.y.min(hi.y))))
            }
            _ => (None, None),
        };
        let extra = serde_json::json!({
            "kind": "window",
            "assetId": window.asset_id,
            "roomId": window.room_id,
        });
        nodes.push(b.node(placed_node(&window.id, pose.as_ref(), mesh, &extra)));
        counts.windows += 1;
    }

    // Objects, each item after the object it stands on.
    if options.objects == ObjectMode::Boxes {
        let mut flat: Vec<(&Object, Option<&str>)> = Vec::new();
        for o in house.objects.iter().filter(|o| keep(&o.room_id)) {
            flatten(o, None, &mut flat);
        }
        let mut made_meshes: BTreeMap<&str, Option<json::Index<json::Mesh>>> = BTreeMap::new();
        for (o, parent) in flat {
            let asset = catalog.get(&o.asset_id);
            let object_type = asset
                .map(|a| a.object_type.clone())
                .or_else(|| made_type(&o.asset_id).map(std::borrow::Cow::Borrowed));
            let r = o.rotation;
            let rotation = euler_rotation(r.x, r.y, r.z);
            let made = options.made.by_uid.get_key_value(o.asset_id.as_str());
            let (mesh, scale) = match (made, asset) {
                (Some((uid, parts)), _) => {
                    let mesh = *made_meshes.entry(uid.as_str()).or_insert_with(|| {
                        let refs: Vec<(&Geometry, Pbr)> =
                            parts.iter().map(|(g, p)| (g, p.clone())).collect();
                        b.mesh(uid, &refs)
                    });
                    (mesh, None)
                }
                (None, Some(a)) => {
                    let pbr = materials::object(&a.object_type);
                    (Some(b.cube_mesh(&pbr)), Some(f32x3(a.bbox_m)))
                }
                (None, None) => (None, None),
            };
            let mut extra = serde_json::json!({
                "kind": "object",
                "assetId": o.asset_id,
                "objectType": object_type,
                "roomId": o.room_id,
                "objectName": o.object_name,
            });
            if let (Some(p), Some(map)) = (parent, extra.as_object_mut()) {
                map.insert("onObject".to_string(), serde_json::Value::from(p));
            }
            let p = o.position;
            let pose = Isometry3::from_parts(Translation3::new(p.x, p.y, p.z), rotation);
            let mut node = placed_node(&o.id, Some(&pose), mesh, &extra);
            node.scale = scale;
            nodes.push(b.node(node));
            counts.objects += 1;
        }
    }

    while b.bin.len() % 4 != 0 {
        b.bin.push(0);
    }
    b.root.push(json::Buffer {
        byte_length: USize64::from(b.bin.len()),
        extensions: None,
        extras: None,
        name: None,
        uri: None,
    });
    let scene = b.root.push(json::Scene {
        extensions: None,
        extras: None,
        name: Some("house".to_string()),
        nodes,
    });
    b.root.scene = Some(scene);
    Ok(Export { root: b.root, bin: b.bin, counts })
}

/// The object type of a made asset's uid (`holoc_<kind>_<hash>`), from its kind.
fn made_type(id: &str) -> Option<&'static str> {
    if !crate::make::is_made_id(id) {
        return None;
    }
    let kind = id.strip_prefix("holoc_")?.rsplit_once('_')?.0;
    crate::make::kind(kind).map(|k| k.object_type)
}

fn flatten<'h>(
    o: &'h Object,
    parent: Option<&'h str>,
    out: &mut Vec<(&'h Object, Option<&'h str>)>,
) {
    out.push((o, parent));
    for c in &o.children {
        flatten(c, Some(&o.id), out);
    }
}

/// A house material's tint without its alpha (the export's surfaces are opaque).
fn rgb(c: Option<crate::lower::thor::Rgba>) -> Option<crate::lower::thor::Rgb> {
    c.map(|c| crate::lower::thor::Rgb { r: c.r, g: c.g, b: c.b })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn euler_angles_turn_as_unity_does() {
        // A quarter turn about y takes +x to -z (clockwise seen from above in AI2-THOR).
        let q = euler_rotation(0.0, 90.0, 0.0);
        let v = q * Vector3::x();
        assert!((v - Vector3::new(0.0, 0.0, -1.0)).norm() < 1e-12);
        // z first, then x, then y.
        let q = euler_rotation(90.0, 90.0, 0.0);
        let v = q * Vector3::y();
        // x turns +y to +z, then y turns +z to +x.
        assert!((v - Vector3::new(1.0, 0.0, 0.0)).norm() < 1e-12);
    }
}

//! The `lower` stage: a [`FloorPlan`] (and the solver's placed objects) becomes the AI2-THOR
//! house JSON, and `holoc validate` checks house files ([`validate`]).
//!
//! Ids follow Holodeck (`wall|<room>|<direction>|<n>`, `door|<n>|<room0>|<room1>`,
//! `window|<wall0>|<k>`, `<object> (<room>)`, `light|<room>`). Lengths are metres, angles
//! degrees. Every float is rounded to 1e-6 before printing ([`crate::geometry::round6`]), so the
//! same input and seed give the same bytes.

mod agent;
mod objects;
pub mod thor;
pub mod validate;

pub use agent::{agent_start, AGENT_RADIUS_M};
pub use objects::objects;

use std::collections::BTreeMap;

use crate::check::scene::{ObjectId, RoomId, Scene};
use crate::plan::FloorPlan;
use crate::resolve::structure::EXTERIOR_WALL_MATERIAL;
use thor::{Light, Rgb, Shadow, Vec3};

/// The schema version written in `metadata.schema`.
pub const SCHEMA_VERSION: &str = "1.0.0";
/// Height of the agent's camera above the floor, metres.
pub const AGENT_Y_M: f64 = 0.95;

/// An object placed by the solver, ready to be written.
#[derive(Clone, Debug, PartialEq)]
pub struct LoweredObject {
    /// `<name> (<room label>)`, e.g. `sofa-0 (living room)`.
    pub id: String,
    /// The asset id.
    pub asset_id: String,
    /// The room it stands in.
    pub room: RoomId,
    /// Bounding-box centre `(x, y, z)`, metres, y up.
    pub position_m: [f64; 3],
    /// Euler rotation `(x, y, z)`, degrees.
    pub rotation_deg: [f64; 3],
    /// Whether physics leaves it in place.
    pub kinematic: bool,
    /// The instance name, e.g. `sofa-0`.
    pub object_name: String,
    /// The id of the receptacle it stands on (it is written among that object's `children`).
    pub parent: Option<String>,
    /// What of the scene it is (the build report finds its id in the house by this).
    pub source: Source,
    /// Its id in the layout (the report's `layout` section): `sofa-0`, `book-0|wall_shelf-0`
    /// (the receptacle declared, which a moved thing keeps there).
    pub layout_id: String,
}

/// What of the scene a house object is.
#[derive(Clone, Copy, Debug, PartialEq, Eq, PartialOrd, Ord, Hash)]
pub enum Source {
    /// A floor or wall object.
    Object(ObjectId),
    /// A copy of a thing on top: the receptacle it is declared on, its `on top` line, the copy.
    Item(ObjectId, usize, u32),
    /// A room's ceiling object.
    Ceiling(RoomId),
}

/// The lowered house, ready to print.
#[derive(Clone, Debug, PartialEq)]
pub struct HouseJson {
    /// The house.
    pub house: thor::House,
}

impl HouseJson {
    /// The house as pretty-printed JSON (fields in AI2-THOR's order) with a final newline.
    /// Every coordinate was rounded to 1e-6 when the house was made ([`thor::Vec3::new`]).
    pub fn to_json_string(&self) -> String {
        let mut s =
            serde_json::to_string_pretty(&self.house).expect("house types always serialize");
        s.push('\n');
        s
    }

    /// Every object of the house, receptacles before the items on them, in the house's order.
    pub fn all_objects(&self) -> Vec<&thor::Object> {
        let mut out = Vec::new();
        let mut pending: Vec<&thor::Object> = self.house.objects.iter().rev().collect();
        while let Some(o) = pending.pop() {
            out.push(o);
            pending.extend(o.children.iter().rev());
        }
        out
    }

    /// How many objects the house holds.
    pub fn object_count(&self) -> usize {
        self.all_objects().len()
    }
}

/// ProcTHOR's room types, with the words of a room label that mean each, in the order they are
/// tried (a "kitchen and living room" is a kitchen; a "bathroom" is never a bedroom).
const ROOM_TYPES: [(&str, &[&str]); 4] = [
    (
        "Bathroom",
        &[
            "bathroom", "bath", "toilet", "restroom", "washroom", "wc", "lavatory", "powder",
            "shower", "ensuite",
        ],
    ),
    ("Kitchen", &["kitchen", "kitchenette", "pantry", "galley", "scullery"]),
    ("Bedroom", &["bedroom", "nursery", "guest", "dorm", "dormitory", "sleeping", "bunk"]),
    (
        "LivingRoom",
        &["living", "lounge", "family", "den", "sitting", "parlor", "parlour", "great", "common"],
    ),
];

/// The `roomType` of a room: one of ProcTHOR's types (`Kitchen`, `LivingRoom`, `Bedroom`,
/// `Bathroom`) when a word of the label means it, else the label itself. AI2-THOR does nothing
/// with the field; ProcTHOR-based code keys on those four. The label always survives in the
/// room's `id`.
pub fn room_type(label: &str) -> String {
    let lower = label.to_lowercase();
    let words: Vec<&str> =
        lower.split(|c: char| !c.is_alphanumeric()).filter(|w| !w.is_empty()).collect();
    ROOM_TYPES
        .iter()
        .find(|(_, keys)| words.iter().any(|w| keys.contains(w)))
        .map_or_else(|| label.to_owned(), |(t, _)| (*t).to_owned())
}

fn v3(p: [f64; 2], y: f64) -> Vec3 {
    Vec3::new(p[0], y, p[1])
}

/// A design's colour as the material's `color` (opaque).
fn tint(color: Option<&crate::resolve::colors::Color>) -> Option<thor::Rgba> {
    color.map(|c| thor::Rgba::opaque(c.rgb))
}

fn soft_shadow(bias: f64) -> Shadow {
    Shadow {
        kind: "Soft".to_owned(),
        strength: 1.0,
        normal_bias: 0.0,
        bias,
        near_plane: 0.2,
        resolution: "FromQualitySettings".to_owned(),
    }
}

/// Lowers a plan and the placed objects to the house JSON.
pub fn lower(scene: &Scene, plan: &FloorPlan, objects: &[LoweredObject]) -> HouseJson {
    let h = plan.wall_height_m;
    let layer = |r: RoomId| plan.layer_name(r);
    let room_id = |r: RoomId| plan.rooms.get(r.0).map_or_else(String::new, |x| x.thor_id.clone());
    let rooms = plan
        .rooms
        .iter()
        .map(|r| thor::Room {
            id: r.thor_id.clone(),
            room_type: scene
                .rooms
                .get(r.id.0)
                .map_or_else(|| r.thor_id.clone(), |s| room_type(&s.label)),
            floor_polygon: r.polygon.iter().map(|&p| v3(p, 0.0)).collect(),
            floor_material: thor::Material {
                name: r.floor_material.clone(),
                color: tint(r.floor_tint.as_ref()),
            },
            ceilings: Vec::new(),
            children: Vec::new(),
            layer: layer(r.id),
            wall_material: thor::Material {
                name: r.wall_material.clone(),
                color: tint(r.wall_tint.as_ref()),
            },
        })
        .collect();
    let mut walls = Vec::new();
    for w in &plan.walls {
        let polygon = vec![v3(w.start, 0.0), v3(w.start, h), v3(w.end, h), v3(w.end, 0.0)];
        let wall_material = plan.rooms.get(w.room.0).map_or_else(
            || thor::Material { name: String::new(), color: None },
            |r| thor::Material { name: r.wall_material.clone(), color: tint(r.wall_tint.as_ref()) },
        );
        if w.exterior {
            walls.push(thor::Wall {
                id: w.exterior_id(),
                room_id: room_id(w.room),
                polygon: polygon.iter().rev().copied().collect(),
                material: thor::Material { name: EXTERIOR_WALL_MATERIAL.to_owned(), color: None },
                layer: layer(w.room),
                empty: None,
            });
        }
        walls.push(thor::Wall {
            id: w.id.clone(),
            room_id: room_id(w.room),
            polygon,
            material: wall_material,
            layer: layer(w.room),
            empty: w.empty.then_some(true),
        });
    }
    let doors = plan
        .doors
        .iter()
        .map(|d| thor::Door {
            id: d.id.clone(),
            asset_id: d.asset_id.clone(),
            openable: d.openable,
            openness: d.openness,
            room0: d.room0.clone(),
            room1: d.room1.clone(),
            wall0: d.wall0.clone(),
            wall1: d.wall1.clone(),
            hole_polygon: vec![
                Vec3::new(d.hole_min[0], d.hole_min[1], 0.0),
                Vec3::new(d.hole_max[0], d.hole_max[1], 0.0),
            ],
            asset_position: Vec3::new(d.asset_position[0], d.asset_position[1], 0.0),
        })
        .collect();
    let windows = plan
        .windows
        .iter()
        .map(|w| thor::Window {
            id: w.id.clone(),
            asset_id: w.asset_id.clone(),
            room0: room_id(w.room),
            room1: room_id(w.room),
            wall0: w.wall0.clone(),
            wall1: w.wall1.clone(),
            hole_polygon: vec![
                Vec3::new(w.hole_min[0], w.hole_min[1], 0.0),
                Vec3::new(w.hole_max[0], w.hole_max[1], 0.0),
            ],
            asset_position: Vec3::new(w.asset_position[0], w.asset_position[1], 0.0),
            room_id: room_id(w.room),
            layer: layer(w.room),
        })
        .collect();
    let thor_object = |o: &LoweredObject| thor::Object {
        id: o.id.clone(),
        asset_id: o.asset_id.clone(),
        kinematic: o.kinematic,
        position: Vec3::new(o.position_m[0], o.position_m[1], o.position_m[2]),
        rotation: Vec3::new(o.rotation_deg[0], o.rotation_deg[1], o.rotation_deg[2]),
        layer: layer(o.room),
        room_id: room_id(o.room),
        object_name: o.object_name.clone(),
        children: Vec::new(),
    };
    // Items on a receptacle go into its `children`, as ProcTHOR writes them.
    let mut top: Vec<thor::Object> = Vec::new();
    for o in objects {
        let parent = o.parent.as_ref().and_then(|p| top.iter_mut().find(|t| t.id == *p));
        match parent {
            Some(receptacle) => receptacle.children.push(thor_object(o)),
            None => top.push(thor_object(o)),
        }
    }
    let objects = top;
    thor_house(plan, rooms, walls, doors, windows, objects)
}

fn thor_house(
    plan: &FloorPlan,
    rooms: Vec<thor::Room>,
    walls: Vec<thor::Wall>,
    doors: Vec<thor::Door>,
    windows: Vec<thor::Window>,
    objects: Vec<thor::Object>,
) -> HouseJson {
    // The directional light follows the skybox's time of day (values of Holodeck's table).
    let (intensity, rgb, rotation) = match plan.time_of_day.as_str() {
        "GoldenHour" => (1.0, Rgb { r: 1.0, g: 0.694, b: 0.78 }, Vec3::new(6.0, -166.0, 0.0)),
        "BlueHour" => (0.5, Rgb { r: 0.638, g: 0.843, b: 1.0 }, Vec3::new(82.0, -30.0, 0.0)),
        _ => (1.0, Rgb { r: 1.0, g: 1.0, b: 1.0 }, Vec3::new(66.0, 75.0, 0.0)),
    };
    let mut lights = vec![Light {
        id: "DirectionalLight".to_owned(),
        kind: "directional".to_owned(),
        position: Vec3::new(0.84, 0.1855, -1.09),
        rotation: Some(rotation),
        intensity,
        indirect_multiplier: Some(1.0),
        range: None,
        rgb,
        shadow: soft_shadow(0.0),
        room_id: None,
        layer: None,
        culling_mask_off: None,
    }];
    for r in &plan.rooms {
        let own = format!("Procedural{}", r.layer);
        lights.push(Light {
            id: format!("light|{}", r.thor_id),
            kind: "point".to_owned(),
            position: Vec3::new(r.centroid[0], plan.wall_height_m - 0.2, r.centroid[1]),
            rotation: None,
            intensity: 0.75,
            indirect_multiplier: None,
            range: Some(15.0),
            rgb: Rgb { r: 1.0, g: 0.855, b: 0.722 },
            shadow: soft_shadow(0.05),
            room_id: Some(r.thor_id.clone()),
            layer: Some(own.clone()),
            culling_mask_off: Some(
                (0..crate::plan::N_LAYERS)
                    .map(|l| format!("Procedural{l}"))
                    .filter(|l| *l != own)
                    .collect(),
            ),
        });
    }
    let pose = |standing: Option<bool>| thor::AgentPose {
        horizon: 30.0,
        position: Vec3::new(plan.agent.position[0], AGENT_Y_M, plan.agent.position[1]),
        rotation: Vec3::new(0.0, plan.agent.rotation_deg, 0.0),
        standing,
    };
    let mut agent_poses = BTreeMap::new();
    for (kind, standing) in
        [("arm", Some(true)), ("default", Some(true)), ("locobot", None), ("stretch", Some(true))]
    {
        agent_poses.insert(kind.to_owned(), pose(standing));
    }
    let ceiling_color =
        Rgb { r: 0.427_450_980_392_156_84, g: 0.384_313_725_490_196_1, b: 0.305_882_352_941_176_5 };
    HouseJson {
        house: thor::House {
            rooms,
            walls,
            doors,
            windows,
            objects,
            procedural_parameters: thor::ProceduralParameters {
                ceiling_color,
                ceiling_material: thor::Material {
                    name: plan.ceiling_material.clone(),
                    color: None,
                },
                floor_collider_thickness: 1.0,
                receptacle_height: 0.7,
                reflections: Vec::new(),
                skybox_id: plan.skybox.clone(),
                lights,
            },
            metadata: thor::Metadata {
                agent: pose(Some(true)),
                agent_poses,
                room_spec_id: "Living Room".to_owned(),
                schema: SCHEMA_VERSION.to_owned(),
                warnings: BTreeMap::new(),
            },
        },
    }
}

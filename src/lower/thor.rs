//! The AI2-THOR house JSON (schema 1.0.0) as serde types. This is the only file that knows
//! AI2-THOR's field names.

use std::collections::BTreeMap;

use serde::{Deserialize, Serialize};

/// A point or vector `{x, y, z}` (metres or degrees).
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
pub struct Vec3 {
    /// x.
    pub x: f64,
    /// y (up).
    pub y: f64,
    /// z.
    pub z: f64,
}

impl Vec3 {
    /// Makes a vector, rounding every component to the output precision (1e-6).
    pub fn new(x: f64, y: f64, z: f64) -> Vec3 {
        use crate::geometry::round6;
        Vec3 { x: round6(x), y: round6(y), z: round6(z) }
    }
}

/// A colour.
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
pub struct Rgb {
    /// Red, 0…1.
    pub r: f64,
    /// Green, 0…1.
    pub g: f64,
    /// Blue, 0…1.
    pub b: f64,
}

/// A colour with its opacity, as AI2-THOR's `SerializableColor` (a material's tint).
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
pub struct Rgba {
    /// Red, 0…1.
    pub r: f64,
    /// Green, 0…1.
    pub g: f64,
    /// Blue, 0…1.
    pub b: f64,
    /// Opacity, 0…1 (AI2-THOR reads 1 when it is absent, as ProcTHOR writes it).
    #[serde(default = "opaque")]
    pub a: f64,
}

fn opaque() -> f64 {
    1.0
}

impl Rgba {
    /// An opaque colour, each channel rounded to the output precision (1e-6).
    pub fn opaque(rgb: [f64; 3]) -> Rgba {
        use crate::geometry::round6;
        Rgba { r: round6(rgb[0]), g: round6(rgb[1]), b: round6(rgb[2]), a: 1.0 }
    }
}

/// A material reference.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct Material {
    /// The material name.
    pub name: String,
    /// An optional tint, multiplied with the material's texture (ProcTHOR paints walls
    /// `PureWhite` with a colour).
    #[serde(skip_serializing_if = "Option::is_none", default)]
    pub color: Option<Rgba>,
}

/// The whole house.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(rename_all = "camelCase")]
pub struct House {
    /// Rooms.
    pub rooms: Vec<Room>,
    /// Walls, each exterior copy just before its interior wall.
    pub walls: Vec<Wall>,
    /// Doors.
    pub doors: Vec<Door>,
    /// Windows.
    pub windows: Vec<Window>,
    /// Objects.
    pub objects: Vec<Object>,
    /// Lights, skybox, ceiling.
    pub procedural_parameters: ProceduralParameters,
    /// Agent pose and schema version.
    pub metadata: Metadata,
}

/// A room.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(rename_all = "camelCase")]
pub struct Room {
    /// The room id.
    pub id: String,
    /// The room type (the label).
    pub room_type: String,
    /// The outline on the floor (`y = 0`), clockwise.
    pub floor_polygon: Vec<Vec3>,
    /// Floor material.
    pub floor_material: Material,
    /// Always empty.
    pub ceilings: Vec<serde_json::Value>,
    /// Always empty.
    pub children: Vec<serde_json::Value>,
    /// Lighting layer.
    pub layer: String,
    /// The wall material (Holodeck extra key).
    pub wall_material: Material,
}

/// A wall.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(rename_all = "camelCase")]
pub struct Wall {
    /// The wall id.
    pub id: String,
    /// The room it belongs to.
    pub room_id: String,
    /// Four corners: start at the floor, start at the top, end at the top, end at the floor.
    pub polygon: Vec<Vec3>,
    /// Material.
    pub material: Material,
    /// Lighting layer.
    pub layer: String,
    /// Present and true for walls left out by an open connection.
    #[serde(skip_serializing_if = "Option::is_none", default)]
    pub empty: Option<bool>,
}

/// A door.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(rename_all = "camelCase")]
pub struct Door {
    /// The door id.
    pub id: String,
    /// The asset.
    pub asset_id: String,
    /// Whether it opens.
    pub openable: bool,
    /// How far it is open.
    pub openness: f64,
    /// First side (a room id or `exterior`).
    pub room0: String,
    /// Second side.
    pub room1: String,
    /// Wall on the first side.
    pub wall0: String,
    /// Wall on the second side.
    pub wall1: String,
    /// Hole min and max corner, wall-local.
    pub hole_polygon: Vec<Vec3>,
    /// Asset centre, wall-local.
    pub asset_position: Vec3,
}

/// A window.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(rename_all = "camelCase")]
pub struct Window {
    /// The window id.
    pub id: String,
    /// The asset.
    pub asset_id: String,
    /// The room.
    pub room0: String,
    /// The room again.
    pub room1: String,
    /// The interior wall.
    pub wall0: String,
    /// Its exterior copy.
    pub wall1: String,
    /// Hole min and max corner, wall-local.
    pub hole_polygon: Vec<Vec3>,
    /// Asset centre, wall-local.
    pub asset_position: Vec3,
    /// The room (Holodeck extra key).
    pub room_id: String,
    /// Lighting layer.
    pub layer: String,
}

/// An object.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(rename_all = "camelCase")]
pub struct Object {
    /// `<name> (<room>)`.
    pub id: String,
    /// The asset.
    pub asset_id: String,
    /// Whether physics leaves it in place.
    pub kinematic: bool,
    /// Bounding-box centre.
    pub position: Vec3,
    /// Euler angles, degrees.
    pub rotation: Vec3,
    /// Lighting layer.
    pub layer: String,
    /// The room (Holodeck extra key).
    pub room_id: String,
    /// The instance name (Holodeck extra key).
    #[serde(rename = "object_name")]
    pub object_name: String,
    /// The objects standing on it, as ProcTHOR nests them (AI2-THOR spawns them with it).
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub children: Vec<Object>,
}

/// Shadow settings of a light.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(rename_all = "camelCase")]
pub struct Shadow {
    /// `Soft`.
    #[serde(rename = "type")]
    pub kind: String,
    /// Strength.
    pub strength: f64,
    /// Normal bias.
    pub normal_bias: f64,
    /// Bias.
    pub bias: f64,
    /// Near plane.
    pub near_plane: f64,
    /// `FromQualitySettings`.
    pub resolution: String,
}

/// A light.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(rename_all = "camelCase")]
pub struct Light {
    /// `DirectionalLight` or `light|<room>`.
    pub id: String,
    /// `directional` or `point`.
    #[serde(rename = "type")]
    pub kind: String,
    /// Position.
    pub position: Vec3,
    /// Rotation (directional light only).
    #[serde(skip_serializing_if = "Option::is_none", default)]
    pub rotation: Option<Vec3>,
    /// Intensity.
    pub intensity: f64,
    /// Indirect multiplier (directional light only).
    #[serde(skip_serializing_if = "Option::is_none", default)]
    pub indirect_multiplier: Option<f64>,
    /// Range (point lights only).
    #[serde(skip_serializing_if = "Option::is_none", default)]
    pub range: Option<f64>,
    /// Colour.
    pub rgb: Rgb,
    /// Shadows.
    pub shadow: Shadow,
    /// The room (point lights).
    #[serde(skip_serializing_if = "Option::is_none", default)]
    pub room_id: Option<String>,
    /// Lighting layer (point lights).
    #[serde(skip_serializing_if = "Option::is_none", default)]
    pub layer: Option<String>,
    /// The layers this light does not light (point lights).
    #[serde(skip_serializing_if = "Option::is_none", default)]
    pub culling_mask_off: Option<Vec<String>>,
}

/// Lights, skybox and ceiling.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(rename_all = "camelCase")]
pub struct ProceduralParameters {
    /// Ceiling tint.
    pub ceiling_color: Rgb,
    /// Ceiling material.
    pub ceiling_material: Material,
    /// Floor collider thickness, metres.
    pub floor_collider_thickness: f64,
    /// Receptacle height, metres.
    pub receptacle_height: f64,
    /// Reflection probes (none).
    pub reflections: Vec<serde_json::Value>,
    /// The skybox.
    pub skybox_id: String,
    /// Lights.
    pub lights: Vec<Light>,
}

/// The agent's pose.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct AgentPose {
    /// Camera pitch, degrees.
    pub horizon: f64,
    /// Position.
    pub position: Vec3,
    /// Rotation.
    pub rotation: Vec3,
    /// Standing (absent for locobot).
    #[serde(skip_serializing_if = "Option::is_none", default)]
    pub standing: Option<bool>,
}

/// House metadata.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(rename_all = "camelCase")]
pub struct Metadata {
    /// The default agent pose.
    pub agent: AgentPose,
    /// Poses per agent kind.
    pub agent_poses: BTreeMap<String, AgentPose>,
    /// `Living Room` in every Holodeck house.
    pub room_spec_id: String,
    /// `1.0.0`.
    pub schema: String,
    /// Always empty.
    pub warnings: BTreeMap<String, serde_json::Value>,
}

//! Every field of an objathor `annotations.json.gz` entry.

use serde_json::Value;

use super::super::catalog::{bbox_of, flags_of, Asset};
use super::super::text::camel_words;

/// The licence of an Objaverse asset (`license_info`).
#[derive(Clone, Debug, Default, PartialEq, Eq, serde::Serialize, serde::Deserialize)]
pub struct License {
    /// The licence's short name (`by`, `by-sa`, `cc0`, …).
    pub license: Option<String>,
    /// The asset's page.
    pub uri: Option<String>,
    /// The creator's user name.
    pub creator_username: Option<String>,
    /// The creator's display name.
    pub creator_display_name: Option<String>,
    /// The creator's profile page.
    pub creator_profile_url: Option<String>,
}

/// Which of the three shapes the bounding box was written in.
#[derive(Clone, Copy, Debug, PartialEq, Eq, serde::Serialize, serde::Deserialize)]
pub enum BoxShape {
    /// `{x, y, z}`.
    Xyz,
    /// `{size: {x, y, z}}`.
    Size,
    /// `{min, max}`.
    MinMax,
}

/// Every field of one annotation entry that holoc reads (what the asset itself does not hold).
#[derive(Clone, Debug, Default, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct Entry {
    /// The written description (`description`).
    pub description: Option<String>,
    /// The generated description (`description_auto`), used when there is no written one.
    pub description_auto: Option<String>,
    /// The WordNet synset (`synset`, e.g. `cat_tree.n.01`).
    pub synset: Option<String>,
    /// The WordNet version (`wn_version`).
    pub wn_version: Option<String>,
    /// Related synsets with their similarity (`near_synsets`), in file order.
    pub near_synsets: Vec<(String, f64)>,
    /// The annotated size, cm (`width`, `depth`, `height`).
    pub size_cm: [Option<f64>; 3],
    /// Volume, litres (`volume`).
    pub volume_l: Option<f64>,
    /// Mass, kg (`mass`).
    pub mass_kg: Option<f64>,
    /// Materials (`materials`) and their shares (`composition`).
    pub materials: Vec<String>,
    /// Shares of the materials.
    pub composition: Vec<f64>,
    /// The view that shows the front (`frontView`).
    pub front_view: Option<i64>,
    /// Rotation about z, radians (`pose_z_rot_angle`).
    pub pose_z_rot_angle: Option<f64>,
    /// The scale (`scale`) and whether it is the z axis's (`z_axis_scale`).
    pub scale: Option<f64>,
    /// Whether `scale` is along z.
    pub z_axis_scale: Option<bool>,
    /// The licence.
    pub license: Option<License>,
    /// The shape the bounding box was written in.
    pub box_shape: Option<BoxShape>,
    /// How alike the asset is in Blender and in AI2-THOR (`blender_thor_similarity`; the
    /// original leaves out assets below 0.6, and takes a missing one as 1.0).
    pub blender_thor_similarity: Option<f64>,
    /// Whether its secondary properties hold `CanBreak` (a small object that breaks is kept
    /// kinematic, as the original does).
    pub can_break: bool,
}

fn string(v: &Value, key: &str) -> Option<String> {
    v.get(key).and_then(Value::as_str).map(str::to_string)
}

fn number(v: &Value, key: &str) -> Option<f64> {
    v.get(key).and_then(Value::as_f64).filter(|x| x.is_finite())
}

/// Reads one entry of the annotations: the asset (id, type, category, description, box,
/// flags, receptacle) and every other field. The error says why the entry is unusable.
pub fn read_entry(uid: &str, entry: &Value, source: usize) -> Result<(Asset, Entry), String> {
    if !entry.is_object() {
        return Err("it is not a JSON object".into());
    }
    let ann = entry.get("annotations").filter(|a| a.is_object()).unwrap_or(entry);
    let placements =
        flags_of(ann).ok_or("it has none of `onFloor`, `onWall`, `onObject`, `onCeiling`")?;
    let meta = entry
        .get("assetMetadata")
        .or_else(|| entry.get("thor_metadata").and_then(|t| t.get("assetMetadata")))
        .or_else(|| ann.get("thor_metadata").and_then(|t| t.get("assetMetadata")))
        .ok_or(
            "it has no `thor_metadata.assetMetadata` (nor `assetMetadata`) with a `boundingBox`",
        )?;
    let bbox_value = meta.get("boundingBox").ok_or("its asset metadata has no `boundingBox`")?;
    let bbox = bbox_of(bbox_value)?;
    let box_shape = if bbox_value.get("x").is_some() {
        BoxShape::Xyz
    } else if bbox_value.get("size").is_some() {
        BoxShape::Size
    } else {
        BoxShape::MinMax
    };
    let category = string(ann, "category");
    let object_type = string(meta, "objectType").filter(|t| !t.is_empty() && t != "Undefined");
    let (category, object_type) = match (category, object_type) {
        (Some(c), Some(t)) => (c, t),
        (Some(c), None) => (c.clone(), c),
        (None, Some(t)) => (camel_words(&t), t),
        (None, None) => return Err("it has no `category` and no `objectType`".into()),
    };
    let description = string(ann, "description");
    let description_auto = string(ann, "description_auto");
    let words = description.clone().or_else(|| description_auto.clone()).unwrap_or_default();
    let secondary = |name: &str| {
        meta.get("secondaryProperties")
            .and_then(Value::as_array)
            .is_some_and(|l| l.iter().any(|p| p.as_str() == Some(name)))
    };
    let secondary_receptacle = secondary("Receptacle");
    let license = ann.get("license_info").filter(|l| l.is_object()).map(|l| License {
        license: string(l, "license"),
        uri: string(l, "uri"),
        creator_username: string(l, "creator_username"),
        creator_display_name: string(l, "creator_display_name"),
        creator_profile_url: string(l, "creator_profile_url"),
    });
    let mut near_synsets: Vec<(String, f64)> = ann
        .get("near_synsets")
        .and_then(Value::as_object)
        .map(|m| m.iter().filter_map(|(k, v)| Some((k.clone(), v.as_f64()?))).collect())
        .unwrap_or_default();
    near_synsets.sort_by(|a, b| a.1.total_cmp(&b.1).then_with(|| a.0.cmp(&b.0)));
    let list = |key: &str| ann.get(key).and_then(Value::as_array);
    let extra = Entry {
        description,
        description_auto,
        synset: string(ann, "synset"),
        wn_version: string(ann, "wn_version"),
        near_synsets,
        size_cm: [number(ann, "width"), number(ann, "depth"), number(ann, "height")],
        volume_l: number(ann, "volume"),
        mass_kg: number(ann, "mass"),
        materials: list("materials")
            .map(|l| l.iter().filter_map(|m| m.as_str().map(str::to_string)).collect())
            .unwrap_or_default(),
        composition: list("composition")
            .map(|l| l.iter().filter_map(Value::as_f64).collect())
            .unwrap_or_default(),
        front_view: ann.get("frontView").and_then(Value::as_i64),
        pose_z_rot_angle: number(ann, "pose_z_rot_angle"),
        scale: number(ann, "scale"),
        z_axis_scale: ann.get("z_axis_scale").and_then(Value::as_bool),
        license,
        box_shape: Some(box_shape),
        // The original reads it from the entry's top level; some exports nest it.
        blender_thor_similarity: number(entry, "blender_thor_similarity")
            .or_else(|| number(ann, "blender_thor_similarity")),
        can_break: secondary("CanBreak"),
    };
    let asset = Asset {
        id: uid.to_string().into(),
        object_type: object_type.into(),
        category: category.into(),
        description: words.into(),
        bbox_m: bbox,
        placements,
        receptacle: secondary_receptacle
            || ann.get("receptacle").and_then(Value::as_bool).unwrap_or(false),
        source,
    };
    Ok((asset, extra))
}

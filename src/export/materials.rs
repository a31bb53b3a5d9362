//! The PBR colours of the glTF export: AI2-THOR's materials and object types, each one base
//! colour from the reviewed tables in `data/export/` (made by `scripts/gen_export_materials.py`
//! from ProcTHOR's material database; every row gives its reason), tinted by a house material's
//! `color`; plus the few fixed materials of the export's own parts (frames, doors, glass).

use std::collections::BTreeMap;
use std::sync::OnceLock;

use crate::lower::thor::Rgb;

const MATERIALS_TSV: &str = include_str!("../../data/export/materials.tsv");
const OBJECT_TYPES_TSV: &str = include_str!("../../data/export/object-types.tsv");

/// A glTF metallic-roughness material.
#[derive(Clone, Debug, PartialEq)]
pub struct Pbr {
    /// The material's name in the glTF file.
    pub name: String,
    /// Linear base colour and alpha.
    pub base_color: [f32; 4],
    /// Roughness, 0…1.
    pub roughness: f32,
    /// Metalness, 0…1.
    pub metalness: f32,
    /// Whether it is see-through (alpha blending, both sides drawn).
    pub glass: bool,
}

/// One row of a table: sRGB colour (0…255), roughness, metalness.
#[derive(Clone, Copy, Debug, PartialEq)]
struct Row {
    srgb: [u8; 3],
    roughness: f32,
    metalness: f32,
}

fn parse_table(text: &str) -> BTreeMap<&str, Row> {
    let mut out = BTreeMap::new();
    for line in text.lines().filter(|l| !l.starts_with('#') && !l.is_empty()) {
        let f: Vec<&str> = line.split('\t').collect();
        let [name, r, g, b, rough, metal, ..] = f[..] else { continue };
        let (Ok(r), Ok(g), Ok(b), Ok(rough), Ok(metal)) =
            (r.parse(), g.parse(), b.parse(), rough.parse(), metal.parse())
        else {
            continue;
        };
        out.insert(name, Row { srgb: [r, g, b], roughness: rough, metalness: metal });
    }
    out
}

fn materials() -> &'static BTreeMap<&'static str, Row> {
    static TABLE: OnceLock<BTreeMap<&'static str, Row>> = OnceLock::new();
    TABLE.get_or_init(|| parse_table(MATERIALS_TSV))
}

fn object_types() -> &'static BTreeMap<&'static str, Row> {
    static TABLE: OnceLock<BTreeMap<&'static str, Row>> = OnceLock::new();
    TABLE.get_or_init(|| parse_table(OBJECT_TYPES_TSV))
}

/// A material the tables do not know: neutral light grey, fairly rough.
const UNKNOWN: Row = Row { srgb: [180, 180, 180], roughness: 0.7, metalness: 0.0 };

/// sRGB (0…1) to linear, as glTF's `baseColorFactor` wants.
fn linear(c: f64) -> f32 {
    let c = c.clamp(0.0, 1.0);
    let l = if c <= 0.04045 { c / 12.92 } else { ((c + 0.055) / 1.055).powf(2.4) };
    // Rounded so that the file does not depend on the last bits of `powf`.
    ((l * 1e4).round() / 1e4) as f32
}

fn pbr(name: String, row: Row, tint: Option<Rgb>) -> Pbr {
    let t = tint.map_or([1.0; 3], |c| [c.r, c.g, c.b]);
    let c = |i: usize| linear(f64::from(row.srgb[i]) / 255.0 * t[i]);
    Pbr {
        name,
        base_color: [c(0), c(1), c(2), 1.0],
        roughness: row.roughness,
        metalness: row.metalness,
        glass: false,
    }
}

/// The colour of an AI2-THOR material (walls, floors, ceilings), tinted by `tint`.
pub fn surface(name: &str, tint: Option<Rgb>) -> Pbr {
    let row = materials().get(name).copied().unwrap_or(UNKNOWN);
    let label = match tint {
        Some(c) => format!("{name} tinted {:.3},{:.3},{:.3}", c.r, c.g, c.b),
        None => name.to_string(),
    };
    pbr(label, row, tint)
}

/// The colour of an object of `object_type` (the type's most common surface in the material
/// database; neutral grey for types it does not list).
pub fn object(object_type: &str) -> Pbr {
    let row = object_types().get(object_type).copied().unwrap_or(UNKNOWN);
    pbr(format!("object {object_type}"), row, None)
}

/// Door and window frames: painted white wood.
pub fn frame() -> Pbr {
    pbr("frame".to_string(), Row { srgb: [235, 232, 225], roughness: 0.5, metalness: 0.0 }, None)
}

/// Door leaves: medium wood.
pub fn door_leaf() -> Pbr {
    pbr("door leaf".to_string(), Row { srgb: [160, 115, 75], roughness: 0.6, metalness: 0.0 }, None)
}

/// A part of an asset holoc made: its swatch's colour (sRGB, 0…1) and finish; glass is
/// see-through.
pub fn made(rgb: [f64; 3], roughness: f64, metalness: f64, glass: bool) -> Pbr {
    let name = format!(
        "made {:.3},{:.3},{:.3} r{roughness:.2} m{metalness:.2}{}",
        rgb[0],
        rgb[1],
        rgb[2],
        if glass { " glass" } else { "" }
    );
    Pbr {
        name,
        base_color: [
            linear(rgb[0]),
            linear(rgb[1]),
            linear(rgb[2]),
            if glass { 0.35 } else { 1.0 },
        ],
        roughness: roughness as f32,
        metalness: metalness as f32,
        glass,
    }
}

/// Window panes: pale blue glass, mostly transparent.
pub fn glass() -> Pbr {
    Pbr {
        name: "glass".to_string(),
        base_color: [linear(0.75), linear(0.85), linear(0.92), 0.3],
        roughness: 0.05,
        metalness: 0.0,
        glass: true,
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_tables_are_read_and_tints_multiply() {
        assert!(materials().len() > 500);
        assert!(object_types().contains_key("Sofa"));
        let white = surface("PureWhite", None);
        assert!(white.base_color[0] > 0.8);
        let red = surface("PureWhite", Some(Rgb { r: 1.0, g: 0.0, b: 0.0 }));
        assert!(red.base_color[0] > 0.8 && red.base_color[1] == 0.0);
        assert_ne!(white.name, red.name);
        assert_eq!(surface("NoSuchMaterial", None).base_color[0], linear(180.0 / 255.0));
    }
}

//! The run-time asset format: the folder AI2-THOR's `ProceduralAssetHookRunner` loads for an
//! asset its build does not ship, as objathor writes it for Holodeck's Objaverse assets.
//!
//! One folder per asset, named by its uid, beside the house (`<house stem>.assets/<uid>/`):
//! - `<uid>.json`: the mesh dict the loaders read (objathor's `to_dict` fields): `name` (the
//!   uid), `vertices`, `triangles`, `normals` and `uvs` (one per face corner), `colliders`
//!   (convex pieces, each with its vertices and triangles), `albedoTexturePath`,
//!   `normalTexturePath`, `receptacleCandidate`, `visibilityPoints`, `physicalProperties` and
//!   `yRotOffset`. Plain `.json` is the one extension both the older runner (Python reads it)
//!   and the newer one (Unity reads it) load, and texture paths are file names, as objathor's
//!   own relative paths are (the hook rewrites them into its build folder);
//! - `albedo.jpg` (the palette: one 16-pixel cell per swatch, each vertex's uv at its part's
//!   cell) and `normal.jpg` (flat), written with `jpeg-encoder`;
//! - `thor_metadata.json`: `{"assetMetadata": {"primaryProperty", "secondaryProperties"}}`, so
//!   that furniture is `Static` and shelves are `Receptacle`s (without it the hook makes every
//!   asset pickupable).
//!
//! [`read_asset`] reads a folder back (for `holoc validate`, `export` and `view`).

use std::path::{Path, PathBuf};

use serde_json::{json, Value};

use super::finish::Swatch;
use super::MadeAsset;

/// The side of a palette cell in the albedo texture, pixels (two JPEG colour blocks, so that
/// a cell's centre keeps its colour through 4:2:0 compression).
pub const CELL_PX: u32 = 16;
/// Cells per row of the albedo texture.
pub const CELLS_PER_ROW: usize = 4;
/// The file names in an asset folder.
pub const ALBEDO: &str = "albedo.jpg";
/// The normal map's file name.
pub const NORMAL: &str = "normal.jpg";
/// The AI2-THOR properties' file name.
pub const THOR_METADATA: &str = "thor_metadata.json";
/// The largest asset file [`read_asset`] reads, bytes.
pub const MAX_ASSET_BYTES: u64 = 16 << 20;

fn grid(cells: usize) -> (usize, usize) {
    let cols = CELLS_PER_ROW.min(cells.max(1));
    let rows = cells.max(1).div_ceil(cols);
    (cols, rows)
}

/// The uv of swatch `s`'s cell centre in a palette of `cells` swatches (Unity's uv origin:
/// bottom left; the first row of cells is the image's bottom row).
pub fn cell_uv(s: usize, cells: usize) -> [f64; 2] {
    let (cols, rows) = grid(cells);
    let (col, row) = (s % cols, s / cols);
    [(col as f64 + 0.5) / cols as f64, (row as f64 + 0.5) / rows as f64]
}

/// The albedo texture: `(width, height, rgb bytes)`.
fn albedo_pixels(palette: &[Swatch]) -> (u16, u16, Vec<u8>) {
    let (cols, rows) = grid(palette.len());
    let (w, h) = (cols as u32 * CELL_PX, rows as u32 * CELL_PX);
    let mut px = vec![255u8; (w * h * 3) as usize];
    for (s, swatch) in palette.iter().enumerate() {
        let (col, row) = ((s % cols) as u32, (s / cols) as u32);
        // Image rows go down; cell row 0 is the bottom one.
        let top = (rows as u32 - 1 - row) * CELL_PX;
        let rgb = swatch.rgb.map(|c| (c.clamp(0.0, 1.0) * 255.0).round() as u8);
        for y in top..top + CELL_PX {
            for x in col * CELL_PX..(col + 1) * CELL_PX {
                let i = ((y * w + x) * 3) as usize;
                px[i..i + 3].copy_from_slice(&rgb);
            }
        }
    }
    (w as u16, h as u16, px)
}

fn jpeg(width: u16, height: u16, rgb: &[u8]) -> Vec<u8> {
    let mut out = Vec::new();
    let encoder = jpeg_encoder::Encoder::new(&mut out, 92);
    // Sizes and data are made here and always agree, so encoding cannot fail; an empty file
    // would only make the loader show the asset untextured.
    if encoder.encode(rgb, width, height, jpeg_encoder::ColorType::Rgb).is_err() {
        out.clear();
    }
    out
}

/// Rounds to 4 decimals (0.1 mm, and normals to 1e-4), so that files stay small and stable;
/// no negative zero.
fn round4(v: f64) -> f64 {
    let r = (v * 10_000.0).round() / 10_000.0;
    if r == 0.0 || !r.is_finite() {
        0.0
    } else {
        r
    }
}

/// Writes a number as JSON (Rust's shortest form of the rounded value: `0.1234`, `1`).
fn num(out: &mut String, v: f64) {
    use std::fmt::Write as _;
    let _ = write!(out, "{}", round4(v));
}

/// `"key":[{"x":…,"y":…,"z":…},…]` (or `x`, `y` for two axes).
fn points<const N: usize>(out: &mut String, key: &str, list: impl Iterator<Item = [f64; N]>) {
    const AXES: [&str; 3] = ["x", "y", "z"];
    out.push('"');
    out.push_str(key);
    out.push_str("\":[");
    for (i, p) in list.enumerate() {
        if i > 0 {
            out.push(',');
        }
        out.push('{');
        for (k, v) in p.iter().enumerate() {
            if k > 0 {
                out.push(',');
            }
            out.push('"');
            out.push_str(AXES[k]);
            out.push_str("\":");
            num(out, *v);
        }
        out.push('}');
    }
    out.push(']');
}

/// `"key":[i,j,…]`.
fn indices(out: &mut String, key: &str, list: &[u32]) {
    use std::fmt::Write as _;
    out.push('"');
    out.push_str(key);
    out.push_str("\":[");
    for (i, t) in list.iter().enumerate() {
        if i > 0 {
            out.push(',');
        }
        let _ = write!(out, "{t}");
    }
    out.push(']');
}

/// The 8 corners and 12 triangles of a collider box, outward.
fn box_piece(out: &mut String, min: [f64; 3], max: [f64; 3]) {
    // Faces -x, +x, -y, +y, -z, +z as two triangles each, counter-clockwise seen from outside.
    const TRIANGLES: [u32; 36] = [
        0, 4, 6, 0, 6, 2, // -x
        1, 3, 7, 1, 7, 5, // +x
        0, 1, 5, 0, 5, 4, // -y
        2, 6, 7, 2, 7, 3, // +y
        0, 2, 3, 0, 3, 1, // -z
        4, 5, 7, 4, 7, 6, // +z
    ];
    let c = |i: usize| {
        [
            if i & 1 == 0 { min[0] } else { max[0] },
            if i & 2 == 0 { min[1] } else { max[1] },
            if i & 4 == 0 { min[2] } else { max[2] },
        ]
    };
    out.push('{');
    points(out, "vertices", (0..8).map(c));
    out.push(',');
    indices(out, "triangles", &TRIANGLES);
    out.push('}');
}

/// The mesh dict of `<uid>.json`, written directly (the mesh is most of the file: a tree of
/// JSON values for it would cost more than making the asset).
pub fn asset_json(asset: &MadeAsset) -> String {
    use std::fmt::Write as _;
    let m = &asset.mesh;
    let [w, h, d] = m.size;
    let mut out = String::with_capacity(64 * m.vertices.len() + 1024);
    out.push('{');
    let _ = write!(
        out,
        "\"name\":{},\"receptacleCandidate\":{},\"albedoTexturePath\":\"{ALBEDO}\",\"normalTexturePath\":\"{NORMAL}\",",
        serde_json::Value::from(asset.uid.as_str()),
        asset.receptacle(),
    );
    points(&mut out, "vertices", m.vertices.iter().copied());
    out.push(',');
    indices(&mut out, "triangles", &m.triangles);
    out.push(',');
    points(&mut out, "normals", m.normals.iter().copied());
    out.push(',');
    points(&mut out, "uvs", m.uvs.iter().copied());
    out.push(',');
    // Where an agent checks that it sees the asset: the box's top corners, the centre of its
    // top and the middle of its front.
    let mut visibility = Vec::new();
    for x in [-w / 2.0, w / 2.0] {
        for z in [-d / 2.0, d / 2.0] {
            visibility.push([x, h / 2.0, z]);
        }
    }
    visibility.push([0.0, h / 2.0, 0.0]);
    visibility.push([0.0, 0.0, d / 2.0]);
    points(&mut out, "visibilityPoints", visibility.into_iter());
    out.push_str(",\"colliders\":[");
    for (i, (a, b)) in m.colliders.iter().enumerate() {
        if i > 0 {
            out.push(',');
        }
        box_piece(&mut out, *a, *b);
    }
    let _ = write!(
        out,
        "],\"physicalProperties\":{{\"mass\":{},\"drag\":0,\"angularDrag\":0.05,\"useGravity\":true,\"isKinematic\":{}}},\"yRotOffset\":0}}",
        round4(asset.mass_kg),
        asset.thor != super::Thor::Pickup,
    );
    out
}

/// `thor_metadata.json`.
pub fn thor_metadata(asset: &MadeAsset) -> Value {
    json!({"assetMetadata": {
        "primaryProperty": asset.thor.primary(),
        "secondaryProperties": asset.thor.secondary(),
    }})
}

/// The files of an asset's folder, by name, with their bytes.
pub fn files(asset: &MadeAsset) -> Vec<(String, Vec<u8>)> {
    let (w, h, px) = albedo_pixels(&asset.palette);
    let normal: Vec<u8> = [128u8, 128, 255].repeat((CELL_PX * CELL_PX) as usize);
    let mut json = asset_json(asset).into_bytes();
    json.push(b'\n');
    let mut meta = serde_json::to_vec_pretty(&thor_metadata(asset)).unwrap_or_default();
    meta.push(b'\n');
    vec![
        (format!("{}.json", asset.uid), json),
        (ALBEDO.to_string(), jpeg(w, h, &px)),
        (NORMAL.to_string(), jpeg(CELL_PX as u16, CELL_PX as u16, &normal)),
        (THOR_METADATA.to_string(), meta),
    ]
}

/// Writes the folders of `assets` into `dir` (made when missing). Each folder is written
/// whole into a temporary folder beside it and renamed into place; a folder already there
/// with the same files is left alone (a uid names its content). Returns the folders written.
pub fn write_all(dir: &Path, assets: &[&MadeAsset]) -> std::io::Result<Vec<PathBuf>> {
    std::fs::create_dir_all(dir)?;
    let mut written = Vec::new();
    for asset in assets {
        let target = dir.join(&asset.uid);
        let files = files(asset);
        if target.is_dir()
            && files.iter().all(|(name, bytes)| {
                std::fs::read(target.join(name)).is_ok_and(|old| old == *bytes)
            })
        {
            written.push(target);
            continue;
        }
        let tmp = tempfile::Builder::new().prefix(".holoc-asset-").tempdir_in(dir)?;
        for (name, bytes) in &files {
            std::fs::write(tmp.path().join(name), bytes)?;
        }
        if target.exists() {
            std::fs::remove_dir_all(&target)?;
        }
        let kept = tmp.keep();
        if let Err(e) = std::fs::rename(&kept, &target) {
            let _ = std::fs::remove_dir_all(&kept);
            return Err(e);
        }
        written.push(target);
    }
    Ok(written)
}

/// What [`read_asset`] reads of an asset folder.
#[derive(Clone, Debug, PartialEq)]
pub struct ReadAsset {
    /// Vertex positions.
    pub vertices: Vec<[f64; 3]>,
    /// Triangles, three indices each.
    pub triangles: Vec<u32>,
    /// The uv of each vertex.
    pub uvs: Vec<[f64; 2]>,
    /// The albedo texture's colour at each triangle's first vertex's uv, when the texture
    /// could be read; otherwise grey.
    pub triangle_rgb: Vec<[f64; 3]>,
    /// Its bounding box size `[x, y, z]`.
    pub size: [f64; 3],
    /// `receptacleCandidate`.
    pub receptacle: bool,
}

/// Why an asset folder cannot be read.
#[derive(Debug, thiserror::Error)]
pub enum ReadError {
    /// No `<uid>.json` in the folder.
    #[error("no {0} in the asset folder")]
    Missing(String),
    /// The file could not be read.
    #[error("cannot read {path}: {message}")]
    Io {
        /// The file.
        path: String,
        /// What went wrong.
        message: String,
    },
    /// The file is not a mesh dict.
    #[error("{path} is not a run-time asset: {message}")]
    Format {
        /// The file.
        path: String,
        /// What is wrong.
        message: String,
    },
}

/// Reads `<dir>/<uid>/<uid>.json` (the loader's first extension), checking what the loaders
/// rely on: `name` is the uid, every triangle index is a vertex, normals and uvs one per
/// vertex, the textures it names are in the folder.
pub fn read_asset(dir: &Path, uid: &str) -> Result<ReadAsset, ReadError> {
    let folder = dir.join(uid);
    let path = folder.join(format!("{uid}.json"));
    let shown = path.display().to_string();
    if !path.is_file() {
        return Err(ReadError::Missing(format!("{uid}.json")));
    }
    let read = crate::source::read_input(&path, MAX_ASSET_BYTES)
        .map_err(|e| ReadError::Io { path: shown.clone(), message: e.to_string() })?;
    let format = |message: String| ReadError::Format { path: shown.clone(), message };
    let value: Value = serde_json::from_slice(&read).map_err(|e| format(e.to_string()))?;
    if value.get("name").and_then(Value::as_str) != Some(uid) {
        return Err(format(format!("its `name` is not `{uid}`")));
    }
    let points = |key: &str, n: usize| -> Result<Vec<Vec<f64>>, ReadError> {
        let list = value
            .get(key)
            .and_then(Value::as_array)
            .ok_or_else(|| format(format!("no `{key}` list")))?;
        let axes: &[&str] = if n == 3 { &["x", "y", "z"] } else { &["x", "y"] };
        list.iter()
            .map(|p| {
                axes.iter()
                    .map(|a| p.get(*a).and_then(Value::as_f64).filter(|v| v.is_finite()))
                    .collect::<Option<Vec<f64>>>()
                    .ok_or_else(|| format(format!("a `{key}` entry is not a point")))
            })
            .collect()
    };
    let vertices: Vec<[f64; 3]> =
        points("vertices", 3)?.into_iter().map(|p| [p[0], p[1], p[2]]).collect();
    let normals = points("normals", 3)?;
    let uvs: Vec<[f64; 2]> = points("uvs", 2)?.into_iter().map(|p| [p[0], p[1]]).collect();
    if normals.len() != vertices.len() || uvs.len() != vertices.len() {
        return Err(format("`normals` and `uvs` must have one entry per vertex".to_string()));
    }
    let triangles: Vec<u32> = value
        .get("triangles")
        .and_then(Value::as_array)
        .ok_or_else(|| format("no `triangles` list".to_string()))?
        .iter()
        .map(|t| t.as_u64().filter(|&i| (i as usize) < vertices.len()).map(|i| i as u32))
        .collect::<Option<Vec<u32>>>()
        .ok_or_else(|| format("a triangle index is not a vertex".to_string()))?;
    if triangles.len() % 3 != 0 || triangles.is_empty() {
        return Err(format("`triangles` is not a list of triangles".to_string()));
    }
    for key in ["albedoTexturePath", "normalTexturePath"] {
        let name =
            value.get(key).and_then(Value::as_str).ok_or_else(|| format(format!("no `{key}`")))?;
        let file = Path::new(name).file_name().map(|f| folder.join(f));
        if !file.is_some_and(|f| f.is_file()) {
            return Err(format(format!("`{key}` names `{name}`, which is not in the folder")));
        }
    }
    let mut min = [f64::INFINITY; 3];
    let mut max = [f64::NEG_INFINITY; 3];
    for v in &vertices {
        for i in 0..3 {
            min[i] = min[i].min(v[i]);
            max[i] = max[i].max(v[i]);
        }
    }
    let size = if vertices.is_empty() { [0.0; 3] } else { [0, 1, 2].map(|i| max[i] - min[i]) };
    let albedo = value
        .get("albedoTexturePath")
        .and_then(Value::as_str)
        .and_then(|n| Path::new(n).file_name().map(|f| folder.join(f)));
    let texture = albedo.and_then(|p| decode_albedo(&p));
    let triangle_rgb = triangles
        .chunks_exact(3)
        .map(|t| {
            let uv = uvs[t[0] as usize];
            texture.as_ref().map_or([0.6; 3], |tex| tex.at(uv))
        })
        .collect();
    let receptacle = value.get("receptacleCandidate").and_then(Value::as_bool).unwrap_or(false);
    Ok(ReadAsset { vertices, triangles, uvs, triangle_rgb, size, receptacle })
}

/// An albedo texture read back: the colour at each cell centre is enough for a palette.
struct Albedo {
    width: usize,
    height: usize,
    rgb: Vec<u8>,
}

impl Albedo {
    fn at(&self, uv: [f64; 2]) -> [f64; 3] {
        let x = ((uv[0].clamp(0.0, 1.0) * self.width as f64) as usize).min(self.width - 1);
        let y_up = ((uv[1].clamp(0.0, 1.0) * self.height as f64) as usize).min(self.height - 1);
        let y = self.height - 1 - y_up;
        let i = (y * self.width + x) * 3;
        [0, 1, 2].map(|k| f64::from(self.rgb[i + k]) / 255.0)
    }
}

/// Decodes an albedo JPEG (`jpeg-decoder`); `None` when it is not a readable RGB or grey
/// JPEG of at most 4096 pixels a side (the asset then draws grey).
fn decode_albedo(path: &Path) -> Option<Albedo> {
    let meta = std::fs::metadata(path).ok()?;
    if !meta.is_file() || meta.len() > MAX_ASSET_BYTES {
        return None;
    }
    let bytes = std::fs::read(path).ok()?;
    let mut decoder = jpeg_decoder::Decoder::new(std::io::Cursor::new(bytes));
    decoder.read_info().ok()?;
    let info = decoder.info()?;
    if info.width == 0 || info.height == 0 || info.width > 4096 || info.height > 4096 {
        return None;
    }
    let pixels = decoder.decode().ok()?;
    let (width, height) = (usize::from(info.width), usize::from(info.height));
    let rgb = match info.pixel_format {
        jpeg_decoder::PixelFormat::RGB24 => pixels,
        jpeg_decoder::PixelFormat::L8 => pixels.iter().flat_map(|&g| [g, g, g]).collect(),
        _ => return None,
    };
    (rgb.len() >= width * height * 3).then_some(Albedo { width, height, rgb })
}

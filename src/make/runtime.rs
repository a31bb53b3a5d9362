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
///
/// The file is read in one pass into the vertex and index arrays (`MeshFile`), not into a
/// tree of JSON values; it accepts and refuses exactly what reading a `serde_json::Value`
/// and checking it did, with the same messages (a test compares the two on hostile files).
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
    let file: MeshFile = serde_json::from_slice(&read).map_err(|e| format(e.to_string()))?;
    drop(read);
    if file.name.as_deref() != Some(uid) {
        return Err(format(format!("its `name` is not `{uid}`")));
    }
    let vertices = point_list(file.vertices, "vertices", &format)?;
    let normals = point_list(file.normals, "normals", &format)?;
    let uvs = point_list(file.uvs, "uvs", &format)?;
    if normals.len() != vertices.len() || uvs.len() != vertices.len() {
        return Err(format("`normals` and `uvs` must have one entry per vertex".to_string()));
    }
    drop(normals);
    let triangles = match file.triangles {
        Indices::NotAList => return Err(format("no `triangles` list".to_string())),
        Indices::BadEntry => return Err(format("a triangle index is not a vertex".to_string())),
        Indices::Good(list) => list,
    };
    if triangles.iter().any(|&i| i as usize >= vertices.len()) {
        return Err(format("a triangle index is not a vertex".to_string()));
    }
    if triangles.len() % 3 != 0 || triangles.is_empty() {
        return Err(format("`triangles` is not a list of triangles".to_string()));
    }
    let mut albedo = None;
    for (key, name) in [("albedoTexturePath", &file.albedo), ("normalTexturePath", &file.normal)] {
        let name = name.as_deref().ok_or_else(|| format(format!("no `{key}`")))?;
        let file = Path::new(name).file_name().map(|f| folder.join(f));
        if !file.as_ref().is_some_and(|f| f.is_file()) {
            return Err(format(format!("`{key}` names `{name}`, which is not in the folder")));
        }
        if key == "albedoTexturePath" {
            albedo = file;
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
    let texture = albedo.and_then(|p| decode_albedo(&p));
    let triangle_rgb = triangles
        .chunks_exact(3)
        .map(|t| {
            let uv = uvs[t[0] as usize];
            texture.as_ref().map_or([0.6; 3], |tex| tex.at(uv))
        })
        .collect();
    let receptacle = file.receptacle.unwrap_or(false);
    Ok(ReadAsset { vertices, triangles, uvs, triangle_rgb, size, receptacle })
}

/// The points of a member, or why not (the words of the reader on a `Value`).
fn point_list<const N: usize>(
    list: Points<N>,
    key: &str,
    format: &dyn Fn(String) -> ReadError,
) -> Result<Vec<[f64; N]>, ReadError> {
    match list {
        Points::NotAList => Err(format(format!("no `{key}` list"))),
        Points::BadEntry => Err(format(format!("a `{key}` entry is not a point"))),
        Points::Good(list) => Ok(list),
    }
}

/// What [`read_asset`] takes of a mesh file, read in one pass with serde visitors (no tree of
/// JSON values: the mesh is most of the file). The visitors never fail on their own: a member
/// of the wrong shape is recorded as such and every check is made afterwards, in the order
/// and with the words of the checks on a `serde_json::Value`, so that the parser's errors
/// (syntax, numbers out of range, strings that are not Unicode, nesting) are exactly those of
/// parsing a `Value` and the checks give the same answer. Members it does not read are still
/// parsed in full (`Skip`), never skipped by a looser scan.
#[derive(Default)]
struct MeshFile {
    name: Option<String>,
    vertices: Points<3>,
    normals: Points<3>,
    uvs: Points<2>,
    triangles: Indices,
    albedo: Option<String>,
    normal: Option<String>,
    receptacle: Option<bool>,
}

/// A member that should be a list of points: absent or not a list, a list with an entry that
/// is not a point, or its points.
#[derive(Default)]
enum Points<const N: usize> {
    #[default]
    NotAList,
    BadEntry,
    Good(Vec<[f64; N]>),
}

/// A member that should be a list of vertex indices: absent or not a list, a list with an
/// entry that is not an index a `u32` holds (never a vertex), or its indices.
#[derive(Default)]
enum Indices {
    #[default]
    NotAList,
    BadEntry,
    Good(Vec<u32>),
}

/// Any JSON value, parsed in full (as a `Value` would be) and dropped.
struct Skip;

impl<'de> serde::Deserialize<'de> for Skip {
    fn deserialize<D: serde::Deserializer<'de>>(d: D) -> Result<Self, D::Error> {
        d.deserialize_any(SkipVisitor)
    }
}

struct SkipVisitor;

impl<'de> serde::de::Visitor<'de> for SkipVisitor {
    type Value = Skip;
    fn expecting(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str("any JSON value")
    }
    fn visit_bool<E>(self, _: bool) -> Result<Skip, E> {
        Ok(Skip)
    }
    fn visit_i64<E>(self, _: i64) -> Result<Skip, E> {
        Ok(Skip)
    }
    fn visit_u64<E>(self, _: u64) -> Result<Skip, E> {
        Ok(Skip)
    }
    fn visit_f64<E>(self, _: f64) -> Result<Skip, E> {
        Ok(Skip)
    }
    fn visit_str<E>(self, _: &str) -> Result<Skip, E> {
        Ok(Skip)
    }
    fn visit_unit<E>(self) -> Result<Skip, E> {
        Ok(Skip)
    }
    fn visit_seq<A: serde::de::SeqAccess<'de>>(self, mut seq: A) -> Result<Skip, A::Error> {
        while seq.next_element::<Skip>()?.is_some() {}
        Ok(Skip)
    }
    fn visit_map<A: serde::de::MapAccess<'de>>(self, mut map: A) -> Result<Skip, A::Error> {
        while map.next_entry::<Skip, Skip>()?.is_some() {}
        Ok(Skip)
    }
}

/// A value kept only when it is of one JSON kind (`Value::as_str`, `as_bool`, `as_f64`,
/// `as_u64`); any other is parsed in full and gives `None`.
struct Kind<T>(Option<T>);

impl<'de, T: KindOf> serde::Deserialize<'de> for Kind<T> {
    fn deserialize<D: serde::Deserializer<'de>>(d: D) -> Result<Self, D::Error> {
        d.deserialize_any(KindVisitor(std::marker::PhantomData))
    }
}

/// What [`Kind`] keeps of each JSON kind.
trait KindOf: Sized {
    fn of_str(_: &str) -> Option<Self> {
        None
    }
    fn of_bool(_: bool) -> Option<Self> {
        None
    }
    fn of_u64(_: u64) -> Option<Self> {
        None
    }
    fn of_i64(_: i64) -> Option<Self> {
        None
    }
    fn of_f64(_: f64) -> Option<Self> {
        None
    }
}

impl KindOf for String {
    fn of_str(s: &str) -> Option<Self> {
        Some(s.to_string())
    }
}

impl KindOf for bool {
    fn of_bool(b: bool) -> Option<Self> {
        Some(b)
    }
}

/// A coordinate: any JSON number, as `Value::as_f64` reads it.
impl KindOf for f64 {
    fn of_u64(v: u64) -> Option<Self> {
        Some(v as f64)
    }
    fn of_i64(v: i64) -> Option<Self> {
        Some(v as f64)
    }
    fn of_f64(v: f64) -> Option<Self> {
        Some(v)
    }
}

/// A vertex index: a JSON integer `Value::as_u64` reads (a non-negative one, not written as a
/// float), when a `u32` holds it.
impl KindOf for u32 {
    fn of_u64(v: u64) -> Option<Self> {
        u32::try_from(v).ok()
    }
    fn of_i64(v: i64) -> Option<Self> {
        u32::try_from(v).ok()
    }
}

struct KindVisitor<T>(std::marker::PhantomData<T>);

impl<'de, T: KindOf> serde::de::Visitor<'de> for KindVisitor<T> {
    type Value = Kind<T>;
    fn expecting(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str("any JSON value")
    }
    fn visit_bool<E>(self, v: bool) -> Result<Kind<T>, E> {
        Ok(Kind(T::of_bool(v)))
    }
    fn visit_i64<E>(self, v: i64) -> Result<Kind<T>, E> {
        Ok(Kind(T::of_i64(v)))
    }
    fn visit_u64<E>(self, v: u64) -> Result<Kind<T>, E> {
        Ok(Kind(T::of_u64(v)))
    }
    fn visit_f64<E>(self, v: f64) -> Result<Kind<T>, E> {
        Ok(Kind(T::of_f64(v)))
    }
    fn visit_str<E>(self, v: &str) -> Result<Kind<T>, E> {
        Ok(Kind(T::of_str(v)))
    }
    fn visit_unit<E>(self) -> Result<Kind<T>, E> {
        Ok(Kind(None))
    }
    fn visit_seq<A: serde::de::SeqAccess<'de>>(self, seq: A) -> Result<Kind<T>, A::Error> {
        SkipVisitor.visit_seq(seq).map(|_| Kind(None))
    }
    fn visit_map<A: serde::de::MapAccess<'de>>(self, map: A) -> Result<Kind<T>, A::Error> {
        SkipVisitor.visit_map(map).map(|_| Kind(None))
    }
}

/// One entry of a point list: a map with a finite number at each axis (`x`, `y` and, for
/// three, `z`; other members are allowed), else `None`.
struct Point<const N: usize>(Option<[f64; N]>);

impl<'de, const N: usize> serde::Deserialize<'de> for Point<N> {
    fn deserialize<D: serde::Deserializer<'de>>(d: D) -> Result<Self, D::Error> {
        d.deserialize_any(PointVisitor::<N>)
    }
}

struct PointVisitor<const N: usize>;

impl<'de, const N: usize> serde::de::Visitor<'de> for PointVisitor<N> {
    type Value = Point<N>;
    fn expecting(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str("any JSON value")
    }
    fn visit_bool<E>(self, _: bool) -> Result<Point<N>, E> {
        Ok(Point(None))
    }
    fn visit_i64<E>(self, _: i64) -> Result<Point<N>, E> {
        Ok(Point(None))
    }
    fn visit_u64<E>(self, _: u64) -> Result<Point<N>, E> {
        Ok(Point(None))
    }
    fn visit_f64<E>(self, _: f64) -> Result<Point<N>, E> {
        Ok(Point(None))
    }
    fn visit_str<E>(self, _: &str) -> Result<Point<N>, E> {
        Ok(Point(None))
    }
    fn visit_unit<E>(self) -> Result<Point<N>, E> {
        Ok(Point(None))
    }
    fn visit_seq<A: serde::de::SeqAccess<'de>>(self, seq: A) -> Result<Point<N>, A::Error> {
        SkipVisitor.visit_seq(seq).map(|_| Point(None))
    }
    fn visit_map<A: serde::de::MapAccess<'de>>(self, mut map: A) -> Result<Point<N>, A::Error> {
        const AXES: [&str; 3] = ["x", "y", "z"];
        let mut p: [Option<f64>; N] = [None; N];
        while let Some(key) = map.next_key::<Key>()? {
            match AXES[..N].iter().position(|a| *a == key.0.as_ref()) {
                // A later member of the same name replaces an earlier one, as in a `Value`.
                Some(i) => p[i] = map.next_value::<Kind<f64>>()?.0.filter(|v| v.is_finite()),
                None => {
                    map.next_value::<Skip>()?;
                }
            }
        }
        let mut out = [0.0; N];
        for (o, v) in out.iter_mut().zip(p) {
            match v {
                Some(v) => *o = v,
                None => return Ok(Point(None)),
            }
        }
        Ok(Point(Some(out)))
    }
}

/// A member name, borrowed from the file when it holds no escape.
struct Key<'de>(std::borrow::Cow<'de, str>);

impl<'de> serde::Deserialize<'de> for Key<'de> {
    fn deserialize<D: serde::Deserializer<'de>>(d: D) -> Result<Self, D::Error> {
        struct V;
        impl<'de> serde::de::Visitor<'de> for V {
            type Value = Key<'de>;
            fn expecting(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
                f.write_str("a member name")
            }
            fn visit_borrowed_str<E>(self, v: &'de str) -> Result<Key<'de>, E> {
                Ok(Key(std::borrow::Cow::Borrowed(v)))
            }
            fn visit_str<E>(self, v: &str) -> Result<Key<'de>, E> {
                Ok(Key(std::borrow::Cow::Owned(v.to_string())))
            }
        }
        d.deserialize_str(V)
    }
}

/// A list of points, of indices: `NotAList` for any other JSON value.
struct List<T>(T);

impl<'de, const N: usize> serde::Deserialize<'de> for List<Points<N>> {
    fn deserialize<D: serde::Deserializer<'de>>(d: D) -> Result<Self, D::Error> {
        struct V<const N: usize>;
        impl<'de, const N: usize> serde::de::Visitor<'de> for V<N> {
            type Value = List<Points<N>>;
            fn expecting(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
                f.write_str("any JSON value")
            }
            fn visit_bool<E>(self, _: bool) -> Result<Self::Value, E> {
                Ok(List(Points::NotAList))
            }
            fn visit_i64<E>(self, _: i64) -> Result<Self::Value, E> {
                Ok(List(Points::NotAList))
            }
            fn visit_u64<E>(self, _: u64) -> Result<Self::Value, E> {
                Ok(List(Points::NotAList))
            }
            fn visit_f64<E>(self, _: f64) -> Result<Self::Value, E> {
                Ok(List(Points::NotAList))
            }
            fn visit_str<E>(self, _: &str) -> Result<Self::Value, E> {
                Ok(List(Points::NotAList))
            }
            fn visit_unit<E>(self) -> Result<Self::Value, E> {
                Ok(List(Points::NotAList))
            }
            fn visit_map<A: serde::de::MapAccess<'de>>(
                self,
                map: A,
            ) -> Result<Self::Value, A::Error> {
                SkipVisitor.visit_map(map).map(|_| List(Points::NotAList))
            }
            fn visit_seq<A: serde::de::SeqAccess<'de>>(
                self,
                mut seq: A,
            ) -> Result<Self::Value, A::Error> {
                let mut list = Vec::with_capacity(seq.size_hint().unwrap_or(0).min(4096));
                let mut bad = false;
                while let Some(p) = seq.next_element::<Point<N>>()? {
                    match p.0 {
                        Some(p) if !bad => list.push(p),
                        _ => bad = true,
                    }
                }
                Ok(List(if bad { Points::BadEntry } else { Points::Good(list) }))
            }
        }
        d.deserialize_any(V::<N>)
    }
}

impl<'de> serde::Deserialize<'de> for List<Indices> {
    fn deserialize<D: serde::Deserializer<'de>>(d: D) -> Result<Self, D::Error> {
        struct V;
        impl<'de> serde::de::Visitor<'de> for V {
            type Value = List<Indices>;
            fn expecting(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
                f.write_str("any JSON value")
            }
            fn visit_bool<E>(self, _: bool) -> Result<Self::Value, E> {
                Ok(List(Indices::NotAList))
            }
            fn visit_i64<E>(self, _: i64) -> Result<Self::Value, E> {
                Ok(List(Indices::NotAList))
            }
            fn visit_u64<E>(self, _: u64) -> Result<Self::Value, E> {
                Ok(List(Indices::NotAList))
            }
            fn visit_f64<E>(self, _: f64) -> Result<Self::Value, E> {
                Ok(List(Indices::NotAList))
            }
            fn visit_str<E>(self, _: &str) -> Result<Self::Value, E> {
                Ok(List(Indices::NotAList))
            }
            fn visit_unit<E>(self) -> Result<Self::Value, E> {
                Ok(List(Indices::NotAList))
            }
            fn visit_map<A: serde::de::MapAccess<'de>>(
                self,
                map: A,
            ) -> Result<Self::Value, A::Error> {
                SkipVisitor.visit_map(map).map(|_| List(Indices::NotAList))
            }
            fn visit_seq<A: serde::de::SeqAccess<'de>>(
                self,
                mut seq: A,
            ) -> Result<Self::Value, A::Error> {
                let mut list = Vec::with_capacity(seq.size_hint().unwrap_or(0).min(4096));
                let mut bad = false;
                while let Some(i) = seq.next_element::<Kind<u32>>()? {
                    match i.0 {
                        Some(i) if !bad => list.push(i),
                        _ => bad = true,
                    }
                }
                Ok(List(if bad { Indices::BadEntry } else { Indices::Good(list) }))
            }
        }
        d.deserialize_any(V)
    }
}

impl<'de> serde::Deserialize<'de> for MeshFile {
    fn deserialize<D: serde::Deserializer<'de>>(d: D) -> Result<Self, D::Error> {
        struct V;
        impl<'de> serde::de::Visitor<'de> for V {
            type Value = MeshFile;
            fn expecting(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
                f.write_str("any JSON value")
            }
            // A file that is not an object has none of the members.
            fn visit_bool<E>(self, _: bool) -> Result<MeshFile, E> {
                Ok(MeshFile::default())
            }
            fn visit_i64<E>(self, _: i64) -> Result<MeshFile, E> {
                Ok(MeshFile::default())
            }
            fn visit_u64<E>(self, _: u64) -> Result<MeshFile, E> {
                Ok(MeshFile::default())
            }
            fn visit_f64<E>(self, _: f64) -> Result<MeshFile, E> {
                Ok(MeshFile::default())
            }
            fn visit_str<E>(self, _: &str) -> Result<MeshFile, E> {
                Ok(MeshFile::default())
            }
            fn visit_unit<E>(self) -> Result<MeshFile, E> {
                Ok(MeshFile::default())
            }
            fn visit_seq<A: serde::de::SeqAccess<'de>>(self, seq: A) -> Result<MeshFile, A::Error> {
                SkipVisitor.visit_seq(seq).map(|_| MeshFile::default())
            }
            fn visit_map<A: serde::de::MapAccess<'de>>(
                self,
                mut map: A,
            ) -> Result<MeshFile, A::Error> {
                let mut file = MeshFile::default();
                // A later member of the same name replaces an earlier one, as in a `Value`.
                while let Some(key) = map.next_key::<Key>()? {
                    match key.0.as_ref() {
                        "name" => file.name = map.next_value::<Kind<String>>()?.0,
                        "vertices" => file.vertices = map.next_value::<List<Points<3>>>()?.0,
                        "normals" => file.normals = map.next_value::<List<Points<3>>>()?.0,
                        "uvs" => file.uvs = map.next_value::<List<Points<2>>>()?.0,
                        "triangles" => file.triangles = map.next_value::<List<Indices>>()?.0,
                        "albedoTexturePath" => file.albedo = map.next_value::<Kind<String>>()?.0,
                        "normalTexturePath" => file.normal = map.next_value::<Kind<String>>()?.0,
                        "receptacleCandidate" => {
                            file.receptacle = map.next_value::<Kind<bool>>()?.0;
                        }
                        _ => {
                            map.next_value::<Skip>()?;
                        }
                    }
                }
                Ok(file)
            }
        }
        d.deserialize_any(V)
    }
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

#[cfg(test)]
mod tests {
    use super::*;

    /// The reader before `MeshFile`: a `serde_json::Value` checked member by member, kept to
    /// compare the typed reader with. Reads `<dir>/<uid>/<uid>.json` (the loader's first extension), checking what the loaders
    /// rely on: `name` is the uid, every triangle index is a vertex, normals and uvs one per
    /// vertex, the textures it names are in the folder.
    fn read_asset_value(dir: &Path, uid: &str) -> Result<ReadAsset, ReadError> {
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
            let name = value
                .get(key)
                .and_then(Value::as_str)
                .ok_or_else(|| format(format!("no `{key}`")))?;
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

    /// The smallest made asset's folder, written into a new temporary folder.
    fn folder() -> (tempfile::TempDir, String, String) {
        let made: Vec<_> = super::super::KINDS
            .iter()
            .map(|kind| {
                super::super::make(&super::super::Request {
                    kind,
                    size_m: None,
                    description: kind.phrases[0].into(),
                })
            })
            .collect();
        let small = made.iter().min_by_key(|m| asset_json(m).len()).expect("a kind");
        let dir = tempfile::tempdir().expect("a temporary folder");
        write_all(dir.path(), &[small]).expect("written");
        let text = asset_json(small);
        (dir, small.uid.clone(), text)
    }

    /// Both readers on `text` as the asset's file: the same asset or the same message.
    fn same(dir: &Path, uid: &str, text: &[u8]) -> Result<(), String> {
        std::fs::write(dir.join(uid).join(format!("{uid}.json")), text).expect("written");
        let typed = read_asset(dir, uid).map_err(|e| e.to_string());
        let value = read_asset_value(dir, uid).map_err(|e| e.to_string());
        if typed == value {
            Ok(())
        } else {
            Err(format!("{}\ntyped: {typed:?}\nvalue: {value:?}", String::from_utf8_lossy(text)))
        }
    }

    #[test]
    fn the_typed_reader_reads_a_made_asset_as_the_value_reader_did() {
        let (dir, uid, text) = folder();
        let read = read_asset(dir.path(), &uid).expect("reads");
        assert_eq!(Ok(read), read_asset_value(dir.path(), &uid).map_err(|e| e.to_string()));
        assert!(same(dir.path(), &uid, text.as_bytes()).is_ok());
    }

    #[test]
    fn the_typed_reader_refuses_what_the_value_reader_did_with_its_words() {
        // The bytes random edits write.
        const ALPHABET: &[u8] = b"{}[],:\"\\0123456789-+.eExyz \n\x00\xff";
        let (dir, uid, text) = folder();
        let mut cases: Vec<Vec<u8>> = Vec::new();
        let mut edit = |from: &str, to: &str| {
            assert!(text.contains(from), "{from}");
            cases.push(text.replacen(from, to, 1).into_bytes());
        };
        // Members missing, of the wrong kind, repeated.
        for key in ["name", "vertices", "normals", "uvs", "triangles", "albedoTexturePath"] {
            edit(&format!("\"{key}\":"), &format!("\"{key}_\":"));
            edit(&format!("\"{key}\":"), &format!("\"{key}\":7,\"{key}_\":"));
            edit(&format!("\"{key}\":"), &format!("\"{key}\":{{}},\"{key}_\":"));
            edit(&format!("\"{key}\":"), &format!("\"{key}\":null,\"{key}\":"));
            edit(&format!("\"{key}\":"), &format!("\"{key}\":\"x\",\"{key}_\":"));
        }
        edit("\"normalTexturePath\":", "\"normalTexturePath_\":");
        edit("\"normalTexturePath\":\"normal.jpg\"", "\"normalTexturePath\":\"other.jpg\"");
        edit("\"albedoTexturePath\":\"albedo.jpg\"", "\"albedoTexturePath\":\"../\"");
        edit("\"albedoTexturePath\":\"albedo.jpg\"", "\"albedoTexturePath\":\"sub/albedo.jpg\"");
        edit("\"name\":\"", "\"name\":\"x");
        edit("\"receptacleCandidate\":", "\"receptacleCandidate\":1,\"r\":");
        edit("\"receptacleCandidate\":", "\"receptacleCandidate\":true,\"rc\":");
        // Points: not maps, an axis missing, of the wrong kind, repeated, extra members.
        for key in ["vertices", "normals", "uvs"] {
            let at = format!("\"{key}\":[{{");
            edit(&at, &format!("\"{key}\":[[1,2,3],{{"));
            edit(&at, &format!("\"{key}\":[{{\"x\":1,\"y\":2}},{{"));
            edit(&at, &format!("\"{key}\":[{{\"x\":1,\"y\":2,\"z\":\"3\"}},{{"));
            edit(&at, &format!("\"{key}\":[{{\"x\":1,\"y\":2,\"z\":3,\"w\":[{{}}]}},{{"));
            edit(&at, &format!("\"{key}\":[{{\"x\":\"1\",\"x\":1,\"y\":-2,\"z\":3e2}},{{"));
            edit(&at, &format!("\"{key}\":[{{\"x\":1,\"y\":2,\"z\":3,\"x\":null}},{{"));
            edit(&at, &format!("\"{key}\":[7,{{"));
            edit(&format!("\"{key}\":["), &format!("\"{key}\":[],\"{key}_\":["));
        }
        // Indices: floats, negative, past the vertices, past `u32`, not triangles, none.
        for bad in ["1.0", "-1", "100000", "4294967296", "18446744073709551616", "\"0\"", "null"] {
            edit("\"triangles\":[", &format!("\"triangles\":[{bad},"));
        }
        edit("\"triangles\":[", "\"triangles\":[0,");
        edit("\"triangles\":[", "\"triangles\":[],\"t\":[");
        // The parser's errors: out of range, not Unicode, lone surrogates, nesting, trailing.
        edit("\"yRotOffset\":0", "\"yRotOffset\":1e400");
        edit("\"yRotOffset\":0", "\"yRotOffset\":\"\\ud800\"");
        edit("\"yRotOffset\":0", "\"yRotOffset\":\"\\ud800\\u0041\"");
        edit("\"yRotOffset\":0", "\"yRotOffset\":\"\\x\"");
        edit(
            "\"yRotOffset\":0",
            &format!("\"yRotOffset\":{}0{}", "[".repeat(200), "]".repeat(200)),
        );
        edit(
            "\"yRotOffset\":0",
            &format!("\"yRotOffset\":{}0{}", "[".repeat(120), "]".repeat(120)),
        );
        edit("\"yRotOffset\":0}", "\"yRotOffset\":0}}");
        edit("\"yRotOffset\":0}", "\"yRotOffset\":0} x");
        edit("\"yRotOffset\":0}", "\"yRotOffset\":0,}");
        edit("\"yRotOffset\":0", "\"yRotOffset\":01");
        edit("\"yRotOffset\":0", "\"yRotOffset\":-");
        edit("\"yRotOffset\":0", "\"yRotOffset\":tru");
        edit("\"yRotOffset\":0", "\"yRotOffset\":\"\u{1}\"");
        let mut not_utf8 =
            text.replacen("\"yRotOffset\":0", "\"yRotOffset\":\"\u{e9}\"", 1).into_bytes();
        let at = not_utf8.iter().position(|&b| b == 0xc3).expect("the é");
        not_utf8[at] = 0xff;
        cases.push(not_utf8.clone());
        not_utf8.truncate(at + 1);
        cases.push(not_utf8);
        // Not an object at all.
        for whole in
            ["", " ", "[]", "[1,{\"name\":1}]", "\"x\"", "1", "null", "true", "{}", "{\"name\":"]
        {
            cases.push(whole.as_bytes().to_vec());
        }
        // Every prefix of the file (a write cut short) and bytes changed at random.
        let bytes = text.as_bytes();
        for end in (0..bytes.len()).step_by(7) {
            cases.push(bytes[..end].to_vec());
        }
        let mut state: u64 = 0x9e37_79b9_7f4a_7c15;
        let mut next = move || {
            state ^= state << 13;
            state ^= state >> 7;
            state ^= state << 17;
            state
        };
        for _ in 0..1500 {
            let mut mutant = bytes.to_vec();
            for _ in 0..=(next() % 3) {
                let at = (next() % mutant.len() as u64) as usize;
                mutant[at] = ALPHABET[(next() % ALPHABET.len() as u64) as usize];
            }
            cases.push(mutant);
        }
        let differ: Vec<String> =
            cases.iter().filter_map(|c| same(dir.path(), &uid, c).err()).take(3).collect();
        assert!(differ.is_empty(), "{}", differ.join("\n\n"));
        // The cases reach every check: the messages, their positions left out.
        let mut kinds = std::collections::BTreeSet::new();
        for c in &cases {
            std::fs::write(dir.path().join(&uid).join(format!("{uid}.json")), c).expect("written");
            if let Err(e) = read_asset(dir.path(), &uid) {
                let e = e.to_string();
                let e = e.split(" at line ").next().unwrap_or_default().to_string();
                kinds.insert(e.rsplit(": ").next().unwrap_or_default().to_string());
            }
        }
        assert!(kinds.len() >= 20, "{kinds:#?}");
    }
}

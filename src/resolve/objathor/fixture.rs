//! Writes objathor version folders for tests and benchmarks: a small hand-made one whose
//! feature vectors are chosen so that rankings, thresholds, the size term and the filters can be
//! asserted exactly ([`write_fixture`]), and a large synthetic one ([`write_synthetic`]).
//!
//! The feature vectors have [`FIXTURE_DIM`] components. Axis `k` stands for one kind of thing
//! (0 cat tower, 1 mirror, 2 curtains, 3 whiteboard, 4 lamp, 5 cat toy, 6 sofa, painting and
//! photo frame); axis 7 is the rest. A CLIP text row is the unit vector of its kind's axis; an image view is `axis + b ×
//! e7`, whose cosine with the axis is `1 / √(1 + b²)`: b = 2.5 → 0.3714, 2.75 → 0.3417,
//! 3 → 0.3162, 3.25 → 0.2941 (all exact in float16).

use std::io::Write as _;
use std::path::{Path, PathBuf};

use serde_json::{json, Value};

use super::pickle::{f32_to_f16, write, NumpyModules, Value as PickleValue};

/// Length of the fixture's feature vectors.
pub const FIXTURE_DIM: usize = 8;

/// The fixture's version name.
pub const FIXTURE_VERSION: &str = "2023_09_23";

/// One fixture asset: a name for tests, its uid, its annotation, its kind axis and the `b` of
/// its three image views.
pub struct FixtureAsset {
    /// A short name tests use.
    pub name: &'static str,
    /// Its uid (32 hex digits).
    pub uid: &'static str,
    /// The axis of its kind.
    pub axis: usize,
    /// The `b` of each view (see the module's documentation).
    pub views: [f32; 3],
}

/// The fixture's assets. `whiteboard`'s folder is missing from `assets/`; `blurry_painting`
/// has a `blender_thor_similarity` of 0.2 (the original never takes it); `photo_frame` can
/// break (its glass); `looking_glass` is a mirror (WordNet's `mirror.n.01`) that shares no word
/// with `mirror`.
pub const FIXTURE_ASSETS: &[FixtureAsset] = &[
    FixtureAsset {
        name: "cat_tower",
        uid: "0a0c1d5e7f9a4b3c8d2e6f1a3b5c7d90",
        axis: 0,
        views: [3.25, 2.5, 3.0],
    },
    FixtureAsset {
        name: "cat_tree",
        uid: "1b1d2e6f8a0b4c5d9e3f7a2b4c6d8e01",
        axis: 0,
        views: [2.75, 3.0, 3.25],
    },
    FixtureAsset {
        name: "cat_bed",
        uid: "2c2e3f7a9b1c4d6e8f4a8b3c5d7e9f12",
        axis: 0,
        views: [3.25, 3.25, 3.25],
    },
    FixtureAsset {
        name: "round_mirror",
        uid: "3d3f4a8b0c2d4e7f9a5b9c4d6e8f0a23",
        axis: 1,
        views: [2.75, 2.75, 3.0],
    },
    FixtureAsset {
        name: "mirror_box",
        uid: "4e4a5b9c1d3e4f8a0b6c0d5e7f9a1b34",
        axis: 1,
        views: [2.5, 2.5, 2.5],
    },
    FixtureAsset {
        name: "linen_curtains",
        uid: "5f5b6c0d2e4f4a9b1c7d1e6f8a0b2c45",
        axis: 2,
        views: [2.75, 2.75, 3.0],
    },
    FixtureAsset {
        name: "tall_curtains",
        uid: "6a6c7d1e3f5a4b0c2d8e2f7a9b1c3d56",
        axis: 2,
        views: [2.5, 2.5, 2.5],
    },
    FixtureAsset {
        name: "window_frame",
        uid: "7b7d8e2f4a6b4c1d3e9f3a8b0c2d4e67",
        axis: 1,
        views: [2.5, 2.5, 2.5],
    },
    FixtureAsset {
        name: "huge_sofa",
        uid: "8c8e9f3a5b7c4d2e4f0a4b9c1d3e5f78",
        axis: 6,
        views: [2.5, 2.5, 2.5],
    },
    FixtureAsset {
        name: "whiteboard",
        uid: "9d9f0a4b6c8d4e3f5a1b5c0d2e4f6a89",
        axis: 3,
        views: [2.5, 2.75, 2.75],
    },
    FixtureAsset {
        name: "pendant_lamp",
        uid: "a0a1b5c7d9e04f4a6b2c6d1e3f5a7b9a",
        axis: 4,
        views: [2.75, 2.75, 2.75],
    },
    FixtureAsset {
        name: "cat_figurine",
        uid: "b1b2c6d8e0f14a5b7c3d7e2f4a6b8c0b",
        axis: 5,
        views: [2.5, 3.0, 3.0],
    },
    FixtureAsset {
        name: "projector",
        uid: "c2c3d7e9f1a24b6c8d4e8f3a5b7c9d1c",
        axis: 4,
        views: [2.5, 2.5, 2.5],
    },
    FixtureAsset {
        name: "abstract_painting",
        uid: "d3d4e8f0a2b34c7d9e5f9a4b6c8d0e2d",
        axis: 6,
        views: [2.5, 2.5, 2.75],
    },
    FixtureAsset {
        name: "photo_frame",
        uid: "e4e5f9a1b3c44d8e0f6a0b5c7d9e1f3e",
        axis: 6,
        views: [2.5, 2.75, 2.75],
    },
    FixtureAsset {
        name: "looking_glass",
        uid: "a6a7b1c3d5e64f0a2b8c2d7e9f1a3b5a",
        axis: 1,
        views: [3.0, 3.0, 3.0],
    },
    FixtureAsset {
        name: "blurry_painting",
        uid: "f5f6a0b2c4d54e9f1a7b1c6d8e0f2a4f",
        axis: 6,
        views: [2.5, 2.5, 2.5],
    },
];

/// The fixture asset named `name`'s uid.
pub fn fixture_uid(name: &str) -> &'static str {
    FIXTURE_ASSETS.iter().find(|a| a.name == name).map_or("", |a| a.uid)
}

fn license(user: &str) -> Value {
    json!({
        "license": "by",
        "uri": format!("https://api.sketchfab.com/v3/models/{user}"),
        "creator_username": user,
        "creator_display_name": user.to_uppercase(),
        "creator_profile_url": format!("https://sketchfab.com/{user}"),
    })
}

/// The annotation entry of each fixture asset: every field objathor writes, the three shapes of
/// bounding box, and both nestings (`annotations` or the fields at the top).
fn annotation(name: &str, uid: &str) -> Value {
    let xyz = |x: f64, y: f64, z: f64| json!({"x": x, "y": y, "z": z});
    let (category, description, flags, bbox): (&str, &str, [bool; 4], Value) = match name {
        "cat_tower" => (
            "cat tower",
            "a carpeted cat tower with three platforms",
            [true, false, false, false],
            xyz(0.6, 1.5, 0.6),
        ),
        "cat_tree" => (
            "cat tree",
            "a tall sisal scratching post for cats",
            [true, false, false, false],
            json!({"size": xyz(0.5, 1.8, 0.5)}),
        ),
        "cat_bed" => (
            "cat bed",
            "a round plush bed for a cat",
            [true, false, true, false],
            json!({"min": xyz(-0.25, 0.0, -0.25), "max": xyz(0.25, 0.2, 0.25)}),
        ),
        "round_mirror" => (
            "mirror",
            "a round wall mirror with a brass rim",
            [false, true, false, false],
            json!({"min": xyz(-0.4, -0.4, -0.015), "max": xyz(0.4, 0.4, 0.015)}),
        ),
        "mirror_box" => (
            "mirror",
            "a deep mirrored wall cabinet",
            [false, true, false, false],
            xyz(0.3, 0.3, 1.2),
        ),
        "linen_curtains" => (
            "curtains",
            "long linen curtains on a rod",
            [false, true, false, false],
            xyz(1.5, 1.9, 0.1),
        ),
        "tall_curtains" => (
            "curtains",
            "floor to ceiling velvet curtains",
            [false, true, false, false],
            xyz(1.5, 2.4, 0.1),
        ),
        "window_frame" => (
            "window frame",
            "a wooden window frame",
            [true, true, false, false],
            xyz(1.0, 1.2, 0.1),
        ),
        "huge_sofa" => {
            ("sofa", "a huge sectional sofa", [true, false, false, false], xyz(4.5, 0.9, 2.0))
        }
        "whiteboard" => (
            "whiteboard",
            "a whiteboard with an aluminium frame",
            [false, true, false, false],
            xyz(1.8, 1.2, 0.05),
        ),
        "pendant_lamp" => (
            "pendant lamp",
            "a pendant lamp with a metal shade",
            [false, false, false, true],
            xyz(0.4, 0.6, 0.4),
        ),
        "cat_figurine" => (
            "cat figurine",
            "a small ceramic cat figurine",
            [false, false, true, false],
            xyz(0.1, 0.15, 0.08),
        ),
        "photo_frame" => (
            "picture frame",
            "a small standing photo frame of dark wood",
            [false, false, true, false],
            xyz(0.2, 0.25, 0.06),
        ),
        "abstract_painting" => (
            "painting",
            "an abstract painting in a thin black frame",
            [false, true, false, false],
            xyz(0.9, 0.7, 0.04),
        ),
        "looking_glass" => (
            "looking glass",
            "an ornate gilded looking glass",
            [false, true, false, false],
            xyz(0.6, 0.9, 0.03),
        ),
        "blurry_painting" => (
            "painting",
            "an abstract painting with a blurry texture",
            [false, true, false, false],
            xyz(0.9, 0.7, 0.04),
        ),
        _ => (
            "projector",
            "a ceiling projector on a long pole",
            [false, false, false, true],
            xyz(0.4, 1.4, 0.4),
        ),
    };
    let ann = json!({
        "uid": uid,
        "category": category,
        "description": description,
        "description_auto": format!("A 3D model of a {category}."),
        // The looking glass is a mirror to WordNet.
        "synset": if name == "looking_glass" {
            "mirror.n.01".to_string()
        } else {
            format!("{}.n.01", category.replace(' ', "_"))
        },
        "wn_version": "oewn:2022",
        "near_synsets": {format!("{}.n.02", category.replace(' ', "_")): 0.5},
        "width": 100.0, "depth": 50.0, "height": 80.0,
        "volume": 12.5, "mass": 3.0,
        "materials": ["wood", "fabric"], "composition": [0.6, 0.4],
        "receptacle": name == "cat_tower",
        "frontView": 1,
        "onFloor": flags[0], "onWall": flags[1], "onObject": flags[2], "onCeiling": flags[3],
        "pose_z_rot_angle": 1.25, "scale": 1.5, "z_axis_scale": true,
        "license_info": license(&format!("maker_{name}")),
    });
    let secondary: Vec<&str> = if name == "photo_frame" { vec!["CanBreak"] } else { Vec::new() };
    let meta = json!({"assetMetadata": {"boundingBox": bbox, "secondaryProperties": secondary}});
    if name == "blurry_painting" {
        // At the entry's top level, where the original reads it.
        return json!({"annotations": ann, "thor_metadata": meta, "blender_thor_similarity": 0.2});
    }
    if name == "cat_bed" || name == "projector" {
        // The fields at the top, as some exports write them.
        let mut flat = ann;
        if let Some(o) = flat.as_object_mut() {
            o.insert("thor_metadata".into(), meta);
        }
        flat
    } else {
        json!({"annotations": ann, "thor_metadata": meta})
    }
}

/// What [`write_fixture`] writes.
#[derive(Clone, Copy, Debug)]
pub struct FixtureOptions {
    /// The pickle protocol of the feature files (2 to 5).
    pub protocol: u8,
    /// The numpy module names of the feature files.
    pub modules: NumpyModules,
    /// Whether `features/` is written.
    pub features: bool,
    /// Whether `assets/` is written (every asset but `whiteboard`).
    pub assets: bool,
    /// Whether the feature arrays are float32 (else float16, as objathor writes them).
    pub float32: bool,
    /// Whether `clip_features.pkl` holds CLIP text rows (`text_features`; 2023_09_23 as
    /// Holodeck main downloads it has image rows only).
    pub text_rows: bool,
    /// Whether the folder is of the web-fetched generation: version `2024_08_16` with an empty
    /// `assets/` (then `assets` is ignored).
    pub web: bool,
    /// Assets left out of the folder, by name.
    pub without: &'static [&'static str],
}

impl Default for FixtureOptions {
    fn default() -> Self {
        FixtureOptions {
            protocol: 4,
            modules: NumpyModules::Core,
            features: true,
            assets: true,
            float32: false,
            text_rows: true,
            web: false,
            without: &[],
        }
    }
}

/// The version of the web-fetched fixture folder.
pub const WEB_FIXTURE_VERSION: &str = "2024_08_16";

fn write_gz(path: &Path, bytes: &[u8]) -> std::io::Result<()> {
    let mut gz = flate2::write::GzEncoder::new(Vec::new(), flate2::Compression::default());
    gz.write_all(bytes)?;
    std::fs::write(path, gz.finish()?)
}

/// Writes the fixture version folder `<dir>/2023_09_23` (`<dir>/2024_08_16` for a web folder)
/// and returns its path.
pub fn write_fixture(dir: &Path, options: FixtureOptions) -> std::io::Result<PathBuf> {
    let root = dir.join(if options.web { WEB_FIXTURE_VERSION } else { FIXTURE_VERSION });
    std::fs::create_dir_all(&root)?;
    let assets: Vec<&FixtureAsset> =
        FIXTURE_ASSETS.iter().filter(|a| !options.without.contains(&a.name)).collect();
    let mut map = serde_json::Map::new();
    for a in &assets {
        map.insert(a.uid.to_string(), annotation(a.name, a.uid));
    }
    write_gz(&root.join("annotations.json.gz"), Value::Object(map).to_string().as_bytes())?;
    if options.features {
        std::fs::create_dir_all(root.join("features"))?;
        let uids: Vec<String> = assets.iter().map(|a| a.uid.to_string()).collect();
        let mut img = Vec::new();
        let mut text = Vec::new();
        let mut sbert = Vec::new();
        for a in &assets {
            for b in a.views {
                let mut v = [0f32; FIXTURE_DIM];
                v[a.axis] = 1.0;
                v[7] = b;
                img.extend(v);
            }
            let mut t = [0f32; FIXTURE_DIM];
            t[a.axis] = 1.0;
            text.extend(t);
            // SBERT rows: the kind's axis and a little of the rest.
            let mut s = [0f32; FIXTURE_DIM];
            s[a.axis] = 1.0;
            s[7] = 0.5;
            sbert.extend(s);
        }
        let n = assets.len();
        let array = |shape, values| feature_array(options.float32, shape, values);
        let mut clip_items = vec![
            ("uids", PickleValue::Strings(uids.clone())),
            ("img_features", array(vec![n, 3, FIXTURE_DIM], img)),
        ];
        if options.text_rows {
            clip_items.push(("text_features", array(vec![n, FIXTURE_DIM], text)));
        }
        let clip = write(&clip_items, options.protocol, options.modules);
        std::fs::write(root.join("features").join("clip_features.pkl"), clip)?;
        let sbert = write(
            &[
                ("uids", PickleValue::Strings(uids)),
                ("text_features", array(vec![n, FIXTURE_DIM], sbert)),
            ],
            options.protocol,
            options.modules,
        );
        std::fs::write(root.join("features").join("sbert_features.pkl"), sbert)?;
    }
    if options.web {
        std::fs::create_dir_all(root.join("assets"))?;
    } else if options.assets {
        for a in assets.iter().filter(|a| a.name != "whiteboard") {
            write_asset_folder(&root.join("assets"), a.uid)?;
        }
    }
    Ok(root)
}

/// A stub asset folder: the model file and the three textures (placeholder bytes).
pub fn write_asset_folder(assets: &Path, uid: &str) -> std::io::Result<()> {
    let folder = assets.join(uid);
    std::fs::create_dir_all(&folder)?;
    write_gz(&folder.join(format!("{uid}.pkl.gz")), b"stub")?;
    for t in super::TEXTURES.iter().chain(&super::OPTIONAL_TEXTURES) {
        std::fs::write(folder.join(t), b"stub")?;
    }
    Ok(())
}

const NOUNS: &[&str] = &[
    "sofa",
    "chair",
    "table",
    "desk",
    "bed",
    "lamp",
    "shelf",
    "cabinet",
    "stool",
    "bench",
    "television",
    "plant",
    "rug",
    "mirror",
    "painting",
    "clock",
    "vase",
    "book",
    "piano",
    "guitar",
    "treadmill",
    "fridge",
    "sink",
    "wardrobe",
    "ottoman",
    "speaker",
    "monitor",
    "whiteboard",
    "chandelier",
    "mug",
    "bowl",
    "bottle",
    "basket",
    "box",
    "statue",
    "pillow",
    "curtains",
    "cat tower",
    "projector",
    "stove",
];
const ADJECTIVES: &[&str] = &[
    "modern", "vintage", "wooden", "metal", "grey", "white", "black", "red", "blue", "green",
    "leather", "velvet", "glass", "small", "large", "round", "square", "tall", "low", "rustic",
];

/// A feature array of `values`, float32 or float16 (as objathor writes them).
fn feature_array(float32: bool, shape: Vec<usize>, values: Vec<f32>) -> PickleValue {
    if float32 {
        PickleValue::F32 { shape, values }
    } else {
        PickleValue::F16 { shape, bits: values.iter().map(|x| f32_to_f16(*x)).collect() }
    }
}

/// The shape of a synthetic version folder ([`write_synthetic`]).
#[derive(Clone, Copy, Debug)]
pub struct Synthetic {
    /// How many assets.
    pub n: usize,
    /// Image views per asset.
    pub views: usize,
    /// Length of a feature vector.
    pub dim: usize,
    /// The random seed of names, sizes and features.
    pub seed: u64,
    /// Whether the features are float32 (else float16).
    pub float32: bool,
    /// Whether `clip_features.pkl` holds CLIP text rows.
    pub text_rows: bool,
}

/// Writes a synthetic version folder `<dir>/synthetic` with `n` annotations and features
/// (`n × views × dim` image rows, `n × dim` text rows when asked, `n × dim` SBERT rows); no
/// `assets/` folder. For the benchmark.
pub fn write_synthetic(dir: &Path, shape: Synthetic) -> std::io::Result<PathBuf> {
    use rand::{Rng as _, SeedableRng as _};
    let Synthetic { n, views, dim, seed, float32, text_rows } = shape;
    let mut rng = rand_chacha::ChaCha8Rng::seed_from_u64(seed);
    let root = dir.join("synthetic");
    std::fs::create_dir_all(root.join("features"))?;
    let mut map = serde_json::Map::new();
    let mut uids = Vec::with_capacity(n);
    for i in 0..n {
        let uid =
            format!("{:032x}", (i as u128).wrapping_mul(0x9e37_79b9_7f4a_7c15_f39c_c060_5ced_c835));
        let noun = NOUNS[rng.gen_range(0..NOUNS.len())];
        let a = ADJECTIVES[rng.gen_range(0..ADJECTIVES.len())];
        let b = ADJECTIVES[rng.gen_range(0..ADJECTIVES.len())];
        let kind = rng.gen_range(0..4);
        let size = [rng.gen_range(0.1..2.5), rng.gen_range(0.05..2.2), rng.gen_range(0.05..1.5)];
        map.insert(
            uid.clone(),
            json!({
                "annotations": {
                    "uid": uid, "category": noun,
                    "description": format!("a {a} {b} {noun}"),
                    "onFloor": kind == 0, "onWall": kind == 1, "onObject": kind == 2, "onCeiling": kind == 3,
                    "license_info": license(&format!("user{}", i % 997)),
                },
                "thor_metadata": {"assetMetadata": {"boundingBox": {"x": size[0], "y": size[1], "z": size[2]}}},
            }),
        );
        uids.push(uid);
    }
    write_gz(&root.join("annotations.json.gz"), Value::Object(map).to_string().as_bytes())?;
    let mut random_rows = |rows: usize| -> Vec<f32> {
        (0..rows * dim).map(|_| rng.gen_range(-0.06f32..0.06)).collect()
    };
    let img = random_rows(n * views);
    let text = random_rows(n);
    let sbert = random_rows(n);
    let array = |shape, values| feature_array(float32, shape, values);
    let mut clip = vec![
        ("uids", PickleValue::Strings(uids.clone())),
        ("img_features", array(vec![n, views, dim], img)),
    ];
    if text_rows {
        clip.push(("text_features", array(vec![n, dim], text)));
    }
    let clip = write(&clip, 4, NumpyModules::Core);
    std::fs::write(root.join("features").join("clip_features.pkl"), clip)?;
    let sbert = write(
        &[("uids", PickleValue::Strings(uids)), ("text_features", array(vec![n, dim], sbert))],
        4,
        NumpyModules::Core,
    );
    std::fs::write(root.join("features").join("sbert_features.pkl"), sbert)?;
    Ok(root)
}

/// The sizes of a tiny CLIP text tower ([`write_tiny_tower`]): CLIP's architecture, shrunk.
#[cfg(feature = "clip")]
#[derive(Clone, Copy, Debug)]
pub struct TinyTower {
    /// Width of the transformer.
    pub hidden: usize,
    /// Attention heads.
    pub heads: usize,
    /// Transformer blocks.
    pub layers: usize,
    /// Width of the MLP.
    pub intermediate: usize,
    /// Length of the output embedding (the folder's CLIP rows').
    pub projection: usize,
}

#[cfg(feature = "clip")]
impl Default for TinyTower {
    fn default() -> Self {
        TinyTower { hidden: 32, heads: 4, layers: 2, intermediate: 64, projection: 64 }
    }
}

/// The tiny tower's merges: enough for the fixture's words to make whole tokens, the rest is
/// spelt byte by byte.
#[cfg(feature = "clip")]
pub const TINY_MERGES: &[(&str, &str)] = &[
    ("c", "a"),
    ("ca", "t</w>"),
    ("t", "o"),
    ("to", "w"),
    ("e", "r</w>"),
    ("tow", "er</w>"),
    ("m", "i"),
    ("r", "r"),
    ("mi", "rr"),
    ("o", "r</w>"),
    ("mirr", "or</w>"),
    ("t", "r"),
    ("e", "e</w>"),
    ("tr", "ee</w>"),
    ("3", "d</w>"),
];

/// Writes a CLIP text tower of CLIP's architecture with tiny sizes and seeded random values
/// into `dir`, in Hugging Face's layout: `model.safetensors` (the `text_model.*` tensors and
/// `text_projection.weight`), `config.json`, `vocab.json` and `merges.txt` (CLIP's 512 byte
/// tokens, [`TINY_MERGES`], the start and end tokens). The same seed writes the same bytes.
#[cfg(feature = "clip")]
pub fn write_tiny_tower(dir: &Path, seed: u64, shape: TinyTower) -> std::io::Result<()> {
    use candle_core::{Device, Tensor};
    use rand::{Rng as _, SeedableRng as _};
    let TinyTower { hidden: h, heads, layers, intermediate: m, projection } = shape;
    std::fs::create_dir_all(dir)?;
    let merges: Vec<(String, String)> =
        TINY_MERGES.iter().map(|(a, b)| ((*a).to_string(), (*b).to_string())).collect();
    let vocab = super::clip::bpe::vocab_for(&merges);
    let n_vocab = vocab.len();
    let mut rng = rand_chacha::ChaCha8Rng::seed_from_u64(seed);
    let mut tensors = std::collections::HashMap::new();
    let mut put = |name: String, shape: Vec<usize>, scale: f32, base: f32| {
        let n: usize = shape.iter().product();
        let values: Vec<f32> = (0..n).map(|_| base + rng.gen_range(-scale..scale)).collect();
        let t = Tensor::from_vec(values, shape, &Device::Cpu).map_err(std::io::Error::other)?;
        tensors.insert(name, t);
        Ok::<_, std::io::Error>(())
    };
    let w = 1.0 / (h as f32).sqrt();
    put("text_model.embeddings.token_embedding.weight".into(), vec![n_vocab, h], 1.0, 0.0)?;
    put("text_model.embeddings.position_embedding.weight".into(), vec![77, h], 0.1, 0.0)?;
    for i in 0..layers {
        let p = format!("text_model.encoder.layers.{i}");
        for ln in ["layer_norm1", "layer_norm2"] {
            put(format!("{p}.{ln}.weight"), vec![h], 0.1, 1.0)?;
            put(format!("{p}.{ln}.bias"), vec![h], 0.1, 0.0)?;
        }
        for proj in ["q_proj", "k_proj", "v_proj", "out_proj"] {
            put(format!("{p}.self_attn.{proj}.weight"), vec![h, h], 2.0 * w, 0.0)?;
            put(format!("{p}.self_attn.{proj}.bias"), vec![h], 0.1, 0.0)?;
        }
        put(format!("{p}.mlp.fc1.weight"), vec![m, h], 2.0 * w, 0.0)?;
        put(format!("{p}.mlp.fc1.bias"), vec![m], 0.1, 0.0)?;
        put(format!("{p}.mlp.fc2.weight"), vec![h, m], 2.0 / (m as f32).sqrt(), 0.0)?;
        put(format!("{p}.mlp.fc2.bias"), vec![h], 0.1, 0.0)?;
    }
    put("text_model.final_layer_norm.weight".into(), vec![h], 0.1, 1.0)?;
    put("text_model.final_layer_norm.bias".into(), vec![h], 0.1, 0.0)?;
    put("text_projection.weight".into(), vec![projection, h], 2.0 * w, 0.0)?;
    super::clip::write_safetensors(&tensors, &dir.join(super::clip::WEIGHTS_FILE))
        .map_err(std::io::Error::other)?;
    let config = json!({
        "architectures": ["CLIPModel"],
        "projection_dim": projection,
        "text_config": {
            "hidden_size": h, "intermediate_size": m, "num_attention_heads": heads,
            "num_hidden_layers": layers, "max_position_embeddings": 77,
            "hidden_act": "gelu", "layer_norm_eps": 1e-5, "vocab_size": n_vocab,
        },
    });
    std::fs::write(dir.join("config.json"), serde_json::to_string_pretty(&config)?)?;
    let ordered: std::collections::BTreeMap<&String, &u32> = vocab.iter().collect();
    std::fs::write(dir.join("vocab.json"), serde_json::to_string(&ordered)?)?;
    let mut text = String::from("#version: 0.2\n");
    for (a, b) in TINY_MERGES {
        text.push_str(a);
        text.push(' ');
        text.push_str(b);
        text.push('\n');
    }
    std::fs::write(dir.join("merges.txt"), text)
}

/// The seed of the clip fixture's tiny tower.
#[cfg(feature = "clip")]
pub const TINY_TOWER_SEED: u64 = 55;

/// The text the fixture asset `name` is described by, as the original's floor and wall query
/// would say it (`a 3D model of <category>, <description>`).
#[cfg(feature = "clip")]
pub fn fixture_text(name: &str) -> String {
    let uid = fixture_uid(name);
    let ann = annotation(name, uid);
    let ann = ann.get("annotations").unwrap_or(&ann);
    let field = |k: &str| ann.get(k).and_then(Value::as_str).unwrap_or("").to_string();
    format!("a 3D model of {}, {}", field("category"), field("description"))
}

/// What one of an asset's renders looks like to the fixture's CLIP besides the asset's own
/// text: (asset, view, text). The cat tree's first view looks like a cat tower.
#[cfg(feature = "clip")]
pub const LOOKS_LIKE: &[(&str, usize, &str)] = &[("cat_tree", 0, "a 3D model of cat tower")];

/// Writes the fixture folder ([`write_fixture`] with `options`) with CLIP rows computed by the
/// tiny tower of [`write_tiny_tower`] (written to `<dir>/clip-tiny`, seed
/// [`TINY_TOWER_SEED`]): each asset's text row is the tower's unit embedding `e` of
/// [`fixture_text`]; its image view `v` is the unit vector `(e + b·w) / √(1+b²)`, where `b` is
/// the view's value in [`FIXTURE_ASSETS`] and `w` a unit vector orthogonal to every text's
/// embedding — so the view's cosine with its text is `1/√(1+b²)` (0.37 to 0.29, CLIP's
/// matching range) and with another text `cos(e, e′)/√(1+b²)`. A view of [`LOOKS_LIKE`] uses
/// that text's embedding for `e`. Returns the version folder and the tower's folder.
#[cfg(feature = "clip")]
pub fn write_clip_fixture(
    dir: &Path,
    options: FixtureOptions,
) -> std::io::Result<(PathBuf, PathBuf)> {
    use rand::{Rng as _, SeedableRng as _};
    let root = write_fixture(dir, FixtureOptions { features: true, ..options })?;
    let weights = dir.join("clip-tiny");
    let shape = TinyTower::default();
    write_tiny_tower(&weights, TINY_TOWER_SEED, shape)?;
    let tower = super::clip::TextTower::load(&weights)
        .map_err(|e| std::io::Error::other(format!("{e:?}")))?;
    let embed = |t: &str| tower.embed(t).map(|v| v.to_vec()).map_err(std::io::Error::other);
    let assets: Vec<&FixtureAsset> =
        FIXTURE_ASSETS.iter().filter(|a| !options.without.contains(&a.name)).collect();
    let dim = shape.projection;
    // An orthonormal basis of every text's embedding, for the views' `w`.
    let mut basis: Vec<Vec<f32>> = Vec::new();
    let add = |v: &[f32], basis: &mut Vec<Vec<f32>>| {
        let mut r = v.to_vec();
        for e in basis.iter() {
            let d: f32 = r.iter().zip(e).map(|(a, b)| a * b).sum();
            r.iter_mut().zip(e).for_each(|(a, b)| *a -= d * b);
        }
        let n: f32 = r.iter().map(|a| a * a).sum::<f32>().sqrt();
        if n > 1e-4 {
            basis.push(r.iter().map(|a| a / n).collect());
        }
    };
    let mut text_rows = Vec::new();
    // Each asset's three views' texts' embeddings.
    let mut units: Vec<Vec<Vec<f32>>> = Vec::new();
    for a in &assets {
        let own = embed(&fixture_text(a.name))?;
        add(&own, &mut basis);
        let mut views = vec![own.clone(); 3];
        for &(_, v, t) in LOOKS_LIKE.iter().filter(|(n, _, _)| *n == a.name) {
            let e = embed(t)?;
            add(&e, &mut basis);
            if let Some(slot) = views.get_mut(v) {
                *slot = e;
            }
        }
        text_rows.extend(own);
        units.push(views);
    }
    let mut rng = rand_chacha::ChaCha8Rng::seed_from_u64(TINY_TOWER_SEED);
    let mut img = Vec::new();
    for (a, views) in assets.iter().zip(&units) {
        for (b, u) in a.views.iter().zip(views) {
            let mut w: Vec<f32> = (0..dim).map(|_| rng.gen_range(-1.0f32..1.0)).collect();
            for e in &basis {
                let d: f32 = w.iter().zip(e).map(|(x, y)| x * y).sum();
                w.iter_mut().zip(e).for_each(|(x, y)| *x -= d * y);
            }
            super::features::normalize(&mut w);
            let norm = (1.0 + b * b).sqrt();
            img.extend(u.iter().zip(&w).map(|(x, y)| (x + b * y) / norm));
        }
    }
    let n = assets.len();
    let uids: Vec<String> = assets.iter().map(|a| a.uid.to_string()).collect();
    let array = |shape, values| feature_array(options.float32, shape, values);
    let mut items =
        vec![("uids", PickleValue::Strings(uids)), ("img_features", array(vec![n, 3, dim], img))];
    if options.text_rows {
        items.push(("text_features", array(vec![n, dim], text_rows)));
    }
    let clip = write(&items, options.protocol, options.modules);
    std::fs::write(root.join("features").join("clip_features.pkl"), clip)?;
    Ok((root, weights))
}

//! Resolving 1,000 descriptions against a 50,000-entry synthetic objathor-format catalog.
//!
//! The catalog is generated in the bench from a fixed seed, written as objathor annotations
//! JSON to a temporary folder and loaded through `Catalog::load`, as a user catalog would be.

use criterion::{criterion_group, criterion_main, Criterion};
use holoc::resolve::{self, Catalog, PlacementKind, Query};
use holoc::source::SourceMap;
use rand::{Rng, SeedableRng};
use rand_chacha::ChaCha8Rng;
use serde_json::{json, Map, Value};

const NOUNS: &[&str] = &[
    "sofa",
    "chair",
    "armchair",
    "table",
    "desk",
    "bed",
    "lamp",
    "shelf",
    "cabinet",
    "dresser",
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
    "oven",
    "sink",
    "toilet",
    "bathtub",
    "wardrobe",
    "nightstand",
    "ottoman",
    "speaker",
    "computer",
    "monitor",
    "printer",
    "whiteboard",
    "chandelier",
    "fan",
    "pendant light",
    "mug",
    "bowl",
    "plate",
    "bottle",
    "basket",
    "box",
    "crate",
    "barrel",
    "statue",
    "trophy",
    "pillow",
];
const ADJECTIVES: &[&str] = &[
    "modern",
    "vintage",
    "wooden",
    "metal",
    "grey",
    "white",
    "black",
    "red",
    "blue",
    "green",
    "leather",
    "velvet",
    "glass",
    "small",
    "large",
    "round",
    "square",
    "rustic",
    "industrial",
    "oak",
    "walnut",
    "marble",
    "brass",
    "plastic",
    "fabric",
    "soft",
    "tall",
    "low",
    "antique",
];
const MODIFIERS: &[&str] = &[
    "dining",
    "office",
    "coffee",
    "side",
    "floor",
    "desk",
    "kitchen",
    "bar",
    "wall",
    "ceiling",
    "gaming",
    "reading",
    "study",
    "living room",
    "bedroom",
    "garden",
    "music",
    "arcade",
];

fn synthetic_catalog(n: usize, seed: u64) -> Value {
    let mut rng = ChaCha8Rng::seed_from_u64(seed);
    let mut map = Map::new();
    for i in 0..n {
        let noun = NOUNS[rng.gen_range(0..NOUNS.len())];
        let modifier = if rng.gen_bool(0.4) {
            format!("{} ", MODIFIERS[rng.gen_range(0..MODIFIERS.len())])
        } else {
            String::new()
        };
        let a1 = ADJECTIVES[rng.gen_range(0..ADJECTIVES.len())];
        let a2 = ADJECTIVES[rng.gen_range(0..ADJECTIVES.len())];
        let kind = rng.gen_range(0..4);
        let size = [rng.gen_range(0.1..2.5), rng.gen_range(0.1..2.2), rng.gen_range(0.05..2.5)];
        map.insert(
            format!("{:032x}", (i as u128) * 0x9e37_79b9_7f4a_7c15 + 1),
            json!({
                "annotations": {
                    "category": format!("{modifier}{noun}"),
                    "description": format!("a {a1} {a2} {modifier}{noun}"),
                    "onFloor": kind == 0, "onWall": kind == 1, "onObject": kind == 2, "onCeiling": kind == 3,
                },
                "assetMetadata": {"boundingBox": {"x": size[0], "y": size[1], "z": size[2]}},
            }),
        );
    }
    Value::Object(map)
}

fn queries(n: usize, seed: u64) -> Vec<Query> {
    let mut rng = ChaCha8Rng::seed_from_u64(seed);
    let kinds = PlacementKind::ALL;
    (0..n)
        .map(|_| {
            let noun = NOUNS[rng.gen_range(0..NOUNS.len())];
            let modifier = MODIFIERS[rng.gen_range(0..MODIFIERS.len())];
            let a = ADJECTIVES[rng.gen_range(0..ADJECTIVES.len())];
            Query {
                category: format!("{modifier} {noun}"),
                description: Some(format!("{a} {modifier} {noun} with a cozy look")),
                size_m: Some([
                    rng.gen_range(0.2..2.0),
                    rng.gen_range(0.2..2.0),
                    rng.gen_range(0.2..2.0),
                ]),
                kind: Some(kinds[rng.gen_range(0..kinds.len())]),
            }
        })
        .collect()
}

fn bench(c: &mut Criterion) {
    let dir = tempfile::tempdir().expect("a temporary folder");
    let path = dir.path().join("annotations.json");
    std::fs::write(&path, synthetic_catalog(50_000, 7).to_string()).expect("write the catalog");
    let mut sources = SourceMap::new();
    let catalog = Catalog::load(&[path.as_path()], &mut sources).value;
    assert!(catalog.assets().len() >= 50_000);
    let queries = queries(1_000, 9);

    let mut group = c.benchmark_group("resolve");
    group.sample_size(10);
    group.bench_function("rank_1000_descriptions_50k_catalog", |b| {
        b.iter(|| {
            let mut chosen = 0usize;
            for q in &queries {
                let ranked = resolve::rank_top(&catalog, q, 1, 128);
                chosen += usize::from(ranked.iter().any(resolve::Candidate::is_good_enough));
            }
            chosen
        });
    });
    group.bench_function("load_50k_objathor_catalog", |b| {
        b.iter(|| {
            let mut sources = SourceMap::new();
            Catalog::load(&[path.as_path()], &mut sources).value.assets().len()
        });
    });
    group.finish();
}

criterion_group!(benches, bench);
criterion_main!(benches);

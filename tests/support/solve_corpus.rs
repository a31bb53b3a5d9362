//! Loads the layout corpus (`tests/corpus/solve/*.json`, written by `make_corpus.py`) into
//! `solve::RoomProblem` values. Shared by `tests/solve.rs` and `benches/layout_bench.rs`.

use std::path::{Path, PathBuf};

use holoc::check::scene::{GlobalKind, RelationKind};
use holoc::solve::{
    CeilingObject, FloorObject, ProblemConstraint, RoomProblem, SmallObject, WallHole, WallObject,
    WallSegment,
};
use serde::Deserialize;

#[derive(Deserialize)]
struct RoomJson {
    name: String,
    outline: Vec<[f64; 2]>,
    wall_height: f64,
    keep_out: Vec<[[f64; 2]; 2]>,
    holes: Vec<HoleJson>,
    objects: Vec<ObjJson>,
    wall_objects: Vec<WallJson>,
    small: Vec<SmallJson>,
    ceiling: Option<CeilJson>,
}

#[derive(Deserialize)]
struct HoleJson {
    wall: usize,
    from: f64,
    to: f64,
    bottom: f64,
    top: f64,
    window: bool,
}

#[derive(Deserialize)]
struct ObjJson {
    id: String,
    size: [f64; 3],
    global: String,
    rel: Vec<[String; 2]>,
}

#[derive(Deserialize)]
struct WallJson {
    id: String,
    size: [f64; 3],
    above: Option<String>,
    height: Option<f64>,
}

#[derive(Deserialize)]
struct SmallJson {
    id: String,
    size: [f64; 3],
    on: String,
}

#[derive(Deserialize)]
struct CeilJson {
    id: String,
    size: [f64; 3],
    above: Option<String>,
}

/// The corpus folder.
pub fn corpus_dir() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/corpus/solve")
}

/// Every corpus room, sorted by file name.
pub fn load_all() -> Vec<(String, RoomProblem)> {
    load_dir(&corpus_dir())
}

/// Every room of a folder of rooms in the corpus's format, sorted by file name.
pub fn load_dir(dir: &Path) -> Vec<(String, RoomProblem)> {
    let mut files: Vec<PathBuf> = std::fs::read_dir(dir)
        .expect("corpus folder exists")
        .filter_map(|e| e.ok().map(|e| e.path()))
        .filter(|p| p.extension().is_some_and(|e| e == "json"))
        .collect();
    files.sort();
    files
        .iter()
        .map(|p| {
            let name = p.file_stem().and_then(|s| s.to_str()).unwrap_or("?").to_string();
            (name, load(p))
        })
        .collect()
}

/// One corpus room.
pub fn load(path: &Path) -> RoomProblem {
    let text = std::fs::read_to_string(path).expect("corpus file is readable");
    let r: RoomJson = serde_json::from_str(&text).expect("corpus file is valid");
    let index = |name: &str| r.objects.iter().position(|o| o.id == name).expect("known object");
    let n = r.outline.len();
    let mut walls: Vec<WallSegment> = (0..n)
        .map(|i| WallSegment { a: r.outline[i], b: r.outline[(i + 1) % n], holes: Vec::new() })
        .collect();
    for h in &r.holes {
        walls[h.wall].holes.push(WallHole {
            from_m: h.from,
            to_m: h.to,
            bottom_m: h.bottom,
            top_m: h.top,
            window: h.window,
        });
    }
    let mut objects: Vec<FloorObject> = r
        .objects
        .iter()
        .map(|o| FloorObject {
            id: o.id.clone(),
            size: [o.size[0], o.size[1]],
            height: o.size[2],
            global: if o.global == "middle" { GlobalKind::Middle } else { GlobalKind::Edge },
            role: holoc::solve::Role::of(o.id.rsplit_once('-').map_or(o.id.as_str(), |(a, _)| a)),
            constraints: o
                .rel
                .iter()
                .map(|[k, t]| {
                    let kind = RelationKind::from_words(k).expect("known relation");
                    ProblemConstraint {
                        kind,
                        written: kind,
                        implied: false,
                        target: index(t),
                        span: None,
                    }
                })
                .collect(),
            pin: None,
            thor_type: None,
            span: None,
        })
        .collect();
    holoc::solve::read_meanings(&mut objects);
    RoomProblem {
        name: r.name.clone(),
        outline: r.outline.clone(),
        wall_height: r.wall_height,
        keep_out: r
            .keep_out
            .iter()
            .map(|[a, b]| vec![*a, [a[0], b[1]], *b, [b[0], a[1]]])
            .collect(),
        walls,
        objects,
        wall_objects: r
            .wall_objects
            .iter()
            .map(|w| WallObject {
                id: w.id.clone(),
                size: w.size,
                above: w.above.as_deref().map(index),
                height_m: w.height,
                thor_type: None,
                resizable: false,
                span: None,
            })
            .collect(),
        small_objects: r
            .small
            .iter()
            .map(|s| SmallObject {
                id: s.id.clone(),
                // The item's name: the id without its copy number (`book-0|desk-0` → `book`).
                item: s
                    .id
                    .split('|')
                    .next()
                    .and_then(|name| name.rsplit_once('-'))
                    .map_or_else(|| s.id.clone(), |(item, _)| item.to_string()),
                size: s.size,
                on: holoc::solve::Holder::Floor(index(&s.on)),
                elsewhere: None,
                absent: None,
                anchor: Vec::new(),
                thor_type: None,
                span: None,
            })
            .collect(),
        ceiling: r.ceiling.as_ref().map(|c| CeilingObject {
            id: c.id.clone(),
            size: c.size,
            above: c.above.as_deref().map(index),
            span: None,
        }),
        span: None,
    }
}

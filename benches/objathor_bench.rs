//! objathor at 50,000 assets: a version folder with 50,000 annotations and 50,000 × 3 × 768
//! image features (and 50,000 × 768 CLIP text and SBERT rows), in three shapes — float16 with
//! text rows (as the newer releases), float32 with text rows (a folder re-saved by other
//! tools), float16 with image rows only (2023_09_23 as Holodeck main downloads it).
//!
//! Run by hand with `cargo bench --bench objathor_bench` (a release build); the folders are
//! generated once by `resolve::objathor::fixture::write_synthetic` into `target/objathor-bench`
//! and kept there. Each figure comes from a process of its own (the bench runs itself again),
//! so that its CPU time and peak resident memory (`VmHWM`) are its own:
//!
//! - `none`: the build of `examples/cat_studio.holo` without `--objathor` (the baseline);
//! - `folder`: the load reading the folder's files (`--objathor-no-index`), then the build;
//! - `index`: the first load with the index (reading the folder and writing its index);
//! - `mapped`: a load from the index, then the build — what every later build costs;
//! - then, in the `folder` and `mapped` processes, 1,000 queries in the `features` mode;
//! - `clip` (built with `--features clip`): a load from the index with a tiny CLIP text tower of
//!   768-long embeddings (`fixture::write_tiny_tower`, seeded random weights), then 1,000 queries
//!   in the `clip` mode — each embedded by the tower and scored against all 50,000 × 3 image
//!   rows, as the original does.
//!
//! `OBJATHOR_BENCH_N=5000` runs the same on a folder of 5,000 assets (a quick run).
//!
//! Targets (issue 55): a build with `--objathor` from the index ≤ 0.3 s of CPU and ≤ 300 MB
//! more than without; `book/src/objathor.md` records the figures.

#![allow(clippy::print_stdout, reason = "the benchmark prints its figures")]

use holoc::compile::{build, BuildOptions};
use holoc::resolve::objathor::fixture::{self, Synthetic};
use holoc::resolve::objathor::ObjathorOptions;
use holoc::resolve::{Catalog, PlacementKind, Query};
use holoc::source::SourceMap;
use std::path::{Path, PathBuf};
use std::process::Command;

const N: usize = 50_000;

/// The number of assets: [`N`], or `OBJATHOR_BENCH_N` for a quick run on a smaller folder.
fn n_assets() -> usize {
    std::env::var("OBJATHOR_BENCH_N").ok().and_then(|v| v.parse().ok()).unwrap_or(N)
}
const SCENE: &str = "examples/cat_studio.holo";

const QUERIES: &[(&str, &str)] = &[
    ("cat tower", "a carpeted cat tower"),
    ("wall mirror", "round mirror with a brass rim"),
    ("curtains", "long grey linen curtains"),
    ("whiteboard", "large whiteboard"),
    ("projector", "ceiling projector"),
    ("stove", "black gas stove"),
    ("sofa", "modern grey velvet sofa"),
    ("desk lamp", "small metal desk lamp"),
    ("bookshelf", "tall wooden bookshelf"),
    ("piano", "black upright piano"),
];

/// The three folder shapes: name, float32, text rows.
const SHAPES: &[(&str, bool, bool)] =
    &[("f16-text", false, true), ("f32-text", true, true), ("f16-image-only", false, false)];

fn peak_rss_mb() -> f64 {
    let Ok(status) = std::fs::read_to_string("/proc/self/status") else { return f64::NAN };
    status
        .lines()
        .find(|l| l.starts_with("VmHWM:"))
        .and_then(|l| l.split_whitespace().nth(1))
        .and_then(|kb| kb.parse::<f64>().ok())
        .map_or(f64::NAN, |kb| kb / 1024.0)
}

/// CPU seconds this process has used (user + system), from `/proc/self/stat`: the figure that
/// does not depend on what else the machine runs.
fn cpu_s() -> f64 {
    let Ok(stat) = std::fs::read_to_string("/proc/self/stat") else { return f64::NAN };
    let Some(after) = stat.rsplit_once(')').map(|(_, r)| r) else { return f64::NAN };
    let fields: Vec<&str> = after.split_whitespace().collect();
    let ticks = |i: usize| fields.get(i).and_then(|f| f.parse::<f64>().ok()).unwrap_or(f64::NAN);
    // utime and stime are fields 14 and 15 of the line (11 and 12 after the name), in 1/100 s.
    (ticks(11) + ticks(12)) / 100.0
}

fn folder(shape: &str, float32: bool, text_rows: bool) -> PathBuf {
    let n = n_assets();
    let base = if n == N {
        Path::new("target").join("objathor-bench").join(shape)
    } else {
        Path::new("target").join("objathor-bench").join(format!("{shape}-{n}"))
    };
    let root = base.join("synthetic");
    if !root.join("annotations.json.gz").is_file() {
        let synthetic = Synthetic { n, views: 3, dim: 768, seed: 34, float32, text_rows };
        fixture::write_synthetic(&base, synthetic).expect("the synthetic folder is written");
        // Files written more than two seconds before their index can be vouched for by it.
        std::thread::sleep(std::time::Duration::from_millis(2100));
    }
    root
}

/// The tiny CLIP text tower of the `clip` figures (768-long embeddings, as objathor's rows), in
/// `target/objathor-bench/clip-tiny`; without the feature, no folder.
fn tiny_tower() -> PathBuf {
    let dir = Path::new("target").join("objathor-bench").join("clip-tiny");
    #[cfg(feature = "clip")]
    if !dir.join("model.safetensors").is_file() {
        let shape = fixture::TinyTower { projection: 768, ..fixture::TinyTower::default() };
        fixture::write_tiny_tower(&dir, 34, shape).expect("the tiny tower is written");
    }
    dir
}

/// One measured process: `mode` on the folder `root`.
fn child(mode: &str, root: &Path) {
    let cpu = cpu_s();
    let mut sources = SourceMap::new();
    let options = (mode != "none").then(|| ObjathorOptions {
        dir: root.to_path_buf(),
        no_index: mode == "folder",
        clip: (mode == "clip").then(tiny_tower),
        ..ObjathorOptions::default()
    });
    if mode == "index" {
        let _ = std::fs::remove_dir_all(root.join(".holoc-index"));
    }
    let loaded = Catalog::load_with(&[] as &[PathBuf], options.as_ref(), &mut sources);
    assert!(!loaded.has_errors(), "the folder loads");
    let catalog = loaded.value;
    let load_cpu = cpu_s() - cpu;
    if let Some(obj) = catalog.objathor() {
        assert_eq!(
            obj.from_index,
            matches!(mode, "mapped" | "clip"),
            "{mode}: read from the index or not"
        );
    }
    let text = std::fs::read_to_string(SCENE).expect("the example");
    let file = sources.add(SCENE, text);
    let built = build(&sources, file, &BuildOptions::new(&catalog));
    assert!(built.value.is_some(), "the example builds");
    let build_cpu = cpu_s() - cpu;
    let rss = peak_rss_mb();
    print!("{load_cpu:.3} {build_cpu:.3} {rss:.0}");
    if matches!(mode, "folder" | "mapped" | "clip") {
        let kinds = [
            PlacementKind::Floor,
            PlacementKind::Wall,
            PlacementKind::OnObject,
            PlacementKind::Ceiling,
        ];
        let cpu = cpu_s();
        let mut good = 0usize;
        for i in 0..1000 {
            let (category, description) = QUERIES[i % QUERIES.len()];
            let query = Query {
                category: category.to_string(),
                description: Some(format!("{description} {i}")),
                size_m: Some([0.5 + (i % 7) as f64 * 0.2, 0.8, 0.6]),
                kind: Some(kinds[i % kinds.len()]),
            };
            let ranked = holoc::resolve::objathor::rank(&catalog, &query, i as u64, 128);
            good += ranked.iter().filter(|c| c.is_good_enough()).count();
        }
        print!(" {:.3} {good} {:.0}", cpu_s() - cpu, peak_rss_mb());
    }
    println!();
}

fn run(mode: &str, root: &Path) -> Vec<String> {
    let out = Command::new(std::env::current_exe().expect("the bench"))
        .env("OBJATHOR_BENCH_CHILD", format!("{mode}\t{}", root.display()))
        .output()
        .expect("the bench runs again");
    assert!(out.status.success(), "{}", String::from_utf8_lossy(&out.stderr));
    String::from_utf8_lossy(&out.stdout).split_whitespace().map(str::to_string).collect()
}

fn main() {
    // `cargo bench` passes `--bench`; anything else is ignored.
    if let Ok(job) = std::env::var("OBJATHOR_BENCH_CHILD") {
        let (mode, root) = job.split_once('\t').expect("mode and folder");
        child(mode, Path::new(root));
        return;
    }
    let none = run("none", Path::new("."));
    println!("without --objathor: build {} s of CPU, peak {} MB", none[1], none[2]);
    let base: f64 = none[2].parse().unwrap_or(f64::NAN);
    println!(
        "| folder | load | build | peak | more than without | 1,000 queries | good candidates |"
    );
    println!("|---|---|---|---|---|---|---|");
    for (shape, float32, text_rows) in SHAPES {
        let root = folder(shape, *float32, *text_rows);
        let modes: &[&str] = if cfg!(feature = "clip") {
            &["folder", "index", "mapped", "clip"]
        } else {
            &["folder", "index", "mapped"]
        };
        for &mode in modes {
            let f = run(mode, &root);
            let peak: f64 = f[2].parse().unwrap_or(f64::NAN);
            let queries = f.get(3).map_or("-".to_string(), |q| format!("{q} s"));
            println!(
                "| {shape}, {mode} | {} s | {} s | {} MB | {:.0} MB | {queries} | {} |",
                f[0],
                f[1],
                f[2],
                peak - base,
                f.get(4).map_or("-", String::as_str),
            );
        }
    }
}

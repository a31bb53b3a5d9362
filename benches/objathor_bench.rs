//! Loading a 50,000-asset objathor version folder with 50,000 × 3 × 768 float16 CLIP image
//! features (and 50,000 × 768 CLIP text and SBERT features), then ranking 1,000 queries in the
//! `features` mode.
//!
//! Run by hand with `cargo bench --bench objathor_bench` (a release build); the folder is
//! generated once by `resolve::objathor::fixture::write_synthetic` into `target/objathor-bench`
//! and kept there. It prints the load time, the time of 1,000 queries and the peak resident
//! memory (`VmHWM`), which `book/src/objathor.md` records. Targets: load ≤ 2 s, 1,000 queries
//! ≤ 1 s, memory ≤ 1 GB.

#![allow(clippy::print_stdout, reason = "the benchmark prints its figures")]

use holoc::resolve::objathor::{fixture, ObjathorOptions};
use holoc::resolve::{Catalog, PlacementKind, Query};
use holoc::source::SourceMap;
use std::path::{Path, PathBuf};
use std::time::Instant;

const N: usize = 50_000;

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

fn peak_rss_mb() -> Option<f64> {
    let status = std::fs::read_to_string("/proc/self/status").ok()?;
    let line = status.lines().find(|l| l.starts_with("VmHWM:"))?;
    let kb: f64 = line.split_whitespace().nth(1)?.parse().ok()?;
    Some(kb / 1024.0)
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

fn folder() -> PathBuf {
    let base = Path::new("target").join("objathor-bench");
    let root = base.join("synthetic");
    if !root.join("annotations.json.gz").is_file() {
        let started = Instant::now();
        fixture::write_synthetic(&base, N, 3, 768, 34).expect("the synthetic folder is written");
        println!("generated {N} assets in {:.1} s", started.elapsed().as_secs_f64());
    }
    root
}

fn main() {
    // `cargo bench` passes `--bench`; anything else is ignored.
    let root = folder();
    let before = peak_rss_mb();
    let started = Instant::now();
    let cpu = cpu_s();
    let mut sources = SourceMap::new();
    let options = ObjathorOptions { dir: root, ..ObjathorOptions::default() };
    let loaded = Catalog::load_with(&[] as &[PathBuf], Some(&options), &mut sources);
    let load_s = started.elapsed().as_secs_f64();
    assert!(!loaded.has_errors(), "the folder loads");
    let catalog = loaded.value;
    let obj = catalog.objathor().expect("loaded");
    println!(
        "load: {:.3} s ({:.2} s of CPU) for {} assets, scoring {} ({})",
        load_s,
        cpu_s() - cpu,
        obj.end - obj.start,
        obj.scoring.as_str(),
        obj.pseudo_query_space().unwrap_or("-")
    );
    let kinds = [
        PlacementKind::Floor,
        PlacementKind::Wall,
        PlacementKind::OnObject,
        PlacementKind::Ceiling,
    ];
    let started = Instant::now();
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
    let query_s = started.elapsed().as_secs_f64();
    println!(
        "1000 queries: {query_s:.3} s ({:.2} s of CPU; {good} good candidates in all)",
        cpu_s() - cpu
    );
    match (before, peak_rss_mb()) {
        (Some(b), Some(a)) => println!("peak memory: {a:.0} MB (before loading: {b:.0} MB)"),
        _ => println!("peak memory: not known on this system"),
    }
    // The same queries ranked by words only, for comparison.
    drop(catalog);
    let options =
        ObjathorOptions { scoring: Some(holoc::resolve::objathor::Scoring::Lexical), ..options };
    let lexical =
        Catalog::load_with(&[] as &[PathBuf], Some(&options), &mut SourceMap::new()).value;
    let started = Instant::now();
    let cpu = cpu_s();
    for i in 0..1000 {
        let (category, description) = QUERIES[i % QUERIES.len()];
        let query = Query {
            category: category.to_string(),
            description: Some(format!("{description} {i}")),
            size_m: Some([0.5 + (i % 7) as f64 * 0.2, 0.8, 0.6]),
            kind: Some(kinds[i % kinds.len()]),
        };
        std::hint::black_box(holoc::resolve::objathor::rank(&lexical, &query, i as u64, 128));
    }
    println!(
        "1000 queries, lexical only: {:.3} s ({:.2} s of CPU)",
        started.elapsed().as_secs_f64(),
        cpu_s() - cpu
    );
}

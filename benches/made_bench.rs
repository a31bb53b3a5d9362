//! What making assets adds: the objects of the original Holodeck's 8 real requests that reach
//! the house, and the new-user scenes of the examples, with and without `crate::make`.
//!
//! `cargo bench --bench made_bench` imports each real Holodeck scene of
//! `../shared/data/real-scenes/` (its model's answers, as `holoc import` reads them), builds it
//! twice (making on, and `--no-make`), and prints per scene the floor, wall and on-top objects
//! of the original that are in the house, the made assets by kind, the made assets' bytes (the
//! largest), the time of a build with and without making (the median of 5: a build with making
//! also places the objects it could not place before), and the time of making and encoding
//! every made asset of the house once more (the cost of making itself). The
//! examples that ask for things no catalog has (`cat_studio`, `meeting_room`,
//! `family_bathroom`) follow. Without `../shared` only the examples are measured.

// The table is the point of this binary: it prints to stdout on purpose.
#![allow(clippy::print_stdout)]

use holoc::check::Placement;
use holoc::compile::{build, BuildOptions, Built};
use holoc::import::{self, ImportOptions};
use holoc::resolve::Catalog;
use holoc::source::SourceMap;
use std::collections::BTreeMap;
use std::path::{Path, PathBuf};
use std::time::Instant;

/// Floor, wall and on-top objects: `(asked, in the house)` each.
#[derive(Default, Clone, Copy)]
struct Kept {
    floor: (usize, usize),
    wall: (usize, usize),
    on_top: (usize, usize),
}

impl std::ops::AddAssign for Kept {
    fn add_assign(&mut self, o: Kept) {
        self.floor = (self.floor.0 + o.floor.0, self.floor.1 + o.floor.1);
        self.wall = (self.wall.0 + o.wall.0, self.wall.1 + o.wall.1);
        self.on_top = (self.on_top.0 + o.on_top.0, self.on_top.1 + o.on_top.1);
    }
}

fn kept(built: &Built) -> Kept {
    let mut k = Kept::default();
    for o in &built.scene.objects {
        let placed = built
            .objects
            .iter()
            .any(|l| l.object_name == o.name && l.room == o.room && l.parent.is_none());
        let slot = match o.placement {
            Placement::Floor { .. } => &mut k.floor,
            Placement::Wall { .. } => &mut k.wall,
        };
        slot.0 += 1;
        slot.1 += usize::from(placed);
        k.on_top.0 += o.on_top.iter().map(|t| t.count as usize).sum::<usize>();
    }
    k.on_top.1 = built.objects.iter().filter(|l| l.parent.is_some()).count();
    k
}

fn build_text(name: &str, text: &str, catalog: &Catalog, make: bool) -> Option<(Built, f64)> {
    let mut times = Vec::new();
    let mut last = None;
    for _ in 0..5 {
        let mut sources = SourceMap::new();
        let id = sources.add(name.to_string(), text.to_string());
        let options = BuildOptions { make, ..BuildOptions::new(catalog) };
        let t = Instant::now();
        let built = build(&sources, id, &options).value?;
        times.push(t.elapsed().as_secs_f64() * 1000.0);
        last = Some(built);
    }
    times.sort_by(f64::total_cmp);
    last.map(|b| (b, times[times.len() / 2]))
}

fn row(name: &str, text: &str, catalog: &Catalog, total: &mut (Kept, Kept)) {
    let (Some((with, ms_with)), Some((without, ms_without))) =
        (build_text(name, text, catalog, true), build_text(name, text, catalog, false))
    else {
        println!("| {name} | does not build | | | | | | |");
        return;
    };
    let (a, b) = (kept(&without), kept(&with));
    total.0 += a;
    total.1 += b;
    let made =
        holoc::make::used_in(&with.resolved, with.objects.iter().map(|o| o.asset_id.as_str()));
    let mut kinds: BTreeMap<&str, usize> = BTreeMap::new();
    let mut largest = 0;
    // The cost of making itself: every made asset made again and its files encoded (what a
    // build with making does beyond placing the objects it could not place before).
    let t = Instant::now();
    for m in &made {
        *kinds.entry(m.kind).or_default() += 1;
        if let Some(kind) = holoc::make::kind(m.kind) {
            let [w, h, d] = m.size_m;
            let description = m.params.get("description").cloned().unwrap_or_default();
            let again = holoc::make::make(&holoc::make::Request {
                kind,
                size_m: Some([w, d, h]),
                description,
            });
            let bytes: usize =
                holoc::make::runtime::files(&again).iter().map(|(_, b)| b.len()).sum();
            largest = largest.max(bytes);
        }
    }
    let making_ms = t.elapsed().as_secs_f64() * 1000.0;
    let kinds: Vec<String> = kinds.iter().map(|(k, n)| format!("{k} {n}")).collect();
    let f = |(asked, got): (usize, usize)| format!("{got}/{asked}");
    println!(
        "| {name} | {} → {} | {} → {} | {} → {} | {} | {} KB | {ms_without:.1} → {ms_with:.1} | {making_ms:.1} |",
        f(a.floor),
        f(b.floor),
        f(a.wall),
        f(b.wall),
        f(a.on_top),
        f(b.on_top),
        if kinds.is_empty() { "–".to_string() } else { kinds.join(", ") },
        largest / 1024,
    );
}

fn main() {
    let catalog = Catalog::embedded();
    println!("| scene | floor kept (no make → make) | wall kept | on top kept | made by kind | largest made asset | build ms (no make → make) | making and encoding ms |");
    println!("|---|---|---|---|---|---|---|---|");
    let mut total = (Kept::default(), Kept::default());
    let real = Path::new("../shared/data/real-scenes");
    let mut paths: Vec<PathBuf> = std::fs::read_dir(real)
        .map(|d| d.flatten().map(|e| e.path()).collect())
        .unwrap_or_default();
    paths.retain(|p| {
        p.extension().is_some_and(|e| e == "json")
            && !p.file_name().is_some_and(|n| n.to_string_lossy().starts_with("procthor-"))
    });
    paths.sort();
    if paths.is_empty() {
        println!("(../shared/data/real-scenes is absent: the real requests are not measured)");
    }
    for path in &paths {
        let Ok(text) = std::fs::read_to_string(path) else { continue };
        let Ok(value) = serde_json::from_str::<serde_json::Value>(&text) else { continue };
        let out =
            import::import_holodeck_scene(&value, &mut SourceMap::new(), &ImportOptions::default());
        let holo = holoc::fmt::print(&out.value);
        let name = path.file_stem().map(|s| s.to_string_lossy().into_owned()).unwrap_or_default();
        row(&name, &holo, &catalog, &mut total);
    }
    if !paths.is_empty() {
        let f = |(asked, got): (usize, usize)| format!("{got}/{asked}");
        println!(
            "| **the 8 real requests** | {} → {} | {} → {} | {} → {} | | | | |",
            f(total.0.floor),
            f(total.1.floor),
            f(total.0.wall),
            f(total.1.wall),
            f(total.0.on_top),
            f(total.1.on_top)
        );
    }
    let mut examples = (Kept::default(), Kept::default());
    for name in ["cat_studio", "meeting_room", "family_bathroom"] {
        let path = format!("examples/{name}.holo");
        let Ok(text) = std::fs::read_to_string(&path) else { continue };
        row(name, &text, &catalog, &mut examples);
    }
}

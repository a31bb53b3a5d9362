//! Export benchmark: for every example and a generated house of 16 rooms, the time to build the
//! house, the time to export it to GLB (`holoc export`'s work after reading the file), the
//! share of the second in the first, the GLB's size and the viewer page's size.
//!
//! `cargo bench --bench export_bench` prints the table (medians of a few runs). The targets
//! (issue 32): export ≤ 20 % of the build time, GLB ≤ 1 MB for the 4-room apartment.

// The table is the point of this binary: it prints to stdout on purpose.
#![allow(clippy::print_stdout)]

use std::fmt::Write as _;
use std::time::{Duration, Instant};

use holoc::compile::{build, BuildOptions};
use holoc::export::{export, viewer, ExportOptions};
use holoc::resolve::Catalog;
use holoc::source::SourceMap;

/// A house of 16 rooms of 5 m × 5 m in a 4 × 4 grid, each with ten pieces of furniture, a
/// door to the previous room and a window where it has an outside wall.
fn sixteen_rooms() -> String {
    let furniture = [
        ("sofa", "grey fabric three seat sofa"),
        ("armchair", "leather armchair"),
        ("bookshelf", "tall oak bookshelf"),
        ("table", "round dining table"),
        ("chair", "wooden dining chair"),
        ("desk", "white writing desk"),
        ("cabinet", "low storage cabinet"),
        ("plant", "potted fern"),
        ("lamp", "floor lamp"),
        ("tv stand", "low tv stand"),
    ];
    let mut text =
        String::from("scene \"a floor of sixteen rooms\" {\n  wall height 2.7 m\n  seed 3\n}\n");
    for r in 0..16 {
        let (x0, z0) = (f64::from(r % 4) * 5.0, f64::from(r / 4) * 5.0);
        let _ = writeln!(
            text,
            "\nroom r{r} \"room {r}\" {{\n  floor \"oak planks\"\n  walls \"white paint\"\n  corners in m ({x0}, {z0}) ({x0}, {}) ({}, {}) ({}, {z0})",
            z0 + 5.0,
            x0 + 5.0,
            z0 + 5.0,
            x0 + 5.0
        );
        if r % 4 == 0 {
            text.push_str("  window west slider 100 cm x 120 cm, count 1, sill 90 cm\n");
        }
        for (k, (category, description)) in furniture.iter().enumerate() {
            let _ = writeln!(
                text,
                "  object o{k} \"{category}\" {{\n    describe \"{description}\"\n    edge\n  }}"
            );
        }
        text.push_str("}\n");
    }
    for r in 0..16 {
        let from = if r == 0 {
            "exterior".to_string()
        } else if r % 4 == 0 {
            format!("r{}", r - 4)
        } else {
            format!("r{}", r - 1)
        };
        let _ = writeln!(text, "door {from} -- r{r} : doorway single");
    }
    text
}

fn median(mut times: Vec<Duration>) -> Duration {
    times.sort();
    times[times.len() / 2]
}

fn main() {
    let catalog = Catalog::embedded();
    let mut scenes: Vec<(String, String)> = std::fs::read_dir("examples")
        .expect("examples")
        .flatten()
        .map(|e| e.path())
        .filter(|p| p.extension().is_some_and(|e| e == "holo"))
        .map(|p| {
            let name = p.file_stem().expect("a name").to_string_lossy().into_owned();
            (name, std::fs::read_to_string(&p).expect("readable"))
        })
        .collect();
    scenes.sort();
    scenes.push(("sixteen_rooms (generated)".to_string(), sixteen_rooms()));
    println!("| house | rooms | objects | build ms | export ms | export / build | GLB bytes | page bytes |");
    println!("|---|---|---|---|---|---|---|---|");
    for (name, text) in scenes {
        let mut sources = SourceMap::new();
        let id = sources.add(format!("{name}.holo"), text);
        let options = BuildOptions::new(&catalog);
        let mut build_times = Vec::new();
        let mut house = None;
        for _ in 0..3 {
            let t = Instant::now();
            let built = build(&sources, id, &options);
            build_times.push(t.elapsed());
            house = built.value.map(|b| b.house.house);
        }
        let Some(house) = house else {
            println!("| {name} | does not build | | | | | | |");
            continue;
        };
        let mut export_times = Vec::new();
        let mut glb = Vec::new();
        let mut counts = None;
        for _ in 0..9 {
            let t = Instant::now();
            let exported = export(&house, &catalog, &ExportOptions::default()).expect("exports");
            glb = exported.to_glb();
            export_times.push(t.elapsed());
            counts = Some(exported.counts);
        }
        let page = viewer::page(&house, &glb, None, &name);
        let (b, e) = (median(build_times), median(export_times));
        let counts = counts.unwrap_or_default();
        println!(
            "| {name} | {} | {} | {:.1} | {:.2} | {:.1} % | {} | {} |",
            counts.rooms,
            counts.objects,
            b.as_secs_f64() * 1000.0,
            e.as_secs_f64() * 1000.0,
            100.0 * e.as_secs_f64() / b.as_secs_f64(),
            glb.len(),
            page.len()
        );
    }
}

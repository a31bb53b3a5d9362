//! Parsing and checking a generated 10,000-line scene.
//!
//! Run with `cargo bench --bench check_bench`; the figure is recorded in the book's
//! performance notes.

use criterion::{criterion_group, criterion_main, Criterion};
use std::fmt::Write as _;
use std::hint::black_box;

/// A scene of `rooms` rooms in a row, each with objects that relate to earlier ones; about
/// 100 lines per room.
fn generated_scene(rooms: usize) -> String {
    let mut text =
        String::from("scene \"a generated benchmark scene\" {\n  wall height 3 m\n  seed 1\n}\n");
    for r in 0..rooms {
        let x0 = r * 6;
        let _ = write!(
            text,
            "\nroom r{r} \"room {r}\" {{\n  floor \"oak\"\n  walls \"white\"\n  corners in m ({x0}, 0) ({x0}, 6) ({}, 6) ({}, 0)\n  window north fixed 150 cm x 120 cm, count 1, sill 90 cm\n",
            x0 + 6,
            x0 + 6
        );
        text.push_str("  object table \"table\" {\n    describe \"oak table\"\n    size 120 cm x 80 cm x 75 cm\n    middle\n  }\n");
        for k in 0..12 {
            let target = if k == 0 { "table-0".to_string() } else { format!("item{}-0", k - 1) };
            let _ = write!(
                text,
                "  object item{k} \"item\" {{\n    describe \"a thing\"\n    size 50 cm x 50 cm x 50 cm\n    edge\n    near {target}\n    face to table-0\n  }}\n"
            );
        }
        text.push_str(
            "  wall object painting \"painting\" {\n    above table-0\n    height 150 cm\n  }\n}\n",
        );
        if r > 0 {
            let _ = writeln!(text, "door r{} -- r{r} : doorway single \"door\"", r - 1);
        }
    }
    text
}

fn bench(c: &mut Criterion) {
    let text = generated_scene(100);
    assert!(text.lines().count() >= 10_000, "the scene has {} lines", text.lines().count());
    c.bench_function("parse+check 10k lines", |b| {
        b.iter(|| {
            let parsed = holoc::parse::parse_str(black_box(&text));
            let checked = holoc::check::check(&parsed.value);
            assert!(!checked.has_errors());
            black_box(checked.value.objects.len())
        });
    });
}

criterion_group!(benches, bench);
criterion_main!(benches);

//! Pins round-trip: the poses `holoc build --emit layout` prints, pinned back into the scene,
//! rebuild with no error into the very same house, for every example.

use holoc::ast::{Item, ObjectStmt, RoomStmt};
use std::collections::BTreeMap;
use std::fmt::Write as _;
use std::path::{Path, PathBuf};
use std::process::Command;

fn holoc() -> Command {
    Command::new(env!("CARGO_BIN_EXE_holoc"))
}

fn examples() -> Vec<PathBuf> {
    let mut out: Vec<PathBuf> = std::fs::read_dir("examples")
        .expect("examples folder")
        .flatten()
        .map(|e| e.path())
        .filter(|p| p.extension().is_some_and(|e| e == "holo"))
        .collect();
    out.sort();
    out
}

/// Runs `holoc build` and returns its standard output, failing on an error.
fn build(scene: &Path, args: &[&str]) -> String {
    let out = holoc()
        .arg("build")
        .arg(scene)
        .args(["--format", "short", "--quiet"])
        .args(args)
        .output()
        .expect("holoc runs");
    let stderr = String::from_utf8_lossy(&out.stderr);
    assert!(
        out.status.success() && !stderr.contains("error["),
        "{} {args:?} fails:\n{stderr}",
        scene.display()
    );
    String::from_utf8(out.stdout).expect("utf-8")
}

/// The pins of each object instance, by room: `floor x at …; facing …` and `wall x height …`
/// lines give the statements before their `//` comment.
fn pins_of(layout: &str) -> BTreeMap<(String, String), Vec<String>> {
    let mut room = String::new();
    let mut out: BTreeMap<(String, String), Vec<String>> = BTreeMap::new();
    for line in layout.lines() {
        if let Some(rest) = line.strip_prefix("room ") {
            room = rest.split(' ').next().unwrap_or_default().to_string();
            continue;
        }
        let line = line.trim();
        let Some(rest) = line.strip_prefix("floor ").or_else(|| line.strip_prefix("wall ")) else {
            continue;
        };
        let statements = rest.split("//").next().unwrap_or_default().trim();
        let (id, statements) = statements.split_once(' ').expect("an id and its pins");
        let pins = statements.split(';').map(|s| s.trim().to_string()).collect();
        out.insert((room.clone(), id.to_string()), pins);
    }
    out
}

/// The pin keywords a block already holds (`at`, `facing`, `height`): those are pinned by the
/// scene already, and a second one is an error.
fn pinned(body: &[ObjectStmt]) -> Vec<&'static str> {
    body.iter()
        .filter_map(|s| match s {
            ObjectStmt::At(..) => Some("at"),
            ObjectStmt::Facing(..) => Some("facing"),
            ObjectStmt::Height(..) => Some("height"),
            _ => None,
        })
        .collect()
}

/// The scene with the pins of every placed instance: in its `instance` block when it has one,
/// else in a new one.
fn pinned_source(text: &str, pins: &BTreeMap<(String, String), Vec<String>>) -> String {
    let file = holoc::parse::parse_str(text).value;
    let mut edits: Vec<(usize, String)> = Vec::new();
    for item in &file.items {
        let Item::Room(room) = item else { continue };
        for stmt in &room.body {
            let (RoomStmt::Object(o) | RoomStmt::WallObject(o)) = stmt else { continue };
            let group_pins = pinned(&o.body);
            let mut blocks = String::new();
            for ((r, id), statements) in pins {
                let group = id.rsplit_once('-').map_or(id.as_str(), |(g, _)| g);
                if *r != room.id.name || group != o.id.name {
                    continue;
                }
                let existing = o.body.iter().find_map(|s| match s {
                    ObjectStmt::Instance(inst) if inst.id.name == *id => Some(inst),
                    _ => None,
                });
                let mut already = group_pins.clone();
                if let Some(inst) = existing {
                    already.extend(pinned(&inst.body));
                }
                let lines: Vec<String> = statements
                    .iter()
                    .filter(|s| !already.iter().any(|k| s.split(' ').next() == Some(*k)))
                    .map(|s| format!("      {s}\n"))
                    .collect();
                if lines.is_empty() {
                    continue;
                }
                match existing {
                    Some(inst) => {
                        let end = inst.span.end as usize;
                        assert_eq!(&text[end - 1..end], "}", "a block ends with its brace");
                        edits.push((end - 1, format!("\n{}    ", lines.concat())));
                    }
                    None => {
                        let _ =
                            write!(blocks, "\n    instance {id} {{\n{}    }}\n", lines.concat());
                    }
                }
            }
            if blocks.is_empty() {
                continue;
            }
            let end = o.span.end as usize;
            if o.has_block {
                assert_eq!(&text[end - 1..end], "}", "a block ends with its brace");
                edits.push((end - 1, format!("{blocks}  ")));
            } else {
                edits.push((end, format!(" {{{blocks}  }}")));
            }
        }
    }
    assert!(!edits.is_empty(), "nothing to pin");
    edits.sort_by_key(|(at, _)| std::cmp::Reverse(*at));
    let mut out = text.to_string();
    for (at, insert) in edits {
        out.insert_str(at, &insert);
    }
    out
}

/// The statements of a layout, without the comments that say how each pose was found.
fn poses(layout: &str) -> String {
    layout
        .lines()
        .map(|l| l.split("//").next().unwrap_or_default().trim_end())
        .collect::<Vec<_>>()
        .join("\n")
}

#[test]
fn every_example_pinned_from_its_layout_rebuilds_into_the_same_house() {
    let dir = tempfile::tempdir().expect("a scratch folder");
    for path in examples() {
        let layout = build(&path, &["--emit", "layout", "-o", "-"]);
        for line in layout.lines().filter(|l| l.contains(" at ") || l.contains(" height ")) {
            // A unit on every number.
            let statements = line.split("//").next().unwrap_or_default();
            let words: Vec<&str> = statements.split_whitespace().collect();
            for (i, word) in words.iter().enumerate() {
                if word.trim_end_matches([',', ';']).parse::<f64>().is_ok() {
                    let unit = words.get(i + 1).copied().unwrap_or_default();
                    assert!(
                        unit.starts_with('m') || unit.starts_with("deg"),
                        "{}: `{word}` has no unit in `{line}`",
                        path.display()
                    );
                }
            }
        }
        let pins = pins_of(&layout);
        let text = std::fs::read_to_string(&path).expect("readable");
        let pinned = pinned_source(&text, &pins);
        let name = path.file_name().expect("a file name");
        let pinned_path = dir.path().join(name);
        std::fs::write(&pinned_path, &pinned).expect("written");

        let house = dir.path().join("before.json");
        let again = dir.path().join("after.json");
        build(&path, &["-o", house.to_str().expect("utf-8")]);
        build(&pinned_path, &["-o", again.to_str().expect("utf-8")]);
        let (a, b) = (
            std::fs::read_to_string(&house).expect("the house"),
            std::fs::read_to_string(&again).expect("the pinned house"),
        );
        assert!(a == b, "{}: the pinned scene builds another house:\n{pinned}", path.display());
        let layout_again = build(&pinned_path, &["--emit", "layout", "-o", "-"]);
        assert_eq!(poses(&layout_again), poses(&layout), "{}: the poses moved", path.display());
    }
}

//! Tests of `holoc import`.
//!
//! Corpus: one raw answer per file under `tests/corpus/import/<stage>/*.txt` (the folder names
//! the stage). Raw answers cannot carry a `// expect:` header, so a fixture may start with
//! directive lines that the driver strips before importing:
//! - `#! expect: E0701, W0702` — the set of codes the import must report (exactly, no order);
//! - `#! room: living room` — the room a per-room answer is about;
//! - `#! before: floor-plan ../floor-plan/clean.txt` — an earlier answer to import first, so
//!   that names are checked against it (path relative to the fixture).
//!
//! Each fixture's snapshot (`snapshots/import/`) holds the answer, the diagnostics and the
//! `.holo` output; the output must be in canonical form (print ∘ parse is the identity).

mod common;

use common::{corpus_name, render, snapshot_body};
use holoc::diag::Code;
use holoc::import::{self, ImportContext, ImportOptions, Stage};
use holoc::source::SourceMap;
use std::path::Path;

struct Fixture {
    expect: Option<Vec<String>>,
    room: Option<String>,
    before: Vec<(Stage, std::path::PathBuf)>,
    body: String,
}

fn read_fixture(path: &Path) -> Fixture {
    let text = std::fs::read_to_string(path).expect("fixture is readable");
    let mut f = Fixture { expect: None, room: None, before: Vec::new(), body: String::new() };
    let mut rest = text.as_str();
    while let Some(line) = rest.strip_prefix("#!") {
        let (directive, after) = line.split_once('\n').unwrap_or((line, ""));
        rest = after;
        let (key, value) = directive.split_once(':').expect("directive is `key: value`");
        let value = value.trim();
        match key.trim() {
            "expect" => {
                let mut codes: Vec<String> = value
                    .split(',')
                    .map(|c| c.trim().to_string())
                    .filter(|c| !c.is_empty())
                    .collect();
                codes.sort();
                codes.dedup();
                f.expect = Some(codes);
            }
            "room" => f.room = Some(value.to_string()),
            "before" => {
                let (stage, p) = value.split_once(' ').expect("before: STAGE PATH");
                let stage = Stage::parse(stage).expect("known stage");
                f.before.push((stage, path.parent().expect("folder").join(p.trim())));
            }
            other => panic!("unknown directive `{other}` in {}", path.display()),
        }
    }
    f.body = rest.to_string();
    f
}

fn stage_of(path: &Path) -> Stage {
    let folder = path.parent().and_then(Path::file_name).and_then(|n| n.to_str()).expect("folder");
    Stage::parse(folder).expect("corpus folder names a stage")
}

static MISMATCHES: std::sync::Mutex<Vec<String>> = std::sync::Mutex::new(Vec::new());

fn run_fixture(path: &Path) {
    let fixture = read_fixture(path);
    let mut sources = SourceMap::new();
    let mut ctx = ImportContext::new();
    for (stage, p) in &fixture.before {
        let earlier = read_fixture(p);
        // Named as the fixture is (`import/objects/clean.txt`), so that a snapshot that points
        // into it is the same on every machine.
        let mut normal = std::path::PathBuf::new();
        for part in p.components() {
            match part {
                std::path::Component::ParentDir => {
                    normal.pop();
                }
                other => normal.push(other),
            }
        }
        let id = sources.add(corpus_name(&normal), earlier.body);
        ctx.set_room(earlier.room.as_deref());
        ctx = import::import_answer(*stage, &sources, id, &ctx).value.context;
    }
    ctx.set_room(fixture.room.as_deref());
    let id = sources.add(corpus_name(path), fixture.body.clone());
    let out = import::import_answer(stage_of(path), &sources, id, &ctx);
    let holo = holoc::fmt::print(&out.value.fragment);
    // Canonical: printing the parsed output gives it back, and it parses without errors.
    let reparsed = holoc::parse::parse_str(&holo);
    assert!(
        !reparsed.has_errors(),
        "{}: output does not parse:\n{holo}\n{:?}",
        path.display(),
        reparsed.diagnostics
    );
    assert_eq!(
        holoc::fmt::print(&reparsed.value),
        holo,
        "{}: output is not canonical",
        path.display()
    );
    let mut codes: Vec<String> =
        out.diagnostics.iter().map(|d| d.code.as_str().to_string()).collect();
    codes.sort();
    codes.dedup();
    if let Some(expect) = &fixture.expect {
        if &codes != expect {
            MISMATCHES.lock().expect("lock").push(format!(
                "{}: expected {expect:?}, got {codes:?}\n{}",
                path.display(),
                render(&sources, &out.diagnostics)
            ));
        }
    }
    let body = snapshot_body(
        &corpus_name(path),
        &fixture.body,
        &render(&sources, &out.diagnostics),
        &holo,
    );
    insta::assert_snapshot!(body);
}

#[test]
fn import_corpus() {
    insta::with_settings!({
        snapshot_path => "../snapshots/import",
        prepend_module_to_snapshot => false,
        omit_expression => true,
    }, {
        insta::glob!("corpus/import", "**/*.txt", run_fixture);
    });
    let mismatches = MISMATCHES.lock().expect("lock");
    assert!(mismatches.is_empty(), "{}", mismatches.join("\n\n"));
}

/// The original Holodeck scene files of `../shared/data/real-scenes` (the ProcTHOR houses
/// beside them left out), in name order; `None` after saying that `test` is skipped when the
/// folder is absent.
fn real_holodeck_scenes(test: &str) -> Option<Vec<std::path::PathBuf>> {
    let dir = common::shared("data/real-scenes", test)?;
    let Ok(entries) = std::fs::read_dir(&dir) else {
        panic!("{} is not a readable folder", dir.display());
    };
    let mut paths: Vec<_> = entries
        .filter_map(Result::ok)
        .map(|e| e.path())
        .filter(|p| p.extension().is_some_and(|e| e == "json"))
        .filter(|p| {
            !p.file_name().and_then(|n| n.to_str()).is_some_and(|n| n.starts_with("procthor-"))
        })
        .collect();
    paths.sort();
    Some(paths)
}

/// The 8 real Holodeck scenes (reads `../shared/data/real-scenes`, relative to the repository
/// root; skipped with a message when absent) import to `.holo` files that `check` accepts,
/// with and without `--keep-layout`, deterministically.
#[test]
fn real_holodeck_scenes_import_and_check() {
    let Some(paths) = real_holodeck_scenes("real_holodeck_scenes_import_and_check") else { return };
    assert_eq!(paths.len(), 8, "expected the 8 Holodeck scenes");
    for path in paths {
        let value: serde_json::Value =
            serde_json::from_str(&std::fs::read_to_string(&path).expect("readable")).expect("json");
        for keep_layout in [false, true] {
            let options = ImportOptions { keep_layout };
            let mut sources = SourceMap::new();
            let out = import::import_holodeck_scene(&value, &mut sources, &options);
            // The model's answers in these files have real mistakes (e.g. a curtain of depth 0
            // in `a_sad_room`, read as 1 cm with a warning, as the original placed it): the
            // original built every one of these houses, so none is an error here.
            let unexpected: Vec<_> = out.diagnostics.iter().filter(|d| d.is_error()).collect();
            // A file without a constraint answer gets one W0705 per room, not one per object.
            let rooms = out.value.items.len();
            let w0705 = out.diagnostics.iter().filter(|d| d.code == Code::W0705).count();
            assert!(w0705 <= rooms, "{}: {w0705} W0705 for {rooms} items", path.display());
            assert!(
                unexpected.is_empty(),
                "{}: import errors\n{}",
                path.display(),
                render(&sources, &out.diagnostics)
            );
            let holo = holoc::fmt::print(&out.value);
            let again = import::import_holodeck_scene(&value, &mut SourceMap::new(), &options);
            assert_eq!(
                holoc::fmt::print(&again.value),
                holo,
                "{}: not deterministic",
                path.display()
            );
            let mut check_sources = SourceMap::new();
            let id = check_sources.add(path.display().to_string(), holo.clone());
            let checked = holoc::compile::check_file(&check_sources, id);
            let errors: Vec<_> =
                checked.diagnostics.iter().filter(|d| d.is_error()).cloned().collect();
            assert!(
                errors.is_empty(),
                "{} (keep_layout {keep_layout}) does not check:\n{}\n{holo}",
                path.display(),
                render(&check_sources, &errors)
            );
            let reparsed = holoc::parse::parse_str(&holo);
            assert_eq!(holoc::fmt::print(&reparsed.value), holo, "not canonical");
        }
    }
}

/// The line and column of a diagnostic's primary label, and the name of its file.
fn place(sources: &SourceMap, d: &holoc::diag::Diagnostic) -> (String, usize, usize) {
    let label = d.primary.as_ref().expect("a primary label");
    let file = sources.get(label.span.file);
    let before = &file.text[..label.span.start as usize];
    let line = before.matches('\n').count() + 1;
    let column = before.len() - before.rfind('\n').map_or(0, |i| i + 1) + 1;
    (file.name.clone(), line, column)
}

/// An original scene file's diagnostics point at the lines they are about, in the file (issue
/// 33): the one W0705 of a file without constraint answers at its `object_selection_plan`, each
/// room's entry labelled; an object's warning at its entry; a raw answer's at its characters.
#[test]
fn scene_file_warnings_point_at_their_lines() {
    let text = r#"{
    "query": "a small bedroom",
    "raw_floor_plan": "bedroom | oak | white | [(0, 0), (0, 4), (4, 4), (4, 0)]\nstudy | oak | white | [(4, 0), (4, 4), (7, 4), (7, 0)]",
    "wall_height": 2.7,
    "raw_doorway_plan": "1. exterior | bedroom | doorway | single | white door\nbedroom | study | doorframe | single | oak",
    "object_selection_plan": {
        "bedroom": {
            "bed": {"description": "double bed", "location": "floor", "size": [200, 160, 50], "quantity": 1, "variance_type": "same", "objects_on_top": []},
            "bookcase": {
                "description": "tall bookcase",
                "location": "floor",
                "size": [90, 30, 180],
                "quantity": 1,
                "variance_type": "same",
                "objects_on_top": [{"object_name": "book", "quantity": 30, "variance_type": "varied"}]
            }
        },
        "study": {
            "desk": {"description": "oak desk", "location": "floor", "size": [120, 60, 75], "quantity": 2, "variance_type": "same", "objects_on_top": []}
        }
    }
}"#;
    let value: serde_json::Value = serde_json::from_str(text).expect("json");
    let mut sources = SourceMap::new();
    let file = sources.add("scene.json", text);
    let out =
        import::import_holodeck_scene_file(&value, &mut sources, file, &ImportOptions::default());
    assert!(!out.has_errors(), "{}", render(&sources, &out.diagnostics));
    let line_of = |needle: &str| {
        let at = text.find(needle).expect("in the text");
        text[..at].matches('\n').count() + 1
    };
    for d in &out.diagnostics {
        let (name, line, column) = place(&sources, d);
        assert_eq!(name, "scene.json", "{:?} points into a copy", d.message);
        assert!((line, column) != (1, 1), "{:?} points at the file's start", d.message);
    }
    let w0705: Vec<_> = out.diagnostics.iter().filter(|d| d.code == Code::W0705).collect();
    assert_eq!(w0705.len(), 1, "one W0705 for the whole file");
    assert_eq!(place(&sources, w0705[0]).1, line_of("\"object_selection_plan\""));
    assert!(
        w0705[0].message.contains("the 4 floor objects of its 2 rooms"),
        "{}",
        w0705[0].message
    );
    let rooms: Vec<usize> = w0705[0]
        .secondary
        .iter()
        .map(|l| text[..l.span.start as usize].matches('\n').count() + 1)
        .collect();
    assert_eq!(rooms, [line_of("\"bedroom\": {"), line_of("\"study\": {")]);
    let books = out
        .diagnostics
        .iter()
        .find(|d| d.message.contains("quantity 30 of `book`"))
        .expect("the 30 books are capped");
    assert_eq!(place(&sources, books).1, line_of("\"bookcase\""));
    let numbering =
        out.diagnostics.iter().find(|d| d.code == Code::W0701).expect("the numbering is noise");
    let (_, line, column) = place(&sources, numbering);
    assert_eq!(line, line_of("\"raw_doorway_plan\""));
    assert_eq!(&text.lines().nth(line - 1).expect("line")[column - 1..=column], "1.");
    // The same file with its layout kept: no pose for anything, so one W0705 as well, with the
    // objects labelled.
    let kept = import::import_holodeck_scene_file(
        &value,
        &mut sources,
        file,
        &ImportOptions { keep_layout: true },
    );
    let w0705: Vec<_> = kept.diagnostics.iter().filter(|d| d.code == Code::W0705).collect();
    assert_eq!(w0705.len(), 1, "{}", render(&sources, &kept.diagnostics));
    assert_eq!(w0705[0].secondary.len(), 3, "bed, bookcase and desk");
}

/// A floor-constraint answer that leaves out an object: one W0705 per object, at its line of
/// the object selection, naming its instances (not one per instance at the answer's start).
#[test]
fn an_object_left_out_of_the_constraints_is_warned_at_its_declaration() {
    let json = r#"{"format": "holoc-transcript", "version": 1, "request": "a small bedroom", "seed": 3,
      "exchanges": [
        {"stage": "floor-plan", "answer": "bedroom | oak | white | [(0, 0), (0, 4), (4, 4), (4, 0)]"},
        {"stage": "doorways", "answer": "exterior | bedroom | doorway | single | white door"},
        {"stage": "objects", "room": "bedroom", "answer": "{\n\"bed\": {\"description\": \"double bed\", \"location\": \"floor\", \"size\": [200, 160, 50], \"quantity\": 1, \"variance_type\": \"same\", \"objects_on_top\": []},\n\"nightstand\": {\"description\": \"oak\", \"location\": \"floor\", \"size\": [50, 40, 55], \"quantity\": 2, \"variance_type\": \"same\", \"objects_on_top\": []}\n}"},
        {"stage": "floor-constraints", "room": "bedroom", "answer": "bed-0 | edge"}
      ]}"#;
    let t: import::Transcript = serde_json::from_str(json).expect("transcript");
    let mut sources = SourceMap::new();
    let out = import::import_transcript(&t, &mut sources, &ImportOptions::default());
    let w0705: Vec<_> = out.diagnostics.iter().filter(|d| d.code == Code::W0705).collect();
    assert_eq!(w0705.len(), 1, "{}", render(&sources, &out.diagnostics));
    assert_eq!(
        w0705[0].message,
        "`nightstand-0` and `nightstand-1` in `bedroom` have no constraints; they will be placed at an edge"
    );
    let (name, line, _) = place(&sources, w0705[0]);
    assert_eq!((name.as_str(), line), ("objects[bedroom]#0", 3));
}

/// The 8 real Holodeck scenes: with their diagnostics pointed into the file (as `holoc import`
/// does), none points at its first line or into the answers' copies, and each has one W0705 at
/// most (reads `../shared/data/real-scenes`; skipped with a message when absent).
#[test]
fn real_scene_warnings_point_into_the_file() {
    let Some(paths) = real_holodeck_scenes("real_scene_warnings_point_into_the_file") else {
        return;
    };
    for path in paths {
        let text = std::fs::read_to_string(&path).expect("readable");
        let value: serde_json::Value = serde_json::from_str(&text).expect("json");
        for keep_layout in [false, true] {
            let mut sources = SourceMap::new();
            let file = sources.add(path.display().to_string(), text.clone());
            let out = import::import_holodeck_scene_file(
                &value,
                &mut sources,
                file,
                &ImportOptions { keep_layout },
            );
            let w0705 = out.diagnostics.iter().filter(|d| d.code == Code::W0705).count();
            assert!(w0705 <= 1, "{}: {w0705} W0705", path.display());
            for d in &out.diagnostics {
                let (name, line, column) = place(&sources, d);
                assert_eq!(name, path.display().to_string(), "{}: {:?}", path.display(), d.message);
                assert!((line, column) != (1, 1), "{}: {:?} at 1:1", path.display(), d.message);
            }
        }
    }
}

/// A transcript with repairs: the highest attempt wins, per-room stages use their room.
#[test]
fn transcript_imports_latest_attempts() {
    let json = r#"{"format": "holoc-transcript", "version": 1, "request": "a small bedroom", "seed": 3,
      "exchanges": [
        {"stage": "wall-height", "answer": "2.8"},
        {"stage": "floor-plan", "answer": "bedroom | oak | white | [(0, 0), (0, 4)]"},
        {"stage": "floor-plan", "attempt": 1, "answer": "bedroom | oak | white | [(0, 0), (0, 4), (4, 4), (4, 0)]"},
        {"stage": "doorways", "answer": "exterior | bedroom | doorway | single | white door"},
        {"stage": "objects", "room": "bedroom", "answer": "{\"bed\": {\"description\": \"double bed\", \"location\": \"floor\", \"size\": [200, 160, 50], \"quantity\": 1, \"variance_type\": \"same\", \"objects_on_top\": []}, \"nightstand\": {\"description\": \"oak\", \"location\": \"floor\", \"size\": [50, 40, 55], \"quantity\": 2, \"variance_type\": \"same\", \"objects_on_top\": [{\"object_name\": \"lamp\", \"quantity\": 1, \"variance_type\": \"same\"}]}}"},
        {"stage": "floor-constraints", "room": "bedroom", "answer": "bed-0 | edge\nnightstand-0 | edge | near, bed-0\nnightstand-1 | edge | near, bed-0"}
      ]}"#;
    let t: import::Transcript = serde_json::from_str(json).expect("transcript");
    let mut sources = SourceMap::new();
    let out = import::import_transcript(&t, &mut sources, &ImportOptions::default());
    assert!(!out.has_errors(), "{}", render(&sources, &out.diagnostics));
    let holo = holoc::fmt::print(&out.value);
    insta::with_settings!({snapshot_path => "../snapshots/import", prepend_module_to_snapshot => false}, {
        insta::assert_snapshot!("transcript_latest_attempts", holo);
    });
    let mut cs = SourceMap::new();
    let id = cs.add("t.holo", holo.clone());
    let checked = holoc::compile::check_file(&cs, id);
    assert!(!checked.has_errors(), "{}\n{holo}", render(&cs, &checked.diagnostics));
}

mod fuzz {
    use super::{import, ImportContext, SourceMap, Stage};
    use proptest::prelude::*;

    fn import_all(text: &str) {
        for &stage in Stage::ALL {
            let mut sources = SourceMap::new();
            let id = sources.add("fuzz", text.to_string());
            let out = import::import_answer(stage, &sources, id, &ImportContext::new());
            let holo = holoc::fmt::print(&out.value.fragment);
            let reparsed = holoc::parse::parse_str(&holo);
            assert_eq!(holoc::fmt::print(&reparsed.value), holo);
        }
    }

    const SEEDS: &[&str] = &[
        "living room | oak | white | [(0, 0), (0, 4), (4, 4), (4, 0)]",
        "exterior | living room | doorway | double | oak door",
        "living room | west | fixed | (130, 130) | 1 | 50",
        "{\"sofa\": {\"description\": \"grey\", \"location\": \"floor\", \"size\": [200, 90, 80], \"quantity\": 2, \"variance_type\": \"same\", \"objects_on_top\": [{\"object_name\": \"pillow\", \"quantity\": 2, \"variance_type\": \"varied\"}]}}",
        "sofa-0 | edge\ntable-0 | middle | near, sofa-0 | face to, sofa-0",
        "painting-0 | above, sofa-0 | 160",
        "sofa-0 (living room) | pillow, 2, varied | book, 1, same",
        "[{\"object_name\": \"sofa-0\", \"position\": {\"X\": 100, \"Y\": 50}, \"rotation\": 90}]",
    ];

    proptest! {
        #![proptest_config(ProptestConfig { cases: 64, rng_seed: proptest::test_runner::RngSeed::Fixed(0x686f_6c6f), .. ProptestConfig::default() })]

        #[test]
        fn random_text_never_panics(text in "\\PC{0,200}") {
            import_all(&text);
        }

        #[test]
        fn mutated_answers_never_panic(seed in 0usize..8, at in 0usize..400, insert in "[|,()\\[\\]{}\"0-9a-z\\-\\.\n ]{0,6}", cut in 0usize..8) {
            let base = SEEDS[seed];
            let mut at = at.min(base.len());
            while !base.is_char_boundary(at) { at -= 1; }
            let end = (at + cut).min(base.len());
            let mut end = end;
            while !base.is_char_boundary(end) { end -= 1; }
            let text = format!("{}{}{}", &base[..at], insert, &base[end.max(at)..]);
            import_all(&text);
        }
    }

    #[test]
    fn adversarial_inputs_never_panic() {
        let big = "living room | oak | white | [(0, 0), (0, 4), (4, 4), (4, 0)]\n".repeat(20_000);
        assert!(big.len() > 1_000_000);
        import_all(&big);
        import_all("");
        import_all("\u{0}\u{1}\u{fffd}\u{7f}|||||\u{200b}");
        import_all("{{{{[[[[(((( | ]]]] }}}");
        import_all("a | NaN | inf | -1e400 | 1e400 | -0");
        import_all("客厅 | 木地板 | 白墙 | [(0, 0), (0, 4), (4, 4), (4, 0)]");
        import_all(&"[".repeat(10_000));
        import_all(&"{".repeat(10_000));
    }
}

/// A lone carriage return ends a line, as `\n` and `\r\n` do: the three spellings of one answer
/// import to the same `.holo`, and a long answer whose lines end in `\r` is read line by line.
#[test]
fn every_line_end_spelling_imports_the_same() {
    let lines = ["sofa-0 | edge", "coffee_table-0 | middle | near, sofa-0", "tv_stand-0 | edge"];
    let import_with = |sep: &str| {
        let mut sources = SourceMap::new();
        let id = sources.add("answer", lines.join(sep));
        let out =
            import::import_answer(Stage::FloorConstraints, &sources, id, &ImportContext::new());
        assert!(!out.has_errors(), "{sep:?}: {}", render(&sources, &out.diagnostics));
        holoc::fmt::print(&out.value.fragment)
    };
    let unix = import_with("\n");
    assert_eq!(import_with("\r\n"), unix);
    assert_eq!(import_with("\r"), unix);
    assert!(unix.contains("coffee_table"), "{unix}");
}

/// A wall height given in prose is the number with a length unit and the words around it, not
/// the first number of the answer (`1b1b` is part of a word).
#[test]
fn wall_height_is_read_from_prose() {
    for (answer, want) in [
        ("For a 1b1b apartment, a wall height of 2.7 m works well.", "wall height 2.7 m"),
        ("Ceilings about 280 cm high suit a studio of 2 rooms", "wall height 2.8 m"),
        ("In 2024 homes, 2.5", "wall height 2.5 m"),
        ("3.0", "wall height 3 m"),
    ] {
        let mut sources = SourceMap::new();
        let id = sources.add("answer", answer.to_string());
        let out = import::import_answer(Stage::WallHeight, &sources, id, &ImportContext::new());
        let holo = holoc::fmt::print(&out.value.fragment);
        assert!(holo.contains(want), "{answer:?} gives\n{holo}");
    }
}

/// The model's order of lines is the placement order, even where instances of one object are
/// grouped in one block: `counter-1 | near, stove-0` after `stove-0` keeps its relation, and
/// the checked scene places counter-0, stove-0, counter-1 in that order.
#[test]
fn grouped_instances_keep_the_models_order() {
    let answer =
        "counter-0 | edge\nstove-0 | edge | near, counter-0\ncounter-1 | edge | near, stove-0\n";
    let mut sources = SourceMap::new();
    let id = sources.add("answer", answer.to_string());
    let out = import::import_answer(Stage::FloorConstraints, &sources, id, &ImportContext::new());
    assert!(!out.has_errors(), "{}", render(&sources, &out.diagnostics));
    let mut holo = holoc::fmt::print(&out.value.fragment);
    assert!(holo.contains("near stove-0"), "{holo}");
    // Give the room an outline and check the scene: no error, and the placement order.
    holo = holo.replacen("{\n", "{\n  corners in m (0, 0) (0, 4) (5, 4) (5, 0)\n", 1);
    let mut sources = SourceMap::new();
    let file = sources.add("scene.holo", holo.clone());
    let checked = holoc::compile::check_file(&sources, file);
    assert!(
        !checked.diagnostics.iter().any(holoc::diag::Diagnostic::is_error),
        "{holo}\n{}",
        render(&sources, &checked.diagnostics)
    );
    let scene = checked.value.expect("a scene");
    let order: Vec<&str> =
        scene.rooms[0].objects.iter().map(|&o| scene.object(o).name.as_str()).collect();
    assert_eq!(order, ["counter-0", "stove-0", "counter-1"]);
}

/// Issue 33's measure: the original's real scenes, imported and built with AI2-THOR's own
/// assets, keep at least 80% of their objects that have an asset (placed over asked less those
/// left out for want of an asset, W0401, over the 8 scenes). Things on a receptacle that has no
/// asset (the floating wall shelves of most of them) go to the room's receptacles that take them
/// (W0506); every house has unique ids. Reads `../shared/data/real-scenes`.
#[test]
fn real_holodeck_scenes_keep_what_has_an_asset() {
    let Some(paths) = real_holodeck_scenes("real_holodeck_scenes_keep_what_has_an_asset") else {
        return;
    };
    let catalog = holoc::resolve::Catalog::embedded();
    let (mut placed_all, mut with_asset_all) = (0usize, 0usize);
    let mut lines = Vec::new();
    for path in &paths {
        let value: serde_json::Value =
            serde_json::from_str(&std::fs::read_to_string(path).expect("readable")).expect("json");
        let out = import::import_holodeck_scene(
            &value,
            &mut SourceMap::new(),
            &ImportOptions { keep_layout: false },
        );
        let holo = holoc::fmt::print(&out.value);
        let mut sources = SourceMap::new();
        let id = sources.add(path.display().to_string(), holo);
        let built =
            holoc::compile::build(&sources, id, &holoc::compile::BuildOptions::new(&catalog));
        let Some(built) = built.value else {
            panic!("{} does not build:\n{}", path.display(), render(&sources, &built.diagnostics));
        };
        let mut placed = 0;
        let mut no_asset = 0;
        let mut asked = 0;
        for room in &built.layout.rooms {
            let l = &room.layout;
            let here =
                l.floor.len() + l.wall.len() + l.small.len() + usize::from(l.ceiling.is_some());
            placed += here;
            asked += here + l.unplaced.len();
            no_asset += l.unplaced.iter().filter(|u| u.code == Code::W0401).count();
        }
        let mut ids: Vec<&str> = built.house.all_objects().iter().map(|o| o.id.as_str()).collect();
        let n = ids.len();
        ids.sort_unstable();
        ids.dedup();
        assert_eq!(ids.len(), n, "{}: object ids repeat", path.display());
        lines.push(format!(
            "{}: {placed} of {asked} placed, {} with an asset",
            path.display(),
            asked - no_asset
        ));
        placed_all += placed;
        with_asset_all += asked - no_asset;
    }
    let share = placed_all as f64 / with_asset_all.max(1) as f64;
    // 0.80 before issue 48: an item whose receptacle is full or lacks an asset is now moved only
    // to a home for it (p ≥ 0.05, at most 3 moved things each) and reported otherwise, where it
    // used to land anywhere (clocks on sofas); the real requests pile 10–14 things on each wall
    // shelf.
    assert!(
        share >= 0.75,
        "{placed_all} of {with_asset_all} objects with an asset placed ({:.1}%):\n{}",
        100.0 * share,
        lines.join("\n")
    );
}

/// Imports one stand-alone answer of `stage` for `room`: its `.holo` and its diagnostics.
fn standalone(
    stage: Stage,
    room: Option<&str>,
    answer: &str,
) -> (String, Vec<holoc::diag::Diagnostic>, SourceMap) {
    let mut sources = SourceMap::new();
    let id = sources.add("answer", answer.to_string());
    let mut ctx = ImportContext::new();
    ctx.set_room(room);
    let out = import::import_answer(stage, &sources, id, &ctx);
    (holoc::fmt::print(&out.value.fragment), out.diagnostics, sources)
}

/// Builds a `.holo` (its rooms given an outline where they have none) with the default
/// catalog: whether it builds, and the diagnostics.
fn builds(holo: &str) -> (bool, String) {
    let with_corners = holo.replacen(
        "room living_room \"living room\" {\n",
        "room living_room \"living room\" {\n  corners in m (0, 0) (0, 6) (6, 6) (6, 0)\n",
        1,
    );
    let text = format!("{with_corners}door exterior -- living_room : doorway single\n");
    let catalog = holoc::resolve::Catalog::embedded();
    let mut sources = SourceMap::new();
    let id = sources.add("scene.holo", text.clone());
    let built = holoc::compile::build(&sources, id, &holoc::compile::BuildOptions::new(&catalog));
    (built.value.is_some(), format!("{text}\n{}", render(&sources, &built.diagnostics)))
}

/// Issue 50: names are resolved after the whole answer is read, in every stage whose lines name
/// things (floor and wall constraints, small objects, doorways, windows, ceiling, absolute
/// layout): a line may name what a later line declares, and a stand-alone answer declares what
/// it names by one rule, spaces and capitals included. None of these is an error.
#[test]
fn every_stage_reads_names_declared_later() {
    let cases: &[(Stage, &str, &[&str])] = &[
        (
            Stage::FloorConstraints,
            "coffee_table-0 | middle | in front of, sofa-0 | near, armchair-0\n\
             sofa-0 | edge\narmchair-0 | edge | near, sofa-0\n",
            &["in front of sofa-0", "near armchair-0", "near sofa-0"],
        ),
        (
            Stage::WallConstraints,
            "painting-0 | above, TV Stand-0 | 160\nmirror-0 | above, tv stand-0 | 150\n",
            &["above tv_stand-0", "object tv_stand"],
        ),
        (
            Stage::SmallObjects,
            "sofa-0 (living room) | remote control for TV, 1, same | book, 2, varied | gray fabric pillow, 2, varied\n\
             tv stand-0 (living room) | 49 inch TV, 1, same | speaker, 2, same\n\
             Book Shelf 2-0 (living room) | vase, 1, same\n",
            &["object sofa", "object tv_stand", "object book_shelf_2", "\"49 inch TV\""],
        ),
        (
            Stage::Doorways,
            "living room | kitchen | doorway | single | oak door\nexterior | kitchen | doorway | single | oak door\n",
            &["door living_room -- kitchen", "door exterior -- kitchen"],
        ),
        (
            Stage::Windows,
            "living room | south | fixed | (130, 130) | 1 | 50\nBed Room | north | fixed | (100, 100) | 1 | 60\n",
            &["room living_room", "room bed_room"],
        ),
        (Stage::Ceiling, "living room | white light\nKitchen 2 | pendant\n", &["room kitchen_2"]),
        (
            Stage::AbsoluteLayout,
            "[{\"object_name\": \"TV Stand-0\", \"position\": {\"X\": 100, \"Y\": 50}, \"rotation\": 0}, \
             {\"object_name\": \"sofa-0\", \"position\": {\"X\": 300, \"Y\": 50}, \"rotation\": 90}]",
            &["object tv_stand", "object sofa"],
        ),
    ];
    for (stage, answer, wanted) in cases {
        let (holo, diagnostics, sources) = standalone(*stage, Some("living room"), answer);
        assert!(
            !diagnostics.iter().any(holoc::diag::Diagnostic::is_error),
            "{stage}: {}\n{holo}",
            render(&sources, &diagnostics)
        );
        for w in *wanted {
            assert!(holo.contains(w), "{stage}: `{w}` missing from\n{holo}");
        }
    }
}

/// Issue 50's first answer: a relation names `armchair-0` one line before its line. It is kept
/// where it closes no circle; here `armchair-0` names `coffee_table-0` back, so the relation of
/// `coffee_table-0` (the one naming a later line) is dropped with W0708 and kept as a comment,
/// and the room imports and builds.
#[test]
fn a_relation_to_a_later_line_is_kept_or_breaks_a_circle() {
    let answer = "sofa-0 | edge\n\
                  coffee_table-0 | middle | in front of, sofa-0 | near, armchair-0\n\
                  armchair-0 | middle | near, coffee_table-0 | face to, coffee_table-0\n";
    let (holo, diagnostics, sources) =
        standalone(Stage::FloorConstraints, Some("living room"), answer);
    let codes: Vec<&str> = diagnostics.iter().map(|d| d.code.as_str()).collect();
    assert_eq!(codes, ["W0708"], "{}", render(&sources, &diagnostics));
    assert!(holo.contains("// raw floor-constraints: near, armchair-0"), "{holo}");
    assert!(
        holo.contains("near coffee_table-0") && holo.contains("face to coffee_table-0"),
        "{holo}"
    );
    let (built, why) = builds(&holo);
    assert!(built, "{why}");
    // Without the circle, the relation to the later line stays and the scene builds.
    let answer = "sofa-0 | edge\n\
                  coffee_table-0 | middle | in front of, sofa-0 | near, armchair-0\n\
                  armchair-0 | edge | near, sofa-0\n";
    let (holo, diagnostics, sources) =
        standalone(Stage::FloorConstraints, Some("living room"), answer);
    assert!(diagnostics.is_empty(), "{}", render(&sources, &diagnostics));
    assert!(holo.contains("near armchair-0"), "{holo}");
    let (built, why) = builds(&holo);
    assert!(built, "{why}");
}

/// Issue 50's second answer: a stand-alone small-object answer with a receptacle whose name has
/// a space imports both receptacles as objects, and the room builds.
#[test]
fn a_receptacle_with_a_space_is_an_object_too() {
    let answer = "sofa-0 (living room) | remote control for TV, 1, same | book, 2, varied | gray fabric pillow, 2, varied\n\
                  tv stand-0 (living room) | 49 inch TV, 1, same | speaker, 2, same\n";
    let (holo, diagnostics, sources) = standalone(Stage::SmallObjects, None, answer);
    assert!(diagnostics.is_empty(), "{}", render(&sources, &diagnostics));
    assert!(holo.contains("object tv_stand \"tv stand\""), "{holo}");
    assert!(holo.contains("on top \"49 inch TV\""), "{holo}");
    let (built, why) = builds(&holo);
    assert!(built, "{why}");
}

/// A scratch folder of this test binary, emptied.
fn scratch(name: &str) -> std::path::PathBuf {
    let dir = std::env::temp_dir().join(format!("holoc-import-{}-{name}", std::process::id()));
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).expect("scratch folder");
    dir
}

/// `import -o` writes the scene whenever something could be read, errors or not (the unusable
/// lines kept as `// raw` comments, exit status 1), and nothing when nothing could be read.
#[test]
fn import_output_is_written_whenever_something_was_read() {
    let dir = scratch("output");
    let answer = dir.join("constraints.txt");
    std::fs::write(&answer, "sofa-0 | edge\ntable-0 | middle | near, lamp-9\n").expect("write");
    let scene = dir.join("scene.holo");
    let run = std::process::Command::new(env!("CARGO_BIN_EXE_holoc"))
        .args([
            "import",
            "--stage",
            "floor-constraints",
            "--room",
            "living room",
            "--format",
            "short",
        ])
        .arg(&answer)
        .arg("-o")
        .arg(&scene)
        .output()
        .expect("runs");
    let stderr = String::from_utf8_lossy(&run.stderr);
    assert_eq!(run.status.code(), Some(1), "{stderr}");
    assert!(stderr.contains("E0707"), "{stderr}");
    assert!(stderr.contains("1 error above"), "{stderr}");
    let written = std::fs::read_to_string(&scene).expect("the scene is written");
    assert!(
        written.contains("object sofa")
            && written.contains("// raw floor-constraints: near, lamp-9"),
        "{written}"
    );
    // Nothing readable: no file, and it says so.
    let empty = dir.join("empty.txt");
    std::fs::write(&empty, "I cannot help with that.\n").expect("write");
    let nothing = dir.join("nothing.holo");
    let run = std::process::Command::new(env!("CARGO_BIN_EXE_holoc"))
        .args(["import", "--stage", "floor-constraints", "--room", "living room"])
        .arg(&empty)
        .arg("-o")
        .arg(&nothing)
        .output()
        .expect("runs");
    let stderr = String::from_utf8_lossy(&run.stderr);
    assert_eq!(run.status.code(), Some(1), "{stderr}");
    assert!(!nothing.exists(), "{stderr}");
    assert!(stderr.contains("nothing could be read"), "{stderr}");
    let _ = std::fs::remove_dir_all(&dir);
}

//! Lower stage: every example and every valid plan fixture becomes a house JSON that is
//! snapshotted in `snapshots/lower/`, is byte-identical when built twice, and passes
//! `holoc validate` without errors.

mod common;

use holoc::lower::{lower, validate::validate};
use holoc::plan::plan;
use holoc::resolve::structure::StructureCatalog;
use holoc::source::SourceMap;
use std::path::Path;

/// Builds a `.holo` file to house JSON text (panics with the diagnostics when it fails).
pub fn build_json(path: &Path) -> String {
    let text = std::fs::read_to_string(path).expect("readable");
    let mut sources = SourceMap::new();
    let id = sources.add(path.display().to_string(), text);
    let checked = holoc::compile::check_file(&sources, id);
    let scene = checked.value.expect("no syntax errors");
    let planned = plan(&scene, StructureCatalog::builtin());
    assert!(
        !planned.diagnostics.iter().any(holoc::diag::Diagnostic::is_error),
        "{}",
        common::render(&sources, &planned.diagnostics)
    );
    lower(&scene, &planned.value, &[]).to_json_string()
}

fn inputs() -> Vec<std::path::PathBuf> {
    let mut out = Vec::new();
    for dir in ["examples", "tests/corpus/plan/ok"] {
        for entry in std::fs::read_dir(dir).expect("folder") {
            let path = entry.expect("entry").path();
            if path.extension().is_some_and(|e| e == "holo") {
                out.push(path);
            }
        }
    }
    out.sort();
    out
}

#[test]
fn lower_snapshots() {
    insta::with_settings!({
        snapshot_path => "../snapshots/lower",
        prepend_module_to_snapshot => false,
        omit_expression => true,
    }, {
        for path in inputs() {
            let name = path.to_string_lossy().replace(['/', '\\'], "__").replace(".holo", "");
            insta::assert_snapshot!(name, build_json(&path));
        }
    });
}

#[test]
fn same_input_same_bytes() {
    for path in inputs() {
        assert_eq!(build_json(&path), build_json(&path), "{}", path.display());
    }
}

#[test]
fn outputs_validate() {
    for path in inputs() {
        let json = build_json(&path);
        let mut sources = SourceMap::new();
        let id = sources.add("house.json", json);
        let outcome = validate(
            &sources,
            id,
            StructureCatalog::builtin(),
            &holoc::resolve::Catalog::embedded(),
        );
        assert!(
            outcome.diagnostics.is_empty(),
            "{}: {}",
            path.display(),
            common::render(&sources, &outcome.diagnostics)
        );
    }
}

#[test]
fn objects_get_their_room_layer() {
    let (scene, planned, object) = hallway_with_a_desk();
    let room = object.room;
    let house = lower(&scene, &planned.value, &[object]);
    let o = &house.house.objects[0];
    assert_eq!(o.layer, planned.value.layer_name(room));
    assert_eq!(o.room_id, "office-2");
    let json = house.to_json_string();
    let mut sources = SourceMap::new();
    let id = sources.add("house.json", json);
    let outcome =
        validate(&sources, id, StructureCatalog::builtin(), &holoc::resolve::Catalog::embedded());
    let codes: Vec<&str> = outcome.diagnostics.iter().map(|d| d.code.as_str()).collect();
    // The desk stands where the test put it, which may be against furniture of nobody: the
    // house is structurally valid whatever warnings its made-up pose gets.
    assert!(outcome.diagnostics.iter().all(|d| !d.is_error()), "{codes:?}");
}

/// Items on a receptacle are written among its `children` and left to physics, as ProcTHOR
/// writes them.
#[test]
fn items_on_a_receptacle_are_its_children() {
    let (scene, planned, desk) = hallway_with_a_desk();
    let room = desk.room;
    let laptop = holoc::lower::LoweredObject {
        id: "laptop-0|desk-0 (office-2)".into(),
        asset_id: "Laptop_1".into(),
        room,
        position_m: [6.0, 0.8, 4.0],
        rotation_deg: [0.0, 90.0, 0.0],
        kinematic: false,
        object_name: "laptop-0".into(),
        parent: Some("desk-0 (office-2)".into()),
        source: holoc::lower::Source::Item(holoc::check::scene::ObjectId(0), 0, 0),
        layout_id: "laptop-0|desk-0".into(),
    };
    let house = lower(&scene, &planned.value, &[desk, laptop]);
    assert_eq!(house.house.objects.len(), 1, "only the desk is at the top level");
    let children = &house.house.objects[0].children;
    assert_eq!(children.len(), 1);
    assert_eq!(children[0].id, "laptop-0|desk-0 (office-2)");
    assert!(!children[0].kinematic);
    assert_eq!(house.object_count(), 2);
    let json: serde_json::Value = serde_json::from_str(&house.to_json_string()).expect("json");
    assert_eq!(json["objects"][0]["children"][0]["assetId"], "Laptop_1");
}

#[test]
fn room_labels_map_to_procthor_room_types() {
    for (label, want) in [
        ("living room", "LivingRoom"),
        ("Kitchen", "Kitchen"),
        ("kitchen and living room", "Kitchen"),
        ("master bedroom", "Bedroom"),
        ("guest bathroom", "Bathroom"),
        ("powder room", "Bathroom"),
        ("nursery", "Bedroom"),
        ("office", "office"),
        ("music room", "music room"),
    ] {
        assert_eq!(holoc::lower::room_type(label), want, "{label}");
    }
}

/// Two `on top` lines naming the same item (a small-objects answer that repeats what the object
/// selection already put on the desk) give objects with different ids, which `validate` accepts.
#[test]
fn repeated_items_on_a_receptacle_get_their_own_ids() {
    let text = "scene \"t\" { seed 1 }\n\nroom a \"a\" {\n  corners in m (0, 0) (0, 4) (4, 4) (4, 0)\n  object desk \"desk\" {\n    edge\n    on top \"desk lamp\" x1 same\n    on top \"desk lamp\" x1 same\n  }\n}\n\ndoor exterior -- a : doorway single\n";
    let (_, out) = build_text(text);
    let built = out.value.expect("builds");
    let ids: Vec<&str> = built.house.all_objects().iter().map(|o| o.id.as_str()).collect();
    let unique: std::collections::BTreeSet<&str> = ids.iter().copied().collect();
    assert_eq!(ids.len(), unique.len(), "{ids:?}");
    assert!(ids.contains(&"desk lamp-1|desk-0 (a)"), "{ids:?}");
}

/// Objects placed by their position relative to an object that is left out follow it out
/// (W0503) and are listed as left out; one that only faces it stays.
#[test]
fn objects_placed_around_a_missing_object_are_left_out() {
    let text = "scene \"t\" { seed 1 }\n\nroom music \"music room\" {\n  corners in m (0, 0) (0, 5) (5, 5) (5, 0)\n  object piano \"grand piano\" {\n    describe \"black lacquered grand piano\"\n    edge\n  }\n  object stool \"stool\" {\n    middle\n    in front of piano-0\n    near piano-0\n  }\n  object sofa \"sofa\" {\n    edge\n    face to piano-0\n  }\n}\n\ndoor exterior -- music : doorway single\n";
    let (_, out) = build_text(text);
    let codes: Vec<&str> = out.diagnostics.iter().map(|d| d.code.as_str()).collect();
    assert!(codes.contains(&"W0503"), "{codes:?}");
    let built = out.value.expect("builds");
    let names: Vec<&str> =
        built.house.all_objects().iter().map(|o| o.object_name.as_str()).collect();
    assert_eq!(names, ["sofa-0"], "the stool follows the piano out; the sofa stays");
    let drawing = holoc::render::drawing(&built);
    assert!(drawing.left_out.iter().any(|l| l.name == "stool-0"));
}

/// An item on top that no asset matches is reported once (W0401) and takes no room: it is not
/// also called "the top is full" (W0501).
#[test]
fn items_without_an_asset_take_no_room_on_their_receptacle() {
    let text = "scene \"t\" { seed 1 }\n\nroom gym \"gym\" {\n  corners in m (0, 0) (0, 4) (4, 4) (4, 0)\n  object bench \"coffee table\" {\n    middle\n    on top \"metronome\" x3 same\n    on top \"book\" x1 same\n  }\n}\n\ndoor exterior -- gym : doorway single\n";
    let (_, out) = build_text(text);
    let codes: Vec<&str> = out.diagnostics.iter().map(|d| d.code.as_str()).collect();
    assert_eq!(codes, ["W0401"], "{codes:?}");
    let built = out.value.expect("builds");
    let names: Vec<&str> =
        built.house.all_objects().iter().map(|o| o.object_name.as_str()).collect();
    assert_eq!(names, ["bench-0", "book-0"]);
}

/// Builds a scene given as text with the defaults of `holoc build`.
fn build_text(text: &str) -> (SourceMap, holoc::diag::Outcome<Option<holoc::compile::Built>>) {
    let mut sources = SourceMap::new();
    let id = sources.add("t.holo", text.to_string());
    let catalog = holoc::resolve::Catalog::embedded();
    let out = holoc::compile::build(&sources, id, &holoc::compile::BuildOptions::new(&catalog));
    (sources, out)
}

/// The hallway with three offices of the plan corpus, planned, and a desk in its third room.
fn hallway_with_a_desk(
) -> (holoc::check::Scene, holoc::diag::Outcome<holoc::plan::FloorPlan>, holoc::lower::LoweredObject)
{
    let text = std::fs::read_to_string("tests/corpus/plan/ok/hallway_three_offices.holo")
        .expect("fixture");
    let mut sources = SourceMap::new();
    let id = sources.add("hall.holo", text);
    let scene = holoc::compile::check_file(&sources, id).value.expect("no syntax errors");
    let planned = plan(&scene, StructureCatalog::builtin());
    let desk = holoc::lower::LoweredObject {
        id: "desk-0 (office-2)".into(),
        asset_id: "Desk_301_1".into(),
        room: holoc::check::scene::RoomId(2),
        position_m: [6.0, 0.4, 4.0],
        rotation_deg: [0.0, 90.0, 0.0],
        kinematic: true,
        object_name: "desk-0".into(),
        parent: None,
        source: holoc::lower::Source::Object(holoc::check::scene::ObjectId(0)),
        layout_id: "desk-0".into(),
    };
    (scene, planned, desk)
}

/// Things on a receptacle AI2-THOR has no asset for (a floating wall shelf, built with
/// `--no-make`) go to the room's
/// receptacles that take them, in the order declared (W0506 says where and why), named by where
/// they are; a name taken there by a thing declared on it gets the next free number, so ids
/// stay unique.
#[test]
fn things_on_a_receptacle_without_an_asset_go_to_one_that_takes_them() {
    let text = r#"scene "a reading wall" { seed 1 }

room den "den" {
  corners in m (0, 0) (0, 4) (4, 4) (4, 0)
  object bookshelf "bookshelf" {
    describe "tall wooden bookshelf"
    edge
    on top "book" x2 varied
  }
  wall object wall_shelf "wall shelf" {
    describe "floating wall shelf"
    size 120 cm x 25 cm x 20 cm
    on top "book" x3 varied
  }
}

door exterior -- den : doorway single
"#;
    let mut sources = SourceMap::new();
    let id = sources.add("reading.holo".to_string(), text.to_string());
    let catalog = holoc::resolve::Catalog::embedded();
    // Without making (`--no-make`): with it, holoc makes the wall shelf and the books stay on it
    // (asserted at the end).
    let options =
        holoc::compile::BuildOptions { make: false, ..holoc::compile::BuildOptions::new(&catalog) };
    let out = holoc::compile::build(&sources, id, &options);
    let codes: Vec<String> = out.diagnostics.iter().map(|d| d.code.as_str().to_string()).collect();
    let built = out.value.unwrap_or_else(|| panic!("does not build: {codes:?}"));
    let made = holoc::compile::build(&sources, id, &holoc::compile::BuildOptions::new(&catalog));
    let made = made.value.expect("builds with making");
    let on_made_shelf: Vec<String> = made
        .house
        .all_objects()
        .iter()
        .filter(|o| o.id.starts_with("book-") && o.id.contains("wall_shelf-0"))
        .map(|o| o.id.clone())
        .collect();
    assert_eq!(on_made_shelf.len(), 3, "the made wall shelf holds its books: {on_made_shelf:?}");
    let books: Vec<String> = built
        .house
        .all_objects()
        .iter()
        .filter(|o| o.id.starts_with("book-"))
        .map(|o| o.id.clone())
        .collect();
    assert_eq!(
        books,
        [
            "book-0|bookshelf-0 (den)",
            "book-1|bookshelf-0 (den)",
            "book-2|bookshelf-0 (den)",
            "book-3|bookshelf-0 (den)",
            "book-4|bookshelf-0 (den)"
        ],
        "{codes:?}"
    );
    let moved: Vec<&holoc::diag::Diagnostic> =
        out.diagnostics.iter().filter(|d| d.code.as_str() == "W0506").collect();
    assert_eq!(moved.len(), 3, "{codes:?}");
    assert!(
        moved.iter().all(|d| d.message.contains("instead of `wall_shelf-0`")),
        "{:?}",
        moved.iter().map(|d| &d.message).collect::<Vec<_>>()
    );
    // The shelf itself is reported as having no asset.
    assert!(codes.iter().any(|c| c == "W0401"), "{codes:?}");
    // And the house is one `holoc validate` accepts.
    let json = built.house.to_json_string();
    let mut sources = SourceMap::new();
    let id = sources.add("house.json", json);
    let outcome =
        validate(&sources, id, StructureCatalog::builtin(), &holoc::resolve::Catalog::embedded());
    assert!(
        outcome.diagnostics.iter().all(|d| !d.is_error()),
        "{}",
        common::render(&sources, &outcome.diagnostics)
    );
}

/// When furniture fills the room the plan starts the agent in (a bed pinned across a small
/// hall), the agent starts on free floor of another room, never inside furniture: the house
/// passes `holoc validate` without W0613.
#[test]
fn the_agent_starts_in_another_room_when_the_first_is_full() {
    let text = r#"scene "a hall filled by a bed" { seed 1 }

room hall "hall" {
  corners in m (0, 0) (0, 2.4) (2.1, 2.4) (2.1, 0)
  object bed "bed" {
    asset "Bed_1"
    at 1.05 m, 1.2 m
    facing 0 deg
  }
}

room study "study" {
  corners in m (2.1, 0) (2.1, 2.4) (5.1, 2.4) (5.1, 0)
}

door exterior -- hall : doorway single
door hall -- study : doorway single
"#;
    let mut sources = SourceMap::new();
    let id = sources.add("full.holo".to_string(), text.to_string());
    let catalog = holoc::resolve::Catalog::embedded();
    let out = holoc::compile::build(&sources, id, &holoc::compile::BuildOptions::new(&catalog));
    let built = out.value.unwrap_or_else(|| {
        panic!("does not build:\n{}", common::render(&sources, &out.diagnostics))
    });
    let json = built.house.to_json_string();
    let value: serde_json::Value = serde_json::from_str(&json).expect("house json");
    let x = value["metadata"]["agent"]["position"]["x"].as_f64().expect("agent x");
    assert!(x > 2.1 + 0.25, "the agent starts at x = {x}, not in the study");
    let mut sources = SourceMap::new();
    let id = sources.add("house.json", json);
    let outcome =
        validate(&sources, id, StructureCatalog::builtin(), &holoc::resolve::Catalog::embedded());
    assert!(
        outcome.diagnostics.iter().all(|d| d.code.as_str() != "W0613"),
        "{}",
        common::render(&sources, &outcome.diagnostics)
    );
}

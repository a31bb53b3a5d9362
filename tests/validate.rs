//! `holoc validate`: our own outputs pass, hand-broken houses are rejected with the right code,
//! and the real ProcTHOR/Holodeck houses of the shared reference data (read from the relative
//! path `../shared/data/real-scenes`, skipped with a message when absent) are accepted or
//! reported without a crash. Diagnostics of the broken houses are snapshotted.

mod common;

use holoc::lower::validate::validate;
use holoc::resolve::structure::StructureCatalog;
use holoc::source::SourceMap;
use serde_json::Value;

fn run(name: &str, json: &str) -> (SourceMap, Vec<holoc::diag::Diagnostic>) {
    let mut sources = SourceMap::new();
    let id = sources.add(name, json.to_string());
    let outcome = validate(&sources, id, StructureCatalog::builtin());
    (sources, outcome.diagnostics)
}

fn codes(d: &[holoc::diag::Diagnostic]) -> Vec<&'static str> {
    let mut c: Vec<&'static str> = d.iter().map(|d| d.code.as_str()).collect();
    c.sort_unstable();
    c.dedup();
    c
}

fn base_house() -> Value {
    let text =
        std::fs::read_to_string("snapshots/lower/tests__corpus__plan__ok__apartment_1b1b.snap")
            .expect("the lower snapshot exists");
    let json = text.splitn(3, "---").nth(2).expect("snapshot body");
    serde_json::from_str(json.trim()).expect("snapshot body is the house")
}

fn broken(name: &str, expect: &str, edit: impl FnOnce(&mut Value)) {
    let mut house = base_house();
    edit(&mut house);
    let json = serde_json::to_string_pretty(&house).expect("prints");
    let (sources, diags) = run(name, &json);
    assert!(codes(&diags).contains(&expect), "{name}: expected {expect}, got {:?}", codes(&diags));
    insta::with_settings!({
        snapshot_path => "../snapshots/validate",
        prepend_module_to_snapshot => false,
        omit_expression => true,
    }, {
        insta::assert_snapshot!(name.to_string(), common::render(&sources, &diags));
    });
}

#[test]
fn base_house_is_valid() {
    let json = serde_json::to_string_pretty(&base_house()).expect("prints");
    let (sources, diags) = run("house.json", &json);
    assert!(diags.is_empty(), "{}", common::render(&sources, &diags));
}

#[test]
fn broken_houses_are_rejected() {
    broken("missing_rooms", "E0601", |h| {
        h.as_object_mut().expect("object").remove("rooms");
    });
    broken("duplicate_wall_id", "E0602", |h| {
        let w = h["walls"][1].clone();
        h["walls"].as_array_mut().expect("array").push(w);
    });
    broken("unknown_wall_reference", "E0603", |h| {
        h["doors"][0]["wall1"] = Value::String("wall|nowhere|west|0".into());
    });
    broken("hole_outside_wall", "E0604", |h| {
        h["doors"][0]["holePolygon"][1]["x"] = serde_json::json!(40.0);
    });
    broken("two_holes_in_one_wall", "E0605", |h| {
        let mut d = h["doors"][1].clone();
        d["id"] = Value::String("door|9|copy".into());
        h["doors"].as_array_mut().expect("array").push(d);
    });
    broken("room_not_closed", "E0606", |h| {
        h["rooms"][0]["floorPolygon"].as_array_mut().expect("array").truncate(2);
    });
    broken("object_outside_room", "E0607", |h| {
        h["objects"] = serde_json::json!([{
            "id": "sofa-0 (living room)", "assetId": "Sofa_201_1", "kinematic": true,
            "position": {"x": -3.0, "y": 0.4, "z": 1.0}, "rotation": {"x": 0, "y": 0, "z": 0},
            "roomId": "living room"
        }]);
    });
}

#[test]
fn not_json_points_at_the_error() {
    let (_, diags) = run("bad.json", "{\"rooms\": [,]}");
    assert_eq!(codes(&diags), ["E0601"]);
}

#[test]
#[allow(clippy::print_stdout, reason = "the test says why it skips and what it found")]
fn real_scenes() {
    let dir = std::path::Path::new("../shared/data/real-scenes");
    if !dir.is_dir() {
        println!("skipping: {} is absent", dir.display());
        return;
    }
    let mut names: Vec<_> = std::fs::read_dir(dir)
        .expect("folder")
        .filter_map(|e| e.ok().map(|e| e.path()))
        .filter(|p| p.extension().is_some_and(|e| e == "json"))
        .collect();
    names.sort();
    for path in names {
        let text = std::fs::read_to_string(&path).expect("readable");
        let name = path.file_name().and_then(|n| n.to_str()).unwrap_or("?").to_string();
        let (sources, diags) = run(&name, &text);
        if name.starts_with("procthor-") {
            assert!(
                !diags.iter().any(holoc::diag::Diagnostic::is_error),
                "{name}: {}",
                common::render(&sources, &diags)
            );
        } else {
            println!("{name}: {:?}", codes(&diags));
        }
    }
}

#[test]
fn not_json_with_non_ascii_text_does_not_panic() {
    let (sources, diags) = run("bad.json", "{\"rooms\": [\"é\" é]}");
    assert_eq!(codes(&diags), ["E0601"]);
    let _ = common::render(&sources, &diags);
}

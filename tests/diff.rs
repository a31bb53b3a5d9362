//! `holoc diff`: one snapshot per kind of change, each made by editing a house built (at test
//! time) from `tests/diff/study.holo`, whose floor objects are all pinned; tolerances and
//! `--ignore`; two `holoc batch` folders; and the properties: `diff X X` is empty for every
//! example and real scene, and `diff(B, A)` is `diff(A, B)` mirrored.

mod common;

use holoc::diff::{self, HouseView, Options};
use serde_json::{json, Value};
use std::path::{Path, PathBuf};
use std::process::Command;

fn holoc() -> Command {
    Command::new(env!("CARGO_BIN_EXE_holoc"))
}

/// A scratch folder of its own for each test.
fn scratch(name: &str) -> PathBuf {
    static N: std::sync::atomic::AtomicUsize = std::sync::atomic::AtomicUsize::new(0);
    let n = N.fetch_add(1, std::sync::atomic::Ordering::Relaxed);
    let dir = std::env::temp_dir().join(format!("holoc-diff-{name}-{}-{n}", std::process::id()));
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).expect("a scratch folder");
    dir
}

/// The study's house and report, built once per test.
fn base() -> (Value, Value) {
    let dir = scratch("base");
    let (house, report) = (dir.join("house.json"), dir.join("report.json"));
    let out = holoc()
        .args(["build", "tests/diff/study.holo", "-q", "-o"])
        .arg(&house)
        .arg("--report")
        .arg(&report)
        .output()
        .expect("holoc runs");
    assert!(out.status.success(), "{}", String::from_utf8_lossy(&out.stderr));
    let read = |p: &Path| -> Value {
        serde_json::from_str(&std::fs::read_to_string(p).expect("written")).expect("JSON")
    };
    let pair = (read(&house), read(&report));
    let _ = std::fs::remove_dir_all(&dir);
    pair
}

fn object<'a>(house: &'a mut Value, id: &str) -> &'a mut Value {
    house["objects"]
        .as_array_mut()
        .expect("objects")
        .iter_mut()
        .find(|o| o["id"] == id)
        .unwrap_or_else(|| panic!("no object {id}"))
}

fn bump(v: &mut Value, by: f64) {
    *v = json!(v.as_f64().expect("a number") + by);
}

/// Writes the two houses (and reports) as `a/study.house.json`… and runs `holoc diff` on them
/// with `args`; returns the exit status and stdout (and stderr when not empty).
fn run(name: &str, a: &(Value, Value), b: &(Value, Value), args: &[&str]) -> (i32, String) {
    let dir = scratch(name);
    for (side, (house, report)) in [("a", a), ("b", b)] {
        std::fs::create_dir_all(dir.join(side)).expect("folder");
        let write = |file: &str, v: &Value| {
            std::fs::write(
                dir.join(side).join(file),
                serde_json::to_string_pretty(v).expect("JSON"),
            )
            .expect("written");
        };
        write("study.house.json", house);
        write("study.report.json", report);
    }
    let out = holoc()
        .current_dir(&dir)
        .arg("diff")
        .args(["a/study.house.json", "b/study.house.json"])
        .args(args)
        .output()
        .expect("holoc runs");
    let _ = std::fs::remove_dir_all(&dir);
    let mut text = String::from_utf8_lossy(&out.stdout).into_owned();
    let stderr = String::from_utf8_lossy(&out.stderr);
    if !stderr.is_empty() {
        text.push_str("----- stderr\n");
        text.push_str(&stderr);
    }
    (out.status.code().unwrap_or(-1), text)
}

fn snapshot(name: &str, args: &[&str], status: i32, text: &str) {
    let command = format!("holoc diff a/study.house.json b/study.house.json {}", args.join(" "));
    let body = format!("$ {}\n? {status}\n{text}", command.trim_end());
    insta::with_settings!({snapshot_path => "../snapshots/diff", prepend_module_to_snapshot => false, omit_expression => true}, {
        insta::assert_snapshot!(name, body);
    });
}

/// Edits a copy of the base, diffs it against the base and snapshots the output.
fn case(name: &str, args: &[&str], edit: impl FnOnce(&mut Value, &mut Value)) -> (i32, String) {
    let a = base();
    let mut b = a.clone();
    edit(&mut b.0, &mut b.1);
    let (status, text) = run(name, &a, &b, args);
    snapshot(name, args, status, &text);
    (status, text)
}

#[test]
fn a_moved_and_turned_object() {
    let (status, _) = case("moved_object", &[], |house, _| {
        let desk = object(house, "desk-0 (study)");
        bump(&mut desk["position"]["x"], 0.3);
        bump(&mut desk["rotation"]["y"], 90.0);
    });
    assert_eq!(status, 1);
}

#[test]
fn a_move_within_the_tolerance_is_no_difference_and_a_finer_tolerance_shows_it() {
    let edit = |house: &mut Value, _: &mut Value| {
        let chair = object(house, "chair-0 (study)");
        bump(&mut chair["position"]["z"], 0.004);
        bump(&mut chair["rotation"]["y"], 0.5);
    };
    let (status, text) = case("within_tolerance", &[], edit);
    assert_eq!((status, text.as_str()), (0, "no differences (within 1 cm, 1°)\n"));
    let (status, _) = case("finer_tolerance", &["--tolerance", "1mm,0.1deg"], edit);
    assert_eq!(status, 1);
}

#[test]
fn a_changed_asset_and_a_changed_type() {
    let (status, text) = case("changed_asset", &[], |house, _| {
        object(house, "shelf-0 (study)")["assetId"] = json!("Shelving_Unit_319_1");
        object(house, "chair-0 (study)")["assetId"] = json!("ArmChair_1");
    });
    assert_eq!(status, 1);
    assert!(text.contains("1 type changed, 1 asset changed"), "{text}");
    // Owners who care about the layout only leave assets out.
    let (status, _) = case("changed_asset_ignored", &["--ignore", "assets"], |house, _| {
        object(house, "shelf-0 (study)")["assetId"] = json!("Shelving_Unit_319_1");
    });
    assert_eq!(status, 0);
}

#[test]
fn a_removed_window() {
    let (status, text) = case("removed_window", &[], |house, _| {
        house["windows"] = json!([]);
    });
    assert_eq!(status, 1);
    assert!(text.contains("1 window removed"), "{text}");
}

#[test]
fn a_relation_no_longer_kept() {
    let (status, text) = case("relation_broken", &[], |house, report| {
        bump(&mut object(house, "chair-0 (study)")["position"]["z"], -0.9);
        let study = report["layout"]
            .as_array_mut()
            .expect("layout")
            .iter_mut()
            .find(|r| r["room"] == "study")
            .expect("the study");
        let chair = study["floor_objects"]
            .as_array_mut()
            .expect("floor objects")
            .iter_mut()
            .find(|o| o["object"] == "chair-0")
            .expect("the chair");
        let near = chair["constraints"]
            .as_array_mut()
            .expect("constraints")
            .iter_mut()
            .find(|c| c["constraint"] == "near desk-0")
            .expect("near desk-0");
        near["satisfied"] = json!(false);
    });
    assert_eq!(status, 1);
    assert!(text.contains("1 relation no longer kept"), "{text}");
}

#[test]
fn a_reshaped_room() {
    let (status, text) = case("room_reshaped", &[], |house, _| {
        let study = house["rooms"]
            .as_array_mut()
            .expect("rooms")
            .iter_mut()
            .find(|r| r["id"] == "study")
            .expect("the study");
        for p in study["floorPolygon"].as_array_mut().expect("outline") {
            if p["x"].as_f64() == Some(7.0) {
                p["x"] = json!(7.5);
            }
        }
    });
    assert_eq!(status, 1);
    assert!(text.contains("12 m² → 13.5 m²"), "{text}");
}

#[test]
fn materials_lights_agent_and_a_renamed_object() {
    let (status, text) = case("materials_and_more", &[], |house, _| {
        let hall = &mut house["rooms"][0];
        hall["floorMaterial"]["name"] = json!("DarkWoodFloors");
        bump(&mut house["metadata"]["agent"]["position"]["x"], 0.5);
        bump(&mut house["proceduralParameters"]["lights"][1]["intensity"], -0.25);
        house["proceduralParameters"]["skyboxId"] = json!("Sky2");
        let chair = object(house, "chair-0 (study)");
        chair["id"] = json!("chair-1 (study)");
        chair["object_name"] = json!("chair-1");
        bump(&mut chair["position"]["x"], 0.1);
    });
    assert_eq!(status, 1);
    assert!(text.contains("(was chair-0 (study)) moved 10 cm"), "{text}");
    let (status, _) = case(
        "materials_and_more_ignored",
        &["--ignore", "materials,agent,lights,metadata"],
        |house, _| {
            house["rooms"][0]["floorMaterial"]["name"] = json!("DarkWoodFloors");
            bump(&mut house["metadata"]["agent"]["position"]["x"], 0.5);
            bump(&mut house["proceduralParameters"]["lights"][1]["intensity"], -0.25);
            house["proceduralParameters"]["skyboxId"] = json!("Sky2");
        },
    );
    assert_eq!(status, 0);
}

#[test]
fn an_added_item_on_top_and_the_json_format() {
    let (status, text) = case("json_format", &["--format", "json"], |house, _| {
        let desk = object(house, "desk-0 (study)");
        let mut book = desk["children"][0].clone();
        book["id"] = json!("book-0|desk-0 (study)");
        book["object_name"] = json!("book-0");
        book["assetId"] = json!("Book_1");
        desk["children"].as_array_mut().expect("children").push(book);
    });
    assert_eq!(status, 1);
    let v: Value = serde_json::from_str(&text).expect("one JSON document");
    assert_eq!(v["summary"], "1 object added");
    assert_eq!(v["changes"][0]["kind"], "object_added");
}

#[test]
fn errors_exit_with_2() {
    let dir = scratch("errors");
    std::fs::write(dir.join("not-a-house.json"), "{\"walls\": []}").expect("written");
    std::fs::write(dir.join("broken.json"), "{\"rooms\": [,]}").expect("written");
    let run = |a: &str, b: &str| {
        let out = holoc().current_dir(&dir).args(["diff", a, b]).output().expect("holoc runs");
        (out.status.code(), String::from_utf8_lossy(&out.stderr).into_owned())
    };
    let (code, err) = run("missing.json", "not-a-house.json");
    assert_eq!(code, Some(2));
    assert!(err.contains("E0001"), "{err}");
    let (code, err) = run("not-a-house.json", "not-a-house.json");
    assert_eq!(code, Some(2));
    assert!(err.contains("E0601") && err.contains("no `rooms` list"), "{err}");
    let (code, err) = run("broken.json", "not-a-house.json");
    assert_eq!(code, Some(2));
    assert!(err.contains("E0601") && err.contains("not valid JSON"), "{err}");
    let (code, err) = run(".", "broken.json");
    assert_eq!(code, Some(2));
    assert!(err.contains("E0004"), "{err}");
    let out = holoc()
        .args(["diff", "a.json", "b.json", "--tolerance", "1 furlong"])
        .output()
        .expect("holoc runs");
    assert_eq!(out.status.code(), Some(2));
    let _ = std::fs::remove_dir_all(&dir);
}

#[test]
fn two_scenes_are_built_with_their_seeds_and_compared() {
    let dir = scratch("scenes");
    let text = std::fs::read_to_string("tests/diff/study.holo").expect("the scene");
    std::fs::write(dir.join("a.holo"), &text).expect("written");
    std::fs::write(dir.join("b.holo"), text.replace("at 4 m, 0.12 m", "at 4.5 m, 0.12 m"))
        .expect("written");
    let out = holoc().current_dir(&dir).args(["diff", "a.holo", "a.holo"]).output().expect("runs");
    assert_eq!(out.status.code(), Some(0), "{}", String::from_utf8_lossy(&out.stderr));
    let out = holoc().current_dir(&dir).args(["diff", "a.holo", "b.holo"]).output().expect("runs");
    let stdout = String::from_utf8_lossy(&out.stdout);
    assert_eq!(out.status.code(), Some(1));
    assert!(stdout.contains("shelf-0 (study) moved 50 cm"), "{stdout}");
    let _ = std::fs::remove_dir_all(&dir);
}

/// Two `holoc batch` runs of one manifest, the second after a scene changed: the folders pair
/// by job (the changed job has another hash, hence another folder).
#[test]
fn two_batch_folders_pair_by_job() {
    let dir = scratch("batch");
    let study = std::fs::read_to_string("tests/diff/study.holo").expect("the scene");
    std::fs::write(dir.join("study.holo"), &study).expect("written");
    std::fs::write(dir.join("hall.holo"), study.replace("seed 7", "seed 8")).expect("written");
    std::fs::write(
        dir.join("manifest.jsonl"),
        "{\"build\": \"study.holo\", \"id\": \"study\"}\n{\"build\": \"hall.holo\", \"id\": \"hall\"}\n",
    )
    .expect("written");
    let batch = |out: &str| {
        let o = holoc()
            .current_dir(&dir)
            .args(["batch", "manifest.jsonl", "-q", "-o", out])
            .output()
            .expect("holoc runs");
        assert!(
            o.status.success(),
            "{:?}: {}{}",
            o.status,
            String::from_utf8_lossy(&o.stdout),
            String::from_utf8_lossy(&o.stderr)
        );
    };
    batch("before");
    std::fs::write(
        dir.join("study.holo"),
        study.replace("asset \"Desk_229_1\"\n    at 5 m", "asset \"Desk_303_1\"\n    at 5.2 m"),
    )
    .expect("written");
    batch("after");
    let diff = |args: &[&str]| {
        let o = holoc()
            .current_dir(&dir)
            .args(["diff", "before", "after"])
            .args(args)
            .output()
            .expect("holoc runs");
        (o.status.code(), String::from_utf8_lossy(&o.stdout).into_owned())
    };
    let (code, stat) = diff(&["--stat"]);
    assert_eq!(code, Some(1));
    assert!(stat.starts_with("study: "), "{stat}");
    assert!(stat.contains("asset changed"), "{stat}");
    assert!(
        stat.ends_with("1 of 2 houses differ: 1 changed (1 object moved, 1 asset changed)\n")
            || stat.contains("1 of 2 houses differ: 1 changed ("),
        "{stat}"
    );
    let (code, full) = diff(&[]);
    assert_eq!(code, Some(1));
    assert!(full.contains("== study\nstudy:\n"), "{full}");
    assert!(full.contains("desk-0 (study) asset Desk_229_1 → Desk_303_1"), "{full}");
    let (code, json) = diff(&["--format", "json", "--stat"]);
    assert_eq!(code, Some(1));
    let v: Value = serde_json::from_str(&json).expect("one JSON document");
    assert_eq!(v["totals"]["changed"], 1);
    assert_eq!(v["totals"]["same"], 1);
    assert_eq!(v["houses"][0]["name"], "study");
    let (code, _) = diff(&["--ignore", "objects,items,agent,relations"]);
    assert_eq!(code, Some(0), "without objects the two runs are the same");
    let _ = std::fs::remove_dir_all(&dir);
}

/// An edit of a house's JSON.
type Edit = Box<dyn Fn(&mut Value)>;

fn view(text: &str) -> HouseView {
    HouseView::read(&serde_json::from_str(text).expect("JSON")).expect("a house")
}

/// Every example (built) and every real scene (read as it is) is the same as itself.
#[test]
fn a_house_is_the_same_as_itself() {
    let catalog = holoc::resolve::Catalog::embedded();
    let mut seen = 0;
    let mut examples: Vec<PathBuf> = std::fs::read_dir("examples")
        .expect("examples")
        .filter_map(|e| e.ok().map(|e| e.path()))
        .filter(|p| p.extension().is_some_and(|e| e == "holo"))
        .collect();
    examples.sort();
    for path in examples {
        let mut sources = holoc::source::SourceMap::new();
        let id =
            sources.add(path.display().to_string(), std::fs::read_to_string(&path).expect("read"));
        let built =
            holoc::compile::build(&sources, id, &holoc::compile::BuildOptions::new(&catalog));
        let product = built.value.expect("the examples build");
        let mut h = view(&product.house.to_json_string());
        h.add_report(&holoc::report::report(&product, &catalog)).expect("a report");
        let d = diff::diff(&h, &h.clone(), &Options::default());
        assert!(d.is_empty(), "{}: {}", path.display(), d.render());
        seen += 1;
    }
    if let Some(dir) =
        common::shared("data/real-scenes", "a_house_is_the_same_as_itself (real scenes)")
    {
        for entry in std::fs::read_dir(dir).expect("folder").flatten() {
            if entry.path().extension().is_none_or(|e| e != "json") {
                continue;
            }
            let text = std::fs::read_to_string(entry.path()).expect("read");
            let h = view(&text);
            let d = diff::diff(&h, &view(&text), &Options::default());
            assert!(d.is_empty(), "{}: {}", entry.path().display(), d.render());
            seen += 1;
        }
    }
    assert!(seen >= 6, "only {seen} houses");
}

/// `diff(B, A)` is `diff(A, B)` with every change mirrored, for each kind of edit above and
/// for pairs of real scenes.
#[test]
fn the_diff_the_other_way_is_the_mirror_image() {
    let (house, report) = base();
    let edits: Vec<Edit> = vec![
        Box::new(|h| bump(&mut object(h, "desk-0 (study)")["position"]["x"], 0.3)),
        Box::new(|h| bump(&mut object(h, "desk-0 (study)")["rotation"]["y"], 90.0)),
        Box::new(|h| object(h, "chair-0 (study)")["assetId"] = json!("ArmChair_1")),
        Box::new(|h| h["windows"] = json!([])),
        Box::new(|h| {
            let chair = object(h, "chair-0 (study)");
            chair["id"] = json!("chair-9 (study)");
            chair["object_name"] = json!("chair-9");
            bump(&mut chair["position"]["x"], 0.2);
            bump(&mut chair["rotation"]["y"], -30.0);
        }),
        Box::new(|h| {
            let desk = object(h, "desk-0 (study)");
            desk["children"] = json!([]);
        }),
        Box::new(|h| {
            h["rooms"][0]["floorPolygon"][2]["x"] = json!(3.5);
            h["rooms"][0]["wallMaterial"]["name"] = json!("BrownDrywall");
            h["proceduralParameters"]["lights"] = json!([]);
        }),
    ];
    let mut all = house.clone();
    for edit in &edits {
        edit(&mut all);
    }
    let mut reports = report.clone();
    reports["layout"][1]["floor_objects"][1]["constraints"][1]["satisfied"] = json!(false);
    let a = {
        let mut v = HouseView::read(&house).expect("a house");
        v.add_report(&report).expect("a report");
        v
    };
    let mut cases: Vec<(HouseView, HouseView)> = Vec::new();
    for edit in &edits {
        let mut h = house.clone();
        edit(&mut h);
        cases.push((a.clone(), HouseView::read(&h).expect("a house")));
    }
    let mut b = HouseView::read(&all).expect("a house");
    b.add_report(&reports).expect("a report");
    cases.push((a.clone(), b));
    if let Some(dir) = common::shared(
        "data/real-scenes",
        "the_diff_the_other_way_is_the_mirror_image (real scenes)",
    ) {
        let mut houses: Vec<HouseView> = std::fs::read_dir(dir)
            .expect("folder")
            .flatten()
            .filter(|e| e.path().extension().is_some_and(|x| x == "json"))
            .map(|e| view(&std::fs::read_to_string(e.path()).expect("read")))
            .collect();
        houses.sort_by_key(|h| h.rooms.first().map(|r| r.id.clone()));
        for w in houses.windows(2) {
            cases.push((w[0].clone(), w[1].clone()));
        }
    }
    for (x, y) in &cases {
        let forth = diff::diff(x, y, &Options::default());
        let back = diff::diff(y, x, &Options::default());
        assert!(!forth.is_empty());
        let mut mirrored =
            diff::Diff { changes: forth.changes.iter().map(diff::Change::mirror).collect() };
        let key =
            |c: &diff::Change| (c.kind, c.room.clone(), c.subject.clone(), c.relation.clone());
        mirrored.changes.sort_by_key(key);
        let mut back_sorted = back.clone();
        back_sorted.changes.sort_by_key(key);
        assert_eq!(mirrored, back_sorted, "forth:\n{}back:\n{}", forth.render(), back.render());
    }
}

#[test]
fn a_renamed_object_is_one_change_and_types_come_from_the_catalog() {
    // Renamed (another name, so another category), same asset, same place: one line.
    let (status, text) = case("renamed_object", &[], |house, _| {
        let chair = object(house, "chair-0 (study)");
        chair["id"] = json!("seat-0 (study)");
        chair["object_name"] = json!("seat-0");
    });
    assert_eq!(status, 1);
    assert!(text.contains("~ seat-0 (study) renamed (was chair-0 (study)"), "{text}");
    assert!(text.contains("1 object renamed") && !text.contains("added"), "{text}");
    // Two Dressers whose ids begin differently: an asset change, not a type change; a Dresser
    // becoming a Shelving Unit is a type change named by the catalog's types.
    let (_, text) = case("types_from_the_catalog", &[], |house, _| {
        object(house, "shelf-0 (study)")["assetId"] = json!("RoboTHOR_dresser_hemnes");
    });
    let mut a = base();
    object(&mut a.0, "shelf-0 (study)")["assetId"] = json!("Dresser_205_1");
    let mut b = a.clone();
    object(&mut b.0, "shelf-0 (study)")["assetId"] = json!("RoboTHOR_dresser_hemnes");
    let (_, same_type) = run("dresser_to_dresser", &a, &b, &[]);
    assert!(same_type.contains("1 asset changed") && !same_type.contains("type"), "{same_type}");
    assert!(text.contains("type ShelvingUnit → Dresser"), "{text}");
}

#[test]
fn a_catalog_version_change_is_said_as_such() {
    let a = base();
    let mut b = a.clone();
    let catalogs = b.1["assets"]["catalogs"].as_array_mut().expect("the catalog lock");
    catalogs[0]["version"] = json!("9.9.9");
    let (status, text) = run("catalog_version", &a, &b, &[]);
    assert_eq!(status, 1, "{text}");
    assert!(text.contains("catalog ") && text.contains("→ version 9.9.9"), "{text}");
    assert!(text.contains("1 setting changed"), "{text}");
}

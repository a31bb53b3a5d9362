//! The assets holoc makes (`src/make/`), as a user gets them: the new-user scenes of the
//! examples (a studio with two cats, a meeting room, a family bathroom) and the gallery of
//! every kind (`tests/make/gallery.holo`) built with `holoc build`; every object reaches the
//! house, each made asset folder reads back as AI2-THOR's run-time asset hook reads it
//! (`tests/make/check_runtime_assets.py`, run with python3), is at most 200 KB, is the same
//! bytes built again, and `holoc validate`, `export` and `view` take the houses; the GLB passes
//! the Khronos glTF validator (node, npm `gltf-validator`, installed by `.ci/run`).
//!
//! Without python3, node or the validator those parts say so and skip.

mod common;

use std::collections::BTreeMap;
use std::path::{Path, PathBuf};
use std::process::Command;

const HOLOC: &str = env!("CARGO_BIN_EXE_holoc");

/// The scenes: each with the number of objects it asks for.
const SCENES: &[&str] = &[
    "examples/cat_studio.holo",
    "examples/meeting_room.holo",
    "examples/family_bathroom.holo",
    "tests/make/gallery.holo",
];

fn runs(program: &str, arg: &str) -> bool {
    Command::new(program).arg(arg).output().is_ok_and(|o| o.status.success())
}

/// Builds `scene` into `dir` with a report; returns the house path and the build's stderr.
fn build(scene: &str, dir: &Path) -> (PathBuf, String) {
    let stem = Path::new(scene).file_stem().expect("a name").to_string_lossy().into_owned();
    let house = dir.join(format!("{stem}.json"));
    let report = dir.join(format!("{stem}.report.json"));
    let out = Command::new(HOLOC)
        .args(["build", scene, "-o"])
        .arg(&house)
        .arg("--report")
        .arg(&report)
        .args(["--format", "short", "--color", "never"])
        .output()
        .expect("holoc runs");
    let stderr = String::from_utf8_lossy(&out.stderr).into_owned();
    assert!(out.status.success(), "{scene} builds: {stderr}");
    (house, stderr)
}

/// Every file under a folder, by path relative to it, with its bytes.
fn files(dir: &Path) -> BTreeMap<PathBuf, Vec<u8>> {
    let mut out = BTreeMap::new();
    let mut stack = vec![dir.to_path_buf()];
    while let Some(d) = stack.pop() {
        for e in std::fs::read_dir(&d).expect("readable").flatten() {
            let p = e.path();
            if p.is_dir() {
                stack.push(p);
            } else {
                let rel = p.strip_prefix(dir).expect("inside").to_path_buf();
                out.insert(rel, std::fs::read(&p).expect("readable"));
            }
        }
    }
    out
}

fn report(house: &Path) -> serde_json::Value {
    let path = house.with_file_name(format!(
        "{}.report.json",
        house.file_stem().expect("a name").to_string_lossy()
    ));
    serde_json::from_slice(&std::fs::read(path).expect("the report")).expect("JSON")
}

#[test]
fn every_object_of_the_new_user_scenes_reaches_the_house() {
    let dir = tempfile::tempdir().expect("a scratch folder");
    for scene in SCENES {
        let (house, stderr) = build(scene, dir.path());
        let last = stderr.lines().last().unwrap_or_default();
        // "… N of N objects placed, …": nothing left out.
        let placed = last
            .split(", ")
            .find(|p| p.contains("objects placed"))
            .unwrap_or_else(|| panic!("{scene}: {last}"));
        let words: Vec<&str> = placed.split_whitespace().collect();
        assert_eq!(words[0], words[2], "{scene} leaves objects out: {stderr}");
        assert!(last.contains("assets made in"), "{scene}: {last}");
        let r = report(&house);
        let made = r["madeAssets"].as_array().expect("made assets listed");
        assert!(!made.is_empty());
        for m in made {
            let folder = PathBuf::from(m["folder"].as_str().expect("a folder"));
            assert!(folder.join(format!("{}.json", m["uid"].as_str().expect("uid"))).is_file());
            assert!(m["parts"].as_array().is_some_and(|p| p.len() >= 2), "{m}");
        }
    }
}

#[test]
fn the_gallery_makes_every_kind_the_words_name() {
    let dir = tempfile::tempdir().expect("a scratch folder");
    let (house, _) = build("tests/make/gallery.holo", dir.path());
    let r = report(&house);
    let kinds: std::collections::BTreeSet<&str> = r["madeAssets"]
        .as_array()
        .expect("made assets")
        .iter()
        .filter_map(|m| m["kind"].as_str())
        .collect();
    for kind in [
        "cat_tree",
        "litter_box",
        "scratching_post",
        "cat_wall_shelf",
        "wall_shelf",
        "wall_cabinet",
        "mirror",
        "whiteboard",
        "blackboard",
        "pin_board",
        "projector_screen",
        "wall_clock",
        "coat_hooks",
        "towel_hooks",
        "curtains",
        "shower_stall",
        "bath_mat",
        "rug",
        "throw",
        "projector",
        "speaker",
        "conference_phone",
        "cutting_board",
        "pitcher",
        "coaster_set",
        "range",
        "photo_frame",
        "pen_holder",
    ] {
        assert!(kinds.contains(kind), "the gallery made no {kind}: {kinds:?}");
    }
    // A cat bed is AI2-THOR's dog bed, a kitchen island its counter top, a picture frame its
    // painting: those built-in assets are the thing itself and come first.
    let chosen: BTreeMap<&str, &str> = r["assets"]["objects"]
        .as_array()
        .expect("objects")
        .iter()
        .filter_map(|o| Some((o["object"].as_str()?, o["objectType"].as_str()?)))
        .collect();
    assert_eq!(chosen.get("cat_bed-0"), Some(&"DogBed"));
    assert_eq!(chosen.get("island-0"), Some(&"CounterTop"));
    assert_eq!(chosen.get("mirror-0"), Some(&"Mirror"), "a round mirror is no painting");
}

#[test]
fn made_assets_load_by_the_hook_s_rules_are_small_and_the_same_twice() {
    let test = "make::made_assets_load_by_the_hook_s_rules_are_small_and_the_same_twice";
    let (a, b) = (tempfile::tempdir().expect("scratch"), tempfile::tempdir().expect("scratch"));
    let mut folders = Vec::new();
    for scene in SCENES {
        let (house_a, _) = build(scene, a.path());
        let (house_b, _) = build(scene, b.path());
        assert_eq!(std::fs::read(&house_a).ok(), std::fs::read(&house_b).ok(), "{scene}");
        let stem = house_a.file_stem().expect("a name").to_string_lossy().into_owned();
        let (fa, fb) =
            (a.path().join(format!("{stem}.assets")), b.path().join(format!("{stem}.assets")));
        let (files_a, files_b) = (files(&fa), files(&fb));
        assert!(!files_a.is_empty(), "{scene} made nothing");
        assert!(files_a == files_b, "{scene}: the assets differ between two builds");
        // At most 200 KB an asset.
        let mut per_asset: BTreeMap<PathBuf, usize> = BTreeMap::new();
        for (path, bytes) in &files_a {
            let uid = path.components().next().expect("a folder").as_os_str().into();
            *per_asset.entry(uid).or_default() += bytes.len();
        }
        for (uid, size) in per_asset {
            assert!(size <= 200 * 1024, "{}: {size} bytes", uid.display());
        }
        // The house with its folder validates; without it, the made ids are E0614.
        let out = Command::new(HOLOC).arg("validate").arg(&house_a).output().expect("runs");
        assert!(out.status.success(), "{}", String::from_utf8_lossy(&out.stderr));
        folders.push(fa);
    }
    let moved = a.path().join("alone");
    std::fs::create_dir_all(&moved).expect("a folder");
    let lone = moved.join("cat_studio.json");
    std::fs::copy(a.path().join("cat_studio.json"), &lone).expect("copied");
    let out = Command::new(HOLOC).arg("validate").arg(&lone).output().expect("runs");
    let stderr = String::from_utf8_lossy(&out.stderr);
    assert_eq!(out.status.code(), Some(1));
    assert!(stderr.contains("E0614") && stderr.contains("an asset holoc made"), "{stderr}");
    if !runs("python3", "--version") {
        common::skip(test, "python3 is missing: the run-time asset reader did not run");
        return;
    }
    let out = Command::new("python3")
        .arg("tests/make/check_runtime_assets.py")
        .args(&folders)
        .output()
        .expect("python3 runs");
    let stdout = String::from_utf8_lossy(&out.stdout);
    assert!(out.status.success(), "{stdout}{}", String::from_utf8_lossy(&out.stderr));
    assert!(stdout.lines().last().is_some_and(|l| l.ends_with(" passed, 0 failed")), "{stdout}");
}

#[test]
fn export_and_view_draw_made_assets_with_their_parts() {
    let test = "make::export_and_view_draw_made_assets_with_their_parts";
    let dir = tempfile::tempdir().expect("a scratch folder");
    let (house, _) = build("tests/make/gallery.holo", dir.path());
    let glb = dir.path().join("gallery.glb");
    let out =
        Command::new(HOLOC).arg("export").arg(&house).arg("-o").arg(&glb).output().expect("runs");
    assert!(out.status.success(), "{}", String::from_utf8_lossy(&out.stderr));
    // The made objects are meshes of several colours, not the unit box.
    let bytes = std::fs::read(&glb).expect("the GLB");
    let doc = gltf::Gltf::from_slice(&bytes).expect("the gltf crate reads the GLB");
    let r = report(&house);
    let made: Vec<String> = r["madeAssets"]
        .as_array()
        .expect("made assets")
        .iter()
        .flat_map(|m| m["objects"].as_array().cloned().unwrap_or_default())
        .filter_map(|o| o.as_str().map(str::to_string))
        .collect();
    for node in doc.nodes() {
        let Some(name) = node.name() else { continue };
        if !made.iter().any(|m| m == name) {
            continue;
        }
        let mesh = node.mesh().unwrap_or_else(|| panic!("{name} has a mesh"));
        // Its own triangles (a box has 12), in one primitive per colour.
        let triangles: usize =
            mesh.primitives().filter_map(|p| p.indices().map(|i| i.count() / 3)).sum();
        assert!(triangles > 12, "{name} is drawn as a box");
        assert!(node.transform().decomposed().2 == [1.0, 1.0, 1.0], "{name} is a scaled box");
    }
    let html = dir.path().join("gallery.html");
    let out =
        Command::new(HOLOC).arg("view").arg(&house).arg("-o").arg(&html).output().expect("runs");
    assert!(out.status.success(), "{}", String::from_utf8_lossy(&out.stderr));
    let modules = std::env::var_os("HOLOC_NPM_PREFIX").map_or_else(
        || Path::new(&std::env::var_os("HOME").unwrap_or_default()).join(".cache/holoc/npm"),
        PathBuf::from,
    );
    let modules = modules.join("node_modules");
    if !runs("node", "--version") || !modules.join("gltf-validator").exists() {
        common::skip(
            test,
            "node or the npm package gltf-validator is missing (.ci/run installs them)",
        );
        return;
    }
    let out = Command::new("node")
        .arg("tests/export/validate_glb.js")
        .arg(&glb)
        .env("NODE_PATH", &modules)
        .output()
        .expect("node runs");
    assert!(out.status.success(), "{}", String::from_utf8_lossy(&out.stderr));
    let line: serde_json::Value =
        serde_json::from_str(String::from_utf8_lossy(&out.stdout).trim()).expect("a JSON line");
    assert_eq!(line["errors"], 0, "{line}");
    assert_eq!(line["warnings"], 0, "{line}");
}

//! The original Holodeck's assets as a catalog (`--objathor`): a generated fixture version
//! folder (`resolve::objathor::fixture`: a dozen annotations with every field and the three
//! box shapes, feature pickles with hand-picked vectors, stub asset folders with one missing),
//! the pickle reader on real numpy pickles (`tests/objathor/pickles/`), the scoring modes, the
//! filters, the seeded pick, the report's lock and attributions, the on-disk check, the command
//! line, and a real objathor folder when one is present.

mod common;

use holoc::compile::{build, BuildOptions};
use holoc::resolve::objathor::fixture::{
    fixture_uid, write_fixture, FixtureOptions, FIXTURE_ASSETS, FIXTURE_VERSION,
};
use holoc::resolve::objathor::pickle::{NumpyModules, Pickle};
use holoc::resolve::objathor::{fits_room, Mix, ObjathorOptions, Pick, Scoring};
use holoc::resolve::{self, Catalog, PlacementKind, Query};
use holoc::source::SourceMap;
use std::path::{Path, PathBuf};
use std::process::Command;

const CAT_ROOM: &str = "tests/objathor/cat_room.holo";

/// A fixture version folder in a fresh temporary folder (kept alive by the returned guard).
fn fixture(options: FixtureOptions) -> (tempfile::TempDir, PathBuf) {
    let dir = tempfile::tempdir().expect("a temporary folder");
    let root = write_fixture(dir.path(), options).expect("the fixture is written");
    (dir, root)
}

fn options(dir: &Path) -> ObjathorOptions {
    ObjathorOptions { dir: dir.to_path_buf(), ..ObjathorOptions::default() }
}

fn load(options: &ObjathorOptions) -> (Catalog, Vec<holoc::diag::Diagnostic>) {
    let mut sources = SourceMap::new();
    let loaded = Catalog::load_with(&[] as &[PathBuf], Some(options), &mut sources);
    (loaded.value, loaded.diagnostics)
}

fn codes(diags: &[holoc::diag::Diagnostic]) -> Vec<&'static str> {
    diags.iter().map(|d| d.code.as_str()).collect()
}

fn query(category: &str, description: &str, kind: PlacementKind) -> Query {
    Query {
        category: category.into(),
        description: Some(description.into()).filter(|d: &String| !d.is_empty()),
        size_m: None,
        kind: Some(kind),
    }
}

fn name_of(uid: &str) -> &'static str {
    FIXTURE_ASSETS.iter().find(|a| a.uid == uid).map_or("?", |a| a.name)
}

#[test]
fn every_field_and_box_shape_is_read() {
    let (_dir, root) = fixture(FixtureOptions::default());
    let (catalog, diags) = load(&options(&root));
    assert!(diags.is_empty(), "{diags:?}");
    let obj = catalog.objathor().expect("loaded");
    assert_eq!(obj.version, FIXTURE_VERSION);
    assert_eq!(obj.end - obj.start, FIXTURE_ASSETS.len());
    assert_eq!(obj.scoring, Scoring::Features);
    assert_eq!(obj.pseudo_query_space(), Some("clip-text"));
    // The three box shapes, in metres.
    let bbox = |name: &str| catalog.get(fixture_uid(name)).expect("there").bbox_m;
    assert_eq!(bbox("cat_tower"), [0.6, 1.5, 0.6]);
    assert_eq!(bbox("cat_tree"), [0.5, 1.8, 0.5]);
    assert_eq!(bbox("cat_bed"), [0.5, 0.2, 0.5]);
    let idx = catalog.index_of(fixture_uid("cat_tower")).expect("there");
    let entry = obj.entry(idx).expect("an entry");
    assert_eq!(entry.synset.as_deref(), Some("cat_tower.n.01"));
    assert_eq!(entry.wn_version.as_deref(), Some("oewn:2022"));
    assert_eq!(entry.size_cm, [Some(100.0), Some(50.0), Some(80.0)]);
    assert_eq!(entry.materials, vec!["wood", "fabric"]);
    assert_eq!(entry.composition, vec![0.6, 0.4]);
    assert_eq!(entry.front_view, Some(1));
    assert_eq!(entry.z_axis_scale, Some(true));
    assert_eq!(entry.near_synsets, vec![("cat_tower.n.02".to_string(), 0.5)]);
    assert_eq!(entry.description_auto.as_deref(), Some("A 3D model of a cat tower."));
    let license = entry.license.as_ref().expect("a licence");
    assert_eq!(license.license.as_deref(), Some("by"));
    assert_eq!(license.creator_username.as_deref(), Some("maker_cat_tower"));
    assert!(catalog.get(fixture_uid("cat_tower")).expect("there").receptacle);
    // The entry written flat (fields at the top) reads the same.
    let bed = catalog.get(fixture_uid("cat_bed")).expect("there");
    assert!(bed.placements.on_floor && bed.placements.on_object);
    // The lock: the annotations and both feature files, hashed.
    assert_eq!(obj.files.len(), 3);
    assert!(obj.files.iter().all(|(_, sha)| sha.len() == 64));
    let source = &catalog.sources()[obj.source];
    assert_eq!(source.name, "objathor");
    assert_eq!(source.version.as_deref(), Some(FIXTURE_VERSION));
}

#[test]
fn real_numpy_pickles_of_every_protocol_and_module_name_read() {
    // Made by `tests/objathor/pickles/make.py` with numpy 1.26 (`numpy.core`) and numpy 2.4
    // (`numpy._core`), protocols 2 to 5.
    let expected_img: [f32; 12] = [
        0.5,
        -0.25,
        1.0,
        0.0,
        2.0,
        -1.5,
        65504.0,
        6.1e-5,
        -0.0,
        0.333_251_95,
        0.099_975_586,
        1.192_092_9e-7,
    ];
    let mut seen = 0;
    for numpy in ["np1", "np2"] {
        for protocol in 2..=5 {
            let path = format!("tests/objathor/pickles/clip_{numpy}_p{protocol}.pkl");
            let bytes = std::fs::read(&path).expect("the pickle is in the repository");
            let p = Pickle::read(&bytes).unwrap_or_else(|e| panic!("{path}: {e}"));
            assert_eq!(
                p.strings("uids").expect("ok"),
                Some(vec!["a".repeat(32), "b".repeat(32)]),
                "{path}"
            );
            let img = p.f16_array("img_features").expect("ok").expect("there");
            assert_eq!(img.shape, vec![2, 2, 3], "{path}");
            let values: Vec<f32> = p
                .array_bytes(&img.bytes)
                .chunks_exact(2)
                .map(|c| {
                    holoc::resolve::objathor::pickle::f16_to_f32(u16::from_le_bytes([c[0], c[1]]))
                })
                .collect();
            for (got, want) in values.iter().zip(expected_img) {
                assert!((got - want).abs() <= want.abs() * 1e-3 + 1e-7, "{path}: {got} vs {want}");
            }
            let text = p.f16_array("text_features").expect("ok").expect("there");
            assert_eq!(text.shape, vec![2, 3]);
            seen += 1;
        }
    }
    assert_eq!(seen, 8);
}

#[test]
fn the_fixture_loads_with_every_protocol_and_module_name() {
    for protocol in 2..=5 {
        for modules in [NumpyModules::Core, NumpyModules::UnderscoreCore] {
            let (_dir, root) =
                fixture(FixtureOptions { protocol, modules, ..FixtureOptions::default() });
            let (catalog, diags) = load(&options(&root));
            assert!(diags.is_empty(), "protocol {protocol} {modules:?}: {diags:?}");
            assert_eq!(catalog.objathor().expect("loaded").scoring, Scoring::Features);
        }
    }
}

/// The names of the ranked candidates, with their CLIP part and whether each is good enough.
fn ranked(catalog: &Catalog, q: &Query) -> Vec<(&'static str, f64, bool)> {
    resolve::objathor::rank(catalog, q, 0, 128)
        .iter()
        .map(|c| {
            (
                name_of(&c.asset_id),
                c.features.as_ref().map_or(f64::NAN, |f| f.clip),
                c.is_good_enough(),
            )
        })
        .collect()
}

fn near(a: f64, b: f64) -> bool {
    (a - b).abs() < 1e-3
}

#[test]
fn features_rank_by_the_best_view_against_the_threshold() {
    let (_dir, root) = fixture(FixtureOptions::default());
    let (catalog, _) = load(&options(&root));
    let got = ranked(&catalog, &query("cat tower", "", PlacementKind::Floor));
    // The pseudo-query is the cat tower's text row (axis 0): its best view has b = 2.5 (37.14),
    // the cat tree's 2.75 (34.17), the cat bed's 3.25 (29.41, under the floor threshold 31).
    let names: Vec<&str> = got.iter().map(|g| g.0).collect();
    assert_eq!(names, vec!["cat_tower", "cat_tree", "cat_bed"]);
    assert!(near(got[0].1, 37.139) && got[0].2);
    assert!(near(got[1].1, 34.174) && got[1].2);
    assert!(near(got[2].1, 29.408) && !got[2].2);
    // Lexically, the cat tree is a cat tower by the synonym table (`cat tower` → `cat tree`,
    // one WordNet synset); the cat bed is not.
    let lexical = ObjathorOptions { scoring: Some(Scoring::Lexical), ..options(&root) };
    let (catalog, _) = load(&lexical);
    let good: Vec<&str> =
        resolve::objathor::rank(&catalog, &query("cat tower", "", PlacementKind::Floor), 0, 128)
            .iter()
            .filter(|c| c.is_good_enough())
            .map(|c| name_of(&c.asset_id))
            .collect();
    assert_eq!(good.len(), 2, "{good:?}");
    assert!(good.contains(&"cat_tower") && good.contains(&"cat_tree"), "{good:?}");
}

#[test]
fn the_size_term_and_sbert_part_are_in_the_score() {
    let (_dir, root) = fixture(FixtureOptions::default());
    let (catalog, _) = load(&options(&root));
    let q = Query { size_m: Some([0.5, 0.5, 1.8]), ..query("cat tower", "", PlacementKind::Floor) };
    let list = resolve::objathor::rank(&catalog, &q, 0, 128);
    let tower = list.iter().find(|c| name_of(&c.asset_id) == "cat_tower").expect("ranked");
    let tree = list.iter().find(|c| name_of(&c.asset_id) == "cat_tree").expect("ranked");
    // Sorted sizes: tower (0.6, 0.6, 1.5) vs (0.5, 0.5, 1.8): mean |Δ| = 0.1667 m; the tree fits.
    assert!(near(tower.size_diff_m.expect("a size"), 0.5 / 3.0));
    assert!(near(tree.size_diff_m.expect("a size"), 0.0));
    let f = tower.features.as_ref().expect("features");
    assert!(near(f.sbert.expect("sbert"), 1.0));
    assert!(near(tower.score, f.clip + 1.0 - 10.0 * 0.5 / 3.0));
    assert!(near(tree.score, 34.174 + 1.0));
}

fn resolve_cat_room(
    options: &ObjathorOptions,
) -> (holoc::resolve::Resolved, holoc::check::Scene, Catalog) {
    let (catalog, _) = load(options);
    let mut sources = SourceMap::new();
    let text = std::fs::read_to_string(CAT_ROOM).expect("the scene");
    let file = sources.add(CAT_ROOM.to_string(), text);
    let scene = holoc::compile::check_file(&sources, file).value.expect("the scene checks");
    let resolved = resolve::resolve(&scene, &catalog, scene.seed).value;
    (resolved, scene, catalog)
}

fn chosen(resolved: &holoc::resolve::Resolved, scene: &holoc::check::Scene, name: &str) -> String {
    let obj = scene.objects.iter().position(|o| o.name == name).expect("the object");
    resolved.objects[obj].choice().map_or_else(|| "-".into(), |c| c.asset_id.clone())
}

#[test]
fn the_original_filters_hold() {
    let (_dir, root) = fixture(FixtureOptions::default());
    let (resolved, scene, _) = resolve_cat_room(&options(&root));
    // The deep mirror cabinet scores higher (37.14) but is too deep for a wall (1.2 > 3 × 0.3).
    assert_eq!(name_of(&chosen(&resolved, &scene, "mirror-0")), "round_mirror");
    // The 2.4 m curtains score higher but are taller than 0.8 of the 2.5 m wall.
    assert_eq!(name_of(&chosen(&resolved, &scene, "curtains-0")), "linen_curtains");
    // The folder's only sofa is too large for the room: the sofa is AI2-THOR's.
    assert!(chosen(&resolved, &scene, "sofa-0").starts_with("Sofa_"));
    assert_eq!(name_of(&chosen(&resolved, &scene, "cat_tower-0")), "cat_tower");
    let room = [5.0, 4.0, 2.5];
    assert!(
        fits_room([4.5, 0.9, 2.0], PlacementKind::Floor, room).is_err(),
        "longer than 0.8 × 5 m"
    );
    assert!(fits_room([3.9, 0.9, 3.1], PlacementKind::Floor, room).is_err(), "footprint over half");
    assert!(fits_room([3.9, 0.9, 2.5], PlacementKind::Floor, room).is_ok());
    assert!(fits_room([0.3, 0.3, 1.2], PlacementKind::Wall, room).is_err());
    assert!(fits_room([0.3, 0.3, 0.9], PlacementKind::Wall, room).is_ok());
    assert!(fits_room([9.0, 9.0, 9.0], PlacementKind::OnObject, room).is_ok());
    // Category exclusions and the ceiling height rule: no window frame on a wall or the
    // floor, no 1.4 m projector on the ceiling.
    let (catalog, _) = load(&options(&root));
    for (category, kind, excluded) in [
        ("window frame", PlacementKind::Wall, "window_frame"),
        ("window frame", PlacementKind::Floor, "window_frame"),
        ("projector", PlacementKind::Ceiling, "projector"),
    ] {
        let got = ranked(&catalog, &query(category, "", kind));
        assert!(got.iter().all(|g| g.0 != excluded), "{category} {kind:?}: {got:?}");
    }
    let lamp = ranked(&catalog, &query("pendant lamp", "", PlacementKind::Ceiling));
    assert_eq!(lamp.first().map(|g| (g.0, g.2)), Some(("pendant_lamp", true)));
}

#[test]
fn mixing_by_score_and_the_seeded_pick() {
    let (_dir, root) = fixture(FixtureOptions::default());
    let q = query("painting", "an abstract painting in a black frame", PlacementKind::Wall);
    // Objathor first (the default, as the original): the folder's painting.
    let (catalog, _) = load(&options(&root));
    let first = resolve::resolve_query(&catalog, &q, 0, &resolve::ResolveOptions::default()).value;
    let first = first.choice().expect("chosen").asset_id.clone();
    assert_eq!(name_of(&first), "abstract_painting");
    assert!(catalog.objathor().expect("loaded").holds(catalog.index_of(&first).expect("known")));
    // Built-in first: AI2-THOR has paintings.
    let (catalog, _) = load(&ObjathorOptions { mix: Mix::BuiltinFirst, ..options(&root) });
    let first = resolve::resolve_query(&catalog, &q, 0, &resolve::ResolveOptions::default()).value;
    let first = first.choice().expect("chosen").asset_id.clone();
    assert!(!catalog.objathor().expect("loaded").holds(catalog.index_of(&first).expect("known")));
    // A thing the folder lacks comes from AI2-THOR's assets in every mix.
    let fridge = query("fridge", "a tall white fridge", PlacementKind::Floor);
    let (catalog, _) = load(&options(&root));
    let got = resolve::resolve_query(&catalog, &fridge, 0, &resolve::ResolveOptions::default());
    let got = got.value.choice().expect("chosen").asset_id.clone();
    assert!(!catalog.objathor().expect("loaded").holds(catalog.index_of(&got).expect("known")));
    // By score: the objathor painting's words match better.
    let (catalog, _) = load(&ObjathorOptions { mix: Mix::Score, ..options(&root) });
    let mixed = resolve::resolve_query(&catalog, &q, 0, &resolve::ResolveOptions::default()).value;
    let mixed = mixed.choice().expect("chosen");
    let builtin_best = resolve::rank(&catalog, &q, 0)[0].score;
    let lexical = mixed
        .parts
        .as_ref()
        .and_then(|p| p.features.as_ref())
        .map_or(f64::NAN, |f| f.lexical_score);
    assert_eq!(name_of(&mixed.asset_id), "abstract_painting", "{lexical} vs {builtin_best}");
    assert!(lexical >= builtin_best);
    // The seeded draw: the same seed gives the same order, and every order is a permutation.
    let scores = [35.0, 34.5, 34.0, 20.0];
    let a = resolve::objathor::seeded_order(&scores, 10, 7, "x");
    assert_eq!(a, resolve::objathor::seeded_order(&scores, 10, 7, "x"));
    let mut sorted = a.clone();
    sorted.sort_unstable();
    assert_eq!(sorted, vec![0, 1, 2, 3]);
    let firsts: std::collections::BTreeSet<usize> =
        (0..64).map(|seed| resolve::objathor::seeded_order(&scores, 10, seed, "x")[0]).collect();
    assert!(firsts.len() > 1 && !firsts.contains(&3), "{firsts:?}");
    // Only the best `pool` are drawn; the rest keep their rank order.
    assert_eq!(&resolve::objathor::seeded_order(&scores, 2, 3, "x")[2..], &[2, 3]);
    let (resolved, scene, _) =
        resolve_cat_room(&ObjathorOptions { pick: Pick::Seeded, ..options(&root) });
    let again = resolve_cat_room(&ObjathorOptions { pick: Pick::Seeded, ..options(&root) });
    assert_eq!(resolved, again.0);
    assert!(["cat_tower", "cat_tree"].contains(&name_of(&chosen(
        &resolved,
        &scene,
        "cat_tower-0"
    ))));
}

fn holoc(args: &[&str]) -> (i32, String, String) {
    let out = Command::new(env!("CARGO_BIN_EXE_holoc"))
        .args(args)
        .env("NO_COLOR", "1")
        .output()
        .expect("holoc runs");
    (
        out.status.code().unwrap_or(-1),
        String::from_utf8_lossy(&out.stdout).into_owned(),
        String::from_utf8_lossy(&out.stderr).into_owned(),
    )
}

#[test]
fn build_writes_houses_the_original_loader_reads_with_attributions() {
    let (dir, root) = fixture(FixtureOptions::default());
    let house = dir.path().join("house.json");
    let report = dir.path().join("report.json");
    let r = root.to_str().expect("utf-8");
    let (code, _, err) = holoc(&[
        "build",
        CAT_ROOM,
        "-o",
        house.to_str().expect("utf-8"),
        "--report",
        report.to_str().expect("utf-8"),
        "--objathor",
        r,
        "-q",
    ]);
    assert_eq!(code, 0, "{err}");
    let json: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(&house).expect("written")).expect("JSON");
    // A bare uid in `assetId`, and a floor object at half its height.
    let tower = json["objects"]
        .as_array()
        .expect("objects")
        .iter()
        .find(|o| o["assetId"] == fixture_uid("cat_tower"))
        .expect("the cat tower");
    assert!(near(tower["position"]["y"].as_f64().expect("y"), 0.75));
    let report: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(&report).expect("written")).expect("JSON");
    let names: Vec<&str> = report["assets"]["attributions"]
        .as_array()
        .expect("attributions")
        .iter()
        .map(|a| name_of(a["assetId"].as_str().expect("id")))
        .collect();
    assert_eq!(names, vec!["cat_tower", "round_mirror", "linen_curtains"]);
    let lock =
        report["assets"]["catalogs"].as_array().expect("lock").last().expect("objathor").clone();
    assert_eq!(lock["version"], FIXTURE_VERSION);
    assert_eq!(lock["scoring"], "features");
    assert_eq!(lock["files"].as_array().map(Vec::len), Some(3));
    // Deterministic: the same input gives the same bytes.
    let again = dir.path().join("again.json");
    holoc(&["build", CAT_ROOM, "-o", again.to_str().expect("utf-8"), "--objathor", r, "-q"]);
    assert_eq!(std::fs::read(&house).expect("one"), std::fs::read(&again).expect("two"));
    // `holoc validate --objathor` accepts the house; without the folder its uids are unknown.
    let h = house.to_str().expect("utf-8");
    let (code, _, err) = holoc(&["validate", h, "--objathor", r]);
    assert_eq!(code, 0, "{err}");
    let (code, _, err) = holoc(&["validate", h]);
    assert_eq!(code, 1);
    assert!(err.contains("E0614"), "{err}");
    // An asset folder removed: the house is not loadable (E0615, naming the uid).
    std::fs::remove_dir_all(root.join("assets").join(fixture_uid("linen_curtains")))
        .expect("removed");
    let (code, _, err) = holoc(&["validate", h, "--objathor", r]);
    assert_eq!(code, 1);
    assert!(err.contains("E0615") && err.contains(fixture_uid("linen_curtains")), "{err}");
    let (code, _, err) =
        holoc(&["build", CAT_ROOM, "-o", again.to_str().expect("utf-8"), "--objathor", r]);
    assert_eq!(code, 1, "{err}");
    assert!(err.contains("E0615") && err.contains(fixture_uid("linen_curtains")), "{err}");
}

#[test]
fn a_missing_asset_folder_is_an_error_and_no_assets_folder_a_warning() {
    let scene = "scene \"s\" {\n  wall height 2.7 m\n  seed 1\n}\n\nroom office \"office\" {\n  corners in m (0, 0) (0, 4) (4, 4) (4, 0)\n  wall object board \"whiteboard\" {\n    height 100 cm\n  }\n}\n\ndoor exterior -- office : doorway single\n";
    let (dir, root) = fixture(FixtureOptions::default());
    let holo = dir.path().join("office.holo");
    std::fs::write(&holo, scene).expect("written");
    let out = dir.path().join("office.json");
    let args = |root: &Path| -> Vec<String> {
        vec![
            "build".into(),
            holo.display().to_string(),
            "-o".into(),
            out.display().to_string(),
            "--objathor".into(),
            root.display().to_string(),
        ]
    };
    let run = |a: Vec<String>| holoc(&a.iter().map(String::as_str).collect::<Vec<_>>());
    let (code, _, err) = run(args(&root));
    assert_eq!(code, 1, "{err}");
    assert!(err.contains("E0615") && err.contains(fixture_uid("whiteboard")), "{err}");
    assert!(!out.exists(), "nothing is written");
    let (dir2, root2) = fixture(FixtureOptions { assets: false, ..FixtureOptions::default() });
    let (code, _, err) = run(args(&root2));
    assert_eq!(code, 0, "{err}");
    assert_eq!(err.matches("W0614").count(), 1, "{err}");
    drop(dir2);
}

#[test]
fn bad_folders_and_feature_files_are_diagnostics() {
    let (dir, root) = fixture(FixtureOptions::default());
    // A folder that does not exist; a base with the version; one with two versions.
    assert_eq!(codes(&load(&options(&dir.path().join("nope"))).1), vec!["E0404"]);
    let (catalog, diags) = load(&options(dir.path()));
    assert!(diags.is_empty() && catalog.objathor().is_some());
    let (catalog, diags) =
        load(&ObjathorOptions { version: Some(FIXTURE_VERSION.into()), ..options(dir.path()) });
    assert!(diags.is_empty() && catalog.objathor().is_some());
    assert_eq!(
        codes(
            &load(&ObjathorOptions { version: Some("1999_01_01".into()), ..options(dir.path()) }).1
        ),
        vec!["E0404"]
    );
    write_fixture(&dir.path().join("more"), FixtureOptions::default()).expect("written");
    std::fs::rename(dir.path().join("more").join(FIXTURE_VERSION), dir.path().join("2024_08_16"))
        .expect("moved");
    assert_eq!(codes(&load(&options(dir.path())).1), vec!["E0404"]);
    // `clip` is not in a build without the feature (E0405), and needs weights in one with it
    // (E0406); `features` without features cannot run.
    assert_eq!(
        codes(&load(&ObjathorOptions { scoring: Some(Scoring::Clip), ..options(&root) }).1),
        vec![if cfg!(feature = "clip") { "E0406" } else { "E0405" }]
    );
    let (_d, bare) = fixture(FixtureOptions { features: false, ..FixtureOptions::default() });
    let (catalog, diags) = load(&options(&bare));
    assert_eq!(codes(&diags), vec!["W0405"]);
    assert_eq!(catalog.objathor().expect("loaded").scoring, Scoring::Lexical);
    assert_eq!(
        codes(&load(&ObjathorOptions { scoring: Some(Scoring::Features), ..options(&bare) }).1),
        vec!["W0405", "E0405"]
    );
    // A broken pickle and a pickle of another shape: warnings, and the folder scores lexically.
    let clip = root.join("features").join("clip_features.pkl");
    let good = std::fs::read(&clip).expect("there");
    std::fs::write(&clip, &good[..good.len() / 2]).expect("cut");
    let (catalog, diags) = load(&options(&root));
    assert_eq!(codes(&diags), vec!["W0405"]);
    assert!(diags[0].message.contains("not a readable pickle"), "{}", diags[0].message);
    assert_eq!(catalog.objathor().expect("loaded").scoring, Scoring::Lexical);
    let other = holoc::resolve::objathor::pickle::write(
        &[("uids", holoc::resolve::objathor::pickle::Value::Strings(vec!["x".into()]))],
        4,
        NumpyModules::Core,
    );
    std::fs::write(&clip, other).expect("written");
    let diags = load(&options(&root)).1;
    assert!(diags[0].message.contains("no `img_features`"), "{}", diags[0].message);
    // Bad annotations: not JSON (E0403), a bad entry (W0402).
    let ann = root.join("annotations.json.gz");
    std::fs::write(&ann, b"{not json").expect("written");
    assert_eq!(codes(&load(&options(&root)).1)[0], "E0403");
    std::fs::write(&ann, br#"{"u1": {"annotations": {"category": "x"}}}"#).expect("written");
    assert_eq!(codes(&load(&options(&root)).1)[0], "W0402");
}

#[test]
fn every_example_builds_with_the_fixture_folder() {
    let (_dir, root) = fixture(FixtureOptions::default());
    let (catalog, _) = load(&options(&root));
    let embedded = Catalog::embedded();
    let mut n = 0;
    for entry in std::fs::read_dir("examples").expect("examples").flatten() {
        let path = entry.path();
        if path.extension().is_none_or(|e| e != "holo") {
            continue;
        }
        let mut sources = SourceMap::new();
        let file = sources
            .add(path.display().to_string(), std::fs::read_to_string(&path).expect("readable"));
        let with = build(&sources, file, &BuildOptions::new(&catalog));
        let without = build(&sources, file, &BuildOptions::new(&embedded));
        let (Some(with), Some(without)) = (with.value, without.value) else {
            panic!("{} does not build with the fixture folder", path.display());
        };
        assert!(with.objects.len() >= without.objects.len(), "{}", path.display());
        n += 1;
    }
    assert!(n >= 5);
}

#[test]
fn a_real_objathor_folder_has_the_counts_and_shapes_it_should() {
    let dir = std::env::var_os("HOLOC_OBJATHOR_DIR").map(PathBuf::from).or_else(|| {
        std::env::var_os("HOME")
            .map(|h| PathBuf::from(h).join(".objathor-assets").join("2023_09_23"))
    });
    let Some(dir) = dir.filter(|d| d.join("annotations.json.gz").is_file()) else {
        common::skip(
            "a_real_objathor_folder_has_the_counts_and_shapes_it_should",
            "no objathor folder (set HOLOC_OBJATHOR_DIR, or have ~/.objathor-assets/2023_09_23)",
        );
        return;
    };
    let (catalog, diags) = load(&options(&dir));
    assert!(!diags.iter().any(holoc::diag::Diagnostic::is_error), "{diags:?}");
    let obj = catalog.objathor().expect("loaded");
    assert!(obj.end - obj.start > 40_000, "{} assets", obj.end - obj.start);
    let features = obj.features.as_ref().expect("features");
    let img = features.img.as_ref().expect("image features");
    assert_eq!((img.views, img.dim), (3, 768));
    assert!(img.len() > 40_000);
    let q = query("cat tower", "", PlacementKind::Floor);
    assert!(resolve::objathor::rank(&catalog, &q, 0, 128)
        .iter()
        .any(holoc::resolve::Candidate::is_good_enough));
}

/// Issue 25's bookshelf of books and photo frames: AI2-THOR's built-in assets have no frame
/// small enough to stand on a shelf, so without objathor the frames are reported (W0401) and
/// never stood in for by a wall painting; with the fixture's small `picture frame` they stand on
/// the bookshelf beside the books.
#[test]
fn photo_frames_stand_on_the_bookshelf_with_objathor() {
    const FRAMES: &str = "tests/objathor/frames_on_a_shelf.holo";
    let (dir, root) = fixture(FixtureOptions::default());
    let run = |with_objathor: bool| -> (serde_json::Value, serde_json::Value, String) {
        let tag = if with_objathor { "with" } else { "without" };
        let house = dir.path().join(format!("{tag}.json"));
        let report = dir.path().join(format!("{tag}-report.json"));
        let mut args = vec![
            "build".to_string(),
            FRAMES.to_string(),
            "-o".to_string(),
            house.display().to_string(),
            "--report".to_string(),
            report.display().to_string(),
            "-q".to_string(),
        ];
        if with_objathor {
            args.extend(["--objathor".to_string(), root.display().to_string()]);
        } else {
            // The catalogs alone: holoc would make the frames otherwise.
            args.push("--no-make".to_string());
        }
        let args: Vec<&str> = args.iter().map(String::as_str).collect();
        let (code, _, err) = holoc(&args);
        assert_eq!(code, 0, "{err}");
        let err = err.clone();
        let read = |p: &Path| -> serde_json::Value {
            serde_json::from_str(&std::fs::read_to_string(p).expect("written")).expect("JSON")
        };
        (read(&house), read(&report), err)
    };
    let frame_uid = fixture_uid("photo_frame");
    let objects = |house: &serde_json::Value| -> Vec<serde_json::Value> {
        house["objects"].as_array().expect("objects").clone()
    };
    let is_frame_id = |o: &serde_json::Value| {
        o["children"]
            .as_array()
            .into_iter()
            .flatten()
            .chain(std::iter::once(o))
            .any(|c| c["id"].as_str().is_some_and(|i| i.contains("frame")))
    };

    let (house, report, _) = run(false);
    // Without objathor no frame is in the house (no wall painting on the shelf) and each of
    // the six is in `not_placed` with W0401.
    assert!(!objects(&house).iter().any(is_frame_id), "{house}");
    let reported: Vec<&serde_json::Value> = report["layout"]
        .as_array()
        .expect("rooms")
        .iter()
        .flat_map(|room| room["not_placed"].as_array().into_iter().flatten())
        .filter(|u| u["object"].as_str().is_some_and(|i| i.starts_with("photo frame")))
        .collect();
    assert_eq!(reported.len(), 6, "{}", report["layout"]);
    assert!(reported.iter().all(|u| u["code"] == "W0401"), "{reported:?}");

    let (house, _, err) = run(true);
    // Things on top are the children of their receptacle in the house.
    let shelf = objects(&house)
        .into_iter()
        .find(|o| o["id"].as_str().is_some_and(|i| i.starts_with("bookshelf")))
        .expect("the bookshelf");
    let on_shelf = shelf["children"].as_array().cloned().unwrap_or_default();
    let frames = on_shelf.iter().filter(|o| o["assetId"] == frame_uid).count();
    let books = on_shelf
        .iter()
        .filter(|o| o["id"].as_str().is_some_and(|i| i.starts_with("book-")))
        .count();
    assert!(frames >= 1 && books >= 1, "{frames} frames and {books} books on the shelf: {err}");
    // No frame anywhere else.
    let elsewhere = objects(&house)
        .iter()
        .filter(|o| !o["id"].as_str().is_some_and(|i| i.starts_with("bookshelf")))
        .flat_map(|o| o["children"].as_array().cloned().unwrap_or_default())
        .filter(|o| o["assetId"] == frame_uid)
        .count();
    assert_eq!(elsewhere, 0);
}

#[test]
fn float32_feature_files_rank_as_float16_ones() {
    // Made by `tests/objathor/pickles/make.py` with numpy 2.4: the same values as float32.
    for protocol in [2, 5] {
        let path = format!("tests/objathor/pickles/clip_np2_f32_p{protocol}.pkl");
        let bytes = std::fs::read(&path).expect("the pickle is in the repository");
        let p = Pickle::read(&bytes).unwrap_or_else(|e| panic!("{path}: {e}"));
        let img = p.f16_array("img_features").expect("ok").expect("there");
        assert_eq!((img.shape.clone(), img.item), (vec![2, 2, 3], 4), "{path}");
        let first: Vec<f32> = p
            .array_bytes(&img.bytes)
            .chunks_exact(4)
            .take(3)
            .map(|c| f32::from_le_bytes([c[0], c[1], c[2], c[3]]))
            .collect();
        assert_eq!(first, vec![0.5, -0.25, 1.0], "{path}");
    }
    let (_d16, root16) = fixture(FixtureOptions::default());
    let (_d32, root32) = fixture(FixtureOptions { float32: true, ..FixtureOptions::default() });
    let (c16, diags16) = load(&options(&root16));
    let (c32, diags32) = load(&options(&root32));
    assert!(diags16.is_empty() && diags32.is_empty(), "{:?}", codes(&diags32));
    assert_eq!(c32.objathor().expect("loaded").scoring, Scoring::Features, "no fallback to words");
    for (category, kind) in [
        ("cat tower", PlacementKind::Floor),
        ("mirror", PlacementKind::Wall),
        ("curtains", PlacementKind::Wall),
        ("pendant lamp", PlacementKind::Ceiling),
    ] {
        let a = ranked(&c16, &query(category, "", kind));
        let b = ranked(&c32, &query(category, "", kind));
        assert_eq!(a.len(), b.len(), "{category}");
        for (x, y) in a.iter().zip(&b) {
            assert_eq!((x.0, x.2), (y.0, y.2), "{category}");
            assert!((x.1 - y.1).abs() < 0.05, "{category}: {} vs {}", x.1, y.1);
        }
    }
}

#[test]
fn image_only_folders_never_hold_image_scores_against_text_thresholds() {
    let (_dir, root) = fixture(FixtureOptions { text_rows: false, ..FixtureOptions::default() });
    let (catalog, diags) = load(&options(&root));
    assert!(diags.is_empty(), "{:?}", codes(&diags));
    let obj = catalog.objathor().expect("loaded");
    assert_eq!((obj.scoring, obj.pseudo_query_space()), (Scoring::Features, Some("clip-image")));
    for (category, kind) in [
        ("wall mirror", PlacementKind::Wall),
        ("cat tower", PlacementKind::Floor),
        ("whiteboard", PlacementKind::Wall),
    ] {
        let list = resolve::objathor::rank(&catalog, &query(category, "", kind), 0, 128);
        for c in &list {
            let f = c.features.as_ref().expect("scored by features");
            assert!(!f.text_space);
            // Image-to-image cosines of anything alike are far above 31: they decide nothing.
            assert_eq!(
                c.is_good_enough(),
                c.relevance >= 0.5,
                "{category}: {}",
                name_of(&c.asset_id)
            );
        }
        let good: Vec<&str> =
            list.iter().filter(|c| c.is_good_enough()).map(|c| name_of(&c.asset_id)).collect();
        assert!(
            !good.iter().any(|n| ["whiteboard", "abstract_painting", "window_frame"].contains(n))
                || category == "whiteboard",
            "{category}: {good:?}"
        );
    }
    // The report leaves the threshold out.
    let report = root.join("report.json");
    let (code, _, err) = holoc(&[
        "build",
        CAT_ROOM,
        "-o",
        root.join("house.json").to_str().expect("utf-8"),
        "--report",
        report.to_str().expect("utf-8"),
        "--objathor",
        root.to_str().expect("utf-8"),
        "-q",
    ]);
    assert_eq!(code, 0, "{err}");
    let text = std::fs::read_to_string(&report).expect("written");
    assert!(text.contains("\"clipThreshold\": null"), "{text}");
    assert!(!text.contains("\"clipThreshold\": 31"), "{text}");
}

#[test]
fn a_cat_tower_finds_a_cat_tree() {
    let (_dir, root) =
        fixture(FixtureOptions { without: &["cat_tower"], ..FixtureOptions::default() });
    for scoring in [Scoring::Lexical, Scoring::Features] {
        let (catalog, _) = load(&ObjathorOptions { scoring: Some(scoring), ..options(&root) });
        let list = resolve::objathor::rank(
            &catalog,
            &query("cat tower", "a tall cat tower with platforms", PlacementKind::Floor),
            0,
            128,
        );
        let first = list.first().expect("a candidate");
        assert_eq!(name_of(&first.asset_id), "cat_tree", "{scoring:?}");
        assert!(first.is_good_enough(), "{scoring:?}");
    }
}

#[test]
fn features_find_what_shares_no_word_with_the_request() {
    let (_dir, root) = fixture(FixtureOptions::default());
    let (catalog, _) = load(&options(&root));
    let got = ranked(&catalog, &query("mirror", "", PlacementKind::Wall));
    // The looking glass shares no word with `mirror`, but the annotations put it under the
    // mirrors' synset (`mirror.n.01`): its best view against the mirrors' text rows, 31.62,
    // passes the wall threshold, as CLIP would find it (after the round mirror's 34.17).
    let glass = got.iter().find(|g| g.0 == "looking_glass").expect("found by its features");
    assert!(near(glass.1, 31.623) && glass.2, "{got:?}");
    // Lexically it is never a candidate.
    let (catalog, _) = load(&ObjathorOptions { scoring: Some(Scoring::Lexical), ..options(&root) });
    assert!(ranked(&catalog, &query("mirror", "", PlacementKind::Wall))
        .iter()
        .all(|g| g.0 != "looking_glass"));
}

#[test]
fn the_original_rules_on_similarity_breakage_textures_and_pickles() {
    let (_dir, root) = fixture(FixtureOptions::default());
    // blender_thor_similarity 0.2 < 0.6: never a candidate, in any mode.
    for scoring in [Scoring::Lexical, Scoring::Features] {
        let (catalog, _) = load(&ObjathorOptions { scoring: Some(scoring), ..options(&root) });
        let got = ranked(&catalog, &query("painting", "abstract painting", PlacementKind::Wall));
        assert!(got.iter().any(|g| g.0 == "abstract_painting"), "{scoring:?}: {got:?}");
        assert!(got.iter().all(|g| g.0 != "blurry_painting"), "{scoring:?}: {got:?}");
    }
    // emission.jpg is optional; a plain .pkl is never read by the loader.
    let assets = root.join("assets");
    let uid = fixture_uid("round_mirror");
    std::fs::remove_file(assets.join(uid).join("emission.jpg")).expect("removed");
    assert_eq!(resolve::objathor::missing_on_disk(&assets, uid), None);
    let model = assets.join(uid).join(format!("{uid}.pkl.gz"));
    std::fs::rename(&model, assets.join(uid).join(format!("{uid}.pkl"))).expect("renamed");
    let why = resolve::objathor::missing_on_disk(&assets, uid).expect("incomplete");
    assert!(why.contains("never reads") && why.contains(".pkl.gz"), "{why}");
}

#[test]
fn a_breakable_small_object_stays_kinematic() {
    // The fixture's picture frame can break (`CanBreak`): on the bookshelf it is kinematic, as
    // the original keeps it; the books beside it are left to physics.
    let (dir, root) = fixture(FixtureOptions::default());
    let out = dir.path().join("frames.json");
    let (code, _, err) = holoc(&[
        "build",
        "tests/objathor/frames_on_a_shelf.holo",
        "-o",
        out.to_str().expect("utf-8"),
        "--objathor",
        root.to_str().expect("utf-8"),
        "-q",
    ]);
    assert_eq!(code, 0, "{err}");
    let house: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(&out).expect("written")).expect("json");
    let items: Vec<&serde_json::Value> = house["objects"]
        .as_array()
        .expect("objects")
        .iter()
        .flat_map(|o| o["children"].as_array().into_iter().flatten())
        .collect();
    let frames: Vec<_> =
        items.iter().filter(|o| o["assetId"] == fixture_uid("photo_frame")).collect();
    assert!(!frames.is_empty(), "{house}");
    assert!(frames.iter().all(|f| f["kinematic"] == true), "{frames:?}");
    let books: Vec<_> =
        items.iter().filter(|o| o["id"].as_str().is_some_and(|i| i.starts_with("book"))).collect();
    assert!(!books.is_empty() && books.iter().all(|b| b["kinematic"] == false), "{books:?}");
}

#[test]
fn web_folders_fetch_their_assets_and_bad_entries_are_summed_up() {
    let (dir, root) = fixture(FixtureOptions { web: true, ..FixtureOptions::default() });
    let (catalog, diags) = load(&options(&root));
    assert!(diags.is_empty(), "{:?}", codes(&diags));
    let obj = catalog.objathor().expect("loaded");
    assert!(obj.fetched && obj.version == "2024_08_16");
    let uids = [fixture_uid("round_mirror"), fixture_uid("whiteboard")];
    let diags = resolve::objathor::check_on_disk(&catalog, uids, &|_| None);
    assert_eq!(
        codes(&diags),
        vec!["W0614"],
        "{:?}",
        diags.iter().map(|d| &d.message).collect::<Vec<_>>()
    );
    assert!(diags[0].message.contains("2 objathor assets") && diags[0].message.contains("web"));
    let help = diags[0].help.as_deref().unwrap_or_default();
    assert!(help.contains("WebProceduralAssetHookRunner"), "{help}");
    drop(dir);
    // 1,000 unusable entries: ten warnings of their own and one that counts the rest; an
    // entry without a licence gives one warning when the house uses it.
    let (_dir, root) = fixture(FixtureOptions::default());
    let ann = root.join("annotations.json.gz");
    let mut map = serde_json::Map::new();
    for i in 0..1000 {
        map.insert(format!("{i:032x}"), serde_json::json!({"annotations": {"category": "x", "onFloor": true}, "thor_metadata": {}}));
    }
    map.insert(
        fixture_uid("round_mirror").into(),
        serde_json::json!({"annotations": {"category": "mirror", "onWall": true}, "thor_metadata": {"assetMetadata": {"boundingBox": {"x": 0.8, "y": 0.8, "z": 0.03}}}}),
    );
    std::fs::write(&ann, serde_json::Value::Object(map).to_string()).expect("written");
    let (catalog, diags) = load(&options(&root));
    let w0402 = diags.iter().filter(|d| d.code.as_str() == "W0402").count();
    assert_eq!(w0402, 11, "{:?}", codes(&diags));
    let last = diags.iter().rfind(|d| d.code.as_str() == "W0402").expect("the sum");
    assert!(last.message.starts_with("990 more"), "{}", last.message);
    let diags =
        resolve::objathor::check_on_disk(&catalog, [fixture_uid("round_mirror")], &|_| None);
    assert_eq!(codes(&diags), vec!["W0406"]);
}

/// The annotations of a fixture folder (gzipped JSON).
fn annotations_of(path: &Path) -> serde_json::Value {
    let bytes = std::fs::read(path).expect("read");
    serde_json::from_reader(flate2::read::GzDecoder::new(&bytes[..])).expect("gzipped JSON")
}

/// Sets the modification time of the folder's files an hour back: an index written now can
/// vouch for them (a file changed within two seconds of its index is read again).
fn age(root: &Path) {
    let back = std::time::SystemTime::now() - std::time::Duration::from_secs(3600);
    let mut files = vec![root.join("annotations.json.gz")];
    if let Ok(entries) = std::fs::read_dir(root.join("features")) {
        files.extend(entries.flatten().map(|e| e.path()));
    }
    for f in files.iter().filter(|f| f.is_file()) {
        let file = std::fs::File::options().write(true).open(f).expect("opened");
        file.set_modified(back).expect("aged");
    }
}

/// What a load gives that a build can see: every asset and entry of the folder, the files the
/// lock records, the diagnostics, and the rankings of a few requests.
fn seen(catalog: &Catalog, diags: &[holoc::diag::Diagnostic]) -> String {
    use std::fmt::Write as _;
    let obj = catalog.objathor().expect("loaded");
    let mut out = format!("{:?}\n{:?}\n{:?}\n", obj.files, obj.entries, obj.scoring);
    for asset in &catalog.assets()[obj.start..obj.end] {
        let _ = writeln!(out, "{asset:?}");
    }
    for d in diags {
        let _ = writeln!(out, "{d:?}");
    }
    for (category, kind) in [
        ("cat tower", PlacementKind::Floor),
        ("mirror", PlacementKind::Wall),
        ("curtains", PlacementKind::Wall),
        ("painting", PlacementKind::Wall),
        ("pendant lamp", PlacementKind::Ceiling),
    ] {
        let _ = writeln!(out, "{:?}", ranked(catalog, &query(category, "", kind)));
    }
    out
}

#[test]
fn the_folder_is_read_once_and_then_from_its_index() {
    for fixture_options in [
        FixtureOptions::default(),
        FixtureOptions { float32: true, ..FixtureOptions::default() },
        FixtureOptions { text_rows: false, ..FixtureOptions::default() },
        FixtureOptions { features: false, ..FixtureOptions::default() },
    ] {
        let (_dir, root) = fixture(fixture_options);
        age(&root);
        let (first, diags) = load(&options(&root));
        let index = root.join(".holoc-index").join("objathor.idx");
        let obj = first.objathor().expect("loaded");
        assert!(
            !obj.from_index && obj.index_file.as_deref() == Some(&*index),
            "{:?}",
            obj.index_file
        );
        assert!(index.is_file());
        let (second, diags_again) = load(&options(&root));
        assert!(second.objathor().expect("loaded").from_index, "read from its index");
        assert_eq!(seen(&first, &diags), seen(&second, &diags_again));
        // Without the index: the same again, and nothing written.
        let (third, diags_third) = load(&ObjathorOptions { no_index: true, ..options(&root) });
        let obj = third.objathor().expect("loaded");
        assert!(!obj.from_index && obj.index_file.is_none());
        assert_eq!(seen(&first, &diags), seen(&third, &diags_third));
    }
}

#[test]
fn an_index_is_read_again_when_its_folder_changes_or_it_is_damaged() {
    let (_dir, root) = fixture(FixtureOptions::default());
    // Files changed just before the index was written: it cannot vouch for them.
    let _ = load(&options(&root));
    assert!(!load(&options(&root)).0.objathor().expect("loaded").from_index);
    age(&root);
    let _ = load(&options(&root));
    assert!(load(&options(&root)).0.objathor().expect("loaded").from_index);
    // The annotations replaced (without the whiteboard): read again, the whiteboard gone.
    let ann = root.join("annotations.json.gz");
    let mut value = annotations_of(&ann);
    value.as_object_mut().expect("object").remove(fixture_uid("whiteboard"));
    std::fs::write(&ann, value.to_string()).expect("written");
    let (catalog, _) = load(&options(&root));
    assert!(!catalog.objathor().expect("loaded").from_index);
    assert!(catalog.index_of(fixture_uid("whiteboard")).is_none());
    age(&root);
    let _ = load(&options(&root));
    let (catalog, _) = load(&options(&root));
    assert!(catalog.objathor().expect("loaded").from_index);
    assert!(catalog.index_of(fixture_uid("whiteboard")).is_none());
    // A feature file added where there was none.
    let (_dir, root) = fixture(FixtureOptions::default());
    let sbert = root.join("features").join("sbert_features.pkl");
    let kept = std::fs::read(&sbert).expect("read");
    std::fs::remove_file(&sbert).expect("removed");
    age(&root);
    let (without, _) = load(&options(&root));
    assert!(without
        .objathor()
        .expect("loaded")
        .features
        .as_ref()
        .is_some_and(|f| f.sbert.is_none()));
    std::fs::write(&sbert, kept).expect("written");
    age(&root);
    let (with, _) = load(&options(&root));
    let obj = with.objathor().expect("loaded");
    assert!(!obj.from_index && obj.features.as_ref().is_some_and(|f| f.sbert.is_some()));
    // What a run killed while writing the index left is removed by the next one that writes.
    let (_other, other) = fixture(FixtureOptions::default());
    std::fs::create_dir(other.join(".holoc-index")).expect("made");
    let stale = other.join(".holoc-index").join(".holoc-999999999-x1y2z3.tmp");
    std::fs::write(&stale, "half an index").expect("written");
    let _ = load(&options(&other));
    assert!(!stale.exists(), "the stale temporary file is removed");
    assert!(other.join(".holoc-index").join("objathor.idx").is_file());
    // A damaged index, cut short or overwritten: the folder is read, the index written again.
    let index = root.join(".holoc-index").join("objathor.idx");
    let whole = std::fs::read(&index).expect("the index");
    let (good, good_diags) = load(&options(&root));
    for damaged in [
        whole[..whole.len() / 2].to_vec(),
        whole[..100].to_vec(),
        vec![0u8; whole.len()],
        whole.iter().enumerate().map(|(i, b)| if i % 97 == 5 { !b } else { *b }).collect(),
        [&whole[..64], &vec![0xff; whole.len() - 64][..]].concat(),
    ] {
        std::fs::write(&index, &damaged).expect("damaged");
        let (catalog, diags) = load(&options(&root));
        let obj = catalog.objathor().expect("loaded");
        assert_eq!(seen(&good, &good_diags), seen(&catalog, &diags));
        if !obj.from_index {
            assert!(load(&options(&root)).0.objathor().expect("loaded").from_index);
        }
    }
}

#[test]
fn unusable_entries_warn_alike_from_the_index() {
    let (_dir, root) = fixture(FixtureOptions::default());
    let ann = root.join("annotations.json.gz");
    let mut value = annotations_of(&ann);
    let map = value.as_object_mut().expect("object");
    for i in 0..25 {
        map.insert(format!("{i:032x}"), serde_json::json!({"annotations": {"category": "x", "onFloor": true}, "thor_metadata": {}}));
    }
    map.insert("bad".into(), serde_json::json!(7));
    std::fs::write(&ann, value.to_string()).expect("written");
    age(&root);
    let render = |diags: &[holoc::diag::Diagnostic], sources: &SourceMap| -> String {
        holoc::diag::lsp::render_lsp(sources, diags)
    };
    let mut sources = SourceMap::new();
    let cold = Catalog::load_with(&[] as &[PathBuf], Some(&options(&root)), &mut sources);
    let cold_text = render(&cold.diagnostics, &sources);
    let mut sources = SourceMap::new();
    let warm = Catalog::load_with(&[] as &[PathBuf], Some(&options(&root)), &mut sources);
    assert!(warm.value.objathor().expect("loaded").from_index);
    assert_eq!(cold_text, render(&warm.diagnostics, &sources));
    assert_eq!(codes(&warm.diagnostics).iter().filter(|c| **c == "W0402").count(), 11);
    let sum = format!("{:?}", warm.diagnostics.last().expect("the sum"));
    assert!(sum.contains("1 × it is not a JSON object (the first: `bad`)"), "{sum}");
}

#[test]
fn a_house_is_the_same_built_from_the_folder_or_its_index() {
    let dir = tempfile::tempdir().expect("a temporary folder");
    let root = write_fixture(dir.path(), FixtureOptions::default()).expect("written");
    age(&root);
    let out = dir.path().join("out");
    let root_s = root.to_str().expect("utf-8");
    let build = |name: &str, extra: &[&str], cache: &Path| {
        let house = out.join(format!("{name}.json"));
        let report = out.join(format!("{name}.report.json"));
        let mut args = vec![
            "build",
            CAT_ROOM,
            "--objathor",
            root_s,
            "-o",
            house.to_str().expect("utf-8"),
            "--report",
            report.to_str().expect("utf-8"),
        ];
        args.extend(extra);
        let got = Command::new(env!("CARGO_BIN_EXE_holoc"))
            .args(&args)
            .env("NO_COLOR", "1")
            .env("HOLOC_CACHE_DIR", cache)
            .output()
            .expect("holoc runs");
        let stderr = String::from_utf8_lossy(&got.stderr).into_owned();
        assert_eq!(got.status.code(), Some(0), "{stderr}");
        let text = |p: PathBuf| std::fs::read_to_string(p).expect("written");
        (text(house), text(report), stderr)
    };
    let cache = dir.path().join("cache");
    let plain = build("plain", &["--objathor-no-index"], &cache);
    assert!(!root.join(".holoc-index").exists() && !cache.exists(), "nothing written");
    let first = build("first", &[], &cache);
    assert!(root.join(".holoc-index").join("objathor.idx").is_file());
    let second = build("second", &[], &cache);
    assert!(plain.0 == first.0 && first.0 == second.0, "the same house");
    assert!(plain.1 == first.1 && first.1 == second.1, "the same report");
    // A folder that cannot take its index: the cache folder does.
    std::fs::remove_dir_all(root.join(".holoc-index")).expect("removed");
    std::fs::write(root.join(".holoc-index"), "in the way").expect("written");
    let cached = build("cached", &[], &cache);
    assert!(plain.0 == cached.0);
    let files: Vec<_> =
        std::fs::read_dir(cache.join("objathor")).expect("the cache").flatten().collect();
    assert_eq!(files.len(), 1, "{files:?}");
    assert!(files[0].file_name().to_string_lossy().starts_with("2023_09_23-"));
    assert!(plain.0 == build("cached_again", &[], &cache).0);
    // Neither: one warning, the same house.
    let blocked = dir.path().join("blocked");
    std::fs::write(&blocked, "a file, not a folder").expect("written");
    let (house, _, stderr) = build("blocked", &[], &blocked);
    assert!(plain.0 == house);
    assert!(stderr.contains("W0407"), "{stderr}");
}

//! The 3D export and the viewer page: every example's house exported to GLB, read back with the
//! `gltf` crate (one node per room, wall, door, window and object; every object's box where the
//! house puts it), checked by the Khronos glTF-Validator (node, npm package `gltf-validator`);
//! the viewer page opened in headless Chromium (the object count it reports, a screenshot that
//! is not blank, a top view compared with a reviewed picture); a snapshot of one small house's
//! JSON chunk.
//!
//! The validator and Chromium are installed by `.ci/run`; without them those tests say so and
//! skip. `HOLOC_UPDATE_PICTURES=1` rewrites the reference top view and the book's pictures.

mod common;

use holoc::compile::{build, BuildOptions};
use holoc::export::{euler_rotation, export, ExportOptions, ObjectMode};
use holoc::lower::thor::{House, Object};
use holoc::resolve::Catalog;
use holoc::source::SourceMap;
use std::collections::{BTreeMap, BTreeSet};
use std::path::{Path, PathBuf};
use std::process::Command;
use std::sync::OnceLock;

/// One built example: its name, its house and its build report.
struct Example {
    name: String,
    house: House,
    report: serde_json::Value,
    /// The assets holoc made for it.
    made: Vec<std::sync::Arc<holoc::make::MadeAsset>>,
}

impl Example {
    /// The catalog with its made assets, and export options that draw them.
    fn with_made(&self, catalog: &Catalog) -> (Catalog, ExportOptions) {
        let with = catalog.with_made(holoc::make::catalog_assets(&self.made));
        let options = ExportOptions {
            made: std::sync::Arc::new(holoc::export::MadeMeshes::of_made(&self.made)),
            ..ExportOptions::default()
        };
        (with, options)
    }
}

fn examples() -> &'static [Example] {
    static BUILT: OnceLock<Vec<Example>> = OnceLock::new();
    BUILT.get_or_init(|| {
        let mut paths: Vec<PathBuf> = std::fs::read_dir("examples")
            .expect("examples folder")
            .flatten()
            .map(|e| e.path())
            .filter(|p| p.extension().is_some_and(|e| e == "holo"))
            .collect();
        paths.sort();
        let catalog = Catalog::embedded();
        paths
            .iter()
            .map(|path| {
                let mut sources = SourceMap::new();
                let text = std::fs::read_to_string(path).expect("readable");
                let id = sources.add(path.display().to_string(), text);
                let built = build(&sources, id, &BuildOptions::new(&catalog));
                let built = built.value.unwrap_or_else(|| panic!("{} builds", path.display()));
                let name = path.file_stem().expect("a name").to_string_lossy().into_owned();
                let report = holoc::report::report(&built, &catalog);
                let made = holoc::make::used_in(
                    &built.resolved,
                    built.objects.iter().map(|o| o.asset_id.as_str()),
                );
                Example { name, house: built.house.house.clone(), report, made }
            })
            .collect()
    })
}

fn example(name: &str) -> &'static Example {
    examples().iter().find(|e| e.name == name).expect("the example exists")
}

fn all_objects(house: &House) -> Vec<&Object> {
    fn walk<'h>(o: &'h Object, out: &mut Vec<&'h Object>) {
        out.push(o);
        for c in &o.children {
            walk(c, out);
        }
    }
    let mut out = Vec::new();
    for o in &house.objects {
        walk(o, &mut out);
    }
    out
}

fn expected_nodes(house: &House) -> usize {
    house.rooms.len()
        + house.walls.len()
        + house.doors.len()
        + house.windows.len()
        + all_objects(house).len()
}

#[test]
fn every_example_reads_back_with_one_node_per_thing_and_every_box_in_place() {
    let catalog = Catalog::embedded();
    for ex in examples() {
        let (catalog, options) = ex.with_made(&catalog);
        let exported = export(&ex.house, &catalog, &options).expect("exports");
        let glb = exported.to_glb();
        assert_eq!(
            export(&ex.house, &catalog, &options).expect("exports").to_glb(),
            glb,
            "{}: not deterministic",
            ex.name
        );
        let doc = gltf::Gltf::from_slice(&glb).expect("the gltf crate reads the GLB");
        let n = expected_nodes(&ex.house);
        assert_eq!(doc.nodes().count(), n, "{}: node count", ex.name);
        assert_eq!(exported.counts.nodes(), n, "{}", ex.name);
        let scene = doc.default_scene().expect("a default scene");
        assert_eq!(scene.nodes().count(), n, "{}: every node in the scene", ex.name);
        let by_name: BTreeMap<&str, gltf::Node<'_>> =
            doc.nodes().filter_map(|node| Some((node.name()?, node))).collect();
        assert_eq!(by_name.len(), n, "{}: node names are the house's unique ids", ex.name);
        for o in all_objects(&ex.house) {
            let node = &by_name[o.id.as_str()];
            let asset = catalog.get(&o.asset_id).expect("the asset is in the catalog");
            // The box the viewer draws: the mesh's bounds, placed by the node.
            let mesh = node.mesh().expect("an object has a mesh");
            // A made asset is several primitives (one per colour): their bounds together.
            let mut bounds = mesh.primitives().next().expect("a primitive").bounding_box();
            for p in mesh.primitives() {
                let b = p.bounding_box();
                for i in 0..3 {
                    bounds.min[i] = bounds.min[i].min(b.min[i]);
                    bounds.max[i] = bounds.max[i].max(b.max[i]);
                }
            }
            let (t, r, s) = node.transform().decomposed();
            let q = nalgebra::UnitQuaternion::from_quaternion(nalgebra::Quaternion::new(
                f64::from(r[3]),
                f64::from(r[0]),
                f64::from(r[1]),
                f64::from(r[2]),
            ));
            let local_centre = nalgebra::Vector3::from_fn(|i, _| {
                f64::from(s[i]) * f64::from(bounds.min[i] + bounds.max[i]) / 2.0
            });
            let centre = nalgebra::Vector3::from_fn(|i, _| f64::from(t[i])) + q * local_centre;
            let size: Vec<f64> = (0..3)
                .map(|i| f64::from(s[i]) * f64::from(bounds.max[i] - bounds.min[i]))
                .collect();
            let want = [o.position.x, o.position.y, o.position.z];
            for i in 0..3 {
                assert!(
                    (centre[i] - want[i]).abs() < 1e-3,
                    "{}: `{}` centre {centre:?} is not the house's {want:?}",
                    ex.name,
                    o.id
                );
                assert!(
                    (size[i] - asset.bbox_m[i]).abs() < 1e-3,
                    "{}: `{}` size {size:?} is not its asset's {:?}",
                    ex.name,
                    o.id,
                    asset.bbox_m
                );
            }
            let turn = euler_rotation(o.rotation.x, o.rotation.y, o.rotation.z);
            assert!(q.angle_to(&turn) < 1e-3, "{}: `{}` is turned otherwise", ex.name, o.id);
            let extras: serde_json::Value =
                serde_json::from_str(node.extras().as_ref().expect("extras").get())
                    .expect("extras are JSON");
            assert_eq!(extras["kind"], "object");
            assert_eq!(extras["assetId"], o.asset_id.as_str());
            assert_eq!(extras["roomId"], o.room_id.as_str());
            assert_eq!(extras["objectType"], &*asset.object_type);
        }
    }
}

#[test]
fn rooms_objects_and_ceilings_can_be_left_out() {
    let catalog = Catalog::embedded();
    let house = &example("apartment_1b1b").house;
    let first = house.rooms[0].id.clone();
    let options = ExportOptions {
        ceiling: false,
        rooms: Some(BTreeSet::from([first.clone()])),
        objects: ObjectMode::None,
        ..ExportOptions::default()
    };
    let exported = export(house, &catalog, &options).expect("exports");
    let c = exported.counts;
    assert_eq!(c.rooms, 1);
    assert_eq!(c.objects, 0);
    assert_eq!(c.walls, house.walls.iter().filter(|w| w.room_id == first).count());
    assert_eq!(
        c.doors,
        house.doors.iter().filter(|d| d.room0 == first || d.room1 == first).count()
    );
    let full = export(house, &catalog, &ExportOptions::default()).expect("exports");
    let with_ceiling = ExportOptions { ceiling: true, ..options.clone() };
    let ceiling = export(house, &catalog, &with_ceiling).expect("exports");
    assert!(ceiling.bin.len() > exported.bin.len(), "the ceiling adds geometry");
    assert!(full.counts.nodes() > ceiling.counts.nodes());
    let unknown = ExportOptions { rooms: Some(BTreeSet::from(["attic".to_string()])), ..options };
    assert!(export(house, &catalog, &unknown).is_err());
}

#[test]
fn the_json_chunk_of_a_small_house() {
    let catalog = Catalog::embedded();
    let exported =
        export(&example("bedroom").house, &catalog, &ExportOptions::default()).expect("exports");
    insta::with_settings!({snapshot_path => "../snapshots/export", prepend_module_to_snapshot => false, omit_expression => true}, {
        insta::assert_snapshot!("bedroom_gltf_json", exported.json_pretty());
    });
}

/// The folder that holds `node_modules/gltf-validator` (where `.ci/run` installs it).
fn npm_prefix() -> PathBuf {
    std::env::var_os("HOLOC_NPM_PREFIX").map_or_else(
        || {
            let home = std::env::var_os("HOME").unwrap_or_default();
            Path::new(&home).join(".cache/holoc/npm")
        },
        PathBuf::from,
    )
}

fn runs(program: &str) -> bool {
    Command::new(program).arg("--version").output().is_ok_and(|o| o.status.success())
}

#[test]
fn the_khronos_validator_finds_no_error_and_no_warning() {
    let test = "export::the_khronos_validator_finds_no_error_and_no_warning";
    let modules = npm_prefix().join("node_modules");
    if !runs("node") || !modules.join("gltf-validator").exists() {
        common::skip(
            test,
            "node or the npm package gltf-validator is missing (.ci/run installs them)",
        );
        return;
    }
    let catalog = Catalog::embedded();
    let dir = tempfile::tempdir().expect("a scratch folder");
    let mut files = Vec::new();
    for ex in examples() {
        let (catalog, drawn) = ex.with_made(&catalog);
        let variants = [
            ("", drawn),
            (
                "-bare",
                ExportOptions {
                    ceiling: false,
                    objects: ObjectMode::None,
                    ..ExportOptions::default()
                },
            ),
        ];
        for (suffix, options) in variants {
            let path = dir.path().join(format!("{}{suffix}.glb", ex.name));
            let glb = export(&ex.house, &catalog, &options).expect("exports").to_glb();
            std::fs::write(&path, glb).expect("written");
            files.push(path);
        }
    }
    let out = Command::new("node")
        .arg("tests/export/validate_glb.js")
        .args(&files)
        .env("NODE_PATH", &modules)
        .output()
        .expect("node runs");
    assert!(out.status.success(), "the validator failed: {}", String::from_utf8_lossy(&out.stderr));
    let text = String::from_utf8_lossy(&out.stdout);
    let reports: Vec<serde_json::Value> =
        text.lines().map(|l| serde_json::from_str(l).expect("a JSON line")).collect();
    assert_eq!(reports.len(), files.len());
    for r in reports {
        assert_eq!(r["errors"], 0, "{r}");
        assert_eq!(r["warnings"], 0, "{r}");
    }
}

/// Headless Chromium with the flags the tests use (WebGL through SwiftShader, nothing from the
/// network, a fresh profile).
fn chromium() -> Option<&'static str> {
    ["chromium", "chromium-browser"].into_iter().find(|p| runs(p))
}

fn run_chromium(browser: &str, profile: &Path, args: &[String]) -> std::process::Output {
    Command::new(browser)
        .args([
            "--headless",
            "--no-sandbox",
            "--disable-gpu",
            "--enable-unsafe-swiftshader",
            "--disable-quic",
            "--no-first-run",
            "--disable-background-networking",
            "--disable-component-update",
            "--disable-sync",
            "--hide-scrollbars",
            "--virtual-time-budget=20000",
        ])
        .arg(format!("--user-data-dir={}", profile.display()))
        .args(args)
        .output()
        .expect("chromium runs")
}

/// The pixels of a PNG as RGB.
fn rgb_pixels(path: &Path) -> (u32, u32, Vec<[u8; 3]>) {
    let decoder = png::Decoder::new(std::fs::File::open(path).expect("the screenshot exists"));
    let mut reader = decoder.read_info().expect("a PNG");
    let mut buf = vec![0; reader.output_buffer_size()];
    let info = reader.next_frame(&mut buf).expect("a frame");
    let step = info.color_type.samples();
    let px = buf[..info.buffer_size()].chunks(step).map(|c| [c[0], c[1], c[2]]).collect();
    (info.width, info.height, px)
}

#[test]
fn the_viewer_page_shows_the_house_in_chromium() {
    let test = "export::the_viewer_page_shows_the_house_in_chromium";
    let Some(browser) = chromium() else {
        common::skip(test, "chromium is missing (.ci/run installs Debian's chromium)");
        return;
    };
    let catalog = Catalog::embedded();
    let ex = example("apartment_1b1b");
    let options = ExportOptions { ceiling: false, ..ExportOptions::default() };
    let exported = export(&ex.house, &catalog, &options).expect("exports");
    let html =
        holoc::export::viewer::page(&ex.house, &exported.to_glb(), Some(&ex.report), &ex.name);
    // Kept after the test, to look at: target/tmp/viewer/.
    let dir = Path::new(env!("CARGO_TARGET_TMPDIR")).join("viewer");
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).expect("a scratch folder");
    let page = dir.join("apartment.html");
    std::fs::write(&page, html).expect("written");
    let url = format!("file://{}", page.display());

    // The page reports the objects it loaded.
    let out = run_chromium(browser, &dir.join("p1"), &["--dump-dom".into(), url.clone()]);
    let dom = String::from_utf8_lossy(&out.stdout);
    let objects = all_objects(&ex.house).len();
    assert!(
        dom.contains(&format!("data-objects=\"{objects}\"")),
        "the page does not report {objects} objects: {}",
        dom.lines().find(|l| l.contains("id=\"status\"")).unwrap_or("no status line")
    );

    // A view in perspective that is not blank.
    let shot = dir.join("perspective.png");
    run_chromium(
        browser,
        &dir.join("p2"),
        &[format!("--screenshot={}", shot.display()), "--window-size=1200,800".into(), url.clone()],
    );
    let (_, _, px) = rgb_pixels(&shot);
    let background = px[0];
    let differing = px.iter().filter(|p| **p != background).count();
    assert!(
        differing * 4 > px.len(),
        "the screenshot is mostly blank ({differing} of {} pixels)",
        px.len()
    );
    let colours: BTreeSet<[u8; 3]> = px.iter().map(|p| [p[0] >> 3, p[1] >> 3, p[2] >> 3]).collect();
    assert!(colours.len() > 30, "the screenshot has only {} colours", colours.len());

    // The top view, compared with the reviewed picture.
    let top = dir.join("top.png");
    run_chromium(
        browser,
        &dir.join("p3"),
        &[
            format!("--screenshot={}", top.display()),
            "--window-size=640,480".into(),
            format!("{url}#top"),
        ],
    );
    let reference = Path::new("tests/export/apartment_top.png");
    if std::env::var_os("HOLOC_UPDATE_PICTURES").is_some() {
        std::fs::copy(&top, reference).expect("reference written");
        std::fs::create_dir_all("book/src/export").expect("book folder");
        std::fs::copy(&shot, "book/src/export/apartment.png").expect("picture written");
        std::fs::copy(&top, "book/src/export/apartment_top.png").expect("picture written");
    }
    let (w, h, now) = rgb_pixels(&top);
    let (rw, rh, want) = rgb_pixels(reference);
    assert_eq!((w, h), (rw, rh), "the top view's size changed");
    let far =
        now.iter().zip(&want).filter(|(a, b)| (0..3).any(|i| a[i].abs_diff(b[i]) > 48)).count();
    let mean: f64 = now
        .iter()
        .zip(&want)
        .map(|(a, b)| (0..3).map(|i| f64::from(a[i].abs_diff(b[i]))).sum::<f64>() / 3.0)
        .sum::<f64>()
        / now.len() as f64;
    assert!(
        far * 50 < now.len() && mean < 4.0,
        "the top view differs from tests/export/apartment_top.png: {far} pixels far off, mean difference {mean:.2} (look at {}; HOLOC_UPDATE_PICTURES=1 rewrites it)",
        top.display()
    );
}

fn holoc() -> Command {
    Command::new(env!("CARGO_BIN_EXE_holoc"))
}

#[test]
fn the_commands_write_what_they_say_and_refuse_what_they_cannot_draw() {
    let dir = Path::new(env!("CARGO_TARGET_TMPDIR")).join("export-cli");
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).expect("a scratch folder");
    let house = dir.join("bedroom.json");
    std::fs::write(&house, serde_json::to_string_pretty(&example("bedroom").house).expect("json"))
        .expect("written");

    // `export` writes the GLB that the library makes, and says what it holds.
    let glb = dir.join("bedroom.glb");
    let out = holoc().arg("export").arg(&house).arg("-o").arg(&glb).output().expect("runs");
    assert!(out.status.success(), "{}", String::from_utf8_lossy(&out.stderr));
    let expected =
        export(&example("bedroom").house, &Catalog::embedded(), &ExportOptions::default())
            .expect("exports")
            .to_glb();
    assert_eq!(std::fs::read(&glb).expect("written"), expected);
    assert!(String::from_utf8_lossy(&out.stderr).starts_with("exported "));

    // `build --emit glb` gives the same file; without `-o` it is a usage error.
    let built = dir.join("built.glb");
    let out = holoc()
        .args(["build", "examples/bedroom.holo", "--emit", "glb", "-q", "-o"])
        .arg(&built)
        .output()
        .expect("runs");
    assert!(out.status.success(), "{}", String::from_utf8_lossy(&out.stderr));
    assert_eq!(std::fs::read(&built).expect("written"), expected);
    let out =
        holoc().args(["build", "examples/bedroom.holo", "--emit", "glb"]).output().expect("runs");
    assert_eq!(out.status.code(), Some(2));
    assert!(String::from_utf8_lossy(&out.stderr).contains("E0004"));

    // A room the house lacks: E0004 with the closest id.
    let out = holoc()
        .arg("export")
        .arg(&house)
        .args(["--rooms", "bedrom", "-o"])
        .arg(dir.join("x.glb"))
        .output()
        .expect("runs");
    assert_eq!(out.status.code(), Some(2));
    let err = String::from_utf8_lossy(&out.stderr);
    assert!(err.contains("E0004") && err.contains("did you mean `bedroom`?"), "{err}");

    // A file that is not a house: E0601, nothing written.
    let broken = dir.join("broken.json");
    std::fs::write(&broken, "{\"rooms\": 3}").expect("written");
    let out = holoc()
        .args(["export", "--format", "short"])
        .arg(&broken)
        .arg("-o")
        .arg(dir.join("broken.glb"))
        .output()
        .expect("runs");
    assert_eq!(out.status.code(), Some(1));
    assert!(String::from_utf8_lossy(&out.stderr).contains("E0601"));
    assert!(!dir.join("broken.glb").exists());

    // `view` and `render --3d` write a page that holds the house and the viewer.
    let page = dir.join("bedroom.html");
    let out = holoc().arg("view").arg(&house).arg("-o").arg(&page).output().expect("runs");
    assert!(out.status.success(), "{}", String::from_utf8_lossy(&out.stderr));
    let html = std::fs::read_to_string(&page).expect("written");
    assert!(html.contains("id=\"holoc-data\"") && html.contains("HOLOC3D"));
    assert!(!html.contains("<script src") && !html.contains("<link "), "the page loads nothing");
    let rendered = dir.join("rendered.html");
    let out = holoc()
        .args(["render", "examples/bedroom.holo", "--3d", "-o"])
        .arg(&rendered)
        .output()
        .expect("runs");
    assert!(out.status.success(), "{}", String::from_utf8_lossy(&out.stderr));
    let html = std::fs::read_to_string(&rendered).expect("written");
    assert!(html.contains("\"hasReport\":true"));
}

/// Every house of `../shared/data/real-scenes/` that `holoc validate` accepts (ProcTHOR's, with
/// no agent, no layers, doors without `openable`…) is exported and viewed: what it leaves out is
/// filled with AI2-THOR's defaults.
#[test]
fn every_real_house_validate_accepts_is_exported_and_viewed() {
    let test = "every_real_house_validate_accepts_is_exported_and_viewed";
    let Some(folder) = common::shared("data/real-scenes", test) else { return };
    let dir = Path::new(env!("CARGO_TARGET_TMPDIR")).join("export-real");
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).expect("a scratch folder");
    let mut files: Vec<PathBuf> = std::fs::read_dir(&folder)
        .expect("readable")
        .flatten()
        .map(|e| e.path())
        .filter(|p| p.extension().is_some_and(|e| e == "json"))
        .collect();
    files.sort();
    let mut accepted = 0;
    for file in &files {
        let validated = holoc().arg("validate").arg(file).output().expect("runs");
        if !validated.status.success() {
            continue;
        }
        accepted += 1;
        let glb = dir.join("house.glb");
        let out = holoc().arg("export").arg(file).arg("-o").arg(&glb).output().expect("runs");
        assert!(
            out.status.success() && glb.exists(),
            "{}: export refuses a house validate accepts:\n{}",
            file.display(),
            String::from_utf8_lossy(&out.stderr)
        );
        let page = dir.join("house.html");
        let out = holoc().arg("view").arg(file).arg("-o").arg(&page).output().expect("runs");
        assert!(
            out.status.success(),
            "{}: view refuses a house validate accepts:\n{}",
            file.display(),
            String::from_utf8_lossy(&out.stderr)
        );
        let house: serde_json::Value =
            serde_json::from_str(&std::fs::read_to_string(file).expect("readable")).expect("json");
        let objects = house["objects"].as_array().map_or(0, Vec::len);
        let html = std::fs::read_to_string(&page).expect("written");
        assert!(html.contains("HOLOC3D"), "{}", file.display());
        assert!(objects > 0, "{}", file.display());
        let _ = std::fs::remove_file(&glb);
    }
    assert!(accepted >= 4, "only {accepted} real houses pass validate");

    // A house without what no default stands in for (a room's floor material): E0616.
    let mut house: serde_json::Value =
        serde_json::to_value(&example("bedroom").house).expect("json");
    if let Some(room) = house["rooms"][0].as_object_mut() {
        room.remove("floorMaterial");
    }
    let broken = dir.join("no-floor-material.json");
    std::fs::write(&broken, house.to_string()).expect("written");
    let validated = holoc().arg("validate").arg(&broken).output().expect("runs");
    if validated.status.success() {
        let out = holoc()
            .args(["export", "--format", "short"])
            .arg(&broken)
            .arg("-o")
            .arg(dir.join("x.glb"))
            .output()
            .expect("runs");
        let err = String::from_utf8_lossy(&out.stderr);
        assert_eq!(out.status.code(), Some(1), "{err}");
        assert!(err.contains("E0616") && err.contains("floorMaterial"), "{err}");
    }
}

/// A click on an object in headless Chromium (`#click=NAME`: the camera looks at it, then a
/// click at its middle) shows its id, asset, size and every relation of the build report, kept
/// or not, for a room whose id (`living_room`) differs from its label (`living room`); and
/// `holoc view BEFORE AFTER` marks a moved, an added and a removed object.
#[test]
fn a_click_shows_relations_and_two_houses_show_what_changed() {
    let test = "export::a_click_shows_relations_and_two_houses_show_what_changed";
    let Some(browser) = chromium() else {
        common::skip(test, "chromium is missing (.ci/run installs Debian's chromium)");
        return;
    };
    let dir = Path::new(env!("CARGO_TARGET_TMPDIR")).join("viewer-click");
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).expect("a scratch folder");
    let ex = example("apartment_1b1b");
    let house = dir.join("apartment.json");
    let report = dir.join("apartment.report.json");
    std::fs::write(&house, serde_json::to_string_pretty(&ex.house).expect("json"))
        .expect("written");
    std::fs::write(&report, serde_json::to_string_pretty(&ex.report).expect("json"))
        .expect("written");
    let page = dir.join("apartment.html");
    let out = holoc()
        .arg("view")
        .arg(&house)
        .arg("--report")
        .arg(&report)
        .arg("-o")
        .arg(&page)
        .output()
        .expect("runs");
    assert!(out.status.success(), "{}", String::from_utf8_lossy(&out.stderr));
    let url = format!("file://{}#click=sofa-0", page.display());
    let out = run_chromium(
        browser,
        &dir.join("p1"),
        &["--window-size=1200,800".into(), "--dump-dom".into(), url],
    );
    let dom = String::from_utf8_lossy(&out.stdout);
    let panel = dom
        .split("id=\"panel\"")
        .nth(1)
        .and_then(|p| p.split("</div>").next())
        .unwrap_or_default()
        .to_string();
    assert!(panel.contains("data-picked=\"sofa-0\""), "the click picked another thing: {panel}");
    assert!(panel.contains("sofa-0 (living room)"), "no id: {panel}");
    let sofa = ex.house.objects.iter().find(|o| o.object_name == "sofa-0").expect("a sofa");
    assert!(panel.contains(&sofa.asset_id), "no asset: {panel}");
    assert!(panel.contains("<dt>size</dt>") && panel.contains(" cm"), "no size: {panel}");
    let relations: Vec<&serde_json::Value> = ex.report["layout"]
        .as_array()
        .expect("layout")
        .iter()
        .filter(|r| r["room"] == "living_room")
        .flat_map(|r| r["floor_objects"].as_array().expect("objects"))
        .filter(|o| o["object"] == "sofa-0")
        .flat_map(|o| o["constraints"].as_array().expect("constraints"))
        .collect();
    assert!(!relations.is_empty());
    for r in &relations {
        let text = r["constraint"].as_str().expect("a constraint");
        let class = if r["satisfied"] == true { "kept" } else { "broken" };
        assert!(
            panel.contains(&format!("class=\"{class}\"")) && panel.contains(text),
            "relation `{text}` not shown as {class}: {panel}"
        );
    }
    assert!(panel.contains("living room · living_room"), "the room by label and id: {panel}");

    // Before and after: the sofa moved, the armchair removed, a plant added.
    let mut after = ex.house.clone();
    let sofa = after.objects.iter_mut().find(|o| o.object_name == "sofa-0").expect("a sofa");
    sofa.position.z -= 0.5;
    let armchair = after.objects.iter().position(|o| o.object_name == "armchair-0").expect("one");
    let mut plant = after.objects.remove(armchair);
    plant.id = "plant-0 (living room)".into();
    plant.object_name = "plant-0".into();
    plant.asset_id = "Houseplant_1".into();
    plant.position.x += 0.2;
    after.objects.push(plant);
    let after_path = dir.join("after.json");
    std::fs::write(&after_path, serde_json::to_string_pretty(&after).expect("json"))
        .expect("written");
    let compare = dir.join("compare.html");
    let out = holoc()
        .arg("view")
        .arg(&house)
        .arg(&after_path)
        .arg("-o")
        .arg(&compare)
        .output()
        .expect("runs");
    assert!(out.status.success(), "{}", String::from_utf8_lossy(&out.stderr));
    let out = run_chromium(
        browser,
        &dir.join("p2"),
        &["--dump-dom".into(), format!("file://{}", compare.display())],
    );
    let dom = String::from_utf8_lossy(&out.stdout);
    let legend = dom.split("id=\"compare\"").nth(1).unwrap_or_default();
    for (what, n) in [("moved", 1), ("added", 1), ("removed", 1)] {
        assert!(legend.contains(&format!("data-{what}=\"{n}\"")), "{what}: {legend:.400}");
    }
}

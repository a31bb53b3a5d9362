//! Every example builds: no errors, a house that `holoc validate` accepts, the same bytes twice,
//! and a reviewed snapshot of its layout; the paper's apartment is also kept as a golden house
//! and a golden SVG plan.

mod common;

use holoc::compile::{build, BuildOptions, Built};
use holoc::resolve::structure::StructureCatalog;
use holoc::resolve::Catalog;
use holoc::solve::Solver;
use holoc::source::SourceMap;
use std::path::{Path, PathBuf};

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

fn build_example(
    path: &Path,
    solver: Solver,
) -> (SourceMap, Option<Built>, Vec<holoc::diag::Diagnostic>) {
    let mut sources = SourceMap::new();
    let id =
        sources.add(path.display().to_string(), std::fs::read_to_string(path).expect("readable"));
    let catalog = Catalog::embedded();
    let options = BuildOptions { solver, ..BuildOptions::new(&catalog) };
    let out = build(&sources, id, &options);
    (sources, out.value, out.diagnostics)
}

#[test]
fn every_example_builds_validates_and_is_deterministic() {
    for path in examples() {
        for solver in [Solver::Dfs, Solver::Milp] {
            let (sources, built, diagnostics) = build_example(&path, solver);
            let Some(built) = built else {
                panic!(
                    "{} does not build:\n{}",
                    path.display(),
                    common::render(&sources, &diagnostics)
                );
            };
            let json = built.house.to_json_string();
            let (_, again, _) = build_example(&path, solver);
            assert_eq!(
                again.expect("builds again").house.to_json_string(),
                json,
                "{}: not deterministic",
                path.display()
            );
            let mut house_sources = SourceMap::new();
            let house = house_sources.add("house.json", json);
            // The assets holoc made are known by their boxes, as `holoc validate` knows them
            // from the folder beside the house.
            let made = holoc::make::used_in(
                &built.resolved,
                built.objects.iter().map(|o| o.asset_id.as_str()),
            );
            let catalog = Catalog::embedded().with_made(holoc::make::catalog_assets(&made));
            let validated = holoc::lower::validate::validate(
                &house_sources,
                house,
                StructureCatalog::builtin(),
                &catalog,
            );
            // No errors and no warnings: every floor object stays in its room and no two
            // overlap, doors to the outside face in, nothing is sunk or off its receptacle, the
            // agent starts on free floor, judged by `holoc validate` from the house file alone.
            let errors: Vec<_> = validated.diagnostics.clone();
            assert!(
                errors.is_empty(),
                "{}: validate rejects the house:\n{}",
                path.display(),
                common::render(&house_sources, &errors)
            );
            // Every floor object is in its room and no two footprints overlap.
            for solved in &built.layout.rooms {
                let floor = &solved.layout.floor;
                for (i, a) in floor.iter().enumerate() {
                    for b in &floor[i + 1..] {
                        let (fa, fb) = (a.footprint, b.footprint);
                        let overlap_x = fa.max_x.min(fb.max_x) - fa.min_x.max(fb.min_x);
                        let overlap_z = fa.max_z.min(fb.max_z) - fa.min_z.max(fb.min_z);
                        assert!(
                            overlap_x <= 1e-6 || overlap_z <= 1e-6,
                            "{}: {} and {} overlap",
                            path.display(),
                            solved.problem.objects[a.index].id,
                            solved.problem.objects[b.index].id
                        );
                    }
                }
            }
        }
    }
}

#[test]
fn example_layouts() {
    insta::with_settings!({snapshot_path => "../snapshots/examples", prepend_module_to_snapshot => false, omit_expression => true}, {
        for path in examples() {
            let (sources, built, diagnostics) = build_example(&path, Solver::Dfs);
            let built = built.expect("builds");
            let name = path.file_stem().expect("file name").to_string_lossy().to_string();
            let body = format!(
                "----- DIAGNOSTICS\n{}----- LAYOUT\n{}",
                common::render(&sources, &diagnostics),
                built.layout.dump(&built.scene)
            );
            insta::assert_snapshot!(format!("layout_{name}"), body);
        }
    });
}

#[test]
fn golden_apartment_house_and_plan() {
    let (_, built, _) = build_example(Path::new("examples/apartment_1b1b.holo"), Solver::Dfs);
    let built = built.expect("builds");
    insta::with_settings!({snapshot_path => "../snapshots/examples", prepend_module_to_snapshot => false, omit_expression => true}, {
        insta::assert_snapshot!("golden_apartment_house", built.house.to_json_string());
        insta::assert_snapshot!("golden_apartment_plan_svg", holoc::render::render_svg(&holoc::render::drawing(&built)));
    });
}

/// The plan's labels are the scene's names (issue 33): the apartment's two dining chairs are
/// told apart by their instance number, the other things are not numbered, no label is an
/// identifier, the books on the coffee table get one label with their count, and the double
/// door to the outside is drawn double.
#[test]
fn plan_labels_are_names() {
    let (_, built, _) = build_example(Path::new("examples/apartment_1b1b.holo"), Solver::Dfs);
    let built = built.expect("builds");
    let drawing = holoc::render::drawing(&built);
    let label = |name: &str| {
        drawing.objects.iter().find(|o| o.name == name).map(|o| o.label.clone()).expect(name)
    };
    assert_eq!(label("dining_chair-0"), "dining chair 0");
    assert_eq!(label("dining_chair-1"), "dining chair 1");
    assert_eq!(label("coffee_table-0"), "coffee table");
    assert_eq!(label("sofa-0"), "sofa");
    let svg = holoc::render::render_svg(&drawing);
    let group = svg.split("id=\"object-labels\"").nth(1).expect("labels");
    let group = group.split("</g>").next().expect("their group");
    let labels: Vec<&str> = group
        .split("</text>")
        .filter_map(|t| t.rsplit('>').next())
        .map(str::trim)
        .filter(|t| !t.is_empty())
        .collect();
    assert!(labels.contains(&"dining chair 1"), "{labels:?}");
    for o in &drawing.objects {
        assert!(!labels.contains(&o.name.as_str()), "`{}` is labelled by its id", o.name);
    }
    let books = drawing
        .objects
        .iter()
        .filter(|o| o.label == "book" && o.on.as_deref() == Some("coffee_table-0"))
        .count();
    assert!(books >= 2, "the coffee table holds books");
    let counted = format!("book ×{books}");
    assert_eq!(labels.iter().filter(|l| **l == counted).count(), 1, "{labels:?}");
    let exterior = drawing.doors.iter().filter(|d| d.double).count();
    assert_eq!(exterior, 1, "the door to the outside is double");
}

/// The plan draws exactly the house: one footprint per object of the house, with its name at
/// its position, and nothing else; what the scene asked for and the house lacks is listed as
/// left out.
#[test]
fn every_plan_draws_exactly_the_house() {
    for path in examples() {
        let (_, built, _) = build_example(&path, Solver::Dfs);
        let built = built.expect("every example builds");
        let drawing = holoc::render::drawing(&built);
        let round = |v: f64| (v * 1000.0).round() as i64;
        let mut drawn: Vec<(String, i64, i64)> = drawing
            .objects
            .iter()
            .map(|o| (o.name.clone(), round(o.center[0]), round(o.center[1])))
            .collect();
        let mut house: Vec<(String, i64, i64)> = built
            .house
            .all_objects()
            .iter()
            .map(|o| (o.object_name.clone(), round(o.position.x), round(o.position.z)))
            .collect();
        drawn.sort();
        house.sort();
        assert_eq!(drawn, house, "{}: the plan's objects differ from the house's", path.display());
        let svg = holoc::render::render_svg(&drawing);
        assert_eq!(
            svg.matches("class=\"object\"").count(),
            built.house.object_count(),
            "{}: the SVG draws another number of objects than the house holds",
            path.display()
        );
        let summary = holoc::report::Summary::of(&built);
        assert_eq!(
            drawing.left_out.len(),
            summary.left_out(),
            "{}: the plan lists {:?} as left out, the build summary counts {}",
            path.display(),
            drawing.left_out.iter().map(|l| &l.name).collect::<Vec<_>>(),
            summary.left_out()
        );
        for needle in ["id=\"legend\"", "id=\"scale-bar\"", "id=\"north-arrow\"", " m²"] {
            assert!(svg.contains(needle), "{}: the plan lacks {needle}", path.display());
        }
    }
}

/// What an example's leading comment says about its build, checked: `// builds: <summary>`
/// (the closing line of `holoc build` without its time), `// claim: NAME left out`,
/// `// claim: NAME placed` and `// claim: NAME against the DIRECTION wall`.
#[test]
fn example_comments_say_what_the_build_does() {
    for path in examples() {
        let text = std::fs::read_to_string(&path).expect("readable");
        let (_, built, _) = build_example(&path, Solver::Dfs);
        let built = built.expect("every example builds");
        let drawing = holoc::render::drawing(&built);
        let mut builds_line = false;
        for line in text.lines().take_while(|l| l.trim_start().starts_with("//")) {
            let line = line.trim_start().trim_start_matches("//").trim();
            if let Some(summary) = line.strip_prefix("builds:") {
                builds_line = true;
                let actual = holoc::report::Summary::of(&built).to_string();
                assert_eq!(
                    summary.trim(),
                    actual,
                    "{}: `// builds:` is not what it builds",
                    path.display()
                );
                continue;
            }
            let Some(claim) = line.strip_prefix("claim:") else { continue };
            let words: Vec<&str> = claim.split_whitespace().collect();
            let name = words.first().copied().unwrap_or_default();
            let drawn = drawing.objects.iter().find(|o| o.name == name);
            match &words[1..] {
                ["left", "out"] => assert!(
                    drawn.is_none() && drawing.left_out.iter().any(|l| l.name == name),
                    "{}: claims {name} is left out",
                    path.display()
                ),
                ["placed"] => {
                    assert!(drawn.is_some(), "{}: claims {name} is placed", path.display());
                }
                ["against", "the", dir, "wall"] => {
                    let o =
                        drawn.unwrap_or_else(|| panic!("{}: {name} is not placed", path.display()));
                    let turned = (o.facing_deg / 90.0).round() as i64 % 2 != 0;
                    let (w, d) =
                        if turned { (o.size[1], o.size[0]) } else { (o.size[0], o.size[1]) };
                    let room = drawing
                        .rooms
                        .iter()
                        .find(|r| holoc::geometry::point_in_or_on_polygon(o.center, &r.polygon))
                        .expect("the object stands in a room");
                    let xs = room.polygon.iter().map(|p| p[0]);
                    let zs = room.polygon.iter().map(|p| p[1]);
                    let gap = match *dir {
                        "north" => zs.fold(f64::NEG_INFINITY, f64::max) - (o.center[1] + d / 2.0),
                        "south" => (o.center[1] - d / 2.0) - zs.fold(f64::INFINITY, f64::min),
                        "east" => xs.fold(f64::NEG_INFINITY, f64::max) - (o.center[0] + w / 2.0),
                        "west" => (o.center[0] - w / 2.0) - xs.fold(f64::INFINITY, f64::min),
                        other => panic!("{}: unknown direction {other}", path.display()),
                    };
                    assert!(
                        gap.abs() < 0.05,
                        "{}: claims {name} stands against the {dir} wall; it is {gap:.2} m from it",
                        path.display()
                    );
                }
                _ => panic!("{}: unreadable claim `{claim}`", path.display()),
            }
        }
        assert!(builds_line, "{}: the leading comment has no `// builds:` line", path.display());
    }
}

/// The examples' houses have every field a ProcTHOR house has, kind by kind (rooms, walls,
/// doors, windows, objects, their children, the procedural parameters, lights, metadata, the
/// agent), with the same JSON types, so that ProcTHOR-based code reads them. Reads the ProcTHOR
/// houses of `../shared/data/real-scenes` (schema 1.0.0); skipped with a message when absent.
/// Only the optional state flags of objects (`isDirty`, `openness`, `isOn`) and `children` (on
/// objects with nothing on them) may be missing.
#[test]
fn example_houses_have_the_fields_of_procthor_houses() {
    use serde_json::Value;
    use std::collections::{BTreeMap, BTreeSet};
    let Some(dir) =
        common::shared("data/real-scenes", "example_houses_have_the_fields_of_procthor_houses")
    else {
        return;
    };
    let kind_of = |v: &Value| match v {
        Value::Null => "null",
        Value::Bool(_) => "bool",
        Value::Number(_) => "number",
        Value::String(_) => "string",
        Value::Array(_) => "array",
        Value::Object(_) => "object",
    };
    // kind → key → JSON types seen.
    let fields = |house: &Value| {
        let mut out: BTreeMap<&'static str, BTreeMap<String, BTreeSet<&'static str>>> =
            BTreeMap::new();
        let objects = house["objects"].as_array().cloned().unwrap_or_default();
        let children: Vec<Value> = objects
            .iter()
            .flat_map(|o| o["children"].as_array().cloned().unwrap_or_default())
            .collect();
        let one = |v: &Value| vec![v.clone()];
        let list = |v: &Value| v.as_array().cloned().unwrap_or_default();
        for (kind, items) in [
            ("house", one(house)),
            ("rooms", list(&house["rooms"])),
            ("walls", list(&house["walls"])),
            ("doors", list(&house["doors"])),
            ("windows", list(&house["windows"])),
            ("objects", objects.clone()),
            ("children", children),
            ("proceduralParameters", one(&house["proceduralParameters"])),
            ("lights", list(&house["proceduralParameters"]["lights"])),
            ("metadata", one(&house["metadata"])),
            ("agent", one(&house["metadata"]["agent"])),
        ] {
            for item in items {
                for (k, v) in item.as_object().into_iter().flatten() {
                    out.entry(kind).or_default().entry(k.clone()).or_default().insert(kind_of(v));
                }
            }
        }
        out
    };
    // As in ProcTHOR, `children` is written only on objects that have some.
    let optional = ["isDirty", "openness", "isOn", "children"];
    let mut procthor = Vec::new();
    for entry in std::fs::read_dir(&dir).expect("folder").flatten() {
        let name = entry.file_name().to_string_lossy().to_string();
        if !name.starts_with("procthor-") {
            continue;
        }
        let house: Value =
            serde_json::from_str(&std::fs::read_to_string(entry.path()).expect("readable"))
                .expect("json");
        if house["metadata"]["schema"] == "1.0.0" {
            procthor.push((name, fields(&house)));
        }
    }
    assert!(!procthor.is_empty(), "no ProcTHOR house of schema 1.0.0 in {}", dir.display());
    for path in examples() {
        let (_, built, _) = build_example(&path, Solver::Dfs);
        let house: Value =
            serde_json::from_str(&built.expect("builds").house.to_json_string()).expect("json");
        let ours = fields(&house);
        for (name, theirs) in &procthor {
            for (kind, keys) in theirs {
                let Some(mine) = ours.get(kind) else {
                    // The example has no such thing (e.g. no windows, nothing on a receptacle).
                    continue;
                };
                for (key, types) in keys {
                    if optional.contains(&key.as_str()) && !mine.contains_key(key) {
                        continue;
                    }
                    let got = mine.get(key).unwrap_or_else(|| {
                        panic!("{}: {kind} lack `{key}`, which {name} has", path.display())
                    });
                    assert!(
                        got.is_subset(types) || types.contains("null"),
                        "{}: {kind}.{key} is {got:?} here, {types:?} in {name}",
                        path.display()
                    );
                }
            }
        }
    }
}

/// The floor objects of a build by instance name: pose and footprint.
fn floor_poses(
    built: &Built,
) -> std::collections::BTreeMap<String, (holoc::solve::Pose, holoc::solve::Rect)> {
    let mut out = std::collections::BTreeMap::new();
    for room in &built.layout.rooms {
        for p in &room.layout.floor {
            out.insert(room.problem.objects[p.index].id.clone(), (p.pose, p.footprint));
        }
    }
    out
}

/// What people mean, in the examples (the layout issue's "done when"): the apartment's coffee
/// table stands at a usable distance before the sofa and the painting above the sofa hangs on
/// the sofa's wall, over it; every classroom chair is at its desk, facing it.
#[test]
fn examples_layouts_mean_what_people_mean() {
    use holoc::solve::constraints::faces;
    let (_, built, _) = build_example(Path::new("examples/apartment_1b1b.holo"), Solver::Dfs);
    let built = built.expect("the apartment builds");
    let floor = floor_poses(&built);
    let (_, sofa) = floor["sofa-0"];
    let (_, table) = floor["coffee_table-0"];
    let gap = sofa.gap(&table);
    assert!((0.3 - 1e-6..=0.6 + 1e-6).contains(&gap), "coffee table {gap} m from the sofa");
    let house: serde_json::Value =
        serde_json::from_str(&built.house.to_json_string()).expect("json");
    let painting = house["objects"]
        .as_array()
        .expect("objects")
        .iter()
        .find(|o| o["id"].as_str().is_some_and(|id| id.starts_with("painting-0")))
        .expect("the painting is in the house");
    let px = painting["position"]["x"].as_f64().expect("x");
    let pz = painting["position"]["z"].as_f64().expect("z");
    // Over the sofa: its centre within the sofa's extent along their wall (as near the sofa's
    // middle as the wall's windows let it hang).
    let over = (sofa.min_x - 1e-6..=sofa.max_x + 1e-6).contains(&px)
        && (sofa.min_z - 1e-6..=sofa.max_z + 1e-6).contains(&pz);
    let along_x = (px - sofa.min_x).abs().min((px - sofa.max_x).abs()) > 0.1;
    assert!(
        over || (along_x && (sofa.min_x..=sofa.max_x).contains(&px))
            || (!along_x && (sofa.min_z..=sofa.max_z).contains(&pz)),
        "painting at ({px}, {pz}) is not over the sofa {sofa:?}"
    );
    let wall_dist = (px - sofa.min_x)
        .abs()
        .min((px - sofa.max_x).abs())
        .min((pz - sofa.min_z).abs())
        .min((pz - sofa.max_z).abs());
    assert!(wall_dist < 0.1, "the painting hangs on the sofa's wall (off by {wall_dist} m)");

    let (_, built, _) = build_example(Path::new("examples/classroom.holo"), Solver::Dfs);
    let built = built.expect("the classroom builds");
    let floor = floor_poses(&built);
    for i in 0..12 {
        let (chair_pose, chair) = floor[&format!("student_chair-{i}")];
        let (_, desk) = floor[&format!("student_desk-{i}")];
        assert!(
            chair.gap(&desk) <= 0.6 + 1e-6,
            "chair {i} is {} m from its desk",
            chair.gap(&desk)
        );
        assert!(faces(&chair_pose, &desk), "chair {i} does not face its desk");
    }
}

/// The scenes whose builds are checked for accounting: the examples and every corpus scene
/// that builds.
fn accounted_scenes() -> Vec<PathBuf> {
    let mut out = examples();
    for dir in
        ["tests/corpus/check", "tests/corpus/plan", "tests/corpus/parse", "tests/corpus/repair"]
    {
        let Ok(entries) = std::fs::read_dir(dir) else { continue };
        let mut found: Vec<PathBuf> = entries
            .flatten()
            .map(|e| e.path())
            .filter(|p| p.extension().is_some_and(|e| e == "holo"))
            .collect();
        found.sort();
        out.extend(found);
    }
    out
}

/// An object's id without its room: `sofa-0 (living room)` → `sofa-0`.
fn without_room(id: &str) -> String {
    match id.rfind(" (") {
        Some(i) if id.ends_with(')') => id[..i].to_string(),
        _ => id.to_string(),
    }
}

/// Every object a scene asks for — floor, wall and ceiling objects and every copy of every
/// thing on top, on floor and wall objects alike — is in the house or in its room's list of
/// objects left out with a reason and a code, object by object, and the build's last line
/// counts the same: asked = placed + left out. Over every example and every corpus scene that
/// builds, with both solvers.
#[test]
fn every_object_asked_is_placed_or_reported() {
    use std::collections::BTreeMap;
    let mut checked = 0;
    for path in accounted_scenes() {
        for solver in [Solver::Dfs, Solver::Milp] {
            let (_, built, _) = build_example(&path, solver);
            let Some(built) = built else { continue };
            checked += 1;
            // What the scene asks for, per room, by id.
            let mut asked: BTreeMap<(String, String), usize> = BTreeMap::new();
            for room in &built.scene.rooms {
                let label = built.plan.room(room.id).thor_id.clone();
                for &id in &room.objects {
                    let o = built.scene.object(id);
                    *asked.entry((label.clone(), o.name.clone())).or_default() += 1;
                    let mut next: BTreeMap<&str, u32> = BTreeMap::new();
                    for item in &o.on_top {
                        for _ in 0..item.count {
                            let n = next.entry(item.item.as_str()).or_insert(0);
                            let key = format!("{}-{n}|{}", item.item, o.name);
                            *asked.entry((label.clone(), key)).or_default() += 1;
                            *n += 1;
                        }
                    }
                }
                if room.ceiling.is_some() && !built.resolved.ceiling_lights.contains_key(&room.id) {
                    *asked.entry((label.clone(), "ceiling".to_string())).or_default() += 1;
                }
            }
            // What the house holds and what the report lists as left out.
            // Things moved to another receptacle (W0506) are named by where they are: back to
            // the names they were asked by.
            let mut moved: BTreeMap<(String, String), String> = BTreeMap::new();
            for solved in &built.layout.rooms {
                let label = built.plan.room(solved.room).thor_id.clone();
                let p = &solved.problem;
                for m in &solved.layout.moved {
                    let (i, to) = (m.small, m.to);
                    let asked_as = p.small_objects[i].id.clone();
                    let item = asked_as.split('|').next().unwrap_or_default().to_string();
                    let holder = match to {
                        holoc::solve::Holder::Floor(j) => p.objects[j].id.clone(),
                        holoc::solve::Holder::Wall(j) => p.wall_objects[j].id.clone(),
                    };
                    moved.insert((label.clone(), format!("{item}|{holder}")), asked_as);
                }
            }
            let mut got: BTreeMap<(String, String), usize> = BTreeMap::new();
            for o in built.house.all_objects() {
                let key = (o.room_id.clone(), without_room(&o.id));
                let key = match moved.get(&key) {
                    Some(asked_as) => (key.0, asked_as.clone()),
                    None => key,
                };
                *got.entry(key).or_default() += 1;
            }
            let mut reported = 0;
            for solved in &built.layout.rooms {
                let label = built.plan.room(solved.room).thor_id.clone();
                for u in &solved.layout.unplaced {
                    assert!(!u.reason.is_empty(), "{}: {} has no reason", path.display(), u.id);
                    *got.entry((label.clone(), without_room(&u.id))).or_default() += 1;
                    reported += 1;
                }
            }
            assert_eq!(
                got,
                asked,
                "{} ({}): the house and the objects left out are not what the scene asks for",
                path.display(),
                solver.as_str()
            );
            let summary = holoc::report::Summary::of(&built);
            assert_eq!(
                summary.asked,
                summary.placed + reported,
                "{} ({}): the build line's counts",
                path.display(),
                solver.as_str()
            );
        }
    }
    assert!(checked >= 12, "only {checked} builds were checked");
}

/// The classroom built with other seeds: the look-ahead counts the rows behind the first row
/// and their chairs (a chain of `behind`), so the rows keep their relations at every seed.
/// Over seeds 1 to 10 the build kept 960 of 980 relations before the chain was looked at, 967
/// after, 972 since the way behind a chair is as wide as the reachability grid needs (the
/// agent and one cell), 973 since a pass of discrepancy tries the teacher's desk's other poses
/// first, and all 980 since a student desk's pull-out space is behind it, where its chair is,
/// and no longer keeps the row behind 0.75 m further back (at some seeds the three rows did not
/// fit along the 7 m wall).
#[test]
fn the_classroom_keeps_its_rows_with_other_seeds() {
    let path = Path::new("examples/classroom.holo");
    let mut sources = SourceMap::new();
    let id =
        sources.add(path.display().to_string(), std::fs::read_to_string(path).expect("readable"));
    let catalog = Catalog::embedded();
    let (mut kept_all, mut total_all) = (0, 0);
    for seed in 1..=10 {
        let options = BuildOptions { seed: Some(seed), ..BuildOptions::new(&catalog) };
        let built = build(&sources, id, &options).value.expect("the classroom builds");
        for solved in &built.layout.rooms {
            // Every floor object stands (the blackboard and the clock find no wall asset).
            let floor_left: Vec<_> =
                solved.layout.unplaced.iter().filter(|u| u.kind == "floor").collect();
            assert!(floor_left.is_empty(), "seed {seed}: {floor_left:?}");
            let (kept, total) = solved.layout.constraint_tally(&solved.problem);
            kept_all += kept;
            total_all += total;
        }
    }
    assert_eq!(total_all, 980);
    assert_eq!(kept_all, 980, "relations kept over seeds 1 to 10");
}

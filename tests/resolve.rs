//! Tests of the resolve stage: ranked candidates for a corpus of descriptions, catalog loading
//! in both formats (with broken entries), resolution of whole scenes, and determinism.
//!
//! Everything read here is in the repository (`tests/`, `examples/`); nothing outside it.

mod common;

use holoc::check::Scene;
use holoc::diag::format::{render_human, HumanOptions};
use holoc::diag::Diagnostic;
use holoc::resolve::{self, Catalog, PlacementKind, Query};
use holoc::source::SourceMap;
use std::fmt::Write as _;
use std::path::Path;

fn settings() -> insta::Settings {
    let mut s = insta::Settings::clone_current();
    s.set_snapshot_path("../snapshots/resolve");
    s.set_prepend_module_to_snapshot(false);
    s
}

fn stem(path: &Path) -> String {
    path.file_stem().map(|s| s.to_string_lossy().into_owned()).unwrap_or_default()
}

fn parse_size(text: &str) -> Option<[f64; 3]> {
    let t = text.trim().strip_suffix("cm")?;
    let v: Vec<f64> = t.split('x').filter_map(|p| p.trim().parse().ok()).collect();
    (v.len() == 3).then(|| [v[0] / 100.0, v[1] / 100.0, v[2] / 100.0])
}

/// One snapshot per corpus file: for each description, the verdict and the top three
/// candidates with the parts of their scores.
#[test]
fn ranked_candidates_for_descriptions() {
    let catalog = Catalog::embedded();
    insta::glob!("corpus/resolve/queries/*.txt", |path| {
        let text = std::fs::read_to_string(path).expect("corpus file is readable");
        let mut out = String::new();
        for line in text.lines().filter(|l| !l.trim().is_empty() && !l.starts_with('#')) {
            let f: Vec<&str> = line.split('|').map(str::trim).collect();
            assert!(f.len() >= 3, "bad corpus line {line:?}");
            let kind = PlacementKind::parse(f[0]).expect("a placement kind");
            let query = Query {
                category: f[1].to_string(),
                description: Some(f[2].to_string()).filter(|d| !d.is_empty()),
                size_m: f.get(3).and_then(|s| parse_size(s)),
                kind: Some(kind),
            };
            let ranked = resolve::rank(&catalog, &query, 0);
            let verdict = match ranked.iter().find(|c| c.is_good_enough()) {
                Some(c) => format!("resolved → {}", c.asset_id),
                None => "W0401 no good match".to_string(),
            };
            let _ = writeln!(out, "{line}\n  {verdict}");
            for c in ranked.iter().take(3) {
                let _ = writeln!(
                    out,
                    "    {:<28} {:<14} score {:>7.3}  rel {:.3} head {} text {:.3} size {}",
                    c.asset_id,
                    c.object_type,
                    c.score,
                    c.relevance,
                    if c.head_match { "yes" } else { "no " },
                    c.text,
                    c.size_diff_m.map_or_else(|| "-".to_string(), |d| format!("{d:.3} m")),
                );
            }
        }
        settings().bind(|| insta::assert_snapshot!(format!("queries__{}", stem(path)), out));
    });
}

fn render(sources: &SourceMap, diagnostics: &[Diagnostic]) -> String {
    let mut sorted = diagnostics.to_vec();
    holoc::diag::sort(&mut sorted);
    render_human(sources, &sorted, HumanOptions { color: false, width: 80 })
}

fn loaded_assets(catalog: &Catalog) -> String {
    let mut out = String::new();
    for s in catalog.sources() {
        let _ = writeln!(
            out,
            "source {} version {:?} assets {} path {:?}",
            s.name, s.version, s.n_assets, s.path
        );
    }
    for a in catalog.assets().iter().filter(|a| a.source > 0) {
        let _ = writeln!(
            out,
            "{} type={} category={:?} bbox={:.3}×{:.3}×{:.3} kinds={} receptacle={}",
            a.id,
            a.object_type,
            a.category,
            a.bbox_m[0],
            a.bbox_m[1],
            a.bbox_m[2],
            a.placements.letters(),
            a.receptacle
        );
    }
    out
}

#[test]
fn loads_both_catalog_formats_with_broken_entries() {
    let mut sources = SourceMap::new();
    let outcome = Catalog::load(
        &[
            "tests/catalog/procthor_small.json",
            "tests/catalog/objathor_small.json",
            "tests/catalog/not_json.json",
            "tests/catalog/missing.json",
        ],
        &mut sources,
    );
    let text = format!(
        "----- DIAGNOSTICS\n{}----- OUTPUT\n{}",
        render(&sources, &outcome.diagnostics),
        loaded_assets(&outcome.value)
    );
    let codes: Vec<&str> = outcome.diagnostics.iter().map(|d| d.code.as_str()).collect();
    assert_eq!(codes.iter().filter(|c| **c == "W0402").count(), 8, "{codes:?}");
    assert_eq!(codes.iter().filter(|c| **c == "E0403").count(), 2, "{codes:?}");
    assert!(outcome.value.get("Test_Grand_Piano").is_some());
    assert!(outcome.value.get("Sofa_201_1").is_some(), "the embedded catalog stays");
    settings().bind(|| insta::assert_snapshot!("catalog_loading", text));
}

#[test]
fn gzip_catalogs_load_like_plain_ones() {
    use std::io::Write as _;
    let plain = std::fs::read("tests/catalog/objathor_small.json").expect("fixture");
    let dir = tempfile::tempdir().expect("a temporary folder");
    let gz_path = dir.path().join("annotations.json.gz");
    let mut enc = flate2::write::GzEncoder::new(Vec::new(), flate2::Compression::default());
    enc.write_all(&plain).expect("compress");
    std::fs::write(&gz_path, enc.finish().expect("compress")).expect("write");

    let mut s1 = SourceMap::new();
    let a = Catalog::load(&["tests/catalog/objathor_small.json"], &mut s1);
    let mut s2 = SourceMap::new();
    let b = Catalog::load(&[gz_path.as_path()], &mut s2);
    let ids = |c: &Catalog| c.assets().iter().map(|a| a.id.clone()).collect::<Vec<_>>();
    assert_eq!(ids(&a.value), ids(&b.value));
    assert_eq!(a.diagnostics.len(), b.diagnostics.len());
    assert_eq!(b.value.sources()[1].name, "annotations");
    // The lock hashes the bytes of the file as given (compressed here).
    assert_ne!(a.value.sources()[1].sha256, b.value.sources()[1].sha256);
}

#[test]
fn later_catalogs_win() {
    let dir = tempfile::tempdir().expect("a temporary folder");
    let path = dir.path().join("override.json");
    std::fs::write(
        &path,
        r#"{"Sofa_201_1": {"annotations": {"category": "sofa", "onFloor": true},
            "assetMetadata": {"boundingBox": {"x": 3.0, "y": 1.0, "z": 1.0}}}}"#,
    )
    .expect("write");
    let mut sources = SourceMap::new();
    let c = Catalog::load(&[path.as_path()], &mut sources);
    assert!(c.diagnostics.is_empty());
    let sofa = c.value.get("Sofa_201_1").expect("still there");
    assert_eq!(sofa.bbox_m, [3.0, 1.0, 1.0]);
    assert_eq!(c.value.source_of(sofa).name, "override");
}

fn scene_of(sources: &mut SourceMap, path: &Path) -> (Option<Scene>, Vec<Diagnostic>) {
    let text = std::fs::read_to_string(path).expect("readable");
    let name = path.strip_prefix(env!("CARGO_MANIFEST_DIR")).unwrap_or(path);
    let id = sources.add(name.display().to_string(), text);
    let out = holoc::compile::check_file(sources, id);
    (out.value, out.diagnostics)
}

fn expected_codes(path: &Path) -> Option<Vec<String>> {
    let text = std::fs::read_to_string(path).ok()?;
    let line = text.lines().next()?.strip_prefix("// expect:")?;
    Some(line.split(',').map(|c| c.trim().to_string()).filter(|c| !c.is_empty()).collect())
}

fn check_scene(path: &Path, catalog: &Catalog) -> String {
    let mut sources = SourceMap::new();
    let (scene, mut diagnostics) = scene_of(&mut sources, path);
    let scene = scene.expect("the fixture checks");
    assert!(!diagnostics.iter().any(Diagnostic::is_error), "{diagnostics:?}");
    let outcome = resolve::resolve(&scene, catalog, scene.seed);
    if let Some(expected) = expected_codes(path) {
        let mut got: Vec<String> =
            outcome.diagnostics.iter().map(|d| d.code.as_str().to_string()).collect();
        got.sort();
        let mut expected = expected;
        expected.sort();
        assert_eq!(got, expected, "{}", path.display());
    }
    diagnostics.extend(outcome.diagnostics.iter().cloned());
    format!(
        "----- SOURCE  {}\n----- DIAGNOSTICS\n{}----- OUTPUT\n{}",
        path.file_name().map(|f| f.to_string_lossy().into_owned()).unwrap_or_default(),
        render(&sources, &diagnostics),
        outcome.value.dump(&scene, catalog)
    )
}

#[test]
fn resolves_scene_fixtures() {
    let catalog = Catalog::embedded();
    insta::glob!("corpus/resolve/scenes/*.holo", |path| {
        let text = check_scene(path, &catalog);
        settings().bind(|| insta::assert_snapshot!(format!("scene__{}", stem(path)), text));
    });
}

#[test]
fn resolves_every_example() {
    let catalog = Catalog::embedded();
    insta::glob!("../examples", "*.holo", |path| {
        let text = check_scene(path, &catalog);
        settings().bind(|| insta::assert_snapshot!(format!("example__{}", stem(path)), text));
    });
}

#[test]
fn user_catalog_fills_the_gaps() {
    let mut sources = SourceMap::new();
    let catalog = Catalog::load(&["tests/catalog/objathor_small.json"], &mut sources).value;
    let path = Path::new("tests/corpus/resolve/scenes/no_match.holo");
    let (scene, _) = scene_of(&mut sources, path);
    let scene = scene.expect("checks");
    let outcome = resolve::resolve(&scene, &catalog, scene.seed);
    assert!(outcome.diagnostics.is_empty(), "{:?}", outcome.diagnostics);
    let report = resolve::report(&scene, &catalog, &outcome.value, &|_| serde_json::Map::new());
    let text = serde_json::to_string_pretty(&report).expect("json");
    settings().bind(|| insta::assert_snapshot!("report__no_match_with_user_catalog", text));
}

#[test]
fn same_input_and_seed_give_identical_results() {
    let catalog = Catalog::embedded();
    for path in
        ["examples/apartment_1b1b.holo", "tests/corpus/resolve/scenes/varied_and_reuse.holo"]
    {
        let mut sources = SourceMap::new();
        let (scene, _) = scene_of(&mut sources, Path::new(path));
        let scene = scene.expect("checks");
        let a = resolve::resolve(&scene, &catalog, 11);
        let b = resolve::resolve(&scene, &catalog, 11);
        assert_eq!(a.value, b.value);
        let ra = serde_json::to_string(&resolve::report(&scene, &catalog, &a.value, &|_| {
            serde_json::Map::new()
        }))
        .expect("json");
        let rb = serde_json::to_string(&resolve::report(&scene, &catalog, &b.value, &|_| {
            serde_json::Map::new()
        }))
        .expect("json");
        assert_eq!(ra, rb);
        // Another seed still resolves everything the first did.
        let c = resolve::resolve(&scene, &catalog, 12);
        let chosen =
            |r: &resolve::Resolved| r.objects.iter().filter(|o| o.choice().is_some()).count();
        assert_eq!(chosen(&a.value), chosen(&c.value));
    }
}

#[test]
fn varied_groups_get_different_assets_and_rooms_avoid_reuse() {
    let catalog = Catalog::embedded();
    let mut sources = SourceMap::new();
    let (scene, _) =
        scene_of(&mut sources, Path::new("tests/corpus/resolve/scenes/varied_and_reuse.holo"));
    let scene = scene.expect("checks");
    let res = resolve::resolve(&scene, &catalog, scene.seed).value;
    let asset_of = |name: &str| {
        let obj = scene.objects.iter().find(|o| o.name == name).expect("object exists");
        res.object(obj.id).expect("resolved").asset_id.clone()
    };
    let chairs: std::collections::BTreeSet<String> =
        (0..4).map(|i| asset_of(&format!("chair-{i}"))).collect();
    assert_eq!(chairs.len(), 4, "varied chairs differ");
    assert_eq!(asset_of("stool-0"), asset_of("stool-1"), "same stools share");
    let sofas: Vec<_> = scene.objects.iter().filter(|o| o.group == "sofa").map(|o| o.id).collect();
    assert_eq!(sofas.len(), 2);
    assert_ne!(
        res.object(sofas[0]).expect("resolved").asset_id,
        res.object(sofas[1]).expect("resolved").asset_id,
        "the den's sofa avoids the living room's"
    );
}

#[test]
fn search_ranks_by_words_and_size() {
    let catalog = Catalog::embedded();
    let list = resolve::search(
        &catalog,
        "light grey sectional sofa",
        Some([2.0, 1.0, 0.8]),
        Some(PlacementKind::Floor),
    );
    assert!(!list.is_empty());
    assert_eq!(list[0].object_type, "Sofa");
    assert!(list.windows(2).all(|w| w[0].score >= w[1].score));
    let wall = resolve::search(&catalog, "painting", None, Some(PlacementKind::Wall));
    assert!(wall.iter().all(|c| c.object_type == "Painting"));
    assert!(resolve::search(&catalog, "", None, None).is_empty());
}

/// The `.holo` example of each resolve diagnostic page produces that code and no other.
#[test]
fn diagnostic_page_examples_produce_their_code() {
    let catalog = Catalog::embedded();
    for code in ["E0401", "E0402", "W0401"] {
        let page = std::fs::read_to_string(format!("book/src/diagnostics/{code}.md"))
            .expect("the page exists");
        let example = page
            .split("```holo\n")
            .nth(1)
            .and_then(|rest| rest.split("```").next())
            .expect("the page has a holo example");
        let mut sources = SourceMap::new();
        let id = sources.add(format!("{code}.holo"), example.to_string());
        let checked = holoc::compile::check_file(&sources, id);
        assert!(!checked.has_errors(), "{code}: {:?}", checked.diagnostics);
        let scene = checked.value.expect("a scene");
        let outcome = resolve::resolve(&scene, &catalog, scene.seed);
        let codes: Vec<&str> = checked
            .diagnostics
            .iter()
            .chain(&outcome.diagnostics)
            .map(|d| d.code.as_str())
            .collect();
        assert_eq!(codes, vec![code], "{code}");
    }
}

/// The asset cases of the shared reference data (`../shared/data/asset-cases.json`: object
/// descriptions as models write them, each with the AI2-THOR types a careful person accepts),
/// through the path a build takes (object name + `describe`): prints the table of right types,
/// objects left out and wrong fills by placement kind, and holds the figures reached so far.
/// Skipped with a message when the shared data is absent.
#[test]
#[allow(clippy::print_stdout, reason = "the test prints its table")]
fn asset_cases_table() {
    use serde_json::Value;
    use std::fmt::Write as _;
    let Some(dir) = common::shared("data", "asset_cases_table") else { return };
    let cases: Vec<Value> = serde_json::from_str(
        &std::fs::read_to_string(dir.join("asset-cases.json")).expect("cases"),
    )
    .expect("json");
    let quote = |s: &str| s.replace(['"', '\\'], " ");
    // One scene: each floor and wall case an object of one room, on-object cases on one host,
    // each ceiling case its own room.
    let mut holo = String::from("scene \"cases\" { seed 1 }\n\nroom cases \"cases\" {\n  corners in m (0, 0) (0, 40) (40, 40) (40, 0)\n  object host \"table\" {\n    middle\n");
    let mut on_top = Vec::new();
    for (i, c) in cases.iter().enumerate() {
        if c["kind"] == "on-object" {
            let _ = writeln!(
                holo,
                "    on top \"{}\" x1 same",
                quote(c["text"].as_str().unwrap_or("thing"))
            );
            on_top.push(i);
        }
    }
    holo.push_str("  }\n");
    for (i, c) in cases.iter().enumerate() {
        let name = quote(c["name"].as_str().unwrap_or("thing"));
        let text = quote(c["text"].as_str().unwrap_or(""));
        let size = c["size_cm"].as_array().filter(|s| s.len() == 3).map(|s| {
            let v: Vec<f64> = s.iter().map(|x| x.as_f64().unwrap_or(50.0).max(1.0)).collect();
            format!("    size {} cm x {} cm x {} cm\n", v[0], v[1], v[2])
        });
        match c["kind"].as_str() {
            Some("floor") => {
                let _ = write!(
                    holo,
                    "  object c{i} \"{name}\" {{\n    describe \"{text}\"\n{}    middle\n  }}\n",
                    size.unwrap_or_default()
                );
            }
            Some("wall") => {
                let _ = write!(
                    holo,
                    "  wall object c{i} \"{name}\" {{\n    describe \"{text}\"\n  }}\n"
                );
            }
            _ => {}
        }
    }
    holo.push_str("}\n");
    let mut ceilings = Vec::new();
    for (i, c) in cases.iter().enumerate() {
        if c["kind"] == "ceiling" {
            let x = 40 + 4 * ceilings.len();
            let _ = write!(
                holo,
                "\nroom r{i} \"r{i}\" {{\n  corners in m ({x}, 0) ({x}, 4) ({}, 4) ({}, 0)\n  ceiling \"{}\"\n}}\n",
                x + 4,
                x + 4,
                quote(c["text"].as_str().unwrap_or(""))
            );
            ceilings.push(i);
        }
    }
    let mut sources = SourceMap::new();
    let id = sources.add("cases.holo", holo);
    let scene = holoc::compile::check_file(&sources, id).value.expect("the case scene checks");
    let catalog = Catalog::embedded();
    let mut figures = Vec::new();
    for stand_ins in [false, true] {
        // The measure of catalog matching: what the catalogs give, without made assets.
        let options = resolve::ResolveOptions { stand_ins, make: false };
        let resolved = resolve::resolve_with(&scene, &catalog, scene.seed, &options).value;
        // What each case got: Some(type), None (left out), or "light" for a ceiling light.
        let mut got: Vec<Option<String>> = vec![None; cases.len()];
        for o in &scene.objects {
            if let Some(i) =
                o.name.strip_prefix('c').and_then(|n| n.split('-').next()?.parse::<usize>().ok())
            {
                got[i] = resolved.object(o.id).map(|c| c.object_type.clone());
            }
        }
        let host = scene.objects.iter().find(|o| o.name == "host-0").expect("host");
        for (k, &i) in on_top.iter().enumerate() {
            got[i] = resolved
                .small
                .get(&(host.id, k))
                .and_then(|v| v.first())
                .and_then(|r| r.choice())
                .map(|c| c.object_type.clone());
        }
        for (room, &i) in scene.rooms.iter().skip(1).zip(&ceilings) {
            got[i] = match resolved.ceilings.get(&room.id).and_then(|r| r.choice()) {
                Some(c) => Some(c.object_type.clone()),
                None if resolved.ceiling_lights.contains_key(&room.id) => Some("light".into()),
                None => None,
            };
        }
        println!("stand-ins {}", if stand_ins { "on" } else { "off" });
        println!("kind        cases  right  left out  wrong | no-match  wrong fills");
        let mut totals = [0usize; 6];
        for kind in ["floor", "wall", "on-object", "ceiling"] {
            let mut row = [0usize; 6];
            for (c, g) in cases.iter().zip(&got).filter(|(c, _)| c["kind"] == kind) {
                let types: Vec<&str> =
                    c["types"].as_array().into_iter().flatten().filter_map(Value::as_str).collect();
                if types.is_empty() {
                    row[4] += 1;
                    if g.as_deref().is_some_and(|t| t != "light") {
                        row[5] += 1;
                    }
                } else {
                    row[0] += 1;
                    match g.as_deref() {
                        Some(t) if types.contains(&t) => row[1] += 1,
                        Some("light") if types.iter().any(|t| t.contains("Light")) => row[1] += 1,
                        None => row[2] += 1,
                        Some(_) => row[3] += 1,
                    }
                }
            }
            println!(
                "{kind:<10} {:>6} {:>6} {:>9} {:>6} | {:>8} {:>12}",
                row[0], row[1], row[2], row[3], row[4], row[5]
            );
            for (t, r) in totals.iter_mut().zip(row) {
                *t += r;
            }
        }
        let pct = |a: usize, b: usize| 100.0 * a as f64 / b.max(1) as f64;
        println!(
            "all        {:>6} {:>5.1}% {:>8.1}% {:>5.1}% | {:>8} {:>11.1}%",
            totals[0],
            pct(totals[1], totals[0]),
            pct(totals[2], totals[0]),
            pct(totals[3], totals[0]),
            totals[4],
            pct(totals[5], totals[4])
        );
        if stand_ins {
            for (c, g) in cases.iter().zip(&got) {
                let types: Vec<&str> =
                    c["types"].as_array().into_iter().flatten().filter_map(Value::as_str).collect();
                let wrong = g.as_deref().is_some_and(|t| t != "light" && !types.contains(&t));
                if g.is_none() && !types.is_empty() {
                    println!(
                        "  left out: {} [{}] ({}), accepted {types:?}",
                        c["name"], c["kind"], c["text"]
                    );
                }
                if wrong {
                    println!(
                        "  wrong: {} ({}) -> {:?}, accepted {types:?}",
                        c["name"], c["text"], g
                    );
                }
            }
        }
        figures.push((
            pct(totals[1], totals[0]),
            pct(totals[2], totals[0]),
            pct(totals[5], totals[4]),
        ));
    }
    let (right, left_out, wrong_fills) = figures[1];
    // The issue's targets on the shared half, through the build path: a change that makes
    // resolution worse fails here.
    assert!(right >= 90.0, "right type fell below 90 %");
    assert!(left_out <= 5.0, "left out rose above 5 %");
    assert!(wrong_fills <= 3.0, "wrong fills rose above 3 %");
}

/// The material chosen for every floor and wall design of the original system's real scenes
/// (read from `../shared/data/real-scenes`; skipped without it), printed as the book's table
/// (`design/catalog-matching.md`): no wood, stone or tile design gets a fabric or carpet.
#[test]
#[allow(clippy::print_stdout, reason = "the test prints the book's table")]
fn real_scene_designs_get_materials_of_their_kind() {
    use holoc::resolve::structure::{StructureCatalog, Surface};
    let Some(dir) =
        common::shared("data/real-scenes", "real_scene_designs_get_materials_of_their_kind")
    else {
        return;
    };
    let catalog = StructureCatalog::builtin();
    let mut files: Vec<_> = std::fs::read_dir(&dir)
        .expect("dir")
        .filter_map(Result::ok)
        .map(|e| e.path())
        .filter(|p| p.extension().is_some_and(|e| e == "json"))
        .collect();
    files.sort();
    let mut rows = std::collections::BTreeSet::new();
    for path in files {
        let text = std::fs::read_to_string(&path).expect("read");
        let Ok(house) = serde_json::from_str::<serde_json::Value>(&text) else { continue };
        let Some(plan) = house["raw_floor_plan"].as_str() else { continue };
        for line in plan.lines() {
            let parts: Vec<&str> = line.split('|').map(str::trim).collect();
            if parts.len() < 3 {
                continue;
            }
            for (design, surface, what) in
                [(parts[1], Surface::Floor, "floor"), (parts[2], Surface::Wall, "wall")]
            {
                let chosen = catalog
                    .select_material(design, surface, &std::collections::BTreeSet::new())
                    .expect("a material");
                let lower = design.to_lowercase();
                let hard = [
                    "wood", "oak", "walnut", "parquet", "bamboo", "hardwood", "marble", "slate",
                    "concrete", "stone", "tile", "ceramic", "granite",
                ]
                .iter()
                .any(|w| lower.contains(w));
                let name = chosen.name().to_lowercase();
                if hard && !lower.contains("carpet") {
                    assert!(
                        !name.contains("carpet") && !chosen.groups().any(|g| g == "Fabric"),
                        "{design} got {}",
                        chosen.name()
                    );
                }
                let words = catalog.deciding_words(design, chosen.name());
                rows.insert(format!(
                    "| {what} | {design} | {} | {} |",
                    chosen.name(),
                    if words.is_empty() { "—".to_string() } else { words.join(", ") }
                ));
            }
        }
    }
    println!("| surface | design | material | decided by |\n|---|---|---|---|");
    for row in &rows {
        println!("{row}");
    }
    assert!(rows.len() >= 10);
}

/// Things on top fit their receptacle: the television chosen for a narrow stand is no wider
/// than the stand's asset while narrower televisions exist.
#[test]
fn things_on_top_fit_their_receptacle() {
    let text = "scene \"t\" { seed 3 }\n\nroom a \"a\" {\n  corners in m (0, 0) (0, 5) (5, 5) (5, 0)\n  object stand \"tv stand\" {\n    size 90 cm x 40 cm x 50 cm\n    edge\n    on top \"large flat screen television\" x1 same\n  }\n}\n";
    let mut sources = SourceMap::new();
    let id = sources.add("t.holo", text.to_string());
    let scene = holoc::compile::check_file(&sources, id).value.expect("checks");
    let catalog = Catalog::embedded();
    let resolved = resolve::resolve(&scene, &catalog, scene.seed).value;
    let stand = resolved.object(scene.objects[0].id).expect("a stand");
    let tv = resolved.small[&(scene.objects[0].id, 0)][0].choice().expect("a television");
    let long = |b: [f64; 3]| b[0].max(b[2]);
    assert!(
        long(tv.bbox_m) <= long(stand.bbox_m) + 1e-9,
        "a {:.2} m television on a {:.2} m stand",
        long(tv.bbox_m),
        long(stand.bbox_m)
    );
}

/// Things on top fit their receptacle's top less the margin the layout keeps round its edge
/// (`SMALL_GAP_M` on each side), so a book that the layout would refuse as too large is not
/// chosen while smaller books exist: a 0.33 m deep book is not chosen for a 0.34 m deep shelf.
#[test]
fn things_on_top_fit_inside_the_layouts_margin() {
    let margin = 2.0 * holoc::solve::SMALL_GAP_M;
    for seed in 1..=8 {
        let text = format!(
            "scene \"t\" {{ seed {seed} }}\n\nroom a \"a\" {{\n  corners in m (0, 0) (0, 5) (5, 5) (5, 0)\n  object shelf \"bookshelf\" {{\n    asset \"Shelving_Unit_313_1\"\n    edge\n    on top \"book\" x5 varied\n  }}\n}}\n"
        );
        let mut sources = SourceMap::new();
        let id = sources.add("t.holo", text);
        let scene = holoc::compile::check_file(&sources, id).value.expect("checks");
        let catalog = Catalog::embedded();
        let resolved = resolve::resolve(&scene, &catalog, scene.seed).value;
        let shelf = resolved.object(scene.objects[0].id).expect("a shelf").bbox_m;
        let sides = |b: [f64; 3]| [b[0].min(b[2]), b[0].max(b[2])];
        let top = sides(shelf).map(|s| s - margin);
        for res in &resolved.small[&(scene.objects[0].id, 0)] {
            let book = res.choice().expect("a book");
            let [short, long] = sides(book.bbox_m);
            assert!(
                short <= top[0] + 1e-9 && long <= top[1] + 1e-9,
                "seed {seed}: `{}` ({short:.3} m × {long:.3} m) on a top of {:.3} m × {:.3} m",
                book.asset_id,
                top[0],
                top[1]
            );
        }
    }
}

/// Issue 25's things on top and stand-ins, asserted one by one (the scene's snapshot shows the
/// whole resolution): a photo frame is never a wall painting on a shelf, a plant stand is never
/// a plant, a stand-in says what stood in for what, papers are never toilet paper, and the
/// items chosen for a receptacle are of types its pair table allows. These are the catalogs'
/// choices, so the scene is resolved without made assets (`tests/make.rs` has what holoc makes
/// for the frames and the curtains).
#[test]
fn things_on_top_are_the_things_people_put_there() {
    let path = Path::new("tests/corpus/resolve/scenes/things_on_top_and_stand_ins.holo");
    let mut sources = SourceMap::new();
    let (scene, _) = scene_of(&mut sources, path);
    let scene = scene.expect("checks");
    let catalog = Catalog::embedded();
    let options = resolve::ResolveOptions { stand_ins: true, make: false };
    let outcome = resolve::resolve_with(&scene, &catalog, scene.seed, &options);
    let res = &outcome.value;
    let id = |name: &str| scene.objects.iter().find(|o| o.name == name).expect("object").id;
    let object_type = |name: &str| res.object(id(name)).map(|c| c.object_type.clone());

    // Books on the shelf; the photo frames are left out, with the size in the warning.
    let shelf = res.object(id("bookshelf-0")).expect("a shelf");
    for book in &res.small[&(id("bookshelf-0"), 0)] {
        let book = book.choice().expect("a book");
        assert_eq!(book.object_type, "Book");
        assert!(resolve::allowed_on(&book.object_type, &shelf.object_type));
    }
    for frame in &res.small[&(id("bookshelf-0"), 1)] {
        assert!(frame.choice().is_none(), "a photo frame is no 0.5 m+ wall painting: {frame:?}");
    }
    let w0401 = outcome
        .diagnostics
        .iter()
        .find(|d| d.code.as_str() == "W0401" && d.message.contains("photo frame"))
        .expect("the frames are reported");
    assert!(w0401.notes.iter().any(|n| n.contains("too large")), "{:?}", w0401.notes);

    // The plant stand holds its plant: a side table stands in, with its warning.
    let stand = res.object(id("plant_stand-0")).expect("a stand-in");
    assert_eq!(stand.object_type, "SideTable");
    assert!(stand.stand_in.is_some());
    let plant = res.small[&(id("plant_stand-0"), 0)][0].choice().expect("a plant");
    assert_eq!(plant.object_type, "HousePlant");
    assert!(resolve::allowed_on("HousePlant", "SideTable"));

    assert_eq!(object_type("cat_bed-0").as_deref(), Some("DogBed"));
    // The only blind of the catalog is a 20 cm roll: too far from 2 m curtains to stand in.
    assert_eq!(object_type("curtains-0"), None);
    assert!(
        outcome.diagnostics.iter().any(|d| d.code.as_str() == "W0401"
            && d.message.contains("curtains-0")
            && d.notes.iter().any(|n| n.contains("Blinds") && n.contains("size ratio"))),
        "{:?}",
        outcome.diagnostics
    );
    let papers = res.small[&(id("desk-0"), 0)][0].choice().expect("papers");
    assert_eq!(papers.object_type, "Newspaper", "never toilet paper");

    let stood_in: Vec<String> = outcome
        .diagnostics
        .iter()
        .filter(|d| d.code.as_str() == "W0403")
        .map(|d| d.message.clone())
        .collect();
    // (A cat bed ranks a dog bed good enough by its words: no stand-in, no warning.)
    for (what, with) in [("plant_stand", "SideTable"), ("papers", "Newspaper")] {
        assert!(
            stood_in.iter().any(|m| m.contains(what) && m.contains(with)),
            "W0403 says a {with} stood in for {what}: {stood_in:?}"
        );
    }
}

/// Stand-ins say how far their size is from the size asked and are refused past
/// `MAX_STAND_IN_RATIO` (issue 33): the bedroom's 1 × 2 m wardrobe gets the nearest dresser by
/// height, within the ratio, not a 0.89 m tall one 1.91 m wide; a 4 m wardrobe gets none, and
/// the warning names the dresser refused; a wall clock is never a desk clock hung on a wall.
/// (The catalogs' choices: resolved without made assets, which would make the wall clock.)
#[test]
fn stand_ins_keep_to_the_size_ratio() {
    let resolve_text = |text: &str| {
        let mut sources = SourceMap::new();
        let id = sources.add("t.holo", text);
        let scene = holoc::compile::check_file(&sources, id).value.expect("checks");
        let catalog = Catalog::embedded();
        let options = resolve::ResolveOptions { stand_ins: true, make: false };
        let outcome = resolve::resolve_with(&scene, &catalog, scene.seed, &options);
        (scene, outcome)
    };
    let wardrobe = |height_cm: u32| {
        format!(
            "scene \"t\" {{ seed 0 }}\nroom a \"a\" {{\n  corners in m (0, 0) (0, 5) (5, 5) (5, 0)\n  object wardrobe \"wardrobe\" {{\n    describe \"tall white two-door wardrobe\"\n    size 100 cm x 60 cm x {height_cm} cm\n    edge\n  }}\n  wall object clock \"wall clock\" {{\n    describe \"round wall clock\"\n    size 30 cm x 5 cm x 30 cm\n  }}\n}}\n"
        )
    };
    let (scene, outcome) = resolve_text(&wardrobe(200));
    let chosen = outcome.value.object(scene.objects[0].id).expect("a dresser stands in");
    assert_eq!(chosen.object_type, "Dresser");
    let ratio = chosen.size_ratio.expect("a size was asked");
    assert!(ratio <= resolve::standins::MAX_STAND_IN_RATIO, "{ratio}");
    assert!(chosen.bbox_m[1] >= 1.2, "the tallest dressers are nearest: {chosen:?}");
    let w0403 = outcome.diagnostics.iter().find(|d| d.code.as_str() == "W0403").expect("W0403");
    assert!(w0403.message.contains(&format!("size ratio {ratio:.2}")), "{}", w0403.message);
    assert!(w0403.notes.iter().any(|n| n.contains("for 100 × 60 × 200 cm asked")), "{w0403:?}");
    // The wall clock: no asset of its own, and no desk clock hung on the wall.
    assert!(outcome.value.object(scene.objects[1].id).is_none(), "{:?}", outcome.diagnostics);
    assert!(!outcome.diagnostics.iter().any(|d| d.code.as_str() == "W0404"));

    let (scene, outcome) = resolve_text(&wardrobe(400));
    assert!(outcome.value.object(scene.objects[0].id).is_none(), "no dresser is 4 m tall");
    let w0401 = outcome
        .diagnostics
        .iter()
        .find(|d| d.code.as_str() == "W0401" && d.message.contains("wardrobe-0"))
        .expect("W0401");
    assert!(
        w0401
            .notes
            .iter()
            .any(|n| n.contains("a Dresser could be used") && n.contains("more than 2")),
        "{w0401:?}"
    );
}

/// `stack of papers` never matches toilet paper by its words (`paper` alone names a material,
/// and toilet paper says which thing of it it is).
#[test]
fn papers_are_not_toilet_paper() {
    let catalog = Catalog::embedded();
    let query = Query {
        category: "stack of papers".into(),
        description: None,
        size_m: None,
        kind: Some(PlacementKind::OnObject),
    };
    let ranked = resolve::rank(&catalog, &query, 0);
    assert!(
        !ranked.iter().any(|c| c.is_good_enough() && c.object_type == "ToiletPaper"),
        "{:?}",
        ranked.iter().take(3).map(|c| (&c.asset_id, c.relevance)).collect::<Vec<_>>()
    );
    let toilet = Query { category: "toilet paper".into(), ..query };
    let ranked = resolve::rank(&catalog, &toilet, 0);
    assert_eq!(ranked[0].object_type, "ToiletPaper");
    assert!(ranked[0].is_good_enough());
}

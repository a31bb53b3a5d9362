//! Plan stage: every fixture under `tests/corpus/plan/` (floor plans, valid under `ok/`) and
//! every example is planned; the diagnostics must match the `// expect:` header and the plan
//! dump is snapshotted in `snapshots/plan/`.

mod common;

use common::{assert_expected, corpus_name, render, snapshot_body};
use holoc::plan::{plan_with, PlanOptions};
use holoc::resolve::structure::StructureCatalog;
use holoc::source::SourceMap;
use std::path::Path;

fn plan_text(
    name: &str,
    text: &str,
    options: PlanOptions,
) -> (SourceMap, Vec<holoc::diag::Diagnostic>, String) {
    let mut sources = SourceMap::new();
    let id = sources.add(name, text.to_string());
    let checked = holoc::compile::check_file(&sources, id);
    let mut diagnostics = checked.diagnostics;
    let output = match checked.value {
        Some(scene) if !diagnostics.iter().any(holoc::diag::Diagnostic::is_error) => {
            let planned = plan_with(&scene, StructureCatalog::builtin(), options);
            diagnostics.extend(planned.diagnostics);
            if diagnostics.iter().any(holoc::diag::Diagnostic::is_error) {
                "(plan errors)\n".to_string()
            } else {
                planned.value.dump(&scene)
            }
        }
        _ => "(check errors)\n".to_string(),
    };
    (sources, diagnostics, output)
}

fn check_plan(path: &Path) {
    let text = std::fs::read_to_string(path).expect("fixture is readable");
    let name = corpus_name(path);
    let (sources, diagnostics, output) = plan_text(&name, &text, PlanOptions::default());
    assert_expected(path, &sources, &text, &diagnostics);
    insta::assert_snapshot!(snapshot_body(&name, &text, &render(&sources, &diagnostics), &output));
}

#[test]
fn plan_corpus() {
    insta::with_settings!({
        snapshot_path => "../snapshots/plan",
        prepend_module_to_snapshot => false,
        omit_expression => true,
    }, {
        insta::glob!("corpus/plan", "**/*.holo", check_plan);
    });
}

#[test]
fn plan_examples() {
    insta::with_settings!({
        snapshot_path => "../snapshots/plan",
        prepend_module_to_snapshot => false,
        omit_expression => true,
    }, {
        insta::glob!("../examples", "*.holo", |path| {
            let text = std::fs::read_to_string(path).expect("example is readable");
            let name = format!("examples/{}", path.file_name().and_then(|n| n.to_str()).unwrap_or("?"));
            let (sources, diagnostics, output) = plan_text(&name, &text, PlanOptions::default());
            assert!(!diagnostics.iter().any(holoc::diag::Diagnostic::is_error), "{}", render(&sources, &diagnostics));
            insta::assert_snapshot!(snapshot_body(&name, &text, &render(&sources, &diagnostics), &output));
        });
    });
}

#[test]
fn add_doors_repairs_reachability() {
    let text = std::fs::read_to_string("tests/corpus/plan/unreachable_room.holo").expect("fixture");
    let (_, diagnostics, output) = plan_text(
        "unreachable_room.holo",
        &text,
        PlanOptions { add_doors: true, ..PlanOptions::default() },
    );
    let codes: Vec<&str> = diagnostics.iter().map(|d| d.code.as_str()).collect();
    assert_eq!(codes, ["W0302"]);
    assert!(output.contains("door|1|a|b"), "{output}");
    let text = std::fs::read_to_string("tests/corpus/plan/no_exterior_door.holo").expect("fixture");
    let (_, diagnostics, output) = plan_text(
        "no_exterior_door.holo",
        &text,
        PlanOptions { add_doors: true, ..PlanOptions::default() },
    );
    let codes: Vec<&str> = diagnostics.iter().map(|d| d.code.as_str()).collect();
    assert_eq!(codes, ["W0302"]);
    assert!(output.contains("door|1|exterior|a"), "{output}");
}

#[test]
fn plan_is_deterministic() {
    for entry in std::fs::read_dir("tests/corpus/plan/ok").expect("corpus") {
        let path = entry.expect("entry").path();
        let text = std::fs::read_to_string(&path).expect("fixture");
        let a = plan_text("x.holo", &text, PlanOptions::default()).2;
        let b = plan_text("x.holo", &text, PlanOptions::default()).2;
        assert_eq!(a, b, "{}", path.display());
    }
}

//! Geometric repair of floor plans (`holoc repair`, `build --repair`): every fixture under
//! `tests/corpus/repair/` is repaired; its diagnostics must match the `// expect:` header and the
//! snapshot in `snapshots/repair/` shows them with the repaired text. The repaired text plans
//! without errors (unless the header expects one), repairing it again changes nothing, and
//! random small breaks of valid plans are repaired within the documented bounds.

mod common;

use common::{assert_expected, corpus_name, render, snapshot_body};
use holoc::diag::{apply_fixes, Diagnostic};
use holoc::plan::repair::{
    apply, area_changes, explain_unrepaired, repair, MAX_AREA_CHANGE, MAX_MOVE_M, MAX_TRANSLATION_M,
};
use holoc::resolve::structure::StructureCatalog;
use holoc::source::SourceMap;
use proptest::prelude::*;
use std::fmt::Write as _;
use std::path::Path;

/// What repairing a text gives: its diagnostics (repair's, then the plan errors left), the
/// repaired text and the plan errors of the repaired text.
struct Repaired {
    sources: SourceMap,
    diagnostics: Vec<Diagnostic>,
    text: String,
    changed: bool,
    max_move_m: f64,
    area_change: f64,
}

fn repair_text(name: &str, text: &str) -> Repaired {
    let mut sources = SourceMap::new();
    let id = sources.add(name, text.to_string());
    let checked = holoc::compile::check_file(&sources, id);
    assert!(
        !checked.diagnostics.iter().any(Diagnostic::is_error),
        "{name} must pass the checker: {:#?}",
        checked.diagnostics
    );
    let scene = checked.value.expect("a checked scene");
    let catalog = StructureCatalog::builtin();
    let repaired = repair(&scene, catalog);
    let after = apply(&scene, &repaired.value);
    let mut diagnostics = repaired.diagnostics.clone();
    diagnostics.extend(
        holoc::plan::plan(&after, catalog)
            .diagnostics
            .into_iter()
            .filter(Diagnostic::is_error)
            .map(explain_unrepaired),
    );
    let area_change = area_changes(&scene, &repaired.value).into_iter().fold(0.0, f64::max);
    Repaired {
        text: apply_fixes(text, id, &repaired.diagnostics),
        sources,
        diagnostics,
        changed: repaired.value.changed,
        max_move_m: repaired.value.max_move_m,
        area_change,
    }
}

/// The plan errors of a text (the checker's and the plan stage's).
fn plan_errors(text: &str) -> Vec<&'static str> {
    let mut sources = SourceMap::new();
    let id = sources.add("repaired.holo", text.to_string());
    let checked = holoc::compile::check_file(&sources, id);
    let mut codes: Vec<_> =
        checked.diagnostics.iter().filter(|d| d.is_error()).map(|d| d.code.as_str()).collect();
    if let Some(scene) = checked.value {
        codes.extend(
            holoc::plan::plan(&scene, StructureCatalog::builtin())
                .diagnostics
                .iter()
                .filter(|d| d.is_error())
                .map(|d| d.code.as_str()),
        );
    }
    codes
}

fn check_repair(path: &Path) {
    let text = std::fs::read_to_string(path).expect("fixture is readable");
    let name = corpus_name(path);
    let repaired = repair_text(&name, &text);
    assert_expected(path, &repaired.sources, &text, &repaired.diagnostics);
    let expects_error = repaired.diagnostics.iter().any(Diagnostic::is_error);
    if expects_error {
        assert_eq!(repaired.text, text, "{name}: what cannot be repaired stays as written");
    } else {
        assert_eq!(plan_errors(&repaired.text), Vec::<&str>::new(), "{name}: repaired text");
        // A room drawn narrower than the narrowest allowed (the `narrow_*` fixtures) must grow
        // past the area bound to be a room at all.
        assert!(
            repaired.area_change <= MAX_AREA_CHANGE || name.contains("narrow"),
            "{name}: area {}",
            repaired.area_change
        );
    }
    // Idempotent and deterministic.
    let again = repair_text(&name, &repaired.text);
    if !expects_error {
        assert!(!again.changed, "{name}: a repaired plan needs no second repair");
    }
    assert_eq!(again.text, repaired.text, "{name}");
    assert_eq!(repair_text(&name, &text).text, repaired.text, "{name}: deterministic");
    let output = if repaired.changed { repaired.text.clone() } else { "(unchanged)\n".into() };
    insta::assert_snapshot!(snapshot_body(
        &name,
        &text,
        &render(&repaired.sources, &repaired.diagnostics),
        &output
    ));
}

#[test]
fn repair_corpus() {
    insta::with_settings!({
        snapshot_path => "../snapshots/repair",
        prepend_module_to_snapshot => false,
        omit_expression => true,
    }, {
        insta::glob!("corpus/repair", "**/*.holo", check_repair);
    });
}

/// Repairing a plan that builds changes nothing: every example and valid plan fixture.
#[test]
fn valid_plans_are_left_as_written() {
    let mut files: Vec<_> = std::fs::read_dir("examples")
        .expect("examples")
        .chain(std::fs::read_dir("tests/corpus/plan/ok").expect("plan corpus"))
        .filter_map(Result::ok)
        .map(|e| e.path())
        .filter(|p| p.extension().is_some_and(|e| e == "holo"))
        .collect();
    files.sort();
    assert!(files.len() >= 6, "{files:?}");
    for path in files {
        let text = std::fs::read_to_string(&path).expect("readable");
        let repaired = repair_text(&path.display().to_string(), &text);
        assert!(!repaired.changed, "{}: {:#?}", path.display(), repaired.diagnostics);
        assert!(repaired.diagnostics.is_empty(), "{}", path.display());
        assert_eq!(repaired.text, text);
    }
}

/// A valid three-room plan with one room's corners pushed by `dx`, `dz` (a gap or an overlap
/// with its neighbours); `which` chooses the room.
fn broken_plan(which: usize, dx: f64, dz: f64) -> String {
    let rooms = [
        ("living", "living room", [(0.0, 0.0), (0.0, 5.0), (5.0, 5.0), (5.0, 0.0)]),
        ("kitchen", "kitchen", [(5.0, 0.0), (5.0, 5.0), (8.0, 5.0), (8.0, 0.0)]),
        ("bedroom", "bedroom", [(0.0, 5.0), (0.0, 9.0), (8.0, 9.0), (8.0, 5.0)]),
    ];
    let mut text = String::from("scene \"broken\" { seed 1 }\n");
    for (i, (id, label, corners)) in rooms.iter().enumerate() {
        let corners: Vec<String> = corners
            .iter()
            .map(|&(x, z)| {
                let (x, z) = if i == which { (x + dx, z + dz) } else { (x, z) };
                format!("({x:.3}, {z:.3})")
            })
            .collect();
        let _ = writeln!(text, "room {id} \"{label}\" {{ corners in m {} }}", corners.join(" "));
    }
    text.push_str(
        "door exterior -- living : doorway single\n\
         door living -- kitchen : doorway single\n\
         door living -- bedroom : doorway single\n",
    );
    text
}

proptest! {
    #![proptest_config(ProptestConfig {
        cases: 300,
        rng_seed: proptest::test_runner::RngSeed::Fixed(0x7265_7061),
        failure_persistence: None,
        ..ProptestConfig::default()
    })]

    /// A room moved by up to 40 cm on each axis is repaired: the result plans without errors,
    /// no corner moved more than the bounds, no area changed more than the bound, and a second
    /// repair changes nothing. The same input gives the same text.
    #[test]
    fn small_breaks_are_repaired_within_the_bounds(
        which in 1usize..3,
        dx in -0.4f64..0.4,
        dz in -0.4f64..0.4,
    ) {
        let text = broken_plan(which, dx, dz);
        let repaired = repair_text("broken.holo", &text);
        prop_assert!(
            !repaired.diagnostics.iter().any(Diagnostic::is_error),
            "{text}\n{}",
            render(&repaired.sources, &repaired.diagnostics)
        );
        prop_assert_eq!(plan_errors(&repaired.text), Vec::<&str>::new(), "{}", repaired.text);
        prop_assert!(repaired.max_move_m <= MAX_MOVE_M.max(MAX_TRANSLATION_M) + 1e-9);
        prop_assert!(repaired.area_change <= MAX_AREA_CHANGE + 1e-9);
        let again = repair_text("repaired.holo", &repaired.text);
        prop_assert!(!again.changed, "{}", repaired.text);
        prop_assert_eq!(repair_text("broken.holo", &text).text, repaired.text);
    }
}

proptest! {
    #![proptest_config(ProptestConfig {
        cases: 200,
        rng_seed: proptest::test_runner::RngSeed::Fixed(0x6964_656d),
        failure_persistence: None,
        ..ProptestConfig::default()
    })]

    /// Repair is idempotent on every output, including partial ones (plans it cannot make
    /// build): breaks of up to 1.2 m on two rooms; repairing the output again changes nothing,
    /// and no error appears that the plan did not have.
    #[test]
    fn repair_is_idempotent_and_never_worse(
        which in 1usize..3,
        dx in -1.2f64..1.2,
        dz in -1.2f64..1.2,
        other_dx in -0.3f64..0.3,
    ) {
        let mut text = broken_plan(which, dx, dz);
        // A second, smaller break of the living room's east wall.
        text = text.replacen("(5.000, 5.000) (5.000, 0.000)", &format!("({0:.3}, 5.000) ({0:.3}, 0.000)", 5.0 + other_dx), 1);
        let before = plan_errors(&text);
        let repaired = repair_text("broken.holo", &text);
        let after = plan_errors(&repaired.text);
        let mut left = before.clone();
        for code in &after {
            let i = left.iter().position(|c| c == code);
            prop_assert!(i.is_some(), "a new error {code}: {before:?} → {after:?}\n{text}\n{}", repaired.text);
            if let Some(i) = i {
                left.remove(i);
            }
        }
        let again = repair_text("repaired.holo", &repaired.text);
        prop_assert_eq!(&again.text, &repaired.text, "{}", text);
        prop_assert!(!again.changed, "{}", repaired.text);
    }
}

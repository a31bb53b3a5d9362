//! Corpus-driven tests of the language stages: one fixture file per behaviour under
//! `tests/corpus/<stage>/`, its expected diagnostics in a `// expect:` header, its snapshot in
//! `snapshots/<stage>/`.

mod common;

use common::{assert_expected, corpus_name, render, snapshot_body};
use holoc::source::SourceMap;
use std::path::Path;

fn check_parse(path: &Path) {
    let text = std::fs::read_to_string(path).expect("fixture is readable");
    let mut sources = SourceMap::new();
    let id = sources.add(corpus_name(path), text.clone());
    let parsed = holoc::parse::parse(&sources, id);
    assert_expected(path, &sources, &text, &parsed.diagnostics);
    let output = holoc::fmt::print(&parsed.value);
    let body =
        snapshot_body(&corpus_name(path), &text, &render(&sources, &parsed.diagnostics), &output);
    insta::assert_snapshot!(body);
}

fn check_check(path: &Path) {
    let text = std::fs::read_to_string(path).expect("fixture is readable");
    let mut sources = SourceMap::new();
    let id = sources.add(corpus_name(path), text.clone());
    let outcome = holoc::compile::check_file(&sources, id);
    assert_expected(path, &sources, &text, &outcome.diagnostics);
    let output =
        outcome.value.as_ref().map_or_else(|| "(syntax errors)\n".to_string(), holoc::check::dump);
    let body =
        snapshot_body(&corpus_name(path), &text, &render(&sources, &outcome.diagnostics), &output);
    insta::assert_snapshot!(body);
}

macro_rules! stage_settings {
    ($stage:literal, $body:block) => {
        insta::with_settings!({
            snapshot_path => concat!("../snapshots/", $stage),
            prepend_module_to_snapshot => false,
            omit_expression => true,
        }, $body)
    };
}

#[test]
fn parse_corpus() {
    stage_settings!("parse", {
        insta::glob!("corpus/parse", "**/*.holo", check_parse);
    });
}

#[test]
fn check_corpus() {
    stage_settings!("check", {
        insta::glob!("corpus/check", "**/*.holo", check_check);
    });
}

#[test]
fn examples_check_clean() {
    for entry in std::fs::read_dir("examples").expect("examples folder") {
        let path = entry.expect("entry").path();
        if path.extension().is_some_and(|e| e == "holo") {
            let text = std::fs::read_to_string(&path).expect("readable");
            let mut sources = SourceMap::new();
            let id = sources.add(path.display().to_string(), text);
            let outcome = holoc::compile::check_file(&sources, id);
            assert!(
                outcome.diagnostics.is_empty(),
                "{} has diagnostics:\n{}",
                path.display(),
                render(&sources, &outcome.diagnostics)
            );
        }
    }
}

/// A file of unbalanced braces (what an editor holds while someone types) is read in linear
/// time: the recovery rule for a broken block no longer tries every way of pairing `{`s (30
/// braces took over 10 s). Not timed here; an exponential parser would not finish.
#[test]
fn unbalanced_braces_are_read_in_linear_time() {
    for text in ["{".repeat(10_000), format!("room a \"a\" {{\n{}", "  {\n".repeat(3_000))] {
        let mut sources = holoc::source::SourceMap::new();
        let id = sources.add("braces.holo", text);
        let diagnostics = holoc::compile::check_file(&sources, id).diagnostics;
        assert!(diagnostics.iter().any(holoc::diag::Diagnostic::is_error));
    }
}

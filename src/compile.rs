//! The driver: runs the stages in order on one file and collects their diagnostics.
//!
//! A stage runs only when the stages before it produced no error.

use crate::check::Scene;
use crate::diag::Outcome;
use crate::source::{FileId, SourceMap};

/// Parses and checks one file. The scene is `None` when the file has syntax errors.
pub fn check_file(sources: &SourceMap, file: FileId) -> Outcome<Option<Scene>> {
    let parsed = crate::parse::parse(sources, file);
    let mut diagnostics = parsed.diagnostics;
    let parse_failed = diagnostics.iter().any(crate::diag::Diagnostic::is_error);
    let checked = crate::check::check(&parsed.value);
    // The checker also runs on a file with syntax errors (the editor wants every problem);
    // bad lines are error nodes that it skips.
    diagnostics.extend(checked.diagnostics);
    let scene = (!parse_failed).then_some(checked.value);
    Outcome::new(scene, diagnostics)
}

/// Runs every stage on one file as far as it gets and returns all diagnostics (what an editor
/// shows, and what the diagnostics catalogue's examples are checked against).
pub fn diagnose(sources: &SourceMap, file: FileId) -> Vec<crate::diag::Diagnostic> {
    check_file(sources, file).diagnostics
}

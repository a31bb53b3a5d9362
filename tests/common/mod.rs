//! Helpers shared by the corpus-driven tests: fixture headers and snapshot bodies.

#![allow(dead_code, reason = "each test binary uses a different part")]

use holoc::diag::{self, format::HumanOptions, Diagnostic};
use holoc::source::SourceMap;
use std::path::Path;

/// One expected diagnostic: a code and, optionally, `line:column`.
#[derive(Debug, PartialEq, Eq, PartialOrd, Ord, Clone)]
pub struct Expected {
    pub code: String,
    pub at: Option<(usize, usize)>,
}

/// Reads the `// expect: E0201 @ 14:13, W0702` header (several header lines are joined).
/// Files under an `ok/` folder expect nothing.
pub fn expectations(text: &str) -> Vec<Expected> {
    let mut out = Vec::new();
    for line in text.lines() {
        let Some(rest) = line.trim().strip_prefix("// expect:") else {
            if line.trim().starts_with("//") {
                continue;
            }
            break;
        };
        for item in rest.split(',').map(str::trim).filter(|s| !s.is_empty()) {
            let (code, at) = match item.split_once('@') {
                Some((c, pos)) => {
                    let (l, c2) = pos.trim().split_once(':').expect("position is line:column");
                    (c.trim(), Some((l.parse().expect("line"), c2.parse().expect("column"))))
                }
                None => (item, None),
            };
            out.push(Expected { code: code.to_string(), at });
        }
    }
    out.sort();
    out
}

/// Checks that the diagnostics are exactly the expected ones (codes, and positions when given).
pub fn assert_expected(path: &Path, sources: &SourceMap, text: &str, diagnostics: &[Diagnostic]) {
    let expected = expectations(text);
    let mut actual: Vec<Expected> = diagnostics
        .iter()
        .map(|d| {
            let at = d.primary.as_ref().map(|l| {
                let lc = sources.get(l.span.file).line_col(l.span.start as usize);
                (lc.line, lc.column)
            });
            let want_pos = expected.iter().any(|e| e.code == d.code.as_str() && e.at.is_some());
            Expected { code: d.code.as_str().to_string(), at: if want_pos { at } else { None } }
        })
        .collect();
    actual.sort();
    assert_eq!(
        actual,
        expected,
        "diagnostics of {} differ from its `// expect:` header",
        path.display()
    );
}

/// Renders diagnostics the way snapshots show them: no colour, unicode, width 80.
pub fn render(sources: &SourceMap, diagnostics: &[Diagnostic]) -> String {
    let mut sorted = diagnostics.to_vec();
    diag::sort(&mut sorted);
    let text =
        diag::format::render_human(sources, &sorted, HumanOptions { color: false, width: 80 });
    if text.is_empty() {
        "(none)\n".to_string()
    } else {
        text
    }
}

/// The body of a stage snapshot.
pub fn snapshot_body(name: &str, source: &str, diagnostics: &str, output: &str) -> String {
    format!(
        "----- SOURCE  [CORPUS]/{name}\n{source}----- DIAGNOSTICS\n{diagnostics}----- OUTPUT\n{output}"
    )
}

/// The corpus-relative name of a fixture.
pub fn corpus_name(path: &Path) -> String {
    let s = path.to_string_lossy().replace('\\', "/");
    s.split("tests/corpus/").nth(1).unwrap_or(&s).to_string()
}

/// Says that a test did not run and why, where a person sees it: on the terminal even though
/// the harness captures the test's output (the message goes straight to stderr, past the
/// capture), and as one line in the file `HOLOC_SKIPPED_LOG` names, which CI counts for its
/// closing line.
pub fn skip(test: &str, reason: &str) {
    use std::io::Write as _;
    let line = format!("SKIPPED {test}: {reason}\n");
    let _ = std::io::stderr().write_all(line.as_bytes());
    if let Some(log) = std::env::var_os("HOLOC_SKIPPED_LOG") {
        if let Ok(mut file) = std::fs::OpenOptions::new().create(true).append(true).open(log) {
            let _ = file.write_all(line.as_bytes());
        }
    }
}

/// The folder `../shared/<rel>` of the reference data, or `None` after [`skip`] said that
/// `test` does not run without it.
pub fn shared(rel: &str, test: &str) -> Option<std::path::PathBuf> {
    let path = Path::new("../shared").join(rel);
    if path.exists() {
        Some(path)
    } else {
        skip(
            test,
            &format!(
                "{} is absent (the reference data is not beside the checkout)",
                path.display()
            ),
        );
        None
    }
}

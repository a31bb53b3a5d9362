use super::place;
use crate::diag::Diagnostic;
use crate::source::SourceMap;
use std::fmt::Write;

/// One line per diagnostic: `file:line:col: severity[code]: message`.
pub fn render_short(sources: &SourceMap, diagnostics: &[Diagnostic]) -> String {
    let mut out = String::new();
    for d in diagnostics {
        let location = d
            .primary
            .as_ref()
            .and_then(|l| place(sources, l.span))
            .map(|p| format!("{}:{}:{}: ", p.file, p.line, p.column))
            .unwrap_or_default();
        let _ =
            writeln!(out, "{location}{}[{}]: {}", d.severity.as_str(), d.code.as_str(), d.message);
    }
    out
}

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
            .map(|p| format!("{}:{}:{}: ", crate::diag::visible(p.file), p.line, p.column))
            .unwrap_or_default();
        let message = crate::diag::visible(&d.message);
        let _ = writeln!(out, "{location}{}[{}]: {message}", d.severity.as_str(), d.code.as_str());
    }
    out
}

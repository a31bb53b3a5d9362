//! Diagnostics as Language Server Protocol `Diagnostic` objects (0-based lines, UTF-16
//! columns).

use super::{Diagnostic, Severity};
use crate::source::{SourceMap, Span};
use lsp_types::{
    CodeDescription, DiagnosticRelatedInformation, DiagnosticSeverity, Location, NumberOrString,
    Position, Range, Uri,
};
use std::str::FromStr;

fn range(sources: &SourceMap, span: Span) -> Range {
    let Some(file) = sources.try_get(span.file) else { return Range::default() };
    let (l0, c0) = file.lsp_position(span.start as usize);
    let (l1, c1) = file.lsp_position(span.end as usize);
    Range { start: Position::new(l0, c0), end: Position::new(l1, c1) }
}

fn uri(sources: &SourceMap, span: Span) -> Option<Uri> {
    let file = sources.try_get(span.file)?;
    let path = std::path::Path::new(&file.name);
    let absolute = if path.is_absolute() {
        path.to_path_buf()
    } else {
        std::env::current_dir().ok()?.join(path)
    };
    Uri::from_str(&format!("file://{}", absolute.display()).replace(' ', "%20")).ok()
}

/// Converts diagnostics to LSP diagnostics, each paired with the file it belongs to.
pub fn to_lsp(
    sources: &SourceMap,
    diagnostics: &[Diagnostic],
) -> Vec<(String, lsp_types::Diagnostic)> {
    diagnostics
        .iter()
        .map(|d| {
            let file = d
                .primary
                .as_ref()
                .and_then(|l| sources.try_get(l.span.file))
                .map(|f| f.name.clone())
                .unwrap_or_default();
            let related: Vec<DiagnosticRelatedInformation> = d
                .secondary
                .iter()
                .filter_map(|l| {
                    Some(DiagnosticRelatedInformation {
                        location: Location {
                            uri: uri(sources, l.span)?,
                            range: range(sources, l.span),
                        },
                        message: l.text.clone(),
                    })
                })
                .collect();
            let mut message = d.message.clone();
            if let Some(help) = &d.help {
                message.push_str("\nhelp: ");
                message.push_str(help);
            }
            let diagnostic = lsp_types::Diagnostic {
                range: d.primary.as_ref().map(|l| range(sources, l.span)).unwrap_or_default(),
                severity: Some(match d.severity {
                    Severity::Error => DiagnosticSeverity::ERROR,
                    Severity::Warning => DiagnosticSeverity::WARNING,
                    Severity::Note => DiagnosticSeverity::INFORMATION,
                }),
                code: Some(NumberOrString::String(d.code.as_str().to_string())),
                code_description: Uri::from_str(&d.code.url())
                    .ok()
                    .map(|href| CodeDescription { href }),
                source: Some("holoc".to_string()),
                message,
                related_information: (!related.is_empty()).then_some(related),
                tags: None,
                data: None,
            };
            (file, diagnostic)
        })
        .collect()
}

/// The LSP form as a JSON document: `{"version": 1, "diagnostics": [{"file", "diagnostic"}]}`.
pub fn render_lsp(sources: &SourceMap, diagnostics: &[Diagnostic]) -> String {
    let items: Vec<serde_json::Value> = to_lsp(sources, diagnostics)
        .into_iter()
        .map(|(file, d)| serde_json::json!({ "file": file, "diagnostic": d }))
        .collect();
    let doc = serde_json::json!({ "version": 1, "diagnostics": items });
    let mut text = serde_json::to_string_pretty(&doc).expect("a JSON value always serializes");
    text.push('\n');
    text
}

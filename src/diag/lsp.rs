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

/// The `file:` URI of a path (made absolute from the working folder), percent-encoded by the
/// `url` crate: a `#`, `%`, space or `é` in a folder name stays part of the path.
pub fn file_uri(name: &str) -> Option<Uri> {
    let path = std::path::Path::new(name);
    let absolute = if path.is_absolute() {
        path.to_path_buf()
    } else {
        std::env::current_dir().ok()?.join(path)
    };
    let url = url::Url::from_file_path(&absolute).ok()?;
    Uri::from_str(url.as_str()).ok()
}

/// How a file of the source map is named in LSP locations, and where a code's page is.
pub struct Links<'a> {
    /// The URI of a file, by its name in the source map.
    pub uri: &'a dyn Fn(&str) -> Option<Uri>,
    /// The `codeDescription.href` of a code (`None`: no `codeDescription`).
    pub href: &'a dyn Fn(super::Code) -> Option<Uri>,
}

/// The absolute `file:` URI of a code's page in the holoc sources this program was built from,
/// when they are there (`None` otherwise: an editor cannot open a relative path, so none is
/// given). `holoc explain CODE` prints the same page.
pub fn page_uri(code: super::Code) -> Option<Uri> {
    use std::sync::OnceLock;
    static PAGES: OnceLock<Option<std::path::PathBuf>> = OnceLock::new();
    let dir = PAGES.get_or_init(|| {
        let dir = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("book/src/diagnostics");
        dir.is_dir().then_some(dir)
    });
    let page = dir.as_ref()?.join(format!("{}.md", code.as_str()));
    file_uri(&page.to_string_lossy())
}

/// Converts diagnostics to LSP diagnostics, each paired with the file it belongs to. Files are
/// named by their path's `file:` URI, and a code's page by [`page_uri`], as the language
/// server names it.
pub fn to_lsp(
    sources: &SourceMap,
    diagnostics: &[Diagnostic],
) -> Vec<(String, lsp_types::Diagnostic)> {
    let links = Links { uri: &file_uri, href: &page_uri };
    to_lsp_with(sources, diagnostics, &links)
}

/// [`to_lsp`] with other names for files (the language server's: its documents' URIs as the
/// editor gave them) and pages.
pub fn to_lsp_with(
    sources: &SourceMap,
    diagnostics: &[Diagnostic],
    links: &Links<'_>,
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
                            uri: (links.uri)(&sources.try_get(l.span.file)?.name)?,
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
                code_description: (links.href)(d.code).map(|href| CodeDescription { href }),
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

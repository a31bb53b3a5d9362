use super::place;
use crate::diag::{Diagnostic, Severity};
use crate::source::SourceMap;
use miette::{GraphicalReportHandler, GraphicalTheme, LabeledSpan, NamedSource, SourceSpan};
use std::fmt;
use std::fmt::Write as _;

/// How human diagnostics are drawn.
#[derive(Clone, Copy, Debug)]
pub struct HumanOptions {
    /// Use colour (ANSI escapes).
    pub color: bool,
    /// Wrap width in columns.
    pub width: usize,
}

impl Default for HumanOptions {
    fn default() -> Self {
        HumanOptions { color: false, width: 80 }
    }
}

/// A diagnostic paired with its source, in the shape miette renders.
struct Report<'a> {
    diagnostic: &'a Diagnostic,
    source: Option<NamedSource<String>>,
    labels: Vec<LabeledSpan>,
    footer: Option<String>,
}

impl fmt::Debug for Report<'_> {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(&self.diagnostic.message)
    }
}

impl fmt::Display for Report<'_> {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(&self.diagnostic.message)
    }
}

impl std::error::Error for Report<'_> {}

impl miette::Diagnostic for Report<'_> {
    fn code<'b>(&'b self) -> Option<Box<dyn fmt::Display + 'b>> {
        Some(Box::new(self.diagnostic.code.as_str()))
    }

    fn severity(&self) -> Option<miette::Severity> {
        Some(match self.diagnostic.severity {
            Severity::Error => miette::Severity::Error,
            Severity::Warning => miette::Severity::Warning,
            Severity::Note => miette::Severity::Advice,
        })
    }

    fn help<'b>(&'b self) -> Option<Box<dyn fmt::Display + 'b>> {
        match (&self.diagnostic.help, &self.footer) {
            (None, None) => None,
            (Some(h), None) => Some(Box::new(h.clone())),
            (None, Some(f)) => Some(Box::new(f.clone())),
            (Some(h), Some(f)) => Some(Box::new(format!("{h}\n{f}"))),
        }
    }

    fn source_code(&self) -> Option<&dyn miette::SourceCode> {
        self.source.as_ref().map(|s| s as &dyn miette::SourceCode)
    }

    fn labels(&self) -> Option<Box<dyn Iterator<Item = LabeledSpan> + '_>> {
        if self.labels.is_empty() {
            None
        } else {
            Some(Box::new(self.labels.iter().cloned()))
        }
    }
}

fn report<'a>(sources: &SourceMap, d: &'a Diagnostic) -> Report<'a> {
    let mut footer_lines: Vec<String> = Vec::new();
    let mut labels = Vec::new();
    let mut source = None;
    if let Some(primary) = &d.primary {
        if let Some(file) = sources.try_get(primary.span.file) {
            source = Some(NamedSource::new(file.name.clone(), file.text.clone()));
            let to_span = |s: crate::source::Span| SourceSpan::from((s.start as usize, s.len()));
            let text = (!primary.text.is_empty()).then(|| primary.text.clone());
            labels.push(LabeledSpan::new_primary_with_span(text, to_span(primary.span)));
            for l in &d.secondary {
                if l.span.file == primary.span.file {
                    let text = (!l.text.is_empty()).then(|| l.text.clone());
                    labels.push(LabeledSpan::new_with_span(text, to_span(l.span)));
                } else if let Some(p) = place(sources, l.span) {
                    footer_lines.push(format!("{}:{}:{}: {}", p.file, p.line, p.column, l.text));
                }
            }
        }
    }
    for n in &d.notes {
        footer_lines.push(format!("note: {n}"));
    }
    let footer = (!footer_lines.is_empty()).then(|| footer_lines.join("\n"));
    Report { diagnostic: d, source, labels, footer }
}

/// Draws diagnostics the way people read them, with the source lines and labels.
pub fn render_human(
    sources: &SourceMap,
    diagnostics: &[Diagnostic],
    options: HumanOptions,
) -> String {
    let theme =
        if options.color { GraphicalTheme::unicode() } else { GraphicalTheme::unicode_nocolor() };
    let handler =
        GraphicalReportHandler::new_themed(theme).with_width(options.width).with_links(false);
    let mut out = String::new();
    for d in diagnostics {
        let r = report(sources, d);
        if handler.render_report(&mut out, &r).is_err() {
            let _ = writeln!(out, "{}[{}]: {}", d.severity.as_str(), d.code.as_str(), d.message);
        }
    }
    out
}

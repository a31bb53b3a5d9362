use super::place;
use crate::diag::{Diagnostic, Severity};
use crate::source::SourceMap;
use miette::{GraphicalReportHandler, GraphicalTheme, LabeledSpan, NamedSource, SourceSpan};
use std::fmt;
use std::fmt::Write as _;
use std::sync::Arc;

use crate::diag::visible;

/// The texts excerpts are drawn from, one per file and render (a file's text is shared by all
/// its diagnostics, never copied for each).
type Texts = std::collections::HashMap<crate::source::FileId, Arc<String>>;

/// A source text with every control character but line breaks and tabs replaced by a
/// character of the same length in bytes (`?` for one byte, `¿` for the two of a C1 control),
/// so that byte offsets stay valid and an excerpt cannot drive the terminal.
fn terminal_safe(text: &str) -> String {
    if !text.chars().any(|c| c.is_control() && !matches!(c, '\n' | '\t' | '\r')) {
        return text.to_string();
    }
    text.chars()
        .map(|c| match c {
            '\n' | '\t' | '\r' => c,
            c if c.is_control() && c.len_utf8() == 1 => '?',
            c if c.is_control() => '¿',
            c => c,
        })
        .collect()
}

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

/// How many lines from the main label a secondary label may be and still be drawn in the
/// excerpt; farther ones are listed under it with their line and column.
const NEAR_LINES: usize = 6;

/// A main label over more lines than this is drawn on its first line only.
const LONG_LABEL_LINES: usize = 10;

/// A diagnostic on a line longer than this (a house written on one line) names its place
/// instead of drawing the line: drawing it would copy the whole line into every diagnostic
/// (32 MB each for the largest house `export` reads).
const LONG_LINE_BYTES: usize = 4096;

/// A diagnostic paired with its source, in the shape miette renders.
struct Report<'a> {
    diagnostic: &'a Diagnostic,
    source: Option<NamedSource<Arc<String>>>,
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
        f.write_str(&visible(&self.diagnostic.message))
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
            (Some(h), None) => Some(Box::new(visible(h).into_owned())),
            (None, Some(f)) => Some(Box::new(visible(f).into_owned())),
            (Some(h), Some(f)) => Some(Box::new(visible(&format!("{h}\n{f}")).into_owned())),
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

fn report<'a>(sources: &SourceMap, texts: &mut Texts, d: &'a Diagnostic) -> Report<'a> {
    let mut footer_lines: Vec<String> = Vec::new();
    let mut labels = Vec::new();
    let mut source = None;
    if let Some(primary) = &d.primary {
        let long_line = sources
            .try_get(primary.span.file)
            .is_some_and(|file| file.line_len_at(primary.span.start as usize) > LONG_LINE_BYTES);
        if long_line {
            for l in std::iter::once(primary).chain(&d.secondary) {
                if let Some(p) = place(sources, l.span) {
                    let what = if l.text.is_empty() { "here" } else { l.text.as_str() };
                    footer_lines.push(
                        visible(&format!("{}:{}:{}: {what}", p.file, p.line, p.column))
                            .into_owned(),
                    );
                }
            }
            footer_lines
                .push(format!("(a line of more than {LONG_LINE_BYTES} bytes is not drawn)"));
        } else if let Some(file) = sources.try_get(primary.span.file) {
            let text = texts
                .entry(primary.span.file)
                .or_insert_with(|| Arc::new(terminal_safe(&file.text)))
                .clone();
            source = Some(NamedSource::new(visible(&file.name), text));
            let to_span = |s: crate::source::Span| SourceSpan::from((s.start as usize, s.len()));
            let line_of = |offset: u32| file.line_col(offset as usize).line;
            // A label over a whole block points at its first line (the header): the excerpt
            // stays a few lines long however long the block is.
            let mut head = primary.span;
            let last_line = line_of(head.end.saturating_sub(1).max(head.start));
            if last_line > line_of(head.start) + LONG_LABEL_LINES {
                if let Some(i) = file.text[head.start as usize..head.end as usize].find('\n') {
                    footer_lines.push(format!("(the marked text runs on to line {last_line})"));
                    head.end = head.start + i as u32;
                }
            }
            let text = (!primary.text.is_empty()).then(|| visible(&primary.text).into_owned());
            labels.push(LabeledSpan::new_primary_with_span(text, to_span(head)));
            let primary_line = line_of(head.start);
            for l in &d.secondary {
                // Places far from the main one are named, not drawn: an excerpt between them
                // would show every line in between.
                let near = l.span.file == primary.span.file
                    && line_of(l.span.start).abs_diff(primary_line) <= NEAR_LINES;
                if near {
                    let mut span = l.span;
                    if line_of(span.end.saturating_sub(1).max(span.start))
                        > line_of(span.start) + LONG_LABEL_LINES
                    {
                        if let Some(i) =
                            file.text[span.start as usize..span.end as usize].find('\n')
                        {
                            span.end = span.start + i as u32;
                        }
                    }
                    let text = (!l.text.is_empty()).then(|| visible(&l.text).into_owned());
                    labels.push(LabeledSpan::new_with_span(text, to_span(span)));
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
    let mut texts = Texts::new();
    for d in diagnostics {
        let r = report(sources, &mut texts, d);
        // A diagnostic the renderer cannot draw (miette has panicked on odd spans) is printed
        // plainly: one bad excerpt never costs the user the other diagnostics.
        DRAWING.with(|f| f.set(true));
        let drawn = std::panic::catch_unwind(std::panic::AssertUnwindSafe(|| {
            let mut text = String::new();
            handler.render_report(&mut text, &r).map(|()| text)
        }));
        DRAWING.with(|f| f.set(false));
        match drawn {
            Ok(Ok(text)) => out.push_str(&text),
            _ => {
                let _ = writeln!(
                    out,
                    "{}[{}]: {}",
                    d.severity.as_str(),
                    d.code.as_str(),
                    visible(&d.message)
                );
                if let Some(p) = d.primary.as_ref().and_then(|l| place(sources, l.span)) {
                    let _ = writeln!(out, "  at {}:{}:{}", visible(p.file), p.line, p.column);
                }
                if let Some(help) = &d.help {
                    let _ = writeln!(out, "  help: {}", visible(help));
                }
            }
        }
    }
    out
}

thread_local! {
    /// Set while a diagnostic is drawn, so that the program's panic hook stays quiet about a
    /// panic the renderer catches.
    static DRAWING: std::cell::Cell<bool> = const { std::cell::Cell::new(false) };
}

/// Whether this thread is drawing a diagnostic (a panic now is caught and drawn plainly).
pub fn is_drawing() -> bool {
    DRAWING.with(std::cell::Cell::get)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::diag::{Code, Diagnostic};
    use crate::source::Span;

    /// A diagnostic on a house written on one line names its place and does not copy the line
    /// (the largest house `export` reads is one line of 32 MB, with a diagnostic per object).
    #[test]
    fn a_diagnostic_on_a_long_line_names_its_place_without_drawing_it() {
        let mut sources = SourceMap::new();
        let line = format!("{{\"objects\": [{}]}}", "{\"id\": \"bed\"},".repeat(2_000));
        let file = sources.add("house.json", line.clone());
        let at = line.find("bed").expect("there");
        let d = Diagnostic::new(Code::W0608, "floor object `bed` overlaps 1 floor object")
            .with_primary(Span::new(file, at, at + 3), "overlaps `bed-1`");
        let text = render_human(&sources, &[d], HumanOptions { color: false, width: 80 });
        assert!(text.contains("house.json:1:22: overlaps `bed-1`"), "{text}");
        assert!(text.contains("is not drawn"), "{text}");
        assert!(text.len() < 1_000, "{} bytes:\n{text}", text.len());
        // A short line is drawn as before.
        let mut sources = SourceMap::new();
        let file = sources.add("house.json", "{\"id\": \"bed\"}\n".to_string());
        let d = Diagnostic::new(Code::W0608, "floor object `bed` overlaps 1 floor object")
            .with_primary(Span::new(file, 8, 11), "overlaps `bed-1`");
        let text = render_human(&sources, &[d], HumanOptions { color: false, width: 80 });
        assert!(text.contains("1 │ {\"id\": \"bed\"}"), "{text}");
    }
}

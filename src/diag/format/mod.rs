//! Printing diagnostics: `human` (miette), `short` (one line each) and `json`.

mod human;
mod json;
mod short;

pub use human::{is_drawing, render_human, HumanOptions};
pub use json::render_json;
pub use short::render_short;

use crate::source::{SourceMap, Span};

/// Where a span lies, for people: file name, 1-based line and column of both ends.
pub(crate) struct Place<'a> {
    pub file: &'a str,
    pub line: usize,
    pub column: usize,
    pub end_line: usize,
    pub end_column: usize,
}

pub(crate) fn place(sources: &SourceMap, span: Span) -> Option<Place<'_>> {
    let file = sources.try_get(span.file)?;
    let start = file.line_col(span.start as usize);
    let end = file.line_col(span.end as usize);
    Some(Place {
        file: &file.name,
        line: start.line,
        column: start.column,
        end_line: end.line,
        end_column: end.column,
    })
}

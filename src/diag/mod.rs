//! Diagnostics: what every stage reports, as data.
//!
//! A [`Diagnostic`] has a [`Code`] (its stage, its name and its page in the book), a severity, a
//! message, a primary [`Label`], secondary labels, at most one help sentence and notes. Stages
//! build them from their own error facts in one place per stage (`<stage>/errors.rs`). Only
//! [`mod@format`] and [`lsp`] know how they are printed or serialized.

pub mod codes;
pub mod format;
pub mod lsp;
pub mod suggest;

pub use codes::Code;

use crate::source::Span;

/// How serious a diagnostic is.
#[derive(Clone, Copy, Debug, PartialEq, Eq, PartialOrd, Ord, Hash)]
pub enum Severity {
    /// The input cannot be used as it is; the stage's output must not be trusted.
    Error,
    /// Something was interpreted or left out; the output is still usable.
    Warning,
    /// Extra information.
    Note,
}

impl Severity {
    /// The lower-case word used in every output format.
    pub fn as_str(self) -> &'static str {
        match self {
            Severity::Error => "error",
            Severity::Warning => "warning",
            Severity::Note => "note",
        }
    }
}

/// A span with a short phrase that explains it.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct Label {
    /// Where.
    pub span: Span,
    /// What about it (may be empty).
    pub text: String,
}

impl Label {
    /// Makes a label.
    pub fn new(span: Span, text: impl Into<String>) -> Label {
        Label { span, text: text.into() }
    }
}

/// One problem found in the input.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct Diagnostic {
    /// The error code; it decides the default severity and the book page.
    pub code: Code,
    /// Error, warning or note.
    pub severity: Severity,
    /// What is wrong, lower-case, no final period.
    pub message: String,
    /// The main place; `None` only for diagnostics about no file at all (CLI, I/O).
    pub primary: Option<Label>,
    /// Every other place involved.
    pub secondary: Vec<Label>,
    /// One sentence of action.
    pub help: Option<String>,
    /// Further facts.
    pub notes: Vec<String>,
    /// Edits that fix it (an editor offers them as code actions; `holoc repair --write`
    /// applies the repair's).
    pub fixes: Vec<Fix>,
}

/// A text edit that fixes a diagnostic.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct Fix {
    /// What it does, in a few words.
    pub title: String,
    /// The text replaced.
    pub span: Span,
    /// The new text.
    pub replacement: String,
}

impl Diagnostic {
    /// A diagnostic with the code's default severity and no labels yet.
    pub fn new(code: Code, message: impl Into<String>) -> Diagnostic {
        Diagnostic {
            code,
            severity: code.severity(),
            message: message.into(),
            primary: None,
            secondary: Vec::new(),
            help: None,
            notes: Vec::new(),
            fixes: Vec::new(),
        }
    }

    /// Adds "did you mean" help for a string literal at `span` (quotes included) that names
    /// nothing, with one fix per candidate near `written`.
    #[must_use]
    pub fn with_quoted_suggestions<'a>(
        self,
        span: crate::source::Span,
        written: &str,
        names: impl IntoIterator<Item = &'a str>,
    ) -> Diagnostic {
        let close = suggest::closest(written, names);
        self.with_help_opt(suggest::did_you_mean(&close))
            .with_fixes(suggest::quoted_replacements(span, &close))
    }

    /// Adds fixes.
    #[must_use]
    pub fn with_fixes(mut self, fixes: impl IntoIterator<Item = Fix>) -> Diagnostic {
        self.fixes.extend(fixes);
        self
    }

    /// Sets the primary label.
    #[must_use]
    pub fn with_primary(mut self, span: Span, text: impl Into<String>) -> Diagnostic {
        self.primary = Some(Label::new(span, text));
        self
    }

    /// Adds a secondary label.
    #[must_use]
    pub fn with_secondary(mut self, span: Span, text: impl Into<String>) -> Diagnostic {
        self.secondary.push(Label::new(span, text));
        self
    }

    /// Sets the help sentence.
    #[must_use]
    pub fn with_help(mut self, help: impl Into<String>) -> Diagnostic {
        self.help = Some(help.into());
        self
    }

    /// Sets the help sentence if there is one.
    #[must_use]
    pub fn with_help_opt(mut self, help: Option<String>) -> Diagnostic {
        if help.is_some() {
            self.help = help;
        }
        self
    }

    /// Adds a note.
    #[must_use]
    pub fn with_note(mut self, note: impl Into<String>) -> Diagnostic {
        self.notes.push(note.into());
        self
    }

    /// Adds a fix.
    #[must_use]
    pub fn with_fix(mut self, fix: Fix) -> Diagnostic {
        self.fixes.push(fix);
        self
    }

    /// Whether this is an error.
    pub fn is_error(&self) -> bool {
        self.severity == Severity::Error
    }

    /// An internal error: a bug in holoc, reported as a diagnostic rather than a panic.
    pub fn internal(what: impl Into<String>) -> Diagnostic {
        Diagnostic::new(Code::E0002, format!("internal error: {}", what.into())).with_help(format!(
            "this is a bug in holoc {}; please report it with the command line and input",
            env!("CARGO_PKG_VERSION")
        ))
    }
}

/// A stage's result: a value (possibly partial) and everything the stage reported.
#[derive(Clone, Debug)]
pub struct Outcome<T> {
    /// The value, possibly partial when there are errors.
    pub value: T,
    /// Every diagnostic, in the order found.
    pub diagnostics: Vec<Diagnostic>,
}

impl<T> Outcome<T> {
    /// Wraps a value with its diagnostics.
    pub fn new(value: T, diagnostics: Vec<Diagnostic>) -> Outcome<T> {
        Outcome { value, diagnostics }
    }

    /// Whether any diagnostic is an error.
    pub fn has_errors(&self) -> bool {
        self.diagnostics.iter().any(Diagnostic::is_error)
    }

    /// Maps the value, keeping the diagnostics.
    pub fn map<U>(self, f: impl FnOnce(T) -> U) -> Outcome<U> {
        Outcome { value: f(self.value), diagnostics: self.diagnostics }
    }
}

/// Sorts diagnostics by file and position (stable for equal positions), the order every output
/// format uses.
pub fn sort(diagnostics: &mut [Diagnostic]) {
    diagnostics
        .sort_by_key(|d| d.primary.as_ref().map(|l| (l.span.file, l.span.start, l.span.end)));
}

/// The most diagnostics of one file that `human` and `short` output print and that the language
/// server publishes for one document; the rest are counted in a closing line (`json` and `lsp`
/// output list them all). Pairwise checks summarise past [`PAIR_DETAIL_LIMIT`] pairs, so that
/// the number of diagnostics stays linear in the input.
pub const MAX_SHOWN_PER_FILE: usize = 100;

/// The most pairs (rooms that overlap, floor objects that overlap) a pairwise check reports one
/// by one; past it, each room or object gets one diagnostic with the number of others.
pub const PAIR_DETAIL_LIMIT: usize = 32;

/// Keeps the first `max` diagnostics of each file (in the order given; diagnostics without a
/// place count as one file) and returns how many were left out.
pub fn cap_per_file(diagnostics: &mut Vec<Diagnostic>, max: usize) -> usize {
    let mut seen: std::collections::HashMap<Option<crate::source::FileId>, usize> =
        std::collections::HashMap::new();
    let before = diagnostics.len();
    diagnostics.retain(|d| {
        let n = seen.entry(d.primary.as_ref().map(|l| l.span.file)).or_insert(0);
        *n += 1;
        *n <= max
    });
    before - diagnostics.len()
}

/// Text safe to print on a terminal: every control character but a line break and a tab is
/// written as an escape (`\u{1b}`), so that a name in a file cannot move the cursor, set the
/// window title or hide what follows.
pub fn visible(text: &str) -> std::borrow::Cow<'_, str> {
    if !text.chars().any(|c| c.is_control() && c != '\n' && c != '\t') {
        return std::borrow::Cow::Borrowed(text);
    }
    let mut out = String::with_capacity(text.len() + 8);
    for c in text.chars() {
        if c.is_control() && c != '\n' && c != '\t' {
            out.push_str(&c.escape_unicode().to_string());
        } else {
            out.push(c);
        }
    }
    std::borrow::Cow::Owned(out)
}

/// The text of `file` with the fixes of `diagnostics` that edit it applied (last first, so
/// that spans stay valid); a fix that overlaps one already applied, or whose span is not in the
/// text, is skipped.
pub fn apply_fixes(text: &str, file: crate::source::FileId, diagnostics: &[Diagnostic]) -> String {
    let mut fixes: Vec<_> =
        diagnostics.iter().flat_map(|d| &d.fixes).filter(|f| f.span.file == file).collect();
    fixes.sort_by_key(|f| std::cmp::Reverse(f.span.start));
    let mut out = text.to_string();
    let mut last_start = usize::MAX;
    for f in fixes {
        let (start, end) = (f.span.start as usize, f.span.end as usize);
        if end > last_start
            || end > out.len()
            || start > end
            || !out.is_char_boundary(start)
            || !out.is_char_boundary(end)
        {
            continue; // overlapping or stale edit
        }
        out.replace_range(start..end, &f.replacement);
        last_start = start;
    }
    out
}

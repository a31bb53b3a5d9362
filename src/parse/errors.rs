//! Diagnostics of the parse stage, made from bad lines and pest errors.

use super::grammar::{HoloParser, Rule};
use super::Context;
use crate::diag::{suggest, Code, Diagnostic};
use crate::source::{FileId, Span};
use pest::error::{ErrorVariant, InputLocation};
use pest::Parser as _;

/// The statements that may start a line of each block, with the form shown in help texts.
fn statements(context: Context) -> &'static [(&'static str, &'static str)] {
    match context {
        Context::Top => &[
            ("scene", "scene \"a cozy bedroom\" { wall height 2.7 m }"),
            ("room", "room bedroom \"bedroom\" { ... }"),
            ("door", "door exterior -- bedroom : doorway single \"white wooden door\""),
        ],
        Context::Scene => &[
            ("wall", "wall height 2.7 m"),
            ("seed", "seed 42"),
            ("ceiling", "ceiling \"white plaster\"  or  ceiling material \"EggshellDrywall\""),
        ],
        Context::Room => &[
            ("floor", "floor \"oak parquet\"  or  floor material \"WoodFloorsCross\""),
            ("walls", "walls \"white plaster\""),
            ("wall", "wall material \"PureWhite\"  or  wall object painting \"painting\" { ... }"),
            ("corners", "corners in m (0, 0) (0, 4) (5, 4) (5, 0)"),
            ("window", "window north fixed 150 cm x 120 cm, count 1, sill 90 cm"),
            ("object", "object sofa \"sofa\" { ... }"),
            ("ceiling", "ceiling \"flush mount light\""),
        ],
        Context::Object => &[
            ("describe", "describe \"grey fabric sofa\""),
            ("size", "size 200 cm x 90 cm x 80 cm"),
            ("count", "count 2 varied"),
            ("asset", "asset \"Sofa_1\""),
            ("on", "on top \"book\" x2 varied"),
            ("instance", "instance chair-1 { near table-0 }"),
            ("above", "above sofa-0"),
            ("height", "height 160 cm"),
            ("at", "at 2 m, 3 m"),
            ("facing", "facing 90 deg"),
            ("edge", "edge"),
            ("middle", "middle"),
            ("near", "near sofa-0"),
            ("far", "far sofa-0"),
            ("in", "in front of sofa-0"),
            ("behind", "behind desk-0"),
            ("side", "side of bed-0"),
            ("left", "left of bed-0"),
            ("right", "right of bed-0"),
            ("around", "around table-0"),
            ("center", "center aligned sofa-0"),
            ("face", "face to sofa-0  or  face same as sofa-0"),
        ],
    }
}

/// Whole phrases of the object block, for suggestions on a misspelt constraint.
const PHRASES: &[&str] = &[
    "describe",
    "size",
    "count",
    "asset",
    "on top",
    "instance",
    "above",
    "height",
    "at",
    "facing",
    "edge",
    "middle",
    "near",
    "far",
    "in front of",
    "behind",
    "side of",
    "left of",
    "right of",
    "around",
    "center aligned",
    "face to",
    "face same as",
];

fn block_name(context: Context) -> &'static str {
    match context {
        Context::Top => "the top level",
        Context::Scene => "a scene block",
        Context::Room => "a room block",
        Context::Object => "an object block",
    }
}

fn alone_rule(context: Context) -> Rule {
    match context {
        Context::Top => Rule::item_alone,
        Context::Scene => Rule::scene_stmt_alone,
        Context::Room => Rule::room_stmt_alone,
        Context::Object => Rule::object_stmt_alone,
    }
}

/// Words for grammar rules, as they appear in "expected ..." messages.
fn describe_rule(rule: Rule) -> Option<&'static str> {
    Some(match rule {
        Rule::quantity | Rule::number | Rule::quantity_nows => "a number",
        Rule::unit | Rule::corners_unit => "a unit (`m`, `cm` or `deg`)",
        Rule::string | Rule::string_inner => "a string in double quotes",
        Rule::ident => "a name",
        Rule::word | Rule::door_size => "a word",
        Rule::point => "a corner such as `(0 m, 0 m)`",
        Rule::object_block => "a `{` block",
        Rule::trailing_comment => "a comment",
        Rule::relation => "a constraint",
        Rule::on_top_count => "a count such as `x2`",
        Rule::window_count | Rule::window_sill | Rule::window_asset => {
            "`count`, `sill` or `asset` after a comma"
        }
        Rule::door_asset => "`asset \"...\"`",
        _ => return None,
    })
}

/// Finds a string problem in a line: an unterminated string or an unknown escape.
fn string_problem(line: &str) -> Option<(usize, usize, &'static str, &'static str)> {
    let bytes = line.as_bytes();
    let mut i = 0;
    while i < bytes.len() {
        if bytes[i..].starts_with(b"//") {
            return None;
        }
        if bytes[i] == b'"' {
            let start = i;
            i += 1;
            loop {
                if i >= bytes.len() || bytes[i] == b'\n' {
                    return Some((
                        start,
                        i,
                        "this string has no closing quote",
                        "add a `\"` at the end of the text",
                    ));
                }
                if bytes[i] == b'\\' {
                    let next = bytes.get(i + 1).copied();
                    if !matches!(next, Some(b'"' | b'\\' | b'n' | b't' | b'u')) {
                        return Some((
                            i,
                            (i + 2).min(bytes.len()),
                            "unknown escape",
                            "write `\\\\` for a backslash; the escapes are \\\" \\\\ \\n \\t \\u{...}",
                        ));
                    }
                    i += 2;
                    continue;
                }
                if bytes[i] == b'"' {
                    break;
                }
                i += 1;
            }
        }
        i += 1;
    }
    None
}

/// The diagnostic for a line that no statement of its block matches.
pub(super) fn bad_line(file: FileId, offset: usize, line: &str, context: Context) -> Diagnostic {
    if let Some((start, end, label, help)) = string_problem(line) {
        let message = if label == "unknown escape" {
            "unknown escape in a string".to_string()
        } else {
            "unterminated string".to_string()
        };
        return Diagnostic::new(Code::E0104, message)
            .with_primary(Span::new(file, offset + start, offset + end), label)
            .with_help(help);
    }
    let trimmed = line.trim_end();
    let first: String =
        trimmed.chars().take_while(|c| c.is_alphanumeric() || *c == '_' || *c == '-').collect();
    let table = statements(context);
    let known = table.iter().find(|(kw, _)| *kw == first);
    match known {
        Some((keyword, form)) => {
            let rule = alone_rule(context);
            match HoloParser::parse(rule, trimmed) {
                Err(error) => {
                    let mut d = from_pest(file, offset, &error, context, trimmed);
                    d.message = format!("malformed `{keyword}` statement: {}", d.message);
                    // A relation of several words misspelt after its first (`in frnt of`).
                    let phrases: Vec<String> = PHRASES
                        .iter()
                        .filter(|p| {
                            context == Context::Object && p.starts_with(&format!("{keyword} "))
                        })
                        .map(|p| (*p).to_string())
                        .collect();
                    d.with_help(format!("write it as `{form}`"))
                        .with_fixes(phrase_fixes(file, offset, trimmed, &phrases))
                }
                Ok(_) => Diagnostic::new(Code::E0101, format!("malformed `{keyword}` statement"))
                    .with_primary(Span::new(file, offset, offset + trimmed.len()), "")
                    .with_help(format!("write it as `{form}`")),
            }
        }
        None => {
            let words: Vec<&str> = trimmed.split_whitespace().collect();
            let head =
                if first.is_empty() { trimmed.chars().take(20).collect() } else { first.clone() };
            let mut candidates: Vec<&str> = table.iter().map(|(kw, _)| *kw).collect();
            if context == Context::Object {
                candidates = PHRASES.to_vec();
            }
            let mut suggestions = suggest::closest(&head, candidates.iter().copied());
            // A one-word suggestion for the first word can replace it in place.
            let word_fixes: Vec<String> = if first.is_empty() {
                Vec::new()
            } else {
                suggestions.iter().filter(|s| !s.contains(' ')).cloned().collect()
            };
            if words.len() >= 2 {
                let two = words[..2].join(" ");
                for s in suggest::closest(&two, candidates.iter().copied()) {
                    if !suggestions.contains(&s) {
                        suggestions.insert(0, s);
                    }
                }
                suggestions.truncate(3);
            }
            let head_end = offset + head.len().max(1).min(trimmed.len().max(1));
            let listed: Vec<String> = candidates.iter().map(|c| format!("`{c}`")).collect();
            Diagnostic::new(
                Code::E0102,
                format!("`{head}` does not start a statement of {}", block_name(context)),
            )
            .with_primary(Span::new(file, offset, head_end), "unknown statement")
            .with_help_opt(suggest::did_you_mean(&suggestions))
            .with_note(format!("{} takes: {}", block_name(context), listed.join(", ")))
            .with_fixes(suggest::replacements(
                Span::new(file, offset, offset + first.len()),
                &word_fixes,
            ))
            .with_fixes(phrase_fixes(file, offset, trimmed, &suggestions))
        }
    }
}

/// Fixes for suggestions of several words (`in front of` for `in frnt of desk-0`): each replaces
/// the first one to three words of the line, as many as read most like it.
fn phrase_fixes(
    file: FileId,
    offset: usize,
    line: &str,
    suggestions: &[String],
) -> Vec<crate::diag::Fix> {
    // The end of each of the line's first three words.
    let mut ends = Vec::new();
    let mut in_word = false;
    for (i, c) in line.char_indices() {
        if c.is_whitespace() {
            if in_word {
                ends.push(i);
            }
            in_word = false;
        } else {
            in_word = true;
        }
        if ends.len() == 3 {
            break;
        }
    }
    if in_word && ends.len() < 3 {
        ends.push(line.len());
    }
    let mut fixes = Vec::new();
    for phrase in suggestions.iter().filter(|s| s.contains(' ')) {
        let best = ends
            .iter()
            .map(|&end| {
                let words = line[..end].split_whitespace().collect::<Vec<_>>().join(" ");
                (strsim::normalized_damerau_levenshtein(&words.to_lowercase(), phrase), end)
            })
            .max_by(|a, b| a.0.total_cmp(&b.0).then(b.1.cmp(&a.1)));
        if let Some((score, end)) = best {
            let written = &line[..end];
            if score >= suggest::THRESHOLD && written != phrase.as_str() {
                fixes.extend(suggest::replacements(
                    Span::new(file, offset, offset + end),
                    std::slice::from_ref(phrase),
                ));
            }
        }
    }
    fixes
}

/// Turns a pest error (from the whole file or from one re-read line) into a diagnostic.
pub(super) fn from_pest(
    file: FileId,
    offset: usize,
    error: &pest::error::Error<Rule>,
    context: Context,
    text: &str,
) -> Diagnostic {
    let pos = match error.location {
        InputLocation::Pos(p) => p,
        InputLocation::Span((s, _)) => s,
    };
    let mut expected: Vec<&str> = match &error.variant {
        ErrorVariant::ParsingError { positives, .. } => {
            positives.iter().filter_map(|r| describe_rule(*r)).collect()
        }
        ErrorVariant::CustomError { .. } => Vec::new(),
    };
    expected.sort_unstable();
    expected.dedup();
    let found: String =
        text[pos.min(text.len())..].chars().take_while(|c| !c.is_whitespace()).take(20).collect();
    let end = pos + found.len().max(usize::from(pos < text.len()));
    let what = if expected.is_empty() {
        "unexpected text".to_string()
    } else {
        format!("expected {}", expected.join(" or "))
    };
    let message = if found.is_empty() {
        format!("{what} at the end of the line")
    } else {
        format!("{what}, found `{found}`")
    };
    let label = if expected.is_empty() { "not expected here".to_string() } else { what };
    let d = Diagnostic::new(Code::E0101, message)
        .with_primary(Span::new(file, offset + pos, offset + end.min(text.len())), label);
    if context == Context::Top && pos < text.len() && text[pos..].starts_with('}') {
        return d.with_help("this `}` closes no block; remove it");
    }
    d
}

/// The diagnostic for a block left open, when the text has one: braces are matched outside
/// strings and comments, and a `}` closes the block whose opening line is indented as it is
/// (so that `room a {` … `object c { edge` … `}` reports the object's `{`, not the room's). The
/// diagnostic points at the `{` that is never closed and at the place it should have been
/// closed: before the `}` that closed the enclosing block instead, or at the end of the file.
pub(crate) fn unclosed_brace(file: FileId, text: &str) -> Option<Diagnostic> {
    let indent_of = |at: usize| {
        let line_start = text[..at].rfind('\n').map_or(0, |i| i + 1);
        text[line_start..].chars().take_while(|c| *c == ' ' || *c == '\t').count()
    };
    // Open braces: (position, indentation of their line). The indentation of the current line
    // is kept as the scan goes, so that the scan stays linear.
    let mut open: Vec<(usize, usize)> = Vec::new();
    // The first brace found unclosed, and where its block should have ended.
    let mut unclosed: Option<(usize, usize)> = None;
    let bytes = text.as_bytes();
    let line_indent =
        |from: usize| bytes[from..].iter().take_while(|b| **b == b' ' || **b == b'\t').count();
    let mut indent = line_indent(0);
    let mut i = 0;
    while i < bytes.len() {
        match bytes[i] {
            b'\n' => indent = line_indent(i + 1),
            b'"' => {
                i += 1;
                while i < bytes.len() && bytes[i] != b'"' && bytes[i] != b'\n' {
                    i += if bytes[i] == b'\\' { 2 } else { 1 };
                }
                if bytes.get(i) == Some(&b'\n') {
                    indent = line_indent(i + 1);
                }
            }
            b'/' if bytes.get(i + 1) == Some(&b'/') => {
                while i < bytes.len() && bytes[i] != b'\n' {
                    i += 1;
                }
                if i < bytes.len() {
                    indent = line_indent(i + 1);
                }
            }
            b'{' => open.push((i, indent)),
            b'}' => {
                // Blocks opened deeper than this `}` and still open were never closed.
                while open.len() > 1 && open.last().is_some_and(|&(_, k)| k > indent) {
                    let (at, _) = open.pop().unwrap_or_default();
                    if unclosed.is_none() {
                        unclosed = Some((at, i));
                    }
                }
                open.pop();
            }
            _ => {}
        }
        i += 1;
    }
    let (at, should_close) = match (unclosed, open.first()) {
        (Some(found), _) => found,
        (None, Some(&(at, _))) => (open.last().map_or(at, |&(a, _)| a), text.len()),
        (None, None) => return None,
    };
    let header_start = text[..at].rfind('\n').map_or(0, |i| i + 1);
    let header: String = {
        let whole = text[header_start..at].trim();
        let short: String = whole.chars().take(40).collect();
        if short.len() < whole.len() {
            format!("{short}…")
        } else {
            short
        }
    };
    let mut d = Diagnostic::new(
        Code::E0101,
        format!(
            "`{}{{` is never closed",
            if header.is_empty() { String::new() } else { format!("{header} ") }
        ),
    )
    .with_primary(Span::new(file, at, at + 1), "this block is never closed");
    let close_at = if should_close >= text.len() {
        // At the end of the file: before the first later line indented no deeper than the
        // block's own line (the next statement of the enclosing block), else at the end.
        let own_indent = indent_of(at);
        let after_header = text[at..].find('\n').map_or(text.len(), |i| at + i + 1);
        let mut last_content_end = text[..after_header].trim_end().len();
        let mut found = None;
        let mut pos = after_header;
        for line in text[after_header..].split_inclusive('\n') {
            let trimmed = line.trim();
            let indent = line.len() - line.trim_start().len();
            if !trimmed.is_empty() && !trimmed.starts_with("//") {
                if indent <= own_indent && !trimmed.starts_with('}') {
                    found = Some(last_content_end);
                    break;
                }
                last_content_end = pos + line.trim_end().len();
            }
            pos += line.len();
        }
        found.unwrap_or_else(|| text.trim_end().len())
    } else {
        text[..should_close].rfind('\n').map_or(should_close, |i| i)
    };
    d = d.with_secondary(Span::new(file, close_at, close_at), "its `}` belongs here");
    Some(d.with_help("add the missing `}` where the block ends"))
}

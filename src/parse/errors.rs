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

/// A block left open: its diagnostic, and the text that closes it where it should have been
/// closed, for the parser to read the rest of the file as if it were there.
pub(crate) struct Unclosed {
    /// E0101 at the `{` never closed, with a label where its `}` belongs.
    pub diagnostic: Diagnostic,
    /// Where the closing text goes, in the text scanned.
    pub insert_at: usize,
    /// The closing text: a line break and a `}` indented as the block's first line.
    pub insert: String,
}

/// An open `{` while braces are matched.
struct OpenBrace {
    /// Its byte offset.
    at: usize,
    /// The indentation of its line.
    indent: usize,
    /// Whether a line of its body is indented deeper than its own line.
    deeper_body: bool,
}

/// The first block left open in a text, when it has one.
///
/// Braces are matched outside strings and comments, and indentation says where a block ended
/// when its `}` is missing: in a block whose body is indented deeper than its opening line, a
/// later line that starts a statement (not a `}`) indented no deeper than that opening line is
/// the block's next sibling, so the block ended before it; a `}` closes the block whose opening line is indented as it is
/// (so that `room a {` … `object c { edge` … `}` reports the object's `{`, not the room's); a
/// block so found, or left open at the end of the file, that is indented deeper than the block
/// around it ended before its first later line at its own indentation.
/// The diagnostic points at the `{` that is never closed and at the place it should have been
/// closed: after the last line of its body, before the next block at its indentation, before the
/// `}` that closed the enclosing block instead, or at the end of the file.
pub(crate) fn unclosed_brace(file: FileId, text: &str) -> Option<Unclosed> {
    let bytes = text.as_bytes();
    let line_indent =
        |from: usize| bytes[from..].iter().take_while(|b| **b == b' ' || **b == b'\t').count();
    let mut open: Vec<OpenBrace> = Vec::new();
    // The first brace found unclosed: its offset, its line's indentation, where the text of
    // the next block starts and what tells so.
    let mut unclosed: Option<(usize, usize, usize, Boundary)> = None;
    let mut indent = line_indent(0);
    let mut i = 0;
    // Whether `i` is at the first character of a line, after its indentation.
    let mut at_line_start = true;
    while i < bytes.len() {
        if at_line_start {
            at_line_start = false;
            i += indent;
            let rest = &text[i.min(text.len())..];
            let starts_statement = !rest.is_empty()
                && !rest.starts_with(['\n', '\r', '}', ';'])
                && !rest.starts_with("//")
                && !rest.starts_with("/*");
            if starts_statement {
                // A block opened on an earlier line at this indentation or deeper, whose body is
                // indented deeper than it, ended before this line.
                if let Some(top) = open.last() {
                    if top.deeper_body && indent <= top.indent {
                        let line_start = i - indent;
                        unclosed = Some((top.at, top.indent, line_start, Boundary::Sibling));
                        break;
                    }
                }
                if let Some(top) = open.last_mut() {
                    if indent > top.indent {
                        top.deeper_body = true;
                    }
                }
            }
            continue;
        }
        match bytes[i] {
            b'\n' => {
                indent = line_indent(i + 1);
                at_line_start = true;
            }
            b'"' => {
                i += 1;
                while i < bytes.len() && bytes[i] != b'"' && bytes[i] != b'\n' {
                    i += if bytes[i] == b'\\' { 2 } else { 1 };
                }
                if bytes.get(i) == Some(&b'\n') {
                    indent = line_indent(i + 1);
                    at_line_start = true;
                }
            }
            b'/' if bytes.get(i + 1) == Some(&b'/') => {
                while i < bytes.len() && bytes[i] != b'\n' {
                    i += 1;
                }
                if i < bytes.len() {
                    indent = line_indent(i + 1);
                    at_line_start = true;
                }
            }
            b'/' if bytes.get(i + 1) == Some(&b'*') => {
                let end = text[i + 2..].find("*/").map_or(bytes.len(), |close| i + 2 + close + 2);
                // A comment over several lines: what follows it is not a line start.
                i = end.saturating_sub(1);
            }
            b'{' => open.push(OpenBrace { at: i, indent, deeper_body: false }),
            b'}' => {
                // Blocks opened deeper than this `}` and still open were never closed.
                if let Some(top) = open.last().filter(|o| open.len() > 1 && o.indent > indent) {
                    unclosed = Some((top.at, top.indent, i, Boundary::Brace));
                    break;
                }
                open.pop();
            }
            _ => {}
        }
        i += 1;
    }
    let (at, indent, mut should_close, mut boundary) = match unclosed {
        Some(found) => found,
        None => {
            let last = open.last()?;
            (last.at, last.indent, text.len(), Boundary::End)
        }
    };
    // A block indented deeper than the block around it, whose body is not indented deeper than
    // itself (`object c { edge` then `corners …` at the object's indentation): now that it is
    // known to be left open, a later line at its indentation is still its next sibling.
    let parent_indent = open.len().checked_sub(2).map(|k| open[k].indent);
    if boundary != Boundary::Sibling && parent_indent.is_some_and(|p| indent > p) {
        if let Some(line_start) = first_line_at_or_above(text, at, should_close, indent) {
            should_close = line_start;
            boundary = Boundary::Sibling;
        }
    }
    let header_start = text[..at].rfind('\n').map_or(0, |i| i + 1);
    let header = short_line(&text[header_start..at]);
    // The `}` goes after the last line of the block's body (not on empty or comment lines).
    let close_at = last_content_end(text, at, should_close);
    let help = match boundary {
        Boundary::Sibling => {
            let line_end = text[should_close..].find('\n').map_or(text.len(), |n| should_close + n);
            let next = short_line(&text[should_close..line_end]);
            format!("add the missing `}}` before `{next}`")
        }
        Boundary::Brace => {
            "add the missing `}` before the `}` that closes the block around it".into()
        }
        Boundary::End => "add the missing `}` at the end of the file".into(),
    };
    let diagnostic = Diagnostic::new(
        Code::E0101,
        format!(
            "`{}{{` is never closed",
            if header.is_empty() { String::new() } else { format!("{header} ") }
        ),
    )
    .with_primary(Span::new(file, at, at + 1), "this block is never closed")
    .with_secondary(Span::new(file, close_at, close_at), "its `}` belongs here")
    .with_help(help);
    // On a line of its own, indented as the block's first line, so that the next scan matches it
    // to this block.
    let insert = format!("\n{}}}", " ".repeat(indent));
    Some(Unclosed { diagnostic, insert_at: close_at, insert })
}

/// The start of the first line after the line of `open` and before `before` that starts a
/// statement (not a `}`, an empty line or a comment) indented no deeper than `indent`.
fn first_line_at_or_above(text: &str, open: usize, before: usize, indent: usize) -> Option<usize> {
    let mut pos = text[open..].find('\n').map(|i| open + i + 1)?;
    while pos < before {
        let line_end = text[pos..].find('\n').map_or(text.len(), |n| pos + n + 1);
        let line = &text[pos..line_end.min(before)];
        let rest = line.trim_start_matches([' ', '\t']);
        let starts_statement = !rest.trim().is_empty()
            && !rest.starts_with(['}', ';'])
            && !rest.starts_with("//")
            && !rest.starts_with("/*");
        if starts_statement && line.len() - rest.len() <= indent {
            return Some(pos);
        }
        pos = line_end;
    }
    None
}

/// What tells where a block left open ended.
#[derive(Clone, Copy, PartialEq, Eq)]
enum Boundary {
    /// The next statement at the block's indentation.
    Sibling,
    /// A `}` that closes the block around it.
    Brace,
    /// The end of the file.
    End,
}

/// A line's text, trimmed and cut to 40 characters.
fn short_line(line: &str) -> String {
    let whole = line.trim();
    let short: String = whole.chars().take(40).collect();
    if short.len() < whole.len() {
        format!("{short}…")
    } else {
        short
    }
}

/// The end of the last line before `before` (and after the line of `open`) that holds more than
/// blanks and a comment; the end of `open`'s line when there is none.
fn last_content_end(text: &str, open: usize, before: usize) -> usize {
    let after_header = text[open..].find('\n').map_or(text.len(), |i| open + i + 1).min(before);
    let mut end = text[..after_header].trim_end().len().max(open + 1);
    let mut pos = after_header;
    while pos < before {
        let line_end = text[pos..].find('\n').map_or(text.len(), |n| pos + n + 1).min(before);
        let line = &text[pos..line_end];
        let trimmed = line.trim();
        if !trimmed.is_empty() && !trimmed.starts_with("//") && !trimmed.starts_with("/*") {
            end = pos + line.trim_end().len();
        }
        pos = line_end;
    }
    end
}

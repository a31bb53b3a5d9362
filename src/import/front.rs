//! The tolerant front shared by every stage: lines, decoration, fields and numbers.

use super::grammar::{LlmParser, Rule};
use super::Noise;
use crate::source::{FileId, Span};
use pest::Parser as _;

/// One line of an answer, decoration removed, with its place in the file.
#[derive(Clone, Debug)]
pub(crate) struct Line {
    /// The original line (without its line break).
    pub raw: String,
    /// Byte offset of the line in the file.
    pub start: usize,
    /// The content after decoration was removed; `*` and backticks are blanked, so byte
    /// offsets into `raw` stay valid: `content` starts at `raw[offset..]`.
    pub content: String,
    /// Offset of `content` inside `raw`.
    pub offset: usize,
    /// The file.
    pub file: FileId,
}

impl Line {
    /// The span of the whole line.
    pub fn span(&self) -> Span {
        Span::new(self.file, self.start, self.start + self.raw.len())
    }

    /// The span of a byte range of `content`.
    pub fn sub(&self, from: usize, to: usize) -> Span {
        let base = self.start + self.offset;
        Span::new(self.file, base + from, base + to)
    }

    /// Splits the content on `|` into trimmed fields with their spans. Empty outer fields
    /// from a table border (`| a | b |`) are dropped.
    pub fn fields(&self) -> Vec<Field> {
        let mut out = Vec::new();
        let mut at = 0;
        for piece in self.content.split('|') {
            let lead = piece.len() - piece.trim_start().len();
            let text = piece.trim();
            let from = at + lead;
            out.push(Field { text: text.to_string(), span: self.sub(from, from + text.len()) });
            at += piece.len() + 1;
        }
        if out.len() > 1 && out.first().is_some_and(|f| f.text.is_empty()) {
            out.remove(0);
        }
        if out.len() > 1 && out.last().is_some_and(|f| f.text.is_empty()) {
            out.pop();
        }
        out
    }

    /// The line as a `// raw <stage>: ...` comment text.
    pub fn raw_comment(&self, stage: &str) -> String {
        raw_comment(stage, &self.raw)
    }
}

/// A comment holding a raw line, made safe to print on one line.
pub(crate) fn raw_comment(stage: &str, raw: &str) -> String {
    let clean: String =
        raw.chars().map(|c| if c.is_control() { ' ' } else { c }).take(300).collect();
    let clean = clean.trim_end();
    if clean.is_empty() {
        // No trailing space: the formatter would remove it, and the output must be canonical.
        format!("// raw {stage}:")
    } else {
        format!("// raw {stage}: {clean}")
    }
}

/// A `|`-separated field.
#[derive(Clone, Debug)]
pub(crate) struct Field {
    /// The trimmed text.
    pub text: String,
    /// Where it is.
    pub span: Span,
}

impl Field {
    /// Whether the field says "not applicable".
    pub fn is_na(&self) -> bool {
        is_na(&self.text)
    }
}

/// Lower-cases and collapses white space.
pub(crate) fn norm(text: &str) -> String {
    text.split_whitespace().collect::<Vec<_>>().join(" ").to_lowercase()
}

/// `N/A`, `n/a`, `NA`, `none`, `-`, empty.
pub(crate) fn is_na(text: &str) -> bool {
    let t = norm(text);
    let t = t.trim_end_matches('.');
    matches!(t, "n/a" | "na" | "none" | "-" | "" | "null" | "n.a")
}

/// What was removed from the lines of an answer.
pub(crate) struct Lines {
    /// The lines that may hold content.
    pub lines: Vec<Line>,
    /// The noise seen, with the first place it was seen and how often.
    pub noise: Vec<(Noise, Span, usize)>,
}

impl Lines {
    fn note(&mut self, noise: Noise, span: Span) {
        if let Some(entry) = self.noise.iter_mut().find(|(n, _, _)| *n == noise) {
            entry.2 += 1;
        } else {
            self.noise.push((noise, span, 1));
        }
    }
}

/// The lines of a text with the byte offset of each: `\n`, `\r\n` and a lone `\r` (old Mac
/// line ends, which some servers send) each end a line.
pub(crate) fn split_lines(text: &str) -> Vec<(usize, &str)> {
    let bytes = text.as_bytes();
    let mut out = Vec::new();
    let mut start = 0;
    let mut i = 0;
    while i < bytes.len() {
        match bytes[i] {
            b'\n' => {
                out.push((start, &text[start..i]));
                start = i + 1;
            }
            b'\r' => {
                out.push((start, &text[start..i]));
                if bytes.get(i + 1) == Some(&b'\n') {
                    i += 1;
                }
                start = i + 1;
            }
            _ => {}
        }
        i += 1;
    }
    out.push((start, &text[start..]));
    out
}

/// Splits an answer into lines, removes decoration, and drops blank lines, code fences and
/// (when `pipe` is set) lines without a `|`, noting each kind of noise once.
pub(crate) fn lines(text: &str, file: FileId, pipe: bool) -> Lines {
    let mut out = Lines { lines: Vec::new(), noise: Vec::new() };
    for (line_start, raw) in split_lines(text) {
        let span = Span::new(file, line_start, line_start + raw.len());
        let trimmed = raw.trim();
        if trimmed.is_empty() {
            continue;
        }
        if trimmed.starts_with("```") || trimmed.starts_with("~~~") {
            out.note(Noise::CodeFence, span);
            continue;
        }
        if pipe && !raw.contains('|') {
            out.note(Noise::Prose, span);
            continue;
        }
        // Markdown table separator rows `|---|---|`.
        if pipe && trimmed.chars().all(|c| matches!(c, '|' | '-' | ':' | ' ' | '\t')) {
            out.note(Noise::Prose, span);
            continue;
        }
        let mut offset = 0;
        if let Ok(mut pairs) = LlmParser::parse(Rule::line_prefix, raw) {
            if let Some(prefix) = pairs.next() {
                for inner in prefix.clone().into_inner() {
                    match inner.as_rule() {
                        Rule::numbering => out.note(Noise::Numbering, span),
                        Rule::bullet => out.note(Noise::Bullet, span),
                        Rule::heading => out.note(Noise::Heading, span),
                        _ => {}
                    }
                }
                offset = prefix.as_str().len();
            }
        }
        let mut content: String = raw[offset..].to_string();
        if content.contains('*') || content.contains('`') {
            out.note(Noise::Bold, span);
            content = content.replace(['*', '`'], " ");
        }
        // Trailing period (not part of a number) is blanked.
        let t = content.trim_end();
        if t.ends_with('.') && !t.ends_with("..") {
            out.note(Noise::TrailingPeriod, span);
            let at = t.len() - 1;
            content.replace_range(at..=at, " ");
        }
        out.lines.push(Line { raw: raw.to_string(), start: line_start, content, offset, file });
    }
    out
}

/// A number read from an answer, with the unit it was written with.
#[derive(Clone, Copy, Debug, PartialEq)]
pub(crate) struct Num {
    /// The value.
    pub value: f64,
    /// The unit, normalised: `m`, `cm`, `mm`, `deg`.
    pub unit: Option<&'static str>,
    /// Whether it was written with a decimal comma.
    pub comma: bool,
}

fn unit_of(text: &str) -> Option<&'static str> {
    let t = text.to_lowercase();
    Some(match t.as_str() {
        "cm" | "centimeter" | "centimeters" | "centimetre" | "centimetres" => "cm",
        "mm" | "millimeters" | "millimetres" => "mm",
        "m" | "meter" | "meters" | "metre" | "metres" => "m",
        "deg" | "degree" | "degrees" | "°" => "deg",
        _ => return None,
    })
}

fn quantity_of(pair: pest::iterators::Pair<'_, Rule>) -> Option<Num> {
    let comma = pair.as_rule() == Rule::comma_quantity;
    let mut value = None;
    let mut unit = None;
    for inner in pair.into_inner() {
        match inner.as_rule() {
            Rule::number => value = inner.as_str().parse::<f64>().ok(),
            Rule::comma_number => value = inner.as_str().replace(',', ".").parse::<f64>().ok(),
            Rule::unit => unit = unit_of(inner.as_str()),
            _ => {}
        }
    }
    let value = value?;
    value.is_finite().then_some(Num { value, unit, comma })
}

/// Reads a field that is one number with an optional unit.
pub(crate) fn number(text: &str) -> Option<Num> {
    let pairs = LlmParser::parse(Rule::quantity_field, text.trim()).ok()?;
    let field = pairs.into_iter().next()?;
    let q = field
        .into_inner()
        .find(|p| matches!(p.as_rule(), Rule::quantity | Rule::comma_quantity))?;
    quantity_of(q)
}

/// Reads a vertex list; `None` when it is not one.
pub(crate) fn vertex_list(text: &str) -> Option<Vec<(Num, Num)>> {
    let pairs = LlmParser::parse(Rule::vertex_list, text.trim()).ok()?;
    let list = pairs.into_iter().next()?;
    let mut out = Vec::new();
    for vertex in list.into_inner().filter(|p| p.as_rule() == Rule::vertex) {
        let mut qs = vertex.into_inner().filter_map(quantity_of);
        let x = qs.next()?;
        let z = qs.next()?;
        out.push((x, z));
    }
    Some(out)
}

/// Reads a `(w, h)` size pair; the unit after the pair applies to both.
pub(crate) fn size_pair(text: &str) -> Option<(Num, Num)> {
    let pairs = LlmParser::parse(Rule::size_pair, text.trim()).ok()?;
    let pair = pairs.into_iter().next()?;
    let mut nums = Vec::new();
    let mut unit = None;
    for inner in pair.into_inner() {
        match inner.as_rule() {
            Rule::quantity => nums.push(quantity_of(inner)?),
            Rule::unit => unit = unit_of(inner.as_str()),
            _ => {}
        }
    }
    let (mut a, mut b) = (*nums.first()?, *nums.get(1)?);
    if unit.is_some() {
        a.unit = a.unit.or(unit);
        b.unit = b.unit.or(unit);
    }
    Some((a, b))
}

/// The first number with an optional unit anywhere in a text (for prose answers).
pub(crate) fn first_number(text: &str) -> Option<(Num, usize, usize)> {
    numbers(text).into_iter().next().map(|(n, a, e, _)| (n, a, e))
}

/// Every number of a prose text, in order, with its span and whether letters are glued to it
/// (`1b1b`, `3rd`: part of a word, not a quantity).
pub(crate) fn numbers(text: &str) -> Vec<(Num, usize, usize, bool)> {
    let mut out = Vec::new();
    let bytes = text.as_bytes();
    let mut i = 0;
    while i < bytes.len() {
        let c = bytes[i];
        let starts =
            c.is_ascii_digit() || (c == b'-' && bytes.get(i + 1).is_some_and(u8::is_ascii_digit));
        let after_word = i > 0 && (bytes[i - 1].is_ascii_alphanumeric() || bytes[i - 1] == b'.');
        if starts && !after_word {
            let mut j = i + 1;
            while j < bytes.len()
                && (bytes[j].is_ascii_digit() || bytes[j] == b'.' || bytes[j] == b',')
            {
                j += 1;
            }
            // Take the unit, if any.
            let mut k = j;
            while k < bytes.len() && bytes[k] == b' ' {
                k += 1;
            }
            let mut e = k;
            while e < bytes.len() && bytes[e].is_ascii_alphabetic() {
                e += 1;
            }
            let num_text = text[i..j].trim_end_matches(['.', ',']);
            let unit_text = &text[k..e];
            let candidate = if unit_of(unit_text).is_some() {
                format!("{num_text} {unit_text}")
            } else {
                num_text.to_string()
            };
            if let Some(n) = number(&candidate) {
                let glued = k == j && e > k && unit_of(unit_text).is_none();
                out.push((n, i, j, glued));
            }
            i = j;
        } else {
            i += text[i..].chars().next().map_or(1, char::len_utf8);
        }
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn numbers_units_and_lists() {
        assert_eq!(number("160cm").map(|n| (n.value, n.unit)), Some((160.0, Some("cm"))));
        assert_eq!(number("2,5 m").map(|n| (n.value, n.comma)), Some((2.5, true)));
        assert!(number("NaN").is_none());
        assert!(number("abc").is_none());
        let v = vertex_list("[(0, 0), (0, 8), (5.5, 8), (5.5, 0)]").expect("list");
        assert_eq!(v.len(), 4);
        assert!(vertex_list("[(0, 0), (0, 8)").is_none());
        let s = size_pair("130x120 cm").expect("pair");
        assert_eq!((s.0.value, s.1.unit), (130.0, Some("cm")));
        assert_eq!(first_number("The height is 3.0 meters.").map(|n| n.0.value), Some(3.0));
    }

    #[test]
    fn decoration_is_removed() {
        let l = lines("Sure!\n1. **a** | b.\n- c | d\n```\n", FileId(0), true);
        assert_eq!(l.lines.len(), 2);
        assert_eq!(l.lines[0].fields()[0].text, "a");
        assert_eq!(l.lines[0].fields()[1].text, "b");
        assert_eq!(l.lines[1].fields()[0].text, "c");
    }
}

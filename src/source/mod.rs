//! Source files, spans and line indexes.
//!
//! Every piece of text the compiler reads (a `.holo` file, a raw LLM answer, a catalog) is added
//! to a [`SourceMap`] and gets a [`FileId`]. Positions are [`Span`]s: byte offsets, half-open.
//! They are turned into lines and columns (1-based for people, 0-based UTF-16 for LSP) only
//! through [`SourceFile::line_col`] and [`SourceFile::lsp_position`].

mod read;

pub use read::{read_input, read_input_or_stdin, read_text, ReadError, STREAM_TIMEOUT};
use std::fmt;

/// Identifies one file in a [`SourceMap`].
#[derive(Clone, Copy, Debug, PartialEq, Eq, PartialOrd, Ord, Hash, Default)]
pub struct FileId(pub u32);

/// A half-open byte range `[start, end)` in one file.
#[derive(Clone, Copy, Debug, PartialEq, Eq, PartialOrd, Ord, Hash, Default)]
pub struct Span {
    /// The file the range belongs to.
    pub file: FileId,
    /// First byte.
    pub start: u32,
    /// One past the last byte.
    pub end: u32,
}

impl Span {
    /// Makes a span from byte offsets.
    pub fn new(file: FileId, start: usize, end: usize) -> Span {
        Span { file, start: start as u32, end: end.max(start) as u32 }
    }

    /// The smallest span that covers both `self` and `other` (same file assumed).
    #[must_use]
    pub fn to(self, other: Span) -> Span {
        Span { file: self.file, start: self.start.min(other.start), end: self.end.max(other.end) }
    }

    /// The span shifted by `offset` bytes (used when a sub-text is parsed on its own).
    #[must_use]
    pub fn shifted(self, offset: usize) -> Span {
        Span { file: self.file, start: self.start + offset as u32, end: self.end + offset as u32 }
    }

    /// Length in bytes.
    pub fn len(self) -> usize {
        (self.end - self.start) as usize
    }

    /// Whether the span covers no byte.
    pub fn is_empty(self) -> bool {
        self.end == self.start
    }

    /// The byte range, for slicing the file's text.
    pub fn range(self) -> std::ops::Range<usize> {
        self.start as usize..self.end as usize
    }
}

/// Where a value the compiler works with came from.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Origin {
    /// Written in a source file at this span.
    Source(Span),
    /// Computed by the compiler from what is written at this span.
    Derived(Span),
    /// Made up by the compiler with no source (a default, a fallback).
    Synthesized,
}

impl Origin {
    /// The span this origin points at, if any.
    pub fn span(self) -> Option<Span> {
        match self {
            Origin::Source(span) | Origin::Derived(span) => Some(span),
            Origin::Synthesized => None,
        }
    }
}

/// A 1-based line and column (column counted in characters).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct LineCol {
    /// 1-based line.
    pub line: usize,
    /// 1-based column, in Unicode scalar values.
    pub column: usize,
}

/// One source file: its name, its text and the offsets of its line starts.
#[derive(Clone, Debug)]
pub struct SourceFile {
    /// The name shown to people (a path, or a label such as `<floor-plan answer>`).
    pub name: String,
    /// The full text.
    pub text: std::sync::Arc<String>,
    /// (Shared by the copies of the file, as its text is; copied when one of them changes.)
    line_starts: std::sync::Arc<Vec<usize>>,
    /// The characters before each [`CHAR_BLOCK`] bytes of the text, worked out the first time
    /// a column far into a long line is asked for (shared as the line starts are, and made
    /// again after a change).
    char_blocks: std::sync::Arc<std::sync::OnceLock<Vec<usize>>>,
}

/// The bytes of text between two counts kept by [`SourceFile::char_blocks`]: a column far into
/// a long line (a house written on one line) is counted from the nearest count before it,
/// never from the line's start.
const CHAR_BLOCK: usize = 4096;

/// The characters (Unicode scalar values) that start in `bytes`: those not a continuation
/// byte. Any range of a string's bytes may be given, even one that cuts a character.
fn chars_starting_in(bytes: &[u8]) -> usize {
    bytes.iter().filter(|&&b| (b as i8) >= -0x40).count()
}

impl SourceFile {
    /// Makes a file and indexes its lines.
    pub fn new(name: impl Into<String>, text: impl Into<String>) -> SourceFile {
        let text = text.into();
        SourceFile {
            name: name.into(),
            line_starts: line_starts(&text).into(),
            char_blocks: std::sync::Arc::default(),
            text: text.into(),
        }
    }

    /// The 0-based line index holding byte `offset`.
    fn line_index(&self, offset: usize) -> usize {
        match self.line_starts.binary_search(&offset) {
            Ok(i) => i,
            Err(i) => i - 1,
        }
    }

    /// Clamps an offset into the text and onto a character boundary.
    fn clamp(&self, offset: usize) -> usize {
        let mut offset = offset.min(self.text.len());
        while !self.text.is_char_boundary(offset) {
            offset -= 1;
        }
        offset
    }

    /// The 1-based line and column of byte `offset`.
    pub fn line_col(&self, offset: usize) -> LineCol {
        let offset = self.clamp(offset);
        let line = self.line_index(offset);
        let start = self.line_starts[line];
        let column = if offset - start <= 2 * CHAR_BLOCK {
            self.text[start..offset].chars().count()
        } else {
            self.chars_before(offset) - self.chars_before(start)
        };
        LineCol { line: line + 1, column: column + 1 }
    }

    /// The characters before byte `offset`, from the nearest block count before it.
    fn chars_before(&self, offset: usize) -> usize {
        let bytes = self.text.as_bytes();
        let blocks = self.char_blocks.get_or_init(|| {
            let mut counts = vec![0];
            for block in bytes.chunks(CHAR_BLOCK) {
                let before = counts.last().copied().unwrap_or(0);
                counts.push(before + chars_starting_in(block));
            }
            counts
        });
        let block = offset / CHAR_BLOCK;
        blocks.get(block).copied().unwrap_or(0)
            + chars_starting_in(&bytes[(block * CHAR_BLOCK).min(offset)..offset])
    }

    /// The LSP position of byte `offset`: 0-based line, 0-based UTF-16 column.
    pub fn lsp_position(&self, offset: usize) -> (u32, u32) {
        let offset = self.clamp(offset);
        let line = self.line_index(offset);
        let column: usize =
            self.text[self.line_starts[line]..offset].chars().map(char::len_utf16).sum();
        (line as u32, column as u32)
    }

    /// The byte offset of an LSP position (0-based line, 0-based UTF-16 column), clamped to
    /// the line's end and the text's end; a column inside a surrogate pair rounds down.
    pub fn offset_of_lsp(&self, line: u32, column: u32) -> usize {
        let Some(&start) = self.line_starts.get(line as usize) else { return self.text.len() };
        let next = self.line_starts.get(line as usize + 1).copied().unwrap_or(self.text.len());
        // The line without its break (`\n`, `\r\n` or a lone `\r`).
        let end = start + self.text[start..next].trim_end_matches(['\n', '\r']).len();
        let mut units = 0u32;
        for (i, c) in self.text[start..end].char_indices() {
            if units + c.len_utf16() as u32 > column {
                return start + i;
            }
            units += c.len_utf16() as u32;
        }
        end
    }

    /// Replaces bytes `range` of the text with `with` (the range clamped into the text and onto
    /// character boundaries) and indexes again only the lines the change touched: the line
    /// starts before it stay and those after it move by the change in length, so that an
    /// editor's keystroke in a long file costs no scan of the whole text.
    pub fn replace_range(&mut self, range: std::ops::Range<usize>, with: &str) {
        let start = self.clamp(range.start);
        let end = self.clamp(range.end).max(start);
        // Grown by a little at a time, not doubled: a large text edited keystroke by keystroke
        // would otherwise hold twice its length.
        let grown = (self.text.len() - (end - start)).saturating_add(with.len());
        // The text is changed in place unless an analysis or the memo of an earlier version
        // shares it: then it is copied once (with room to grow), and they keep theirs.
        if std::sync::Arc::get_mut(&mut self.text).is_none() {
            let mut copy = String::with_capacity(grown + (grown / 64).max(1024));
            copy.push_str(&self.text);
            self.text = std::sync::Arc::new(copy);
        }
        let text = std::sync::Arc::make_mut(&mut self.text);
        if grown > text.capacity() {
            let slack = (grown / 64).max(1024);
            text.reserve_exact(grown - text.len() + slack);
        }
        text.replace_range(start..end, with);
        // The counts of characters are made again if asked for.
        self.char_blocks = std::sync::Arc::default();
        let new_end = start + with.len();
        // A line start `s` depends on bytes `s - 1` and `s`: those from `start` to `end` (old)
        // are made again from the new text, from byte `start - 1` to `new_end`.
        let keep = self.line_starts.partition_point(|&s| s < start);
        let after = self.line_starts.partition_point(|&s| s <= end);
        let bytes = self.text.as_bytes();
        let mut fresh = Vec::new();
        if start == 0 {
            fresh.push(0);
        }
        for i in start.saturating_sub(1)..new_end {
            if bytes[i] == b'\n' || (bytes[i] == b'\r' && bytes.get(i + 1) != Some(&b'\n')) {
                fresh.push(i + 1);
            }
        }
        let added = fresh.len();
        let line_starts = std::sync::Arc::make_mut(&mut self.line_starts);
        let _ = line_starts.splice(keep..after, fresh);
        for s in &mut line_starts[keep + added..] {
            *s = *s - end + new_end;
        }
    }

    /// The number of lines (a final line without a break counts).
    pub fn line_count(&self) -> usize {
        self.line_starts.len()
    }

    /// The length in bytes of the line that holds byte `offset`, its line break included.
    pub fn line_len_at(&self, offset: usize) -> usize {
        let line = self.line_index(self.clamp(offset));
        let end = self.line_starts.get(line + 1).copied().unwrap_or(self.text.len());
        end - self.line_starts[line]
    }

    /// The text of 1-based line `line`, without its line break.
    pub fn line_text(&self, line: usize) -> &str {
        let Some(&start) = self.line_starts.get(line.saturating_sub(1)) else { return "" };
        let end = self.line_starts.get(line).copied().unwrap_or(self.text.len());
        self.text[start..end].trim_end_matches(['\n', '\r'])
    }

    /// The text a span covers (empty if the span does not fit the file).
    pub fn slice(&self, span: Span) -> &str {
        let start = self.clamp(span.start as usize);
        let end = self.clamp(span.end as usize).max(start);
        &self.text[start..end]
    }
}

/// Where each line starts: after every `\n`, `\r\n` and lone `\r` (the line breaks the grammar
/// and the Language Server Protocol know).
fn line_starts(text: &str) -> Vec<usize> {
    let bytes = text.as_bytes();
    let mut starts = vec![0];
    for (i, &b) in bytes.iter().enumerate() {
        if b == b'\n' || (b == b'\r' && bytes.get(i + 1) != Some(&b'\n')) {
            starts.push(i + 1);
        }
    }
    starts
}

/// All files of one compilation.
#[derive(Clone, Debug, Default)]
pub struct SourceMap {
    files: Vec<SourceFile>,
}

impl SourceMap {
    /// An empty map.
    pub fn new() -> SourceMap {
        SourceMap::default()
    }

    /// Adds a file and returns its id.
    pub fn add(&mut self, name: impl Into<String>, text: impl Into<String>) -> FileId {
        self.files.push(SourceFile::new(name, text));
        FileId((self.files.len() - 1) as u32)
    }

    /// Adds a file made already and returns its id.
    pub fn add_file(&mut self, file: SourceFile) -> FileId {
        self.files.push(file);
        FileId((self.files.len() - 1) as u32)
    }

    /// The file with this id.
    ///
    /// # Panics
    /// If the id does not come from this map.
    pub fn get(&self, id: FileId) -> &SourceFile {
        &self.files[id.0 as usize]
    }

    /// The file with this id, if it exists.
    pub fn try_get(&self, id: FileId) -> Option<&SourceFile> {
        self.files.get(id.0 as usize)
    }

    /// All files, in the order they were added.
    pub fn files(&self) -> impl Iterator<Item = (FileId, &SourceFile)> {
        self.files.iter().enumerate().map(|(i, f)| (FileId(i as u32), f))
    }
}

impl fmt::Display for Span {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(f, "{}..{}", self.start, self.end)
    }
}

/// Where two versions of a text differ: `(start, old_end, new_end)`, where bytes
/// `start..old_end` of `old` became `start..new_end` of `new` and the rest is their common
/// prefix and suffix (the suffix taken as long as it can be without overlapping the prefix).
pub fn changed_range(old: &str, new: &str) -> (usize, usize, usize) {
    let (a, b) = (old.as_bytes(), new.as_bytes());
    let start = common_prefix(a, b);
    let room = a.len().min(b.len()) - start;
    let suffix = common_suffix(&a[a.len() - room..], &b[b.len() - room..]);
    (start, a.len() - suffix, b.len() - suffix)
}

/// The length of the longest common prefix of two byte strings (compared a block at a time,
/// which the compiler turns into `memcmp`, then byte by byte in the first block that differs).
fn common_prefix(a: &[u8], b: &[u8]) -> usize {
    const BLOCK: usize = 64;
    let n = a.len().min(b.len());
    let mut i = 0;
    while i + BLOCK <= n && a[i..i + BLOCK] == b[i..i + BLOCK] {
        i += BLOCK;
    }
    i + a[i..n].iter().zip(&b[i..n]).take_while(|(x, y)| x == y).count()
}

/// The length of the longest common suffix of two byte strings.
fn common_suffix(a: &[u8], b: &[u8]) -> usize {
    const BLOCK: usize = 64;
    let n = a.len().min(b.len());
    let (a, b) = (&a[a.len() - n..], &b[b.len() - n..]);
    let mut k = 0;
    while k + BLOCK <= n && a[n - k - BLOCK..n - k] == b[n - k - BLOCK..n - k] {
        k += BLOCK;
    }
    k + a[..n - k].iter().rev().zip(b[..n - k].iter().rev()).take_while(|(x, y)| x == y).count()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn line_and_utf16_columns() {
        let file = SourceFile::new("t", "ab\nçé😀x\n");
        assert_eq!(file.line_col(0), LineCol { line: 1, column: 1 });
        assert_eq!(file.line_col(3), LineCol { line: 2, column: 1 });
        let x = file.text.find('x').expect("x is in the text");
        assert_eq!(file.line_col(x), LineCol { line: 2, column: 4 });
        assert_eq!(file.lsp_position(x), (1, 4));
        assert_eq!(file.line_text(2), "çé😀x");
    }

    #[test]
    fn a_column_far_into_a_long_line_is_the_count_of_its_characters() {
        // Lines longer than two blocks, of characters of 1 to 4 bytes, cut by blocks anywhere.
        let piece = "aé😀ç\u{2028}b";
        let long: String = piece.repeat(3 * CHAR_BLOCK / piece.len() + 7);
        let text = format!("first\n{long}\nx{long}");
        let mut file = SourceFile::new("t", text.clone());
        let plain = |text: &str, offset: usize| {
            let start = text[..offset].rfind('\n').map_or(0, |i| i + 1);
            text[start..offset].chars().count() + 1
        };
        let offsets: Vec<usize> = text
            .char_indices()
            .map(|(i, _)| i)
            .filter(|i| i % 9973 < 4 || *i > text.len() - 8)
            .chain([text.len()])
            .collect();
        for &offset in &offsets {
            assert_eq!(file.line_col(offset).column, plain(&text, offset), "offset {offset}");
        }
        // After an edit the counts are made again.
        file.replace_range(0..0, "😀😀");
        let edited = file.text.to_string();
        let end = edited.len();
        assert_eq!(file.line_col(end).column, plain(&edited, end));
        assert_eq!(file.line_col(end - long.len()).column, plain(&edited, end - long.len()));
    }

    #[test]
    fn a_replaced_range_indexes_the_lines_as_a_new_file_does() {
        // Every edit of every range of short texts made of line breaks and letters.
        let texts = ["", "a", "\n", "\r", "\r\n", "a\r\nb\rc\n", "\r\r\n\n\r", "ab\ncd\r\nef"];
        let inserts = ["", "x", "\n", "\r", "\r\n", "\nq\r", "é\n"];
        for text in texts {
            for start in 0..=text.len() {
                for end in start..=text.len() {
                    for with in inserts {
                        let mut file = SourceFile::new("t", text);
                        file.replace_range(start..end, with);
                        let mut expected = text.to_string();
                        expected.replace_range(start..end, with);
                        assert_eq!(*file.text, expected);
                        assert_eq!(
                            *file.line_starts,
                            line_starts(&expected),
                            "{text:?} {start}..{end} {with:?}"
                        );
                    }
                }
            }
        }
        // A range past the end or inside a character is clamped.
        let mut file = SourceFile::new("t", "é\nb");
        file.replace_range(1..99, "x");
        assert_eq!((file.text.as_str(), (*file.line_starts).clone()), ("x", vec![0]));
    }

    #[test]
    fn lone_carriage_returns_and_crlf_end_lines() {
        let file = SourceFile::new("t", "ab\rcd\r\nef\ngh");
        assert_eq!(file.line_count(), 4);
        assert_eq!(file.lsp_position(3), (1, 0));
        assert_eq!(file.lsp_position(7), (2, 0));
        assert_eq!(file.line_text(2), "cd");
        // A column past the line's end stops before its break.
        assert_eq!(file.offset_of_lsp(1, 99), 5);
        assert_eq!(file.offset_of_lsp(0, 99), 2);
        assert_eq!(file.offset_of_lsp(3, 99), 12);
    }
}

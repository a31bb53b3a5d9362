//! Semantic tokens (`textDocument/semanticTokens/full` and `/range`): what each word of a
//! `.holo` text is, for the editor to colour it.
//!
//! The tokens are read from the text by one flat scan, not from the syntax tree: a half-typed
//! line is coloured while it is typed, a line the parser cannot read is coloured too, and the
//! cost is one pass over the text, whatever the analysis is doing. Names are told apart by where
//! they stand in their statement, as the grammar (`grammar/holo.pest`) places them: the word
//! after `room` declares a room, after `object`, `wall object` or `instance` an object group or
//! instance; the words of a `door` line before its `:` name rooms (`exterior` the outside); the
//! word after a relation or `above` names an object. The editors' grammars (`editors/`) give the
//! same words the same classes, which their tests check against [`tokens`].

use lsp_types::{SemanticToken, SemanticTokenModifier, SemanticTokenType, SemanticTokensLegend};

/// What a token is.
#[derive(Clone, Copy, Debug, PartialEq, Eq, PartialOrd, Ord, Hash)]
pub enum Class {
    /// A statement keyword (`room`, `object`, `describe`, `size`, …) or a relation (`near`,
    /// `in front of`).
    Keyword,
    /// A room's name, where it is declared or named (a door's rooms).
    Room,
    /// An object group's or instance's name, where it is declared or named (a relation's
    /// target, `above`).
    Object,
    /// A unit after a number (`cm`, `m`, `deg`; also those the checker refuses with a fix).
    Unit,
    /// A word of a fixed vocabulary: directions, window types, door kinds and sizes, variance.
    Word,
    /// A string in double quotes.
    String,
    /// A number.
    Number,
    /// A comment.
    Comment,
    /// The multiplication sign between dimensions and before a count (`x`, `×`).
    Operator,
}

impl Class {
    /// Every class, in the legend's order (a token's type is its place here).
    pub const ALL: [Class; 9] = [
        Class::Keyword,
        Class::Room,
        Class::Object,
        Class::Unit,
        Class::Word,
        Class::String,
        Class::Number,
        Class::Comment,
        Class::Operator,
    ];

    /// The standard token type the class is sent as (editors' themes colour these).
    pub fn token_type(self) -> SemanticTokenType {
        match self {
            Class::Keyword => SemanticTokenType::KEYWORD,
            Class::Room => SemanticTokenType::NAMESPACE,
            Class::Object => SemanticTokenType::VARIABLE,
            Class::Unit => SemanticTokenType::TYPE,
            Class::Word => SemanticTokenType::ENUM_MEMBER,
            Class::String => SemanticTokenType::STRING,
            Class::Number => SemanticTokenType::NUMBER,
            Class::Comment => SemanticTokenType::COMMENT,
            Class::Operator => SemanticTokenType::OPERATOR,
        }
    }

    /// A short lowercase name, as tests and the book print it.
    pub fn as_str(self) -> &'static str {
        match self {
            Class::Keyword => "keyword",
            Class::Room => "room",
            Class::Object => "object",
            Class::Unit => "unit",
            Class::Word => "word",
            Class::String => "string",
            Class::Number => "number",
            Class::Comment => "comment",
            Class::Operator => "operator",
        }
    }
}

/// The modifier bit of a name where it is declared.
pub const DECLARATION: u32 = 1;
/// The modifier bit of a name the language defines (`exterior`).
pub const DEFAULT_LIBRARY: u32 = 2;

/// The legend the server announces: the token types in [`Class::ALL`]'s order, and the
/// modifiers by their bits ([`DECLARATION`], [`DEFAULT_LIBRARY`]).
pub fn legend() -> SemanticTokensLegend {
    SemanticTokensLegend {
        token_types: Class::ALL.iter().map(|c| c.token_type()).collect(),
        token_modifiers: vec![
            SemanticTokenModifier::DECLARATION,
            SemanticTokenModifier::DEFAULT_LIBRARY,
        ],
    }
}

/// One token: a byte range of the text, on one line.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Token {
    /// The first byte.
    pub start: usize,
    /// The byte after the last.
    pub end: usize,
    /// What it is.
    pub class: Class,
    /// Its modifier bits ([`DECLARATION`], [`DEFAULT_LIBRARY`]).
    pub modifiers: u32,
}

/// The keywords of the grammar (its `kw_*` rules).
const KEYWORDS: &[&str] = &[
    "scene", "room", "door", "wall", "walls", "height", "seed", "floor", "material", "corners",
    "in", "window", "count", "sill", "asset", "object", "ceiling", "describe", "size", "above",
    "at", "facing", "on", "top", "instance",
];

/// The relations of the grammar's `relation` rule, word by word (words are separated by
/// spaces).
const RELATIONS: &[&[&str]] = &[
    &["in", "front", "of"],
    &["behind"],
    &["side", "of"],
    &["left", "of"],
    &["right", "of"],
    &["around"],
    &["center", "aligned"],
    &["face", "to"],
    &["face", "same", "as"],
    &["near"],
    &["far"],
    &["edge"],
    &["middle"],
];

/// The vocabulary the checker reads from `word`s: directions, window types, door kinds and
/// sizes, and whether a group's instances share one asset.
const VOCABULARY: &[&str] = &[
    "north",
    "east",
    "south",
    "west",
    "fixed",
    "hung",
    "slider",
    "doorway",
    "doorframe",
    "open",
    "single",
    "double",
    "same",
    "varied",
];

/// The units of the grammar's `unit` rule.
const UNITS: &[&str] = &["cm", "mm", "m", "deg", "ft", "in", "rad"];

/// What the next name of a statement is.
#[derive(Clone, Copy, PartialEq, Eq)]
enum Expect {
    Nothing,
    RoomDeclaration,
    ObjectDeclaration,
    ObjectReference,
    /// A door's rooms, up to its `:`.
    DoorRooms,
    /// The unit of `corners in m`.
    Unit,
}

/// Where the scan is in a statement.
struct Statement<'t> {
    /// The statement's first word.
    first: Option<&'t str>,
    /// How many words, strings and numbers came before.
    parts: usize,
    expect: Expect,
}

impl Statement<'_> {
    fn new() -> Self {
        Statement { first: None, parts: 0, expect: Expect::Nothing }
    }
}

fn is_ident_byte(b: u8) -> bool {
    b.is_ascii_alphanumeric() || b == b'_'
}

/// The end of the identifier or word starting at `start`: letters, digits and `_`, with inner
/// `-` and `/` (`chair-1`, `N/A`).
fn word_end(bytes: &[u8], start: usize) -> usize {
    let mut end = start + 1;
    while end < bytes.len() {
        if is_ident_byte(bytes[end]) {
            end += 1;
        } else if matches!(bytes[end], b'-' | b'/')
            && bytes.get(end + 1).copied().is_some_and(is_ident_byte)
        {
            end += 2;
        } else {
            break;
        }
    }
    end
}

/// The end of the relation that starts at `start`, if one does.
fn relation_end(bytes: &[u8], start: usize) -> Option<usize> {
    'phrases: for phrase in RELATIONS {
        let mut at = start;
        for (k, word) in phrase.iter().enumerate() {
            if k > 0 {
                let spaces = bytes[at..].iter().take_while(|&&b| b == b' ').count();
                if spaces == 0 {
                    continue 'phrases;
                }
                at += spaces;
            }
            if !bytes[at..].starts_with(word.as_bytes()) {
                continue 'phrases;
            }
            at += word.len();
        }
        if bytes.get(at).copied().is_some_and(is_ident_byte) {
            continue;
        }
        return Some(at);
    }
    None
}

/// The end of the line that `at` is on (before its line break).
fn line_end(bytes: &[u8], at: usize) -> usize {
    bytes[at..].iter().position(|&b| b == b'\n' || b == b'\r').map_or(bytes.len(), |k| at + k)
}

/// Every token of `text`, in order, each on one line (a comment over several lines is one
/// token per line).
pub fn tokens(text: &str) -> Vec<Token> {
    let bytes = text.as_bytes();
    let mut out = Vec::new();
    let mut push = |start: usize, end: usize, class: Class, modifiers: u32| {
        if end > start {
            out.push(Token { start, end, class, modifiers });
        }
    };
    let mut statement = Statement::new();
    let mut i = 0;
    while i < bytes.len() {
        let b = bytes[i];
        let next = bytes.get(i + 1).copied();
        match b {
            b'\n' | b'\r' | b';' | b'{' | b'}' => {
                statement = Statement::new();
                i += 1;
            }
            b' ' | b'\t' | b',' | b'(' | b')' => i += 1,
            b':' => {
                if statement.expect == Expect::DoorRooms {
                    statement.expect = Expect::Nothing;
                }
                i += 1;
            }
            b'/' if next == Some(b'/') => {
                let end = line_end(bytes, i);
                push(i, end, Class::Comment, 0);
                i = end;
            }
            b'/' if next == Some(b'*') => {
                let end = text[i + 2..].find("*/").map_or(bytes.len(), |k| i + 2 + k + 2);
                // One token per line of the comment.
                let mut start = i;
                while start < end {
                    let stop = line_end(bytes, start).min(end);
                    push(start, stop, Class::Comment, 0);
                    start = stop;
                    while start < end && matches!(bytes[start], b'\n' | b'\r') {
                        start += 1;
                    }
                }
                i = end;
            }
            b'"' => {
                let mut end = i + 1;
                while end < bytes.len() {
                    match bytes[end] {
                        b'"' => {
                            end += 1;
                            break;
                        }
                        b'\n' | b'\r' => break,
                        b'\\' => {
                            end += 1;
                            // Skip the escaped character whole (it may be any character).
                            end += text[end..]
                                .chars()
                                .next()
                                .filter(|c| *c != '\n' && *c != '\r')
                                .map_or(0, char::len_utf8);
                        }
                        _ => end += 1,
                    }
                }
                push(i, end, Class::String, 0);
                statement.parts += 1;
                i = end;
            }
            b'0'..=b'9' | b'-' if b != b'-' || next.is_some_and(|n| n.is_ascii_digit()) => {
                i = number(bytes, i, &mut push);
                statement.parts += 1;
            }
            b'-' if next == Some(b'-') => i += 2,
            b if b.is_ascii_alphabetic() || b == b'_' => {
                i = word(text, i, &mut statement, &mut push);
            }
            _ => {
                let c = text[i..].chars().next().map_or(1, char::len_utf8);
                if text[i..].starts_with('×') {
                    push(i, i + c, Class::Operator, 0);
                }
                i += c;
            }
        }
    }
    out
}

/// A number at `start` and the unit after it, if any; returns where the scan goes on.
fn number(bytes: &[u8], start: usize, push: &mut impl FnMut(usize, usize, Class, u32)) -> usize {
    let mut end = start + 1;
    while end < bytes.len() && bytes[end].is_ascii_digit() {
        end += 1;
    }
    if bytes.get(end) == Some(&b'.') && bytes.get(end + 1).is_some_and(u8::is_ascii_digit) {
        end += 1;
        while end < bytes.len() && bytes[end].is_ascii_digit() {
            end += 1;
        }
    }
    push(start, end, Class::Number, 0);
    let unit_start = end + bytes[end..].iter().take_while(|&&b| b == b' ' || b == b'\t').count();
    for unit in UNITS {
        let unit_end = unit_start + unit.len();
        if bytes[unit_start..].starts_with(unit.as_bytes())
            && !bytes.get(unit_end).copied().is_some_and(is_ident_byte)
        {
            push(unit_start, unit_end, Class::Unit, 0);
            return unit_end;
        }
    }
    end
}

/// A word at `start` (a keyword, a relation, a name, a vocabulary word or `x`); returns where
/// the scan goes on.
fn word<'t>(
    text: &'t str,
    start: usize,
    statement: &mut Statement<'t>,
    push: &mut impl FnMut(usize, usize, Class, u32),
) -> usize {
    let bytes = text.as_bytes();
    if statement.parts == 0 {
        if let Some(end) = relation_end(bytes, start) {
            push(start, end, Class::Keyword, 0);
            statement.parts += 1;
            statement.first = Some("relation");
            statement.expect = Expect::ObjectReference;
            return end;
        }
    }
    let end = word_end(bytes, start);
    let word = &text[start..end];
    let first = statement.parts == 0;
    statement.parts += 1;
    match statement.expect {
        Expect::RoomDeclaration => {
            statement.expect = Expect::Nothing;
            push(start, end, Class::Room, DECLARATION);
            return end;
        }
        Expect::ObjectDeclaration => {
            statement.expect = Expect::Nothing;
            push(start, end, Class::Object, DECLARATION);
            return end;
        }
        Expect::ObjectReference => {
            statement.expect = Expect::Nothing;
            push(start, end, Class::Object, 0);
            return end;
        }
        Expect::DoorRooms => {
            let modifiers = if word == "exterior" { DEFAULT_LIBRARY } else { 0 };
            push(start, end, Class::Room, modifiers);
            return end;
        }
        Expect::Unit => {
            statement.expect = Expect::Nothing;
            if UNITS.contains(&word) {
                push(start, end, Class::Unit, 0);
                return end;
            }
        }
        Expect::Nothing => {}
    }
    if first {
        statement.first = Some(word);
    }
    if KEYWORDS.contains(&word) && (first || statement.first.is_some_and(|f| KEYWORDS.contains(&f)))
    {
        push(start, end, Class::Keyword, 0);
        statement.expect = match (statement.first, word) {
            (Some("room"), "room") => Expect::RoomDeclaration,
            (Some("object" | "instance"), "object" | "instance") | (Some("wall"), "object") => {
                Expect::ObjectDeclaration
            }
            (Some("door"), "door") => Expect::DoorRooms,
            (Some("above"), "above") => Expect::ObjectReference,
            (Some("corners"), "in") => Expect::Unit,
            _ => Expect::Nothing,
        };
    } else if word == "x"
        || (word.starts_with('x') && word[1..].bytes().all(|b| b.is_ascii_digit()))
    {
        // `x` between dimensions, or `x2` after the things on top.
        push(start, start + 1, Class::Operator, 0);
        if end > start + 1 {
            push(start + 1, end, Class::Number, 0);
        }
    } else if !first && VOCABULARY.contains(&word) {
        push(start, end, Class::Word, 0);
    }
    end
}

/// The tokens in the protocol's form: lines from 0, columns and lengths in UTF-16 code units,
/// each relative to the one before; only the tokens on the lines `lines` (both ends
/// included) when given. Line breaks are `\n`, `\r\n` or a lone `\r`, as the protocol counts
/// them.
pub fn encode(text: &str, tokens: &[Token], lines: Option<(u32, u32)>) -> Vec<SemanticToken> {
    let mut out = Vec::new();
    // Where the walk is: its byte, line and UTF-16 column.
    let (mut at, mut line, mut column) = (0usize, 0u32, 0u32);
    let (mut last_line, mut last_column) = (0u32, 0u32);
    let walk = |to: usize, at: &mut usize, line: &mut u32, column: &mut u32| {
        let mut chars = text[*at..to].chars().peekable();
        while let Some(c) = chars.next() {
            match c {
                '\r' if chars.peek() == Some(&'\n') => {}
                '\n' | '\r' => {
                    *line += 1;
                    *column = 0;
                }
                c => *column += c.len_utf16() as u32,
            }
        }
        *at = to;
    };
    for token in tokens {
        walk(token.start, &mut at, &mut line, &mut column);
        let (token_line, token_column) = (line, column);
        walk(token.end, &mut at, &mut line, &mut column);
        if let Some((first, last)) = lines {
            if token_line < first {
                continue;
            }
            if token_line > last {
                break;
            }
        }
        let class = Class::ALL.iter().position(|c| *c == token.class).unwrap_or(0);
        out.push(SemanticToken {
            delta_line: token_line - last_line,
            delta_start: if token_line == last_line {
                token_column - last_column
            } else {
                token_column
            },
            length: column - token_column,
            token_type: class as u32,
            token_modifiers_bitset: token.modifiers,
        });
        (last_line, last_column) = (token_line, token_column);
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;
    use proptest::prelude::*;

    proptest! {
        /// Any text, broken or not: the tokens are in order, apart, on character boundaries and
        /// on one line each, and their encoding counts every one of them.
        #[test]
        fn tokens_are_ordered_and_on_one_line_whatever_the_text(
            text in "(room |object |wall |near |in front of |door |exterior|--|:|x2|x |×|é|😀|\"|\\\\|/\\*|\\*/|//|[ \t\r\n{};(),0-9.-]|[a-z_]{1,6}|cm|m ){0,80}"
        ) {
            let found = tokens(&text);
            let mut last = 0;
            for t in &found {
                prop_assert!(last <= t.start && t.start < t.end && t.end <= text.len());
                prop_assert!(text.is_char_boundary(t.start) && text.is_char_boundary(t.end));
                prop_assert!(!text[t.start..t.end].contains(['\n', '\r']));
                last = t.end;
            }
            prop_assert_eq!(encode(&text, &found, None).len(), found.len());
        }
    }

    fn show(text: &str) -> String {
        tokens(text)
            .iter()
            .map(|t| {
                let marks = match t.modifiers {
                    DECLARATION => "+decl",
                    DEFAULT_LIBRARY => "+builtin",
                    _ => "",
                };
                format!("{}:{}{marks}", &text[t.start..t.end], t.class.as_str())
            })
            .collect::<Vec<_>>()
            .join(" ")
    }

    #[test]
    fn names_are_told_apart_by_where_they_stand() {
        let text = "room bed_room \"bedroom\" {\n  object chair \"chair\" {\n    count 2 same\n    in  front of desk-0 // by the desk\n    instance chair-1 { near bed-0 }\n  }\n  wall object poster \"poster\" { above bed-0; height 140 cm }\n}\ndoor exterior -- bed_room : doorway single \"white\"\n";
        assert_eq!(
            show(text),
            "room:keyword bed_room:room+decl \"bedroom\":string \
             object:keyword chair:object+decl \"chair\":string \
             count:keyword 2:number same:word \
             in  front of:keyword desk-0:object // by the desk:comment \
             instance:keyword chair-1:object+decl near:keyword bed-0:object \
             wall:keyword object:keyword poster:object+decl \"poster\":string above:keyword bed-0:object \
             height:keyword 140:number cm:unit \
             door:keyword exterior:room+builtin bed_room:room doorway:word single:word \
             \"white\":string"
        );
    }

    #[test]
    fn quantities_units_and_counts() {
        assert_eq!(
            show("size 120cm x 60 cm × 75 cm\non top \"book\" x2 varied\ncorners in m (0, -1.5)"),
            "size:keyword 120:number cm:unit x:operator 60:number cm:unit ×:operator 75:number cm:unit \
             on:keyword top:keyword \"book\":string x:operator 2:number varied:word \
             corners:keyword in:keyword m:unit 0:number -1.5:number"
        );
    }

    #[test]
    fn strings_and_comments_stay_on_their_lines() {
        let text = "describe \"a \\\"b\\é\" /* one\r\ntwo */ floor \"open";
        assert_eq!(
            show(text),
            "describe:keyword \"a \\\"b\\é\":string /* one:comment two */:comment \
             floor:keyword \"open:string"
        );
        let encoded = encode(text, &tokens(text), None);
        let lines: Vec<(u32, u32, u32)> =
            encoded.iter().map(|t| (t.delta_line, t.delta_start, t.length)).collect();
        assert_eq!(lines, vec![(0, 0, 8), (0, 9, 9), (0, 10, 6), (1, 0, 6), (0, 7, 5), (0, 6, 5)]);
        // Only the second line.
        let second = encode(text, &tokens(text), Some((1, 1)));
        assert_eq!(second.first().map(|t| (t.delta_line, t.delta_start)), Some((1, 0)));
        assert_eq!(second.len(), 3);
    }

    #[test]
    fn columns_count_utf16_code_units() {
        let text = "  describe \"ü😀\" // 😀\n";
        let encoded = encode(text, &tokens(text), None);
        let spans: Vec<(u32, u32)> = encoded.iter().map(|t| (t.delta_start, t.length)).collect();
        assert_eq!(spans, vec![(2, 8), (9, 5), (6, 5)]);
    }
}

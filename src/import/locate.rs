//! Where things are in a JSON text: the spans of its members and elements by path, and the
//! offset in the file of a character of a string value, so that the diagnostics of an imported
//! scene file point at the lines they are about.
//!
//! The reader is a scanner, not a parser: it trusts the text to be JSON (the file was read with
//! `serde_json` first) and gives `None` wherever it is not. It never recurses: a value it skips
//! is skipped by counting brackets, so any depth is read in one pass.

/// One step of a path: a member of an object by its key, or an element of an array.
#[derive(Clone, Copy, Debug)]
pub(crate) enum Step<'k> {
    /// The member with this key (compared after decoding escapes).
    Key(&'k str),
    /// The element at this index.
    Index(usize),
}

/// A JSON text to find things in.
#[derive(Clone, Copy, Debug)]
pub(crate) struct JsonText<'t> {
    text: &'t str,
}

/// A member or element found: where its key is (for a member) and where its value is.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(crate) struct Found {
    /// The key's string, quotes included; the value's span for an element.
    pub key: (usize, usize),
    /// The value.
    pub value: (usize, usize),
}

impl<'t> JsonText<'t> {
    /// The text to read.
    pub(crate) fn new(text: &'t str) -> JsonText<'t> {
        JsonText { text }
    }

    /// The member or element at `path` from the top-level value; `None` when the path does not
    /// lead anywhere in the text.
    pub(crate) fn find(&self, path: &[Step<'_>]) -> Option<Found> {
        let start = self.skip_ws(0);
        let mut found = Found { key: (start, start), value: (start, self.value_end(start)?) };
        for step in path {
            found = match *step {
                Step::Key(key) => self.member(found.value.0, key)?,
                Step::Index(index) => self.element(found.value.0, index)?,
            };
        }
        Some(found)
    }

    /// The offset in the text of the byte `decoded` of the string value starting at `at` (its
    /// opening quote), as its escapes decode; the closing quote's offset past its end.
    pub(crate) fn string_offset(&self, at: usize, decoded: usize) -> Option<usize> {
        let bytes = self.text.as_bytes();
        if bytes.get(at) != Some(&b'"') {
            return None;
        }
        let mut i = at + 1;
        let mut count = 0usize;
        while i < bytes.len() && bytes[i] != b'"' {
            if count >= decoded {
                return Some(i);
            }
            if bytes[i] == b'\\' {
                let (len, out) = match bytes.get(i + 1) {
                    Some(b'u') => {
                        let hex = self.text.get(i + 2..i + 6)?;
                        let code = u32::from_str_radix(hex, 16).ok()?;
                        // Each half of a surrogate pair counts two of the four bytes of the
                        // character the pair makes.
                        let out = match code {
                            0xD800..=0xDFFF => 2,
                            _ => char::from_u32(code).map_or(3, char::len_utf8),
                        };
                        (6, out)
                    }
                    Some(_) => (2, 1),
                    None => return None,
                };
                i += len;
                count += out;
            } else {
                i += 1;
                count += 1;
            }
        }
        Some(i)
    }

    fn skip_ws(&self, mut i: usize) -> usize {
        let bytes = self.text.as_bytes();
        while bytes.get(i).is_some_and(|b| matches!(b, b' ' | b'\t' | b'\n' | b'\r')) {
            i += 1;
        }
        i
    }

    /// The end of the string starting at `at` (past its closing quote).
    fn string_end(&self, at: usize) -> Option<usize> {
        let bytes = self.text.as_bytes();
        let mut i = at + 1;
        while i < bytes.len() {
            match bytes[i] {
                b'\\' => i += 2,
                b'"' => return Some(i + 1),
                _ => i += 1,
            }
        }
        None
    }

    /// The end of the value starting at `at`.
    fn value_end(&self, at: usize) -> Option<usize> {
        let bytes = self.text.as_bytes();
        match bytes.get(at)? {
            b'"' => self.string_end(at),
            b'{' | b'[' => {
                let mut depth = 0usize;
                let mut i = at;
                while i < bytes.len() {
                    match bytes[i] {
                        b'"' => {
                            i = self.string_end(i)?;
                            continue;
                        }
                        b'{' | b'[' => depth += 1,
                        b'}' | b']' => {
                            depth -= 1;
                            if depth == 0 {
                                return Some(i + 1);
                            }
                        }
                        _ => {}
                    }
                    i += 1;
                }
                None
            }
            _ => {
                let rest = &bytes[at..];
                let len = rest
                    .iter()
                    .position(|b| matches!(b, b',' | b'}' | b']' | b' ' | b'\t' | b'\n' | b'\r'))
                    .unwrap_or(rest.len());
                Some(at + len)
            }
        }
    }

    fn decode(&self, start: usize, end: usize) -> Option<String> {
        serde_json::from_str::<String>(self.text.get(start..end)?).ok()
    }

    /// The member `key` of the object whose `{` is at `at`.
    fn member(&self, at: usize, key: &str) -> Option<Found> {
        let bytes = self.text.as_bytes();
        if bytes.get(at) != Some(&b'{') {
            return None;
        }
        let mut i = self.skip_ws(at + 1);
        while bytes.get(i) == Some(&b'"') {
            let key_end = self.string_end(i)?;
            let colon = self.skip_ws(key_end);
            if bytes.get(colon) != Some(&b':') {
                return None;
            }
            let value = self.skip_ws(colon + 1);
            let value_end = self.value_end(value)?;
            if self.decode(i, key_end).as_deref() == Some(key) {
                return Some(Found { key: (i, key_end), value: (value, value_end) });
            }
            let next = self.skip_ws(value_end);
            if bytes.get(next) != Some(&b',') {
                return None;
            }
            i = self.skip_ws(next + 1);
        }
        None
    }

    /// The element `index` of the array whose `[` is at `at`.
    fn element(&self, at: usize, index: usize) -> Option<Found> {
        let bytes = self.text.as_bytes();
        if bytes.get(at) != Some(&b'[') {
            return None;
        }
        let mut i = self.skip_ws(at + 1);
        let mut k = 0;
        while i < bytes.len() && bytes[i] != b']' {
            let end = self.value_end(i)?;
            if k == index {
                return Some(Found { key: (i, end), value: (i, end) });
            }
            k += 1;
            let next = self.skip_ws(end);
            if bytes.get(next) != Some(&b',') {
                return None;
            }
            i = self.skip_ws(next + 1);
        }
        None
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    const TEXT: &str = "{\n  \"a\": {\"b c\": [1, {\"d\": \"x\\ny\"}], \"e\": 2},\n  \"f\": \"\\u00e9t\\u00e9 z\"\n}";

    #[test]
    fn finds_members_and_elements() {
        let json = JsonText::new(TEXT);
        let b = json.find(&[Step::Key("a"), Step::Key("b c")]).expect("a.b c");
        assert_eq!(&TEXT[b.key.0..b.key.1], "\"b c\"");
        let d = json.find(&[Step::Key("a"), Step::Key("b c"), Step::Index(1), Step::Key("d")]);
        let d = d.expect("a.b c[1].d");
        assert_eq!(&TEXT[d.value.0..d.value.1], "\"x\\ny\"");
        assert!(json.find(&[Step::Key("a"), Step::Key("nope")]).is_none());
        assert!(json.find(&[Step::Key("a"), Step::Key("b c"), Step::Index(2)]).is_none());
    }

    #[test]
    fn maps_decoded_offsets_into_the_literal() {
        let json = JsonText::new(TEXT);
        let f = json.find(&[Step::Key("f")]).expect("f");
        // `été z`: é is two bytes decoded, six in the text.
        let at = |decoded| json.string_offset(f.value.0, decoded).expect("offset");
        assert_eq!(&TEXT[at(0)..at(0) + 6], "\\u00e9");
        assert_eq!(&TEXT[at(2)..=at(2)], "t");
        assert_eq!(&TEXT[at(3)..at(3) + 6], "\\u00e9");
        assert_eq!(&TEXT[at(5)..=at(5)], " ");
        assert_eq!(&TEXT[at(6)..=at(6)], "z");
    }
}

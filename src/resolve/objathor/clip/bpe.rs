//! CLIP's byte-level BPE tokenizer, as open_clip's `SimpleTokenizer` (and Hugging Face's
//! `CLIPTokenizer`) encode a query: whitespace collapsed and the text lower-cased, split by
//! CLIP's pattern, each piece's UTF-8 bytes mapped to printable characters (`bytes_to_unicode`),
//! the last character marked `</w>`, merged by rank, then `<|startoftext|>` … `<|endoftext|>`,
//! at most [`CONTEXT_LENGTH`] tokens (the last one `<|endoftext|>` when cut).
//!
//! What is left out of the original's cleaning: `ftfy.fix_text` and `html.unescape` (mojibake
//! repair and HTML entities, which an LLM's object names do not hold).

use std::collections::HashMap;

/// The tokens CLIP's text tower reads: `<|startoftext|>`, the text's, `<|endoftext|>`.
pub const CONTEXT_LENGTH: usize = 77;

/// The start token.
pub const START: &str = "<|startoftext|>";
/// The end token (the tower's pooled output is taken there).
pub const END: &str = "<|endoftext|>";

/// CLIP's pre-split pattern (case-insensitive, as the original compiles it).
const PATTERN: &str = r"(?i)<\|startoftext\|>|<\|endoftext\|>|'s|'t|'re|'ve|'m|'ll|'d|[\p{L}]+|[\p{N}]|[^\s\p{L}\p{N}]+";

/// GPT-2's and CLIP's reversible map of the 256 byte values to printable characters: the
/// printable Latin-1 bytes map to themselves, the others to U+0100 onwards in byte order.
pub fn bytes_to_unicode() -> [char; 256] {
    let printable = |b: u32| {
        (0x21..=0x7e).contains(&b) || (0xa1..=0xac).contains(&b) || (0xae..=0xff).contains(&b)
    };
    let mut out = ['\0'; 256];
    let mut n = 0u32;
    for b in 0..256u32 {
        let c = if printable(b) {
            b
        } else {
            n += 1;
            255 + n
        };
        out[b as usize] = char::from_u32(c).unwrap_or('\u{fffd}');
    }
    out
}

/// A loaded tokenizer: the vocabulary and the merges' ranks.
#[derive(Clone, Debug)]
pub struct Bpe {
    encoder: HashMap<String, u32>,
    ranks: HashMap<(String, String), usize>,
    byte_chars: [char; 256],
    pattern: regex::Regex,
    start: u32,
    end: u32,
}

impl Bpe {
    /// A tokenizer from its vocabulary (token → id) and its merges in rank order. Checked so
    /// that encoding never meets a token outside the vocabulary: every byte's character, alone
    /// and with `</w>`, each merge's result, and the start and end tokens must be in it.
    #[allow(clippy::implicit_hasher, reason = "the vocabulary is kept as given")]
    pub fn new(vocab: HashMap<String, u32>, merges: Vec<(String, String)>) -> Result<Bpe, String> {
        let byte_chars = bytes_to_unicode();
        for c in byte_chars {
            for token in [c.to_string(), format!("{c}</w>")] {
                if !vocab.contains_key(&token) {
                    return Err(format!(
                        "the vocabulary lacks the byte-level token `{token}` (a CLIP vocabulary has all 512)"
                    ));
                }
            }
        }
        let mut ranks = HashMap::with_capacity(merges.len());
        for (rank, (a, b)) in merges.into_iter().enumerate() {
            let joined = format!("{a}{b}");
            if !vocab.contains_key(&joined) {
                return Err(format!(
                    "merge {} (`{a} {b}`) makes `{joined}`, which is not in the vocabulary",
                    rank + 1
                ));
            }
            // As Python's `dict(zip(merges, range(…)))`: a repeated merge keeps its last rank.
            ranks.insert((a, b), rank);
        }
        let id =
            |t: &str| vocab.get(t).copied().ok_or_else(|| format!("the vocabulary lacks `{t}`"));
        let start = id(START)?;
        let end = id(END)?;
        let pattern = regex::Regex::new(PATTERN).map_err(|e| e.to_string())?;
        Ok(Bpe { encoder: vocab, ranks, byte_chars, pattern, start, end })
    }

    /// A tokenizer from Hugging Face's `vocab.json` (an object token → id) and `merges.txt`
    /// (one `a b` a line after a `#version` line).
    pub fn from_vocab_merges(vocab_json: &str, merges_txt: &str) -> Result<Bpe, String> {
        let vocab: HashMap<String, u32> = serde_json::from_str(vocab_json)
            .map_err(|e| format!("`vocab.json` is not an object of token ids: {e}"))?;
        let mut merges = Vec::new();
        for (i, line) in merges_txt.lines().enumerate() {
            if line.starts_with("#version") || line.trim().is_empty() {
                continue;
            }
            let mut parts = line.split(' ');
            match (parts.next(), parts.next(), parts.next()) {
                (Some(a), Some(b), None) if !a.is_empty() && !b.is_empty() => {
                    merges.push((a.to_string(), b.to_string()));
                }
                _ => return Err(format!("`merges.txt` line {} is not two tokens", i + 1)),
            }
        }
        Bpe::new(vocab, merges)
    }

    /// A tokenizer from Hugging Face's `tokenizer.json` (its `model.vocab` and `model.merges`,
    /// each merge `"a b"` or `["a", "b"]`).
    pub fn from_tokenizer_json(text: &str) -> Result<Bpe, String> {
        let value: serde_json::Value =
            serde_json::from_str(text).map_err(|e| format!("`tokenizer.json` is not JSON: {e}"))?;
        let model = value.get("model").ok_or("`tokenizer.json` has no `model`")?;
        let vocab: HashMap<String, u32> = model
            .get("vocab")
            .cloned()
            .map(serde_json::from_value)
            .ok_or("`tokenizer.json` has no `model.vocab`")?
            .map_err(|e| format!("`model.vocab` is not an object of token ids: {e}"))?;
        let list = model
            .get("merges")
            .and_then(serde_json::Value::as_array)
            .ok_or("`tokenizer.json` has no `model.merges` list")?;
        let mut merges = Vec::with_capacity(list.len());
        for (i, m) in list.iter().enumerate() {
            let pair = match m {
                serde_json::Value::String(s) => {
                    s.split_once(' ').map(|(a, b)| (a.into(), b.into()))
                }
                serde_json::Value::Array(a) => match a.as_slice() {
                    [serde_json::Value::String(x), serde_json::Value::String(y)] => {
                        Some((x.clone(), y.clone()))
                    }
                    _ => None,
                },
                _ => None,
            };
            merges.push(pair.ok_or_else(|| format!("merge {} is not two tokens", i + 1))?);
        }
        Bpe::new(vocab, merges)
    }

    /// The id of `<|endoftext|>`.
    pub fn end_id(&self) -> u32 {
        self.end
    }

    /// How many tokens the vocabulary has.
    pub fn vocab_len(&self) -> usize {
        self.encoder.len()
    }

    /// The BPE pieces of one pre-split piece already mapped to byte characters.
    fn bpe(&self, token: &str) -> Vec<String> {
        let chars: Vec<char> = token.chars().collect();
        let Some((last, rest)) = chars.split_last() else { return Vec::new() };
        let mut word: Vec<String> = rest.iter().map(char::to_string).collect();
        word.push(format!("{last}</w>"));
        while word.len() > 1 {
            // The pair of lowest rank; `None` when no pair is a merge.
            let best = word
                .windows(2)
                .filter_map(|p| self.ranks.get(&(p[0].clone(), p[1].clone())).map(|&r| (r, p)))
                .min_by_key(|(r, _)| *r)
                .map(|(_, p)| (p[0].clone(), p[1].clone()));
            let Some((first, second)) = best else { break };
            let mut merged = Vec::with_capacity(word.len());
            let mut i = 0;
            while i < word.len() {
                if i + 1 < word.len() && word[i] == first && word[i + 1] == second {
                    merged.push(format!("{first}{second}"));
                    i += 2;
                } else {
                    merged.push(std::mem::take(&mut word[i]));
                    i += 1;
                }
            }
            word = merged;
        }
        word
    }

    /// The ids of `text` without the start and end tokens.
    pub fn encode(&self, text: &str) -> Vec<u32> {
        let cleaned = text.split_whitespace().collect::<Vec<_>>().join(" ").to_lowercase();
        let mut out = Vec::new();
        for m in self.pattern.find_iter(&cleaned) {
            let piece = m.as_str();
            if piece == START || piece == END {
                out.push(if piece == START { self.start } else { self.end });
                continue;
            }
            let mapped: String = piece.bytes().map(|b| self.byte_chars[b as usize]).collect();
            for token in self.bpe(&mapped) {
                // `new` checked that every piece BPE can make is in the vocabulary.
                if let Some(&id) = self.encoder.get(&token) {
                    out.push(id);
                }
            }
        }
        out
    }

    /// What the tower reads for `text`: `<|startoftext|>`, its ids, `<|endoftext|>`; cut to
    /// [`CONTEXT_LENGTH`] with `<|endoftext|>` last, as open_clip's `tokenize` does (the padding
    /// after it changes nothing under the causal mask, so none is added).
    pub fn tokenize(&self, text: &str) -> Vec<u32> {
        let mut ids = Vec::with_capacity(CONTEXT_LENGTH);
        ids.push(self.start);
        ids.extend(self.encode(text));
        ids.push(self.end);
        if ids.len() > CONTEXT_LENGTH {
            ids.truncate(CONTEXT_LENGTH);
            ids[CONTEXT_LENGTH - 1] = self.end;
        }
        ids
    }
}

/// CLIP's vocabulary for `merges`, built as open_clip builds it from its merges file: the 256
/// byte characters (in `bytes_to_unicode`'s order: the printable bytes, then the others), the
/// same with `</w>`, each merge's result in rank order, `<|startoftext|>`, `<|endoftext|>`. With
/// CLIP's 48,894 merges this is its 49,408 tokens (`a</w>` 320, `<|endoftext|>` 49407).
pub fn vocab_for(merges: &[(String, String)]) -> HashMap<String, u32> {
    let chars = bytes_to_unicode();
    let printable: Vec<usize> = (0..256).filter(|&b| u32::from(chars[b]) == b as u32).collect();
    let others: Vec<usize> = (0..256).filter(|&b| u32::from(chars[b]) != b as u32).collect();
    let order: Vec<char> = printable.iter().chain(&others).map(|&b| chars[b]).collect();
    let mut tokens: Vec<String> = order.iter().map(char::to_string).collect();
    tokens.extend(order.iter().map(|c| format!("{c}</w>")));
    tokens.extend(merges.iter().map(|(a, b)| format!("{a}{b}")));
    tokens.push(START.into());
    tokens.push(END.into());
    let mut vocab = HashMap::with_capacity(tokens.len());
    for (i, t) in tokens.into_iter().enumerate() {
        vocab.insert(t, i as u32);
    }
    vocab
}

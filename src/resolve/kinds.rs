//! Kinds of things: words whose thing is a kind of an AI2-THOR type (a `chaise longue` is a
//! kind of sofa, a `wristwatch` a kind of watch, a `recycling bin` a kind of garbage can).
//!
//! The table, `data/catalog/kinds.tsv`, is made by `scripts/gen_kind_table.py` from WordNet
//! 3.0: for each type the senses that are that type, chosen by hand, with their hyponyms
//! reviewed, plus reviewed words WordNet does not relate. Resolution consults it only when no
//! asset ranks good enough by its words: the thing then gets an asset of the type it is a kind
//! of, and the choice says which word decided and where the row came from.

use std::collections::BTreeMap;
use std::sync::OnceLock;

use super::text;

/// The table as shipped.
const TABLE: &str = include_str!("../../data/catalog/kinds.tsv");

/// One row of the table.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct Kind {
    /// The word or phrase (lower case, words separated by spaces).
    pub word: &'static str,
    /// The AI2-THOR object types it is a kind of, best first (`-` alone: a reviewed phrase that
    /// is no kind of any type, such as `reading glasses`).
    pub types: Vec<&'static str>,
    /// Where the row came from (`wordnet: chaise.1`, `reviewed: …`).
    pub source: &'static str,
}

fn table() -> &'static BTreeMap<&'static str, Kind> {
    static TABLE_MAP: OnceLock<BTreeMap<&'static str, Kind>> = OnceLock::new();
    TABLE_MAP.get_or_init(|| {
        let mut map = BTreeMap::new();
        for line in TABLE.lines().filter(|l| !l.starts_with('#') && !l.trim().is_empty()) {
            let mut fields = line.split('\t');
            let (Some(word), Some(types), Some(source)) =
                (fields.next(), fields.next(), fields.next())
            else {
                continue;
            };
            map.insert(word, Kind { word, types: types.split(',').collect(), source });
        }
        map
    })
}

/// The number of rows (for the book and the tests).
pub fn len() -> usize {
    table().len()
}

/// The row for a noun phrase: the longest run of its last words that the table knows, tried
/// as written, singular and written as one word (`bean bag` / `beanbag`), so that words in
/// front that the table does not know (`small`, `wooden`, `vintage`) do not count. `None` when no ending of the phrase is a known kind.
pub fn lookup(noun_phrase: &str) -> Option<&'static Kind> {
    let words: Vec<String> = noun_phrase
        .split(|c: char| !(c.is_alphanumeric() || c == '-' || c == '\''))
        .map(|w| w.trim_matches(|c| c == '-' || c == '\'').to_lowercase())
        .filter(|w| !w.is_empty())
        .collect();
    let map = table();
    for start in 0..words.len() {
        let tail = &words[start..];
        let as_written = tail.join(" ");
        let mut singular: Vec<String> = tail.to_vec();
        if let Some(last) = singular.last_mut() {
            *last = text::singular(last);
        }
        let singular = singular.join(" ");
        let joined = singular.replace(' ', "");
        for key in [as_written.as_str(), singular.as_str(), joined.as_str()] {
            if let Some(kind) = map.get(key) {
                // A reviewed phrase that is no kind of any type ends the lookup.
                return (kind.types != ["-"]).then_some(kind);
            }
        }
    }
    None
}

#[cfg(test)]
mod tests {
    use super::*;

    fn types(phrase: &str) -> Option<Vec<&'static str>> {
        lookup(phrase).map(|k| k.types.clone())
    }

    #[test]
    fn kinds_name_their_type() {
        assert_eq!(types("vintage chaise longue"), Some(vec!["Sofa"]));
        assert_eq!(types("wristwatch"), Some(vec!["Watch"]));
        assert_eq!(types("blue recycling bin"), Some(vec!["GarbageCan"]));
        assert_eq!(types("cookbooks"), Some(vec!["Book"]));
        assert_eq!(types("ring-binder"), Some(vec!["Book"]));
        assert_eq!(types("succulents"), Some(vec!["HousePlant"]));
        assert_eq!(types("statuette"), Some(vec!["Statue"]));
        assert_eq!(types("picture frame"), Some(vec!["Painting"]));
        assert_eq!(types("candle holder"), Some(vec!["Candle"]));
        assert!(len() > 500);
    }

    #[test]
    fn unrelated_things_are_not_kinds() {
        assert_eq!(types("wheelchair"), None);
        assert_eq!(types("music stand"), None);
        assert_eq!(types("grand piano"), None);
        assert_eq!(types("mouse pad"), None);
        assert_eq!(types("whiteboard"), None);
        assert_eq!(types("reading glasses"), None);
        assert_eq!(types("air hockey table"), None);
        assert_eq!(types("vital signs monitor"), None);
    }
}

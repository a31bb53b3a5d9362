//! Which things go on which receptacles: the pairs (item type, receptacle type) of ProcTHOR's
//! `receptacles.json`, as `data/catalog/receptacles.tsv` (made by
//! `scripts/gen_receptacle_table.py`; a few pairs people make that the file lacks, a television
//! on its stand, are added there with their reasons).
//!
//! Resolution prefers, for a thing on top of a receptacle whose asset type is known, assets of
//! types the pair allows (a book on a shelving unit, never a house plant on a house plant); the
//! solve stage asks [`allowed_on`] to put a thing whose pair is not allowed on another
//! receptacle of the room. Types are AI2-THOR object types (`ShelvingUnit`, `HousePlant`).

use std::collections::{BTreeMap, BTreeSet};
use std::sync::OnceLock;

const TABLE: &str = include_str!("../../data/catalog/receptacles.tsv");

/// Receptacle type → item type → how often ProcTHOR saw it there (`None`: a pair added by
/// holoc).
type Pairs = BTreeMap<&'static str, BTreeMap<&'static str, Option<u32>>>;

fn pairs() -> &'static Pairs {
    static PAIRS: OnceLock<Pairs> = OnceLock::new();
    PAIRS.get_or_init(|| {
        let mut map: Pairs = BTreeMap::new();
        for line in TABLE.lines().filter(|l| !l.starts_with('#') && !l.trim().is_empty()) {
            let f: Vec<&str> = line.split('\t').collect();
            if let [receptacle, item, count] = f[..] {
                map.entry(receptacle).or_default().insert(item, count.parse().ok());
            }
        }
        map
    })
}

/// Whether the table can judge a thing of `item_type`: an AI2-THOR object type (one word,
/// capitalised: `Book`, `HousePlant`). An objathor asset whose annotation has no AI2-THOR type
/// has its category as type (`picture frame`), which ProcTHOR's houses never held: the pair
/// rule neither prefers nor refuses it, as the original system put such assets on any
/// receptacle.
pub fn judges(item_type: &str) -> bool {
    item_type.chars().next().is_some_and(|c| c.is_ascii_uppercase())
        && item_type.chars().all(|c| c.is_ascii_alphanumeric() || c == '_')
}

/// Whether a thing of `item_type` may be put on a receptacle of `receptacle_type`: the pair is
/// in the table. `false` for a receptacle type the table does not know (see
/// [`is_receptacle_type`]) and for an item type never put on this receptacle.
pub fn allowed_on(item_type: &str, receptacle_type: &str) -> bool {
    pairs().get(receptacle_type).is_some_and(|items| items.contains_key(item_type))
}

/// How often ProcTHOR's houses had a thing of `item_type` on a receptacle of
/// `receptacle_type` (`None` when the pair is not in the table or was added by holoc).
pub fn pair_count(item_type: &str, receptacle_type: &str) -> Option<u32> {
    pairs().get(receptacle_type).and_then(|items| items.get(item_type).copied().flatten())
}

/// Every receptacle type of the table, sorted (`ArmChair` … `TowelHolder`).
pub fn receptacle_types() -> Vec<&'static str> {
    pairs().keys().copied().collect()
}

/// Whether the table knows `receptacle_type` as a receptacle (things are put on it).
pub fn is_receptacle_type(receptacle_type: &str) -> bool {
    pairs().contains_key(receptacle_type)
}

/// The item types the table allows on `receptacle_type`, sorted (empty for a type it does not
/// know).
pub fn items_on(receptacle_type: &str) -> Vec<&'static str> {
    pairs().get(receptacle_type).map(|items| items.keys().copied().collect()).unwrap_or_default()
}

/// Every item type the table puts on some receptacle, sorted.
pub fn item_types() -> BTreeSet<&'static str> {
    pairs().values().flat_map(|items| items.keys().copied()).collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn pairs_of_the_table() {
        assert!(allowed_on("Book", "ShelvingUnit"));
        assert!(allowed_on("HousePlant", "ShelvingUnit"));
        assert!(allowed_on("Towel", "TowelHolder"));
        assert!(allowed_on("Pillow", "Bed"));
        assert!(allowed_on("HousePlant", "SideTable"));
        assert!(allowed_on("Television", "TVStand"), "added: a television on its stand");
        assert_eq!(pair_count("Television", "TVStand"), None);
        assert_eq!(pair_count("Book", "Bed"), Some(15));
        // What the issue calls absurd pairs.
        assert!(!allowed_on("HousePlant", "HousePlant"), "no plant on a plant");
        assert!(!allowed_on("DeskLamp", "ArmChair"), "no desk lamp on an armchair's seat");
        assert!(!allowed_on("ToiletPaper", "Desk"));
        assert!(!allowed_on("Book", "Painting"), "a painting is no receptacle");
        assert!(!is_receptacle_type("HousePlant"));
        assert!(is_receptacle_type("CoffeeTable"));
        let types = receptacle_types();
        assert_eq!(types.len(), 26);
        assert!(types.windows(2).all(|w| w[0] < w[1]));
        assert!(items_on("TowelHolder").contains(&"Towel"));
        assert!(items_on("Nothing").is_empty());
        assert!(item_types().contains("Book"));
    }

    /// Every type of the table names a type of the embedded catalog (a typo would silently
    /// allow nothing).
    #[test]
    fn every_type_is_in_the_catalog() {
        let catalog = super::super::Catalog::embedded();
        let known: BTreeSet<&str> = catalog.assets().iter().map(|a| &*a.object_type).collect();
        for r in receptacle_types() {
            assert!(known.contains(r), "receptacle {r}");
        }
        for i in item_types() {
            // `Window` is in ProcTHOR's table (things on a window sill) but is no object asset;
            // the things holoc makes have types of their own.
            let made = crate::make::KINDS.iter().any(|k| k.object_type == i);
            assert!(known.contains(i) || i == "Window" || made, "item {i}");
        }
    }
}

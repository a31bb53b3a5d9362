//! Stand-ins: when no asset is good enough for an object, an asset of another AI2-THOR type
//! that does the same job in the room takes its place, so the room keeps its furniture.
//!
//! The table is written by hand, one line per kind of thing, each with the types that may
//! stand in and the reason a person would accept it (a wardrobe and a dresser both store
//! clothes). Only what is in the table stands in: a thing with no entry (a piano, a treadmill)
//! stays out and is reported, never filled with something unrelated. Keys are read from the
//! object's category, from the noun phrase that names the thing: a two-word key ending at the
//! head (`console table`) before the head word (`wardrobe`); no other word counts, so a `plant
//! stand` is never a plant. A line without types says a thing has no stand-in (a `privacy
//! curtain` is no window covering). When the thing has things on top, only types that hold
//! things stand in (resolution filters the line's types).

use super::catalog::{Asset, Catalog, PlacementKind};

/// One line of the table.
pub struct StandIn {
    /// The words of the category it applies to (one or two words).
    pub key: &'static str,
    /// The AI2-THOR object types that may stand in, best first (none: known to have no
    /// stand-in).
    pub types: &'static [&'static str],
    /// Why a person accepts it.
    pub reason: &'static str,
}

/// The stand-in table.
pub const STAND_INS: &[StandIn] = &[
    // Storage.
    StandIn {
        key: "wardrobe",
        types: &["Dresser"],
        reason: "both store clothes in a tall case with doors or drawers",
    },
    StandIn { key: "armoire", types: &["Dresser"], reason: "both store clothes in a tall case" },
    StandIn {
        key: "closet",
        types: &["Dresser"],
        reason: "a free-standing closet stores clothes like a dresser",
    },
    StandIn { key: "chest", types: &["Dresser"], reason: "a chest of drawers is a dresser" },
    StandIn { key: "bureau", types: &["Dresser"], reason: "a bureau is a chest of drawers" },
    StandIn { key: "tallboy", types: &["Dresser"], reason: "a tallboy is a tall chest of drawers" },
    StandIn { key: "highboy", types: &["Dresser"], reason: "a highboy is a tall chest of drawers" },
    StandIn {
        key: "sideboard",
        types: &["Dresser", "TVStand"],
        reason: "a low storage cabinet against a wall",
    },
    StandIn {
        key: "buffet",
        types: &["Dresser", "TVStand"],
        reason: "a low storage cabinet against a wall",
    },
    StandIn {
        key: "credenza",
        types: &["Dresser", "TVStand"],
        reason: "a low storage cabinet against a wall",
    },
    StandIn {
        key: "cabinet",
        types: &["Dresser", "ShelvingUnit"],
        reason: "storage with doors or drawers",
    },
    StandIn { key: "cupboard", types: &["Dresser", "ShelvingUnit"], reason: "storage with doors" },
    StandIn { key: "locker", types: &["Dresser"], reason: "storage for personal things" },
    StandIn { key: "bookcase", types: &["ShelvingUnit"], reason: "shelves that hold books" },
    StandIn { key: "bookshelf", types: &["ShelvingUnit"], reason: "shelves that hold books" },
    StandIn { key: "shelf", types: &["ShelvingUnit"], reason: "a shelf is a shelving unit" },
    StandIn { key: "shelves", types: &["ShelvingUnit"], reason: "shelves are a shelving unit" },
    StandIn { key: "etagere", types: &["ShelvingUnit"], reason: "open shelves" },
    // Tables.
    StandIn {
        key: "console table",
        types: &["SideTable"],
        reason: "a narrow table against a wall",
    },
    StandIn { key: "hall table", types: &["SideTable"], reason: "a narrow table against a wall" },
    StandIn { key: "entry table", types: &["SideTable"], reason: "a narrow table against a wall" },
    StandIn { key: "end table", types: &["SideTable"], reason: "an end table is a side table" },
    StandIn { key: "accent table", types: &["SideTable"], reason: "a small table beside seating" },
    StandIn { key: "nightstand", types: &["SideTable"], reason: "a bedside table is a side table" },
    StandIn {
        key: "bedside table",
        types: &["SideTable"],
        reason: "a bedside table is a side table",
    },
    StandIn {
        key: "conference table",
        types: &["DiningTable"],
        reason: "a large table to sit around",
    },
    StandIn { key: "meeting table", types: &["DiningTable"], reason: "a table to sit around" },
    StandIn {
        key: "bistro table",
        types: &["DiningTable", "SideTable"],
        reason: "a small table to sit at",
    },
    StandIn { key: "kitchen table", types: &["DiningTable"], reason: "a table to eat at" },
    StandIn { key: "breakfast table", types: &["DiningTable"], reason: "a table to eat at" },
    StandIn { key: "work table", types: &["Desk", "DiningTable"], reason: "a table to work at" },
    StandIn { key: "writing table", types: &["Desk"], reason: "a table to write at is a desk" },
    StandIn {
        key: "kitchen island",
        types: &["CounterTop"],
        reason: "an island is a free-standing counter",
    },
    StandIn { key: "island", types: &["CounterTop"], reason: "a kitchen island is a counter" },
    StandIn { key: "media console", types: &["TVStand"], reason: "a low cabinet for a screen" },
    StandIn { key: "entertainment center", types: &["TVStand"], reason: "a cabinet for a screen" },
    StandIn { key: "vanity", types: &["Sink"], reason: "a bathroom vanity is a sink cabinet" },
    StandIn { key: "vanity unit", types: &["Sink"], reason: "a bathroom vanity is a sink cabinet" },
    StandIn { key: "media unit", types: &["TVStand"], reason: "a low cabinet for a screen" },
    StandIn { key: "media cabinet", types: &["TVStand"], reason: "a low cabinet for a screen" },
    StandIn {
        key: "entertainment unit",
        types: &["TVStand"],
        reason: "a low cabinet for a screen",
    },
    StandIn {
        key: "wine rack",
        types: &["ShelvingUnit"],
        reason: "open shelving that holds bottles",
    },
    StandIn {
        key: "card catalog",
        types: &["Dresser"],
        reason: "a cabinet of small drawers, like a chest of drawers",
    },
    StandIn {
        key: "carrel",
        types: &["Desk"],
        reason: "a study carrel is a desk with side panels",
    },
    // Seats and beds.
    StandIn { key: "loveseat", types: &["Sofa"], reason: "a loveseat is a small sofa" },
    StandIn { key: "couch", types: &["Sofa"], reason: "a couch is a sofa" },
    StandIn { key: "settee", types: &["Sofa"], reason: "a settee is a small sofa" },
    StandIn { key: "futon", types: &["Sofa"], reason: "a futon is a sofa bed" },
    StandIn {
        key: "recliner",
        types: &["ArmChair"],
        reason: "a recliner is an upholstered armchair",
    },
    StandIn { key: "pouf", types: &["Ottoman", "Footstool"], reason: "a low upholstered seat" },
    StandIn { key: "pouffe", types: &["Ottoman", "Footstool"], reason: "a low upholstered seat" },
    StandIn { key: "hassock", types: &["Ottoman", "Footstool"], reason: "a low upholstered seat" },
    StandIn { key: "barstool", types: &["Stool"], reason: "a bar stool is a stool" },
    StandIn {
        key: "bench",
        types: &["Ottoman", "Sofa"],
        reason: "a backless seat for sitting down briefly, like an ottoman",
    },
    StandIn {
        key: "booth",
        types: &["Sofa"],
        reason: "booth seating is an upholstered bench with a back, like a sofa",
    },
    StandIn { key: "crib", types: &["Bed"], reason: "a crib is a child's bed" },
    StandIn { key: "cot", types: &["Bed"], reason: "a cot is a small bed" },
    StandIn { key: "daybed", types: &["Bed", "Sofa"], reason: "a daybed is a bed used as a seat" },
    // Things people keep and show.
    StandIn { key: "plant", types: &["HousePlant"], reason: "a potted plant" },
    StandIn { key: "succulent", types: &["HousePlant"], reason: "a potted plant" },
    StandIn { key: "cactus", types: &["HousePlant"], reason: "a potted plant" },
    StandIn { key: "fern", types: &["HousePlant"], reason: "a potted plant" },
    StandIn { key: "bonsai", types: &["HousePlant"], reason: "a potted plant" },
    StandIn { key: "orchid", types: &["HousePlant"], reason: "a potted plant" },
    StandIn { key: "sculpture", types: &["Statue"], reason: "a decorative figure" },
    StandIn { key: "statuette", types: &["Statue"], reason: "a small statue" },
    StandIn { key: "figurine", types: &["Statue"], reason: "a small statue" },
    StandIn { key: "bust", types: &["Statue"], reason: "a sculpted head is a statue" },
    StandIn { key: "poster", types: &["Painting"], reason: "a picture on the wall" },
    StandIn { key: "print", types: &["Painting"], reason: "a picture on the wall" },
    StandIn { key: "artwork", types: &["Painting"], reason: "a picture on the wall" },
    StandIn { key: "picture", types: &["Painting"], reason: "a picture on the wall" },
    StandIn { key: "novel", types: &["Book"], reason: "a novel is a book" },
    StandIn { key: "notebook", types: &["Book"], reason: "a bound notebook looks like a book" },
    StandIn { key: "journal", types: &["Book"], reason: "a bound journal looks like a book" },
    StandIn { key: "textbook", types: &["Book"], reason: "a textbook is a book" },
    StandIn { key: "magazine", types: &["Newspaper", "Book"], reason: "printed pages to read" },
    StandIn { key: "wristwatch", types: &["Watch"], reason: "a wristwatch is a watch" },
    StandIn { key: "cushion", types: &["Pillow"], reason: "a cushion is a pillow" },
    StandIn {
        key: "computer monitor",
        types: &["Desktop", "Laptop"],
        reason: "a computer screen on a desk",
    },
    StandIn { key: "computer", types: &["Desktop", "Laptop"], reason: "a computer" },
    StandIn { key: "teacup", types: &["Cup", "Mug"], reason: "a cup" },
    StandIn {
        key: "spice jar",
        types: &["SaltShaker", "PepperShaker"],
        reason: "a small container of seasoning by the stove",
    },
    StandIn {
        key: "spice rack",
        types: &["SaltShaker", "PepperShaker"],
        reason: "small containers of seasoning by the stove",
    },
    StandIn { key: "tumbler", types: &["Cup"], reason: "a drinking cup" },
    StandIn { key: "wastebasket", types: &["GarbageCan"], reason: "a bin for waste" },
    StandIn { key: "hamper", types: &["LaundryHamper"], reason: "a basket for laundry" },
    StandIn {
        key: "towel rack",
        types: &["TowelHolder", "HandTowelHolder"],
        reason: "a rack for towels",
    },
    StandIn {
        key: "towel bar",
        types: &["TowelHolder", "HandTowelHolder"],
        reason: "a bar for towels",
    },
    StandIn {
        key: "towel rail",
        types: &["TowelHolder", "HandTowelHolder"],
        reason: "a rail for towels",
    },
    StandIn {
        key: "paper holder",
        types: &["ToiletPaperHanger"],
        reason: "a holder for the toilet roll",
    },
    // Pets: the catalog's pet beds are dog beds.
    StandIn {
        key: "cat bed",
        types: &["DogBed"],
        reason: "a pet's cushioned bed on the floor; the catalog's pet beds are dog beds",
    },
    StandIn {
        key: "pet bed",
        types: &["DogBed"],
        reason: "a pet's cushioned bed on the floor; the catalog's pet beds are dog beds",
    },
    StandIn {
        key: "kitty bed",
        types: &["DogBed"],
        reason: "a pet's cushioned bed on the floor; the catalog's pet beds are dog beds",
    },
    // Window coverings: blinds cover a window as curtains do.
    StandIn {
        key: "curtain",
        types: &["Blinds"],
        reason: "a window covering; blinds cover the window as curtains do",
    },
    StandIn {
        key: "drape",
        types: &["Blinds"],
        reason: "a window covering; blinds cover the window as drapes do",
    },
    StandIn { key: "shade", types: &["Blinds"], reason: "a window shade is a blind" },
    // Not over a window: no stand-in (a privacy curtain on a ceiling track is no blind).
    StandIn {
        key: "privacy curtain",
        types: &[],
        reason: "it hangs across a room, not at a window",
    },
    StandIn { key: "lamp shade", types: &[], reason: "a part of a lamp, not a window covering" },
    // Papers: loose printed pages lie flat like a newspaper.
    StandIn {
        key: "papers",
        types: &["Newspaper"],
        reason: "loose printed pages lying flat, like a folded newspaper",
    },
    StandIn {
        key: "documents",
        types: &["Newspaper"],
        reason: "printed pages lying flat, like a folded newspaper",
    },
    StandIn {
        key: "plant stand",
        types: &["SideTable"],
        reason: "a small stand that holds a plant, like a small side table",
    },
    StandIn { key: "refrigerator", types: &["Fridge"], reason: "a refrigerator is a fridge" },
    StandIn { key: "washer", types: &["WashingMachine"], reason: "a washer is a washing machine" },
    StandIn { key: "dryer", types: &["ClothesDryer"], reason: "a clothes dryer" },
];

/// The words of a category, lower-case, without punctuation, plural `s` kept.
fn words(text: &str) -> Vec<String> {
    text.to_lowercase()
        .split(|c: char| !c.is_alphanumeric())
        .filter(|w| !w.is_empty())
        .map(str::to_owned)
        .collect()
}

/// The table line for a category, read from the noun phrase that names the thing (`writing
/// desk with drawers` → `writing desk`, `stack of papers` → `papers`): its last two words
/// (`console table`), else its last word (`tall white wardrobe`), each also with a plural made
/// singular. Only the head counts: a `plant stand` is a stand, never a plant. `None` also for a
/// line that names no type (a `privacy curtain` is known to have no stand-in).
pub fn lookup(category: &str) -> Option<&'static StandIn> {
    let (phrase, _) = super::text::split_phrase(category);
    let w = words(&phrase);
    let find = |key: &str| {
        let singular = key.strip_suffix('s').unwrap_or(key);
        STAND_INS.iter().find(|s| s.key == key || s.key == singular)
    };
    let line = match w.as_slice() {
        [.., a, b] => find(&format!("{a} {b}")).or_else(|| find(b)),
        [b] => find(b),
        [] => None,
    };
    line.filter(|l| !l.types.is_empty())
}

/// A stand-in (or a thing placed in a way its type does not list, W0404) is refused when its
/// size ratio ([`size_ratio`]) to the size asked is above this: an asset of another type may be
/// at most twice as large or half as large as the thing, side by side. Twice is the bound the
/// things on top already keep (`resolve::MAX_SIZE_RATIO`); it lets a 1.30 m dresser stand in
/// for a 2 m wardrobe, and keeps out a 0.89 m tall one.
pub const MAX_STAND_IN_RATIO: f64 = 2.0;

/// The shortest side a size ratio compares, metres: sides below it count as 1 cm, so that a
/// thing written with no depth is not infinitely far from any asset.
const RATIO_MIN_SIDE_M: f64 = 0.01;

/// How far an asset's size is from the size asked: the largest, over the sides compared, of
/// the longer length over the shorter (1 is the same size, 2 twice as large or half as large on
/// some side). `asset_m` is an asset's bounding box (x width, y height, z depth), `asked_m` the
/// size written (width, depth, height). Which sides are compared depends on how the thing is
/// placed, since its asset stands upright and turns only about the vertical:
/// - on the floor or at the ceiling: the heights, and the two horizontal sides sorted (a thing
///   on the floor turns, so its width may be the asset's depth);
/// - on a wall: the width along the wall and the height (not the thickness, a few centimetres
///   either way);
/// - on top of another object: the two longest sides of each, sorted (a book may lie or stand).
pub fn size_ratio(asset_m: [f64; 3], asked_m: [f64; 3], kind: PlacementKind) -> f64 {
    let side = |a: f64, b: f64| {
        let (a, b) = (a.max(RATIO_MIN_SIDE_M), b.max(RATIO_MIN_SIDE_M));
        a.max(b) / a.min(b)
    };
    let sorted2 = |a: f64, b: f64| if a <= b { [a, b] } else { [b, a] };
    let [x, y, z] = asset_m;
    let [width, depth, height] = asked_m;
    match kind {
        PlacementKind::Floor | PlacementKind::Ceiling => {
            let (h, w) = (sorted2(x, z), sorted2(width, depth));
            side(y, height).max(side(h[0], w[0])).max(side(h[1], w[1]))
        }
        PlacementKind::Wall => side(x, width).max(side(y, height)),
        PlacementKind::OnObject => {
            let longest_two = |mut v: [f64; 3]| {
                v.sort_by(f64::total_cmp);
                [v[1], v[2]]
            };
            let (a, b) = (longest_two(asset_m), longest_two(asked_m));
            side(a[0], b[0]).max(side(a[1], b[1]))
        }
    }
}

/// The asset that stands in, of the line's types (see [`pick_stand_in`]).
pub fn pick<'c>(
    catalog: &'c Catalog,
    line: &StandIn,
    kind: PlacementKind,
    size_m: Option<[f64; 3]>,
) -> Option<(&'c Asset, Option<f64>)> {
    pick_stand_in(catalog, line.types, kind, size_m)
}

/// The asset that stands in: of `types` in order, the first type's asset of the right placement
/// kind with the smallest size ratio to the asked size (ties: catalog order), with that ratio;
/// a later type only when the earlier ones have no asset within [`MAX_STAND_IN_RATIO`]. When
/// no type has one within it, the nearest asset of all, which the caller refuses. Without an
/// asked size, the first asset in catalog order of the first type that has one, and no ratio.
/// `None` when the catalog has none of the types.
pub fn pick_stand_in<'c>(
    catalog: &'c Catalog,
    types: &[&str],
    kind: PlacementKind,
    size_m: Option<[f64; 3]>,
) -> Option<(&'c Asset, Option<f64>)> {
    let mut nearest: Option<(&Asset, Option<f64>)> = None;
    for ty in types {
        let mut best: Option<(&Asset, Option<f64>)> = None;
        for asset in catalog.assets().iter().filter(|a| a.object_type == *ty && a.allows(kind)) {
            let ratio = size_m.map(|want| size_ratio(asset.bbox_m, want, kind));
            let better = match (best, ratio) {
                (None, _) => true,
                (Some((_, Some(b))), Some(r)) => r < b - 1e-12,
                _ => false,
            };
            if better {
                best = Some((asset, ratio));
            }
        }
        let Some(best) = best else { continue };
        if best.1.is_none_or(|r| r <= MAX_STAND_IN_RATIO + 1e-9) {
            return Some(best);
        }
        if nearest.is_none_or(|(_, n)| best.1 < n) {
            nearest = Some(best);
        }
    }
    nearest
}

/// Of `types` in order, the asset of the right placement kind whose sorted size is closest to
/// the wanted one (or the first in catalog order without a wanted size).
pub fn pick_of_types<'c>(
    catalog: &'c Catalog,
    types: &[&str],
    kind: PlacementKind,
    size_m: Option<[f64; 3]>,
) -> Option<&'c Asset> {
    let sorted = |mut v: [f64; 3]| {
        v.sort_by(f64::total_cmp);
        v
    };
    for ty in types {
        let mut best: Option<(f64, &Asset)> = None;
        for asset in catalog.assets().iter().filter(|a| a.object_type == *ty && a.allows(kind)) {
            let diff = size_m.map_or(0.0, |want| {
                let (a, b) = (sorted(asset.bbox_m), sorted(want));
                (0..3).map(|i| (a[i] - b[i]).abs()).sum::<f64>() / 3.0
            });
            if best.is_none_or(|(d, _)| diff < d - 1e-12) {
                best = Some((diff, asset));
            }
        }
        if let Some((_, asset)) = best {
            return Some(asset);
        }
    }
    None
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn keys_are_read_from_the_category() {
        assert_eq!(lookup("tall white wardrobe").map(|s| s.key), Some("wardrobe"));
        assert_eq!(lookup("oak console table").map(|s| s.key), Some("console table"));
        assert_eq!(lookup("succulents").map(|s| s.key), Some("succulent"));
        assert_eq!(lookup("pouffes").map(|s| s.key), Some("pouffe"));
        assert!(lookup("grand piano").is_none());
        assert!(lookup("treadmill").is_none());
    }

    #[test]
    fn only_the_head_decides() {
        assert_eq!(lookup("wooden plant stand").map(|s| s.types), Some(&["SideTable"][..]));
        assert_eq!(lookup("cat bed").map(|s| s.types), Some(&["DogBed"][..]));
        assert_eq!(lookup("plush pet bed").map(|s| s.types), Some(&["DogBed"][..]));
        assert_eq!(lookup("linen curtains").map(|s| s.types), Some(&["Blinds"][..]));
        assert_eq!(lookup("stack of papers").map(|s| s.types), Some(&["Newspaper"][..]));
        assert_eq!(lookup("bookshelf with plants").map(|s| s.key), Some("bookshelf"));
        // A word before the head is no key: a plant stand is no plant, a cat tree no cat.
        assert!(lookup("plant pot holder").is_none());
        assert!(lookup("privacy curtain").is_none(), "known to have no stand-in");
        assert!(lookup("wrapping paper").is_none());
        assert!(lookup("wall mirror").is_none());
    }

    #[test]
    fn size_ratio_compares_the_sides_a_placement_keeps() {
        // A 1.91 m wide, 0.89 m tall dresser for a 1 m wide, 2 m tall wardrobe: the heights
        // decide (2.25), not the sorted sides (which would match its width to the height).
        let dresser = [1.9121, 0.8935, 0.7207];
        let wardrobe = [1.0, 0.6, 2.0];
        let r = size_ratio(dresser, wardrobe, PlacementKind::Floor);
        assert!((r - 2.0 / 0.8935).abs() < 1e-9, "{r}");
        assert!(r > MAX_STAND_IN_RATIO);
        // Turned on the floor: width and depth are compared sorted.
        let r = size_ratio([0.6, 2.0, 1.0], wardrobe, PlacementKind::Floor);
        assert!((r - 1.0).abs() < 1e-9, "{r}");
        // On a wall the thickness does not count.
        let r = size_ratio([0.6, 0.8, 0.05], [0.6, 0.01, 0.8], PlacementKind::Wall);
        assert!((r - 1.0).abs() < 1e-9, "{r}");
        // A thing written with no depth is compared as 1 cm.
        let r = size_ratio([1.0, 1.0, 0.0], [1.0, 0.0, 1.0], PlacementKind::Floor);
        assert!(r.is_finite());
    }

    #[test]
    fn the_stand_in_is_the_nearest_in_size_and_refused_past_the_ratio() {
        let catalog = Catalog::embedded();
        let (asset, ratio) =
            pick_stand_in(&catalog, &["Dresser"], PlacementKind::Floor, Some([1.0, 0.6, 2.0]))
                .expect("a dresser");
        let ratio = ratio.expect("a size was asked");
        assert!(ratio <= MAX_STAND_IN_RATIO, "{} at {ratio}", asset.id);
        assert!(asset.bbox_m[1] > 1.2, "the tallest dressers are nearest: {}", asset.id);
        // A 4 m wardrobe: no dresser is within twice, the nearest is given to be refused.
        let (_, ratio) =
            pick_stand_in(&catalog, &["Dresser"], PlacementKind::Floor, Some([1.0, 0.6, 4.0]))
                .expect("a dresser");
        assert!(ratio.expect("a ratio") > MAX_STAND_IN_RATIO);
    }

    #[test]
    fn every_type_of_the_table_is_in_the_embedded_catalog() {
        let catalog = Catalog::embedded();
        for line in STAND_INS {
            assert!(!line.reason.is_empty(), "{}: every line has its reason", line.key);
            for ty in line.types {
                assert!(
                    catalog.assets().iter().any(|a| a.object_type == *ty),
                    "{}: no {ty} in the catalog",
                    line.key
                );
            }
        }
    }
}

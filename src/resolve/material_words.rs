//! The word rules of materials that do not depend on a design: the kinds of material words
//! name, whether words say light or dark, and which materials a tint colours.
//!
//! Plain `std` code on purpose: `build.rs` includes this file too, so that the facts of each
//! material it works out at compile time (`resolve::structure`) are those the run-time code
//! would work out.

/// Kinds of material a person names, with the words that name each (in a design text or in a
/// material's name). A design that names a kind ranks the materials of that kind up and the
/// materials of another kind down, so `walnut parquet` is a wood, never a fabric.
pub(crate) const MATERIAL_KINDS: [(&str, &[&str]); 7] = [
    (
        "wood",
        &[
            "wood",
            "wooden",
            "hardwood",
            "parquet",
            "plank",
            "planks",
            "laminate",
            "oak",
            "walnut",
            "maple",
            "pine",
            "cherry",
            "birch",
            "ash",
            "teak",
            "mahogany",
            "beech",
            "bamboo",
            "cedar",
            "timber",
            "woodfloors",
            "floorboards",
        ],
    ),
    (
        "stone",
        &[
            "stone",
            "marble",
            "granite",
            "greygranite",
            "slate",
            "concrete",
            "cement",
            "terrazzo",
            "travertine",
            "limestone",
            "sandstone",
            "quartz",
            "brick",
            "bricks",
        ],
    ),
    ("tile", &["tile", "tiles", "ceramic", "porcelain", "vinyl", "linoleum", "mosaic"]),
    ("carpet", &["carpet", "rug", "wool", "carpeted"]),
    ("fabric", &["fabric", "cloth", "velvet", "linen", "cotton", "upholstery"]),
    ("paint", &["drywall", "plaster", "paint", "painted", "stucco", "wallpaper", "eggshell"]),
    ("metal", &["metal", "steel", "iron", "aluminium", "aluminum", "brass", "copper"]),
];

/// A set of the kinds of [`MATERIAL_KINDS`]: bit `i` is its `i`-th kind.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub(crate) struct Kinds(pub(crate) u8);

impl Kinds {
    /// The kinds some words name.
    pub(crate) fn of<'a>(words: impl IntoIterator<Item = &'a str>) -> Kinds {
        let mut bits = 0u8;
        for word in words {
            for (i, (_, keys)) in MATERIAL_KINDS.iter().enumerate() {
                if keys.contains(&word) {
                    bits |= 1 << i;
                }
            }
        }
        Kinds(bits)
    }

    /// The set of one kind, by its name (empty for a name that is no kind).
    pub(crate) fn named(kind: &str) -> Kinds {
        let i = MATERIAL_KINDS.iter().position(|(name, _)| *name == kind);
        Kinds(i.map_or(0, |i| 1 << i))
    }

    /// Whether no kind is in the set.
    pub(crate) fn is_empty(self) -> bool {
        self.0 == 0
    }

    /// Whether the two sets share a kind.
    pub(crate) fn meets(self, other: Kinds) -> bool {
        self.0 & other.0 != 0
    }

    /// Whether every kind of the set is in `other`.
    pub(crate) fn within(self, other: Kinds) -> bool {
        self.0 & !other.0 == 0
    }

    /// The names of the kinds in the set, in the order of [`MATERIAL_KINDS`].
    pub(crate) fn names(self) -> impl Iterator<Item = &'static str> {
        MATERIAL_KINDS
            .iter()
            .enumerate()
            .filter(move |(i, _)| self.0 & (1 << i) != 0)
            .map(|(_, (name, _))| *name)
    }
}

/// The kinds a material's name words name, or `fabric` for a material of the `Fabric` group
/// whose words name none.
#[allow(dead_code, reason = "only build.rs works out a material's kinds")]
pub(crate) fn own_kinds<'a>(
    words: impl IntoIterator<Item = &'a str>,
    groups: impl IntoIterator<Item = &'a str>,
) -> Kinds {
    let own = Kinds::of(words);
    if own.is_empty() && groups.into_iter().any(|g| g == "Fabric") {
        Kinds::named("fabric")
    } else {
        own
    }
}

/// Name words of the near-white materials a tint may colour.
const TINTABLE_WORDS: [&str; 6] = ["white", "pure", "eggshell", "cream", "creame", "beige"];

/// Whether a tint colours a material of these name words truly: AI2-THOR multiplies the
/// texture by the `color`, so only a white or near-white texture (its name says `white`,
/// `eggshell`, `cream` or `beige`) shows the colour asked; a dark wood tinted blue is nearly
/// black.
pub(crate) fn is_tintable<'a>(mut words: impl Iterator<Item = &'a str>) -> bool {
    words.any(|w| TINTABLE_WORDS.contains(&w))
}

/// Whether words say light (`light`, `pale`, `white`) or dark (`dark`, `black`, `ebony`):
/// `Some(true)` light, `Some(false)` dark, `None` neither or both.
pub(crate) fn shade_of<'a>(words: impl Iterator<Item = &'a str> + Clone) -> Option<bool> {
    let has = |set: &[&str]| words.clone().any(|w| set.contains(&w));
    match (has(&["light", "pale", "white"]), has(&["dark", "black"])) {
        (true, false) => Some(true),
        (false, true) => Some(false),
        _ => None,
    }
}

/// Whether the groups of a material suit a floor (`Wood`, `Fabric`) and a wall (`Wall`).
#[allow(dead_code, reason = "only build.rs works out which surfaces a material suits")]
pub(crate) fn suits<'a>(groups: impl Iterator<Item = &'a str> + Clone) -> [bool; 2] {
    [groups.clone().any(|g| g == "Wood" || g == "Fabric"), groups.clone().any(|g| g == "Wall")]
}

/// Whether a material is a floor or wall candidate (groups `Wall`, `Wood`, `Fabric`).
pub(crate) fn is_surface<'a>(mut groups: impl Iterator<Item = &'a str>) -> bool {
    groups.any(|g| matches!(g, "Wall" | "Wood" | "Fabric"))
}

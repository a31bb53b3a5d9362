//! Placement kinds and flags, and which assets a kind admits.
//!
//! Plain `std` code on purpose: `build.rs` includes this file too, so that the embedded
//! catalog's index, made at compile time, decides placements exactly as the run-time code does.

/// Where an object can be placed.
#[derive(Clone, Copy, Debug, PartialEq, Eq, PartialOrd, Ord, Hash)]
pub enum PlacementKind {
    /// Stands on the floor.
    Floor,
    /// Hangs on a wall.
    Wall,
    /// Stands on another object (small objects).
    OnObject,
    /// Hangs from the ceiling.
    Ceiling,
}

impl PlacementKind {
    /// Every kind, in this order.
    pub const ALL: [PlacementKind; 4] = [
        PlacementKind::Floor,
        PlacementKind::Wall,
        PlacementKind::OnObject,
        PlacementKind::Ceiling,
    ];

    /// The word used on the command line and in reports.
    pub fn as_str(self) -> &'static str {
        match self {
            PlacementKind::Floor => "floor",
            PlacementKind::Wall => "wall",
            PlacementKind::OnObject => "on-object",
            PlacementKind::Ceiling => "ceiling",
        }
    }

    /// Parses [`PlacementKind::as_str`] (also `object` and `small` for on-object).
    pub fn parse(text: &str) -> Option<PlacementKind> {
        match text.trim().to_ascii_lowercase().as_str() {
            "floor" => Some(PlacementKind::Floor),
            "wall" => Some(PlacementKind::Wall),
            "on-object" | "object" | "small" | "on_object" => Some(PlacementKind::OnObject),
            "ceiling" => Some(PlacementKind::Ceiling),
            _ => None,
        }
    }
}

/// The placement flags of an asset, as in the objathor annotations.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct Placements {
    /// `onFloor`.
    pub on_floor: bool,
    /// `onWall`.
    pub on_wall: bool,
    /// `onObject`.
    pub on_object: bool,
    /// `onCeiling`.
    pub on_ceiling: bool,
}

impl Placements {
    /// Whether an asset with these flags may be used for `kind`, by the rules of the original
    /// (floor: on the floor and not on the ceiling; ceiling: at most 1 m high).
    pub fn allows(self, kind: PlacementKind, height_m: f64) -> bool {
        match kind {
            PlacementKind::Floor => self.on_floor && !self.on_ceiling,
            PlacementKind::Wall => self.on_wall,
            PlacementKind::OnObject => self.on_object,
            PlacementKind::Ceiling => self.on_ceiling && height_m <= 1.0,
        }
    }

    /// The letters `F`, `W`, `O`, `C` of the set flags.
    pub fn letters(self) -> String {
        let mut s = String::new();
        for (on, c) in [
            (self.on_floor, 'F'),
            (self.on_wall, 'W'),
            (self.on_object, 'O'),
            (self.on_ceiling, 'C'),
        ] {
            if on {
                s.push(c);
            }
        }
        s
    }

    /// The flags of the letters `F`, `W`, `O`, `C` (the embedded catalog's `kinds` column).
    pub fn from_letters(text: &str) -> Placements {
        Placements {
            on_floor: text.contains('F'),
            on_wall: text.contains('W'),
            on_object: text.contains('O'),
            on_ceiling: text.contains('C'),
        }
    }
}

/// Whether an asset of this category, placement flags and height (metres) may be used for
/// `kind`: the placement flags, the ceiling height, and the original's category filters (no
/// doors, windows or frames on the floor, no doors or windows on walls).
pub fn category_allows(
    category: &str,
    placements: Placements,
    height_m: f64,
    kind: PlacementKind,
) -> bool {
    let category = category.to_lowercase();
    let structural = match kind {
        PlacementKind::Floor => ["door", "window", "frame"].iter().any(|w| category.contains(w)),
        PlacementKind::Wall => ["door", "window"].iter().any(|w| category.contains(w)),
        _ => false,
    };
    !structural && placements.allows(kind, height_m)
}

//! Where a receptacle carries the things put on it: the surfaces of each kind of furniture
//! (a mattress, a seat, the shelves of a bookcase, a table top) and the bar a towel hangs from.
//!
//! AI2-THOR's asset data gives each asset's bounding box, not its surfaces, so the table below
//! comes from furniture practice and is written relative to the box (the book's layout
//! semantics chapter lists it with its sources):
//!
//! | AI2-THOR type | surface | height above the bottom | area |
//! |---|---|---|---|
//! | `Bed` | the mattress | 0.6 × the box height, at most 0.65 m | less a 10 cm headboard; things go to the head end |
//! | `Sofa`, `ArmChair` | the seat | 0.5 × the box height | less the backrest (30% of the depth) and 12 cm arms; things go against the backrest |
//! | `Chair` | the seat | 0.5 × the box height | less the backrest (25% of the depth) |
//! | `Shelf`, `ShelvingUnit`, `Bookcase`, `TVStand` | one shelf every ~38 cm, and the top | evenly spaced | less 2 cm side panels |
//! | `TowelHolder`, `HandTowelHolder` | a bar | the box's top | things hang from it |
//! | anything else | the top | the box height | the whole top |
//!
//! A sofa's seat at half its height matches the 40–45 cm seat height of furniture practice for
//! the 80–90 cm boxes of AI2-THOR's sofas; a mattress top at 0.6 of a bed's box (headboard
//! included) gives the 50–60 cm of a double bed; bookcase shelves are 30–40 cm apart.

/// One surface of a receptacle, in the receptacle's frame (`u` to its right, `v` to its front,
/// both from the centre of its box; `y` above its bottom).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Surface {
    /// Height above the receptacle's bottom, metres.
    pub y: f64,
    /// The usable area: `[u_min, u_max, v_min, v_max]`, metres.
    pub area: [f64; 4],
    /// The free height above it (the next shelf), metres; infinite for a top.
    pub headroom: f64,
    /// Where things on it go first: against its back (a pillow at the head of a bed, a
    /// cushion against the backrest) or spread over it.
    pub against_back: bool,
}

impl Surface {
    /// Its width along `u` and depth along `v`.
    pub fn extent(&self) -> [f64; 2] {
        [self.area[1] - self.area[0], self.area[3] - self.area[2]]
    }
}

/// How a receptacle carries things.
#[derive(Clone, Debug, PartialEq)]
pub enum Carrier {
    /// On its surfaces, in the order they are filled.
    Surfaces(Vec<Surface>),
    /// Hung from a bar at this height above its bottom (a towel on a towel holder).
    Bar {
        /// Height of the bar above the receptacle's bottom, metres.
        y: f64,
        /// Its length, metres.
        length: f64,
    },
}

/// The gap between shelves of a bookcase, metres (furniture practice: 30–40 cm).
pub const SHELF_PITCH_M: f64 = 0.38;
/// The thickness of a shelf board and of a bookcase's side panels, metres.
pub const BOARD_M: f64 = 0.02;

/// The surfaces (or bar) of a receptacle of AI2-THOR type `thor_type` (when known) and box
/// `[width, depth, height]`, less `margin` round each surface's edge.
pub fn carrier(thor_type: Option<&str>, size: [f64; 3], margin: f64) -> Carrier {
    let [w, d, h] = size;
    let top = |y: f64, area: [f64; 4], against_back: bool| Surface {
        y,
        area: shrink(area, margin),
        headroom: f64::INFINITY,
        against_back,
    };
    let whole = [-w / 2.0, w / 2.0, -d / 2.0, d / 2.0];
    let t = thor_type.unwrap_or("").to_ascii_lowercase();
    match t.as_str() {
        "bed" => {
            let y = (0.6 * h).min(0.65);
            Carrier::Surfaces(vec![top(y, [-w / 2.0, w / 2.0, -d / 2.0 + 0.1, d / 2.0], true)])
        }
        "sofa" | "armchair" => {
            let arm = 0.12_f64.min(w / 6.0);
            let back = 0.3 * d;
            Carrier::Surfaces(vec![top(
                0.5 * h,
                [-w / 2.0 + arm, w / 2.0 - arm, -d / 2.0 + back, d / 2.0],
                true,
            )])
        }
        "chair" => Carrier::Surfaces(vec![top(
            0.5 * h,
            [-w / 2.0, w / 2.0, -d / 2.0 + 0.25 * d, d / 2.0],
            true,
        )]),
        _ if has_bar(&t) => Carrier::Bar { y: h, length: w },
        "shelf" | "shelvingunit" | "bookcase" | "tvstand" => {
            Carrier::Surfaces(shelves(size, margin))
        }
        _ => Carrier::Surfaces(vec![top(h, whole, false)]),
    }
}

/// Whether a receptacle of this AI2-THOR type hangs what it carries from a bar (a towel
/// holder), case aside: what hangs there has its top at the receptacle's top.
pub fn has_bar(thor_type: &str) -> bool {
    matches!(thor_type.to_ascii_lowercase().as_str(), "towelholder" | "handtowelholder")
}

/// The surfaces of a bookcase: a shelf every [`SHELF_PITCH_M`] or so from the bottom board up,
/// then the top; filled from the shelf at eye level down, then the ones above it, the top of
/// a tall one last.
fn shelves(size: [f64; 3], margin: f64) -> Vec<Surface> {
    let [w, d, h] = size;
    let inner = shrink([-w / 2.0 + BOARD_M, w / 2.0 - BOARD_M, -d / 2.0, d / 2.0], margin);
    let levels = ((h / SHELF_PITCH_M).round() as usize).clamp(1, 8);
    let pitch = h / levels as f64;
    // Shelf `i` stands at `i × pitch` (0: the bottom board), and has the pitch less a board
    // above it.
    let mut inside: Vec<Surface> = (0..levels)
        .map(|i| Surface {
            y: if i == 0 { BOARD_M } else { i as f64 * pitch },
            area: inner,
            headroom: pitch - if i == 0 { 2.0 * BOARD_M } else { BOARD_M },
            against_back: false,
        })
        .collect();
    // Eye level (about 1.5 m) first, then down, then up.
    let eye = 1.5;
    inside.sort_by(|a, b| {
        let key = |s: &Surface| if s.y <= eye + 1e-9 { (0, -s.y) } else { (1, s.y) };
        let (ka, kb) = (key(a), key(b));
        ka.0.cmp(&kb.0).then(ka.1.total_cmp(&kb.1))
    });
    let top = Surface {
        y: h,
        area: shrink([-w / 2.0, w / 2.0, -d / 2.0, d / 2.0], margin),
        headroom: f64::INFINITY,
        against_back: false,
    };
    if h <= eye {
        inside.insert(0, top);
    } else {
        inside.push(top);
    }
    inside
}

fn shrink(a: [f64; 4], m: f64) -> [f64; 4] {
    let (u0, u1) = shrink_range(a[0], a[1], m);
    let (v0, v1) = shrink_range(a[2], a[3], m);
    [u0, u1, v0, v1]
}

fn shrink_range(lo: f64, hi: f64, m: f64) -> (f64, f64) {
    if hi - lo > 2.0 * m {
        (lo + m, hi - m)
    } else {
        let c = 0.5 * (lo + hi);
        (c, c)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_bed_carries_on_its_mattress_not_its_headboard() {
        let Carrier::Surfaces(s) = carrier(Some("Bed"), [1.6, 2.0, 0.91], 0.02) else {
            panic!("a bed has surfaces")
        };
        assert_eq!(s.len(), 1);
        assert!((s[0].y - 0.546).abs() < 1e-9, "{}", s[0].y);
        assert!(s[0].against_back);
    }

    #[test]
    fn a_tall_bookcase_has_shelves_and_its_top_last() {
        let Carrier::Surfaces(s) = carrier(Some("ShelvingUnit"), [0.8, 0.3, 2.0], 0.02) else {
            panic!("a bookcase has surfaces")
        };
        assert_eq!(s.len(), 6);
        assert!((s[0].y - 1.2).abs() < 1e-9, "eye level first: {}", s[0].y);
        assert!((s[5].y - 2.0).abs() < 1e-9 && s[5].headroom.is_infinite());
        assert!(s[..5].iter().all(|x| x.headroom > 0.3 && x.headroom < 0.4));
    }

    #[test]
    fn a_towel_holder_is_a_bar() {
        assert_eq!(
            carrier(Some("TowelHolder"), [0.7, 0.15, 0.02], 0.02),
            Carrier::Bar { y: 0.02, length: 0.7 }
        );
    }

    #[test]
    fn a_table_carries_on_its_top() {
        let Carrier::Surfaces(s) = carrier(Some("DiningTable"), [3.0, 1.2, 0.75], 0.02) else {
            panic!("a table has a top")
        };
        assert_eq!(s.len(), 1);
        assert!((s[0].y - 0.75).abs() < 1e-9);
        assert_eq!(s[0].extent(), [2.96, 1.16]);
    }
}

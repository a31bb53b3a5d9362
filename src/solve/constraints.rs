//! The geometric meaning of every layout constraint and hard rule, as pure functions.
//!
//! The solver (both back ends), the report, `validate` and the SVG renderer all call these
//! functions, so a relation means the same thing everywhere. `book/src/design/layout-semantics.md`
//! states the same definitions in prose. Units are metres and degrees; `x` grows east, `z` grows
//! north, and a rotation of 0° faces +z (AI2-THOR's convention, left-handed: facing +z, the
//! object's right is +x).

use crate::check::scene::{GlobalKind, RelationKind};

/// Tolerance for "touching" comparisons, metres.
pub const EPS: f64 = 1e-6;
/// `edge`: the middle of the back side is at most this far from a wall, metres.
pub const EDGE_TOLERANCE_M: f64 = 0.02;
/// `middle`: every side of the footprint keeps at least this gap to every wall, metres.
pub const MIDDLE_GAP_M: f64 = 0.4;
/// `near`: satisfied when the gap between footprints is at most this, metres.
pub const NEAR_MAX_M: f64 = 1.5;
/// `far`: satisfied when the gap between footprints is at least this, metres.
pub const FAR_MIN_M: f64 = 1.5;
/// `around`: satisfied when the gap is at most this (and the object faces the target), metres.
pub const AROUND_MAX_M: f64 = 0.6;
/// `center aligned`: satisfied when the centres differ by at most this on x or z, metres.
pub const ALIGN_TOLERANCE_M: f64 = 0.05;
/// Free depth kept in front of every floor object, inside the room, metres.
pub const FRONT_CLEARANCE_M: f64 = 0.4;
/// Depth of the zone in front of a window that tall floor objects must keep free, metres.
pub const WINDOW_ZONE_M: f64 = 0.25;
/// Radius of the agent used for the reachability rule by default, metres (AI2-THOR's agent;
/// `--agent-radius` changes it).
pub const AGENT_RADIUS_M: f64 = 0.25;
/// The largest closed pocket of free floor allowed, square metres: free floor an agent
/// cannot reach from a door, counted where the agent's centre can stand.
pub const MAX_POCKET_M2: f64 = 0.1;
/// Cell size of the reachability grid, metres.
pub const REACH_CELL_M: f64 = 0.1;

/// A rotation about the vertical axis, a multiple of 90°.
#[derive(Clone, Copy, Debug, PartialEq, Eq, PartialOrd, Ord, Hash)]
pub enum Rot {
    /// Faces +z (north).
    R0,
    /// Faces +x (east).
    R90,
    /// Faces −z (south).
    R180,
    /// Faces −x (west).
    R270,
}

impl Rot {
    /// All four, in the order 0, 90, 180, 270.
    pub const ALL: [Rot; 4] = [Rot::R0, Rot::R90, Rot::R180, Rot::R270];

    /// The angle in degrees.
    pub fn deg(self) -> f64 {
        match self {
            Rot::R0 => 0.0,
            Rot::R90 => 90.0,
            Rot::R180 => 180.0,
            Rot::R270 => 270.0,
        }
    }

    /// The nearest multiple of 90° to an angle in degrees.
    pub fn from_deg(deg: f64) -> Rot {
        let q = ((deg / 90.0).round() as i64).rem_euclid(4);
        match q {
            0 => Rot::R0,
            1 => Rot::R90,
            2 => Rot::R180,
            _ => Rot::R270,
        }
    }

    /// The unit facing direction `(dx, dz)`.
    pub fn front(self) -> [f64; 2] {
        match self {
            Rot::R0 => [0.0, 1.0],
            Rot::R90 => [1.0, 0.0],
            Rot::R180 => [0.0, -1.0],
            Rot::R270 => [-1.0, 0.0],
        }
    }

    /// The unit direction to the object's right `(dx, dz)`.
    pub fn right(self) -> [f64; 2] {
        let [fx, fz] = self.front();
        [fz, -fx]
    }

    /// Whether width and depth swap (90° and 270°).
    pub fn swaps(self) -> bool {
        matches!(self, Rot::R90 | Rot::R270)
    }

    /// The rotation whose front is this unit direction, if it is axis-aligned.
    pub fn facing(dir: [f64; 2]) -> Option<Rot> {
        Rot::ALL.into_iter().find(|r| {
            let f = r.front();
            (f[0] - dir[0]).abs() < 1e-9 && (f[1] - dir[1]).abs() < 1e-9
        })
    }
}

/// Where a floor object stands: the centre of its footprint and its rotation.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Pose {
    /// Centre x, metres.
    pub x: f64,
    /// Centre z, metres.
    pub z: f64,
    /// Rotation.
    pub rot: Rot,
}

/// An axis-aligned rectangle on the floor, metres.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Rect {
    /// West side.
    pub min_x: f64,
    /// South side.
    pub min_z: f64,
    /// East side.
    pub max_x: f64,
    /// North side.
    pub max_z: f64,
}

impl Rect {
    /// Whether the segment from `a` to `b` passes through the rectangle's inside (touching
    /// its outline is not meeting it).
    pub fn meets_segment(&self, a: [f64; 2], b: [f64; 2]) -> bool {
        // Clip the segment's parameter range to each slab (Liang–Barsky).
        let (mut t0, mut t1) = (0.0_f64, 1.0_f64);
        let d = [b[0] - a[0], b[1] - a[1]];
        for (p, q) in [
            (-d[0], a[0] - self.min_x),
            (d[0], self.max_x - a[0]),
            (-d[1], a[1] - self.min_z),
            (d[1], self.max_z - a[1]),
        ] {
            if p.abs() < 1e-12 {
                if q <= EPS {
                    return false;
                }
                continue;
            }
            let t = q / p;
            if p < 0.0 {
                t0 = t0.max(t);
            } else {
                t1 = t1.min(t);
            }
        }
        t1 - t0 > 1e-9 && {
            let mid = f64::midpoint(t0, t1);
            let m = [a[0] + d[0] * mid, a[1] + d[1] * mid];
            m[0] > self.min_x + EPS
                && m[0] < self.max_x - EPS
                && m[1] > self.min_z + EPS
                && m[1] < self.max_z - EPS
        }
    }

    /// The rectangle between two corners in any order.
    pub fn from_corners(a: [f64; 2], b: [f64; 2]) -> Rect {
        Rect {
            min_x: a[0].min(b[0]),
            min_z: a[1].min(b[1]),
            max_x: a[0].max(b[0]),
            max_z: a[1].max(b[1]),
        }
    }

    /// The bounding box of some points (a zero rectangle for none).
    pub fn bounding(points: &[[f64; 2]]) -> Rect {
        let mut r = Rect {
            min_x: f64::INFINITY,
            min_z: f64::INFINITY,
            max_x: f64::NEG_INFINITY,
            max_z: f64::NEG_INFINITY,
        };
        for p in points {
            r.min_x = r.min_x.min(p[0]);
            r.min_z = r.min_z.min(p[1]);
            r.max_x = r.max_x.max(p[0]);
            r.max_z = r.max_z.max(p[1]);
        }
        if points.is_empty() {
            Rect { min_x: 0.0, min_z: 0.0, max_x: 0.0, max_z: 0.0 }
        } else {
            r
        }
    }

    /// The centre.
    pub fn center(&self) -> [f64; 2] {
        [f64::midpoint(self.min_x, self.max_x), f64::midpoint(self.min_z, self.max_z)]
    }

    /// Extent along x.
    pub fn width(&self) -> f64 {
        self.max_x - self.min_x
    }

    /// Extent along z.
    pub fn depth(&self) -> f64 {
        self.max_z - self.min_z
    }

    /// Grown by `m` on every side (shrunk for negative `m`).
    #[must_use]
    pub fn grow(&self, m: f64) -> Rect {
        Rect {
            min_x: self.min_x - m,
            min_z: self.min_z - m,
            max_x: self.max_x + m,
            max_z: self.max_z + m,
        }
    }

    /// Whether the interiors intersect (touching is not overlapping).
    pub fn overlaps(&self, o: &Rect) -> bool {
        self.min_x < o.max_x - EPS
            && o.min_x < self.max_x - EPS
            && self.min_z < o.max_z - EPS
            && o.min_z < self.max_z - EPS
    }

    /// Whether `o` lies inside this rectangle (touching allowed).
    pub fn contains(&self, o: &Rect) -> bool {
        o.min_x >= self.min_x - EPS
            && o.max_x <= self.max_x + EPS
            && o.min_z >= self.min_z - EPS
            && o.max_z <= self.max_z + EPS
    }

    /// Whether a point is inside or on the border.
    pub fn contains_point(&self, p: [f64; 2]) -> bool {
        p[0] >= self.min_x - EPS
            && p[0] <= self.max_x + EPS
            && p[1] >= self.min_z - EPS
            && p[1] <= self.max_z + EPS
    }

    /// The gap between two rectangles (0 when they touch or overlap).
    pub fn gap(&self, o: &Rect) -> f64 {
        let dx = (o.min_x - self.max_x).max(self.min_x - o.max_x).max(0.0);
        let dz = (o.min_z - self.max_z).max(self.min_z - o.max_z).max(0.0);
        (dx * dx + dz * dz).sqrt()
    }

    /// Distance from a point to the rectangle (0 inside).
    pub fn distance_to_point(&self, p: [f64; 2]) -> f64 {
        self.distance_sq_to_point(p).sqrt()
    }

    /// The squared distance from a point to the rectangle (0 inside).
    pub fn distance_sq_to_point(&self, p: [f64; 2]) -> f64 {
        let dx = (self.min_x - p[0]).max(p[0] - self.max_x).max(0.0);
        let dz = (self.min_z - p[1]).max(p[1] - self.max_z).max(0.0);
        dx * dx + dz * dz
    }
}

/// Half extents `(hx, hz)` of a `width × depth` footprint at a rotation.
pub fn half_extents(size: [f64; 2], rot: Rot) -> [f64; 2] {
    if rot.swaps() {
        [size[1] / 2.0, size[0] / 2.0]
    } else {
        [size[0] / 2.0, size[1] / 2.0]
    }
}

/// The footprint of an object of `size = [width, depth]` at a pose.
pub fn footprint(pose: &Pose, size: [f64; 2]) -> Rect {
    let [hx, hz] = half_extents(size, pose.rot);
    Rect { min_x: pose.x - hx, min_z: pose.z - hz, max_x: pose.x + hx, max_z: pose.z + hz }
}

/// The floor area in front of an object that must stay inside the room.
pub fn front_zone(pose: &Pose, size: [f64; 2], depth: f64) -> Rect {
    let fp = footprint(pose, size);
    match pose.rot {
        Rot::R0 => Rect { min_z: fp.max_z, max_z: fp.max_z + depth, ..fp },
        Rot::R180 => Rect { min_z: fp.min_z - depth, max_z: fp.min_z, ..fp },
        Rot::R90 => Rect { min_x: fp.max_x, max_x: fp.max_x + depth, ..fp },
        Rot::R270 => Rect { min_x: fp.min_x - depth, max_x: fp.min_x, ..fp },
    }
}

/// The middle of the back side of the footprint.
pub fn back_center(pose: &Pose, size: [f64; 2]) -> [f64; 2] {
    let [fx, fz] = pose.rot.front();
    let d = size[1] / 2.0;
    [pose.x - fx * d, pose.z - fz * d]
}

/// A room's floor: a rectilinear outline, split into the maximal rectangles it contains.
#[derive(Clone, Debug, PartialEq)]
pub struct RoomShape {
    /// The outline corners, in order, metres.
    pub outline: Vec<[f64; 2]>,
    /// Every maximal axis-aligned rectangle inside the outline. A rectangle lies inside the
    /// room exactly when it lies inside one of these.
    pub rects: Vec<Rect>,
    /// The bounding box.
    pub bounds: Rect,
}

impl RoomShape {
    /// Builds the shape of a rectilinear outline. Returns `None` when the outline has fewer than
    /// four corners, an edge that is not axis-aligned, or no area.
    pub fn new(outline: &[[f64; 2]]) -> Option<RoomShape> {
        if outline.len() < 4 || outline.iter().any(|p| !p[0].is_finite() || !p[1].is_finite()) {
            return None;
        }
        for i in 0..outline.len() {
            let a = outline[i];
            let b = outline[(i + 1) % outline.len()];
            if (a[0] - b[0]).abs() > EPS && (a[1] - b[1]).abs() > EPS {
                return None;
            }
        }
        let mut xs: Vec<f64> = outline.iter().map(|p| p[0]).collect();
        let mut zs: Vec<f64> = outline.iter().map(|p| p[1]).collect();
        xs.sort_by(f64::total_cmp);
        zs.sort_by(f64::total_cmp);
        xs.dedup_by(|a, b| (*a - *b).abs() < EPS);
        zs.dedup_by(|a, b| (*a - *b).abs() < EPS);
        let (nx, nz) = (xs.len().saturating_sub(1), zs.len().saturating_sub(1));
        let mut inside = vec![vec![false; nz]; nx];
        for (i, col) in inside.iter_mut().enumerate() {
            for (j, cell) in col.iter_mut().enumerate() {
                let c = [f64::midpoint(xs[i], xs[i + 1]), f64::midpoint(zs[j], zs[j + 1])];
                *cell = point_in_polygon(c, outline);
            }
        }
        let all_in = |i0: usize, i1: usize, j0: usize, j1: usize| {
            (i0..=i1).all(|i| (j0..=j1).all(|j| inside[i][j]))
        };
        let mut candidates = Vec::new();
        for i0 in 0..nx {
            for i1 in i0..nx {
                for j0 in 0..nz {
                    for j1 in j0..nz {
                        if all_in(i0, i1, j0, j1) {
                            candidates.push((i0, i1, j0, j1));
                        }
                    }
                }
            }
        }
        let maximal: Vec<_> = candidates
            .iter()
            .filter(|&&(i0, i1, j0, j1)| {
                !candidates.iter().any(|&(a0, a1, b0, b1)| {
                    (a0, a1, b0, b1) != (i0, i1, j0, j1)
                        && a0 <= i0
                        && a1 >= i1
                        && b0 <= j0
                        && b1 >= j1
                })
            })
            .map(|&(i0, i1, j0, j1)| Rect {
                min_x: xs[i0],
                min_z: zs[j0],
                max_x: xs[i1 + 1],
                max_z: zs[j1 + 1],
            })
            .collect();
        if maximal.is_empty() {
            return None;
        }
        Some(RoomShape {
            outline: outline.to_vec(),
            rects: maximal,
            bounds: Rect::bounding(outline),
        })
    }

    /// Whether a rectangle lies inside the room (touching the walls allowed).
    pub fn contains_rect(&self, r: &Rect) -> bool {
        self.rects.iter().any(|m| m.contains(r))
    }

    /// Whether a point is inside the room or on its walls.
    pub fn contains_point(&self, p: [f64; 2]) -> bool {
        self.rects.iter().any(|m| m.contains_point(p))
    }

    /// The distance from a point to the nearest wall line of the outline.
    pub fn distance_to_wall(&self, p: [f64; 2]) -> f64 {
        let n = self.outline.len();
        (0..n)
            .map(|i| segment_distance(p, self.outline[i], self.outline[(i + 1) % n]))
            .fold(f64::INFINITY, f64::min)
    }

    /// Whether a point lies within `d` of a wall line of the outline (`distance_to_wall(p) <=
    /// d`), measuring only the walls whose bounding box comes that near (the box is never
    /// farther than its wall).
    pub fn near_wall(&self, p: [f64; 2], d: f64) -> bool {
        let n = self.outline.len();
        (0..n).any(|i| {
            let (a, b) = (self.outline[i], self.outline[(i + 1) % n]);
            let out_x = (a[0].min(b[0]) - p[0]).max(p[0] - a[0].max(b[0]));
            let out_z = (a[1].min(b[1]) - p[1]).max(p[1] - a[1].max(b[1]));
            // (A little slack for rounding: the measure itself decides.)
            out_x <= d + 1e-9 && out_z <= d + 1e-9 && segment_distance(p, a, b) <= d
        })
    }

    /// The walls as segments with the unit normal pointing into the room, in outline order.
    pub fn walls(&self) -> Vec<([f64; 2], [f64; 2], [f64; 2])> {
        let n = self.outline.len();
        let mut out = Vec::new();
        for i in 0..n {
            let a = self.outline[i];
            let b = self.outline[(i + 1) % n];
            let len = (b[0] - a[0]).hypot(b[1] - a[1]);
            if len < EPS {
                continue;
            }
            let d = [(b[0] - a[0]) / len, (b[1] - a[1]) / len];
            let mid = [f64::midpoint(a[0], b[0]), f64::midpoint(a[1], b[1])];
            let left = [-d[1], d[0]];
            let probe = [mid[0] + left[0] * 1e-3, mid[1] + left[1] * 1e-3];
            let normal = if point_in_polygon(probe, &self.outline) { left } else { [d[1], -d[0]] };
            out.push((a, b, [normal[0].round(), normal[1].round()]));
        }
        out
    }

    /// The area centroid of the outline.
    pub fn centroid(&self) -> [f64; 2] {
        let n = self.outline.len();
        let (mut a, mut cx, mut cz) = (0.0, 0.0, 0.0);
        for i in 0..n {
            let p = self.outline[i];
            let q = self.outline[(i + 1) % n];
            let cross = p[0] * q[1] - q[0] * p[1];
            a += cross;
            cx += (p[0] + q[0]) * cross;
            cz += (p[1] + q[1]) * cross;
        }
        if a.abs() < EPS {
            return self.bounds.center();
        }
        [cx / (3.0 * a), cz / (3.0 * a)]
    }
}

/// Even-odd point-in-polygon test.
pub fn point_in_polygon(p: [f64; 2], poly: &[[f64; 2]]) -> bool {
    let mut inside = false;
    let n = poly.len();
    let mut j = n.wrapping_sub(1);
    for i in 0..n {
        let (a, b) = (poly[i], poly[j]);
        if (a[1] > p[1]) != (b[1] > p[1])
            && p[0] < (b[0] - a[0]) * (p[1] - a[1]) / (b[1] - a[1]) + a[0]
        {
            inside = !inside;
        }
        j = i;
    }
    inside
}

/// Distance from a point to a segment.
pub fn segment_distance(p: [f64; 2], a: [f64; 2], b: [f64; 2]) -> f64 {
    let (dx, dz) = (b[0] - a[0], b[1] - a[1]);
    let len2 = dx * dx + dz * dz;
    let t = if len2 < EPS * EPS {
        0.0
    } else {
        (((p[0] - a[0]) * dx + (p[1] - a[1]) * dz) / len2).clamp(0.0, 1.0)
    };
    (p[0] - a[0] - t * dx).hypot(p[1] - a[1] - t * dz)
}

/// A measured constraint: whether it holds, its contribution in `[0, 1]` and the measured value.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Measure {
    /// Whether the constraint holds.
    pub satisfied: bool,
    /// Satisfaction in `[0, 1]`, multiplied by the weight in the score.
    pub score: f64,
    /// The measured value (see [`Measure::unit`]).
    pub value: f64,
    /// `"m"` or `"deg"`.
    pub unit: &'static str,
}

impl Measure {
    fn yes_no(ok: bool, value: f64, unit: &'static str) -> Measure {
        Measure { satisfied: ok, score: if ok { 1.0 } else { 0.0 }, value, unit }
    }
}

/// What an object is for, as the meanings of relations and the use-clearances need it; read
/// from the words of its category (see [`Role::of`]).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Default)]
pub enum Role {
    /// A chair, stool, armchair or bench: someone sits on it.
    Seat,
    /// A sofa, couch or loveseat.
    Sofa,
    /// A bed.
    Bed,
    /// A table to sit at or work at (dining table, counter, island).
    Table,
    /// A desk (or workbench): a table worked at from its front, where its chair pulls out.
    Desk,
    /// A low table in front of seats (coffee table).
    LowTable,
    /// A small table beside a bed or a seat (nightstand, side table, end table).
    SideTable,
    /// A television, or the stand or unit that carries one.
    Screen,
    /// A fridge.
    Fridge,
    /// A dresser, wardrobe, chest of drawers, cabinet or pantry: something opened from its
    /// front, whose drawers or doors swing out.
    Storage,
    /// Open storage stood against a wall: a bookcase, shelf or shelving unit.
    Shelf,
    /// An ottoman, footstool or pouf: the one thing besides a table that may stand in a seat's
    /// front strip.
    Ottoman,
    /// A fixture a person stands in front of to cook or wash: a stove, range, cooktop, oven,
    /// dishwasher, washing machine or dryer (its door opens and its user stands before it).
    Appliance,
    /// A basin a person stands at to wash: a sink, washbasin, lavatory or vanity.
    Basin,
    /// Anything else.
    #[default]
    Other,
}

impl Role {
    /// The role named by a category's words: the last word that names a role decides
    /// (`desk chair` is a seat, `coffee table` a low table, `tv stand` a screen).
    pub fn of(category: &str) -> Role {
        let words: Vec<String> = category
            .to_lowercase()
            .split(|c: char| !c.is_alphanumeric())
            .filter(|w| !w.is_empty())
            .map(|w| w.trim_end_matches('s').to_string())
            .collect();
        let has = |w: &str| words.iter().any(|x| x == w);
        if has("tv") || has("television") || has("media") || has("entertainment") {
            return Role::Screen;
        }
        if has("coffee") || has("cocktail") {
            return Role::LowTable;
        }
        // A hood over a range, a machine that washes clothes.
        if has("hood") || has("extractor") {
            return Role::Other;
        }
        if has("washing") && has("machine") {
            return Role::Appliance;
        }
        if (has("nightstand") || has("bedside") || has("night") || has("side") || has("end"))
            && words.last().is_some_and(|w| w == "table" || w == "nightstand" || w == "stand")
        {
            return Role::SideTable;
        }
        for w in words.iter().rev() {
            let role = match w.as_str() {
                "chair" | "armchair" | "stool" | "seat" | "bench" | "recliner" | "barstool" => {
                    Role::Seat
                }
                "sofa" | "couch" | "loveseat" | "sectional" | "settee" | "futon" => Role::Sofa,
                "bed" | "bunk" | "crib" => Role::Bed,
                "table" | "counter" | "countertop" | "island" => Role::Table,
                // A piano is sat at from its front, as a desk is.
                "desk" | "workbench" | "workstation" | "piano" | "organ" => Role::Desk,
                "nightstand" => Role::SideTable,
                "fridge" | "refrigerator" | "freezer" => Role::Fridge,
                "dresser" | "wardrobe" | "chest" | "drawer" | "armoire" | "closet" | "cabinet"
                | "cupboard" | "pantry" | "sideboard" | "credenza" | "hutch" => Role::Storage,
                "stove" | "range" | "cooktop" | "hob" | "cooker" | "oven" | "dishwasher"
                | "washer" | "dryer" => Role::Appliance,
                "sink" | "washbasin" | "basin" | "lavatory" | "vanity" => Role::Basin,
                "bookcase" | "bookshelf" | "shelf" | "shelve" | "shelving" | "bookshelve"
                | "etagere" => Role::Shelf,
                "ottoman" | "footstool" | "pouf" | "pouffe" | "footrest" | "hassock" => {
                    Role::Ottoman
                }
                _ => continue,
            };
            return role;
        }
        Role::Other
    }

    fn seats(self) -> bool {
        matches!(self, Role::Seat | Role::Sofa)
    }

    /// A chair, stool, armchair or bench (not a sofa).
    pub fn is_seat(self) -> bool {
        self == Role::Seat
    }

    /// Storage (a bookcase, shelf, wardrobe, dresser, cabinet, pantry): asked `edge`, it stands
    /// against a wall or not at all.
    pub fn wants_wall(self) -> bool {
        matches!(self, Role::Storage | Role::Shelf)
    }

    /// A table or desk that chairs are drawn up to (not a coffee table).
    pub fn sat_at(self) -> bool {
        matches!(self, Role::Table | Role::Desk)
    }

    /// Whether an object of role `other` (`related` when it has a relation with this one) may
    /// stand in this one's use-clearance: a seat's or sofa's front strip takes only a table,
    /// desk, coffee table or ottoman, related or not (nobody sits facing a chair's back or a
    /// chaise's end); a desk's pull-out space only a related seat (the desk's chair; a student
    /// desk `in front of` the teacher's desk keeps out of it); the swing of a fridge's,
    /// cabinet's, pantry's or wardrobe's doors, a dresser's drawers and the place before a
    /// stove, oven, dishwasher, washing machine or sink where its user stands nothing; any
    /// other clearance any related object (a coffee table before its sofa, a nightstand by its
    /// bed, a stool at its counter).
    pub fn lets_in(self, other: Role, related: bool) -> bool {
        match self {
            Role::Seat | Role::Sofa => {
                matches!(other, Role::Table | Role::Desk | Role::LowTable | Role::Ottoman)
            }
            Role::Desk => related && other.seats(),
            Role::Fridge | Role::Storage | Role::Appliance | Role::Basin => false,
            _ => related,
        }
    }

    /// The depth (metres) in front of the object that its use needs free: legroom before a
    /// sofa, the pull-out space of a desk, the work aisle of a counter, the swing of a fridge
    /// door, the drawers of a dresser (see the book's layout semantics for the sources).
    pub fn front_clearance(self, height_m: f64) -> f64 {
        match self {
            Role::Sofa | Role::Seat => SEAT_FRONT_M,
            Role::Desk => DESK_CLEARANCE_M,
            Role::Table if height_m >= COUNTER_HEIGHT_M => COUNTER_CLEARANCE_M,
            Role::Fridge => FRIDGE_CLEARANCE_M,
            Role::Storage => STORAGE_CLEARANCE_M,
            Role::Appliance => APPLIANCE_CLEARANCE_M,
            Role::Basin => BASIN_CLEARANCE_M,
            _ => 0.0,
        }
    }
}

/// Legroom kept free in front of a sofa (a coffee table stands 0.3–0.6 m away).
pub const SOFA_CLEARANCE_M: f64 = 0.3;
/// The strip in front of a seat or sofa kept free of anything but a table, desk, coffee table
/// or ottoman: where the sitter's legs and feet go (furniture planning: 45 cm of knee space).
pub const SEAT_FRONT_M: f64 = 0.45;
/// The way between the backs of two chairs drawn up to different tables or desks (furniture
/// planning: 40 cm to pull a chair out and pass), metres.
pub const CHAIRS_APART_M: f64 = 0.4;
/// The widest angle between a screen's facing and the way to its seat, and between the seat's
/// facing and the way to the screen, for the pair to watch (furniture planning's 30° cone).
pub const VIEWING_ANGLE_DEG: f64 = 30.0;
/// The space kept free in front of a desk for its chair to pull out and its user to sit
/// (furniture practice: at least 75 cm from the desk's edge).
pub const DESK_CLEARANCE_M: f64 = 0.75;
/// The work aisle kept free in front of a counter (kitchen planning: at least 0.9 m).
pub const COUNTER_CLEARANCE_M: f64 = 0.9;
/// A table at least this high is a counter (a dining table or desk is about 0.75 m).
pub const COUNTER_HEIGHT_M: f64 = 0.85;
/// The swing of a fridge door kept free.
pub const FRIDGE_CLEARANCE_M: f64 = 0.8;
/// The space to open a dresser's drawers.
pub const STORAGE_CLEARANCE_M: f64 = 0.5;
/// The space before a stove, range, oven, dishwasher, washing machine or dryer: its door
/// open and its user standing before it (kitchen planning's 0.9 m work aisle; an open oven
/// or dishwasher door reaches about 0.55 m).
pub const APPLIANCE_CLEARANCE_M: f64 = 0.9;
/// The space before a sink or washbasin where its user stands (bathroom planning: 0.55 m at
/// least, 0.75 m comfortable).
pub const BASIN_CLEARANCE_M: f64 = 0.75;
/// The access kept free along the open long sides of a bed.
pub const BED_SIDE_CLEARANCE_M: f64 = 0.5;
/// `near` means at least this gap (not touching), unless the pair touches by nature.
pub const NEAR_MIN_M: f64 = 0.1;
/// The farthest a side relation (`in front of`, `behind`, `left of`, `right of`, `side of`)
/// reaches by default: beyond it, the thing is elsewhere in the room.
pub const SIDE_MAX_M: f64 = 2.0;
/// A seat in front of (or around) a table or desk is within reach of it: the seat's edge at
/// most this far from it.
pub const REACH_MAX_M: f64 = 0.6;
/// A coffee table stands this far from the front of its seats (furniture practice: 30–60 cm).
pub const LOW_TABLE_GAP_M: (f64, f64) = (0.3, 0.6);
/// Furniture taller than this between a screen and a seat across from it blocks the view
/// (a seated person's eyes are at about 1.1 m, a TV's screen from about 0.6 m up; a coffee
/// table is lower), metres.
pub const SIGHT_LINE_M: f64 = 0.6;
/// A screen (a TV, or the stand that carries one) counts as at least this tall for the window
/// rule: a TV on a low stand still stands in front of the window, metres.
pub const SCREEN_TOP_M: f64 = 1.3;
/// A screen faces its seats across the room: this range of gaps (1.5 m to 4.5 m, about 1.5–3
/// screen diagonals for the screen sizes of AI2-THOR's televisions).
pub const VIEWING_GAP_M: (f64, f64) = (1.5, 4.5);

/// What a relation between two objects means in numbers: the range of the gap between their
/// footprints and whether the object must face its target.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Meaning {
    /// Smallest gap, metres.
    pub min_gap: f64,
    /// Largest gap, metres.
    pub max_gap: f64,
    /// Whether the object must face the target.
    pub face: bool,
    /// For a seat `around` a table: the seats of the table its group shares (the relation is
    /// kept at one of them).
    pub ring: Option<SeatRing>,
    /// A screen and a seat of a seating group (`face to` or `in front of` between them): the
    /// viewing rule, each within [`VIEWING_ANGLE_DEG`] of facing the other, at a viewing gap,
    /// with a clear line of sight.
    pub view: bool,
}

/// The seats round a table that a group of chairs `around` it shares: how many and how large
/// each chair is. Where the seats are is [`seat_poses`].
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct SeatRing {
    /// How many chairs are around the table.
    pub seats: usize,
    /// The largest chair's `[width, depth]`, metres.
    pub seat: [f64; 2],
}

/// The length of table edge a diner needs (furniture practice: 60 cm a place setting).
pub const SEAT_PITCH_M: f64 = 0.6;
/// The least length of table edge a chair takes when the table is crowded: its width and this.
pub const SEAT_PITCH_CROWDED_EXTRA_M: f64 = 0.02;
/// The gap between a chair at a table and the table's edge, metres: none, its front at the
/// edge (a chair at a table is drawn up to it).
pub const SEAT_GAP_M: f64 = 0.0;
/// How much of its score a seat drawn up to the front or back of a desk or table loses from
/// the middle of the edge to its end (it still holds: the chair is at the desk).
pub const SEAT_OFF_MIDDLE_PENALTY: f64 = 0.3;
/// How far from its seat (centre to centre) a chair still stands at it, metres.
pub const SEAT_TOLERANCE_M: f64 = 0.15;

/// How many of `n` chairs stand at each side of a table with sides of these lengths (front,
/// back, right, left of the table), each side holding at most `caps` of them: one after the
/// other to the side with the most edge per chair once it has one more (the D'Hondt rule, so
/// that the chairs are spread over the sides in proportion to their lengths), a tie going to
/// the earlier side (front, back, right, left: opposite sides fill together).
pub fn seats_per_side(n: usize, lengths: [f64; 4], caps: [usize; 4]) -> [usize; 4] {
    let mut counts = [0usize; 4];
    for _ in 0..n {
        let mut best: Option<(f64, usize)> = None;
        for s in 0..4 {
            if counts[s] >= caps[s] {
                continue;
            }
            let q = lengths[s] / (counts[s] + 1) as f64;
            if best.is_none_or(|(b, _)| q > b + 1e-9) {
                best = Some((q, s));
            }
        }
        let Some((_, s)) = best else { break };
        counts[s] += 1;
    }
    counts
}

/// The seats of a table at `target` (footprint `target_size` at rotation 0) for a ring of
/// chairs: spread over its sides by [`seats_per_side`], evenly along each side, each chair
/// [`SEAT_GAP_M`] off the edge and facing the table. A side takes a chair per
/// [`SEAT_PITCH_M`] of its length, or, when the table is too small for that, per the chair's
/// width and [`SEAT_PITCH_CROWDED_EXTRA_M`]; chairs beyond that have no seat.
pub fn seat_poses(target: &Pose, target_size: [f64; 2], ring: &SeatRing) -> Vec<Pose> {
    seat_offsets(target.rot, target_size, ring).iter().map(|o| o.at(target)).collect()
}

/// Where a seat of [`seat_poses`] stands from its table's centre, for a table at one rotation:
/// the way out from the edge and the way along it, kept apart so that a seat at a table is
/// worked out with the same arithmetic whether its offsets were kept or not.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct SeatOffset {
    /// From the table's centre out to the seat's line: `[x, z]`, metres.
    pub out: [f64; 2],
    /// Along the edge to the seat: `[x, z]`, metres.
    pub along: [f64; 2],
    /// The seat's rotation (facing the table).
    pub rot: Rot,
}

impl SeatOffset {
    /// The seat's pose for a table at `target`.
    pub fn at(&self, target: &Pose) -> Pose {
        Pose {
            x: target.x + self.out[0] + self.along[0],
            z: target.z + self.out[1] + self.along[1],
            rot: self.rot,
        }
    }
}

/// The offsets of the seats of a table at rotation `rot` (see [`seat_poses`]): they depend on
/// the table's rotation, size and ring only, so a search keeps them per table.
pub fn seat_offsets(rot: Rot, target_size: [f64; 2], ring: &SeatRing) -> Vec<SeatOffset> {
    let front = rot.front();
    let right = rot.right();
    let [w, d] = target_size;
    // (outward axis, along axis, side length, distance from the centre to the edge)
    let sides = [
        (front, right, w, d / 2.0),
        ([-front[0], -front[1]], right, w, d / 2.0),
        (right, front, d, w / 2.0),
        ([-right[0], -right[1]], front, d, w / 2.0),
    ];
    let lengths = sides.map(|s| s.2);
    let caps_for = |pitch: f64| lengths.map(|l| ((l + EPS) / pitch).floor().max(0.0) as usize);
    let mut caps = caps_for(SEAT_PITCH_M.max(ring.seat[0] + SEAT_PITCH_CROWDED_EXTRA_M));
    if caps.iter().sum::<usize>() < ring.seats {
        caps = caps_for(ring.seat[0] + SEAT_PITCH_CROWDED_EXTRA_M);
    }
    let counts = seats_per_side(ring.seats, lengths, caps);
    let mut out = Vec::with_capacity(ring.seats);
    for ((out_axis, along, len, edge), c) in sides.iter().zip(counts) {
        let Some(rot) = Rot::facing([-out_axis[0], -out_axis[1]]) else { continue };
        let reach = edge + SEAT_GAP_M + ring.seat[1] / 2.0;
        for i in 0..c {
            let t = -len / 2.0 + len * (i as f64 + 0.5) / c as f64;
            out.push(SeatOffset {
                out: [out_axis[0] * reach, out_axis[1] * reach],
                along: [along[0] * t, along[1] * t],
                rot,
            });
        }
    }
    out
}

impl Meaning {
    /// The meaning of `kind` for an object of role `me` towards a target of role `target`;
    /// `contact` when the pair touches by nature (a nightstand beside a bed, an object also
    /// `side of` its target). Written once here and shared by both solvers, the report, the
    /// SVG and the book's table.
    pub fn of(kind: RelationKind, me: Role, target: Role, contact: bool) -> Meaning {
        let any =
            Meaning { min_gap: 0.0, max_gap: f64::INFINITY, face: false, ring: None, view: false };
        let table_like = |r: Role| matches!(r, Role::Table | Role::Desk | Role::LowTable);
        let viewing = Meaning {
            min_gap: VIEWING_GAP_M.0,
            max_gap: VIEWING_GAP_M.1,
            face: true,
            ring: None,
            view: true,
        };
        let drawn_up = Meaning { min_gap: 0.0, max_gap: REACH_MAX_M, face: true, ..any };
        match kind {
            RelationKind::Near => Meaning {
                min_gap: if contact { 0.0 } else { NEAR_MIN_M },
                max_gap: NEAR_MAX_M,
                ..any
            },
            RelationKind::Far => Meaning { min_gap: FAR_MIN_M, ..any },
            RelationKind::InFrontOf => {
                if me.seats() && table_like(target) {
                    drawn_up
                } else if me == Role::LowTable && (target.seats() || target == Role::Bed) {
                    Meaning { min_gap: LOW_TABLE_GAP_M.0, max_gap: LOW_TABLE_GAP_M.1, ..any }
                } else if views(me, target) {
                    viewing
                } else {
                    Meaning { max_gap: SIDE_MAX_M, ..any }
                }
            }
            // A seat behind a desk or table (a student's chair) is at it, within reach.
            RelationKind::Behind if me.seats() && table_like(target) => drawn_up,
            RelationKind::Behind
            | RelationKind::LeftOf
            | RelationKind::RightOf
            | RelationKind::SideOf => Meaning { max_gap: SIDE_MAX_M, ..any },
            RelationKind::Around => Meaning { max_gap: AROUND_MAX_M, face: true, ..any },
            // A screen facing its seats, or a seat facing its screen: across from each other
            // at a viewing distance.
            RelationKind::FaceTo if views(me, target) => viewing,
            _ => any,
        }
    }
}

/// Whether a pair of roles is a screen and what one watches it from (a seat, a sofa or a bed),
/// either way round: their `face to` and `in front of` are the viewing rule.
pub fn views(me: Role, target: Role) -> bool {
    let watcher = |r: Role| r.seats() || r == Role::Bed;
    (me == Role::Screen && watcher(target)) || (watcher(me) && target == Role::Screen)
}

/// Whether two roles touch by nature when one is `near` the other.
pub fn touch_by_nature(a: Role, b: Role) -> bool {
    let pair = |x: Role, y: Role| (a == x && b == y) || (a == y && b == x);
    pair(Role::SideTable, Role::Bed)
        || pair(Role::SideTable, Role::Sofa)
        || pair(Role::SideTable, Role::Seat)
}

/// The use-clearance of an object at a pose: the strips its use needs free of other
/// furniture, and whether all of them must be free (the front of a sofa, desk, counter,
/// fridge or dresser) or one is enough (one open long side of a bed). Empty for other roles.
pub fn use_zones(role: Role, pose: &Pose, size: [f64; 2], height_m: f64) -> (Vec<Rect>, bool) {
    if role == Role::Bed {
        let fp = footprint(pose, size);
        let d = BED_SIDE_CLEARANCE_M;
        let right = pose.rot.right();
        let strips = if right[0] == 0.0 {
            // The bed's long sides face ±z.
            vec![
                Rect { min_z: fp.max_z, max_z: fp.max_z + d, ..fp },
                Rect { min_z: fp.min_z - d, max_z: fp.min_z, ..fp },
            ]
        } else {
            vec![
                Rect { min_x: fp.max_x, max_x: fp.max_x + d, ..fp },
                Rect { min_x: fp.min_x - d, max_x: fp.min_x, ..fp },
            ]
        };
        return (strips, false);
    }
    let depth = role.front_clearance(height_m);
    if depth <= EPS {
        return (Vec::new(), true);
    }
    (vec![front_zone(pose, size, depth)], true)
}

/// Scores a gap against a range: 1 inside, falling linearly to 0 one metre outside (for
/// `near` up to [`NEAR_MAX_M`] the score keeps the old slope, closer is better).
fn gap_score(gap: f64, m: &Meaning) -> f64 {
    if gap < m.min_gap - EPS {
        (1.0 - (m.min_gap - gap)).clamp(0.0, 1.0)
    } else if gap > m.max_gap + EPS {
        (1.0 - (gap - m.max_gap)).clamp(0.0, 1.0)
    } else {
        1.0
    }
}

/// The documented weight of a relation in the score.
pub fn weight(kind: RelationKind) -> f64 {
    match kind {
        RelationKind::Around => 1.5,
        RelationKind::CenterAligned | RelationKind::FaceSameAs => 0.5,
        _ => 1.0,
    }
}

/// Projects a footprint onto an axis: `(min, max)` of `dot(p, axis)` over the rectangle.
fn project(r: &Rect, axis: [f64; 2]) -> (f64, f64) {
    let xs = [r.min_x * axis[0], r.max_x * axis[0]];
    let zs = [r.min_z * axis[1], r.max_z * axis[1]];
    (xs[0].min(xs[1]) + zs[0].min(zs[1]), xs[0].max(xs[1]) + zs[0].max(zs[1]))
}

fn dot(a: [f64; 2], b: [f64; 2]) -> f64 {
    a[0] * b[0] + a[1] * b[1]
}

/// How far the object's footprint lies beyond the target's footprint along `axis` (the
/// target's own front or right), and whether the object's centre is within the target's
/// extent across that axis. Positive separation means "on that side".
fn side_measure(me: &Rect, target: &Rect, axis: [f64; 2]) -> (f64, bool) {
    let (_, t_max) = project(target, axis);
    let (m_min, _) = project(me, axis);
    let across = [axis[1], -axis[0]];
    let (t_lo, t_hi) = project(target, across);
    let c = dot(me.center(), across);
    (m_min - t_max, c >= t_lo - EPS && c <= t_hi + EPS)
}

/// Where an object that must be `kind` of a target (in front of, behind, left of, right of,
/// side of, around: any side) could stand: squares of side `side` centred on the target's axis on that side,
/// one after the other, at gaps from the target's footprint within `gaps` (metres; what the
/// object's other relations to the target allow) and inside `limit` (the room's bounds).
/// Empty for the other relations. The search uses these zones to look ahead: a pose of the target
/// that leaves none of them free cannot satisfy the relation later, and an object that covers
/// all of them breaks it in advance.
pub fn side_zones(
    kind: RelationKind,
    target: &Pose,
    target_size: [f64; 2],
    side: f64,
    gaps: (f64, f64),
    limit: &Rect,
) -> Vec<Rect> {
    side_zones_and_next_to(kind, target, target_size, [side, 0.0], gaps, limit).0
}

/// [`side_zones`], and with it the zones right next to the target (what [`side_zones`] gives
/// for the gaps `(gaps.0, gaps.0)`: the first zone on each side), in one pass. `zone` is
/// `[side, beyond]`: each square of side `side` reaches `beyond` further out from the target
/// (the way to a chair drawn up to a desk, kept with it).
pub fn side_zones_and_next_to(
    kind: RelationKind,
    target: &Pose,
    target_size: [f64; 2],
    zone: [f64; 2],
    gaps: (f64, f64),
    limit: &Rect,
) -> (Vec<Rect>, Vec<Rect>) {
    let (mut out, mut next_to) = (Vec::new(), Vec::new());
    for_each_side_zone(kind, target, target_size, zone, gaps, limit, |z, listed, next| {
        if next {
            next_to.push(z);
        }
        if listed {
            out.push(z);
        }
    });
    (out, next_to)
}

/// Calls `f(zone, listed, next_to)` for each zone of [`side_zones_and_next_to`], in order:
/// `listed` when [`side_zones`] lists it, `next_to` when it is right next to the target.
pub fn for_each_side_zone(
    kind: RelationKind,
    target: &Pose,
    target_size: [f64; 2],
    [side, beyond]: [f64; 2],
    gaps: (f64, f64),
    limit: &Rect,
    mut f: impl FnMut(Rect, bool, bool),
) {
    let front = target.rot.front();
    let right = target.rot.right();
    let axes: &[[f64; 2]] = match kind {
        RelationKind::InFrontOf => &[front],
        RelationKind::Behind => &[[-front[0], -front[1]]],
        RelationKind::RightOf => &[right],
        RelationKind::LeftOf => &[[-right[0], -right[1]]],
        RelationKind::SideOf => &[right, [-right[0], -right[1]]],
        RelationKind::Around => &[front, [-front[0], -front[1]], right, [-right[0], -right[1]]],
        _ => &[],
    };
    if side <= EPS {
        return;
    }
    let tf = footprint(target, target_size);
    let half = [tf.width() / 2.0, tf.depth() / 2.0];
    for a in axes {
        let start = half[0] * a[0].abs() + half[1] * a[1].abs() + gaps.0 + side / 2.0;
        for n in 0..MAX_SIDE_ZONES {
            let gap = gaps.0 + side * n as f64;
            // The first zone is right next to the target whatever the largest gap.
            let within = gap <= gaps.1 + EPS;
            if !within && n > 0 {
                break;
            }
            let reach = start + side * n as f64;
            let c = [target.x + a[0] * reach, target.z + a[1] * reach];
            // The square, stretched `beyond` outwards along the axis.
            let out = [a[0] * beyond, a[1] * beyond];
            let z = Rect::from_corners(
                [c[0] - side / 2.0 + out[0].min(0.0), c[1] - side / 2.0 + out[1].min(0.0)],
                [c[0] + side / 2.0 + out[0].max(0.0), c[1] + side / 2.0 + out[1].max(0.0)],
            );
            if !limit.contains(&z) {
                break;
            }
            f(z, within, n == 0);
            if !within {
                break;
            }
        }
    }
}

/// The most zones [`side_zones`] lists on one side.
const MAX_SIDE_ZONES: usize = 64;

/// The viewing rule's facing for a screen and a seat (`me` at `mf`, `target` at `tf`): whether
/// both hold, whether `me` faces the target (its facing ray meets the target's footprint and
/// points within [`VIEWING_ANGLE_DEG`] of the target's centre), whether the target faces `me`
/// the same way.
pub fn watch(me: &Pose, mf: &Rect, target: &Pose, tf: &Rect) -> (bool, bool, bool) {
    let sees =
        |a: &Pose, b: &Rect| faces(a, b) && angle_to(a, b.center()) <= VIEWING_ANGLE_DEG + 1e-6;
    let mine = sees(me, tf);
    let theirs = sees(target, mf);
    (mine && theirs, mine, theirs)
}

/// Whether the ray from the pose's centre along its facing direction meets the rectangle.
pub fn faces(pose: &Pose, target: &Rect) -> bool {
    let [fx, fz] = pose.rot.front();
    let c = [pose.x, pose.z];
    if fx == 0.0 {
        let across = c[0] >= target.min_x - EPS && c[0] <= target.max_x + EPS;
        across && ((fz > 0.0 && target.max_z > c[1]) || (fz < 0.0 && target.min_z < c[1]))
    } else {
        let across = c[1] >= target.min_z - EPS && c[1] <= target.max_z + EPS;
        across && ((fx > 0.0 && target.max_x > c[0]) || (fx < 0.0 && target.min_x < c[0]))
    }
}

/// The score of a `face to` kept by turning towards the target (within 45°) without the
/// facing ray meeting it: kept, but the search still prefers facing it squarely.
pub const TURNED_TO_SCORE: f64 = 0.8;

/// Whether the pose is turned towards a point: of the four rotations, its own is the one
/// nearest to the way to the point (the point lies within 45° of its facing). A row of desks
/// wider than the teacher's desk faces it this way, each desk turned to the board, although
/// the ray from an outer desk passes beside the teacher's desk.
pub fn turned_to(pose: &Pose, p: [f64; 2]) -> bool {
    let f = pose.rot.front();
    let d = [p[0] - pose.x, p[1] - pose.z];
    let ahead = dot(f, d);
    let across = (f[0] * d[1] - f[1] * d[0]).abs();
    ahead > EPS && across <= ahead + EPS
}

/// The angle in degrees between the pose's facing direction and the direction to a point.
pub fn angle_to(pose: &Pose, p: [f64; 2]) -> f64 {
    let f = pose.rot.front();
    let d = [p[0] - pose.x, p[1] - pose.z];
    let len = d[0].hypot(d[1]);
    if len < EPS {
        return 0.0;
    }
    (dot(f, d) / len).clamp(-1.0, 1.0).acos().to_degrees()
}

/// Measures one relation of an object (`me`, `my_size = [width, depth]`) to its target.
pub fn relation(
    kind: RelationKind,
    me: &Pose,
    my_size: [f64; 2],
    target: &Pose,
    target_size: [f64; 2],
) -> Measure {
    let meaning = Meaning::of(kind, Role::Other, Role::Other, false);
    measure_relation::<true>(kind, &meaning, me, my_size, target, target_size)
}

/// [`relation`] with the meaning the pair's roles give it.
pub fn relation_meant(
    kind: RelationKind,
    meaning: &Meaning,
    me: &Pose,
    my_size: [f64; 2],
    target: &Pose,
    target_size: [f64; 2],
) -> Measure {
    measure_relation::<true>(kind, meaning, me, my_size, target, target_size)
}

/// [`relation`] without the measured value where it costs more than the test (the angle of
/// `face to` is left at 0): what the search needs at every candidate, by the same definition.
pub fn relation_fit(
    kind: RelationKind,
    meaning: &Meaning,
    me: &Pose,
    my_size: [f64; 2],
    target: &Pose,
    target_size: [f64; 2],
) -> Measure {
    measure_relation::<false>(kind, meaning, me, my_size, target, target_size)
}

/// [`relation_fit`] with both footprints given (`mf` of `me`, `tf` of `target`), for a caller
/// that has them at hand.
pub fn relation_fit_with(
    kind: RelationKind,
    meaning: &Meaning,
    me: &Pose,
    mf: &Rect,
    target: &Pose,
    tf: &Rect,
) -> Measure {
    measure_relation_with::<false>(kind, meaning, me, *mf, target, *tf)
}

fn measure_relation<const VALUE: bool>(
    kind: RelationKind,
    meaning: &Meaning,
    me: &Pose,
    my_size: [f64; 2],
    target: &Pose,
    target_size: [f64; 2],
) -> Measure {
    let mf = footprint(me, my_size);
    let tf = footprint(target, target_size);
    measure_relation_with::<VALUE>(kind, meaning, me, mf, target, tf)
}

fn measure_relation_with<const VALUE: bool>(
    kind: RelationKind,
    meaning: &Meaning,
    me: &Pose,
    mf: Rect,
    target: &Pose,
    tf: Rect,
) -> Measure {
    let gap = || mf.gap(&tf);
    let front = target.rot.front();
    let right = target.rot.right();
    let back = [-front[0], -front[1]];
    let left = [-right[0], -right[1]];
    match kind {
        RelationKind::Near => {
            let gap = gap();
            let within = gap >= meaning.min_gap - EPS && gap <= meaning.max_gap + EPS;
            // Inside the range closer is still a little better, so that `near` pulls.
            let pull = (1.0 - 0.2 * (gap - meaning.min_gap).max(0.0) / NEAR_MAX_M).clamp(0.8, 1.0);
            Measure {
                satisfied: within,
                score: if within { pull } else { 0.8 * gap_score(gap, meaning) },
                value: gap,
                unit: "m",
            }
        }
        RelationKind::Far => {
            let gap = gap();
            Measure {
                satisfied: gap >= FAR_MIN_M - EPS,
                score: (gap / FAR_MIN_M).clamp(0.0, 1.0),
                value: gap,
                unit: "m",
            }
        }
        RelationKind::InFrontOf
        | RelationKind::Behind
        | RelationKind::LeftOf
        | RelationKind::RightOf => {
            let axis = match kind {
                RelationKind::InFrontOf => front,
                RelationKind::Behind => back,
                RelationKind::LeftOf => left,
                _ => right,
            };
            let (sep, within) = side_measure(&mf, &tf, axis);
            let facing = if meaning.view {
                watch(me, &mf, target, &tf).0
            } else {
                !meaning.face || faces(me, &tf)
            };
            let in_range = sep >= meaning.min_gap - EPS && sep <= meaning.max_gap + EPS;
            let ok = sep >= -EPS && within && in_range && facing;
            let score = if ok && meaning.face {
                // A seat drawn up to a desk or table: best at the middle of its edge, so that
                // chairs sit at their own desks and not where two desks meet.
                let across = [axis[1], -axis[0]];
                let (m0, m1) = project(&mf, across);
                let (t0, t1) = project(&tf, across);
                let off = ((m0 + m1) - (t0 + t1)).abs() / 2.0;
                1.0 - SEAT_OFF_MIDDLE_PENALTY * (off / ((t1 - t0) / 2.0).max(EPS)).min(1.0)
            } else if ok {
                1.0
            } else if sep >= -EPS && within {
                0.5 * gap_score(sep, meaning) + if facing { 0.4 } else { 0.0 }
            } else {
                0.0
            };
            Measure { satisfied: ok, score, value: sep, unit: "m" }
        }
        RelationKind::SideOf => {
            let (sl, wl) = side_measure(&mf, &tf, left);
            let (sr, wr) = side_measure(&mf, &tf, right);
            let fits = |sep: f64, w: bool| {
                w && sep >= -EPS && sep >= meaning.min_gap - EPS && sep <= meaning.max_gap + EPS
            };
            let ok = fits(sl, wl) || fits(sr, wr);
            Measure::yes_no(ok, sl.max(sr), "m")
        }
        RelationKind::Around if meaning.ring.is_some() => {
            let seats = meaning
                .ring
                .map(|r| seat_poses(target, target_size_of(target, &tf), &r))
                .unwrap_or_default();
            around_seats(meaning, me, &mf, &tf, &seats)
        }
        RelationKind::Around => {
            let facing = faces(me, &tf);
            let gap = gap();
            let close = gap <= meaning.max_gap + EPS;
            let near_part = (1.0 - gap / (2.0 * meaning.max_gap)).clamp(0.0, 1.0);
            let score = 0.5 * near_part + if facing { 0.5 } else { 0.0 };
            Measure {
                satisfied: facing && close,
                score: if facing && close { 1.0 } else { score.min(0.9) },
                value: gap,
                unit: "m",
            }
        }
        RelationKind::CenterAligned => {
            let d = (me.x - target.x).abs().min((me.z - target.z).abs());
            Measure::yes_no(d <= ALIGN_TOLERANCE_M + EPS, d, "m")
        }
        RelationKind::FaceTo if meaning.view => {
            // A screen and its seats: across from each other (each within the viewing angle
            // of facing the other) at a viewing distance.
            let (both, mine, theirs) = watch(me, &mf, target, &tf);
            let gap = gap();
            let in_range = gap >= meaning.min_gap - EPS && gap <= meaning.max_gap + EPS;
            let ok = both && in_range;
            let score = if ok {
                1.0
            } else {
                0.4 * f64::from(u8::from(mine))
                    + 0.3 * f64::from(u8::from(theirs))
                    + 0.2 * gap_score(gap, meaning)
            };
            let angle = if VALUE { angle_to(me, [target.x, target.z]) } else { 0.0 };
            Measure { satisfied: ok, score, value: angle, unit: "deg" }
        }
        RelationKind::FaceTo => {
            let angle = if VALUE { angle_to(me, [target.x, target.z]) } else { 0.0 };
            // Held when turned towards it; best when the facing ray meets it.
            let ray = faces(me, &tf);
            let ok = ray || turned_to(me, tf.center());
            let score = if ray {
                1.0
            } else if ok {
                TURNED_TO_SCORE
            } else {
                0.0
            };
            Measure { satisfied: ok, score, value: angle, unit: "deg" }
        }
        RelationKind::FaceSameAs => {
            let diff = (me.rot.deg() - target.rot.deg()).rem_euclid(360.0);
            let diff = diff.min(360.0 - diff);
            Measure::yes_no(me.rot == target.rot, diff, "deg")
        }
    }
}

/// The footprint size `[width, depth]` at rotation 0 of an object at `pose` whose footprint is
/// `fp` (a quarter turn swaps the two).
/// `around` a table for one of the chairs that share its seats (`seats`, as [`seat_poses`]
/// gives them for the table's pose): at one of them, facing the table as that seat does; the
/// distance to the nearest is the measure. The search works the seats out once per table pose.
pub fn around_seats(meaning: &Meaning, me: &Pose, mf: &Rect, tf: &Rect, seats: &[Pose]) -> Measure {
    let exact = |p: &Pose| ((p.x - me.x).hypot(p.z - me.z), p.rot);
    // The squared distances narrow the seats whose exact distance can be the least to those
    // within a relative 1e-9 of the least square (rounding moves either by a few units in the
    // last place), so `hypot` is worked out for the nearest only; with nothing left (NaN),
    // every seat.
    let square = |p: &Pose| (p.x - me.x) * (p.x - me.x) + (p.z - me.z) * (p.z - me.z);
    let least = seats.iter().map(square).fold(f64::INFINITY, f64::min);
    let nearest = seats
        .iter()
        .filter(|p| square(p) <= least * (1.0 + 1e-9))
        .map(exact)
        .min_by(|a, b| a.0.total_cmp(&b.0))
        .or_else(|| seats.iter().map(exact).min_by(|a, b| a.0.total_cmp(&b.0)));
    let (dist, rot) = nearest.unwrap_or((f64::INFINITY, me.rot));
    let at_seat = dist <= SEAT_TOLERANCE_M + EPS && rot == me.rot;
    let facing = faces(me, tf);
    let gap = mf.gap(tf);
    let close = gap <= meaning.max_gap + EPS;
    // Drawn to the seats: most for standing at one, some for being close and facing.
    let toward = (1.0 - dist / 2.0).clamp(0.0, 1.0);
    // At a seat, the nearer its middle the better, so that chairs stand evenly.
    let score = if at_seat {
        1.0 - 0.1 * dist / SEAT_TOLERANCE_M
    } else {
        0.3 * toward
            + if facing && close {
                0.5
            } else if facing {
                0.2
            } else {
                0.0
            }
    };
    Measure { satisfied: at_seat, score, value: dist.min(1e9), unit: "m" }
}

pub(crate) fn target_size_of(pose: &Pose, fp: &Rect) -> [f64; 2] {
    let right = pose.rot.right();
    if right[0].abs() > 0.5 {
        [fp.width(), fp.depth()]
    } else {
        [fp.depth(), fp.width()]
    }
}

/// Measures a global constraint: for `edge` the distance from the middle of the back side to
/// the nearest wall, for `middle` the smallest gap between the footprint and the walls.
pub fn global(kind: GlobalKind, pose: &Pose, size: [f64; 2], room: &RoomShape) -> Measure {
    match kind {
        GlobalKind::Edge => {
            let d = room.distance_to_wall(back_center(pose, size));
            Measure::yes_no(
                d <= EDGE_TOLERANCE_M + EPS && room.contains_rect(&footprint(pose, size)),
                d,
                "m",
            )
        }
        GlobalKind::Middle => {
            let fp = footprint(pose, size);
            let ok = room.contains_rect(&fp.grow(MIDDLE_GAP_M));
            let corners = [
                [fp.min_x, fp.min_z],
                [fp.min_x, fp.max_z],
                [fp.max_x, fp.min_z],
                [fp.max_x, fp.max_z],
            ];
            let mut d =
                corners.iter().map(|c| room.distance_to_wall(*c)).fold(f64::INFINITY, f64::min);
            // Walls may also pass beside a side without touching a corner.
            let n = room.outline.len();
            for i in 0..n {
                let a = room.outline[i];
                let b = room.outline[(i + 1) % n];
                d = d.min(Rect::from_corners(a, b).gap(&fp));
            }
            Measure::yes_no(ok, d, "m")
        }
    }
}

/// The hard rules a floor pose must keep, in the order they are checked.
#[derive(Clone, Copy, Debug, PartialEq, Eq, PartialOrd, Ord, Hash)]
pub enum HardRule {
    /// The footprint lies inside the room.
    InsideRoom,
    /// The global constraint (`edge` or `middle`).
    Global,
    /// The footprint avoids every door keep-out zone.
    DoorKeepOut,
    /// The front clearance lies inside the room.
    FrontClearance,
    /// A tall object does not stand in front of a window.
    Window,
    /// The footprint overlaps no other placed footprint.
    NoOverlap,
    /// The use-clearances (the front of a sofa, desk, counter, fridge or dresser, an open side
    /// of a bed) stay free of unrelated furniture.
    UseClearance,
    /// Every placed object stays reachable from a door.
    Reachable,
}

impl HardRule {
    /// A short phrase naming the rule.
    pub fn describe(self) -> &'static str {
        match self {
            HardRule::InsideRoom => "inside the room",
            HardRule::Global => "the global constraint",
            HardRule::DoorKeepOut => "door keep-out zones",
            HardRule::FrontClearance => "front clearance",
            HardRule::Window => "window zones",
            HardRule::NoOverlap => "no overlap",
            HardRule::UseClearance => "use-clearances",
            HardRule::Reachable => "reachability from a door",
        }
    }
}

/// A window seen from the floor: the zone in front of it and the height of its sill.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct WindowZone {
    /// The floor zone (both sides of the wall line, [`WINDOW_ZONE_M`] deep).
    pub zone: Rect,
    /// Height of the bottom of the window above the floor, metres.
    pub sill_m: f64,
}

/// Whether a floor object of `height_m` standing on `fp` blocks a window.
pub fn blocks_window(fp: &Rect, height_m: f64, w: &WindowZone) -> bool {
    height_m > w.sill_m + EPS && fp.overlaps(&w.zone)
}

/// The static hard rules of a pose (everything but overlap and reachability): the first rule
/// it breaks, if any. `global_kind: None` leaves the global constraint out (an `edge` object
/// that no wall can take is placed elsewhere, its `edge` reported as not kept).
pub fn static_rules(
    pose: &Pose,
    size: [f64; 2],
    height_m: f64,
    global_kind: Option<GlobalKind>,
    room: &RoomShape,
    keep_out: &[Rect],
    windows: &[WindowZone],
) -> Option<HardRule> {
    let fp = footprint(pose, size);
    if !room.contains_rect(&fp) {
        return Some(HardRule::InsideRoom);
    }
    let global_ok = match global_kind {
        Some(GlobalKind::Edge) => room.near_wall(back_center(pose, size), EDGE_TOLERANCE_M + EPS),
        Some(GlobalKind::Middle) => room.contains_rect(&fp.grow(MIDDLE_GAP_M)),
        None => true,
    };
    if !global_ok {
        return Some(HardRule::Global);
    }
    if keep_out.iter().any(|k| k.overlaps(&fp)) {
        return Some(HardRule::DoorKeepOut);
    }
    if !room.contains_rect(&front_zone(pose, size, FRONT_CLEARANCE_M)) {
        return Some(HardRule::FrontClearance);
    }
    if windows.iter().any(|w| blocks_window(&fp, height_m, w)) {
        return Some(HardRule::Window);
    }
    None
}

/// A grid over the room's floor for the reachability rule.
#[derive(Clone, Debug)]
pub struct ReachGrid {
    /// The agent's radius, metres.
    radius: f64,
    origin: [f64; 2],
    nx: usize,
    nz: usize,
    /// Cells whose agent disk fits inside the room.
    open: Vec<bool>,
    /// The open cells inside a door zone, where the flood starts.
    sources: Vec<usize>,
}

/// A cell of a flood that an agent cannot stand on.
const BLOCKED: u8 = 0;
/// A cell of a flood where an agent fits but that it does not reach from a door.
const FREE: u8 = 1;
/// A cell of a flood that an agent reaches from a door.
const REACHED: u8 = 2;

impl ReachGrid {
    /// The agent's radius, metres.
    pub fn radius(&self) -> f64 {
        self.radius
    }

    /// The narrowest way between two footprints that the grid lets the agent through wherever
    /// the footprints stand: the agent's width and one cell (the way must hold a cell centre a
    /// radius from both).
    pub fn aisle(&self) -> f64 {
        2.0 * self.radius + REACH_CELL_M
    }

    /// Builds the grid of a room with its door keep-out zones, for an agent of `radius` metres.
    pub fn new(room: &RoomShape, doors: &[Rect], radius: f64) -> ReachGrid {
        let radius = if radius.is_finite() && radius > 0.0 { radius } else { AGENT_RADIUS_M };
        let b = room.bounds;
        let nx = ((b.width() / REACH_CELL_M).ceil() as usize).max(1);
        let nz = ((b.depth() / REACH_CELL_M).ceil() as usize).max(1);
        let mut open = vec![false; nx * nz];
        let mut source = vec![false; nx * nz];
        for i in 0..nx {
            for j in 0..nz {
                let c = [
                    b.min_x + (i as f64 + 0.5) * REACH_CELL_M,
                    b.min_z + (j as f64 + 0.5) * REACH_CELL_M,
                ];
                let disk =
                    Rect { min_x: c[0], min_z: c[1], max_x: c[0], max_z: c[1] }.grow(radius - 1e-3);
                open[i * nz + j] = room.contains_rect(&disk);
                source[i * nz + j] = doors.iter().any(|d| d.contains_point(c));
            }
        }
        let sources = (0..nx * nz).filter(|&k| source[k] && open[k]).collect();
        ReachGrid { radius, origin: [b.min_x, b.min_z], nx, nz, open, sources }
    }

    /// Whether there is any door to start from.
    pub fn has_sources(&self) -> bool {
        !self.sources.is_empty()
    }

    /// An empty occupancy for this grid (no footprint on the floor).
    pub fn occupancy(&self) -> Occupancy {
        Occupancy { blocked: vec![0; self.nx * self.nz] }
    }

    /// Adds (`delta = 1`) or removes (`delta = -1`) one footprint: every cell whose centre is
    /// closer than the agent's radius to it is blocked for the agent.
    pub fn mark(&self, occupancy: &mut Occupancy, fp: &Rect, delta: i16) {
        let r = self.radius - 1e-3;
        let (i0, i1, j0, j1) = self.cell_range(&fp.grow(r));
        let near = |i: usize, j: usize| fp.distance_sq_to_point(self.cell_center(i, j)) < r * r;
        for i in i0..=i1 {
            // Along a row the distance to the footprint falls and then rises (each step of
            // it rounded the same way), so the cells near enough are one run: found from both
            // ends, the cells between taken without measuring each.
            let Some(a) = (j0..=j1).find(|&j| near(i, j)) else { continue };
            let b = (a..=j1).rev().find(|&j| near(i, j)).unwrap_or(a);
            for cell in &mut occupancy.blocked[i * self.nz + a..=i * self.nz + b] {
                *cell = cell.saturating_add_signed(delta);
            }
        }
    }

    /// The occupancy of a set of footprints.
    fn occupancy_of(&self, footprints: &[Rect]) -> Occupancy {
        let mut occ = self.occupancy();
        for fp in footprints {
            self.mark(&mut occ, fp, 1);
        }
        occ
    }

    /// The number of free cells (agent fits, no footprint) and which of them an agent entering
    /// through a door reaches.
    /// Floods the free cells (agent fits, no footprint) from the doors. Returns the number of
    /// free cells, the number reached, and per cell [`BLOCKED`], [`FREE`] or [`REACHED`].
    fn flood(&self, occ: &Occupancy) -> (usize, usize, Vec<u8>) {
        let (nx, nz) = (self.nx, self.nz);
        let mut cell: Vec<u8> = self
            .open
            .iter()
            .zip(&occ.blocked)
            .map(|(o, b)| if *o && *b == 0 { FREE } else { BLOCKED })
            .collect();
        let n_free: usize = cell.iter().map(|&c| usize::from(c == FREE)).sum();
        let mut n_seen = 0;
        // Span filling: a seed grows into the run of free cells along z that contains it, and
        // the runs next to that run in the neighbouring x columns become seeds.
        let mut stack: Vec<usize> = self.sources.clone();
        while let Some(k) = stack.pop() {
            if cell[k] != FREE {
                continue;
            }
            let (i, j) = (k / nz, k % nz);
            let row = i * nz;
            let (mut a, mut b) = (j, j);
            while a > 0 && cell[row + a - 1] == FREE {
                a -= 1;
            }
            while b + 1 < nz && cell[row + b + 1] == FREE {
                b += 1;
            }
            cell[row + a..=row + b].fill(REACHED);
            n_seen += b - a + 1;
            for ni in [i.wrapping_sub(1), i + 1] {
                if ni >= nx {
                    continue;
                }
                // A seed at the start of each run of free cells beside this run.
                let first = ni * nz + a;
                let beside = &cell[first..=first + (b - a)];
                let mut t = 0;
                while let Some(skip) = beside[t..].iter().position(|&c| c == FREE) {
                    t += skip;
                    stack.push(first + t);
                    match beside[t..].iter().position(|&c| c != FREE) {
                        Some(run) => t += run,
                        None => break,
                    }
                }
            }
        }
        (n_free, n_seen, cell)
    }

    fn cell_center(&self, i: usize, j: usize) -> [f64; 2] {
        [
            self.origin[0] + (i as f64 + 0.5) * REACH_CELL_M,
            self.origin[1] + (j as f64 + 0.5) * REACH_CELL_M,
        ]
    }

    /// The cells `(i0, i1, j0, j1)` (inclusive, clamped) that a rectangle covers.
    fn cell_range(&self, r: &Rect) -> (usize, usize, usize, usize) {
        let cell = |v: f64, o: f64, n: usize| {
            (((v - o) / REACH_CELL_M).floor().max(0.0) as usize).min(n - 1)
        };
        (
            cell(r.min_x, self.origin[0], self.nx),
            cell(r.max_x, self.origin[0], self.nx),
            cell(r.min_z, self.origin[1], self.nz),
            cell(r.max_z, self.origin[1], self.nz),
        )
    }

    /// Whether an agent standing on a reached cell is close enough to touch the footprint.
    fn reached(&self, fp: &Rect, cells: &[u8]) -> bool {
        let reach = self.radius + 1.5 * REACH_CELL_M;
        let (i0, i1, j0, j1) = self.cell_range(&fp.grow(reach));
        (i0..=i1).any(|i| {
            (j0..=j1).any(|j| {
                cells[i * self.nz + j] == REACHED
                    && fp.distance_sq_to_point(self.cell_center(i, j)) <= reach * reach
            })
        })
    }

    /// The footprints (indices into `footprints`) that no agent coming in through a door can
    /// reach (stand within [`AGENT_RADIUS_M`] + 1.5 cells of). Empty when the room has no door.
    pub fn unreachable(&self, footprints: &[Rect]) -> Vec<usize> {
        if !self.has_sources() || footprints.is_empty() {
            return Vec::new();
        }
        let (_, _, cells) = self.flood(&self.occupancy_of(footprints));
        (0..footprints.len()).filter(|&n| !self.reached(&footprints[n], &cells)).collect()
    }

    /// The reachability rule: every footprint is reachable, and no closed pocket of free floor
    /// (free cells no agent coming through a door reaches, connected) is larger than
    /// [`MAX_POCKET_M2`]. Always true for a room with no door.
    pub fn ok(&self, footprints: &[Rect]) -> bool {
        self.ok_with(&self.occupancy_of(footprints), footprints)
    }

    /// [`ReachGrid::ok`] for footprints whose occupancy the caller keeps up to date with
    /// [`ReachGrid::mark`] (the search adds and removes one footprint per step instead of
    /// rebuilding the grid).
    pub fn ok_with(&self, occupancy: &Occupancy, footprints: &[Rect]) -> bool {
        footprints.is_empty() || self.base(occupancy, footprints).ok()
    }

    /// What a flood of these footprints finds, kept so that [`ReachGrid::extend`] can judge
    /// one more footprint on top of them, most often without a flood of its own.
    pub fn base(&self, occupancy: &Occupancy, footprints: &[Rect]) -> ReachBase {
        if !self.has_sources() {
            return ReachBase {
                footprints: footprints.to_vec(),
                cells: Vec::new(),
                pockets_ok: true,
                reached: vec![true; footprints.len()],
            };
        }
        let (n_free, n_seen, cells) = self.flood(occupancy);
        let pockets_ok = n_free == n_seen
            || self.largest_pocket(&mut cells.clone(), Self::pocket_cells())
                <= Self::pocket_cells();
        let reached = footprints.iter().map(|fp| self.reached(fp, &cells)).collect();
        ReachBase { footprints: footprints.to_vec(), cells, pockets_ok, reached }
    }

    /// The base of `base`'s footprints and one more, `added`, whose cells are already marked
    /// in `occupancy`, worked out from `base` without a flood; `None` when that cannot be done
    /// (then [`ReachGrid::base`] floods the room).
    ///
    /// When the base keeps its pockets small, the one footprint added cannot make a pocket
    /// larger (the cells no agent reaches can only lose cells), and when the cells an agent
    /// reached right around the new footprint still join up near it, every cell it reached
    /// before and the footprint does not cover is still reached: a way that went through the
    /// footprint's cells goes round them instead. Then the new flood is the old one less the
    /// footprint's cells, and only the footprints near the new one can change their answer.
    pub fn extend(
        &self,
        base: &ReachBase,
        occupancy: &Occupancy,
        added: &Rect,
    ) -> Option<ReachBase> {
        if !self.has_sources() || !base.pockets_ok || base.cells.len() != occupancy.blocked.len() {
            return None;
        }
        let covered = self.cell_range(&added.grow(self.radius - 1e-3));
        if !self.reached_cells_join_round(base, occupancy, covered) {
            return None;
        }
        let mut cells = base.cells.clone();
        let (i0, i1, j0, j1) = covered;
        for i in i0..=i1 {
            let row = i * self.nz + j0..=i * self.nz + j1;
            for (cell, &blocked) in cells[row.clone()].iter_mut().zip(&occupancy.blocked[row]) {
                if blocked > 0 {
                    *cell = BLOCKED;
                }
            }
        }
        let reach = self.radius + 1.5 * REACH_CELL_M;
        let meets = |(a0, a1, b0, b1): (usize, usize, usize, usize)| {
            a0 <= i1 && i0 <= a1 && b0 <= j1 && j0 <= b1
        };
        let mut footprints = base.footprints.clone();
        footprints.push(*added);
        let reached = footprints
            .iter()
            .enumerate()
            .map(|(n, fp)| match base.reached.get(n) {
                Some(&before) if !meets(self.cell_range(&fp.grow(reach))) => before,
                _ => self.reached(fp, &cells),
            })
            .collect();
        Some(ReachBase { footprints, cells, pockets_ok: true, reached })
    }

    /// Whether every cell an agent reached in `base` next to a cell that `occupancy` now blocks
    /// is joined to the others through reached cells left free, within a few cells of the
    /// blocked range `covered` (a door cell blocked counts as not joined).
    fn reached_cells_join_round(
        &self,
        base: &ReachBase,
        occupancy: &Occupancy,
        covered: (usize, usize, usize, usize),
    ) -> bool {
        const MARGIN: usize = 3;
        let (nx, nz) = (self.nx, self.nz);
        let (i0, i1, j0, j1) = covered;
        let still = |k: usize| base.cells[k] == REACHED && occupancy.blocked[k] == 0;
        let lost = |k: usize| base.cells[k] == REACHED && occupancy.blocked[k] > 0;
        if self.sources.iter().any(|&k| lost(k)) {
            return false;
        }
        // The window searched: the covered range and `MARGIN` cells round it.
        let (wi0, wi1) = (i0.saturating_sub(MARGIN), (i1 + MARGIN).min(nx - 1));
        let (wj0, wj1) = (j0.saturating_sub(MARGIN), (j1 + MARGIN).min(nz - 1));
        let wz = wj1 - wj0 + 1;
        let local = |i: usize, j: usize| (i - wi0) * wz + (j - wj0);
        // The reached cells left free beside a reached cell now blocked.
        let mut ring: Vec<(usize, usize)> = Vec::new();
        let mut is_ring = vec![false; (wi1 - wi0 + 1) * wz];
        for i in i0..=i1 {
            for j in j0..=j1 {
                if !lost(i * nz + j) {
                    continue;
                }
                let beside =
                    [(i.wrapping_sub(1), j), (i + 1, j), (i, j.wrapping_sub(1)), (i, j + 1)];
                for (a, b) in beside {
                    if a < nx && b < nz && still(a * nz + b) && !is_ring[local(a, b)] {
                        is_ring[local(a, b)] = true;
                        ring.push((a, b));
                    }
                }
            }
        }
        let Some(&start) = ring.first() else {
            return true;
        };
        // A flood of the reached cells left free, inside the window, from one of them.
        let mut seen = vec![false; is_ring.len()];
        seen[local(start.0, start.1)] = true;
        let mut stack = vec![start];
        let mut found = 0;
        while let Some((i, j)) = stack.pop() {
            if is_ring[local(i, j)] {
                found += 1;
                if found == ring.len() {
                    return true;
                }
            }
            let beside = [(i.wrapping_sub(1), j), (i + 1, j), (i, j.wrapping_sub(1)), (i, j + 1)];
            for (a, b) in beside {
                if (wi0..=wi1).contains(&a)
                    && (wj0..=wj1).contains(&b)
                    && !seen[local(a, b)]
                    && still(a * nz + b)
                {
                    seen[local(a, b)] = true;
                    stack.push((a, b));
                }
            }
        }
        false
    }

    /// The most cells a closed pocket may have.
    fn pocket_cells() -> usize {
        (MAX_POCKET_M2 / (REACH_CELL_M * REACH_CELL_M)).round() as usize
    }

    /// The size in cells of the largest closed pocket (connected free cells not reached),
    /// counting no further than `stop_above + 1`. Marks the pockets' cells as blocked.
    fn largest_pocket(&self, cells: &mut [u8], stop_above: usize) -> usize {
        let (nx, nz) = (self.nx, self.nz);
        let mut largest = 0;
        let mut stack = Vec::new();
        for start in 0..cells.len() {
            if cells[start] != FREE {
                continue;
            }
            cells[start] = BLOCKED;
            stack.push(start);
            let mut size = 0;
            while let Some(k) = stack.pop() {
                size += 1;
                let (i, j) = (k / nz, k % nz);
                let mut push = |n: usize| {
                    if cells[n] == FREE {
                        cells[n] = BLOCKED;
                        stack.push(n);
                    }
                };
                if i > 0 {
                    push(k - nz);
                }
                if i + 1 < nx {
                    push(k + nz);
                }
                if j > 0 {
                    push(k - 1);
                }
                if j + 1 < nz {
                    push(k + 1);
                }
            }
            largest = largest.max(size);
            if largest > stop_above {
                break;
            }
        }
        largest
    }

    /// The largest closed pocket of free floor, square metres, with these footprints on the
    /// floor (0 for a room with no door): what the benchmark reports.
    pub fn largest_pocket_m2(&self, footprints: &[Rect]) -> f64 {
        if !self.has_sources() {
            return 0.0;
        }
        let (_, _, mut cells) = self.flood(&self.occupancy_of(footprints));
        self.largest_pocket(&mut cells, usize::MAX) as f64 * REACH_CELL_M * REACH_CELL_M
    }
}

/// A flood of a set of footprints kept by [`ReachGrid::base`].
#[derive(Clone, Debug)]
pub struct ReachBase {
    /// The footprints flooded.
    pub footprints: Vec<Rect>,
    /// Per cell, [`BLOCKED`], [`FREE`] or [`REACHED`].
    cells: Vec<u8>,
    /// Whether no closed pocket is larger than [`MAX_POCKET_M2`].
    pockets_ok: bool,
    /// Per footprint, whether an agent reaches it.
    reached: Vec<bool>,
}

impl ReachBase {
    /// The reachability rule on these footprints ([`ReachGrid::ok`]).
    pub fn ok(&self) -> bool {
        self.footprints.is_empty() || (self.pockets_ok && self.reached.iter().all(|&r| r))
    }
}

/// How many footprints block each cell of a [`ReachGrid`].
#[derive(Clone, Debug)]
pub struct Occupancy {
    blocked: Vec<u16>,
}

#[cfg(test)]
mod tests {
    use super::*;

    fn rect_room() -> RoomShape {
        RoomShape::new(&[[0.0, 0.0], [0.0, 4.0], [5.0, 4.0], [5.0, 0.0]]).expect("valid room")
    }

    #[test]
    fn l_shape_has_two_maximal_rects() {
        let l = RoomShape::new(&[
            [0.0, 0.0],
            [0.0, 4.0],
            [2.0, 4.0],
            [2.0, 2.0],
            [4.0, 2.0],
            [4.0, 0.0],
        ])
        .expect("L");
        assert_eq!(l.rects.len(), 2);
        assert!(l.contains_rect(&Rect::from_corners([0.0, 0.0], [4.0, 2.0])));
        assert!(!l.contains_rect(&Rect::from_corners([1.0, 1.0], [3.0, 3.0])));
    }

    #[test]
    fn left_and_right_follow_the_target() {
        let t = Pose { x: 2.0, z: 2.0, rot: Rot::R0 };
        let left = Pose { x: 0.5, z: 2.0, rot: Rot::R0 };
        assert!(relation(RelationKind::LeftOf, &left, [1.0, 1.0], &t, [1.0, 1.0]).satisfied);
        assert!(!relation(RelationKind::RightOf, &left, [1.0, 1.0], &t, [1.0, 1.0]).satisfied);
        let t90 = Pose { rot: Rot::R90, ..t };
        // Facing +x, the target's left is +z.
        let up = Pose { x: 2.0, z: 3.5, rot: Rot::R0 };
        assert!(relation(RelationKind::LeftOf, &up, [1.0, 1.0], &t90, [1.0, 1.0]).satisfied);
    }

    #[test]
    fn in_front_and_face_to() {
        let t = Pose { x: 2.0, z: 0.5, rot: Rot::R0 };
        let me = Pose { x: 2.0, z: 2.0, rot: Rot::R180 };
        assert!(relation(RelationKind::InFrontOf, &me, [1.0, 1.0], &t, [1.0, 1.0]).satisfied);
        assert!(relation(RelationKind::FaceTo, &me, [1.0, 1.0], &t, [1.0, 1.0]).satisfied);
        assert!(!relation(RelationKind::Behind, &me, [1.0, 1.0], &t, [1.0, 1.0]).satisfied);
    }

    #[test]
    fn edge_and_middle() {
        let room = rect_room();
        let against = Pose { x: 2.0, z: 0.5, rot: Rot::R0 };
        assert!(global(GlobalKind::Edge, &against, [2.0, 1.0], &room).satisfied);
        assert!(!global(GlobalKind::Middle, &against, [2.0, 1.0], &room).satisfied);
        let centre = Pose { x: 2.5, z: 2.0, rot: Rot::R0 };
        assert!(global(GlobalKind::Middle, &centre, [1.0, 1.0], &room).satisfied);
    }

    #[test]
    fn boxed_in_object_is_unreachable() {
        let room = rect_room();
        let door = Rect::from_corners([2.0, 0.0], [3.0, 1.0]);
        let grid = ReachGrid::new(&room, &[door], AGENT_RADIUS_M);
        let wall = Rect::from_corners([0.0, 1.5], [5.0, 2.0]);
        let behind = Rect::from_corners([2.0, 3.0], [3.0, 4.0]);
        assert_eq!(grid.unreachable(&[wall, behind]), vec![1]);
        assert!(grid.unreachable(&[behind]).is_empty());
    }

    /// A way through a row of furniture as wide as [`ReachGrid::aisle`] lets the agent through
    /// wherever it stands; one exactly as wide as the agent does not everywhere.
    #[test]
    fn an_aisle_lets_the_agent_through_wherever_it_stands() {
        let room = rect_room();
        let door = Rect::from_corners([2.0, 0.0], [3.0, 1.0]);
        let grid = ReachGrid::new(&room, &[door], AGENT_RADIUS_M);
        let behind = Rect::from_corners([2.0, 3.0], [3.0, 4.0]);
        let through = |start: f64, width: f64| {
            let left = Rect::from_corners([0.0, 1.5], [start, 2.0]);
            let right = Rect::from_corners([start + width, 1.5], [5.0, 2.0]);
            grid.unreachable(&[left, right, behind]).is_empty()
        };
        let starts: Vec<f64> = (0..40).map(|i| 1.5 + 0.0071 * f64::from(i)).collect();
        assert!(starts.iter().all(|&s| through(s, grid.aisle())));
        assert!(starts.iter().any(|&s| !through(s, 2.0 * AGENT_RADIUS_M)));
    }

    /// Adds the footprints one by one: every flood worked out by [`ReachGrid::extend`] is the
    /// flood of the room (cell for cell, footprint for footprint, same answer), and `None`
    /// only leaves the answer to a full flood.
    fn extend_agrees(room: &RoomShape, door: Rect, footprints: &[Rect]) -> usize {
        let grid = ReachGrid::new(room, &[door], AGENT_RADIUS_M);
        let mut occ = grid.occupancy();
        let mut base = grid.base(&occ, &[]);
        let mut extended = 0;
        for (n, fp) in footprints.iter().enumerate() {
            grid.mark(&mut occ, fp, 1);
            let full = grid.base(&occ, &footprints[..=n]);
            assert_eq!(full.ok(), grid.ok(&footprints[..=n]), "{:?}", &footprints[..=n]);
            if let Some(next) = grid.extend(&base, &occ, fp) {
                extended += 1;
                assert_eq!(next.cells, full.cells, "{:?}", &footprints[..=n]);
                assert_eq!(next.reached, full.reached, "{:?}", &footprints[..=n]);
                assert_eq!(next.ok(), full.ok());
            }
            base = full;
        }
        extended
    }

    #[test]
    fn extend_takes_the_short_way_for_furniture_along_the_walls() {
        let room = rect_room();
        let door = Rect::from_corners([2.0, 0.0], [3.0, 1.0]);
        let along = [
            Rect::from_corners([0.0, 3.4], [1.2, 4.0]),
            Rect::from_corners([3.8, 3.0], [5.0, 4.0]),
            Rect::from_corners([0.0, 0.0], [0.6, 1.5]),
            Rect::from_corners([2.0, 1.8], [3.0, 2.6]),
        ];
        assert_eq!(extend_agrees(&room, door, &along), along.len());
        // A wall across the room cuts it in two: the short way refuses, the flood decides.
        let across = [Rect::from_corners([0.0, 1.5], [5.0, 2.0])];
        assert_eq!(extend_agrees(&room, door, &across), 0);
    }

    proptest::proptest! {
        /// [`ReachGrid::mark`] marks the cells of its run per row exactly as measuring every
        /// cell's centre in the footprint's range against the footprint does.
        #[test]
        fn mark_blocks_the_cells_within_the_radius(
            x in -0.5..5.0f64, z in -0.5..4.0f64, w in 0.0..2.0f64, d in 0.0..2.0f64,
        ) {
            let grid = ReachGrid::new(&rect_room(), &[], AGENT_RADIUS_M);
            let fp = Rect::from_corners([x, z], [x + w, z + d]);
            let mut occ = grid.occupancy();
            grid.mark(&mut occ, &fp, 1);
            let r = grid.radius - 1e-3;
            let (i0, i1, j0, j1) = grid.cell_range(&fp.grow(r));
            for i in 0..grid.nx {
                for j in 0..grid.nz {
                    let near = (i0..=i1).contains(&i)
                        && (j0..=j1).contains(&j)
                        && fp.distance_sq_to_point(grid.cell_center(i, j)) < r * r;
                    proptest::prop_assert_eq!(occ.blocked[i * grid.nz + j], u16::from(near));
                }
            }
            grid.mark(&mut occ, &fp, -1);
            proptest::prop_assert!(occ.blocked.iter().all(|&b| b == 0));
        }

        #[test]
        fn extend_is_the_flood_of_the_room(
            boxes in proptest::collection::vec(
                (0.0..5.0f64, 0.0..4.0f64, 0.1..1.6f64, 0.1..1.6f64), 1..9),
            l_shaped in proptest::bool::ANY,
        ) {
            let room = if l_shaped {
                RoomShape::new(&[[0.0, 0.0], [0.0, 4.0], [2.5, 4.0], [2.5, 2.0], [5.0, 2.0], [5.0, 0.0]])
                    .expect("L")
            } else {
                rect_room()
            };
            let door = Rect::from_corners([2.0, 0.0], [3.0, 1.0]);
            let footprints: Vec<Rect> = boxes
                .iter()
                .map(|&(x, z, w, d)| Rect::from_corners([x, z], [(x + w).min(5.0), (z + d).min(4.0)]))
                .collect();
            extend_agrees(&room, door, &footprints);
        }
    }
}

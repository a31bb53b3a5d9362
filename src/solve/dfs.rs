//! The depth-first floor solver: branch and bound over candidate poses, in plan order, with
//! limited discrepancy and a node budget.
//!
//! An object's candidates ([`super::candidates`]: its static grid, shared by the objects alike,
//! and the poses derived from its placed targets) are worked out once per object and per set of
//! target poses. At a node, candidates that overlap a placed footprint are dropped, the rest are
//! walked best first by a bound of their key (ties in a seeded order), and the search descends
//! into them.

use std::cell::RefCell;
use std::collections::{BTreeMap, BinaryHeap};
use std::rc::Rc;

use rustc_hash::FxHashMap;

use super::candidates::{
    anywhere_candidates, dedup_cands, derived_for_target, derived_targets, drawn_up, fast_score,
    flush_values, kept_out_of, shuffle_static, static_grid, static_grid_key, Cand, StaticGridKey,
};
use super::constraints::{
    self, footprint, half_extents, HardRule, Occupancy, Pose, ReachBase, Rect, Rot,
};
use super::grid::{CentreIndex, FootprintGrid, ZoneGrid};
use super::{measure_object, PlacedFloor, Prepared, RoomLayout, SolveOptions, Unplaced};
use crate::check::scene::{GlobalKind, RelationKind};

/// The most reachability checks per node before the object counts as boxed in.
const REACH_TRIES: usize = 24;
/// The largest discrepancy tried (number of non-best choices on one path).
const MAX_DISCREPANCY: usize = 3;

/// How far round a broken relation's objects (metres) the objects that may take a
/// discrepancy are looked for ([`Search::conflicts`]), at least.
const CONFLICT_REACH_M: f64 = 0.75;
/// The ordering bonus per side of a footprint touching a wall or a placed footprint (less than
/// any satisfied relation is worth; it only breaks near-ties in favour of compact layouts).
const CONTACT_BONUS: f64 = 0.1;
/// The ordering bonus per side relation of a later object that finds a free zone right next
/// to its target (and the penalty for covering such a zone): it keeps chairs next to their
/// desks instead of a row of desks later.
const ROOM_NEXT_TO_BONUS: f64 = 0.5;
/// How close (metres) a side must be to a wall or a footprint to count as touching it.
const CONTACT_M: f64 = 0.02;

/// Whether an `edge` object with no wall pose left may stand elsewhere (`edge` is soft): not
/// storage (a bookcase, shelf, wardrobe, dresser or cabinet stands against a wall or is left
/// out, never a free-standing divider).
fn stands_elsewhere(obj: &super::FloorObject) -> bool {
    obj.global == GlobalKind::Edge && !obj.role.wants_wall()
}

/// Whether relation `c` of object `j` is a `near` between two objects against the walls
/// with no side relation beside it to the same target: the later object stands along the wall
/// beside its target, on either side.
fn near_along_wall(problem: &super::RoomProblem, j: usize, c: &super::ProblemConstraint) -> bool {
    let obj = &problem.objects[j];
    let Some(target) = problem.objects.get(c.target) else { return false };
    obj.global == GlobalKind::Edge
        && target.global == GlobalKind::Edge
        && !obj.constraints.iter().any(|o| o.target == c.target && is_side_relation(o.kind))
}

/// Whether a relation puts the later object on a side of its target (the relations the
/// look-ahead keeps room for).
fn is_side_relation(kind: RelationKind) -> bool {
    matches!(
        kind,
        RelationKind::InFrontOf
            | RelationKind::Behind
            | RelationKind::LeftOf
            | RelationKind::RightOf
            | RelationKind::SideOf
            | RelationKind::Around
    )
}

/// [`fast_score`] for many poses of one object with its targets fixed: each relation whose
/// target is placed, with its meaning, weight and the target's pose and footprint worked out
/// once. Gives [`fast_score`]'s value to the bit.
struct Scorer {
    /// Each relation with its meaning, weight, the target's pose and footprint, and, for a
    /// chair around a table, the table's seats.
    relations: Vec<(RelationKind, constraints::Meaning, f64, Pose, Rect, Vec<Pose>)>,
    /// Per relation, for a chair around a table, the smallest rectangle holding the centres
    /// of the table's seats ([`Scorer::far_bound`]).
    seat_boxes: Vec<Option<Rect>>,
    sat_value: f64,
}

impl Scorer {
    fn new(prep: &Prepared<'_>, k: usize, poses: &[Option<Pose>], sat_value: f64) -> Scorer {
        let obj = &prep.problem.objects[k];
        let (mut relations, mut seat_boxes) = (Vec::new(), Vec::new());
        for (ci, c) in obj.constraints.iter().enumerate() {
            if let (Some(Some(tp)), Some(t)) =
                (poses.get(c.target), prep.problem.objects.get(c.target))
            {
                let meaning = prep.meaning(k, ci);
                let tf = footprint(tp, t.size);
                // As the shared measure works them out, to the bit.
                let seats = match (&meaning.ring, c.kind) {
                    (Some(ring), RelationKind::Around) => {
                        constraints::seat_poses(tp, constraints::target_size_of(tp, &tf), ring)
                    }
                    _ => Vec::new(),
                };
                seat_boxes.push(seats.first().map(|first| {
                    seats.iter().fold(footprint(first, [0.0, 0.0]), |r, p| Rect {
                        min_x: r.min_x.min(p.x),
                        min_z: r.min_z.min(p.z),
                        max_x: r.max_x.max(p.x),
                        max_z: r.max_z.max(p.z),
                    })
                }));
                relations.push((c.kind, meaning, constraints::weight(c.kind), *tp, tf, seats));
            }
        }
        Scorer { relations, seat_boxes, sat_value }
    }

    /// An upper bound of [`Scorer::score`] for a candidate too far from its table's seats
    /// to stand at one (the seats' measure is the costly part of a chair's score), or `None`
    /// when it is near enough, or has no table: its score is worked out. Away from every seat
    /// a chair's `around` is not kept, and its graded score is at most what the distance to the
    /// seats' rectangle (no more than to the nearest seat) draws it by, with the most for
    /// facing the table; every other relation is worked out as [`Scorer::score`] does. Summed
    /// as the score is, term by term no less, so that no rounding puts the score above it.
    fn far_bound(&self, c: &Cand) -> Option<f64> {
        // A little farther than the seats' own tolerance, so that no rounding is left out.
        const SLACK: f64 = 1e-6;
        let reach = constraints::SEAT_TOLERANCE_M + constraints::EPS + SLACK;
        let centre = [c.pose.x, c.pose.z];
        let boxes = || self.seat_boxes.iter().flatten();
        if boxes().next().is_none() || boxes().any(|b| b.distance_to_point(centre) <= reach) {
            return None;
        }
        let mut s = 0.0;
        for ((kind, meaning, weight, tp, tf, seats), seat_box) in
            self.relations.iter().zip(&self.seat_boxes)
        {
            if let Some(seat_box) = seat_box {
                let d = seat_box.distance_to_point(centre);
                let toward = (1.0 - (d - SLACK).max(0.0) / 2.0).clamp(0.0, 1.0);
                s += weight * (0.3 * toward + 0.5) + 0.0;
            } else {
                let m = if seats.is_empty() {
                    constraints::relation_fit_with(*kind, meaning, &c.pose, &c.fp, tp, tf)
                } else {
                    constraints::around_seats(meaning, &c.pose, &c.fp, tf, seats)
                };
                s += weight * m.score + if m.satisfied { self.sat_value } else { 0.0 };
            }
        }
        Some(s)
    }

    /// Per relation, how near a candidate must stand to its target for the relation to hold
    /// ([`Reach`]).
    fn reaches(&self) -> Vec<Reach> {
        // Wider than the measures' own tolerances by more than any rounding of a gap.
        const SLACK: f64 = 1e-6;
        let (eps, seat) = (constraints::EPS, constraints::SEAT_TOLERANCE_M);
        self.relations
            .iter()
            .zip(&self.seat_boxes)
            .map(|((kind, meaning, _, _, tf, _), seat_box)| match (kind, seat_box) {
                (RelationKind::Around, Some(seats)) => Reach::Seats(*seats, seat + eps + SLACK),
                (RelationKind::Around, None) if meaning.ring.is_some() => Reach::Anywhere,
                (
                    RelationKind::Near
                    | RelationKind::InFrontOf
                    | RelationKind::Behind
                    | RelationKind::LeftOf
                    | RelationKind::RightOf
                    | RelationKind::SideOf
                    | RelationKind::Around
                    | RelationKind::FaceTo,
                    _,
                ) if meaning.max_gap.is_finite() => {
                    // A side relation also asks the centre to lie across from the target
                    // (within `EPS`), which the gap of the footprints measures with it.
                    Reach::Gap(*tf, meaning.max_gap + 3.0 * eps + SLACK)
                }
                _ => Reach::Anywhere,
            })
            .collect()
    }

    /// An upper bound of the score of every candidate that stands beyond the reach of every
    /// relation `reaches` bounds (none of those holds there; each score is at most 1), summed
    /// as [`Scorer::score`] sums, term by term no less.
    fn beyond_reach(&self, reaches: &[Reach]) -> f64 {
        let mut s = 0.0;
        for ((_, _, weight, ..), reach) in self.relations.iter().zip(reaches) {
            let sat = if matches!(reach, Reach::Anywhere) { self.sat_value } else { 0.0 };
            s += weight * 1.0 + sat;
        }
        s
    }

    fn score(&self, c: &Cand) -> f64 {
        let mut s = 0.0;
        for (kind, meaning, weight, tp, tf, seats) in &self.relations {
            let m = if seats.is_empty() {
                constraints::relation_fit_with(*kind, meaning, &c.pose, &c.fp, tp, tf)
            } else {
                constraints::around_seats(meaning, &c.pose, &c.fp, tf, seats)
            };
            s += weight * m.score + if m.satisfied { self.sat_value } else { 0.0 };
        }
        s
    }
}

/// How near to its target a candidate must stand for a relation to hold: its footprint within
/// a gap of the target's footprint, its centre within a distance of the rectangle holding a
/// table's seats, or anywhere (a relation of facing or alignment).
#[derive(Clone, Copy, Debug)]
enum Reach {
    Gap(Rect, f64),
    Seats(Rect, f64),
    Anywhere,
}

impl Reach {
    /// Whether candidate `c` stands within the reach (always for `Anywhere`).
    fn holds(&self, c: &Cand) -> bool {
        match self {
            Reach::Gap(tf, d) => c.fp.gap(tf) <= *d,
            Reach::Seats(seats, d) => seats.distance_to_point([c.pose.x, c.pose.z]) <= *d,
            Reach::Anywhere => true,
        }
    }
}

/// A side relation of a later object to an earlier one, looked ahead at.
#[derive(Clone, Copy, Debug)]
struct Dependent {
    /// The later object.
    object: usize,
    kind: RelationKind,
    /// The gaps (metres) its other relations to the same target allow: `near` caps it,
    /// `far` sets a floor.
    gaps: (f64, f64),
    /// One of the chairs around a table: it needs one of the table's seats, not any free
    /// zone beside it.
    ring: bool,
    /// How much further out than itself its zone reaches (metres): a chair drawn up to the
    /// front or back of a desk or table needs the way to it too, the agent's width (a row of
    /// desks leaves an aisle behind its chairs).
    beyond: f64,
    /// How far out beyond its square its zone reaches (metres): `beyond`, or further when the
    /// object heads a chain that stands beyond it the same way ([`chain_depth`]: a row of
    /// desks in front of the teacher's desk, with the rows behind it and their chairs).
    reach: f64,
}

/// The relations of object `j` (which stands `kind` of its target and faces it or the way it
/// faces, `facing`) that put a later object further out the same way: a desk facing the
/// teacher's desk has the next row `behind` it; a desk beside another, facing the same way,
/// has the next desk `side of` it. Empty when `j` is not turned by its target.
fn outward_kinds(kind: RelationKind, facing: Option<RelationKind>) -> &'static [RelationKind] {
    match (facing, kind) {
        (Some(RelationKind::FaceTo), RelationKind::InFrontOf | RelationKind::Behind) => {
            &[RelationKind::Behind]
        }
        (Some(RelationKind::FaceSameAs), RelationKind::InFrontOf) => &[RelationKind::InFrontOf],
        (Some(RelationKind::FaceSameAs), RelationKind::Behind) => &[RelationKind::Behind],
        (Some(RelationKind::FaceSameAs), RelationKind::SideOf) => &[RelationKind::SideOf],
        _ => &[],
    }
}

/// How much of the room, out from its target, a dependent and what stands beyond it the same
/// way need (metres): its own depth that way, the way to it (`beyond`), and for each later
/// object standing further out from it ([`outward_kinds`]), that object's least gap and its own
/// chain, one after the other (the rows of a classroom and their chairs stack). `memo` keeps
/// each dependent's answer by (object, relation).
fn chain_depth(
    problem: &super::RoomProblem,
    dependents: &[Vec<Dependent>],
    target: usize,
    d: &Dependent,
    memo: &mut FxHashMap<(usize, RelationKind), f64>,
) -> f64 {
    if let Some(&known) = memo.get(&(d.object, d.kind)) {
        return known;
    }
    let obj = &problem.objects[d.object];
    let facing = obj
        .constraints
        .iter()
        .find(|c| {
            c.target == target && matches!(c.kind, RelationKind::FaceTo | RelationKind::FaceSameAs)
        })
        .map(|c| c.kind);
    let outward = outward_kinds(d.kind, facing);
    // Its depth along the way out: its depth when its front or back faces that way, its width
    // when a side does, and its smaller side when it is not turned by its target.
    let own = match (facing, d.kind) {
        (Some(_), RelationKind::InFrontOf | RelationKind::Behind) => obj.size[1],
        (Some(RelationKind::FaceSameAs), RelationKind::SideOf) => obj.size[0],
        _ => obj.size[0].min(obj.size[1]),
    };
    let mut depth = own + d.beyond;
    for next in dependents[d.object].iter().filter(|n| !n.ring && outward.contains(&n.kind)) {
        depth += next.gaps.0 + chain_depth(problem, dependents, d.object, next, memo);
    }
    memo.insert((d.object, d.kind), depth);
    depth
}

/// A side relation of a later object to a placed one that can still be kept: its free zones
/// and, among them, those right next to the target.
struct Promise {
    zones: Vec<Rect>,
    next_to: Vec<Rect>,
}

/// The seats of a placed table that chairs still to come need: the free seat zones and how
/// many chairs are still to come.
struct SeatPromise {
    seats: Vec<Rect>,
    need: usize,
}

impl SeatPromise {
    /// How many of the chairs to come lose their seat if `fp` is placed.
    fn broken_by(&self, fp: &Rect) -> usize {
        let covered = self.seats.iter().filter(|z| z.overlaps(fp)).count();
        let left = self.seats.len() - covered;
        self.need.saturating_sub(left) - self.need.saturating_sub(self.seats.len())
    }
}

/// How far behind a chair at a table's seat the seat's zone reaches (metres): the room to pull
/// the chair out and sit down, kept free of other furniture and of other tables' seats.
const SEAT_BACK_M: f64 = 0.4;

/// The zone a chair of `ring` needs at a seat pose: its footprint and [`SEAT_BACK_M`] behind.
fn seat_zone(pose: &Pose, ring: &constraints::SeatRing) -> Rect {
    let fp = footprint(pose, ring.seat);
    let [fx, fz] = pose.rot.front();
    // The chair faces the table; its back is the other way.
    Rect {
        min_x: fp.min_x - if fx > 0.5 { SEAT_BACK_M } else { 0.0 },
        max_x: fp.max_x + if fx < -0.5 { SEAT_BACK_M } else { 0.0 },
        min_z: fp.min_z - if fz > 0.5 { SEAT_BACK_M } else { 0.0 },
        max_z: fp.max_z + if fz < -0.5 { SEAT_BACK_M } else { 0.0 },
    }
}

/// How far apart (metres) the chairs of two tables stay, every way: half of it round each
/// chair. A person passes between them, and two tables' chairs back to back leave room to
/// pull them out.
const SEATS_APART_M: f64 = 0.4;

/// The zone round a seat of `ring` at `pose` that the seats of other tables keep out of: its
/// footprint grown by half of [`SEATS_APART_M`].
fn seat_apart_zone(pose: &Pose, ring: &constraints::SeatRing) -> Rect {
    footprint(pose, ring.seat).grow(SEATS_APART_M / 2.0)
}

/// The static candidates of one object with what the search asks of them at every node.
struct StaticSet {
    /// Per position, the candidate's place in the grid: the grid in the object's seeded order.
    order: Vec<u32>,
    /// Per candidate, what [`Search::room_left_for_dependents`] would count with nothing
    /// placed: an upper bound of it at every node.
    room_static: Vec<(u8, u8)>,
    /// The most of each part of `room_static` over the candidates.
    room_max: (u8, u8),
    /// The grid the candidates were shuffled from, shared by the objects alike.
    grid: Rc<SharedGrid>,
    /// Per place in the grid, the candidate's position in `order`.
    pos_of: Vec<u32>,
}

/// A static grid ([`static_grid`]) with what the objects alike share: the sides of each
/// candidate touching a wall, and the candidates by each side of their footprints.
struct SharedGrid {
    cands: Vec<Cand>,
    fails: BTreeMap<HardRule, usize>,
    wall_touch: Vec<u8>,
    /// The places in the grid by each side of their footprints (`min_x`, `max_x`, `min_z`,
    /// `max_z`), sorted by that coordinate: the candidates that can touch a placed footprint
    /// are looked up here ([`SharedGrid::touching`]).
    edges: [Vec<(f64, u32)>; 4],
    /// The places in the grid by their centres: the candidates near a placed target are
    /// looked up here ([`Search::target_context`]).
    centres: CentreIndex,
}

impl SharedGrid {
    fn new(prep: &Prepared<'_>, k: usize) -> SharedGrid {
        let (cands, fails) = static_grid(prep, k);
        let wall_touch =
            cands.iter().map(|c| touching(&c.fp, |m| !prep.room.contains_rect(m))).collect();
        let edge = |side: fn(&Rect) -> f64| {
            // Sorted as `f64::total_cmp` and then by place, on integer keys: the coordinate's
            // bits turned so that they order as `total_cmp` does, above the place.
            let mut keys: Vec<u128> = cands
                .iter()
                .zip(0u32..)
                .map(|(c, i)| {
                    let bits = side(&c.fp).to_bits();
                    let ordered = if bits >> 63 == 1 { !bits } else { bits | (1 << 63) };
                    (u128::from(ordered) << 32) | u128::from(i)
                })
                .collect();
            keys.sort_unstable();
            let place = |key: u128| (key & u128::from(u32::MAX)) as u32;
            keys.iter().map(|&key| (side(&cands[place(key) as usize].fp), place(key))).collect()
        };
        let edges = [edge(|r| r.min_x), edge(|r| r.max_x), edge(|r| r.min_z), edge(|r| r.max_z)];
        let fps: Vec<Rect> = cands.iter().map(|c| c.fp).collect();
        let centres = CentreIndex::new(&prep.room.bounds, &fps);
        SharedGrid { cands, fails, wall_touch, edges, centres }
    }

    /// The places in the grid (each once) of the candidates that come within [`CONTACT_M`] of
    /// the placed footprint `p` without overlapping it, each with the sides it comes near `p`
    /// by (bits: −x, +x, −z, +z): every candidate that it can add a touching side to, and every
    /// side it can add (a candidate at `p`'s corner comes near but touches by none). A side can
    /// only touch a footprint from just outside one of its edges, so each edge is looked up in
    /// the sorted sides of the candidates.
    fn touching(&self, p: &Rect) -> Vec<(u32, u8)> {
        // A little wider than the rules below, so that no rounding leaves a candidate out;
        // the test itself is the one the walk makes.
        const SLACK: f64 = 1e-9;
        let (eps, c) = (constraints::EPS, CONTACT_M);
        let mut out = Vec::new();
        {
            let grown = p.grow(c);
            // (side of the candidate, from, to): beyond +x, short of −x, beyond +z, short of −z.
            let shells = [
                (0, p.max_x - eps, p.max_x + c),
                (1, p.min_x - c, p.min_x + eps),
                (2, p.max_z - eps, p.max_z + c),
                (3, p.min_z - c, p.min_z + eps),
            ];
            for (side, from, to) in shells {
                let edge = &self.edges[side];
                let a = edge.partition_point(|e| e.0 < from - SLACK);
                let b = edge.partition_point(|e| e.0 <= to + SLACK);
                for &(_, g) in &edge[a..b.max(a)] {
                    let fp = &self.cands[g as usize].fp;
                    if fp.overlaps(&grown) && !fp.overlaps(p) {
                        out.push((g, 1u8 << side));
                    }
                }
            }
        }
        // Each place once, with every side it touches `p` by.
        out.sort_unstable();
        out.dedup_by(|later, first| {
            let same = later.0 == first.0;
            if same {
                first.1 |= later.1;
            }
            same
        });
        out
    }
}

/// What the search knows of an object once the poses of its relations' targets are fixed:
/// the candidates derived from them, the score of every candidate (static ones first), and an
/// upper bound of every candidate's ordering key, with the candidates sorted by it (best
/// first). An object is met again and again with the same targets (the search branches on
/// other objects), so this is worked out once per set of target poses.
struct TargetContext {
    derived: Vec<Cand>,
    scorer: Scorer,
    /// Whether a chair's static candidates far from its table's seats are bounded without
    /// their scores ([`Scorer::far_bound`]).
    lazy: bool,
    /// The candidates that do not overlap a placed target in the order of their bounds (best
    /// first), put in order lazily: a node rarely walks far down the list.
    walk: RefCell<Walk>,
    /// The candidates that overlap a placed target: blocked at every node of this context.
    on_targets: Vec<u32>,
    /// The static candidates of `on_targets`, one bit each.
    on_target_bits: Vec<u64>,
}

/// One step of a walk: a candidate's bound, footprint and position (statics then derived),
/// side by side so that a walk reads memory in order.
#[derive(Clone, Copy)]
struct Step {
    bound: f64,
    cand: Cand,
    score: f64,
    index: u32,
}

/// A walk put in order so far, and the candidates not yet in it.
struct Walk {
    steps: Vec<Step>,
    rest: Vec<u32>,
    /// Per candidate, its score; NaN for one bounded without it ([`Scorer::far_bound`]) or not
    /// worked out yet (waiting in a tier).
    scores: Vec<f64>,
    /// Per candidate, an upper bound of its ordering key (worked out for those in `rest`).
    bounds: Vec<f64>,
    /// Per candidate, the tier it waits in, plus one (0: not waiting).
    waiting: Vec<u8>,
    /// The candidates beyond the reach ([`Reach`]) of some of the object's relations that have
    /// one, by how many of those relations they are within reach of: every other such
    /// relation is broken there, so each tier has one bound for all its candidates, and none
    /// of them is worked out until the walk comes down to it. Best (last) first.
    tiers: Vec<Tier>,
    /// How many of `rest` have a bound above the best tier waiting, once counted: the walk
    /// takes them best first, so it counts them again only when a tier joins.
    above: Option<usize>,
}

/// How many candidates a walk puts in order at first; each further piece doubles it.
const FIRST_STEPS: usize = 64;

/// The candidates waiting for the walk to come down to a bound.
#[derive(Clone, Copy, Debug)]
struct Tier {
    /// An upper bound of the ordering key of each of them, every side touching something.
    bound: f64,
    /// Whether they have joined the walk.
    joined: bool,
}

impl TargetContext {
    /// The `n`th step of object `k`'s walk, putting more of it in order when needed.
    fn step(&self, n: usize, search: &Search<'_, '_>, k: usize) -> Option<Step> {
        let mut walk = self.walk.borrow_mut();
        if n >= walk.steps.len() {
            self.extend(&mut walk, search, k);
        }
        walk.steps.get(n).copied()
    }

    /// The best tier still waiting, if any.
    fn next_tier(walk: &Walk) -> Option<usize> {
        walk.tiers.iter().rposition(|t| !t.joined)
    }

    /// How many candidates of `rest` come before the best tier waiting (all of them when none
    /// waits).
    fn above_tier(walk: &mut Walk) -> usize {
        let Some(t) = TargetContext::next_tier(walk) else { return walk.rest.len() };
        let (bound, bounds, rest) = (walk.tiers[t].bound, &walk.bounds, &walk.rest);
        *walk.above.get_or_insert_with(|| {
            rest.iter().filter(|&&i| bounds[i as usize].total_cmp(&bound).is_gt()).count()
        })
    }

    /// When the `n`th step of the walk is a tier's to give (every step before it taken, and
    /// nothing left above the tier), the tier's bound: a walk that needs nothing that high
    /// stops without working its candidates out.
    fn tier_next(&self, n: usize) -> Option<f64> {
        let mut walk = self.walk.borrow_mut();
        if n < walk.steps.len() || TargetContext::above_tier(&mut walk) > 0 {
            return None;
        }
        TargetContext::next_tier(&walk).map(|t| walk.tiers[t].bound)
    }

    /// Puts the next piece of the walk in order. A tier waiting joins it first when nothing
    /// left in it has a bound above the tier's.
    fn extend(&self, walk: &mut Walk, search: &Search<'_, '_>, k: usize) {
        let set = &search.statics[k];
        let n_static = set.len();
        let cand_of =
            |i: usize| if i < n_static { set.cand(i) } else { self.derived[i - n_static] };
        loop {
            let above = TargetContext::above_tier(walk);
            if above == 0 {
                let Some(t) = TargetContext::next_tier(walk) else { return };
                self.join(walk, t, search, k);
                walk.above = None;
                continue;
            }
            // The best `take` of `rest` all come before the tier: counted off as they leave.
            if let Some(left) = &mut walk.above {
                *left -= above.min(walk.steps.len().max(FIRST_STEPS));
            }
            let Walk { steps, rest, scores, bounds, .. } = &mut *walk;
            let bounds = &*bounds;
            let better = |a: &u32, b: &u32| {
                bounds[*b as usize].total_cmp(&bounds[*a as usize]).then(a.cmp(b))
            };
            let take = steps.len().max(FIRST_STEPS).min(above);
            if take < rest.len() {
                rest.select_nth_unstable_by(take - 1, better);
            }
            let mut piece: Vec<u32> = rest.drain(..take).collect();
            piece.sort_unstable_by(better);
            steps.extend(piece.into_iter().map(|i| {
                let at = i as usize;
                let cand = cand_of(at);
                let score = if scores[at].is_nan() { self.scorer.score(&cand) } else { scores[at] };
                Step { bound: bounds[at], cand, score, index: i }
            }));
            return;
        }
    }

    /// Works out tier `t`'s candidates as the others were, and puts them with the rest.
    fn join(&self, walk: &mut Walk, t: usize, search: &Search<'_, '_>, k: usize) {
        let set = &search.statics[k];
        let n_static = set.len();
        walk.tiers[t].joined = true;
        let mark = u8::try_from(t + 1).unwrap_or(u8::MAX);
        for at in 0..walk.waiting.len() {
            if walk.waiting[at] != mark {
                continue;
            }
            walk.waiting[at] = 0;
            let (score, bound) = if at < n_static {
                static_bound(&self.scorer, self.lazy, search.sat_value, set, at)
            } else {
                search.derived_bound(&self.scorer, k, &self.derived[at - n_static])
            };
            walk.scores[at] = score;
            walk.bounds[at] = bound;
            walk.rest.push(u32::try_from(at).unwrap_or(u32::MAX));
        }
    }

    /// Static candidate `i`'s step in a node's walk of the candidates touching placed
    /// footprints: bounded with every side that touches a wall or comes near a placed footprint
    /// (`near`, bits: −x, +x, −z, +z) counted as touching, by its tier's bound for one waiting
    /// (its score worked out only if the walk comes to it, NaN until then).
    fn touch_step(&self, i: u32, set: &StaticSet, sat_value: f64, near: u8) -> Step {
        let at = i as usize;
        let cand = set.cand(at);
        let walk = self.walk.borrow();
        if let Some(t) = walk.waiting.get(at).and_then(|&w| w.checked_sub(1)) {
            let bound = walk.tiers[t as usize].bound;
            return Step { bound, cand, score: f64::NAN, index: i };
        }
        let score =
            if walk.scores[at].is_nan() { self.scorer.score(&cand) } else { walk.scores[at] };
        let (kept, close) = set.room_static.get(at).copied().unwrap_or((u8::MAX, u8::MAX));
        let sides = f64::from((set.wall_touch(at) | near).count_ones());
        let bound = ordering_key(score, sat_value, f64::from(kept), f64::from(close), sides);
        Step { bound, cand, score, index: i }
    }
}

/// Static candidate `i`'s score (NaN when bounded without it) and the upper bound of its
/// ordering key with every relation of a later object still kept and the sides that touch a
/// wall (those that touch a placed footprint are the node's to add, see `NodeWalk::touch`).
fn static_bound(
    scorer: &Scorer,
    lazy: bool,
    sat_value: f64,
    set: &StaticSet,
    i: usize,
) -> (f64, f64) {
    let g = set.order[i] as usize;
    // A chair's static candidate far from its table's seats is bounded without its score,
    // worked out only if the walk comes to it. With no relation placed the score is 0, and
    // the candidate is not read at all.
    let (s, score) = if scorer.relations.is_empty() {
        (0.0, 0.0)
    } else {
        let c = &set.grid.cands[g];
        match lazy.then(|| scorer.far_bound(c)).flatten() {
            Some(bound) => (bound, f64::NAN),
            None => {
                let s = scorer.score(c);
                (s, s)
            }
        }
    };
    let (kept, close) = set.room_static.get(i).copied().unwrap_or((u8::MAX, u8::MAX));
    let sides = set.grid.wall_touch[g].count_ones();
    (score, ordering_key(s, sat_value, f64::from(kept), f64::from(close), f64::from(sides)))
}

#[cfg(test)]
thread_local! {
    /// Tests set this to work out every candidate of a target context, without tiers.
    static WHOLE_CONTEXTS: std::cell::Cell<bool> = const { std::cell::Cell::new(false) };
}

/// Whether target contexts work out every candidate (only tests ask for it, to compare).
fn whole_contexts() -> bool {
    #[cfg(test)]
    {
        WHOLE_CONTEXTS.with(std::cell::Cell::get)
    }
    #[cfg(not(test))]
    {
        false
    }
}

/// The most target contexts kept; the cache is emptied when it is full (a room with many
/// objects and a large budget would otherwise keep one per node).
const MAX_TARGET_CONTEXTS: usize = 256;

impl StaticSet {
    /// Object `k`'s candidates: the shared grid in the object's seeded order (`plan_index`, its
    /// place in the plan), with no room for later objects worked out yet.
    fn new(grid: Rc<SharedGrid>, plan_index: usize, seed: u64) -> StaticSet {
        let mut order: Vec<u32> =
            (0..u32::try_from(grid.cands.len()).unwrap_or(u32::MAX)).collect();
        shuffle_static(&mut order, plan_index, seed);
        let mut pos_of = vec![0; order.len()];
        for (at, &g) in (0u32..).zip(&order) {
            pos_of[g as usize] = at;
        }
        StaticSet { order, room_static: Vec::new(), room_max: (0, 0), grid, pos_of }
    }

    /// How many static candidates the object has.
    fn len(&self) -> usize {
        self.order.len()
    }

    /// The candidate at position `i` (read from the shared grid: each object keeps only its
    /// order, not a copy of the grid).
    fn cand(&self, i: usize) -> Cand {
        self.grid.cands[self.order[i] as usize]
    }

    /// The sides (bits: −x, +x, −z, +z) of the candidate at position `i` that touch a wall.
    fn wall_touch(&self, i: usize) -> u8 {
        self.grid.wall_touch[self.order[i] as usize]
    }
}

/// A candidate's ordering key (see [`Search::walk_to`]) from its score, the side relations of
/// later objects it leaves room for (`kept`, and `close` of them right next to it) and its
/// sides touching something; with the most of each, an upper bound of the key. Keys and bounds
/// are summed the same way, so that a bound equal to a key is equal to the bit.
fn ordering_key(score: f64, sat_value: f64, kept: f64, close: f64, sides: f64) -> f64 {
    score + sat_value * kept + ROOM_NEXT_TO_BONUS * close + CONTACT_BONUS * sides
}

/// A footprint moved by [`CONTACT_M`] towards −x, +x, −z and +z.
fn nudged(fp: &Rect) -> [Rect; 4] {
    let d = CONTACT_M;
    [
        Rect { min_x: fp.min_x - d, max_x: fp.max_x - d, ..*fp },
        Rect { min_x: fp.min_x + d, max_x: fp.max_x + d, ..*fp },
        Rect { min_z: fp.min_z - d, max_z: fp.max_z - d, ..*fp },
        Rect { min_z: fp.min_z + d, max_z: fp.max_z + d, ..*fp },
    ]
}

/// The sides of a footprint (bits: −x, +x, −z, +z) for which `blocked` holds of the footprint
/// moved by [`CONTACT_M`] that way: with "leaves the room", the sides touching a wall; with
/// "overlaps a footprint", the sides touching it.
fn touching(fp: &Rect, blocked: impl Fn(&Rect) -> bool) -> u8 {
    nudged(fp).iter().enumerate().filter(|(_, m)| blocked(m)).fold(0, |acc, (i, _)| acc | (1 << i))
}

/// The use-clearances around a node: whether the object being placed relates to each placed
/// footprint (those it relates to, and that it lets into its use-clearance, are not in its
/// way) and the zones placed objects keep free from it (all of a list, or one of a bed's open
/// sides). The placed footprints themselves are the node's grid, passed beside it.
struct Clearances {
    /// Per placed footprint, in the grid's order.
    related: Vec<bool>,
    /// The zones that must stay wholly free of the object (the `all` lists), bucketed.
    keep_free: ZoneGrid,
    /// The lists of zones of which one must stay free (a bed's open sides).
    one_free: Vec<Vec<Rect>>,
    /// Per placed footprint, in the grid's order: a chair of another table, which the way
    /// behind the object (a chair drawn up to its table) keeps out.
    back: Vec<bool>,
    /// The lines of sight of the placed seating groups (screen and seat centres) that the
    /// object, taller than [`constraints::SIGHT_LINE_M`], keeps off.
    sight: Vec<([f64; 2], [f64; 2])>,
}

/// Why an object has no pose: the rule and the words.
type Reason = (HardRule, String);

/// Search state along one path.
#[derive(Clone)]
struct State {
    poses: Vec<Option<Pose>>,
    fps: Vec<Rect>,
    /// The footprints placed with [`Search::place`], bucketed, kept as objects are placed and
    /// taken back.
    grid: FootprintGrid,
    /// The object of each footprint of `grid`, in its order.
    objs: Vec<usize>,
    /// The reachability grid's occupancy by `fps`.
    occ: Occupancy,
    value: f64,
    fails: Vec<Option<(HardRule, String)>>,
    by: Vec<&'static str>,
}

struct Search<'p, 'a> {
    prep: &'p Prepared<'a>,
    placed_value: f64,
    sat_value: f64,
    statics: Vec<StaticSet>,
    static_fails: Vec<BTreeMap<HardRule, usize>>,
    remaining_max: Vec<f64>,
    /// Per object, the later objects' side relations (`in front of`, `behind`, …) that target
    /// it, with the gaps the later object's other relations to it allow.
    dependents: Vec<Vec<Dependent>>,
    /// Per object, the ring of chairs around it when it is a table with chairs `around` it.
    rings: Vec<Option<constraints::SeatRing>>,
    /// Per table with a ring, its seats' offsets at each rotation (in [`Rot::ALL`]'s order).
    seat_offsets: Vec<Option<[Vec<constraints::SeatOffset>; 4]>>,
    budget: u64,
    seed: u64,
    nodes: u64,
    best: Option<State>,
    /// The best complete layout found so far under the documented order (objects placed, then
    /// constraints kept as the report measures them, then score), with that measure: what the
    /// search returns. Every layout the search improves on is measured, so a larger budget,
    /// which walks the same nodes first, never returns a worse layout.
    kept: Option<(State, Rank)>,
    /// The first object without a pin: where each round of discrepancy tries other poses
    /// first (see [`Search::visit`]).
    anchor: Option<usize>,
    /// Per object, whether a round of discrepancy may try its other poses: the objects that
    /// can change what the best layout so far loses ([`Search::conflicts`]). `None`: every
    /// object (no layout yet, or one that leaves an object out).
    conflict: Option<Vec<bool>>,
    /// The nodes walked when `kept` was found.
    found_at: u64,
    pin_breaks: Vec<(usize, HardRule)>,
    /// Per object, its poses anywhere in the room ([`anywhere_candidates`]), once asked for.
    anywhere: RefCell<Vec<Option<Rc<Vec<Cand>>>>>,
    /// Per static grid (its address) and placed footprint (its bits), the places of the grid's
    /// candidates it touches.
    touch_answers: RefCell<FxHashMap<TouchKey, Touching>>,
    /// Per object against the walls with room to keep beside it, and placed footprint (its
    /// bits), the object's wall poses flush beside that footprint ([`Search::flush_beside`]).
    flush_answers: RefCell<FxHashMap<TouchKey, Rc<[Cand]>>>,
    /// Target contexts by object and the bits of its targets' poses.
    contexts: RefCell<FxHashMap<ContextKey, Rc<TargetContext>>>,
    /// The candidates derived from one target ([`derived_for_target`]) by the object, the
    /// target and the bits of its pose: a target context is made again for every new pose of
    /// any of its targets, most of which stand where they stood before.
    derived_pieces: RefCell<FxHashMap<DerivedKey, Rc<[Cand]>>>,
    /// Reachability answers by the bits of the footprints (placed, then the candidate).
    reach_answers: FxHashMap<Vec<u64>, bool>,
    /// The candidates of nodes met, by the object and the bits of every object's pose.
    node_answers: FxHashMap<Vec<u64>, Rc<NodeCandidates>>,
    /// Per depth, the flood of the footprints placed on the path to the node being expanded;
    /// a candidate is judged on its node's flood, which most often gives the flood with the
    /// candidate placed without a flood of its own (see [`constraints::ReachGrid::extend`]).
    reach_bases: Vec<Option<ReachBase>>,
}

/// The candidates of an object at a node, best first.
enum NodeCandidates {
    /// Known whole: poses anywhere for an `edge` object with no wall pose left, or none, with
    /// why.
    Whole(Vec<(Cand, f64)>, Option<Reason>),
    /// Put in order only as far as the search has asked ([`Search::walk_to`]): a node is most
    /// often left after its first candidate or two, and the best `m` of a walk are the first
    /// `m` of a longer one.
    Walk(RefCell<NodeWalk>),
}

/// How far the walk of a node's candidates has come.
struct NodeWalk {
    /// The candidates met so far that keep every rule (at most [`REACH_TRIES`]), best key
    /// first: (ordering key, position among statics then derived, score, candidate).
    kept: Vec<(f64, usize, f64, Cand)>,
    /// The next step of the target context's walk to meet.
    next: usize,
    /// The static candidates that a placed footprint comes within [`CONTACT_M`] of
    /// ([`SharedGrid::touching`]), one bit each: the context's walk bounds a static candidate
    /// with the sides that touch a wall only, so these are met in a walk of their own, `touch`,
    /// bounded with every side touching something.
    touch_bits: Vec<u64>,
    /// The steps of the touch set not met yet, the next (best bound, then first position) on
    /// top: a node most often meets only its first few, so they are not sorted whole.
    touch: BinaryHeap<TouchFirst>,
    /// Whether every step has been met.
    done: bool,
    /// For why nothing is left: the candidates blocked, by the placed footprint they overlap
    /// first, and those standing in a use-clearance.
    blockers: BTreeMap<usize, usize>,
    cleared_out: usize,
    /// What the walk holds its candidates to at this node, worked out the first time the walk
    /// meets a candidate and kept while the search is at the node: its walk is taken further
    /// again and again (once per candidate the search asks for), and these depend on the node
    /// alone.
    rules: Option<Rc<NodeRules>>,
}

/// What the candidates of an object are held to and ordered by at one node: the
/// use-clearances, the side relations and the seats that later objects still need, and the
/// zones round the seats of the tables placed (for a table's own chairs).
struct NodeRules {
    clearances: Clearances,
    promises: Vec<Promise>,
    seat_promises: Vec<SeatPromise>,
    reserved: Vec<Rect>,
    /// The zones placed objects keep free from this object's chairs (a sofa's legroom keeps a
    /// dining chair out, though it lets a table in): a seat there is no seat for them. `None`
    /// for an object without a ring of chairs.
    seat_keep_free: Option<ZoneGrid>,
}

/// A step of a node's touch walk, ordered so that the one met first is the greatest: the
/// higher bound, then the earlier position (the order the walk meets steps in).
struct TouchFirst(Step);

impl Ord for TouchFirst {
    fn cmp(&self, other: &Self) -> std::cmp::Ordering {
        self.0.bound.total_cmp(&other.0.bound).then(other.0.index.cmp(&self.0.index))
    }
}

impl PartialOrd for TouchFirst {
    fn partial_cmp(&self, other: &Self) -> Option<std::cmp::Ordering> {
        Some(self.cmp(other))
    }
}

impl PartialEq for TouchFirst {
    fn eq(&self, other: &Self) -> bool {
        self.cmp(other).is_eq()
    }
}

impl Eq for TouchFirst {}

/// The bits of a footprint, as the stores of answers key it.
fn rect_bits(r: &Rect) -> [u64; 4] {
    [r.min_x, r.min_z, r.max_x, r.max_z].map(f64::to_bits)
}

/// The answer `store` keeps under `key`, or `make`'s, then kept (the store emptied first when it
/// holds `most`): the search meets the same questions again and again.
fn kept_answer<K: std::hash::Hash + Eq, V: Clone>(
    store: &RefCell<FxHashMap<K, V>>,
    key: K,
    most: usize,
    make: impl FnOnce() -> V,
) -> V {
    if let Some(found) = store.borrow().get(&key) {
        return found.clone();
    }
    let found = make();
    let mut answers = store.borrow_mut();
    if answers.len() >= most {
        answers.clear();
    }
    answers.insert(key, found.clone());
    found
}

/// An answer of [`Search::touching`]: places in a grid, each with the sides (bits) it comes near
/// the footprint by.
type Touching = Rc<[(u32, u8)]>;

/// A key of [`Search::touching`] (a grid's address) or [`Search::flush_beside`] (an object),
/// and the bits of a placed footprint.
type TouchKey = (usize, [u64; 4]);

/// The most answers of [`Search::touching`] kept; the store is emptied when it is full.
const MAX_TOUCH_ANSWERS: usize = 1 << 16;

/// The most nodes whose candidates are kept; the store is emptied when it is full.
const MAX_NODE_ANSWERS: usize = 4096;

/// A target context's key: the object and the bits of its targets' poses.
type ContextKey = (usize, Vec<u64>);

/// A key of [`Search::derived_pieces`]: the object, the target and the bits of its pose.
type DerivedKey = (usize, usize, [u64; 3]);

/// The most pieces of derived candidates kept; the store is emptied when it is full.
const MAX_DERIVED_PIECES: usize = 4096;

/// The most reachability answers kept; the store is emptied when it is full.
const MAX_REACH_ANSWERS: usize = 8192;

impl Search<'_, '_> {
    fn better(&self, value: f64) -> bool {
        self.best.as_ref().is_none_or(|b| value > b.value + 1e-9)
    }

    /// The objects whose other poses can change what the layout `st` loses: each object that
    /// breaks one of its relations, the objects it relates to and those related to it, and
    /// every object standing where it or its targets could move to (their footprints grown by
    /// the relation's reach, or by [`CONFLICT_REACH_M`] for a relation of facing or alignment).
    /// `None` (every object) when an object is left out: it may stand anywhere.
    fn conflicts(&self, st: &State) -> Option<Vec<bool>> {
        let problem = self.prep.problem;
        let n = problem.objects.len();
        let mut conflict = vec![false; n];
        let mut regions = Vec::new();
        for (j, obj) in problem.objects.iter().enumerate() {
            let pose = st.poses[j]?;
            let s = fast_score(self.prep, j, &pose, &st.poses, self.sat_value);
            let kept = (s / self.sat_value + 1e-9).floor();
            if kept >= obj.constraints.len() as f64 {
                continue;
            }
            conflict[j] = true;
            let own = obj.size[0].max(obj.size[1]);
            regions.push(footprint(&pose, obj.size).grow(CONFLICT_REACH_M));
            for (ci, c) in obj.constraints.iter().enumerate() {
                let Some(t) = problem.objects.get(c.target) else { continue };
                conflict[c.target] = true;
                let Some(tp) = st.poses[c.target] else { continue };
                let gap = self.prep.meaning(j, ci).max_gap;
                let reach = if gap.is_finite() { gap + own } else { CONFLICT_REACH_M };
                regions.push(footprint(&tp, t.size).grow(reach.max(CONFLICT_REACH_M)));
            }
            for (i, other) in problem.objects.iter().enumerate() {
                if other.constraints.iter().any(|c| c.target == j) {
                    conflict[i] = true;
                }
            }
        }
        for (i, obj) in problem.objects.iter().enumerate() {
            if let Some(p) = st.poses[i] {
                let fp = footprint(&p, obj.size);
                conflict[i] |= regions.iter().any(|r| r.overlaps(&fp));
            }
        }
        Some(conflict)
    }

    fn out_of_budget(&self) -> bool {
        // A cancelled batch job (`crate::cancel`) stops here; its layout is thrown away.
        (self.best.is_some() && self.nodes >= self.budget) || crate::cancel::requested()
    }

    fn visit(&mut self, k: usize, disc: usize, st: &mut State) {
        let n = self.prep.problem.objects.len();
        if k == n {
            if self.better(st.value) {
                self.conflict = self.conflicts(st);
                self.best = Some(st.clone());
                let mut finished = st.clone();
                self.finish(&mut finished);
                let rank = rank(self.prep, &finished);
                if self.kept.as_ref().is_none_or(|(_, r)| rank.beats(r)) {
                    self.kept = Some((finished, rank));
                    self.found_at = self.nodes;
                }
            }
            return;
        }
        if self.out_of_budget() {
            return;
        }
        if let Some(b) = &self.best {
            if st.value + self.remaining_max[k] <= b.value + 1e-9 {
                return;
            }
        }
        self.nodes += 1;
        let obj = &self.prep.problem.objects[k];
        if let Some(pin) = obj.pin {
            let fp = footprint(&pin, obj.size);
            // Every hard rule, as a candidate is held to: the static ones, no overlap, the
            // use-clearances and reachability (a pinned lamp that cuts a bookcase off).
            // Every rule it breaks is listed (the first fixed rule of the room, then each of
            // the others), not only the first.
            let cand = Cand { pose: pin, fp };
            let ctx = self.clearance_context(k, st);
            let cleared = self.clearances_kept(k, &cand, &st.grid, &ctx);
            let rules = [
                self.prep.static_rule(k, &pin),
                st.fps.iter().any(|f| f.overlaps(&fp)).then_some(HardRule::NoOverlap),
                (!cleared).then_some(HardRule::UseClearance),
                self.boxed(&cand, st).then_some(HardRule::Reachable),
            ];
            if !self.pin_breaks.iter().any(|(i, _)| *i == k) {
                self.pin_breaks.extend(rules.into_iter().flatten().map(|rule| (k, rule)));
            }
            let s = fast_score(self.prep, k, &pin, &st.poses, self.sat_value);
            self.place(k, pin, fp, self.placed_value + s, "pin", st);
            self.visit(k + 1, disc, st);
            self.unplace(k, self.placed_value + s, st);
            return;
        }
        let found = self.node_candidates(k, st);
        if let NodeCandidates::Whole(cands, reason) = &*found {
            if cands.is_empty() {
                st.fails[k].clone_from(reason);
                self.visit(k + 1, disc, st);
                st.fails[k] = None;
                return;
            }
        }
        // A discrepancy is spent only where it can change what the best layout loses; any
        // other object takes its best pose and passes the discrepancy on.
        let disc_here = if self.conflict.as_ref().is_none_or(|c| c[k]) { disc } else { 0 };
        let mut tried = 0usize;
        let mut pruned = false;
        let mut reach_checks = 0;
        // At the anchor (the first object the search chooses a pose for: the first of the
        // largest group, see `placement_order`) a round spends its discrepancy here first: its
        // best pose, with the discrepancy left for the objects after it, is walked last. The
        // same paths, in another order.
        let anchor_first = Some(k) == self.anchor && disc_here > 0;
        let mut best_last: Option<(Cand, f64)> = None;
        while tried <= disc_here && reach_checks < REACH_TRIES {
            let Some((c, s)) = self.node_candidate(k, st, &found, reach_checks) else { break };
            let (c, s) = (&c, &s);
            reach_checks += 1;
            if let Some(b) = &self.best {
                if st.value + self.placed_value + s + self.remaining_max[k + 1] <= b.value + 1e-9 {
                    pruned = true;
                    continue;
                }
            }
            if self.boxed(c, st) {
                continue;
            }
            if anchor_first && tried == 0 {
                best_last = Some((*c, *s));
                tried += 1;
                continue;
            }
            let v = self.placed_value + s;
            self.place(k, c.pose, c.fp, v, "dfs", st);
            self.visit(k + 1, disc - tried, st);
            self.unplace(k, v, st);
            tried += 1;
            if self.out_of_budget() {
                break;
            }
        }
        if let Some((c, s)) = best_last {
            if !self.out_of_budget() {
                let v = self.placed_value + s;
                self.place(k, c.pose, c.fp, v, "dfs", st);
                self.visit(k + 1, disc, st);
                self.unplace(k, v, st);
            }
        }
        // The node is left: its walk keeps how far it has come, but not its rules (worked out
        // again if a later round takes the walk further), so that what is kept grows with
        // the path and not with every node met.
        if let NodeCandidates::Walk(walk) = &*found {
            walk.borrow_mut().rules = None;
        }
        if tried == 0 && !pruned {
            st.fails[k] = Some((
                HardRule::Reachable,
                "every pose left would leave a placed object (or itself) unreachable from the door"
                    .to_string(),
            ));
            self.visit(k + 1, disc, st);
            st.fails[k] = None;
        }
    }

    /// The places in object `k`'s static grid of the candidates that the placed footprint
    /// `fp` can add a touching side to ([`SharedGrid::touching`]): worked out once per grid
    /// and footprint, as the search meets the same footprints placed again and again, and the
    /// objects alike (the chairs of a set) share their grid.
    fn touching(&self, k: usize, fp: &Rect) -> Touching {
        let grid = &self.statics[k].grid;
        // The grid's address tells it from the others while the search holds them all.
        let key = (Rc::as_ptr(grid) as usize, rect_bits(fp));
        kept_answer(&self.touch_answers, key, MAX_TOUCH_ANSWERS, || grid.touching(fp).into())
    }

    /// Whether object `k` looks for wall poses flush beside placed footprints: an object
    /// against the walls that a later one wants to stand beside (a shelf with its plant), whose
    /// gap between two placed objects may be only just wide enough for both.
    fn packs_walls(&self, k: usize) -> bool {
        self.prep.problem.objects[k].global == GlobalKind::Edge
            && self.dependents[k].iter().any(|d| !d.ring)
    }

    /// Object `k`'s wall poses right beside the placed footprint `fp`, along each wall it
    /// could stand flush against, keeping every static rule. The static grid steps along the
    /// walls by [`super::candidates::wall_step`], so a gap between two placed objects only just
    /// wide enough for `k` and what must stand beside it is met only here. Worked out once per
    /// footprint.
    fn flush_beside(&self, k: usize, fp: &Rect) -> Rc<[Cand]> {
        kept_answer(&self.flush_answers, (k, rect_bits(fp)), MAX_TOUCH_ANSWERS, || {
            self.flush_beside_now(k, fp)
        })
    }

    /// [`Search::flush_beside`], worked out.
    fn flush_beside_now(&self, k: usize, fp: &Rect) -> Rc<[Cand]> {
        let prep = self.prep;
        let size = prep.problem.objects[k].size;
        let eps = constraints::EPS;
        let mut out = Vec::new();
        for rot in Rot::ALL {
            let h = half_extents(size, rot);
            let (fx, fz) = flush_values(prep, h);
            // Flush against a wall across x (x fixed): beside `fp` along z, when the two
            // share some of that wall's band; and the same turned.
            for &x in &fx {
                if fp.max_x > x - h[0] + eps && fp.min_x < x + h[0] - eps {
                    out.extend([fp.max_z + h[1], fp.min_z - h[1]].map(|z| Pose { x, z, rot }));
                }
            }
            for &z in &fz {
                if fp.max_z > z - h[1] + eps && fp.min_z < z + h[1] - eps {
                    out.extend([fp.max_x + h[0], fp.min_x - h[0]].map(|x| Pose { x, z, rot }));
                }
            }
        }
        let mut cands: Vec<Cand> = out
            .into_iter()
            .filter(|pose| prep.static_rule(k, pose).is_none())
            .map(|pose| Cand { pose, fp: footprint(&pose, size) })
            .collect();
        dedup_cands(&mut cands);
        cands.into()
    }

    /// The candidates of object `k` at this node, the first of them found. Each round of
    /// discrepancy walks the paths of the rounds before, so the same node comes back: its
    /// answer (and how far its walk has come) is kept by the poses of every object.
    fn node_candidates(&mut self, k: usize, st: &State) -> Rc<NodeCandidates> {
        let mut key = Vec::with_capacity(1 + 3 * st.poses.len());
        key.push(k as u64);
        for pose in &st.poses {
            match pose {
                Some(p) => key.extend([p.x.to_bits(), p.z.to_bits(), p.rot as u64]),
                None => key.push(u64::MAX),
            }
        }
        if let Some(found) = self.node_answers.get(&key) {
            return Rc::clone(found);
        }
        let mut found = self.candidates(k, st);
        if let NodeCandidates::Whole(cands, _) = &found {
            if cands.is_empty() && stands_elsewhere(&self.prep.problem.objects[k]) {
                // `edge` is soft: with no wall pose left, the object stands elsewhere now, so
                // that what relates to it is placed after it, not left without it.
                let elsewhere = self.anywhere_at_node(k, st);
                if !elsewhere.is_empty() {
                    found = NodeCandidates::Whole(elsewhere, None);
                }
            }
        }
        let found = Rc::new(found);
        if self.node_answers.len() >= MAX_NODE_ANSWERS {
            self.node_answers.clear();
        }
        self.node_answers.insert(key, Rc::clone(&found));
        found
    }

    /// Whether placing `c` would leave a placed object (or itself) unreachable, or close off a
    /// pocket of floor. The search meets the same layouts again (each round of discrepancy
    /// walks the paths of the rounds before), so answers are kept by the footprints.
    fn boxed(&mut self, c: &Cand, st: &mut State) -> bool {
        let mut key: Vec<u64> = Vec::with_capacity(4 * (st.fps.len() + 1));
        for fp in st.fps.iter().chain(std::iter::once(&c.fp)) {
            key.extend(rect_bits(fp));
        }
        if let Some(&boxed) = self.reach_answers.get(&key) {
            return boxed;
        }
        let prep = self.prep;
        let reach = &prep.reach;
        let depth = st.fps.len();
        self.ensure_reach_base(st);
        reach.mark(&mut st.occ, &c.fp, 1);
        let next = self.reach_bases[depth]
            .as_ref()
            .and_then(|b| reach.extend(b, &st.occ, &c.fp))
            .unwrap_or_else(|| {
                st.fps.push(c.fp);
                let flooded = reach.base(&st.occ, &st.fps);
                st.fps.pop();
                flooded
            });
        let boxed = !next.ok();
        if !boxed {
            // Placed next: its node finds its flood here.
            self.reach_bases.truncate(depth + 1);
            self.reach_bases.push(Some(next));
        }
        reach.mark(&mut st.occ, &c.fp, -1);
        if self.reach_answers.len() >= MAX_REACH_ANSWERS {
            self.reach_answers.clear();
        }
        self.reach_answers.insert(key, boxed);
        boxed
    }

    /// Makes `reach_bases[d]` the flood of the `d` footprints placed: kept from before, worked
    /// out from the flood one level up, or flooded.
    fn ensure_reach_base(&mut self, st: &State) {
        let depth = st.fps.len();
        let holds = |b: &Option<ReachBase>, n: usize| {
            b.as_ref().is_some_and(|b| b.footprints[..] == st.fps[..n])
        };
        if self.reach_bases.get(depth).is_some_and(|b| holds(b, depth)) {
            return;
        }
        self.reach_bases.resize(depth + 1, None);
        let reach = &self.prep.reach;
        let derived = match depth.checked_sub(1) {
            Some(up) if holds(&self.reach_bases[up], up) => {
                self.reach_bases[up].as_ref().and_then(|b| reach.extend(b, &st.occ, &st.fps[up]))
            }
            _ => None,
        };
        self.reach_bases[depth] = Some(derived.unwrap_or_else(|| reach.base(&st.occ, &st.fps)));
    }

    fn place(&self, k: usize, pose: Pose, fp: Rect, v: f64, by: &'static str, st: &mut State) {
        st.poses[k] = Some(pose);
        self.prep.reach.mark(&mut st.occ, &fp, 1);
        st.fps.push(fp);
        st.grid.push(fp);
        st.objs.push(k);
        st.value += v;
        st.by[k] = by;
    }

    fn unplace(&self, k: usize, v: f64, st: &mut State) {
        st.poses[k] = None;
        if let Some(fp) = st.fps.pop() {
            self.prep.reach.mark(&mut st.occ, &fp, -1);
        }
        st.grid.pop();
        st.objs.pop();
        st.value -= v;
    }

    /// The zones where the later object of a side relation could stand next to its target at
    /// `pose` (see [`constraints::side_zones`]), and which of them touch the target.
    fn zones_of(&self, d: &Dependent, pose: &Pose, size: [f64; 2]) -> (Vec<Rect>, Vec<Rect>) {
        let dep = &self.prep.problem.objects[d.object];
        let side = dep.size[0].min(dep.size[1]);
        let bounds = &self.prep.room.bounds;
        constraints::side_zones_and_next_to(d.kind, pose, size, [side, d.reach], d.gaps, bounds)
    }

    /// What candidate `c` of object `k` leaves for the side relations later objects have to
    /// `k`: how many still find a free zone, and how many find one right next to `k`. A zone is
    /// free when no placed footprint and no use-clearance `k` must keep out of (`keep_free`: a
    /// sofa's legroom, a desk's pull-out space) covers it: a plant beside its shelf does not
    /// stand in the legroom of the sofa next to the shelf either. A table's seat counts when
    /// its chair there would keep out of the zones placed objects keep free from chairs
    /// (`seat_keep_free`).
    fn room_left_for_dependents(
        &self,
        k: usize,
        c: &Cand,
        placed: &FootprintGrid,
        keep_free: &ZoneGrid,
        reserved: &[Rect],
        seat_keep_free: Option<&ZoneGrid>,
    ) -> (usize, usize) {
        let (kept, close) =
            self.room_left_where(k, c, |z| self.zone_free(z, placed) && !keep_free.any_overlap(z));
        let seats = self.seats_left(k, c, |p, ring| {
            let apart = seat_apart_zone(p, ring);
            self.zone_free(&seat_zone(p, ring), placed)
                && !reserved.iter().any(|r| r.overlaps(&apart))
                && seat_keep_free.is_none_or(|z| !z.any_overlap(&footprint(p, ring.seat)))
        });
        (kept + seats, close + seats)
    }

    /// How many of the chairs around table `k` still find a seat with the table at `c`: the
    /// table's seats for which `free` holds, as many as there are chairs.
    fn seats_left(
        &self,
        k: usize,
        c: &Cand,
        free: impl Fn(&Pose, &constraints::SeatRing) -> bool,
    ) -> usize {
        let Some(ring) = &self.rings[k] else { return 0 };
        let chairs = self.dependents[k].iter().filter(|d| d.ring).count();
        if chairs == 0 {
            return 0;
        }
        let free_seats = self.seats_at(k, c.pose).filter(|p| free(p, ring)).count();
        free_seats.min(chairs)
    }

    /// The seats of table `k` (one with a ring) standing at `pose`: [`constraints::seat_poses`],
    /// from the offsets kept for the table.
    fn seats_at(&self, k: usize, pose: Pose) -> impl Iterator<Item = Pose> + '_ {
        let offsets = self.seat_offsets[k].as_ref().map(|o| &o[pose.rot as usize]);
        offsets.into_iter().flatten().map(move |o| o.at(&pose))
    }

    /// Everything [`Search::room_left_static`] reads of object `k` besides its candidate and
    /// its static grid: its ring of chairs and, per later object with a side relation to it,
    /// the relation, gaps and reach and the later object's smaller side.
    fn room_signature(&self, k: usize) -> Vec<u64> {
        let mut sig = Vec::new();
        if let Some(ring) = &self.rings[k] {
            sig.extend([ring.seats as u64, ring.seat[0].to_bits(), ring.seat[1].to_bits()]);
        }
        for d in &self.dependents[k] {
            let dep = &self.prep.problem.objects[d.object];
            let side = dep.size[0].min(dep.size[1]);
            sig.extend([
                u64::MAX,
                u64::from(dep.global == GlobalKind::Edge),
                d.kind as u64,
                d.gaps.0.to_bits(),
                d.gaps.1.to_bits(),
                u64::from(d.ring),
                d.reach.to_bits(),
                side.to_bits(),
            ]);
        }
        sig
    }

    /// [`Search::room_left_for_dependents`] with nothing placed: what no node can exceed.
    fn room_left_static(&self, k: usize, c: &Cand) -> (u8, u8) {
        let (kept, close) = self.room_left_where(k, c, |z| self.zone_open(z));
        let seats = self.seats_left(k, c, |p, ring| self.zone_open(&seat_zone(p, ring)));
        let (kept, close) = (kept + seats, close + seats);
        let small = |n: usize| u8::try_from(n).unwrap_or(u8::MAX);
        (small(kept), small(close))
    }

    fn room_left_where(&self, k: usize, c: &Cand, free: impl Fn(&Rect) -> bool) -> (usize, usize) {
        let size = self.prep.problem.objects[k].size;
        let bounds = &self.prep.room.bounds;
        let (mut kept, mut close) = (0, 0);
        for d in self.dependents[k].iter().filter(|d| !d.ring) {
            let dep = &self.prep.problem.objects[d.object];
            let side = dep.size[0].min(dep.size[1]);
            // An object that wants a wall `in front of` or `behind` its target (a TV stand in
            // front of the sofa) stands only in a zone with a wall within its own width: across
            // the room from the sofa, not in the middle of the floor. (Beside its target, a
            // nightstand by a bed, it stands against the target's wall, which the zone beside
            // the middle of the bed does not show.)
            let edge = dep.global == GlobalKind::Edge
                && matches!(d.kind, RelationKind::InFrontOf | RelationKind::Behind);
            let (mut some_free, mut some_free_next_to) = (false, false);
            let zone = |z: Rect, listed: bool, next_to: bool| {
                let wanted = (listed && !some_free) || (next_to && !some_free_next_to);
                if wanted && (!edge || self.by_a_wall(&z, side)) && free(&z) {
                    some_free |= listed;
                    some_free_next_to |= next_to;
                }
            };
            let z = [side, d.reach];
            constraints::for_each_side_zone(d.kind, &c.pose, size, z, d.gaps, bounds, zone);
            kept += usize::from(some_free);
            close += usize::from(some_free_next_to);
        }
        (kept, close)
    }

    /// Derived candidate `c`'s score and the upper bound of its ordering key: its room for
    /// later objects worked out here, every side counted as touching something.
    fn derived_bound(&self, scorer: &Scorer, k: usize, c: &Cand) -> (f64, f64) {
        let s = scorer.score(c);
        let (kept, close) = self.room_left_static(k, c);
        (s, ordering_key(s, self.sat_value, f64::from(kept), f64::from(close), 4.0))
    }

    /// [`super::candidates::derived_candidates`] of object `k` with its targets posed as in `poses`, each
    /// target's piece worked out once per pose.
    fn derived(&self, k: usize, poses: &[Option<Pose>]) -> Vec<Cand> {
        let mut out = Vec::new();
        for target in derived_targets(self.prep, k) {
            let Some(Some(tp)) = poses.get(target) else { continue };
            let key = (k, target, [tp.x.to_bits(), tp.z.to_bits(), tp.rot as u64]);
            let piece = kept_answer(&self.derived_pieces, key, MAX_DERIVED_PIECES, || {
                derived_for_target(self.prep, k, target, tp).into()
            });
            out.extend_from_slice(&piece);
        }
        dedup_cands(&mut out);
        out
    }

    /// The target context of object `k` with the targets posed as in `poses`, worked out now
    /// or found again.
    fn target_context(&self, k: usize, poses: &[Option<Pose>]) -> Rc<TargetContext> {
        let prep = self.prep;
        let obj = &prep.problem.objects[k];
        let mut key_bits = Vec::with_capacity(3 * obj.constraints.len());
        for c in &obj.constraints {
            match poses.get(c.target).copied().flatten() {
                Some(p) => key_bits.extend([p.x.to_bits(), p.z.to_bits(), p.rot as u64]),
                None => key_bits.push(u64::MAX),
            }
        }
        let key = (k, key_bits);
        if let Some(found) = self.contexts.borrow().get(&key) {
            return Rc::clone(found);
        }
        let set = &self.statics[k];
        let derived = self.derived(k, poses);
        let n_static = set.len();
        let n = n_static + derived.len();
        let scorer = Scorer::new(prep, k, poses, self.sat_value);
        let lazy = scorer.seat_boxes.iter().any(Option::is_some);
        let targets: Vec<Rect> = obj
            .constraints
            .iter()
            .filter_map(|c| {
                let pose = poses.get(c.target).copied().flatten()?;
                Some(footprint(&pose, prep.problem.objects.get(c.target)?.size))
            })
            .collect();
        let on_target = |c: &Cand| targets.iter().any(|t| t.overlaps(&c.fp));
        let (mut scores, mut bounds) = (vec![f64::NAN; n], vec![f64::NAN; n]);
        let (mut rest, mut on_targets) = (Vec::new(), Vec::new());
        let mut waiting = Vec::new();
        let mut tiers = Vec::new();
        // The relations that hold only near their targets: a candidate beyond reach of some
        // of them waits in a tier (see `Walk::tiers`); with none, every candidate is worked out.
        let reaches = scorer.reaches();
        let limited: Vec<&Reach> =
            reaches.iter().filter(|r| !matches!(r, Reach::Anywhere)).collect();
        let sat = self.sat_value;
        // (Tiers are counted in bytes: an object with more such relations than that is worked
        // out whole.)
        if limited.is_empty() || limited.len() >= usize::from(u8::MAX) || whole_contexts() {
            for i in 0..u32::try_from(n_static).unwrap_or(u32::MAX) {
                let at = i as usize;
                if on_target(&set.cand(at)) {
                    on_targets.push(i);
                } else {
                    (scores[at], bounds[at]) = static_bound(&scorer, lazy, sat, set, at);
                    rest.push(i);
                }
            }
        } else {
            // How many of those relations each static candidate is within reach of, and
            // which stand on a target (looked up by their centres).
            let grid = &set.grid;
            let mut within = vec![0u8; n_static];
            let mut on = vec![false; n_static];
            for reach in &limited {
                let (Reach::Gap(r, d) | Reach::Seats(r, d)) = reach else { continue };
                grid.centres.within(r, *d, |g| {
                    if reach.holds(&grid.cands[g as usize]) {
                        let at = set.pos_of[g as usize] as usize;
                        within[at] = within[at].saturating_add(1);
                    }
                });
            }
            for t in &targets {
                grid.centres.within(t, 0.0, |g| {
                    if t.overlaps(&grid.cands[g as usize].fp) {
                        on[set.pos_of[g as usize] as usize] = true;
                    }
                });
            }
            let all = u8::try_from(limited.len()).unwrap_or(u8::MAX);
            waiting = vec![0u8; n];
            for i in 0..u32::try_from(n_static).unwrap_or(u32::MAX) {
                let at = i as usize;
                if on[at] {
                    on_targets.push(i);
                } else if within[at] >= all {
                    (scores[at], bounds[at]) = static_bound(&scorer, lazy, sat, set, at);
                    rest.push(i);
                } else {
                    waiting[at] = within[at] + 1;
                }
            }
            // Every tier's bound: its relations within reach may hold, the others cannot;
            // every later object's relation kept (as many as there are, for a derived
            // candidate) and every side touching something.
            let most = u8::try_from(self.dependents[k].len()).unwrap_or(u8::MAX);
            let (kept, close) = (set.room_max.0.max(most), set.room_max.1.max(most));
            let full = scorer.beyond_reach(&reaches);
            for j in 0..all {
                let s = full + sat * f64::from(j);
                let key = ordering_key(s, sat, f64::from(kept), f64::from(close), 4.0);
                // Above any rounding of the keys it bounds.
                tiers.push(Tier { bound: key + key.abs() * 1e-12 + 1e-9, joined: false });
            }
        }
        for (i, c) in (0..u32::try_from(n).unwrap_or(u32::MAX)).skip(n_static).zip(&derived) {
            let at = i as usize;
            if on_target(c) {
                on_targets.push(i);
                continue;
            }
            let within = limited.iter().filter(|r| r.holds(c)).count();
            if !tiers.is_empty() && within < limited.len() {
                waiting[at] = u8::try_from(within + 1).unwrap_or(u8::MAX);
                continue;
            }
            (scores[at], bounds[at]) = self.derived_bound(&scorer, k, c);
            rest.push(i);
        }
        let mut on_target_bits = vec![0u64; n_static.div_ceil(64)];
        for &i in on_targets.iter().filter(|&&i| (i as usize) < n_static) {
            on_target_bits[i as usize / 64] |= 1 << (i % 64);
        }
        let walk = RefCell::new(Walk {
            steps: Vec::new(),
            rest,
            scores,
            bounds,
            waiting,
            tiers,
            above: None,
        });
        let context =
            Rc::new(TargetContext { derived, scorer, lazy, walk, on_targets, on_target_bits });
        let mut contexts = self.contexts.borrow_mut();
        if contexts.len() >= MAX_TARGET_CONTEXTS {
            contexts.clear();
        }
        contexts.insert(key, Rc::clone(&context));
        context
    }

    /// The side relations that objects after `k` have to objects already placed and that can
    /// still be kept, with their free zones. A pose of `k` that covers all of a promise's
    /// zones breaks the relation in advance; one that covers its free zones next to the target
    /// pushes the later object away.
    fn open_promises(&self, k: usize, placed: &FootprintGrid, st: &State) -> Vec<Promise> {
        let prep = self.prep;
        let mut out = Vec::new();
        for (t, deps) in self.dependents.iter().enumerate().take(k) {
            let Some(tp) = st.poses[t] else { continue };
            let t_size = prep.problem.objects[t].size;
            for d in deps.iter().filter(|d| d.object > k && !d.ring) {
                let (all, next_to) = self.zones_of(d, &tp, t_size);
                let free = |v: Vec<Rect>| -> Vec<Rect> {
                    v.into_iter().filter(|z| self.zone_free(z, placed)).collect()
                };
                let promise = Promise { zones: free(all), next_to: free(next_to) };
                if !promise.zones.is_empty() {
                    out.push(promise);
                }
            }
        }
        out
    }

    /// The seats of placed tables that chairs after `k` still need, free at this node.
    fn open_seats(&self, k: usize, placed: &FootprintGrid, st: &State) -> Vec<SeatPromise> {
        let mut out = Vec::new();
        for (t, ring) in self.rings.iter().enumerate().take(k) {
            let (Some(ring), Some(tp)) = (ring, st.poses[t]) else { continue };
            let need = self.dependents[t].iter().filter(|d| d.ring && d.object > k).count();
            if need == 0 {
                continue;
            }
            let seats: Vec<Rect> = self
                .seats_at(t, tp)
                .map(|p| seat_zone(&p, ring))
                .filter(|z| self.zone_free(z, placed))
                .collect();
            if !seats.is_empty() {
                out.push(SeatPromise { seats, need });
            }
        }
        out
    }

    /// The zones round the seats of every table before `k` placed at this node
    /// ([`seat_apart_zone`]).
    fn placed_seat_zones(&self, k: usize, st: &State) -> Vec<Rect> {
        let mut out = Vec::new();
        for (t, ring) in self.rings.iter().enumerate().take(k) {
            let (Some(ring), Some(tp)) = (ring, st.poses[t]) else { continue };
            out.extend(self.seats_at(t, tp).map(|p| seat_apart_zone(&p, ring)));
        }
        out
    }

    /// The best-scored poses of `edge` object `k` anywhere in the room (at most
    /// [`REACH_TRIES`], best first) that keep every hard rule but its `edge` at this node.
    fn anywhere_at_node(&self, k: usize, st: &State) -> Vec<(Cand, f64)> {
        let prep = self.prep;
        let clearances = self.clearance_context(k, st);
        let scorer = Scorer::new(prep, k, &st.poses, self.sat_value);
        let placed = &st.grid;
        // Scored first and met best first: the rules are asked of the best ones only, until
        // enough keep them.
        let anywhere = self.anywhere(k);
        let mut scored: Vec<(f64, usize)> =
            anywhere.iter().enumerate().map(|(i, c)| (scorer.score(c), i)).collect();
        scored.sort_by(|a, b| b.0.total_cmp(&a.0).then(a.1.cmp(&b.1)));
        scored
            .into_iter()
            .map(|(s, i)| (anywhere[i], s))
            .filter(|(c, _)| {
                !placed.any_overlap(&c.fp) && self.clearances_kept(k, c, placed, &clearances)
            })
            .take(REACH_TRIES)
            .collect()
    }

    /// The poses of object `k` anywhere in the room: worked out once, the first time asked.
    fn anywhere(&self, k: usize) -> Rc<Vec<Cand>> {
        let mut kept = self.anywhere.borrow_mut();
        let slot = &mut kept[k];
        Rc::clone(slot.get_or_insert_with(|| Rc::new(anywhere_candidates(self.prep, k, self.seed))))
    }

    /// Completes a layout the search finished: every object it left out is tried again against
    /// the finished layout (its own candidates, then, for an `edge` object, poses anywhere in
    /// the room: `edge` is soft) and stands at its best-scored pose that keeps every hard rule.
    /// One that still finds none gets the reason the finished layout gives, so the report never
    /// names a rule that a free pose would keep.
    fn finish(&self, st: &mut State) {
        let prep = self.prep;
        let objects = &prep.problem.objects;
        for (k, obj) in objects.iter().enumerate() {
            if st.poses[k].is_some() || obj.pin.is_some() {
                continue;
            }
            let set = &self.statics[k];
            let mut cands: Vec<Cand> = (0..set.len()).map(|i| set.cand(i)).collect();
            cands.extend(self.derived(k, &st.poses));
            let mut why = self.place_best(k, st, &cands);
            if why.is_some() && stands_elsewhere(obj) {
                let anywhere = self.anywhere(k);
                why = self.place_best(k, st, &anywhere).or(why);
            }
            if let Some(why) = why {
                st.fails[k] = Some(why);
            }
        }
    }

    /// Places object `k` at the best-scored of `cands` that keeps every hard rule with the
    /// layout `st` (no overlap, use-clearances, reachability), or says why none does.
    fn place_best(&self, k: usize, st: &mut State, cands: &[Cand]) -> Option<Reason> {
        let prep = self.prep;
        let clearances = self.clearances_with(k, &st.poses, &st.objs);
        let mut best: Option<(f64, Cand)> = None;
        let (mut overlapping, mut cleared_out, mut boxed) = (0usize, 0usize, 0usize);
        let mut blockers: BTreeMap<usize, usize> = BTreeMap::new();
        for c in cands {
            if let Some(i) = st.poses.iter().enumerate().position(|(i, p)| {
                p.is_some_and(|p| footprint(&p, prep.problem.objects[i].size).overlaps(&c.fp))
            }) {
                overlapping += 1;
                *blockers.entry(i).or_insert(0) += 1;
                continue;
            }
            if !self.clearances_kept(k, c, &st.grid, &clearances) {
                cleared_out += 1;
                continue;
            }
            let s = fast_score(prep, k, &c.pose, &st.poses, self.sat_value);
            if best.as_ref().is_some_and(|(b, _)| *b >= s) {
                continue;
            }
            let reach = &prep.reach;
            reach.mark(&mut st.occ, &c.fp, 1);
            st.fps.push(c.fp);
            let ok = reach.ok_with(&st.occ, &st.fps);
            st.fps.pop();
            reach.mark(&mut st.occ, &c.fp, -1);
            if ok {
                best = Some((s, *c));
            } else {
                boxed += 1;
            }
        }
        if let Some((s, c)) = best {
            st.fails[k] = None;
            self.place(k, c.pose, c.fp, self.placed_value + s, "dfs", st);
            return None;
        }
        if cands.is_empty() {
            return Some(static_reason(&self.static_fails[k]));
        }
        // Every rule that removed poses, with how many (the fixed rules of the room first
        // counted over the grid of poses, then those of the finished layout).
        let names = blockers.iter().map(|(&i, &n)| (n, prep.problem.objects[i].id.as_str()));
        let removed = [
            (HardRule::NoOverlap, overlapping),
            (HardRule::UseClearance, cleared_out),
            (HardRule::Reachable, boxed),
        ];
        Some(super::errors::removed_reason(&self.static_fails[k], &removed, names))
    }

    /// What the use-clearance rule needs at a node for object `k`: the placed footprints, the
    /// placed objects' clearance zones, and which placed objects `k` relates to.
    fn clearance_context(&self, k: usize, st: &State) -> Clearances {
        self.clearances_with(k, &st.poses, &st.objs)
    }

    /// [`Search::clearance_context`] from the parts of a state it reads (so that the state's
    /// other parts may change while it is held).
    fn clearances_with(&self, k: usize, poses: &[Option<Pose>], objs: &[usize]) -> Clearances {
        let objects = &self.prep.problem.objects;
        let related = |a: usize, b: usize| {
            objects[a].constraints.iter().any(|x| x.target == b)
                || objects[b].constraints.iter().any(|x| x.target == a)
        };
        let related_to_k =
            objs.iter().map(|&i| objects[k].role.lets_in(objects[i].role, related(i, k)));
        let related_to_k = related_to_k.collect();
        let back = objs.iter().map(|&i| super::back_to_back(self.prep.problem, i, k)).collect();
        let mut sight = Vec::new();
        if objects[k].height > constraints::SIGHT_LINE_M {
            for (i, o) in objects.iter().enumerate() {
                let Some(p) = poses[i] else { continue };
                for (ci, c) in o.constraints.iter().enumerate() {
                    if i == k || c.target == k || !self.prep.meaning(i, ci).view {
                        continue;
                    }
                    if let Some(Some(t)) = poses.get(c.target) {
                        sight.push(([p.x, p.z], [t.x, t.z]));
                    }
                }
            }
        }
        let mut keep_free = Vec::new();
        let mut one_free = Vec::new();
        for (i, o) in objects.iter().enumerate() {
            let Some(p) = poses[i] else { continue };
            if i == k {
                continue;
            }
            if super::back_to_back(self.prep.problem, i, k) {
                keep_free.push(super::back_zone(&p, o.size));
            }
            let rel = related(i, k);
            let (z, all) = self.prep.use_zones(i, &p);
            if z.is_empty() || o.role.lets_in(objects[k].role, rel) {
                continue;
            }
            // For a bed, the sides still open with the other placed furniture.
            let z = if all {
                z
            } else {
                z.into_iter()
                    .filter(|r| {
                        self.prep.room.contains_rect(r)
                            && objects.iter().enumerate().all(|(j, oj)| {
                                j == i
                                    || j == k
                                    || related(i, j)
                                    || poses[j]
                                        .is_none_or(|pj| !footprint(&pj, oj.size).overlaps(r))
                            })
                    })
                    .collect()
            };
            if all {
                keep_free.extend(z);
            } else {
                one_free.push(z);
            }
        }
        let bounds = &self.prep.room.bounds;
        Clearances {
            related: related_to_k,
            keep_free: ZoneGrid::new(bounds, keep_free),
            one_free,
            back,
            sight,
        }
    }

    /// Whether candidate `c` of object `k` keeps the use-clearances: its own (inside the room
    /// and free of placed furniture it has no relation with) and those of the placed objects
    /// (it does not stand in them unless it relates to that object: a chair at its desk, a
    /// coffee table before its sofa, a nightstand by its bed).
    fn clearances_kept(
        &self,
        k: usize,
        c: &Cand,
        placed: &FootprintGrid,
        ctx: &Clearances,
    ) -> bool {
        let (zones, all) = self.prep.use_zones(k, &c.pose);
        let own_free = |z: &Rect| {
            self.prep.room.contains_rect(z) && !placed.any_overlap_where(z, |i| !ctx.related[i])
        };
        let own_ok = zones.is_empty()
            || if all { zones.iter().all(own_free) } else { zones.iter().any(own_free) };
        let back_ok = !ctx.back.iter().any(|&b| b) || {
            let z = super::back_zone(&c.pose, self.prep.problem.objects[k].size);
            !placed.any_overlap_where(&z, |i| ctx.back[i])
        };
        own_ok
            && back_ok
            && !ctx.sight.iter().any(|(a, b)| c.fp.meets_segment(*a, *b))
            && !ctx.keep_free.any_overlap(&c.fp)
            && ctx.one_free.iter().all(|z| z.is_empty() || z.iter().any(|r| !r.overlaps(&c.fp)))
    }

    /// What object `k`'s candidates are held to at this node ([`NodeRules`]).
    fn node_rules(&self, k: usize, st: &State) -> NodeRules {
        let placed = &st.grid;
        // The seats of the tables placed, a chair at them or not, with the room behind each to
        // pull the chair out: this object's own chairs do not take them (two tables whose
        // seats share that room leave their chairs back to back with no way between).
        let reserved =
            if self.rings[k].is_some() { self.placed_seat_zones(k, st) } else { Vec::new() };
        // The first chair of the ring stands for them all: they are alike, and none relates
        // to anything placed yet (their table is not).
        let chair = self.dependents[k].iter().find(|d| d.ring).map(|d| d.object);
        let seat_keep_free = chair.map(|j| self.clearances_with(j, &st.poses, &st.objs).keep_free);
        NodeRules {
            clearances: self.clearance_context(k, st),
            promises: self.open_promises(k, placed, st),
            seat_promises: self.open_seats(k, placed, st),
            reserved,
            seat_keep_free,
        }
    }

    /// Whether a zone is inside the room, outside the door zones and free of footprints.
    fn zone_free(&self, z: &Rect, placed: &FootprintGrid) -> bool {
        self.zone_open(z) && !placed.any_overlap(z)
    }

    /// Whether zone `z` (inside the room) has a wall within `d` of one of its sides: moved by
    /// `d` one way or another, it leaves the room.
    fn by_a_wall(&self, z: &Rect, d: f64) -> bool {
        let room = &self.prep.room;
        [[-d, 0.0], [d, 0.0], [0.0, -d], [0.0, d]].iter().any(|m| {
            let moved = Rect {
                min_x: z.min_x + m[0],
                max_x: z.max_x + m[0],
                min_z: z.min_z + m[1],
                max_z: z.max_z + m[1],
            };
            !room.contains_rect(&moved)
        })
    }

    /// Whether a zone is inside the room and outside the door zones.
    fn zone_open(&self, z: &Rect) -> bool {
        self.prep.room.contains_rect(z) && !self.prep.keep_out.iter().any(|o| o.overlaps(z))
    }

    /// The candidates of object `k` at this node with the first of them found, or, when there
    /// is none, why.
    fn candidates(&self, k: usize, st: &State) -> NodeCandidates {
        let prep = self.prep;
        let context = self.target_context(k, &st.poses);
        let n_static = self.statics[k].len();
        if n_static == 0
            && context.derived.is_empty()
            && prep.problem.objects[k].global != GlobalKind::Edge
        {
            return NodeCandidates::Whole(Vec::new(), Some(static_reason(&self.static_fails[k])));
        }
        // The static candidates a placed footprint can add a touching side to, but those on a
        // target (met apart, below): each met once, in the node's own walk.
        // With the sides each comes near a placed footprint by: with those that touch a wall,
        // every side its key can count.
        let set = &self.statics[k];
        let mut touch_bits = vec![0u64; n_static.div_ceil(64)];
        let mut near_sides: Vec<(u32, u8)> = Vec::new();
        for fp in st.grid.rects() {
            for &(g, sides) in self.touching(k, fp).iter() {
                let i = set.pos_of[g as usize];
                touch_bits[i as usize / 64] |= 1 << (i % 64);
                near_sides.push((i, sides));
            }
        }
        for (bits, on) in touch_bits.iter_mut().zip(&context.on_target_bits) {
            *bits &= !on;
        }
        near_sides.sort_unstable();
        let mut touch = Vec::new();
        for run in near_sides.chunk_by(|a, b| a.0 == b.0) {
            let i = run[0].0;
            if touch_bits[i as usize / 64] & (1 << (i % 64)) != 0 {
                let sides = run.iter().fold(0, |acc, r| acc | r.1);
                touch.push(TouchFirst(context.touch_step(i, set, self.sat_value, sides)));
            }
        }
        // Wall poses flush beside placed footprints, met in the touch walk after the statics
        // and the derived (by position), bounded as a derived candidate is.
        if self.packs_walls(k) {
            let mut at = u32::try_from(n_static + context.derived.len()).unwrap_or(u32::MAX);
            for fp in st.grid.rects() {
                for c in self.flush_beside(k, fp).iter() {
                    let (score, bound) = self.derived_bound(&context.scorer, k, c);
                    touch.push(TouchFirst(Step { bound, cand: *c, score, index: at }));
                    at = at.saturating_add(1);
                }
            }
        }
        let mut walk = NodeWalk {
            kept: Vec::new(),
            next: 0,
            touch_bits,
            touch: BinaryHeap::from(touch),
            done: false,
            blockers: BTreeMap::new(),
            cleared_out: 0,
            rules: None,
        };
        self.walk_to(k, st, &mut walk, 1);
        if !walk.kept.is_empty() {
            return NodeCandidates::Walk(RefCell::new(walk));
        }
        let NodeWalk { mut blockers, cleared_out, .. } = walk;
        // Why nothing is left counts the candidates standing on a target too.
        let set = &self.statics[k];
        let derived = &context.derived;
        let pick = |i: usize| if i < n_static { set.cand(i) } else { derived[i - n_static] };
        for &i in &context.on_targets {
            let first = st.grid.first_overlap(&pick(i as usize).fp).unwrap_or(usize::MAX);
            *blockers.entry(first).or_insert(0) += 1;
        }
        if n_static == 0 && derived.is_empty() {
            return NodeCandidates::Whole(Vec::new(), Some(static_reason(&self.static_fails[k])));
        }
        if cleared_out > 0 && cleared_out >= blockers.values().sum() {
            let why = "every pose left stands in the space another object needs for its use (or \
                       blocks its own)";
            return NodeCandidates::Whole(Vec::new(), Some((HardRule::UseClearance, why.into())));
        }
        let names = blockers.iter().filter_map(|(&slot, &count)| {
            st.objs.get(slot).map(|&i| (count, prep.problem.objects[i].id.as_str()))
        });
        NodeCandidates::Whole(Vec::new(), Some(overlap_reason(names)))
    }

    /// Candidate `j` (from 0, best first) of object `k` at this node, walking further when it
    /// is not known yet.
    fn node_candidate(
        &self,
        k: usize,
        st: &State,
        found: &NodeCandidates,
        j: usize,
    ) -> Option<(Cand, f64)> {
        match found {
            NodeCandidates::Whole(cands, _) => cands.get(j).copied(),
            NodeCandidates::Walk(walk) => {
                let mut walk = walk.borrow_mut();
                self.walk_to(k, st, &mut walk, j + 1);
                walk.kept.get(j).map(|&(_, _, s, c)| (c, s))
            }
        }
    }

    /// Walks object `k`'s candidates at this node until the best `m` are known: every step
    /// not met yet has a bound below the `m`th key kept (or there is no step left).
    ///
    /// The ordering key of a candidate is its score plus what the pose leaves for later objects
    /// (room for the side relations that target this object, and a small bonus per side
    /// touching a wall or a placed object); the score alone is what the layout is worth. Only
    /// the best [`REACH_TRIES`] keys are ever visited. The candidates are met in the order of
    /// an upper bound of their key (the target context's walk), so no candidate after the stop
    /// could come before the `m`th. Ties go to the earlier position, which is the seeded
    /// order.
    fn walk_to(&self, k: usize, st: &State, walk: &mut NodeWalk, m: usize) {
        let m = m.min(REACH_TRIES);
        let context = self.target_context(k, &st.poses);
        let set = &self.statics[k];
        let n_static = set.len();
        // No step left can come before the `m`th kept: the steps are met in the order of their
        // bounds and then of their positions, as the kept are ordered by key and position.
        let stops = |walk: &NodeWalk, step: &Step| {
            walk.kept.len() >= m && {
                let (key, at, ..) = walk.kept[m - 1];
                step.bound < key || (step.bound == key && step.index as usize > at)
            }
        };
        // The `m`th key kept, below which the walk stops: a tier waiting with a bound below
        // it is never worked out (most often a chair at a free seat, with every pose away from
        // its table waiting).
        let stop_below = |walk: &NodeWalk| (walk.kept.len() >= m).then(|| walk.kept[m - 1].0);
        if walk.done {
            return;
        }
        match next_step(&context, walk, self, k, stop_below(walk)) {
            None => walk.done = true,
            Some((step, _)) if stops(walk, &step) => return,
            Some(_) => {}
        }
        if walk.done {
            return;
        }
        let prep = self.prep;
        // The placed footprints, bucketed: each question below looks only at those near it.
        let placed = &st.grid;
        let rules = Rc::clone(walk.rules.get_or_insert_with(|| Rc::new(self.node_rules(k, st))));
        let NodeRules { clearances, promises, seat_promises, reserved, seat_keep_free } = &*rules;
        let order = |a: &(f64, usize, f64, Cand), b: &(f64, usize, f64, Cand)| {
            b.0.total_cmp(&a.0).then(a.1.cmp(&b.1))
        };
        // The sides of a candidate that touch a wall or a placed footprint: a placed footprint
        // grown by the contact distance that the candidate overlaps (while the footprint itself
        // does not) is touched.
        let sides = |i: usize, c: &Cand| {
            if i < n_static {
                let mut sides = set.wall_touch(i);
                placed.near(&c.fp.grow(CONTACT_M), |j| {
                    let fp = &placed.rects()[j];
                    if c.fp.overlaps(&fp.grow(CONTACT_M)) {
                        sides |= touching(&c.fp, |m| m.overlaps(fp));
                    }
                });
                sides
            } else {
                touching(&c.fp, |m| !prep.room.contains_rect(m) || placed.any_overlap(m))
            }
        };
        loop {
            let Some((step, touches)) = next_step(&context, walk, self, k, stop_below(walk)) else {
                walk.done = true;
                // Nothing is met again at this node.
                walk.rules = None;
                break;
            };
            if stops(walk, &step) {
                break;
            }
            if touches {
                walk.touch.pop();
            } else {
                walk.next += 1;
            }
            let c = step.cand;
            let i = step.index as usize;
            // The placed footprint the candidate overlaps first (lowest index), if any.
            if let Some(first) = placed.first_overlap(&c.fp) {
                *walk.blockers.entry(first).or_insert(0) += 1;
                continue;
            }
            if !self.clearances_kept(k, &c, placed, clearances) {
                walk.cleared_out += 1;
                continue;
            }
            let sides = sides(i, &c);
            // A touching candidate beyond reach is scored only now.
            let s = if step.score.is_nan() { context.scorer.score(&c) } else { step.score };
            let (kept, close) = self.room_left_for_dependents(
                k,
                &c,
                placed,
                &clearances.keep_free,
                reserved,
                seat_keep_free.as_ref(),
            );
            let covers = |zones: &[Rect]| zones.iter().all(|z| z.overlaps(&c.fp));
            let broken = promises.iter().filter(|p| covers(&p.zones)).count()
                + seat_promises.iter().map(|p| p.broken_by(&c.fp)).sum::<usize>();
            let crowded =
                promises.iter().filter(|p| !p.next_to.is_empty() && covers(&p.next_to)).count();
            let key = ordering_key(
                s,
                self.sat_value,
                kept as f64 - broken as f64,
                close as f64 - crowded as f64,
                f64::from(sides.count_ones()),
            );
            let entry = (key, i, s, c);
            let at = walk.kept.partition_point(|t| order(t, &entry).is_lt());
            if at < REACH_TRIES {
                walk.kept.insert(at, entry);
                walk.kept.truncate(REACH_TRIES);
            }
        }
    }
}

/// The next step of a node's walk, and whether it is one of the candidates touching a placed
/// footprint: the better of the context's next step (those in the touch set passed over) and
/// the touch walk's, by bound and then position. Where the context's next is a tier's whose
/// bound is below `stop_below` (the key the walk stops under), a step with the tier's bound and
/// no candidate (position `u32::MAX`) stands for it: the walk stops there, never taking it.
fn next_step(
    context: &TargetContext,
    walk: &mut NodeWalk,
    search: &Search<'_, '_>,
    k: usize,
    stop_below: Option<f64>,
) -> Option<(Step, bool)> {
    let n_static = search.statics[k].len();
    let from_context = loop {
        // The context's next step is a tier's to give: a touching step at or above the tier's
        // bound comes first, and a walk that stops below `stop_below` stops at the tier's
        // bound (which bounds every candidate of the tier), neither with the tier worked out.
        if let Some(tier) = context.tier_next(walk.next) {
            let top = walk.touch.peek().map(|t| t.0);
            if let Some(top) = top.filter(|t| t.bound >= tier) {
                return Some((top, true));
            }
            if stop_below.is_some_and(|key| tier < key) {
                let pose = Pose { x: 0.0, z: 0.0, rot: Rot::R0 };
                let cand = Cand { pose, fp: footprint(&pose, [0.0, 0.0]) };
                return Some((Step { bound: tier, cand, score: f64::NAN, index: u32::MAX }, false));
            }
        }
        match context.step(walk.next, search, k) {
            Some(step)
                if (step.index as usize) < n_static
                    && walk.touch_bits[step.index as usize / 64] & (1 << (step.index % 64))
                        != 0 =>
            {
                walk.next += 1;
            }
            other => break other,
        }
    };
    let from_touch = walk.touch.peek().map(|t| t.0);
    match (from_context, from_touch) {
        (Some(a), Some(b)) => {
            let touch_first = b.bound > a.bound || (b.bound == a.bound && b.index < a.index);
            Some(if touch_first { (b, true) } else { (a, false) })
        }
        (Some(a), None) => Some((a, false)),
        (None, Some(b)) => Some((b, true)),
        (None, None) => None,
    }
}

/// Where a complete layout stands in the documented order: objects placed, constraints kept
/// (measured as the report measures them), then the weighted score.
#[derive(Clone, Copy, Debug)]
struct Rank {
    placed: usize,
    /// Seating groups whose viewing rule is kept: a room's use before its plan's wording (a
    /// sofa off the wall that watches its TV beats one against the wall that cannot).
    views: usize,
    kept: usize,
    score: f64,
}

impl Rank {
    /// Strictly better (a tie keeps the layout found first).
    fn beats(&self, other: &Rank) -> bool {
        (self.placed, self.views, self.kept)
            .cmp(&(other.placed, other.views, other.kept))
            .then(self.score.total_cmp(&(other.score + 1e-9)))
            .is_gt()
    }
}

fn rank(prep: &Prepared<'_>, st: &State) -> Rank {
    let mut r = Rank { placed: 0, views: 0, kept: 0, score: 0.0 };
    for (k, pose) in st.poses.iter().enumerate() {
        let Some(pose) = pose else { continue };
        let (reports, score) = measure_object(prep.problem, &prep.room, k, pose, &st.poses);
        r.placed += 1;
        r.kept += reports.iter().filter(|c| c.measure.satisfied).count();
        // The relations' reports follow the global constraint's.
        r.views += reports
            .iter()
            .skip(1)
            .enumerate()
            .filter(|(ci, c)| c.measure.satisfied && prep.meaning(k, *ci).view)
            .count();
        r.score += score;
    }
    r
}

/// W0501's reason when every pose overlaps placed objects: the (at most three) objects in the
/// way of the most poses, given as (poses blocked, id).
fn overlap_reason<'a>(blockers: impl Iterator<Item = (usize, &'a str)>) -> Reason {
    let mut names: Vec<(usize, &str)> = blockers.collect();
    names.sort_by(|a, b| b.0.cmp(&a.0).then(a.1.cmp(b.1)));
    let list: Vec<String> = names.iter().take(3).map(|(_, n)| format!("`{n}`")).collect();
    (
        HardRule::NoOverlap,
        format!("every pose overlaps an object already placed ({})", list.join(", ")),
    )
}

pub(crate) fn static_reason(fails: &BTreeMap<HardRule, usize>) -> (HardRule, String) {
    let beyond_inside: Vec<(&HardRule, &usize)> =
        fails.iter().filter(|(r, _)| **r != HardRule::InsideRoom).collect();
    let pick =
        beyond_inside.iter().max_by_key(|(r, n)| (**n, std::cmp::Reverse(**r))).map(|(r, _)| **r);
    match pick {
        Some(rule) => (rule, format!("no pose inside the room keeps {}", rule.describe())),
        None => (HardRule::InsideRoom, "the object does not fit inside the room".to_string()),
    }
}

/// The order the search places the floor objects in: group by group, a group being the objects
/// joined by relations (a table and its chairs, a sofa with its coffee table and side table, a
/// shelf and its plant), each group's objects in plan order (a relation's target comes before
/// the object that refers to it; an object whose target comes later in the plan, as an implied
/// seating group's sofa turned to its screen, waits for it: [`super::targets_first`]). Groups with a pinned object come first, in plan order (what
/// is fixed is there before anything is placed round it); then the others, the group with the
/// most floor (its objects' footprints summed) first, ties in plan order: the large pieces
/// find their place while the room is open and the small ones fill what is left between them,
/// as in packing a shelf.
pub(crate) fn placement_order(problem: &super::RoomProblem) -> Vec<usize> {
    fn find(root: &mut [usize], mut k: usize) -> usize {
        while root[k] != k {
            root[k] = root[root[k]];
            k = root[k];
        }
        k
    }
    let n = problem.objects.len();
    // Union by the smaller index: each group's root is its first object.
    let mut root: Vec<usize> = (0..n).collect();
    for (k, obj) in problem.objects.iter().enumerate() {
        for c in obj.constraints.iter().filter(|c| c.target < n) {
            let (a, b) = (find(&mut root, k), find(&mut root, c.target));
            root[a.max(b)] = a.min(b);
        }
    }
    let mut members: Vec<Vec<usize>> = vec![Vec::new(); n];
    let mut pinned = vec![false; n];
    for (k, obj) in problem.objects.iter().enumerate() {
        let g = find(&mut root, k);
        members[g].push(k);
        pinned[g] |= obj.pin.is_some();
    }
    let mut anchors: Vec<usize> = (0..n).filter(|&g| !members[g].is_empty()).collect();
    // A group's floor: the footprints of its objects, summed.
    let floor: Vec<f64> = members
        .iter()
        .map(|m| m.iter().map(|&k| problem.objects[k].size[0] * problem.objects[k].size[1]).sum())
        .collect();
    anchors.sort_by(|&a, &b| {
        pinned[b].cmp(&pinned[a]).then_with(|| {
            if pinned[a] {
                a.cmp(&b)
            } else {
                floor[b].total_cmp(&floor[a]).then(a.cmp(&b))
            }
        })
    });
    anchors
        .into_iter()
        .flat_map(|g| super::targets_first(problem, &std::mem::take(&mut members[g])))
        .collect()
}

/// Runs the search in [`placement_order`] and turns the best state into a layout, in plan
/// order.
pub(crate) fn solve(prep: &Prepared<'_>, options: &SolveOptions) -> RoomLayout {
    let order = placement_order(prep.problem);
    if order.iter().enumerate().all(|(i, &k)| i == k) {
        return solve_in_order(prep, options, &order);
    }
    // The problem with its objects in placement order, each relation's target renumbered.
    let mut at = vec![0; order.len()];
    for (i, &k) in order.iter().enumerate() {
        at[k] = i;
    }
    let mut problem = prep.problem.clone();
    problem.objects = order
        .iter()
        .map(|&k| {
            let mut obj = prep.problem.objects[k].clone();
            for c in &mut obj.constraints {
                c.target = at.get(c.target).copied().unwrap_or(c.target);
            }
            obj
        })
        .collect();
    let placing = Prepared {
        problem: &problem,
        room: prep.room.clone(),
        keep_out: prep.keep_out.clone(),
        windows: prep.windows.clone(),
        reach: prep.reach.clone(),
        walls: prep.walls.clone(),
        meanings: order.iter().map(|&k| prep.meanings[k].clone()).collect(),
        from_behind: order.iter().map(|&k| prep.from_behind[k]).collect(),
    };
    let mut layout = solve_in_order(&placing, options, &order);
    // Back to plan order: the placed objects by index, the objects left out in the order of
    // their indices, the score summed in plan order.
    let placed: Vec<bool> = {
        let mut v = vec![false; order.len()];
        for f in &layout.floor {
            v[f.index] = true;
        }
        v
    };
    let mut unplaced: Vec<(usize, super::Unplaced)> = (0..order.len())
        .filter(|&i| !placed[i])
        .map(|i| order[i])
        .zip(std::mem::take(&mut layout.unplaced))
        .collect();
    unplaced.sort_by_key(|(k, _)| *k);
    layout.unplaced = unplaced.into_iter().map(|(_, u)| u).collect();
    for f in &mut layout.floor {
        f.index = order[f.index];
    }
    layout.floor.sort_by_key(|f| f.index);
    layout.score = layout.floor.iter().map(|f| f.score).sum();
    for (k, _) in &mut layout.pinned_breaks {
        *k = order[*k];
    }
    layout.pinned_breaks.sort_by_key(|(k, _)| *k);
    layout
}

/// Runs the search over `prep`'s objects in their order; `order` gives each one's index in
/// plan order (its candidates' tie-breaking order is drawn from it).
fn solve_in_order(prep: &Prepared<'_>, options: &SolveOptions, order: &[usize]) -> RoomLayout {
    let n = prep.problem.objects.len();
    let mut statics = Vec::with_capacity(n);
    let mut static_fails = Vec::with_capacity(n);
    // Objects alike get the same grid: worked out once for them all.
    let mut grids: FxHashMap<StaticGridKey, Rc<SharedGrid>> = FxHashMap::default();
    for (k, &plan_index) in order.iter().enumerate().take(n) {
        if crate::cancel::requested() {
            return RoomLayout::default();
        }
        let grid = grids
            .entry(static_grid_key(prep, k))
            .or_insert_with(|| Rc::new(SharedGrid::new(prep, k)));
        static_fails.push(grid.fails.clone());
        statics.push(StaticSet::new(Rc::clone(grid), plan_index, options.seed));
    }
    run(prep, options, statics, static_fails)
}

/// A shared grid (by its address, which only tells grids apart) and what
/// [`Search::room_left_static`] reads of an object ([`Search::room_signature`]).
type RoomKey = (usize, Vec<u64>);

/// The search over objects from their static candidates.
fn run(
    prep: &Prepared<'_>,
    options: &SolveOptions,
    statics: Vec<StaticSet>,
    static_fails: Vec<BTreeMap<HardRule, usize>>,
) -> RoomLayout {
    let n = prep.problem.objects.len();
    // Lexicographic objective: placed objects, then satisfied relations, then graded score.
    let graded_max: f64 = prep.problem.objects.iter().map(super::max_score).sum();
    let relations: usize = prep.problem.objects.iter().map(|o| o.constraints.len()).sum();
    let sat_value = graded_max + 1.0;
    let placed_value = sat_value * (relations as f64 + 1.0);
    let mut remaining_max = vec![0.0; n + 1];
    for k in (0..n).rev() {
        let obj = &prep.problem.objects[k];
        remaining_max[k] =
            remaining_max[k + 1] + placed_value + sat_value * obj.constraints.len() as f64;
    }
    let mut dependents: Vec<Vec<Dependent>> = vec![Vec::new(); n];
    let aisle = prep.reach.aisle();
    for (j, obj) in prep.problem.objects.iter().enumerate() {
        for c in &obj.constraints {
            let side = is_side_relation(c.kind);
            let along_wall = c.kind == RelationKind::Near && near_along_wall(prep.problem, j, c);
            if !(side || along_wall) || c.target >= j {
                continue;
            }
            // `near` between two objects against the walls looks ahead as `side of`: the later
            // one needs a free piece of wall beside its target (a plant beside its shelf).
            let kind = if along_wall { RelationKind::SideOf } else { c.kind };
            // The gaps every relation of the object to this target means, intersected.
            let mut gaps = (0.0, f64::INFINITY);
            for other in obj.constraints.iter().filter(|o| o.target == c.target) {
                let m = super::meaning_of(prep.problem, j, other);
                gaps.0 = f64::max(gaps.0, m.min_gap);
                gaps.1 = gaps.1.min(m.max_gap);
            }
            // In front of its target, beyond the target's use-clearance it may not enter.
            if kind == RelationKind::InFrontOf {
                if let Some(clear) = kept_out_of(prep, j, c.target) {
                    gaps.0 = gaps.0.max(clear);
                }
            }
            if gaps.1 < gaps.0 {
                gaps.1 = gaps.0;
            }
            gaps.1 = gaps.1.min(constraints::SIDE_MAX_M.max(gaps.0));
            let ring = c.kind == RelationKind::Around
                && super::meaning_of(prep.problem, j, c).ring.is_some();
            let beyond = if drawn_up(prep.problem, j, c) { aisle } else { 0.0 };
            let reach = beyond;
            dependents[c.target].push(Dependent { object: j, kind, gaps, ring, beyond, reach });
        }
    }
    // A dependent's zone reaches as far out as its chain needs.
    let mut memo = FxHashMap::default();
    for t in (0..n).rev() {
        for i in 0..dependents[t].len() {
            let d = dependents[t][i];
            if d.ring {
                continue;
            }
            let depth = chain_depth(prep.problem, &dependents, t, &d, &mut memo);
            let size = prep.problem.objects[d.object].size;
            let side = size[0].min(size[1]);
            dependents[t][i].reach = d.beyond.max(depth - side);
        }
    }
    // A chair drawn up to a desk stands between the desk and what else stands out that way
    // (the row of desks behind): that object's zone starts beyond the chair and its way.
    for list in &mut dependents {
        let chairs: Vec<(RelationKind, f64)> = list
            .iter()
            .filter(|d| d.beyond > 0.0 && !d.ring)
            .map(|d| {
                let size = prep.problem.objects[d.object].size;
                (d.kind, d.gaps.0 + size[0].min(size[1]) + d.reach)
            })
            .collect();
        for d in list.iter_mut().filter(|d| d.beyond == 0.0 && !d.ring) {
            for &(kind, out) in &chairs {
                if kind == d.kind && out > d.gaps.0 {
                    d.gaps.0 = out;
                    d.gaps.1 = d.gaps.1.max(out);
                }
            }
        }
    }
    let rings: Vec<Option<constraints::SeatRing>> = (0..n)
        .map(|t| {
            if dependents[t].iter().any(|d| d.ring) {
                super::seat_ring(prep.problem, t)
            } else {
                None
            }
        })
        .collect();
    let seat_offsets = rings
        .iter()
        .enumerate()
        .map(|(t, ring)| {
            let size = prep.problem.objects[t].size;
            ring.as_ref().map(|r| Rot::ALL.map(|rot| constraints::seat_offsets(rot, size, r)))
        })
        .collect();
    let mut search = Search {
        dependents,
        rings,
        seat_offsets,
        prep,
        placed_value,
        sat_value,
        statics: Vec::with_capacity(n),
        static_fails,
        remaining_max,
        budget: options.node_budget.min(super::MAX_NODE_BUDGET),
        seed: options.seed,
        nodes: 0,
        best: None,
        kept: None,
        anchor: prep.problem.objects.iter().position(|o| o.pin.is_none()),
        conflict: None,
        found_at: 0,
        pin_breaks: Vec::new(),
        anywhere: RefCell::new(vec![None; n]),
        contexts: RefCell::new(FxHashMap::default()),
        derived_pieces: RefCell::new(FxHashMap::default()),
        touch_answers: RefCell::new(FxHashMap::default()),
        flush_answers: RefCell::new(FxHashMap::default()),
        reach_answers: FxHashMap::default(),
        node_answers: FxHashMap::default(),
        reach_bases: Vec::new(),
    };
    // What a candidate leaves for later objects with nothing placed depends on the grid and
    // on the later objects' relations: objects alike with alike dependents (the desks of a
    // row) share it, worked out once in the grid's order.
    let mut room_by_grid: FxHashMap<RoomKey, Vec<(u8, u8)>> = FxHashMap::default();
    for (k, mut set) in statics.into_iter().enumerate() {
        let key = (Rc::as_ptr(&set.grid) as usize, search.room_signature(k));
        let by_grid = room_by_grid.entry(key).or_insert_with(|| {
            set.grid.cands.iter().map(|c| search.room_left_static(k, c)).collect()
        });
        let mut room_static = vec![(0, 0); set.len()];
        for (g, &at) in set.pos_of.iter().enumerate() {
            room_static[at as usize] = by_grid[g];
        }
        set.room_static = room_static;
        set.room_max = set.room_static.iter().fold((0, 0), |m, r| (m.0.max(r.0), m.1.max(r.1)));
        search.statics.push(set);
    }
    let mut st = State {
        poses: vec![None; n],
        fps: Vec::new(),
        grid: FootprintGrid::new(&prep.room.bounds, Vec::new()),
        objs: Vec::new(),
        occ: prep.reach.occupancy(),
        value: 0.0,
        fails: vec![None; n],
        by: vec!["dfs"; n],
    };
    for disc in 0..=MAX_DISCREPANCY {
        search.visit(0, disc, &mut st);
        if search.out_of_budget() {
            break;
        }
    }
    let nodes = search.nodes;
    let pin_breaks = std::mem::take(&mut search.pin_breaks);
    // `edge` is soft: an edge object that no wall pose could take is stood elsewhere, its
    // `edge` reported as not kept (done for every layout kept, see `Search::finish`).
    let best = match search.kept.take() {
        Some((best, _)) => best,
        None => {
            search.finish(&mut st);
            st
        }
    };
    let mut layout = RoomLayout { nodes, found_at: search.found_at, ..RoomLayout::default() };
    for k in 0..n {
        let obj = &prep.problem.objects[k];
        if let Some(pose) = best.poses[k] {
            {
                let (reports, score) =
                    measure_object(prep.problem, &prep.room, k, &pose, &best.poses);
                layout.score += score;
                let tag = best.by[k];
                layout.floor.push(PlacedFloor {
                    index: k,
                    pose,
                    footprint: footprint(&pose, obj.size),
                    constraints: reports,
                    score,
                    by: tag,
                });
            }
        } else {
            {
                let (rule, reason) = best.fails[k]
                    .clone()
                    .unwrap_or((HardRule::NoOverlap, "no pose left by the search".to_string()));
                layout.unplaced.push(Unplaced {
                    id: obj.id.clone(),
                    kind: "floor",
                    rule: Some(rule),
                    reason,
                    code: crate::diag::Code::W0501,
                });
            }
        }
    }
    for (k, rule) in pin_breaks {
        layout.pinned_breaks.push((k, rule));
    }
    layout
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::solve::{FloorObject, ProblemConstraint, Role, RoomProblem};
    use proptest::prelude::*;

    /// Test object `k`: its size, whether it stands against a wall, its role and its relations
    /// (kind, target).
    fn object(
        k: usize,
        size: [f64; 2],
        edge: bool,
        role: Role,
        relations: &[(RelationKind, usize)],
    ) -> FloorObject {
        FloorObject {
            id: format!("obj-{k}"),
            size,
            height: 0.8,
            global: if edge { GlobalKind::Edge } else { GlobalKind::Middle },
            role,
            constraints: relations
                .iter()
                .map(|&(kind, target)| ProblemConstraint {
                    kind,
                    written: kind,
                    implied: false,
                    target,
                    span: None,
                })
                .collect(),
            pin: None,
            thor_type: None,
            span: None,
        }
    }

    /// A room of objects `(size, edge, pinned, targets)`.
    fn problem(objects: &[([f64; 2], bool, bool, Vec<usize>)]) -> RoomProblem {
        let objects = objects
            .iter()
            .enumerate()
            .map(|(k, (size, edge, pinned, targets))| {
                let near: Vec<_> = targets.iter().map(|&t| (RelationKind::Near, t)).collect();
                FloorObject {
                    pin: pinned.then_some(Pose { x: 1.0, z: 1.0, rot: Rot::R0 }),
                    ..object(k, *size, *edge, Role::Other, &near)
                }
            })
            .collect();
        RoomProblem {
            name: "order".into(),
            outline: vec![[0.0, 0.0], [0.0, 5.0], [5.0, 5.0], [5.0, 0.0]],
            wall_height: 2.7,
            keep_out: Vec::new(),
            walls: Vec::new(),
            objects,
            wall_objects: Vec::new(),
            small_objects: Vec::new(),
            ceiling: None,
            span: None,
        }
    }

    #[test]
    fn groups_go_pinned_first_then_the_most_floor_first() {
        let p = problem(&[
            ([0.4, 0.4], true, false, vec![]),      // 0: a plant (0.16 m²)
            ([1.0, 0.4], true, false, vec![]),      // 1: a shelf
            ([0.4, 0.4], true, false, vec![1]),     // 2: its plant (with it 0.56 m²)
            ([1.2, 0.8], false, false, vec![]),     // 3: a table
            ([0.5, 0.5], false, false, vec![3]),    // 4: its chair
            ([2.0, 0.9], true, false, vec![]),      // 5: a sofa
            ([0.5, 0.5], false, false, vec![5]),    // 6: its coffee table
            ([0.6, 0.6], false, false, vec![]),     // 7: an armchair on its own (0.36 m²)
            ([0.3, 0.3], true, true, vec![]),       // 8: a pinned lamp
            ([0.5, 0.5], false, false, vec![3, 5]), // 9: joins the table's group to the sofa's
        ]);
        // The lamp; the table's group, joined to the sofa's by 9 (3.51 m², in plan order); the
        // shelf and its plant; the armchair; the plant alone.
        assert_eq!(placement_order(&p), vec![8, 3, 4, 5, 6, 9, 1, 2, 7, 0]);
        // Nothing to reorder: plan order.
        let q = problem(&[([1.0, 1.0], true, false, vec![]), ([0.5, 0.5], true, false, vec![0])]);
        assert_eq!(placement_order(&q), vec![0, 1]);
    }

    /// One object of a test room: its size, whether it stands against a wall, its role and its
    /// relations (kind, target).
    type TestObject = ([f64; 2], bool, Role, Vec<(RelationKind, usize)>);

    /// A room of objects, 6 m by 5 m.
    fn problem_with(objects: &[TestObject]) -> RoomProblem {
        let mut p = problem(&[]);
        p.outline = vec![[0.0, 0.0], [0.0, 5.0], [6.0, 5.0], [6.0, 0.0]];
        p.objects = objects
            .iter()
            .enumerate()
            .map(|(k, (size, edge, role, relations))| object(k, *size, *edge, *role, relations))
            .collect();
        p
    }

    /// Every pose, the unplaced and the nodes of a layout, to compare two to the bit.
    fn layout_bits(l: &RoomLayout) -> String {
        use std::fmt::Write as _;
        let mut out = format!("nodes {} found {} score {:?}\n", l.nodes, l.found_at, l.score);
        for f in &l.floor {
            let _ = writeln!(out, "{} {:?} {:?} {:?}", f.index, f.pose.x, f.pose.z, f.pose.rot);
        }
        for u in &l.unplaced {
            let _ = writeln!(out, "unplaced {} {}", u.id, u.reason);
        }
        out
    }

    const KINDS: [RelationKind; 9] = [
        RelationKind::Near,
        RelationKind::SideOf,
        RelationKind::InFrontOf,
        RelationKind::Behind,
        RelationKind::LeftOf,
        RelationKind::FaceTo,
        RelationKind::FaceSameAs,
        RelationKind::CenterAligned,
        RelationKind::Around,
    ];
    const ROLES: [Role; 5] = [Role::Other, Role::Seat, Role::Table, Role::Desk, Role::Screen];

    proptest! {
        #![proptest_config(ProptestConfig { cases: 48, rng_seed: proptest::test_runner::RngSeed::Fixed(0x7469_6572), ..ProptestConfig::default() })]
        /// The tiers of a target context (candidates beyond reach of a relation met only when
        /// the walk comes down to them) change no layout: the same poses, nodes and score as
        /// with every candidate worked out.
        #[test]
        fn tiers_change_no_layout(
            objects in prop::collection::vec(
                ((0.3f64..1.6, 0.3f64..1.6), prop::bool::weighted(0.3), 0usize..5,
                 prop::collection::vec((0usize..9, any::<prop::sample::Index>()), 0..3)),
                2..10,
            ),
            seed in 0u64..4,
        ) {
            let objects: Vec<_> = objects
                .iter()
                .enumerate()
                .map(|(k, ((w, d), edge, role, relations))| {
                    let relations = if k == 0 {
                        Vec::new()
                    } else {
                        relations.iter().map(|(kind, t)| (KINDS[*kind], t.index(k))).collect()
                    };
                    ([*w, *d], *edge, ROLES[*role], relations)
                })
                .collect();
            let p = problem_with(&objects);
            let options = SolveOptions { seed, node_budget: 150, ..SolveOptions::default() };
            let tiered = crate::solve::solve_room(&p, &options).value;
            WHOLE_CONTEXTS.with(|w| w.set(true));
            let whole = crate::solve::solve_room(&p, &options).value;
            WHOLE_CONTEXTS.with(|w| w.set(false));
            prop_assert_eq!(layout_bits(&tiered), layout_bits(&whole));
        }
    }

    proptest! {
        #![proptest_config(ProptestConfig { cases: 200, rng_seed: proptest::test_runner::RngSeed::Fixed(0x6f72_6465), ..ProptestConfig::default() })]
        /// Every object once, every relation's target before the object that refers to it, a
        /// group's objects one after the other in plan order, pinned groups first.
        #[test]
        fn the_placement_order_keeps_targets_first_and_groups_whole(
            objects in prop::collection::vec(
                ((0.3f64..2.0, 0.3f64..2.0), any::<bool>(), prop::bool::weighted(0.1), prop::collection::vec(any::<prop::sample::Index>(), 0..3)),
                0..24,
            ),
        ) {
            let objects: Vec<([f64; 2], bool, bool, Vec<usize>)> = objects
                .into_iter()
                .enumerate()
                .map(|(k, ((w, d), edge, pin, ts))| {
                    let targets = if k == 0 { Vec::new() } else { ts.iter().map(|t| t.index(k)).collect() };
                    ([w, d], edge, pin, targets)
                })
                .collect();
            let p = problem(&objects);
            let order = placement_order(&p);
            let mut sorted = order.clone();
            sorted.sort_unstable();
            prop_assert_eq!(sorted, (0..objects.len()).collect::<Vec<_>>());
            let mut at = vec![0; order.len()];
            for (i, &k) in order.iter().enumerate() {
                at[k] = i;
            }
            for (k, (_, _, _, targets)) in objects.iter().enumerate() {
                for &t in targets {
                    prop_assert!(at[t] < at[k], "{} before its target {}", k, t);
                }
            }
            // A pinned object's group before every group without one.
            let pinned_at = order.iter().rposition(|&k| objects[k].2);
            if let Some(last_pin) = pinned_at {
                // Everything up to the last pin is in a group with a pin: an object with no
                // relation and no pin cannot come before it.
                for &k in &order[..last_pin] {
                    let alone = objects[k].3.is_empty() && !objects[k].2
                        && !objects.iter().any(|o| o.3.contains(&k));
                    prop_assert!(!alone, "{} alone before a pinned group", k);
                }
            }
            // Each group (objects joined by relations) one run, in plan order.
            let mut label: Vec<usize> = (0..objects.len()).collect();
            loop {
                let mut changed = false;
                for (k, o) in objects.iter().enumerate() {
                    for &t in &o.3 {
                        let m = label[k].min(label[t]);
                        if label[k] != m || label[t] != m {
                            label[k] = m;
                            label[t] = m;
                            changed = true;
                        }
                    }
                }
                if !changed {
                    break;
                }
            }
            let mut seen = Vec::new();
            for w in order.windows(2) {
                if label[w[0]] == label[w[1]] {
                    prop_assert!(w[0] < w[1], "{} after {} in one group", w[1], w[0]);
                } else {
                    seen.push(label[w[0]]);
                    prop_assert!(!seen.contains(&label[w[1]]), "group of {} split", w[1]);
                }
            }
        }
    }
}

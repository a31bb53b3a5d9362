//! Geometric repair of a floor plan: the fewest and smallest corner movements that turn a
//! plan the plan stage rejects (rooms that overlap by a little, leave gaps, have slanted or
//! doubled edges, float apart or meet only at a corner) into one it accepts, before any model
//! is asked again. Doors and windows are read (a door needs its rooms to share a wall), never
//! moved.
//!
//! A plan's *badness* is what the plan stage says about its geometry
//! ([`super::PlanOptions::geometry_only`]): its errors other than a missing exterior door, an
//! unreachable room or an unknown asset, and its gaps between facing rooms (W0308). A plan
//! without either comes back unchanged. Otherwise:
//!
//! 0. **Jitter snapped onto shared lines** (`jitter.rs`), when outlines in at least two rooms
//!    have slanted edges: nearly straight edges, facing walls and walls continuing one another
//!    within twice [`MAX_JITTER_M`] become one line each, before any room moves; the snapped
//!    plan is kept when it is never worse and better (see step 3).
//! 1. **Outline clean-up**, of outlines with a repeated corner or a slanted edge: repeated
//!    corners and corners in the middle of a straight wall are dropped; an edge slanted by at
//!    most [`MAX_MOVE_M`] is made straight by moving the corner whose coordinate no nearby room
//!    shares (the other one is aligned with the rooms around it; a room far off on the same
//!    line does not count); when both are, the one whose neighbour's wall runs along more of
//!    the edge stays (the room across it, not a room met at its end); otherwise the rounder
//!    coordinate stays (`5` rather than `5.3`).
//! 2. **One room moved back whole**: the *suspects* (rooms that overlap another, leave a gap
//!    to another, touch no room, or do not touch a room they have a door to) are tried at
//!    every translation that puts one of their wall coordinates onto a wall coordinate of a
//!    nearby room: at most [`MAX_MOVE_M`] along each axis, or [`MAX_TRANSLATION_M`] in all for
//!    a room apart from a room it has a door to. A translation counts only when it leaves
//!    fewer of the room's wall coordinates off the other rooms' lines than it had (the room
//!    goes back onto the plan's lines, not along them) and makes none of them less round
//!    unless it lands on a line (a wall drawn at `8` with nothing beside it stays at `8`: the
//!    other wall was drawn wrong, and step 3 moves that one alone). The candidates go in the
//!    order of: within [`MAX_MOVE_M`] first, the near misses they leave (see below), the
//!    room's coordinates left off the lines, the distance moved, whether the plan's lowest x
//!    and z stay (the drawing's origin), the roundness of the new coordinates, then the room's
//!    outline and the move, so that the order rooms are declared in does not matter. The
//!    first that makes the plan clean (no error, no gap) is a candidate repair.
//!    **Or one room redrawn onto the lines**: a suspect none of whose walls is on another
//!    room's line may be drawn too large or too small rather than shifted. Along each axis its
//!    first and last wall each stay, go onto the nearest line on either side (at most
//!    [`MAX_MOVE_M`]), or move as the opposite wall does when that one goes onto a line,
//!    mirrored (the room scaled back about its centre, so an outer wall with nothing beside it
//!    follows); the walls between follow in proportion, so an L-shaped room keeps its shape.
//!    These go in the order of: walls left off the lines, the largest wall move, whether the
//!    walls that move all move as far, whether the plan's origin stays, roundness, the sum of
//!    the moves, then the room declared later. Of the two candidate repairs, the one that
//!    leaves fewer walls of the plan off the lines wins (the move back whole on a tie); no
//!    other room moves. A room redrawn onto the lines, or scaled back, fills the place the plan
//!    has for it and is exempt from the area bound.
//! 3. Otherwise, **repair steps**, at most [`MAX_STEPS`], each from the plan the last one left.
//!    The candidates of a step are:
//!    - *one room at a time*: for every room, each of its wall coordinates snapped onto a
//!      facing wall of another room at most [`MAX_MOVE_M`] away (one or two per axis), or the
//!      whole room moved by the distance that makes one of its walls meet a facing wall, by
//!      the gap to a room it has a door to (at most [`MAX_TRANSLATION_M`]), or slid along the
//!      wall of a room it has a door to but meets only at a corner (0.5 m, 1 m, the least
//!      distance that gives its doors the wall they need, or [`MAX_SLIDE_M`]);
//!    - *two rooms at once*, for a room that meets the room it has a door to only at a corner
//!      when their doors need more than [`MAX_TRANSLATION_M`] of wall: both slid half the way,
//!      or one slid a metre and the other's facing wall moved the rest;
//!    - *every room at once*: facing walls of different rooms within the bound joined, each
//!      group at the coordinate that moves the least length of wall, then detached rooms moved
//!      onto the room they have a door to.
//!
//!    A candidate counts only when it is *never worse*: each error after it was there before
//!    (the same kinds, no more of each) and it has fewer errors, or as many and fewer gaps.
//!    Among those, the least bad wins; among equally bad ones, the one that moves no corner
//!    more than [`MAX_TRANSLATION_M`], then the one that moves the fewest rooms, then leaves the fewest near misses (wall coordinates of neighbouring rooms less
//!    than the bound apart but not equal), then takes away the least wall rooms shared, then
//!    moves the fewest corners, then sweeps the least floor; the last tie goes to the room
//!    declared later (as W0308's fix: an answer is drawn room after room, each fitted to those
//!    before). A room whose walls already meet its neighbours' therefore stays, whatever the
//!    order the rooms are declared in, and a room never becomes narrower than
//!    [`super::MIN_ROOM_SIDE_M`] (that is an error, E0303).
//!
//! The result is kept only when every room's area changes by at most [`MAX_AREA_CHANGE`] (a
//! room narrower than [`super::MIN_ROOM_SIDE_M`] as written is exempt: it must grow; so is a
//! room whose every wall ends on another room's line, or the room step 2 scaled back) and
//! the whole repair is never worse than the plan as written; otherwise the plan is returned as
//! written. Steps go on until no candidate improves the plan, so repairing a repaired plan
//! (even one still with errors) changes nothing: repair is idempotent (a plan repaired by
//! step 2 is clean, so it comes back unchanged). What it cannot fix is left for the plan stage
//! to report.
//!
//! A plan of more than [`MAX_REPAIR_ROOMS`] rooms is left as written (W0309). The whole repair
//! is bounded by [`MAX_REPAIR_WORK`] (W0309 when reached), and a room's
//! candidate moves per axis by `MAX_AXIS_CANDIDATES`, the nearest first, so that a room with
//! many walls gives candidates in proportion to its walls, not their square.

mod jitter;

use std::collections::BTreeMap;

pub use jitter::MAX_JITTER_M;

use crate::check::scene::{DoorSide, Scene};
use crate::diag::{Code, Diagnostic, Fix, Outcome};
use crate::resolve::structure::StructureCatalog;

/// The most a corner moves to close a gap, remove an overlap or straighten an edge, metres.
pub const MAX_MOVE_M: f64 = 0.5;
/// The most a detached room is moved, whole, to meet its neighbour, metres.
pub const MAX_TRANSLATION_M: f64 = 1.0;
/// The most a room is slid along the wall of a room it has a door to but meets only at a
/// corner, metres.
pub const MAX_SLIDE_M: f64 = 1.5;
/// The most a room's floor area changes in a repair, as a share of its area as written.
pub const MAX_AREA_CHANGE: f64 = 0.4;
/// The most repair steps (see the module documentation).
pub const MAX_STEPS: usize = 8;
/// Facing walls overlapping along their length by less than this are not a gap, metres.
const MIN_GAP_FACE_M: f64 = 0.1;
/// Coordinates closer than this are the same, metres.
const SAME_M: f64 = 1e-6;
/// The side of the cells [`facing_gaps`] finds nearby rooms by, metres.
const GAP_GRID_CELL_M: f64 = 4.0;
/// How far beyond a room's box [`facing_gaps`] looks, besides the move, metres: far more than
/// its tolerances ([`SAME_M`]).
const GAP_GRID_MARGIN_M: f64 = 1e-3;

/// The most work a repair does, in corners handled: each candidate plan built and each plan
/// the plan stage judges costs its number of corners (a judged plan `JUDGE_COST` times
/// over). A repair that reaches it stops where it is (W0309): the work of a repair is bounded
/// whatever the plan, about a second on the slowest plans measured.
pub const MAX_REPAIR_WORK: u64 = 2_500_000;
/// The most rooms a plan may have for the repair to try it (W0309 otherwise): a house has tens.
pub const MAX_REPAIR_ROOMS: usize = 500;
/// How many times its corners a plan the plan stage judges counts in [`MAX_REPAIR_WORK`].
const JUDGE_COST: u64 = 20;
/// The most candidate moves of one room along one axis (the nearest first): rooms with many
/// walls (a staircase) would otherwise give candidates in the square of their walls.
const MAX_AXIS_CANDIDATES: usize = 24;

/// A room with more corners than this (not a rectangle, an L or a T) gets at most
/// [`MANY_CORNERS_OPTIONS`] options per axis in a repair step.
const MANY_CORNERS: usize = 16;
/// See [`MANY_CORNERS`].
const MANY_CORNERS_OPTIONS: usize = 6;
/// The share of [`MAX_REPAIR_WORK`] that moving one room back whole or redrawing it onto the
/// lines may spend, so that the repair steps after them keep the rest.
const ONE_ROOM_SHARE: u64 = 2;

/// The work a repair has done, against [`MAX_REPAIR_WORK`].
#[derive(Debug)]
struct Work {
    spent: u64,
    limit: u64,
    /// The bound of the current phase (at most `limit`).
    phase: u64,
}

impl Work {
    /// Counts `units` of work; whether the repair (and its phase) may go on.
    fn spend(&mut self, units: usize) -> bool {
        self.spent = self.spent.saturating_add(units as u64);
        self.spent <= self.limit.min(self.phase)
    }

    /// Starts a phase that may spend at most `share` more.
    fn start_phase(&mut self, share: u64) {
        self.phase = self.spent.saturating_add(share);
    }

    /// Ends the current phase: the whole bound applies again.
    fn end_phase(&mut self) {
        self.phase = u64::MAX;
    }

    /// Counts a plan judged by the plan stage; whether the repair may go on.
    fn judge(&mut self, rooms: &[Vec<[f64; 2]>]) -> bool {
        self.spend(corner_count(rooms).saturating_mul(JUDGE_COST as usize))
    }

    fn exhausted(&self) -> bool {
        self.spent > self.limit
    }
}

fn corner_count(rooms: &[Vec<[f64; 2]>]) -> usize {
    rooms.iter().map(Vec::len).sum()
}

/// The work of weighing one candidate that changes room `r`: every corner of the plan, and
/// each corner of `r` against each corner of the rooms near it (their shared walls, overlaps
/// and near misses are measured pair by pair).
fn candidate_work(rooms: &[Vec<[f64; 2]>], r: usize) -> usize {
    let near: usize = rooms_near(rooms, r).map(Vec::len).sum();
    corner_count(rooms).saturating_add(rooms[r].len().saturating_mul(near))
}

/// The repaired outlines, one per room of the scene, and whether anything moved.
#[derive(Clone, Debug, PartialEq)]
pub struct Repair {
    /// Per room, in scene order: the corners after repair, metres.
    pub corners: Vec<Vec<[f64; 2]>>,
    /// Whether any corner moved.
    pub changed: bool,
    /// The largest distance any corner moved, metres.
    pub max_move_m: f64,
    /// The largest distance any wall moved (a corner's larger change of x or z), metres: the
    /// figure the bounds limit.
    pub max_wall_move_m: f64,
}

/// Repairs the scene's floor plan (see the module documentation). Each room that changed gets
/// one warning W0307 listing its moves, with a fix per corner that rewrites it.
pub fn repair(scene: &Scene, catalog: &StructureCatalog) -> Outcome<Repair> {
    let original: Vec<Vec<[f64; 2]>> = scene.rooms.iter().map(|r| r.corners.clone()).collect();
    let unchanged =
        Repair { corners: original.clone(), changed: false, max_move_m: 0.0, max_wall_move_m: 0.0 };
    if scene.rooms.is_empty() {
        return Outcome::new(unchanged, Vec::new());
    }
    let before = Badness::of(scene, &original, catalog);
    if before.is_clean() {
        return Outcome::new(unchanged, Vec::new());
    }
    // Several of the steps weigh every pair of rooms: a plan of thousands of rooms (no house
    // has them; a runaway answer or a hostile file does) is left as written, at once.
    if scene.rooms.len() > MAX_REPAIR_ROOMS {
        let mut d = Diagnostic::new(
            Code::W0309,
            format!(
                "the floor-plan repair does not try a plan of {} rooms (at most {MAX_REPAIR_ROOMS})",
                scene.rooms.len()
            ),
        )
        .with_help("the plan is left as written; the plan stage reports what is wrong with it")
        .with_note("the bound keeps every repair under about a second, whatever the plan");
        if let Some(room) = scene.rooms.first() {
            d = d.with_primary(room.name_span, "the plan starts here");
        }
        return Outcome::new(unchanged, vec![d]);
    }
    let mut work = Work { spent: 0, limit: MAX_REPAIR_WORK, phase: u64::MAX };
    let mut state = State {
        rooms: original.clone(),
        // For each repaired corner, the index of the corner as written it comes from.
        origins: original.iter().map(|c| (0..c.len()).collect()).collect(),
    };
    // Jitter (slanted edges in several rooms) is snapped onto the plan's lines before any room
    // moves, so that rooms that nearly share a wall share it.
    if jitter::jittered(&state.rooms) {
        let mut snapped = state.clone();
        snapped.rooms = jitter::snap(&state.rooms);
        for r in 0..snapped.rooms.len() {
            if needs_cleaning(&snapped.rooms[r]) {
                let others = other_coordinates(&snapped.rooms, r);
                let walls = nearby_walls(&snapped.rooms, r);
                clean_outline(&mut snapped.rooms[r], &mut snapped.origins[r], &others, &walls);
            }
        }
        work.judge(&snapped.rooms);
        if Badness::of(scene, &snapped.rooms, catalog).improves_on(&before) {
            state = snapped;
        }
    }
    // Only outlines that need it are cleaned: a room with a corner on a straight wall (the
    // plan stage accepts those) and nothing else wrong stays as written.
    for r in 0..state.rooms.len() {
        if needs_cleaning(&state.rooms[r]) {
            let others = other_coordinates(&state.rooms, r);
            let walls = nearby_walls(&state.rooms, r);
            clean_outline(&mut state.rooms[r], &mut state.origins[r], &others, &walls);
        }
    }
    let mut bad = Badness::of(scene, &state.rooms, catalog);
    // The room, if any, refitted into the place the plan has for it (exempt from the area
    // bound).
    let mut area_exempt: Option<usize> = None;
    // A room drawn off as a whole goes back whole, and alone, when that is enough.
    if !bad.is_clean() {
        // A room none of whose walls is on the plan's lines may be drawn too large or too
        // small rather than shifted: of the two, the plan with fewer walls off the lines wins
        // (the move back whole on a tie).
        work.start_phase(MAX_REPAIR_WORK / ONE_ROOM_SHARE / 2);
        let back =
            move_one_room_back(scene, &state.rooms, catalog, &mut work).map(|rooms| (rooms, None));
        work.start_phase(MAX_REPAIR_WORK / ONE_ROOM_SHARE / 2);
        let fit = fit_one_room_to_lines(scene, &state.rooms, catalog, &mut work);
        work.end_phase();
        let chosen = match (back, fit) {
            (Some(back), Some(fit)) => {
                Some(if walls_off_lines(&fit.0) < walls_off_lines(&back.0) { fit } else { back })
            }
            (back, fit) => back.or(fit),
        };
        if let Some((rooms, exempt)) = chosen {
            area_exempt = exempt;
            state.rooms = rooms;
            bad = Badness::of(scene, &state.rooms, catalog);
        }
    }
    for _ in 0..MAX_STEPS {
        if bad.is_clean() || work.exhausted() {
            break;
        }
        match best_step(scene, &state, &bad, catalog, &mut work) {
            Some((next, next_bad)) => {
                state = next;
                bad = next_bad;
            }
            None => break,
        }
    }
    let rooms = state.rooms;
    let origins = state.origins;
    // Within the area bound, and never worse than the plan as written: otherwise the plan
    // stays as written and the plan stage reports it.
    // A room drawn narrower than the narrowest room allowed (E0303) must grow more than the
    // bound to be a room at all: it is held to the movement bounds only.
    // A room whose every wall ends on another room's line fills the place the plan has for
    // it: it is held to the movement bounds only.
    let coords = room_coordinates(&rooms);
    let within_area = original.iter().zip(&rooms).enumerate().all(|(r, (before, after))| {
        let a0 = area(before);
        let narrow = (0..2).any(|axis| {
            let (lo, hi) = extent(before, axis);
            hi - lo < super::MIN_ROOM_SIDE_M
        });
        a0 <= 0.0
            || narrow
            || area_exempt == Some(r)
            || off_lines(&coords, r) == 0
            || (area(after) - a0).abs() / a0 <= MAX_AREA_CHANGE
    });
    let mut diagnostics = Vec::new();
    if work.exhausted() {
        diagnostics.push(work_bound_reached(scene, &work));
    }
    if !within_area || !bad.improves_on(&before) {
        return Outcome::new(unchanged, diagnostics);
    }

    let mut max_move: f64 = 0.0;
    let mut max_wall_move: f64 = 0.0;
    let mut changed = false;
    for (i, room) in scene.rooms.iter().enumerate() {
        if same_outline(&original[i], &rooms[i]) {
            continue;
        }
        changed = true;
        let moves = describe_moves(&original[i], &rooms[i], &origins[i]);
        max_move = max_move.max(moves.iter().map(|m| m.distance()).fold(0.0, f64::max));
        for change in &moves {
            if let CornerChange::Moved { from, to, .. } = change {
                max_wall_move =
                    max_wall_move.max((to[0] - from[0]).abs().max((to[1] - from[1]).abs()));
            }
        }
        let mut d = Diagnostic::new(
            Code::W0307,
            format!(
                "the outline of room `{}` was repaired: {}",
                room.name,
                summary(&original[i], &rooms[i], &moves)
            ),
        )
        .with_primary(room.name_span, "its corners were moved to fit the other rooms")
        .with_help("review the new corners; `holoc repair --write` writes them into the file");
        for change in &moves {
            d = d.with_note(match *change {
                CornerChange::Moved { from, to, distance } => format!(
                    "({}, {}) → ({}, {}): {distance:.2} m",
                    num(from[0]),
                    num(from[1]),
                    num(to[0]),
                    num(to[1]),
                ),
                CornerChange::Dropped { at, distance } if distance <= SAME_M => format!(
                    "({}, {}) dropped: it repeats a corner or lies on a straight wall",
                    num(at[0]),
                    num(at[1])
                ),
                CornerChange::Dropped { at, distance } => format!(
                    "({}, {}) dropped: the straightened wall passes {distance:.2} m from it",
                    num(at[0]),
                    num(at[1])
                ),
            });
        }
        if let Some(fix) = corner_fix(room, &rooms[i]) {
            d = d.with_fix(fix);
        }
        diagnostics.push(d);
    }
    Outcome::new(
        Repair { corners: rooms, changed, max_move_m: max_move, max_wall_move_m: max_wall_move },
        diagnostics,
    )
}

/// W0309: the repair stopped at its bound on work, at the first room's name.
fn work_bound_reached(scene: &Scene, work: &Work) -> Diagnostic {
    let mut d = Diagnostic::new(
        Code::W0309,
        format!(
            "the floor-plan repair stopped at its bound on work ({} of {} units, {} corners)",
            work.spent.min(work.limit),
            work.limit,
            scene.rooms.iter().map(|r| r.corners.len()).sum::<usize>()
        ),
    )
    .with_help(
        "what the repair found so far is kept when it is better than the plan as written; \
         redraw the rooms the plan stage still reports, with fewer corners",
    )
    .with_note("the bound keeps every repair under about a second, whatever the plan");
    if let Some(room) = scene.rooms.first() {
        d = d.with_primary(room.name_span, "the plan starts here");
    }
    d
}

/// A fix that rewrites the corners of `room` as `corners`: `corners in cm (…)` becomes
/// `corners in m (…)`; `corners (x m, z m)` keeps units on every number.
pub(crate) fn corner_fix(room: &crate::check::scene::Room, corners: &[[f64; 2]]) -> Option<Fix> {
    let (first, last) = (room.corner_spans.first()?, room.corner_spans.last()?);
    let (start, replacement) = match room.corners_unit_span {
        Some(unit) => (
            unit.start,
            format!(
                "m {}",
                corners
                    .iter()
                    .map(|p| format!("({}, {})", num(p[0]), num(p[1])))
                    .collect::<Vec<_>>()
                    .join(" ")
            ),
        ),
        None => (
            first.start,
            corners
                .iter()
                .map(|p| format!("({} m, {} m)", num(p[0]), num(p[1])))
                .collect::<Vec<_>>()
                .join(" "),
        ),
    };
    Some(Fix {
        title: format!("write the repaired corners of `{}`", room.name),
        span: crate::source::Span { file: first.file, start, end: last.end },
        replacement,
    })
}

/// The outlines of a plan being repaired, with, per corner, the index of the corner as
/// written it comes from.
#[derive(Clone, Debug)]
struct State {
    rooms: Vec<Vec<[f64; 2]>>,
    origins: Vec<Vec<usize>>,
}

/// What the plan stage says about a plan's geometry: its errors (codes, sorted) and its gaps
/// between facing rooms (W0308).
#[derive(Clone, Debug, PartialEq, Eq)]
struct Badness {
    errors: Vec<Code>,
    gaps: usize,
}

impl Badness {
    fn of(scene: &Scene, rooms: &[Vec<[f64; 2]>], catalog: &StructureCatalog) -> Badness {
        let mut with = scene.clone();
        for (room, corners) in with.rooms.iter_mut().zip(rooms) {
            room.corners.clone_from(corners);
        }
        let options = super::PlanOptions { geometry_only: true, ..super::PlanOptions::default() };
        let diagnostics = super::plan_with(&with, catalog, options).diagnostics;
        let mut errors: Vec<Code> = diagnostics
            .iter()
            .filter(|d| {
                d.is_error()
                    && !matches!(d.code, Code::E0314 | Code::E0315 | Code::E0313 | Code::E0319)
            })
            .map(|d| d.code)
            .collect();
        errors.sort_by_key(|c| c.as_str());
        let gaps = diagnostics.iter().filter(|d| d.code == Code::W0308).count();
        Badness { errors, gaps }
    }

    fn is_clean(&self) -> bool {
        self.errors.is_empty() && self.gaps == 0
    }

    fn key(&self) -> (usize, usize) {
        (self.errors.len(), self.gaps)
    }

    /// Never worse than `before` (each error was there before, no more of each kind) and
    /// better (fewer errors, or as many and fewer gaps).
    fn improves_on(&self, before: &Badness) -> bool {
        let mut left = before.errors.clone();
        for e in &self.errors {
            match left.iter().position(|b| b == e) {
                Some(i) => {
                    left.remove(i);
                }
                None => return false,
            }
        }
        self.key() < before.key()
    }
}

/// The order among candidates equally bad: whether a corner moves more than
/// [`MAX_TRANSLATION_M`] (a plan's intent is kept within a metre where a candidate can: two
/// rooms meeting at a corner slide half the way each rather than one the whole way), rooms
/// moved, near misses left, shared wall lost (in mm, so that float noise does not decide: a
/// room that shares its walls with the plan stays), corners moved, floor swept (the area
/// between each moved room's old and new outline, in mm², so that a shorter wall moves rather
/// than a longer one), then the sequence number (the room declared last first, then every
/// room at once).
type Cost = (bool, usize, usize, u64, usize, u64, usize);

/// The best next step from `state` (see the module documentation), with its badness; `None`
/// when no candidate improves the plan.
fn best_step(
    scene: &Scene,
    state: &State,
    bad: &Badness,
    catalog: &StructureCatalog,
    work: &mut Work,
) -> Option<(State, Badness)> {
    let mut candidates: Vec<(Cost, State)> = Vec::new();
    let links = door_links(scene, state.rooms.len());
    let needs = door_needs(scene, catalog, &links);
    for r in 0..state.rooms.len() {
        let each = candidate_work(&state.rooms, r);
        // On a true tie the room declared later moves (as W0308's fix has it): an answer is
        // drawn room after room, each fitted to those before.
        let seq = state.rooms.len() - 1 - r;
        for rooms in single_room_candidates(&state.rooms, r, &links, &needs) {
            if !work.spend(each) {
                return None;
            }
            let mut next = state.clone();
            next.rooms = rooms;
            let others = other_coordinates(&next.rooms, r);
            let walls = nearby_walls(&next.rooms, r);
            clean_outline(&mut next.rooms[r], &mut next.origins[r], &others, &walls);
            candidates.push((cost(&state.rooms, &next.rooms, seq), next));
        }
        for (o, rooms) in pair_slide_candidates(&state.rooms, r, &links, &needs) {
            if !work.spend(each + candidate_work(&state.rooms, o)) {
                return None;
            }
            let mut next = state.clone();
            next.rooms = rooms;
            for moved in [r, o] {
                let others = other_coordinates(&next.rooms, moved);
                let walls = nearby_walls(&next.rooms, moved);
                clean_outline(&mut next.rooms[moved], &mut next.origins[moved], &others, &walls);
            }
            candidates.push((cost(&state.rooms, &next.rooms, seq), next));
        }
    }
    {
        let mut next = state.clone();
        share_walls(&mut next.rooms, 0);
        share_walls(&mut next.rooms, 1);
        for r in 0..next.rooms.len() {
            if !same_outline(&next.rooms[r], &state.rooms[r]) || needs_cleaning(&next.rooms[r]) {
                let others = other_coordinates(&next.rooms, r);
                let walls = nearby_walls(&next.rooms, r);
                clean_outline(&mut next.rooms[r], &mut next.origins[r], &others, &walls);
            }
        }
        attach_detached(scene, &mut next.rooms);
        let seq = next.rooms.len();
        candidates.push((cost(&state.rooms, &next.rooms, seq), next));
    }
    candidates.sort_by_key(|a| a.0);
    let overlaps_now = overlap_count(&state.rooms);
    let mut best: Option<((usize, usize), Cost, State, Badness)> = None;
    for (c, next) in candidates {
        if next.rooms.iter().zip(&state.rooms).all(|(a, b)| same_outline(a, b)) {
            continue;
        }
        // A candidate that makes rooms overlap that did not cannot be never worse.
        if overlap_count(&next.rooms) > overlaps_now {
            continue;
        }
        if !work.judge(&next.rooms) {
            break;
        }
        let b = Badness::of(scene, &next.rooms, catalog);
        if !b.improves_on(bad) {
            continue;
        }
        if best.as_ref().is_none_or(|(k, bc, _, _)| (b.key(), c) < (*k, *bc)) {
            let clean = b.is_clean();
            best = Some((b.key(), c, next, b));
            // Candidates come in the order of their cost: the first clean one is the best.
            if clean {
                break;
            }
        }
    }
    best.map(|(_, _, s, b)| (s, b))
}

/// The most plans [`move_one_room_back`] gives to the plan stage.
/// The rooms a repair may move whole (see [`move_one_room_back`]): those that overlap
/// another, leave a gap to another, touch no room or do not touch a room they have a door to;
/// and, of those, the ones apart from a room they have a door to.
fn suspects(scene: &Scene, rooms: &[Vec<[f64; 2]>]) -> (Vec<bool>, Vec<bool>) {
    let n = rooms.len();
    let links = door_links(scene, n);
    let mut suspect = vec![false; n];
    for a in 0..n {
        for b in a + 1..n {
            if overlap(&rooms[a], &rooms[b]) {
                suspect[a] = true;
                suspect[b] = true;
            }
        }
    }
    for gap in facing_gaps(rooms) {
        suspect[gap.moving] = true;
        suspect[gap.staying] = true;
    }
    let mut apart = vec![false; n];
    for r in 0..n {
        for &o in &links[r] {
            if !touch(&rooms[r], &rooms[o]) {
                apart[r] = true;
                suspect[r] = true;
            }
        }
        if !(0..n).any(|o| o != r && touch(&rooms[r], &rooms[o])) {
            suspect[r] = true;
        }
    }
    (suspect, apart)
}

const MAX_WHOLE_MOVES_TRIED: usize = 32;

/// The order among whole-room moves (see [`move_one_room_back`]): beyond [`MAX_MOVE_M`] on an
/// axis, near misses left, the room's wall coordinates left off the other rooms' lines, the
/// distance in mm, whether the plan's lowest x or z moved, the roundness of the room's new
/// coordinates, the room's outline as written (sorted corners, mm), the move (mm).
type WholeMoveOrder = (bool, usize, usize, u64, bool, u32, Vec<(i64, i64)>, [i64; 2]);

/// The plan made clean (no error, no gap) by moving one room whole, or `None` (see the
/// module documentation). Only *suspects* move: rooms that overlap another, leave a gap to
/// another, or do not touch a room they have a door to (or any room). Each suspect is tried
/// at every translation that puts one of its wall coordinates onto a wall coordinate of a
/// nearby room, at most [`MAX_MOVE_M`] along each axis ([`MAX_TRANSLATION_M`] for a room
/// apart from a room it has a door to), and that leaves fewer of its wall coordinates off
/// the other rooms' lines than it had (a room goes back onto the plan's lines, not along
/// them). The candidates go in the order of: within [`MAX_MOVE_M`] first, the near misses
/// they leave, the room's coordinates left off the lines, the distance moved, whether the
/// plan's lowest x and z stay (the drawing's origin), the roundness of the new coordinates,
/// then the room's outline and the move (so that the order rooms are declared in does not
/// matter); the first clean one is taken.
fn move_one_room_back(
    scene: &Scene,
    rooms: &[Vec<[f64; 2]>],
    catalog: &StructureCatalog,
    work: &mut Work,
) -> Option<Vec<Vec<[f64; 2]>>> {
    let n = rooms.len();
    if n < 2 {
        return None;
    }
    let (suspect, apart) = suspects(scene, rooms);
    let coords = room_coordinates(rooms);
    let near_before: Vec<usize> = (0..n)
        .map(|r| (0..n).filter(|&o| o != r).map(|o| pair_near_misses(rooms, &coords, r, o)).sum())
        .collect();
    let off_before: Vec<usize> = (0..n).map(|r| off_lines(&coords, r)).collect();
    let total_before: usize = near_before.iter().sum::<usize>() / 2;
    let lowest = |rs: &[Vec<[f64; 2]>], axis: usize| {
        rs.iter().map(|c| extent(c, axis).0).fold(f64::INFINITY, f64::min)
    };
    let origin = [lowest(rooms, 0), lowest(rooms, 1)];
    let mm = |v: f64| (v * 1e3).round() as i64;
    let mut candidates: Vec<(WholeMoveOrder, usize, [f64; 2])> = Vec::new();
    for r in (0..n).filter(|&r| suspect[r]) {
        let each = candidate_work(rooms, r);
        let bound = if apart[r] { MAX_TRANSLATION_M } else { MAX_MOVE_M };
        let mut deltas: [Vec<f64>; 2] = [vec![0.0], vec![0.0]];
        for (axis, out) in deltas.iter_mut().enumerate() {
            for o in (0..n).filter(|&o| o != r) {
                let g = box_gap(&rooms[r], &rooms[o]);
                if g[0] > bound + SAME_M || g[1] > bound + SAME_M {
                    continue;
                }
                for &v in &coords[r][axis] {
                    for &t in &coords[o][axis] {
                        let d = t - v;
                        if d.abs() > SAME_M && d.abs() <= bound + SAME_M {
                            out.push(d);
                        }
                    }
                }
            }
            out.sort_by(f64::total_cmp);
            out.dedup_by(|a, b| (*a - *b).abs() <= SAME_M);
            nearest_first(out);
        }
        let mut outline: Vec<(i64, i64)> = rooms[r].iter().map(|p| (mm(p[0]), mm(p[1]))).collect();
        outline.sort_unstable();
        for &dx in &deltas[0] {
            for &dz in &deltas[1] {
                if dx.abs() <= SAME_M && dz.abs() <= SAME_M {
                    continue;
                }
                if !work.spend(each) {
                    return None;
                }
                let moved: Vec<[f64; 2]> =
                    rooms[r].iter().map(|p| [p[0] + dx, p[1] + dz]).collect();
                let mut next = rooms.to_vec();
                next[r] = moved;
                if dx.hypot(dz) > bound + SAME_M
                    || (0..n).any(|o| o != r && overlap(&next[r], &next[o]))
                {
                    continue;
                }
                let next_coords = {
                    let mut c = coords.clone();
                    c[r] = room_coordinates(&next[r..=r]).swap_remove(0);
                    c
                };
                // The room's wall coordinates off the plan's lines: a move must leave fewer
                // than there were (a room goes back onto the lines, not along them).
                let off = off_lines(&next_coords, r);
                if off >= off_before[r] || !keeps_roundness(&coords, r, [dx, dz]) {
                    continue;
                }
                let near_after: usize = (0..n)
                    .filter(|&o| o != r)
                    .map(|o| pair_near_misses(&next, &next_coords, r, o))
                    .sum();
                let near = total_before + near_after - near_before[r];
                let origin_moved = (lowest(&next, 0) - origin[0]).abs() > SAME_M
                    || (lowest(&next, 1) - origin[1]).abs() > SAME_M;
                let round: u32 =
                    next_coords[r].iter().flatten().map(|&v| roundness(v)).sum::<u32>();
                let order = (
                    dx.abs().max(dz.abs()) > MAX_MOVE_M + SAME_M,
                    near,
                    off,
                    (dx.hypot(dz) * 1e3).round() as u64,
                    origin_moved,
                    round,
                    outline.clone(),
                    [mm(dx), mm(dz)],
                );
                candidates.push((order, r, [dx, dz]));
            }
        }
    }
    candidates.sort_by(|a, b| a.0.cmp(&b.0));
    let plans = candidates.into_iter().map(|(_, r, [dx, dz])| {
        let mut next = rooms.to_vec();
        for p in &mut next[r] {
            p[0] += dx;
            p[1] += dz;
        }
        (next, ())
    });
    first_clean(scene, catalog, plans, work).map(|(next, ())| next)
}

/// Keeps the [`MAX_AXIS_CANDIDATES`] smallest moves of `deltas` (sorted), in their order.
fn nearest_first(deltas: &mut Vec<f64>) {
    if deltas.len() > MAX_AXIS_CANDIDATES {
        let mut by_size = deltas.clone();
        by_size.sort_by(|a, b| a.abs().total_cmp(&b.abs()).then(a.total_cmp(b)));
        by_size.truncate(MAX_AXIS_CANDIDATES);
        deltas.retain(|d| by_size.iter().any(|k| k.to_bits() == d.to_bits()));
    }
}

/// The outlines of a plan's rooms, in scene order, metres.
type Outlines = Vec<Vec<[f64; 2]>>;

/// The order among refitted rooms (see [`fit_one_room_to_lines`]): the room's wall
/// coordinates left off the other rooms' lines, the largest wall move (mm), whether the walls
/// that move do not all move as far (the room neither scaled about its centre nor shifted),
/// whether the plan's lowest x or z moved, the roundness of the room's new coordinates, the
/// sum of the walls' moves (mm), then, on a true tie, the room declared later first (as in
/// the repair steps: an answer is drawn room after room, each fitted to those before), then
/// the new extents (mm).
type RefitOrder = (usize, u64, bool, bool, u32, u64, std::cmp::Reverse<usize>, [[i64; 2]; 2]);

/// The plan made clean by redrawing one room none of whose walls is on the plan's lines (a
/// room drawn a little too large or too small as a whole), with the room if it is exempt from
/// the area bound; or `None`. Only suspects (see [`suspects`]) with straight sides are tried.
/// Along each axis the room's first and last wall each stay, go onto the nearest line of
/// another room on either side at most [`MAX_MOVE_M`] away, or move as the opposite wall does
/// when that one goes onto a line, mirrored (the room scaled back about its centre); the walls
/// between them follow in proportion (an L-shaped room keeps its shape). A candidate counts
/// only when it leaves fewer of the room's wall coordinates off the lines, overlaps no room,
/// and changes the room's area by at most [`MAX_AREA_CHANGE`] unless it puts every wall on a
/// line or moves every wall that moves by as much (then the room fills the place the plan has
/// for it, and is exempt). The candidates go in the order of [`RefitOrder`]; the first that
/// makes the plan clean is taken.
fn fit_one_room_to_lines(
    scene: &Scene,
    rooms: &[Vec<[f64; 2]>],
    catalog: &StructureCatalog,
    work: &mut Work,
) -> Option<(Outlines, Option<usize>)> {
    let n = rooms.len();
    if n < 2 {
        return None;
    }
    let (suspect, _) = suspects(scene, rooms);
    let coords = room_coordinates(rooms);
    let mm = |v: f64| (v * 1e3).round() as i64;
    let lowest = |rs: &[Vec<[f64; 2]>], axis: usize| {
        rs.iter().map(|c| extent(c, axis).0).fold(f64::INFINITY, f64::min)
    };
    let origin = [lowest(rooms, 0), lowest(rooms, 1)];
    let mut candidates: Vec<(RefitOrder, usize, Vec<[f64; 2]>, bool)> = Vec::new();
    for r in (0..n).filter(|&r| suspect[r]) {
        let each = candidate_work(rooms, r);
        let total = coords[r][0].len() + coords[r][1].len();
        let straight = rooms[r]
            .iter()
            .zip(rooms[r].iter().cycle().skip(1))
            .all(|(p, q)| (p[0] - q[0]).abs() <= SAME_M || (p[1] - q[1]).abs() <= SAME_M);
        if !straight || off_lines(&coords, r) < total {
            continue;
        }
        // Per axis, the other rooms' lines and the extents the room's first and last wall may
        // take.
        let lines = lines_of_others(&coords, r);
        let mut extents: [Vec<[f64; 2]>; 2] = [Vec::new(), Vec::new()];
        for (axis, out) in extents.iter_mut().enumerate() {
            let lines = &lines[axis];
            let onto_lines = |v: f64| {
                let below = lines.iter().rev().find(|&&t| t < v - SAME_M);
                let above = lines.iter().find(|&&t| t > v + SAME_M);
                below.into_iter().chain(above).copied().filter(move |t| (t - v).abs() <= MAX_MOVE_M)
            };
            let (lo, hi) = (coords[r][axis][0], coords[r][axis][coords[r][axis].len() - 1]);
            // Each wall stays, goes onto a line, or moves as the opposite wall does when that
            // one goes onto a line, mirrored (the room drawn too large or too small about its
            // centre).
            let mut los: Vec<f64> = std::iter::once(lo).chain(onto_lines(lo)).collect();
            let mut his: Vec<f64> = std::iter::once(hi).chain(onto_lines(hi)).collect();
            los.extend(onto_lines(hi).map(|t| lo - (t - hi)));
            his.extend(onto_lines(lo).map(|t| hi - (t - lo)));
            for &a in &los {
                for &b in &his {
                    if b - a >= super::MIN_ROOM_SIDE_M {
                        out.push([a, b]);
                    }
                }
            }
            out.sort_by(|p, q| p[0].total_cmp(&q[0]).then(p[1].total_cmp(&q[1])));
            out.dedup_by(|p, q| (p[0] - q[0]).abs() <= SAME_M && (p[1] - q[1]).abs() <= SAME_M);
        }
        let (x, z) = (extent(&rooms[r], 0), extent(&rooms[r], 1));
        let before = [[x.0, x.1], [z.0, z.1]];
        for &ex in &extents[0] {
            for &ez in &extents[1] {
                let fit = [ex, ez];
                if fit == before {
                    continue;
                }
                if !work.spend(each) {
                    return None;
                }
                let mut next = rooms.to_vec();
                next[r] = refit(&rooms[r], before, fit, &lines);
                if (0..n).any(|o| o != r && overlap(&next[r], &next[o])) {
                    continue;
                }
                let mut next_coords = coords.clone();
                next_coords[r] = room_coordinates(&next[r..=r]).swap_remove(0);
                let off = off_lines(&next_coords, r);
                let moves = [
                    (fit[0][0] - before[0][0]).abs(),
                    (fit[0][1] - before[0][1]).abs(),
                    (fit[1][0] - before[1][0]).abs(),
                    (fit[1][1] - before[1][1]).abs(),
                ];
                // Every wall that moves moves as far, and each axis's two walls either stay
                // or both move (the room scaled about its centre, or shifted).
                let largest = moves.iter().copied().fold(0.0, f64::max);
                let uniform = (0..2).all(|axis| {
                    let (m0, m1) = (moves[2 * axis], moves[2 * axis + 1]);
                    (m0 <= SAME_M && m1 <= SAME_M)
                        || ((m0 - largest).abs() <= 1e-3 && (m1 - largest).abs() <= 1e-3)
                });
                // A room that goes wholly onto the lines, or is scaled back about its centre,
                // fills the place the plan has for it: the area bound does not apply.
                let a0 = area(&rooms[r]);
                if off >= total
                    || (off > 0 && !uniform && (area(&next[r]) - a0).abs() > MAX_AREA_CHANGE * a0)
                {
                    continue;
                }
                let round: u32 =
                    next_coords[r].iter().flatten().map(|&v| roundness(v)).sum::<u32>();
                let origin_moved = (lowest(&next, 0) - origin[0]).abs() > SAME_M
                    || (lowest(&next, 1) - origin[1]).abs() > SAME_M;
                let order = (
                    off,
                    (largest * 1e3).round() as u64,
                    !uniform,
                    origin_moved,
                    round,
                    (moves.iter().sum::<f64>() * 1e3).round() as u64,
                    std::cmp::Reverse(r),
                    [[mm(ex[0]), mm(ex[1])], [mm(ez[0]), mm(ez[1])]],
                );
                candidates.push((order, r, std::mem::take(&mut next[r]), off == 0 || uniform));
            }
        }
    }
    candidates.sort_by_key(|c| c.0);
    let plans = candidates.into_iter().map(|(_, r, outline, exempt)| {
        let mut next = rooms.to_vec();
        next[r] = outline;
        (next, exempt.then_some(r))
    });
    first_clean(scene, catalog, plans, work)
}

/// The first of `plans` (each with what the caller keeps with it) that leaves no gap between
/// facing walls and is clean, trying at most [`MAX_WHOLE_MOVES_TRIED`] of those without gaps.
fn first_clean<T>(
    scene: &Scene,
    catalog: &StructureCatalog,
    plans: impl Iterator<Item = (Outlines, T)>,
    work: &mut Work,
) -> Option<(Outlines, T)> {
    plans
        .filter(|(next, _)| facing_gaps(next).is_empty())
        .take(MAX_WHOLE_MOVES_TRIED)
        .take_while(|(next, _)| work.judge(next))
        .find(|(next, _)| Badness::of(scene, next, catalog).is_clean())
}

/// Per axis, the wall coordinates of every room but `r`, sorted and distinct.
fn lines_of_others(coords: &[[Vec<f64>; 2]], r: usize) -> [Vec<f64>; 2] {
    let mut out = [Vec::new(), Vec::new()];
    for (axis, slot) in out.iter_mut().enumerate() {
        *slot = coords
            .iter()
            .enumerate()
            .filter(|&(o, _)| o != r)
            .flat_map(|(_, c)| c[axis].iter().copied())
            .collect();
        slot.sort_by(f64::total_cmp);
        slot.dedup_by(|a, b| (*a - *b).abs() <= SAME_M);
    }
    out
}

/// Within this of a line, a wall moved in proportion goes onto it, metres (plans are written
/// to the millimetre or finer).
const ONTO_LINE_M: f64 = 0.002;

/// `corners` with each axis's extent `from` mapped onto `to`, the coordinates between in
/// proportion (onto a line of `lines`, per axis, when one is within [`ONTO_LINE_M`]).
fn refit(
    corners: &[[f64; 2]],
    from: [[f64; 2]; 2],
    to: [[f64; 2]; 2],
    lines: &[Vec<f64>; 2],
) -> Vec<[f64; 2]> {
    corners
        .iter()
        .map(|p| {
            let mut q = *p;
            for axis in 0..2 {
                let [lo, hi] = from[axis];
                let [a, b] = to[axis];
                q[axis] = if (p[axis] - lo).abs() <= SAME_M {
                    a
                } else if (p[axis] - hi).abs() <= SAME_M {
                    b
                } else {
                    let v = a + (p[axis] - lo) * (b - a) / (hi - lo);
                    lines[axis].iter().copied().find(|t| (t - v).abs() <= ONTO_LINE_M).unwrap_or(v)
                };
            }
            q
        })
        .collect()
}

/// Per room and axis, its distinct wall coordinates, sorted.
fn room_coordinates(rooms: &[Vec<[f64; 2]>]) -> Vec<[Vec<f64>; 2]> {
    rooms
        .iter()
        .map(|c| {
            let mut out = [Vec::new(), Vec::new()];
            for (axis, slot) in out.iter_mut().enumerate() {
                let mut vs: Vec<f64> = c.iter().map(|p| p[axis]).collect();
                vs.sort_by(f64::total_cmp);
                vs.dedup_by(|a, b| (*a - *b).abs() <= SAME_M);
                *slot = vs;
            }
            out
        })
        .collect()
}

/// Whether moving room `r` by `delta` leaves each of its moved wall coordinates either on a
/// line of another room or as round as it was: a wall drawn at `8` next to nothing stays
/// there (the other wall was drawn wrong), a wall at `8.2` may go back to `8`.
fn keeps_roundness(coords: &[[Vec<f64>; 2]], r: usize, delta: [f64; 2]) -> bool {
    (0..2).all(|axis| {
        delta[axis].abs() <= SAME_M
            || coords[r][axis].iter().all(|&v| {
                let w = v + delta[axis];
                roundness(w) <= roundness(v)
                    || coords
                        .iter()
                        .enumerate()
                        .any(|(o, c)| o != r && c[axis].iter().any(|&u| (u - w).abs() <= SAME_M))
            })
    })
}

/// How many wall coordinates of the plan's rooms (per room and axis, distinct) no other room
/// has.
fn walls_off_lines(rooms: &[Vec<[f64; 2]>]) -> usize {
    let coords = room_coordinates(rooms);
    (0..rooms.len()).map(|r| off_lines(&coords, r)).sum()
}

/// How many of room `r`'s wall coordinates (per axis, distinct) no other room has.
fn off_lines(coords: &[[Vec<f64>; 2]], r: usize) -> usize {
    (0..2)
        .map(|axis| {
            coords[r][axis]
                .iter()
                .filter(|&&v| {
                    !coords
                        .iter()
                        .enumerate()
                        .any(|(o, c)| o != r && c[axis].iter().any(|&w| (w - v).abs() <= SAME_M))
                })
                .count()
        })
        .sum()
}

/// The near misses (see [`near_misses`]) between rooms `a` and `b`.
fn pair_near_misses(
    rooms: &[Vec<[f64; 2]>],
    coords: &[[Vec<f64>; 2]],
    a: usize,
    b: usize,
) -> usize {
    let g = box_gap(&rooms[a], &rooms[b]);
    let mut n = 0;
    for axis in 0..2 {
        if g[1 - axis] > MAX_MOVE_M {
            continue;
        }
        for &u in &coords[a][axis] {
            for &v in &coords[b][axis] {
                let d = (u - v).abs();
                if d > SAME_M && d < MAX_MOVE_M - SAME_M {
                    n += 1;
                }
            }
        }
    }
    n
}

/// Pairs of rooms joined by a door or open connection, per room.
fn door_links(scene: &Scene, n: usize) -> Vec<Vec<usize>> {
    let mut links = vec![Vec::new(); n];
    for d in &scene.doors {
        if let (DoorSide::Room(a), DoorSide::Room(b)) = (&d.from, &d.to) {
            if a.0 < n && b.0 < n && a.0 != b.0 {
                links[a.0].push(b.0);
                links[b.0].push(a.0);
            }
        }
    }
    for l in &mut links {
        l.sort_unstable();
        l.dedup();
    }
    links
}

/// Per room, aligned with its [`door_links`]: the length of shared wall its doors to that room
/// need (the widest door of the catalog of the door's kind and size, and a margin at each
/// end, rounded up to 5 cm; 1 m for an open connection), at most [`MAX_SLIDE_M`].
fn door_needs(scene: &Scene, catalog: &StructureCatalog, links: &[Vec<usize>]) -> Vec<Vec<f64>> {
    links
        .iter()
        .enumerate()
        .map(|(a, others)| {
            others
                .iter()
                .map(|&b| {
                    let need = scene
                        .doors
                        .iter()
                        .filter(|d| match (&d.from, &d.to) {
                            (DoorSide::Room(x), DoorSide::Room(y)) => {
                                (x.0, y.0) == (a, b) || (x.0, y.0) == (b, a)
                            }
                            _ => false,
                        })
                        .map(|d| {
                            let widest = d.size.and_then(|size| {
                                catalog
                                    .doors
                                    .iter()
                                    .filter(|c| c.kind == d.kind && c.size == size)
                                    .map(|c| c.bbox_m[0])
                                    .reduce(f64::max)
                            });
                            widest.map_or(1.0, |w| w + 2.0 * super::DOOR_CORNER_MARGIN_M)
                        })
                        .fold(0.0, f64::max);
                    ((need * 20.0 - 1e-6).ceil() / 20.0).min(MAX_SLIDE_M)
                })
                .collect()
        })
        .collect()
}

/// How many pairs of rooms overlap.
fn overlap_count(rooms: &[Vec<[f64; 2]>]) -> usize {
    let mut n = 0;
    for a in 0..rooms.len() {
        for b in a + 1..rooms.len() {
            if overlap(&rooms[a], &rooms[b]) {
                n += 1;
            }
        }
    }
    n
}

/// Whether two rooms share floor (bounding boxes that share area, then exactly).
fn overlap(a: &[[f64; 2]], b: &[[f64; 2]]) -> bool {
    let g = box_gap(a, b);
    g[0] < -1e-3 && g[1] < -1e-3 && crate::geometry::rectilinear_intersection_area(a, b) > 1e-4
}

/// The cost of going from `before` to `after` (see [`Cost`]).
fn cost(before: &[Vec<[f64; 2]>], after: &[Vec<[f64; 2]>], seq: usize) -> Cost {
    let mut rooms = 0;
    let mut corners = 0;
    let mut swept = 0.0;
    let mut lost = 0.0;
    let mut far = false;
    for (r, (a, b)) in before.iter().zip(after).enumerate() {
        if same_outline(a, b) {
            continue;
        }
        rooms += 1;
        // A corner that moved: the nearest corner of the old outline to each new one (a
        // cleaned outline may have lost or merged corners).
        far |= b.iter().any(|p| {
            a.iter().map(|q| (p[0] - q[0]).hypot(p[1] - q[1])).fold(f64::INFINITY, f64::min)
                > MAX_TRANSLATION_M + 1e-3
        });
        // Corners of the new outline that are not corners of the old one.
        corners += b
            .iter()
            .filter(|p| {
                !a.iter().any(|q| (p[0] - q[0]).abs() <= SAME_M && (p[1] - q[1]).abs() <= SAME_M)
            })
            .count();
        let common = crate::geometry::rectilinear_intersection_area(a, b);
        swept += (area(a) + area(b) - 2.0 * common).max(0.0);
        for o in 0..before.len() {
            if o != r {
                lost += (shared_length(a, &before[o]) - shared_length(b, &after[o])).max(0.0);
            }
        }
    }
    (
        far,
        rooms,
        near_misses(after),
        (lost * 1e3).round() as u64,
        corners,
        (swept * 1e6).round() as u64,
        seq,
    )
}

/// The length of wall two outlines share.
fn shared_length(p: &[[f64; 2]], q: &[[f64; 2]]) -> f64 {
    let g = box_gap(p, q);
    if g[0] > SAME_M || g[1] > SAME_M {
        return 0.0;
    }
    let mut total = 0.0;
    for i in 0..p.len() {
        for j in 0..q.len() {
            if let Some((s, e)) = crate::geometry::segment_overlap(
                p[i],
                p[(i + 1) % p.len()],
                q[j],
                q[(j + 1) % q.len()],
            ) {
                total += (e[0] - s[0]).hypot(e[1] - s[1]);
            }
        }
    }
    total
}

/// Wall coordinates of neighbouring rooms (boxes at most the bound apart on the other axis)
/// that are less than the bound apart but not equal: the marks of a plan drawn slightly off.
fn near_misses(rooms: &[Vec<[f64; 2]>]) -> usize {
    let coords = room_coordinates(rooms);
    let mut n = 0;
    for a in 0..rooms.len() {
        for b in a + 1..rooms.len() {
            n += pair_near_misses(rooms, &coords, a, b);
        }
    }
    n
}

/// The outlines of the rooms other than `r` whose bounding boxes are at most [`MAX_MOVE_M`]
/// from its own.
fn rooms_near(rooms: &[Vec<[f64; 2]>], r: usize) -> impl Iterator<Item = &Vec<[f64; 2]>> {
    rooms
        .iter()
        .enumerate()
        .filter(move |&(o, c)| {
            let g = box_gap(&rooms[r], c);
            o != r && g[0] <= MAX_MOVE_M && g[1] <= MAX_MOVE_M
        })
        .map(|(_, c)| c)
}

/// Per axis, every wall coordinate of the rooms other than `r` near it (bounding boxes at
/// most [`MAX_MOVE_M`] apart: the lines a wall of `r` can be aligned with), sorted.
fn other_coordinates(rooms: &[Vec<[f64; 2]>], r: usize) -> [Vec<f64>; 2] {
    let mut out = [Vec::new(), Vec::new()];
    for c in rooms_near(rooms, r) {
        for p in c {
            out[0].push(p[0]);
            out[1].push(p[1]);
        }
    }
    for v in &mut out {
        v.sort_by(f64::total_cmp);
        v.dedup_by(|a, b| (*a - *b).abs() <= SAME_M);
    }
    out
}

/// Per axis, the walls of the rooms near room `r` (as in [`other_coordinates`]).
fn nearby_walls(rooms: &[Vec<[f64; 2]>], r: usize) -> [Vec<Wall>; 2] {
    let mut out = [Vec::new(), Vec::new()];
    for c in rooms_near(rooms, r) {
        for (axis, slot) in out.iter_mut().enumerate() {
            slot.extend(walls_of(c, axis));
        }
    }
    out
}

/// The coordinates a wall of room `r` at `at` (on `axis`, outward `outward`) could move to: the
/// facing walls of other rooms at most `bound` away that overlap it along its length.
fn facing_targets(
    rooms: &[Vec<[f64; 2]>],
    r: usize,
    axis: usize,
    wall: &Wall,
    bound: f64,
    only: Option<usize>,
) -> Vec<f64> {
    let mut out = Vec::new();
    for (o, corners) in rooms.iter().enumerate() {
        if o == r || only.is_some_and(|x| x != o) {
            continue;
        }
        for w in walls_of(corners, axis) {
            if w.outward * wall.outward >= 0.0 {
                continue;
            }
            let d = (w.at - wall.at).abs();
            let (lo, hi) = (w.from.max(wall.from), w.to.min(wall.to));
            if d > SAME_M && d <= bound + SAME_M && hi - lo > 0.01 {
                out.push(w.at);
            }
        }
    }
    out.sort_by(f64::total_cmp);
    out.dedup_by(|a, b| (*a - *b).abs() <= SAME_M);
    // The nearest first; at most three.
    out.sort_by(|a, b| (a - wall.at).abs().total_cmp(&(b - wall.at).abs()).then(a.total_cmp(b)));
    out.truncate(3);
    out
}

/// The plans that change room `r` alone (see the module documentation).
fn single_room_candidates(
    rooms: &[Vec<[f64; 2]>],
    r: usize,
    links: &[Vec<usize>],
    needs: &[Vec<f64>],
) -> Vec<Vec<Vec<[f64; 2]>>> {
    // Per axis: maps from old coordinate to new (`None`: the whole room moves by a delta).
    let mut per_axis: [Vec<AxisMove>; 2] = [vec![AxisMove::Keep], vec![AxisMove::Keep]];
    let corners = &rooms[r];
    for (axis, options) in per_axis.iter_mut().enumerate() {
        let walls = walls_of(corners, axis);
        // Snaps of one coordinate onto a facing wall within the bound.
        let mut snaps: Vec<(f64, f64)> = Vec::new();
        for w in &walls {
            for t in facing_targets(rooms, r, axis, w, MAX_MOVE_M, None) {
                snaps.push((w.at, t));
            }
        }
        snaps.sort_by(|a, b| a.0.total_cmp(&b.0).then(a.1.total_cmp(&b.1)));
        snaps.dedup_by(|a, b| (a.0 - b.0).abs() <= SAME_M && (a.1 - b.1).abs() <= SAME_M);
        // A room with many walls (a staircase) keeps its smallest snaps: their pairs would
        // otherwise be the square of its walls.
        if snaps.len() > MAX_AXIS_CANDIDATES / 4 {
            snaps.sort_by(|a, b| {
                (a.1 - a.0).abs().total_cmp(&(b.1 - b.0).abs()).then(a.0.total_cmp(&b.0))
            });
            snaps.truncate(MAX_AXIS_CANDIDATES / 4);
            snaps.sort_by(|a, b| a.0.total_cmp(&b.0).then(a.1.total_cmp(&b.1)));
        }
        for &(from, to) in &snaps {
            options.push(AxisMove::Snap(vec![(from, to)]));
        }
        for (i, &(f1, t1)) in snaps.iter().enumerate() {
            for &(f2, t2) in &snaps[i + 1..] {
                if (f1 - f2).abs() > SAME_M {
                    options.push(AxisMove::Snap(vec![(f1, t1), (f2, t2)]));
                }
            }
        }
        // The whole room moved so that one wall meets a facing wall.
        let mut deltas: Vec<f64> = snaps.iter().map(|&(f, t)| t - f).collect();
        // …or onto a room it has a door to and does not touch.
        for (k, &o) in links[r].iter().enumerate() {
            if touch(corners, &rooms[o]) {
                continue;
            }
            for w in &walls {
                for t in facing_targets(rooms, r, axis, w, MAX_TRANSLATION_M, Some(o)) {
                    deltas.push(t - w.at);
                }
            }
            // Rooms that meet only at a corner: slide along the other's wall, the least
            // distance that gives their doors the wall they need (issue 50), or further.
            let g = box_gap(corners, &rooms[o]);
            if g[0].abs() <= SAME_M && g[1].abs() <= SAME_M {
                let (lr, _) = extent(corners, axis);
                let (lo, _) = extent(&rooms[o], axis);
                let toward = if lr > lo { -1.0 } else { 1.0 };
                let need = needs.get(r).and_then(|n| n.get(k)).copied().unwrap_or(MAX_SLIDE_M);
                for step in [0.5, 1.0, need, MAX_SLIDE_M] {
                    deltas.push(toward * step);
                }
            }
        }
        deltas.sort_by(f64::total_cmp);
        deltas.dedup_by(|a, b| (*a - *b).abs() <= SAME_M);
        nearest_first(&mut deltas);
        for d in deltas {
            if d.abs() > SAME_M {
                options.push(AxisMove::Shift(d));
            }
        }
    }
    // A room of many corners keeps the first options of each axis (keep, then its nearest
    // snaps): each of its candidates is weighed against its neighbours corner by corner.
    if corners.len() > MANY_CORNERS {
        for options in &mut per_axis {
            options.truncate(MANY_CORNERS_OPTIONS);
        }
    }
    let mut out = Vec::new();
    for mx in &per_axis[0] {
        for mz in &per_axis[1] {
            if matches!((mx, mz), (AxisMove::Keep, AxisMove::Keep)) {
                continue;
            }
            let mut next = rooms.to_vec();
            for p in &mut next[r] {
                p[0] = mx.apply(p[0]);
                p[1] = mz.apply(p[1]);
            }
            out.push(next);
        }
    }
    out
}

/// Two rooms with a door between them that meet only at a corner, moved towards each other
/// along one axis (either axis) until they share the length of wall their doors need, as
/// `(the other room, the plan)`: only when that length is more than [`MAX_TRANSLATION_M`],
/// so that no corner moves more than a metre where one room alone would have to (issue 50).
/// Three ways each: both slide half the way; one slides a metre and the other's wall facing
/// it along the axis follows for the rest (the room grows a little, and keeps the walls it
/// shares elsewhere); the same the other way round. A way that parts either room from a room
/// it shares a wall with is left out. Each pair is given once, from its room declared first.
fn pair_slide_candidates(
    rooms: &[Vec<[f64; 2]>],
    r: usize,
    links: &[Vec<usize>],
    needs: &[Vec<f64>],
) -> Vec<(usize, Vec<Vec<[f64; 2]>>)> {
    let mut out = Vec::new();
    for (k, &o) in links[r].iter().enumerate() {
        if o <= r {
            continue;
        }
        let need = needs.get(r).and_then(|n| n.get(k)).copied().unwrap_or(MAX_SLIDE_M);
        if need <= MAX_TRANSLATION_M + SAME_M {
            continue;
        }
        let g = box_gap(&rooms[r], &rooms[o]);
        if g[0].abs() > SAME_M || g[1].abs() > SAME_M || touch(&rooms[r], &rooms[o]) {
            continue;
        }
        for axis in 0..2 {
            let (lr, hr) = extent(&rooms[r], axis);
            let (lo, ho) = extent(&rooms[o], axis);
            // The direction `r` goes to meet `o`, and the wall of each that faces the other.
            let toward = if lr > lo { -1.0 } else { 1.0 };
            let (r_wall, o_wall) = if toward > 0.0 { (hr, lo) } else { (lr, ho) };
            let rest = need - MAX_TRANSLATION_M;
            let shift = |room: &mut Vec<[f64; 2]>, by: f64| {
                for p in room.iter_mut() {
                    p[axis] += by;
                }
            };
            let stretch = |room: &mut Vec<[f64; 2]>, wall: f64, by: f64| {
                for p in room.iter_mut() {
                    if (p[axis] - wall).abs() <= SAME_M {
                        p[axis] += by;
                    }
                }
            };
            let mut halves = rooms.to_vec();
            shift(&mut halves[r], toward * need / 2.0);
            shift(&mut halves[o], -toward * need / 2.0);
            let mut r_slides = rooms.to_vec();
            shift(&mut r_slides[r], toward * MAX_TRANSLATION_M);
            stretch(&mut r_slides[o], o_wall, -toward * rest);
            let mut o_slides = rooms.to_vec();
            shift(&mut o_slides[o], -toward * MAX_TRANSLATION_M);
            stretch(&mut o_slides[r], r_wall, toward * rest);
            // A way that parts either room from a room it shares a wall with is no repair.
            let keeps_walls = |next: &[Vec<[f64; 2]>]| {
                [r, o].into_iter().all(|moved| {
                    (0..rooms.len()).filter(|&x| x != moved).all(|x| {
                        shared_length(&rooms[moved], &rooms[x]) <= SAME_M
                            || shared_length(&next[moved], &next[x]) > SAME_M
                    })
                })
            };
            for next in [halves, r_slides, o_slides] {
                if keeps_walls(&next) {
                    out.push((o, next));
                }
            }
        }
    }
    out
}

/// How a single-room candidate changes one axis of the room.
#[derive(Clone, Debug)]
enum AxisMove {
    Keep,
    /// These coordinates move to those.
    Snap(Vec<(f64, f64)>),
    /// Every coordinate moves by this much.
    Shift(f64),
}

impl AxisMove {
    fn apply(&self, v: f64) -> f64 {
        match self {
            AxisMove::Keep => v,
            AxisMove::Shift(d) => v + d,
            AxisMove::Snap(moves) => {
                moves.iter().find(|(f, _)| (f - v).abs() <= SAME_M).map_or(v, |&(_, t)| t)
            }
        }
    }
}

/// A gap between facing walls of two rooms (see [`facing_gaps`]).
#[derive(Clone, Debug, PartialEq)]
pub(crate) struct Gap {
    /// The room whose wall would move to close it (the shorter facing wall; on a tie, the room
    /// declared later).
    pub moving: usize,
    /// The other room.
    pub staying: usize,
    /// The axis of the gap (0: the walls are at constant x).
    pub axis: usize,
    /// The moving room's wall coordinate and the staying room's.
    pub from: f64,
    /// The coordinate the moving wall goes to.
    pub to: f64,
}

impl Gap {
    /// The gap's width, metres.
    pub fn width(&self) -> f64 {
        (self.to - self.from).abs()
    }
}

/// Gaps of at most [`MAX_MOVE_M`] between walls of two rooms that face each other (overlapping
/// along their length by more than 10 cm), with no third room's floor between them: rooms
/// that were most likely meant to share that wall.
pub(crate) fn facing_gaps(rooms: &[Vec<[f64; 2]>]) -> Vec<Gap> {
    // Only rooms whose boxes come within a move of each other can face each other across a
    // gap (`super::grid`): each room is asked about those alone, in room order, as a look at
    // every pair would ask. A gap's middle lies inside a room only within that room's box.
    let mut near = super::grid::Grid::new(GAP_GRID_CELL_M);
    for corners in rooms {
        let (min, max) = super::grid::widened_box(corners, GAP_GRID_MARGIN_M);
        near.push(min, max);
    }
    let reach = MAX_MOVE_M + 2.0 * SAME_M + GAP_GRID_MARGIN_M;
    let nearby: Vec<Vec<usize>> = rooms
        .iter()
        .map(|corners| {
            let (min, max) = super::grid::widened_box(corners, reach);
            near.query(min, max)
        })
        .collect();
    let mut out: Vec<Gap> = Vec::new();
    for axis in 0..2 {
        let other = 1 - axis;
        let walls: Vec<Vec<Wall>> = rooms.iter().map(|c| walls_of(c, axis)).collect();
        for ra in 0..rooms.len() {
            for &rb in &nearby[ra] {
                if ra == rb {
                    continue;
                }
                // `a` faces +, `b` faces - and lies beyond it.
                for a in walls[ra].iter().filter(|w| w.outward > 0.0) {
                    for b in walls[rb].iter().filter(|w| w.outward < 0.0) {
                        let d = b.at - a.at;
                        let (lo, hi) = (a.from.max(b.from), a.to.min(b.to));
                        if d <= SAME_M || d > MAX_MOVE_M + SAME_M || hi - lo <= MIN_GAP_FACE_M {
                            continue;
                        }
                        let mut mid = [0.0; 2];
                        mid[axis] = f64::midpoint(a.at, b.at);
                        mid[other] = f64::midpoint(lo, hi);
                        if near.query(mid, mid).into_iter().any(|c| inside(mid, &rooms[c])) {
                            continue;
                        }
                        let (la, lb) = (a.to - a.from, b.to - b.from);
                        let a_moves = la < lb - SAME_M || ((la - lb).abs() <= SAME_M && ra > rb);
                        let gap = if a_moves {
                            Gap { moving: ra, staying: rb, axis, from: a.at, to: b.at }
                        } else {
                            Gap { moving: rb, staying: ra, axis, from: b.at, to: a.at }
                        };
                        if !out.contains(&gap) {
                            out.push(gap);
                        }
                    }
                }
            }
        }
    }
    out
}

/// The outline of a room with one wall coordinate moved (every corner on it).
pub(crate) fn with_wall_moved(
    corners: &[[f64; 2]],
    axis: usize,
    from: f64,
    to: f64,
) -> Vec<[f64; 2]> {
    corners
        .iter()
        .map(|p| {
            let mut q = *p;
            if (q[axis] - from).abs() <= SAME_M {
                q[axis] = to;
            }
            q
        })
        .collect()
}

/// The scene with repaired outlines (corner spans kept where a corner survived).
pub fn apply(scene: &Scene, repair: &Repair) -> Scene {
    let mut out = scene.clone();
    for (room, corners) in out.rooms.iter_mut().zip(&repair.corners) {
        if !same_outline(&room.corners, corners) {
            let span = room.corner_spans.first().copied().unwrap_or_default();
            room.corner_spans = vec![span; corners.len()];
            room.corners.clone_from(corners);
        }
    }
    out
}

/// A number as a plan writes it: metres, at most three decimals, no trailing zeros.
fn num(v: f64) -> String {
    let r = (v * 1000.0).round() / 1000.0;
    let r = if r == 0.0 { 0.0 } else { r };
    let mut s = format!("{r:.3}");
    while s.ends_with('0') {
        s.pop();
    }
    if s.ends_with('.') {
        s.pop();
    }
    s
}

fn same_outline(a: &[[f64; 2]], b: &[[f64; 2]]) -> bool {
    a.len() == b.len()
        && a.iter()
            .zip(b)
            .all(|(p, q)| (p[0] - q[0]).abs() < SAME_M && (p[1] - q[1]).abs() < SAME_M)
}

/// Drops repeated corners and corners in the middle of a straight wall, and straightens
/// edges slanted by at most [`MAX_MOVE_M`] by moving the corner whose coordinate no other room
/// shares (`others`: the other rooms' coordinates per axis); when neither or both are shared,
/// the rounder coordinate stays, then the first corner's. `origin` holds, for each corner, the
/// index of the corner as written it comes from; it is kept in step.
fn clean_outline(
    corners: &mut Vec<[f64; 2]>,
    origin: &mut Vec<usize>,
    others: &[Vec<f64>; 2],
    walls: &[Vec<Wall>; 2],
) {
    let same =
        |p: [f64; 2], q: [f64; 2]| (p[0] - q[0]).abs() <= SAME_M && (p[1] - q[1]).abs() <= SAME_M;
    let mut pts: Vec<([f64; 2], usize)> = Vec::with_capacity(corners.len());
    for (p, o) in corners.iter().zip(origin.iter()) {
        if pts.last().is_none_or(|q| !same(q.0, *p)) {
            pts.push((*p, *o));
        }
    }
    while pts.len() > 1 && same(pts[0].0, pts[pts.len() - 1].0) {
        pts.pop();
    }
    let shared = |axis: usize, v: f64| others[axis].iter().any(|w| (w - v).abs() <= SAME_M);
    // Twice: straightening an edge by moving its first corner may slant the edge before it.
    let n = pts.len();
    for _ in 0..2 {
        if n < 3 {
            break;
        }
        for i in 0..n {
            let j = (i + 1) % n;
            let (a, b) = (pts[i].0, pts[j].0);
            let (dx, dz) = ((b[0] - a[0]).abs(), (b[1] - a[1]).abs());
            if dx <= SAME_M || dz <= SAME_M || dx.min(dz) > MAX_MOVE_M {
                continue;
            }
            let axis = usize::from(dx > dz);
            let (va, vb) = (a[axis], b[axis]);
            // Which value the edge keeps: the one aligned with the other rooms; when both
            // are, the one whose walls run along more of the edge (the room across it, not a
            // room met at its end); else the rounder one, else the first corner's.
            let (lo, hi) = (a[1 - axis].min(b[1 - axis]), a[1 - axis].max(b[1 - axis]));
            let along = |v: f64| -> f64 {
                walls[axis]
                    .iter()
                    .filter(|w| (w.at - v).abs() <= SAME_M)
                    .map(|w| (w.to.min(hi) - w.from.max(lo)).max(0.0))
                    .sum()
            };
            let keep_a = match (shared(axis, va), shared(axis, vb)) {
                (true, false) => true,
                (false, true) => false,
                (true, true) if (along(va) - along(vb)).abs() > SAME_M => along(va) > along(vb),
                _ => roundness(va) <= roundness(vb),
            };
            if keep_a {
                pts[j].0[axis] = va;
            } else {
                pts[i].0[axis] = vb;
            }
        }
    }
    // Drop corners on a straight line between their neighbours.
    let mut changed = true;
    while changed && pts.len() > 3 {
        changed = false;
        let n = pts.len();
        for i in 0..n {
            let (p, c, q) = (pts[(i + n - 1) % n].0, pts[i].0, pts[(i + 1) % n].0);
            let same_x = (p[0] - c[0]).abs() <= SAME_M && (c[0] - q[0]).abs() <= SAME_M;
            let same_z = (p[1] - c[1]).abs() <= SAME_M && (c[1] - q[1]).abs() <= SAME_M;
            if same_x || same_z || same(c, q) {
                pts.remove(i);
                changed = true;
                break;
            }
        }
    }
    *corners = pts.iter().map(|p| p.0).collect();
    *origin = pts.iter().map(|p| p.1).collect();
}

/// Whether an outline has a repeated corner or a slanted edge.
fn needs_cleaning(corners: &[[f64; 2]]) -> bool {
    let n = corners.len();
    (0..n).any(|i| {
        let (a, b) = (corners[i], corners[(i + 1) % n]);
        let (dx, dz) = ((b[0] - a[0]).abs(), (b[1] - a[1]).abs());
        (dx <= SAME_M && dz <= SAME_M) || (dx > SAME_M && dz > SAME_M)
    })
}

/// How many decimals a coordinate needs (0 to 4; 4 for anything finer).
fn roundness(v: f64) -> u32 {
    (0..4)
        .find(|&d| {
            let scaled = v * 10f64.powi(d as i32);
            (scaled - scaled.round()).abs() < 1e-6
        })
        .unwrap_or(4)
}

/// The extent of a room along an axis (0: x, 1: z).
fn extent(corners: &[[f64; 2]], axis: usize) -> (f64, f64) {
    corners
        .iter()
        .fold((f64::INFINITY, f64::NEG_INFINITY), |(lo, hi), p| (lo.min(p[axis]), hi.max(p[axis])))
}

/// Makes facing walls of different rooms one, along `axis` (0: walls of constant x, 1: of
/// constant z). See the module documentation.
fn share_walls(rooms: &mut [Vec<[f64; 2]>], axis: usize) {
    let other = 1 - axis;
    // Every distinct coordinate of every room on this axis.
    let mut values: Vec<(f64, usize)> = Vec::new();
    for (r, corners) in rooms.iter().enumerate() {
        let mut vs: Vec<f64> = corners.iter().map(|p| p[axis]).collect();
        vs.sort_by(f64::total_cmp);
        vs.dedup_by(|a, b| (*a - *b).abs() <= SAME_M);
        values.extend(vs.into_iter().map(|v| (v, r)));
    }
    let n = values.len();
    let mut parent: Vec<usize> = (0..n).collect();
    // Candidate pairs: a wall of one room and a wall of another that face each other (their
    // outward sides point at each other), overlap along the other axis, and lie at most the
    // bound apart across a gap or an overlap with no third room's floor between them.
    let walls: Vec<Vec<Wall>> = rooms.iter().map(|c| walls_of(c, axis)).collect();
    let index_of = |v: f64, r: usize| {
        values.iter().position(|&(w, room)| room == r && (w - v).abs() <= SAME_M)
    };
    let mut pairs: Vec<(f64, usize, usize)> = Vec::new();
    for (ra, wa) in walls.iter().enumerate() {
        for (rb, wb) in walls.iter().enumerate() {
            if ra == rb {
                continue;
            }
            for a in wa.iter().filter(|w| w.outward > 0.0) {
                for b in wb.iter().filter(|w| w.outward < 0.0) {
                    let d = (a.at - b.at).abs();
                    let (lo, hi) = (a.from.max(b.from), a.to.min(b.to));
                    // Walls already shared (d = 0) pair too, so that they move together.
                    if d > MAX_MOVE_M + SAME_M || hi - lo <= 0.01 {
                        continue;
                    }
                    let mut mid = [0.0; 2];
                    mid[axis] = f64::midpoint(a.at, b.at);
                    mid[other] = f64::midpoint(lo, hi);
                    let between =
                        rooms.iter().enumerate().any(|(r, c)| r != ra && r != rb && inside(mid, c));
                    if between {
                        continue;
                    }
                    if let (Some(i), Some(j)) = (index_of(a.at, ra), index_of(b.at, rb)) {
                        pairs.push((d, i.min(j), i.max(j)));
                    }
                }
            }
        }
    }
    pairs.sort_by(|x, y| x.0.total_cmp(&y.0).then(x.1.cmp(&y.1)).then(x.2.cmp(&y.2)));
    pairs.dedup();
    // Closest pairs first, so that a wall joins its nearest neighbour's.
    pairs.sort_by(|x, y| x.0.total_cmp(&y.0).then(x.1.cmp(&y.1)).then(x.2.cmp(&y.2)));
    let mut members: Vec<Vec<usize>> = (0..n).map(|i| vec![i]).collect();
    for (_, a, b) in pairs {
        let (ra, rb) = (super::build::find(&mut parent, a), super::build::find(&mut parent, b));
        if ra == rb {
            continue;
        }
        // Never two different coordinates of one room in one group, and never a group wider
        // than the bound.
        let joined: Vec<usize> = members[ra].iter().chain(&members[rb]).copied().collect();
        let same_room_twice = joined.iter().any(|&i| {
            joined.iter().any(|&j| {
                i != j && values[i].1 == values[j].1 && (values[i].0 - values[j].0).abs() > SAME_M
            })
        });
        let (lo, hi) = joined.iter().fold((f64::INFINITY, f64::NEG_INFINITY), |(lo, hi), &i| {
            (lo.min(values[i].0), hi.max(values[i].0))
        });
        if same_room_twice || hi - lo > MAX_MOVE_M + SAME_M {
            continue;
        }
        parent[rb] = ra;
        let moved = std::mem::take(&mut members[rb]);
        members[ra].extend(moved);
    }
    // Each group meets at the coordinate that moves the least length of wall (ties: the
    // coordinate of the room declared first).
    let wall_length = |i: usize| -> f64 {
        let (v, r) = values[i];
        walls[r].iter().filter(|w| (w.at - v).abs() <= SAME_M).map(|w| w.to - w.from).sum()
    };
    let mut target: BTreeMap<(usize, u64), f64> = BTreeMap::new();
    for i in 0..n {
        let root = super::build::find(&mut parent, i);
        let group = &members[root];
        if group.len() < 2 {
            continue;
        }
        let cost = |value: f64| -> f64 {
            group.iter().map(|&j| (values[j].0 - value).abs() * wall_length(j)).sum()
        };
        let keep = group
            .iter()
            .map(|&j| (cost(values[j].0), values[j].1, j))
            .min_by(|a, b| {
                // Costs within a square millimetre of wall are equal.
                let (ca, cb) = ((a.0 * 1e6).round(), (b.0 * 1e6).round());
                ca.total_cmp(&cb).then(a.1.cmp(&b.1)).then(a.2.cmp(&b.2))
            })
            .map(|(_, _, j)| values[j].0);
        if let Some(keep) = keep {
            target.insert((values[i].1, values[i].0.to_bits()), keep);
        }
    }
    for (r, corners) in rooms.iter_mut().enumerate() {
        for p in corners.iter_mut() {
            if let Some(v) = target.get(&(r, p[axis].to_bits())) {
                p[axis] = *v;
            } else {
                // The coordinate may differ by rounding from the one recorded.
                if let Some((_, v)) = target.iter().find(|((room, bits), _)| {
                    *room == r && (f64::from_bits(*bits) - p[axis]).abs() <= SAME_M
                }) {
                    p[axis] = *v;
                }
            }
        }
    }
}

/// One straight wall of a room on an axis: at `at` (its constant coordinate), from `from` to
/// `to` along the other axis, and which way its outside points along the axis (+1 or -1).
#[derive(Clone, Copy, Debug)]
struct Wall {
    at: f64,
    from: f64,
    to: f64,
    outward: f64,
}

/// The walls of an outline that run along `axis`'s constant coordinate (0: walls of constant
/// x), with their outward direction from the outline's winding.
fn walls_of(corners: &[[f64; 2]], axis: usize) -> Vec<Wall> {
    let other = 1 - axis;
    let n = corners.len();
    let signed: f64 = (0..n)
        .map(|i| {
            let (a, b) = (corners[i], corners[(i + 1) % n]);
            a[0] * b[1] - b[0] * a[1]
        })
        .sum();
    let mut out = Vec::new();
    for i in 0..n {
        let (a, b) = (corners[i], corners[(i + 1) % n]);
        if (a[axis] - b[axis]).abs() > SAME_M || (a[other] - b[other]).abs() <= SAME_M {
            continue;
        }
        // For a counter-clockwise outline (positive signed area in x, z), the outside of an
        // edge running along +z lies towards +x; along +x it lies towards -z.
        let along = (b[other] - a[other]).signum();
        let ccw = if signed >= 0.0 { 1.0 } else { -1.0 };
        let outward = if axis == 0 { along * ccw } else { -along * ccw };
        out.push(Wall {
            at: a[axis],
            from: a[other].min(b[other]),
            to: a[other].max(b[other]),
            outward,
        });
    }
    out
}

/// Whether a point lies strictly inside an outline (even-odd rule).
fn inside(p: [f64; 2], corners: &[[f64; 2]]) -> bool {
    let n = corners.len();
    let mut inside = false;
    for i in 0..n {
        let (a, b) = (corners[i], corners[(i + 1) % n]);
        if (a[1] > p[1]) != (b[1] > p[1]) {
            let x = a[0] + (p[1] - a[1]) / (b[1] - a[1]) * (b[0] - a[0]);
            if p[0] < x {
                inside = !inside;
            }
        }
    }
    inside
}

/// The gap between two rooms' bounding boxes along each axis (negative: overlap).
fn box_gap(a: &[[f64; 2]], b: &[[f64; 2]]) -> [f64; 2] {
    let mut out = [0.0; 2];
    for (axis, slot) in out.iter_mut().enumerate() {
        let (la, ha) = extent(a, axis);
        let (lb, hb) = extent(b, axis);
        *slot = (lb - ha).max(la - hb);
    }
    out
}

/// Whether two rooms share a stretch of wall (longer than a centimetre).
fn touch(a: &[[f64; 2]], b: &[[f64; 2]]) -> bool {
    let g = box_gap(a, b);
    (g[0].abs() <= SAME_M && g[1] < -0.01) || (g[1].abs() <= SAME_M && g[0] < -0.01)
}

/// Moves rooms that touch no other room onto their nearest neighbour.
fn attach_detached(scene: &Scene, rooms: &mut [Vec<[f64; 2]>]) {
    if rooms.len() < 2 {
        return;
    }
    for r in 0..rooms.len() {
        let linked: Vec<usize> = scene
            .doors
            .iter()
            .filter_map(|d| match (&d.from, &d.to) {
                (DoorSide::Room(a), DoorSide::Room(b)) if a.0 == r => Some(b.0),
                (DoorSide::Room(a), DoorSide::Room(b)) if b.0 == r => Some(a.0),
                _ => None,
            })
            .filter(|&o| o < rooms.len() && o != r)
            .collect();
        let isolated = !(0..rooms.len()).any(|o| o != r && touch(&rooms[r], &rooms[o]));
        // A room declared after a room it has a door to, but not touching it, moves onto it.
        let apart: Vec<usize> =
            linked.iter().copied().filter(|&o| o < r && !touch(&rooms[r], &rooms[o])).collect();
        let candidates: Vec<usize> = if !apart.is_empty() {
            apart
        } else if !isolated {
            continue;
        } else if linked.is_empty() {
            (0..rooms.len()).filter(|&o| o != r).collect()
        } else {
            linked
        };
        // The move that makes the room touch a candidate: close the gap on one axis, and on
        // the other axis only what keeps the rooms side by side.
        let mut best: Option<(f64, [f64; 2])> = None;
        for o in candidates {
            let g = box_gap(&rooms[r], &rooms[o]);
            for axis in 0..2 {
                let other = 1 - axis;
                if g[axis] <= SAME_M || g[other] > -0.5 {
                    continue;
                }
                let (lr, _) = extent(&rooms[r], axis);
                let (lo, _) = extent(&rooms[o], axis);
                let mut shift = [0.0; 2];
                shift[axis] = if lr > lo { -g[axis] } else { g[axis] };
                let dist = g[axis];
                if dist <= MAX_TRANSLATION_M && best.is_none_or(|(d, _)| dist < d) {
                    best = Some((dist, shift));
                }
            }
        }
        if let Some((_, shift)) = best {
            for p in &mut rooms[r] {
                p[0] += shift[0];
                p[1] += shift[1];
            }
        }
    }
}

/// What happened to one corner as written.
#[derive(Clone, Copy, Debug)]
enum CornerChange {
    /// Moved to a corner of the repaired outline, this far (metres).
    Moved { from: [f64; 2], to: [f64; 2], distance: f64 },
    /// Dropped: it repeated the corner before it, or lay on a straight wall of the repaired
    /// outline (this far from it, metres).
    Dropped { at: [f64; 2], distance: f64 },
}

impl CornerChange {
    fn distance(self) -> f64 {
        match self {
            Self::Moved { distance, .. } | Self::Dropped { distance, .. } => distance,
        }
    }
}

/// The distance from a point to the segment from `a` to `b`.
fn to_segment(p: [f64; 2], a: [f64; 2], b: [f64; 2]) -> f64 {
    let (dx, dz) = (b[0] - a[0], b[1] - a[1]);
    let len2 = dx * dx + dz * dz;
    let t = if len2 <= 0.0 {
        0.0
    } else {
        (((p[0] - a[0]) * dx + (p[1] - a[1]) * dz) / len2).clamp(0.0, 1.0)
    };
    (p[0] - a[0] - t * dx).hypot(p[1] - a[1] - t * dz)
}

/// What happened to each corner as written: the repaired corner that comes from it (`origin`
/// gives, per repaired corner, the index of the corner as written), or, when none does, it was
/// dropped (a repeat, or a corner on what is now a straight wall).
fn describe_moves(before: &[[f64; 2]], after: &[[f64; 2]], origin: &[usize]) -> Vec<CornerChange> {
    let n = after.len();
    let mut out = Vec::new();
    for (b, p) in before.iter().enumerate() {
        match origin.iter().position(|&o| o == b) {
            Some(a) => {
                let d = (after[a][0] - p[0]).hypot(after[a][1] - p[1]);
                if d > SAME_M {
                    out.push(CornerChange::Moved { from: *p, to: after[a], distance: d });
                }
            }
            None => {
                let to_wall = (0..n)
                    .map(|e| to_segment(*p, after[e], after[(e + 1) % n]))
                    .fold(f64::INFINITY, f64::min);
                out.push(CornerChange::Dropped { at: *p, distance: to_wall });
            }
        }
    }
    out
}

fn area(corners: &[[f64; 2]]) -> f64 {
    let n = corners.len();
    (0..n)
        .map(|i| {
            let (a, b) = (corners[i], corners[(i + 1) % n]);
            a[0] * b[1] - b[0] * a[1]
        })
        .sum::<f64>()
        .abs()
        / 2.0
}

fn summary(before: &[[f64; 2]], after: &[[f64; 2]], changes: &[CornerChange]) -> String {
    let far = changes.iter().map(|c| c.distance()).fold(0.0, f64::max);
    let moved = changes.iter().filter(|c| matches!(c, CornerChange::Moved { .. })).count();
    let dropped = changes.len() - moved;
    let plural = |n: usize| if n == 1 { "" } else { "s" };
    let mut what = Vec::new();
    if moved > 0 {
        what.push(format!("{moved} corner{} moved", plural(moved)));
    }
    if dropped > 0 {
        what.push(format!("{dropped} corner{} dropped", plural(dropped)));
    }
    if what.is_empty() {
        what.push("corners reordered".to_string());
    }
    let far = if far > SAME_M { format!(" (at most {far:.2} m)") } else { String::new() };
    format!("{}{far}, area {:.2} m² → {:.2} m²", what.join(", "), area(before), area(after))
}

/// The area change of a repair, as a share of the original area, per room (for the
/// benchmark).
pub fn area_changes(before: &Scene, repair: &Repair) -> Vec<f64> {
    before
        .rooms
        .iter()
        .zip(&repair.corners)
        .map(|(r, c)| {
            let a0 = area(&r.corners);
            if a0 <= 0.0 {
                0.0
            } else {
                (area(c) - a0).abs() / a0
            }
        })
        .collect()
}

/// A plan-stage error of the geometry of rooms, as left after repair, with a note that says
/// why repair did not fix it (it needs more than the bounds allow); other diagnostics are
/// returned as they are.
pub fn explain_unrepaired(d: Diagnostic) -> Diagnostic {
    let geometric = d.is_error()
        && matches!(
            d.code,
            Code::E0301 | Code::E0302 | Code::E0305 | Code::E0306 | Code::E0307 | Code::E0308
        );
    if !geometric {
        return d;
    }
    d.with_note(format!(
        "not repaired: it needs more than repair allows (a corner moves at most {MAX_MOVE_M} m, \
         a detached room at most {MAX_TRANSLATION_M} m, a room's area changes by at most {}%); \
         edit the corners by hand",
        MAX_AREA_CHANGE * 100.0
    ))
}

#[cfg(test)]
mod tests {
    use super::*;
    use proptest::prelude::*;

    /// The look at every pair of rooms that `facing_gaps` replaced.
    fn facing_gaps_of_every_pair(rooms: &[Vec<[f64; 2]>]) -> Vec<Gap> {
        let mut out: Vec<Gap> = Vec::new();
        for axis in 0..2 {
            let other = 1 - axis;
            let walls: Vec<Vec<Wall>> = rooms.iter().map(|c| walls_of(c, axis)).collect();
            for ra in 0..rooms.len() {
                for rb in 0..rooms.len() {
                    if ra == rb {
                        continue;
                    }
                    for a in walls[ra].iter().filter(|w| w.outward > 0.0) {
                        for b in walls[rb].iter().filter(|w| w.outward < 0.0) {
                            let d = b.at - a.at;
                            let (lo, hi) = (a.from.max(b.from), a.to.min(b.to));
                            if d <= SAME_M || d > MAX_MOVE_M + SAME_M || hi - lo <= MIN_GAP_FACE_M {
                                continue;
                            }
                            let mut mid = [0.0; 2];
                            mid[axis] = f64::midpoint(a.at, b.at);
                            mid[other] = f64::midpoint(lo, hi);
                            if rooms.iter().any(|c| inside(mid, c)) {
                                continue;
                            }
                            let (la, lb) = (a.to - a.from, b.to - b.from);
                            let a_moves =
                                la < lb - SAME_M || ((la - lb).abs() <= SAME_M && ra > rb);
                            let gap = if a_moves {
                                Gap { moving: ra, staying: rb, axis, from: a.at, to: b.at }
                            } else {
                                Gap { moving: rb, staying: ra, axis, from: b.at, to: a.at }
                            };
                            if !out.contains(&gap) {
                                out.push(gap);
                            }
                        }
                    }
                }
            }
        }
        out
    }

    /// A rectangle or an L, either winding, at a corner on a 0.1 m grid plus a small offset.
    fn room() -> impl Strategy<Value = Vec<[f64; 2]>> {
        (0i32..80, 0i32..80, 10i32..40, 10i32..40, 0i32..4, any::<bool>(), any::<bool>()).prop_map(
            |(x, z, w, d, nudge, l_shape, reverse)| {
                let (x, z) = (f64::from(x) * 0.1 + f64::from(nudge) * 0.07, f64::from(z) * 0.1);
                let (w, d) = (f64::from(w) * 0.1, f64::from(d) * 0.1);
                let mut corners = if l_shape {
                    vec![
                        [x, z],
                        [x, z + d],
                        [x + w / 2.0, z + d],
                        [x + w / 2.0, z + d / 2.0],
                        [x + w, z + d / 2.0],
                        [x + w, z],
                    ]
                } else {
                    vec![[x, z], [x, z + d], [x + w, z + d], [x + w, z]]
                };
                if reverse {
                    corners.reverse();
                }
                corners
            },
        )
    }

    proptest! {
        /// The gaps (and their order) are those a look at every pair of rooms finds.
        #[test]
        fn gaps_are_those_of_every_pair(rooms in proptest::collection::vec(room(), 0..14)) {
            prop_assert_eq!(facing_gaps(&rooms), facing_gaps_of_every_pair(&rooms));
        }
    }

    #[test]
    fn gaps_are_found_between_facing_rooms_far_apart_in_the_list() {
        // A row of rooms with a 0.2 m gap between the first and the last one's neighbour.
        let mut rooms: Vec<Vec<[f64; 2]>> = (0..40)
            .map(|k| {
                let x = f64::from(k) * 4.0 + 100.0;
                vec![[x, 0.0], [x, 3.0], [x + 4.0, 3.0], [x + 4.0, 0.0]]
            })
            .collect();
        rooms.push(vec![[96.0, 0.0], [96.0, 3.0], [99.8, 3.0], [99.8, 0.0]]);
        let gaps = facing_gaps(&rooms);
        assert_eq!(gaps, facing_gaps_of_every_pair(&rooms));
        assert_eq!(gaps.len(), 1);
    }
}

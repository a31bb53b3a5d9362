//! The `solve` stage: places every object of a room.
//!
//! Floor objects are placed by a depth-first branch-and-bound search ([`Solver::Dfs`], the
//! default) or by a sequence of small MILPs ([`Solver::Milp`]); both use the hard rules and
//! the scoring of [`constraints`]. Wall objects hang on the room's walls, small objects are
//! packed on top of their receptacles and the ceiling object hangs at the ceiling. The entry
//! verb is [`solve_room`]; its output noun is [`RoomLayout`].
//!
//! Hard rules are never broken: an object that cannot keep them is left out and reported with
//! the rule that blocked it (W0501), and the objects after it are still placed.

mod candidates;
pub mod constraints;
mod dfs;
mod errors;
mod grid;
mod milp;
mod others;
mod pipeline;
mod scene;
pub mod surfaces;

use crate::check::scene::{GlobalKind, RelationKind};
use crate::diag::{Diagnostic, Outcome};
use crate::source::Span;

pub use constraints::{HardRule, Meaning, Measure, Pose, Rect, Role, RoomShape, Rot};
pub use others::{PILE_MAX_M, SMALL_GAP_M};
pub use pipeline::{solve, solve_by_room, GivenUp, Layout, RoomDone, SolvedRoom};
pub(crate) use scene::item_ids;
pub use scene::{room_problem, Sizes, WrittenSizes};

/// Which floor solver to run.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Default)]
pub enum Solver {
    /// Depth-first search with branch and bound over candidate poses.
    #[default]
    Dfs,
    /// One small MILP per object (good_lp), falling back to the DFS for an object it cannot
    /// place.
    Milp,
}

impl Solver {
    /// Both solvers, in the order `dfs`, `milp`.
    pub const ALL: [Solver; 2] = [Solver::Dfs, Solver::Milp];

    /// The name used on the command line (`dfs`, `milp`).
    pub fn as_str(self) -> &'static str {
        match self {
            Solver::Dfs => "dfs",
            Solver::Milp => "milp",
        }
    }

    /// Parses a command-line name.
    pub fn from_name(name: &str) -> Option<Solver> {
        Solver::ALL.into_iter().find(|s| s.as_str().eq_ignore_ascii_case(name.trim()))
    }
}

/// Settings of the solve stage.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct SolveOptions {
    /// The floor solver.
    pub solver: Solver,
    /// The seed of every tie-break.
    pub seed: u64,
    /// The most search nodes (poses tried) per room; the search never looks at the clock.
    pub node_budget: u64,
    /// The radius of the agent that must reach every object and all the free floor, metres.
    pub agent_radius_m: f64,
    /// Whether the rooms of a scene are solved on rayon's threads (the default) or one after
    /// the other on the calling thread (`holoc batch`, whose jobs are what runs in parallel:
    /// rayon's workers spin for a while each time they run out of rooms). The layout is the
    /// same either way.
    pub rooms_in_parallel: bool,
}

impl Default for SolveOptions {
    fn default() -> SolveOptions {
        SolveOptions {
            solver: Solver::Dfs,
            seed: 0,
            node_budget: DEFAULT_NODE_BUDGET,
            agent_radius_m: constraints::AGENT_RADIUS_M,
            rooms_in_parallel: true,
        }
    }
}

/// The longest side of a room the solver accepts, metres (larger rooms are E0501).
pub const MAX_ROOM_SIDE_M: f64 = 100.0;

/// The default node budget per room.
pub const DEFAULT_NODE_BUDGET: u64 = 1000;
/// The most floor objects the solver places in one room; the ones after them in placement
/// order are left out (W0504). A real room holds a few dozen; the limit keeps a runaway scene
/// (a room of 10,000 boxes) to seconds.
pub const MAX_FLOOR_OBJECTS_PER_ROOM: usize = 100;
/// The largest node budget the DFS takes (about 6 s in the slowest corpus room); `--node-budget`
/// refuses more.
pub const MAX_NODE_BUDGET: u64 = 10_000;

/// A hole in a wall: a door or a window.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct WallHole {
    /// Start of the hole along the wall, metres from the wall's first end.
    pub from_m: f64,
    /// End of the hole along the wall, metres from the wall's first end.
    pub to_m: f64,
    /// Height of the bottom above the floor, metres (0 for doors).
    pub bottom_m: f64,
    /// Height of the top above the floor, metres.
    pub top_m: f64,
    /// Whether it is a window (else a door or an open connection).
    pub window: bool,
}

/// A straight wall of the room, from `a` to `b`, with its holes.
#[derive(Clone, Debug, PartialEq)]
pub struct WallSegment {
    /// First end, metres.
    pub a: [f64; 2],
    /// Second end, metres.
    pub b: [f64; 2],
    /// Doors and windows in it.
    pub holes: Vec<WallHole>,
}

/// A relation of a floor object to an earlier floor object of the same problem.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ProblemConstraint {
    /// The relation as the layout means it: a chair `near` (or `face to`) a desk or table is
    /// drawn up to it (`in front of`/`behind` a desk, `around` a table; [`draw_up_seats`]).
    pub kind: RelationKind,
    /// The relation as the scene writes it (what the report prints).
    pub written: RelationKind,
    /// Whether the layout adds it, unwritten: the main seat of its room's seating group
    /// facing its screen ([`seating_groups`]), a set of desks in rows ([`desk_rows`]).
    pub implied: bool,
    /// Index of the target in [`RoomProblem::objects`] (earlier, but for an implied seating
    /// group's seat, which waits for its screen: [`targets_first`]).
    pub target: usize,
    /// Where the constraint is written.
    pub span: Option<Span>,
}

/// A floor object to place.
#[derive(Clone, Debug, PartialEq)]
pub struct FloorObject {
    /// The instance name, e.g. `sofa-0`.
    pub id: String,
    /// Footprint `[width, depth]` at rotation 0, metres.
    pub size: [f64; 2],
    /// Height, metres.
    pub height: f64,
    /// `edge` (also when none is written) or `middle`.
    pub global: GlobalKind,
    /// What it is for (from its category's words): decides what its relations mean and which
    /// use-clearance it keeps.
    pub role: constraints::Role,
    /// The relations to earlier objects.
    pub constraints: Vec<ProblemConstraint>,
    /// A pinned pose: used as it is (and reported if it breaks a hard rule).
    pub pin: Option<Pose>,
    /// The AI2-THOR object type of its asset, when known: decides the surfaces it carries
    /// things on ([`surfaces::carrier`]).
    pub thor_type: Option<String>,
    /// Where the object is declared.
    pub span: Option<Span>,
}

/// A wall object to hang.
#[derive(Clone, Debug, PartialEq)]
pub struct WallObject {
    /// The instance name.
    pub id: String,
    /// `[width, depth, height]`, metres.
    pub size: [f64; 3],
    /// The floor object (index in [`RoomProblem::objects`]) it hangs above.
    pub above: Option<usize>,
    /// Height of its bottom above the floor, metres (default 1.5 m, `others::DEFAULT_WALL_HEIGHT_M`).
    pub height_m: Option<f64>,
    /// The AI2-THOR object type of its asset, when known (a towel holder hangs its towels).
    pub thor_type: Option<String>,
    /// Whether its asset can be made again at another size (an asset holoc made): curtains
    /// and blinds then dress a window at its size.
    pub resizable: bool,
    /// Where the object is declared.
    pub span: Option<Span>,
}

/// What a small object is put on: a floor object or a wall object of the problem.
#[derive(Clone, Copy, Debug, PartialEq, Eq, PartialOrd, Ord, Hash)]
pub enum Holder {
    /// An index into [`RoomProblem::objects`].
    Floor(usize),
    /// An index into [`RoomProblem::wall_objects`].
    Wall(usize),
}

/// A small object to put on a receptacle.
#[derive(Clone, Debug, PartialEq)]
pub struct SmallObject {
    /// The instance name, e.g. `book-0`.
    pub id: String,
    /// What it is, as the `on top` line names it (e.g. `book`): things of the same name may be
    /// piled when they do not fit side by side.
    pub item: String,
    /// `[width, depth, height]`, metres.
    pub size: [f64; 3],
    /// The receptacle.
    pub on: Holder,
    /// When its receptacle may not carry it (a desk lamp on an armchair, a plant on a plant):
    /// the receptacles of the room that may, in the order they are declared; the nearest one
    /// placed with room for it takes it (W0506), else it is left out. `None`: it stays on its
    /// receptacle.
    pub elsewhere: Option<Vec<Holder>>,
    /// When the receptacle it is declared on is left out before the layout (no asset): that
    /// receptacle's name. `on` is then the first of `elsewhere`, which is never `None`.
    pub absent: Option<String>,
    /// When its receptacle is left out (`absent`): the floor and wall objects that receptacle
    /// was asked to stand by (its relations' targets, the object it hangs above); the moved
    /// thing goes to the receptacle nearest to them (to the room's centre when there are none).
    pub anchor: Vec<Holder>,
    /// The AI2-THOR type of its asset, when known (which receptacles it may be moved to, and
    /// the `p` of the pair: `resolve::receptacles::move_to`).
    pub thor_type: Option<String>,
    /// Where it is declared.
    pub span: Option<Span>,
}

/// The ceiling object of a room.
#[derive(Clone, Debug, PartialEq)]
pub struct CeilingObject {
    /// Its name.
    pub id: String,
    /// `[width, depth, height]`, metres.
    pub size: [f64; 3],
    /// The floor object it hangs over (else the room's area centroid).
    pub above: Option<usize>,
    /// Where it is declared.
    pub span: Option<Span>,
}

/// Everything the solver needs about one room.
#[derive(Clone, Debug, PartialEq)]
pub struct RoomProblem {
    /// The room's name (for messages).
    pub name: String,
    /// The rectilinear outline, metres.
    pub outline: Vec<[f64; 2]>,
    /// The wall height, metres.
    pub wall_height: f64,
    /// Door keep-out zones on the floor (polygons; their bounding boxes are used).
    pub keep_out: Vec<Vec<[f64; 2]>>,
    /// The walls with their holes; when empty, the outline's edges without holes.
    pub walls: Vec<WallSegment>,
    /// Floor objects in plan order.
    pub objects: Vec<FloorObject>,
    /// Wall objects in plan order.
    pub wall_objects: Vec<WallObject>,
    /// Small objects in plan order.
    pub small_objects: Vec<SmallObject>,
    /// The ceiling object.
    pub ceiling: Option<CeilingObject>,
    /// The room's declaration.
    pub span: Option<Span>,
}

impl RoomProblem {
    /// The name of a receptacle of the room (a floor or wall object), `?` when it has none.
    pub fn holder_name(&self, h: Holder) -> &str {
        errors::holder_name(self, h)
    }

    /// The AI2-THOR type of a receptacle of the room, when known.
    pub fn holder_type(&self, h: Holder) -> Option<&str> {
        match h {
            Holder::Floor(i) => self.objects.get(i)?.thor_type.as_deref(),
            Holder::Wall(i) => self.wall_objects.get(i)?.thor_type.as_deref(),
        }
    }
}

/// One constraint in the report.
#[derive(Clone, Debug, PartialEq)]
pub struct ConstraintReport {
    /// The relation (`None` for the global constraint).
    pub kind: Option<RelationKind>,
    /// The words, e.g. `near sofa-0` or `edge`.
    pub text: String,
    /// The measurement.
    pub measure: Measure,
    /// The documented range of the measured gap (metres) the relation means for this pair, if
    /// it has one (`near`: 0.1–1.5 m, a coffee table in front of a sofa: 0.3–0.6 m…).
    pub range: Option<(f64, f64)>,
}

/// A placed floor object.
#[derive(Clone, Debug, PartialEq)]
pub struct PlacedFloor {
    /// Index in [`RoomProblem::objects`].
    pub index: usize,
    /// Its pose.
    pub pose: Pose,
    /// Its footprint.
    pub footprint: Rect,
    /// Each constraint, global first.
    pub constraints: Vec<ConstraintReport>,
    /// Its weighted score.
    pub score: f64,
    /// The solver that placed it (`dfs`, `milp`, `pin`).
    pub by: &'static str,
}

/// A placed object in world coordinates (wall, small and ceiling objects).
#[derive(Clone, Debug, PartialEq)]
pub struct PlacedObject {
    /// The instance name.
    pub id: String,
    /// The centre of its box, metres `(x, y, z)`.
    pub position_m: [f64; 3],
    /// Rotation about y, degrees.
    pub rotation_deg: f64,
    /// For small objects, the receptacle.
    pub on: Option<Holder>,
    /// When the layout sized it (curtains and blinds to the window they dress): its box
    /// `[width, depth, height]`, metres.
    pub sized_m: Option<[f64; 3]>,
}

/// An object left out, and why.
#[derive(Clone, Debug, PartialEq)]
pub struct Unplaced {
    /// The instance name.
    pub id: String,
    /// `floor`, `wall`, `small` or `ceiling`.
    pub kind: &'static str,
    /// The hard rule that removed the last candidate poses.
    pub rule: Option<HardRule>,
    /// The full reason in words.
    pub reason: String,
    /// The code of the diagnostic that reports it (W0401 no asset, W0501 no pose, W0503 left
    /// out with its target or receptacle, W0504 over the room's limit, W0506 not allowed on
    /// its receptacle).
    pub code: crate::diag::Code,
}

/// The solved room.
#[derive(Clone, Debug, PartialEq, Default)]
pub struct RoomLayout {
    /// Placed floor objects, in plan order.
    pub floor: Vec<PlacedFloor>,
    /// Floor objects as world boxes (centre at half height), plan order.
    pub floor_world: Vec<PlacedObject>,
    /// Placed wall objects, plan order.
    pub wall: Vec<PlacedObject>,
    /// Placed small objects, plan order.
    pub small: Vec<PlacedObject>,
    /// The ceiling object.
    pub ceiling: Option<PlacedObject>,
    /// Objects left out.
    pub unplaced: Vec<Unplaced>,
    /// Total score of the floor objects.
    pub score: f64,
    /// Search nodes used.
    pub nodes: u64,
    /// Search nodes walked when the layout returned was found (the rest of the walk found
    /// nothing better).
    pub found_at: u64,
    /// Pinned floor objects (index) whose pose breaks a hard rule, one entry per rule broken;
    /// they stay as pinned.
    pub pinned_breaks: Vec<(usize, HardRule)>,
    /// Small objects put on another receptacle than the one declared, because that one may not
    /// carry them.
    pub moved: Vec<Moved>,
}

/// A small object put on another receptacle than the one declared, because people do not put
/// such a thing there (W0506).
#[derive(Clone, Debug, PartialEq)]
pub struct Moved {
    /// The small object's index.
    pub small: usize,
    /// The receptacle declared.
    pub from: Holder,
    /// The receptacle used.
    pub to: Holder,
    /// The nearer receptacles that take it but were full, nearest first.
    pub full: Vec<Holder>,
    /// The receptacle declared when it is left out for want of an asset (then `from` is the
    /// first receptacle tried).
    pub absent: Option<String>,
    /// The `p` of the pair (its AI2-THOR type on the receptacle used) in ProcTHOR's receptacle
    /// table; `None` for a pair holoc added or a thing the table cannot judge.
    pub p: Option<f64>,
}

impl RoomLayout {
    /// How many constraints (global and relations) of placed floor objects hold, and how many
    /// there are in total (unplaced objects' constraints count as not holding).
    pub fn constraint_tally(&self, problem: &RoomProblem) -> (usize, usize) {
        let total = problem.objects.iter().map(|o| 1 + o.constraints.len()).sum();
        let ok =
            self.floor.iter().flat_map(|p| &p.constraints).filter(|c| c.measure.satisfied).count();
        (ok, total)
    }
}

/// Validated inputs shared by the solvers.
pub(crate) struct Prepared<'a> {
    pub problem: &'a RoomProblem,
    pub room: RoomShape,
    pub keep_out: Vec<Rect>,
    pub windows: Vec<constraints::WindowZone>,
    pub reach: constraints::ReachGrid,
    /// The room's walls with their inward normals.
    pub walls: Vec<([f64; 2], [f64; 2], [f64; 2])>,
    /// Per object and relation, what the relation means ([`meaning_of`], worked out once).
    pub meanings: Vec<Vec<Meaning>>,
    /// Per object, whether it is used from behind ([`used_from_behind`]).
    pub from_behind: Vec<bool>,
}

impl Prepared<'_> {
    /// Object `k`'s use-clearance at `pose` ([`constraints::use_zones`]), on the side it is
    /// used from.
    pub(crate) fn use_zones(&self, k: usize, pose: &Pose) -> (Vec<Rect>, bool) {
        let o = &self.problem.objects[k];
        constraints::use_zones(o.role, &use_pose(pose, self.from_behind[k]), o.size, o.height)
    }

    /// What relation `c` of floor object `k` means.
    pub(crate) fn meaning(&self, k: usize, c: usize) -> Meaning {
        self.meanings[k][c]
    }

    /// The static hard rule (inside the room, global, door zones, front clearance, windows)
    /// that floor object `k` breaks at `pose`, if any.
    pub(crate) fn static_rule(&self, k: usize, pose: &Pose) -> Option<constraints::HardRule> {
        let obj = &self.problem.objects[k];
        // A seat turned to its screen by an implied seating group may leave the wall.
        let global = (!(obj.constraints.iter().any(|c| c.implied)
            && leaves_wall_to_watch(self.problem, k)))
        .then_some(obj.global);
        constraints::static_rules(
            pose,
            obj.size,
            window_height(obj),
            global,
            &self.room,
            &self.keep_out,
            &self.windows,
        )
    }

    /// [`Prepared::static_rule`] without the global constraint.
    pub(crate) fn static_rule_anywhere(
        &self,
        k: usize,
        pose: &Pose,
    ) -> Option<constraints::HardRule> {
        let obj = &self.problem.objects[k];
        constraints::static_rules(
            pose,
            obj.size,
            window_height(obj),
            None,
            &self.room,
            &self.keep_out,
            &self.windows,
        )
    }
}

/// The height an object counts as for the window rule: its own, or for a screen (a TV stand
/// with its TV) at least [`constraints::SCREEN_TOP_M`].
pub(crate) fn window_height(obj: &FloorObject) -> f64 {
    if obj.role == Role::Screen {
        obj.height.max(constraints::SCREEN_TOP_M)
    } else {
        obj.height
    }
}

/// Places every object of one room.
pub fn solve_room(problem: &RoomProblem, options: &SolveOptions) -> Outcome<RoomLayout> {
    let mut diags: Vec<Diagnostic> = Vec::new();
    let Some(room) = RoomShape::new(&problem.outline)
        .filter(|r| r.bounds.width().max(r.bounds.depth()) <= MAX_ROOM_SIDE_M)
    else {
        diags.push(errors::bad_room(problem));
        return Outcome::new(RoomLayout::default(), diags);
    };
    let objects_ok = errors::check_objects(problem, &mut diags);
    if !objects_ok {
        return Outcome::new(RoomLayout::default(), diags);
    }
    let keep_out: Vec<Rect> =
        problem.keep_out.iter().filter(|p| !p.is_empty()).map(|p| Rect::bounding(p)).collect();
    let windows = others::window_zones(problem, &room);
    let reach = constraints::ReachGrid::new(&room, &keep_out, options.agent_radius_m);
    let walls = room.walls();
    let meanings = problem
        .objects
        .iter()
        .enumerate()
        .map(|(k, o)| o.constraints.iter().map(|c| meaning_of(problem, k, c)).collect())
        .collect();
    let from_behind = (0..problem.objects.len()).map(|k| used_from_behind(problem, k)).collect();
    let prep = Prepared { problem, room, keep_out, windows, reach, walls, meanings, from_behind };
    let mut layout = match options.solver {
        Solver::Dfs => dfs::solve(&prep, options),
        Solver::Milp => milp::solve(&prep, options),
    };
    others::finish(&prep, &mut layout);
    // One diagnostic per pinned object, naming every rule its pose breaks.
    let mut breaks: std::collections::BTreeMap<usize, Vec<HardRule>> =
        std::collections::BTreeMap::new();
    for &(k, rule) in &layout.pinned_breaks {
        breaks.entry(k).or_default().push(rule);
    }
    for (k, rules) in breaks {
        diags.push(errors::pin_breaks(problem, k, &rules));
    }
    for u in &layout.unplaced {
        diags.push(errors::unplaced(problem, u));
    }
    for m in &layout.moved {
        diags.push(errors::moved(problem, m));
    }
    Outcome::new(layout, diags)
}

/// Places the floor objects with the greedy baseline: each object in plan order takes its
/// best-scored pose, with no backtracking. Used by the benchmarks to compare with the search.
pub fn solve_room_greedy(problem: &RoomProblem, options: &SolveOptions) -> Outcome<RoomLayout> {
    let greedy = SolveOptions { solver: Solver::Dfs, node_budget: 0, ..*options };
    solve_room(problem, &greedy)
}

/// Measures every constraint of a floor object at a pose against already placed targets
/// (`poses[i]` is the pose of object `i`, if placed). Returns the reports (global first) and
/// the weighted score.
pub fn measure_object(
    problem: &RoomProblem,
    room: &RoomShape,
    index: usize,
    pose: &Pose,
    poses: &[Option<Pose>],
) -> (Vec<ConstraintReport>, f64) {
    let obj = &problem.objects[index];
    let g = constraints::global(obj.global, pose, obj.size, room);
    let gname = match obj.global {
        GlobalKind::Edge => "edge",
        GlobalKind::Middle => "middle",
    };
    let mut out =
        vec![ConstraintReport { kind: None, text: gname.to_string(), measure: g, range: None }];
    let mut score = 0.0;
    for c in &obj.constraints {
        let target_id = problem.objects.get(c.target).map_or("?", |t| t.id.as_str());
        let meaning = meaning_of(problem, index, c);
        let by_bed = problem.objects.get(c.target).is_some_and(|t| t.role == Role::Bed);
        let note = match c.kind {
            _ if !c.implied => "",
            RelationKind::Around => " (at the table)",
            _ if obj.role == Role::Desk => " (rows)",
            _ if by_bed => " (by the bed)",
            _ => " (seating group)",
        };
        let text = format!("{} {target_id}{note}", c.written.as_str());
        let target = poses.get(c.target).copied().flatten().zip(problem.objects.get(c.target));
        let mut measure = match target {
            Some((tp, t)) => {
                constraints::relation_meant(c.kind, &meaning, pose, obj.size, &tp, t.size)
            }
            None => Measure { satisfied: false, score: 0.0, value: f64::NAN, unit: "m" },
        };
        // A screen and a seat across from each other see each other only over what is lower
        // than the line of sight.
        if meaning.view && measure.satisfied {
            let line = ([pose.x, pose.z], target.map_or([pose.x, pose.z], |(tp, _)| [tp.x, tp.z]));
            let blocked = poses.iter().enumerate().any(|(j, p)| {
                let (Some(p), Some(o)) = (p, problem.objects.get(j)) else { return false };
                j != index
                    && j != c.target
                    && o.height > constraints::SIGHT_LINE_M
                    && constraints::footprint(p, o.size).meets_segment(line.0, line.1)
            });
            if blocked {
                measure.satisfied = false;
                measure.score *= 0.5;
            }
        }
        score += constraints::weight(c.kind) * measure.score;
        let range = (meaning.min_gap > 0.0 || meaning.max_gap.is_finite())
            .then_some((meaning.min_gap, meaning.max_gap));
        out.push(ConstraintReport { kind: Some(c.kind), text, measure, range });
    }
    (out, score)
}

/// What constraint `c` of floor object `k` means for this pair of objects (their roles, and
/// whether they touch by nature: a nightstand by a bed, or an object also beside its target).
pub fn meaning_of(problem: &RoomProblem, k: usize, c: &ProblemConstraint) -> Meaning {
    let obj = &problem.objects[k];
    let target = problem.objects.get(c.target).map_or(Role::Other, |t| t.role);
    // Beside its target, or one of the chairs around a table (drawn up to it).
    let beside = obj.constraints.iter().any(|d| {
        d.target == c.target
            && (matches!(
                d.kind,
                RelationKind::SideOf | RelationKind::LeftOf | RelationKind::RightOf
            ) || (d.kind == RelationKind::Around && obj.role == Role::Seat && target.sat_at()))
    });
    let contact = beside || constraints::touch_by_nature(obj.role, target);
    let mut meaning = Meaning::of(c.kind, obj.role, target, contact);
    if c.kind == RelationKind::Around && obj.role == Role::Seat && target.sat_at() {
        meaning.ring = seat_ring(problem, c.target);
    }
    meaning
}

/// The seats round table `t` that the chairs `around` it share: every seat of the problem with
/// an `around` relation to it, and the largest of them.
pub fn seat_ring(problem: &RoomProblem, t: usize) -> Option<constraints::SeatRing> {
    let mut seats = 0;
    let mut seat = [0.0_f64, 0.0_f64];
    for o in &problem.objects {
        if o.role == Role::Seat
            && o.constraints.iter().any(|c| c.kind == RelationKind::Around && c.target == t)
        {
            seats += 1;
            seat = [seat[0].max(o.size[0]), seat[1].max(o.size[1])];
        }
    }
    (seats > 0).then_some(constraints::SeatRing { seats, seat })
}

/// Whether object `k` is used from behind: a desk whose seat is drawn up `behind` it (a
/// student desk facing the teacher, its chair behind it, the way the desk faces). Its
/// pull-out space is then behind it, where its chair stands, not in front, where the row
/// ahead sits.
pub(crate) fn used_from_behind(problem: &RoomProblem, k: usize) -> bool {
    problem.objects.get(k).is_some_and(|desk| desk.role == Role::Desk)
        && problem.objects.iter().any(|o| {
            o.role.is_seat()
                && o.constraints.iter().any(|c| c.target == k && c.kind == RelationKind::Behind)
        })
}

/// The table or desk that seat `k` is drawn up to (`in front of`, `behind` or `around` it).
pub(crate) fn drawn_to(problem: &RoomProblem, k: usize) -> Option<usize> {
    let o = problem.objects.get(k)?;
    if !o.role.is_seat() {
        return None;
    }
    o.constraints
        .iter()
        .find(|c| {
            matches!(c.kind, RelationKind::InFrontOf | RelationKind::Behind | RelationKind::Around)
                && problem.objects.get(c.target).is_some_and(|t| t.role.sat_at())
        })
        .map(|c| c.target)
}

/// Whether objects `a` and `b` are chairs drawn up to two different tables or desks: each
/// keeps [`constraints::CHAIRS_APART_M`] behind it free of the other ([`back_zone`]).
pub(crate) fn back_to_back(problem: &RoomProblem, a: usize, b: usize) -> bool {
    match (drawn_to(problem, a), drawn_to(problem, b)) {
        (Some(x), Some(y)) => x != y,
        _ => false,
    }
}

/// The way behind a chair at `pose` (footprint `size` at rotation 0) that the chairs of another
/// table keep out of: [`constraints::CHAIRS_APART_M`] deep, as wide as the chair.
pub(crate) fn back_zone(pose: &Pose, size: [f64; 2]) -> Rect {
    let back = Pose { rot: Rot::from_deg(pose.rot.deg() + 180.0), ..*pose };
    constraints::front_zone(&back, size, constraints::CHAIRS_APART_M)
}

/// The pose whose front is the side an object is used from: turned round when it is used
/// from behind.
pub(crate) fn use_pose(pose: &Pose, from_behind: bool) -> Pose {
    if from_behind {
        Pose { rot: Rot::from_deg(pose.rot.deg() + 180.0), ..*pose }
    } else {
        *pose
    }
}

/// The use-clearance of floor object `k` at `pose` ([`constraints::use_zones`]) on the side it
/// is used from: behind a desk whose chair is drawn up `behind` it (a student desk facing the
/// teacher, its chair behind it).
pub fn use_zones_of(problem: &RoomProblem, k: usize, pose: &Pose) -> (Vec<Rect>, bool) {
    let o = &problem.objects[k];
    let pose = use_pose(pose, used_from_behind(problem, k));
    constraints::use_zones(o.role, &pose, o.size, o.height)
}

/// How many of the placed floor objects that have a use-clearance keep it free (inside the
/// room and clear of placed furniture they have no relation with; one open side for a bed),
/// and how many have one: what the benchmark reports.
pub fn use_clearances_kept(problem: &RoomProblem, layout: &RoomLayout) -> (usize, usize) {
    let Some(room) = RoomShape::new(&problem.outline) else { return (0, 0) };
    let related = |a: usize, b: usize| {
        problem.objects[a].constraints.iter().any(|x| x.target == b)
            || problem.objects[b].constraints.iter().any(|x| x.target == a)
    };
    let (mut kept, mut total) = (0, 0);
    for p in &layout.floor {
        let o = &problem.objects[p.index];
        let (zones, all) = use_zones_of(problem, p.index, &p.pose);
        if zones.is_empty() {
            continue;
        }
        total += 1;
        let free = |z: &Rect| {
            room.contains_rect(z)
                && layout
                    .floor
                    .iter()
                    .filter(|q| {
                        q.index != p.index
                            && !o
                                .role
                                .lets_in(problem.objects[q.index].role, related(p.index, q.index))
                    })
                    .all(|q| !q.footprint.overlaps(z))
        };
        if if all { zones.iter().all(free) } else { zones.iter().any(free) } {
            kept += 1;
        }
    }
    (kept, total)
}

/// The largest closed pocket of free floor (square metres) an agent of `radius` coming
/// through the room's doors leaves unreached in a layout: what the benchmark reports.
pub fn largest_pocket_m2(problem: &RoomProblem, layout: &RoomLayout, radius: f64) -> f64 {
    let Some(room) = RoomShape::new(&problem.outline) else { return 0.0 };
    let keep_out: Vec<Rect> =
        problem.keep_out.iter().filter(|p| !p.is_empty()).map(|p| Rect::bounding(p)).collect();
    let grid = constraints::ReachGrid::new(&room, &keep_out, radius);
    let fps: Vec<Rect> = layout.floor.iter().map(|p| p.footprint).collect();
    grid.largest_pocket_m2(&fps)
}

/// The best score an object can reach: the sum of its relation weights.
pub fn max_score(obj: &FloorObject) -> f64 {
    obj.constraints.iter().map(|c| constraints::weight(c.kind)).sum()
}

/// What the layout reads into a room's floor objects before it places them, the same for the
/// build, the report, the benchmarks and `holoc check`'s outcomes: chairs drawn up to their
/// desks and tables whatever word the plan used ([`draw_up_seats`]) and the screen of a
/// seating group facing its main seat ([`seating_groups`]).
pub fn read_meanings(objects: &mut [FloorObject]) {
    desk_rows(objects);
    chairs_at_the_table(objects);
    nightstands_by_the_bed(objects);
    draw_up_seats(objects);
    seating_groups(objects);
}

/// Whether an object is unrelated: it has no relation and nothing relates to it.
fn unrelated(objects: &[FloorObject], k: usize) -> bool {
    objects[k].constraints.is_empty()
        && !objects.iter().any(|o| o.constraints.iter().any(|c| c.target == k))
}

/// Nightstands (bedside tables) that a plan relates to nothing in a room with a bed stand by
/// the room's largest bed, one to a side as far as they go: `side of` and `near` it (implied,
/// printed `(by the bed)`), their unwritten `edge` giving way.
pub fn nightstands_by_the_bed(objects: &mut [FloorObject]) {
    let area = |o: &FloorObject| o.size[0] * o.size[1];
    let Some(bed) = (0..objects.len())
        .filter(|&i| objects[i].role == Role::Bed)
        .max_by(|&a, &b| area(&objects[a]).total_cmp(&area(&objects[b])).then(b.cmp(&a)))
    else {
        return;
    };
    let bedside = |id: &str| {
        let id = id.to_lowercase();
        id.contains("night") || id.contains("bedside")
    };
    let stands: Vec<usize> = (0..objects.len())
        .filter(|&k| {
            objects[k].role == Role::SideTable
                && objects[k].pin.is_none()
                && bedside(&objects[k].id)
                && unrelated(objects, k)
        })
        .collect();
    for k in stands {
        for kind in [RelationKind::SideOf, RelationKind::Near] {
            objects[k].constraints.push(ProblemConstraint {
                kind,
                written: kind,
                implied: true,
                target: bed,
                span: None,
            });
        }
    }
}

/// Chairs that a plan relates to nothing in a room with a table (the original system's
/// replayed plans write a conference or dining room so: a table, ten chairs, nothing related)
/// are the table's chairs, as a person reads the room: each is `around` the room's largest
/// table (an implied relation, printed `(at the table)`), sharing its seats, and the table,
/// when nothing else relates to it, stands in the middle. Armchairs,
/// recliners, benches and lounge chairs are not (they stand by a coffee table or a wall).
pub fn chairs_at_the_table(objects: &mut [FloorObject]) {
    let area = |o: &FloorObject| o.size[0] * o.size[1];
    let Some(table) = (0..objects.len())
        .filter(|&i| objects[i].role == Role::Table)
        .max_by(|&a, &b| area(&objects[a]).total_cmp(&area(&objects[b])).then(b.cmp(&a)))
    else {
        return;
    };
    let chairs: Vec<usize> = (0..objects.len())
        .filter(|&k| {
            objects[k].role == Role::Seat
                && objects[k].pin.is_none()
                && !lounging(&objects[k].id)
                && unrelated(objects, k)
        })
        .collect();
    // The table stands where its chairs can be drawn up round it (its `edge`, written by no
    // such plan, gives way to `middle`).
    if chairs.len() >= 2 && unrelated(objects, table) {
        objects[table].global = GlobalKind::Middle;
    }
    for k in chairs {
        objects[k].constraints.push(ProblemConstraint {
            kind: RelationKind::Around,
            written: RelationKind::Around,
            implied: true,
            target: table,
            span: None,
        });
    }
}

/// A chair (a seat, not a sofa) that relates to a desk or table only by `near` or `face to` is
/// drawn up to it, as a person reads the plan: its first such relation means `around` a table
/// (one of the chairs that share its seats), `in front of` a desk, or `behind` a desk that
/// faces elsewhere (`face to` something, or `face same as` such a desk: a student desk facing
/// the teacher, its chair behind it facing the same way). A chair already `in front of`,
/// `behind` or `around` its desk or table keeps its relations as they are. The report prints
/// the relation as written ([`ProblemConstraint::written`]).
pub fn draw_up_seats(objects: &mut [FloorObject]) {
    for k in 0..objects.len() {
        if !objects[k].role.is_seat() {
            continue;
        }
        let mut targets: Vec<usize> = objects[k].constraints.iter().map(|c| c.target).collect();
        targets.sort_unstable();
        targets.dedup();
        for t in targets {
            let Some(target) = objects.get(t) else { continue };
            if t == k || !target.role.sat_at() {
                continue;
            }
            let mine = &objects[k].constraints;
            let drawn = mine.iter().any(|c| {
                c.target == t
                    && matches!(
                        c.kind,
                        RelationKind::InFrontOf | RelationKind::Behind | RelationKind::Around
                    )
            });
            if drawn {
                continue;
            }
            let Some(ci) = mine.iter().position(|c| {
                c.target == t && matches!(c.kind, RelationKind::Near | RelationKind::FaceTo)
            }) else {
                continue;
            };
            let kind = if target.role == Role::Table {
                RelationKind::Around
            } else if faces_elsewhere(objects, t, 0) {
                RelationKind::Behind
            } else {
                RelationKind::InFrontOf
            };
            objects[k].constraints[ci].kind = kind;
        }
    }
}

/// Desks of one set (`count N`: the same name before the instance number) that all `face to`
/// the same object and have no relation among themselves (the original system's plans write
/// a classroom so) stand in rows facing it, as a person sets out a classroom: rows of
/// `ceil(n / floor(sqrt(n)))` desks (ten desks: rows of four, four and two), the first desk `in
/// front of` what they face, each next desk of a row `side of` and `near` the one before it,
/// the first of each next row `behind` and `center aligned` with the first of the row before,
/// every desk `face same as` the one it follows. The relations are implied
/// ([`ProblemConstraint::implied`]): the report prints them with `(rows)`.
pub fn desk_rows(objects: &mut [FloorObject]) {
    let stem = |id: &str| id.rsplit_once('-').map_or(id.to_string(), |(s, _)| s.to_string());
    let mut done = vec![false; objects.len()];
    for first in 0..objects.len() {
        if done[first] || objects[first].role != Role::Desk {
            continue;
        }
        let name = stem(&objects[first].id);
        let set: Vec<usize> = (first..objects.len())
            .filter(|&i| objects[i].role == Role::Desk && stem(&objects[i].id) == name)
            .collect();
        for &i in &set {
            done[i] = true;
        }
        if set.len() < 3 {
            continue;
        }
        let faced = |o: &FloorObject| {
            o.constraints.iter().find(|c| c.kind == RelationKind::FaceTo).map(|c| c.target)
        };
        let Some(target) = faced(&objects[first]) else { continue };
        let alike = set.iter().all(|&i| {
            faced(&objects[i]) == Some(target)
                && !set.contains(&target)
                && !objects[i].constraints.iter().any(|c| set.contains(&c.target))
        });
        if !alike {
            continue;
        }
        let n = set.len();
        let rows = ((n as f64).sqrt().floor() as usize).max(1);
        let per_row = n.div_ceil(rows);
        let implied = |kind: RelationKind, target: usize| ProblemConstraint {
            kind,
            written: kind,
            implied: true,
            target,
            span: None,
        };
        for (j, &i) in set.iter().enumerate() {
            let added: Vec<ProblemConstraint> = if j == 0 {
                let ahead = objects[i]
                    .constraints
                    .iter()
                    .any(|c| c.target == target && c.kind == RelationKind::InFrontOf);
                if ahead {
                    Vec::new()
                } else {
                    vec![implied(RelationKind::InFrontOf, target)]
                }
            } else if j % per_row != 0 {
                let before = set[j - 1];
                vec![
                    implied(RelationKind::SideOf, before),
                    implied(RelationKind::Near, before),
                    implied(RelationKind::FaceSameAs, before),
                ]
            } else {
                let ahead = set[j - per_row];
                vec![
                    implied(RelationKind::Behind, ahead),
                    implied(RelationKind::CenterAligned, ahead),
                    implied(RelationKind::FaceSameAs, ahead),
                ]
            };
            objects[i].constraints.extend(added);
        }
    }
}

/// Whether desk `t` faces something other than its chair: it is `face to` something, or `face
/// same as` a desk that does (a row of student desks facing the teacher).
fn faces_elsewhere(objects: &[FloorObject], t: usize, depth: usize) -> bool {
    let Some(desk) = objects.get(t) else { return false };
    depth < 64
        && desk.constraints.iter().any(|c| match c.kind {
            RelationKind::FaceTo => !objects.get(c.target).is_some_and(|o| o.role.is_seat()),
            RelationKind::FaceSameAs => {
                c.target != t
                    && objects.get(c.target).is_some_and(|o| o.role == Role::Desk)
                    && faces_elsewhere(objects, c.target, depth + 1)
            }
            _ => false,
        })
}

/// A room with a screen (a TV or its stand) and a sofa is a seating group even when its plan
/// relates none of them: a screen no seat, sofa or bed relates to (and that relates to none)
/// faces the room's main seat (its largest sofa) by the viewing rule, as an implied `face to`
/// ([`ProblemConstraint::implied`]) on the sofa, turned to its screen.
pub fn seating_groups(objects: &mut [FloorObject]) {
    let watcher = |r: Role| matches!(r, Role::Seat | Role::Sofa | Role::Bed);
    let area = |o: &FloorObject| o.size[0] * o.size[1];
    let Some(main) = (0..objects.len())
        .filter(|&i| objects[i].role == Role::Sofa)
        .max_by(|&a, &b| area(&objects[a]).total_cmp(&area(&objects[b])).then(b.cmp(&a)))
    else {
        return;
    };
    for s in 0..objects.len() {
        if objects[s].role != Role::Screen {
            continue;
        }
        let related = objects[s]
            .constraints
            .iter()
            .any(|c| objects.get(c.target).is_some_and(|t| watcher(t.role)))
            || objects
                .iter()
                .any(|o| watcher(o.role) && o.constraints.iter().any(|c| c.target == s));
        if related {
            continue;
        }
        // The seat turns to its screen: the screen stands where the room puts it (against a
        // wall) and is placed first ([`targets_first`]); the seat faces it from a viewing
        // distance, off the wall when the room is too deep for it to watch from there
        // ([`leaves_wall_to_watch`]).
        objects[main].constraints.push(ProblemConstraint {
            kind: RelationKind::FaceTo,
            written: RelationKind::FaceTo,
            implied: true,
            target: s,
            span: None,
        });
    }
    coffee_table_group(objects, main);
}

/// The rest of a seating group its plan did not write: the room's coffee table that nothing
/// relates to stands `in front of` the main sofa (0.3–0.6 m before it), and the armchairs,
/// accent, lounge and club chairs and recliners that nothing relates to stand `near` the
/// coffee table and `face to` it, as a person sets out a living room. Implied relations,
/// printed `(seating group)`; their `edge`, which no such plan wrote, gives way.
fn coffee_table_group(objects: &mut [FloorObject], main: usize) {
    let area = |o: &FloorObject| o.size[0] * o.size[1];
    let Some(table) = (0..objects.len())
        .filter(|&i| {
            objects[i].role == Role::LowTable && objects[i].pin.is_none() && unrelated(objects, i)
        })
        .max_by(|&a, &b| area(&objects[a]).total_cmp(&area(&objects[b])).then(b.cmp(&a)))
    else {
        return;
    };
    let implied = |kind: RelationKind, target: usize| ProblemConstraint {
        kind,
        written: kind,
        implied: true,
        target,
        span: None,
    };
    let seats: Vec<usize> = (0..objects.len())
        .filter(|&k| {
            objects[k].role == Role::Seat
                && objects[k].pin.is_none()
                && lounging(&objects[k].id)
                && unrelated(objects, k)
        })
        .collect();
    objects[table].constraints.push(implied(RelationKind::InFrontOf, main));
    for k in seats {
        objects[k].constraints.push(implied(RelationKind::Near, table));
        objects[k].constraints.push(implied(RelationKind::FaceTo, table));
    }
}

/// A seat one lounges in (an armchair, recliner, bench, lounge, accent, club, rocking or
/// bean-bag chair), by the words of its name: not a chair drawn up to a table.
fn lounging(id: &str) -> bool {
    let id = id.to_lowercase();
    ["armchair", "recliner", "bench", "lounge", "accent", "club", "rocking", "bean"]
        .iter()
        .any(|w| id.contains(w))
}

/// Whether floor object `k` is a piece of a seating group its plan did not write (the sofa's
/// implied `face to` its screen, the coffee table before it, the armchairs by it), or a chair
/// its plan relates to nothing that is drawn up to the room's table (an implied `around`):
/// its `edge`, which no plan wrote either, gives way to the viewing rule or the table's seats, so that it may stand off the wall facing the screen from a viewing distance
/// (a sofa floating in a room deeper than 4.5 m, its back to the rest of the room).
pub fn leaves_wall_to_watch(problem: &RoomProblem, k: usize) -> bool {
    let Some(obj) = problem.objects.get(k) else { return false };
    obj.role != Role::Desk && obj.constraints.iter().any(|c| c.implied)
}

/// The objects of a problem in an order in which every relation's target comes before the
/// object that refers to it when it can: plan order, but an object whose target comes later
/// (an implied seating group's sofa, which turns to its screen) waits for it. Plans whose
/// relations all refer to earlier objects keep their order; a cycle is broken at the
/// earliest object left.
pub fn targets_first(problem: &RoomProblem, members: &[usize]) -> Vec<usize> {
    let mut left: Vec<usize> = members.to_vec();
    let mut out = Vec::with_capacity(left.len());
    while !left.is_empty() {
        let ready = left
            .iter()
            .position(|&k| {
                problem.objects[k]
                    .constraints
                    .iter()
                    .all(|c| c.target == k || !left.contains(&c.target))
            })
            .unwrap_or(0);
        out.push(left.remove(ready));
    }
    out
}

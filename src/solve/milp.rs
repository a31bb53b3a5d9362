//! The MILP floor solver: one small mixed-integer program per object and rotation, in plan
//! order, with earlier objects fixed.
//!
//! For an object at a fixed rotation the variables are its centre `(x, z)`; binaries choose the
//! room rectangle that holds it (the room is a union of maximal rectangles), the wall its back
//! touches (`edge`), the side of every obstacle it keeps to (non-overlap as a four-way
//! disjunction), and whether each soft relation holds. Obstacles are added lazily: the first
//! program sees only the door zones and the object's targets; every obstacle the solution
//! overlaps is added and the program solved again (at most [`MAX_ROUNDS`] times); so is every
//! use-clearance the solution breaks ([`clearance_obstacles`]). The result
//! is checked with the shared hard rules and scored with the shared scorer; the best rotation
//! wins. When no rotation gives a valid pose the object falls back to the DFS candidates.

use good_lp::{
    constraint, variable, Expression, ProblemVariables, Solution, SolverModel, Variable,
};

use super::candidates::{derived_candidates, fast_score, static_candidates, Cand};
use super::constraints::{self, footprint, half_extents, HardRule, Pose, Rect, Rot};
use super::{measure_object, PlacedFloor, Prepared, RoomLayout, SolveOptions, Unplaced};
use crate::check::scene::{GlobalKind, RelationKind};

/// Rounds of lazy obstacle generation per program.
pub const MAX_ROUNDS: usize = 6;

#[cfg(feature = "highs")]
fn backend(p: good_lp::variable::UnsolvedProblem) -> impl SolverModel {
    good_lp::highs(p)
}

#[cfg(not(feature = "highs"))]
fn backend(p: good_lp::variable::UnsolvedProblem) -> good_lp::solvers::microlp::MicroLpProblem {
    good_lp::microlp(p)
}

/// A linear model under construction: variables, constraints, objective.
struct Model {
    vars: ProblemVariables,
    cons: Vec<good_lp::Constraint>,
    objective: Expression,
}

impl Model {
    fn binary(&mut self) -> Variable {
        self.vars.add(variable().binary())
    }
}

/// `coord + sign·h` for a footprint side along one axis: the expression of the side of the
/// footprint that lies furthest along `axis` (a unit axis vector).
fn far_side(x: Variable, z: Variable, h: [f64; 2], axis: [f64; 2]) -> Expression {
    if axis[0] == 0.0 {
        axis[1] * z + h[1]
    } else {
        axis[0] * x + h[0]
    }
}

/// The object's centre projected on a unit axis.
fn along(x: Variable, z: Variable, axis: [f64; 2]) -> Expression {
    if axis[0] == 0.0 {
        axis[1] * z + 0.0
    } else {
        axis[0] * x + 0.0
    }
}

fn proj_max(r: &Rect, axis: [f64; 2]) -> f64 {
    if axis[0] > 0.0 {
        r.max_x
    } else if axis[0] < 0.0 {
        -r.min_x
    } else if axis[1] > 0.0 {
        r.max_z
    } else {
        -r.min_z
    }
}

fn proj_range(r: &Rect, axis: [f64; 2]) -> (f64, f64) {
    let a = proj_max(r, axis);
    let b = -proj_max(r, [-axis[0], -axis[1]]);
    (b.min(a), a.max(b))
}

/// Solves one object at one rotation; `obstacles` are rectangles it must not overlap.
fn solve_one(
    prep: &Prepared<'_>,
    k: usize,
    rot: Rot,
    poses: &[Option<Pose>],
    obstacles: &[Rect],
) -> Option<Pose> {
    let obj = &prep.problem.objects[k];
    let h = half_extents(obj.size, rot);
    let b = prep.room.bounds;
    let big = 2.0 * (b.width() + b.depth()) + 10.0;
    let mut m =
        Model { vars: ProblemVariables::new(), cons: Vec::new(), objective: Expression::from(0.0) };
    let x = m.vars.add(variable().min(b.min_x + h[0]).max(b.max_x - h[0]));
    let z = m.vars.add(variable().min(b.min_z + h[1]).max(b.max_z - h[1]));
    if b.min_x + h[0] > b.max_x - h[0] || b.min_z + h[1] > b.max_z - h[1] {
        return None;
    }
    // The rectangle that must lie inside the room: the footprint plus its front clearance, or
    // for `middle` the footprint grown by the middle gap.
    let f = rot.front();
    let grow = if obj.global == GlobalKind::Middle { constraints::MIDDLE_GAP_M } else { 0.0 };
    // In front: the front clearance, or the use-clearance when it is deeper (a desk's pull-out
    // space, a counter's aisle), which must lie inside the room too.
    let ahead = constraints::FRONT_CLEARANCE_M.max(obj.role.front_clearance(obj.height));
    let lo = [
        h[0] + grow + if f[0] < 0.0 { ahead } else { 0.0 },
        h[1] + grow + if f[1] < 0.0 { ahead } else { 0.0 },
    ];
    let hi = [
        h[0] + grow + if f[0] > 0.0 { ahead } else { 0.0 },
        h[1] + grow + if f[1] > 0.0 { ahead } else { 0.0 },
    ];
    let fits: Vec<&Rect> = prep
        .room
        .rects
        .iter()
        .filter(|r| r.width() + 1e-9 >= lo[0] + hi[0] && r.depth() + 1e-9 >= lo[1] + hi[1])
        .collect();
    if fits.is_empty() {
        return None;
    }
    let mut pick: Expression = Expression::from(0.0);
    for r in &fits {
        let y = m.binary();
        pick += y;
        m.cons.push(constraint!(x - lo[0] >= r.min_x - big * (1.0 - y)));
        m.cons.push(constraint!(x + hi[0] <= r.max_x + big * (1.0 - y)));
        m.cons.push(constraint!(z - lo[1] >= r.min_z - big * (1.0 - y)));
        m.cons.push(constraint!(z + hi[1] <= r.max_z + big * (1.0 - y)));
    }
    m.cons.push(constraint!(pick == 1.0));
    // A seat of a seating group its plan did not write (an implied `face to` its screen) may
    // stand off the wall to keep the viewing rule: its `edge` is then a preference.
    let off_wall = super::leaves_wall_to_watch(prep.problem, k);
    if obj.global == GlobalKind::Edge {
        // The back touches a wall whose inward normal is the object's front.
        let mut any: Expression = Expression::from(0.0);
        let mut count = 0;
        for &(a, bb, n) in &prep.walls {
            if n != f {
                continue;
            }
            count += 1;
            let e = m.binary();
            any += e;
            let back = far_side(x, z, h, [-f[0], -f[1]]);
            let wall = if f[0] == 0.0 { -f[1] * a[1] } else { -f[0] * a[0] };
            m.cons.push(constraint!(back.clone() <= wall + big * (1.0 - e)));
            m.cons.push(constraint!(back >= wall - big * (1.0 - e)));
            let (s0, s1) = if f[0] == 0.0 {
                (a[0].min(bb[0]), a[0].max(bb[0]))
            } else {
                (a[1].min(bb[1]), a[1].max(bb[1]))
            };
            let lateral = if f[0] == 0.0 { x } else { z };
            m.cons.push(constraint!(lateral >= s0 - big * (1.0 - e)));
            m.cons.push(constraint!(lateral <= s1 + big * (1.0 - e)));
        }
        if count == 0 && !off_wall {
            return None;
        }
        if off_wall {
            m.cons.push(constraint!(any.clone() <= 1.0));
            m.objective += 0.5 * any;
        } else {
            m.cons.push(constraint!(any == 1.0));
        }
    }
    // Non-overlap: one of four sides for every obstacle.
    for o in obstacles {
        let (l, r, s, n) = (m.binary(), m.binary(), m.binary(), m.binary());
        m.cons.push(constraint!(x + h[0] <= o.min_x + big * (1.0 - l)));
        m.cons.push(constraint!(x - h[0] >= o.max_x - big * (1.0 - r)));
        m.cons.push(constraint!(z + h[1] <= o.min_z + big * (1.0 - s)));
        m.cons.push(constraint!(z - h[1] >= o.max_z - big * (1.0 - n)));
        m.cons.push(constraint!(l + r + s + n >= 1.0));
    }
    // Soft relations.
    let scale = b.width() + b.depth();
    for (ci, c) in obj.constraints.iter().enumerate() {
        let (Some(Some(tp)), Some(t)) = (poses.get(c.target), prep.problem.objects.get(c.target))
        else {
            continue;
        };
        let tf = footprint(tp, t.size);
        // The gap range the relation means for this pair (a coffee table 0.3–0.6 m in front of
        // its sofa, `near` not touching): the same meanings as the DFS and the report.
        let meaning = prep.meaning(k, ci);
        let (gap_min, gap_max) = (meaning.min_gap, meaning.max_gap);
        let w = constraints::weight(c.kind);
        let tfront = tp.rot.front();
        let tright = tp.rot.right();
        let side = |m: &mut Model, axis: [f64; 2]| -> Variable {
            // Footprint beyond the target's side along `axis`, centre within its extent across.
            let ind = m.binary();
            let near_side = far_side(x, z, h, [-axis[0], -axis[1]]);
            let edge = proj_max(&tf, axis);
            m.cons.push(constraint!(-near_side.clone() >= edge + gap_min - big * (1.0 - ind)));
            if gap_max.is_finite() {
                m.cons.push(constraint!(-near_side <= edge + gap_max + big * (1.0 - ind)));
            }
            let across = [axis[1], -axis[0]];
            let (a0, a1) = proj_range(&tf, across);
            let c_across = along(x, z, across);
            m.cons.push(constraint!(c_across.clone() >= a0 - big * (1.0 - ind)));
            m.cons.push(constraint!(c_across <= a1 + big * (1.0 - ind)));
            ind
        };
        let within = |m: &mut Model, gap: f64| -> Variable {
            let ind = m.binary();
            m.cons.push(constraint!(x - h[0] <= tf.max_x + gap + big * (1.0 - ind)));
            m.cons.push(constraint!(x + h[0] >= tf.min_x - gap - big * (1.0 - ind)));
            m.cons.push(constraint!(z - h[1] <= tf.max_z + gap + big * (1.0 - ind)));
            m.cons.push(constraint!(z + h[1] >= tf.min_z - gap - big * (1.0 - ind)));
            ind
        };
        let facing = |m: &mut Model| -> Variable {
            let ind = m.binary();
            if f[0] == 0.0 {
                m.cons.push(constraint!(x >= tf.min_x - big * (1.0 - ind)));
                m.cons.push(constraint!(x <= tf.max_x + big * (1.0 - ind)));
                m.cons.push(constraint!(f[1] * z <= proj_max(&tf, f) - 0.01 + big * (1.0 - ind)));
            } else {
                m.cons.push(constraint!(z >= tf.min_z - big * (1.0 - ind)));
                m.cons.push(constraint!(z <= tf.max_z + big * (1.0 - ind)));
                m.cons.push(constraint!(f[0] * x <= proj_max(&tf, f) - 0.01 + big * (1.0 - ind)));
            }
            ind
        };
        match c.kind {
            RelationKind::Near => {
                let ind = within(&mut m, gap_max.min(constraints::NEAR_MAX_M));
                if gap_min > 0.0 {
                    // Not touching: clear of the target grown by the smallest gap on one side.
                    let g = tf.grow(gap_min);
                    let (l, r, s, n) = (m.binary(), m.binary(), m.binary(), m.binary());
                    m.cons.push(constraint!(x + h[0] <= g.min_x + big * (1.0 - l)));
                    m.cons.push(constraint!(x - h[0] >= g.max_x - big * (1.0 - r)));
                    m.cons.push(constraint!(z + h[1] <= g.min_z + big * (1.0 - s)));
                    m.cons.push(constraint!(z - h[1] >= g.max_z - big * (1.0 - n)));
                    m.cons.push(constraint!(l + r + s + n >= ind));
                }
                let (u, v) = (m.vars.add(variable().min(0.0)), m.vars.add(variable().min(0.0)));
                m.cons.push(constraint!(u >= x - tp.x));
                m.cons.push(constraint!(u >= tp.x - x));
                m.cons.push(constraint!(v >= z - tp.z));
                m.cons.push(constraint!(v >= tp.z - z));
                m.objective += w * ind - (w / scale) * (u + v);
            }
            RelationKind::Far => {
                let cap =
                    constraints::FAR_MIN_M + tf.width().max(tf.depth()) + h[0].max(h[1]) * 2.0;
                let (p, q) = (
                    m.vars.add(variable().min(0.0).max(cap)),
                    m.vars.add(variable().min(0.0).max(cap)),
                );
                let (sx, sz) = (m.binary(), m.binary());
                m.cons.push(constraint!(p <= x - tp.x + big * (1.0 - sx)));
                m.cons.push(constraint!(p <= tp.x - x + big * sx));
                m.cons.push(constraint!(q <= z - tp.z + big * (1.0 - sz)));
                m.cons.push(constraint!(q <= tp.z - z + big * sz));
                m.objective += (w / cap) * (p + q);
            }
            RelationKind::InFrontOf => {
                let i = side(&mut m, tfront);
                m.objective += w * i;
            }
            RelationKind::Behind => {
                let i = side(&mut m, [-tfront[0], -tfront[1]]);
                m.objective += w * i;
            }
            RelationKind::RightOf => {
                let i = side(&mut m, tright);
                m.objective += w * i;
            }
            RelationKind::LeftOf => {
                let i = side(&mut m, [-tright[0], -tright[1]]);
                m.objective += w * i;
            }
            RelationKind::SideOf => {
                let a = side(&mut m, tright);
                let bb = side(&mut m, [-tright[0], -tright[1]]);
                m.cons.push(constraint!(a + bb <= 1.0));
                m.objective += w * a + w * bb;
            }
            RelationKind::Around => {
                let a = within(&mut m, constraints::AROUND_MAX_M);
                let fc = facing(&mut m);
                let both = m.binary();
                m.cons.push(constraint!(both <= a));
                m.cons.push(constraint!(both <= fc));
                m.objective += w * both;
            }
            RelationKind::CenterAligned => {
                let (ax, az) = (m.binary(), m.binary());
                let tol = constraints::ALIGN_TOLERANCE_M;
                m.cons.push(constraint!(x - tp.x <= tol + big * (1.0 - ax)));
                m.cons.push(constraint!(tp.x - x <= tol + big * (1.0 - ax)));
                m.cons.push(constraint!(z - tp.z <= tol + big * (1.0 - az)));
                m.cons.push(constraint!(tp.z - z <= tol + big * (1.0 - az)));
                m.cons.push(constraint!(ax + az <= 1.0));
                m.objective += w * ax + w * az;
            }
            RelationKind::FaceTo if meaning.view => {
                // The viewing rule: across from each other (opposite rotations), each within
                // the viewing angle of the other's centre, at a viewing gap.
                // Facing it at all is worth part (as the shared score grades it).
                let ray = facing(&mut m);
                m.objective += 0.4 * w * ray;
                if tfront != [-f[0], -f[1]] {
                    continue;
                }
                let i = facing(&mut m);
                let tan = constraints::VIEWING_ANGLE_DEG.to_radians().tan();
                let across = [f[1], -f[0]];
                // Mine: the target's centre ahead, within the angle.
                let ahead = f[0] * (tp.x - x) + f[1] * (tp.z - z);
                let lateral = across[0] * (tp.x - x) + across[1] * (tp.z - z);
                m.cons.push(constraint!(lateral.clone() <= tan * ahead.clone() + big * (1.0 - i)));
                m.cons.push(constraint!(-lateral <= tan * ahead + big * (1.0 - i)));
                // Theirs: the target's ray meets my footprint and my centre is within its angle.
                let back = [-f[0], -f[1]];
                let t_lat = across[0] * (x - tp.x) + across[1] * (z - tp.z);
                let t_ahead = back[0] * (x - tp.x) + back[1] * (z - tp.z);
                let half = if f[0] == 0.0 { h[0] } else { h[1] };
                m.cons.push(constraint!(t_lat.clone() <= half + big * (1.0 - i)));
                m.cons.push(constraint!(-t_lat.clone() <= half + big * (1.0 - i)));
                m.cons.push(constraint!(t_lat.clone() <= tan * t_ahead.clone() + big * (1.0 - i)));
                m.cons.push(constraint!(-t_lat <= tan * t_ahead + big * (1.0 - i)));
                // The gap between my front and the target's near side.
                let near = -proj_max(&tf, back);
                let my_front = far_side(x, z, h, f);
                m.cons.push(constraint!(near - my_front.clone() >= gap_min - big * (1.0 - i)));
                m.cons.push(constraint!(near - my_front <= gap_max + big * (1.0 - i)));
                m.objective += 2.0 * w * i;
            }
            RelationKind::FaceTo => {
                // The ray meets the target, or the target's centre lies within 45° of the
                // facing (turned towards it).
                let ray = facing(&mut m);
                let cone = m.binary();
                let ahead = f[0] * (tp.x - x) + f[1] * (tp.z - z);
                let lateral = f[1] * (tp.x - x) - f[0] * (tp.z - z);
                m.cons.push(constraint!(lateral.clone() <= ahead.clone() + big * (1.0 - cone)));
                m.cons.push(constraint!(-lateral <= ahead.clone() + big * (1.0 - cone)));
                m.cons.push(constraint!(ahead >= 0.01 - big * (1.0 - cone)));
                let i = m.binary();
                m.cons.push(constraint!(i <= ray + cone));
                m.objective += w * (constraints::TURNED_TO_SCORE * i + 0.2 * ray);
            }
            RelationKind::FaceSameAs => {}
        }
    }
    // A small pull makes the optimum unique: free-standing objects towards the room's
    // centroid, objects against a wall away from it, into the corners, which keeps the
    // walls' length for the objects that come later (the DFS's contact term does the same).
    let centre = prep.room.centroid();
    let (cu, cv) = (m.vars.add(variable().min(0.0)), m.vars.add(variable().min(0.0)));
    if obj.global == GlobalKind::Edge {
        // cu ≤ |x − cx| through one sign binary per axis (maximised, so it reaches it).
        let (sx, sz) = (m.binary(), m.binary());
        m.cons.push(constraint!(cu <= x - centre[0] + big * sx));
        m.cons.push(constraint!(cu <= centre[0] - x + big * (1.0 - sx)));
        m.cons.push(constraint!(cv <= z - centre[1] + big * sz));
        m.cons.push(constraint!(cv <= centre[1] - z + big * (1.0 - sz)));
        m.objective += 1e-3 * (cu + cv);
    } else {
        m.cons.push(constraint!(cu >= x - centre[0]));
        m.cons.push(constraint!(cu >= centre[0] - x));
        m.cons.push(constraint!(cv >= z - centre[1]));
        m.cons.push(constraint!(cv >= centre[1] - z));
        m.objective += -1e-3 * (cu + cv);
    }
    let Model { vars, cons, objective } = m;
    let mut problem = backend(vars.maximise(objective));
    for c in cons {
        problem = problem.with(c);
    }
    let sol = problem.solve().ok()?;
    let (px, pz) = (sol.value(x), sol.value(z));
    if !(px.is_finite() && pz.is_finite()) {
        return None;
    }
    // Snap to a millimetre so that the result does not depend on the solver's round-off.
    Some(Pose { x: (px * 1000.0).round() / 1000.0, z: (pz * 1000.0).round() / 1000.0, rot })
}

/// The use-clearances object `k` at `pose` breaks, as rectangles its footprint must keep out of
/// (empty when it keeps them all): the front zone of a placed object that does not let it in
/// (a dresser's drawers, a desk's pull-out space), and, for its own front zone blocked by a
/// placed footprint, that footprint stretched back by the zone's depth (the footprint keeps out
/// of it exactly when the zone keeps out of the placed one). Added to the program's obstacles
/// like any other, so the clearances are modelled lazily, as non-overlap is. A bed's "one long
/// side open" is a choice of two zones that this does not express: the MILP leaves beds' sides
/// to the check after solving (the book says so).
fn clearance_obstacles(
    prep: &Prepared<'_>,
    k: usize,
    pose: &Pose,
    poses: &[Option<Pose>],
) -> Vec<Rect> {
    let objects = &prep.problem.objects;
    let obj = &objects[k];
    let related = |a: usize, b: usize| {
        objects[a].constraints.iter().any(|x| x.target == b)
            || objects[b].constraints.iter().any(|x| x.target == a)
    };
    let fp = footprint(pose, obj.size);
    let (own, own_all) = prep.use_zones(k, pose);
    let depth = obj.role.front_clearance(obj.height);
    let f = super::use_pose(pose, prep.from_behind[k]).rot.front();
    let mut out = Vec::new();
    // The lines of sight of the placed seating groups: a piece taller than the line keeps off
    // them (the segment between the screen's and the seat's centres, as an obstacle).
    if obj.height > constraints::SIGHT_LINE_M {
        for (i, o) in objects.iter().enumerate() {
            let Some(p) = poses.get(i).copied().flatten() else { continue };
            for (ci, c) in o.constraints.iter().enumerate() {
                if i == k || c.target == k || !prep.meaning(i, ci).view {
                    continue;
                }
                let Some(t) = poses.get(c.target).copied().flatten() else { continue };
                if fp.meets_segment([p.x, p.z], [t.x, t.z]) {
                    out.push(Rect {
                        min_x: p.x.min(t.x),
                        max_x: p.x.max(t.x),
                        min_z: p.z.min(t.z),
                        max_z: p.z.max(t.z),
                    });
                }
            }
        }
    }
    for (i, o) in objects.iter().enumerate() {
        let Some(p) = poses.get(i).copied().flatten() else { continue };
        if i == k {
            continue;
        }
        let rel = related(i, k);
        let ofp = footprint(&p, o.size);
        if own_all && !obj.role.lets_in(o.role, rel) && own.iter().any(|z| z.overlaps(&ofp)) {
            out.push(Rect {
                min_x: ofp.min_x - if f[0] > 0.0 { depth } else { 0.0 },
                max_x: ofp.max_x + if f[0] < 0.0 { depth } else { 0.0 },
                min_z: ofp.min_z - if f[1] > 0.0 { depth } else { 0.0 },
                max_z: ofp.max_z + if f[1] < 0.0 { depth } else { 0.0 },
            });
        }
        if super::back_to_back(prep.problem, i, k) {
            // The way behind each of two chairs of different tables: the other keeps out.
            let theirs = super::back_zone(&p, o.size);
            if theirs.overlaps(&fp) {
                out.push(theirs);
            }
            if super::back_zone(pose, obj.size).overlaps(&ofp) {
                let b = [-f[0], -f[1]];
                let d = constraints::CHAIRS_APART_M;
                out.push(Rect {
                    min_x: ofp.min_x - if b[0] > 0.0 { d } else { 0.0 },
                    max_x: ofp.max_x + if b[0] < 0.0 { d } else { 0.0 },
                    min_z: ofp.min_z - if b[1] > 0.0 { d } else { 0.0 },
                    max_z: ofp.max_z + if b[1] < 0.0 { d } else { 0.0 },
                });
            }
        }
        let (theirs, all) = prep.use_zones(i, &p);
        if all && !o.role.lets_in(obj.role, rel) {
            out.extend(theirs.into_iter().filter(|z| z.overlaps(&fp)));
        }
    }
    out
}

/// Places object `k` with the MILP; `None` when no rotation gives a pose that keeps the
/// shared hard rules and the use-clearances (a bed's open side excepted).
fn place_milp(
    prep: &Prepared<'_>,
    k: usize,
    poses: &[Option<Pose>],
    fps: &[Rect],
) -> Option<(Pose, f64)> {
    let obj = &prep.problem.objects[k];
    let mut best: Option<(Pose, f64)> = None;
    for rot in Rot::ALL {
        let mut obstacles: Vec<Rect> = prep.keep_out.clone();
        obstacles.extend(
            prep.windows.iter().filter(|w| super::window_height(obj) > w.sill_m).map(|w| w.zone),
        );
        for c in &obj.constraints {
            if let (Some(Some(tp)), Some(t)) =
                (poses.get(c.target), prep.problem.objects.get(c.target))
            {
                obstacles.push(footprint(tp, t.size));
            }
        }
        for _ in 0..MAX_ROUNDS {
            let Some(pose) = solve_one(prep, k, rot, poses, &obstacles) else { break };
            let fp = footprint(&pose, obj.size);
            let hit: Vec<Rect> = fps.iter().filter(|f| f.overlaps(&fp)).copied().collect();
            if !hit.is_empty() {
                obstacles.extend(hit);
                continue;
            }
            if prep.static_rule(k, &pose).is_some() {
                break;
            }
            let cleared = clearance_obstacles(prep, k, &pose, poses);
            if !cleared.is_empty() {
                obstacles.extend(cleared);
                continue;
            }
            let mut all = fps.to_vec();
            all.push(fp);
            if !prep.reach.ok(&all) {
                break;
            }
            let mut s = fast_score(prep, k, &pose, poses, 10.0);
            s -= 1e-6 * rot.deg();
            if best.as_ref().is_none_or(|(_, b)| s > *b + 1e-9) {
                best = Some((pose, s));
            }
            break;
        }
    }
    best
}

/// The DFS fallback for one object: its best candidate that keeps every hard rule.
fn place_fallback(
    prep: &Prepared<'_>,
    k: usize,
    seed: u64,
    poses: &[Option<Pose>],
    fps: &[Rect],
) -> Result<Pose, (HardRule, String)> {
    let (mut cands, fails) = static_candidates(prep, k, seed);
    cands.extend(derived_candidates(prep, k, poses));
    if cands.is_empty() {
        return Err(super::dfs::static_reason(&fails));
    }
    let clear: Vec<&Cand> =
        cands.iter().filter(|c| !fps.iter().any(|f| f.overlaps(&c.fp))).collect();
    if clear.is_empty() {
        return Err((
            HardRule::NoOverlap,
            "every pose overlaps an object already placed".to_string(),
        ));
    }
    let mut free: Vec<(Pose, Rect, f64)> = clear
        .into_iter()
        .filter(|c| clearance_obstacles(prep, k, &c.pose, poses).is_empty())
        .map(|c| (c.pose, c.fp, fast_score(prep, k, &c.pose, poses, 10.0)))
        .collect();
    if free.is_empty() {
        return Err((
            HardRule::UseClearance,
            "every pose left stands in the space another object needs for its use (or blocks \
             its own)"
                .to_string(),
        ));
    }
    free.sort_by(|a, b| b.2.total_cmp(&a.2));
    for (pose, fp, _) in free.iter().take(24) {
        let mut all = fps.to_vec();
        all.push(*fp);
        if prep.reach.ok(&all) {
            return Ok(*pose);
        }
    }
    Err((
        HardRule::Reachable,
        "every pose left would leave a placed object unreachable from the door".to_string(),
    ))
}

/// Places the floor objects one by one with the MILP, falling back to the DFS candidates.
pub(crate) fn solve(prep: &Prepared<'_>, options: &SolveOptions) -> RoomLayout {
    let n = prep.problem.objects.len();
    let mut poses: Vec<Option<Pose>> = vec![None; n];
    let mut fps: Vec<Rect> = Vec::new();
    let mut by = vec!["milp"; n];
    let mut layout = RoomLayout::default();
    let mut fails: Vec<Option<(HardRule, String)>> = vec![None; n];
    // Plan order, a relation's target first (an implied seating group's sofa after its screen).
    let all: Vec<usize> = (0..n).collect();
    for k in super::targets_first(prep.problem, &all) {
        let obj = &prep.problem.objects[k];
        layout.nodes += 1;
        if let Some(pin) = obj.pin {
            let fp = footprint(&pin, obj.size);
            // The rules the MILP models (a bed's open side excepted), then reachability.
            let mut with = fps.clone();
            with.push(fp);
            // Every rule it breaks (the first fixed rule of the room, then each of the others).
            let rules = [
                prep.static_rule(k, &pin),
                fps.iter().any(|f| f.overlaps(&fp)).then_some(HardRule::NoOverlap),
                (!clearance_obstacles(prep, k, &pin, &poses).is_empty())
                    .then_some(HardRule::UseClearance),
                (!prep.reach.ok(&with)).then_some(HardRule::Reachable),
            ];
            layout.pinned_breaks.extend(rules.into_iter().flatten().map(|rule| (k, rule)));
            poses[k] = Some(pin);
            fps.push(fp);
            by[k] = "pin";
            continue;
        }
        match place_milp(prep, k, &poses, &fps) {
            Some((pose, _)) => {
                poses[k] = Some(pose);
                fps.push(footprint(&pose, obj.size));
            }
            None => match place_fallback(prep, k, options.seed, &poses, &fps) {
                Ok(pose) => {
                    poses[k] = Some(pose);
                    fps.push(footprint(&pose, obj.size));
                    by[k] = "dfs";
                }
                Err(reason) => fails[k] = Some(reason),
            },
        }
    }
    for k in 0..n {
        let obj = &prep.problem.objects[k];
        if let Some(pose) = poses[k] {
            {
                let (reports, score) = measure_object(prep.problem, &prep.room, k, &pose, &poses);
                layout.score += score;
                layout.floor.push(PlacedFloor {
                    index: k,
                    pose,
                    footprint: footprint(&pose, obj.size),
                    constraints: reports,
                    score,
                    by: by[k],
                });
            }
        } else {
            {
                let (rule, reason) =
                    fails[k].take().unwrap_or((HardRule::NoOverlap, "no pose found".to_string()));
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
    layout
}

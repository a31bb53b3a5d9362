//! The poses the floor solvers choose from, and what a pose is worth.
//!
//! An object's candidates come in two parts. The static part (a grid of centres plus every
//! wall-flush position, four rotations, filtered by the static hard rules) depends only on the
//! object and the room. The derived part (positions flush against, or aligned with, the targets
//! of the object's relations, and stood off them by the gaps the relations mean) depends on
//! where the targets stand. Both solvers draw from them: the DFS ([`super::dfs`]) walks them in
//! the order of a bound of their worth, the MILP ([`super::milp`]) starts from the best.

use std::collections::BTreeMap;

use rand::seq::SliceRandom;
use rand_chacha::rand_core::SeedableRng;
use rand_chacha::ChaCha8Rng;

use super::constraints::{self, footprint, half_extents, HardRule, Pose, Rect, Rot};
use super::Prepared;
use crate::check::scene::{GlobalKind, RelationKind};

/// A candidate pose with its footprint.
#[derive(Clone, Copy, Debug)]
pub(crate) struct Cand {
    pub pose: Pose,
    pub fp: Rect,
}

/// The grid step for free-standing positions: 1/24 of the room's longer side, between 15 and
/// 40 cm.
pub(crate) fn grid_step(bounds: &Rect) -> f64 {
    (bounds.width().max(bounds.depth()) / 24.0).clamp(0.15, 0.4)
}

/// The step along walls: 1/60 of the room's longer side, between 10 and 15 cm.
pub(crate) fn wall_step(bounds: &Rect) -> f64 {
    (bounds.width().max(bounds.depth()) / 60.0).clamp(0.1, 0.15)
}

/// Coordinates along one axis: a grid from `lo + h` to `hi − h` plus both ends.
fn axis_values(lo: f64, hi: f64, h: f64, g: f64) -> Vec<f64> {
    let (a, b) = (lo + h, hi - h);
    if b < a - constraints::EPS {
        return Vec::new();
    }
    let mut v = Vec::new();
    let mut t = a;
    while t < b - 1e-9 {
        v.push(t);
        t += g;
    }
    v.push(b);
    v
}

/// Wall-flush centre coordinates for a footprint with half extents `h`: `(xs, zs)`.
pub(crate) fn flush_values(prep: &Prepared<'_>, h: [f64; 2]) -> (Vec<f64>, Vec<f64>) {
    let (mut xs, mut zs) = (Vec::new(), Vec::new());
    for &(a, _b, n) in &prep.walls {
        if n[0] == 0.0 {
            zs.push(a[1] + n[1] * h[1]);
        } else {
            xs.push(a[0] + n[0] * h[0]);
        }
    }
    (xs, zs)
}

fn dedup(v: &mut Vec<f64>) {
    v.sort_by(f64::total_cmp);
    v.dedup_by(|a, b| (*a - *b).abs() < 1e-6);
}

/// Static candidates of object `k` (before any other object is placed) and the tally of the
/// hard rules that rejected the others.
pub(crate) fn static_candidates(
    prep: &Prepared<'_>,
    k: usize,
    seed: u64,
) -> (Vec<Cand>, BTreeMap<HardRule, usize>) {
    let (mut out, fails) = static_grid(prep, k);
    shuffle_static(&mut out, k, seed);
    (out, fails)
}

/// What the static candidates of object `k` depend on: its footprint's size, the height that
/// decides whether it blocks a window, and its global constraint (objects alike in these, the
/// chairs of a set, get the same grid before each is shuffled by its own seed).
pub(super) fn static_grid_key(prep: &Prepared<'_>, k: usize) -> StaticGridKey {
    let obj = &prep.problem.objects[k];
    let height = super::window_height(obj);
    ([obj.size[0].to_bits(), obj.size[1].to_bits(), height.to_bits()], obj.global)
}

/// The bits of an object's footprint size and window height, and its global constraint.
pub(super) type StaticGridKey = ([u64; 3], GlobalKind);

/// Static candidates in the grid's order, with the tally of the rules that rejected the others.
pub(super) type StaticGrid = (Vec<Cand>, BTreeMap<HardRule, usize>);

/// Shuffles object `k`'s static candidates (or their places in the grid) in its seeded order.
pub(super) fn shuffle_static<T>(cands: &mut [T], k: usize, seed: u64) {
    let mut rng = ChaCha8Rng::seed_from_u64(seed ^ (k as u64).wrapping_mul(0x9E37_79B9_7F4A_7C15));
    cands.shuffle(&mut rng);
}

/// [`static_candidates`] in the grid's order, before the shuffle.
pub(super) fn static_grid(prep: &Prepared<'_>, k: usize) -> StaticGrid {
    let obj = &prep.problem.objects[k];
    let b = prep.room.bounds;
    let g = if obj.global == GlobalKind::Edge { wall_step(&b) } else { grid_step(&b) };
    let mut out = Vec::new();
    let mut fails = BTreeMap::new();
    for rot in Rot::ALL {
        let h = half_extents(obj.size, rot);
        let (mut fx, mut fz) = flush_values(prep, h);
        dedup(&mut fx);
        dedup(&mut fz);
        let mut gx = axis_values(b.min_x, b.max_x, h[0], g);
        let mut gz = axis_values(b.min_z, b.max_z, h[1], g);
        gx.extend(fx.iter().copied());
        gz.extend(fz.iter().copied());
        dedup(&mut gx);
        dedup(&mut gz);
        let mut points = Vec::new();
        if obj.global == GlobalKind::Edge {
            for &x in &gx {
                for &z in &fz {
                    points.push((x, z));
                }
            }
            for &x in &fx {
                for &z in &gz {
                    points.push((x, z));
                }
            }
        } else {
            for &x in &gx {
                for &z in &gz {
                    points.push((x, z));
                }
            }
        }
        for (x, z) in points {
            let pose = Pose { x, z, rot };
            match prep.static_rule(k, &pose) {
                None => out.push(Cand { pose, fp: footprint(&pose, obj.size) }),
                Some(rule) => *fails.entry(rule).or_insert(0) += 1,
            }
        }
    }
    dedup_cands(&mut out);
    (out, fails)
}

/// Candidates of an `edge` object anywhere in the room (a grid of centres, four rotations),
/// keeping every static hard rule but the global one.
pub(crate) fn anywhere_candidates(prep: &Prepared<'_>, k: usize, seed: u64) -> Vec<Cand> {
    let obj = &prep.problem.objects[k];
    let b = prep.room.bounds;
    let g = grid_step(&b);
    let mut out = Vec::new();
    for rot in Rot::ALL {
        let h = half_extents(obj.size, rot);
        for &x in &axis_values(b.min_x, b.max_x, h[0], g) {
            for &z in &axis_values(b.min_z, b.max_z, h[1], g) {
                let pose = Pose { x, z, rot };
                if prep.static_rule_anywhere(k, &pose).is_none() {
                    out.push(Cand { pose, fp: footprint(&pose, obj.size) });
                }
            }
        }
    }
    dedup_cands(&mut out);
    let mut rng = ChaCha8Rng::seed_from_u64(seed ^ (k as u64).wrapping_mul(0xD1B5_4A32_D192_ED03));
    out.shuffle(&mut rng);
    out
}

pub(super) fn dedup_cands(v: &mut Vec<Cand>) {
    // Coordinates to a tenth of a millimetre, rounded half up (the offset keeps the value
    // positive so that the cast truncates like `floor`, which is cheaper than `round`).
    let q = |v: f64| (v * 1e4 + 1e9 + 0.5) as i64;
    let key = |c: &Cand| (q(c.pose.x), q(c.pose.z), c.pose.rot);
    // Each key worked out once and sorted with the candidate's place (equal keys keep their
    // order, the first of them is kept), the candidates gathered after.
    let mut keyed: Vec<_> = v.iter().zip(0u32..).map(|(c, i)| (key(c), i)).collect();
    keyed.sort_unstable();
    keyed.dedup_by(|a, b| a.0 == b.0);
    let kept: Vec<Cand> = keyed.iter().map(|&(_, i)| v[i as usize]).collect();
    *v = kept;
}

/// Candidates derived from the placed targets of object `k`'s relations: flush against a
/// side of the target or aligned with its centre, combined with wall-flush coordinates.
pub(crate) fn derived_candidates(
    prep: &Prepared<'_>,
    k: usize,
    poses: &[Option<Pose>],
) -> Vec<Cand> {
    let mut out = Vec::new();
    for target in derived_targets(prep, k) {
        if let Some(Some(tp)) = poses.get(target) {
            out.extend(derived_for_target(prep, k, target, tp));
        }
    }
    dedup_cands(&mut out);
    out
}

/// The targets of object `k`'s relations, each once, in the order of the relations: those
/// whose poses [`derived_candidates`] derives candidates from.
pub(super) fn derived_targets(prep: &Prepared<'_>, k: usize) -> Vec<usize> {
    let mut targets = Vec::new();
    for c in &prep.problem.objects[k].constraints {
        if !targets.contains(&c.target) && prep.problem.objects.get(c.target).is_some() {
            targets.push(c.target);
        }
    }
    targets
}

/// The candidates of object `k` derived from one target at pose `tp`, before they are put
/// together with those of its other targets and deduplicated ([`derived_candidates`]).
pub(super) fn derived_for_target(
    prep: &Prepared<'_>,
    k: usize,
    target: usize,
    tp: &Pose,
) -> Vec<Cand> {
    let obj = &prep.problem.objects[k];
    let mut out = Vec::new();
    let Some(t) = prep.problem.objects.get(target) else { return out };
    let tf = footprint(tp, t.size);
    let mut gaps = target_gaps(prep, k, target);
    // Right beyond the target's use-clearance that the object may not enter (a student
    // desk in front of the teacher's, beyond its pull-out space).
    if let Some(clear) = kept_out_of(prep, k, target) {
        gaps.push(clear);
    }
    // The gaps the object's relations to this target mean (a coffee table 0.3–0.6 m in
    // front of its sofa, `near` not touching): their ends and middle; and the seats of a
    // table the object is one of the chairs around.
    for (di, _) in obj.constraints.iter().enumerate().filter(|(_, d)| d.target == target) {
        let m = prep.meaning(k, di);
        if let Some(ring) = &m.ring {
            for pose in constraints::seat_poses(tp, t.size, ring) {
                if prep.static_rule(k, &pose).is_none() {
                    out.push(Cand { pose, fp: footprint(&pose, obj.size) });
                }
            }
        }
        gaps.push(m.min_gap);
        if m.max_gap.is_finite() {
            gaps.push(0.5 * (m.min_gap + m.max_gap.min(m.min_gap + 2.0)));
        }
    }
    dedup(&mut gaps);
    for rot in Rot::ALL {
        let h = half_extents(obj.size, rot);
        let mut tx = vec![tp.x, tf.min_x + h[0], tf.max_x - h[0]];
        let mut tz = vec![tp.z, tf.min_z + h[1], tf.max_z - h[1]];
        for g in &gaps {
            tx.extend([tf.min_x - h[0] - g, tf.max_x + h[0] + g]);
            tz.extend([tf.min_z - h[1] - g, tf.max_z + h[1] + g]);
        }
        let (fx, fz) = flush_values(prep, h);
        let xs: Vec<f64> = tx.iter().chain(fx.iter()).copied().collect();
        let zs: Vec<f64> = tz.iter().chain(fz.iter()).copied().collect();
        for (i, &x) in xs.iter().enumerate() {
            for (j, &z) in zs.iter().enumerate() {
                if i >= tx.len() && j >= tz.len() {
                    continue;
                }
                let pose = Pose { x, z, rot };
                if prep.static_rule(k, &pose).is_none() {
                    out.push(Cand { pose, fp: footprint(&pose, obj.size) });
                }
            }
        }
    }
    out
}

/// The gaps at which derived candidates of object `k` stand off a side of `target`: flush
/// (0), and the smaller side of each other object that has a relation to the same target (the
/// room a chair needs behind its desk, say), so that `k` can leave that room.
pub(super) fn target_gaps(prep: &Prepared<'_>, k: usize, target: usize) -> Vec<f64> {
    let mut gaps = vec![0.0];
    let mut aisles = Vec::new();
    for (j, other) in prep.problem.objects.iter().enumerate() {
        if j == k {
            continue;
        }
        // The least gap the other object's relations to the target leave (a chair `near` its
        // desk stands 0.1 m off it).
        let least = (0..other.constraints.len())
            .filter(|&ci| other.constraints[ci].target == target)
            .map(|ci| prep.meaning(j, ci).min_gap)
            .fold(0.0, f64::max);
        // Its depth, when it faces the target or the way the target faces (a chair at a desk),
        // as the look-ahead counts it (`dfs::chain_depth`).
        let faces = other.constraints.iter().any(|c| {
            c.target == target && matches!(c.kind, RelationKind::FaceTo | RelationKind::FaceSameAs)
        });
        for c in other.constraints.iter().filter(|c| c.target == target) {
            let side = other.size[0].min(other.size[1]);
            gaps.push(side);
            if drawn_up(prep.problem, j, c) {
                // A chair drawn up to the same desk, at its least gap, and the way to it.
                let depth = if faces { other.size[1] } else { side };
                aisles.push(least + depth + prep.reach.aisle());
            }
        }
    }
    dedup(&mut gaps);
    gaps.truncate(MAX_TARGET_GAPS);
    dedup(&mut aisles);
    gaps.extend(aisles.into_iter().take(1));
    dedup(&mut gaps);
    gaps
}

/// The depth of `target`'s use-clearance in front of it when object `k` may not stand in it
/// (a desk's pull-out space keeps out everything but a seat): `k` stands in front of it at
/// least that far off.
pub(super) fn kept_out_of(prep: &Prepared<'_>, k: usize, target: usize) -> Option<f64> {
    let (obj, t) = (prep.problem.objects.get(k)?, prep.problem.objects.get(target)?);
    let depth = t.role.front_clearance(t.height);
    let in_front = !prep.from_behind[target];
    (in_front && depth > constraints::EPS && !t.role.lets_in(obj.role, true)).then_some(depth)
}

/// The most stand-off gaps [`target_gaps`] gives (the smallest ones), besides the one that
/// leaves a chair and its aisle.
const MAX_TARGET_GAPS: usize = 3;

/// The search value of object `k` at a pose: `sat_value` per satisfied relation plus the
/// weighted soft score.
pub(crate) fn fast_score(
    prep: &Prepared<'_>,
    k: usize,
    pose: &Pose,
    poses: &[Option<Pose>],
    sat_value: f64,
) -> f64 {
    let obj = &prep.problem.objects[k];
    let mut s = 0.0;
    for (ci, c) in obj.constraints.iter().enumerate() {
        if let (Some(Some(tp)), Some(t)) = (poses.get(c.target), prep.problem.objects.get(c.target))
        {
            let meaning = prep.meaning(k, ci);
            let m = constraints::relation_fit(c.kind, &meaning, pose, obj.size, tp, t.size);
            s += constraints::weight(c.kind) * m.score + if m.satisfied { sat_value } else { 0.0 };
        }
    }
    s
}

/// Whether relation `c` of object `j` draws a seat up to the front or back of a desk or table
/// (a student's chair `behind` its desk): the chair needs the way to it as well as its own
/// floor.
pub(super) fn drawn_up(
    problem: &super::RoomProblem,
    j: usize,
    c: &super::ProblemConstraint,
) -> bool {
    matches!(c.kind, RelationKind::InFrontOf | RelationKind::Behind)
        && problem.objects[j].role.is_seat()
        && problem.objects.get(c.target).is_some_and(|t| t.role.sat_at())
}

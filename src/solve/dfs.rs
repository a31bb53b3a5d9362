//! The depth-first floor solver: branch and bound over candidate poses, in plan order, with
//! limited discrepancy and a node budget.
//!
//! Candidates of an object are computed in two parts. The static part (a grid of centres plus
//! every wall-flush position, four rotations, filtered by the static hard rules) is computed
//! once per object. The derived part (positions flush against, or aligned with, the targets of
//! the object's relations) is computed when the targets are placed. At a node, candidates that
//! overlap a placed footprint are dropped, the rest are scored and sorted (ties in a seeded
//! order), and the search descends into them best first.

use std::collections::BTreeMap;

use rand::seq::SliceRandom;
use rand_chacha::rand_core::SeedableRng;
use rand_chacha::ChaCha8Rng;

use super::constraints::{self, footprint, half_extents, static_rules, HardRule, Pose, Rect, Rot};
use super::{measure_object, PlacedFloor, Prepared, RoomLayout, SolveOptions, Unplaced};
use crate::check::scene::GlobalKind;

/// The most reachability checks per node before the object counts as boxed in.
const REACH_TRIES: usize = 24;
/// The largest discrepancy tried (number of non-best choices on one path).
const MAX_DISCREPANCY: usize = 3;

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

/// The step along walls: 1/40 of the room's longer side, between 10 and 25 cm.
pub(crate) fn wall_step(bounds: &Rect) -> f64 {
    (bounds.width().max(bounds.depth()) / 40.0).clamp(0.1, 0.25)
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
            match static_rules(
                &pose,
                obj.size,
                obj.height,
                obj.global,
                &prep.room,
                &prep.keep_out,
                &prep.windows,
            ) {
                None => out.push(Cand { pose, fp: footprint(&pose, obj.size) }),
                Some(rule) => *fails.entry(rule).or_insert(0) += 1,
            }
        }
    }
    dedup_cands(&mut out);
    let mut rng = ChaCha8Rng::seed_from_u64(seed ^ (k as u64).wrapping_mul(0x9E37_79B9_7F4A_7C15));
    out.shuffle(&mut rng);
    (out, fails)
}

fn dedup_cands(v: &mut Vec<Cand>) {
    let key =
        |c: &Cand| ((c.pose.x * 1e4).round() as i64, (c.pose.z * 1e4).round() as i64, c.pose.rot);
    v.sort_by_key(key);
    v.dedup_by_key(|c| key(c));
}

/// Candidates derived from the placed targets of object `k`'s relations: flush against a
/// side of the target or aligned with its centre, combined with wall-flush coordinates.
pub(crate) fn derived_candidates(
    prep: &Prepared<'_>,
    k: usize,
    poses: &[Option<Pose>],
) -> Vec<Cand> {
    let obj = &prep.problem.objects[k];
    let mut out = Vec::new();
    let mut seen_targets = Vec::new();
    for c in &obj.constraints {
        if seen_targets.contains(&c.target) {
            continue;
        }
        seen_targets.push(c.target);
        let (Some(Some(tp)), Some(t)) = (poses.get(c.target), prep.problem.objects.get(c.target))
        else {
            continue;
        };
        let tf = footprint(tp, t.size);
        for rot in Rot::ALL {
            let h = half_extents(obj.size, rot);
            let tx = [tp.x, tf.min_x - h[0], tf.max_x + h[0], tf.min_x + h[0], tf.max_x - h[0]];
            let tz = [tp.z, tf.min_z - h[1], tf.max_z + h[1], tf.min_z + h[1], tf.max_z - h[1]];
            let (fx, fz) = flush_values(prep, h);
            let xs: Vec<f64> = tx.iter().chain(fx.iter()).copied().collect();
            let zs: Vec<f64> = tz.iter().chain(fz.iter()).copied().collect();
            for (i, &x) in xs.iter().enumerate() {
                for (j, &z) in zs.iter().enumerate() {
                    if i >= tx.len() && j >= tz.len() {
                        continue;
                    }
                    let pose = Pose { x, z, rot };
                    if static_rules(
                        &pose,
                        obj.size,
                        obj.height,
                        obj.global,
                        &prep.room,
                        &prep.keep_out,
                        &prep.windows,
                    )
                    .is_none()
                    {
                        out.push(Cand { pose, fp: footprint(&pose, obj.size) });
                    }
                }
            }
        }
    }
    dedup_cands(&mut out);
    out
}

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
    for c in &obj.constraints {
        if let (Some(Some(tp)), Some(t)) = (poses.get(c.target), prep.problem.objects.get(c.target))
        {
            let m = constraints::relation(c.kind, pose, obj.size, tp, t.size);
            s += constraints::weight(c.kind) * m.score + if m.satisfied { sat_value } else { 0.0 };
        }
    }
    s
}

/// Why an object has no pose: the rule and the words.
type Reason = (HardRule, String);

/// Search state along one path.
#[derive(Clone)]
struct State {
    poses: Vec<Option<Pose>>,
    fps: Vec<Rect>,
    value: f64,
    fails: Vec<Option<(HardRule, String)>>,
    by: Vec<&'static str>,
}

struct Search<'p, 'a> {
    prep: &'p Prepared<'a>,
    placed_value: f64,
    sat_value: f64,
    statics: Vec<Vec<Cand>>,
    static_fails: Vec<BTreeMap<HardRule, usize>>,
    remaining_max: Vec<f64>,
    budget: u64,
    nodes: u64,
    best: Option<State>,
    pin_breaks: Vec<(usize, HardRule)>,
}

impl Search<'_, '_> {
    fn better(&self, value: f64) -> bool {
        self.best.as_ref().is_none_or(|b| value > b.value + 1e-9)
    }

    fn out_of_budget(&self) -> bool {
        self.best.is_some() && self.nodes >= self.budget
    }

    fn visit(&mut self, k: usize, disc: usize, st: &mut State) {
        let n = self.prep.problem.objects.len();
        if k == n {
            if self.better(st.value) {
                self.best = Some(st.clone());
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
            if let Some(rule) = static_rules(
                &pin,
                obj.size,
                obj.height,
                obj.global,
                &self.prep.room,
                &self.prep.keep_out,
                &self.prep.windows,
            )
            .or_else(|| st.fps.iter().any(|f| f.overlaps(&fp)).then_some(HardRule::NoOverlap))
            {
                if !self.pin_breaks.iter().any(|(i, _)| *i == k) {
                    self.pin_breaks.push((k, rule));
                }
            }
            let s = fast_score(self.prep, k, &pin, &st.poses, self.sat_value);
            Self::place(k, pin, fp, self.placed_value + s, "pin", st);
            self.visit(k + 1, disc, st);
            Self::unplace(k, self.placed_value + s, st);
            return;
        }
        let (cands, reason) = self.candidates(k, st);
        if cands.is_empty() {
            st.fails[k] = reason;
            self.visit(k + 1, disc, st);
            st.fails[k] = None;
            return;
        }
        let mut tried = 0usize;
        let mut pruned = false;
        for (reach_checks, (c, s)) in cands.iter().enumerate() {
            if let Some(b) = &self.best {
                if st.value + self.placed_value + s + self.remaining_max[k + 1] <= b.value + 1e-9 {
                    pruned = true;
                    break;
                }
            }
            if tried > disc || reach_checks >= REACH_TRIES {
                break;
            }
            st.fps.push(c.fp);
            let boxed = !self.prep.reach.ok(&st.fps);
            st.fps.pop();
            if boxed {
                continue;
            }
            let v = self.placed_value + s;
            Self::place(k, c.pose, c.fp, v, "dfs", st);
            self.visit(k + 1, disc - tried, st);
            Self::unplace(k, v, st);
            tried += 1;
            if self.out_of_budget() {
                break;
            }
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

    fn place(k: usize, pose: Pose, fp: Rect, v: f64, by: &'static str, st: &mut State) {
        st.poses[k] = Some(pose);
        st.fps.push(fp);
        st.value += v;
        st.by[k] = by;
    }

    fn unplace(k: usize, v: f64, st: &mut State) {
        st.poses[k] = None;
        st.fps.pop();
        st.value -= v;
    }

    /// Scored candidates of object `k` (best first), or why there are none.
    fn candidates(&self, k: usize, st: &State) -> (Vec<(Cand, f64)>, Option<Reason>) {
        let prep = self.prep;
        let derived = derived_candidates(prep, k, &st.poses);
        if self.statics[k].is_empty() && derived.is_empty() {
            return (Vec::new(), Some(static_reason(&self.static_fails[k])));
        }
        let mut blockers: BTreeMap<usize, usize> = BTreeMap::new();
        let mut scored = Vec::new();
        for &c in self.statics[k].iter().chain(derived.iter()) {
            if let Some(i) = st.fps.iter().position(|f| f.overlaps(&c.fp)) {
                *blockers.entry(i).or_insert(0) += 1;
                continue;
            }
            scored.push((c, fast_score(prep, k, &c.pose, &st.poses, self.sat_value)));
        }
        if scored.is_empty() {
            let placed: Vec<usize> = (0..k).filter(|&i| st.poses[i].is_some()).collect();
            let mut names: Vec<(usize, String)> = blockers
                .iter()
                .filter_map(|(&slot, &count)| {
                    placed.get(slot).map(|&i| (count, prep.problem.objects[i].id.clone()))
                })
                .collect();
            names.sort_by(|a, b| b.0.cmp(&a.0).then(a.1.cmp(&b.1)));
            let list: Vec<String> = names.iter().take(3).map(|(_, n)| format!("`{n}`")).collect();
            return (
                Vec::new(),
                Some((
                    HardRule::NoOverlap,
                    format!("every pose overlaps an object already placed ({})", list.join(", ")),
                )),
            );
        }
        scored.sort_by(|a, b| b.1.total_cmp(&a.1));
        (scored, None)
    }
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

/// Runs the search and turns the best state into a layout.
pub(crate) fn solve(prep: &Prepared<'_>, options: &SolveOptions) -> RoomLayout {
    let n = prep.problem.objects.len();
    let mut statics = Vec::with_capacity(n);
    let mut static_fails = Vec::with_capacity(n);
    for k in 0..n {
        let (c, f) = static_candidates(prep, k, options.seed);
        statics.push(c);
        static_fails.push(f);
    }
    run(prep, options, statics, static_fails)
}

/// The search over objects from their static candidates.
pub(crate) fn run(
    prep: &Prepared<'_>,
    options: &SolveOptions,
    statics: Vec<Vec<Cand>>,
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
    let mut search = Search {
        prep,
        placed_value,
        sat_value,
        statics,
        static_fails,
        remaining_max,
        budget: options.node_budget,
        nodes: 0,
        best: None,
        pin_breaks: Vec::new(),
    };
    let mut st = State {
        poses: vec![None; n],
        fps: Vec::new(),
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
    let best = search.best.unwrap_or(st);
    let mut layout = RoomLayout { nodes, ..RoomLayout::default() };
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
                });
            }
        }
    }
    for (k, rule) in pin_breaks {
        layout.pinned_breaks.push((k, rule));
    }
    layout
}

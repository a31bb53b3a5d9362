//! Geometric repair benchmark: broken floor plans made from valid ones, repaired.
//!
//! `cargo bench --bench repair_bench` prints one table row per kind of break: plans, how many
//! become valid, the largest and the median corner movement, the largest area change and the
//! median time per plan. The valid plans are the multi-room houses of
//! `../shared/data/real-scenes/` (skipped with a message when it is absent), the examples'
//! floor plans and 40 plans of our own (a rectangle cut into 2 to 6 rooms). The breaks:
//!
//! - `shift`: one room moved by 5, 10, 20, 30, 40 or 50 cm along x or z, either way (overlaps
//!   and gaps of up to 0.5 m);
//! - `scale`: one room grown or shrunk about its centre so that its walls move 5 to 40 cm;
//! - `slant`: one corner moved 5 to 30 cm along one axis (a slanted wall);
//! - `doubled`: one corner written twice and a corner added in the middle of a wall;
//! - `detached`: a room with one neighbour moved 30 to 90 cm away from it;
//! - `corner dropped`: one corner of a room left out (a slanted wall across the room; most of
//!   these need more than the bounds allow and stay errors, reported for information);
//! - `jitter` (issue 50): every corner of the plan moved by up to 17 cm on each axis, three
//!   ways per plan;
//! - `corner only` (issue 50): a room with one neighbour slid along their shared wall until the
//!   two meet only at a corner (up to 4 m: for this kind the plan meant is the answer as
//!   written, its wall-sharing pairs and the door's pair, as no repair within a metre can
//!   undo such a slide);
//! - `staircase` (issue 50): a room whose side is a staircase of 50 to 199 corners (holoc takes
//!   at most 200 per room) drawn 10 to 30 cm into its neighbour (our own plans only).
//!
//! Issue 50 adds, per kind: the share of repaired plans that keep the wall-sharing pairs of the
//! plan meant (*pairs kept*; target 99% for `jitter` and `corner only`), the farthest a corner
//! of the plan meant is from the repaired plan (*deviation from meant*; target at most 1 m),
//! and the CPU per plan; then plans of up to 64 KB (rows of rooms of 199 corners each drawn
//! into the next, and grids of up to 576 small rooms, jittered or with one room drawn into its
//! neighbour) with their time and whether the bound on work (W0309) was reached (target: no
//! repair over 1 s). `REPAIR_BENCH_ONLY=large` prints those two tables alone,
//! `REPAIR_BENCH_KINDS=jitter,corner only` measures those kinds of break alone, and
//! `REPAIR_BENCH_NO_GENERATE=1` leaves out the `holoc generate` figures.
//!
//! The target (issue 15): at least 95% of the `shift` and `scale` plans (overlaps and gaps of up
//! to 0.5 m) valid after repair with no corner moved by more than 0.5 m, every run identical,
//! under 1 ms per plan.
//!
//! Issue 27 adds, per kind of break: the share of changed plans equal to the plan before the
//! break (*equal to meant*), how many changed plans moved a room other than the broken one,
//! how many left an error of a kind the broken plan did not have (target 0), and the share
//! whose output a second repair leaves unchanged (target 100%); then the issue's examples (the
//! fixtures under `tests/corpus/repair/`: valid after repair, rooms moved, idempotent); then
//! every fifth `shift`, `scale`, `slant` and `detached` break given to `holoc generate` as the
//! model's floor-plan answer over a loopback server (the doorways answer lists the plan's
//! doors): the share of the answers needing repair that end in a scene (target 98%), the
//! share that end in the plan meant, and the model requests per run.

// The table is the point of this binary: it prints to stdout on purpose.
#![allow(clippy::print_stdout, clippy::print_stderr)]

#[path = "../tests/support/llm_server.rs"]
mod llm_server;

use std::fmt::Write as _;
use std::time::{Duration, Instant};

use holoc::diag::Diagnostic;
use holoc::plan::repair::{apply, area_changes, repair};
use holoc::resolve::structure::StructureCatalog;
use holoc::source::SourceMap;

/// A floor plan: rooms (id, outline in metres) and doors between rooms (`None`: outside).
#[derive(Clone, Debug)]
struct Plan {
    name: String,
    rooms: Vec<(String, Vec<[f64; 2]>)>,
    doors: Vec<(Option<usize>, usize)>,
}

impl Plan {
    fn to_holo(&self) -> String {
        let mut text = format!("scene \"{}\" {{ seed 1 }}\n", self.name);
        for (id, corners) in &self.rooms {
            let cs: Vec<String> =
                corners.iter().map(|p| format!("({:.4}, {:.4})", p[0], p[1])).collect();
            let _ = writeln!(text, "room {id} \"{id}\" {{ corners in m {} }}", cs.join(" "));
        }
        for (a, b) in &self.doors {
            let from = a.map_or("exterior".to_string(), |i| self.rooms[i].0.clone());
            let _ = writeln!(text, "door {from} -- {} : doorway single", self.rooms[*b].0);
        }
        text
    }
}

/// The geometric plan errors of a text (checker and plan stage), or `None` when it does not
/// pass the checker.
fn plan_errors(text: &str) -> Option<Vec<&'static str>> {
    let mut sources = SourceMap::new();
    let id = sources.add("plan.holo", text.to_string());
    let checked = holoc::compile::check_file(&sources, id);
    if checked.diagnostics.iter().any(Diagnostic::is_error) {
        return None;
    }
    let scene = checked.value?;
    Some(
        holoc::plan::plan(&scene, StructureCatalog::builtin())
            .diagnostics
            .iter()
            .filter(|d| d.is_error())
            .map(|d| d.code.as_str())
            .collect(),
    )
}

/// What repairing one broken plan gave.
struct Outcome {
    /// The outlines after repair, per room.
    corners: Vec<Vec<[f64; 2]>>,
    /// Error codes of the plan stage after repair.
    errors_after: Vec<&'static str>,
    /// Whether repairing the repaired text changes nothing.
    idempotent: bool,
    valid: bool,
    changed: bool,
    max_move: f64,
    max_wall_move: f64,
    area_change: f64,
    time: Duration,
    text: String,
    /// Whether the repair reached its bound on work (W0309).
    bounded: bool,
}

fn repair_plan(text: &str) -> Option<Outcome> {
    let mut sources = SourceMap::new();
    let id = sources.add("broken.holo", text.to_string());
    let checked = holoc::compile::check_file(&sources, id);
    if checked.diagnostics.iter().any(Diagnostic::is_error) {
        return None;
    }
    let scene = checked.value?;
    let catalog = StructureCatalog::builtin();
    // The time of the repair itself (the median of a few runs).
    let mut times: Vec<Duration> = (0..5)
        .map(|_| {
            let t = Instant::now();
            std::hint::black_box(repair(&scene, catalog));
            t.elapsed()
        })
        .collect();
    times.sort();
    let repaired = repair(&scene, catalog);
    let after = apply(&scene, &repaired.value);
    let errors_after: Vec<&'static str> = holoc::plan::plan(&after, catalog)
        .diagnostics
        .iter()
        .filter(|d| d.is_error())
        .map(|d| d.code.as_str())
        .collect();
    let valid = errors_after.is_empty();
    let area_change = area_changes(&scene, &repaired.value).into_iter().fold(0.0, f64::max);
    let again = repair(&after, catalog);
    Some(Outcome {
        corners: repaired.value.corners.clone(),
        errors_after,
        idempotent: !again.value.changed,
        valid,
        changed: repaired.value.changed,
        max_move: repaired.value.max_move_m,
        max_wall_move: repaired.value.max_wall_move_m,
        area_change,
        time: times[times.len() / 2],
        text: holoc::diag::apply_fixes(text, id, &repaired.diagnostics),
        bounded: repaired.diagnostics.iter().any(|d| d.code.as_str() == "W0309"),
    })
}

/// The multi-room houses of `../shared/data/real-scenes/`.
fn real_plans() -> Vec<Plan> {
    let dir = std::path::Path::new("../shared/data/real-scenes");
    let Ok(entries) = std::fs::read_dir(dir) else {
        eprintln!("SKIPPED real floor plans: ../shared/data/real-scenes is absent");
        return Vec::new();
    };
    let mut files: Vec<_> = entries
        .filter_map(Result::ok)
        .map(|e| e.path())
        .filter(|p| p.extension().is_some_and(|e| e == "json"))
        .collect();
    files.sort();
    let mut plans = Vec::new();
    for path in files {
        let Ok(text) = std::fs::read_to_string(&path) else { continue };
        let Ok(house) = serde_json::from_str::<serde_json::Value>(&text) else { continue };
        let Some(rooms) = house["rooms"].as_array() else { continue };
        if rooms.len() < 2 {
            continue;
        }
        let ids: Vec<String> =
            rooms.iter().map(|r| r["id"].as_str().unwrap_or("room").to_string()).collect();
        let ident = |s: &str| {
            let mut id: String =
                s.chars().map(|c| if c.is_ascii_alphanumeric() { c } else { '_' }).collect();
            if !id.starts_with(|c: char| c.is_ascii_alphabetic()) {
                id.insert(0, 'r');
            }
            id
        };
        let plan_rooms: Vec<(String, Vec<[f64; 2]>)> = rooms
            .iter()
            .zip(&ids)
            .map(|(r, id)| {
                let corners = r["floorPolygon"]
                    .as_array()
                    .map(|ps| {
                        ps.iter()
                            .map(|p| {
                                [p["x"].as_f64().unwrap_or(0.0), p["z"].as_f64().unwrap_or(0.0)]
                            })
                            .collect()
                    })
                    .unwrap_or_default();
                (ident(id), corners)
            })
            .collect();
        let index = |s: &str| ids.iter().position(|i| i == s);
        let mut doors = Vec::new();
        for d in house["doors"].as_array().into_iter().flatten() {
            let (a, b) = (d["room0"].as_str().unwrap_or(""), d["room1"].as_str().unwrap_or(""));
            match (index(a), index(b)) {
                (Some(i), Some(j)) if i == j => doors.push((None, i)),
                (Some(i), Some(j)) => doors.push((Some(i), j)),
                (None, Some(j)) | (Some(j), None) => doors.push((None, j)),
                (None, None) => {}
            }
        }
        let stem = path.file_stem().map(|s| s.to_string_lossy().to_string()).unwrap_or_default();
        plans.push(Plan { name: stem, rooms: plan_rooms, doors });
    }
    plans
}

/// A small deterministic generator (splitmix64) for our own plans.
struct Rng(u64);

impl Rng {
    fn next(&mut self) -> u64 {
        self.0 = self.0.wrapping_add(0x9e37_79b9_7f4a_7c15);
        let mut z = self.0;
        z = (z ^ (z >> 30)).wrapping_mul(0xbf58_476d_1ce4_e5b9);
        z = (z ^ (z >> 27)).wrapping_mul(0x94d0_49bb_1331_11eb);
        z ^ (z >> 31)
    }
    fn range(&mut self, lo: f64, hi: f64) -> f64 {
        lo + (hi - lo) * (self.next() >> 11) as f64 / (1u64 << 53) as f64
    }
}

/// Our own plans: a rectangle cut into rooms, each cut splitting the largest room across its
/// longer side at 35–65% (rooms stay at least 2 m wide); doors between rooms that share a wall
/// and one to the outside.
fn own_plans(count: usize) -> Vec<Plan> {
    let mut rng = Rng(0x686f_6c6f);
    let mut plans = Vec::new();
    for n in 0..count {
        let (w, d) = (rng.range(7.0, 14.0), rng.range(6.0, 11.0));
        let want = 2 + n % 5;
        let mut boxes: Vec<[f64; 4]> = vec![[0.0, 0.0, round(w), round(d)]];
        while boxes.len() < want {
            let (i, _) = boxes
                .iter()
                .enumerate()
                .map(|(i, b)| (i, (b[2] - b[0]) * (b[3] - b[1])))
                .fold((0, 0.0), |acc, x| if x.1 > acc.1 { x } else { acc });
            let b = boxes[i];
            let along_x = b[2] - b[0] >= b[3] - b[1];
            let (lo, hi) = if along_x { (b[0], b[2]) } else { (b[1], b[3]) };
            if hi - lo < 4.0 {
                break;
            }
            let cut = round(lo + (hi - lo) * rng.range(0.35, 0.65));
            boxes.remove(i);
            if along_x {
                boxes.push([b[0], b[1], cut, b[3]]);
                boxes.push([cut, b[1], b[2], b[3]]);
            } else {
                boxes.push([b[0], b[1], b[2], cut]);
                boxes.push([b[0], cut, b[2], b[3]]);
            }
        }
        let rooms: Vec<(String, Vec<[f64; 2]>)> = boxes
            .iter()
            .enumerate()
            .map(|(i, b)| {
                (format!("room{i}"), vec![[b[0], b[1]], [b[0], b[3]], [b[2], b[3]], [b[2], b[1]]])
            })
            .collect();
        let mut doors = vec![(None, 0)];
        for i in 0..boxes.len() {
            for j in i + 1..boxes.len() {
                if shared_wall(&boxes[i], &boxes[j]) >= 1.2 {
                    doors.push((Some(i), j));
                }
            }
        }
        plans.push(Plan { name: format!("own {n}"), rooms, doors });
    }
    plans
}

fn round(v: f64) -> f64 {
    (v * 10.0).round() / 10.0
}

fn shared_wall(a: &[f64; 4], b: &[f64; 4]) -> f64 {
    let overlap = |lo1: f64, hi1: f64, lo2: f64, hi2: f64| (hi1.min(hi2) - lo1.max(lo2)).max(0.0);
    let touch = |x: f64, y: f64| (x - y).abs() < 1e-9;
    if touch(a[2], b[0]) || touch(b[2], a[0]) {
        overlap(a[1], a[3], b[1], b[3])
    } else if touch(a[3], b[1]) || touch(b[3], a[1]) {
        overlap(a[0], a[2], b[0], b[2])
    } else {
        0.0
    }
}

/// A broken plan: its kind, the room broken (`usize::MAX`: every room) and the plan.
type Break = (&'static str, usize, Plan);

/// The broken plans of each kind made from one valid plan.
fn breaks(plan: &Plan) -> Vec<Break> {
    let mut out = Vec::new();
    let n = plan.rooms.len();
    let with = |room: usize, corners: Vec<[f64; 2]>| {
        let mut p = plan.clone();
        p.rooms[room].1 = corners;
        (room, p)
    };
    for room in 1..n {
        let corners = &plan.rooms[room].1;
        for &d in &[0.05, 0.1, 0.2, 0.3, 0.4, 0.5] {
            for axis in 0..2 {
                for sign in [-1.0, 1.0] {
                    let moved = corners
                        .iter()
                        .map(|p| {
                            let mut q = *p;
                            q[axis] += sign * d;
                            q
                        })
                        .collect();
                    let (r, p) = with(room, moved);
                    out.push(("shift", r, p));
                }
            }
        }
        let (cx, cz) = centre(corners);
        let half = extent(corners);
        for &m in &[0.05, 0.1, 0.2, 0.3, 0.4] {
            for sign in [-1.0, 1.0] {
                // Each wall moves by `m`: the scale on each axis is (half + m) / half.
                let sx = (half[0] + sign * m) / half[0];
                let sz = (half[1] + sign * m) / half[1];
                let scaled = corners
                    .iter()
                    .map(|p| [cx + (p[0] - cx) * sx, cz + (p[1] - cz) * sz])
                    .collect();
                let (r, p) = with(room, scaled);
                out.push(("scale", r, p));
            }
        }
    }
    for room in 0..n {
        let corners = &plan.rooms[room].1;
        for (k, &d) in [0.05, 0.1, 0.2, 0.3].iter().enumerate() {
            let mut slanted = corners.clone();
            let c = k % slanted.len();
            slanted[c][k % 2] += d;
            let (r, p) = with(room, slanted);
            out.push(("slant", r, p));
        }
        let mut doubled = corners.clone();
        doubled.insert(1, corners[0]);
        let (a, b) = (corners[1], corners[2]);
        doubled.insert(3, [f64::midpoint(a[0], b[0]), f64::midpoint(a[1], b[1])]);
        let (r, p) = with(room, doubled);
        out.push(("doubled", r, p));
        if corners.len() > 3 {
            let mut dropped = corners.clone();
            dropped.remove(0);
            let (r, p) = with(room, dropped);
            out.push(("corner dropped", r, p));
        }
    }
    // Every corner moved by up to 17 cm on each axis, three ways.
    let mut rng = Rng(0x6a69_7474 ^ (n as u64) ^ plan.name.len() as u64);
    for _ in 0..3 {
        let mut p = plan.clone();
        for (_, corners) in &mut p.rooms {
            for c in corners.iter_mut() {
                c[0] += rng.range(-0.17, 0.17);
                c[1] += rng.range(-0.17, 0.17);
            }
        }
        out.push(("jitter", usize::MAX, p));
    }
    // A room with one neighbour slid along their shared wall until they meet at a corner only.
    for room in 1..n {
        let neighbours: Vec<usize> = plan
            .doors
            .iter()
            .filter_map(|&(a, b)| match a {
                Some(a) if a == room => Some(b),
                Some(a) if b == room => Some(a),
                _ => None,
            })
            .collect();
        if neighbours.len() != 1 {
            continue;
        }
        let (lo, hi) = bounds(&plan.rooms[room].1);
        let (olo, ohi) = bounds(&plan.rooms[neighbours[0]].1);
        for axis in 0..2 {
            let other = 1 - axis;
            // They share a wall across `axis`: slide along `other` past the neighbour's end.
            let meets = (lo[axis] - ohi[axis]).abs() < 1e-6 || (olo[axis] - hi[axis]).abs() < 1e-6;
            if !meets {
                continue;
            }
            for toward_high in [false, true] {
                let mut shift = [0.0; 2];
                shift[other] =
                    if toward_high { ohi[other] - lo[other] } else { olo[other] - hi[other] };
                if shift[other].abs() > 4.0 {
                    continue;
                }
                let moved =
                    plan.rooms[room].1.iter().map(|p| [p[0] + shift[0], p[1] + shift[1]]).collect();
                let (r, p) = with(room, moved);
                out.push(("corner only", r, p));
            }
        }
    }
    // A room with one neighbour, moved away from it.
    for room in 1..n {
        let neighbours: Vec<usize> = plan
            .doors
            .iter()
            .filter_map(|&(a, b)| match a {
                Some(a) if a == room => Some(b),
                Some(a) if b == room => Some(a),
                _ => None,
            })
            .collect();
        if neighbours.len() != 1 {
            continue;
        }
        let other = neighbours[0];
        let (cx, cz) = centre(&plan.rooms[room].1);
        let (ox, oz) = centre(&plan.rooms[other].1);
        let (dx, dz) = (cx - ox, cz - oz);
        let dir = if dx.abs() >= dz.abs() { [dx.signum(), 0.0] } else { [0.0, dz.signum()] };
        for &d in &[0.3, 0.6, 0.9] {
            let moved =
                plan.rooms[room].1.iter().map(|p| [p[0] + dir[0] * d, p[1] + dir[1] * d]).collect();
            let (r, p) = with(room, moved);
            out.push(("detached", r, p));
        }
    }
    out
}

fn centre(corners: &[[f64; 2]]) -> (f64, f64) {
    let (lo, hi) = bounds(corners);
    (f64::midpoint(lo[0], hi[0]), f64::midpoint(lo[1], hi[1]))
}

fn extent(corners: &[[f64; 2]]) -> [f64; 2] {
    let (lo, hi) = bounds(corners);
    [(hi[0] - lo[0]) / 2.0, (hi[1] - lo[1]) / 2.0]
}

fn bounds(corners: &[[f64; 2]]) -> ([f64; 2], [f64; 2]) {
    corners.iter().fold(([f64::INFINITY; 2], [f64::NEG_INFINITY; 2]), |(lo, hi), p| {
        ([lo[0].min(p[0]), lo[1].min(p[1])], [hi[0].max(p[0]), hi[1].max(p[1])])
    })
}

fn median(mut v: Vec<f64>) -> f64 {
    if v.is_empty() {
        return 0.0;
    }
    v.sort_by(f64::total_cmp);
    v[v.len() / 2]
}

#[derive(Default)]
struct Row {
    plans: usize,
    already_valid: usize,
    repaired: usize,
    moves: Vec<f64>,
    wall_moves: Vec<f64>,
    area: f64,
    times: Vec<f64>,
    max_time: f64,
    /// Repaired plans equal to the plan before the break.
    meant: usize,
    /// Changed plans where a room other than the broken one moved.
    others_moved: usize,
    /// Repairs that left an error of a kind the broken plan did not have.
    new_kinds: usize,
    /// Repairs whose output a second repair leaves unchanged.
    idempotent: usize,
    /// Plans repaired (changed), valid or not.
    changed: usize,
    /// Changed plans not equal to the plan meant (numbering for `REPAIR_BENCH_DUMP`).
    missed: usize,
    /// Repaired plans whose wall-sharing pairs are those of the plan meant.
    pairs_kept: usize,
    /// The farthest a corner of the plan meant is from its repaired room's corners, metres.
    deviation: f64,
    /// Repairs that reached the bound on work (W0309).
    bounded: usize,
}

fn main() {
    // `cargo bench` passes `--bench`; nothing else is read. `REPAIR_BENCH_ONLY=large` runs the
    // table of large plans alone.
    if std::env::var("REPAIR_BENCH_ONLY").is_ok_and(|v| v == "large") {
        large_plans();
        grid_plans();
        return;
    }
    let mut valid_plans = real_plans();
    for entry in std::fs::read_dir("examples").into_iter().flatten().filter_map(Result::ok) {
        let path = entry.path();
        if path.extension().is_some_and(|e| e == "holo") {
            if let Some(plan) = plan_of_example(&path) {
                valid_plans.push(plan);
            }
        }
    }
    valid_plans.extend(own_plans(40));
    valid_plans.sort_by(|a, b| a.name.cmp(&b.name));
    // Only plans that are valid as they are make broken plans.
    let bases: Vec<Plan> = valid_plans
        .into_iter()
        .filter(|p| plan_errors(&p.to_holo()).is_some_and(|e| e.is_empty()))
        .collect();
    let kinds = [
        "shift",
        "scale",
        "slant",
        "doubled",
        "detached",
        "corner dropped",
        "jitter",
        "corner only",
        "staircase",
    ];
    let mut rows: Vec<Row> = kinds.iter().map(|_| Row::default()).collect();
    let mut deterministic = true;
    let mut failures: Vec<String> = Vec::new();
    let staircases = staircase_plans();
    let all: Vec<(Plan, Vec<Break>)> = bases
        .iter()
        .map(|b| (b.clone(), breaks(b)))
        .chain(
            staircases.into_iter().map(|(meant, broken)| (meant, vec![("staircase", 1, broken)])),
        )
        .collect();
    // `REPAIR_BENCH_KINDS=jitter,corner only` measures those kinds alone.
    let only: Option<Vec<String>> = std::env::var("REPAIR_BENCH_KINDS")
        .ok()
        .map(|v| v.split(',').map(|k| k.trim().to_string()).collect());
    for (base, broken_plans) in &all {
        for (kind, broken_room, broken) in broken_plans.iter().cloned() {
            if only.as_ref().is_some_and(|o| !o.iter().any(|k| k == kind)) {
                continue;
            }
            let text = broken.to_holo();
            let Some(errors) = plan_errors(&text) else { continue };
            let row = &mut rows[kinds.iter().position(|k| *k == kind).unwrap_or(0)];
            row.plans += 1;
            if errors.is_empty() {
                row.already_valid += 1;
                continue;
            }
            let Some(out) = repair_plan(&text) else { continue };
            if repair_plan(&text).is_none_or(|again| again.text != out.text) {
                deterministic = false;
            }
            if out.idempotent {
                row.idempotent += 1;
            }
            if out.errors_after.iter().any(|c| !errors.contains(c)) {
                row.new_kinds += 1;
            }
            // What the plan means: the valid plan before the break, except for `corner only`,
            // whose break slides a room metres away: there it is the answer as written, its
            // wall-sharing pairs and the pair with a door that met only at a corner (a repair
            // moves it the least distance, never a corner more than 1 m from the answer).
            let (meant, pairs_meant) = if kind == "corner only" {
                let mut pairs = sharing_pairs_of(&broken);
                for &(a, b) in &broken.doors {
                    if let Some(a) = a {
                        pairs.push((a.min(b), a.max(b)));
                    }
                }
                pairs.sort_unstable();
                pairs.dedup();
                (&broken, pairs)
            } else {
                (base, sharing_pairs_of(base))
            };
            if out.changed && out.valid {
                if sharing_pairs(&out.corners) == pairs_meant {
                    row.pairs_kept += 1;
                } else if let Some(dir) = std::env::var_os("REPAIR_BENCH_DUMP") {
                    // The plans whose wall-sharing pairs changed, with both lists.
                    let path = std::path::Path::new(&dir).join(format!(
                        "pairs-{}-{}.holo",
                        kind.replace(' ', "_"),
                        row.repaired - row.pairs_kept
                    ));
                    let mut dump = text.clone();
                    let _ = writeln!(dump, "// pairs meant: {pairs_meant:?}");
                    let _ = writeln!(dump, "// pairs after: {:?}", sharing_pairs(&out.corners));
                    for l in base.to_holo().lines() {
                        let _ = writeln!(dump, "// meant: {l}");
                    }
                    for l in out.text.lines() {
                        let _ = writeln!(dump, "// repaired: {l}");
                    }
                    let _ = std::fs::write(path, dump);
                }
                row.deviation = row.deviation.max(deviation_from_meant(meant, &out.corners));
            }
            if out.bounded {
                row.bounded += 1;
            }
            if out.changed {
                row.changed += 1;
                if same_plan(&out.corners, base) {
                    row.meant += 1;
                } else if let Some(dir) = std::env::var_os("REPAIR_BENCH_DUMP") {
                    // The plans not brought back to the plan meant, with the meant and the
                    // repaired text, to study.
                    row.missed += 1;
                    let path = std::path::Path::new(&dir).join(format!(
                        "missed-{}-{}.holo",
                        kind.replace(' ', "_"),
                        row.missed
                    ));
                    let mut dump = text.clone();
                    for l in base.to_holo().lines() {
                        let _ = writeln!(dump, "// meant: {l}");
                    }
                    for l in out.text.lines() {
                        let _ = writeln!(dump, "// repaired: {l}");
                    }
                    let _ = std::fs::write(path, dump);
                }
                let others = out
                    .corners
                    .iter()
                    .zip(&broken.rooms)
                    .enumerate()
                    .any(|(i, (c, r))| i != broken_room && !same_outline(c, &r.1));
                let others = others && broken_room != usize::MAX;
                if others {
                    row.others_moved += 1;
                }
            }
            let ms = out.time.as_secs_f64() * 1000.0;
            row.times.push(ms);
            row.max_time = row.max_time.max(ms);
            if out.valid && out.changed {
                row.repaired += 1;
                row.moves.push(out.max_move);
                row.wall_moves.push(out.max_wall_move);
                row.area = row.area.max(out.area_change);
            } else if kind != "corner dropped" {
                failures.push(format!("{kind} of {}: {errors:?}", base.name));
                // `REPAIR_BENCH_DUMP=DIR` keeps the plans that were not repaired, to study.
                if let Some(dir) = std::env::var_os("REPAIR_BENCH_DUMP") {
                    let path = std::path::Path::new(&dir).join(format!("{}.holo", failures.len()));
                    let _ = std::fs::write(path, &text);
                }
            }
        }
    }
    println!(
        "{} valid plans ({} with real houses), broken {} ways\n",
        bases.len(),
        bases.iter().filter(|p| !p.name.starts_with("own")).count(),
        kinds.len()
    );
    println!(
        "| break | plans | valid as broken | to repair | repaired | share | equal to meant | pairs kept | deviation from meant m | other rooms moved | new error kinds | idempotent | largest corner move m | median corner move m | largest wall move m | largest area change | median ms | max ms | W0309 |"
    );
    println!("|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|");
    for (kind, row) in kinds.iter().zip(&rows) {
        let to_repair = row.plans - row.already_valid;
        let share =
            |n: usize, of: usize| if of == 0 { 100.0 } else { 100.0 * n as f64 / of as f64 };
        println!(
            "| {kind} | {} | {} | {to_repair} | {} | {:.1}% | {:.1}% | {:.1}% | {:.2} | {} | {} | {:.1}% | {:.2} | {:.2} | {:.2} | {:.1}% | {:.3} | {:.3} | {} |",
            row.plans,
            row.already_valid,
            row.repaired,
            share(row.repaired, to_repair),
            share(row.meant, row.changed),
            share(row.pairs_kept, row.repaired),
            row.deviation,
            row.others_moved,
            row.new_kinds,
            share(row.idempotent, to_repair),
            row.moves.iter().copied().fold(0.0, f64::max),
            median(row.moves.clone()),
            row.wall_moves.iter().copied().fold(0.0, f64::max),
            row.area * 100.0,
            median(row.times.clone()),
            row.max_time,
            row.bounded,
        );
    }
    let target: Vec<&Row> = rows.iter().take(2).collect();
    let to_repair: usize = target.iter().map(|r| r.plans - r.already_valid).sum();
    let repaired: usize = target.iter().map(|r| r.repaired).sum();
    let within = target.iter().flat_map(|r| &r.wall_moves).all(|&m| m <= 0.5 + 1e-9);
    println!(
        "\noverlaps and gaps up to 0.5 m (shift, scale): {repaired}/{to_repair} = {:.1}% valid, every wall moved at most 0.5 m: {within}; deterministic: {deterministic}",
        100.0 * repaired as f64 / to_repair.max(1) as f64
    );
    for f in failures.iter().take(10) {
        println!("not repaired: {f}");
    }
    large_plans();
    grid_plans();
    issue_cases();
    if std::env::var_os("REPAIR_BENCH_NO_GENERATE").is_none() {
        generate_figures(&bases);
    }
}

/// The pairs of rooms (by index) that share more than 10 cm of wall.
fn sharing_pairs(rooms: &[Vec<[f64; 2]>]) -> Vec<(usize, usize)> {
    let mut out = Vec::new();
    for i in 0..rooms.len() {
        for j in i + 1..rooms.len() {
            if shared_wall_m(&rooms[i], &rooms[j]) > 0.1 {
                out.push((i, j));
            }
        }
    }
    out
}

fn sharing_pairs_of(plan: &Plan) -> Vec<(usize, usize)> {
    let rooms: Vec<Vec<[f64; 2]>> = plan.rooms.iter().map(|r| r.1.clone()).collect();
    sharing_pairs(&rooms)
}

/// The length of wall two rectilinear outlines share.
fn shared_wall_m(a: &[[f64; 2]], b: &[[f64; 2]]) -> f64 {
    let mut total = 0.0;
    for i in 0..a.len() {
        let (p, q) = (a[i], a[(i + 1) % a.len()]);
        for j in 0..b.len() {
            let (r, s) = (b[j], b[(j + 1) % b.len()]);
            for axis in 0..2 {
                let other = 1 - axis;
                let on_line = (p[axis] - q[axis]).abs() < 1e-6
                    && (r[axis] - s[axis]).abs() < 1e-6
                    && (p[axis] - r[axis]).abs() < 1e-6;
                if on_line {
                    let lo = p[other].min(q[other]).max(r[other].min(s[other]));
                    let hi = p[other].max(q[other]).min(r[other].max(s[other]));
                    total += (hi - lo).max(0.0);
                }
            }
        }
    }
    total
}

/// The farthest a corner of the plan meant is from the nearest corner of its repaired room.
fn deviation_from_meant(meant: &Plan, got: &[Vec<[f64; 2]>]) -> f64 {
    let mut worst: f64 = 0.0;
    for ((_, m), g) in meant.rooms.iter().zip(got) {
        for p in m {
            let nearest =
                g.iter().map(|q| (p[0] - q[0]).hypot(p[1] - q[1])).fold(f64::INFINITY, f64::min);
            worst = worst.max(nearest);
        }
    }
    worst
}

/// A room whose north-east side is a staircase of `steps` steps from (0, 6) down to (6, 1),
/// and a room south of it: the plan meant.
fn staircase_plan(steps: usize, south_top: f64) -> Plan {
    let (w, h) = (6.0, 6.0);
    let (s, t) = (w / steps as f64, (h - 1.0) / steps as f64);
    let mut corners = vec![[0.0, 0.0], [0.0, h]];
    for i in 0..steps {
        corners.push([(i + 1) as f64 * s, h - i as f64 * t]);
        corners.push([(i + 1) as f64 * s, h - (i + 1) as f64 * t]);
    }
    corners.push([w, 0.0]);
    Plan {
        name: format!("staircase {}", corners.len()),
        rooms: vec![
            ("stairs".into(), corners),
            ("south".into(), vec![[0.0, -3.0], [0.0, south_top], [6.0, south_top], [6.0, -3.0]]),
        ],
        doors: vec![(None, 0), (Some(0), 1)],
    }
}

/// Staircase rooms of 51 to 199 corners, each with its neighbour drawn 10, 20 or 30 cm into it.
fn staircase_plans() -> Vec<(Plan, Plan)> {
    let mut out = Vec::new();
    for steps in [24, 49, 74, 98] {
        for overlap in [0.1, 0.2, 0.3] {
            out.push((staircase_plan(steps, 0.0), staircase_plan(steps, overlap)));
        }
    }
    out
}

/// Plans of up to 64 KB: a row of rooms of 199 corners each (their walls cut into many short
/// pieces), each drawn 10 cm into the one before. The time of one repair and whether it
/// reached the bound on work (W0309).
fn large_plans() {
    println!(
        "
| large plan | rooms | corners | KB | repaired | ms | W0309 |"
    );
    println!("|---|---|---|---|---|---|---|");
    for rooms in [2, 5, 10, 17] {
        let mut plan =
            Plan { name: format!("row of {rooms}"), rooms: Vec::new(), doors: vec![(None, 0)] };
        for r in 0..rooms {
            let x0 = r as f64 * 4.0 - if r > 0 { 0.1 } else { 0.0 };
            let x1 = (r + 1) as f64 * 4.0;
            // 199 corners: 50 on each of the west, north and east walls, 49 on the south one.
            let mut corners = Vec::new();
            for i in 0..50 {
                corners.push([x0, 6.0 * i as f64 / 50.0]);
            }
            for i in 0..50 {
                corners.push([x0 + (x1 - x0) * i as f64 / 50.0, 6.0]);
            }
            for i in 0..50 {
                corners.push([x1, 6.0 - 6.0 * i as f64 / 50.0]);
            }
            for i in 0..49 {
                corners.push([x1 - (x1 - x0) * i as f64 / 49.0, 0.0]);
            }
            plan.rooms.push((format!("r{r}"), corners));
            if r > 0 {
                plan.doors.push((Some(r - 1), r));
            }
        }
        let text = plan.to_holo();
        let corners: usize = plan.rooms.iter().map(|r| r.1.len()).sum();
        let Some(out) = repair_plan(&text) else {
            println!(
                "| {} | {rooms} | {corners} | {:.1} | (not checked) | | |",
                plan.name,
                text.len() as f64 / 1024.0
            );
            continue;
        };
        println!(
            "| {} | {rooms} | {corners} | {:.1} | {} | {:.1} | {} |",
            plan.name,
            text.len() as f64 / 1024.0,
            out.valid && out.changed,
            out.time.as_secs_f64() * 1000.0,
            out.bounded
        );
    }
}

/// Plans of up to 64 KB of many small rooms: a grid of `side` × `side` rooms of 3 m × 3 m
/// (doors between neighbours in a row and down the first column), every corner jittered by
/// up to 17 cm, or one room drawn 30 cm into its neighbour. The time of one repair, whether
/// the plan came out valid and whether it reached the bound on work (W0309).
fn grid_plans() {
    println!("\n| grid plan | rooms | corners | KB | repaired | ms | W0309 |");
    println!("|---|---|---|---|---|---|---|");
    for side in [5, 10, 17, 24] {
        for jitter in [true, false] {
            let mut rng = Rng(0x6772_6964 ^ side as u64);
            let mut plan = Plan {
                name: format!("grid of {side}x{side}{}", if jitter { ", jittered" } else { "" }),
                rooms: Vec::new(),
                doors: vec![(None, 0)],
            };
            for i in 0..side {
                for j in 0..side {
                    let (x0, z0) = (i as f64 * 3.0, j as f64 * 3.0);
                    let mut corners =
                        vec![[x0, z0], [x0, z0 + 3.0], [x0 + 3.0, z0 + 3.0], [x0 + 3.0, z0]];
                    if jitter {
                        for c in &mut corners {
                            c[0] += rng.range(-0.17, 0.17);
                            c[1] += rng.range(-0.17, 0.17);
                        }
                    } else if i == side / 2 && j == side / 2 {
                        for c in &mut corners {
                            c[0] -= 0.3;
                        }
                    }
                    let r = plan.rooms.len();
                    plan.rooms.push((format!("g{i}_{j}"), corners));
                    if j > 0 {
                        plan.doors.push((Some(r - 1), r));
                    } else if i > 0 {
                        plan.doors.push((Some(r - side), r));
                    }
                }
            }
            let text = plan.to_holo();
            let corners: usize = plan.rooms.iter().map(|r| r.1.len()).sum();
            let kb = text.len() as f64 / 1024.0;
            match repair_plan(&text) {
                Some(out) => println!(
                    "| {} | {} | {corners} | {kb:.1} | {} | {:.1} | {} |",
                    plan.name,
                    plan.rooms.len(),
                    out.valid && out.changed,
                    out.time.as_secs_f64() * 1000.0,
                    out.bounded
                ),
                None => println!(
                    "| {} | {} | {corners} | {kb:.1} | (not checked) | | |",
                    plan.name,
                    plan.rooms.len()
                ),
            }
        }
    }
}

/// Whether two outlines have the same corners (as sets, to the millimetre).
fn same_outline(a: &[[f64; 2]], b: &[[f64; 2]]) -> bool {
    let key = |c: &[[f64; 2]]| {
        let mut k: Vec<(i64, i64)> = c
            .iter()
            .map(|p| ((p[0] * 1000.0).round() as i64, (p[1] * 1000.0).round() as i64))
            .collect();
        k.sort_unstable();
        k.dedup();
        k
    };
    key(a) == key(b)
}

/// Whether repaired outlines are the plan meant, room by room.
fn same_plan(corners: &[Vec<[f64; 2]>], meant: &Plan) -> bool {
    corners.len() == meant.rooms.len()
        && corners.iter().zip(&meant.rooms).all(|(c, r)| same_outline(c, &r.1))
}

/// The examples of issue 27 (the fixtures under `tests/corpus/repair/`): whether each becomes
/// valid, which rooms move, and whether a second repair changes anything.
fn issue_cases() {
    println!("\n| issue case | valid after repair | rooms moved | idempotent |");
    println!("|---|---|---|---|");
    for name in [
        "laundry_into_hallway",
        "laundry_declared_first",
        "gap_accepted",
        "corner_only",
        "slant_rounder",
        "shifted_room",
        "narrow_hallway",
    ] {
        let path = format!("tests/corpus/repair/{name}.holo");
        let Ok(text) = std::fs::read_to_string(&path) else {
            println!("| {name} | (missing) | | |");
            continue;
        };
        let mut sources = SourceMap::new();
        let id = sources.add(path.clone(), text.clone());
        let Some(scene) = holoc::compile::check_file(&sources, id).value else { continue };
        let Some(out) = repair_plan(&text) else { continue };
        let moved: Vec<&str> = scene
            .rooms
            .iter()
            .zip(&out.corners)
            .filter(|(r, c)| !same_outline(&r.corners, c))
            .map(|(r, _)| r.name.as_str())
            .collect();
        println!("| {name} | {} | {} | {} |", out.valid, moved.join(", "), out.idempotent);
    }
}

/// Broken plans given to `holoc generate` as the model's floor-plan answers over the loopback
/// server (the doorways answer lists the plan's doors, the windows answer says there are none,
/// every room gets one chair): the share that ends in a scene, the share whose scene is the
/// plan meant, and the model requests per run.
fn generate_figures(bases: &[Plan]) {
    use holoc::generate::{generate, GenerateOptions, HttpLlm, HttpOptions, Request};
    use std::sync::{Arc, Mutex};
    let script: Arc<Mutex<(String, String)>> = Arc::new(Mutex::new((String::new(), String::new())));
    let answers = Arc::clone(&script);
    let server = llm_server::Server::start(Arc::new(move |asked: &llm_server::Asked, _| {
        let (plan, doors) = answers.lock().map(|a| a.clone()).unwrap_or_default();
        match asked.stage {
            "floor-plan" => llm_server::Reply::answer(&plan),
            "doorways" => llm_server::Reply::answer(&doors),
            "windows" => llm_server::Reply::answer("No windows."),
            "wall-height" => llm_server::Reply::answer("2.7"),
            "objects" => llm_server::Reply::answer(
                r#"{"chair": {"description": "wooden chair", "location": "floor", "size": [50, 50, 90], "quantity": 1, "variance_type": "same", "objects_on_top": []}}"#,
            ),
            "floor-constraints" => llm_server::Reply::answer("chair-0 | edge"),
            _ => llm_server::Reply::answer("none"),
        }
    }));
    let mut options = HttpOptions::new(server.base_url.clone(), "bench-model");
    options.retries = 0;
    let llm = HttpLlm::new(options);
    let generate_options = GenerateOptions {
        jobs: 1,
        small_objects: false,
        ceiling: false,
        ..GenerateOptions::default()
    };
    let mut runs = 0usize;
    let mut needing = 0usize;
    let mut scenes = 0usize;
    let mut meant = 0usize;
    let mut floor_requests = 0usize;
    let mut all_requests = 0usize;
    let mut k = 0usize;
    for base in bases {
        for (kind, _, broken) in breaks(base) {
            if !matches!(kind, "shift" | "scale" | "slant" | "detached") {
                continue;
            }
            k += 1;
            // Every fifth break, to keep the run short.
            if k % 5 != 0 {
                continue;
            }
            let text = broken.to_holo();
            let Some(errors) = plan_errors(&text) else { continue };
            if errors.is_empty() && !has_gaps(&text) {
                continue;
            }
            needing += 1;
            let plan_answer: Vec<String> = broken
                .rooms
                .iter()
                .map(|(id, c)| {
                    let cs: Vec<String> =
                        c.iter().map(|p| format!("({:.4}, {:.4})", p[0], p[1])).collect();
                    format!("{id} | oak | white | [{}]", cs.join(", "))
                })
                .collect();
            let doors: Vec<String> = broken
                .doors
                .iter()
                .map(|(a, b)| {
                    let from = a.map_or("exterior".to_string(), |i| broken.rooms[i].0.clone());
                    format!(
                        "{from} | {} | doorway | single | white wooden door",
                        broken.rooms[*b].0
                    )
                })
                .collect();
            if let Ok(mut s) = script.lock() {
                *s = (plan_answer.join("\n"), doors.join("\n"));
            }
            let before = server.calls();
            let request = Request { text: format!("bench {}", broken.name), seed: 1 };
            let outcome = generate(&request, &llm, &generate_options);
            runs += 1;
            all_requests += server.calls() - before;
            floor_requests += outcome
                .value
                .transcript
                .exchanges
                .iter()
                .filter(|e| e.stage == "floor-plan" && e.usage.is_some())
                .count();
            if outcome.has_errors() || outcome.value.holo.is_empty() {
                // `REPAIR_BENCH_DUMP=DIR` keeps the answers that ended in no scene, with the
                // run's errors.
                if let Some(dir) = std::env::var_os("REPAIR_BENCH_DUMP") {
                    let mut dump = text.clone();
                    for d in outcome.diagnostics.iter().filter(|d| d.is_error()) {
                        let _ = writeln!(dump, "// error: {} {}", d.code.as_str(), d.message);
                    }
                    let path = std::path::Path::new(&dir).join(format!("no-scene-{runs}.holo"));
                    let _ = std::fs::write(path, dump);
                }
                continue;
            }
            let mut sources = SourceMap::new();
            let id = sources.add("generated.holo", outcome.value.holo.clone());
            let checked = holoc::compile::check_file(&sources, id);
            let Some(scene) = checked.value else { continue };
            let planned = holoc::plan::plan(&scene, StructureCatalog::builtin());
            if planned.diagnostics.iter().any(Diagnostic::is_error) {
                continue;
            }
            scenes += 1;
            let corners: Vec<Vec<[f64; 2]>> =
                scene.rooms.iter().map(|r| r.corners.clone()).collect();
            if same_plan(&corners, base) {
                meant += 1;
            }
        }
    }
    let share = |n: usize| 100.0 * n as f64 / needing.max(1) as f64;
    println!(
        "\ngenerate over the loopback server: {needing} broken plans needing repair as model answers; {scenes} ({:.1}%) end in a scene, {meant} ({:.1}%) in the plan meant; {:.2} model requests per run, {:.2} of them for the floor plan",
        share(scenes),
        share(meant),
        all_requests as f64 / runs.max(1) as f64,
        floor_requests as f64 / runs.max(1) as f64,
    );
}

/// Whether a plan text has gaps between facing rooms (W0308).
fn has_gaps(text: &str) -> bool {
    let mut sources = SourceMap::new();
    let id = sources.add("plan.holo", text.to_string());
    let Some(scene) = holoc::compile::check_file(&sources, id).value else { return false };
    holoc::plan::plan(&scene, StructureCatalog::builtin())
        .diagnostics
        .iter()
        .any(|d| d.code.as_str() == "W0308")
}

/// The floor plan of an example `.holo` file (rooms and doors only).
fn plan_of_example(path: &std::path::Path) -> Option<Plan> {
    let text = std::fs::read_to_string(path).ok()?;
    let mut sources = SourceMap::new();
    let id = sources.add(path.display().to_string(), text);
    let scene = holoc::compile::check_file(&sources, id).value?;
    if scene.rooms.len() < 2 {
        return None;
    }
    let rooms = scene.rooms.iter().map(|r| (r.name.clone(), r.corners.clone())).collect();
    let doors = scene
        .doors
        .iter()
        .filter_map(|d| {
            use holoc::check::scene::DoorSide;
            match (&d.from, &d.to) {
                (DoorSide::Room(a), DoorSide::Room(b)) => Some((Some(a.0), b.0)),
                (DoorSide::Exterior, DoorSide::Room(b))
                | (DoorSide::Room(b), DoorSide::Exterior) => Some((None, b.0)),
                _ => None,
            }
        })
        .collect();
    let name = path.file_stem()?.to_string_lossy().to_string();
    Some(Plan { name, rooms, doors })
}

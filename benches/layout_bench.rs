//! Layout benchmark over the corpus `tests/corpus/solve/*.json`.
//!
//! `cargo bench --bench layout_bench -- --table` prints a table per room (median time of the
//! DFS over a few runs, objects placed, constraints satisfied by the DFS, by the MILP and by the
//! greedy baseline), then the generator's rooms of 10 to 100 objects
//! (`tests/corpus/solve-generated`, also alone with `--generated`) with their nodes, time per
//! node and the fitted exponents. Without `--table` it runs criterion on a few representative rooms (a
//! criterion filter such as `dfs/classroom_25` picks one). `--why` prints the objects each room
//! leaves out and the constraints its layout breaks, `--summary` one line per room and the
//! totals (`--budget N` sets their node budget); `--only NAME` keeps one room, `--dir DIR` reads
//! the rooms of another folder.

// The table is the point of this binary: it prints to stdout on purpose.
#![allow(clippy::print_stdout)]

#[path = "../tests/support/solve_corpus.rs"]
mod solve_corpus;

use std::time::{Duration, Instant};

use criterion::{black_box, Criterion};
use holoc::solve::{self, RoomProblem, SolveOptions, Solver};

fn median_time(problem: &RoomProblem, opts: &SolveOptions, runs: usize) -> Duration {
    let mut times: Vec<Duration> = (0..runs)
        .map(|_| {
            let t = Instant::now();
            black_box(solve::solve_room(problem, opts));
            t.elapsed()
        })
        .collect();
    times.sort();
    times[times.len() / 2]
}

/// The slope of `ln y` against `ln x` by least squares: the exponent of a power law.
fn fitted_exponent(points: &[(f64, f64)]) -> f64 {
    let n = points.len() as f64;
    let (lx, ly): (Vec<f64>, Vec<f64>) = points.iter().map(|(x, y)| (x.ln(), y.ln())).unzip();
    let mx = lx.iter().sum::<f64>() / n;
    let my = ly.iter().sum::<f64>() / n;
    let sxy: f64 = lx.iter().zip(&ly).map(|(x, y)| (x - mx) * (y - my)).sum();
    let sxx: f64 = lx.iter().map(|x| (x - mx) * (x - mx)).sum();
    sxy / sxx
}

fn table(rooms: &[(String, RoomProblem)]) {
    println!(
        "| room | objects | DFS median ms | nodes | found at | placed | DFS sat | clearances kept | largest pocket m² | greedy ms | greedy sat | MILP ms | MILP placed | MILP sat | overlaps |"
    );
    println!("|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|");
    let (mut sat_all, mut total_all, mut placed_all, mut objects_all) = (0, 0, 0, 0);
    let mut slowest = (Duration::ZERO, String::new());
    let mut times = Vec::new();
    let mut generated = Vec::new();
    for (name, p) in rooms {
        let dfs = SolveOptions::default();
        let milp = SolveOptions { solver: Solver::Milp, ..SolveOptions::default() };
        let t = median_time(p, &dfs, 7);
        let out = solve::solve_room(p, &dfs).value;
        let greedy = solve::solve_room_greedy(p, &dfs).value;
        let tg = median_time(p, &SolveOptions { node_budget: 0, ..dfs }, 3);
        let tm = median_time(p, &milp, 1);
        let mo = solve::solve_room(p, &milp).value;
        let (ok, total) = out.constraint_tally(p);
        let (gok, _) = greedy.constraint_tally(p);
        let (mok, _) = mo.constraint_tally(p);
        let overlaps = out
            .floor
            .iter()
            .enumerate()
            .flat_map(|(i, a)| out.floor[i + 1..].iter().map(move |b| (a, b)))
            .filter(|(a, b)| a.footprint.overlaps(&b.footprint))
            .count();
        sat_all += ok;
        total_all += total;
        placed_all += out.floor.len();
        objects_all += p.objects.len();
        times.push(t);
        if t > slowest.0 {
            slowest = (t, name.clone());
        }
        if name.starts_with("generated_") {
            generated.push((p.objects.len() as f64, t.as_secs_f64()));
        }
        let (ck, ct) = solve::use_clearances_kept(p, &out);
        let pocket = solve::largest_pocket_m2(p, &out, dfs.agent_radius_m);
        println!(
            "| {name} | {} | {:.1} | {} | {} | {}/{} | {ok}/{total} | {ck}/{ct} | {pocket:.2} | {:.1} | {gok}/{total} | {:.0} | {}/{} | {mok}/{total} | {overlaps} |",
            p.objects.len(),
            t.as_secs_f64() * 1000.0,
            out.nodes,
            out.found_at,
            out.floor.len(),
            p.objects.len(),
            tg.as_secs_f64() * 1000.0,
            tm.as_secs_f64() * 1000.0,
            mo.floor.len(),
            p.objects.len(),
        );
    }
    let mut by_time: Vec<(Duration, &str)> =
        rooms.iter().zip(&times).map(|((name, _), &t)| (t, name.as_str())).collect();
    by_time.sort_by(|a, b| b.0.cmp(&a.0).then(a.1.cmp(b.1)));
    times.sort();
    println!();
    let slowest5: Vec<String> = by_time
        .iter()
        .take(5)
        .map(|(t, name)| format!("{name} {:.1} ms", t.as_secs_f64() * 1000.0))
        .collect();
    println!("slowest 5 rooms: {}", slowest5.join(", "));
    println!(
        "all rooms: {placed_all}/{objects_all} placed, {sat_all}/{total_all} constraints kept ({:.3}), median {:.1} ms, slowest {:.1} ms ({})",
        sat_all as f64 / total_all.max(1) as f64,
        times.get(times.len() / 2).map_or(0.0, |t| t.as_secs_f64() * 1000.0),
        slowest.0.as_secs_f64() * 1000.0,
        slowest.1,
    );
    if generated.len() >= 2 {
        println!(
            "solve time against objects over the generated rooms: exponent {:.2} (1.0 is linear)",
            fitted_exponent(&generated)
        );
    }
    println!();
    println!("| room | budget | placed | kept | ms |");
    println!("|---|---|---|---|---|");
    for (name, p) in rooms.iter().filter(|(n, _)| {
        ["restaurant_34", "restaurant_tables_first", "generated_80", "packed_bedroom_60"]
            .contains(&n.as_str())
    }) {
        let mut last = (0, 0);
        for budget in [1000, 2000, 4000, 8000, 10_000] {
            let opts = SolveOptions { node_budget: budget, ..SolveOptions::default() };
            let t = Instant::now();
            let out = solve::solve_room(p, &opts).value;
            let ms = t.elapsed().as_secs_f64() * 1000.0;
            let r = (out.floor.len(), out.constraint_tally(p).0);
            let worse = if r < last { " (worse!)" } else { "" };
            println!("| {name} | {budget} | {} | {}{worse} | {ms:.1} |", r.0, r.1);
            last = r;
        }
    }
}

/// The relations a room's first (greedy) layout breaks: what keeps its search going, printed
/// for rooms whose search walks more nodes than they have objects.
fn searched_for(problem: &RoomProblem) -> Vec<String> {
    let first = SolveOptions { node_budget: 1, ..SolveOptions::default() };
    let out = solve::solve_room(problem, &first).value;
    let mut broken: Vec<String> =
        out.unplaced.iter().map(|u| format!("{} left out", u.id)).collect();
    for f in &out.floor {
        for c in f.constraints.iter().filter(|c| !c.measure.satisfied) {
            broken.push(format!("{} {}", problem.objects[f.index].id, c.text));
        }
    }
    broken
}

/// The generator's rooms of 10 to 100 objects (`tests/corpus/solve-generated`): per room its
/// median time, nodes and time per node, and the fitted exponents of time, nodes and time per
/// node against objects.
fn generated_table(rooms: &[(String, RoomProblem)]) {
    let mut rooms: Vec<&(String, RoomProblem)> = rooms.iter().collect();
    rooms.sort_by_key(|(_, p)| p.objects.len());
    println!(
        "| generated room | objects | median ms | nodes | µs per node | kept | searched for |"
    );
    println!("|---|---|---|---|---|---|---|");
    let (mut time, mut nodes, mut per_node) = (Vec::new(), Vec::new(), Vec::new());
    for (name, p) in rooms {
        let opts = SolveOptions::default();
        let t = median_time(p, &opts, 5).as_secs_f64();
        let out = solve::solve_room(p, &opts).value;
        let (ok, total) = out.constraint_tally(p);
        let n = p.objects.len() as f64;
        let walked = out.nodes.max(1) as f64;
        let why = if out.nodes as usize > p.objects.len() {
            searched_for(p).join("; ")
        } else {
            String::new()
        };
        println!(
            "| {name} | {} | {:.1} | {} | {:.0} | {ok}/{total} | {why} |",
            p.objects.len(),
            t * 1000.0,
            out.nodes,
            t / walked * 1e6,
        );
        time.push((n, t));
        nodes.push((n, walked));
        per_node.push((n, t / walked));
    }
    if time.len() >= 2 {
        println!(
            "over the generated rooms: time N^{:.2}, nodes N^{:.2}, time per node N^{:.2}",
            fitted_exponent(&time),
            fitted_exponent(&nodes),
            fitted_exponent(&per_node)
        );
    }
}

fn main() {
    let args: Vec<String> = std::env::args().collect();
    // `--dir DIR` reads the rooms of another folder in the corpus's format (the generator of
    // `make_corpus.py` at other seeds and sizes) instead of the corpus.
    let mut rooms = match args.iter().position(|a| a == "--dir").and_then(|i| args.get(i + 1)) {
        Some(dir) => solve_corpus::load_dir(std::path::Path::new(dir)),
        None => solve_corpus::load_all(),
    };
    // `--only NAME` keeps one room (for profiling with `--table` or `--repeat`).
    if let Some(name) = args.iter().position(|a| a == "--only").and_then(|i| args.get(i + 1)) {
        rooms.retain(|(n, _)| n == name);
    }
    // `--repeat N` solves each room N times and prints nothing else: a loop for a profiler.
    if let Some(n) = args.iter().position(|a| a == "--repeat").and_then(|i| args.get(i + 1)) {
        let n: usize = n.parse().unwrap_or(1);
        for (_, p) in &rooms {
            for _ in 0..n {
                black_box(solve::solve_room(black_box(p), &SolveOptions::default()));
            }
        }
        return;
    }
    if args.iter().any(|a| a == "--table") {
        table(&rooms);
        // Beside the corpus, the generator's rooms of every size from 10 to 100 objects.
        if !args.iter().any(|a| a == "--dir" || a == "--only") {
            println!();
            generated_table(&solve_corpus::load_dir(
                &solve_corpus::corpus_dir().with_file_name("solve-generated"),
            ));
        }
        return;
    }
    // `--generated` prints the table of the generator's rooms alone.
    if args.iter().any(|a| a == "--generated") {
        let dir = solve_corpus::corpus_dir().with_file_name("solve-generated");
        generated_table(&solve_corpus::load_dir(&dir));
        return;
    }
    // `--budget N` sets the node budget of `--summary` and `--why` (0: the greedy pass).
    let options = match args.iter().position(|a| a == "--budget").and_then(|i| args.get(i + 1)) {
        Some(n) => {
            SolveOptions { node_budget: n.parse().unwrap_or(1000), ..SolveOptions::default() }
        }
        None => SolveOptions::default(),
    };
    // `--summary` prints one line per room (objects, placed, constraints kept, nodes, found
    // at) and the totals: a quick comparison of two builds over many rooms.
    if args.iter().any(|a| a == "--summary") {
        let (mut placed, mut kept, mut total, mut nodes) = (0, 0, 0, 0);
        for (name, p) in &rooms {
            let out = solve::solve_room(p, &options).value;
            let (ok, all) = out.constraint_tally(p);
            println!(
                "{name} {} placed {} kept {ok}/{all} nodes {} found {}",
                p.objects.len(),
                out.floor.len(),
                out.nodes,
                out.found_at
            );
            (placed, kept, total, nodes) =
                (placed + out.floor.len(), kept + ok, total + all, nodes + out.nodes);
        }
        println!("all: placed {placed} kept {kept}/{total} nodes {nodes}");
        return;
    }
    // `--why` prints, per room, the objects left out and the constraints the layout breaks
    // (`--poses`: and every placed object's pose and footprint).
    if args.iter().any(|a| a == "--why") {
        for (name, p) in &rooms {
            let out = solve::solve_room(p, &options).value;
            println!("{name}: {} nodes, found at {}", out.nodes, out.found_at);
            for u in &out.unplaced {
                println!("  left out {}: {}", u.id, u.reason);
            }
            for f in &out.floor {
                if args.iter().any(|a| a == "--poses") {
                    let r = &f.footprint;
                    println!(
                        "  {} at ({:.2}, {:.2}) {:?}: [{:.2}, {:.2}]-[{:.2}, {:.2}]",
                        p.objects[f.index].id,
                        f.pose.x,
                        f.pose.z,
                        f.pose.rot,
                        r.min_x,
                        r.min_z,
                        r.max_x,
                        r.max_z
                    );
                }
                for c in f.constraints.iter().filter(|c| !c.measure.satisfied) {
                    println!("  {} {}: {:?}", p.objects[f.index].id, c.text, c.measure);
                }
            }
        }
        return;
    }
    let mut c = Criterion::default().configure_from_args().sample_size(20);
    for (name, p) in rooms.iter().filter(|(n, _)| {
        ["bedroom", "classroom_25", "open_office_40", "restaurant_34", "l_shaped_living"]
            .contains(&n.as_str())
    }) {
        c.bench_function(&format!("dfs/{name}"), |b| {
            b.iter(|| solve::solve_room(black_box(p), &SolveOptions::default()));
        });
    }
    c.final_summary();
}

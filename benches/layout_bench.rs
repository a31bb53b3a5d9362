//! Layout benchmark over the corpus `tests/corpus/solve/*.json`.
//!
//! `cargo bench --bench layout_bench -- --table` prints a table per room (median time of the
//! DFS over a few runs, objects placed, constraints satisfied by the DFS, by the MILP and by the
//! greedy baseline). Without `--table` it runs criterion on a few representative rooms (a
//! criterion filter such as `dfs/classroom_25` picks one).

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

fn table(rooms: &[(String, RoomProblem)]) {
    println!(
        "| room | objects | DFS median ms | nodes | placed | DFS sat | clearances kept | largest pocket m² | greedy ms | greedy sat | MILP ms | MILP placed | MILP sat | overlaps |"
    );
    println!("|---|---|---|---|---|---|---|---|---|---|---|---|---|---|");
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
        let (ck, ct) = solve::use_clearances_kept(p, &out);
        let pocket = solve::largest_pocket_m2(p, &out, dfs.agent_radius_m);
        println!(
            "| {name} | {} | {:.1} | {} | {}/{} | {ok}/{total} | {ck}/{ct} | {pocket:.2} | {:.1} | {gok}/{total} | {:.0} | {}/{} | {mok}/{total} | {overlaps} |",
            p.objects.len(),
            t.as_secs_f64() * 1000.0,
            out.nodes,
            out.floor.len(),
            p.objects.len(),
            tg.as_secs_f64() * 1000.0,
            tm.as_secs_f64() * 1000.0,
            mo.floor.len(),
            p.objects.len(),
        );
    }
}

fn main() {
    let rooms = solve_corpus::load_all();
    if std::env::args().any(|a| a == "--table") {
        table(&rooms);
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

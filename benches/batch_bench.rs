//! `holoc batch` figures: build throughput, memory against the number of jobs, and the cost of
//! resuming a finished manifest.
//!
//! `cargo bench --bench batch_bench` writes manifests of 1,000 and 10,000 builds of the
//! examples (each with its own seed) into a scratch folder and runs the release binary on
//! them: houses per second per core (`--jobs 1`), the peak memory of the 1,000- and the
//! 10,000-job runs with one thread per core (read with `/usr/bin/time -f %M` when it exists),
//! and the time per job of a second run over the finished 10,000-job manifest (every job
//! skipped). `-- --small N --large M` change the sizes.
//!
//! Then the figures of a week-long run: the cost per job of resuming jobs that all name a
//! 30 MB catalog (`--catalog-jobs`, default 200), the throughput of generate jobs against a
//! loopback model server that answers each request in 1 s (with `--jobs 1` and
//! `--llm-concurrency` 4 and 8, then `--jobs 4 --llm-concurrency 4`: the rate follows the model
//! slots, not the CPU workers), and the balance of 4 shards over a mixed manifest (the largest
//! shard's summed job time against the mean). `-- --only week` runs only these.

// The table is the point of this binary: it prints to stdout on purpose.
#![allow(clippy::print_stdout)]

#[path = "../tests/support/llm_server.rs"]
mod llm_server;

use std::fmt::Write as _;
use std::path::{Path, PathBuf};
use std::process::Command;
use std::time::Instant;

fn manifest(dir: &Path, jobs: usize, examples: &[PathBuf]) -> PathBuf {
    let mut lines = String::new();
    for k in 0..jobs {
        let example = &examples[k % examples.len()];
        let _ = writeln!(
            lines,
            "{{\"build\": \"{}\", \"seed\": {}}}",
            example.display(),
            k / examples.len() + 1
        );
    }
    let path = dir.join(format!("manifest-{jobs}.jsonl"));
    std::fs::write(&path, lines).expect("the manifest is written");
    path
}

/// Runs `holoc batch` and returns (seconds, peak resident memory in KB when measurable).
fn run(manifest: &Path, out: &Path, jobs: usize) -> (f64, Option<u64>) {
    let holoc = env!("CARGO_BIN_EXE_holoc");
    let time = Path::new("/usr/bin/time");
    let started = Instant::now();
    let output = if time.exists() {
        Command::new(time)
            .args(["-f", "%M", holoc, "batch"])
            .arg(manifest)
            .arg("-o")
            .arg(out)
            // The examples are outside the manifests' scratch folder.
            .args(["-q", "--allow-outside", "--jobs", &jobs.to_string()])
            .output()
    } else {
        Command::new(holoc)
            .arg("batch")
            .arg(manifest)
            .arg("-o")
            .arg(out)
            // The examples are outside the manifests' scratch folder.
            .args(["-q", "--allow-outside", "--jobs", &jobs.to_string()])
            .output()
    }
    .expect("holoc runs");
    let seconds = started.elapsed().as_secs_f64();
    let stderr = String::from_utf8_lossy(&output.stderr);
    assert!(output.status.success(), "the batch failed: {stderr}");
    let peak = stderr.lines().last().and_then(|l| l.trim().parse().ok());
    (seconds, peak)
}

/// A procthor-format catalog of about `mb` megabytes.
fn big_catalog(path: &Path, mb: usize) {
    let mut text = String::from("{\n  \"Sofa\": [\n");
    let mut k = 0;
    while text.len() < mb * 1024 * 1024 {
        let _ = writeln!(
            text,
            "    {{\"assetId\": \"Bench_Sofa_{k}\", \"objectType\": \"Sofa\", \"boundingBox\": {{\"x\": 2.1, \"y\": 0.85, \"z\": 0.95}}, \"description\": \"a sofa of the benchmark number {k}\"}},"
        );
        k += 1;
    }
    text.push_str("    {\"assetId\": \"Bench_Sofa_last\", \"objectType\": \"Sofa\"}\n  ]\n}\n");
    std::fs::write(path, text).expect("the catalog is written");
}

/// Runs `holoc batch` with extra arguments; returns the seconds.
fn run_with(manifest: &Path, out: &Path, extra: &[&str]) -> f64 {
    let started = Instant::now();
    let output = Command::new(env!("CARGO_BIN_EXE_holoc"))
        .arg("batch")
        .arg(manifest)
        .arg("-o")
        .arg(out)
        .args(["-q", "--allow-outside", "--allow-job-base-url"])
        .args(extra)
        .output()
        .expect("holoc runs");
    assert!(
        output.status.code().is_some_and(|c| c <= 1),
        "{}",
        String::from_utf8_lossy(&output.stderr)
    );
    started.elapsed().as_secs_f64()
}

fn summary(path: &Path) -> serde_json::Value {
    serde_json::from_str(&std::fs::read_to_string(path).expect("summary")).expect("json")
}

/// The figures of a week-long run (see the module's comment).
fn week(dir: &Path, examples: &[PathBuf], catalog_jobs: usize) {
    println!("| measure | value |\n|---|---|");
    // Resume with a 30 MB catalog.
    let catalog = dir.join("big.json");
    big_catalog(&catalog, 30);
    let bedroom = examples.iter().find(|p| p.ends_with("bedroom.holo")).expect("the bedroom");
    let mut lines = String::new();
    for seed in 1..=catalog_jobs {
        let _ = writeln!(
            lines,
            "{{\"build\": \"{}\", \"seed\": {seed}, \"catalog\": [\"big.json\"]}}",
            bedroom.display()
        );
    }
    let manifest = dir.join("catalog.jsonl");
    std::fs::write(&manifest, lines).expect("write");
    let first = run_with(&manifest, &dir.join("out-catalog"), &["--jobs", "2"]);
    let resume = run_with(&manifest, &dir.join("out-catalog"), &["--jobs", "2"]);
    println!("| first run, {catalog_jobs} jobs naming a 30 MB catalog, --jobs 2 | {first:.1} s |");
    println!(
        "| resume of them | {resume:.2} s ({:.3} ms per job, the catalog hashed once included) |",
        resume * 1000.0 / catalog_jobs as f64
    );
    // Generate throughput against a server answering in 1 s.
    let server = llm_server::Server::start(std::sync::Arc::new(|asked: &llm_server::Asked, _| {
        let mut reply = llm_server::clean_answer(asked);
        reply.delay_ms = 1000;
        reply
    }));
    for (jobs, k, n) in [(1, 4, 8), (1, 8, 8), (4, 4, 8)] {
        let mut lines = String::new();
        for seed in 1..=n {
            let _ = writeln!(
                lines,
                "{{\"generate\": \"a 1b1b apartment\", \"seed\": {seed}, \"base_url\": \"{}\", \"model\": \"bench-{jobs}-{k}\"}}",
                server.base_url
            );
        }
        let manifest = dir.join(format!("generate-{jobs}-{k}.jsonl"));
        std::fs::write(&manifest, lines).expect("write");
        let before = server.calls();
        let seconds = run_with(
            &manifest,
            &dir.join(format!("out-generate-{jobs}-{k}")),
            &["--jobs", &jobs.to_string(), "--llm-concurrency", &k.to_string()],
        );
        let calls = server.calls() - before;
        println!(
            "| {n} generate jobs, model 1 s per answer, --jobs {jobs} --llm-concurrency {k} | {seconds:.1} s, {calls} requests, {:.2} requests/s |",
            calls as f64 / seconds
        );
    }
    // Shard balance on a mixed manifest: every example, 20 seeds each.
    let mut lines = String::new();
    for seed in 1..=20 {
        for example in examples {
            let _ = writeln!(lines, "{{\"build\": \"{}\", \"seed\": {seed}}}", example.display());
        }
    }
    let manifest = dir.join("mixed.jsonl");
    std::fs::write(&manifest, lines).expect("write");
    let out = dir.join("out-mixed");
    let mut work = Vec::new();
    for i in 0..4 {
        run_with(&manifest, &out, &["--jobs", "1", "--shard", &format!("{i}/4")]);
        let s = summary(&out.join(format!("summary.shard-{i}-of-4.json")));
        let jobs = s["jobs"].as_array().expect("jobs");
        work.push((jobs.len(), jobs.iter().filter_map(|j| j["seconds"].as_f64()).sum::<f64>()));
    }
    let mean = work.iter().map(|w| w.1).sum::<f64>() / 4.0;
    let most = work.iter().map(|w| w.1).fold(0.0, f64::max);
    let shown: Vec<String> = work.iter().map(|(n, s)| format!("{n} jobs {s:.2} s")).collect();
    println!(
        "| 4 shards of {} mixed jobs (the six examples, 20 seeds each) | {}; largest {:.2}x the mean |",
        examples.len() * 20,
        shown.join(", "),
        most / mean
    );
}

fn main() {
    let args: Vec<String> = std::env::args().collect();
    let value = |name: &str, default: usize| {
        args.iter()
            .position(|a| a == name)
            .and_then(|i| args.get(i + 1))
            .and_then(|v| v.parse().ok())
            .unwrap_or(default)
    };
    let (small, large) = (value("--small", 1000), value("--large", 10_000));
    let dir = std::env::temp_dir().join(format!("holoc-batch-bench-{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).expect("scratch folder");
    let mut examples: Vec<PathBuf> = std::fs::read_dir("examples")
        .expect("examples")
        .filter_map(Result::ok)
        .map(|e| e.path())
        .filter(|p| p.extension().is_some_and(|e| e == "holo"))
        .map(|p| std::fs::canonicalize(p).expect("a path"))
        .collect();
    examples.sort();
    if args.iter().any(|a| a == "week") {
        week(&dir, &examples, value("--catalog-jobs", 200));
        let _ = std::fs::remove_dir_all(&dir);
        return;
    }
    let m_small = manifest(&dir, small, &examples);
    let m_large = manifest(&dir, large, &examples);
    let (t_small, _) = run(&m_small, &dir.join("out-small"), 1);
    let cores = std::thread::available_parallelism().map_or(1, usize::from);
    // Memory is compared at the same number of threads (each thread keeps its own scratch).
    let (_, mem_small) = run(&m_small, &dir.join("out-small-threads"), cores);
    let (t_large, mem_large) = run(&m_large, &dir.join("out-large"), cores);
    let (t_resume, _) = run(&m_large, &dir.join("out-large"), cores);
    let kb =
        |m: Option<u64>| m.map_or("n/a".to_string(), |m| format!("{:.1} MB", m as f64 / 1024.0));
    println!("| measure | value |\n|---|---|");
    println!("| {small} builds of the {} examples, --jobs 1 | {t_small:.1} s |", examples.len());
    println!("| houses per second per core | {:.1} |", small as f64 / t_small);
    println!(
        "| {large} builds, --jobs {cores} | {t_large:.1} s ({:.1} houses/s) |",
        large as f64 / t_large
    );
    println!("| peak memory, {small} jobs, --jobs {cores} | {} |", kb(mem_small));
    println!("| peak memory, {large} jobs, --jobs {cores} | {} |", kb(mem_large));
    if let (Some(a), Some(b)) = (mem_small, mem_large) {
        println!(
            "| memory growth from {small} to {large} jobs | {:+.1}% |",
            (b as f64 / a as f64 - 1.0) * 100.0
        );
    }
    println!(
        "| resume of a finished {large}-job manifest | {t_resume:.2} s ({:.3} ms per job) |",
        t_resume * 1000.0 / large as f64
    );
    println!();
    week(&dir, &examples, value("--catalog-jobs", 200));
    let _ = std::fs::remove_dir_all(&dir);
}

//! `holoc batch` figures: build throughput, memory against the number of jobs, and the cost of
//! resuming a finished manifest.
//!
//! `cargo bench --bench batch_bench` writes manifests of 1,000 and 10,000 builds of the
//! examples (each with its own seed) into a scratch folder and runs the release binary on
//! them: houses per second per core (`--jobs 1`), the peak memory of the 1,000- and the
//! 10,000-job runs with one thread per core (read with `/usr/bin/time -f %M` when it exists),
//! and the time per job of a second run over the finished 10,000-job manifest (every job
//! skipped). `-- --small N --large M` change the sizes.

// The table is the point of this binary: it prints to stdout on purpose.
#![allow(clippy::print_stdout)]

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
            .args(["-q", "--jobs", &jobs.to_string()])
            .output()
    } else {
        Command::new(holoc)
            .arg("batch")
            .arg(manifest)
            .arg("-o")
            .arg(out)
            .args(["-q", "--jobs", &jobs.to_string()])
            .output()
    }
    .expect("holoc runs");
    let seconds = started.elapsed().as_secs_f64();
    let stderr = String::from_utf8_lossy(&output.stderr);
    assert!(output.status.success(), "the batch failed: {stderr}");
    let peak = stderr.lines().last().and_then(|l| l.trim().parse().ok());
    (seconds, peak)
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
    let _ = std::fs::remove_dir_all(&dir);
}

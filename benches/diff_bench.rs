//! `holoc diff` figures: the time and peak memory of a diff of two folders of houses laid out
//! like `holoc batch` outputs, 5% of the houses changed.
//!
//! `cargo bench --bench diff_bench` builds the examples once (house and report), writes two
//! folders of 1,000 and two of 10,000 job folders (`<hash>/house.json`, `report.json`,
//! `job.json`, the houses taken in turn from the examples), moves one object and changes one
//! asset in every twentieth house of the second folder, and runs the release binary's
//! `holoc diff --stat` on each pair (peak memory read with `/usr/bin/time -f %M` when it
//! exists). `-- --small N --large M` change the sizes.

// The table is the point of this binary: it prints to stdout on purpose.
#![allow(clippy::print_stdout)]

use std::path::{Path, PathBuf};
use std::process::Command;
use std::time::Instant;

/// The examples' houses and reports, built once.
fn build_examples(dir: &Path) -> Vec<(String, String)> {
    let holoc = env!("CARGO_BIN_EXE_holoc");
    let mut examples: Vec<PathBuf> = std::fs::read_dir("examples")
        .expect("examples")
        .filter_map(Result::ok)
        .map(|e| e.path())
        .filter(|p| p.extension().is_some_and(|e| e == "holo"))
        .collect();
    examples.sort();
    let mut out = Vec::new();
    for (k, example) in examples.iter().enumerate() {
        let house = dir.join(format!("example-{k}.json"));
        let report = dir.join(format!("example-{k}.report.json"));
        let status = Command::new(holoc)
            .arg("build")
            .arg(example)
            .arg("-o")
            .arg(&house)
            .arg("--report")
            .arg(&report)
            .arg("-q")
            .status()
            .expect("holoc runs");
        assert!(status.success(), "{} builds", example.display());
        out.push((
            std::fs::read_to_string(&house).expect("house"),
            std::fs::read_to_string(&report).expect("report"),
        ));
    }
    out
}

/// The house with its first object moved 30 cm and its second object's asset changed.
fn changed(house: &str) -> String {
    let mut v: serde_json::Value = serde_json::from_str(house).expect("a house");
    if let Some(objects) = v["objects"].as_array_mut() {
        if let Some(o) = objects.first_mut() {
            let x = o["position"]["x"].as_f64().unwrap_or(0.0);
            o["position"]["x"] = serde_json::json!(x + 0.3);
        }
        if let Some(o) = objects.get_mut(1) {
            let asset = o["assetId"].as_str().unwrap_or_default().to_string();
            o["assetId"] = serde_json::json!(format!("{asset}_changed"));
        }
    }
    serde_json::to_string_pretty(&v).expect("JSON")
}

/// Writes two folders of `n` job folders; every twentieth house of the second is changed.
fn folders(dir: &Path, n: usize, examples: &[(String, String)]) -> (PathBuf, PathBuf) {
    let (a, b) = (dir.join(format!("a-{n}")), dir.join(format!("b-{n}")));
    let changed_houses: Vec<String> = examples.iter().map(|(h, _)| changed(h)).collect();
    for k in 0..n {
        let (house, report) = &examples[k % examples.len()];
        let job = format!("{{\"line\": {}, \"id\": \"job-{k:05}\"}}\n", k + 1);
        for (root, changed) in [(&a, false), (&b, k % 20 == 0)] {
            let folder = root.join(format!("{k:016x}"));
            std::fs::create_dir_all(&folder).expect("a job folder");
            let text = if changed { &changed_houses[k % examples.len()] } else { house };
            std::fs::write(folder.join("house.json"), text).expect("house");
            std::fs::write(folder.join("report.json"), report).expect("report");
            std::fs::write(folder.join("job.json"), &job).expect("job");
            std::fs::write(folder.join("done"), "").expect("marker");
        }
    }
    (a, b)
}

/// Runs `holoc diff --stat` and returns (seconds, peak resident memory in KB when measurable).
fn run(a: &Path, b: &Path) -> (f64, Option<u64>) {
    let holoc = env!("CARGO_BIN_EXE_holoc");
    let time = Path::new("/usr/bin/time");
    let started = Instant::now();
    let output = if time.exists() {
        Command::new(time).args(["-f", "%M", holoc, "diff", "--stat"]).arg(a).arg(b).output()
    } else {
        Command::new(holoc).args(["diff", "--stat"]).arg(a).arg(b).output()
    }
    .expect("holoc runs");
    let seconds = started.elapsed().as_secs_f64();
    let stdout = String::from_utf8_lossy(&output.stdout);
    let stderr = String::from_utf8_lossy(&output.stderr);
    assert_eq!(output.status.code(), Some(1), "the folders differ: {stderr}");
    let last = stdout.lines().last().unwrap_or_default().to_string();
    println!("    {last}");
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
    let dir = std::env::temp_dir().join(format!("holoc-diff-bench-{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).expect("scratch folder");
    let examples = build_examples(&dir);
    let bytes: usize =
        examples.iter().map(|(h, r)| h.len() + r.len()).sum::<usize>() / examples.len();
    let cores = std::thread::available_parallelism().map_or(1, usize::from);
    let kb =
        |m: Option<u64>| m.map_or("n/a".to_string(), |m| format!("{:.1} MB", m as f64 / 1024.0));
    let mut rows = Vec::new();
    for n in [small, large] {
        let (a, b) = folders(&dir, n, &examples);
        let (seconds, peak) = run(&a, &b);
        rows.push((n, seconds, peak));
        let _ = std::fs::remove_dir_all(&a);
        let _ = std::fs::remove_dir_all(&b);
    }
    println!("| measure | value |\n|---|---|");
    println!(
        "| house + report, average size | {:.0} KB ({} examples) |",
        bytes as f64 / 1024.0,
        examples.len()
    );
    for (n, seconds, peak) in &rows {
        println!(
            "| `holoc diff --stat` of two {n}-house folders, 5% changed, {cores} cores | {seconds:.2} s ({:.2} ms per pair), peak memory {} |",
            seconds * 1000.0 / *n as f64,
            kb(*peak)
        );
    }
    let _ = std::fs::remove_dir_all(&dir);
}

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
use std::sync::atomic::{AtomicUsize, Ordering};
use std::sync::{Arc, Mutex};
use std::time::{Duration, Instant};

/// The holoc binary to measure: `HOLOC_BIN` (a release build, when the benchmark itself runs in
/// test mode: `cargo test --bench batch_bench`), else the one cargo built with the benchmark.
fn holoc_bin() -> PathBuf {
    std::env::var_os("HOLOC_BIN")
        .map_or_else(|| PathBuf::from(env!("CARGO_BIN_EXE_holoc")), PathBuf::from)
}

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
    let holoc = holoc_bin();
    let time = Path::new("/usr/bin/time");
    let started = Instant::now();
    let output = if time.exists() {
        Command::new(time)
            .args(["-f", "%M"])
            .arg(&holoc)
            .arg("batch")
            .arg(manifest)
            .arg("-o")
            .arg(out)
            // The examples are outside the manifests' scratch folder.
            .args(["-q", "--allow-outside", "--jobs", &jobs.to_string()])
            .output()
    } else {
        Command::new(&holoc)
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
    let output = Command::new(holoc_bin())
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
    if args.iter().any(|a| a == "stable") {
        stable(&dir, &examples);
        let _ = std::fs::remove_dir_all(&dir);
        return;
    }
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
    println!();
    stable(&dir, &examples);
    let _ = std::fs::remove_dir_all(&dir);
}

/// Runs the holoc binary with `args` (and `env`), returning its exit status, its stderr and the
/// CPU it used (user + system seconds, read with `/usr/bin/time -f` when it exists, else the
/// wall clock).
fn timed(args: &[&std::ffi::OsStr], env: &[(&str, &str)]) -> (Option<i32>, String, f64) {
    let time = Path::new("/usr/bin/time");
    let mut command = if time.exists() {
        let mut c = Command::new(time);
        c.args(["-f", "cpu %U %S"]).arg(holoc_bin());
        c
    } else {
        Command::new(holoc_bin())
    };
    command.args(args);
    for (k, v) in env {
        command.env(k, v);
    }
    let started = Instant::now();
    let output = command.output().expect("holoc runs");
    let wall = started.elapsed().as_secs_f64();
    let stderr = String::from_utf8_lossy(&output.stderr).into_owned();
    let cpu = stderr
        .lines()
        .rev()
        .find_map(|l| l.strip_prefix("cpu "))
        .and_then(|l| {
            let mut f = l.split_whitespace().map(str::parse::<f64>);
            Some(f.next()?.ok()? + f.next()?.ok()?)
        })
        .unwrap_or(wall);
    (output.status.code(), stderr, cpu)
}

fn os(s: &str) -> &std::ffi::OsStr {
    std::ffi::OsStr::new(s)
}

/// A manifest of `files` (names in `dir`) at `seeds`, one line per (seed, file).
fn seeded_manifest(
    dir: &Path,
    name: &str,
    files: &[String],
    seeds: std::ops::RangeInclusive<u64>,
) -> PathBuf {
    let mut lines = String::new();
    for seed in seeds {
        for f in files {
            let _ = writeln!(lines, "{{\"build\": \"{f}\", \"seed\": {seed}}}");
        }
    }
    let path = dir.join(name);
    std::fs::write(&path, lines).expect("write");
    path
}

/// The shard of every line of a manifest (line → shard), as `holoc batch --shard I/N` splits it.
fn shards_of(manifest: &Path, count: usize) -> std::collections::BTreeMap<usize, usize> {
    let text = std::fs::read_to_string(manifest).expect("manifest");
    let base = manifest.parent().expect("a folder");
    let files = holoc::batch::FileHashes::default();
    let url = "http://127.0.0.1:9/v1";
    holoc::batch::manifest_lines(&text)
        .filter_map(|(line, raw)| match holoc::batch::read_line(line, raw, base)? {
            Ok(job) => Some((line, holoc::batch::job_place(&job, &files, url).shard(count))),
            Err(_) => {
                Some((line, holoc::batch::shard_of(&holoc::batch::line_identity(raw), count)))
            }
        })
        .collect()
}

/// The figures of issue 52 (a run that loses nothing): jobs moved by a one-line edit, the
/// balance of the shards by CPU, merge of a partial run, an outage of the model of 1 and 5
/// minutes, a full disk, and houses per CPU-second on the examples and on a mix.
/// `-- --only stable` runs only these.
fn stable(dir: &Path, examples: &[PathBuf]) {
    let work = dir.join("stable");
    std::fs::create_dir_all(&work).expect("folder");
    let mut names = Vec::new();
    for e in examples {
        let name = e.file_name().expect("a name").to_string_lossy().into_owned();
        std::fs::copy(e, work.join(&name)).expect("copy");
        names.push(name);
    }
    println!("| measure | value |\n|---|---|");
    // Houses per CPU-second: the examples at seeds 1–30, --jobs 1, a fresh folder.
    let manifest = seeded_manifest(&work, "examples.jsonl", &names, 1..=30);
    let jobs = names.len() * 30;
    let out = work.join("out-examples");
    let (code, stderr, cpu) = timed(
        &[
            os("batch"),
            manifest.as_os_str(),
            os("-o"),
            out.as_os_str(),
            os("-q"),
            os("--jobs"),
            os("1"),
        ],
        &[],
    );
    assert_eq!(code, Some(0), "{stderr}");
    println!(
        "| houses per CPU-second, the {} examples at seeds 1–30 ({jobs} jobs), `--jobs 1` | {:.0} ({cpu:.2} CPU-s) |",
        names.len(),
        jobs as f64 / cpu
    );
    // The CPU of each job (its seconds at --jobs 1), for the balance below.
    let per_job: std::collections::BTreeMap<usize, f64> = summary(&out.join("summary.json"))
        ["jobs"]
        .as_array()
        .expect("jobs")
        .iter()
        .filter_map(|j| Some((j["line"].as_u64()? as usize, j["seconds"].as_f64()?)))
        .collect();
    // A mix: the examples and the scenes of the corpus that build, each at seeds 1–10.
    let mut mix = names.clone();
    for folder in ["tests/corpus/plan/ok", "tests/corpus/resolve/scenes", "tests/corpus/repair/ok"]
    {
        let Ok(entries) = std::fs::read_dir(folder) else { continue };
        let mut found: Vec<PathBuf> = entries
            .filter_map(Result::ok)
            .map(|e| e.path())
            .filter(|p| p.extension().is_some_and(|e| e == "holo"))
            .collect();
        found.sort();
        for p in found {
            let name = format!("mix-{}", p.file_name().expect("name").to_string_lossy());
            std::fs::copy(&p, work.join(&name)).expect("copy");
            mix.push(name);
        }
    }
    let mixed = seeded_manifest(&work, "mix.jsonl", &mix, 1..=10);
    let out = work.join("out-mix");
    let (code, stderr, cpu) = timed(
        &[
            os("batch"),
            mixed.as_os_str(),
            os("-o"),
            out.as_os_str(),
            os("-q"),
            os("--jobs"),
            os("1"),
        ],
        &[],
    );
    assert!(code.is_some_and(|c| c <= 1), "{stderr}");
    let s = summary(&out.join("summary.json"));
    let houses = s["done"].as_u64().unwrap_or(0);
    println!(
        "| houses per CPU-second, a mix of {} scenes at seeds 1–10 ({} jobs, {} failed) | {:.0} ({cpu:.2} CPU-s) |",
        mix.len(),
        houses + s["failed"].as_u64().unwrap_or(0),
        s["failed"],
        houses as f64 / cpu
    );

    // Balance by CPU, from each job's measured seconds, and jobs moved by a one-line edit.
    for count in [4usize, 8, 32] {
        let split = shards_of(&manifest, count);
        let mut sum = vec![0.0f64; count];
        for (line, shard) in &split {
            sum[*shard] += per_job.get(line).copied().unwrap_or(0.0);
        }
        let mean = sum.iter().sum::<f64>() / count as f64;
        let most = sum.iter().copied().fold(0.0, f64::max);
        println!(
            "| {count} shards of the {jobs} jobs, by their measured CPU | largest {:.3}x the mean |",
            most / mean
        );
    }
    let count = 32;
    let before = shards_of(&manifest, count);
    let text = std::fs::read_to_string(&manifest).expect("manifest");
    // One seed edited (line 5), a line added at the top: every other line moves down by one.
    let mut lines: Vec<String> = text.lines().map(str::to_string).collect();
    lines[4] = lines[4].replace("\"seed\": 1}", "\"seed\": 1000}");
    let edited = work.join("edited.jsonl");
    std::fs::write(
        &edited,
        format!("{{\"build\": \"{}\", \"seed\": 77}}\n{}\n", names[0], lines.join("\n")),
    )
    .expect("write");
    let after = shards_of(&edited, count);
    let moved =
        before.iter().filter(|(l, s)| **l != 5 && after.get(&(**l + 1)) != Some(*s)).count();
    println!("| jobs moved by a one-line edit and a line added, 32 shards | {moved} of {} besides the edited line |", jobs - 1);
    // A comment added to one scene: its 30 jobs are new jobs; the others stay.
    let touched = &names[0];
    let mut scene = std::fs::read_to_string(work.join(touched)).expect("scene");
    scene.push_str("// a comment\n");
    let copy = work.join("commented");
    std::fs::create_dir_all(&copy).expect("folder");
    for n in &names {
        std::fs::copy(work.join(n), copy.join(n)).expect("copy");
    }
    std::fs::write(copy.join(touched), scene).expect("write");
    std::fs::copy(&manifest, copy.join("examples.jsonl")).expect("copy");
    let after = shards_of(&copy.join("examples.jsonl"), count);
    let moved_other = before
        .iter()
        .filter(|(l, s)| {
            !text.lines().nth(**l - 1).is_some_and(|t| t.contains(touched.as_str()))
                && after.get(l) != Some(*s)
        })
        .count();
    println!(
        "| jobs of other scenes moved by a comment added to one scene, 32 shards | {moved_other} of {} |",
        jobs - 30
    );

    // Merge of a partial run: 4 shards of 40 jobs, one line then edited and only its old
    // shard re-run.
    let small = seeded_manifest(&work, "small.jsonl", &names[..4], 1..=10);
    let out = work.join("out-merge");
    for i in 0..4 {
        let shard = format!("{i}/4");
        let (code, stderr, _) = timed(
            &[
                os("batch"),
                small.as_os_str(),
                os("-o"),
                out.as_os_str(),
                os("-q"),
                os("--shard"),
                os(&shard),
            ],
            &[],
        );
        assert_eq!(code, Some(0), "{stderr}");
    }
    let (code, _, _) = timed(
        &[
            os("batch"),
            os("merge"),
            out.as_os_str(),
            os("-q"),
            os("-o"),
            work.join("merged.json").as_os_str(),
        ],
        &[],
    );
    println!("| merge of 4 complete shards (40 jobs) | exit {} |", code.unwrap_or(-1));
    let text = std::fs::read_to_string(&small).expect("manifest");
    // The first line of seed 3 edited to a new seed, and the shard that ran it re-run (read
    // from the shards' summaries: the benchmark's own build of holoc has another identity),
    // until the new seed takes the line to another shard.
    let line = text.lines().position(|l| l.contains("\"seed\": 3}")).expect("a line") + 1;
    let old_shard = (0..4)
        .find(|i| {
            summary(&out.join(format!("summary.shard-{i}-of-4.json")))["jobs"]
                .as_array()
                .is_some_and(|jobs| jobs.iter().any(|j| j["line"].as_u64() == Some(line as u64)))
        })
        .expect("the line's shard");
    let mut result = (None, String::new(), 0.0);
    for new_seed in 300..340 {
        let edited = text.replacen("\"seed\": 3}", &format!("\"seed\": {new_seed}}}"), 1);
        std::fs::write(&small, &edited).expect("write");
        let shard = format!("{old_shard}/4");
        let (code, _, _) = timed(
            &[
                os("batch"),
                small.as_os_str(),
                os("-o"),
                out.as_os_str(),
                os("-q"),
                os("--shard"),
                os(&shard),
            ],
            &[],
        );
        assert!(code.is_some_and(|c| c <= 1));
        let merged = work.join("merged.json");
        result = timed(
            &[os("batch"), os("merge"), out.as_os_str(), os("-q"), os("-o"), merged.as_os_str()],
            &[],
        );
        if result.0 != Some(0) {
            break;
        }
    }
    let (code, stderr, _) = result;
    let named = stderr.lines().filter(|l| l.contains("note:") && l.contains("line")).count();
    let (partial, _, _) = timed(
        &[
            os("batch"),
            os("merge"),
            out.as_os_str(),
            os("-q"),
            os("--partial"),
            os("-o"),
            work.join("partial.json").as_os_str(),
        ],
        &[],
    );
    let incomplete =
        summary(&work.join("partial.json"))["incomplete"].as_array().map_or(0, Vec::len);
    println!(
        "| merge after one line edited and its old shard re-run | exit {} naming {named} line(s); `--partial` exit {}, {incomplete} line(s) under `incomplete` |",
        code.unwrap_or(-1),
        partial.unwrap_or(-1)
    );

    // An outage of the model of 1 and 5 minutes, played 100 times faster
    // (HOLOC_BATCH_TIME_SCALE): the server answers the first 3 requests, then fails every
    // request (503, 502, 429 with Retry-After: 30, 500 in turn) for the outage's length, then
    // answers again. Default back-off (1 s) and patience (15 minutes).
    let scale = 100.0;
    for (minutes, patience) in [(1u64, None), (5, None), (5, Some("2m"))] {
        let down_from: Arc<Mutex<Option<Instant>>> = Arc::default();
        let failed = Arc::new(AtomicUsize::new(0));
        let (from, fails) = (Arc::clone(&down_from), Arc::clone(&failed));
        let outage = Duration::from_secs_f64(minutes as f64 * 60.0 / scale);
        let server = llm_server::Server::start(Arc::new(move |asked: &llm_server::Asked, n| {
            if n >= 3 {
                let mut start = from.lock().expect("lock");
                let at = *start.get_or_insert_with(Instant::now);
                if at.elapsed() < outage {
                    let k = fails.fetch_add(1, Ordering::SeqCst);
                    return match k % 4 {
                        0 => llm_server::Reply::status(503, "{}"),
                        1 => llm_server::Reply::status(502, "{}"),
                        2 => llm_server::Reply {
                            retry_after: Some("30"),
                            ..llm_server::Reply::status(429, "{}")
                        },
                        _ => llm_server::Reply::status(500, "{}"),
                    };
                }
            }
            llm_server::clean_answer(asked)
        }));
        let manifest = work.join(format!("outage-{minutes}.jsonl"));
        std::fs::write(&manifest, "{\"generate\": \"a 1b1b apartment\", \"seed\": 4}\n")
            .expect("write");
        let out = work.join(format!("out-outage-{minutes}-{}", patience.unwrap_or("default")));
        let mut args = vec![
            os("batch"),
            manifest.as_os_str(),
            os("-o"),
            out.as_os_str(),
            os("-q"),
            os("--base-url"),
            os(&server.base_url),
        ];
        if let Some(p) = patience {
            args.extend([os("--model-patience"), os(p)]);
        }
        let started = Instant::now();
        let (code, stderr, _) = timed(&args, &[("HOLOC_BATCH_TIME_SCALE", "100")]);
        let first_wall = started.elapsed().as_secs_f64();
        let first_calls = server.calls();
        let s = summary(&out.join("summary.json"));
        let record = &s["jobs"][0];
        let mut line = format!(
            "| outage of {minutes} min, patience {} | exit {}, {} done, {} requests ({} failed, {} retries), {:.0} s simulated",
            patience.unwrap_or("15m (default)"),
            code.unwrap_or(-1),
            s["done"],
            first_calls,
            failed.load(Ordering::SeqCst),
            record["model_retries"],
            first_wall * scale,
        );
        if code != Some(0) {
            // The outage over: the same command again.
            while down_from.lock().expect("lock").is_some_and(|at| at.elapsed() < outage) {
                std::thread::sleep(Duration::from_millis(20));
            }
            let (again, _, _) = timed(&args, &[("HOLOC_BATCH_TIME_SCALE", "100")]);
            let asked = server.calls() - first_calls;
            let _ = write!(
                line,
                "; run again: exit {}, {} done, {asked} requests, the {} answered before reused",
                again.unwrap_or(-1),
                summary(&out.join("summary.json"))["done"],
                3
            );
            let _ = stderr;
        }
        println!("{line} |");
    }

    // A full disk: writes fail after the 6th file of the run (HOLOC_BATCH_DISK_FULL_AFTER).
    let manifest = seeded_manifest(&work, "disk.jsonl", &names[..2], 1..=5);
    let out = work.join("out-disk");
    let (code, _, _) = timed(
        &[
            os("batch"),
            manifest.as_os_str(),
            os("-o"),
            out.as_os_str(),
            os("-q"),
            os("--jobs"),
            os("1"),
        ],
        &[("HOLOC_BATCH_DISK_FULL_AFTER", "6")],
    );
    let s = summary(&out.join("summary.json"));
    let failures =
        std::fs::read_to_string(out.join("failures.jsonl")).map_or(0, |t| t.lines().count());
    let (again, _, _) =
        timed(&[os("batch"), manifest.as_os_str(), os("-o"), out.as_os_str(), os("-q")], &[]);
    let t = summary(&out.join("summary.json"));
    println!(
        "| disk full after 6 files, 10 jobs | exit {}, summary.json with {} done + {} failed, failures.jsonl {failures} lines; run again: exit {}, {} done + {} skipped |",
        code.unwrap_or(-1),
        s["done"],
        s["failed"],
        again.unwrap_or(-1),
        t["done"],
        t["skipped"]
    );
}

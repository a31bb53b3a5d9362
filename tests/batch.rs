//! `holoc batch` through the binary: shards are disjoint and cover the manifest, a run killed
//! part way and run again gives the same outputs byte for byte as an uninterrupted run, a
//! failing job is recorded with its codes while the others finish, generate jobs run against
//! the loopback server and reuse what they recorded, and `batch merge` joins the shards.

mod common;
#[path = "support/llm_server.rs"]
mod llm_server;

use llm_server::{clean_answer, Asked, Reply, Server};
use std::collections::BTreeMap;
use std::path::{Path, PathBuf};
use std::process::{Command, Output};
use std::sync::atomic::{AtomicBool, Ordering};
use std::sync::Arc;

fn holoc() -> Command {
    Command::new(env!("CARGO_BIN_EXE_holoc"))
}

fn scratch(name: &str) -> PathBuf {
    let dir = std::env::temp_dir().join(format!("holoc-batch-{}-{name}", std::process::id()));
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).expect("scratch folder");
    dir
}

/// A manifest of `n` builds of the bedroom example with seeds 1..=n, in `dir`.
fn builds(dir: &Path, n: u64) -> PathBuf {
    builds_of(dir, "bedroom", n)
}

/// A manifest of `n` builds of an example with seeds 1..=n, in `dir`.
fn builds_of(dir: &Path, example: &str, n: u64) -> PathBuf {
    let file = format!("{example}.holo");
    std::fs::copy(Path::new("examples").join(&file), dir.join(&file)).expect("copy");
    let lines: Vec<String> =
        (1..=n).map(|seed| format!(r#"{{"build": "{file}", "seed": {seed}}}"#)).collect();
    let manifest = dir.join("manifest.jsonl");
    std::fs::write(&manifest, lines.join("\n") + "\n").expect("write");
    manifest
}

fn batch(args: &[&str], manifest: &Path, out: &Path) -> Output {
    holoc()
        .arg("batch")
        .arg(manifest)
        .arg("-o")
        .arg(out)
        .args(["-q"])
        .args(args)
        .output()
        .expect("holoc runs")
}

/// [`batch`] for manifests whose generate jobs name the test's loopback server: a job may
/// choose its server only with `--allow-job-base-url`.
fn batch_llm(args: &[&str], manifest: &Path, out: &Path) -> Output {
    let mut all = vec!["--allow-job-base-url"];
    all.extend_from_slice(args);
    batch(&all, manifest, out)
}

/// Every job folder of `out` with the bytes of its files.
fn folders(out: &Path) -> BTreeMap<String, BTreeMap<String, Vec<u8>>> {
    let mut all = BTreeMap::new();
    for entry in std::fs::read_dir(out).expect("out").filter_map(Result::ok) {
        let path = entry.path();
        let name = entry.file_name().to_string_lossy().to_string();
        if !path.is_dir() || name.starts_with('.') {
            continue;
        }
        let files = std::fs::read_dir(&path)
            .expect("job folder")
            .filter_map(Result::ok)
            .map(|f| {
                (
                    f.file_name().to_string_lossy().to_string(),
                    std::fs::read(f.path()).expect("file"),
                )
            })
            .collect();
        all.insert(name, files);
    }
    all
}

fn summary(path: &Path) -> serde_json::Value {
    serde_json::from_str(&std::fs::read_to_string(path).expect("summary")).expect("json")
}

#[test]
fn shards_are_disjoint_and_cover_the_manifest_and_merge_into_one() {
    let dir = scratch("shards");
    let manifest = builds(&dir, 7);
    let whole = batch(&[], &manifest, &dir.join("whole"));
    assert!(whole.status.success(), "{}", String::from_utf8_lossy(&whole.stderr));
    let out = dir.join("sharded");
    let mut seen: Vec<String> = Vec::new();
    for i in 0..3 {
        let shard = format!("{i}/3");
        let run = batch(&["--shard", &shard], &manifest, &out);
        assert!(run.status.success(), "{}", String::from_utf8_lossy(&run.stderr));
        let s = summary(&out.join(format!("summary.shard-{i}-of-3.json")));
        for job in s["jobs"].as_array().expect("jobs") {
            seen.push(job["hash"].as_str().expect("hash").to_string());
        }
    }
    let total = seen.len();
    seen.sort();
    seen.dedup();
    assert_eq!(seen.len(), total, "no job is in two shards");
    assert_eq!(total, 7, "the shards cover the manifest");
    assert_eq!(folders(&out), folders(&dir.join("whole")), "sharded = whole, byte for byte");
    let merged = holoc()
        .args(["batch", "merge", "-q", "-o"])
        .arg(dir.join("merged.json"))
        .arg(&out)
        .output()
        .expect("runs");
    assert!(merged.status.success(), "{}", String::from_utf8_lossy(&merged.stderr));
    let m = summary(&dir.join("merged.json"));
    assert_eq!(m["done"], 7);
    assert_eq!(m["shards"], serde_json::json!(["0/3", "1/3", "2/3"]));
}

#[test]
fn a_killed_batch_run_again_gives_the_same_outputs() {
    let dir = scratch("resume");
    // The classroom (tens of milliseconds a job) so that the run is still going when it is
    // killed: the kill comes once the first job's folder is there, not after a fixed time.
    let manifest = builds_of(&dir, "classroom", 30);
    let reference = batch(&["--jobs", "2"], &manifest, &dir.join("reference"));
    assert!(reference.status.success());
    let out = dir.join("killed");
    let mut child = holoc()
        .arg("batch")
        .arg(&manifest)
        .arg("-o")
        .arg(&out)
        .args(["-q", "--jobs", "1"])
        .spawn()
        .expect("starts");
    let started = std::time::Instant::now();
    while (!out.exists() || folders(&out).is_empty())
        && started.elapsed() < std::time::Duration::from_secs(60)
    {
        std::thread::sleep(std::time::Duration::from_millis(2));
    }
    let _ = child.kill();
    let _ = child.wait();
    let partial = folders(&out).len();
    assert!(partial < 30, "the batch was killed part way");
    let again = batch(&["--jobs", "2"], &manifest, &out);
    assert!(again.status.success(), "{}", String::from_utf8_lossy(&again.stderr));
    let s = summary(&out.join("summary.json"));
    assert_eq!(s["skipped"].as_u64(), Some(partial as u64), "finished jobs are skipped");
    assert_eq!(folders(&out), folders(&dir.join("reference")));
    // A third run does nothing; `--force` redoes every job, to the same bytes.
    let third = batch(&[], &manifest, &out);
    assert_eq!(summary(&out.join("summary.json"))["skipped"], 30, "{third:?}");
    let forced = batch(&["--force"], &manifest, &out);
    assert!(forced.status.success());
    assert_eq!(summary(&out.join("summary.json"))["done"], 30);
    assert_eq!(folders(&out), folders(&dir.join("reference")));
}

#[test]
fn a_failing_job_is_recorded_and_the_others_finish() {
    let dir = scratch("failing");
    std::fs::copy("examples/bedroom.holo", dir.join("bedroom.holo")).expect("copy");
    std::fs::write(
        dir.join("broken.holo"),
        "room a \"a\" {\n  corners in m (0, 0) (0, 4) (4, 4) (4, 0)\n  object c \"chair\" { near sofa-0 }\n}\ndoor exterior -- a : doorway single\n",
    )
    .expect("write");
    let manifest = dir.join("m.jsonl");
    std::fs::write(
        &manifest,
        "{\"build\": \"bedroom.holo\"}\n{\"build\": \"broken.holo\"}\n{\"build\": \"bedroom.holo\", \"seed\": 9}\nnot json\n",
    )
    .expect("write");
    let out = dir.join("out");
    let run = holoc().arg("batch").arg(&manifest).arg("-o").arg(&out).output().expect("runs");
    assert_eq!(run.status.code(), Some(1));
    let stderr = String::from_utf8_lossy(&run.stderr);
    assert!(stderr.contains("| 4 | 2 | 0 | 2 |"), "{stderr}");
    let failures: Vec<serde_json::Value> = std::fs::read_to_string(out.join("failures.jsonl"))
        .expect("failures")
        .lines()
        .map(|l| serde_json::from_str(l).expect("a JSON line"))
        .collect();
    assert_eq!(failures.len(), 2);
    assert_eq!(failures[0]["line"], 2);
    assert_eq!(failures[0]["stage"], "check");
    assert_eq!(failures[0]["codes"], serde_json::json!(["E0201"]));
    assert_eq!(failures[1]["stage"], "manifest");
    assert_eq!(folders(&out).len(), 2, "the two good jobs are built");
}

#[test]
fn generate_jobs_run_against_the_loopback_server_and_reuse_their_answers() {
    let dir = scratch("generate");
    // The first server refuses the windows question; the job fails and keeps its answers.
    let refuse = Arc::new(AtomicBool::new(true));
    let gate = refuse.clone();
    let server = Server::start(Arc::new(move |asked: &Asked, _| {
        if asked.stage == "windows" && gate.load(Ordering::SeqCst) {
            Reply::status(400, r#"{"error": {"message": "refused"}}"#)
        } else {
            clean_answer(asked)
        }
    }));
    let manifest = dir.join("m.jsonl");
    std::fs::write(
        &manifest,
        format!(
            "{{\"generate\": \"a 1b1b apartment of a researcher who has a cat\", \"seed\": 7, \"scene_type\": \"apartment\", \"base_url\": \"{}\", \"model\": \"test-model\"}}\n",
            server.base_url
        ),
    )
    .expect("write");
    let out = dir.join("out");
    let first = batch_llm(&["--llm-concurrency", "2"], &manifest, &out);
    assert_eq!(first.status.code(), Some(1), "{}", String::from_utf8_lossy(&first.stderr));
    assert_eq!(summary(&out.join("summary.json"))["jobs"][0]["stage"], "generate");
    let paid = server.calls();
    assert!(paid >= 4, "floor plan, wall height, doorways, windows: {paid}");
    refuse.store(false, Ordering::SeqCst);
    let second = batch_llm(&[], &manifest, &out);
    assert!(second.status.success(), "{}", String::from_utf8_lossy(&second.stderr));
    let asked_again = server.calls() - paid;
    let jobs = folders(&out);
    let files = jobs.values().next().expect("one job folder");
    for name in ["scene.holo", "transcript.json", "house.json", "report.json", "job.json", "done"] {
        assert!(files.contains_key(name), "{name} in {:?}", files.keys());
    }
    // The three answers recorded before the refusal were not paid for again.
    let clean = Server::start(Arc::new(|asked: &Asked, _| clean_answer(asked)));
    let fresh = dir.join("fresh.jsonl");
    std::fs::write(
        &fresh,
        std::fs::read_to_string(&manifest)
            .expect("manifest")
            .replace(&server.base_url, &clean.base_url),
    )
    .expect("write");
    let full = batch_llm(&[], &fresh, &dir.join("fresh"));
    assert!(full.status.success());
    assert_eq!(asked_again + 3, clean.calls(), "a re-run never pays twice for an answer");
    let third = batch_llm(&[], &manifest, &out);
    assert!(third.status.success());
    assert_eq!(server.calls() - paid, asked_again, "a finished job asks nothing");
}

fn failures_of(out: &Path, suffix: &str) -> Vec<serde_json::Value> {
    std::fs::read_to_string(out.join(format!("failures{suffix}.jsonl")))
        .expect("failures")
        .lines()
        .map(|l| serde_json::from_str(l).expect("a JSON line"))
        .collect()
}

/// One generate job against `base_url`, as a manifest in `dir`.
fn generate_manifest(dir: &Path, base_url: &str, seeds: &[u64]) -> PathBuf {
    let manifest = dir.join("m.jsonl");
    let lines: Vec<String> = seeds
        .iter()
        .map(|seed| format!(
            "{{\"generate\": \"a 1b1b apartment of a researcher who has a cat\", \"seed\": {seed}, \"base_url\": \"{base_url}\", \"model\": \"test-model\"}}"
        ))
        .collect();
    std::fs::write(&manifest, lines.join("\n") + "\n").expect("write");
    manifest
}

#[test]
fn a_refused_question_is_asked_again_by_the_next_run_and_force_asks_everything() {
    let dir = scratch("refused");
    // The refusal is an answer (HTTP 200), not an error: it used to be recorded and replayed.
    let refuse = Arc::new(AtomicBool::new(true));
    let gate = refuse.clone();
    let asked: Arc<std::sync::Mutex<Vec<String>>> = Arc::default();
    let log = asked.clone();
    let server = Server::start(Arc::new(move |a: &Asked, _| {
        log.lock().expect("log").push(a.stage.to_string());
        if a.stage == "windows" && gate.load(Ordering::SeqCst) {
            Reply::answer("I'm sorry, but I can't help with that.")
        } else {
            clean_answer(a)
        }
    }));
    let manifest = generate_manifest(&dir, &server.base_url, &[7]);
    let out = dir.join("out");
    let first = batch_llm(&[], &manifest, &out);
    assert_eq!(first.status.code(), Some(1), "{}", String::from_utf8_lossy(&first.stderr));
    let record = &summary(&out.join("summary.json"))["jobs"][0];
    assert_eq!(record["stage"], "generate", "{record}");
    assert_eq!(record["tries"], 1);
    let floor_plans = |log: &[String]| log.iter().filter(|s| *s == "floor-plan").count();
    let before = asked.lock().expect("log").clone();
    refuse.store(false, Ordering::SeqCst);
    let second = batch_llm(&[], &manifest, &out);
    assert!(second.status.success(), "{}", String::from_utf8_lossy(&second.stderr));
    let after = asked.lock().expect("log").clone();
    let new: Vec<&String> = after[before.len()..].iter().collect();
    assert!(new.iter().any(|s| *s == "windows"), "the refused question is asked again: {new:?}");
    assert_eq!(floor_plans(&after), floor_plans(&before), "answers that were fine are reused");
    let record = &summary(&out.join("summary.json"))["jobs"][0];
    assert_eq!(record["status"], "done");
    assert_eq!(record["tries"], 2, "{record}");
    // `--force` asks every question again.
    let forced = batch_llm(&["--force"], &manifest, &out);
    assert!(forced.status.success());
    assert_eq!(floor_plans(&asked.lock().expect("log")), floor_plans(&after) + 1);
}

#[test]
fn a_passing_model_error_is_retried_within_the_run_and_counted() {
    let dir = scratch("transient");
    let failed_once = Arc::new(AtomicBool::new(false));
    let server = Server::start(Arc::new(move |a: &Asked, _| {
        if a.stage == "doorways" && !failed_once.swap(true, Ordering::SeqCst) {
            Reply::status(503, r#"{"error": {"message": "overloaded"}}"#)
        } else {
            clean_answer(a)
        }
    }));
    let manifest = generate_manifest(&dir, &server.base_url, &[3]);
    let out = dir.join("out");
    let run = batch_llm(&[], &manifest, &out);
    assert!(run.status.success(), "{}", String::from_utf8_lossy(&run.stderr));
    let record = &summary(&out.join("summary.json"))["jobs"][0];
    assert_eq!(record["model_retries"], 1, "{record}");
    assert_eq!(record["tries"], 1);
}

#[test]
fn retry_failed_tries_a_failed_job_again_in_the_same_run() {
    let dir = scratch("retry-failed");
    let refused_once = Arc::new(AtomicBool::new(false));
    let server = Server::start(Arc::new(move |a: &Asked, _| {
        if a.stage == "windows" && !refused_once.swap(true, Ordering::SeqCst) {
            Reply::status(400, r#"{"error": {"message": "refused"}}"#)
        } else {
            clean_answer(a)
        }
    }));
    let manifest = generate_manifest(&dir, &server.base_url, &[5]);
    let out = dir.join("out");
    let run = batch_llm(&["--retry-failed"], &manifest, &out);
    assert!(run.status.success(), "{}", String::from_utf8_lossy(&run.stderr));
    let record = &summary(&out.join("summary.json"))["jobs"][0];
    assert_eq!(record["status"], "done");
    assert_eq!(record["tries"], 2, "{record}");
}

#[test]
fn model_requests_overlap_up_to_llm_concurrency_whatever_jobs_says() {
    let dir = scratch("llm-concurrency");
    let in_flight = Arc::new(std::sync::atomic::AtomicUsize::new(0));
    let most = Arc::new(std::sync::atomic::AtomicUsize::new(0));
    let (now, peak) = (in_flight.clone(), most.clone());
    let server = Server::start(Arc::new(move |a: &Asked, _| {
        let n = now.fetch_add(1, Ordering::SeqCst) + 1;
        peak.fetch_max(n, Ordering::SeqCst);
        std::thread::sleep(std::time::Duration::from_millis(150));
        now.fetch_sub(1, Ordering::SeqCst);
        clean_answer(a)
    }));
    let manifest = generate_manifest(&dir, &server.base_url, &[1, 2, 3, 4, 5, 6]);
    let run = batch_llm(&["--jobs", "1", "--llm-concurrency", "4"], &manifest, &dir.join("out"));
    assert!(run.status.success(), "{}", String::from_utf8_lossy(&run.stderr));
    let peak = most.load(Ordering::SeqCst);
    assert!((3..=4).contains(&peak), "requests in flight at most: {peak}");
}

#[test]
fn a_job_past_its_time_limit_is_stopped_and_the_worker_goes_on() {
    let dir = scratch("timeout");
    std::fs::copy("examples/bedroom.holo", dir.join("bedroom.holo")).expect("copy");
    std::fs::write(dir.join("slow.holo"), slow_scene()).expect("write");
    let manifest = dir.join("m.jsonl");
    let mut lines =
        vec![r#"{"build": "slow.holo", "node_budget": 10000, "id": "slow"}"#.to_string()];
    lines.extend((1..=5).map(|s| format!(r#"{{"build": "bedroom.holo", "seed": {s}}}"#)));
    std::fs::write(&manifest, lines.join("\n") + "\n").expect("write");
    let out = dir.join("out");
    let started = std::time::Instant::now();
    let run = batch(&["--jobs", "1", "--job-timeout", "1s"], &manifest, &out);
    assert_eq!(run.status.code(), Some(1), "{}", String::from_utf8_lossy(&run.stderr));
    assert!(started.elapsed() < std::time::Duration::from_secs(20));
    let failures = failures_of(&out, "");
    assert_eq!(failures.len(), 1, "{failures:?}");
    assert_eq!(failures[0]["id"], "slow");
    assert_eq!(failures[0]["codes"], serde_json::json!(["E0006"]));
    assert_eq!(failures[0]["stage"], "solve", "{}", failures[0]);
    let message = failures[0]["message"].as_str().unwrap_or_default();
    assert!(!message.contains("left to end"), "the solver stopped at once: {message}");
    assert_eq!(folders(&out).len(), 5, "the jobs behind the slow one ran");
    // What was built does not depend on the time limit.
    let reference = dir.join("reference.jsonl");
    std::fs::write(&reference, lines[1..].join("\n") + "\n").expect("write");
    let whole = batch(&[], &reference, &dir.join("reference"));
    assert!(whole.status.success());
    assert_eq!(folders(&out), folders(&dir.join("reference")));
}

/// Four rooms of 90 objects each tied to the one before: a solve of seconds.
fn slow_scene() -> String {
    use std::fmt::Write as _;
    let mut text = String::new();
    for (i, r) in ["a", "b", "c", "d"].iter().enumerate() {
        let (x0, x1) = (i * 12, i * 12 + 12);
        let _ = writeln!(
            text,
            "room {r} \"room {r}\" {{\n  corners in m ({x0}, 0) ({x0}, 12) ({x1}, 12) ({x1}, 0)"
        );
        for k in 0..90 {
            let near = if k == 0 { "edge".to_string() } else { format!("near t{}-0", k - 1) };
            let _ = writeln!(text, "  object t{k} \"small wooden table\" {{ {near} }}");
        }
        text.push_str("}\n");
    }
    text.push_str("door exterior -- a : doorway single\ndoor a -- b : doorway single\ndoor b -- c : doorway single\ndoor c -- d : doorway single\n");
    text
}

#[test]
fn the_hash_holds_the_model_and_version_shows_the_build() {
    let dir = scratch("identity");
    let manifest = dir.join("m.jsonl");
    std::fs::write(
        &manifest,
        "{\"generate\": \"a bedroom\", \"base_url\": \"http://127.0.0.1:1/v1\"}\n",
    )
    .expect("write");
    let hash = |model: &str| {
        let out = dir.join(format!("out-{model}"));
        let run = holoc()
            .arg("batch")
            .arg(&manifest)
            .arg("-o")
            .arg(&out)
            .arg("-q")
            .env("HOLOC_MODEL", model)
            .output()
            .expect("runs");
        assert_eq!(run.status.code(), Some(1));
        summary(&out.join("summary.json"))["jobs"][0]["hash"].as_str().expect("hash").to_string()
    };
    assert_ne!(hash("model-a"), hash("model-b"), "a changed model is a new job");
    let version = holoc().arg("--version").output().expect("runs");
    let text = String::from_utf8_lossy(&version.stdout);
    assert!(
        text.contains("commit ") && text.contains("data ") && text.contains("source "),
        "{text}"
    );
}

/// The hashes in each shard's summary.
fn shard_hashes(out: &Path, count: usize) -> Vec<std::collections::BTreeSet<String>> {
    (0..count)
        .map(|i| {
            summary(&out.join(format!("summary.shard-{i}-of-{count}.json")))["jobs"]
                .as_array()
                .expect("jobs")
                .iter()
                .map(|j| j["hash"].as_str().expect("hash").to_string())
                .collect()
        })
        .collect()
}

#[test]
fn shards_are_balanced_and_ignore_comments_and_order() {
    let dir = scratch("balance");
    let manifest = builds(&dir, 10);
    let out = dir.join("plain");
    for i in 0..3 {
        let run = batch(&["--shard", &format!("{i}/3")], &manifest, &out);
        assert!(run.status.success(), "{}", String::from_utf8_lossy(&run.stderr));
    }
    let plain = shard_hashes(&out, 3);
    let sizes: Vec<usize> = plain.iter().map(std::collections::BTreeSet::len).collect();
    assert_eq!(sizes.iter().sum::<usize>(), 10, "{sizes:?}");
    // A comment above every job, and the lines in reverse order: the same shards.
    let text = std::fs::read_to_string(&manifest).expect("manifest");
    let mut lines: Vec<String> = text.lines().map(|l| format!("# a comment\n{l}")).collect();
    lines.reverse();
    std::fs::write(&manifest, lines.join("\n") + "\n").expect("write");
    let out2 = dir.join("commented");
    for i in 0..3 {
        let run = batch(&["--shard", &format!("{i}/3")], &manifest, &out2);
        assert!(run.status.success());
    }
    assert_eq!(shard_hashes(&out2, 3), plain);
    let bad = batch(&["--shard", "3/2"], &manifest, &dir.join("bad"));
    assert_eq!(bad.status.code(), Some(2));
}

/// The body of the first `text` block of the batch page that contains `needle`.
fn book_block(needle: &str) -> String {
    let page = std::fs::read_to_string("book/src/cli/batch.md").expect("the batch page");
    page.split("```text\n")
        .skip(1)
        .map(|b| b.split("```").next().unwrap_or_default().to_string())
        .find(|b| b.contains(needle))
        .expect("the block is in the book")
}

#[test]
fn the_books_sbatch_script_survives_a_re_submission_of_some_indices() {
    let dir = scratch("sbatch");
    let manifest = builds(&dir, 6);
    let out = dir.join("houses");
    let script = book_block("#SBATCH --array")
        .replace("holoc batch", &format!("'{}' batch", env!("CARGO_BIN_EXE_holoc")))
        .replace("manifest.jsonl", &manifest.display().to_string())
        .replace("/shared/houses", &out.display().to_string());
    let file = dir.join("holoc.sbatch");
    std::fs::write(&file, &script).expect("write");
    let size: usize = script
        .lines()
        .find_map(|l| l.strip_prefix("#SBATCH --array=0-"))
        .and_then(|n| n.trim().parse::<usize>().ok())
        .expect("the array's range")
        + 1;
    // As Slurm sets it for `sbatch --array=1,3 holoc.sbatch`, then for the rest of the array.
    let task = |index: usize, count: usize, min: usize, max: usize| {
        let run = Command::new("bash")
            .arg(&file)
            .env("SLURM_ARRAY_TASK_ID", index.to_string())
            .env("SLURM_ARRAY_TASK_COUNT", count.to_string())
            .env("SLURM_ARRAY_TASK_MIN", min.to_string())
            .env("SLURM_ARRAY_TASK_MAX", max.to_string())
            .env("SLURM_CPUS_PER_TASK", "1")
            .output();
        let Ok(run) = run else { return false };
        assert!(run.status.success(), "task {index}: {}", String::from_utf8_lossy(&run.stderr));
        true
    };
    if !task(1, 2, 1, 3) {
        common::skip(
            "the_books_sbatch_script_survives_a_re_submission_of_some_indices",
            "bash is absent",
        );
        return;
    }
    task(3, 2, 1, 3);
    for i in (0..size).filter(|i| *i != 1 && *i != 3) {
        task(i, size - 2, 0, size - 1);
    }
    let merged = holoc()
        .args(["batch", "merge", "-q", "-o"])
        .arg(dir.join("merged.json"))
        .arg(&out)
        .output()
        .expect("runs");
    assert!(merged.status.success(), "{}", String::from_utf8_lossy(&merged.stderr));
    assert_eq!(summary(&dir.join("merged.json"))["done"], 6);
}

#[test]
fn the_books_kubernetes_job_exits_0_when_the_batch_ran_with_failed_lines() {
    let yaml = book_block("kind: Job");
    assert!(yaml.contains("restartPolicy: Never") && yaml.contains("podFailurePolicy"), "{yaml}");
    let dir = scratch("k8s");
    let manifest = builds(&dir, 2);
    let mut text = std::fs::read_to_string(&manifest).expect("manifest");
    text.push_str("not a job\n[1, 2]\n");
    std::fs::write(&manifest, text).expect("write");
    let out = dir.join("houses");
    let line = yaml
        .lines()
        .find(|l| l.contains("holoc batch"))
        .expect("the command")
        .trim()
        .trim_start_matches("- ")
        .replace("holoc batch", &format!("'{}' batch", env!("CARGO_BIN_EXE_holoc")))
        .replace("/data/manifest.jsonl", &manifest.display().to_string())
        .replace("/data/houses", &out.display().to_string());
    let count: usize = line
        .split("--shard \"$JOB_COMPLETION_INDEX/")
        .nth(1)
        .and_then(|r| r.split('"').next())
        .and_then(|n| n.parse().ok())
        .expect("the shard count");
    let mut failed = 0;
    for index in 0..count {
        let run = Command::new("sh")
            .args(["-c", &line])
            .env("JOB_COMPLETION_INDEX", index.to_string())
            .output()
            .expect("sh runs");
        assert_eq!(run.status.code(), Some(0), "{}", String::from_utf8_lossy(&run.stderr));
        failed += failures_of(&out, &format!(".shard-{index}-of-{count}")).len();
    }
    assert_eq!(failed, 2, "the two bad lines are recorded");
}

#[test]
fn two_runs_on_one_folder_share_the_work() {
    let dir = scratch("two-runs");
    let manifest = builds_of(&dir, "classroom", 16);
    let reference = batch(&[], &manifest, &dir.join("reference"));
    assert!(reference.status.success());
    let out = dir.join("out");
    let start = || {
        holoc()
            .arg("batch")
            .arg(&manifest)
            .arg("-o")
            .arg(&out)
            .args(["-q", "--jobs", "1"])
            .spawn()
            .expect("starts")
    };
    let (a, b) = (start(), start());
    let (a, b) = (a.wait_with_output().expect("a"), b.wait_with_output().expect("b"));
    assert!(a.status.success() && b.status.success(), "{a:?} {b:?}");
    assert_eq!(folders(&out), folders(&dir.join("reference")));
    let s = summary(&out.join("summary.json"));
    assert_eq!(s["failed"], 0, "{s}");
    // One summary of both runs: the jobs the other run did are not left `busy`.
    assert_eq!(s["busy"], 0, "{s}");
    assert_eq!(s["done"].as_u64().unwrap_or(0) + s["skipped"].as_u64().unwrap_or(0), 16, "{s}");
    assert!(!out.join(".tmp").exists(), "the scratch is gone");
}

#[test]
fn failure_records_have_their_code_line_and_id() {
    let dir = scratch("records");
    std::fs::copy("examples/bedroom.holo", dir.join("bedroom.holo")).expect("copy");
    std::fs::write(dir.join("latin1.holo"), b"room a \"caf\xe9\" {}\n").expect("write");
    let manifest = dir.join("m.jsonl");
    std::fs::write(
        &manifest,
        "\u{feff}{\"build\": \"bedroom.holo\"}\n[\"build\", \"bedroom.holo\"]\n{\"id\": \"typo\", \"biuld\": \"bedroom.holo\"}\n{\"build\": \"latin1.holo\", \"id\": \"latin\"}\n",
    )
    .expect("write");
    let out = dir.join("out");
    let run = batch(&[], &manifest, &out);
    assert_eq!(run.status.code(), Some(1));
    let failures = failures_of(&out, "");
    assert_eq!(failures.len(), 3, "{failures:?}");
    assert_eq!(failures[0]["line"], 2);
    assert_eq!(failures[0]["codes"], serde_json::json!(["E0005"]));
    assert_eq!(failures[1]["id"], "typo");
    assert_eq!(failures[1]["codes"], serde_json::json!(["E0005"]));
    assert_eq!(failures[2]["id"], "latin");
    assert_eq!(failures[2]["codes"], serde_json::json!(["E0003"]));
    assert_eq!(failures[2]["stage"], "input");
    assert_eq!(summary(&out.join("summary.json"))["done"], 1, "the BOM line is a job");
}

#[test]
fn a_full_disk_fails_jobs_cleanly_and_the_records_are_written() {
    let dir = scratch("disk-full");
    let manifest = builds(&dir, 4);
    let out = dir.join("out");
    // Each job writes four files and its marker: the second job's writes fail part way.
    let run = holoc()
        .arg("batch")
        .arg(&manifest)
        .arg("-o")
        .arg(&out)
        .args(["-q", "--jobs", "1"])
        .env("HOLOC_BATCH_DISK_FULL_AFTER", "6")
        .output()
        .expect("runs");
    // A full disk may pass: exit 75, for a scheduler to requeue.
    assert_eq!(run.status.code(), Some(75), "{}", String::from_utf8_lossy(&run.stderr));
    assert!(!out.join(".records.reserve").exists(), "the reserve is given back");
    let failures = failures_of(&out, "");
    assert_eq!(failures.len(), 3, "{failures:?}");
    for f in &failures {
        assert_eq!(f["stage"], "write");
        assert_eq!(f["codes"], serde_json::json!(["E0007"]), "{f}");
    }
    let jobs = folders(&out);
    assert_eq!(jobs.len(), 1);
    assert!(jobs.values().all(|files| files.contains_key("done")), "no half-written job");
    assert!(!out.join(".tmp").exists(), "no scratch is left");
    // Space again: the same command finishes the work.
    let again = batch(&[], &manifest, &out);
    assert!(again.status.success());
    assert_eq!(folders(&out).len(), 4);
}

#[test]
fn progress_lines_go_to_a_log() {
    let dir = scratch("progress");
    let manifest = builds_of(&dir, "classroom", 12);
    let run = holoc()
        .arg("batch")
        .arg(&manifest)
        .arg("-o")
        .arg(dir.join("out"))
        .args(["--jobs", "1", "--progress-every", "0.05"])
        .output()
        .expect("runs");
    assert!(run.status.success());
    let stderr = String::from_utf8_lossy(&run.stderr);
    let lines: Vec<&str> = stderr.lines().filter(|l| l.starts_with("holoc batch: ")).collect();
    assert!(lines.len() >= 2, "{stderr}");
    assert!(lines.iter().all(|l| l.contains("jobs/s") && l.contains("eta")), "{stderr}");
    assert!(lines.last().is_some_and(|l| l.contains("12/12 jobs")), "{stderr}");
}

#[test]
fn merge_refuses_when_a_shard_is_missing() {
    let dir = scratch("merge-missing");
    let manifest = builds(&dir, 4);
    let out = dir.join("out");
    for i in [0, 2] {
        assert!(batch(&["--shard", &format!("{i}/3")], &manifest, &out).status.success());
    }
    let merged = holoc()
        .args(["batch", "merge", "-q", "-o"])
        .arg(dir.join("m.json"))
        .arg(&out)
        .output()
        .expect("runs");
    assert_eq!(merged.status.code(), Some(2));
    let stderr = String::from_utf8_lossy(&merged.stderr);
    assert!(stderr.contains("E0008") && stderr.contains("1/3"), "{stderr}");
    assert!(!dir.join("m.json").exists());
}

#[test]
fn duplicate_lines_are_one_job_and_outputs_depend_on_the_job_alone() {
    let dir = scratch("duplicates");
    std::fs::copy("examples/bedroom.holo", dir.join("bedroom.holo")).expect("copy");
    std::fs::copy("tests/catalog/procthor_small.json", dir.join("cat.json")).expect("copy");
    let line = r#"{"build": "bedroom.holo", "seed": 4, "catalog": ["cat.json"]}"#;
    let manifest = dir.join("m.jsonl");
    std::fs::write(&manifest, format!("{line}\n").repeat(24)).expect("write");
    let out = dir.join("out");
    for _ in 0..3 {
        let run = batch(&["--jobs", "8", "--force"], &manifest, &out);
        assert!(run.status.success(), "{}", String::from_utf8_lossy(&run.stderr));
        let s = summary(&out.join("summary.json"));
        assert_eq!((s["done"].as_u64(), s["skipped"].as_u64()), (Some(1), Some(23)), "{s}");
    }
    // From another working folder, through another spelling of the manifest's path.
    let other = dir.join("other");
    let run = holoc()
        .current_dir(&dir)
        .args(["batch", "./m.jsonl", "-q", "-o"])
        .arg(&other)
        .output()
        .expect("runs");
    assert!(run.status.success());
    assert_eq!(folders(&out), folders(&other));
    let report =
        String::from_utf8_lossy(&folders(&out).values().next().expect("a job")["report.json"])
            .to_string();
    assert!(report.contains("\"path\": \"cat.json\""), "the catalog as the manifest names it");
}

#[test]
fn scratch_left_by_a_killed_run_is_removed() {
    let dir = scratch("stale");
    let manifest = builds(&dir, 1);
    let out = dir.join("out");
    std::fs::create_dir_all(out.join(".tmp/run-1-000000001/abc-3")).expect("mkdir");
    std::fs::write(out.join(".tmp/run-1-000000001.lock"), "").expect("write");
    std::fs::create_dir_all(out.join(".tmp/0123456789abcdef-99")).expect("mkdir");
    let run = batch(&[], &manifest, &out);
    assert!(run.status.success());
    assert!(
        !out.join(".tmp").exists(),
        "{:?}",
        std::fs::read_dir(out.join(".tmp")).map(Iterator::count)
    );
}

#[test]
fn a_failed_import_writes_no_scene() {
    let dir = scratch("import");
    let bad = dir.join("bad.json");
    std::fs::write(&bad, "{not json").expect("write");
    let scene = dir.join("scene.holo");
    let run = holoc().arg("import").arg(&bad).arg("-o").arg(&scene).output().expect("runs");
    assert_eq!(run.status.code(), Some(1));
    assert!(!scene.exists());
    let empty = dir.join("empty.json");
    std::fs::write(&empty, r#"{"format": "holoc-transcript", "request": "x", "seed": 1, "exchanges": [{"stage": "floor-plan", "attempt": 0, "prompt": "p", "answer": "I cannot help."}]}"#).expect("write");
    let run = holoc().arg("import").arg(&empty).arg("-o").arg(&scene).output().expect("runs");
    assert_eq!(run.status.code(), Some(1), "{}", String::from_utf8_lossy(&run.stderr));
    assert!(!scene.exists(), "an import with errors makes no file");
}

/// A manifest from someone else can make holoc read only files below its folder, and cannot
/// send the API key to a server of its choosing.
#[test]
fn a_manifest_reads_only_its_folder_and_chooses_no_server() {
    let dir = scratch("confined");
    let outside = dir.join("outside.holo");
    std::fs::copy("examples/bedroom.holo", &outside).expect("copy");
    let inner = dir.join("inner");
    std::fs::create_dir_all(&inner).expect("mkdir");
    std::fs::copy("examples/bedroom.holo", inner.join("bedroom.holo")).expect("copy");
    let manifest = inner.join("m.jsonl");
    std::fs::write(
        &manifest,
        "{\"build\": \"bedroom.holo\"}\n{\"build\": \"../outside.holo\"}\n\
         {\"generate\": \"a bedroom\", \"base_url\": \"http://127.0.0.1:1/v1\"}\n",
    )
    .expect("write");
    let out = dir.join("out");
    let run = holoc()
        .arg("batch")
        .arg(&manifest)
        .args(["-o"])
        .arg(&out)
        .arg("-q")
        .env("HOLOC_API_KEY", "sk-secret")
        .output()
        .expect("runs");
    assert_eq!(run.status.code(), Some(1), "{}", String::from_utf8_lossy(&run.stderr));
    let failures = std::fs::read_to_string(out.join("failures.jsonl")).expect("failures");
    assert!(failures.contains("outside the manifest's folder"), "{failures}");
    assert!(failures.contains("may not choose its model server"), "{failures}");
    assert!(!failures.contains("sk-secret"));
    let jobs = summary(&out.join("summary.json"))["jobs"].as_array().expect("jobs").clone();
    let ok = jobs.iter().filter(|j| j["status"] == "done").count();
    assert_eq!(ok, 1, "only the job inside the folder builds: {jobs:?}");
    // With `--allow-outside` the outside file is read.
    let out2 = dir.join("out2");
    let run = holoc()
        .arg("batch")
        .arg(&manifest)
        .args(["-o"])
        .arg(&out2)
        .args(["-q", "--allow-outside"])
        .output()
        .expect("runs");
    assert_eq!(run.status.code(), Some(1));
    let jobs = summary(&out2.join("summary.json"))["jobs"].as_array().expect("jobs").clone();
    assert_eq!(jobs.iter().filter(|j| j["status"] == "done").count(), 2, "{jobs:?}");
}

/// A run leaves the hashes of the files it read for the next one, which reads a file again only
/// when its size or time stamp changed; a damaged memo is ignored.
#[test]
fn file_hashes_are_kept_for_the_next_run() {
    let dir = scratch("memo");
    std::fs::copy("examples/bedroom.holo", dir.join("bedroom.holo")).expect("copy");
    let manifest = dir.join("m.jsonl");
    std::fs::write(&manifest, "{\"build\": \"bedroom.holo\"}\n").expect("write");
    let out = dir.join("out");
    assert_eq!(batch(&[], &manifest, &out).status.code(), Some(0));
    let memo = std::fs::read_to_string(out.join(".cache/file-hashes.tsv")).expect("memo");
    let bytes = std::fs::read(dir.join("bedroom.holo")).expect("read");
    let sha = {
        use sha2::Digest as _;
        use std::fmt::Write as _;
        sha2::Sha256::digest(&bytes).iter().fold(String::new(), |mut s, b| {
            let _ = write!(s, "{b:02x}");
            s
        })
    };
    assert!(memo.lines().any(|l| l.starts_with(&sha) && l.ends_with("bedroom.holo")), "{memo}");
    // The second run skips the finished job, with the memo or with a damaged one.
    let second = batch(&[], &manifest, &out);
    assert_eq!(second.status.code(), Some(0));
    assert_eq!(summary(&out.join("summary.json"))["skipped"], 1);
    std::fs::write(out.join(".cache/file-hashes.tsv"), "garbage\tline\n\u{0}\n").expect("damage");
    assert_eq!(batch(&[], &manifest, &out).status.code(), Some(0));
    assert_eq!(summary(&out.join("summary.json"))["skipped"], 1);
    // A changed file is a new job.
    std::fs::write(dir.join("bedroom.holo"), [bytes.as_slice(), b"\n// changed\n"].concat())
        .expect("change");
    assert_eq!(batch(&[], &manifest, &out).status.code(), Some(0));
    assert_eq!(summary(&out.join("summary.json"))["done"], 1);
}

/// The shard of every job line, from the shards' summaries (line → shard index).
fn shard_of_lines(out: &Path, count: usize) -> BTreeMap<u64, usize> {
    let mut lines = BTreeMap::new();
    for i in 0..count {
        let s = summary(&out.join(format!("summary.shard-{i}-of-{count}.json")));
        for job in s["jobs"].as_array().expect("jobs") {
            lines.insert(job["line"].as_u64().expect("line"), i);
        }
    }
    lines
}

fn run_shards(manifest: &Path, out: &Path, count: usize) {
    for i in 0..count {
        let run = batch(&["--shard", &format!("{i}/{count}")], manifest, out);
        assert!(
            matches!(run.status.code(), Some(0 | 1)),
            "{}",
            String::from_utf8_lossy(&run.stderr)
        );
    }
}

/// A job's shard is a function of its own identity: editing one line (a new seed) moves at
/// most that line, and adding a line above every other one moves none of them.
#[test]
fn a_one_line_edit_moves_only_that_line() {
    let dir = scratch("stable-shards");
    let manifest = builds(&dir, 24);
    let count = 6;
    run_shards(&manifest, &dir.join("before"), count);
    let before = shard_of_lines(&dir.join("before"), count);
    assert_eq!(before.len(), 24, "every line is in one shard");
    let text = std::fs::read_to_string(&manifest).expect("manifest");
    let edited = text.replace(r#""seed": 5}"#, r#""seed": 500}"#);
    assert_ne!(edited, text);
    // A line added at the top too: every other line's number grows by one.
    std::fs::write(&manifest, format!("{{\"build\": \"bedroom.holo\", \"seed\": 77}}\n{edited}"))
        .expect("write");
    run_shards(&manifest, &dir.join("after"), count);
    let after = shard_of_lines(&dir.join("after"), count);
    let moved: Vec<u64> = before
        .iter()
        .filter(|(line, shard)| **line != 5 && after.get(&(**line + 1)) != Some(*shard))
        .map(|(line, _)| *line)
        .collect();
    assert!(moved.is_empty(), "lines moved by an edit elsewhere: {moved:?}");
}

/// Shards balance by CPU: the consecutive seeds of each scene are dealt out one per shard, so a
/// scene that costs many times another (the dining room ten times the bathroom, release build)
/// is split as evenly as the cheap one; and an edit of one line still moves only that line.
#[test]
fn shards_balance_by_cpu_dealing_each_scenes_seeds() {
    let dir = scratch("balance-cpu");
    for example in ["bathroom_towels", "dining_room"] {
        let file = format!("{example}.holo");
        std::fs::copy(Path::new("examples").join(&file), dir.join(&file)).expect("copy");
    }
    // Seeds 3 to 8 over 3 shards: two whole rounds of each scene.
    let mut lines = Vec::new();
    for seed in 3..=8 {
        for example in ["bathroom_towels", "dining_room"] {
            lines.push(format!(r#"{{"build": "{example}.holo", "seed": {seed}}}"#));
        }
    }
    let manifest = dir.join("manifest.jsonl");
    std::fs::write(&manifest, lines.join("\n") + "\n").expect("write");
    let count = 3;
    run_shards(&manifest, &dir.join("out"), count);
    let shards = shard_of_lines(&dir.join("out"), count);
    assert_eq!(shards.len(), 12, "every line in one shard");
    // Per shard, the jobs of each scene (odd lines: the bathroom, even lines: the dining room).
    let mut per = vec![[0usize; 2]; count];
    for (line, shard) in &shards {
        per[*shard][usize::from(line % 2 == 0)] += 1;
    }
    assert!(per.iter().all(|p| *p == [2, 2]), "{per:?}");
    // So by CPU (the dining room about ten times the bathroom, release build, 30 seeds each)
    // every shard holds the same work: 2 x 10 + 2 x 1 against a mean of 22.
    // One line's seed edited: only it moves.
    let text = std::fs::read_to_string(&manifest).expect("manifest");
    let edited = text.replacen(r#""seed": 5}"#, r#""seed": 50}"#, 1);
    std::fs::write(&manifest, &edited).expect("write");
    let edited_line = text.lines().position(|l| l.contains(r#""seed": 5}"#)).expect("a line") + 1;
    run_shards(&manifest, &dir.join("after"), count);
    let after = shard_of_lines(&dir.join("after"), count);
    for (line, shard) in &shards {
        if *line != edited_line as u64 {
            assert_eq!(after.get(line), Some(shard), "line {line} moved");
        }
    }
}

/// The issue's case: a line fails, is fixed, the failed index is re-run; if the fixed job now
/// belongs to another shard, merge refuses and names the line and that shard, and merges once
/// it has run. `--partial` accepts a partial run.
#[test]
fn merge_refuses_a_line_that_is_not_done_and_names_its_shard() {
    let dir = scratch("merge-lines");
    std::fs::copy("examples/bedroom.holo", dir.join("bedroom.holo")).expect("copy");
    std::fs::write(
        dir.join("fixme.holo"),
        "room a \"a\" {\n  object c \"chair\" { near sofa-0 }\n}\n",
    )
    .expect("write");
    let manifest = dir.join("m.jsonl");
    let mut lines: Vec<String> =
        (1..=8).map(|s| format!(r#"{{"build": "bedroom.holo", "seed": {s}}}"#)).collect();
    lines.insert(2, r#"{"build": "fixme.holo", "id": "fixme"}"#.to_string());
    std::fs::write(&manifest, lines.join("\n") + "\n").expect("write");
    let out = dir.join("out");
    let count = 4;
    run_shards(&manifest, &out, count);
    let merge = |extra: &[&str]| {
        holoc()
            .args(["batch", "merge", "-q", "-o"])
            .arg(dir.join("merged.json"))
            .args(extra)
            .arg(&out)
            .output()
            .expect("runs")
    };
    let refused = merge(&[]);
    assert_eq!(refused.status.code(), Some(1));
    let stderr = String::from_utf8_lossy(&refused.stderr);
    assert!(stderr.contains("E0811") && stderr.contains("line 3 (fixme)"), "{stderr}");
    assert!(!dir.join("merged.json").exists(), "nothing is written");
    let failed_shard = shard_of_lines(&out, count)[&3];
    // The fix: the scene is mended; only the failed index is re-run.
    std::fs::copy("examples/bedroom.holo", dir.join("fixme.holo")).expect("fix");
    let run = batch(&["--shard", &format!("{failed_shard}/{count}")], &manifest, &out);
    assert!(matches!(run.status.code(), Some(0 | 1)));
    let merged = merge(&[]);
    if merged.status.code() != Some(0) {
        // The fixed job moved: merge names it and the shard to re-run, and nothing else.
        let stderr = String::from_utf8_lossy(&merged.stderr);
        assert_eq!(merged.status.code(), Some(1), "{stderr}");
        assert!(stderr.contains("1 line of the manifest is not done"), "{stderr}");
        let shard = stderr
            .split("(shard ")
            .nth(1)
            .and_then(|r| r.split(" runs it now").next())
            .expect("the shard is named")
            .to_string();
        assert!(stderr.contains("line 3 (fixme): in no summary"), "{stderr}");
        // `--partial` accepts it, listing the line.
        let partial = merge(&["--partial"]);
        assert_eq!(partial.status.code(), Some(0));
        let m = summary(&dir.join("merged.json"));
        assert_eq!(m["incomplete"][0]["line"], 3, "{m}");
        std::fs::remove_file(dir.join("merged.json")).expect("remove");
        let run = batch(&["--shard", &shard], &manifest, &out);
        assert!(run.status.success(), "{}", String::from_utf8_lossy(&run.stderr));
        let merged = merge(&[]);
        assert_eq!(merged.status.code(), Some(0), "{}", String::from_utf8_lossy(&merged.stderr));
    }
    let m = summary(&dir.join("merged.json"));
    assert_eq!(m["failed"], 0, "{m}");
    assert_eq!(m["jobs"].as_array().map(Vec::len), Some(9));
    assert!(m["jobs"].as_array().expect("jobs").iter().all(|j| j["status"] != "failed"));
}

/// A manifest of one generate job for `--base-url` (the job names no server).
fn generate_for_run(dir: &Path, seeds: &[u64]) -> PathBuf {
    let manifest = dir.join("m.jsonl");
    let lines: Vec<String> = seeds
        .iter()
        .map(|seed| format!(
            "{{\"generate\": \"a 1b1b apartment of a researcher who has a cat\", \"seed\": {seed}, \"model\": \"test-model\"}}"
        ))
        .collect();
    std::fs::write(&manifest, lines.join("\n") + "\n").expect("write");
    manifest
}

#[test]
fn an_outage_of_the_model_is_waited_out_with_retry_after_honoured() {
    let dir = scratch("outage");
    let times: Arc<std::sync::Mutex<Vec<std::time::Instant>>> = Arc::default();
    let log = times.clone();
    // Down for the first five requests: 503, 502, 429 with Retry-After: 1, 500, 504.
    let server = Server::start(Arc::new(move |a: &Asked, n| {
        log.lock().expect("log").push(std::time::Instant::now());
        match n {
            0 => Reply::status(503, "{}"),
            1 => Reply::status(502, "{}"),
            2 => Reply { retry_after: Some("1"), ..Reply::status(429, "{}") },
            3 => Reply::status(500, "{}"),
            4 => Reply::status(504, "{}"),
            _ => clean_answer(a),
        }
    }));
    let manifest = generate_for_run(&dir, &[2]);
    let out = dir.join("out");
    let run = batch(
        &["--base-url", &server.base_url, "--model-backoff", "20ms", "--model-patience", "30s"],
        &manifest,
        &out,
    );
    assert!(run.status.success(), "{}", String::from_utf8_lossy(&run.stderr));
    let record = &summary(&out.join("summary.json"))["jobs"][0];
    assert_eq!(record["model_retries"], 5, "{record}");
    let t = times.lock().expect("log").clone();
    assert!(t[3] - t[2] >= std::time::Duration::from_millis(990), "Retry-After is honoured");
}

#[test]
fn an_unreachable_server_fails_as_transient_with_exit_75_after_the_patience() {
    let dir = scratch("unreachable");
    // A port nobody listens on.
    let port = std::net::TcpListener::bind("127.0.0.1:0")
        .and_then(|l| l.local_addr())
        .map(|a| a.port())
        .expect("a free port");
    let manifest = generate_for_run(&dir, &[1]);
    let mut text = std::fs::read_to_string(&manifest).expect("manifest");
    text.push_str("not a job\n");
    std::fs::write(&manifest, text).expect("write");
    let out = dir.join("out");
    let started = std::time::Instant::now();
    let run = batch(
        &[
            "--base-url",
            &format!("http://127.0.0.1:{port}/v1"),
            "--model-backoff",
            "20ms",
            "--model-patience",
            "300ms",
            "--allow-failures",
        ],
        &manifest,
        &out,
    );
    assert_eq!(run.status.code(), Some(75), "{}", String::from_utf8_lossy(&run.stderr));
    assert!(started.elapsed() >= std::time::Duration::from_millis(300), "it waited");
    let failures = failures_of(&out, "");
    assert_eq!(failures[0]["codes"], serde_json::json!(["E0805"]), "{failures:?}");
    assert!(failures[0]["model_retries"].as_u64().unwrap_or(0) >= 2, "{failures:?}");
    // Bad input alone is exit 1 (0 with --allow-failures), not 75.
    std::fs::write(&manifest, "not a job\n").expect("write");
    assert_eq!(batch(&[], &manifest, &dir.join("bad")).status.code(), Some(1));
    assert_eq!(batch(&["--allow-failures"], &manifest, &dir.join("bad2")).status.code(), Some(0));
}

/// A generate job killed while it waits for an answer keeps every answer it had: the run after
/// it asks only the questions that had no answer.
#[test]
fn a_killed_generate_job_resumes_without_asking_again() {
    let dir = scratch("killed-generate");
    let answered: Arc<std::sync::Mutex<Vec<String>>> = Arc::default();
    let asked_windows = Arc::new(AtomicBool::new(false));
    let (log, windows) = (answered.clone(), asked_windows.clone());
    let server = Server::start(Arc::new(move |a: &Asked, _| {
        if a.stage == "windows" && !windows.swap(true, Ordering::SeqCst) {
            // The first windows question hangs: the job is killed meanwhile.
            return Reply { delay_ms: 3000, ..Reply::status(503, "{}") };
        }
        log.lock().expect("log").push(format!("{}/{:?}/{}", a.stage, a.room, a.repair));
        clean_answer(a)
    }));
    let manifest = generate_for_run(&dir, &[4]);
    let out = dir.join("out");
    let mut child = holoc()
        .arg("batch")
        .arg(&manifest)
        .arg("-o")
        .arg(&out)
        .args(["-q", "--base-url", &server.base_url])
        .spawn()
        .expect("starts");
    let started = std::time::Instant::now();
    while !asked_windows.load(Ordering::SeqCst)
        && started.elapsed() < std::time::Duration::from_secs(60)
    {
        std::thread::sleep(std::time::Duration::from_millis(5));
    }
    let _ = child.kill();
    let _ = child.wait();
    let before = answered.lock().expect("log").len();
    assert!(before >= 3, "floor plan, wall height, doorways were answered");
    let again = batch(&["--base-url", &server.base_url], &manifest, &out);
    assert!(again.status.success(), "{}", String::from_utf8_lossy(&again.stderr));
    let all = answered.lock().expect("log").clone();
    let mut distinct = all.clone();
    distinct.sort();
    distinct.dedup();
    assert_eq!(distinct.len(), all.len(), "no answered question is asked twice: {all:?}");
    assert!(all.len() > before);
}

/// The run's server and every generation parameter are the job's identity and in its
/// `job.json`; a build ignores the generation-only fields (W0802); an empty scene fails (E0812).
#[test]
fn identity_holds_the_server_and_ignores_generation_fields_of_builds() {
    let dir = scratch("identity-server");
    let server = Server::start(Arc::new(|a: &Asked, _| clean_answer(a)));
    let manifest = generate_for_run(&dir, &[6]);
    let out = dir.join("out");
    let run = batch(&["--base-url", &server.base_url], &manifest, &out);
    assert!(run.status.success(), "{}", String::from_utf8_lossy(&run.stderr));
    let jobs = folders(&out);
    let job: serde_json::Value =
        serde_json::from_slice(&jobs.values().next().expect("a job")["job.json"]).expect("json");
    assert_eq!(job["model"]["base_url"], server.base_url.as_str(), "{job}");
    assert_eq!(job["model"]["model"], "test-model");
    assert_eq!(job["model"]["parameters"]["temperature"], 0.0);
    // Another server: another job, made there (not skipped).
    let other = Server::start(Arc::new(|a: &Asked, _| clean_answer(a)));
    let run = batch(&["--base-url", &other.base_url], &manifest, &out);
    assert!(run.status.success());
    assert_eq!(summary(&out.join("summary.json"))["done"], 1);
    assert!(other.calls() > 0);
    // Builds: the same job with or without generation fields, with a warning.
    std::fs::copy("examples/bedroom.holo", dir.join("bedroom.holo")).expect("copy");
    std::fs::write(dir.join("empty.holo"), "// nothing here\n").expect("write");
    let builds = dir.join("b.jsonl");
    std::fs::write(
        &builds,
        "{\"build\": \"bedroom.holo\", \"seed\": 2}\n{\"build\": \"bedroom.holo\", \"seed\": 2, \"temperature\": 0.9, \"model\": \"m\"}\n{\"build\": \"empty.holo\"}\n",
    )
    .expect("write");
    let out = dir.join("builds");
    let run = batch(&[], &builds, &out);
    assert_eq!(run.status.code(), Some(1), "{}", String::from_utf8_lossy(&run.stderr));
    let s = summary(&out.join("summary.json"));
    assert_eq!(s["jobs"][0]["hash"], s["jobs"][1]["hash"], "{s}");
    assert_eq!(s["done"], 1);
    assert!(s["jobs"][1]["codes"].as_array().expect("codes").contains(&"W0802".into()), "{s}");
    assert_eq!(s["jobs"][2]["codes"], serde_json::json!(["E0812"]), "{s}");
    assert_eq!(s["jobs"][2]["stage"], "input");
    assert_eq!(folders(&out).len(), 1);
}

#[test]
fn a_resumed_run_keeps_the_warnings() {
    let dir = scratch("warnings");
    let manifest = builds_of(&dir, "classroom", 2);
    let out = dir.join("out");
    assert!(batch(&[], &manifest, &out).status.success());
    let first = summary(&out.join("summary.json"));
    assert!(batch(&[], &manifest, &out).status.success());
    let second = summary(&out.join("summary.json"));
    assert_eq!(second["skipped"], 2);
    for k in 0..2 {
        assert_eq!(first["jobs"][k]["codes"], second["jobs"][k]["codes"], "{first} {second}");
    }
}

/// When the disk fills up during a run, the records are written from the room reserved when
/// it started; without that room, the unfinished jobs are named on stderr with exit 74.
#[test]
fn a_full_disk_without_room_for_the_records_names_the_unfinished_jobs() {
    let dir = scratch("disk-full-records");
    let manifest = builds(&dir, 4);
    let out = dir.join("out");
    let run = holoc()
        .arg("batch")
        .arg(&manifest)
        .arg("-o")
        .arg(&out)
        .args(["-q", "--jobs", "1"])
        .env("HOLOC_BATCH_DISK_FULL_AFTER", "6")
        .env("HOLOC_BATCH_RESERVE", "0")
        .output()
        .expect("runs");
    assert_eq!(run.status.code(), Some(74), "{}", String::from_utf8_lossy(&run.stderr));
    let stderr = String::from_utf8_lossy(&run.stderr);
    for line in ["line 2 (line-2)", "line 3 (line-3)", "line 4 (line-4)"] {
        assert!(stderr.contains(line), "{stderr}");
    }
    assert!(stderr.contains("3 unfinished jobs"), "{stderr}");
}

/// The book's Kubernetes Job passes strict schema validation for every version the book names,
/// with `kubernetes-validate` (pip) when it is installed.
#[test]
fn the_books_kubernetes_job_passes_strict_schema_validation() {
    let yaml = book_block("kind: Job");
    assert!(yaml.contains("status: \"True\""), "{yaml}");
    let dir = scratch("k8s-schema");
    let file = dir.join("holoc-job.yaml");
    std::fs::write(&file, &yaml).expect("write");
    for minor in 29..=34 {
        let run = Command::new("kubernetes-validate")
            .args(["--strict", "-k", &format!("1.{minor}.0")])
            .arg(&file)
            .output();
        let Ok(run) = run else {
            common::skip(
                "the_books_kubernetes_job_passes_strict_schema_validation",
                "kubernetes-validate is absent (pip install kubernetes-validate)",
            );
            return;
        };
        assert!(
            run.status.success(),
            "1.{minor}: {}{}",
            String::from_utf8_lossy(&run.stdout),
            String::from_utf8_lossy(&run.stderr)
        );
    }
    // The exit codes the policy names are those holoc uses.
    for code in ["values: [2]", "values: [75]", "values: [74]"] {
        assert!(yaml.contains(code), "{code}");
    }
}

/// Every file and folder under `dir` (links not followed), with the bytes of the files.
fn listing(dir: &Path) -> BTreeMap<PathBuf, Option<Vec<u8>>> {
    let mut all = BTreeMap::new();
    let mut stack = vec![dir.to_path_buf()];
    while let Some(d) = stack.pop() {
        for entry in std::fs::read_dir(&d).into_iter().flatten().filter_map(Result::ok) {
            let path = entry.path();
            let kind = entry.file_type().expect("type");
            if kind.is_dir() {
                stack.push(path.clone());
                all.insert(path, None);
            } else if kind.is_symlink() {
                all.insert(
                    path.clone(),
                    Some(
                        std::fs::read_link(&path)
                            .expect("link")
                            .into_os_string()
                            .into_encoded_bytes(),
                    ),
                );
            } else {
                all.insert(path.clone(), Some(std::fs::read(&path).expect("file")));
            }
        }
    }
    all
}

/// A way out of the output folder: its name and what makes it in a fresh folder.
#[cfg(unix)]
type Way<'a> = (&'a str, Box<dyn Fn(&Path) + 'a>);

#[cfg(unix)]
fn link(target: &Path, at: &Path) {
    std::os::unix::fs::symlink(target, at).expect("symlink");
}

/// `holoc batch` writes only inside its output folder: a job's folder, `.partial`, `.locks`,
/// `.tmp`, `.cache`, the records reserve, the summary and the failures file made links to a
/// file or folder outside (or to nothing) are refused (E0009) or left alone, never written
/// through; nothing outside the folder changes, and a dangling link's target is not created.
/// Job names with `..` name no path: job folders are named by hash.
#[cfg(unix)]
#[test]
fn batch_writes_only_inside_its_output_folder() {
    let dir = scratch("confined");
    let manifest = builds(&dir, 1);
    // One job that fails (its tries go to `.partial`), with a name that climbs out.
    let mut text = std::fs::read_to_string(&manifest).expect("read");
    text.push_str("{\"id\": \"../../escape\", \"build\": \"missing.holo\"}\n");
    std::fs::write(&manifest, &text).expect("write");
    // The job's folder name, from a run into a fresh folder.
    let fresh = dir.join("fresh");
    let run = batch(&["--allow-failures"], &manifest, &fresh);
    assert!(run.status.success(), "{}", String::from_utf8_lossy(&run.stderr));
    let hash = folders(&fresh).keys().next().expect("a job folder").clone();
    assert!(!dir.join("escape").exists() && !fresh.join("escape").exists());

    let outside = dir.join("outside");
    std::fs::create_dir_all(&outside).expect("mkdir");
    std::fs::write(outside.join("victim.txt"), "keep me\n").expect("write");
    // A folder that looks like a dead run's scratch: `.tmp` cleaning must not reach it.
    std::fs::create_dir_all(outside.join("run-1-000000001")).expect("mkdir");
    // A finished job's folder elsewhere: a link to it is not this run's finished job.
    std::fs::create_dir_all(outside.join("job")).expect("mkdir");
    for (name, bytes) in &folders(&fresh)[&hash] {
        std::fs::write(outside.join("job").join(name), bytes).expect("write");
    }
    let before = listing(&outside);
    let missing = dir.join("created-through-a-link");

    let ways: Vec<Way> = vec![
        (
            "job folder -> folder outside",
            Box::new(|out: &Path| link(&outside.join("job"), &out.join(&hash))),
        ),
        (
            ".partial -> folder outside",
            Box::new(|out: &Path| link(&outside, &out.join(".partial"))),
        ),
        (".locks -> folder outside", Box::new(|out: &Path| link(&outside, &out.join(".locks")))),
        (".tmp -> folder outside", Box::new(|out: &Path| link(&outside, &out.join(".tmp")))),
        (".cache -> dangling", Box::new(|out: &Path| link(&missing, &out.join(".cache")))),
        (
            "reserve -> file outside",
            Box::new(|out: &Path| link(&outside.join("victim.txt"), &out.join(".records.reserve"))),
        ),
        (
            "reserve -> dangling",
            Box::new(|out: &Path| link(&missing, &out.join(".records.reserve"))),
        ),
        (
            "summary -> file outside",
            Box::new(|out: &Path| link(&outside.join("victim.txt"), &out.join("summary.json"))),
        ),
        ("summary -> dangling", Box::new(|out: &Path| link(&missing, &out.join("summary.json")))),
        (
            "failures -> file outside",
            Box::new(|out: &Path| link(&outside.join("victim.txt"), &out.join("failures.jsonl"))),
        ),
    ];
    for (k, (what, make)) in ways.iter().enumerate() {
        let out = dir.join(format!("out-{k}"));
        std::fs::create_dir_all(&out).expect("mkdir");
        make(&out);
        let run = batch(&["--allow-failures"], &manifest, &out);
        let err = String::from_utf8_lossy(&run.stderr).to_string();
        assert!(run.status.code().is_some(), "{what}: ended by a signal");
        assert_eq!(listing(&outside), before, "{what}: something outside changed\n{err}");
        assert!(!missing.exists(), "{what}: a dangling link's target was made\n{err}");
        assert!(!dir.join("escape").exists(), "{what}");
        // Where the run wrote its records, the refused job says why.
        if let Ok(summary) = std::fs::read_to_string(out.join("summary.json")) {
            if what.starts_with("job folder") || what.starts_with(".locks") {
                assert!(summary.contains("E0009"), "{what}: {summary}");
            }
        } else {
            assert!(err.contains("E0009") || err.contains("E0001"), "{what}: {err}");
        }
    }
}

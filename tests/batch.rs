//! `holoc batch` through the binary: shards are disjoint and cover the manifest, a run killed
//! part way and run again gives the same outputs byte for byte as an uninterrupted run, a
//! failing job is recorded with its codes while the others finish, generate jobs run against
//! the loopback server and reuse what they recorded, and `batch merge` joins the shards.

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
            let line = job["line"].as_u64().expect("line");
            assert_eq!(line % 3, i, "line {line} is not in shard {i}");
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
    assert_eq!(failures[0]["stage"], "build");
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
    let first = batch(&["--llm-concurrency", "2", "--allow-job-base-url"], &manifest, &out);
    assert_eq!(first.status.code(), Some(1), "{}", String::from_utf8_lossy(&first.stderr));
    assert_eq!(summary(&out.join("summary.json"))["jobs"][0]["stage"], "generate");
    let paid = server.calls();
    assert!(paid >= 4, "floor plan, wall height, doorways, windows: {paid}");
    refuse.store(false, Ordering::SeqCst);
    let second = batch(&["--allow-job-base-url"], &manifest, &out);
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
    let full = batch(&["--allow-job-base-url"], &fresh, &dir.join("fresh"));
    assert!(full.status.success());
    assert_eq!(asked_again + 3, clean.calls(), "a re-run never pays twice for an answer");
    let third = batch(&["--allow-job-base-url"], &manifest, &out);
    assert!(third.status.success());
    assert_eq!(server.calls() - paid, asked_again, "a finished job asks nothing");
}

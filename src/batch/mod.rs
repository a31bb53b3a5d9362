//! `holoc batch`: many scenes from a manifest, resumable and sharded.
//!
//! A manifest is JSON Lines, one job per line: a `.holo` file to build (`"build"`) or a request
//! to generate (`"generate"`), with optional overrides. Each job's outputs go under a folder
//! named by a content hash of the job (its settings, the bytes of its input and of its
//! catalogs, the holoc version), written in a temporary folder and renamed into place with its
//! completion marker, so a folder that exists is complete. A run skips the jobs whose folder
//! exists, so a killed run resumes where it stopped and a changed job (a new hash) is redone.
//! `--shard I/N` takes the jobs whose line number is I modulo N: disjoint slices that cover the
//! manifest, the same on every machine.

use crate::compile::{build, BuildOptions};
use crate::diag::{Diagnostic, Outcome};
use crate::generate::{
    self, GenerateOptions, HttpLlm, HttpOptions, Llm, LlmAnswer, LlmError, LlmRequest, ModelInfo,
    Request,
};
use crate::resolve::Catalog;
use crate::solve::Solver;
use crate::source::SourceMap;
use serde::{Deserialize, Serialize};
use std::collections::BTreeMap;
use std::collections::HashMap;
use std::path::{Path, PathBuf};
use std::sync::{Arc, Condvar, Mutex};
use std::time::Instant;

/// The name of the completion marker inside a job's folder.
pub const DONE_MARKER: &str = "done";

/// One line of a manifest, as written.
#[derive(Clone, Debug, Default, Deserialize, Serialize, PartialEq)]
#[serde(deny_unknown_fields)]
pub struct JobSpec {
    /// A name for the job in the summary (default: `line-<n>`); not part of the hash.
    #[serde(default, skip_serializing)]
    pub id: Option<String>,
    /// A `.holo` file to build, relative to the manifest's folder.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub build: Option<String>,
    /// A request to generate (then build).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub generate: Option<String>,
    /// The scene type of a generated scene (recorded in the summary, e.g. `bedroom`).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub scene_type: Option<String>,
    /// The seed (build: instead of the scene's; generate: the request's, default 1).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub seed: Option<u64>,
    /// `dfs` (default) or `milp`.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub solver: Option<String>,
    /// The DFS node budget per room.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub node_budget: Option<u64>,
    /// User catalogs, relative to the manifest's folder.
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub catalog: Vec<String>,
    /// Whether stand-ins fill in (default true).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub stand_ins: Option<bool>,
    /// The model of a generate job (default: `HOLOC_MODEL`, else holoc's default).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub model: Option<String>,
    /// The API of a generate job (default: `HOLOC_BASE_URL`, else holoc's default).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub base_url: Option<String>,
    /// The sampling temperature of a generate job.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub temperature: Option<f64>,
}

/// A job of the manifest, ready to run.
#[derive(Clone, Debug)]
pub struct Job {
    /// The line of the manifest (1-based).
    pub line: usize,
    /// The job's name.
    pub id: String,
    /// What the line asks for.
    pub spec: JobSpec,
    /// The content hash (hex, 16 characters): the job's folder name.
    pub hash: String,
    /// The `.holo` file of a build job.
    pub input: Option<PathBuf>,
    /// The catalogs, as paths.
    pub catalogs: Vec<PathBuf>,
}

/// A manifest line that is not a job.
#[derive(Clone, Debug, Serialize, PartialEq)]
pub struct ManifestError {
    /// The line (1-based).
    pub line: usize,
    /// What is wrong.
    pub message: String,
}

/// How a job ended.
#[derive(Clone, Copy, Debug, Serialize, Deserialize, PartialEq, Eq)]
#[serde(rename_all = "lowercase")]
pub enum Status {
    /// Built now.
    Done,
    /// Its folder was complete already.
    Skipped,
    /// Failed; nothing was written for it.
    Failed,
}

/// One job's line of the summary.
#[derive(Clone, Debug, Serialize, Deserialize, PartialEq)]
pub struct JobResult {
    /// The manifest line.
    pub line: usize,
    /// The job's name.
    pub id: String,
    /// The folder name.
    pub hash: String,
    /// How it ended.
    pub status: Status,
    /// The stage that failed (`manifest`, `input`, `catalog`, `generate`, `build`, `write`,
    /// `panic`).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub stage: Option<String>,
    /// The codes of the errors (failed) or warnings (done).
    #[serde(default)]
    pub codes: Vec<String>,
    /// The first error's message, for a failed job.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub message: Option<String>,
    /// Wall-clock seconds (not part of any output of the job).
    pub seconds: f64,
}

/// The summary of a run (or of merged shards).
#[derive(Clone, Debug, Default, Serialize, Deserialize, PartialEq)]
pub struct Summary {
    /// The holoc version.
    pub holoc: String,
    /// The shards this summary covers, as `I/N` (empty: the whole manifest).
    pub shards: Vec<String>,
    /// Jobs by status.
    pub done: usize,
    /// Jobs skipped because their folder was complete.
    pub skipped: usize,
    /// Jobs that failed.
    pub failed: usize,
    /// Every job of the run, by manifest line.
    pub jobs: Vec<JobResult>,
}

impl Summary {
    /// A summary of these results.
    pub fn of(mut jobs: Vec<JobResult>, shards: Vec<String>) -> Summary {
        jobs.sort_by_key(|j| j.line);
        let count = |s: Status| jobs.iter().filter(|j| j.status == s).count();
        Summary {
            holoc: env!("CARGO_PKG_VERSION").to_string(),
            shards,
            done: count(Status::Done),
            skipped: count(Status::Skipped),
            failed: count(Status::Failed),
            jobs,
        }
    }

    /// The shards' summaries as one (a job listed twice keeps its last result).
    pub fn merge(parts: Vec<Summary>) -> Summary {
        let mut by_line: BTreeMap<usize, JobResult> = BTreeMap::new();
        let mut shards = Vec::new();
        for part in parts {
            shards.extend(part.shards);
            for job in part.jobs {
                by_line.insert(job.line, job);
            }
        }
        shards.sort();
        shards.dedup();
        Summary::of(by_line.into_values().collect(), shards)
    }
}

/// A slice of the manifest: jobs whose line number modulo `count` is `index`.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Shard {
    /// Which slice, from 0.
    pub index: usize,
    /// How many slices.
    pub count: usize,
}

impl Shard {
    /// Reads `I/N` (0 ≤ I < N).
    pub fn parse(text: &str) -> Result<Shard, String> {
        let (i, n) = text.split_once('/').ok_or_else(|| format!("`{text}` is not I/N"))?;
        let index: usize = i.trim().parse().map_err(|_| format!("`{i}` is not a number"))?;
        let count: usize = n.trim().parse().map_err(|_| format!("`{n}` is not a number"))?;
        if count == 0 || index >= count {
            return Err(format!("the shard must be I/N with 0 <= I < N, not {index}/{count}"));
        }
        Ok(Shard { index, count })
    }

    /// Whether the job of this manifest line belongs to the shard.
    pub fn takes(self, line: usize) -> bool {
        line % self.count == self.index
    }
}

/// Reads a manifest: its jobs, and the lines that are not jobs. Blank lines and lines starting
/// with `//` or `#` are skipped. Paths are relative to `base`.
pub fn read_manifest(text: &str, base: &Path) -> (Vec<Job>, Vec<ManifestError>) {
    let mut jobs = Vec::new();
    let mut errors = Vec::new();
    for (k, raw) in text.lines().enumerate() {
        match read_line(k + 1, raw, base) {
            Some(Ok(job)) => jobs.push(job),
            Some(Err(e)) => errors.push(e),
            None => {}
        }
    }
    (jobs, errors)
}

/// One line of a manifest (`line` is 1-based): a job, a line that is not one, or `None` for a
/// blank or comment line.
pub fn read_line(line: usize, raw: &str, base: &Path) -> Option<Result<Job, ManifestError>> {
    let trimmed = raw.trim();
    if trimmed.is_empty() || trimmed.starts_with("//") || trimmed.starts_with('#') {
        return None;
    }
    let error = |message: String| Some(Err(ManifestError { line, message }));
    let spec: JobSpec = match serde_json::from_str(trimmed) {
        Ok(spec) => spec,
        Err(e) => return error(format!("not a job: {e}")),
    };
    if spec.build.is_some() == spec.generate.is_some() {
        return error("a job has exactly one of `build` and `generate`".into());
    }
    if let Some(s) = &spec.solver {
        if s != "dfs" && s != "milp" {
            return error(format!("unknown solver `{s}`"));
        }
    }
    if spec.node_budget.is_some_and(|b| b > crate::solve::MAX_NODE_BUDGET) {
        return error(format!("the node budget is at most {}", crate::solve::MAX_NODE_BUDGET));
    }
    let input = spec.build.as_ref().map(|p| base.join(p));
    let catalogs: Vec<PathBuf> = spec.catalog.iter().map(|c| base.join(c)).collect();
    let id = spec.id.clone().unwrap_or_else(|| format!("line-{line}"));
    Some(Ok(Job { line, id, spec, hash: String::new(), input, catalogs }))
}

/// The job's paths (its input and catalogs) that lie outside `base`, the manifest's folder,
/// once links are followed: a manifest from someone else must not make holoc read any file
/// the user can read (`--allow-outside` lifts this). A path that does not exist is judged by
/// its text.
pub fn outside_folder(job: &Job, base: &Path) -> Option<ManifestError> {
    let root =
        std::fs::canonicalize(if base.as_os_str().is_empty() { Path::new(".") } else { base })
            .ok()?;
    let inside = |p: &Path| match std::fs::canonicalize(p) {
        Ok(real) => real.starts_with(&root),
        // A path that does not exist: below the folder by its text alone.
        Err(_) => p.strip_prefix(base).is_ok_and(|rest| {
            rest.components().all(|c| {
                matches!(c, std::path::Component::Normal(_) | std::path::Component::CurDir)
            })
        }),
    };
    let paths = job.input.iter().chain(&job.catalogs);
    let out: Vec<&PathBuf> = paths.filter(|p| !inside(p)).collect();
    let first = out.first()?;
    Some(ManifestError {
        line: job.line,
        message: format!(
            "`{}` is outside the manifest's folder (give `--allow-outside` to read it)",
            first.display()
        ),
    })
}

/// The origin (scheme, host, port) of a URL, for comparing where requests go.
fn origin(url: &str) -> Option<String> {
    reqwest::Url::parse(url).ok().map(|u| u.origin().ascii_serialization())
}

/// A failed result for a manifest line that is not a job.
pub fn manifest_failure(e: &ManifestError) -> JobResult {
    JobResult {
        line: e.line,
        id: format!("line-{}", e.line),
        hash: String::new(),
        status: Status::Failed,
        stage: Some("manifest".into()),
        codes: Vec::new(),
        message: Some(e.message.clone()),
        seconds: 0.0,
    }
}

/// The job's content hash: its settings, the bytes of its input and catalogs, the holoc
/// version. An input or catalog that cannot be read hashes as its path (the job then fails
/// at that stage and is retried on every run).
pub fn job_hash(job: &Job) -> String {
    let key = serde_json::json!({
        "holoc": env!("CARGO_PKG_VERSION"),
        "spec": job.spec,
        "input": job.input.as_deref().map(file_hash),
        "catalogs": job.catalogs.iter().map(|p| file_hash(p)).collect::<Vec<_>>(),
    });
    crate::resolve::sha256_hex(key.to_string().as_bytes())[..16].to_string()
}

/// SHA-256 of a regular file's bytes, or its path when it cannot be read or is not a regular
/// file (a named pipe or a device is never opened here; the job's own read reports it).
fn file_hash(p: &Path) -> String {
    if !std::fs::metadata(p).is_ok_and(|m| m.is_file()) {
        return format!("unreadable:{}", p.display());
    }
    match crate::source::read_input(p, crate::resolve::MAX_CATALOG_BYTES) {
        Ok(bytes) => crate::resolve::sha256_hex(&bytes),
        Err(_) => format!("unreadable:{}", p.display()),
    }
}

/// The stack of each worker thread of a batch, bytes: room for the deepest recursion a job
/// can reach (blocks nest at most `parse::MAX_NESTING` levels, JSON answers at most
/// `import::MAX_JSON_NESTING`) many times over. A stack overflow aborts the process and cannot
/// be caught like a panic, so the bounds are kept where the input is read and the stack is
/// sized for them.
pub const WORKER_STACK_BYTES: usize = 16 * 1024 * 1024;

/// Settings of a whole run.
#[derive(Debug)]
pub struct RunOptions {
    /// The output folder.
    pub out: PathBuf,
    /// Redo jobs whose folder exists.
    pub force: bool,
    /// Generate requests in flight at once, over all jobs.
    pub llm_concurrency: usize,
    /// The API key of generate jobs (never written anywhere).
    pub api_key: Option<String>,
    /// The catalogs loaded so far, shared by the jobs that name the same files.
    pub catalogs: CatalogCache,
    /// Where generate jobs send their requests: `--base-url`, else `HOLOC_BASE_URL`, else
    /// holoc's default. The API key goes to this server only.
    pub base_url: String,
    /// Whether a job's own `base_url` is used (`--allow-job-base-url`); without it such a job
    /// fails. A job's server on another host than [`RunOptions::base_url`] never gets the key.
    pub allow_job_base_url: bool,
}

/// A loaded catalog set: the catalog, the sources its diagnostics point into, the diagnostics.
type LoadedCatalogs = Arc<(Catalog, SourceMap, Vec<Diagnostic>)>;

/// The catalog sets a run has loaded, by their paths and the bytes of their files: a job
/// whose catalogs were loaded by an earlier job (every job without `catalog`, usually) shares
/// that catalog instead of building it again. A changed file is a new key. At most
/// [`CatalogCache::MAX_SETS`] sets are kept, so memory stays flat with many distinct sets.
#[derive(Debug, Default)]
pub struct CatalogCache {
    sets: Mutex<HashMap<Vec<(PathBuf, String)>, LoadedCatalogs>>,
}

impl CatalogCache {
    /// The most catalog sets kept at once.
    pub const MAX_SETS: usize = 8;

    /// The catalog set of `paths`, loaded now or earlier.
    fn get(&self, paths: &[PathBuf]) -> LoadedCatalogs {
        let key: Vec<(PathBuf, String)> = paths.iter().map(|p| (p.clone(), file_hash(p))).collect();
        // A job that panicked while holding the lock leaves a map that is still whole (only
        // whole inserts and clears happen under it).
        let lock = || self.sets.lock().unwrap_or_else(std::sync::PoisonError::into_inner);
        if let Some(found) = lock().get(&key) {
            return Arc::clone(found);
        }
        let mut sources = SourceMap::new();
        let loaded = Catalog::load(paths, &mut sources);
        let set = Arc::new((loaded.value, sources, loaded.diagnostics));
        let mut sets = lock();
        if sets.len() >= Self::MAX_SETS {
            sets.clear();
        }
        Arc::clone(sets.entry(key).or_insert(set))
    }
}

/// A counting semaphore for model requests (std only).
#[derive(Debug)]
pub struct Permits {
    free: Mutex<usize>,
    freed: Condvar,
}

impl Permits {
    /// `n` permits (at least one).
    pub fn new(n: usize) -> Permits {
        Permits { free: Mutex::new(n.max(1)), freed: Condvar::new() }
    }

    fn acquire(&self) {
        let mut free = self.free.lock().unwrap_or_else(std::sync::PoisonError::into_inner);
        while *free == 0 {
            free = self.freed.wait(free).unwrap_or_else(std::sync::PoisonError::into_inner);
        }
        *free -= 1;
    }

    fn release(&self) {
        let mut free = self.free.lock().unwrap_or_else(std::sync::PoisonError::into_inner);
        *free += 1;
        self.freed.notify_one();
    }
}

/// A model that answers from a recorded transcript first and asks the live model only for
/// what was not recorded, each live request holding one permit: a re-run never pays twice
/// for the same answer, and the batch never has more than `--llm-concurrency` requests out.
struct ReusingLlm<'a> {
    recorded: BTreeMap<(String, Option<String>, u32), String>,
    live: &'a dyn Llm,
    permits: &'a Permits,
}

impl Llm for ReusingLlm<'_> {
    fn complete(&self, request: &LlmRequest<'_>) -> Result<LlmAnswer, LlmError> {
        let key = (request.stage.to_string(), request.room.map(str::to_string), request.attempt);
        if let Some(text) = self.recorded.get(&key) {
            return Ok(LlmAnswer { text: text.clone(), usage: generate::Usage::default() });
        }
        self.permits.acquire();
        let answer = self.live.complete(request);
        self.permits.release();
        answer
    }

    fn info(&self) -> ModelInfo {
        self.live.info()
    }
}

/// The files a finished job writes, by name.
type Files = Vec<(&'static str, String)>;

/// The outcome of running one job's work (before it is written).
struct Work {
    files: Files,
    diagnostics: Vec<Diagnostic>,
    failed_stage: Option<&'static str>,
}

fn failed(stage: &'static str, diagnostics: Vec<Diagnostic>) -> Work {
    Work { files: Vec::new(), diagnostics, failed_stage: Some(stage) }
}

fn solver_of(spec: &JobSpec) -> Solver {
    if spec.solver.as_deref() == Some("milp") {
        Solver::Milp
    } else {
        Solver::Dfs
    }
}

/// Builds `.holo` text into the house and its report.
fn build_text(
    name: &str,
    text: String,
    job: &Job,
    catalogs: &CatalogCache,
    files: &mut Files,
) -> Work {
    let loaded = catalogs.get(&job.catalogs);
    let (catalog, catalog_sources, catalog_diagnostics) = &*loaded;
    if catalog_diagnostics.iter().any(Diagnostic::is_error) {
        return failed("catalog", catalog_diagnostics.clone());
    }
    let mut sources = catalog_sources.clone();
    let file = sources.add(name, text);
    let options = BuildOptions {
        seed: if job.spec.generate.is_some() { None } else { job.spec.seed },
        solver: solver_of(&job.spec),
        node_budget: job.spec.node_budget,
        stand_ins: job.spec.stand_ins.unwrap_or(true),
        ..BuildOptions::new(catalog)
    };
    let built = build(&sources, file, &options);
    let mut diagnostics = catalog_diagnostics.clone();
    diagnostics.extend(built.diagnostics);
    let Some(product) = built.value else { return failed("build", diagnostics) };
    let mut report =
        serde_json::to_string_pretty(&crate::report::report(&product, catalog)).unwrap_or_default();
    report.push('\n');
    files.push(("house.json", product.house.to_json_string()));
    files.push(("report.json", report));
    Work { files: std::mem::take(files), diagnostics, failed_stage: None }
}

fn run_build_job(job: &Job, catalogs: &CatalogCache) -> Work {
    let Some(path) = &job.input else { return failed("input", Vec::new()) };
    let cannot = |e: &dyn std::fmt::Display| {
        failed(
            "input",
            vec![Diagnostic::new(
                crate::diag::Code::E0001,
                format!("cannot read `{}`: {e}", path.display()),
            )],
        )
    };
    // Like every input: a named pipe is refused, a device read up to the limit and for a
    // bounded time.
    let text = match crate::source::read_input(path, crate::cli::common::MAX_INPUT_BYTES) {
        Ok(bytes) => match String::from_utf8(bytes) {
            Ok(t) => t,
            Err(_) => return cannot(&"it is not UTF-8 text"),
        },
        Err(e) => return cannot(&e),
    };
    // Nothing of a file that is not a scene reaches the summary: a diagnostic would quote it.
    if !looks_like_scene(&text) {
        return cannot(&"it is not a .holo scene (no `scene`, `room` or `door` item)");
    }
    build_text(&path.display().to_string(), text, job, catalogs, &mut Vec::new())
}

/// Whether a text has a line that starts like a `scene`, `room` or `door` item (the parse
/// that follows says whether it is a good one).
fn looks_like_scene(text: &str) -> bool {
    text.lines().any(|line| {
        let mut words = line.split_whitespace();
        matches!(words.next(), Some("scene" | "room" | "door")) && words.next().is_some()
    })
}

fn run_generate_job(job: &Job, options: &RunOptions, permits: &Permits) -> Work {
    let text = job.spec.generate.clone().unwrap_or_default();
    let seed = job.spec.seed.unwrap_or(1);
    let base_url = match &job.spec.base_url {
        Some(url) if options.allow_job_base_url => url.clone(),
        Some(_) => {
            return failed(
                "manifest",
                vec![Diagnostic::new(
                    crate::diag::Code::E0004,
                    "a job may not choose its server (`base_url`); give `--base-url`, \
                     `HOLOC_BASE_URL`, or `--allow-job-base-url`",
                )],
            )
        }
        None => options.base_url.clone(),
    };
    let model = job
        .spec
        .model
        .clone()
        .or_else(|| std::env::var("HOLOC_MODEL").ok())
        .unwrap_or_else(|| generate::client::DEFAULT_MODEL.to_string());
    // The key goes only to the run's own server: a job's server on another host gets none.
    let same_host = origin(&base_url).is_some() && origin(&base_url) == origin(&options.base_url);
    let mut http = HttpOptions::new(base_url, model);
    if same_host {
        http.api_key.clone_from(&options.api_key);
    }
    http.seed = Some(seed);
    if let Some(t) = job.spec.temperature {
        http.temperature = t;
    }
    let live = HttpLlm::new(http);
    // Answers recorded by an earlier run of this job that did not finish.
    let partial = partial_transcript(&options.out, &job.hash);
    let recorded = std::fs::read_to_string(&partial)
        .ok()
        .and_then(|t| serde_json::from_str::<crate::import::Transcript>(&t).ok())
        .map(|t| {
            generate::recorded_answers(&t)
                .into_iter()
                .map(|a| ((a.stage, a.room, a.attempt), a.answer))
                .collect()
        })
        .unwrap_or_default();
    let llm = ReusingLlm { recorded, live: &live, permits };
    let request = Request { text, seed };
    let options_g = GenerateOptions { jobs: 1, repair_rounds: 2, ..GenerateOptions::default() };
    let outcome: Outcome<generate::Generated> = generate::generate(&request, &llm, &options_g);
    let mut transcript =
        serde_json::to_string_pretty(&outcome.value.transcript).unwrap_or_default();
    transcript.push('\n');
    if outcome.has_errors() {
        // Keep what was paid for, for the next run.
        if let Some(parent) = partial.parent() {
            let _ = std::fs::create_dir_all(parent);
        }
        let tmp = partial.with_extension(format!("tmp-{}", std::process::id()));
        if std::fs::write(&tmp, transcript.as_bytes()).is_ok() {
            let _ = std::fs::rename(&tmp, &partial);
        }
        return failed("generate", outcome.diagnostics);
    }
    let mut files: Files =
        vec![("scene.holo", outcome.value.holo.clone()), ("transcript.json", transcript)];
    let mut work = build_text("scene.holo", outcome.value.holo, job, &options.catalogs, &mut files);
    let mut diagnostics = outcome.diagnostics;
    diagnostics.append(&mut work.diagnostics);
    work.diagnostics = diagnostics;
    work
}

/// Where a generate job that failed keeps its transcript for the next run.
fn partial_transcript(out: &Path, hash: &str) -> PathBuf {
    out.join(".partial").join(format!("{hash}.transcript.json"))
}

fn codes(diagnostics: &[Diagnostic], errors: bool) -> Vec<String> {
    let mut codes: Vec<String> = diagnostics
        .iter()
        .filter(|d| d.is_error() == errors)
        .map(|d| d.code.as_str().to_string())
        .collect();
    codes.sort();
    codes.dedup();
    codes
}

/// Writes a finished job's folder: a temporary folder with every file and the marker, renamed
/// into place.
fn write_job(
    out: &Path,
    job: &Job,
    files: &Files,
    diagnostics: &[Diagnostic],
) -> std::io::Result<()> {
    let target = out.join(&job.hash);
    let tmp = out.join(".tmp").join(format!("{}-{}", job.hash, std::process::id()));
    let _ = std::fs::remove_dir_all(&tmp);
    std::fs::create_dir_all(&tmp)?;
    for (name, text) in files {
        std::fs::write(tmp.join(name), text)?;
    }
    let mut job_json = serde_json::to_string_pretty(&serde_json::json!({
        "line": job.line, "id": job.id, "hash": job.hash, "spec": job.spec,
        "warnings": codes(diagnostics, false),
    }))
    .unwrap_or_default();
    job_json.push('\n');
    std::fs::write(tmp.join("job.json"), job_json)?;
    std::fs::write(tmp.join(DONE_MARKER), "")?;
    if target.exists() {
        std::fs::remove_dir_all(&target)?;
    }
    std::fs::rename(&tmp, &target)
}

/// Runs one job: skipped when its folder is complete (unless forced), else its work, written.
/// A panic inside the job is caught and recorded as a failure of stage `panic`.
pub fn run_job(job: &Job, options: &RunOptions, permits: &Permits) -> JobResult {
    let started = Instant::now();
    let mut result = JobResult {
        line: job.line,
        id: job.id.clone(),
        hash: job.hash.clone(),
        status: Status::Done,
        stage: None,
        codes: Vec::new(),
        message: None,
        seconds: 0.0,
    };
    if !options.force && options.out.join(&job.hash).join(DONE_MARKER).exists() {
        result.status = Status::Skipped;
        return result;
    }
    let work = std::panic::catch_unwind(std::panic::AssertUnwindSafe(|| {
        if job.spec.generate.is_some() {
            run_generate_job(job, options, permits)
        } else {
            run_build_job(job, &options.catalogs)
        }
    }));
    match work {
        Err(payload) => {
            let message = payload
                .downcast_ref::<String>()
                .cloned()
                .or_else(|| payload.downcast_ref::<&str>().map(|s| (*s).to_string()))
                .unwrap_or_else(|| "a panic".into());
            result.status = Status::Failed;
            result.stage = Some("panic".into());
            result.message = Some(message);
        }
        Ok(work) if work.failed_stage.is_some() => {
            result.status = Status::Failed;
            result.stage = work.failed_stage.map(str::to_string);
            result.codes = codes(&work.diagnostics, true);
            result.message =
                work.diagnostics.iter().find(|d| d.is_error()).map(|d| d.message.clone());
        }
        Ok(work) => {
            result.codes = codes(&work.diagnostics, false);
            if let Err(e) = write_job(&options.out, job, &work.files, &work.diagnostics) {
                result.status = Status::Failed;
                result.stage = Some("write".into());
                result.message = Some(e.to_string());
            } else if job.spec.generate.is_some() {
                let _ = std::fs::remove_file(partial_transcript(&options.out, &job.hash));
            }
        }
    }
    result.seconds = started.elapsed().as_secs_f64();
    result
}

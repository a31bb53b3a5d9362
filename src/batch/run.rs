//! Running one job: the skip check, the job's lock, its work on its worker's runner thread
//! under the time limit, the retries, and the writing of its folder.
//!
//! A job's work runs on a thread that holds a [`crate::cancel::Token`] (the runner its worker
//! keeps from job to job, or a new one when the last job's work did not come back whole);
//! past `--job-timeout` the token is cancelled, the stages stop at their next check and the
//! job is recorded as timed out (E0006) with the stage it was in. Work that does not stop within a short grace is left
//! to end on its own (its thread keeps its CPU permit until then) and the worker goes on.
//! Nothing a cancelled job computed is written, so outputs never depend on time.
//!
//! CPU work holds one of `--jobs` permits; model requests hold one of `--llm-concurrency`
//! permits and no CPU permit, so generate jobs overlap the model's latency with builds.

use super::files::{CatalogCache, FileHashes, FileLock};
use super::{Job, JobResult, Status, DONE_MARKER};
use crate::cancel::Token;
use crate::cli::common::confine_io;
use crate::compile::{build, BuildOptions};
use crate::diag::{Code, Diagnostic, Outcome};
use crate::generate::{
    self, GenerateOptions, HttpLlm, HttpOptions, Llm, LlmAnswer, LlmError, LlmRequest, ModelInfo,
    Request,
};
use crate::solve::Solver;
use std::collections::{BTreeMap, BTreeSet};
use std::path::{Path, PathBuf};
use std::sync::atomic::{AtomicU32, AtomicU64, AtomicUsize, Ordering};
use std::sync::{Arc, Condvar, Mutex};
use std::time::{Duration, Instant};

/// Settings and shared state of a whole run.
#[derive(Debug)]
pub struct RunOptions {
    /// The output folder.
    pub out: PathBuf,
    /// This run's scratch folder (inside `out/.tmp/`).
    pub scratch: PathBuf,
    /// Redo jobs whose folder exists, and ask the model again for every answer.
    pub force: bool,
    /// A failed job whose failure may pass (the model, the disk, a panic) is tried once more
    /// in the same run.
    pub retry_failed: bool,
    /// The time limit of one job.
    pub job_timeout: Duration,
    /// How long a cancelled job is given to stop before the worker leaves it.
    pub grace: Duration,
    /// The API key of generate jobs (never written anywhere).
    pub api_key: Option<String>,
    /// Model requests in flight, over all jobs.
    pub llm: Permits,
    /// CPU work at once, over all jobs.
    pub cpu: Permits,
    /// The catalogs loaded so far.
    pub catalogs: CatalogCache,
    /// The hashes of the files read so far.
    pub files: FileHashes,
    /// The first pause before a model request that failed for a passing reason is sent again
    /// (it doubles each time, up to [`MAX_MODEL_PAUSE`], with jitter).
    pub model_backoff: Duration,
    /// How long one model request may keep failing for a passing reason before its job fails
    /// (`--model-patience`, default [`DEFAULT_MODEL_PATIENCE`]).
    pub model_patience: Duration,
    /// The manifest's folder: a job reads only files below it unless `allow_outside`.
    pub manifest_dir: PathBuf,
    /// Jobs may read inputs and catalogs outside the manifest's folder (`--allow-outside`).
    pub allow_outside: bool,
    /// The run's model server (`--base-url`, else `HOLOC_BASE_URL`, else holoc's default):
    /// the only server the API key is sent to.
    pub base_url: String,
    /// A job may name its own server (`--allow-job-base-url`); it gets the key only when it
    /// is the run's server.
    pub allow_job_base_url: bool,
    /// Numbers the scratch folders of the jobs of this run.
    counter: AtomicU64,
}

impl RunOptions {
    /// Options for a run into `out` with scratch folder `scratch`, `jobs` CPU permits and
    /// `llm` model permits; the rest at their defaults (30 minutes per job).
    pub fn new(out: PathBuf, scratch: PathBuf, jobs: usize, llm: usize) -> RunOptions {
        RunOptions {
            out,
            scratch,
            force: false,
            retry_failed: false,
            job_timeout: DEFAULT_JOB_TIMEOUT,
            grace: Duration::from_secs(5),
            api_key: None,
            llm: Permits::new(llm),
            cpu: Permits::new(jobs),
            manifest_dir: PathBuf::from("."),
            allow_outside: false,
            base_url: std::env::var("HOLOC_BASE_URL")
                .ok()
                .filter(|u| !u.trim().is_empty())
                .unwrap_or_else(|| crate::generate::client::DEFAULT_BASE_URL.to_string()),
            allow_job_base_url: false,
            catalogs: CatalogCache::default(),
            files: FileHashes::default(),
            model_backoff: Duration::from_secs(1),
            model_patience: DEFAULT_MODEL_PATIENCE,
            counter: AtomicU64::new(0),
        }
    }
}

/// The time limit of a job unless `--job-timeout` says otherwise: far above any normal job
/// (the slowest example builds in a tenth of a second; a generate job asks about twenty
/// questions).
pub const DEFAULT_JOB_TIMEOUT: Duration = Duration::from_secs(30 * 60);

/// A counting semaphore (std only).
#[derive(Debug)]
pub struct Permits {
    free: Mutex<usize>,
    freed: Condvar,
}

/// One permit, given back when dropped.
pub struct Permit<'a>(&'a Permits);

impl Drop for Permit<'_> {
    fn drop(&mut self) {
        self.0.release();
    }
}

impl Permits {
    /// `n` permits (at least one).
    pub fn new(n: usize) -> Permits {
        Permits { free: Mutex::new(n.max(1)), freed: Condvar::new() }
    }

    /// Waits for a permit.
    pub fn acquire(&self) -> Permit<'_> {
        let mut free = self.free.lock().unwrap_or_else(std::sync::PoisonError::into_inner);
        while *free == 0 {
            free = self.freed.wait(free).unwrap_or_else(std::sync::PoisonError::into_inner);
        }
        *free -= 1;
        Permit(self)
    }

    fn release(&self) {
        let mut free = self.free.lock().unwrap_or_else(std::sync::PoisonError::into_inner);
        *free += 1;
        self.freed.notify_one();
    }
}

/// The recorded answers of a job, by question: (stage, room, attempt, SHA-256 of the prompt).
type Recorded = BTreeMap<(String, Option<String>, u32, String), String>;

/// A model that answers from what an earlier run of the job recorded, when the question is
/// exactly the same (stage, room, attempt and prompt), and asks the live model otherwise, each
/// live request holding one model permit. Every answer received is appended at once to the
/// job's answer log (`.partial/<hash>.answers.jsonl`), so a job cancelled or killed part way
/// keeps it. A request that fails for a passing reason ([`LlmError::is_transient`]: the server
/// unreachable or dropping the connection, a timeout, 429, 5xx) is sent again after a pause
/// without the permit ([`pause`]: exponential, with jitter drawn from the job's hash, at least
/// the server's `Retry-After`), until the pauses add up to the run's patience
/// (`--model-patience`). A cancelled job gets no more answers.
struct ReusingLlm<'a> {
    recorded: Recorded,
    live: &'a dyn Llm,
    options: &'a RunOptions,
    token: &'a Token,
    retries: &'a AtomicU32,
    /// The job's hash (the jitter's seed).
    hash: &'a str,
    /// The answer log, appended to as answers come.
    log: Mutex<Option<std::fs::File>>,
    /// Set when a request gave up on an error that may pass (past the patience).
    gave_up_transient: std::sync::atomic::AtomicBool,
}

/// The default of `--model-patience`: how long one model request may keep failing for a
/// passing reason (the sum of the pauses between its tries, a try that timed out counting its
/// time limit) before its job fails as transient (exit status 75).
pub const DEFAULT_MODEL_PATIENCE: Duration = Duration::from_secs(15 * 60);

/// The longest pause between two tries of a request (a `Retry-After` may ask for more, up to
/// the patience left).
pub const MAX_MODEL_PAUSE: Duration = Duration::from_secs(60);

fn prompt_key(prompt: &str) -> String {
    crate::resolve::sha256_hex(prompt.as_bytes())
}

/// The pause before try `n + 1` (`n` ≥ 1 tries failed) of a request: `first · 2^(n-1)`, capped
/// at [`MAX_MODEL_PAUSE`], times a jitter in [0.5, 1) drawn from the job's hash, the question
/// and `n` (so two jobs that failed together do not come back together, and the same job
/// waits the same each time: no clock or random source), and at least `retry_after`.
pub fn pause(first: Duration, n: u32, seed: &str, retry_after: Option<Duration>) -> Duration {
    let doubled = first.saturating_mul(1u32 << (n.saturating_sub(1)).min(20)).min(MAX_MODEL_PAUSE);
    let draw = crate::resolve::sha256_hex(format!("{seed}/{n}").as_bytes());
    let unit = u64::from_str_radix(&draw[..8], 16).unwrap_or(0) as f64 / f64::from(u32::MAX);
    let jittered = doubled.mul_f64(0.5 + 0.5 * unit.clamp(0.0, 1.0));
    retry_after.map_or(jittered, |after| after.max(jittered))
}

/// One line of a job's answer log.
#[derive(serde::Serialize, serde::Deserialize)]
struct LoggedAnswer {
    stage: String,
    room: Option<String>,
    attempt: u32,
    prompt_sha256: String,
    answer: String,
}

impl ReusingLlm<'_> {
    /// Appends an answer to the job's log (a failure to write only costs the next run a
    /// request).
    fn keep(&self, key: &(String, Option<String>, u32, String), answer: &str) {
        use std::io::Write as _;
        let mut log = self.log.lock().unwrap_or_else(std::sync::PoisonError::into_inner);
        if log.is_none() {
            let path = answer_log(&self.options.out, self.hash);
            // Appended to only inside the run's folder: never through a link.
            if confine_io(&self.options.out, &path).is_ok() {
                *log = std::fs::OpenOptions::new().create(true).append(true).open(&path).ok();
            }
        }
        let Some(file) = log.as_mut() else { return };
        let line = LoggedAnswer {
            stage: key.0.clone(),
            room: key.1.clone(),
            attempt: key.2,
            prompt_sha256: key.3.clone(),
            answer: answer.to_string(),
        };
        if let Ok(mut text) = serde_json::to_string(&line) {
            text.push('\n');
            // One write per line: a kill leaves at most the last line cut short (skipped
            // when read).
            let _ = file.write_all(text.as_bytes());
        }
    }

    /// Sleeps `d` in short slices, stopping early when the job is cancelled (`d` divided by
    /// the time scale of the test hook, [`time_scale`]).
    fn sleep(&self, d: Duration) {
        let until = Instant::now() + d.div_f64(time_scale());
        while !self.token.is_cancelled() {
            let now = Instant::now();
            if now >= until {
                return;
            }
            std::thread::sleep((until - now).min(Duration::from_millis(50)));
        }
    }
}

impl Llm for ReusingLlm<'_> {
    fn complete(&self, request: &LlmRequest<'_>) -> Result<LlmAnswer, LlmError> {
        let key = (
            request.stage.to_string(),
            request.room.map(str::to_string),
            request.attempt,
            prompt_key(request.prompt),
        );
        if let Some(text) = self.recorded.get(&key) {
            return Ok(LlmAnswer { text: text.clone(), usage: generate::Usage::default() });
        }
        let seed = format!("{}/{}/{:?}/{}", self.hash, key.0, key.1, key.2);
        let patience = self.options.model_patience;
        let mut waited = Duration::ZERO;
        let mut n = 0u32;
        loop {
            n += 1;
            if self.token.is_cancelled() {
                return Err(LlmError::Timeout {
                    seconds: self.options.job_timeout.as_secs_f64(),
                    tries: n - 1,
                });
            }
            let answer = {
                let _permit = self.options.llm.acquire();
                self.live.complete(request)
            };
            let error = match answer {
                Ok(answer) => {
                    self.keep(&key, &answer.text);
                    return Ok(answer);
                }
                Err(e) if e.is_transient() => e,
                Err(e) => return Err(e),
            };
            // A try that timed out used up its time limit of the patience.
            if let LlmError::Timeout { seconds, .. } = &error {
                waited += Duration::from_secs_f64((seconds * time_scale()).clamp(0.0, 1e9));
            }
            let retry_after = match &error {
                LlmError::Server { retry_after, .. } => *retry_after,
                _ => None,
            };
            if waited >= patience {
                self.gave_up_transient.store(true, Ordering::Relaxed);
                return Err(with_tries(error, n));
            }
            let wait = pause(self.options.model_backoff, n, &seed, retry_after)
                .min(patience.saturating_sub(waited));
            self.retries.fetch_add(1, Ordering::Relaxed);
            self.sleep(wait);
            waited += wait;
        }
    }

    fn info(&self) -> ModelInfo {
        self.live.info()
    }
}

/// The error of the last of `tries` tries, saying how many there were.
fn with_tries(error: LlmError, tries: u32) -> LlmError {
    match error {
        LlmError::Timeout { seconds, .. } => LlmError::Timeout { seconds, tries },
        LlmError::Server { status, body, retry_after, .. } => {
            LlmError::Server { status, tries, body, retry_after }
        }
        LlmError::Unreachable { base_url, reason } => {
            LlmError::Unreachable { base_url, reason: format!("{reason} ({tries} tries)") }
        }
        other => other,
    }
}

/// The files a finished job writes, by name.
type Files = Vec<(&'static str, String)>;

/// The outcome of running one job's work (before it is written).
struct Work {
    files: Files,
    diagnostics: Vec<Diagnostic>,
    failed_stage: Option<&'static str>,
    model_retries: u32,
    /// The failure may pass (the model server out past the patience).
    transient: bool,
}

fn failed(stage: &'static str, diagnostics: Vec<Diagnostic>) -> Work {
    Work {
        files: Vec::new(),
        diagnostics,
        failed_stage: Some(stage),
        model_retries: 0,
        transient: false,
    }
}

fn solver_of(job: &Job) -> Solver {
    if job.spec.solver.as_deref() == Some("milp") {
        Solver::Milp
    } else {
        Solver::Dfs
    }
}

/// Builds `.holo` text into the house and its report (holding a CPU permit).
fn build_text(name: &str, text: String, job: &Job, options: &RunOptions, files: Files) -> Work {
    let _cpu = options.cpu.acquire();
    crate::cancel::stage("catalog");
    let loaded = options.catalogs.get(&job.catalogs, job.objathor.as_ref(), &options.files);
    let (catalog, catalog_sources, catalog_diagnostics) = &*loaded;
    if catalog_diagnostics.iter().any(Diagnostic::is_error) {
        return failed("catalog", catalog_diagnostics.clone());
    }
    let mut sources = catalog_sources.clone();
    let file = sources.add(name, text);
    let build_options = BuildOptions {
        seed: if job.spec.generate.is_some() { None } else { job.spec.seed },
        solver: solver_of(job),
        node_budget: job.spec.node_budget,
        stand_ins: job.spec.stand_ins.unwrap_or(true),
        make: true,
        // The jobs run in parallel (`--jobs`); a job's rooms one after the other.
        rooms_in_parallel: false,
        ..BuildOptions::new(catalog)
    };
    let built = build(&sources, file, &build_options);
    let mut diagnostics = catalog_diagnostics.clone();
    diagnostics.extend(built.diagnostics);
    if let Some(product) = &built.value {
        // Before anything is written: the objathor assets the house uses must be on disk.
        diagnostics.extend(crate::resolve::objathor::check_on_disk(
            catalog,
            product.objects.iter().map(|o| o.asset_id.as_str()),
            &|_| None,
        ));
    }
    let Some(product) = built.value.filter(|_| !diagnostics.iter().any(Diagnostic::is_error))
    else {
        let stage = diagnostics.iter().find(|d| d.is_error()).map_or("build", |d| stage_of(d.code));
        return failed(stage, diagnostics);
    };
    if product.house.house.rooms.is_empty() {
        // An empty scene (or one of comments only) builds a house of no rooms: not a house.
        diagnostics.push(
            Diagnostic::new(
                Code::E0812,
                format!("`{name}` declares no room: a house of no rooms is not a job's output"),
            )
            .with_help("give the scene at least one `room`, or remove the line from the manifest"),
        );
        return failed("input", diagnostics);
    }
    crate::cancel::stage("write");
    let mut report = crate::report::report(&product, catalog);
    // The report names the catalogs as the manifest does (relative to its folder), not as
    // they were reached from the working folder.
    if let Some(list) = report.pointer_mut("/assets/catalogs").and_then(|v| v.as_array_mut()) {
        for (entry, written) in list.iter_mut().skip(1).zip(&job.spec.catalog) {
            if let Some(path) = entry.get_mut("path") {
                *path = serde_json::json!(written);
            }
        }
    }
    let mut report = serde_json::to_string_pretty(&report).unwrap_or_default();
    report.push('\n');
    let mut files = files;
    files.push(("house.json", product.house.to_json_string()));
    files.push(("report.json", report));
    Work { files, diagnostics, failed_stage: None, model_retries: 0, transient: false }
}

/// The stage a build error comes from, by its code's band.
fn stage_of(code: Code) -> &'static str {
    match &code.as_str()[..3] {
        "E00" => "input",
        "E01" | "E02" => "check",
        "E03" => "plan",
        "E04" => "resolve",
        "E05" => "solve",
        "E06" => "lower",
        _ => "build",
    }
}

fn run_build_job(job: &Job, options: &RunOptions) -> Work {
    let Some(path) = &job.input else { return failed("input", Vec::new()) };
    crate::cancel::stage("input");
    let mut sources = crate::source::SourceMap::new();
    let text = match crate::cli::common::read_source(&mut sources, path) {
        Ok(id) => sources.get(id).text.to_string(),
        Err(d) => return failed("input", vec![d]),
    };
    // Diagnostics name the file as the manifest writes it.
    let name = job.spec.build.clone().unwrap_or_default();
    build_text(&name, text, job, options, Vec::new())
}

/// The answers earlier runs of this job recorded: the transcript a failed run kept (without
/// the questions that failed) and the answer log, answer by answer as they came (a line cut
/// short by a kill is skipped).
fn recorded_answers(out: &Path, hash: &str) -> Recorded {
    let mut recorded = Recorded::new();
    if let Some(transcript) =
        crate::source::read_text(&partial_transcript(out, hash), 32 * 1024 * 1024)
            .ok()
            .and_then(|t| serde_json::from_str::<crate::import::Transcript>(&t).ok())
    {
        recorded.extend(
            transcript
                .exchanges
                .into_iter()
                .map(|e| ((e.stage, e.room, e.attempt, prompt_key(&e.prompt)), e.answer)),
        );
    }
    let log =
        crate::source::read_text(&answer_log(out, hash), 64 * 1024 * 1024).unwrap_or_default();
    for line in log.lines() {
        if let Ok(a) = serde_json::from_str::<LoggedAnswer>(line) {
            recorded.insert((a.stage, a.room, a.attempt, a.prompt_sha256), a.answer);
        }
    }
    recorded
}

/// Rewrites the answer log without the answers to `gave_up` questions (so that the next run
/// asks them again).
fn forget_answers(options: &RunOptions, hash: &str, gave_up: &BTreeSet<(String, Option<String>)>) {
    let path = answer_log(&options.out, hash);
    let Ok(log) = crate::source::read_text(&path, 64 * 1024 * 1024) else { return };
    let mut kept = String::new();
    for line in log.lines() {
        match serde_json::from_str::<LoggedAnswer>(line) {
            Ok(a) if !gave_up.contains(&(a.stage.clone(), a.room.clone())) => {
                kept.push_str(line);
                kept.push('\n');
            }
            _ => {}
        }
    }
    let _ = write_atomically(&path, &kept, &options.scratch, options);
}

fn run_generate_job(job: &Job, options: &RunOptions, token: &Token) -> Work {
    crate::cancel::stage("generate");
    let text = job.spec.generate.clone().unwrap_or_default();
    let seed = job.spec.seed.unwrap_or(1);
    let base_url = match &job.spec.base_url {
        Some(url) if options.allow_job_base_url => url.clone(),
        Some(_) => {
            return failed(
                "manifest",
                vec![Diagnostic::new(
                    Code::E0005,
                    "a job may not choose its model server (`base_url`): give `--base-url` (or \
                     `HOLOC_BASE_URL`) for the run, or `--allow-job-base-url`",
                )],
            )
        }
        None => options.base_url.clone(),
    };
    // The key goes to the run's own server only: a job's server elsewhere gets none.
    let same_server = super::origin(&base_url).is_some()
        && super::origin(&base_url) == super::origin(&options.base_url);
    let mut http = HttpOptions::new(base_url, job.spec.resolved_model());
    if same_server {
        http.api_key.clone_from(&options.api_key);
    }
    http.seed = Some(seed);
    // Passing errors are retried here, without holding a model permit while waiting.
    http.retries = 0;
    http.timeout = http.timeout.min(options.job_timeout.max(Duration::from_secs(1)));
    if let Some(t) = job.spec.temperature {
        http.temperature = t;
    }
    let live = HttpLlm::new(http);
    let partial = partial_transcript(&options.out, &job.hash);
    let recorded =
        if options.force { Recorded::new() } else { recorded_answers(&options.out, &job.hash) };
    let retries = AtomicU32::new(0);
    let llm = ReusingLlm {
        recorded,
        live: &live,
        options,
        token,
        retries: &retries,
        hash: &job.hash,
        log: Mutex::new(None),
        gave_up_transient: std::sync::atomic::AtomicBool::new(false),
    };
    let request = Request { text, seed };
    let options_g = GenerateOptions {
        jobs: 1,
        repair_rounds: super::REPAIR_ROUNDS,
        ..GenerateOptions::default()
    };
    let outcome: Outcome<generate::Generated> = generate::generate(&request, &llm, &options_g);
    let model_retries = retries.load(Ordering::Relaxed);
    if outcome.has_errors() {
        // Keep what went well, for the next run: the exchanges of the questions whose answers
        // still had errors are left out, so that the next run asks them again.
        let gave_up: BTreeSet<(String, Option<String>)> =
            outcome.value.failed_questions.iter().cloned().collect();
        let mut kept = outcome.value.transcript.clone();
        kept.exchanges.retain(|e| !gave_up.contains(&(e.stage.clone(), e.room.clone())));
        let mut text = serde_json::to_string_pretty(&kept).unwrap_or_default();
        text.push('\n');
        if !token.is_cancelled() {
            let _ = write_atomically(&partial, &text, &options.scratch, options);
            forget_answers(options, &job.hash, &gave_up);
        }
        let mut work = failed("generate", outcome.diagnostics);
        work.model_retries = model_retries;
        work.transient = llm.gave_up_transient.load(Ordering::Relaxed);
        return work;
    }
    let mut transcript =
        serde_json::to_string_pretty(&outcome.value.transcript).unwrap_or_default();
    transcript.push('\n');
    let files: Files =
        vec![("scene.holo", outcome.value.holo.clone()), ("transcript.json", transcript)];
    let mut work = build_text("scene.holo", outcome.value.holo, job, options, files);
    let mut diagnostics = outcome.diagnostics;
    diagnostics.append(&mut work.diagnostics);
    work.diagnostics = diagnostics;
    work.model_retries = model_retries;
    work
}

/// Where a generate job that failed keeps its transcript for the next run.
fn partial_transcript(out: &Path, hash: &str) -> PathBuf {
    out.join(".partial").join(format!("{hash}.transcript.json"))
}

/// Where a generate job appends every answer it receives, as it receives it.
fn answer_log(out: &Path, hash: &str) -> PathBuf {
    out.join(".partial").join(format!("{hash}.answers.jsonl"))
}

/// Where a job that failed keeps how many times it was tried.
fn tries_file(out: &Path, hash: &str) -> PathBuf {
    out.join(".partial").join(format!("{hash}.tries"))
}

/// Where the lock of a job is.
fn lock_file(out: &Path, hash: &str) -> PathBuf {
    out.join(".locks").join(format!("{hash}.lock"))
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

/// How many times faster than the wall clock the pauses between a model request's tries run,
/// from `HOLOC_BATCH_TIME_SCALE` (a test hook, default 1): with 100, a pause of 60 s (the
/// back-off's, a `Retry-After`'s) sleeps 0.6 s and counts 60 s against `--model-patience`, so
/// that a benchmark can play an outage of minutes in seconds, every decision (which pause, when
/// to give up) being the one a real run takes. Nothing a job writes depends on it.
fn time_scale() -> f64 {
    static SCALE: std::sync::OnceLock<f64> = std::sync::OnceLock::new();
    *SCALE.get_or_init(|| {
        std::env::var("HOLOC_BATCH_TIME_SCALE")
            .ok()
            .and_then(|v| v.trim().parse::<f64>().ok())
            .filter(|v| v.is_finite())
            .map_or(1.0, |v| v.clamp(1.0, 1e6))
    })
}

/// The number of job files after which writes fail as on a full disk, from
/// `HOLOC_BATCH_DISK_FULL_AFTER` (a test hook: a real full disk is hard to come by in a test).
fn disk_full_after() -> Option<usize> {
    static AFTER: std::sync::OnceLock<Option<usize>> = std::sync::OnceLock::new();
    *AFTER.get_or_init(|| {
        std::env::var("HOLOC_BATCH_DISK_FULL_AFTER").ok().and_then(|v| v.trim().parse().ok())
    })
}

static FILES_WRITTEN: AtomicUsize = AtomicUsize::new(0);

/// Whether the run has let go of its records reserve (the test hook's disk then has room for
/// the records again).
static RESERVE_RELEASED: std::sync::atomic::AtomicBool = std::sync::atomic::AtomicBool::new(false);

/// Says that the run removed its records reserve, freeing its space.
pub fn release_reserve() {
    RESERVE_RELEASED.store(true, Ordering::SeqCst);
}

/// Whether the disk-full test hook has fired and no reserve was let go since: the records
/// cannot be written then, as on a real full disk.
pub fn records_blocked() -> bool {
    disk_full_after().is_some_and(|after| FILES_WRITTEN.load(Ordering::SeqCst) >= after)
        && !RESERVE_RELEASED.load(Ordering::SeqCst)
}

/// Writes one file of a job (through the disk-full test hook).
fn write_file(path: &Path, text: &str) -> std::io::Result<()> {
    if let Some(after) = disk_full_after() {
        if FILES_WRITTEN.fetch_add(1, Ordering::SeqCst) >= after {
            // Part of the file is written, as on a real full disk.
            let _ = std::fs::write(path, &text.as_bytes()[..text.len() / 2]);
            return Err(std::io::Error::from(std::io::ErrorKind::StorageFull));
        }
    }
    std::fs::write(path, text)
}

/// Whether an I/O error means the disk (or the quota) is full.
pub fn is_disk_full(e: &std::io::Error) -> bool {
    e.kind() == std::io::ErrorKind::StorageFull || matches!(e.raw_os_error(), Some(28 | 122))
}

/// Removes `path`, a file of the run's folder, unless it leads outside the folder.
fn remove_inside(out: &Path, path: &Path) {
    if confine_io(out, path).is_ok() {
        let _ = std::fs::remove_file(path);
    }
}

/// The message of an error of [`confine_io`] that refused a path outside the folder (E0009).
pub fn outside(e: &std::io::Error) -> Option<String> {
    let text = e.to_string();
    text.strip_prefix("[E0009] ").map(str::to_owned)
}

/// Writes `text` to `path` through a scratch file and a rename.
fn write_atomically(
    path: &Path,
    text: &str,
    scratch: &Path,
    options: &RunOptions,
) -> std::io::Result<()> {
    confine_io(&options.out, path)?;
    let n = options.counter.fetch_add(1, Ordering::Relaxed);
    let tmp = scratch.join(format!("file-{n}"));
    if let Err(e) = write_file(&tmp, text) {
        let _ = std::fs::remove_file(&tmp);
        return Err(e);
    }
    std::fs::rename(&tmp, path)
}

/// Writes a finished job's folder: a scratch folder with every file and the marker, renamed
/// into place.
fn write_job(
    job: &Job,
    files: &Files,
    diagnostics: &[Diagnostic],
    options: &RunOptions,
) -> std::io::Result<()> {
    let target = options.out.join(&job.hash);
    // The folder, if there, must be a real one inside the run's folder (not a link to one
    // elsewhere, which the rename would not follow but the removal before it would empty).
    if std::fs::symlink_metadata(&target).is_ok() {
        confine_io(&options.out, &target.join(DONE_MARKER))?;
    } else {
        confine_io(&options.out, &target)?;
    }
    let n = options.counter.fetch_add(1, Ordering::Relaxed);
    let tmp = options.scratch.join(format!("{}-{n}", job.hash));
    let written = (|| {
        std::fs::create_dir_all(&tmp)?;
        for (name, text) in files {
            write_file(&tmp.join(name), text)?;
        }
        let model = super::generation_identity(&job.spec, &options.base_url);
        let mut job_json = serde_json::to_string_pretty(&serde_json::json!({
            "hash": job.hash,
            "holoc": crate::build_info::LONG_VERSION,
            "spec": job.spec.for_identity(),
            "model": model,
            "warnings": codes(diagnostics, false),
        }))
        .unwrap_or_default();
        job_json.push('\n');
        write_file(&tmp.join("job.json"), &job_json)?;
        write_file(&tmp.join(DONE_MARKER), "")?;
        if target.exists() {
            std::fs::remove_dir_all(&target)?;
        }
        std::fs::rename(&tmp, &target)
    })();
    if written.is_err() {
        let _ = std::fs::remove_dir_all(&tmp);
    }
    written
}

/// How one try of a job's work ended.
enum Ended {
    Finished(std::thread::Result<Work>),
    TimedOut { stage: &'static str, stopped: bool },
}

/// The stack of each job's thread, bytes: room for the deepest recursion a job can reach
/// (blocks nest at most `parse::MAX_NESTING` levels, JSON answers a bounded depth) many times
/// over. A stack overflow aborts the whole process and cannot be caught like a panic, so the
/// depth is bounded where the input is read and the stack sized for it.
pub const WORKER_STACK_BYTES: usize = 16 * 1024 * 1024;

/// A thread that runs jobs' work, one job after another: each worker of a run keeps one
/// between its jobs (in [`RUNNER`]), instead of starting a thread with a fresh
/// [`WORKER_STACK_BYTES`] stack for every job (its stack mapped and faulted in again, its
/// allocator arena and the parser's stack guard set up again: a third of a small job's CPU).
/// A runner is given back only after work that ended, without a panic, while its worker
/// waited: a job left to end on its own keeps its runner busy, and a panic may have left a
/// thread's scratch state half written, so the next job gets a new runner then. A runner whose
/// worker drops it ends once its work is done.
struct Runner {
    tasks: std::sync::mpsc::Sender<Box<dyn FnOnce() + Send>>,
}

thread_local! {
    /// This worker thread's runner, between two jobs.
    static RUNNER: std::cell::RefCell<Option<Runner>> = const { std::cell::RefCell::new(None) };
}

impl Runner {
    /// This thread's runner (taken: it is given back with [`Runner::give_back`]), or a new one.
    fn take() -> std::io::Result<Runner> {
        if let Some(runner) = RUNNER.with_borrow_mut(Option::take) {
            return Ok(runner);
        }
        let (tasks, queue) = std::sync::mpsc::channel::<Box<dyn FnOnce() + Send>>();
        std::thread::Builder::new().name("holoc-job".into()).stack_size(WORKER_STACK_BYTES).spawn(
            move || {
                for task in queue {
                    task();
                }
            },
        )?;
        Ok(Runner { tasks })
    }

    /// Keeps the runner for this thread's next job.
    fn give_back(self) {
        RUNNER.with_borrow_mut(|r| *r = Some(self));
    }
}

/// Runs the job's work on a runner thread (see [`Runner`]) under the time limit.
fn work_once(job: &Job, options: &Arc<RunOptions>) -> Ended {
    let token = Token::new(if job.spec.generate.is_some() { "generate" } else { "input" });
    let (tx, rx) = std::sync::mpsc::channel();
    let thread_job = job.clone();
    let thread_options = Arc::clone(options);
    let thread_token = Arc::clone(&token);
    let task = Box::new(move || {
        thread_token.install();
        let work = std::panic::catch_unwind(std::panic::AssertUnwindSafe(|| {
            let outside = (!thread_options.allow_outside)
                .then(|| super::outside_folder(&thread_job, &thread_options.manifest_dir))
                .flatten();
            if let Some(path) = outside {
                return failed(
                    "manifest",
                    vec![Diagnostic::new(
                        Code::E0005,
                        format!(
                            "`{}` is outside the manifest's folder: a manifest reads only \
                             files below its folder (give `--allow-outside` to lift this)",
                            path.display()
                        ),
                    )],
                );
            }
            if thread_job.spec.generate.is_some() {
                run_generate_job(&thread_job, &thread_options, &thread_token)
            } else {
                run_build_job(&thread_job, &thread_options)
            }
        }));
        let _ = tx.send(work);
    });
    let runner = match Runner::take() {
        Ok(runner) => runner,
        Err(e) => {
            return Ended::Finished(Ok(failed(
                "panic",
                vec![Diagnostic::new(Code::E0002, format!("cannot start the job's thread: {e}"))],
            )))
        }
    };
    if runner.tasks.send(task).is_err() {
        // The runner's thread is gone (it cannot end while its worker holds it but by an
        // abort): the work was never run.
        return Ended::Finished(Err(Box::new("the job's thread ended without a result")));
    }
    // The runner is kept for the next job when its work came back whole.
    let keep = |work: &std::thread::Result<Work>| {
        if work.is_ok() {
            runner.give_back();
        }
    };
    match rx.recv_timeout(options.job_timeout) {
        Ok(work) => {
            keep(&work);
            if token.is_cancelled() {
                Ended::TimedOut { stage: token.stage(), stopped: true }
            } else {
                Ended::Finished(work)
            }
        }
        Err(std::sync::mpsc::RecvTimeoutError::Disconnected) => {
            Ended::Finished(Err(Box::new("the job's thread ended without a result")))
        }
        Err(std::sync::mpsc::RecvTimeoutError::Timeout) => {
            token.cancel();
            let stage = token.stage();
            let stopped = match rx.recv_timeout(options.grace) {
                Ok(work) => {
                    keep(&work);
                    true
                }
                Err(_) => false,
            };
            Ended::TimedOut { stage, stopped }
        }
    }
}

/// Whether a failure may pass if the job is tried again at once.
fn passing(result: &JobResult) -> bool {
    matches!(result.stage.as_deref(), Some("generate" | "write" | "panic"))
}

/// Formats a duration for people: `90s`, `30m`, `1.5s`.
pub fn human_duration(d: Duration) -> String {
    let s = d.as_secs_f64();
    if s >= 3600.0 && s % 3600.0 == 0.0 {
        format!("{}h", s as u64 / 3600)
    } else if s >= 60.0 && s % 60.0 == 0.0 {
        format!("{}m", s as u64 / 60)
    } else if s >= 1.0 {
        format!("{s}s")
    } else {
        format!("{}ms", d.as_millis())
    }
}

/// One try of a job: its work, then its folder.
fn try_once(job: &Job, options: &Arc<RunOptions>, result: &mut JobResult) {
    match work_once(job, options) {
        Ended::TimedOut { stage, stopped } => {
            let mut message = format!(
                "the job ran past its time limit (--job-timeout {}) in stage `{stage}` and was stopped",
                human_duration(options.job_timeout)
            );
            if !stopped {
                message.push_str("; it did not stop at once and is left to end on its own");
            }
            *result = result.clone().fail(stage, Code::E0006, message);
        }
        Ended::Finished(Err(payload)) => {
            let message = payload
                .downcast_ref::<String>()
                .cloned()
                .or_else(|| payload.downcast_ref::<&str>().map(|s| (*s).to_string()))
                .unwrap_or_else(|| "a panic".into());
            *result = result.clone().fail("panic", Code::E0002, message);
        }
        Ended::Finished(Ok(work)) => {
            result.model_retries += work.model_retries;
            if let Some(stage) = work.failed_stage {
                result.status = Status::Failed;
                result.stage = Some(stage.to_string());
                result.codes = codes(&work.diagnostics, true);
                result.message =
                    work.diagnostics.iter().find(|d| d.is_error()).map(|d| d.message.clone());
                result.transient = work.transient;
                return;
            }
            result.status = Status::Done;
            result.stage = None;
            result.message = None;
            result.codes = codes(&work.diagnostics, false);
            if let Err(e) = write_job(job, &work.files, &work.diagnostics, options) {
                let (code, message) = if is_disk_full(&e) {
                    (Code::E0007, format!("the disk is full: {e}"))
                } else if let Some(why) = outside(&e) {
                    (Code::E0009, why)
                } else {
                    (Code::E0001, format!("cannot write the job's folder: {e}"))
                };
                *result = result.clone().fail("write", code, message);
                result.transient = code == Code::E0007;
            }
        }
    }
}

/// Runs one job: skipped when its folder is complete (unless forced) or when another run holds
/// its lock (busy); else its work, written. A panic inside the job is caught and recorded as a
/// failure of stage `panic`; a failed job records how many times it was tried, for the next run.
pub fn run_job(job: &Job, options: &Arc<RunOptions>) -> JobResult {
    let started = Instant::now();
    let mut result = JobResult::of(job, Status::Done);
    // A job's folder that is a link (to a finished folder elsewhere, say) is not this run's.
    let done = || {
        let folder = options.out.join(&job.hash);
        std::fs::symlink_metadata(&folder).is_ok_and(|m| m.is_dir())
            && folder.join(DONE_MARKER).exists()
    };
    if !options.force && done() {
        result.status = Status::Skipped;
        result.codes = recorded_warnings(&options.out, &job.hash);
        note_ignored_fields(job, &mut result);
        return result;
    }
    let lock_path = lock_file(&options.out, &job.hash);
    let taken = confine_io(&options.out, &lock_path).and_then(|()| FileLock::try_take(&lock_path));
    let lock = match taken {
        Ok(Some(lock)) => lock,
        Ok(None) => {
            result.status = Status::Busy;
            result.message = Some("another run on this folder is doing this job".into());
            return result;
        }
        Err(e) => {
            if let Some(why) = outside(&e) {
                return result.fail("write", Code::E0009, why);
            }
            let code = if is_disk_full(&e) { Code::E0007 } else { Code::E0001 };
            let mut result = result.fail("write", code, format!("cannot take the job's lock: {e}"));
            result.transient = code == Code::E0007;
            return result;
        }
    };
    // Another run may have finished the job while this one waited for the lock.
    if !options.force && done() {
        result.status = Status::Skipped;
        result.codes = recorded_warnings(&options.out, &job.hash);
        note_ignored_fields(job, &mut result);
        lock.remove();
        return result;
    }
    let tries = tries_file(&options.out, &job.hash);
    if options.force {
        remove_inside(&options.out, &partial_transcript(&options.out, &job.hash));
        remove_inside(&options.out, &answer_log(&options.out, &job.hash));
        remove_inside(&options.out, &tries);
    }
    let earlier: u32 =
        crate::source::read_text(&tries, 64).ok().and_then(|t| t.trim().parse().ok()).unwrap_or(0);
    result.tries = earlier + 1;
    try_once(job, options, &mut result);
    if options.retry_failed && result.status == Status::Failed && passing(&result) {
        result.tries += 1;
        let model_retries = result.model_retries;
        result =
            JobResult { tries: result.tries, model_retries, ..JobResult::of(job, Status::Done) };
        try_once(job, options, &mut result);
    }
    if result.status == Status::Failed {
        let _ = write_atomically(&tries, &format!("{}\n", result.tries), &options.scratch, options);
        drop(lock);
    } else {
        remove_inside(&options.out, &tries);
        remove_inside(&options.out, &partial_transcript(&options.out, &job.hash));
        remove_inside(&options.out, &answer_log(&options.out, &job.hash));
        lock.remove();
    }
    note_ignored_fields(job, &mut result);
    result.seconds = started.elapsed().as_secs_f64();
    result
}

/// The warnings' codes a finished job recorded in its `job.json`, so that a skipped job's
/// record says what its build said.
fn recorded_warnings(out: &Path, hash: &str) -> Vec<String> {
    crate::source::read_text(&out.join(hash).join("job.json"), 1024 * 1024)
        .ok()
        .and_then(|t| serde_json::from_str::<serde_json::Value>(&t).ok())
        .and_then(|v| {
            v.get("warnings").and_then(serde_json::Value::as_array).map(|w| {
                w.iter().filter_map(serde_json::Value::as_str).map(str::to_string).collect()
            })
        })
        .unwrap_or_default()
}

/// A build line that names generation-only fields: W0802 in its record (not in its folder,
/// which depends on the job alone, and the job is the same without them).
pub fn note_ignored_fields(job: &Job, result: &mut JobResult) {
    let fields = job.spec.generation_only_fields();
    if fields.is_empty() || result.status == Status::Failed {
        return;
    }
    let code = Code::W0802.as_str().to_string();
    if !result.codes.contains(&code) {
        result.codes.push(code);
        result.codes.sort();
    }
    let listed: Vec<String> = fields.iter().map(|f| format!("`{f}`")).collect();
    result.message = Some(format!(
        "{} {} only for generate jobs and {} ignored for a build (not part of its identity)",
        listed.join(", "),
        if fields.len() == 1 { "is" } else { "are" },
        if fields.len() == 1 { "is" } else { "are" },
    ));
}

/// Whether a failed job may succeed if run again later without any change: the model server
/// was unreachable, timed out or failed with 429/5xx past the patience, or the disk was full.
/// A run with such a failure exits with status 75 (`EX_TEMPFAIL`) so a scheduler requeues it.
pub fn is_transient(result: &JobResult) -> bool {
    result.status == Status::Failed && result.transient
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Runs a task on this thread's runner and says which thread ran it.
    fn runs_on(runner: &Runner) -> std::thread::ThreadId {
        let (tx, rx) = std::sync::mpsc::channel();
        runner
            .tasks
            .send(Box::new(move || {
                let _ = tx.send(std::thread::current().id());
            }))
            .expect("the runner takes work");
        rx.recv().expect("the runner ran it")
    }

    #[test]
    fn a_worker_keeps_its_runner_only_when_given_back() {
        std::thread::spawn(|| {
            let first = Runner::take().expect("a runner");
            let ran = runs_on(&first);
            assert_ne!(ran, std::thread::current().id(), "the work runs on the runner");
            first.give_back();
            let again = Runner::take().expect("the same runner");
            assert_eq!(runs_on(&again), ran, "one thread for the worker's jobs");
            // Not given back (work left running, or a panic): the next job gets a new one.
            drop(again);
            let fresh = Runner::take().expect("a new runner");
            assert_ne!(runs_on(&fresh), ran);
        })
        .join()
        .expect("the worker");
    }
}

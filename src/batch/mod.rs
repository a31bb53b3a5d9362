//! `holoc batch`: many scenes from a manifest, resumable, sharded, bounded.
//!
//! A manifest is JSON Lines, one job per line: a `.holo` file to build (`"build"`) or a request
//! to generate (`"generate"`), with optional overrides. Each job's outputs go under a folder
//! named by the job's identity ([`job_hash`]: its settings, the bytes of its input and of its
//! catalogs, the model and API of a generate job, and the build identity of holoc), written in
//! a scratch folder and renamed into place with its completion marker, so a folder that exists
//! is complete. A run skips the jobs whose folder exists, so a killed run resumes where it
//! stopped and a changed job (a new hash) is redone; a failed job is tried again by the next
//! run (a generate job reusing the answers of the questions that went well).
//!
//! The parts: this file holds the manifest ([`JobSpec`], [`read_line`]), the identity, the
//! records ([`JobResult`], [`Summary`]); [`shard`] splits the jobs into balanced shards by
//! their identity; [`files`] holds what a run shares (file hashes, catalogs, locks, scratch);
//! [`run`] runs one job (locks, time limit, retries, writing).

pub mod files;
pub mod run;
pub mod shard;

pub use files::{CatalogCache, FileHashes, Scratch};
pub use run::{run_job, Permits, RunOptions};
pub use shard::{assign, line_identity, shard_of, Place, Planned, Shard};

use crate::diag::Code;
use serde::{Deserialize, Serialize};
use std::collections::BTreeMap;
use std::path::{Path, PathBuf};

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
    /// An objathor version folder (or base), relative to the manifest's folder.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub objathor: Option<String>,
    /// The version folder under `objathor`.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub objathor_version: Option<String>,
    /// `lexical`, `features` or `clip`.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub objathor_scoring: Option<String>,
    /// `objathor-first` (the default), `builtin-first` or `score`.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub objathor_mix: Option<String>,
    /// `argmax` or `seeded`.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub objathor_pick: Option<String>,
    /// The CLIP text tower's weights folder of the `clip` mode, relative to the manifest's
    /// folder.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub objathor_clip: Option<String>,
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

impl JobSpec {
    /// The model a generate job asks: its own, else `HOLOC_MODEL`, else holoc's default.
    pub fn resolved_model(&self) -> String {
        self.model
            .clone()
            .or_else(|| std::env::var("HOLOC_MODEL").ok().filter(|m| !m.trim().is_empty()))
            .unwrap_or_else(|| crate::generate::client::DEFAULT_MODEL.to_string())
    }

    /// The API a generate job asks: its own, else the run's (`--base-url`, else
    /// `HOLOC_BASE_URL`, else holoc's default).
    pub fn resolved_base_url(&self, run: &str) -> String {
        self.base_url.clone().unwrap_or_else(|| run.to_string())
    }

    /// The fields of the line that only a generate job uses, when the line is a build: they
    /// are left out of its identity (W0802).
    pub fn generation_only_fields(&self) -> Vec<&'static str> {
        if self.generate.is_some() {
            return Vec::new();
        }
        let mut fields = Vec::new();
        if self.model.is_some() {
            fields.push("model");
        }
        if self.base_url.is_some() {
            fields.push("base_url");
        }
        if self.temperature.is_some() {
            fields.push("temperature");
        }
        fields
    }

    /// The spec as it enters the identity: a build's generation-only fields left out.
    #[must_use]
    pub fn for_identity(&self) -> JobSpec {
        let mut spec = self.clone();
        if spec.generate.is_none() {
            spec.model = None;
            spec.base_url = None;
            spec.temperature = None;
        }
        spec
    }
}

/// How many repair rounds a generate job of `holoc batch` allows each answer.
pub const REPAIR_ROUNDS: u32 = 2;

/// What a generate job asks of the model, all of it part of its identity and of `job.json`:
/// the server (`base_url`, the job's own or the run's), the model and every parameter of the
/// requests and of the generation. `None` for a build.
pub fn generation_identity(spec: &JobSpec, run_base_url: &str) -> Option<serde_json::Value> {
    spec.generate.as_ref().map(|_| {
        serde_json::json!({
            "model": spec.resolved_model(),
            "base_url": spec.resolved_base_url(run_base_url),
            "parameters": {
                "temperature": spec.temperature.unwrap_or(0.0),
                "seed": spec.seed.unwrap_or(1),
                "max_tokens": serde_json::Value::Null,
                "repair_rounds": REPAIR_ROUNDS,
            },
        })
    })
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
    /// The objathor folder and how it is used.
    pub objathor: Option<crate::resolve::objathor::ObjathorOptions>,
}

/// How good a result is, for merging: a finished job beats a failed one beats a busy one.
pub fn rank(status: Status) -> u8 {
    match status {
        Status::Done | Status::Skipped => 3,
        Status::Failed => 2,
        Status::Busy => 1,
    }
}

/// A manifest line that is not a job.
#[derive(Clone, Debug, Serialize, PartialEq)]
pub struct ManifestError {
    /// The line (1-based).
    pub line: usize,
    /// The line's `id`, when it is an object that has one.
    pub id: Option<String>,
    /// What is wrong.
    pub message: String,
}

/// How a job ended.
#[derive(Clone, Copy, Debug, Serialize, Deserialize, PartialEq, Eq)]
#[serde(rename_all = "lowercase")]
pub enum Status {
    /// Built now.
    Done,
    /// Its folder was complete already (or another line of the manifest is the same job).
    Skipped,
    /// Another run on the same folder holds the job's lock and is doing it.
    Busy,
    /// Failed; nothing was written for it.
    Failed,
}

#[allow(
    clippy::trivially_copy_pass_by_ref,
    reason = "serde's skip_serializing_if passes a reference"
)]
fn is_zero(n: &u32) -> bool {
    *n == 0
}

fn one() -> u32 {
    1
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
    /// The stage that failed (`manifest`, `input`, `catalog`, `generate`, `check`, `plan`,
    /// `resolve`, `solve`, `lower`, `build`, `write`, `panic`).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub stage: Option<String>,
    /// The codes of the errors (failed) or warnings (done).
    #[serde(default)]
    pub codes: Vec<String>,
    /// The first error's message, for a failed job.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub message: Option<String>,
    /// The how-manieth try of the job this was, over every run (1 the first time).
    #[serde(default = "one")]
    pub tries: u32,
    /// Model requests of this run that failed for a passing reason (429, 5xx, a timeout) and
    /// were asked again after a pause.
    #[serde(default, skip_serializing_if = "is_zero")]
    pub model_retries: u32,
    /// The failure may pass if the job is run again later without any change (the model
    /// server out past `--model-patience`, a full disk): the run exits with status 75.
    #[serde(default, skip_serializing_if = "std::ops::Not::not")]
    pub transient: bool,
    /// Wall-clock seconds (not part of any output of the job).
    pub seconds: f64,
}

impl JobResult {
    /// A result for `job` with nothing filled in yet.
    pub fn of(job: &Job, status: Status) -> JobResult {
        JobResult {
            line: job.line,
            id: job.id.clone(),
            hash: job.hash.clone(),
            status,
            stage: None,
            codes: Vec::new(),
            message: None,
            tries: 1,
            model_retries: 0,
            transient: false,
            seconds: 0.0,
        }
    }

    /// A failure of `stage` with one code and its message.
    #[must_use]
    pub fn fail(mut self, stage: &str, code: Code, message: String) -> JobResult {
        self.status = Status::Failed;
        self.transient = false;
        self.stage = Some(stage.to_string());
        self.codes = vec![code.as_str().to_string()];
        self.message = Some(message);
        self
    }
}

/// The summary of a run (or of merged shards).
#[derive(Clone, Debug, Default, Serialize, Deserialize, PartialEq)]
pub struct Summary {
    /// The holoc build identity ([`crate::build_info::LONG_VERSION`]).
    pub holoc: String,
    /// The shards this summary covers, as `I/N` (empty: the whole manifest).
    pub shards: Vec<String>,
    /// Jobs built now.
    pub done: usize,
    /// Jobs skipped because their folder was complete.
    pub skipped: usize,
    /// Jobs another run on the same folder was doing.
    #[serde(default)]
    pub busy: usize,
    /// Jobs that failed.
    pub failed: usize,
    /// Every job of the run, by manifest line.
    pub jobs: Vec<JobResult>,
    /// The manifest the run read (its full path), for `holoc batch merge`.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub manifest: Option<String>,
    /// The run's model server (`--base-url`, without any user name or password), part of the
    /// identity of its generate jobs, for `holoc batch merge`.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub base_url: Option<String>,
    /// The lines of the manifest a merge accepted as not done (`--partial`).
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub incomplete: Vec<Incomplete>,
}

/// A manifest line that is not done, as `holoc batch merge` finds it.
#[derive(Clone, Debug, Serialize, Deserialize, PartialEq)]
pub struct Incomplete {
    /// The line (1-based).
    pub line: usize,
    /// The job's name.
    pub id: String,
    /// The job's identity now (empty for a line that is not a job).
    pub hash: String,
    /// The shard that runs it now, as `I/N` (when the run was sharded).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub shard: Option<String>,
    /// Why it is not done.
    pub why: String,
}

/// A server address as a summary records it: without user name and password.
pub fn public_url(url: &str) -> String {
    match url::Url::parse(url) {
        Ok(mut u) => {
            let _ = u.set_username("");
            let _ = u.set_password(None);
            u.to_string().trim_end_matches('/').to_string()
        }
        Err(_) => url.to_string(),
    }
}

impl Summary {
    /// A summary of these results.
    pub fn of(mut jobs: Vec<JobResult>, shards: Vec<String>) -> Summary {
        jobs.sort_by_key(|j| j.line);
        let count = |s: Status| jobs.iter().filter(|j| j.status == s).count();
        Summary {
            holoc: crate::build_info::LONG_VERSION.to_string(),
            shards,
            done: count(Status::Done),
            skipped: count(Status::Skipped),
            busy: count(Status::Busy),
            failed: count(Status::Failed),
            jobs,
            manifest: None,
            base_url: None,
            incomplete: Vec::new(),
        }
    }

    /// The shards' summaries as one, by line: a line listed more than once keeps its best
    /// result (done or skipped before failed before busy; the later one on a tie).
    pub fn merge(parts: Vec<Summary>) -> Summary {
        let mut by_line: BTreeMap<usize, JobResult> = BTreeMap::new();
        let mut shards = Vec::new();
        let manifest = Self::agreed(&parts, |p| p.manifest.clone());
        let base_url = Self::agreed(&parts, |p| p.base_url.clone());
        for part in parts {
            shards.extend(part.shards);
            for job in part.jobs {
                match by_line.get(&job.line) {
                    Some(old) if rank(old.status) > rank(job.status) => {}
                    _ => {
                        by_line.insert(job.line, job);
                    }
                }
            }
        }
        shards.sort_by_key(|s| Shard::parse(s).map(|s| (s.count, s.index)).unwrap_or_default());
        shards.dedup();
        let mut merged = Summary::of(by_line.into_values().collect(), shards);
        merged.manifest = manifest;
        merged.base_url = base_url;
        merged
    }

    /// The value every part that has one agrees on, if they agree.
    pub fn agreed(parts: &[Summary], get: impl Fn(&Summary) -> Option<String>) -> Option<String> {
        let mut values: Vec<String> = parts.iter().filter_map(get).collect();
        values.sort();
        values.dedup();
        if values.len() == 1 {
            values.pop()
        } else {
            None
        }
    }

    /// What keeps these summaries from being merged into the summary of a whole run: shards of
    /// different sizes, or shards missing. `None` when they cover the manifest (a summary of a
    /// whole run covers it alone).
    pub fn missing_shards(parts: &[Summary]) -> Option<String> {
        if parts.iter().any(|p| p.shards.is_empty()) {
            return None;
        }
        let mut seen: BTreeMap<usize, std::collections::BTreeSet<usize>> = BTreeMap::new();
        for s in parts.iter().flat_map(|p| &p.shards) {
            match Shard::parse(s) {
                Ok(s) => {
                    seen.entry(s.count).or_default().insert(s.index);
                }
                Err(e) => return Some(format!("a summary names the shard `{s}`: {e}")),
            }
        }
        let listed = |set: &std::collections::BTreeSet<usize>, n: usize| {
            set.iter().map(|i| format!("{i}/{n}")).collect::<Vec<_>>().join(", ")
        };
        if seen.len() > 1 {
            let sizes: Vec<String> = seen.keys().map(ToString::to_string).collect();
            return Some(format!(
                "the summaries are of shards of different runs ({} shards)",
                sizes.join(" and ")
            ));
        }
        let (&n, indices) = seen.iter().next()?;
        let missing: Vec<String> =
            (0..n).filter(|i| !indices.contains(i)).map(|i| format!("{i}/{n}")).collect();
        if missing.is_empty() {
            return None;
        }
        Some(format!(
            "the summaries cover shards {} of {n}: shard{} {} {} missing",
            listed(indices, n),
            if missing.len() == 1 { "" } else { "s" },
            missing.join(", "),
            if missing.len() == 1 { "is" } else { "are" }
        ))
    }
}

/// The first of the job's paths (its input and catalogs) that lies outside `base`, the
/// manifest's folder, once links are followed: a manifest from someone else must not make
/// holoc read whatever file the user can read. A path that does not exist is judged by its
/// text (below the folder, no `..`).
pub fn outside_folder(job: &Job, base: &Path) -> Option<PathBuf> {
    let folder = if base.as_os_str().is_empty() { Path::new(".") } else { base };
    let root = std::fs::canonicalize(folder).ok()?;
    let inside = |p: &Path| match std::fs::canonicalize(p) {
        Ok(real) => real.starts_with(&root),
        Err(_) => p.strip_prefix(base).is_ok_and(|rest| {
            rest.components().all(|c| {
                matches!(c, std::path::Component::Normal(_) | std::path::Component::CurDir)
            })
        }),
    };
    job.input.iter().chain(&job.catalogs).find(|p| !inside(p)).cloned()
}

/// The origin (scheme, host, port) of a URL, to compare where requests go.
pub(crate) fn origin(url: &str) -> Option<String> {
    url::Url::parse(url).ok().map(|u| u.origin().ascii_serialization())
}

/// The lines of a manifest, numbered from 1, without a byte order mark.
pub fn manifest_lines(text: &str) -> impl Iterator<Item = (usize, &str)> {
    text.strip_prefix('\u{feff}').unwrap_or(text).lines().enumerate().map(|(k, l)| (k + 1, l))
}

/// Whether a manifest line holds nothing to run: blank, or a `#` or `//` comment.
pub fn is_comment(raw: &str) -> bool {
    let t = raw.trim();
    t.is_empty() || t.starts_with("//") || t.starts_with('#')
}

/// Reads a manifest: its jobs, and the lines that are not jobs. Blank lines and lines starting
/// with `//` or `#` are skipped, as is a byte order mark. Paths are relative to `base`.
pub fn read_manifest(text: &str, base: &Path) -> (Vec<Job>, Vec<ManifestError>) {
    let mut jobs = Vec::new();
    let mut errors = Vec::new();
    for (line, raw) in manifest_lines(text) {
        match read_line(line, raw, base) {
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
    if is_comment(raw) {
        return None;
    }
    let trimmed = raw.trim().trim_start_matches('\u{feff}');
    let value: serde_json::Value = match serde_json::from_str(trimmed) {
        Ok(v) => v,
        Err(e) => {
            return Some(Err(ManifestError {
                line,
                id: None,
                message: format!("line {line} is not a job: not JSON ({e})"),
            }))
        }
    };
    let id = value.get("id").and_then(serde_json::Value::as_str).map(str::to_string);
    let error = |message: String| {
        Some(Err(ManifestError { line, id: id.clone(), message: format!("line {line} {message}") }))
    };
    let kind = match &value {
        serde_json::Value::Object(_) => None,
        serde_json::Value::Array(_) => Some("a JSON array"),
        serde_json::Value::String(_) => Some("a JSON string"),
        serde_json::Value::Number(_) => Some("a JSON number"),
        serde_json::Value::Bool(_) => Some("a JSON boolean"),
        serde_json::Value::Null => Some("JSON null"),
    };
    if let Some(kind) = kind {
        return error(format!("is not a job: {kind}, not an object"));
    }
    let spec: JobSpec = match serde_json::from_value(value) {
        Ok(spec) => spec,
        Err(e) => return error(format!("is not a job: {e}")),
    };
    if spec.build.is_some() == spec.generate.is_some() {
        return error("is not a job: a job has exactly one of `build` and `generate`".into());
    }
    if let Some(s) = &spec.solver {
        if s != "dfs" && s != "milp" {
            return error(format!("is not a job: unknown solver `{s}`"));
        }
    }
    if spec.node_budget.is_some_and(|b| b > crate::solve::MAX_NODE_BUDGET) {
        return error(format!(
            "is not a job: the node budget is at most {}",
            crate::solve::MAX_NODE_BUDGET
        ));
    }
    let objathor = match crate::resolve::objathor::ObjathorOptions::from_words(
        base,
        spec.objathor.as_deref().map(Path::new),
        spec.objathor_version.as_deref(),
        spec.objathor_scoring.as_deref(),
        spec.objathor_mix.as_deref(),
        spec.objathor_pick.as_deref(),
        spec.objathor_clip.as_deref().map(Path::new),
    ) {
        Ok(o) => o,
        Err(message) => return error(format!("is not a job: {message}")),
    };
    let input = spec.build.as_ref().map(|p| base.join(p));
    let catalogs: Vec<PathBuf> = spec.catalog.iter().map(|c| base.join(c)).collect();
    let id = spec.id.clone().unwrap_or_else(|| format!("line-{line}"));
    Some(Ok(Job { line, id, spec, hash: String::new(), input, catalogs, objathor }))
}

/// A failed result for a manifest line that is not a job (E0005).
pub fn manifest_failure(e: &ManifestError) -> JobResult {
    JobResult {
        line: e.line,
        id: e.id.clone().unwrap_or_else(|| format!("line-{}", e.line)),
        hash: String::new(),
        status: Status::Failed,
        stage: Some("manifest".into()),
        codes: vec![Code::E0005.as_str().to_string()],
        message: Some(e.message.clone()),
        tries: 1,
        model_retries: 0,
        transient: false,
        seconds: 0.0,
    }
}

/// The job's identity, hashed: its settings (a build's without the fields only generate jobs
/// use), the bytes of its input and catalogs, for a generate job the server, model and
/// parameters it asks with ([`generation_identity`]; `run_base_url` is the run's server), and
/// the build identity of holoc (version, commit, hashes of the embedded data and the source).
/// An input or catalog that cannot be read hashes as its path (the job then fails at that
/// stage and is tried again by the next run). Files are read through `files`, so each is read
/// and hashed once per run while it does not change.
pub fn job_hash(job: &Job, files: &FileHashes, run_base_url: &str) -> String {
    hash_of_spec(job, &job.spec, files, run_base_url)
}

/// Where the job goes among shards ([`shard::Place`]): its group, the hash of the job as
/// [`job_hash`] computes it but without its seed (the same scene, settings, catalogs, model),
/// and its seed.
pub fn job_place(job: &Job, files: &FileHashes, run_base_url: &str) -> shard::Place {
    let unseeded = JobSpec { seed: None, ..job.spec.clone() };
    let group = hash_of_spec(job, &unseeded, files, run_base_url);
    shard::Place::of_group(&group, job.spec.seed)
}

fn hash_of_spec(job: &Job, spec: &JobSpec, files: &FileHashes, run_base_url: &str) -> String {
    let model = generation_identity(spec, run_base_url);
    let key = serde_json::json!({
        "holoc": crate::build_info::LONG_VERSION,
        "spec": spec.for_identity(),
        "input": job.input.as_deref().map(|p| files.hash(p)),
        "catalogs": job.catalogs.iter().map(|p| files.hash(p)).collect::<Vec<_>>(),
        "model": model,
    });
    // With an objathor folder, its annotations' bytes are part of the identity too (the key
    // is unchanged without one).
    let key = match &job.objathor {
        Some(o) => {
            let dir = o.version.as_ref().map_or_else(|| o.dir.clone(), |v| o.dir.join(v));
            let annotations = ["annotations.json.gz", "annotations.json"]
                .iter()
                .map(|n| dir.join(n))
                .find(|p| p.is_file())
                .map(|p| files.hash(&p));
            serde_json::json!({"job": key, "objathor": annotations})
        }
        None => key,
    };
    crate::resolve::sha256_hex(key.to_string().as_bytes())[..16].to_string()
}

/// How much work a job is likely to be, for balancing shards: a build grows with the square of
/// its scene's size (its objects and the relations between them), times its node budget
/// (against the default) and four for the MILP; a generate job waits for the model for about
/// as long as a large build takes.
pub fn job_weight(job: &Job, files: &FileHashes) -> u64 {
    if job.spec.generate.is_some() {
        return 100_000_000;
    }
    let bytes = job.input.as_deref().map_or(0, |p| files.len(p));
    let budget = job.spec.node_budget.unwrap_or(crate::solve::DEFAULT_NODE_BUDGET);
    let budget_factor = (budget / crate::solve::DEFAULT_NODE_BUDGET).max(1);
    let solver_factor = if job.spec.solver.as_deref() == Some("milp") { 4 } else { 1 };
    (bytes.saturating_mul(bytes) / 1000 + 1)
        .saturating_mul(budget_factor)
        .saturating_mul(solver_factor)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_bom_is_skipped_and_a_line_that_is_not_an_object_is_an_error() {
        let text = "\u{feff}{\"build\": \"a.holo\"}\n[\"build\", \"a.holo\"]\n# c\n{\"id\": \"x\", \"nope\": 1}\n";
        let (jobs, errors) = read_manifest(text, Path::new("."));
        assert_eq!(jobs.len(), 1);
        assert_eq!(jobs[0].line, 1);
        assert_eq!(errors.len(), 2);
        assert_eq!(errors[0].line, 2);
        assert!(errors[0].message.contains("a JSON array"), "{}", errors[0].message);
        assert_eq!(errors[1].id.as_deref(), Some("x"));
        let failure = manifest_failure(&errors[1]);
        assert_eq!(failure.id, "x");
        assert_eq!(failure.codes, vec!["E0005"]);
    }

    #[test]
    fn a_job_names_its_objathor_folder_relative_to_the_manifest() {
        let line = r#"{"build": "a.holo", "objathor": "assets/2023_09_23", "objathor_scoring": "lexical", "objathor_pick": "seeded"}"#;
        let job = read_line(1, line, Path::new("m")).expect("a line").expect("a job");
        let o = job.objathor.expect("an objathor folder");
        assert_eq!(o.dir, Path::new("m").join("assets/2023_09_23"));
        assert_eq!(o.scoring, Some(crate::resolve::objathor::Scoring::Lexical));
        assert_eq!(o.pick, crate::resolve::objathor::Pick::Seeded);
        let bad = r#"{"build": "a.holo", "objathor": "x", "objathor_mix": "half"}"#;
        let err = read_line(1, bad, Path::new(".")).expect("a line").expect_err("not a job");
        assert!(err.message.contains("unknown objathor mix `half`"), "{}", err.message);
        // Without the folder, the job's identity is what it was.
        let plain = read_line(1, r#"{"build": "a.holo"}"#, Path::new(".")).expect("a line");
        assert!(plain.expect("a job").objathor.is_none());
    }

    #[test]
    fn missing_shards_are_named() {
        let part = |s: &str| Summary { shards: vec![s.into()], ..Summary::default() };
        assert_eq!(Summary::missing_shards(&[part("0/3"), part("2/3"), part("1/3")]), None);
        let missing = Summary::missing_shards(&[part("0/3"), part("2/3")]).expect("missing");
        assert!(missing.contains("shard 1/3 is missing"), "{missing}");
        assert!(Summary::missing_shards(&[part("0/2"), part("1/3")]).is_some());
        assert_eq!(Summary::missing_shards(&[Summary::default()]), None);
    }
}

//! `holoc batch MANIFEST -o OUT`: build or generate every job of a manifest (see
//! [`crate::batch`]); `holoc batch merge`: the shards' summaries as one.
//!
//! A run reads the manifest twice: first every line, for the jobs' identities (which the
//! shards and the duplicates are worked out from), then the lines of its shard, streamed to
//! `--jobs` CPU workers (plus `--llm-concurrency` more when there are generate jobs, which
//! mostly wait for the model). Results are written as they come, in manifest order, to a
//! scratch file from which the summary is made at the end.

use super::common;
use crate::batch::{self, Job, JobResult, RunOptions, Scratch, Shard, Status, Summary};
use crate::diag::{Code, Diagnostic};
use indicatif::{ProgressBar, ProgressDrawTarget, ProgressStyle};
use std::collections::{BTreeMap, HashMap, HashSet};
use std::fmt::Write as _;
use std::io::IsTerminal as _;
use std::path::{Path, PathBuf};
use std::process::ExitCode;
use std::sync::Arc;
use std::time::{Duration, Instant};

/// Arguments of `holoc batch`.
#[derive(Debug, clap::Args)]
#[command(args_conflicts_with_subcommands = true)]
#[allow(clippy::struct_excessive_bools, reason = "independent switches of the command line")]
pub struct BatchArgs {
    /// `merge`: collect the summaries of shards.
    #[command(subcommand)]
    pub command: Option<BatchCommand>,
    /// The manifest: JSON Lines, one job per line (`{"build": "a.holo", "seed": 3}` or
    /// `{"generate": "a bedroom", "seed": 7}`).
    pub manifest: Option<PathBuf>,
    /// The output folder: one folder per job, named by the job's content hash, and the summary.
    #[arg(short, long)]
    pub output: Option<PathBuf>,
    /// CPU work at once (default: the machine's cores).
    #[arg(long)]
    pub jobs: Option<usize>,
    /// Model requests in flight at once, over all generate jobs (independent of `--jobs`).
    #[arg(long, default_value_t = 4)]
    pub llm_concurrency: usize,
    /// Take only shard I of N (0 <= I < N; N is the size of the whole array), e.g.
    /// `--shard $SLURM_ARRAY_TASK_ID/32`. Jobs are split by their identity, not their line.
    #[arg(long, value_parser = Shard::parse)]
    pub shard: Option<Shard>,
    /// Redo jobs whose folder is complete, and ask the model again for every answer.
    #[arg(long)]
    pub force: bool,
    /// Try a job that failed for a reason that may pass (the model, the disk, a panic) once
    /// more in this run (a failed job is always tried again by the next run).
    #[arg(long)]
    pub retry_failed: bool,
    /// The time limit of one job (`90s`, `30m`, `2h`; default 30m); a job past it is stopped
    /// and recorded as timed out (E0006).
    #[arg(long, value_parser = parse_duration)]
    pub job_timeout: Option<Duration>,
    /// Exit with status 0 when the batch ran, even if some jobs failed (they are in
    /// `failures.jsonl`); for schedulers that restart a task that exits with another status.
    #[arg(long)]
    pub allow_failures: bool,
    /// Let jobs read inputs and catalogs outside the manifest's folder (by default a job that
    /// names such a file fails: a manifest from someone else cannot make holoc read any file
    /// you can read).
    #[arg(long)]
    pub allow_outside: bool,
    /// The model server of generate jobs, before `/chat/completions` (default:
    /// `HOLOC_BASE_URL`, else holoc's default). The API key is sent to this server only.
    #[arg(long)]
    pub base_url: Option<String>,
    /// Let a job name its own server (`base_url`); it gets the API key only when it is the
    /// run's server. Without this flag such a job fails.
    #[arg(long)]
    pub allow_job_base_url: bool,
    /// How long one model request may keep failing for a passing reason (unreachable, a
    /// dropped connection, a timeout, 429, 5xx) before its job fails (`90s`, `30m`, `2h`;
    /// default 15m): the pauses between its tries add up to this. A run with such a failure
    /// exits with status 75.
    #[arg(long, value_parser = parse_duration)]
    pub model_patience: Option<Duration>,
    /// The first pause before a model request that failed for a passing reason is sent again
    /// (default 1s); it doubles each time, up to 60 s, with jitter.
    #[arg(long, value_parser = parse_duration)]
    pub model_backoff: Option<Duration>,
    /// Seconds between progress lines when stderr is not a terminal (a log).
    #[arg(long, default_value_t = 60.0)]
    pub progress_every: f64,
    /// No progress bar, no progress lines and no table.
    #[arg(short, long)]
    pub quiet: bool,
}

/// Reads `90`, `90s`, `500ms`, `30m`, `2h`.
fn parse_duration(text: &str) -> Result<Duration, String> {
    let t = text.trim();
    let (number, unit) =
        t.find(|c: char| c.is_ascii_alphabetic()).map_or((t, "s"), |at| (&t[..at], &t[at..]));
    let value: f64 = number.trim().parse().map_err(|_| format!("`{text}` is not a duration"))?;
    let seconds = match unit {
        "ms" => value / 1000.0,
        "s" => value,
        "m" => value * 60.0,
        "h" => value * 3600.0,
        _ => return Err(format!("`{text}`: the unit is one of ms, s, m, h")),
    };
    if !seconds.is_finite() || seconds <= 0.0 || seconds > 1e9 {
        return Err(format!("`{text}` is not a positive duration"));
    }
    Ok(Duration::from_secs_f64(seconds))
}

/// The subcommands of `holoc batch`.
#[derive(Debug, clap::Subcommand)]
pub enum BatchCommand {
    /// Collect the summaries of several shards (or runs) into one.
    Merge(MergeArgs),
}

/// Arguments of `holoc batch merge`.
#[derive(Debug, clap::Args)]
pub struct MergeArgs {
    /// The summaries (`summary*.json`), or output folders whose summaries to collect.
    #[arg(required = true)]
    pub summaries: Vec<PathBuf>,
    /// Where to write the merged summary (default: stdout).
    #[arg(short, long)]
    pub output: Option<PathBuf>,
    /// Accept a partial run: merge even when some shards are missing or some lines of the
    /// manifest are not done (they are listed under `incomplete`), and exit 0.
    #[arg(long)]
    pub partial: bool,
    /// The manifest to check the summaries against (default: the one the summaries name).
    #[arg(long)]
    pub manifest: Option<PathBuf>,
    /// The run's model server, part of generate jobs' identities (default: the one the
    /// summaries name, else `HOLOC_BASE_URL`, else holoc's default).
    #[arg(long)]
    pub base_url: Option<String>,
    /// No table.
    #[arg(short, long)]
    pub quiet: bool,
}

/// Prints a diagnostic without a source to stderr with its notes (each unfinished job, each
/// line not done), which [`common::emit_plain`] leaves out.
fn emit(d: &Diagnostic) {
    let mut plain = d.clone();
    plain.notes.clear();
    common::emit_plain(&plain);
    for note in &d.notes {
        common::emit_status(&format!("  = note: {note}"));
    }
}

fn usage(message: &str) -> ExitCode {
    common::emit_plain(
        &Diagnostic::new(Code::E0004, message.to_string()).with_help("see `holoc batch --help`"),
    );
    ExitCode::from(2)
}

fn io_failure(what: &str, e: &std::io::Error) -> ExitCode {
    let code = write_error_code(e);
    emit(
        &Diagnostic::new(code, format!("{what}: {e}"))
            .with_note("no job was run: every job of the manifest is unfinished"),
    );
    ExitCode::from(EXIT_RECORDS)
}

/// The code of a failed write into the output folder: E0007 (disk full), E0009 (a path that
/// leads outside the folder) or E0001.
fn write_error_code(e: &std::io::Error) -> Code {
    if batch::run::is_disk_full(e) {
        Code::E0007
    } else if batch::run::outside(e).is_some() {
        Code::E0009
    } else {
        Code::E0001
    }
}

/// What the run does with one line of its shard.
enum Item {
    Run(Job),
    NotAJob(batch::ManifestError),
    /// The same job as an earlier line (by hash).
    Same {
        job: Job,
        first: usize,
    },
}

/// Runs `holoc batch`.
pub fn run(args: &BatchArgs) -> ExitCode {
    if let Some(BatchCommand::Merge(merge)) = &args.command {
        return run_merge(merge);
    }
    let (Some(manifest), Some(out)) = (&args.manifest, &args.output) else {
        return usage("`holoc batch` needs a manifest and `-o OUT_DIR`");
    };
    let mut sources = crate::source::SourceMap::new();
    let file = match common::read_source(&mut sources, manifest) {
        Ok(f) => f,
        Err(d) => {
            common::emit_plain(&d);
            return ExitCode::from(2);
        }
    };
    let base = manifest.parent().unwrap_or(Path::new("."));
    let text = &sources.get(file).text;
    let shard = args.shard;
    if let Err(e) = std::fs::create_dir_all(out) {
        return io_failure(&format!("cannot make the output folder `{}`", out.display()), &e);
    }
    let scratch = match Scratch::create(out) {
        Ok(s) => s,
        Err(e) => return io_failure(&format!("cannot write into `{}`", out.display()), &e),
    };
    let threads = args
        .jobs
        .unwrap_or_else(|| std::thread::available_parallelism().map_or(1, usize::from))
        .max(1);
    let mut options =
        RunOptions::new(out.clone(), scratch.dir.clone(), threads, args.llm_concurrency);
    options.force = args.force;
    options.retry_failed = args.retry_failed;
    options.files = batch::FileHashes::load(out);
    options.manifest_dir = base.to_path_buf();
    options.allow_outside = args.allow_outside;
    options.allow_job_base_url = args.allow_job_base_url;
    if let Some(url) = &args.base_url {
        options.base_url.clone_from(url);
    }
    if let Some(t) = args.job_timeout {
        options.job_timeout = t;
    }
    if let Some(p) = args.model_patience {
        options.model_patience = p;
    }
    if let Some(b) = args.model_backoff {
        options.model_backoff = b;
    }
    options.api_key = ["HOLOC_API_KEY", "OPENAI_API_KEY"]
        .iter()
        .find_map(|name| std::env::var(name).ok().filter(|k| !k.trim().is_empty()));
    let options = Arc::new(options);

    // First pass: every job's identity, for the shards and the duplicates. A job's shard is
    // a function of its identity alone (`batch::shard`).
    let mut planned: Vec<(usize, String)> = Vec::new();
    let mut generates = false;
    let mut in_shard: HashSet<usize> = HashSet::new();
    for (line, raw) in batch::manifest_lines(text) {
        if let Some(Ok(job)) = batch::read_line(line, raw, base) {
            generates |= job.spec.generate.is_some();
            if shard.is_none_or(|s| {
                s.takes_place(batch::job_place(&job, &options.files, &options.base_url))
            }) {
                in_shard.insert(line);
            }
            planned.push((line, batch::job_hash(&job, &options.files, &options.base_url)));
        }
    }
    let mut first_line: HashMap<&str, usize> = HashMap::new();
    let mut hash_of: HashMap<usize, &str> = HashMap::new();
    for (line, hash) in &planned {
        if in_shard.contains(line) {
            first_line.entry(hash.as_str()).or_insert(*line);
            hash_of.insert(*line, hash.as_str());
        }
    }
    let job_lines: HashSet<usize> = planned.iter().map(|(l, _)| *l).collect();
    let total = hash_of.len()
        + batch::manifest_lines(text)
            .filter(|(line, raw)| {
                !batch::is_comment(raw)
                    && !job_lines.contains(line)
                    && shard.is_none_or(|s| s.takes_line(raw))
            })
            .count();
    // Hashes listed more than once: their first line's result stands for the others.
    let mut seen_twice: HashSet<&str> = HashSet::new();
    {
        let mut seen: HashSet<&str> = HashSet::new();
        // In line order (`planned` is), so that the set does not depend on a hash map's order.
        for (line, hash) in &planned {
            if hash_of.contains_key(line) && !seen.insert(hash.as_str()) {
                seen_twice.insert(hash.as_str());
            }
        }
    }

    let shards = shard.map(|s| vec![format!("{}/{}", s.index, s.count)]).unwrap_or_default();
    let suffix = shard.map_or(String::new(), |s| format!(".shard-{}-of-{}", s.index, s.count));
    let mut log = match ResultLog::create(out, &scratch.dir, &suffix) {
        Ok(log) => log,
        Err(e) => return io_failure(&format!("cannot write into `{}`", out.display()), &e),
    };
    // Room for the records, taken now and given back just before they are written: a disk
    // that fills up during the run still has room for the summary and the failures.
    let reserve = out.join(format!(".records{suffix}.reserve"));
    let reserved = std::env::var("HOLOC_BATCH_RESERVE").map_or(true, |v| v.trim() != "0")
        && common::confine_io(out, &reserve).is_ok()
        && reserve_space(&reserve, records_room(total)).is_ok();
    let header = Header {
        shards: shards.clone(),
        manifest: std::fs::canonicalize(manifest).ok().map(|p| p.display().to_string()),
        base_url: generates.then(|| batch::public_url(&options.base_url)),
    };
    let started = Instant::now();
    let workers = threads + if generates { args.llm_concurrency.max(1) } else { 0 };
    let mut progress = Progress::new(total, args.quiet, args.progress_every);

    std::thread::scope(|scope| {
        let (items_tx, items_rx) = crossbeam_channel::bounded::<(usize, Item)>(workers * 2);
        let (results_tx, results_rx) =
            crossbeam_channel::unbounded::<(usize, JobResult, Option<usize>)>();
        // The reader: the lines of this shard, in order, numbered.
        let (hash_of, first_line) = (&hash_of, &first_line);
        scope.spawn(move || {
            let mut seq = 0;
            for (line, raw) in batch::manifest_lines(text) {
                let item = match batch::read_line(line, raw, base) {
                    None => continue,
                    Some(Err(e)) => {
                        if !shard.is_none_or(|s| s.takes_line(raw)) {
                            continue;
                        }
                        Item::NotAJob(e)
                    }
                    Some(Ok(mut job)) => {
                        let Some(hash) = hash_of.get(&line) else { continue };
                        job.hash = (*hash).to_string();
                        match first_line.get(hash) {
                            Some(&first) if first != line => Item::Same { job, first },
                            _ => Item::Run(job),
                        }
                    }
                };
                if items_tx.send((seq, item)).is_err() {
                    return;
                }
                seq += 1;
            }
        });
        for _ in 0..workers {
            let items_rx = items_rx.clone();
            let results_tx = results_tx.clone();
            let options = Arc::clone(&options);
            scope.spawn(move || {
                for (seq, item) in items_rx {
                    let (result, same) = match item {
                        Item::Run(job) => (batch::run_job(&job, &options), None),
                        Item::NotAJob(e) => (batch::manifest_failure(&e), None),
                        Item::Same { job, first } => {
                            let mut r = JobResult::of(&job, Status::Skipped);
                            batch::run::note_ignored_fields(&job, &mut r);
                            (r, Some(first))
                        }
                    };
                    if results_tx.send((seq, result, same)).is_err() {
                        return;
                    }
                }
            });
        }
        drop(items_rx);
        drop(results_tx);
        // The collector: results in manifest order, to the log, and the progress.
        let mut waiting: BTreeMap<usize, (JobResult, Option<usize>)> = BTreeMap::new();
        let mut next = 0;
        let mut by_hash: HashMap<String, JobResult> = HashMap::new();
        loop {
            match results_rx.recv_timeout(Duration::from_millis(250)) {
                Ok((seq, result, same)) => {
                    waiting.insert(seq, (result, same));
                }
                Err(crossbeam_channel::RecvTimeoutError::Timeout) => {}
                Err(crossbeam_channel::RecvTimeoutError::Disconnected) => break,
            }
            let mut ready = Vec::new();
            while let Some((mut result, same)) = waiting.remove(&next) {
                if let Some(first) = same {
                    // The first line of the job comes earlier, so its result is known.
                    if let Some(owner) = by_hash.get(&result.hash) {
                        result = same_as(owner, &result, first);
                    }
                } else if seen_twice.contains(result.hash.as_str()) {
                    by_hash.insert(result.hash.clone(), result.clone());
                }
                progress.count(&result);
                ready.push(result);
                next += 1;
            }
            log.append(&ready);
            progress.tick(started);
        }
    });
    progress.finish(started);
    if reserved {
        let _ = std::fs::remove_file(&reserve);
        batch::run::release_reserve();
    }
    let records = log.finish(&header, out, &suffix);
    // The hashes for the next run (a failure to write them only costs that run a read).
    let _ = options.files.save(out, &scratch.dir);
    scratch.finish();
    let counts = match &records {
        Ok(counts) => *counts,
        Err(failure) => {
            let mut d = Diagnostic::new(
                write_error_code(&failure.error),
                format!(
                    "cannot write the summary into `{}`: {}",
                    out.display(),
                    batch::run::outside(&failure.error)
                        .unwrap_or_else(|| failure.error.to_string())
                ),
            );
            let help = if d.code == Code::E0009 {
                "remove the link and run the same command again: finished jobs are skipped"
            } else {
                "free space and run the same command again: finished jobs are skipped"
            };
            if !failure.unfinished.is_empty() {
                d = d.with_note(format!(
                    "{} unfinished job{}: {}",
                    failure.unfinished.len(),
                    if failure.unfinished.len() == 1 { "" } else { "s" },
                    failure.unfinished.join("; ")
                ));
            }
            emit(&d.with_help(help));
            return ExitCode::from(EXIT_RECORDS);
        }
    };
    if !args.quiet {
        let summary = crate::source::read_text(
            &out.join(format!("summary{suffix}.json")),
            common::MAX_INPUT_BYTES,
        )
        .ok()
        .and_then(|t| serde_json::from_str::<Summary>(&t).ok())
        .unwrap_or_default();
        print_table(&summary, started.elapsed().as_secs_f64());
    }
    if log_transient(&counts) {
        ExitCode::from(EXIT_TRANSIENT)
    } else if counts.failed > 0 && !args.allow_failures {
        ExitCode::from(1)
    } else {
        ExitCode::SUCCESS
    }
}

/// The exit status of a run some of whose jobs failed for a reason that may pass (the model
/// server out past the patience, a full disk): `EX_TEMPFAIL`, so that a scheduler requeues the
/// task (`--allow-failures` does not hide it).
pub const EXIT_TRANSIENT: u8 = 75;

/// The exit status of a run whose records (summary, failures) could not be written:
/// `EX_IOERR`. The unfinished jobs are named on stderr.
pub const EXIT_RECORDS: u8 = 74;

fn log_transient(counts: &Counts) -> bool {
    counts.transient > 0
}

/// Room for the records of `lines` lines: half a kilobyte a line and 64 KiB, at most 256 MiB.
fn records_room(lines: usize) -> u64 {
    (lines as u64).saturating_mul(512).saturating_add(64 * 1024).min(256 * 1024 * 1024)
}

/// Writes `bytes` zeros to `path` (a reserve the run gives back before writing its records).
fn reserve_space(path: &Path, bytes: u64) -> std::io::Result<()> {
    use std::io::Write as _;
    let written = (|| {
        let mut file = std::fs::File::create(path)?;
        let chunk = vec![0u8; 64 * 1024];
        let mut left = bytes;
        while left > 0 {
            let n = left.min(chunk.len() as u64) as usize;
            file.write_all(&chunk[..n])?;
            left -= n as u64;
        }
        Ok(())
    })();
    if written.is_err() {
        let _ = std::fs::remove_file(path);
    }
    written
}

/// The record of a line that repeats the job of line `first`.
fn same_as(owner: &JobResult, this: &JobResult, first: usize) -> JobResult {
    let mut r = owner.clone();
    r.line = this.line;
    r.id.clone_from(&this.id);
    r.seconds = 0.0;
    if r.status == Status::Done {
        r.status = Status::Skipped;
    }
    let said = r.message.take().map_or(String::new(), |m| format!(": {m}"));
    r.message = Some(format!("the same job as line {first}{said}"));
    // This line's own warning (generation-only fields on a build line).
    let ignored = Code::W0802.as_str();
    if this.codes.iter().any(|c| c == ignored) && !r.codes.iter().any(|c| c == ignored) {
        r.codes.push(ignored.to_string());
        r.codes.sort();
        if let Some(m) = &this.message {
            r.message = Some(format!("{}; {m}", r.message.unwrap_or_default()));
        }
    }
    r
}

/// Progress: a bar on a terminal, a line every `every` seconds otherwise (a log).
struct Progress {
    bar: Option<ProgressBar>,
    lines: Option<Duration>,
    last: Instant,
    total: usize,
    /// Done, skipped, busy, failed.
    counts: [usize; 4],
}

impl Progress {
    fn new(total: usize, quiet: bool, every: f64) -> Progress {
        let terminal = std::io::stderr().is_terminal();
        let bar = (!quiet && terminal).then(|| {
            let bar =
                ProgressBar::with_draw_target(Some(total as u64), ProgressDrawTarget::stderr());
            if let Ok(style) = ProgressStyle::with_template(
                "{bar:30} {pos}/{len} jobs, {msg}, {per_sec}, {elapsed_precise} (eta {eta})",
            ) {
                bar.set_style(style);
            }
            bar
        });
        let lines = (!quiet && !terminal && every.is_finite() && every > 0.0)
            .then(|| Duration::from_secs_f64(every.min(1e6)));
        Progress { bar, lines, last: Instant::now(), total, counts: [0; 4] }
    }

    fn count(&mut self, r: &JobResult) {
        self.counts[slot(r.status)] += 1;
        if let Some(bar) = &self.bar {
            bar.set_message(format!("{} failed", self.counts[3]));
            bar.inc(1);
        }
    }

    fn line(&self, started: Instant) -> String {
        let finished: usize = self.counts.iter().sum();
        let seconds = started.elapsed().as_secs_f64();
        let rate = if seconds > 0.0 { finished as f64 / seconds } else { 0.0 };
        let left = self.total.saturating_sub(finished);
        let eta = if rate > 0.0 {
            format!("{}s", (left as f64 / rate).round() as u64)
        } else {
            "?".to_string()
        };
        format!(
            "holoc batch: {finished}/{} jobs (done {}, skipped {}, busy {}, failed {}), {rate:.1} jobs/s, {:.0}s elapsed, eta {eta}",
            self.total, self.counts[0], self.counts[1], self.counts[2], self.counts[3], seconds
        )
    }

    fn tick(&mut self, started: Instant) {
        if let Some(every) = self.lines {
            if self.last.elapsed() >= every {
                self.last = Instant::now();
                common::emit_status(&self.line(started));
            }
        }
    }

    fn finish(&self, started: Instant) {
        if let Some(bar) = &self.bar {
            bar.finish_and_clear();
        }
        if self.lines.is_some() {
            common::emit_status(&self.line(started));
        }
    }
}

fn slot(status: Status) -> usize {
    match status {
        Status::Done => 0,
        Status::Skipped => 1,
        Status::Busy => 2,
        Status::Failed => 3,
    }
}

/// What a summary's header says besides the counts.
struct Header {
    shards: Vec<String>,
    manifest: Option<String>,
    base_url: Option<String>,
}

/// The counts of a run's records.
#[derive(Clone, Copy, Debug, Default)]
struct Counts {
    done: usize,
    skipped: usize,
    busy: usize,
    failed: usize,
    /// Failed for a reason that may pass ([`batch::run::is_transient`]).
    transient: usize,
}

impl Counts {
    fn add(&mut self, r: &JobResult) {
        match r.status {
            Status::Done => self.done += 1,
            Status::Skipped => self.skipped += 1,
            Status::Busy => self.busy += 1,
            Status::Failed => self.failed += 1,
        }
        if batch::run::is_transient(r) {
            self.transient += 1;
        }
    }
}

/// Why the records could not be written, and the jobs they would have named unfinished.
struct RecordsFailure {
    error: std::io::Error,
    unfinished: Vec<String>,
}

fn blocked() -> std::io::Result<()> {
    if batch::run::records_blocked() {
        return Err(std::io::Error::from(std::io::ErrorKind::StorageFull));
    }
    Ok(())
}

/// The results of a run as they come: job lines in a scratch file, failures in their file,
/// and the counts. When the disk is full the lines wait in memory and are written later.
struct ResultLog {
    jobs_path: PathBuf,
    failures_path: PathBuf,
    jobs: std::io::BufWriter<std::fs::File>,
    failures: std::io::BufWriter<std::fs::File>,
    /// Lines not written yet (job lines, failure lines).
    pending: (Vec<String>, Vec<String>),
    counts: Counts,
    /// The jobs not done (failed or busy) so far, as `line N (id)`, for stderr when the
    /// records cannot be written.
    unfinished: Vec<String>,
}

impl ResultLog {
    fn create(out: &Path, scratch: &Path, suffix: &str) -> std::io::Result<ResultLog> {
        let _ = out;
        let jobs_path = scratch.join(format!("jobs{suffix}"));
        let failures_path = scratch.join(format!("failures{suffix}"));
        let open = |p: &Path| std::fs::File::create(p).map(std::io::BufWriter::new);
        Ok(ResultLog {
            jobs: open(&jobs_path)?,
            failures: open(&failures_path)?,
            jobs_path,
            failures_path,
            pending: (Vec::new(), Vec::new()),
            counts: Counts::default(),
            unfinished: Vec::new(),
        })
    }

    fn append(&mut self, results: &[JobResult]) {
        for r in results {
            let line = serde_json::to_string(r).unwrap_or_default();
            self.counts.add(r);
            if matches!(r.status, Status::Failed | Status::Busy) {
                self.unfinished.push(format!("line {} ({})", r.line, r.id));
            }
            if r.status == Status::Failed {
                self.pending.1.push(line.clone());
            }
            self.pending.0.push(line);
        }
        let _ = self.flush_pending();
    }

    fn flush_pending(&mut self) -> std::io::Result<()> {
        use std::io::Write as _;
        blocked()?;
        let write = |w: &mut std::io::BufWriter<std::fs::File>, lines: &mut Vec<String>| {
            let mut written = 0;
            let result = lines.iter().try_for_each(|line| {
                writeln!(w, "{line}")?;
                written += 1;
                Ok(())
            });
            lines.drain(..written);
            result
        };
        write(&mut self.jobs, &mut self.pending.0)?;
        write(&mut self.failures, &mut self.pending.1)
    }

    /// Writes `summary<suffix>.json` (streamed from the scratch file) and
    /// `failures<suffix>.jsonl`, each by a rename, under the folder's summary lock. When this
    /// run found jobs `busy` (another run on the folder was doing them) and that run's summary
    /// is there, its results for those jobs replace `busy`, so the last run to finish leaves
    /// one summary of both. On failure: the error and the jobs that are not done.
    fn finish(
        mut self,
        header: &Header,
        out: &Path,
        suffix: &str,
    ) -> Result<Counts, RecordsFailure> {
        use std::io::{BufRead as _, Write as _};
        let summary_path = out.join(format!("summary{suffix}.json"));
        let failures_out = out.join(format!("failures{suffix}.jsonl"));
        let written = (|| {
            self.flush_pending()?;
            self.jobs.flush()?;
            self.failures.flush()?;
            blocked()?;
            // Every file written into the folder stays inside it: none is a link, nor in a
            // folder that is a link to elsewhere.
            let lock_path = out.join(".locks").join(format!("summary{suffix}.lock"));
            common::confine_io(out, &lock_path)?;
            common::confine_io(out, &summary_path)?;
            common::confine_io(out, &failures_out)?;
            let _lock = batch::files::FileLock::take(&lock_path)?;
            let others = if self.counts.busy > 0 { other_results(&summary_path) } else { None };
            let summary_tmp = self.jobs_path.with_extension("summary");
            let mut counts = self.counts;
            // With another run's results: the job lines again, `busy` replaced, and the
            // failures written anew from them.
            let lines: Option<Vec<String>> = match &others {
                Some(others) => {
                    let reader = std::io::BufReader::new(std::fs::File::open(&self.jobs_path)?);
                    let mut lines = Vec::new();
                    let mut failures = String::new();
                    counts = Counts::default();
                    for line in reader.lines() {
                        let line = line?;
                        let Ok(mut r) = serde_json::from_str::<JobResult>(&line) else { continue };
                        if r.status == Status::Busy {
                            if let Some(theirs) = others.get(&(r.line, r.hash.clone())) {
                                let (line_no, id) = (r.line, r.id.clone());
                                r = theirs.clone();
                                r.line = line_no;
                                r.id = id;
                            }
                        }
                        counts.add(&r);
                        let text = serde_json::to_string(&r).unwrap_or_default();
                        if r.status == Status::Failed {
                            failures.push_str(&text);
                            failures.push('\n');
                        }
                        lines.push(text);
                    }
                    std::fs::write(&self.failures_path, failures)?;
                    Some(lines)
                }
                None => None,
            };
            {
                let mut w = std::io::BufWriter::new(std::fs::File::create(&summary_tmp)?);
                writeln!(w, "{{")?;
                writeln!(
                    w,
                    "  \"holoc\": {},",
                    serde_json::json!(crate::build_info::LONG_VERSION)
                )?;
                writeln!(w, "  \"shards\": {},", serde_json::json!(header.shards))?;
                if let Some(m) = &header.manifest {
                    writeln!(w, "  \"manifest\": {},", serde_json::json!(m))?;
                }
                if let Some(u) = &header.base_url {
                    writeln!(w, "  \"base_url\": {},", serde_json::json!(u))?;
                }
                writeln!(w, "  \"done\": {},", counts.done)?;
                writeln!(w, "  \"skipped\": {},", counts.skipped)?;
                writeln!(w, "  \"busy\": {},", counts.busy)?;
                writeln!(w, "  \"failed\": {},", counts.failed)?;
                write!(w, "  \"jobs\": [")?;
                let mut k = 0;
                let mut put = |w: &mut std::io::BufWriter<std::fs::File>, line: &str| {
                    let r = write!(w, "{}\n    {}", if k == 0 { "" } else { "," }, line);
                    k += 1;
                    r
                };
                match &lines {
                    Some(lines) => {
                        for line in lines {
                            put(&mut w, line)?;
                        }
                    }
                    None => {
                        let reader = std::io::BufReader::new(std::fs::File::open(&self.jobs_path)?);
                        for line in reader.lines() {
                            put(&mut w, &line?)?;
                        }
                    }
                }
                writeln!(w, "\n  ]\n}}")?;
                w.flush()?;
            }
            std::fs::rename(&self.failures_path, &failures_out)?;
            std::fs::rename(&summary_tmp, &summary_path)?;
            Ok(counts)
        })();
        written.map_err(|error| RecordsFailure { error, unfinished: self.unfinished })
    }
}

/// The results, by line and job, of the run whose summary is at `path` (another run on the
/// same folder), without its `busy` ones.
fn other_results(path: &Path) -> Option<HashMap<(usize, String), JobResult>> {
    let text = crate::source::read_text(path, common::MAX_INPUT_BYTES).ok()?;
    let summary: Summary = serde_json::from_str(&text).ok()?;
    Some(
        summary
            .jobs
            .into_iter()
            .filter(|j| j.status != Status::Busy)
            .map(|j| ((j.line, j.hash.clone()), j))
            .collect(),
    )
}

fn print_table(summary: &Summary, seconds: f64) {
    let total = summary.done + summary.skipped + summary.busy + summary.failed;
    let rate = if seconds > 0.0 { summary.done as f64 / seconds } else { 0.0 };
    let mut text = format!(
        "| jobs | done | skipped | failed | seconds | built per second |\n|---|---|---|---|---|---|\n| {total} | {} | {} | {} | {seconds:.1} | {rate:.1} |\n",
        summary.done, summary.skipped + summary.busy, summary.failed
    );
    if summary.busy > 0 {
        let _ =
            writeln!(text, "{} of the skipped jobs were being done by another run", summary.busy);
    }
    for job in summary.jobs.iter().filter(|j| j.status == Status::Failed).take(20) {
        let _ = writeln!(
            text,
            "failed: line {} ({}) at {}: {} {}",
            job.line,
            job.id,
            job.stage.as_deref().unwrap_or("?"),
            job.codes.join(" "),
            job.message.as_deref().unwrap_or("")
        );
    }
    common::emit_status(text.trim_end());
}

fn run_merge(args: &MergeArgs) -> ExitCode {
    let mut files: Vec<PathBuf> = Vec::new();
    for path in &args.summaries {
        if path.is_dir() {
            let Ok(entries) = std::fs::read_dir(path) else {
                return usage(&format!("cannot list `{}`", path.display()));
            };
            let mut found: Vec<PathBuf> = entries
                .filter_map(Result::ok)
                .map(|e| e.path())
                .filter(|p| {
                    let name = p.file_name().map(|n| n.to_string_lossy().to_string());
                    name.is_some_and(|n| {
                        n.starts_with("summary")
                            && Path::new(&n)
                                .extension()
                                .is_some_and(|e| e.eq_ignore_ascii_case("json"))
                    })
                })
                .collect();
            found.sort();
            files.extend(found);
        } else {
            files.push(path.clone());
        }
    }
    let mut parts = Vec::new();
    for path in &files {
        let mut sources = crate::source::SourceMap::new();
        let id = match common::read_source(&mut sources, path) {
            Ok(id) => id,
            Err(d) => {
                common::emit_plain(&d);
                return ExitCode::from(2);
            }
        };
        match serde_json::from_str::<Summary>(&sources.get(id).text) {
            Ok(summary) => parts.push(summary),
            Err(e) => return usage(&format!("`{}` is not a batch summary: {e}", path.display())),
        }
    }
    if parts.is_empty() {
        return usage("no summary to merge (`summary*.json` in the folders given)");
    }
    let missing = Summary::missing_shards(&parts);
    if let Some(why) = &missing {
        common::emit_plain(
            &Diagnostic::new(Code::E0008, why.clone())
                .with_help("wait for the missing shards to finish (or run them again), then merge"),
        );
        if !args.partial {
            return ExitCode::from(2);
        }
    }
    let count =
        parts.iter().flat_map(|p| &p.shards).find_map(|s| Shard::parse(s).ok()).map(|s| s.count);
    let manifest = args.manifest.clone().or_else(|| {
        Summary::agreed(&parts, |p| p.manifest.clone()).map(PathBuf::from).filter(|p| p.is_file())
    });
    let base_url = args
        .base_url
        .clone()
        .or_else(|| Summary::agreed(&parts, |p| p.base_url.clone()))
        .unwrap_or_else(|| RunOptions::new(PathBuf::new(), PathBuf::new(), 1, 1).base_url);
    let folders: Vec<PathBuf> = args.summaries.iter().filter(|p| p.is_dir()).cloned().collect();
    let (merged, incomplete) = match &manifest {
        Some(path) => match against_manifest(path, &parts, count, &base_url, &folders) {
            Ok(found) => found,
            Err(code) => return code,
        },
        None => {
            let merged = Summary::merge(parts);
            let incomplete = merged
                .jobs
                .iter()
                .filter(|j| matches!(j.status, Status::Failed | Status::Busy))
                .map(|j| batch::Incomplete {
                    line: j.line,
                    id: j.id.clone(),
                    hash: j.hash.clone(),
                    shard: None,
                    why: why_not_done(j),
                })
                .collect();
            (merged, incomplete)
        }
    };
    if !incomplete.is_empty() {
        let n = incomplete.len();
        let mut d = Diagnostic::new(
            Code::E0811,
            format!(
                "{n} line{} of the manifest {} not done: the merged summary would not cover the manifest",
                if n == 1 { "" } else { "s" },
                if n == 1 { "is" } else { "are" }
            ),
        );
        for i in &incomplete {
            let shard =
                i.shard.as_ref().map_or(String::new(), |s| format!(" (shard {s} runs it now)"));
            d = d.with_note(format!("line {} ({}): {}{shard}", i.line, i.id, i.why));
        }
        if manifest.is_none() {
            d = d.with_note(
                "the manifest is unknown (give `--manifest`): lines in no summary cannot be named",
            );
        }
        emit(&d.with_help(if args.partial {
            "merged anyway (`--partial`): the lines are listed under `incomplete`"
        } else {
            "re-run the shards named (`--shard I/N`), or give `--partial` to merge what there is"
        }));
        if !args.partial {
            return ExitCode::from(1);
        }
    }
    let mut merged = merged;
    merged.incomplete = incomplete;
    let mut json = serde_json::to_string_pretty(&merged).unwrap_or_default();
    json.push('\n');
    if let Err(d) = common::write_output(args.output.as_deref(), &json) {
        common::emit_plain(&d);
        return ExitCode::from(EXIT_RECORDS);
    }
    if !args.quiet {
        print_table(&merged, merged.jobs.iter().map(|j| j.seconds).sum());
    }
    ExitCode::SUCCESS
}

/// Why a recorded job is not done, in words.
fn why_not_done(j: &JobResult) -> String {
    match j.status {
        Status::Busy => "busy (another run was doing it)".to_string(),
        _ => format!(
            "failed at stage `{}` ({}){}",
            j.stage.as_deref().unwrap_or("?"),
            j.codes.join(" "),
            j.message.as_ref().map_or(String::new(), |m| format!(": {m}"))
        ),
    }
}

/// The summaries checked against the manifest as it is now: every line's job by its current
/// identity, found done in some summary (or its folder complete in one of `folders`), else
/// incomplete, with the shard (of `count`) that runs it now. Results are matched by identity,
/// not line, so lines that moved (a line added above) are still found.
fn against_manifest(
    path: &Path,
    parts: &[Summary],
    count: Option<usize>,
    base_url: &str,
    folders: &[PathBuf],
) -> Result<(Summary, Vec<batch::Incomplete>), ExitCode> {
    let mut sources = crate::source::SourceMap::new();
    let file = match common::read_source(&mut sources, path) {
        Ok(f) => f,
        Err(d) => {
            common::emit_plain(&d);
            return Err(ExitCode::from(2));
        }
    };
    let text = &sources.get(file).text;
    let base = path.parent().unwrap_or(Path::new("."));
    let mut best: HashMap<&str, &JobResult> = HashMap::new();
    for j in parts.iter().flat_map(|p| &p.jobs).filter(|j| !j.hash.is_empty()) {
        match best.get(j.hash.as_str()) {
            Some(old) if batch::rank(old.status) >= batch::rank(j.status) => {}
            _ => {
                best.insert(j.hash.as_str(), j);
            }
        }
    }
    let files = batch::FileHashes::default();
    let shard_name = |place: batch::Place| count.map(|n| format!("{}/{n}", place.shard(n)));
    let mut jobs = Vec::new();
    let mut incomplete = Vec::new();
    for (line, raw) in batch::manifest_lines(text) {
        match batch::read_line(line, raw, base) {
            None => {}
            Some(Err(e)) => {
                let hash = batch::line_identity(raw);
                incomplete.push(batch::Incomplete {
                    line,
                    id: e.id.clone().unwrap_or_else(|| format!("line-{line}")),
                    shard: shard_name(batch::Place::of_hash(&hash)),
                    hash: String::new(),
                    why: e.message.clone(),
                });
                jobs.push(batch::manifest_failure(&e));
            }
            Some(Ok(job)) => {
                let hash = batch::job_hash(&job, &files, base_url);
                let place = batch::job_place(&job, &files, base_url);
                let complete = |dir: &PathBuf| dir.join(&hash).join(batch::DONE_MARKER).is_file();
                match best.get(hash.as_str()) {
                    Some(r) if batch::rank(r.status) == 3 => {
                        let mut r = (*r).clone();
                        r.line = line;
                        r.id.clone_from(&job.id);
                        jobs.push(r);
                    }
                    found => {
                        if folders.iter().any(complete) {
                            let mut r = JobResult::of(&job, Status::Skipped);
                            r.hash.clone_from(&hash);
                            r.message = Some("its folder is complete".into());
                            jobs.push(r);
                            continue;
                        }
                        let why = match found {
                            Some(r) => why_not_done(r),
                            None => "in no summary".to_string(),
                        };
                        if let Some(r) = found {
                            let mut r = (*r).clone();
                            r.line = line;
                            r.id.clone_from(&job.id);
                            jobs.push(r);
                        }
                        incomplete.push(batch::Incomplete {
                            line,
                            id: job.id.clone(),
                            shard: shard_name(place),
                            hash,
                            why,
                        });
                    }
                }
            }
        }
    }
    let mut shards: Vec<String> = parts.iter().flat_map(|p| p.shards.clone()).collect();
    shards.sort_by_key(|s| Shard::parse(s).map(|s| (s.count, s.index)).unwrap_or_default());
    shards.dedup();
    let mut merged = Summary::of(jobs, shards);
    merged.manifest = Some(
        std::fs::canonicalize(path)
            .map_or_else(|_| path.display().to_string(), |p| p.display().to_string()),
    );
    merged.base_url = Summary::agreed(parts, |p| p.base_url.clone());
    Ok((merged, incomplete))
}

#[cfg(test)]
mod tests {
    use super::parse_duration;
    use std::time::Duration;

    #[test]
    fn durations_read_with_their_units() {
        assert_eq!(parse_duration("90"), Ok(Duration::from_secs(90)));
        assert_eq!(parse_duration("30m"), Ok(Duration::from_secs(1800)));
        assert_eq!(parse_duration("2h"), Ok(Duration::from_secs(7200)));
        assert_eq!(parse_duration("250ms"), Ok(Duration::from_millis(250)));
        assert!(parse_duration("0").is_err());
        assert!(parse_duration("5 weeks").is_err());
    }
}

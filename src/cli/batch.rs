//! `holoc batch MANIFEST -o OUT`: build or generate every job of a manifest (see
//! [`crate::batch`]); `holoc batch merge`: the shards' summaries as one.

use super::common;
use crate::batch::{self, JobResult, Permits, RunOptions, Shard, Status, Summary};
use indicatif::{ProgressBar, ProgressDrawTarget, ProgressStyle};
use rayon::prelude::*;
use std::fmt::Write as _;
use std::path::{Path, PathBuf};
use std::process::ExitCode;
use std::time::Instant;

/// Arguments of `holoc batch`.
#[derive(Debug, clap::Args)]
#[command(args_conflicts_with_subcommands = true)]
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
    /// Jobs run at once (default: the machine's cores).
    #[arg(long)]
    pub jobs: Option<usize>,
    /// Model requests in flight at once, over all generate jobs.
    #[arg(long, default_value_t = 4)]
    pub llm_concurrency: usize,
    /// Take only the slice I of N of the manifest (jobs whose line number is I modulo N), e.g.
    /// `--shard $SLURM_ARRAY_TASK_ID/$SLURM_ARRAY_TASK_COUNT`.
    #[arg(long, value_parser = Shard::parse)]
    pub shard: Option<Shard>,
    /// Redo jobs whose folder is complete.
    #[arg(long)]
    pub force: bool,
    /// No progress bar and no table.
    #[arg(short, long)]
    pub quiet: bool,
    /// Read inputs and catalogs the manifest names outside its own folder.
    #[arg(long)]
    pub allow_outside: bool,
    /// The server of generate jobs (default: `HOLOC_BASE_URL`, else holoc's default); the API
    /// key is sent there and nowhere else.
    #[arg(long)]
    pub base_url: Option<String>,
    /// Let a job's own `base_url` choose its server (it gets the API key only when it is on
    /// the same host as `--base-url`).
    #[arg(long)]
    pub allow_job_base_url: bool,
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
    /// No table.
    #[arg(short, long)]
    pub quiet: bool,
}

fn usage(message: &str) -> ExitCode {
    common::emit_plain(
        &crate::diag::Diagnostic::new(crate::diag::Code::E0004, message.to_string())
            .with_help("see `holoc batch --help`"),
    );
    ExitCode::from(2)
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
        return usage(&format!("cannot make the output folder `{}`: {e}", out.display()));
    }
    let options = RunOptions {
        out: out.clone(),
        force: args.force,
        llm_concurrency: args.llm_concurrency,
        api_key: ["HOLOC_API_KEY", "OPENAI_API_KEY"]
            .iter()
            .find_map(|name| std::env::var(name).ok().filter(|k| !k.trim().is_empty())),
        catalogs: batch::CatalogCache::default(),
        base_url: args
            .base_url
            .clone()
            .or_else(|| std::env::var("HOLOC_BASE_URL").ok())
            .unwrap_or_else(|| crate::generate::client::DEFAULT_BASE_URL.to_string()),
        allow_job_base_url: args.allow_job_base_url,
    };
    let permits = Permits::new(args.llm_concurrency);
    let threads = args
        .jobs
        .unwrap_or_else(|| std::thread::available_parallelism().map_or(1, usize::from))
        .max(1);
    let pool = match rayon::ThreadPoolBuilder::new()
        .num_threads(threads)
        .stack_size(crate::batch::WORKER_STACK_BYTES)
        .build()
    {
        Ok(pool) => pool,
        Err(e) => return usage(&format!("cannot start {threads} threads: {e}")),
    };
    let in_shard = |line: usize| shard.is_none_or(|s| s.takes(line));
    let total = text
        .lines()
        .enumerate()
        .filter(|(k, raw)| {
            let t = raw.trim();
            in_shard(k + 1) && !t.is_empty() && !t.starts_with('#') && !t.starts_with("//")
        })
        .count();
    let bar = progress(total as u64, args.quiet);
    let started = Instant::now();
    let shards = shard.map(|s| vec![format!("{}/{}", s.index, s.count)]).unwrap_or_default();
    let suffix = shard.map_or(String::new(), |s| format!(".shard-{}-of-{}", s.index, s.count));
    // The results go to a scratch file as they come, chunk by chunk, so that memory does not
    // grow with the manifest; the summary is written from it at the end.
    let mut log = match ResultLog::create(out, &suffix) {
        Ok(log) => log,
        Err(e) => return usage(&format!("cannot write into `{}`: {e}", out.display())),
    };
    let failed_so_far = std::sync::atomic::AtomicUsize::new(0);
    let lines: Vec<(usize, &str)> =
        text.lines().enumerate().map(|(k, l)| (k + 1, l)).filter(|(n, _)| in_shard(*n)).collect();
    for chunk in lines.chunks(CHUNK) {
        let mut results: Vec<JobResult> = pool.install(|| {
            chunk
                .par_iter()
                .filter_map(|&(line, raw)| batch::read_line(line, raw, base))
                .map(|read| {
                    let outside = |job: &batch::Job| {
                        (!args.allow_outside).then(|| batch::outside_folder(job, base)).flatten()
                    };
                    let read = read.and_then(|job| outside(&job).map_or(Ok(job), Err));
                    let result = match read {
                        Ok(mut job) => {
                            job.hash = batch::job_hash(&job);
                            batch::run_job(&job, &options, &permits)
                        }
                        Err(e) => batch::manifest_failure(&e),
                    };
                    if result.status == Status::Failed {
                        failed_so_far.fetch_add(1, std::sync::atomic::Ordering::Relaxed);
                    }
                    bar.set_message(format!(
                        "{} failed",
                        failed_so_far.load(std::sync::atomic::Ordering::Relaxed)
                    ));
                    bar.inc(1);
                    result
                })
                .collect()
        });
        results.sort_by_key(|r| r.line);
        if let Err(e) = log.append(&results) {
            return usage(&format!("cannot write into `{}`: {e}", out.display()));
        }
    }
    bar.finish_and_clear();
    let counts = log.counts;
    if let Err(e) = log.finish(&shards) {
        return usage(&format!("cannot write the summary into `{}`: {e}", out.display()));
    }
    // The scratch folder goes when nothing is left in it (another shard may still use it).
    let _ = std::fs::remove_dir(out.join(".tmp"));
    if !args.quiet {
        let summary = std::fs::read_to_string(out.join(format!("summary{suffix}.json")))
            .ok()
            .and_then(|t| serde_json::from_str::<Summary>(&t).ok())
            .unwrap_or_default();
        print_table(&summary, started.elapsed().as_secs_f64());
    }
    if counts[2] > 0 {
        ExitCode::from(1)
    } else {
        ExitCode::SUCCESS
    }
}

/// Jobs read and run at once; the results of a chunk are written before the next is read.
const CHUNK: usize = 256;

/// The results of a run as they come: job lines in a scratch file, failures in their file,
/// and the counts.
struct ResultLog {
    out: PathBuf,
    suffix: String,
    jobs: std::io::BufWriter<std::fs::File>,
    failures: std::io::BufWriter<std::fs::File>,
    /// Done, skipped, failed.
    counts: [usize; 3],
}

impl ResultLog {
    fn scratch(out: &Path, suffix: &str, what: &str) -> PathBuf {
        out.join(".tmp").join(format!("{what}{suffix}.{}", std::process::id()))
    }

    fn create(out: &Path, suffix: &str) -> std::io::Result<ResultLog> {
        std::fs::create_dir_all(out.join(".tmp"))?;
        let open = |what: &str| {
            std::fs::File::create(Self::scratch(out, suffix, what)).map(std::io::BufWriter::new)
        };
        Ok(ResultLog {
            out: out.to_path_buf(),
            suffix: suffix.to_string(),
            jobs: open("jobs")?,
            failures: open("failures")?,
            counts: [0; 3],
        })
    }

    fn append(&mut self, results: &[JobResult]) -> std::io::Result<()> {
        use std::io::Write as _;
        for r in results {
            let line = serde_json::to_string(r).unwrap_or_default();
            writeln!(self.jobs, "{line}")?;
            let slot = match r.status {
                Status::Done => 0,
                Status::Skipped => 1,
                Status::Failed => 2,
            };
            self.counts[slot] += 1;
            if r.status == Status::Failed {
                writeln!(self.failures, "{line}")?;
            }
        }
        Ok(())
    }

    /// Writes `summary<suffix>.json` (streamed from the scratch file) and
    /// `failures<suffix>.jsonl`, each by a rename.
    fn finish(mut self, shards: &[String]) -> std::io::Result<()> {
        use std::io::{BufRead as _, Write as _};
        self.jobs.flush()?;
        self.failures.flush()?;
        let jobs_path = Self::scratch(&self.out, &self.suffix, "jobs");
        let summary_tmp = Self::scratch(&self.out, &self.suffix, "summary");
        {
            let mut w = std::io::BufWriter::new(std::fs::File::create(&summary_tmp)?);
            writeln!(w, "{{")?;
            writeln!(w, "  \"holoc\": {},", serde_json::json!(env!("CARGO_PKG_VERSION")))?;
            writeln!(w, "  \"shards\": {},", serde_json::json!(shards))?;
            writeln!(w, "  \"done\": {},", self.counts[0])?;
            writeln!(w, "  \"skipped\": {},", self.counts[1])?;
            writeln!(w, "  \"failed\": {},", self.counts[2])?;
            write!(w, "  \"jobs\": [")?;
            let reader = std::io::BufReader::new(std::fs::File::open(&jobs_path)?);
            for (k, line) in reader.lines().enumerate() {
                write!(w, "{}\n    {}", if k == 0 { "" } else { "," }, line?)?;
            }
            writeln!(w, "\n  ]\n}}")?;
            w.flush()?;
        }
        std::fs::rename(&summary_tmp, self.out.join(format!("summary{}.json", self.suffix)))?;
        std::fs::rename(
            Self::scratch(&self.out, &self.suffix, "failures"),
            self.out.join(format!("failures{}.jsonl", self.suffix)),
        )?;
        std::fs::remove_file(jobs_path)
    }
}

fn progress(len: u64, quiet: bool) -> ProgressBar {
    let bar = ProgressBar::with_draw_target(
        Some(len),
        if quiet { ProgressDrawTarget::hidden() } else { ProgressDrawTarget::stderr() },
    );
    if let Ok(style) = ProgressStyle::with_template(
        "{bar:30} {pos}/{len} jobs, {msg}, {per_sec}, {elapsed_precise} (eta {eta})",
    ) {
        bar.set_style(style);
    }
    bar
}

fn print_table(summary: &Summary, seconds: f64) {
    let total = summary.done + summary.skipped + summary.failed;
    let rate = if seconds > 0.0 { summary.done as f64 / seconds } else { 0.0 };
    let mut text = format!(
        "| jobs | done | skipped | failed | seconds | built per second |\n|---|---|---|---|---|---|\n| {total} | {} | {} | {} | {seconds:.1} | {rate:.1} |\n",
        summary.done, summary.skipped, summary.failed
    );
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
    let merged = Summary::merge(parts);
    let mut json = serde_json::to_string_pretty(&merged).unwrap_or_default();
    json.push('\n');
    if let Err(d) = common::write_output(args.output.as_deref(), &json) {
        common::emit_plain(&d);
        return ExitCode::from(2);
    }
    if !args.quiet {
        print_table(&merged, merged.jobs.iter().map(|j| j.seconds).sum());
    }
    if merged.failed > 0 {
        ExitCode::from(1)
    } else {
        ExitCode::SUCCESS
    }
}

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
    let (mut jobs, errors) = batch::read_manifest(&sources.get(file).text, base);
    let shard = args.shard;
    jobs.retain(|j| shard.is_none_or(|s| s.takes(j.line)));
    for job in &mut jobs {
        job.hash = batch::job_hash(job);
    }
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
    };
    let permits = Permits::new(args.llm_concurrency);
    let threads = args
        .jobs
        .unwrap_or_else(|| std::thread::available_parallelism().map_or(1, usize::from))
        .max(1);
    let bar = progress(jobs.len() as u64, args.quiet);
    let started = Instant::now();
    let pool = match rayon::ThreadPoolBuilder::new().num_threads(threads).build() {
        Ok(pool) => pool,
        Err(e) => return usage(&format!("cannot start {threads} threads: {e}")),
    };
    let failed_so_far = std::sync::atomic::AtomicUsize::new(0);
    let mut results: Vec<JobResult> = pool.install(|| {
        jobs.par_iter()
            .map(|job| {
                let result = batch::run_job(job, &options, &permits);
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
    bar.finish_and_clear();
    results.extend(errors.iter().filter(|e| shard.is_none_or(|s| s.takes(e.line))).map(|e| {
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
    }));
    let shards = shard.map(|s| vec![format!("{}/{}", s.index, s.count)]).unwrap_or_default();
    let summary = Summary::of(results, shards);
    let suffix = shard.map_or(String::new(), |s| format!(".shard-{}-of-{}", s.index, s.count));
    if let Err(code) = write_summary(out, &suffix, &summary) {
        return code;
    }
    if !args.quiet {
        print_table(&summary, started.elapsed().as_secs_f64());
    }
    if summary.failed > 0 {
        ExitCode::from(1)
    } else {
        ExitCode::SUCCESS
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

/// Writes `summary<suffix>.json` and `failures<suffix>.jsonl` atomically.
fn write_summary(out: &Path, suffix: &str, summary: &Summary) -> Result<(), ExitCode> {
    let mut json = serde_json::to_string_pretty(summary).unwrap_or_default();
    json.push('\n');
    let mut failures = String::new();
    for job in summary.jobs.iter().filter(|j| j.status == Status::Failed) {
        failures.push_str(&serde_json::to_string(job).unwrap_or_default());
        failures.push('\n');
    }
    for (name, text) in
        [(format!("summary{suffix}.json"), json), (format!("failures{suffix}.jsonl"), failures)]
    {
        if let Err(d) = common::write_atomic(&out.join(name), text.as_bytes()) {
            common::emit_plain(&d);
            return Err(ExitCode::from(2));
        }
    }
    Ok(())
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

//! `holoc generate "REQUEST" -o scene.holo`: ask a model the questions of the pipeline and
//! write the scene, with a transcript of every exchange.

use super::common::{self, ColorChoice};
use crate::diag::{Code, Diagnostic};
use crate::generate::{
    self, GenerateOptions, HttpLlm, HttpOptions, Llm, ModelInfo, Progress, ProgressEvent,
    ReplayLlm, Request, Template,
};
use crate::import::transcript::Transcript;
use crate::source::SourceMap;
use indicatif::{ProgressBar, ProgressStyle};
use std::collections::BTreeMap;
use std::path::{Path, PathBuf};
use std::process::ExitCode;
use std::sync::{Arc, Mutex};
use std::time::Duration;

pub use crate::generate::client::{DEFAULT_BASE_URL, DEFAULT_MODEL};

/// Arguments of `holoc generate`.
#[derive(Debug, clap::Args)]
pub struct GenerateArgs {
    /// The English request, e.g. "a 1b1b apartment of a researcher who has a cat".
    pub request: String,
    /// Where to write the `.holo` scene (stdout when absent or `-`).
    #[arg(short, long)]
    pub output: Option<PathBuf>,
    /// The OpenAI-compatible server, before `/chat/completions` [env: HOLOC_BASE_URL;
    /// default: `https://api.openai.com/v1`].
    #[arg(long)]
    pub base_url: Option<String>,
    /// The model name [env: HOLOC_MODEL; default: gpt-4o].
    #[arg(long)]
    pub model: Option<String>,
    /// Sampling temperature.
    #[arg(long, default_value_t = 0.0)]
    pub temperature: f64,
    /// The scene's seed, also passed to the model.
    #[arg(long, default_value_t = 0)]
    pub seed: u64,
    /// Longest answer in tokens (server default when absent).
    #[arg(long)]
    pub max_tokens: Option<u32>,
    /// Seconds to wait for one answer.
    #[arg(long, default_value_t = 120.0)]
    pub timeout: f64,
    /// How many times a request that failed with 429, 5xx or a timeout is repeated.
    #[arg(long, default_value_t = 3)]
    pub retries: u32,
    /// Milliseconds to wait before the first retry (doubled for each further one).
    #[arg(long, default_value_t = 1000)]
    pub retry_delay_ms: u64,
    /// Longest wait between two tries, in seconds (`Retry-After` included).
    #[arg(long, default_value_t = 30.0)]
    pub max_retry_delay: f64,
    /// How many rooms are asked about at once.
    #[arg(long, short = 'j', default_value_t = 4)]
    pub jobs: usize,
    /// How many times an answer with errors is asked again, with the problems listed.
    #[arg(long, default_value_t = 2)]
    pub repair_rounds: u32,
    /// A folder of prompt templates (`floor_plan.txt`, …) replacing the embedded ones.
    #[arg(long, value_name = "DIR")]
    pub prompts: Option<PathBuf>,
    /// Where to write the transcript (default: `<output>.transcript.json`).
    #[arg(long, value_name = "FILE")]
    pub record: Option<PathBuf>,
    /// Do not write a transcript.
    #[arg(long, conflicts_with = "record")]
    pub no_record: bool,
    /// Answer from a recorded transcript instead of a server (no network).
    #[arg(long, value_name = "FILE")]
    pub replay: Option<PathBuf>,
    /// Ask for a single room.
    #[arg(long)]
    pub single_room: bool,
    /// Skip the small-objects question.
    #[arg(long)]
    pub no_small_objects: bool,
    /// Skip the ceiling question.
    #[arg(long)]
    pub no_ceiling: bool,
    /// Also build the house JSON next to the output: `<output>` with the extension `.json`
    /// (`scene.holo` → `scene.json`), or `<stem>.house.json` when the output already ends in
    /// `.json`. Needs `-o`.
    #[arg(long, requires = "output")]
    pub build: bool,
    /// User asset catalogs and the objathor folder `--build` resolves against.
    #[command(flatten)]
    pub catalogs: super::assets::CatalogArgs,
    /// No progress, no cost summary and no warnings on stderr (errors are still printed).
    #[arg(long, short)]
    pub quiet: bool,
    /// When to colour diagnostics.
    #[arg(long, value_enum, default_value_t = ColorChoice::Auto)]
    pub color: ColorChoice,
}

/// Draws progress on stderr with indicatif.
struct Bar {
    bar: ProgressBar,
    rooms_done: Mutex<BTreeMap<String, usize>>,
}

impl Bar {
    fn new() -> Bar {
        let bar = ProgressBar::new_spinner();
        bar.set_style(
            ProgressStyle::with_template("{spinner} {elapsed:>4} {pos:>3} answers  {msg}")
                .unwrap_or_else(|_| ProgressStyle::default_spinner()),
        );
        bar.enable_steady_tick(Duration::from_millis(120));
        Bar { bar, rooms_done: Mutex::new(BTreeMap::new()) }
    }
}

impl Progress for Bar {
    fn event(&self, event: &ProgressEvent) {
        match event {
            ProgressEvent::StageStarted { .. } => {}
            ProgressEvent::Asking { stage, room, attempt } => {
                // Room names come from the model: escaped like every name on a terminal.
                let room = room
                    .as_ref()
                    .map(|r| format!(" [{}]", crate::diag::visible(r)))
                    .unwrap_or_default();
                let repair =
                    if *attempt > 0 { format!(" (repair {attempt})") } else { String::new() };
                self.bar.set_message(format!("asking {}{room}{repair}", stage.as_str()));
            }
            ProgressEvent::Answered { stage, room, errors, .. } => {
                self.bar.inc(1);
                if let Some(room) = room {
                    let room = crate::diag::visible(room);
                    if let Ok(mut done) = self.rooms_done.lock() {
                        *done.entry(stage.as_str().to_string()).or_default() += 1;
                    }
                    if *errors > 0 {
                        self.bar.println(format!(
                            "  {} [{room}]: {errors} error(s), asking again",
                            stage.as_str()
                        ));
                    }
                } else if *errors > 0 {
                    self.bar
                        .println(format!("  {}: {errors} error(s), asking again", stage.as_str()));
                }
            }
            ProgressEvent::StageFinished { stage } => {
                let rooms = self
                    .rooms_done
                    .lock()
                    .ok()
                    .and_then(|d| d.get(stage.as_str()).copied())
                    .map(|n| format!(" ({n} room(s))"))
                    .unwrap_or_default();
                self.bar.println(format!("  done {}{rooms}", stage.as_str()));
            }
        }
    }
}

fn usage(message: String, help: &str) -> ExitCode {
    common::emit_plain(&Diagnostic::new(Code::E0004, message).with_help(help));
    ExitCode::from(2)
}

#[allow(
    clippy::result_large_err,
    reason = "the error is printed at once; it is rare and never propagated far"
)]
fn read_text(path: &Path) -> Result<String, Diagnostic> {
    let mut sources = SourceMap::new();
    let id = common::read_source(&mut sources, path)?;
    Ok(sources.get(id).text.to_string())
}

fn api_key() -> Option<String> {
    ["HOLOC_API_KEY", "OPENAI_API_KEY"]
        .iter()
        .find_map(|name| std::env::var(name).ok().filter(|k| !k.trim().is_empty()))
        .map(|k| k.trim().to_string())
}

/// The transcript path: `--record`, else `<output>.transcript.json`, else none.
fn record_path(args: &GenerateArgs) -> Option<PathBuf> {
    if args.no_record {
        return None;
    }
    if let Some(p) = &args.record {
        return Some(p.clone());
    }
    let out = args.output.as_ref().filter(|p| p.as_os_str() != "-")?;
    let mut name = out.as_os_str().to_owned();
    name.push(".transcript.json");
    Some(PathBuf::from(name))
}

/// Runs `holoc generate`.
pub fn run(args: &GenerateArgs) -> ExitCode {
    if !(args.timeout.is_finite() && args.timeout > 0.0) {
        return usage(
            format!("`--timeout {}` is not a positive number of seconds", args.timeout),
            "e.g. `--timeout 60`",
        );
    }
    if !(args.max_retry_delay.is_finite() && args.max_retry_delay >= 0.0) {
        return usage(
            format!("`--max-retry-delay {}` is not a number of seconds", args.max_retry_delay),
            "e.g. `--max-retry-delay 30`",
        );
    }
    if !args.temperature.is_finite() {
        return usage("`--temperature` is not a number".to_string(), "e.g. `--temperature 0.2`");
    }
    if args.jobs == 0 {
        return usage("`--jobs 0` would never ask anything".to_string(), "use `--jobs 1` or more");
    }

    // Prompt templates from `--prompts DIR`.
    let mut overrides = BTreeMap::new();
    if let Some(dir) = &args.prompts {
        if !dir.is_dir() {
            return usage(
                format!("`--prompts {}` is not a folder", dir.display()),
                "give a folder holding files such as `floor_plan.txt`",
            );
        }
        for template in Template::ALL {
            let path = dir.join(template.file_name());
            if path.is_file() {
                match read_text(&path) {
                    Ok(text) => {
                        overrides.insert(template, (path.display().to_string(), text));
                    }
                    Err(d) => {
                        common::emit_plain(&d);
                        return ExitCode::from(2);
                    }
                }
            }
        }
    }

    // The model: a server or a recorded transcript.
    let http;
    let replay;
    let llm: &dyn Llm = if let Some(path) = &args.replay {
        let text = match read_text(path) {
            Ok(t) => t,
            Err(d) => {
                common::emit_plain(&d);
                return ExitCode::from(2);
            }
        };
        let transcript: Transcript = match serde_json::from_str(&text) {
            Ok(t) => t,
            Err(e) => {
                return usage(
                    format!("`{}` is not a holoc transcript: {e}", path.display()),
                    "give a file written by `holoc generate --record`",
                )
            }
        };
        let model = transcript.model.clone().unwrap_or_default();
        replay = ReplayLlm::new(
            generate::recorded_answers(&transcript),
            ModelInfo {
                base_url: format!("replay:{}", path.display()),
                model: model.model,
                temperature: model.temperature,
                parameters: BTreeMap::new(),
            },
        );
        &replay
    } else if !cfg!(feature = "generate") {
        return usage(
            "this holoc was built without its `generate` feature: it cannot ask a model".into(),
            "install holoc with its default features (`cargo install --locked --path .`); \
             `--replay` runs a recorded transcript without it",
        );
    } else {
        let base_url = args
            .base_url
            .clone()
            .or_else(|| std::env::var("HOLOC_BASE_URL").ok())
            .unwrap_or_else(|| DEFAULT_BASE_URL.to_string());
        let model = args
            .model
            .clone()
            .or_else(|| std::env::var("HOLOC_MODEL").ok())
            .unwrap_or_else(|| DEFAULT_MODEL.to_string());
        let mut options = HttpOptions::new(base_url, model);
        options.api_key = api_key();
        options.temperature = args.temperature;
        options.seed = Some(args.seed);
        options.max_tokens = args.max_tokens;
        options.timeout = Duration::from_secs_f64(args.timeout);
        options.retries = args.retries;
        options.base_delay = Duration::from_millis(args.retry_delay_ms);
        options.max_delay = Duration::from_secs_f64(args.max_retry_delay);
        http = HttpLlm::new(options);
        &http
    };

    let bar = (!args.quiet).then(|| Arc::new(Bar::new()));
    let options = GenerateOptions {
        jobs: args.jobs,
        repair_rounds: args.repair_rounds,
        prompt_overrides: overrides,
        single_room: args.single_room,
        small_objects: !args.no_small_objects,
        ceiling: !args.no_ceiling,
        progress: bar.clone().map(|b| b as Arc<dyn Progress + Send>),
    };
    let request = Request { text: args.request.clone(), seed: args.seed };
    let outcome = generate::generate(&request, llm, &options);
    if let Some(bar) = &bar {
        bar.bar.finish_and_clear();
    }
    let generated = &outcome.value;

    let mut io_failed = false;
    if let Some(path) = record_path(args).filter(|_| !generated.transcript.exchanges.is_empty()) {
        match serde_json::to_string_pretty(&generated.transcript) {
            Ok(mut json) => {
                json.push('\n');
                if let Err(d) = common::write_atomic(&path, json.as_bytes()) {
                    common::emit_plain(&d);
                    io_failed = true;
                }
            }
            Err(e) => {
                common::emit_plain(&Diagnostic::internal(format!(
                    "cannot serialize the transcript: {e}"
                )));
                io_failed = true;
            }
        }
    }
    // A run with errors never replaces the user's files: its scene goes beside them.
    let failed = outcome.diagnostics.iter().any(Diagnostic::is_error);
    let mut written_to: Option<PathBuf> = None;
    if !generated.holo.is_empty() {
        let target = match args.output.as_deref() {
            Some(p) if p.as_os_str() != "-" && failed => Some(partial_path(p)),
            Some(p) if p.as_os_str() != "-" => Some(p.to_path_buf()),
            _ => None,
        };
        if let Err(d) = common::write_output(target.as_deref(), &generated.holo) {
            common::emit_plain(&d);
            io_failed = true;
        } else {
            written_to = target;
        }
    }
    let shown: Vec<Diagnostic> =
        outcome.diagnostics.iter().filter(|d| !args.quiet || d.is_error()).cloned().collect();
    common::emit(&generated.sources, &shown, common::DiagFormat::Human, args.color);
    if let (true, Some(out), Some(partial)) = (failed, args.output.as_deref(), &written_to) {
        common::err(&format!(
            "the run had errors: `{}` is left as it was; the scene so far is in `{}`\n",
            out.display(),
            partial.display()
        ));
    }
    if !args.quiet {
        // Model calls and local (geometric) repairs are counted apart: a repair asks no model.
        let repairs = |n: u64| {
            if n == 0 {
                String::new()
            } else {
                format!(", {n} local repair(s)")
            }
        };
        for cost in &generated.costs {
            common::err(&format!(
                "{:>18}: {:>2} call(s), {:>6} prompt + {:>5} answer tokens, {:>6.1} s{}\n",
                cost.stage,
                cost.calls,
                cost.prompt_tokens,
                cost.completion_tokens,
                cost.seconds.abs(),
                repairs(cost.repairs)
            ));
        }
        if let Some(t) = &generated.transcript.totals {
            common::err(&format!(
                "{:>18}: {:>2} call(s), {:>6} prompt + {:>5} answer tokens, {:>6.1} s{}\n",
                "total",
                t.calls,
                t.prompt_tokens,
                t.completion_tokens,
                t.seconds.abs(),
                repairs(generated.costs.iter().map(|c| c.repairs).sum())
            ));
        }
    }
    let mut build_failed = false;
    if args.build && !generated.holo.is_empty() && !failed {
        build_failed = !build_house(
            &generated.holo,
            args.output.as_deref(),
            &args.catalogs,
            args.color,
            args.quiet,
        );
    }
    let model_failed = outcome.diagnostics.iter().any(|d| {
        matches!(
            d.code,
            Code::E0803
                | Code::E0804
                | Code::E0805
                | Code::E0806
                | Code::E0807
                | Code::E0808
                | Code::E0810
        )
    });
    if io_failed || model_failed {
        return ExitCode::from(2);
    }
    if build_failed {
        return ExitCode::from(1);
    }
    common::exit_for(&outcome.diagnostics)
}

/// Where a failed run puts its scene: `<stem>.partial.holo` beside the output.
fn partial_path(output: &std::path::Path) -> PathBuf {
    let stem =
        output.file_stem().map_or_else(|| "scene".into(), |s| s.to_string_lossy().into_owned());
    output.with_file_name(format!("{stem}.partial.holo"))
}

/// Where `--build` puts the house: the output with the extension `.json`, or
/// `<stem>.house.json` when the output already ends in `.json` (never the scene itself).
pub fn house_path(output: &std::path::Path) -> PathBuf {
    let stem =
        output.file_stem().map_or_else(|| "scene".into(), |s| s.to_string_lossy().into_owned());
    if output.extension().is_some_and(|e| e.eq_ignore_ascii_case("json")) {
        output.with_file_name(format!("{stem}.house.json"))
    } else {
        output.with_extension("json")
    }
}

/// `--build`: compiles the generated scene and writes the house next to the output (see
/// [`house_path`]). Returns whether it worked.
fn build_house(
    holo: &str,
    output: Option<&std::path::Path>,
    catalogs: &super::assets::CatalogArgs,
    color: ColorChoice,
    quiet: bool,
) -> bool {
    let mut sources = crate::source::SourceMap::new();
    let loaded = catalogs.load(&mut sources);
    if loaded.has_errors() {
        common::emit(&sources, &loaded.diagnostics, common::DiagFormat::Human, color);
        return false;
    }
    let catalog = loaded.value;
    let name = output.map_or_else(|| "<generated>.holo".to_string(), |p| p.display().to_string());
    let file = sources.add(name, holo.to_string());
    let options = crate::compile::BuildOptions::new(&catalog);
    let mut built = crate::compile::build(&sources, file, &options);
    built.diagnostics.splice(0..0, loaded.diagnostics);
    if let Some(product) = &built.value {
        built.diagnostics.extend(crate::resolve::objathor::check_on_disk(
            &catalog,
            product.objects.iter().map(|o| o.asset_id.as_str()),
            &|_| None,
        ));
    }
    let failed = built.diagnostics.iter().any(Diagnostic::is_error);
    let shown: Vec<Diagnostic> =
        built.diagnostics.iter().filter(|d| !quiet || d.is_error()).cloned().collect();
    common::emit(&sources, &shown, common::DiagFormat::Human, color);
    let Some(product) = built.value.filter(|_| !failed) else { return false };
    let Some(output) = output.filter(|p| p.as_os_str() != "-") else {
        common::emit_plain(&Diagnostic::new(
            Code::E0004,
            "`--build` needs `-o FILE` to know where the house goes",
        ));
        return false;
    };
    let path = house_path(output);
    match common::write_atomic(&path, product.house.to_json_string().as_bytes()) {
        Ok(()) => true,
        Err(d) => {
            common::emit_plain(&d);
            false
        }
    }
}

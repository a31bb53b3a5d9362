//! `holoc diff A B`: what changed between two houses, two scenes (built with their seeds) or
//! two folders of houses (paired by job), as a list grouped by room, within tolerances.
//!
//! Exit status: 0 the same within the tolerances, 1 different, 2 an input could not be read or
//! built (or bad usage).

use super::common::{self, ColorChoice, DiagFormat};
use crate::compile::BuildOptions;
use crate::diag::{Code, Diagnostic};
use crate::diff::{self, folder, Diff, Group, HouseView, Options, Tolerance};
use crate::resolve::Catalog;
use crate::source::SourceMap;
use clap::ValueEnum;
use std::collections::BTreeMap;
use std::fmt::Write as _;
use std::path::{Path, PathBuf};
use std::process::ExitCode;

/// How `holoc diff` and `holoc test` print.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, ValueEnum)]
pub enum DiffFormat {
    /// The changes grouped by room, and a summary line.
    #[default]
    Human,
    /// One JSON document for tools.
    Json,
}

/// Arguments of `holoc diff`.
#[derive(Debug, clap::Args)]
pub struct DiffArgs {
    /// The first house: a house JSON file, a `.holo` scene or a folder of houses.
    pub first: PathBuf,
    /// The second house, of the same kind.
    pub second: PathBuf,
    /// The build reports of the two houses (give it twice: the first's, then the second's);
    /// relations are compared when both houses have one. A house `NAME.house.json` or
    /// `house.json` finds its `NAME.report.json` or `report.json` beside it by itself.
    #[arg(long, value_name = "FILE")]
    pub report: Vec<PathBuf>,
    /// How far a length or angle may differ and still be the same, e.g. `1cm,1deg`, `5mm`.
    #[arg(long, default_value = "1cm,1deg", value_parser = Tolerance::parse)]
    pub tolerance: Tolerance,
    /// Groups of fields to leave out, e.g. `--ignore materials,lights`.
    #[arg(long, value_enum, value_delimiter = ',')]
    pub ignore: Vec<Group>,
    /// How to print the differences.
    #[arg(long, value_enum, default_value_t = DiffFormat::Human)]
    pub format: DiffFormat,
    /// For folders: one line per house that differs, and the totals.
    #[arg(long)]
    pub stat: bool,
    /// Houses compared at once for folders (default: the number of cores).
    #[arg(long, short = 'j')]
    pub jobs: Option<usize>,
    /// User asset catalogs, for `.holo` scenes.
    #[command(flatten)]
    pub catalogs: super::assets::CatalogArgs,
    /// How to print the diagnostics of scenes that do not build.
    #[arg(long = "diagnostics", value_enum, default_value_t = DiagFormat::Human)]
    pub diagnostics: DiagFormat,
    /// When to colour human diagnostics.
    #[arg(long, value_enum, default_value_t = ColorChoice::Auto)]
    pub color: ColorChoice,
}

/// The report beside a house file: `NAME.report.json` for `NAME.house.json` or `NAME.json`,
/// `report.json` for `house.json`.
pub(crate) fn report_beside(house: &Path) -> Option<PathBuf> {
    let name = house.file_name()?.to_str()?;
    let report = if name == "house.json" {
        "report.json".to_string()
    } else {
        let stem = name.strip_suffix(".json")?;
        format!("{}.report.json", stem.strip_suffix(".house").unwrap_or(stem))
    };
    Some(house.with_file_name(report)).filter(|p| p.is_file())
}

/// A scene built for comparing: its house JSON text, its report and the view the diff reads.
pub(crate) struct BuiltScene {
    pub house_json: String,
    pub report_json: String,
    pub view: HouseView,
    /// The assets holoc made for it.
    pub made: Vec<std::sync::Arc<crate::make::MadeAsset>>,
}

/// Builds a `.holo` scene with its own seed. On failure, the diagnostics (printed by the
/// caller).
pub(crate) fn build_scene(
    sources: &mut SourceMap,
    path: &Path,
    catalog: &Catalog,
) -> Result<BuiltScene, Vec<Diagnostic>> {
    let file = common::read_source(sources, path).map_err(|d| vec![d])?;
    build_file(sources, file, catalog)
}

/// Builds a scene already in `sources`, as [`build_scene`] does.
fn build_file(
    sources: &mut SourceMap,
    file: crate::source::FileId,
    catalog: &Catalog,
) -> Result<BuiltScene, Vec<Diagnostic>> {
    let built = crate::compile::build(sources, file, &BuildOptions::new(catalog));
    let errors: Vec<Diagnostic> =
        built.diagnostics.into_iter().filter(Diagnostic::is_error).collect();
    let Some(product) = built.value.filter(|_| errors.is_empty()) else {
        return Err(errors);
    };
    let house_json = product.house.to_json_string();
    let mut report = crate::report::report(&product, catalog);
    // No absolute path in a golden report: paths relative to the project (the folder of
    // `holoc.toml`, else the current folder).
    let base = super::assets::project_file()
        .and_then(|p| p.parent().map(Path::to_path_buf))
        .or_else(|| std::env::current_dir().ok())
        .unwrap_or_default();
    crate::report::portable_paths(&mut report, &base);
    let mut report_json = serde_json::to_string_pretty(&report).unwrap_or_default();
    report_json.push('\n');
    let value: serde_json::Value = serde_json::from_str(&house_json).map_err(|e| {
        vec![Diagnostic::new(Code::E0002, format!("the built house is not JSON: {e}"))]
    })?;
    let mut view = HouseView::read(&value).map_err(|e| vec![Diagnostic::new(Code::E0002, e)])?;
    view.add_report(&report).map_err(|e| vec![Diagnostic::new(Code::E0002, e)])?;
    let made = crate::make::used_in(
        &product.resolved,
        product.objects.iter().map(|o| o.asset_id.as_str()),
    );
    Ok(BuiltScene { house_json, report_json, view, made })
}

fn is_scene(path: &Path) -> bool {
    path.extension().is_some_and(|e| e == "holo")
}

/// Runs `holoc diff`.
pub fn run(args: &DiffArgs) -> ExitCode {
    let options = Options { tolerance: args.tolerance, ignore: args.ignore.clone() };
    if args.report.len() > 2 {
        return usage("give `--report` at most twice: the first house's report, then the second's");
    }
    let stdin = |p: &Path| p.as_os_str() == "-";
    if stdin(&args.first) && stdin(&args.second) {
        return usage(
            "standard input (`-`) can be only one of the two sides; write the other to a file",
        );
    }
    let (a_dir, b_dir) = (args.first.is_dir(), args.second.is_dir());
    if a_dir != b_dir {
        return usage("compare a folder with a folder, or a house or scene with a house or scene");
    }
    if a_dir {
        if !args.report.is_empty() {
            return usage(
                "`--report` is for two houses; the houses of a folder bring their own reports",
            );
        }
        return run_folders(args, &options);
    }
    let mut sources = SourceMap::new();
    let mut catalog = None;
    // Standard input is read once, here, and is a house when it begins with `{`, else a scene.
    let mut piped = None;
    for side in [&args.first, &args.second] {
        if stdin(side) {
            match common::read_source(&mut sources, side) {
                Ok(file) => piped = Some(file),
                Err(d) => {
                    common::emit_plain(&d);
                    return ExitCode::from(2);
                }
            }
        }
    }
    let piped_house = piped.filter(|f| sources.get(*f).text.trim_start().starts_with('{'));
    let mut load = |path: &Path, report: Option<&PathBuf>| -> Result<HouseView, ExitCode> {
        if let (true, Some(file)) = (stdin(path), piped_house) {
            let view = serde_json::from_str::<serde_json::Value>(&sources.get(file).text)
                .map_err(|e| format!("the input is not valid JSON: {e}"))
                .and_then(|value| HouseView::read(&value));
            let mut view = match view {
                Ok(v) => v,
                Err(why) => {
                    common::emit_plain(
                        &Diagnostic::new(Code::E0601, format!("`<stdin>` is not a house: {why}"))
                            .with_help("pipe an AI2-THOR house JSON file or a `.holo` scene"),
                    );
                    return Err(ExitCode::from(2));
                }
            };
            if let Some(r) = report {
                if let Err(d) = folder::add_report(&mut view, r) {
                    common::emit_plain(&d);
                    return Err(ExitCode::from(2));
                }
            }
            return Ok(view);
        }
        if is_scene(path) || (stdin(path) && piped.is_some()) {
            if catalog.is_none() {
                let loaded = args.catalogs.load(&mut sources);
                if loaded.has_errors() {
                    common::emit(&sources, &loaded.diagnostics, args.diagnostics, args.color);
                    return Err(ExitCode::from(2));
                }
                catalog = Some(loaded.value);
            }
            let catalog = catalog.as_ref().unwrap_or_else(|| unreachable!("loaded just above"));
            let built = match piped.filter(|_| stdin(path)) {
                Some(file) => build_file(&mut sources, file, catalog),
                None => build_scene(&mut sources, path, catalog),
            };
            match built {
                Ok(mut built) => {
                    if let Some(r) = report {
                        // An explicit report replaces the scene's own.
                        built.view.relations = None;
                        built.view.metadata.retain(|(k, _)| k != "request" && k != "seed");
                        if let Err(d) = folder::add_report(&mut built.view, r) {
                            common::emit_plain(&d);
                            return Err(ExitCode::from(2));
                        }
                    }
                    Ok(built.view)
                }
                Err(diagnostics) => {
                    common::emit(&sources, &diagnostics, args.diagnostics, args.color);
                    Err(ExitCode::from(2))
                }
            }
        } else {
            let report = report.cloned().or_else(|| report_beside(path));
            folder::load(path, report.as_deref()).map_err(|d| {
                common::emit_plain(&d);
                ExitCode::from(2)
            })
        }
    };
    let a = match load(&args.first, args.report.first()) {
        Ok(h) => h,
        Err(code) => return code,
    };
    let b = match load(&args.second, args.report.get(1)) {
        Ok(h) => h,
        Err(code) => return code,
    };
    let d = diff::diff(&a, &b, &options);
    match args.format {
        DiffFormat::Json => {
            let mut text = serde_json::to_string_pretty(&diff::to_json(&d)).unwrap_or_default();
            text.push('\n');
            common::out(&text);
        }
        DiffFormat::Human => say(&human(&d, args.stat, args.tolerance)),
    }
    if d.is_empty() {
        ExitCode::SUCCESS
    } else {
        ExitCode::from(1)
    }
}

/// Prints human text on stdout with its control characters escaped (`diag::visible`): ids,
/// names and paths come from the houses and must not move the cursor or retitle the window.
fn say(text: &str) {
    common::out(&crate::diag::visible(text));
}

/// The text of one diff: the changes (unless `stat`) and the summary line.
pub(crate) fn human(d: &Diff, stat: bool, tolerance: Tolerance) -> String {
    if d.is_empty() {
        return format!("no differences (within {tolerance})\n");
    }
    let mut text = if stat { String::new() } else { d.render() };
    text.push_str(&d.summary());
    text.push('\n');
    text
}

fn usage(message: &str) -> ExitCode {
    common::emit_plain(&Diagnostic::new(Code::E0004, message.to_string()));
    ExitCode::from(2)
}

/// Two folders: paired by name, compared a chunk at a time, printed in name order.
fn run_folders(args: &DiffArgs, options: &Options) -> ExitCode {
    let read = |p: &Path| {
        folder::entries(p).map_err(|e| {
            common::emit_plain(&Diagnostic::new(
                Code::E0001,
                format!("cannot read the folder `{}`: {e}", p.display()),
            ));
            ExitCode::from(2)
        })
    };
    let a = match read(&args.first) {
        Ok(e) => e,
        Err(code) => return code,
    };
    let b = match read(&args.second) {
        Ok(e) => e,
        Err(code) => return code,
    };
    let threads = args.jobs.unwrap_or(0);
    let pool = match rayon::ThreadPoolBuilder::new().num_threads(threads).build() {
        Ok(p) => p,
        Err(e) => return usage(&format!("cannot start the worker threads: {e}")),
    };
    let mut tally = Tally::default();
    let json = args.format == DiffFormat::Json;
    if json {
        common::out("{\n  \"version\": 1,\n  \"houses\": [");
    }
    let mut first = true;
    pool.install(|| {
        folder::compare(&a, &b, options, 64, |paired| {
            let status = tally.add(&paired.outcome);
            if json {
                let mut entry = serde_json::json!({"name": paired.key, "status": status});
                match &paired.outcome {
                    folder::Outcome::Changed(d) => {
                        entry["summary"] = d.summary().into();
                        if !args.stat {
                            entry["changes"] = serde_json::to_value(&d.changes).unwrap_or_default();
                        }
                    }
                    folder::Outcome::Error(e) => entry["message"] = e.message.clone().into(),
                    _ => {}
                }
                if paired.outcome != folder::Outcome::Same || !args.stat {
                    let sep = if first { "\n    " } else { ",\n    " };
                    first = false;
                    common::out(&format!(
                        "{sep}{}",
                        serde_json::to_string(&entry).unwrap_or_default()
                    ));
                }
                return;
            }
            match &paired.outcome {
                folder::Outcome::Same => {}
                folder::Outcome::Changed(d) if args.stat => {
                    say(&format!("{}: {}\n", paired.key, d.summary()));
                }
                folder::Outcome::Changed(d) => {
                    say(&format!("== {}\n{}", paired.key, human(d, false, args.tolerance)));
                }
                folder::Outcome::OnlyFirst => {
                    say(&format!("{}: only in {}\n", paired.key, args.first.display()));
                }
                folder::Outcome::OnlySecond => {
                    say(&format!("{}: only in {}\n", paired.key, args.second.display()));
                }
                folder::Outcome::Error(e) => common::emit_plain(e),
            }
        });
    });
    if json {
        let counts: BTreeMap<String, usize> = tally
            .kinds
            .iter()
            .map(|(k, n)| {
                (
                    serde_json::to_value(k)
                        .ok()
                        .and_then(|v| v.as_str().map(str::to_string))
                        .unwrap_or_default(),
                    *n,
                )
            })
            .collect();
        let totals = serde_json::json!({
            "total": tally.total, "same": tally.same, "changed": tally.changed,
            "only_first": tally.only_first, "only_second": tally.only_second,
            "errors": tally.errors, "summary": diff::summary_of(&tally.kinds), "counts": counts,
        });
        let closing = if first { "],\n" } else { "\n  ],\n" };
        common::out(&format!(
            "{closing}  \"totals\": {}\n}}\n",
            serde_json::to_string(&totals).unwrap_or_default()
        ));
    } else {
        common::out(&format!("{}\n", tally.line()));
    }
    if tally.errors > 0 {
        ExitCode::from(2)
    } else if tally.same == tally.total {
        ExitCode::SUCCESS
    } else {
        ExitCode::from(1)
    }
}

/// The counts of a folder diff.
#[derive(Default)]
struct Tally {
    total: usize,
    same: usize,
    changed: usize,
    only_first: usize,
    only_second: usize,
    errors: usize,
    kinds: BTreeMap<diff::Kind, usize>,
}

impl Tally {
    fn add(&mut self, outcome: &folder::Outcome) -> &'static str {
        self.total += 1;
        match outcome {
            folder::Outcome::Same => {
                self.same += 1;
                "same"
            }
            folder::Outcome::Changed(d) => {
                self.changed += 1;
                for (k, n) in d.counts() {
                    *self.kinds.entry(k).or_insert(0) += n;
                }
                "changed"
            }
            folder::Outcome::OnlyFirst => {
                self.only_first += 1;
                "only_first"
            }
            folder::Outcome::OnlySecond => {
                self.only_second += 1;
                "only_second"
            }
            folder::Outcome::Error(_) => {
                self.errors += 1;
                "error"
            }
        }
    }

    fn line(&self) -> String {
        let mut parts = vec![format!("{} changed", self.changed)];
        if self.only_first > 0 {
            parts.push(format!("{} only in the first", self.only_first));
        }
        if self.only_second > 0 {
            parts.push(format!("{} only in the second", self.only_second));
        }
        if self.errors > 0 {
            parts.push(format!("{} unreadable", self.errors));
        }
        let mut line = format!(
            "{} of {} houses differ: {}",
            self.total - self.same,
            self.total,
            parts.join(", ")
        );
        if !self.kinds.is_empty() {
            let _ = write!(line, " ({})", diff::summary_of(&self.kinds));
        }
        line
    }
}

//! `holoc test [PATHS…]`: golden-file tests of scenes. Each `.holo` scene is built with its
//! seed and compared, through the same semantic diff as `holoc diff`, with its golden house
//! (`NAME.house.json` beside it, or under the golden folder that the `[test]` table of
//! `holoc.toml` names) and, when there is one, its golden report (`NAME.report.json`, for the
//! relations). Prints like `cargo test`; `--bless` writes the goldens of the failing and new
//! scenes (atomically, only those), `--review` asks for each one; `--format junit` writes a
//! JUnit XML report for CI.
//!
//! Exit status: 0 every scene matches its golden (or was blessed), 1 a scene differs, has no
//! golden, has a golden that is not a valid house, or does not build, 2 bad usage or I/O.

use super::common::{self, ColorChoice};
use super::diff::{build_scene, BuiltScene};
use crate::diag::format::HumanOptions;
use crate::diag::{Code, Diagnostic};
use crate::diff::{self, Diff, Group, Options, Tolerance};
use crate::resolve::structure::StructureCatalog;
use crate::resolve::Catalog;
use crate::source::SourceMap;
use clap::ValueEnum;
use rayon::prelude::*;
use std::fmt::Write as _;
use std::io::BufRead as _;
use std::path::{Path, PathBuf};
use std::process::ExitCode;

/// How `holoc test` prints its results.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, ValueEnum)]
pub enum TestFormat {
    /// Like `cargo test`: a line per scene, the failures, a summary line.
    #[default]
    Human,
    /// A JUnit XML report (what GitLab, Jenkins and GitHub test reporters read).
    Junit,
    /// One JSON document for tools.
    Json,
}

/// Arguments of `holoc test`.
#[derive(Debug, clap::Args)]
pub struct TestArgs {
    /// Scenes, or folders searched for `.holo` scenes (default: the `scenes` of the `[test]`
    /// table of `holoc.toml`, else the current folder).
    pub paths: Vec<PathBuf>,
    /// Write the goldens of the failing and new scenes (atomically, only those).
    #[arg(long, conflicts_with = "review")]
    pub bless: bool,
    /// Show each difference and ask whether to accept it as the new golden.
    #[arg(long)]
    pub review: bool,
    /// With `--review`: read the answers (`y` or `n`, one a line, in the order of the scenes
    /// shown) from this file instead of asking.
    #[arg(long, value_name = "FILE", requires = "review")]
    pub answers: Option<PathBuf>,
    /// With `--bless` or `--review`: also write a golden report (relations) for scenes that
    /// have none.
    #[arg(long)]
    pub reports: bool,
    /// Scenes built at once (default: the number of cores).
    #[arg(long, short = 'j')]
    pub jobs: Option<usize>,
    /// How to print the results.
    #[arg(long, value_enum, default_value_t = TestFormat::Human)]
    pub format: TestFormat,
    /// How far a length or angle may differ (default: `holoc.toml`'s, else `1cm,1deg`).
    #[arg(long, value_parser = Tolerance::parse)]
    pub tolerance: Option<Tolerance>,
    /// Groups of fields to leave out (added to `holoc.toml`'s `ignore`).
    #[arg(long, value_enum, value_delimiter = ',')]
    pub ignore: Vec<Group>,
    /// User asset catalogs (added to `holoc.toml`'s `catalogs`).
    #[command(flatten)]
    pub catalogs: super::assets::CatalogArgs,
    /// When to colour the diagnostics of scenes that do not build.
    #[arg(long, value_enum, default_value_t = ColorChoice::Never)]
    pub color: ColorChoice,
}

/// The `holoc.toml` settings `holoc test` reads.
#[derive(Debug, Default, serde::Deserialize)]
#[serde(deny_unknown_fields)]
struct Config {
    /// Catalogs every command of the project uses (relative to the file's folder).
    #[serde(default)]
    catalogs: Vec<PathBuf>,
    /// The objathor folder every command of the project uses (relative to the file's folder),
    /// and how it is used.
    objathor: Option<PathBuf>,
    /// The version folder under `objathor`.
    objathor_version: Option<String>,
    /// `lexical`, `features` or `clip`.
    objathor_scoring: Option<String>,
    /// `objathor-first` (the default), `builtin-first` or `score`.
    objathor_mix: Option<String>,
    /// `argmax` or `seeded`.
    objathor_pick: Option<String>,
    /// The CLIP text tower's weights folder of the `clip` mode.
    objathor_clip: Option<PathBuf>,
    /// The `[test]` table.
    #[serde(default)]
    test: TestConfig,
}

/// The `[test]` table of `holoc.toml`.
#[derive(Debug, Default, serde::Deserialize)]
#[serde(deny_unknown_fields)]
struct TestConfig {
    /// What to test when no path is given.
    #[serde(default)]
    scenes: Vec<PathBuf>,
    /// The folder of the goldens: `scenes/bedroom.holo`'s golden is
    /// `<goldens>/scenes/bedroom.house.json`. Beside each scene when absent.
    goldens: Option<PathBuf>,
    /// The tolerances, e.g. `"1cm,1deg"`.
    tolerance: Option<String>,
    /// Groups of fields left out.
    #[serde(default)]
    ignore: Vec<String>,
}

/// The `holoc.toml` of the current folder or the nearest folder above it, with its folder.
#[allow(
    clippy::result_large_err,
    reason = "the error is printed at once; it is rare and never propagated far"
)]
fn read_config() -> Result<Option<(PathBuf, Config)>, Diagnostic> {
    let cwd = std::env::current_dir().unwrap_or_else(|_| PathBuf::from("."));
    let Some(path) = cwd.ancestors().map(|d| d.join("holoc.toml")).find(|p| p.is_file()) else {
        return Ok(None);
    };
    let text = common::read_text(&path)?;
    let config: Config = toml::from_str(&text).map_err(|e| {
        Diagnostic::new(Code::E0004, format!("`{}` is not usable: {e}", path.display()))
            .with_help("see `holoc test` in the book for the `[test]` table")
    })?;
    let dir = path.parent().map_or_else(|| PathBuf::from("."), Path::to_path_buf);
    Ok(Some((dir, config)))
}

/// One scene under test and where its goldens are.
#[derive(Clone, Debug)]
struct Case {
    /// The scene, as shown.
    scene: PathBuf,
    /// The folder its goldens must stay in (the folder given, or that of `holoc.toml`).
    root: PathBuf,
    /// Its golden house.
    golden: PathBuf,
    /// Its golden report.
    report: PathBuf,
}

/// How a scene's test ended.
enum Status {
    /// The same as its golden.
    Ok,
    /// Different from its golden.
    Failed(Diff),
    /// No golden yet.
    New,
    /// The golden is not a valid house (or report): the diagnostics.
    Invalid(SourceMap, Vec<Diagnostic>),
    /// The scene does not build: the diagnostics.
    Broken(SourceMap, Vec<Diagnostic>),
}

/// One scene's test, as run.
struct TestResult {
    case: Case,
    status: Status,
    built: Option<BuiltScene>,
    /// Whether its goldens were written by this run.
    blessed: bool,
    /// Whether a review rejected its new house (no pending golden is kept).
    rejected: bool,
}

fn usage(d: &Diagnostic) -> ExitCode {
    common::emit_plain(d);
    ExitCode::from(2)
}

/// The `.holo` files under a path (the path itself for a file), sorted, skipping hidden
/// folders and `target`. Links are followed only to what lies inside the folder given, and a
/// folder is searched once however many links lead to it (`a -> .` and `b -> .` end); a link
/// to a scene outside is refused (E0009, in `refused`), a link to a folder outside is left.
fn scenes_under(
    path: &Path,
    out: &mut Vec<PathBuf>,
    refused: &mut Vec<Diagnostic>,
) -> std::io::Result<()> {
    let meta = std::fs::metadata(path)?;
    if !meta.is_dir() {
        out.push(path.to_path_buf());
        return Ok(());
    }
    let root = std::fs::canonicalize(path)?;
    let mut seen = std::collections::BTreeSet::from([root.clone()]);
    walk_scenes(path, &root, &mut seen, out, refused)
}

fn walk_scenes(
    dir: &Path,
    root: &Path,
    seen: &mut std::collections::BTreeSet<PathBuf>,
    out: &mut Vec<PathBuf>,
    refused: &mut Vec<Diagnostic>,
) -> std::io::Result<()> {
    let mut entries: Vec<PathBuf> =
        std::fs::read_dir(dir)?.filter_map(|e| e.ok().map(|e| e.path())).collect();
    entries.sort();
    for p in entries {
        let name = p.file_name().and_then(|n| n.to_str()).unwrap_or_default();
        if name.starts_with('.') || name == "target" {
            continue;
        }
        let is_scene = p.extension().is_some_and(|e| e == "holo");
        let Ok(meta) = std::fs::symlink_metadata(&p) else { continue };
        let link = meta.file_type().is_symlink();
        // A link that leads nowhere (dangling, or a loop) is kept when it names a scene: the
        // read then says why it fails.
        let Ok(real) = std::fs::canonicalize(&p) else {
            if is_scene {
                out.push(p);
            }
            continue;
        };
        if link && !real.starts_with(root) {
            if is_scene {
                refused.push(
                    Diagnostic::new(
                        Code::E0009,
                        format!(
                            "not testing `{}`: it is a link to `{}`, outside the folder `{}`",
                            crate::diag::visible(&p.display().to_string()),
                            crate::diag::visible(&real.display().to_string()),
                            crate::diag::visible(&root.display().to_string())
                        ),
                    )
                    .with_help("copy the scene into the folder, or test its own folder"),
                );
            }
            continue;
        }
        if real.is_dir() {
            if seen.insert(real) {
                walk_scenes(&p, root, seen, out, refused)?;
            }
        } else if is_scene {
            out.push(p);
        }
    }
    Ok(())
}

/// Where a scene's goldens are: beside it, or under the golden folder.
fn case_of(scene: &Path, root: &Path, goldens: Option<&(PathBuf, PathBuf)>) -> Case {
    let stem = scene.file_stem().and_then(|s| s.to_str()).unwrap_or("scene").to_string();
    let base = match goldens {
        Some((root, folder)) => {
            let absolute = std::path::absolute(scene).unwrap_or_else(|_| scene.to_path_buf());
            let root_abs = std::path::absolute(root).unwrap_or_else(|_| root.clone());
            let rel = absolute.strip_prefix(&root_abs).map_or_else(
                |_| PathBuf::from(scene.file_name().unwrap_or_default()),
                Path::to_path_buf,
            );
            folder.join(rel).with_file_name(&stem)
        }
        None => scene.with_file_name(&stem),
    };
    let with = |suffix: &str| {
        let mut name = base.file_name().unwrap_or_default().to_os_string();
        name.push(suffix);
        base.with_file_name(name)
    };
    let root = match goldens {
        Some((config_root, _)) => config_root.clone(),
        None => root.to_path_buf(),
    };
    Case {
        scene: scene.to_path_buf(),
        root,
        golden: with(".house.json"),
        report: with(".report.json"),
    }
}

/// Runs one scene's test.
fn run_case(case: Case, base: &SourceMap, catalog: &Catalog, options: &Options) -> TestResult {
    let mut sources = base.clone();
    let built = match build_scene(&mut sources, &case.scene, catalog) {
        Ok(b) => b,
        Err(diagnostics) => {
            return TestResult {
                case,
                status: Status::Broken(sources, diagnostics),
                built: None,
                blessed: false,
                rejected: false,
            }
        }
    };
    let mut golden_sources = base.clone();
    let invalid =
        |sources: SourceMap, d: Vec<Diagnostic>, case: Case, built: BuiltScene| TestResult {
            case,
            status: Status::Invalid(sources, d),
            built: Some(built),
            blessed: false,
            rejected: false,
        };
    // A golden that is a link is read only when it leads to a file inside the folder.
    let refused =
        leads_out(&case.root, &case.golden).or_else(|| leads_out(&case.root, &case.report));
    if let Some(d) = refused {
        return invalid(golden_sources, vec![d], case, built);
    }
    if !case.golden.is_file() {
        return TestResult {
            case,
            status: Status::New,
            built: Some(built),
            blessed: false,
            rejected: false,
        };
    }
    let file = match common::read_source(&mut golden_sources, &case.golden) {
        Ok(f) => f,
        Err(d) => return invalid(golden_sources, vec![d], case, built),
    };
    // The made assets the golden names: those beside it (`<golden stem>.assets/`, written by
    // `--bless`) and those this build made.
    let (mut made, _) = crate::make::read_folder(&crate::make::folder_beside(&case.golden));
    made.extend(crate::make::catalog_assets(&built.made));
    let with_made = catalog.with_made(made);
    let checked = crate::lower::validate::validate(
        &golden_sources,
        file,
        StructureCatalog::builtin(),
        &with_made,
    );
    let errors: Vec<Diagnostic> =
        checked.diagnostics.into_iter().filter(Diagnostic::is_error).collect();
    if !errors.is_empty() {
        return invalid(golden_sources, errors, case, built);
    }
    let golden = match diff::folder::load(
        &case.golden,
        Some(&case.report).filter(|r| r.is_file()).map(PathBuf::as_path),
    ) {
        Ok(g) => g,
        Err(d) => return invalid(golden_sources, vec![d], case, built),
    };
    let d = diff::diff(&golden, &built.view, options);
    let status = if d.is_empty() { Status::Ok } else { Status::Failed(d) };
    TestResult { case, status, built: Some(built), blessed: false, rejected: false }
}

/// E0009 when `path` is a symbolic link that leads outside `root` (or nowhere inside it).
fn leads_out(root: &Path, path: &Path) -> Option<Diagnostic> {
    let link = std::fs::symlink_metadata(path).ok()?.file_type().is_symlink();
    if !link {
        return None;
    }
    let inside = match (std::fs::canonicalize(root), std::fs::canonicalize(path)) {
        (Ok(root), Ok(real)) => real.starts_with(root),
        _ => false,
    };
    (!inside).then(|| {
        Diagnostic::new(
            Code::E0009,
            format!(
                "the golden `{}` is a link that leads outside the folder `{}`",
                crate::diag::visible(&path.display().to_string()),
                crate::diag::visible(&root.display().to_string())
            ),
        )
        .with_help("remove the link; `holoc test --bless` then writes the golden in its place")
    })
}

/// Writes a scene's goldens: the house, and the report when it has one or `reports` asks.
#[allow(
    clippy::result_large_err,
    reason = "the error is printed at once; it is rare and never propagated far"
)]
fn bless(result: &mut TestResult, reports: bool) -> Result<(), Diagnostic> {
    let Some(built) = &result.built else { return Ok(()) };
    let has_report = result.case.report.is_file();
    // The made assets first, beside the golden (`<golden stem>.assets/<uid>/`), inside the
    // folder as the golden is.
    let folder = crate::make::folder_beside(&result.case.golden);
    for made in &built.made {
        for (name, bytes) in crate::make::runtime::files(made) {
            common::write_confined(&result.case.root, &folder.join(&made.uid).join(name), &bytes)?;
        }
    }
    common::write_confined(&result.case.root, &result.case.golden, built.house_json.as_bytes())?;
    if has_report || reports {
        common::write_confined(
            &result.case.root,
            &result.case.report,
            built.report_json.as_bytes(),
        )?;
    }
    result.blessed = true;
    Ok(())
}

/// Runs `holoc test`.
pub fn run(args: &TestArgs) -> ExitCode {
    let config = match read_config() {
        Ok(c) => c,
        Err(d) => return usage(&d),
    };
    let (root, config) = config.unwrap_or_else(|| (PathBuf::from("."), Config::default()));
    let mut options = Options::default();
    if let Some(t) = &config.test.tolerance {
        match Tolerance::parse(t) {
            Ok(t) => options.tolerance = t,
            Err(e) => {
                return usage(&Diagnostic::new(
                    Code::E0004,
                    format!("holoc.toml: [test] tolerance: {e}"),
                ))
            }
        }
    }
    for name in &config.test.ignore {
        match Group::from_str(name, true) {
            Ok(g) => options.ignore.push(g),
            Err(_) => {
                return usage(&Diagnostic::new(
                    Code::E0004,
                    format!("holoc.toml: [test] ignore: `{name}` is not a group of fields"),
                ))
            }
        }
    }
    if let Some(t) = args.tolerance {
        options.tolerance = t;
    }
    options.ignore.extend(args.ignore.iter().copied());
    if let Some(g) = &config.test.goldens {
        if !g
            .components()
            .all(|c| matches!(c, std::path::Component::Normal(_) | std::path::Component::CurDir))
        {
            return usage(
                &Diagnostic::new(
                    Code::E0009,
                    format!(
                        "holoc.toml: [test] goldens `{}` leads outside the folder of `holoc.toml`",
                        crate::diag::visible(&g.display().to_string())
                    ),
                )
                .with_help("name a folder inside the project, e.g. `goldens = \"tests/golden\"`"),
            );
        }
    }
    let goldens = config.test.goldens.as_ref().map(|g| (root.clone(), root.join(g)));
    // Each path to search with the folder its goldens stay in: a folder given is its own, a
    // scene given its folder's, the `[test]` table's scenes the folder of `holoc.toml`.
    let paths: Vec<(PathBuf, PathBuf)> = if !args.paths.is_empty() {
        args.paths
            .iter()
            .map(|p| {
                let folder = if p.is_dir() {
                    p.clone()
                } else {
                    p.parent()
                        .filter(|d| !d.as_os_str().is_empty())
                        .map_or_else(|| PathBuf::from("."), Path::to_path_buf)
                };
                (p.clone(), folder)
            })
            .collect()
    } else if !config.test.scenes.is_empty() {
        config.test.scenes.iter().map(|s| (root.join(s), root.clone())).collect()
    } else {
        vec![(PathBuf::from("."), PathBuf::from("."))]
    };
    let mut scenes = Vec::new();
    let mut refused = Vec::new();
    for (p, folder) in &paths {
        let mut found = Vec::new();
        if let Err(e) = scenes_under(p, &mut found, &mut refused) {
            return usage(&Diagnostic::new(
                Code::E0001,
                format!("cannot read `{}`: {e}", crate::diag::visible(&p.display().to_string())),
            ));
        }
        scenes.extend(found.into_iter().map(|s| (s, folder.clone())));
    }
    for d in &refused {
        common::emit_plain(d);
    }
    let scenes: Vec<(PathBuf, PathBuf)> = scenes
        .into_iter()
        .map(|(p, folder)| (p.strip_prefix("./").map_or(p.clone(), Path::to_path_buf), folder))
        .collect();
    let mut base = SourceMap::new();
    let mut catalog_paths: Vec<PathBuf> = config.catalogs.iter().map(|c| root.join(c)).collect();
    catalog_paths.extend(args.catalogs.catalogs.iter().cloned());
    let objathor = match args.catalogs.objathor_options() {
        Some(o) => Some(o),
        None => match crate::resolve::objathor::ObjathorOptions::from_words(
            &root,
            config.objathor.as_deref(),
            config.objathor_version.as_deref(),
            config.objathor_scoring.as_deref(),
            config.objathor_mix.as_deref(),
            config.objathor_pick.as_deref(),
            config.objathor_clip.as_deref(),
        ) {
            Ok(o) => o,
            Err(message) => {
                return usage(&Diagnostic::new(Code::E0004, format!("holoc.toml: {message}")));
            }
        },
    };
    let loaded = Catalog::load_with(&catalog_paths, objathor.as_ref(), &mut base);
    if loaded.has_errors() {
        common::emit(&base, &loaded.diagnostics, common::DiagFormat::Human, args.color);
        return ExitCode::from(2);
    }
    let catalog = loaded.value;
    let pool = match rayon::ThreadPoolBuilder::new().num_threads(args.jobs.unwrap_or(0)).build() {
        Ok(p) => p,
        Err(e) => {
            return usage(&Diagnostic::new(Code::E0002, format!("cannot start threads: {e}")))
        }
    };
    let cases: Vec<Case> =
        scenes.iter().map(|(s, folder)| case_of(s, folder, goldens.as_ref())).collect();
    let mut results: Vec<TestResult> = pool.install(|| {
        cases.into_par_iter().map(|c| run_case(c, &base, &catalog, &options)).collect()
    });
    let mut write_failed = false;
    if args.bless {
        for r in &mut results {
            if matches!(r.status, Status::Failed(_) | Status::New | Status::Invalid(..)) {
                if let Err(d) = bless(r, args.reports) {
                    common::emit_plain(&d);
                    write_failed = true;
                }
            }
        }
    } else if args.review {
        if let Err(code) = review(&mut results, args) {
            return code;
        }
    }
    if let Err(d) = write_pending(&results) {
        common::emit_plain(&d);
        write_failed = true;
    }
    let text = match args.format {
        TestFormat::Human => human(&results, options.tolerance),
        TestFormat::Junit => junit(&results, options.tolerance),
        TestFormat::Json => json(&results),
    };
    // Scene paths, ids and names come from files: their control characters are escaped in
    // the human text (JUnit drops them, JSON escapes them).
    common::out(&crate::diag::visible(&text));
    if write_failed {
        return ExitCode::from(2);
    }
    if refused.is_empty() && results.iter().all(|r| r.blessed || matches!(r.status, Status::Ok)) {
        ExitCode::SUCCESS
    } else {
        ExitCode::from(1)
    }
}

/// Where the answers of `--review` come from.
enum Answers {
    /// `--answers FILE`: one answer a line (`#` comments and empty lines skipped).
    File(std::vec::IntoIter<String>),
    /// A terminal: one key a scene, read as it is pressed.
    Keys(console::Term),
    /// Piped standard input: one answer a line, read as each scene is shown (not all first).
    Lines(std::io::StdinLock<'static>),
}

/// One answer of a review.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
enum Answer {
    /// Write the new house as the golden.
    Accept,
    /// This one and every one after it.
    All,
    /// Keep the old golden; no pending `.new` golden.
    Reject,
    /// Keep the old golden and leave the new house pending (`.new`) for later.
    Skip,
    /// Stop; the scenes not reviewed are left pending.
    Quit,
}

impl Answer {
    /// A typed answer (`y`, `yes`, `accept`, `n`, `no`, `reject`, `s`, `skip`, `a`, `all`, `q`,
    /// `quit`); anything else rejects, as an answer that is not a yes always did.
    fn of_word(word: &str) -> Answer {
        match word.trim().to_lowercase().as_str() {
            "y" | "yes" | "accept" => Answer::Accept,
            "a" | "all" => Answer::All,
            "s" | "skip" => Answer::Skip,
            "q" | "quit" => Answer::Quit,
            _ => Answer::Reject,
        }
    }

    /// A key pressed at a terminal: `a`/`y` accept, `r`/`n` reject, `s` skip, `q`/Esc quit,
    /// `A` accept this and every one after; `None` for another key (asked again).
    fn of_key(key: &console::Key) -> Option<Answer> {
        match key {
            console::Key::Char('a' | 'y' | 'Y') => Some(Answer::Accept),
            console::Key::Char('A') => Some(Answer::All),
            console::Key::Char('r' | 'n' | 'R' | 'N') => Some(Answer::Reject),
            console::Key::Char('s' | 'S') => Some(Answer::Skip),
            console::Key::Char('q' | 'Q') | console::Key::Escape => Some(Answer::Quit),
            _ => None,
        }
    }
}

impl Answers {
    /// The answer for the scene just shown; `Reject` when the answers run out (as an empty
    /// answer).
    fn next(&mut self) -> Answer {
        match self {
            Answers::File(lines) => lines.next().map_or(Answer::Reject, |l| Answer::of_word(&l)),
            Answers::Lines(stdin) => {
                let mut line = String::new();
                match stdin.read_line(&mut line) {
                    Ok(0) | Err(_) => Answer::Reject,
                    Ok(_) => Answer::of_word(&line),
                }
            }
            Answers::Keys(term) => {
                common::err("[a]ccept  [r]eject  [s]kip  [q]uit  (A: accept all) ");
                loop {
                    match term.read_key() {
                        Ok(key) => {
                            if let Some(answer) = Answer::of_key(&key) {
                                let word = match answer {
                                    Answer::Accept => "accept",
                                    Answer::All => "accept all",
                                    Answer::Reject => "reject",
                                    Answer::Skip => "skip",
                                    Answer::Quit => "quit",
                                };
                                common::err(&format!("{word}\n"));
                                return answer;
                            }
                        }
                        Err(_) => return Answer::Quit,
                    }
                }
            }
        }
    }
}

/// Asks, for each scene that differs, is new or has an invalid golden, whether to accept the
/// new house as its golden: key by key at a terminal (standard input and error both
/// terminals), else a line at a time from standard input or from `--answers`. A scene rejected
/// keeps its old golden and leaves no pending golden; one skipped, or not reached after a
/// quit, keeps its pending `.new` golden for a later review.
fn review(results: &mut [TestResult], args: &TestArgs) -> Result<(), ExitCode> {
    use std::io::IsTerminal as _;
    let mut answers = match &args.answers {
        Some(path) => match common::read_text(path) {
            Ok(t) => Answers::File(
                t.lines()
                    .map(str::trim)
                    .filter(|l| !l.is_empty() && !l.starts_with('#'))
                    .map(str::to_string)
                    .collect::<Vec<_>>()
                    .into_iter(),
            ),
            Err(d) => return Err(usage(&d)),
        },
        None if std::io::stdin().is_terminal() && std::io::stderr().is_terminal() => {
            Answers::Keys(console::Term::stderr())
        }
        None => Answers::Lines(std::io::stdin().lock()),
    };
    let to_review = results
        .iter()
        .filter(|r| matches!(r.status, Status::Failed(_) | Status::New | Status::Invalid(..)))
        .count();
    let mut all = false;
    let mut n = 0;
    for r in results.iter_mut() {
        let shown = match &r.status {
            Status::Failed(d) => format!("{}{}\n", d.render(), d.summary()),
            Status::New => format!("new: no golden at {}\n", r.case.golden.display()),
            Status::Invalid(sources, d) => {
                format!("the golden is not valid:\n{}", render_diagnostics(sources, d))
            }
            Status::Ok | Status::Broken(..) => continue,
        };
        n += 1;
        common::err(&crate::diag::visible(&format!(
            "---- {} ---- ({n} of {to_review})\n{shown}",
            r.case.scene.display()
        )));
        let answer = if all { Answer::Accept } else { answers.next() };
        match answer {
            Answer::All => all = true,
            Answer::Quit => {
                common::err("stopped; the scenes not reviewed keep their pending `.new` goldens\n");
                break;
            }
            Answer::Accept | Answer::Reject | Answer::Skip => {}
        }
        let accept = matches!(answer, Answer::Accept | Answer::All);
        common::err(match answer {
            Answer::Skip => "skipped: the new house waits as a `.new` golden\n\n",
            Answer::Reject => "kept the old golden\n\n",
            _ => "accepted\n\n",
        });
        r.rejected = answer == Answer::Reject;
        if accept {
            if let Err(d) = bless(r, args.reports) {
                return Err(usage(&d));
            }
        }
    }
    Ok(())
}

/// Where a scene's pending golden goes: the golden's name with `.new` after it
/// (`bedroom.house.json.new`), as insta keeps `.snap.new` beside a snapshot.
fn pending_path(golden: &Path) -> PathBuf {
    let mut name = golden.as_os_str().to_os_string();
    name.push(".new");
    PathBuf::from(name)
}

/// Writes the pending golden of every scene that failed, is new or has an invalid golden and
/// was neither accepted nor rejected, and removes the pending golden of every other scene.
#[allow(
    clippy::result_large_err,
    reason = "the error is printed at once; it is rare and never propagated far"
)]
fn write_pending(results: &[TestResult]) -> Result<(), Diagnostic> {
    for r in results {
        let pending = pending_path(&r.case.golden);
        let waits = !r.blessed
            && !r.rejected
            && matches!(r.status, Status::Failed(_) | Status::New | Status::Invalid(..));
        match (&r.built, waits) {
            (Some(built), true) => {
                common::write_confined(&r.case.root, &pending, built.house_json.as_bytes())?;
            }
            _ => {
                if std::fs::symlink_metadata(&pending).is_ok_and(|m| m.is_file()) {
                    let _ = std::fs::remove_file(&pending);
                }
            }
        }
    }
    Ok(())
}

fn render_diagnostics(sources: &SourceMap, diagnostics: &[Diagnostic]) -> String {
    let mut sorted = diagnostics.to_vec();
    crate::diag::sort(&mut sorted);
    crate::diag::format::render_human(sources, &sorted, HumanOptions { color: false, width: 100 })
}

/// The word of a result in the `test … ...` line and the reports.
fn word(r: &TestResult) -> &'static str {
    match (&r.status, r.blessed) {
        (Status::Ok, _) => "ok",
        (Status::Failed(_), false) => "FAILED",
        (Status::New, false) => "new",
        (Status::Invalid(..), false) => "invalid golden",
        (Status::Broken(..), _) => "does not build",
        (_, true) => "blessed",
    }
}

/// The failure's text: the diff, the missing golden, or the diagnostics.
fn details(r: &TestResult, tolerance: Tolerance) -> String {
    match &r.status {
        Status::Ok => String::new(),
        Status::Failed(d) => super::diff::human(d, false, tolerance),
        Status::New => format!(
            "no golden at {}: run `holoc test --bless` to write it\n",
            r.case.golden.display()
        ),
        Status::Invalid(sources, d) => format!(
            "the golden {} is not a valid house:\n{}",
            r.case.golden.display(),
            render_diagnostics(sources, d)
        ),
        Status::Broken(sources, d) => render_diagnostics(sources, d),
    }
}

/// The counts of the summary line: passed, failed, new, invalid, broken, blessed.
fn counts(results: &[TestResult]) -> [usize; 6] {
    let mut c = [0; 6];
    for r in results {
        if r.blessed {
            c[5] += 1;
            continue;
        }
        let i = match r.status {
            Status::Ok => 0,
            Status::Failed(_) => 1,
            Status::New => 2,
            Status::Invalid(..) => 3,
            Status::Broken(..) => 4,
        };
        c[i] += 1;
    }
    c
}

fn human(results: &[TestResult], tolerance: Tolerance) -> String {
    let n = results.len();
    let mut out = format!("\nrunning {n} scene test{}\n", if n == 1 { "" } else { "s" });
    for r in results {
        let _ = writeln!(out, "test {} ... {}", r.case.scene.display(), word(r));
    }
    let failing: Vec<&TestResult> =
        results.iter().filter(|r| !matches!(r.status, Status::Ok) && !r.blessed).collect();
    let blessed: Vec<&TestResult> = results.iter().filter(|r| r.blessed).collect();
    if !blessed.is_empty() {
        out.push_str("\nblessed:\n");
        for r in &blessed {
            let what = match &r.status {
                Status::Failed(d) => d.summary(),
                Status::New => "new".to_string(),
                _ => "the invalid golden replaced".to_string(),
            };
            let _ = writeln!(out, "    {} ({what})", r.case.golden.display());
        }
    }
    if !failing.is_empty() {
        out.push_str("\nfailures:\n");
        for r in &failing {
            let _ =
                write!(out, "\n---- {} ----\n{}", r.case.scene.display(), details(r, tolerance));
        }
        out.push_str("\nfailures:\n");
        for r in &failing {
            let _ = writeln!(out, "    {}", r.case.scene.display());
        }
    }
    let [passed, failed, new, invalid, broken, blessed_n] = counts(results);
    let verdict = if failing.is_empty() { "ok" } else { "FAILED" };
    let mut line = format!("\ntest result: {verdict}. {passed} passed; {failed} failed; {new} new");
    if invalid > 0 {
        let _ = write!(line, "; {invalid} invalid");
    }
    if broken > 0 {
        let _ = write!(line, "; {broken} did not build");
    }
    if blessed_n > 0 {
        let _ = write!(line, "; {blessed_n} blessed");
    }
    if !failing.is_empty()
        && blessed_n == 0
        && failing.iter().any(|r| !matches!(r.status, Status::Broken(..)))
    {
        line.push_str("\n(`holoc test --bless` accepts the new houses, `--review` asks for each)");
    }
    out.push_str(&line);
    out.push('\n');
    out
}

/// Escapes text for XML, leaving out the control characters XML 1.0 cannot hold.
fn xml(text: &str) -> String {
    let mut out = String::with_capacity(text.len());
    for c in text.chars() {
        match c {
            '&' => out.push_str("&amp;"),
            '<' => out.push_str("&lt;"),
            '>' => out.push_str("&gt;"),
            '"' => out.push_str("&quot;"),
            '\'' => out.push_str("&apos;"),
            '\t' | '\n' | '\r' => out.push(c),
            c if (c as u32) < 0x20 => {}
            c => out.push(c),
        }
    }
    out
}

/// The JUnit XML report: one `testsuite` of one `testcase` per scene; a difference or a
/// missing golden is a `failure`, an invalid golden or a scene that does not build an
/// `error`. No times: the report is the same on every run.
fn junit(results: &[TestResult], tolerance: Tolerance) -> String {
    let [passed, failed, new, invalid, broken, blessed] = counts(results);
    let _ = passed + blessed;
    let (failures, errors) = (failed + new, invalid + broken);
    let mut out = String::from("<?xml version=\"1.0\" encoding=\"UTF-8\"?>\n");
    // The strict Ant schema wants `time`, `timestamp`, `hostname`, `package` and `id` on the
    // suite, `properties`, `system-out` and `system-err` in it and no attribute on the root;
    // the report stays the same on every run (times 0, the time of `SOURCE_DATE_EPOCH` or
    // 1970-01-01T00:00:00, host `localhost`).
    let head = format!(
        "name=\"holoc test\" tests=\"{}\" failures=\"{failures}\" errors=\"{errors}\"",
        results.len()
    );
    let _ = writeln!(out, "<testsuites>");
    let _ = writeln!(
        out,
        "  <testsuite {head} skipped=\"0\" time=\"0\" timestamp=\"{}\" hostname=\"localhost\" \
         package=\"holoc\" id=\"0\">",
        junit_timestamp(std::env::var("SOURCE_DATE_EPOCH").ok().as_deref())
    );
    out.push_str("    <properties/>\n");
    for r in results {
        let name = xml(&r.case.scene.display().to_string());
        let class = xml(&format!(
            "holoc.{}",
            r.case
                .scene
                .parent()
                .map(|p| p.display().to_string())
                .filter(|p| !p.is_empty())
                .unwrap_or_else(|| ".".into())
        ));
        let open = format!("    <testcase name=\"{name}\" classname=\"{class}\" time=\"0\"");
        let body = |tag: &str, kind: &str, message: &str| {
            format!(
                "{open}>\n      <{tag} type=\"{kind}\" message=\"{}\">{}</{tag}>\n    </testcase>\n",
                xml(message),
                xml(&details(r, tolerance))
            )
        };
        let case = match (&r.status, r.blessed) {
            (Status::Ok, _) | (_, true) => format!("{open}/>\n"),
            (Status::Failed(d), _) => body("failure", "changed", &d.summary()),
            (Status::New, _) => body("failure", "new", "no golden"),
            (Status::Invalid(..), _) => {
                body("error", "invalid-golden", "the golden is not a valid house")
            }
            (Status::Broken(..), _) => body("error", "build", "the scene does not build"),
        };
        out.push_str(&case);
    }
    out.push_str("    <system-out/>\n    <system-err/>\n  </testsuite>\n</testsuites>\n");
    out
}

/// The suite's `timestamp` (ISO 8601 without a zone, as the Ant schema wants it): the time of
/// `SOURCE_DATE_EPOCH` (seconds since 1970, the reproducible-builds convention) when it is a
/// number, else 1970-01-01T00:00:00, so that the report never depends on the clock.
fn junit_timestamp(epoch: Option<&str>) -> String {
    let secs = epoch.and_then(|e| e.trim().parse::<i64>().ok()).unwrap_or(0).max(0);
    let (days, rest) = (secs / 86_400, secs % 86_400);
    // Civil date from days since 1970-01-01 (Howard Hinnant's algorithm).
    let z = days + 719_468;
    let era = z / 146_097;
    let doe = z - era * 146_097;
    let yoe = (doe - doe / 1460 + doe / 36_524 - doe / 146_096) / 365;
    let doy = doe - (365 * yoe + yoe / 4 - yoe / 100);
    let mp = (5 * doy + 2) / 153;
    let day = doy - (153 * mp + 2) / 5 + 1;
    let month = if mp < 10 { mp + 3 } else { mp - 9 };
    let year = yoe + era * 400 + i64::from(month <= 2);
    format!(
        "{year:04}-{month:02}-{day:02}T{:02}:{:02}:{:02}",
        rest / 3600,
        rest % 3600 / 60,
        rest % 60
    )
}

fn json(results: &[TestResult]) -> String {
    let [passed, failed, new, invalid, broken, blessed] = counts(results);
    let tests: Vec<serde_json::Value> = results
        .iter()
        .map(|r| {
            let status = match (&r.status, r.blessed) {
                (Status::Ok, _) => "ok",
                (_, true) => "blessed",
                (Status::Failed(_), _) => "failed",
                (Status::New, _) => "new",
                (Status::Invalid(..), _) => "invalid",
                (Status::Broken(..), _) => "broken",
            };
            let mut t = serde_json::json!({
                "scene": r.case.scene.display().to_string(),
                "golden": r.case.golden.display().to_string(),
                "status": status,
            });
            match &r.status {
                Status::Failed(d) => {
                    t["summary"] = d.summary().into();
                    t["changes"] = serde_json::to_value(&d.changes).unwrap_or_default();
                }
                Status::Invalid(_, d) | Status::Broken(_, d) => {
                    t["diagnostics"] = d
                        .iter()
                        .map(|d| serde_json::json!({"code": d.code.as_str(), "message": d.message}))
                        .collect();
                }
                _ => {}
            }
            t
        })
        .collect();
    let mut text = serde_json::to_string_pretty(&serde_json::json!({
        "version": 1,
        "passed": passed, "failed": failed, "new": new, "invalid": invalid,
        "broken": broken, "blessed": blessed,
        "tests": tests,
    }))
    .unwrap_or_default();
    text.push('\n');
    text
}

#[cfg(test)]
mod tests {
    use super::junit_timestamp;

    #[test]
    fn the_junit_timestamp_is_the_civil_time_of_source_date_epoch() {
        assert_eq!(junit_timestamp(None), "1970-01-01T00:00:00");
        assert_eq!(junit_timestamp(Some("not a number")), "1970-01-01T00:00:00");
        assert_eq!(junit_timestamp(Some("951782400")), "2000-02-29T00:00:00");
        assert_eq!(junit_timestamp(Some("1796651573")), "2026-12-07T13:52:53");
    }
}

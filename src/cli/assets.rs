//! `holoc assets search|list`: look into the asset catalogs.

use super::common::{self, ColorChoice, DiagFormat};
use crate::diag::{Code, Diagnostic, Outcome};
use crate::resolve::{self, Catalog, PlacementKind};
use crate::source::SourceMap;
use std::fmt::Write as _;
use std::path::PathBuf;
use std::process::ExitCode;

/// The catalog options every command that resolves assets shares (flatten it into its args).
#[derive(Clone, Debug, Default, clap::Args)]
pub struct CatalogArgs {
    /// A catalog file to add to the embedded one: a ProcTHOR asset database or objathor
    /// annotations (`.json` or `.json.gz`). Repeatable; later files win on id clashes.
    #[arg(long = "catalog", value_name = "FILE")]
    pub catalogs: Vec<PathBuf>,
    /// The original Holodeck's assets: an objathor version folder (the one with
    /// `annotations.json.gz`, `features/` and `assets/`), or the base folder with
    /// `--objathor-version`.
    #[arg(long, value_name = "DIR")]
    pub objathor: Option<PathBuf>,
    /// The version folder under `--objathor` (e.g. `2023_09_23`).
    #[arg(long, value_name = "VERSION")]
    pub objathor_version: Option<String>,
    /// How objathor assets are ranked: `lexical` (words and size), `features` (the stored CLIP
    /// rows; the default when the folder has them) or `clip` (the original's retrieval with
    /// CLIP's text tower: builds with the cargo feature `clip`, weights from `--objathor-clip`;
    /// the default when they are given).
    #[arg(long, value_name = "MODE", value_parser = ["lexical", "features", "clip"])]
    pub objathor_scoring: Option<String>,
    /// The CLIP text tower of `--objathor-scoring clip`: a folder with Hugging Face's
    /// `model.safetensors`, `config.json`, `vocab.json` and `merges.txt` (or `tokenizer.json`)
    /// of `laion/CLIP-ViT-L-14-laion2B-s32B-b82K`.
    #[arg(long, value_name = "DIR")]
    pub objathor_clip: Option<PathBuf>,
    /// `objathor-first` (default, as the original: objathor's good assets first, the other
    /// catalogs for what it lacks), `builtin-first` (objathor assets only for what the other
    /// catalogs lack) or `score` (both, merged by score).
    #[arg(long, value_name = "HOW", value_parser = ["objathor-first", "builtin-first", "score"])]
    pub objathor_mix: Option<String>,
    /// `argmax` (default: the best objathor asset) or `seeded` (a draw from the softmax of the
    /// best 10, 5 for small objects, from the scene's seed).
    #[arg(long, value_name = "HOW", value_parser = ["argmax", "seeded"])]
    pub objathor_pick: Option<String>,
    /// Read the objathor folder's files on every build instead of its index (which is then
    /// neither used nor written).
    #[arg(long)]
    pub objathor_no_index: bool,
}

/// The catalog settings of a project's `holoc.toml` (its other tables are read by the commands
/// that use them): the one source of catalogs of every command.
#[derive(Debug, Default, serde::Deserialize)]
struct ProjectCatalogs {
    #[serde(default)]
    catalogs: Vec<PathBuf>,
    objathor: Option<PathBuf>,
    objathor_version: Option<String>,
    objathor_scoring: Option<String>,
    objathor_mix: Option<String>,
    objathor_pick: Option<String>,
    objathor_clip: Option<PathBuf>,
}

/// The nearest `holoc.toml` in the current folder or above it.
pub(crate) fn project_file() -> Option<PathBuf> {
    let cwd = std::env::current_dir().ok()?;
    cwd.ancestors().map(|d| d.join("holoc.toml")).find(|p| p.is_file())
}

impl CatalogArgs {
    /// Loads the embedded catalog, the catalogs of the nearest `holoc.toml` (relative to its
    /// folder) and the files given, then the objathor folder (the one given, else the one of
    /// `holoc.toml`), adding the files' text to `sources`. `build`, `check`, `render`,
    /// `export`, `view`, `diff` and `generate` load their catalogs here, and `holoc test` and
    /// the language server read the same `holoc.toml` keys, so one scene builds into one house
    /// whichever command builds it.
    pub fn load(&self, sources: &mut SourceMap) -> Outcome<Catalog> {
        match self.with_project(project_file().as_deref()) {
            Ok(args) => {
                Catalog::load_with(&args.catalogs, args.objathor_options().as_ref(), sources)
            }
            Err(d) => Outcome::new(Catalog::embedded(), vec![*d]),
        }
    }

    /// These options with the catalogs of `holoc.toml` at `project` (when there is one) before
    /// the files given, and its objathor folder when none is given.
    pub(crate) fn with_project(
        &self,
        project: Option<&std::path::Path>,
    ) -> Result<CatalogArgs, Box<Diagnostic>> {
        let Some(path) = project else { return Ok(self.clone()) };
        let text = common::read_text(path).map_err(Box::new)?;
        let config: ProjectCatalogs = toml::from_str(&text).map_err(|e| {
            Box::new(
                Diagnostic::new(Code::E0004, format!("`{}` is not usable: {e}", path.display()))
                    .with_help("see `holoc test` in the book for the keys of `holoc.toml`"),
            )
        })?;
        let dir = path.parent().unwrap_or_else(|| std::path::Path::new("."));
        let mut out = self.clone();
        out.catalogs = config.catalogs.iter().map(|c| dir.join(c)).collect();
        out.catalogs.extend(self.catalogs.iter().cloned());
        if out.objathor.is_none() {
            if let Some(o) = &config.objathor {
                out.objathor = Some(dir.join(o));
                out.objathor_version.clone_from(&config.objathor_version);
                out.objathor_scoring.clone_from(&config.objathor_scoring);
                out.objathor_mix.clone_from(&config.objathor_mix);
                out.objathor_pick.clone_from(&config.objathor_pick);
                out.objathor_clip = config.objathor_clip.as_ref().map(|c| dir.join(c));
            }
        }
        Ok(out)
    }

    /// What `--objathor` and its companions ask (`None` without `--objathor`).
    pub fn objathor_options(&self) -> Option<resolve::objathor::ObjathorOptions> {
        use resolve::objathor::{Mix, ObjathorOptions, Pick, Scoring};
        let dir = self.objathor.clone()?;
        Some(ObjathorOptions {
            dir,
            version: self.objathor_version.clone(),
            scoring: self.objathor_scoring.as_deref().and_then(Scoring::parse),
            mix: self.objathor_mix.as_deref().and_then(Mix::parse).unwrap_or_default(),
            pick: self.objathor_pick.as_deref().and_then(Pick::parse).unwrap_or_default(),
            no_index: self.objathor_no_index,
            clip: self.objathor_clip.clone(),
        })
    }
}

/// Arguments of `holoc assets`.
#[derive(Debug, clap::Args)]
pub struct AssetsArgs {
    /// What to do.
    #[command(subcommand)]
    pub command: AssetsCommand,
}

/// The `holoc assets` subcommands.
#[derive(Debug, clap::Subcommand)]
pub enum AssetsCommand {
    /// Rank the catalog's assets for a description, with the parts of each score.
    Search(SearchArgs),
    /// List assets, optionally of one object type or placement kind.
    List(ListArgs),
}

/// Output format of `holoc assets`.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, clap::ValueEnum)]
pub enum AssetsFormat {
    /// A table for people.
    #[default]
    Human,
    /// A JSON array in rank (or list) order.
    Json,
}

/// A placement kind on the command line.
#[derive(Clone, Copy, Debug, PartialEq, Eq, clap::ValueEnum)]
pub enum KindArg {
    /// Stands on the floor.
    Floor,
    /// Hangs on a wall.
    Wall,
    /// Stands on another object.
    OnObject,
    /// Hangs from the ceiling.
    Ceiling,
}

impl KindArg {
    fn kind(self) -> PlacementKind {
        match self {
            KindArg::Floor => PlacementKind::Floor,
            KindArg::Wall => PlacementKind::Wall,
            KindArg::OnObject => PlacementKind::OnObject,
            KindArg::Ceiling => PlacementKind::Ceiling,
        }
    }
}

/// Arguments of `holoc assets search`.
#[derive(Debug, clap::Args)]
pub struct SearchArgs {
    /// The description, e.g. "light grey sectional sofa", read as a build reads an object's
    /// name: its noun phrase names the thing (`writing desk with drawers` is a desk).
    pub query: String,
    /// The object's name, as in `object NAME "…"` with the text as its `describe`: the name
    /// then says what the thing is and the text how it looks.
    #[arg(long, value_name = "NAME")]
    pub name: Option<String>,
    /// Do not let an asset of another type stand in (as `holoc build --no-stand-ins`).
    #[arg(long)]
    pub no_stand_ins: bool,
    /// Show what the built-in and user catalogs give, without the assets holoc makes.
    #[arg(long)]
    pub no_make: bool,
    /// Desired size, width x depth x height with a unit: `200x100x80cm`, `2x1x0.8m`.
    #[arg(long, value_name = "WxDxH")]
    pub size: Option<String>,
    /// Only assets that can be placed this way.
    #[arg(long, value_enum)]
    pub kind: Option<KindArg>,
    /// How many candidates to print.
    #[arg(long, default_value_t = 10)]
    pub limit: usize,
    /// Output format.
    #[arg(long, value_enum, default_value_t = AssetsFormat::Human)]
    pub format: AssetsFormat,
    /// When to colour diagnostics.
    #[arg(long, value_enum, default_value_t = ColorChoice::Auto)]
    pub color: ColorChoice,
    /// Catalogs.
    #[command(flatten)]
    pub catalog: CatalogArgs,
}

/// Arguments of `holoc assets list`.
#[derive(Debug, clap::Args)]
pub struct ListArgs {
    /// Only assets of this object type (`Sofa`; case-insensitive).
    #[arg(long = "type", value_name = "TYPE")]
    pub object_type: Option<String>,
    /// Only assets that can be placed this way.
    #[arg(long, value_enum)]
    pub kind: Option<KindArg>,
    /// Output format.
    #[arg(long, value_enum, default_value_t = AssetsFormat::Human)]
    pub format: AssetsFormat,
    /// When to colour diagnostics.
    #[arg(long, value_enum, default_value_t = ColorChoice::Auto)]
    pub color: ColorChoice,
    /// Catalogs.
    #[command(flatten)]
    pub catalog: CatalogArgs,
}

/// Runs `holoc assets`.
pub fn run(args: &AssetsArgs) -> ExitCode {
    match &args.command {
        AssetsCommand::Search(a) => search(a),
        AssetsCommand::List(a) => list(a),
    }
}

/// Parses `200x100x80cm`, `2 x 1 x 0.8 m` or `200×100×80 cm` into metres.
pub fn parse_size(text: &str) -> Result<[f64; 3], String> {
    let t = text.trim().to_lowercase();
    let (numbers, scale) = if let Some(n) = t.strip_suffix("cm") {
        (n, 0.01)
    } else if let Some(n) = t.strip_suffix("mm") {
        (n, 0.001)
    } else if let Some(n) = t.strip_suffix('m') {
        (n, 1.0)
    } else {
        return Err(format!("size `{text}` has no unit; write e.g. `200x100x80cm`"));
    };
    let parts: Vec<&str> = numbers.split(['x', '×', ',']).map(str::trim).collect();
    let [a, b, c] = parts[..] else {
        return Err(format!("size `{text}` needs three numbers, width x depth x height"));
    };
    let mut out = [0.0; 3];
    for (slot, p) in out.iter_mut().zip([a, b, c]) {
        let v: f64 = p.parse().map_err(|_| format!("`{p}` in size `{text}` is not a number"))?;
        if !v.is_finite() || v <= 0.0 {
            return Err(format!("size `{text}` must be positive"));
        }
        *slot = v * scale;
    }
    Ok(out)
}

/// Loads the catalogs and prints their diagnostics; `None` when a file could not be used.
fn load(catalog: &CatalogArgs, color: ColorChoice) -> Option<Catalog> {
    let mut sources = SourceMap::new();
    let outcome = catalog.load(&mut sources);
    common::emit(&sources, &outcome.diagnostics, DiagFormat::Human, color);
    if outcome.diagnostics.iter().any(|d| d.code == Code::E0403 || d.is_error()) {
        return None;
    }
    Some(outcome.value)
}

/// How `assets search` names a kind of placement in its verdict.
fn kind_words(kind: PlacementKind) -> &'static str {
    match kind {
        PlacementKind::Floor => "a floor object",
        PlacementKind::Wall => "a wall object",
        PlacementKind::OnObject => "a thing on furniture",
        PlacementKind::Ceiling => "a ceiling object",
    }
}

fn f3(v: [f64; 3]) -> String {
    format!("{:.2}×{:.2}×{:.2}", v[0], v[1], v[2])
}

fn search(args: &SearchArgs) -> ExitCode {
    let size = match args.size.as_deref().map(parse_size).transpose() {
        Ok(s) => s,
        Err(message) => {
            common::emit_plain(
                &Diagnostic::new(Code::E0004, message).with_help("e.g. `--size 200x100x80cm`"),
            );
            return ExitCode::from(2);
        }
    };
    let Some(catalog) = load(&args.catalog, args.color) else {
        return ExitCode::from(2);
    };
    let kind = args.kind.map(KindArg::kind);
    let query = match &args.name {
        Some(name) => resolve::Query {
            category: name.clone(),
            description: Some(args.query.clone()),
            size_m: size,
            kind,
        },
        None => {
            resolve::Query { category: args.query.clone(), description: None, size_m: size, kind }
        }
    };
    let mut candidates = resolve::rank(&catalog, &query, 0);
    if catalog.objathor().is_some() {
        // The objathor folder's candidates too, merged by their lexical score.
        candidates.extend(resolve::objathor::rank(&catalog, &query, 0, args.limit.max(1)));
        let lexical =
            |c: &resolve::Candidate| c.features.as_ref().map_or(c.score, |f| f.lexical_score);
        candidates.sort_by(|a, b| lexical(b).total_cmp(&lexical(a)));
    }
    let options = resolve::ResolveOptions { stand_ins: !args.no_stand_ins, make: !args.no_make };
    // The verdict is for one kind of placement: the one asked, else the first the best
    // candidate allows (a coffee machine stands on furniture), else the floor; it is named.
    let verdict_kind = kind
        .or_else(|| {
            let best = catalog.get(&candidates.first()?.asset_id)?;
            PlacementKind::ALL.into_iter().find(|k| best.allows(*k))
        })
        .unwrap_or(PlacementKind::Floor);
    let resolution = resolve::resolve_query(
        &catalog,
        &resolve::Query { kind: Some(verdict_kind), ..query.clone() },
        0,
        &options,
    )
    .value;
    let shown = &candidates[..candidates.len().min(args.limit)];
    // What a build would choose when no ranked candidate is good enough: the kind the thing
    // is, a stand-in or another placement.
    let fallback = resolution.choice().filter(|c| c.parts.is_none());
    let text = match args.format {
        AssetsFormat::Json => {
            let mut list: Vec<serde_json::Value> = Vec::new();
            if let Some(c) = fallback {
                list.push(serde_json::json!({
                    "assetId": c.asset_id,
                    "objectType": c.object_type,
                    "catalog": catalog.sources().get(c.source).map(|s| s.name.clone()),
                    "bboxM": c.bbox_m,
                    "accepted": true,
                    "standIn": c.stand_in.is_some(),
                    "standInReason": c.stand_in,
                    "kindOf": c.kind_of,
                    "placedAs": c.placed_as,
                    "sizeRatio": c.size_ratio,
                }));
            }
            list.extend(shown.iter().map(|c| {
                let mut v = resolve::candidate_json(c, &catalog);
                if let Some(map) = v.as_object_mut() {
                    map.insert("accepted".into(), c.is_good_enough().into());
                    map.insert("standIn".into(), false.into());
                }
                v
            }));
            let mut s = serde_json::to_string_pretty(&list).unwrap_or_else(|_| "[]".into());
            s.push('\n');
            s
        }
        AssetsFormat::Human => {
            let mut s = String::new();
            let _ = writeln!(
                s,
                "{:>4}  {:<32} {:<16} {:>7}  {:>9}  {:>4}  {:>5}  {:>7}  bbox m",
                "rank", "asset", "type", "score", "relevance", "head", "text", "size Δ"
            );
            if let Some(c) = fallback {
                let how = c
                    .kind_of
                    .clone()
                    .or_else(|| c.stand_in.as_ref().map(|r| format!("stands in: {r}")))
                    .unwrap_or_default();
                let way = c.placed_as.as_ref().map(|w| format!(", placed {w}")).unwrap_or_default();
                let way = match c.size_ratio {
                    Some(r) => format!("{way}, size ratio {r:.2}"),
                    None => way,
                };
                let _ = writeln!(
                    s,
                    "{:>4}  {:<32} {:<16} {}{way}  {}",
                    "→",
                    c.asset_id,
                    c.object_type,
                    how,
                    f3(c.bbox_m)
                );
            } else if resolution.choice().is_none() {
                let _ = writeln!(
                    s,
                    "   →  nothing as {}: a build leaves it out (W0401)",
                    kind_words(verdict_kind)
                );
            } else if let Some(c) = resolution.choice().filter(|_| kind.is_none()) {
                let _ = writeln!(
                    s,
                    "   →  as {}: a build takes `{}`",
                    kind_words(verdict_kind),
                    c.asset_id
                );
            }
            for (i, c) in shown.iter().enumerate() {
                let good = if c.is_good_enough() { "" } else { "  (below threshold)" };
                let _ = writeln!(
                    s,
                    "{:>4}  {:<32} {:<16} {:>7.3}  {:>9.3}  {:>4}  {:>5.3}  {:>7}  {}{good}",
                    i + 1,
                    c.asset_id,
                    c.object_type,
                    c.score,
                    c.relevance,
                    if c.head_match { "yes" } else { "no" },
                    c.text,
                    c.size_diff_m.map_or_else(|| "-".to_string(), |d| format!("{d:.3}")),
                    f3(c.bbox_m),
                );
            }
            if candidates.is_empty() {
                s.push_str("no asset shares a word with the query\n");
            } else if candidates.len() > shown.len() {
                let _ = writeln!(s, "… {} more (use --limit)", candidates.len() - shown.len());
            }
            s
        }
    };
    match common::write_output(None, &text) {
        Ok(()) => ExitCode::SUCCESS,
        Err(d) => {
            common::emit_plain(&d);
            ExitCode::from(2)
        }
    }
}

fn list(args: &ListArgs) -> ExitCode {
    let Some(catalog) = load(&args.catalog, args.color) else {
        return ExitCode::from(2);
    };
    let mut assets: Vec<&resolve::Asset> = catalog
        .assets()
        .iter()
        .filter(|a| {
            args.object_type.as_ref().is_none_or(|t| t.eq_ignore_ascii_case(&a.object_type))
        })
        .filter(|a| args.kind.is_none_or(|k| a.allows(k.kind())))
        .collect();
    assets.sort_by(|a, b| a.object_type.cmp(&b.object_type).then_with(|| a.id.cmp(&b.id)));
    if assets.is_empty() {
        if let Some(t) = &args.object_type {
            let mut types: Vec<&str> = catalog.assets().iter().map(|a| &*a.object_type).collect();
            types.sort_unstable();
            types.dedup();
            let close = crate::diag::suggest::closest(t, types);
            common::emit_plain(
                &Diagnostic::new(Code::E0004, format!("no asset has object type `{t}`"))
                    .with_help_opt(crate::diag::suggest::did_you_mean(&close)),
            );
            return ExitCode::from(2);
        }
    }
    let text = match args.format {
        AssetsFormat::Json => {
            let list: Vec<serde_json::Value> = assets
                .iter()
                .map(|a| {
                    serde_json::json!({
                        "assetId": a.id,
                        "objectType": a.object_type,
                        "category": a.category,
                        "description": a.description,
                        "bboxM": a.bbox_m,
                        "placements": PlacementKind::ALL.into_iter().filter(|k| a.allows(*k)).map(PlacementKind::as_str).collect::<Vec<_>>(),
                        "receptacle": a.receptacle,
                        "catalog": catalog.source_of(a).name,
                    })
                })
                .collect();
            let mut s = serde_json::to_string_pretty(&list).unwrap_or_else(|_| "[]".into());
            s.push('\n');
            s
        }
        AssetsFormat::Human => {
            let mut s = String::new();
            let _ = writeln!(
                s,
                "{:<32} {:<16} {:<18} {:<6} {:<4} catalog",
                "asset", "type", "bbox m", "kinds", "rec"
            );
            for a in &assets {
                let _ = writeln!(
                    s,
                    "{:<32} {:<16} {:<18} {:<6} {:<4} {}",
                    a.id,
                    a.object_type,
                    f3(a.bbox_m),
                    a.placements.letters(),
                    if a.receptacle { "yes" } else { "no" },
                    catalog.source_of(a).name
                );
            }
            let _ = writeln!(s, "{} asset(s)", assets.len());
            s
        }
    };
    match common::write_output(None, &text) {
        Ok(()) => ExitCode::SUCCESS,
        Err(d) => {
            common::emit_plain(&d);
            ExitCode::from(2)
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn sizes_parse() {
        assert_eq!(parse_size("200x100x80cm"), Ok([2.0, 1.0, 0.8]));
        assert_eq!(parse_size("2 x 1 x 0.5 m"), Ok([2.0, 1.0, 0.5]));
        assert!(parse_size("200x100x80").is_err());
        assert!(parse_size("200x100cm").is_err());
        assert!(parse_size("0x1x1m").is_err());
    }
}

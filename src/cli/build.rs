//! `holoc build SCENE.holo [-o house.json] [--seed N] [--emit STAGE] [--report FILE] …`.

use super::common::{self, ColorChoice, DiagFormat};
use crate::compile::BuildOptions;
use crate::plan::PlanOptions;
use crate::solve::Solver;
use crate::source::SourceMap;
use clap::ValueEnum;
use std::path::PathBuf;
use std::process::ExitCode;

/// What `holoc build` prints: the dump of one stage, or the house.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, ValueEnum)]
pub enum Emit {
    /// The syntax tree.
    Ast,
    /// The checked scene.
    Scene,
    /// The floor plan: rooms, walls, doors, windows, keep-out zones.
    Plan,
    /// The chosen assets with their scores.
    Resolved,
    /// The solved layout.
    Layout,
    /// The AI2-THOR house JSON.
    #[default]
    House,
    /// The house in 3D as glTF 2.0 binary (as `holoc export` writes it; needs `-o`).
    Glb,
}

/// The floor solver, as named on the command line.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, ValueEnum)]
pub enum SolverArg {
    /// Depth-first search with branch and bound (default).
    #[default]
    Dfs,
    /// Mixed-integer linear programming (good_lp).
    Milp,
}

/// Arguments of `holoc build`.
#[derive(Debug, clap::Args)]
pub struct BuildArgs {
    /// The `.holo` scene.
    pub file: PathBuf,
    /// Where to write the product (stdout when absent or `-`); written atomically.
    #[arg(short, long)]
    pub output: Option<PathBuf>,
    /// Overrides the scene's seed.
    #[arg(long)]
    pub seed: Option<u64>,
    /// What to produce.
    #[arg(long, value_enum, default_value_t = Emit::House)]
    pub emit: Emit,
    /// Also write the build report (assets, poses, constraints, objects left out) to this file.
    #[arg(long)]
    pub report: Option<PathBuf>,
    /// The floor solver.
    #[arg(long, value_enum, default_value_t = SolverArg::Dfs)]
    pub solver: SolverArg,
    /// The search budget per room in nodes (default 1000, at most 10000); the search never
    /// looks at the clock.
    #[arg(long, value_parser = clap::value_parser!(u64).range(0..=crate::solve::MAX_NODE_BUDGET))]
    pub node_budget: Option<u64>,
    /// The radius of the agent (metres) that must reach every object and all the free floor
    /// from a door (default 0.25, AI2-THOR's agent).
    #[arg(long, value_name = "METRES", value_parser = parse_radius)]
    pub agent_radius: Option<f64>,
    /// Repair a floor plan that does not build by moving room corners as little as possible
    /// (W0307) before planning, as `holoc repair` does.
    #[arg(long)]
    pub repair: bool,
    /// Add a doorway for every room that cannot be reached from outside (warning W0302)
    /// instead of failing with E0314/E0315.
    #[arg(long)]
    pub add_doors: bool,
    /// User asset catalogs.
    #[command(flatten)]
    pub catalogs: super::assets::CatalogArgs,
    /// How to print diagnostics.
    #[arg(long, value_enum, default_value_t = DiagFormat::Human)]
    pub format: DiagFormat,
    /// When to colour human diagnostics.
    #[arg(long, value_enum, default_value_t = ColorChoice::Auto)]
    pub color: ColorChoice,
    /// Print no summary line at the end (diagnostics are still printed).
    #[arg(short, long)]
    pub quiet: bool,
    /// Leave out things the catalog lacks instead of letting an asset of another type that does
    /// the same job stand in (W0403).
    #[arg(long)]
    pub no_stand_ins: bool,
    /// Make nothing: things no catalog has are stood in for or left out, and the house uses
    /// built-in assets only (for a plain `CreateHouse` without the run-time asset hook).
    #[arg(long)]
    pub no_make: bool,
    /// Where to write the folders of the assets holoc makes (default: `<house stem>.assets/`
    /// beside `-o`).
    #[arg(long, value_name = "DIR")]
    pub assets_dir: Option<PathBuf>,
}

/// Runs `holoc build`.
pub fn run(args: &BuildArgs) -> ExitCode {
    let started = std::time::Instant::now();
    let mut sources = SourceMap::new();
    let file = match common::read_source(&mut sources, &args.file) {
        Ok(id) => id,
        Err(d) => {
            common::emit_plain(&d);
            return ExitCode::from(2);
        }
    };
    if matches!(args.emit, Emit::Ast | Emit::Scene) {
        return emit_front(&sources, file, args);
    }
    let solver = match args.solver {
        SolverArg::Dfs => Solver::Dfs,
        SolverArg::Milp => Solver::Milp,
    };
    let request = BuildRequest {
        catalogs: &args.catalogs,
        seed: args.seed,
        add_doors: args.add_doors,
        solver,
        node_budget: args.node_budget,
        agent_radius_m: args.agent_radius,
        repair: args.repair,
        format: args.format,
        color: args.color,
        stdout_taken: args.output.as_deref().is_none_or(|p| p.as_os_str() == "-"),
        stand_ins: !args.no_stand_ins,
        make: !args.no_make,
    };
    if args.emit == Emit::Glb && request.stdout_taken {
        common::emit_plain(
            &crate::diag::Diagnostic::new(
                crate::diag::Code::E0004,
                "`--emit glb` writes a binary file: name it with `-o`",
            )
            .with_help("e.g. `-o out/house.glb`"),
        );
        return ExitCode::from(2);
    }
    let (product, catalog, diagnostics) = match run_build(&mut sources, file, &request) {
        Ok(built) => built,
        Err(code) => return code,
    };
    // The assets holoc made, written before the house that names them.
    let made = crate::make::used_in(
        &product.resolved,
        product.objects.iter().map(|o| o.asset_id.as_str()),
    );
    let made_folder = args.assets_dir.clone().or_else(|| match args.output.as_deref() {
        Some(p) if p.as_os_str() != "-" => Some(crate::make::folder_beside(p)),
        _ => None,
    });
    let writes_house = args.emit == Emit::House;
    if let (false, true, Some(dir)) = (made.is_empty(), writes_house, &made_folder) {
        let refs: Vec<&crate::make::MadeAsset> = made.iter().map(AsRef::as_ref).collect();
        if let Err(e) = crate::make::runtime::write_all(dir, &refs) {
            common::emit_plain(&crate::diag::Diagnostic::new(
                crate::diag::Code::E0001,
                format!("cannot write the made assets into {}: {e}", dir.display()),
            ));
            return ExitCode::from(2);
        }
    }
    let bytes: Vec<u8> = match args.emit {
        Emit::Glb => {
            let options = crate::export::ExportOptions {
                made: std::sync::Arc::new(crate::export::MadeMeshes::of_made(&made)),
                ..crate::export::ExportOptions::default()
            };
            match super::export::export_or_report(&product.house.house, &catalog, &options) {
                Ok(e) => e.to_glb(),
                Err(code) => return code,
            }
        }
        Emit::Plan => product.plan.dump(&product.scene).into_bytes(),
        Emit::Resolved => product.resolved.dump(&product.scene, &catalog).into_bytes(),
        Emit::Layout => {
            crate::report::pins::layout_pins(&product.layout, &product.scene).into_bytes()
        }
        Emit::House | Emit::Ast | Emit::Scene => product.house.to_json_string().into_bytes(),
    };
    if let Some(path) = &args.report {
        let mut report = crate::report::report(&product, &catalog);
        crate::report::add_made_folder(&mut report, made_folder.as_deref());
        // Catalog paths relative to the project (the folder of `holoc.toml`, else the current
        // folder): a report kept as a golden holds no absolute path.
        let base = super::assets::project_file()
            .and_then(|p| p.parent().map(std::path::Path::to_path_buf))
            .or_else(|| std::env::current_dir().ok())
            .unwrap_or_default();
        crate::report::portable_catalog_paths(&mut report, &base);
        let mut json = serde_json::to_string_pretty(&report).unwrap_or_default();
        json.push('\n');
        if let Err(d) = common::write_atomic(path, json.as_bytes()) {
            common::emit_plain(&d);
            return ExitCode::from(2);
        }
    }
    let written = match args.output.as_deref() {
        Some(p) if p.as_os_str() != "-" => common::write_atomic(p, &bytes),
        _ => common::write_output(None, &String::from_utf8_lossy(&bytes)),
    };
    if let Err(d) = written {
        common::emit_plain(&d);
        return ExitCode::from(2);
    }
    if !args.quiet {
        let summary = crate::report::Summary::of(&product);
        let target = match args.output.as_deref() {
            Some(p) if p.as_os_str() != "-" => p.display().to_string(),
            _ => "stdout".to_string(),
        };
        let made_note = match (if writes_house { made.len() } else { 0 }, &made_folder) {
            (0, _) => String::new(),
            (n, Some(dir)) => {
                format!(", {n} asset{} made in {}", if n == 1 { "" } else { "s" }, dir.display())
            }
            (n, None) => format!(
                ", {n} asset{} made (not written: name a folder with --assets-dir)",
                if n == 1 { "" } else { "s" }
            ),
        };
        common::emit_status(&format!(
            "built {target}: {summary}{made_note}, in {} ms",
            started.elapsed().as_millis()
        ));
    }
    common::exit_for(&diagnostics)
}

/// `--emit ast` and `--emit scene`: the front end only.
fn emit_front(sources: &SourceMap, file: crate::source::FileId, args: &BuildArgs) -> ExitCode {
    let stdout_taken = args.output.as_deref().is_none_or(|p| p.as_os_str() == "-");
    let parsed = crate::parse::parse(sources, file);
    let text = if args.emit == Emit::Ast {
        common::emit_beside(sources, &parsed.diagnostics, args.format, args.color, stdout_taken);
        format!("{:#?}\n", parsed.value.items)
    } else {
        let checked = crate::compile::check_file(sources, file);
        common::emit_beside(sources, &checked.diagnostics, args.format, args.color, stdout_taken);
        match &checked.value {
            Some(scene) if !checked.has_errors() => crate::check::dump(scene),
            _ => return common::exit_for(&checked.diagnostics),
        }
    };
    if let Err(d) = common::write_output(args.output.as_deref(), &text) {
        common::emit_plain(&d);
        return ExitCode::from(2);
    }
    if parsed.has_errors() {
        ExitCode::from(1)
    } else {
        ExitCode::SUCCESS
    }
}

/// Reads `--agent-radius`: metres, between 0.05 and 1.
pub(crate) fn parse_radius(text: &str) -> Result<f64, String> {
    let v: f64 = text
        .trim()
        .trim_end_matches('m')
        .trim()
        .parse()
        .map_err(|_| format!("`{text}` is not a number of metres"))?;
    if !(0.05..=1.0).contains(&v) {
        return Err(format!("the agent's radius must be between 0.05 and 1 m, not {v}"));
    }
    Ok(v)
}

/// What `holoc build` and `holoc render` ask of the pipeline.
pub(crate) struct BuildRequest<'a> {
    pub catalogs: &'a super::assets::CatalogArgs,
    pub seed: Option<u64>,
    pub add_doors: bool,
    pub solver: Solver,
    pub node_budget: Option<u64>,
    pub agent_radius_m: Option<f64>,
    pub repair: bool,
    pub format: DiagFormat,
    pub color: ColorChoice,
    /// Whether the product goes to stdout (then json and lsp diagnostics go to stderr).
    pub stdout_taken: bool,
    /// Whether stand-ins fill in for things the catalog lacks.
    pub stand_ins: bool,
    /// Whether holoc makes what no catalog has.
    pub make: bool,
}

/// Loads the catalogs, builds the file and prints the diagnostics. On success: the build, the
/// catalog it used and every diagnostic; otherwise the exit code.
pub(crate) fn run_build(
    sources: &mut SourceMap,
    file: crate::source::FileId,
    request: &BuildRequest<'_>,
) -> Result<(crate::compile::Built, crate::resolve::Catalog, Vec<crate::diag::Diagnostic>), ExitCode>
{
    let loaded = request.catalogs.load(sources);
    if loaded.has_errors() {
        common::emit_beside(
            sources,
            &loaded.diagnostics,
            request.format,
            request.color,
            request.stdout_taken,
        );
        return Err(ExitCode::from(1));
    }
    let catalog = loaded.value;
    let options = BuildOptions {
        seed: request.seed,
        plan: PlanOptions { add_doors: request.add_doors, ..PlanOptions::default() },
        catalog: &catalog,
        solver: request.solver,
        node_budget: request.node_budget,
        agent_radius_m: request.agent_radius_m,
        repair: request.repair,
        stand_ins: request.stand_ins,
        make: request.make,
        rooms_in_parallel: true,
    };
    let mut built = crate::compile::build(sources, file, &options);
    built.diagnostics.splice(0..0, loaded.diagnostics);
    // Before anything is written: the objathor assets the house uses must be on disk.
    if let Some(product) = &built.value {
        built.diagnostics.extend(crate::resolve::objathor::check_on_disk(
            &catalog,
            product.objects.iter().map(|o| o.asset_id.as_str()),
            &|_| None,
        ));
        if built.diagnostics.iter().any(crate::diag::Diagnostic::is_error) {
            built.value = None;
        }
    }
    common::emit_beside(
        sources,
        &built.diagnostics,
        request.format,
        request.color,
        request.stdout_taken,
    );
    match built.value {
        Some(product) => Ok((product, catalog, built.diagnostics)),
        None => Err(common::exit_for(&built.diagnostics)),
    }
}

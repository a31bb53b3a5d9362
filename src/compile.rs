//! The driver: runs the stages in order on one file and collects their diagnostics.
//!
//! A stage runs only when the stages before it produced no error. The driver does no I/O:
//! sources come in a [`SourceMap`], catalogs as values.

use crate::check::Scene;
use crate::diag::{Diagnostic, Outcome};
use crate::lower::{HouseJson, LoweredObject};
use crate::plan::{FloorPlan, PlanOptions};
use crate::resolve::structure::StructureCatalog;
use crate::resolve::{Catalog, Resolved};
use crate::solve::{Layout, SolveOptions, Solver};
use crate::source::{FileId, SourceMap};

/// Parses and checks one file. The scene is `None` when the file has syntax errors.
pub fn check_file(sources: &SourceMap, file: FileId) -> Outcome<Option<Scene>> {
    let parsed = crate::parse::parse(sources, file);
    let mut diagnostics = parsed.diagnostics;
    let parse_failed = diagnostics.iter().any(Diagnostic::is_error);
    let checked = crate::check::check(&parsed.value);
    // The checker also runs on a file with syntax errors (the editor wants every problem);
    // bad lines are error nodes that it skips.
    diagnostics.extend(checked.diagnostics);
    let scene = (!parse_failed).then_some(checked.value);
    Outcome::new(scene, diagnostics)
}

/// The last stage `holoc check` runs.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, PartialOrd, Ord)]
pub enum CheckStage {
    /// The grammar only.
    Parse,
    /// Names, references, units and kinds.
    Check,
    /// The floor plan: outlines, walls, doors, windows, reachability.
    Plan,
    /// Assets and materials (everything before the layout solver).
    #[default]
    Resolve,
}

/// What the stages before the layout solver made of one file: each product is there when its
/// stage ran (the stages before it produced no error).
#[derive(Clone, Debug)]
pub struct Analysed {
    /// The syntax tree (with error nodes where lines could not be read).
    pub ast: crate::ast::File,
    /// The checked scene, when the file has no syntax or checker errors.
    pub scene: Option<Scene>,
    /// The floor plan, when the plan stage ran without errors.
    pub plan: Option<FloorPlan>,
    /// The chosen assets, when the asset stage ran.
    pub resolved: Option<Resolved>,
    /// Every diagnostic, in the order the stages produced them.
    pub diagnostics: Vec<Diagnostic>,
}

/// Runs every stage up to `last` that does not need the layout solver, each only when the ones
/// before it produced no error, and keeps every product: what an editor reads for hover,
/// go-to-definition and diagnostics.
pub fn analyse(sources: &SourceMap, file: FileId, catalog: &Catalog, last: CheckStage) -> Analysed {
    // Parsed without a cache to fill: a second copy of every item would live as long as the
    // analysis (twice the memory of the tree on a 32 MiB file).
    let parsed = crate::parse::parse(sources, file);
    analyse_parsed(parsed, catalog, last, &mut crate::resolve::RankCache::default())
}

/// What an editor keeps between two analyses of one document: the parsed top-level items and
/// the asset rankings, reused where the text and the queries have not changed.
#[derive(Debug, Default)]
pub struct AnalysisCache {
    /// Top-level items by their text.
    pub parse: crate::parse::ParseCache,
    /// Asset rankings by query (for one catalog and seed).
    pub ranks: crate::resolve::RankCache,
}

/// [`analyse`], reusing what `cache` holds of earlier versions of the document (the language
/// server keeps one cache per document); the result is the same as without it.
pub fn analyse_cached(
    sources: &SourceMap,
    file: FileId,
    catalog: &Catalog,
    last: CheckStage,
    cache: &mut AnalysisCache,
) -> Analysed {
    let parsed = crate::parse::parse_cached(sources, file, &mut cache.parse);
    analyse_parsed(parsed, catalog, last, &mut cache.ranks)
}

/// The stages after the parse of [`analyse_cached`].
fn analyse_parsed(
    parsed: Outcome<crate::ast::File>,
    catalog: &Catalog,
    last: CheckStage,
    ranks: &mut crate::resolve::RankCache,
) -> Analysed {
    let mut analysed = Analysed {
        ast: parsed.value,
        scene: None,
        plan: None,
        resolved: None,
        diagnostics: parsed.diagnostics,
    };
    if last == CheckStage::Parse {
        return analysed;
    }
    let parse_failed = has_errors(&analysed.diagnostics);
    // The checker also runs on a file with syntax errors (the editor wants every problem);
    // bad lines are error nodes that it skips.
    let checked = crate::check::check(&analysed.ast);
    analysed.diagnostics.extend(checked.diagnostics);
    if parse_failed || has_errors(&analysed.diagnostics) || last == CheckStage::Check {
        if !parse_failed && !has_errors(&analysed.diagnostics) {
            analysed.scene = Some(checked.value);
        }
        return analysed;
    }
    let scene = checked.value;
    let planned =
        crate::plan::plan_with(&scene, StructureCatalog::builtin(), PlanOptions::default());
    analysed.diagnostics.extend(planned.diagnostics);
    if last == CheckStage::Plan || has_errors(&analysed.diagnostics) {
        analysed.scene = Some(scene);
        return analysed;
    }
    analysed.plan = Some(planned.value);
    let resolved = crate::resolve::resolve_cached(
        &scene,
        catalog,
        scene.seed,
        &crate::resolve::ResolveOptions::default(),
        ranks,
    );
    analysed.diagnostics.extend(resolved.diagnostics);
    analysed.resolved = Some(resolved.value);
    analysed.scene = Some(scene);
    analysed
}

/// Runs every stage up to `last` that does not need the layout solver, each only when the ones
/// before it produced no error, and returns every diagnostic: what `holoc check` and an editor
/// show. Floor-plan, door, window and asset problems that `build` would stop on appear here.
pub fn check_stages(
    sources: &SourceMap,
    file: FileId,
    catalog: &Catalog,
    last: CheckStage,
) -> Vec<Diagnostic> {
    analyse(sources, file, catalog, last).diagnostics
}

/// How to build.
#[derive(Clone, Copy, Debug)]
pub struct BuildOptions<'a> {
    /// Overrides the scene's seed.
    pub seed: Option<u64>,
    /// Options of the plan stage.
    pub plan: PlanOptions,
    /// The asset catalog objects are resolved against.
    pub catalog: &'a Catalog,
    /// The floor solver.
    pub solver: Solver,
    /// The search budget per room (`None`: the solver's default).
    pub node_budget: Option<u64>,
    /// The radius of the agent the layout must leave room for (`None`: 0.25 m).
    pub agent_radius_m: Option<f64>,
    /// Whether a floor plan the plan stage rejects is first repaired geometrically (W0307).
    pub repair: bool,
    /// Whether assets of another type that do the same job stand in for things the catalog
    /// lacks (W0403); `--no-stand-ins` turns it off.
    pub stand_ins: bool,
    /// Whether holoc makes what no catalog has (`crate::make`); on by default.
    pub make: bool,
    /// Whether the rooms are solved in parallel ([`SolveOptions::rooms_in_parallel`]).
    pub rooms_in_parallel: bool,
}

impl<'a> BuildOptions<'a> {
    /// The defaults of `holoc build` with this catalog: the scene's seed, no added doors, the
    /// DFS with its default budget, stand-ins on.
    pub fn new(catalog: &'a Catalog) -> BuildOptions<'a> {
        BuildOptions {
            seed: None,
            plan: PlanOptions::default(),
            catalog,
            solver: Solver::Dfs,
            node_budget: None,
            agent_radius_m: None,
            repair: false,
            stand_ins: true,
            make: true,
            rooms_in_parallel: true,
        }
    }
}

/// Everything a build produced, stage by stage.
#[derive(Clone, Debug)]
pub struct Built {
    /// The checked scene (with the seed override applied).
    pub scene: Scene,
    /// The floor plan.
    pub plan: FloorPlan,
    /// The chosen assets.
    pub resolved: Resolved,
    /// The solved layout.
    pub layout: Layout,
    /// The objects as they go into the house.
    pub objects: Vec<LoweredObject>,
    /// The house.
    pub house: HouseJson,
}

fn has_errors(diagnostics: &[Diagnostic]) -> bool {
    diagnostics.iter().any(Diagnostic::is_error)
}

/// Runs parse → check → plan → resolve → solve → lower on one file. The product is `None`
/// when a stage reported an error.
pub fn build(
    sources: &SourceMap,
    file: FileId,
    options: &BuildOptions<'_>,
) -> Outcome<Option<Built>> {
    let (ready, mut diagnostics) = before_solve(sources, file, options);
    let Some(Ready { scene, plan, resolved, solve_options }) = ready else {
        return Outcome::new(None, diagnostics);
    };
    let solved = crate::solve::solve(&scene, &plan, &resolved, &solve_options);
    diagnostics.extend(solved.diagnostics);
    if has_errors(&diagnostics) || crate::cancel::requested() {
        return Outcome::new(None, diagnostics);
    }
    let layout = solved.value;
    let mut resolved = resolved;
    crate::make::fit_to_layout(&layout, &mut resolved);
    crate::cancel::stage("lower");
    let mut plan = plan;
    plan.agent = crate::lower::agent_start(&plan, &layout);
    let objects = crate::lower::objects(&layout, &scene, &plan, &resolved);
    let house = crate::lower::lower(&scene, &plan, &objects);
    Outcome::new(Some(Built { scene, plan, resolved, layout, objects, house }), diagnostics)
}

/// What `build` hands the layout solver.
struct Ready {
    scene: Scene,
    plan: FloorPlan,
    resolved: Resolved,
    solve_options: SolveOptions,
}

/// The stages of `build` before the layout solver, and their diagnostics; `None` when one
/// reported an error (or the work was cancelled, `crate::cancel`).
fn before_solve(
    sources: &SourceMap,
    file: FileId,
    options: &BuildOptions<'_>,
) -> (Option<Ready>, Vec<Diagnostic>) {
    // Each stage says where a batch job is (`crate::cancel`); a job past its time limit stops
    // at the next stage, or inside the solver's search, and its result is thrown away.
    crate::cancel::stage("check");
    let checked = check_file(sources, file);
    let mut diagnostics = checked.diagnostics;
    let Some(mut scene) = checked.value.filter(|_| !has_errors(&diagnostics)) else {
        return (None, diagnostics);
    };
    if let Some(seed) = options.seed {
        scene.seed = seed;
    }
    if options.repair {
        let repaired = crate::plan::repair::repair(&scene, StructureCatalog::builtin());
        if repaired.value.changed {
            scene = crate::plan::repair::apply(&scene, &repaired.value);
        }
        diagnostics.extend(repaired.diagnostics);
    }
    crate::cancel::stage("plan");
    let planned = crate::plan::plan_with(&scene, StructureCatalog::builtin(), options.plan);
    if options.repair {
        diagnostics
            .extend(planned.diagnostics.into_iter().map(crate::plan::repair::explain_unrepaired));
    } else {
        diagnostics.extend(planned.diagnostics);
    }
    if has_errors(&diagnostics) || crate::cancel::requested() {
        return (None, diagnostics);
    }
    let plan = planned.value;
    crate::cancel::stage("resolve");
    let resolved = crate::resolve::resolve_with(
        &scene,
        options.catalog,
        scene.seed,
        &crate::resolve::ResolveOptions { stand_ins: options.stand_ins, make: options.make },
    );
    diagnostics.extend(resolved.diagnostics);
    if has_errors(&diagnostics) || crate::cancel::requested() {
        return (None, diagnostics);
    }
    let resolved = resolved.value;
    crate::cancel::stage("solve");
    let mut solve_options = SolveOptions {
        solver: options.solver,
        seed: scene.seed,
        rooms_in_parallel: options.rooms_in_parallel,
        ..SolveOptions::default()
    };
    if let Some(budget) = options.node_budget {
        solve_options.node_budget = budget;
    }
    if let Some(radius) = options.agent_radius_m {
        solve_options.agent_radius_m = radius;
    }
    (Some(Ready { scene, plan, resolved, solve_options }), diagnostics)
}

/// Runs `build`'s stages up to the layout solver and solves the rooms one by one
/// ([`crate::solve::solve_by_room`]): `on_room` is called with each room as soon as it is
/// solved, the room named `first` before the others, and with the scene it belongs to. The
/// diagnostics are every stage's up to the solver, exactly as `build` gives them (those of
/// the solver are the rooms' own and their relations given up, in room order); the layout is
/// `None` when a stage reported an error or the work was cancelled (`crate::cancel`).
pub fn solve_by_room(
    sources: &SourceMap,
    file: FileId,
    options: &BuildOptions<'_>,
    first: Option<&str>,
    on_room: &(dyn Fn(&Scene, crate::solve::RoomDone<'_>) + Sync),
) -> Outcome<Option<Layout>> {
    let (ready, mut diagnostics) = before_solve(sources, file, options);
    let Some(Ready { scene, plan, resolved, solve_options }) = ready else {
        return Outcome::new(None, diagnostics);
    };
    let first = first.and_then(|name| scene.rooms.iter().find(|r| r.name == name)).map(|r| r.id);
    let report = |done: crate::solve::RoomDone<'_>| on_room(&scene, done);
    let solved =
        crate::solve::solve_by_room(&scene, &plan, &resolved, &solve_options, first, &report);
    diagnostics.extend(solved.diagnostics);
    if has_errors(&diagnostics) || crate::cancel::requested() {
        return Outcome::new(None, diagnostics);
    }
    Outcome::new(Some(solved.value), diagnostics)
}

/// Runs every stage on one file as far as it gets, with the embedded catalogs, and returns all
/// diagnostics (what an editor shows, and what the diagnostics catalogue's examples are checked
/// against).
pub fn diagnose(sources: &SourceMap, file: FileId) -> Vec<Diagnostic> {
    let catalog = Catalog::embedded();
    let options = BuildOptions::new(&catalog);
    build(sources, file, &options).diagnostics
}

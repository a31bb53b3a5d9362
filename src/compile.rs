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

/// Runs every stage up to `last` that does not need the layout solver, each only when the ones
/// before it produced no error, and returns every diagnostic: what `holoc check` and an editor
/// show. Floor-plan, door, window and asset problems that `build` would stop on appear here.
pub fn check_stages(
    sources: &SourceMap,
    file: FileId,
    catalog: &Catalog,
    last: CheckStage,
) -> Vec<Diagnostic> {
    if last == CheckStage::Parse {
        return crate::parse::parse(sources, file).diagnostics;
    }
    let checked = check_file(sources, file);
    let mut diagnostics = checked.diagnostics;
    let Some(scene) = checked.value.filter(|_| !has_errors(&diagnostics)) else {
        return diagnostics;
    };
    if last == CheckStage::Check {
        return diagnostics;
    }
    let planned =
        crate::plan::plan_with(&scene, StructureCatalog::builtin(), PlanOptions::default());
    diagnostics.extend(planned.diagnostics);
    if last == CheckStage::Plan || has_errors(&diagnostics) {
        return diagnostics;
    }
    diagnostics.extend(crate::resolve::resolve(&scene, catalog, scene.seed).diagnostics);
    diagnostics
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
    let checked = check_file(sources, file);
    let mut diagnostics = checked.diagnostics;
    let Some(mut scene) = checked.value.filter(|_| !has_errors(&diagnostics)) else {
        return Outcome::new(None, diagnostics);
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
    let planned = crate::plan::plan_with(&scene, StructureCatalog::builtin(), options.plan);
    if options.repair {
        diagnostics
            .extend(planned.diagnostics.into_iter().map(crate::plan::repair::explain_unrepaired));
    } else {
        diagnostics.extend(planned.diagnostics);
    }
    if has_errors(&diagnostics) {
        return Outcome::new(None, diagnostics);
    }
    let plan = planned.value;
    let resolved = crate::resolve::resolve_with(
        &scene,
        options.catalog,
        scene.seed,
        &crate::resolve::ResolveOptions { stand_ins: options.stand_ins },
    );
    diagnostics.extend(resolved.diagnostics);
    if has_errors(&diagnostics) {
        return Outcome::new(None, diagnostics);
    }
    let resolved = resolved.value;
    let mut solve_options =
        SolveOptions { solver: options.solver, seed: scene.seed, ..SolveOptions::default() };
    if let Some(budget) = options.node_budget {
        solve_options.node_budget = budget;
    }
    if let Some(radius) = options.agent_radius_m {
        solve_options.agent_radius_m = radius;
    }
    let solved = crate::solve::solve(&scene, &plan, &resolved, &solve_options);
    diagnostics.extend(solved.diagnostics);
    if has_errors(&diagnostics) {
        return Outcome::new(None, diagnostics);
    }
    let layout = solved.value;
    let mut plan = plan;
    plan.agent = crate::lower::agent_start(&plan, &layout);
    let objects = crate::lower::objects(&layout, &scene, &plan, &resolved);
    let house = crate::lower::lower(&scene, &plan, &objects);
    Outcome::new(Some(Built { scene, plan, resolved, layout, objects, house }), diagnostics)
}

/// Runs every stage on one file as far as it gets, with the embedded catalogs, and returns all
/// diagnostics (what an editor shows, and what the diagnostics catalogue's examples are checked
/// against).
pub fn diagnose(sources: &SourceMap, file: FileId) -> Vec<Diagnostic> {
    let catalog = Catalog::embedded();
    let options = BuildOptions::new(&catalog);
    build(sources, file, &options).diagnostics
}

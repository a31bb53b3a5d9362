//! `holoc build SCENE.holo [-o house.json] [--seed N] [--emit plan|house] [--add-doors]`.

use super::common::{self, ColorChoice, DiagFormat};
use crate::check::Scene;
use crate::diag::Outcome;
use crate::lower::{HouseJson, LoweredObject};
use crate::plan::{FloorPlan, PlanOptions};
use crate::resolve::structure::StructureCatalog;
use crate::source::{FileId, SourceMap};
use clap::ValueEnum;
use std::path::PathBuf;
use std::process::ExitCode;

/// What `holoc build` prints.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, ValueEnum)]
pub enum Emit {
    /// The human-readable floor-plan dump (what the plan snapshots show).
    Plan,
    /// The AI2-THOR house JSON.
    #[default]
    House,
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
    /// Add a doorway for every room that cannot be reached from outside (warning W0302)
    /// instead of failing with E0314/E0315.
    #[arg(long)]
    pub add_doors: bool,
    /// How to print diagnostics.
    #[arg(long, value_enum, default_value_t = DiagFormat::Human)]
    pub format: DiagFormat,
    /// When to colour human diagnostics.
    #[arg(long, value_enum, default_value_t = ColorChoice::Auto)]
    pub color: ColorChoice,
}

/// The products of a successful build.
#[derive(Clone, Debug)]
pub struct BuildProduct {
    /// The checked scene.
    pub scene: Scene,
    /// Its floor plan.
    pub plan: FloorPlan,
    /// The house.
    pub house: HouseJson,
}

/// Runs parse → check → plan → lower on one file. The product is `None` when a stage failed.
pub fn build_file(
    sources: &SourceMap,
    file: FileId,
    seed: Option<u64>,
    options: PlanOptions,
    objects: &[LoweredObject],
) -> Outcome<Option<BuildProduct>> {
    let checked = crate::compile::check_file(sources, file);
    let mut diagnostics = checked.diagnostics;
    let Some(mut scene) =
        checked.value.filter(|_| !diagnostics.iter().any(crate::diag::Diagnostic::is_error))
    else {
        return Outcome::new(None, diagnostics);
    };
    if let Some(seed) = seed {
        scene.seed = seed;
    }
    let planned = crate::plan::plan_with(&scene, StructureCatalog::builtin(), options);
    diagnostics.extend(planned.diagnostics);
    if diagnostics.iter().any(crate::diag::Diagnostic::is_error) {
        return Outcome::new(None, diagnostics);
    }
    let plan = planned.value;
    let house = crate::lower::lower(&scene, &plan, objects);
    Outcome::new(Some(BuildProduct { scene, plan, house }), diagnostics)
}

/// Runs `holoc build`.
pub fn run(args: &BuildArgs) -> ExitCode {
    let mut sources = SourceMap::new();
    let file = match common::read_source(&mut sources, &args.file) {
        Ok(id) => id,
        Err(d) => {
            common::emit_plain(&d);
            return ExitCode::from(2);
        }
    };
    let options = PlanOptions { add_doors: args.add_doors };
    let built = build_file(&sources, file, args.seed, options, &[]);
    common::emit(&sources, &built.diagnostics, args.format, args.color);
    let Some(product) = built.value else {
        return common::exit_for(&built.diagnostics);
    };
    let text = match args.emit {
        Emit::Plan => product.plan.dump(&product.scene),
        Emit::House => product.house.to_json_string(),
    };
    if let Err(d) = common::write_output(args.output.as_deref(), &text) {
        common::emit_plain(&d);
        return ExitCode::from(2);
    }
    common::exit_for(&built.diagnostics)
}

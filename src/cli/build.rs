//! `holoc build SCENE.holo [-o house.json] [--seed N] [--emit plan|house] [--add-doors]`.

use super::common::{self, ColorChoice, DiagFormat};
use crate::compile::BuildOptions;
use crate::plan::PlanOptions;
use crate::source::SourceMap;
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
    /// User asset catalogs.
    #[command(flatten)]
    pub catalogs: super::assets::CatalogArgs,
    /// How to print diagnostics.
    #[arg(long, value_enum, default_value_t = DiagFormat::Human)]
    pub format: DiagFormat,
    /// When to colour human diagnostics.
    #[arg(long, value_enum, default_value_t = ColorChoice::Auto)]
    pub color: ColorChoice,
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
    let loaded = args.catalogs.load(&mut sources);
    if loaded.has_errors() {
        common::emit(&sources, &loaded.diagnostics, args.format, args.color);
        return ExitCode::from(1);
    }
    let catalog = loaded.value;
    let options = BuildOptions {
        seed: args.seed,
        plan: PlanOptions { add_doors: args.add_doors },
        catalog: &catalog,
    };
    let mut built = crate::compile::build(&sources, file, &options);
    built.diagnostics.splice(0..0, loaded.diagnostics);
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

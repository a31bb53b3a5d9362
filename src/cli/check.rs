//! `holoc check FILE…`: every stage before the layout solver, every problem reported.

use super::common::{self, ColorChoice, DiagFormat};
use crate::compile::CheckStage;
use crate::source::SourceMap;
use std::path::PathBuf;
use std::process::ExitCode;

/// Arguments of `holoc check`.
#[derive(Debug, clap::Args)]
pub struct CheckArgs {
    /// The `.holo` files to check.
    #[arg(required = true)]
    pub files: Vec<PathBuf>,
    /// How to print diagnostics.
    #[arg(long, value_enum, default_value_t = DiagFormat::Human)]
    pub format: DiagFormat,
    /// When to colour human diagnostics.
    #[arg(long, value_enum, default_value_t = ColorChoice::Auto)]
    pub color: ColorChoice,
    /// The last stage to run: every stage before the layout solver by default.
    #[arg(long, value_enum, default_value_t = StageArg::Resolve)]
    pub stage: StageArg,
    /// User asset catalogs (for the asset stage).
    #[command(flatten)]
    pub catalogs: super::assets::CatalogArgs,
}

/// The last stage `holoc check` runs, as named on the command line.
#[derive(Clone, Copy, Debug, PartialEq, Eq, clap::ValueEnum)]
pub enum StageArg {
    /// The grammar only.
    Parse,
    /// Names, references, units and kinds.
    Check,
    /// The floor plan: outlines, walls, doors, windows, reachability.
    Plan,
    /// Assets and materials.
    Resolve,
}

/// Runs `holoc check`.
pub fn run(args: &CheckArgs) -> ExitCode {
    let mut sources = SourceMap::new();
    let stage = match args.stage {
        StageArg::Parse => CheckStage::Parse,
        StageArg::Check => CheckStage::Check,
        StageArg::Plan => CheckStage::Plan,
        StageArg::Resolve => CheckStage::Resolve,
    };
    let loaded = args.catalogs.load(&mut sources);
    if loaded.has_errors() {
        common::emit(&sources, &loaded.diagnostics, args.format, args.color);
        return ExitCode::from(1);
    }
    let catalog = loaded.value;
    let mut diagnostics = loaded.diagnostics;
    let mut io_failed = false;
    for path in &args.files {
        match common::read_source(&mut sources, path) {
            Ok(id) => {
                diagnostics.extend(crate::compile::check_stages(&sources, id, &catalog, stage));
            }
            Err(d) => {
                common::emit_plain(&d);
                io_failed = true;
            }
        }
    }
    common::emit(&sources, &diagnostics, args.format, args.color);
    if io_failed {
        return ExitCode::from(2);
    }
    common::exit_for(&diagnostics)
}

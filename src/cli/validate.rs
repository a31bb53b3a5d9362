//! `holoc validate HOUSE.json…`: schema and geometric checks of house files.

use super::common::{self, ColorChoice, DiagFormat};
use crate::resolve::structure::StructureCatalog;
use crate::source::SourceMap;
use std::path::PathBuf;
use std::process::ExitCode;

/// Arguments of `holoc validate`.
#[derive(Debug, clap::Args)]
pub struct ValidateArgs {
    /// The house JSON files.
    #[arg(required = true)]
    pub files: Vec<PathBuf>,
    /// User asset catalogs: they give the sizes of assets beyond the embedded AI2-THOR catalog
    /// for the footprint checks.
    #[command(flatten)]
    pub catalogs: super::assets::CatalogArgs,
    /// How to print diagnostics.
    #[arg(long, value_enum, default_value_t = DiagFormat::Human)]
    pub format: DiagFormat,
    /// When to colour human diagnostics.
    #[arg(long, value_enum, default_value_t = ColorChoice::Auto)]
    pub color: ColorChoice,
}

/// Runs `holoc validate`.
pub fn run(args: &ValidateArgs) -> ExitCode {
    let mut sources = SourceMap::new();
    let mut diagnostics = Vec::new();
    let mut io_failed = false;
    let loaded = args.catalogs.load(&mut sources);
    if loaded.has_errors() {
        common::emit(&sources, &loaded.diagnostics, args.format, args.color);
        return ExitCode::from(1);
    }
    diagnostics.extend(loaded.diagnostics);
    let catalog = loaded.value;
    for path in &args.files {
        match common::read_source(&mut sources, path) {
            Ok(id) => {
                let outcome = crate::lower::validate::validate(
                    &sources,
                    id,
                    StructureCatalog::builtin(),
                    &catalog,
                );
                diagnostics.extend(outcome.diagnostics);
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

//! `holoc check FILE…`: parse and check, report every problem.

use super::common::{self, ColorChoice, DiagFormat};
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
}

/// Runs `holoc check`.
pub fn run(args: &CheckArgs) -> ExitCode {
    let mut sources = SourceMap::new();
    let mut diagnostics = Vec::new();
    let mut io_failed = false;
    for path in &args.files {
        match common::read_source(&mut sources, path) {
            Ok(id) => diagnostics.extend(crate::compile::check_file(&sources, id).diagnostics),
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

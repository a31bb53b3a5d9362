//! `holoc repair FILE`: move room corners, as little as possible, so that the floor plan builds.

use super::common::{self, ColorChoice, DiagFormat};
use crate::diag::Diagnostic;
use crate::resolve::structure::StructureCatalog;
use crate::source::SourceMap;
use std::path::PathBuf;
use std::process::ExitCode;

/// Arguments of `holoc repair`.
#[derive(Debug, clap::Args)]
pub struct RepairArgs {
    /// The `.holo` scene whose floor plan to repair.
    pub file: PathBuf,
    /// Where to write the repaired scene (`-` or nothing: standard output).
    #[arg(short, long, conflicts_with = "write")]
    pub output: Option<PathBuf>,
    /// Rewrite the file in place (atomically).
    #[arg(long)]
    pub write: bool,
    /// How to print diagnostics.
    #[arg(long, value_enum, default_value_t = DiagFormat::Human)]
    pub format: DiagFormat,
    /// When to colour human diagnostics.
    #[arg(long, value_enum, default_value_t = ColorChoice::Auto)]
    pub color: ColorChoice,
}

/// Runs `holoc repair`.
pub fn run(args: &RepairArgs) -> ExitCode {
    let mut sources = SourceMap::new();
    let id = match common::read_source(&mut sources, &args.file) {
        Ok(id) => id,
        Err(d) => {
            common::emit_plain(&d);
            return ExitCode::from(2);
        }
    };
    let checked = crate::compile::check_file(&sources, id);
    let Some(scene) =
        checked.value.filter(|_| !checked.diagnostics.iter().any(Diagnostic::is_error))
    else {
        common::emit(&sources, &checked.diagnostics, args.format, args.color);
        return ExitCode::from(1);
    };
    let catalog = StructureCatalog::builtin();
    let repaired = crate::plan::repair::repair(&scene, catalog);
    let mut diagnostics = repaired.diagnostics.clone();
    // What the plan stage still says about the repaired plan.
    let after = crate::plan::repair::apply(&scene, &repaired.value);
    let planned = crate::plan::plan(&after, catalog);
    diagnostics.extend(
        planned
            .diagnostics
            .into_iter()
            .filter(Diagnostic::is_error)
            .map(crate::plan::repair::explain_unrepaired),
    );

    let stdout_taken = !args.write && args.output.as_deref().is_none_or(|p| p.as_os_str() == "-");
    common::emit_beside(&sources, &diagnostics, args.format, args.color, stdout_taken);
    let text = crate::diag::apply_fixes(&sources.get(id).text, id, &repaired.diagnostics);
    let target = if args.write { Some(args.file.as_path()) } else { args.output.as_deref() };
    if !args.write || repaired.value.changed {
        if let Err(d) = common::write_output(target, &text) {
            common::emit_plain(&d);
            return ExitCode::from(2);
        }
    }
    if diagnostics.iter().any(Diagnostic::is_error) {
        ExitCode::from(1)
    } else {
        ExitCode::SUCCESS
    }
}

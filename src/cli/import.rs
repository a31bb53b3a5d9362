//! `holoc import`: raw model answers → `.holo`.
//!
//! Two forms: `holoc import --stage STAGE FILE [--room NAME]` reads one answer and prints the
//! `.holo` fragment it says; `holoc import TRANSCRIPT [-o scene.holo] [--keep-layout]` reads a
//! whole scene (a holoc transcript or an original Holodeck scene JSON).

use super::common::{self, ColorChoice, DiagFormat};
use crate::diag::{Code, Diagnostic};
use crate::import::{self, ImportContext, ImportOptions, Stage, Transcript};
use crate::source::SourceMap;
use std::path::PathBuf;
use std::process::ExitCode;

/// Arguments of `holoc import`.
#[derive(Debug, clap::Args)]
pub struct ImportArgs {
    /// The answer file (with `--stage`), or a transcript / Holodeck scene JSON.
    pub file: PathBuf,
    /// Read one answer of this stage: floor-plan, wall-height, doorways, windows, objects,
    /// objects-pipe, floor-constraints, wall-constraints, small-objects, ceiling,
    /// absolute-layout.
    #[arg(long)]
    pub stage: Option<String>,
    /// The room a per-room answer is about (its label).
    #[arg(long)]
    pub room: Option<String>,
    /// Write the `.holo` here (atomically) instead of stdout.
    #[arg(short, long)]
    pub output: Option<PathBuf>,
    /// Pin the solved layout of an original scene (asset, at, facing).
    #[arg(long)]
    pub keep_layout: bool,
    /// How to print diagnostics.
    #[arg(long, value_enum, default_value_t = DiagFormat::Human)]
    pub format: DiagFormat,
    /// When to colour human diagnostics.
    #[arg(long, value_enum, default_value_t = ColorChoice::Auto)]
    pub color: ColorChoice,
}

/// Runs `holoc import`.
pub fn run(args: &ImportArgs) -> ExitCode {
    let mut sources = SourceMap::new();
    let file = match common::read_source(&mut sources, &args.file) {
        Ok(f) => f,
        Err(d) => {
            common::emit_plain(&d);
            return ExitCode::from(2);
        }
    };
    let (holo, diagnostics) = if let Some(stage_name) = &args.stage {
        let Some(stage) = Stage::parse(stage_name) else {
            let names: Vec<&str> = Stage::ALL.iter().map(|s| Stage::as_str(*s)).collect();
            common::emit_plain(
                &Diagnostic::new(Code::E0004, format!("unknown stage `{stage_name}`"))
                    .with_help(format!("stages: {}", names.join(", "))),
            );
            return ExitCode::from(2);
        };
        let mut ctx = ImportContext::new();
        ctx.set_room(args.room.as_deref());
        let out = import::import_answer(stage, &sources, file, &ctx);
        (crate::fmt::print(&out.value.fragment), out.diagnostics)
    } else {
        let text = sources.get(file).text.clone();
        let options = ImportOptions { keep_layout: args.keep_layout };
        match serde_json::from_str::<serde_json::Value>(&text) {
            Ok(value)
                if value.get("format").and_then(|f| f.as_str()) == Some("holoc-transcript") =>
            {
                match serde_json::from_value::<Transcript>(value) {
                    Ok(t) => {
                        let out = import::import_transcript(&t, &mut sources, &options);
                        (crate::fmt::print(&out.value), out.diagnostics)
                    }
                    Err(e) => {
                        common::emit_plain(
                            &Diagnostic::new(
                                Code::E0709,
                                format!("`{}` is not a valid transcript: {e}", args.file.display()),
                            )
                            .with_help(
                                "see the transcript format in the book (reference/transcript)",
                            ),
                        );
                        return ExitCode::from(1);
                    }
                }
            }
            Ok(value) => {
                let out = import::import_holodeck_scene_file(&value, &mut sources, file, &options);
                (crate::fmt::print(&out.value), out.diagnostics)
            }
            Err(e) => {
                common::emit_plain(
                    &Diagnostic::new(Code::E0709, format!("`{}` is not JSON: {e}", args.file.display()))
                        .with_help("pass a transcript or a Holodeck scene JSON, or use `--stage` for one raw answer"),
                );
                return ExitCode::from(1);
            }
        }
    };
    common::emit(&sources, &diagnostics, args.format, args.color);
    // An import with errors writes no file: an empty or partial scene would later build as
    // if it were the answer. The text still goes to stdout when no `-o` is given, to be read.
    if args.output.is_some() && diagnostics.iter().any(Diagnostic::is_error) {
        return common::exit_for(&diagnostics);
    }
    if args.format != DiagFormat::Json || args.output.is_some() {
        if let Err(d) = common::write_output(args.output.as_deref(), &holo) {
            common::emit_plain(&d);
            return ExitCode::from(2);
        }
    }
    common::exit_for(&diagnostics)
}

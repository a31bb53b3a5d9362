//! `holoc import`: raw model answers → `.holo`.
//!
//! Two forms: `holoc import --stage STAGE FILE [--room NAME]` reads one answer and prints the
//! `.holo` fragment it says; `holoc import TRANSCRIPT [-o scene.holo] [--keep-layout]` reads a
//! whole scene (a holoc transcript or an original Holodeck scene JSON).

use super::common::{self, ColorChoice, DiagFormat};
use crate::ast;
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
    let (scene, diagnostics) = if let Some(stage_name) = &args.stage {
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
        (out.value.fragment, out.diagnostics)
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
                        (out.value, out.diagnostics)
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
                (out.value, out.diagnostics)
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
    let holo = crate::fmt::print(&scene);
    common::emit(&sources, &diagnostics, args.format, args.color);
    // The scene is written whenever something could be read: the lines that could not be used
    // are diagnostics and stay in it as `// raw` comments, so nothing the model said is lost.
    // Only an import that read nothing writes no file (an existing one is left as it was).
    if let Some(path) = args.output.as_deref() {
        if !read_anything(&scene.items) {
            if args.format != DiagFormat::Json {
                common::emit_status(&format!(
                    "nothing could be read from `{}`: `{}` was not written",
                    args.file.display(),
                    path.display()
                ));
            }
            return common::exit_for(&diagnostics);
        }
    }
    if args.format != DiagFormat::Json || args.output.is_some() {
        if let Err(d) = common::write_output(args.output.as_deref(), &holo) {
            common::emit_plain(&d);
            return ExitCode::from(2);
        }
    }
    if let Some(path) = args.output.as_deref() {
        let dropped = diagnostics.iter().filter(|d| d.is_error()).count();
        if dropped > 0 && args.format != DiagFormat::Json {
            common::emit_status(&format!(
                "wrote `{}`; {dropped} error{} above: what could not be read is kept there as \
                 `// raw` comments",
                path.display(),
                if dropped == 1 { "" } else { "s" }
            ));
        }
    }
    common::exit_for(&diagnostics)
}

/// Whether an import read anything from the answers: a scene setting (the request and seed of a
/// transcript do not count), a door, or a room with a statement that is not a comment.
fn read_anything(items: &[ast::Item]) -> bool {
    items.iter().any(|item| match item {
        ast::Item::Scene(scene) => scene.body.iter().any(|stmt| {
            !matches!(
                stmt,
                ast::SceneStmt::Seed(..)
                    | ast::SceneStmt::Comment(_)
                    | ast::SceneStmt::Blank(_)
                    | ast::SceneStmt::Error(_)
            )
        }),
        ast::Item::Door(_) => true,
        ast::Item::Room(room) => room.body.iter().any(|stmt| {
            !matches!(
                stmt,
                ast::RoomStmt::Comment(_) | ast::RoomStmt::Blank(_) | ast::RoomStmt::Error(_)
            )
        }),
        ast::Item::Comment(_) | ast::Item::Blank(_) | ast::Item::Error(_) => false,
    })
}

//! The command line: one file per subcommand; the only module that prints.
//!
//! Exit codes: 0 success (warnings allowed), 1 errors in the input, 2 bad usage, I/O failure or
//! an internal error.

pub mod assets;
pub mod batch;
pub mod build;
pub mod check;
pub mod common;
pub mod completions;
pub mod diff;
pub mod explain;
pub mod export;
pub mod fmt;
pub mod generate;
pub mod import;
pub mod lsp;
pub mod render;
pub mod repair;
pub mod test;
pub mod validate;
pub mod view;

use clap::{Parser, Subcommand};
use std::process::ExitCode;

/// holoc: English request → `.holo` scene → AI2-THOR house.
#[derive(Debug, Parser)]
#[command(name = "holoc", version = crate::build_info::LONG_VERSION, about, long_about = None)]
pub struct Cli {
    /// The subcommand.
    #[command(subcommand)]
    pub command: Command,
}

/// The subcommands.
#[derive(Debug, Subcommand)]
pub enum Command {
    /// Search and list the asset catalogs.
    Assets(assets::AssetsArgs),
    /// Compile a `.holo` scene to an AI2-THOR house.
    Build(build::BuildArgs),
    /// Check `.holo` files and report every problem.
    Check(check::CheckArgs),
    /// Print `.holo` files in canonical form.
    Fmt(fmt::FmtArgs),
    /// Show what changed between two houses, scenes or folders of houses.
    Diff(diff::DiffArgs),
    /// Explain a diagnostic code.
    Explain(explain::ExplainArgs),
    /// Ask a language model the paper's questions and write the scene.
    Generate(generate::GenerateArgs),
    /// Turn LLM answers, a transcript or an original Holodeck scene into `.holo`.
    Import(import::ImportArgs),
    /// Serve editors over the Language Server Protocol (stdio).
    Lsp(lsp::LspArgs),
    /// Build or generate every job of a manifest, resumable and sharded.
    Batch(batch::BatchArgs),
    /// Build a scene and draw its plan as SVG.
    Render(render::RenderArgs),
    /// Move room corners, as little as possible, so that the floor plan builds.
    Repair(repair::RepairArgs),
    /// Build scenes and compare them with their golden houses.
    Test(test::TestArgs),
    /// Check house JSON files against the schema and the geometric rules.
    Validate(validate::ValidateArgs),
    /// Write a house as glTF 2.0 binary (`.glb`) to open in Blender or a 3D viewer.
    Export(export::ExportArgs),
    /// Write a self-contained HTML page that shows a house in 3D.
    View(view::ViewArgs),
    /// Print the shell completion script (`holoc completions bash > ~/.local/share/bash-completion/completions/holoc`).
    Completions(completions::CompletionsArgs),
}

/// Runs a parsed command line.
pub fn run(cli: Cli) -> ExitCode {
    match &cli.command {
        Command::Assets(args) => assets::run(args),
        Command::Build(args) => build::run(args),
        Command::Check(args) => check::run(args),
        Command::Fmt(args) => fmt::run(args),
        Command::Diff(args) => diff::run(args),
        Command::Explain(args) => explain::run(args),
        Command::Generate(args) => generate::run(args),
        Command::Import(args) => import::run(args),
        Command::Lsp(args) => lsp::run(args),
        Command::Batch(args) => batch::run(args),
        Command::Render(args) => render::run(args),
        Command::Repair(args) => repair::run(args),
        Command::Test(args) => test::run(args),
        Command::Validate(args) => validate::run(args),
        Command::Export(args) => export::run(args),
        Command::View(args) => view::run(args),
        Command::Completions(args) => completions::run(args),
    }
}

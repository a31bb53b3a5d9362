//! The command line: one file per subcommand; the only module that prints.
//!
//! Exit codes: 0 success (warnings allowed), 1 errors in the input, 2 bad usage, I/O failure or
//! an internal error.

pub mod check;
pub mod common;
pub mod explain;
pub mod fmt;

use clap::{Parser, Subcommand};
use std::process::ExitCode;

/// holoc: English request → `.holo` scene → AI2-THOR house.
#[derive(Debug, Parser)]
#[command(name = "holoc", version, about, long_about = None)]
pub struct Cli {
    /// The subcommand.
    #[command(subcommand)]
    pub command: Command,
}

/// The subcommands.
#[derive(Debug, Subcommand)]
pub enum Command {
    /// Check `.holo` files and report every problem.
    Check(check::CheckArgs),
    /// Print `.holo` files in canonical form.
    Fmt(fmt::FmtArgs),
    /// Explain a diagnostic code.
    Explain(explain::ExplainArgs),
}

/// Runs a parsed command line.
pub fn run(cli: Cli) -> ExitCode {
    match &cli.command {
        Command::Check(args) => check::run(args),
        Command::Fmt(args) => fmt::run(args),
        Command::Explain(args) => explain::run(args),
    }
}

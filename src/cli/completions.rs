//! `holoc completions`: the shell completion script of the command line, written by
//! clap_complete from the same definitions the parser uses.

use clap::CommandFactory as _;
use std::process::ExitCode;

/// Arguments of `holoc completions`.
#[derive(Debug, clap::Args)]
pub struct CompletionsArgs {
    /// The shell: `bash`, `zsh`, `fish`, `elvish` or `powershell`.
    pub shell: clap_complete::Shell,
}

/// Prints the completion script on standard output.
pub fn run(args: &CompletionsArgs) -> ExitCode {
    let mut command = super::Cli::command();
    let mut script = Vec::new();
    clap_complete::generate(args.shell, &mut command, "holoc", &mut script);
    super::common::out(&String::from_utf8_lossy(&script));
    ExitCode::SUCCESS
}

//! The `holoc` command: parses arguments and hands over to [`holoc::cli::run`].

use clap::Parser as _;

fn main() -> std::process::ExitCode {
    holoc::cli::run(holoc::cli::Cli::parse())
}

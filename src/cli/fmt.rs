//! `holoc fmt FILE…`: print the canonical form (`--check`, `--write`).

use super::common::{self, ColorChoice, DiagFormat};
use crate::source::SourceMap;
use std::path::PathBuf;
use std::process::ExitCode;

/// Arguments of `holoc fmt`.
#[derive(Debug, clap::Args)]
pub struct FmtArgs {
    /// The `.holo` files to format.
    #[arg(required = true)]
    pub files: Vec<PathBuf>,
    /// Exit 1 and name the files that are not in canonical form; change nothing.
    #[arg(long, conflicts_with = "write")]
    pub check: bool,
    /// Rewrite the files in place (atomically).
    #[arg(long)]
    pub write: bool,
    /// When to colour diagnostics.
    #[arg(long, value_enum, default_value_t = ColorChoice::Auto)]
    pub color: ColorChoice,
}

/// Runs `holoc fmt`.
#[allow(
    clippy::print_stdout,
    clippy::print_stderr,
    reason = "the CLI is the only place that prints"
)]
pub fn run(args: &FmtArgs) -> ExitCode {
    let mut sources = SourceMap::new();
    let mut status = ExitCode::SUCCESS;
    for path in &args.files {
        if args.write && path.as_os_str() == "-" {
            common::err("`fmt --write -`: standard input cannot be written back; leave out `--write` to print the formatted text\n");
            return ExitCode::from(2);
        }
        let id = match common::read_source(&mut sources, path) {
            Ok(id) => id,
            Err(d) => {
                common::emit_plain(&d);
                return ExitCode::from(2);
            }
        };
        let parsed = crate::parse::parse(&sources, id);
        if parsed.has_errors() {
            common::emit(&sources, &parsed.diagnostics, DiagFormat::Human, args.color);
            common::err(&format!("not formatting `{}`: it has syntax errors\n", path.display()));
            status = ExitCode::from(1);
            continue;
        }
        let printed = crate::fmt::print(&parsed.value);
        let original = sources.get(id).text.as_str();
        if args.check {
            if printed != original {
                common::out(&format!("{}\n", path.display()));
                status = ExitCode::from(1);
            }
        } else if args.write {
            if printed != original {
                if let Err(d) = common::write_atomic(path, printed.as_bytes()) {
                    common::emit_plain(&d);
                    return ExitCode::from(2);
                }
            }
        } else {
            common::out(&printed);
        }
    }
    status
}

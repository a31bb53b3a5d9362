//! `holoc lsp`: the language server, over stdin and stdout.

use super::common;
use std::process::ExitCode;

/// Arguments of `holoc lsp`.
#[derive(Debug, clap::Args)]
pub struct LspArgs {
    /// User asset catalogs, added to those of the initialization options and `holoc.toml`.
    #[command(flatten)]
    pub catalogs: super::assets::CatalogArgs,
    /// Do not run a layout solve in the background on open and save (objects that cannot be
    /// placed are then not reported while editing).
    #[arg(long)]
    pub no_solve: bool,
    /// Accepted for editors that pass it; the server always speaks over stdin and stdout.
    #[arg(long, hide = true)]
    pub stdio: bool,
}

/// Runs `holoc lsp` until the client says `exit`.
pub fn run(args: &LspArgs) -> ExitCode {
    let options = crate::lsp::ServerOptions {
        catalogs: args.catalogs.catalogs.clone(),
        objathor: args.catalogs.objathor_options(),
        solve_on_save: !args.no_solve,
        solve_gate: None,
    };
    match crate::lsp::run_stdio(options) {
        Ok(crate::lsp::Ending::AfterShutdown) => ExitCode::SUCCESS,
        // The protocol's exit code for an `exit` that no `shutdown` came before.
        Ok(crate::lsp::Ending::WithoutShutdown) => ExitCode::from(1),
        Err(message) => {
            common::err(&format!("holoc lsp: {message}\n"));
            ExitCode::from(2)
        }
    }
}

//! `holoc explain CODE`: print a code's page from the diagnostics catalogue.

use super::common;
use crate::diag::{Code, Diagnostic};
use std::process::ExitCode;

/// Arguments of `holoc explain`.
#[derive(Debug, clap::Args)]
pub struct ExplainArgs {
    /// A code (`E0201`) or its name (`unknown-object`); `--list` prints them all.
    pub code: Option<String>,
    /// List every code with its name and summary.
    #[arg(long)]
    pub list: bool,
}

/// Runs `holoc explain`.
pub fn run(args: &ExplainArgs) -> ExitCode {
    if args.list {
        for code in Code::ALL {
            common::out(&format!("{}  {:<28} {}\n", code.as_str(), code.name(), code.summary()));
        }
        return ExitCode::SUCCESS;
    }
    let Some(text) = args.code.as_deref() else {
        let d = Diagnostic::new(Code::E0004, "which code? `holoc explain` takes a code or a name")
            .with_help_opt(Some(
                "`holoc explain E0201` (or `holoc explain unknown-object`) prints its page; \
                 `holoc explain --list` prints every code"
                    .to_string(),
            ));
        super::common::emit_plain(&d);
        return ExitCode::from(2);
    };
    match Code::parse(text) {
        Some(code) => {
            common::out(code.page());
            ExitCode::SUCCESS
        }
        None => {
            let names: Vec<&str> = Code::ALL.iter().flat_map(|c| [c.as_str(), c.name()]).collect();
            let candidates = crate::diag::suggest::closest(text, names.iter().copied());
            let d = Diagnostic::new(Code::E0004, format!("unknown diagnostic code `{text}`"))
                .with_help_opt(
                    crate::diag::suggest::did_you_mean(&candidates)
                        .or_else(|| Some("`holoc explain --list` prints every code".to_string())),
                );
            super::common::emit_plain(&d);
            ExitCode::from(2)
        }
    }
}

//! What every subcommand shares: reading sources, printing diagnostics, writing outputs.

use crate::diag::{self, format::HumanOptions, Code, Diagnostic};
use crate::source::{FileId, SourceMap};
use clap::ValueEnum;
use std::io::{IsTerminal, Write};
use std::path::Path;
use std::process::ExitCode;

/// How diagnostics are printed.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, ValueEnum)]
pub enum DiagFormat {
    /// Source excerpts with labels (stderr).
    #[default]
    Human,
    /// One line per diagnostic (stderr).
    Short,
    /// `{"version": 1, "diagnostics": [...]}` (stdout).
    Json,
    /// LSP `Diagnostic` objects (stdout).
    Lsp,
}

/// When to use colour.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, ValueEnum)]
pub enum ColorChoice {
    /// When stderr is a terminal and `NO_COLOR` is not set.
    #[default]
    Auto,
    /// Always.
    Always,
    /// Never.
    Never,
}

impl ColorChoice {
    /// Whether to colour stderr.
    pub fn enabled(self) -> bool {
        match self {
            ColorChoice::Always => true,
            ColorChoice::Never => false,
            ColorChoice::Auto => {
                std::env::var_os("NO_COLOR").is_none() && std::io::stderr().is_terminal()
            }
        }
    }
}

/// Prints one status line on stderr (a command's closing summary).
#[allow(clippy::print_stderr, reason = "only the CLI prints; this is its status line")]
pub fn emit_status(line: &str) {
    eprintln!("{line}");
}

/// The exit code for a set of diagnostics: 1 if any is an error, else 0.
pub fn exit_for(diagnostics: &[Diagnostic]) -> ExitCode {
    if diagnostics.iter().any(Diagnostic::is_error) {
        ExitCode::from(1)
    } else {
        ExitCode::SUCCESS
    }
}

/// Reads a file into the source map, or returns the diagnostic (E0001, E0003).
#[allow(
    clippy::result_large_err,
    reason = "the error is printed at once; it is rare and never propagated far"
)]
pub fn read_source(sources: &mut SourceMap, path: &Path) -> Result<FileId, Diagnostic> {
    let bytes = std::fs::read(path).map_err(|e| {
        Diagnostic::new(Code::E0001, format!("cannot read `{}`: {e}", path.display()))
            .with_help("check the path and the file's permissions")
    })?;
    let text = String::from_utf8(bytes).map_err(|e| {
        Diagnostic::new(
            Code::E0003,
            format!(
                "`{}` is not UTF-8 text (invalid byte at offset {})",
                path.display(),
                e.utf8_error().valid_up_to()
            ),
        )
        .with_help("save the file as UTF-8")
    })?;
    Ok(sources.add(path.display().to_string(), text))
}

/// Prints diagnostics in the chosen format: human and short to stderr, json and lsp to stdout.
#[allow(
    clippy::print_stdout,
    clippy::print_stderr,
    reason = "the CLI is the only place that prints"
)]
pub fn emit(
    sources: &SourceMap,
    diagnostics: &[Diagnostic],
    format: DiagFormat,
    color: ColorChoice,
) {
    let mut sorted = diagnostics.to_vec();
    diag::sort(&mut sorted);
    match format {
        DiagFormat::Human => {
            let text = diag::format::render_human(
                sources,
                &sorted,
                HumanOptions { color: color.enabled(), width: 100 },
            );
            eprint!("{text}");
            let errors = sorted.iter().filter(|d| d.is_error()).count();
            let warnings = sorted.len() - errors;
            if errors + warnings > 0 {
                eprintln!("{errors} error(s), {warnings} warning(s)");
            }
        }
        DiagFormat::Short => eprint!("{}", diag::format::render_short(sources, &sorted)),
        DiagFormat::Json => print!("{}", diag::format::render_json(sources, &sorted)),
        DiagFormat::Lsp => print!("{}", diag::lsp::render_lsp(sources, &sorted)),
    }
}

/// Prints one diagnostic that has no source (I/O, usage) to stderr.
#[allow(clippy::print_stderr, reason = "the CLI is the only place that prints")]
pub fn emit_plain(d: &Diagnostic) {
    eprintln!("{}[{}]: {}", d.severity.as_str(), d.code.as_str(), d.message);
    if let Some(help) = &d.help {
        eprintln!("  help: {help}");
    }
}

/// Writes `contents` to `path` atomically: a temporary file in the same folder, then a rename.
/// On failure the existing file is untouched.
#[allow(
    clippy::result_large_err,
    reason = "the error is printed at once; it is rare and never propagated far"
)]
pub fn write_atomic(path: &Path, contents: &[u8]) -> Result<(), Diagnostic> {
    let dir = match path.parent() {
        Some(p) if !p.as_os_str().is_empty() => p.to_path_buf(),
        _ => std::path::PathBuf::from("."),
    };
    let io = |e: std::io::Error| {
        Diagnostic::new(Code::E0001, format!("cannot write `{}`: {e}", path.display()))
            .with_help("check that the folder exists and is writable")
    };
    let mut tmp = tempfile::NamedTempFile::new_in(&dir).map_err(io)?;
    tmp.write_all(contents).map_err(io)?;
    tmp.as_file().sync_all().map_err(io)?;
    // A temporary file is private (0600); an output gets the usual permissions of a new file,
    // or keeps those of the file it replaces.
    #[cfg(unix)]
    {
        use std::os::unix::fs::PermissionsExt as _;
        let mode = std::fs::metadata(path).map_or(0o644, |m| m.permissions().mode() & 0o7777);
        std::fs::set_permissions(tmp.path(), std::fs::Permissions::from_mode(mode)).map_err(io)?;
    }
    tmp.persist(path).map_err(|e| io(e.error))?;
    Ok(())
}

/// Writes a product to `-o PATH` atomically, or to stdout when no path is given.
#[allow(clippy::print_stdout, reason = "the CLI is the only place that prints")]
#[allow(
    clippy::result_large_err,
    reason = "the error is printed at once; it is rare and never propagated far"
)]
pub fn write_output(path: Option<&Path>, contents: &str) -> Result<(), Diagnostic> {
    match path {
        Some(p) if p.as_os_str() != "-" => write_atomic(p, contents.as_bytes()),
        _ => {
            print!("{contents}");
            Ok(())
        }
    }
}

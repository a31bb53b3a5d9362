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

/// Writes text to stdout. When the reader has gone away (`holoc assets list | head -2`), the
/// command stops quietly with status 0, as a filter should; any other write error is reported
/// (E0001) and ends the command with status 2.
pub fn out(text: &str) {
    use std::io::Write as _;
    let mut stdout = std::io::stdout().lock();
    if let Err(e) = stdout.write_all(text.as_bytes()).and_then(|()| stdout.flush()) {
        if e.kind() == std::io::ErrorKind::BrokenPipe {
            std::process::exit(0);
        }
        err(&format!("error[E0001]: cannot write to stdout: {e}\n"));
        std::process::exit(2);
    }
}

/// Writes text to stderr; nothing is left to say anything with when stderr itself is closed,
/// so its errors are ignored.
pub fn err(text: &str) {
    use std::io::Write as _;
    let mut stderr = std::io::stderr().lock();
    let _ = stderr.write_all(text.as_bytes()).and_then(|()| stderr.flush());
}

/// Prints one status line on stderr (a command's closing summary).
pub fn emit_status(line: &str) {
    err(&format!("{line}\n"));
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
    let cannot = |e: &dyn std::fmt::Display| {
        Diagnostic::new(Code::E0001, format!("cannot read `{}`: {e}", path.display()))
            .with_help("check the path and the file's permissions")
    };
    // A named pipe is refused before it is opened (opening one waits for a writer); the pipe
    // of a shell's `<(…)` and devices are read up to the limit and for at most
    // `source::STREAM_TIMEOUT`: `/dev/zero` or a runaway pipe ends with an error instead of
    // filling the memory or waiting for ever.
    // `-` is standard input (`cat a.holo | holoc check -`), read up to the same limit.
    let read = crate::source::read_input_or_stdin(path, MAX_INPUT_BYTES);
    let bytes =
        match read {
            Ok(bytes) => bytes,
            Err(e @ crate::source::ReadError::NamedPipe) => {
                return Err(cannot(&e).with_help(
                    "give a file; to read a stream, use `<(command)` or a file written first",
                ))
            }
            Err(crate::source::ReadError::Folder) => {
                return Err(cannot(&"it is a folder").with_help("give a file, not a folder"))
            }
            Err(crate::source::ReadError::TooLarge(_)) => return Err(Diagnostic::new(
                Code::E0001,
                format!(
                    "`{}` is larger than {} MiB, the most holoc reads",
                    path.display(),
                    MAX_INPUT_BYTES / (1024 * 1024)
                ),
            )
            .with_help(
                "a scene, an answer or a house is far smaller; check that this is the right file",
            )),
            Err(e) => return Err(cannot(&e)),
        };
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
    let name =
        if path.as_os_str() == "-" { "<stdin>".to_string() } else { path.display().to_string() };
    Ok(sources.add(name, text))
}

/// The text of a file that is not a source of diagnostics (`holoc.toml`, review answers, a
/// report), read as [`read_source`] reads a scene: bounded, `-` for stdin, E0001 or E0003.
#[allow(
    clippy::result_large_err,
    reason = "the error is printed at once; it is rare and never propagated far"
)]
pub fn read_text(path: &Path) -> Result<String, Diagnostic> {
    let mut sources = SourceMap::new();
    let file = read_source(&mut sources, path)?;
    Ok(sources.get(file).text.to_string())
}

/// The largest input file holoc reads (a scene, an answer, a transcript, a house), bytes.
pub const MAX_INPUT_BYTES: u64 = 32 * 1024 * 1024;

/// Prints diagnostics in the chosen format: human and short to stderr, json and lsp to stdout.
pub fn emit(
    sources: &SourceMap,
    diagnostics: &[Diagnostic],
    format: DiagFormat,
    color: ColorChoice,
) {
    emit_beside(sources, diagnostics, format, color, false);
}

/// Like [`emit`]; when the command's product goes to stdout (`stdout_taken`), json and lsp
/// diagnostics go to stderr instead, so that stdout holds exactly one document.
pub fn emit_beside(
    sources: &SourceMap,
    diagnostics: &[Diagnostic],
    format: DiagFormat,
    color: ColorChoice,
    stdout_taken: bool,
) {
    let data = |text: String| if stdout_taken { err(&text) } else { out(&text) };
    let mut sorted = diagnostics.to_vec();
    diag::sort(&mut sorted);
    let errors = sorted.iter().filter(|d| d.is_error()).count();
    let warnings = sorted.len() - errors;
    let more = |shown: &mut Vec<Diagnostic>| {
        let hidden = diag::cap_per_file(shown, diag::MAX_SHOWN_PER_FILE);
        move || {
            if hidden > 0 {
                err(&format!(
                    "... and {hidden} more diagnostic(s) not shown (at most {} per file; \
                     `--format json` lists them all)\n",
                    diag::MAX_SHOWN_PER_FILE
                ));
            }
        }
    };
    match format {
        DiagFormat::Human => {
            let mut shown = sorted.clone();
            let closing = more(&mut shown);
            let text = diag::format::render_human(
                sources,
                &shown,
                HumanOptions { color: color.enabled(), width: 100 },
            );
            err(&text);
            closing();
            if errors + warnings > 0 {
                err(&format!("{errors} error(s), {warnings} warning(s)\n"));
            }
        }
        DiagFormat::Short => {
            let mut shown = sorted.clone();
            let closing = more(&mut shown);
            err(&diag::format::render_short(sources, &shown));
            closing();
        }
        DiagFormat::Json => data(diag::format::render_json(sources, &sorted)),
        DiagFormat::Lsp => data(diag::lsp::render_lsp(sources, &sorted)),
    }
}

/// Prints one diagnostic that has no source (I/O, usage) to stderr.
pub fn emit_plain(d: &Diagnostic) {
    let help =
        d.help.as_ref().map(|h| format!("  help: {}\n", diag::visible(h))).unwrap_or_default();
    err(&format!(
        "{}[{}]: {}\n{help}",
        d.severity.as_str(),
        d.code.as_str(),
        diag::visible(&d.message)
    ));
}

/// Writes `contents` to `path`.
///
/// A regular file (or a new one) is replaced atomically: a temporary file in the same folder,
/// synced, then renamed over it, so a reader or a crash sees the old file or the whole new one.
/// A symbolic link keeps being a link: the file it points to is what gets replaced. A device,
/// FIFO or socket (`/dev/null`, `/dev/stdout`, a named pipe) is written in place, since renaming
/// over it would replace the device with a file. A folder is an error (E0001); missing folders
/// on the way are made. On failure an existing file is untouched.
#[allow(
    clippy::result_large_err,
    reason = "the error is printed at once; it is rare and never propagated far"
)]
pub fn write_atomic(path: &Path, contents: &[u8]) -> Result<(), Diagnostic> {
    let io = |e: std::io::Error| {
        Diagnostic::new(Code::E0001, format!("cannot write `{}`: {e}", path.display()))
            .with_help("check that the folder exists and is writable")
    };
    // Follow a symbolic link to the file it names (which may not exist yet).
    let mut target = path.to_path_buf();
    for _ in 0..40 {
        match std::fs::symlink_metadata(&target) {
            Ok(m) if m.file_type().is_symlink() => {
                let link = std::fs::read_link(&target).map_err(io)?;
                target = match target.parent() {
                    Some(dir) if link.is_relative() => dir.join(link),
                    _ => link,
                };
            }
            _ => break,
        }
    }
    match std::fs::metadata(&target) {
        Ok(m) if m.is_dir() => {
            return Err(Diagnostic::new(
                Code::E0001,
                format!("cannot write `{}`: it is a folder", path.display()),
            )
            .with_help("name a file inside it, e.g. `-o folder/house.json`"));
        }
        Ok(m) if !m.is_file() => {
            // A device, FIFO or socket: written in place.
            let mut f = std::fs::OpenOptions::new().write(true).open(&target).map_err(io)?;
            return f.write_all(contents).and_then(|()| f.flush()).map_err(io);
        }
        _ => {}
    }
    let dir = match target.parent() {
        Some(p) if !p.as_os_str().is_empty() => p.to_path_buf(),
        _ => std::path::PathBuf::from("."),
    };
    // A missing folder is made, as `-o out/house.json` on a fresh clone expects.
    std::fs::create_dir_all(&dir).map_err(io)?;
    remove_stale_temporaries(&dir);
    // `.holoc-<pid>-XXXXXX.tmp`: a later run knows it for one of holoc's, and whose.
    let mut tmp = tempfile::Builder::new()
        .prefix(&format!("{TEMP_PREFIX}{}-", std::process::id()))
        .suffix(TEMP_SUFFIX)
        .tempfile_in(&dir)
        .map_err(io)?;
    tmp.write_all(contents).map_err(io)?;
    tmp.as_file().sync_all().map_err(io)?;
    // A temporary file is private (0600); an output gets the usual permissions of a new file,
    // or keeps those of the file it replaces.
    #[cfg(unix)]
    {
        use std::os::unix::fs::PermissionsExt as _;
        let mode = std::fs::metadata(&target).map_or(0o644, |m| m.permissions().mode() & 0o7777);
        std::fs::set_permissions(tmp.path(), std::fs::Permissions::from_mode(mode)).map_err(io)?;
    }
    tmp.persist(&target).map_err(|e| io(e.error))?;
    Ok(())
}

/// The start of the name of an atomic write's temporary file (then the process id, `-`, six
/// random characters and [`TEMP_SUFFIX`]).
pub const TEMP_PREFIX: &str = ".holoc-";
/// The end of the name of an atomic write's temporary file.
pub const TEMP_SUFFIX: &str = ".tmp";

/// Removes, once per folder and process, the temporary files of atomic writes that a holoc
/// killed before its rename left in `dir` (`kill -9` during `fmt --write`): those whose
/// process no longer runs. Only names of holoc's own form are touched, and only on Linux,
/// where `/proc` says which processes run; elsewhere they stay.
pub(crate) fn remove_stale_temporaries(dir: &Path) {
    static DONE: std::sync::Mutex<std::collections::BTreeSet<std::path::PathBuf>> =
        std::sync::Mutex::new(std::collections::BTreeSet::new());
    if !cfg!(target_os = "linux") || !Path::new("/proc/self").exists() {
        return;
    }
    let key = std::fs::canonicalize(dir).unwrap_or_else(|_| dir.to_path_buf());
    if !DONE.lock().is_ok_and(|mut done| done.insert(key)) {
        return;
    }
    let Ok(entries) = std::fs::read_dir(dir) else { return };
    for entry in entries.flatten() {
        let name = entry.file_name();
        let Some(pid) = name
            .to_str()
            .and_then(|n| n.strip_prefix(TEMP_PREFIX))
            .filter(|n| n.ends_with(TEMP_SUFFIX))
            .and_then(|n| n.split_once('-'))
            .and_then(|(pid, _)| pid.parse::<u32>().ok())
        else {
            continue;
        };
        let is_file = entry.file_type().is_ok_and(|t| t.is_file());
        if is_file && pid != std::process::id() && !Path::new(&format!("/proc/{pid}")).exists() {
            let _ = std::fs::remove_file(entry.path());
        }
    }
}

/// A path's components without `.`.
fn words(p: &Path) -> Vec<std::path::Component<'_>> {
    p.components().filter(|c| !matches!(c, std::path::Component::CurDir)).collect()
}

/// Writes `contents` to `path` atomically, only inside the folder `root`: `path` must lie
/// under `root` by its words (no `..`), every folder between them that exists must be a real
/// folder inside `root` once links are resolved (a missing one is made), and `path` itself must
/// not be a link (a golden that links to `~/.bashrc` is refused, not written through). E0009.
#[allow(
    clippy::result_large_err,
    reason = "the error is printed at once; it is rare and never propagated far"
)]
pub fn write_confined(root: &Path, path: &Path, contents: &[u8]) -> Result<(), Diagnostic> {
    confine(root, path)?;
    write_atomic(path, contents)
}

/// The checks of [`write_confined`] without the write, for a command that writes `path` its
/// own way (a rename from its scratch folder, an append, a lock): `path` lies under `root` by
/// its words, every folder between them is a real folder inside `root` once links are resolved
/// (missing ones are made), and `path` is not a link (nor a folder or device). E0009 (E0001
/// for an I/O error or a path that is not a regular file).
#[allow(
    clippy::result_large_err,
    reason = "the error is printed at once; it is rare and never propagated far"
)]
pub fn confine(root: &Path, path: &Path) -> Result<(), Diagnostic> {
    let outside = |why: &str| {
        Diagnostic::new(
            Code::E0009,
            format!(
                "not writing `{}`: {why} outside the folder `{}`",
                diag::visible(&path.display().to_string()),
                diag::visible(&root.display().to_string())
            ),
        )
        .with_help("remove the link, or give a folder that holds the file itself")
    };
    let io = |e: std::io::Error| {
        Diagnostic::new(Code::E0001, format!("cannot write `{}`: {e}", path.display()))
            .with_help("check that the folder exists and is writable")
    };
    std::fs::create_dir_all(root).map_err(io)?;
    let root_real = std::fs::canonicalize(root).map_err(io)?;
    // Both as absolute words without `.`: `./a.house.json` is under `.`.
    let (root_abs, path_abs) = match (std::path::absolute(root), std::path::absolute(path)) {
        (Ok(r), Ok(p)) => (r, p),
        (Err(e), _) | (_, Err(e)) => return Err(io(e)),
    };
    let (root_words, path_words) = (words(&root_abs), words(&path_abs));
    let Some(parts) = path_words.strip_prefix(&root_words[..]) else {
        return Err(outside("it lies"));
    };
    if parts.is_empty() || !parts.iter().all(|c| matches!(c, std::path::Component::Normal(_))) {
        return Err(outside("its path climbs with `..`"));
    }
    let mut dir = root_abs.clone();
    for part in &parts[..parts.len() - 1] {
        dir.push(part);
        match std::fs::symlink_metadata(&dir) {
            Err(e) if e.kind() == std::io::ErrorKind::NotFound => {
                match std::fs::create_dir(&dir) {
                    Ok(()) => continue,
                    // Made meanwhile (by another thread or run): checked as one that was there.
                    Err(e) if e.kind() == std::io::ErrorKind::AlreadyExists => {}
                    Err(e) => return Err(io(e)),
                }
            }
            Err(e) => return Err(io(e)),
            Ok(_) => {}
        }
        let real = std::fs::canonicalize(&dir).map_err(io)?;
        if !real.starts_with(&root_real) {
            return Err(outside(&format!(
                "the folder `{}` is a link that leads",
                diag::visible(&dir.display().to_string())
            )));
        }
    }
    match std::fs::symlink_metadata(path) {
        Ok(m) if m.file_type().is_symlink() => {
            return Err(outside("it is a symbolic link, which may lead"));
        }
        Ok(m) if !m.is_file() => {
            return Err(Diagnostic::new(
                Code::E0001,
                format!("cannot write `{}`: it is not a regular file", path.display()),
            )
            .with_help("remove it, or write the file somewhere else"));
        }
        _ => {}
    }
    Ok(())
}

/// [`confine`] for the writers that speak `std::io::Error`: the diagnostic's message as an
/// error of kind `PermissionDenied` (E0009) or `Other`.
pub fn confine_io(root: &Path, path: &Path) -> std::io::Result<()> {
    confine(root, path).map_err(|d| {
        let kind = if d.code == Code::E0009 {
            std::io::ErrorKind::PermissionDenied
        } else {
            std::io::ErrorKind::Other
        };
        std::io::Error::new(kind, format!("[{}] {}", d.code.as_str(), d.message))
    })
}

/// Writes a product to `-o PATH` atomically, or to stdout when no path is given.
#[allow(
    clippy::result_large_err,
    reason = "the error is printed at once; it is rare and never propagated far"
)]
pub fn write_output(path: Option<&Path>, contents: &str) -> Result<(), Diagnostic> {
    match path {
        Some(p) if p.as_os_str() != "-" => write_atomic(p, contents.as_bytes()),
        _ => {
            out(contents);
            Ok(())
        }
    }
}

//! Real editors against the real binary and the repository's editor files.
//!
//! - Neovim (headless), set up by the book's Lua as written, starts `holoc lsp` over stdio for
//!   an example in a project's subfolder (its `holoc.toml` one folder up), types a typo and
//!   reads back the diagnostic the server published, and checks the syntax colours and the
//!   word under completion.
//! - Vim's syntax (`editors/vim`) gives every token of every example and corpus file the class
//!   the server's semantic tokens give it.
//!
//! Skipped with a message when `nvim` is not installed (`.ci/run` installs Debian's `neovim`).

mod common;

use std::fmt::Write as _;
use std::path::Path;
use std::process::{Command, Stdio};
use std::time::{Duration, Instant};

/// Whether neovim can run here; says why not (and that `test` is skipped) when it cannot.
fn neovim(test: &str) -> bool {
    let Ok(version) = Command::new("nvim").arg("--version").output() else {
        common::skip(
            test,
            "neovim (`nvim`) is not installed; `apt-get install neovim` or run .ci/run",
        );
        return false;
    };
    assert!(version.status.success());
    true
}

/// A scratch folder of its own for one test.
fn scratch(name: &str) -> std::path::PathBuf {
    let dir = std::env::temp_dir().join(format!("holoc-editor-{name}-{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).expect("scratch folder");
    dir
}

/// Runs neovim headless on the Lua file `script` with `env`, `holoc` on the `PATH`, and returns
/// what the script wrote to `$HOLO_OUT`.
fn run_neovim(dir: &Path, script: &str, env: &[(&str, &std::ffi::OsStr)]) -> String {
    let out = dir.join("out.txt");
    let bin = Path::new(env!("CARGO_BIN_EXE_holoc")).parent().expect("a folder");
    let path = std::env::join_paths(
        std::iter::once(bin.to_path_buf())
            .chain(std::env::split_paths(&std::env::var_os("PATH").unwrap_or_default())),
    )
    .expect("a PATH");
    let script = std::path::absolute(script).expect("absolute path");
    let mut command = Command::new("nvim");
    command
        .args(["--headless", "--clean", "-n", "-c"])
        .arg(format!("luafile {}", script.display()))
        .env("PATH", path)
        .env("HOLO_OUT", &out)
        .env("XDG_STATE_HOME", dir)
        .env("XDG_DATA_HOME", dir)
        .env("XDG_CACHE_HOME", dir)
        .stdin(Stdio::null())
        .stdout(Stdio::null())
        .stderr(Stdio::piped());
    for (key, value) in env {
        command.env(key, value);
    }
    let mut child = command.spawn().expect("nvim starts");
    let started = Instant::now();
    let status = loop {
        if let Some(status) = child.try_wait().expect("wait") {
            break status;
        }
        if started.elapsed() > Duration::from_secs(120) {
            let _ = child.kill();
            panic!("neovim did not finish in two minutes");
        }
        std::thread::sleep(Duration::from_millis(50));
    };
    let report = std::fs::read_to_string(&out).unwrap_or_default();
    assert!(status.success(), "nvim exited with {status}: {report}");
    report
}

#[test]
fn neovim_shows_the_diagnostic_holoc_lsp_publishes_for_a_typo() {
    if !neovim("neovim_shows_the_diagnostic_holoc_lsp_publishes_for_a_typo") {
        return;
    }
    let dir = scratch("typo");
    // A project whose scenes are in a subfolder, with its catalog named by `holoc.toml` one
    // folder up: the bed's pinned asset is only in that catalog (without it, E0401).
    let project = dir.join("project");
    std::fs::create_dir_all(project.join("scenes")).expect("folders");
    std::fs::copy("tests/catalog/procthor_small.json", project.join("mine.json")).expect("copy");
    std::fs::write(project.join("holoc.toml"), "catalogs = [\"mine.json\"]\n").expect("write");
    let scene = project.join("scenes/bedroom.holo");
    let example = std::fs::read_to_string("examples/bedroom.holo").expect("example");
    let pinned = example.replacen(
        "    size 160 cm x 210 cm x 100 cm\n",
        "    size 160 cm x 210 cm x 100 cm\n    asset \"Test_Grand_Piano\"\n",
        1,
    );
    std::fs::write(&scene, &pinned).expect("the scene");
    // The book's Neovim setup, as written: the first Lua block of the Neovim section, its first
    // line pointed at this repository's `editors/vim`.
    let page = std::fs::read_to_string("book/src/cli/lsp.md").expect("the editor page");
    let section = page.split("### Neovim").nth(1).expect("a Neovim section");
    let setup = section
        .split("```lua\n")
        .nth(1)
        .and_then(|rest| rest.split("```").next())
        .expect("a Lua block");
    let (first, rest) = setup.split_once('\n').expect("lines");
    assert!(first.starts_with("local holoc_vim = "), "the block's first line names the folder");
    let runtime = std::path::absolute("editors/vim").expect("absolute");
    let setup = format!("local holoc_vim = {:?}\n{rest}", runtime.display().to_string());
    let setup_path = dir.join("setup.lua");
    std::fs::write(&setup_path, setup).expect("write the setup");
    let report = run_neovim(
        &dir,
        "tests/editor/neovim.lua",
        &[("HOLO_SETUP", setup_path.as_os_str()), ("HOLO_SCENE", scene.as_os_str())],
    );
    let lines: Vec<&str> = report.lines().collect();
    // The example builds: at most warnings when it is opened (a stand-in asset, W0403); the
    // pinned asset is found in the catalog of `holoc.toml` one folder up.
    let opened = lines.first().copied().unwrap_or_default();
    assert!(opened.starts_with("opened:") && !opened.contains('E'), "{report}");
    assert_eq!(lines.last().copied(), Some("done"), "{report}");
    let typo_line = pinned
        .lines()
        .position(|l| l.trim_start().starts_with("far bed-0"))
        .expect("the example has `far bed-0`")
        + 1;
    let expected = format!("{typo_line} E0102 `fra` does not start a statement of an object block");
    assert!(report.lines().any(|l| l == expected), "expected `{expected}` in:\n{report}");
    // Colours from `editors/vim` and the word completion replaces.
    for expected in [
        "syntax room holoKeyword",
        "syntax bedroom holoRoomDecl",
        "syntax bed-0 holoObjectRef",
        "syntax cm holoUnit",
        "syntax \"white panel door\" holoString",
        "completion replaces desk-",
    ] {
        assert!(report.lines().any(|l| l == expected), "expected `{expected}` in:\n{report}");
    }
    let _ = std::fs::remove_dir_all(&dir);
}

/// Every `.holo` file of the examples and the corpus, sorted.
fn scenes() -> Vec<std::path::PathBuf> {
    fn walk(dir: &Path, out: &mut Vec<std::path::PathBuf>) {
        let Ok(entries) = std::fs::read_dir(dir) else { return };
        for entry in entries.flatten() {
            let path = entry.path();
            if path.is_dir() {
                walk(&path, out);
            } else if path.extension().is_some_and(|e| e == "holo") {
                out.push(path);
            }
        }
    }
    let mut out = Vec::new();
    walk(Path::new("examples"), &mut out);
    walk(Path::new("tests/corpus"), &mut out);
    out.sort();
    out
}

/// The server's tokens of a text: (line, byte column, class), both from 1.
fn server_tokens(text: &str) -> Vec<(usize, usize, &'static str)> {
    let mut starts = vec![0];
    let bytes = text.as_bytes();
    for (i, b) in bytes.iter().enumerate() {
        if *b == b'\n' || (*b == b'\r' && bytes.get(i + 1) != Some(&b'\n')) {
            starts.push(i + 1);
        }
    }
    holoc::lsp::highlight::tokens(text)
        .iter()
        .map(|t| {
            let line = starts.partition_point(|&s| s <= t.start);
            (line, t.start - starts[line - 1] + 1, t.class.as_str())
        })
        .collect()
}

#[test]
fn vim_syntax_gives_every_token_the_class_of_the_servers_tokens() {
    if !neovim("vim_syntax_gives_every_token_the_class_of_the_servers_tokens") {
        return;
    }
    let dir = scratch("syntax");
    let mut cases = String::new();
    let mut classes = std::collections::BTreeSet::new();
    for path in scenes() {
        let text = std::fs::read_to_string(&path).expect("a scene");
        // Vim reads a lone `\r` as a line break only in `fileformat=mac`, which it does not
        // guess by default: such files are left to the server's own tests.
        if text.replace("\r\n", "").contains('\r') {
            continue;
        }
        let absolute = std::path::absolute(&path).expect("absolute");
        let _ = writeln!(cases, "file {}", absolute.display());
        for (line, column, class) in server_tokens(&text) {
            classes.insert(class);
            let _ = writeln!(cases, "{line} {column} {class}");
        }
    }
    let every: std::collections::BTreeSet<&str> =
        holoc::lsp::highlight::Class::ALL.iter().map(|c| c.as_str()).collect();
    assert_eq!(classes, every, "the examples and corpus show every class");
    let cases_path = dir.join("cases.txt");
    std::fs::write(&cases_path, cases).expect("write");
    let runtime = std::path::absolute("editors/vim").expect("absolute");
    let report = run_neovim(
        &dir,
        "tests/editor/syntax.lua",
        &[("HOLO_CASES", cases_path.as_os_str()), ("HOLO_RUNTIME", runtime.as_os_str())],
    );
    let names: Vec<&str> = every.iter().copied().collect();
    let expected = format!("seen {}\ndone\n", names.join(" "));
    assert_eq!(report, expected);
    let _ = std::fs::remove_dir_all(&dir);
}

/// The folder `.ci/run` installs npm packages into (`HOLOC_NPM_PREFIX`, else
/// `~/.cache/holoc/npm`).
fn npm_prefix() -> std::path::PathBuf {
    std::env::var_os("HOLOC_NPM_PREFIX").map_or_else(
        || Path::new(&std::env::var_os("HOME").unwrap_or_default()).join(".cache/holoc/npm"),
        std::path::PathBuf::from,
    )
}

fn runs(program: &str) -> bool {
    Command::new(program).arg("--version").output().is_ok_and(|o| o.status.success())
}

#[test]
fn the_textmate_grammar_gives_every_token_the_class_of_the_servers_tokens() {
    let test = "the_textmate_grammar_gives_every_token_the_class_of_the_servers_tokens";
    let modules = npm_prefix().join("node_modules");
    if !runs("node") || !modules.join("vscode-textmate").exists() {
        common::skip(
            test,
            "node or the npm packages vscode-textmate and vscode-oniguruma are missing (.ci/run installs them)",
        );
        return;
    }
    let dir = scratch("textmate");
    // Lines and UTF-16 columns (from 0), as JavaScript strings count them.
    let mut cases = String::new();
    for path in scenes() {
        let text = std::fs::read_to_string(&path).expect("a scene");
        let _ = writeln!(cases, "file {}", std::path::absolute(&path).expect("path").display());
        let lines: Vec<&str> = text.split("\r\n").flat_map(|l| l.split(['\n', '\r'])).collect();
        let mut starts = vec![0];
        for line in &lines {
            starts.push(starts.last().copied().unwrap_or(0) + line.len() + 1);
        }
        for (line, column, class) in server_tokens(&text) {
            let before = &lines[line - 1][..column - 1];
            let _ = writeln!(cases, "{line} {} {class}", before.encode_utf16().count());
        }
    }
    let cases_path = dir.join("cases.txt");
    std::fs::write(&cases_path, cases).expect("write");
    let output = Command::new("node")
        .arg("tests/editor/textmate.js")
        .arg(&cases_path)
        .env("NODE_PATH", &modules)
        .output()
        .expect("node runs");
    let report = String::from_utf8_lossy(&output.stdout);
    assert!(output.status.success(), "{report}{}", String::from_utf8_lossy(&output.stderr));
    let every: Vec<&str> = holoc::lsp::highlight::Class::ALL.iter().map(|c| c.as_str()).collect();
    let mut sorted = every.clone();
    sorted.sort_unstable();
    assert_eq!(report, format!("seen {}\ndone\n", sorted.join(" ")));
    let _ = std::fs::remove_dir_all(&dir);
}

#[test]
fn the_vscode_extension_packages_with_vsce() {
    let test = "the_vscode_extension_packages_with_vsce";
    let vsce = npm_prefix().join("node_modules/.bin/vsce");
    let deps = npm_prefix().join("holoc-vscode");
    let locked = std::fs::read("editors/vscode/package-lock.json").expect("the lock file");
    if !runs("node")
        || !vsce.exists()
        || std::fs::read(deps.join("package-lock.json")).ok() != Some(locked)
    {
        common::skip(
            test,
            "node, @vscode/vsce or the extension's locked dependencies are missing (.ci/run installs them)",
        );
        return;
    }
    let dir = scratch("vscode");
    let folder = dir.join("holoc");
    let copy = |from: &Path, to: &Path| {
        let status = Command::new("cp").arg("-r").arg(from).arg(to).status().expect("cp runs");
        assert!(status.success());
    };
    copy(Path::new("editors/vscode"), &folder);
    let _ = std::fs::remove_dir_all(folder.join("node_modules"));
    copy(&deps.join("node_modules"), &folder.join("node_modules"));
    let output = Command::new(&vsce)
        .args(["package", "--allow-missing-repository", "--skip-license", "--out", "holoc.vsix"])
        .current_dir(&folder)
        .stdin(Stdio::null())
        .output()
        .expect("vsce runs");
    let said = format!(
        "{}{}",
        String::from_utf8_lossy(&output.stdout),
        String::from_utf8_lossy(&output.stderr)
    );
    assert!(output.status.success(), "{said}");
    assert!(folder.join("holoc.vsix").metadata().is_ok_and(|m| m.len() > 10_000), "{said}");
    // What the package holds: the manifest, the client, the grammar, the client library.
    let listed = Command::new(&vsce).arg("ls").current_dir(&folder).output().expect("vsce runs");
    let files = String::from_utf8_lossy(&listed.stdout);
    for file in [
        "package.json",
        "extension.js",
        "language-configuration.json",
        "syntaxes/holo.tmLanguage.json",
        "node_modules/vscode-languageclient/package.json",
    ] {
        assert!(files.lines().any(|l| l == file), "{file} is not packaged:\n{files}");
    }
    // The manifest says what the book says: the language, its files and the grammar.
    let manifest: serde_json::Value =
        serde_json::from_slice(&std::fs::read("editors/vscode/package.json").expect("read"))
            .expect("JSON");
    assert_eq!(manifest["contributes"]["languages"][0]["id"], "holo");
    assert_eq!(manifest["contributes"]["languages"][0]["extensions"][0], ".holo");
    assert_eq!(manifest["contributes"]["grammars"][0]["scopeName"], "source.holo");
    let _ = std::fs::remove_dir_all(&dir);
}

#[test]
fn the_books_helix_setup_is_the_repositorys_and_names_the_server() {
    let page = std::fs::read_to_string("book/src/cli/lsp.md").expect("the editor page");
    let section = page.split("### Helix").nth(1).expect("a Helix section");
    let block = section
        .split("```toml\n")
        .nth(1)
        .and_then(|rest| rest.split("```").next())
        .expect("a TOML block");
    let file = std::fs::read_to_string("editors/helix/languages.toml").expect("the Helix file");
    assert_eq!(block, file, "the book's block is editors/helix/languages.toml");
    let config: toml::Value = toml::from_str(&file).expect("TOML");
    assert_eq!(config["language-server"]["holoc"]["command"].as_str(), Some("holoc"));
    let language = &config["language"][0];
    assert_eq!(language["name"].as_str(), Some("holo"));
    assert_eq!(language["file-types"][0].as_str(), Some("holo"));
    assert_eq!(language["language-servers"][0].as_str(), Some("holoc"));
}

//! A real editor against the real binary: neovim (headless), set up by the book's Lua as written,
//! starts `holoc lsp` over stdio for an example, types a typo and reads back the diagnostic the
//! server published. Skipped with a
//! message when `nvim` is not installed (`.ci/run` installs Debian's `neovim`).

mod common;

use std::process::{Command, Stdio};
use std::time::{Duration, Instant};

#[test]
fn neovim_shows_the_diagnostic_holoc_lsp_publishes_for_a_typo() {
    let Ok(version) = Command::new("nvim").arg("--version").output() else {
        common::skip(
            "neovim_shows_the_diagnostic_holoc_lsp_publishes_for_a_typo",
            "neovim (`nvim`) is not installed; `apt-get install neovim` or run .ci/run",
        );
        return;
    };
    assert!(version.status.success());
    let dir = std::env::temp_dir().join(format!("holoc-editor-{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).expect("scratch folder");
    let scene = dir.join("bedroom.holo");
    std::fs::copy("examples/bedroom.holo", &scene).expect("copy the example");
    let out = dir.join("out.txt");
    // The book's Neovim setup, as written: the first Lua block of the Neovim section.
    let page = std::fs::read_to_string("book/src/cli/lsp.md").expect("the editor page");
    let section = page.split("### Neovim").nth(1).expect("a Neovim section");
    let setup = section
        .split("```lua\n")
        .nth(1)
        .and_then(|rest| rest.split("```").next())
        .expect("a Lua block");
    let setup_path = dir.join("setup.lua");
    std::fs::write(&setup_path, setup).expect("write the setup");
    // `holoc` on the PATH, as the setup names it.
    let bin = std::path::Path::new(env!("CARGO_BIN_EXE_holoc")).parent().expect("a folder");
    let path = std::env::join_paths(
        std::iter::once(bin.to_path_buf())
            .chain(std::env::split_paths(&std::env::var_os("PATH").unwrap_or_default())),
    )
    .expect("a PATH");
    let script = std::path::absolute("tests/editor/neovim.lua").expect("absolute path");
    let mut child = Command::new("nvim")
        .args(["--headless", "--clean", "-n", "-c"])
        .arg(format!("luafile {}", script.display()))
        .env("PATH", path)
        .env("HOLO_SETUP", &setup_path)
        .env("HOLO_SCENE", &scene)
        .env("HOLO_OUT", &out)
        .env("XDG_STATE_HOME", &dir)
        .env("XDG_DATA_HOME", &dir)
        .env("XDG_CACHE_HOME", &dir)
        .stdin(Stdio::null())
        .stdout(Stdio::null())
        .stderr(Stdio::piped())
        .spawn()
        .expect("nvim starts");
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
    let lines: Vec<&str> = report.lines().collect();
    // The example builds: at most warnings when it is opened (a stand-in asset, W0403).
    let opened = lines.first().copied().unwrap_or_default();
    assert!(opened.starts_with("opened:") && !opened.contains('E'), "{report}");
    assert_eq!(lines.last().copied(), Some("done"), "{report}");
    let typo_line = std::fs::read_to_string("examples/bedroom.holo")
        .expect("example")
        .lines()
        .position(|l| l.trim_start().starts_with("far bed-0"))
        .expect("the example has `far bed-0`")
        + 1;
    let expected = format!("{typo_line} E0102 `fra` does not start a statement of an object block");
    assert!(report.lines().any(|l| l == expected), "expected `{expected}` in:\n{report}");
    let _ = std::fs::remove_dir_all(&dir);
}

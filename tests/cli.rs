//! What the command line does with its outputs: a closed pipe ends a command quietly, `-o`
//! replaces regular files atomically, writes devices and FIFOs in place, follows symbolic
//! links and refuses folders, and machine-readable stdout holds exactly one document.

use std::io::Read as _;
use std::process::{Command, Stdio};

fn holoc() -> Command {
    Command::new(env!("CARGO_BIN_EXE_holoc"))
}

fn scratch(name: &str) -> std::path::PathBuf {
    let dir = std::env::temp_dir().join(format!("holoc-cli-{}-{name}", std::process::id()));
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).expect("scratch folder");
    dir
}

#[test]
fn a_closed_pipe_ends_a_command_quietly() {
    for args in [&["assets", "list"][..], &["explain", "--list"][..]] {
        let mut child = holoc()
            .args(args)
            .stdout(Stdio::piped())
            .stderr(Stdio::piped())
            .spawn()
            .expect("holoc starts");
        // Read a little, then hang up, as `| head -2` does.
        let mut stdout = child.stdout.take().expect("stdout");
        let mut first = [0u8; 64];
        let _ = stdout.read(&mut first).expect("some output");
        drop(stdout);
        let mut stderr = String::new();
        child.stderr.take().expect("stderr").read_to_string(&mut stderr).expect("stderr");
        let status = child.wait().expect("holoc ends");
        assert!(!stderr.contains("panicked"), "{args:?}: {stderr}");
        assert_eq!(status.code(), Some(0), "{args:?}: {stderr}");
    }
}

#[test]
fn build_json_to_stdout_is_one_document() {
    let out = holoc()
        .args(["build", "examples/bedroom.holo", "--format", "json", "-q"])
        .output()
        .expect("holoc runs");
    assert!(out.status.success());
    let house: serde_json::Value =
        serde_json::from_slice(&out.stdout).expect("stdout is one JSON document");
    assert!(house.get("rooms").is_some(), "stdout holds the house");
    let diags: serde_json::Value =
        serde_json::from_slice(&out.stderr).expect("stderr is the diagnostics document");
    assert!(diags.get("diagnostics").is_some());
}

#[test]
fn outputs_replace_files_follow_links_write_fifos_and_refuse_folders() {
    let dir = scratch("outputs");
    let build = |target: &std::path::Path| {
        holoc()
            .args(["build", "examples/bedroom.holo", "-q", "--format", "short", "-o"])
            .arg(target)
            .output()
            .expect("holoc runs")
    };
    // A symbolic link stays a link; the file it names gets the house.
    let real = dir.join("real.json");
    std::fs::write(&real, "old").expect("writable");
    #[cfg(unix)]
    {
        let link = dir.join("link.json");
        std::os::unix::fs::symlink("real.json", &link).expect("symlink");
        assert!(build(&link).status.success());
        assert!(std::fs::symlink_metadata(&link).expect("link").file_type().is_symlink());
        assert!(std::fs::read_to_string(&real).expect("real").contains("\"rooms\""));
    }
    // A folder is a clear error, exit 2.
    let folder = dir.join("folder");
    std::fs::create_dir_all(&folder).expect("folder");
    let out = build(&folder);
    assert_eq!(out.status.code(), Some(2));
    assert!(String::from_utf8_lossy(&out.stderr).contains("it is a folder"));
    assert!(folder.is_dir());
    // A FIFO is written in place, not replaced by a file.
    #[cfg(unix)]
    {
        let fifo = dir.join("pipe");
        let made = Command::new("mkfifo").arg(&fifo).status();
        if made.is_ok_and(|s| s.success()) {
            let reader = {
                let fifo = fifo.clone();
                std::thread::spawn(move || std::fs::read(&fifo).expect("the FIFO can be read"))
            };
            assert!(build(&fifo).status.success());
            let bytes = reader.join().expect("reader");
            assert!(String::from_utf8_lossy(&bytes).contains("\"rooms\""));
            assert!(std::os::unix::fs::FileTypeExt::is_fifo(
                &std::fs::metadata(&fifo).expect("fifo").file_type()
            ));
        }
    }
    let _ = std::fs::remove_dir_all(&dir);
}

/// `holoc repair --write` rewrites the corners in place, then finds nothing more to do;
/// `build --repair` builds the broken plan that `build` rejects; the JSON diagnostics carry the
/// fix that `--write` applied.
#[test]
fn repair_writes_the_corners_and_build_repair_builds() {
    let dir = scratch("repair");
    let scene = dir.join("overlap.holo");
    std::fs::copy("tests/corpus/repair/overlap_small.holo", &scene).expect("copy");
    let plain = holoc().args(["build", "-q"]).arg(&scene).output().expect("holoc runs");
    assert_eq!(plain.status.code(), Some(1), "the plan does not build as written");
    let repaired = holoc()
        .args(["build", "--repair", "-q", "-o"])
        .arg(dir.join("house.json"))
        .arg(&scene)
        .output()
        .expect("holoc runs");
    assert!(repaired.status.success(), "{}", String::from_utf8_lossy(&repaired.stderr));
    assert!(String::from_utf8_lossy(&repaired.stderr).contains("W0307"));
    let json = holoc()
        .args(["repair", "--format", "json", "-o"])
        .arg(dir.join("fixed.holo"))
        .arg(&scene)
        .output()
        .expect("holoc runs");
    let diags: serde_json::Value = serde_json::from_slice(&json.stdout).expect("one document");
    let fix = &diags["diagnostics"][0]["fixes"][0];
    assert_eq!(fix["replacement"], "m (4, 0) (4, 4) (8, 4) (8, 0)", "{diags:#}");
    let written = holoc().args(["repair", "--write"]).arg(&scene).output().expect("holoc runs");
    assert!(written.status.success());
    let text = std::fs::read_to_string(&scene).expect("readable");
    assert!(text.contains("room bedroom \"bedroom\" { corners in m (4, 0) (4, 4) (8, 4) (8, 0) }"));
    assert_eq!(text, std::fs::read_to_string(dir.join("fixed.holo")).expect("readable"));
    let again = holoc().args(["repair", "--write"]).arg(&scene).output().expect("holoc runs");
    assert!(again.status.success());
    assert!(again.stderr.is_empty() || !String::from_utf8_lossy(&again.stderr).contains("W0307"));
    assert_eq!(std::fs::read_to_string(&scene).expect("readable"), text, "idempotent");
    let built = holoc().args(["build", "-q", "-o"]).arg(dir.join("h2.json")).arg(&scene).output();
    assert!(built.expect("holoc runs").status.success(), "the repaired file builds");
}

/// `-` reads standard input in `check` and `fmt`; `fmt --write -` is refused.
#[test]
fn check_and_fmt_read_standard_input() {
    use std::io::Write as _;
    let scene = std::fs::read("examples/bedroom.holo").expect("example");
    let run = |args: &[&str]| {
        let mut child = holoc()
            .args(args)
            .stdin(Stdio::piped())
            .stdout(Stdio::piped())
            .stderr(Stdio::piped())
            .spawn()
            .expect("runs");
        // `fmt --write -` refuses before it reads: the pipe may be closed then.
        let _ = child.stdin.take().expect("stdin").write_all(&scene);
        child.wait_with_output().expect("output")
    };
    let check = run(&["check", "-"]);
    assert_eq!(check.status.code(), Some(0), "{}", String::from_utf8_lossy(&check.stderr));
    let fmt = run(&["fmt", "-"]);
    assert_eq!(fmt.status.code(), Some(0));
    assert_eq!(fmt.stdout, scene, "the example is formatted already");
    let write = run(&["fmt", "--write", "-"]);
    assert_eq!(write.status.code(), Some(2));
}

/// `explain` without a code says what to give.
#[test]
fn explain_without_a_code_names_list() {
    let out = holoc().arg("explain").output().expect("runs");
    assert_eq!(out.status.code(), Some(2));
    assert!(String::from_utf8_lossy(&out.stderr).contains("--list"));
}

/// `holoc completions` prints a script for each shell that knows the subcommands.
#[test]
fn completions_know_the_subcommands() {
    for shell in ["bash", "zsh", "fish"] {
        let out = holoc().args(["completions", shell]).output().expect("runs");
        assert_eq!(out.status.code(), Some(0), "{shell}");
        let text = String::from_utf8_lossy(&out.stdout);
        for sub in ["build", "check", "batch", "completions"] {
            assert!(text.contains(sub), "{shell}: {sub}");
        }
    }
}

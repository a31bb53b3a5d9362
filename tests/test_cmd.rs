//! `holoc test`: a folder with a passing, a failing, a new and an invalid golden, then
//! `--bless`, then a clean run; `--review` with answers from a file; the `[test]` table of
//! `holoc.toml`; the JSON report; the JUnit report checked against the JUnit XML schema
//! (`tests/junit/junit-10.xsd`) with `xmllint` (skipped with a message when it is absent).
//! Every golden is made by the test itself from `tests/diff/study.holo`, whose floor objects
//! are pinned.

mod common;

use std::path::{Path, PathBuf};
use std::process::Command;

fn holoc() -> Command {
    Command::new(env!("CARGO_BIN_EXE_holoc"))
}

fn scratch(name: &str) -> PathBuf {
    let dir = std::env::temp_dir().join(format!("holoc-test-{name}-{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(dir.join("scenes")).expect("a scratch folder");
    dir
}

fn study() -> String {
    std::fs::read_to_string("tests/diff/study.holo").expect("the scene")
}

/// Builds `scene` (in `dir`) into `golden` (and `report`).
fn build(dir: &Path, scene: &str, golden: &str, report: Option<&str>) {
    let mut cmd = holoc();
    cmd.current_dir(dir).args(["build", scene, "-q", "-o", golden]);
    if let Some(r) = report {
        cmd.args(["--report", r]);
    }
    let out = cmd.output().expect("holoc runs");
    assert!(out.status.success(), "{}", String::from_utf8_lossy(&out.stderr));
}

/// A folder of four scenes: `pass` (its golden is its house), `fail` (its golden and report
/// were made before its shelf moved and its chair stopped being near the desk), `new` (no
/// golden) and `invalid` (a golden that is not a house).
fn four_scenes(name: &str) -> PathBuf {
    let dir = scratch(name);
    let s = study();
    std::fs::write(dir.join("scenes/pass.holo"), &s).expect("written");
    build(&dir, "scenes/pass.holo", "scenes/pass.house.json", None);
    std::fs::write(dir.join("scenes/fail.holo"), &s).expect("written");
    build(&dir, "scenes/fail.holo", "scenes/fail.house.json", Some("scenes/fail.report.json"));
    let moved =
        s.replace("at 4 m, 0.12 m", "at 4.5 m, 0.12 m").replace("at 5 m, 2.1 m", "at 4 m, 1.2 m");
    assert_ne!(moved, s);
    std::fs::write(dir.join("scenes/fail.holo"), moved).expect("written");
    std::fs::write(dir.join("scenes/new.holo"), &s).expect("written");
    std::fs::write(dir.join("scenes/invalid.holo"), &s).expect("written");
    std::fs::write(dir.join("scenes/invalid.house.json"), "{\"rooms\": 3}\n").expect("written");
    dir
}

fn run(dir: &Path, args: &[&str]) -> (i32, String, String) {
    let out = holoc().current_dir(dir).arg("test").args(args).output().expect("holoc runs");
    (
        out.status.code().unwrap_or(-1),
        String::from_utf8_lossy(&out.stdout).into_owned(),
        String::from_utf8_lossy(&out.stderr).into_owned(),
    )
}

fn snapshot(name: &str, args: &[&str], status: i32, stdout: &str) {
    let body = format!("$ holoc test {}\n? {status}\n{stdout}", args.join(" "));
    insta::with_settings!({snapshot_path => "../snapshots/test", prepend_module_to_snapshot => false, omit_expression => true}, {
        insta::assert_snapshot!(name, body);
    });
}

#[test]
fn pass_fail_new_invalid_then_bless_then_clean() {
    let dir = four_scenes("cycle");
    let pass_before = std::fs::read(dir.join("scenes/pass.house.json")).expect("golden");
    let pass_time = std::fs::metadata(dir.join("scenes/pass.house.json"))
        .and_then(|m| m.modified())
        .expect("a time");

    let (status, stdout, stderr) = run(&dir, &["scenes"]);
    snapshot("first_run", &["scenes"], status, &stdout);
    assert_eq!(status, 1, "{stderr}");
    assert!(stdout.contains("test scenes/pass.holo ... ok\n"), "{stdout}");
    assert!(stdout.contains("test scenes/fail.holo ... FAILED\n"), "{stdout}");
    assert!(stdout.contains("test scenes/new.holo ... new\n"), "{stdout}");
    assert!(stdout.contains("test scenes/invalid.holo ... invalid golden\n"), "{stdout}");
    assert!(stdout.contains("relation"), "the golden report's relations are compared: {stdout}");
    // A missing golden is reported, never created without --bless.
    assert!(!dir.join("scenes/new.house.json").exists());

    let (status, stdout, stderr) = run(&dir, &["scenes", "--bless"]);
    snapshot("bless", &["scenes", "--bless"], status, &stdout);
    assert_eq!(status, 0, "{stdout}{stderr}");
    assert!(dir.join("scenes/new.house.json").is_file());
    assert!(!dir.join("scenes/new.report.json").exists(), "reports only where asked");
    assert!(dir.join("scenes/fail.report.json").is_file());
    // Only the goldens that changed are written.
    assert_eq!(std::fs::read(dir.join("scenes/pass.house.json")).expect("golden"), pass_before);
    let pass_after = std::fs::metadata(dir.join("scenes/pass.house.json"))
        .and_then(|m| m.modified())
        .expect("a time");
    assert_eq!(pass_time, pass_after, "a passing golden is not rewritten");
    // No temporary file is left behind.
    let leftovers: Vec<_> = std::fs::read_dir(dir.join("scenes"))
        .expect("folder")
        .flatten()
        .map(|e| e.file_name().to_string_lossy().into_owned())
        .filter(|n| n.starts_with('.'))
        .collect();
    assert!(leftovers.is_empty(), "{leftovers:?}");

    let (status, stdout, _) = run(&dir, &["scenes", "--jobs", "1"]);
    snapshot("clean", &["scenes", "--jobs", "1"], status, &stdout);
    assert_eq!(status, 0, "{stdout}");
    assert!(stdout.ends_with("test result: ok. 4 passed; 0 failed; 0 new\n"), "{stdout}");
    let _ = std::fs::remove_dir_all(&dir);
}

#[test]
fn the_json_report_and_the_same_results_with_any_number_of_jobs() {
    let dir = four_scenes("json");
    let (status, one, _) = run(&dir, &["scenes", "--format", "json", "--jobs", "1"]);
    let (_, two, _) = run(&dir, &["scenes", "--format", "json", "--jobs", "2"]);
    assert_eq!(status, 1);
    assert_eq!(one, two);
    let v: serde_json::Value = serde_json::from_str(&one).expect("one JSON document");
    assert_eq!(
        (v["passed"].as_u64(), v["failed"].as_u64(), v["new"].as_u64(), v["invalid"].as_u64()),
        (Some(1), Some(1), Some(1), Some(1))
    );
    let fail = v["tests"]
        .as_array()
        .expect("tests")
        .iter()
        .find(|t| t["scene"] == "scenes/fail.holo")
        .expect("fail");
    assert_eq!(fail["status"], "failed");
    assert!(fail["changes"].as_array().is_some_and(|c| !c.is_empty()));
    let _ = std::fs::remove_dir_all(&dir);
}

#[test]
fn the_junit_report_follows_the_junit_schema() {
    let dir = four_scenes("junit");
    let (status, xml, _) = run(&dir, &["scenes", "--format", "junit"]);
    assert_eq!(status, 1);
    assert!(
        xml.contains("<testsuite name=\"holoc test\" tests=\"4\" failures=\"2\" errors=\"1\""),
        "{xml}"
    );
    assert!(
        xml.contains("<testcase name=\"scenes/pass.holo\" classname=\"holoc.scenes\" time=\"0\"/>"),
        "{xml}"
    );
    let report = dir.join("report.xml");
    std::fs::write(&report, &xml).expect("written");
    // Jenkins' schema and the strict one of Apache Ant's JUnit task (which wants `time`,
    // `timestamp` and `hostname` on the suite and `time` on every case).
    for schema in ["tests/junit/junit-10.xsd", "tests/junit/ant-junit.xsd"] {
        let schema = std::fs::canonicalize(schema).expect("the schema");
        match Command::new("xmllint")
            .arg("--noout")
            .arg("--schema")
            .arg(&schema)
            .arg(&report)
            .output()
        {
            Ok(out) => assert!(
                out.status.success(),
                "xmllint rejects the report by {}:\n{}\n{xml}",
                schema.display(),
                String::from_utf8_lossy(&out.stderr)
            ),
            Err(_) => {
                common::skip(
                    "the_junit_report_follows_the_junit_schema",
                    "xmllint is not installed (Debian: libxml2-utils; .ci/run installs it)",
                );
                break;
            }
        }
    }
    let _ = std::fs::remove_dir_all(&dir);
}

#[test]
fn review_takes_its_answers_from_a_file() {
    let dir = four_scenes("review");
    // Shown in order: fail, invalid, new (the scenes sorted by path; `pass` passes).
    std::fs::write(dir.join("answers.txt"), "# fail\ny\n# invalid\nn\n# new\ny\n")
        .expect("written");
    let (status, stdout, stderr) = run(&dir, &["scenes", "--review", "--answers", "answers.txt"]);
    assert_eq!(status, 1, "the invalid golden stays: {stdout}");
    assert!(stderr.contains("---- scenes/fail.holo ----"), "{stderr}");
    assert!(stdout.contains("test scenes/fail.holo ... blessed"), "{stdout}");
    assert!(stdout.contains("test scenes/invalid.holo ... invalid golden"), "{stdout}");
    assert!(stdout.contains("test scenes/new.holo ... blessed"), "{stdout}");
    assert_eq!(
        std::fs::read_to_string(dir.join("scenes/invalid.house.json")).expect("kept"),
        "{\"rooms\": 3}\n"
    );
    let (status, _, _) = run(&dir, &["scenes/fail.holo", "scenes/new.holo", "scenes/pass.holo"]);
    assert_eq!(status, 0);
    let _ = std::fs::remove_dir_all(&dir);
}

#[test]
fn holoc_toml_names_the_scenes_and_a_golden_folder() {
    let dir = scratch("toml");
    std::fs::write(dir.join("scenes/study.holo"), study()).expect("written");
    std::fs::write(
        dir.join("holoc.toml"),
        "[test]\nscenes = [\"scenes\"]\ngoldens = \"goldens\"\ntolerance = \"2cm,2deg\"\nignore = [\"lights\"]\n",
    )
    .expect("written");
    let (status, stdout, _) = run(&dir, &[]);
    assert_eq!(status, 1, "{stdout}");
    assert!(stdout.contains("no golden at "), "{stdout}");
    let (status, _, _) = run(&dir, &["--bless", "--reports"]);
    assert_eq!(status, 0);
    assert!(dir.join("goldens/scenes/study.house.json").is_file());
    assert!(dir.join("goldens/scenes/study.report.json").is_file());
    assert!(!dir.join("scenes/study.house.json").exists());
    let (status, stdout, _) = run(&dir, &[]);
    assert_eq!(status, 0, "{stdout}");
    std::fs::write(dir.join("holoc.toml"), "[test]\ncolour = \"blue\"\n").expect("written");
    let (status, _, stderr) = run(&dir, &[]);
    assert_eq!(status, 2);
    assert!(stderr.contains("E0004"), "{stderr}");
    let _ = std::fs::remove_dir_all(&dir);
}

/// One catalog source: under a `holoc.toml` that names a catalog, `holoc build` of a scene gives
/// the house `holoc test` checks (here a sofa pinned to an asset only that catalog has), and the
/// golden report holds no absolute path.
#[test]
fn build_and_test_read_the_same_catalogs_from_holoc_toml() {
    let dir = scratch("toml-catalog");
    std::fs::copy("tests/catalog/procthor_small.json", dir.join("mine.json")).expect("copy");
    std::fs::write(dir.join("holoc.toml"), "catalogs = [\"mine.json\"]\n").expect("written");
    let scene = study().replace(
        "  object lamp \"floor lamp\" {",
        "  object sofa \"sofa\" {\n    asset \"Test_Sofa_Green\"\n    middle\n  }\n  object lamp \"floor lamp\" {",
    );
    std::fs::write(dir.join("scenes/sofa.holo"), &scene).expect("written");
    // `build` reads the catalog of `holoc.toml` (from a folder under it, too).
    let out = holoc()
        .current_dir(dir.join("scenes"))
        .args(["build", "sofa.holo", "-q", "-o", "sofa.house.json", "--report", "sofa.report.json"])
        .output()
        .expect("holoc runs");
    assert!(out.status.success(), "{}", String::from_utf8_lossy(&out.stderr));
    let house = std::fs::read_to_string(dir.join("scenes/sofa.house.json")).expect("the house");
    assert!(house.contains("Test_Sofa_Green"), "the catalog of holoc.toml is not used");
    // `test` checks the same house: it passes.
    let (status, stdout, stderr) = run(&dir, &["scenes/sofa.holo"]);
    assert_eq!(status, 0, "{stdout}\n{stderr}");
    // Blessing writes a report whose paths are relative to the project.
    let (status, _, stderr) = run(&dir, &["scenes/sofa.holo", "--bless", "--reports"]);
    assert_eq!(status, 0, "{stderr}");
    let report = std::fs::read_to_string(dir.join("scenes/sofa.report.json")).expect("a report");
    let root = dir.display().to_string();
    assert!(!report.contains(&root), "an absolute path in the golden report:\n{report}");
    assert!(report.contains("\"path\": \"mine.json\""), "{report}");
    // Outside the project the catalog is not there: the pinned asset is unknown.
    let elsewhere = scratch("toml-catalog-elsewhere");
    std::fs::write(elsewhere.join("sofa.holo"), &scene).expect("written");
    let out = holoc()
        .current_dir(&elsewhere)
        .args(["build", "sofa.holo", "-q", "-o", "sofa.house.json"])
        .output()
        .expect("holoc runs");
    assert!(String::from_utf8_lossy(&out.stderr).contains("E0401"));
    let _ = std::fs::remove_dir_all(&dir);
    let _ = std::fs::remove_dir_all(&elsewhere);
}

/// The python3 script that runs a command under a pseudo-terminal: it waits for each prompt,
/// presses one key (no Enter), and prints what the terminal showed, then `EXIT <status>`.
const PTY_DRIVER: &str = r#"
import os, pty, sys, select, time
keys = sys.argv[1]
argv = sys.argv[2:]
pid, fd = pty.fork()
if pid == 0:
    os.execv(argv[0], argv)
seen = b""
def read_some(limit):
    global seen
    end = time.time() + limit
    while time.time() < end:
        r, _, _ = select.select([fd], [], [], 0.1)
        if r:
            try:
                chunk = os.read(fd, 65536)
            except OSError:
                return False
            if not chunk:
                return False
            seen += chunk
            return True
    return True
for key in keys:
    prompts = seen.count(b"[a]ccept")
    deadline = time.time() + 120
    while seen.count(b"[a]ccept") == prompts and time.time() < deadline:
        if not read_some(1):
            break
    time.sleep(0.2)
    os.write(fd, key.encode())
while read_some(5):
    pass
_, status = os.waitpid(pid, 0)
sys.stdout.write(seen.decode("utf-8", "replace"))
sys.stdout.write("\nEXIT %d\n" % os.waitstatus_to_exitcode(status))
"#;

/// `holoc test --review` at a terminal: one scene at a time, its difference, then one key read
/// as it is pressed: `a` accepts (the golden is written), `r` rejects (the old golden stays, no
/// pending golden), `s` skips (the new house waits as `.new`). Driven through a pseudo-terminal
/// by python3's `pty` module (skipped with a message without python3).
#[test]
fn review_at_a_terminal_reads_one_key_a_scene() {
    let test = "review_at_a_terminal_reads_one_key_a_scene";
    if Command::new("python3")
        .arg("-c")
        .arg("import pty")
        .output()
        .map_or(true, |o| !o.status.success())
    {
        common::skip(test, "python3 with its pty module is not installed");
        return;
    }
    let dir = four_scenes("pty");
    let out = Command::new("python3")
        .current_dir(&dir)
        .arg("-c")
        .arg(PTY_DRIVER)
        .arg("ars")
        .arg(env!("CARGO_BIN_EXE_holoc"))
        .args(["test", "scenes", "--review", "--color", "never"])
        .output()
        .expect("python3 runs");
    let shown = String::from_utf8_lossy(&out.stdout);
    // Shown in order, one at a time: fail, invalid, new.
    let fail = shown.find("---- scenes/fail.holo ---- (1 of 3)").expect(&shown);
    let invalid = shown.find("---- scenes/invalid.holo ---- (2 of 3)").expect(&shown);
    let new = shown.find("---- scenes/new.holo ---- (3 of 3)").expect(&shown);
    assert!(fail < invalid && invalid < new, "{shown}");
    // The second scene is shown only after the first key.
    let first_answer = shown.find("accept\r\n").or_else(|| shown.find("accept\n")).expect(&shown);
    assert!(fail < first_answer && first_answer < invalid, "{shown}");
    assert!(shown.contains("reject") && shown.contains("skip"), "{shown}");
    assert!(shown.contains("EXIT 1"), "the invalid golden stays:\n{shown}");
    // `a`: the golden of fail is the new house; no pending golden.
    let (status, _, _) = run(&dir, &["scenes/fail.holo"]);
    assert_eq!(status, 0);
    assert!(!dir.join("scenes/fail.house.json.new").exists());
    // `r`: the invalid golden stays, nothing pending.
    assert_eq!(
        std::fs::read_to_string(dir.join("scenes/invalid.house.json")).expect("kept"),
        "{\"rooms\": 3}\n"
    );
    assert!(!dir.join("scenes/invalid.house.json.new").exists());
    // `s`: no golden yet, the new house waits beside where it goes.
    assert!(!dir.join("scenes/new.house.json").exists());
    let pending = std::fs::read_to_string(dir.join("scenes/new.house.json.new")).expect("pending");
    assert!(pending.contains("\"rooms\""));
    let _ = std::fs::remove_dir_all(&dir);
}

/// A failing run leaves a `.new` golden beside each golden it could not match, for a review
/// later or in another tool; a passing run removes it.
#[test]
fn failing_scenes_leave_pending_goldens() {
    let dir = four_scenes("pending");
    let (status, _, _) = run(&dir, &["scenes"]);
    assert_eq!(status, 1);
    for name in ["fail", "new", "invalid"] {
        let pending = dir.join(format!("scenes/{name}.house.json.new"));
        assert!(pending.is_file(), "no pending golden for {name}");
    }
    assert!(!dir.join("scenes/pass.house.json.new").exists());
    // Moving the pending golden into place is an accepted review.
    std::fs::rename(dir.join("scenes/new.house.json.new"), dir.join("scenes/new.house.json"))
        .expect("moved");
    let (status, stdout, _) = run(&dir, &["scenes/new.holo"]);
    assert_eq!(status, 0, "{stdout}");
    assert!(!dir.join("scenes/new.house.json.new").exists());
    let _ = std::fs::remove_dir_all(&dir);
}

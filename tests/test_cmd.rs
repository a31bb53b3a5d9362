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
        xml.contains("<testcase name=\"scenes/pass.holo\" classname=\"holoc.scenes\"/>"),
        "{xml}"
    );
    let report = dir.join("report.xml");
    std::fs::write(&report, &xml).expect("written");
    let schema = std::fs::canonicalize("tests/junit/junit-10.xsd").expect("the schema");
    match Command::new("xmllint").arg("--noout").arg("--schema").arg(&schema).arg(&report).output()
    {
        Ok(out) => assert!(
            out.status.success(),
            "xmllint rejects the report:\n{}\n{xml}",
            String::from_utf8_lossy(&out.stderr)
        ),
        Err(_) => common::skip(
            "the_junit_report_follows_the_junit_schema",
            "xmllint is not installed (Debian: libxml2-utils; .ci/run installs it)",
        ),
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

//! The CI recipe of the book's guide for scene owners (`book/src/scenes-under-test.md`, "In
//! CI"), played from a scene repository that is not the holoc checkout: a temporary folder
//! with a `holoc.toml`, two scenes of the examples and git. The commands are read from the
//! page itself, so the page and this test cannot drift: the `$ ` lines of "Write, bless,
//! change, review", then the GitHub workflow's `run:` lines (which must be the GitLab
//! `script:` lines), clean and after a change to a scene.
//!
//! The `cargo install` line is not run (a release compile of minutes): the `holoc` this test
//! was built with is put on `PATH` in its place, or the one `HOLOC_CI_RECIPE_BIN` names —
//! `tests/scripts/ci_recipe.sh` installs holoc for real with the page's line and runs this
//! test with it.

#![cfg(unix)]

mod common;

use std::path::{Path, PathBuf};
use std::process::Command;

const PAGE: &str = "book/src/scenes-under-test.md";

/// The text of the section of `page` headed `heading`, up to the next `## ` heading.
fn section<'a>(page: &'a str, heading: &str) -> &'a str {
    let start = page.find(heading).unwrap_or_else(|| panic!("{PAGE} has `{heading}`"));
    let rest = &page[start + heading.len()..];
    rest.find("\n## ").map_or(rest, |end| &rest[..end])
}

/// The fenced code blocks of `text`: (info string, body).
fn blocks(text: &str) -> Vec<(String, String)> {
    let mut out = Vec::new();
    let mut lines = text.lines();
    while let Some(line) = lines.next() {
        if let Some(info) = line.strip_prefix("```") {
            let body: Vec<&str> = lines.by_ref().take_while(|l| !l.starts_with("```")).collect();
            out.push((info.to_string(), body.join("\n")));
        }
    }
    out
}

/// A shell line without its trailing `# comment`.
fn command(line: &str) -> String {
    line.split(" # ").next().unwrap_or(line).trim().to_string()
}

/// The recipe's lines: the GitHub workflow's `run:` lines, checked to be the GitLab job's
/// `script:` lines.
fn recipe(page: &str) -> Vec<String> {
    let ci = blocks(section(page, "## In CI"));
    let github = &ci.iter().find(|(_, b)| b.starts_with("# .github/workflows/")).expect("GitHub").1;
    let gitlab = &ci.iter().find(|(_, b)| b.starts_with("# .gitlab-ci.yml")).expect("GitLab").1;
    let runs: Vec<String> = github
        .lines()
        .filter_map(|l| l.trim_start().strip_prefix("- run: "))
        .map(command)
        .collect();
    let script: Vec<String> = gitlab
        .lines()
        .skip_while(|l| l.trim() != "script:")
        .skip(1)
        .take_while(|l| l.trim_start().starts_with("- "))
        .map(|l| command(l.trim_start().trim_start_matches("- ")))
        .collect();
    assert_eq!(runs, script, "the GitHub and GitLab recipes run the same commands");
    assert!(runs.len() >= 2, "{runs:?}");
    runs
}

/// The `$ ` lines of the first block of "Write, bless, change, review" that blesses.
fn walkthrough(page: &str) -> Vec<String> {
    blocks(section(page, "## Write, bless, change, review"))
        .into_iter()
        .find(|(_, b)| b.contains("--bless"))
        .expect("the block that blesses")
        .1
        .lines()
        .filter_map(|l| l.strip_prefix("$ "))
        .map(command)
        .collect()
}

/// A scene repository in a temporary folder: `holoc.toml`, two scenes, git.
fn scene_repository() -> PathBuf {
    let dir = std::env::temp_dir().join(format!("holoc-ci-recipe-{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(dir.join("scenes")).expect("a scratch folder");
    std::fs::write(dir.join("holoc.toml"), "[test]\nscenes = [\"scenes\"]\n").expect("written");
    for (from, to) in [("bedroom", "bedroom"), ("professor_office", "office")] {
        std::fs::copy(format!("examples/{from}.holo"), dir.join(format!("scenes/{to}.holo")))
            .expect("an example");
    }
    dir
}

/// `holoc` on a `bin` folder of its own, to put first on `PATH`.
fn bin_folder(dir: &Path) -> PathBuf {
    let bin = dir.join("bin");
    std::fs::create_dir_all(&bin).expect("a bin folder");
    let holoc = std::env::var_os("HOLOC_CI_RECIPE_BIN")
        .map_or_else(|| PathBuf::from(env!("CARGO_BIN_EXE_holoc")), PathBuf::from);
    assert!(holoc.is_file(), "no holoc at {}", holoc.display());
    std::os::unix::fs::symlink(&holoc, bin.join("holoc")).expect("linked");
    bin
}

struct Shell {
    repo: PathBuf,
    path: std::ffi::OsString,
}

impl Shell {
    /// Runs `line` as `sh -c` would in the scene repository: (exit status, stdout, stderr).
    fn run(&self, line: &str) -> (i32, String, String) {
        let out = Command::new("sh")
            .arg("-c")
            .arg(line)
            .current_dir(&self.repo)
            .env("PATH", &self.path)
            .env("HOLOC_GIT", "file:///nowhere/holoc")
            .env("GIT_AUTHOR_NAME", "ci")
            .env("GIT_AUTHOR_EMAIL", "ci@example.org")
            .env("GIT_COMMITTER_NAME", "ci")
            .env("GIT_COMMITTER_EMAIL", "ci@example.org")
            .env("NO_COLOR", "1")
            .output()
            .expect("sh runs");
        (
            out.status.code().unwrap_or(-1),
            String::from_utf8_lossy(&out.stdout).into_owned(),
            String::from_utf8_lossy(&out.stderr).into_owned(),
        )
    }

    /// Plays the recipe's lines; the exit status of the last that ran, the JUnit report.
    fn recipe(&self, lines: &[String]) -> (i32, String) {
        let mut status = 0;
        for line in lines {
            if line.starts_with("cargo install") {
                // holoc is on PATH already (see the module's comment).
                assert!(line.contains("--locked") && line.contains("holoc"), "{line}");
                continue;
            }
            let (s, stdout, stderr) = self.run(line);
            assert!(s == 0 || s == 1, "`{line}` exits {s}:\n{stdout}{stderr}");
            status = s;
        }
        let report = lines
            .iter()
            .find_map(|l| l.split("> ").nth(1))
            .map(|f| self.repo.join(f.trim()))
            .expect("the recipe writes a report");
        (status, std::fs::read_to_string(report).expect("the JUnit report"))
    }
}

fn strict_junit(test: &str, report: &Path) {
    let schema = std::fs::canonicalize("tests/junit/ant-junit.xsd").expect("the schema");
    match Command::new("xmllint").arg("--noout").arg("--schema").arg(&schema).arg(report).output() {
        Ok(out) => assert!(
            out.status.success(),
            "xmllint rejects {}: {}",
            report.display(),
            String::from_utf8_lossy(&out.stderr)
        ),
        Err(_) => common::skip(test, "xmllint is not installed (Debian: libxml2-utils)"),
    }
}

#[test]
fn the_ci_recipe_works_from_a_scene_repository() {
    let page = std::fs::read_to_string(PAGE).expect("the book's page");
    let lines = recipe(&page);
    assert!(lines.iter().any(|l| l.starts_with("cargo install")), "{lines:?}");
    let walk = walkthrough(&page);
    assert_eq!(walk.len(), 3, "{walk:?}");

    let repo = scene_repository();
    let bin = bin_folder(&repo);
    let mut path = std::ffi::OsString::from(&bin);
    path.push(":");
    path.push(std::env::var_os("PATH").unwrap_or_default());
    let shell = Shell { repo: repo.clone(), path };
    let git = shell.run("git init -q").0 == 0;

    // Write, bless: the first run reports both scenes new, the second writes their goldens.
    let (status, stdout, stderr) = shell.run(&walk[0]);
    assert_eq!(status, 1, "{stdout}{stderr}");
    assert!(stdout.contains("test scenes/bedroom.holo ... new"), "{stdout}");
    assert!(stdout.contains("0 passed; 0 failed; 2 new"), "{stdout}");
    let (status, stdout, stderr) = shell.run(&walk[1]);
    assert_eq!(status, 0, "{stdout}{stderr}");
    for name in ["bedroom", "office"] {
        for golden in ["house", "report"] {
            let file = repo.join(format!("scenes/{name}.{golden}.json"));
            assert!(file.is_file(), "{} after `{}`", file.display(), walk[1]);
        }
    }
    if git {
        let (status, stdout, stderr) = shell.run(&walk[2]);
        assert_eq!(status, 0, "`{}`: {stdout}{stderr}", walk[2]);
    } else {
        common::skip("the_ci_recipe_works_from_a_scene_repository", "git does not run: no commit");
    }

    // CI, clean: exit 0, both scenes pass.
    let (status, xml) = shell.recipe(&lines);
    assert_eq!(status, 0, "{xml}");
    assert!(xml.contains("tests=\"2\" failures=\"0\" errors=\"0\""), "{xml}");
    strict_junit("the_ci_recipe_works_from_a_scene_repository", &repo.join("holoc-test.xml"));

    // A change to a scene: the job fails with one failure, and leaves the new house to review.
    let scene = repo.join("scenes/bedroom.holo");
    let text = std::fs::read_to_string(&scene).expect("the scene");
    let changed = text.replace("(0, 4.5) (4, 4.5)", "(0, 5) (4, 5)");
    assert_ne!(changed, text);
    std::fs::write(&scene, changed).expect("written");
    let (status, xml) = shell.recipe(&lines);
    assert_eq!(status, 1, "{xml}");
    assert!(xml.contains("tests=\"2\" failures=\"1\""), "{xml}");
    assert!(xml.contains("scenes/bedroom.holo"), "{xml}");
    assert!(repo.join("scenes/bedroom.house.json.new").is_file());
    strict_junit("the_ci_recipe_works_from_a_scene_repository", &repo.join("holoc-test.xml"));

    let _ = std::fs::remove_dir_all(&repo);
}

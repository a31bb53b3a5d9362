//! Resource bounds and faults, through the binary: runaway inputs end in seconds with a
//! diagnostic or a result and bounded memory, and a failing or interrupted command never leaves
//! a half-written output.

mod common;

use std::fmt::Write as _;
use std::io::Write as _;
use std::path::{Path, PathBuf};
use std::process::{Command, Output};

fn holoc() -> Command {
    Command::new(env!("CARGO_BIN_EXE_holoc"))
}

fn scratch(name: &str) -> PathBuf {
    let dir = std::env::temp_dir().join(format!("holoc-limits-{}-{name}", std::process::id()));
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).expect("scratch folder");
    dir
}

fn stderr(out: &Output) -> String {
    String::from_utf8_lossy(&out.stderr).into_owned()
}

/// A room of `n` boxes along its walls.
fn warehouse(n: usize) -> String {
    let mut text = String::from(
        "scene \"warehouse\" { seed 1 }\nroom a \"warehouse\" {\n  corners in m (0, 0) (0, 30) (30, 30) (30, 0)\n",
    );
    for i in 0..n {
        let _ = writeln!(text, "  object box{i} \"cardboard box\" {{ edge }}");
    }
    text.push_str("}\ndoor exterior -- a : doorway single\n");
    text
}

#[test]
fn a_room_of_ten_thousand_objects_builds_its_first_hundred() {
    let dir = scratch("objects");
    let scene = dir.join("warehouse.holo");
    std::fs::write(&scene, warehouse(10_000)).expect("write");
    let out = holoc()
        .args(["build", "--format", "short", "-o"])
        .arg(dir.join("house.json"))
        .arg(&scene)
        .output()
        .expect("holoc runs");
    assert_eq!(out.status.code(), Some(0), "{}", stderr(&out));
    let err = stderr(&out);
    assert!(err.contains("warning[W0504]"), "{err}");
    assert!(err.contains("100 of 10000 objects placed"), "{}", err.lines().last().unwrap_or(""));
}

#[test]
fn an_outline_of_a_hundred_thousand_corners_is_refused() {
    let dir = scratch("corners");
    let mut corners = vec!["(0, 0)".to_string()];
    for k in 0..50_000 {
        let x = f64::from(k) * 0.01 + 0.01;
        corners.push(format!("({x:.2}, {:.2})", f64::from(k) * 0.01));
        corners.push(format!("({x:.2}, {:.2})", f64::from(k + 1) * 0.01));
    }
    corners.push("(0, 500)".to_string());
    let scene = dir.join("stairs.holo");
    std::fs::write(
        &scene,
        format!(
            "room a \"a\" {{\n  corners in m {}\n}}\ndoor exterior -- a : doorway single\n",
            corners.join(" ")
        ),
    )
    .expect("write");
    let out = holoc().args(["check", "--format", "short"]).arg(&scene).output().expect("runs");
    assert_eq!(out.status.code(), Some(1));
    assert!(stderr(&out).contains("error[E0220]"), "{}", stderr(&out));
}

#[test]
fn inputs_that_never_end_or_are_too_large_are_refused() {
    let dir = scratch("inputs");
    // 40 MB of a valid-looking scene: more than holoc reads.
    let large = dir.join("large.holo");
    let mut file = std::fs::File::create(&large).expect("create");
    let line = "// a comment line that fills the file with bytes and nothing else\n";
    for _ in 0..(40 * 1024 * 1024 / line.len()) {
        file.write_all(line.as_bytes()).expect("write");
    }
    drop(file);
    for input in [large.as_path(), Path::new("/dev/zero")] {
        if !input.exists() {
            continue;
        }
        let out = holoc().args(["check", "--format", "short"]).arg(input).output().expect("runs");
        assert_eq!(out.status.code(), Some(2), "{}: {}", input.display(), stderr(&out));
        assert!(stderr(&out).contains("larger than 32 MiB"), "{}", stderr(&out));
    }
    // A named pipe with no writer: refused at once, not waited on.
    let fifo = dir.join("scene.fifo");
    if Command::new("mkfifo").arg(&fifo).status().is_ok_and(|s| s.success()) {
        let out = holoc().args(["check", "--format", "short"]).arg(&fifo).output().expect("runs");
        assert_eq!(out.status.code(), Some(2), "{}", stderr(&out));
        assert!(stderr(&out).contains("it is a named pipe"), "{}", stderr(&out));
    } else {
        common::skip("inputs_that_never_end_or_are_too_large_are_refused (fifo)", "no mkfifo here");
    }
    let folder = holoc().args(["check"]).arg(&dir).output().expect("runs");
    assert_eq!(folder.status.code(), Some(2));
    assert!(stderr(&folder).contains("it is a folder"), "{}", stderr(&folder));
}

#[test]
fn a_gzip_bomb_catalog_is_refused_in_bounded_memory() {
    let dir = scratch("bomb");
    let bomb = dir.join("bomb.json.gz");
    let mut enc = flate2::write::GzEncoder::new(
        std::fs::File::create(&bomb).expect("create"),
        flate2::Compression::fast(),
    );
    let chunk = vec![b' '; 1024 * 1024];
    for _ in 0..520 {
        enc.write_all(&chunk).expect("write");
    }
    enc.finish().expect("finish");
    assert!(std::fs::metadata(&bomb).expect("written").len() < 8 * 1024 * 1024);
    let out =
        holoc().args(["assets", "search", "chair", "--catalog"]).arg(&bomb).output().expect("runs");
    assert!(stderr(&out).contains("larger than 512 MiB"), "{}", stderr(&out));
}

#[test]
fn a_huge_node_budget_is_bad_usage() {
    let out = holoc()
        .args(["build", "examples/bedroom.holo", "--node-budget", "1000000000000", "-o", "-"])
        .output()
        .expect("runs");
    assert_eq!(out.status.code(), Some(2));
    assert!(stderr(&out).contains("0..=10000"), "{}", stderr(&out));
}

#[test]
fn a_read_only_output_folder_is_a_clear_error_and_nothing_is_written() {
    let dir = scratch("readonly");
    let out_dir = dir.join("out");
    std::fs::create_dir_all(&out_dir).expect("folder");
    let mut perms = std::fs::metadata(&out_dir).expect("meta").permissions();
    perms.set_readonly(true);
    std::fs::set_permissions(&out_dir, perms).expect("read-only");
    // Root ignores permissions; the test says so instead of asserting nothing.
    let probe = out_dir.join("probe");
    if std::fs::write(&probe, b"x").is_ok() {
        let _ = std::fs::remove_file(&probe);
        common::skip(
            "a_read_only_output_folder_is_a_clear_error_and_nothing_is_written",
            "this user (root) can write into read-only folders",
        );
    } else {
        let out = holoc()
            .args(["build", "examples/bedroom.holo", "-q", "-o"])
            .arg(out_dir.join("house.json"))
            .output()
            .expect("runs");
        assert_eq!(out.status.code(), Some(2), "{}", stderr(&out));
        assert!(stderr(&out).contains("E0001"), "{}", stderr(&out));
        assert_eq!(std::fs::read_dir(&out_dir).expect("list").count(), 0, "nothing half-written");
    }
    let mut perms = std::fs::metadata(&out_dir).expect("meta").permissions();
    #[allow(clippy::permissions_set_readonly_false, reason = "the scratch folder is removed next")]
    perms.set_readonly(false);
    let _ = std::fs::set_permissions(&out_dir, perms);
}

/// Two builds writing one output at once: the output is one whole house (the same either
/// way), never a mix.
#[test]
fn two_builds_writing_one_output_leave_a_whole_house() {
    let dir = scratch("race");
    let target = dir.join("house.json");
    let children: Vec<_> = (0..2)
        .map(|_| {
            holoc()
                .args(["build", "examples/apartment_1b1b.holo", "-q", "-o"])
                .arg(&target)
                .spawn()
                .expect("holoc starts")
        })
        .collect();
    for mut c in children {
        assert!(c.wait().expect("ends").success());
    }
    let alone = holoc()
        .args(["build", "examples/apartment_1b1b.holo", "-q", "-o", "-"])
        .output()
        .expect("runs");
    assert_eq!(std::fs::read(&target).expect("written"), alone.stdout);
}

/// `kill -9` during a build: the output is the old file or the whole new one.
#[test]
fn a_killed_build_leaves_the_old_output_or_the_new_one() {
    let dir = scratch("kill");
    let scene = dir.join("warehouse.holo");
    std::fs::write(&scene, warehouse(150)).expect("write");
    let target = dir.join("house.json");
    for delay_ms in [50u64, 400, 1500] {
        std::fs::write(&target, b"the old house").expect("old output");
        let mut child = holoc()
            .args(["build", "-q", "-o"])
            .arg(&target)
            .arg(&scene)
            .stderr(std::process::Stdio::null())
            .spawn()
            .expect("starts");
        std::thread::sleep(std::time::Duration::from_millis(delay_ms));
        let _ = child.kill();
        let _ = child.wait();
        let now = std::fs::read(&target).expect("the output exists");
        let whole = now == b"the old house"
            || serde_json::from_slice::<serde_json::Value>(&now)
                .is_ok_and(|v| v.get("rooms").is_some());
        assert!(whole, "after {delay_ms} ms: {} bytes, neither old nor whole", now.len());
    }
}

/// `x 1000000` wherever a quantity is written: the `.holo` language refuses it at the number
/// (E0208) without a cascade of unknown instances, and the importer either refuses the field
/// with the answer's text kept (E0702) or, for the JSON objects answer, clamps it with a
/// warning (W0707). Nothing expands a million of anything.
#[test]
fn quantities_of_a_million_are_refused_or_clamped() {
    let dir = scratch("quantities");
    let example = std::fs::read_to_string("examples/apartment_1b1b.holo").expect("example");
    let scene = example
        .replacen("count 2, sill 90 cm", "count 1000000, sill 90 cm", 1)
        .replacen("\"book\" x2 varied", "\"book\" x1000000 varied", 1)
        .replacen("count 2 same", "count 1000000 same", 1);
    assert_eq!(scene.matches("1000000").count(), 3, "the example changed; update this test");
    let path = dir.join("million.holo");
    std::fs::write(&path, &scene).expect("write");
    for command in ["check", "build"] {
        let out = holoc()
            .args([command, "--format", "short"])
            .arg(&path)
            .args(if command == "build" { vec!["-o", "-"] } else { vec![] })
            .output()
            .expect("holoc runs");
        assert_eq!(out.status.code(), Some(1), "{command}: {}", stderr(&out));
        let err = stderr(&out);
        let errors: Vec<&str> = err.lines().filter(|l| l.contains(": error[")).collect();
        assert_eq!(errors.len(), 3, "{command}: exactly the three counts: {err}");
        assert!(errors.iter().all(|l| l.contains("error[E0208]")), "{err}");
        assert!(
            err.contains("the window count `1000000` is not a whole number from 1 to 20"),
            "{err}"
        );
        assert!(err.contains("the number of items `1000000`"), "{err}");
        assert!(
            err.contains("the object count `1000000` is not a whole number from 1 to 50"),
            "{err}"
        );
    }

    let answers = [
        ("windows", "living room | west | fixed | (150, 120) | 1000000 | 90\n"),
        ("objects-pipe", "living room | floor | chair | a chair | 1000000, same\n"),
        ("small-objects", "sofa-0 (living room) | cushion, 1000000, varied\n"),
    ];
    for (stage, answer) in answers {
        let file = dir.join(format!("{stage}.txt"));
        std::fs::write(&file, answer).expect("write");
        let out = holoc()
            .args(["import", "--format", "short", "--room", "living room", "--stage", stage])
            .arg(&file)
            .output()
            .expect("holoc runs");
        let err = stderr(&out);
        assert!(
            err.contains("error[E0702]: `1000000` is not a quantity from 1 to 100"),
            "{stage}: {err}"
        );
        let holo = String::from_utf8_lossy(&out.stdout);
        assert!(holo.contains("1000000"), "{stage}: the answer is kept in the output: {holo}");
    }

    let json = r#"{"chair": {"description": "a chair", "location": "floor", "size": [50, 50, 90], "quantity": 1000000, "variance_type": "same", "objects_on_top": [{"object_name": "book", "quantity": 1000000, "variance_type": "varied"}]}}"#;
    let file = dir.join("objects.txt");
    std::fs::write(&file, json).expect("write");
    let out = holoc()
        .args(["import", "--format", "short", "--room", "living room", "--stage", "objects"])
        .arg(&file)
        .output()
        .expect("holoc runs");
    let err = stderr(&out);
    assert!(err.contains("warning[W0707]: quantity 1000000 of `chair` became 10"), "{err}");
    assert!(err.contains("warning[W0707]: quantity 1000000 of `book` became 10"), "{err}");
    let holo = String::from_utf8_lossy(&out.stdout);
    assert!(
        holo.contains("count 10 same") && holo.contains("on top \"book\" x10 varied"),
        "{holo}"
    );
}

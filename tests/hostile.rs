//! Hostile and huge inputs, through the binary: deep nesting, pipes and devices where a file is
//! expected, inputs whose checks are pairwise, absurd numbers, manifests that reach outside
//! their folder or choose where the key goes, control characters, a malformed language-server
//! transport. Each ends with a clear diagnostic, in bounded time and memory, with no abort.
//! (Nothing is timed here: the figures are `benches/hostile_bench.rs`'s.)

mod common;
#[path = "support/llm_server.rs"]
mod llm_server;

use std::fmt::Write as _;
use std::io::{BufRead as _, Read as _, Write as _};
use std::path::{Path, PathBuf};
use std::process::{Command, Output, Stdio};

fn holoc() -> Command {
    Command::new(env!("CARGO_BIN_EXE_holoc"))
}

fn scratch(name: &str) -> PathBuf {
    let dir = std::env::temp_dir().join(format!("holoc-hostile-{}-{name}", std::process::id()));
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).expect("scratch folder");
    dir
}

fn stderr(out: &Output) -> String {
    String::from_utf8_lossy(&out.stderr).into_owned()
}

/// Stderr with its diagnostics' wrapped lines joined: a message naming a scratch path (whose
/// length follows the process id) wraps at different words from run to run.
fn stderr_unwrapped(out: &Output) -> String {
    let text = stderr(out);
    let words: Vec<&str> = text.split_whitespace().filter(|w| *w != "│").collect();
    words.join(" ")
}

fn mkfifo(path: &Path) -> bool {
    Command::new("mkfifo").arg(path).status().is_ok_and(|s| s.success())
}

/// A process that did not end by a signal (a stack overflow aborts with SIGABRT or SIGSEGV).
fn no_abort(out: &Output) {
    assert!(out.status.code().is_some(), "ended by a signal: {:?}\n{}", out.status, stderr(out));
}

#[test]
fn deep_nesting_is_a_diagnostic_not_an_abort() {
    let dir = scratch("deep");
    let scene = dir.join("deep.holo");
    let deep = format!(
        "room a \"a\" {{\n  corners in m (0, 0) (0, 4) (4, 4) (4, 0)\n  {}{}\n}}\n",
        "{".repeat(4000),
        "}".repeat(4000)
    );
    std::fs::write(&scene, &deep).expect("write");
    let out = holoc().args(["check", "--format", "short"]).arg(&scene).output().expect("runs");
    no_abort(&out);
    assert_eq!(out.status.code(), Some(1), "{}", stderr(&out));
    assert!(stderr(&out).contains("error[E0107]"), "{}", stderr(&out));
    assert!(stderr(&out).contains("deeper than 64 levels"), "{}", stderr(&out));
    let out = holoc().args(["fmt", "--check"]).arg(&scene).output().expect("runs");
    no_abort(&out);
    // Deep `instance` blocks (valid statements, nested) in a batch: one job fails, the other
    // is built, the summary is written.
    let mut nested = String::from(
        "room a \"a\" {\n  corners in m (0, 0) (0, 4) (4, 4) (4, 0)\n  object t \"table\" ",
    );
    for _ in 0..1000 {
        nested.push_str("{ instance t-0 ");
    }
    nested.push_str(&"}".repeat(1000));
    nested.push_str("\n}\n");
    std::fs::write(dir.join("nested.holo"), nested).expect("write");
    std::fs::copy("examples/bedroom.holo", dir.join("bedroom.holo")).expect("copy");
    std::fs::write(
        dir.join("jobs.jsonl"),
        "{\"build\": \"nested.holo\"}\n{\"build\": \"bedroom.holo\"}\n",
    )
    .expect("write");
    let out = holoc()
        .args(["batch", "-q", "--jobs", "2"])
        .arg(dir.join("jobs.jsonl"))
        .arg("-o")
        .arg(dir.join("out"))
        .output()
        .expect("runs");
    no_abort(&out);
    let summary = std::fs::read_to_string(dir.join("out/summary.json")).expect("a summary");
    assert!(summary.contains("E0107"), "{summary}");
    assert!(summary.contains("\"done\""), "{summary}");
}

#[test]
fn a_deeply_nested_json_answer_is_refused() {
    let dir = scratch("json");
    let answer = dir.join("objects.txt");
    std::fs::write(&answer, format!("{}{}", "{\"a\": ".repeat(5000), "}".repeat(5000)))
        .expect("write");
    let out = holoc()
        .args(["import", "--stage", "objects", "--room", "living room", "--format", "short"])
        .arg(&answer)
        .output()
        .expect("runs");
    no_abort(&out);
    assert_eq!(out.status.code(), Some(1), "{}", stderr(&out));
    assert!(stderr(&out).contains("deeper than 128 levels"), "{}", stderr(&out));
}

#[test]
fn pipes_and_devices_are_never_waited_on_for_ever() {
    let dir = scratch("fifo");
    let fifo = dir.join("catalog.json");
    if !mkfifo(&fifo) {
        common::skip("pipes_and_devices_are_never_waited_on_for_ever", "no mkfifo here");
        return;
    }
    // A catalog that is a named pipe: refused at once by build and assets.
    let out = holoc()
        .args(["build", "examples/bedroom.holo", "-q", "-o", "-", "--catalog"])
        .arg(&fifo)
        .output()
        .expect("runs");
    assert!(stderr_unwrapped(&out).contains("it is a named pipe"), "{}", stderr(&out));
    let out = holoc().args(["assets", "search", "chair", "--catalog"]).arg(&fifo).output();
    assert!(stderr(&out.expect("runs")).contains("it is a named pipe"));
    // In a batch: the scene and the catalog may be pipes, and `/dev/zero` a scene.
    std::fs::copy("examples/bedroom.holo", dir.join("bedroom.holo")).expect("copy");
    let scene_fifo = dir.join("scene.holo");
    assert!(mkfifo(&scene_fifo));
    let mut manifest = String::new();
    let _ = writeln!(manifest, "{{\"build\": \"scene.holo\"}}");
    let _ = writeln!(manifest, "{{\"build\": \"bedroom.holo\", \"catalog\": [\"catalog.json\"]}}");
    let _ = writeln!(manifest, "{{\"build\": \"/dev/zero\"}}");
    let _ = writeln!(manifest, "{{\"build\": \"bedroom.holo\"}}");
    std::fs::write(dir.join("jobs.jsonl"), manifest).expect("write");
    // `--allow-outside`: `/dev/zero` is outside the manifest's folder.
    let out = holoc()
        .args(["batch", "-q", "--allow-outside"])
        .arg(dir.join("jobs.jsonl"))
        .arg("-o")
        .arg(dir.join("out"))
        .output()
        .expect("runs");
    no_abort(&out);
    let summary = std::fs::read_to_string(dir.join("out/summary.json")).expect("a summary");
    assert!(summary.contains("it is a named pipe"), "{summary}");
    assert!(summary.contains("larger than 32 MiB"), "{summary}");
    assert!(summary.contains("\"done\""), "{summary}");
    // A manifest that is a pipe is refused too.
    let manifest_fifo = dir.join("manifest.jsonl");
    assert!(mkfifo(&manifest_fifo));
    let out = holoc()
        .args(["batch", "-q"])
        .arg(&manifest_fifo)
        .arg("-o")
        .arg(dir.join("o2"))
        .output()
        .expect("runs");
    assert_eq!(out.status.code(), Some(2));
    assert!(stderr(&out).contains("it is a named pipe"), "{}", stderr(&out));
}

/// `n` rooms of 4 m × 4 m, every one on the same square.
fn overlapping_rooms(n: usize) -> String {
    let mut text = String::new();
    for i in 0..n {
        let _ = writeln!(
            text,
            "room r{i} \"room {i}\" {{\n  corners in m (0, 0) (0, 4) (4, 4) (4, 0)\n}}"
        );
    }
    text.push_str("door exterior -- r0 : doorway single\n");
    text
}

#[test]
fn pairwise_checks_are_summarised() {
    let dir = scratch("pairs");
    let scene = dir.join("rooms.holo");
    std::fs::write(&scene, overlapping_rooms(2000)).expect("write");
    let out = holoc().args(["check", "--format", "json"]).arg(&scene).output().expect("runs");
    assert_eq!(out.status.code(), Some(1), "{}", stderr(&out));
    let json: serde_json::Value = serde_json::from_slice(&out.stdout).expect("json");
    let list = json["diagnostics"].as_array().expect("a list");
    assert!(list.len() <= 1001, "{} diagnostics", list.len());
    assert!(
        list.iter()
            .any(|d| d["message"] == "… and 1000 more rooms overlap others, from `r1000` on"),
        "the rooms past the first 1,000 get one diagnostic together"
    );
    let text = String::from_utf8_lossy(&out.stdout);
    // Each room is compared with at most 64 of the rooms before it that it overlaps (the work
    // stays linear in the rooms); the first room is met by every later one.
    assert!(
        text.contains("room `r0` overlaps at least 1999 other rooms"),
        "{}",
        &text[..2000.min(text.len())]
    );
    // Human output shows at most 100 per file and says how many more there are.
    let out = holoc().args(["check", "--format", "short"]).arg(&scene).output().expect("runs");
    let err = stderr(&out);
    assert!(err.lines().count() <= 102, "{} lines", err.lines().count());
    // 1,000 rooms with a diagnostic each and one for the 1,000 others: 100 shown, 901 not.
    assert!(err.contains("and 901 more diagnostic(s) not shown"), "{err}");
    // A few overlaps are still reported pair by pair.
    std::fs::write(&scene, overlapping_rooms(3)).expect("write");
    let out = holoc().args(["check", "--format", "short"]).arg(&scene).output().expect("runs");
    assert!(stderr(&out).contains("lies inside room"), "{}", stderr(&out));
}

/// Twenty thousand rooms drawn over each other: every room is reported, and the work is
/// bounded per room (it was quadratic: 200 million pairs, 47 s and 8.7 GB in a release build).
#[test]
fn twenty_thousand_rooms_drawn_over_each_other_are_checked_in_bounded_work() {
    let dir = scratch("pairs20k");
    let scene = dir.join("rooms.holo");
    std::fs::write(&scene, overlapping_rooms(20_000)).expect("write");
    let out = holoc().args(["check", "--format", "json"]).arg(&scene).output().expect("runs");
    assert_eq!(out.status.code(), Some(1), "{}", stderr(&out));
    let json: serde_json::Value = serde_json::from_slice(&out.stdout).expect("json");
    let list = json["diagnostics"].as_array().expect("a list");
    // One E0305 for each of the first 1,000 rooms, then one for the 19,000 others: what is
    // kept of the diagnostics does not grow with the rooms either.
    let overlaps: Vec<_> = list.iter().filter(|d| d["code"] == "E0305").collect();
    assert_eq!(overlaps.len(), 1001, "one E0305 per room up to 1,000, then one for the rest");
    let last = overlaps.last().and_then(|d| d["message"].as_str()).unwrap_or_default();
    assert_eq!(last, "… and 19000 more rooms overlap others, from `r1000` on");
}

/// Rooms side by side in a column along z (their x ranges all the same): the sweep that finds
/// the rooms whose bounds meet looks only at those near in z too. It looked at every pair (a
/// column of 500,000 rooms would have been 10^11 tests); here 40,000 rooms end at once.
#[test]
fn a_column_of_rooms_is_not_compared_pair_by_pair() {
    let dir = scratch("column");
    let scene = dir.join("rooms.holo");
    let mut text = String::new();
    for i in 0..40_000 {
        let (z0, z1) = (4 * i, 4 * i + 4);
        let _ = writeln!(
            text,
            "room r{i} \"r\" {{\n  corners in m (0, {z0}) (0, {z1}) (4, {z1}) (4, {z0})\n}}"
        );
    }
    text.push_str("door exterior -- r0 : doorway single\n");
    for i in 1..40_000 {
        let _ = writeln!(text, "door r{} -- r{i} : doorway single", i - 1);
    }
    std::fs::write(&scene, &text).expect("write");
    let out = bounded(
        {
            let mut c = holoc();
            c.args(["check", "--format", "short"]).arg(&scene);
            c
        },
        "check of a column of 40,000 rooms",
        120,
    );
    no_abort(&out);
    // No room overlaps another: the rooms are side by side.
    assert!(!stderr(&out).contains("E0305"), "{}", &stderr(&out)[..2000.min(stderr(&out).len())]);
}

/// A shape of scene: its name, the text before the items, one item (numbered), the text after.
type Shape = (&'static str, &'static str, fn(usize) -> String, &'static str);

/// A file of more than a million tokens (32 MiB of rooms drawn over each other, of objects, of
/// doors, of corners) is refused before the grammar runs, by every command that reads a scene:
/// E0010, exit 1, at once and in little memory (the rooms took 4.7 GB).
#[test]
fn a_file_of_more_than_a_million_tokens_is_refused_before_it_is_parsed() {
    let dir = scratch("tokens");
    let shapes: [Shape; 3] = [
        (
            "rooms",
            "",
            |i| format!("room r{i} \"r\" {{\n  corners in m (0, 0) (0, 4) (4, 4) (4, 0)\n}}\n"),
            "door exterior -- r0 : doorway single\n",
        ),
        (
            "objects",
            "room a \"a\" {\n  corners in m (0, 0) (0, 4) (4, 4) (4, 0)\n",
            |i| format!("  object o{i} \"chair\" {{\n    size 40 cm x 40 cm x 80 cm\n  }}\n"),
            "}\ndoor exterior -- a : doorway single\n",
        ),
        ("corners", "room a \"a\" {\n  corners in m ", |_| "(0, 0) ".to_owned(), "\n}\n"),
    ];
    for (name, head, item, tail) in shapes {
        let mut text = String::from(head);
        let mut i = 0;
        while holoc::parse::count_tokens(&text) < 1_000_100 {
            for _ in 0..1000 {
                text.push_str(&item(i));
                i += 1;
            }
        }
        text.push_str(tail);
        let scene = dir.join(format!("{name}.holo"));
        std::fs::write(&scene, &text).expect("write");
        for args in [
            vec!["check", "--format", "short"],
            vec!["fmt", "--check"],
            vec!["build", "-q", "-o", "-"],
            vec!["repair"],
        ] {
            let mut cmd = holoc();
            cmd.args(&args).arg(&scene);
            let out = bounded(cmd, &format!("{} of {name}", args[0]), 60);
            no_abort(&out);
            assert_eq!(out.status.code(), Some(1), "{} of {name}: {}", args[0], stderr(&out));
            assert!(stderr(&out).contains("E0010"), "{} of {name}: {}", args[0], stderr(&out));
        }
    }
    // Comments do not count: the classroom under a million comment words is read as before.
    let mut text = std::fs::read_to_string("examples/classroom.holo").expect("example");
    for _ in 0..100_000 {
        text.push_str("// a comment of ten words that the token count leaves out\n");
    }
    let scene = dir.join("comments.holo");
    std::fs::write(&scene, &text).expect("write");
    let out = holoc().args(["check", "--format", "short"]).arg(&scene).output().expect("runs");
    assert!(!stderr(&out).contains("E0010"), "{}", stderr(&out));
}

/// Twenty thousand beds on one spot: `validate` reports them in bounded work (the pairs were
/// all kept: 200 million of them).
#[test]
fn validate_twenty_thousand_objects_on_one_spot_in_bounded_work() {
    let dir = scratch("crowded20k");
    let house = dir.join("house.json");
    std::fs::write(&house, crowded_house(20_000)).expect("write");
    let out = holoc().args(["validate", "--format", "json"]).arg(&house).output().expect("runs");
    no_abort(&out);
    let json: serde_json::Value = serde_json::from_slice(&out.stdout).expect("json");
    let list = json["diagnostics"].as_array().expect("a list");
    let overlapping = list.iter().filter(|d| d["code"] == "W0608").count();
    assert!(overlapping >= 20_000, "{overlapping} W0608");
}

/// A house of the bedroom example with its first floor object copied `n` times.
fn crowded_house(n: usize) -> String {
    let out =
        holoc().args(["build", "examples/bedroom.holo", "-q", "-o", "-"]).output().expect("builds");
    assert!(out.status.success(), "{}", stderr(&out));
    let mut house: serde_json::Value = serde_json::from_slice(&out.stdout).expect("json");
    let objects = house["objects"].as_array_mut().expect("objects");
    let bed = objects
        .iter()
        .find(|o| o["assetId"].as_str().is_some_and(|a| a.starts_with("Bed")))
        .expect("a bed")
        .clone();
    for k in 0..n {
        let mut copy = bed.clone();
        copy["id"] = serde_json::json!(format!("copy-{k}"));
        copy["children"] = serde_json::json!([]);
        objects.push(copy);
    }
    serde_json::to_string_pretty(&house).expect("prints")
}

#[test]
fn validate_summarises_pairs_and_refuses_absurd_numbers() {
    let dir = scratch("validate");
    let house = dir.join("house.json");
    std::fs::write(&house, crowded_house(200)).expect("write");
    let out = holoc().args(["validate", "--format", "short"]).arg(&house).output().expect("runs");
    no_abort(&out);
    let err = stderr(&out);
    // Each object's overlaps are worked out up to 64 (the work stays linear in the objects).
    assert!(err.contains("overlaps at least 64 floor objects"), "{err}");
    assert!(err.lines().filter(|l| l.contains("W0608")).count() <= 100, "{err}");
    // 1e308 as a coordinate: an error, not a panic.
    let text = std::fs::read_to_string(&house).expect("read");
    let at = text.find("\"x\": ").expect("a coordinate") + 5;
    let end = at + text[at..].find([',', '\n']).expect("end");
    let absurd = format!("{}1e308{}", &text[..at], &text[end..]);
    std::fs::write(&house, absurd).expect("write");
    let out = holoc().args(["validate", "--format", "short"]).arg(&house).output().expect("runs");
    no_abort(&out);
    assert_eq!(out.status.code(), Some(1), "{}", stderr(&out));
    assert!(stderr(&out).contains("is beyond 1e5 m"), "{}", stderr(&out));
}

#[test]
fn a_pin_outside_its_room_is_an_error_at_build() {
    let text = std::fs::read_to_string("examples/bedroom.holo").expect("example");
    let pinned = text.replacen(
        "    size 160 cm x 210 cm x 100 cm\n",
        "    size 160 cm x 210 cm x 100 cm\n    at 40 m, 40 m\n",
        1,
    );
    assert_ne!(pinned, text, "the example has the bed's size line");
    let dir = scratch("pin");
    std::fs::write(dir.join("pinned.holo"), pinned).expect("write");
    let out = holoc()
        .args(["build", "--format", "short", "-o"])
        .arg(dir.join("house.json"))
        .arg(dir.join("pinned.holo"))
        .output()
        .expect("runs");
    assert_eq!(out.status.code(), Some(1), "{}", stderr(&out));
    assert!(stderr(&out).contains("error[E0502]"), "{}", stderr(&out));
    assert!(!dir.join("house.json").exists(), "no house that validate would reject");
}

#[test]
fn the_documented_door_asset_form_parses() {
    let dir = scratch("door");
    let text = std::fs::read_to_string("examples/bedroom.holo").expect("example");
    let line = text.lines().find(|l| l.starts_with("door ")).expect("a door line");
    let (head, _) = line.split_once(':').expect("a door kind");
    let written = text.replacen(line, &format!("{head}: doorway asset \"Doorway_1\""), 1);
    std::fs::write(dir.join("door.holo"), written).expect("write");
    let out = holoc().args(["check", "--format", "short"]).arg(dir.join("door.holo")).output();
    let out = out.expect("runs");
    assert_eq!(out.status.code(), Some(0), "{}", stderr(&out));
}

#[test]
fn control_characters_never_reach_the_terminal() {
    let dir = scratch("control");
    let text = std::fs::read_to_string("examples/bedroom.holo").expect("example");
    let hostile = text.replacen("\"bed\"", "\"bed\\u{1b}]0;pwned\\u{7}\"", 1);
    assert_ne!(hostile, text);
    std::fs::write(dir.join("c.holo"), &hostile).expect("write");
    std::fs::write(dir.join("raw.holo"), text.replacen("seed 1", "seed 1 \u{1b}[2J", 1))
        .expect("write");
    for file in ["c.holo", "raw.holo"] {
        for format in ["human", "short"] {
            let out = holoc()
                .args(["check", "--color", "never", "--format", format])
                .arg(dir.join(file))
                .output()
                .expect("runs");
            let err = stderr(&out);
            assert!(!err.contains('\u{1b}') && !err.contains('\u{7}'), "{file} {format}: {err:?}");
        }
    }
    // The SVG stays well-formed XML: checked by a real parser.
    let out = holoc()
        .args(["render", "-o"])
        .arg(dir.join("plan.svg"))
        .arg(dir.join("c.holo"))
        .output()
        .expect("runs");
    assert!(out.status.success(), "{}", stderr(&out));
    let svg = std::fs::read_to_string(dir.join("plan.svg")).expect("svg");
    roxmltree::Document::parse(&svg).expect("the SVG is well-formed XML");
    assert!(!svg.contains('\u{1b}'));
}

/// One framed message of the language server protocol.
fn frame(body: &str) -> String {
    format!("Content-Length: {}\r\n\r\n{body}", body.len())
}

/// Reads one framed message.
fn read_message(reader: &mut impl std::io::BufRead) -> serde_json::Value {
    let mut length = 0;
    loop {
        let mut line = String::new();
        assert!(reader.read_line(&mut line).expect("reads") > 0, "the server ended");
        let line = line.trim_end();
        if line.is_empty() {
            break;
        }
        if let Some(n) = line.strip_prefix("Content-Length: ") {
            length = n.parse().expect("a length");
        }
    }
    let mut body = vec![0; length];
    reader.read_exact(&mut body).expect("a body");
    serde_json::from_slice(&body).expect("json")
}

#[test]
fn the_language_server_skips_bad_frames() {
    let mut child = holoc()
        .arg("lsp")
        .stdin(Stdio::piped())
        .stdout(Stdio::piped())
        .stderr(Stdio::piped())
        .spawn()
        .expect("starts");
    let mut input = child.stdin.take().expect("stdin");
    let mut output = std::io::BufReader::new(child.stdout.take().expect("stdout"));
    let mut send = |text: &str| input.write_all(text.as_bytes()).expect("writes");
    send(&frame(r#"{"jsonrpc":"2.0","id":1,"method":"initialize","params":{"capabilities":{}}}"#));
    let init = read_message(&mut output);
    assert_eq!(init["id"], 1, "{init}");
    send(&frame(r#"{"jsonrpc":"2.0","method":"initialized","params":{}}"#));
    // Garbage (answered with JSON-RPC's parse error), a request that is not one (answered), a
    // huge length (refused, its body skipped).
    send(&frame("{this is not json"));
    let answer = read_message(&mut output);
    assert_eq!(answer["id"], serde_json::Value::Null, "{answer}");
    assert_eq!(answer["error"]["code"], -32700, "{answer}");
    send(&frame(r#"{"jsonrpc":"2.0","id":2,"method":7}"#));
    let answer = read_message(&mut output);
    assert_eq!(answer["id"], 2, "{answer}");
    assert!(answer["error"]["code"].is_number(), "{answer}");
    // The server still answers after them.
    send(&frame(r#"{"jsonrpc":"2.0","id":3,"method":"shutdown"}"#));
    let answer = read_message(&mut output);
    assert_eq!(answer["id"], 3, "{answer}");
    send("Content-Length: 100000000000\r\n\r\n");
    // The skipped body would be 100 GB; the server is still reading it, so end the input
    // here and check the process ends cleanly instead of aborting in an allocation.
    drop(input);
    let status = child.wait().expect("ends");
    assert!(status.code().is_some(), "ended by a signal: {status:?}");
    let mut err = String::new();
    child.stderr.take().expect("stderr").read_to_string(&mut err).expect("reads");
    assert!(err.contains("answered a parse error: a message that is not JSON:"), "{err}");
    assert!(err.contains("skipped a message that is not JSON-RPC"), "{err}");
    assert!(err.contains("over the limit"), "{err}");
    let _ = output.fill_buf();
}

#[test]
fn a_feature_array_whose_shape_overflows_is_refused_not_read_past_its_end() {
    use holoc::resolve::objathor::fixture::{write_fixture, FixtureOptions, FIXTURE_ASSETS};
    use holoc::resolve::objathor::pickle::{write, NumpyModules, Value};
    let dir = scratch("overflow-shape");
    let root = write_fixture(&dir, FixtureOptions::default()).expect("the fixture");
    let uids: Vec<String> = FIXTURE_ASSETS.iter().map(|a| a.uid.to_string()).collect();
    let n = uids.len();
    // `n × 2^62 × 8` float16 elements: the product wraps to zero bytes in 64 bits, which the
    // empty data then matches.
    for (shape, protocol) in [(vec![n, 0], 2), (vec![n, 1 << 62, 8], 5), (vec![n, 1 << 62, 8], 4)] {
        let clip = write(
            &[
                ("uids", Value::Strings(uids.clone())),
                ("img_features", Value::F16 { shape: shape.clone(), bits: Vec::new() }),
            ],
            protocol,
            NumpyModules::Core,
        );
        std::fs::write(root.join("features").join("clip_features.pkl"), &clip).expect("write");
        for args in [
            &["check", "tests/objathor/cat_room.holo", "--format", "short"][..],
            &["build", "tests/objathor/cat_room.holo", "-q", "-o", "-"][..],
            &["assets", "search", "cat tower", "--objathor-scoring", "lexical"][..],
        ] {
            let out = holoc().args(args).arg("--objathor").arg(&root).output().expect("runs");
            no_abort(&out);
            assert_ne!(out.status.code(), Some(101), "{args:?} {shape:?}: {}", stderr(&out));
            assert!(stderr(&out).contains("W0405"), "{args:?} {shape:?}: {}", stderr(&out));
        }
    }
}

/// Runs a command with stdin closed, killing it (and failing) when it runs past `seconds`.
fn bounded(mut cmd: Command, what: &str, seconds: u64) -> Output {
    let mut child = cmd
        .stdin(Stdio::null())
        .stdout(Stdio::piped())
        .stderr(Stdio::piped())
        .spawn()
        .expect("holoc starts");
    let deadline = std::time::Instant::now() + std::time::Duration::from_secs(seconds);
    // The pipes are drained on threads, so a chatty child never blocks on a full pipe.
    let mut out_pipe = child.stdout.take().expect("piped");
    let mut err_pipe = child.stderr.take().expect("piped");
    let out_thread = std::thread::spawn(move || {
        let mut v = Vec::new();
        let _ = out_pipe.read_to_end(&mut v);
        v
    });
    let err_thread = std::thread::spawn(move || {
        let mut v = Vec::new();
        let _ = err_pipe.read_to_end(&mut v);
        v
    });
    let status = loop {
        if let Some(status) = child.try_wait().expect("wait") {
            break status;
        }
        if std::time::Instant::now() > deadline {
            let _ = child.kill();
            let _ = child.wait();
            panic!("{what}: still running after {seconds} s");
        }
        std::thread::sleep(std::time::Duration::from_millis(20));
    };
    Output {
        status,
        stdout: out_thread.join().expect("stdout"),
        stderr: err_thread.join().expect("stderr"),
    }
}

/// Every command, with every path it reads in turn replaced by a named pipe, `/dev/zero`, a
/// link to itself and a file over the 32 MiB bound: each ends at once with a diagnostic
/// (exit 1 or 2), never waits for a writer, never reads without end, never panics.
#[test]
fn every_command_refuses_pipes_devices_link_loops_and_oversize_files() {
    let dir = scratch("walk");
    let fifo = dir.join("fifo.json");
    if !mkfifo(&fifo) || !Path::new("/dev/zero").exists() {
        common::skip(
            "every_command_refuses_pipes_devices_link_loops_and_oversize_files",
            "no FIFO",
        );
        return;
    }
    let looped = dir.join("loop.json");
    std::os::unix::fs::symlink(&looped, &looped).expect("a link to itself");
    let big = dir.join("big.json");
    std::fs::File::create(&big).expect("create").set_len(33 * 1024 * 1024).expect("sparse");
    let house = dir.join("house.json");
    let out = holoc().args(["build", "examples/bedroom.holo", "-q", "-o"]).arg(&house).output();
    assert!(out.expect("runs").status.success());
    let tests = dir.join("tests");
    std::fs::create_dir_all(&tests).expect("folder");
    std::fs::copy("examples/bedroom.holo", tests.join("bedroom.holo")).expect("copy");
    let h = house.to_str().expect("utf-8");
    let o = dir.join("out");
    let o = o.to_str().expect("utf-8");
    let (glb, html, svg, holo) =
        (format!("{o}.glb"), format!("{o}.html"), format!("{o}.svg"), format!("{o}.holo"));
    let t = tests.to_str().expect("utf-8");
    let commands: Vec<Vec<&str>> = vec![
        vec!["check", "@"],
        vec!["fmt", "@"],
        vec!["import", "@"],
        vec!["validate", "@"],
        vec!["build", "@", "-o", &holo],
        vec!["render", "@", "-o", &svg],
        vec!["repair", "@", "-o", &holo],
        vec!["export", "@", "-o", &glb],
        vec!["view", "@", "-o", &html],
        vec!["view", h, "--report", "@", "-o", &html],
        vec!["diff", "@", h],
        vec!["diff", h, "@"],
        vec!["diff", h, h, "--report", "@", "--report", "@"],
        vec!["assets", "search", "chair", "--catalog", "@"],
        vec!["build", "examples/bedroom.holo", "-q", "-o", &holo, "--catalog", "@"],
        vec!["batch", "-q", "@", "-o", o],
        vec!["test", "--review", "--answers", "@", t],
    ];
    let zero = PathBuf::from("/dev/zero");
    for hostile in [&fifo, &zero, &looped, &big] {
        let p = hostile.to_str().expect("utf-8");
        for args in &commands {
            let args: Vec<&str> = args.iter().map(|a| if *a == "@" { p } else { a }).collect();
            let mut cmd = holoc();
            cmd.args(&args).env("NO_COLOR", "1");
            let what = format!("holoc {}", args.join(" "));
            let out = bounded(cmd, &what, 120);
            no_abort(&out);
            assert!(
                matches!(out.status.code(), Some(1 | 2)),
                "{what}: {:?}\n{}",
                out.status,
                stderr(&out)
            );
            assert!(!stderr(&out).is_empty(), "{what}: says nothing");
        }
    }
}

#[test]
fn bless_writes_only_inside_the_folder_it_was_given() {
    use std::os::unix::fs::symlink;
    let dir = scratch("bless");
    let tests = dir.join("tests");
    std::fs::create_dir_all(&tests).expect("folder");
    std::fs::copy("examples/bedroom.holo", tests.join("bedroom.holo")).expect("copy");
    let precious = dir.join("bashrc");
    std::fs::write(&precious, "precious\n").expect("write");
    let golden = tests.join("bedroom.house.json");
    let report = tests.join("bedroom.report.json");
    let bless = |extra: &[&str]| {
        let mut cmd = holoc();
        cmd.args(["test", "--bless"]).args(extra).arg(&tests);
        bounded(cmd, "holoc test --bless", 120)
    };
    // A golden that links outside, a dangling one, a report that links outside.
    symlink(&precious, &golden).expect("link");
    let out = bless(&[]);
    assert_eq!(out.status.code(), Some(2), "{}", stderr(&out));
    assert!(stderr(&out).contains("error[E0009]"), "{}", stderr(&out));
    assert_eq!(std::fs::read_to_string(&precious).expect("there"), "precious\n");
    std::fs::remove_file(&golden).expect("unlink");
    let created = dir.join("created.json");
    symlink(&created, &golden).expect("link");
    let out = bless(&[]);
    assert_eq!(out.status.code(), Some(2), "{}", stderr(&out));
    assert!(!created.exists(), "a dangling link's target was created");
    std::fs::remove_file(&golden).expect("unlink");
    symlink(&precious, &report).expect("link");
    let out = bless(&["--reports"]);
    assert_eq!(out.status.code(), Some(2), "{}", stderr(&out));
    assert_eq!(std::fs::read_to_string(&precious).expect("there"), "precious\n");
    std::fs::remove_file(&report).expect("unlink");
    // A folder on the way that links outside.
    let sub = tests.join("sub");
    let elsewhere = dir.join("elsewhere");
    std::fs::create_dir_all(&elsewhere).expect("folder");
    std::fs::copy("examples/bedroom.holo", elsewhere.join("bedroom.holo")).expect("copy");
    symlink(&elsewhere, &sub).expect("link");
    // A scene that links outside, and two links to the folder itself.
    symlink(elsewhere.join("bedroom.holo"), tests.join("linked.holo")).expect("link");
    symlink(".", tests.join("a")).expect("link");
    symlink(".", tests.join("b")).expect("link");
    let out = bless(&[]);
    assert_eq!(out.status.code(), Some(1), "{}", stderr(&out));
    let err = stderr(&out);
    assert!(err.contains("not testing") && err.contains("linked.holo"), "{err}");
    let text = String::from_utf8_lossy(&out.stdout).into_owned();
    assert!(text.contains("running 1 scene test"), "the folder is searched once: {text}");
    assert!(golden.is_file() && !golden.is_symlink(), "the golden inside is written");
    assert_eq!(std::fs::read_dir(&elsewhere).expect("there").count(), 1, "nothing written outside");
    // `holoc.toml` whose goldens climb out or are absolute, or a goldens folder that is a link.
    for goldens in ["../out", "/tmp/holoc-goldens", "g"] {
        let project = scratch(&format!("bless-toml-{}", goldens.len()));
        std::fs::copy("examples/bedroom.holo", project.join("bedroom.holo")).expect("copy");
        std::fs::write(project.join("holoc.toml"), format!("[test]\ngoldens = \"{goldens}\"\n"))
            .expect("write");
        symlink(&elsewhere, project.join("g")).expect("link");
        let mut cmd = holoc();
        cmd.args(["test", "--bless"]).current_dir(&project);
        let out = bounded(cmd, "holoc test --bless (holoc.toml)", 120);
        assert_eq!(out.status.code(), Some(2), "{goldens}: {}", stderr(&out));
        assert!(stderr(&out).contains("E0009"), "{goldens}: {}", stderr(&out));
        assert!(!project.parent().expect("parent").join("out").exists());
        assert!(!Path::new("/tmp/holoc-goldens").exists());
        assert_eq!(std::fs::read_dir(&elsewhere).expect("there").count(), 1);
    }
}

#[test]
fn diff_and_test_escape_control_characters_and_diff_reads_stdin_once() {
    let dir = scratch("diff-escape");
    let house = dir.join("a.json");
    let out = holoc().args(["build", "examples/bedroom.holo", "-q", "-o"]).arg(&house).output();
    assert!(out.expect("runs").status.success());
    let text = std::fs::read_to_string(&house).expect("house");
    let value: serde_json::Value = serde_json::from_str(&text).expect("json");
    let asset = value["objects"][0]["assetId"].as_str().expect("an asset").to_string();
    let hostile = text.replacen(&format!("\"{asset}\""), "\"bed\\u001b]0;pwned\\u0007\"", 1);
    assert_ne!(hostile, text);
    std::fs::write(dir.join("b.json"), &hostile).expect("write");
    let out = holoc().arg("diff").arg(&house).arg(dir.join("b.json")).output().expect("runs");
    assert_eq!(out.status.code(), Some(1), "{}", stderr(&out));
    let shown = String::from_utf8_lossy(&out.stdout);
    assert!(shown.contains("\\u{1b}]0;pwned"), "{shown}");
    assert!(!shown.contains('\u{1b}') && !shown.contains('\u{7}'), "{shown:?}");
    // Standard input on one side (a house or a scene), never on both.
    let mut child = holoc()
        .args(["diff", "-"])
        .arg(dir.join("b.json"))
        .stdin(Stdio::piped())
        .stdout(Stdio::piped())
        .spawn()
        .expect("runs");
    child.stdin.take().expect("piped").write_all(text.as_bytes()).expect("write");
    let out = child.wait_with_output().expect("ends");
    assert_eq!(out.status.code(), Some(1));
    let mut child = holoc()
        .args(["diff", "examples/bedroom.holo", "-"])
        .stdin(Stdio::piped())
        .stdout(Stdio::piped())
        .spawn()
        .expect("runs");
    let scene = std::fs::read("examples/bedroom.holo").expect("scene");
    child.stdin.take().expect("piped").write_all(&scene).expect("write");
    let out = child.wait_with_output().expect("ends");
    assert_eq!(out.status.code(), Some(0), "a scene against itself");
    let out = holoc().args(["diff", "-", "-"]).stdin(Stdio::null()).output().expect("runs");
    assert_eq!(out.status.code(), Some(2));
    assert!(stderr(&out).contains("only one of the two sides"), "{}", stderr(&out));
    // A coordinate `validate` refuses is refused by diff too, never printed as `NaN m²`.
    let absurd = text.replacen("\"x\": 0.0", "\"x\": 1e308", 1);
    assert_ne!(absurd, text, "the house has a zero x");
    std::fs::write(dir.join("c.json"), &absurd).expect("write");
    let out = holoc().arg("diff").arg(&house).arg(dir.join("c.json")).output().expect("runs");
    assert_eq!(out.status.code(), Some(2), "{}", stderr(&out));
    assert!(stderr(&out).contains("largest holoc reads"), "{}", stderr(&out));
    assert!(!String::from_utf8_lossy(&out.stdout).contains("NaN"));
    // `holoc test`: a scene whose name holds an escape, and a golden that differs.
    let tests = dir.join("tests");
    std::fs::create_dir_all(&tests).expect("folder");
    let name = "bed\u{1b}]0;pwned\u{7}";
    std::fs::copy("examples/bedroom.holo", tests.join(format!("{name}.holo"))).expect("copy");
    std::fs::write(tests.join(format!("{name}.house.json")), &hostile).expect("write");
    let out = holoc().arg("test").arg(&tests).output().expect("runs");
    assert_eq!(out.status.code(), Some(1), "{}", stderr(&out));
    let shown = String::from_utf8_lossy(&out.stdout);
    assert!(!shown.contains('\u{1b}') && !shown.contains('\u{7}'), "{shown:?}");
    let answers = dir.join("answers");
    std::fs::write(&answers, "n\n").expect("write");
    let out = holoc()
        .args(["test", "--review", "--answers"])
        .arg(&answers)
        .arg(&tests)
        .output()
        .expect("runs");
    let all = format!("{}{}", String::from_utf8_lossy(&out.stdout), stderr(&out));
    assert!(!all.contains('\u{1b}') && !all.contains('\u{7}'), "{all:?}");
}

#[test]
fn a_label_cannot_comment_out_or_close_the_viewer_script() {
    let dir = scratch("viewer-label");
    let house = dir.join("h.json");
    let out = holoc().args(["build", "examples/bedroom.holo", "-q", "-o"]).arg(&house).output();
    assert!(out.expect("runs").status.success());
    // An object's id (a label of the page) that opens a comment and a script.
    let mut value: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(&house).expect("house")).expect("json");
    value["objects"][0]["id"] = "bed <!--<script> </script> \u{2028}".into();
    std::fs::write(&house, value.to_string()).expect("write");
    let out = holoc().arg("view").arg(&house).arg("-o").arg(dir.join("v.html")).output();
    assert!(out.expect("runs").status.success());
    let page = std::fs::read_to_string(dir.join("v.html")).expect("page");
    let start = page.find("<script id=\"holoc-data\" type=\"application/json\">").expect("data");
    let body = &page[start + 48..];
    let end = body.find("</script>").expect("closed");
    let data = &body[..end];
    for bad in ["<", ">", "&", "\u{2028}"] {
        assert!(!data.contains(bad), "{bad:?} in the data block");
    }
    let value: serde_json::Value = serde_json::from_str(data).expect("the block is JSON");
    assert!(value.to_string().contains("<!--<script>"), "the text reads back the same");
    assert_eq!(page.matches("<script").count(), 3, "no element opened by the data");
}

#[test]
fn a_killed_write_leaves_no_temporary_file_a_later_run_keeps() {
    let dir = scratch("stale-tmp");
    // Not in canonical form, so that `fmt --write` writes.
    let text = std::fs::read_to_string("examples/bedroom.holo").expect("example");
    std::fs::write(dir.join("s.holo"), format!("\n\n\n{text}")).expect("write");
    // What `kill -9` during `fmt --write` leaves: a temporary file of a process that is gone
    // (pid 0 never names a user process), beside one that is not holoc's.
    let stale = dir.join(".holoc-0-abcdef.tmp");
    let other = dir.join(".tmpabcdef");
    std::fs::write(&stale, "half").expect("write");
    std::fs::write(&other, "someone else's").expect("write");
    let out = holoc().args(["fmt", "--write"]).arg(dir.join("s.holo")).output().expect("runs");
    assert!(out.status.success(), "{}", stderr(&out));
    assert!(!stale.exists() || !cfg!(target_os = "linux"), "the stale temporary file is removed");
    assert!(other.exists(), "a file holoc did not make is left alone");
    let names: Vec<String> = std::fs::read_dir(&dir)
        .expect("there")
        .filter_map(|e| e.ok()?.file_name().into_string().ok())
        .filter(|n| n.starts_with(".holoc-"))
        .collect();
    assert!(names.is_empty(), "{names:?}");
}

#[test]
fn objathor_annotations_that_are_a_pipe_or_too_large_say_so() {
    use holoc::resolve::objathor::fixture::{write_fixture, FixtureOptions};
    let dir = scratch("objathor-files");
    let root = write_fixture(&dir, FixtureOptions::default()).expect("the fixture");
    let annotations = root.join("annotations.json.gz");
    std::fs::remove_file(&annotations).expect("remove");
    if !mkfifo(&annotations) {
        common::skip("objathor_annotations_that_are_a_pipe_or_too_large_say_so", "no mkfifo");
        return;
    }
    let mut cmd = holoc();
    cmd.args(["check", "examples/bedroom.holo", "--objathor"]).arg(&root);
    let out = bounded(cmd, "holoc check --objathor (FIFO annotations)", 60);
    assert!(matches!(out.status.code(), Some(1 | 2)), "{}", stderr(&out));
    assert!(stderr(&out).contains("it is a named pipe"), "{}", stderr(&out));
    std::fs::remove_file(&annotations).expect("remove");
    std::fs::File::create(&annotations)
        .expect("create")
        .set_len(513 * 1024 * 1024)
        .expect("sparse");
    let mut cmd = holoc();
    cmd.args(["check", "examples/bedroom.holo", "--objathor"]).arg(&root);
    let out = bounded(cmd, "holoc check --objathor (oversize annotations)", 120);
    assert!(matches!(out.status.code(), Some(1 | 2)), "{}", stderr(&out));
    let err = stderr_unwrapped(&out);
    assert!(err.contains("larger than 512 MiB") && err.contains("--objathor"), "{err}");
    assert!(!err.contains("--catalog"), "{err}");
}

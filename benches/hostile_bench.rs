//! Time and peak memory of `holoc check`, `build`, `validate` and `lsp` on inputs 10× and 100×
//! the largest example and on the hostile shapes of `tests/hostile.rs` (deep nesting, rooms that
//! all overlap, a crowded house, a very long name, the largest input holoc reads); and of
//! `check`, `build`, `repair` and `fmt --check` on every shape that repeats one thing (rooms on
//! one square, in a row, in a column; objects, windows, corners of one room; doors), each at
//! 32 MiB and at the most holoc reads (`parse::MAX_TOKENS`), with their CPU seconds.
//!
//! Run by hand with `cargo bench --bench hostile_bench`; it prints a table (seconds and peak
//! resident memory of each run, from `/usr/bin/time` when it is there) that
//! `book/src/design/robustness.md` records. The targets: every stage near-linear in the input,
//! and no input of 32 MiB or less over 10 s or 1 GB.

#![allow(clippy::print_stdout, reason = "the benchmark prints its table")]

use std::fmt::Write as _;
use std::io::{BufRead as _, Read as _, Write as _};
use std::path::{Path, PathBuf};
use std::process::{Command, Stdio};
use std::time::{Duration, Instant};

/// The classroom example repeated `n` times: rooms in a row, each with its door to the one
/// before (the first to the outside).
fn classrooms(n: usize) -> String {
    let example = std::fs::read_to_string("examples/classroom.holo").expect("the example");
    let start = example.find("room classroom").expect("the room");
    let end = example.find("\ndoor exterior").expect("the door");
    let room = &example[start..end];
    let mut text = String::from("scene \"classrooms\" {\n  wall height 3 m\n  seed 21\n}\n\n");
    for i in 0..n {
        let x = 7 * i;
        let copy = room
            .replacen("room classroom \"classroom\"", &format!("room c{i} \"classroom {i}\""), 1)
            .replacen(
                "corners in m (0, 0) (0, 8) (7, 8) (7, 0)",
                &format!("corners in m ({x}, 0) ({x}, 8) ({}, 8) ({}, 0)", x + 7, x + 7),
                1,
            )
            .replacen("window east", "window north", 1);
        text.push_str(&copy);
        text.push('\n');
    }
    text.push_str("door exterior -- c0 : doorway single\n");
    for i in 1..n {
        let _ = writeln!(text, "door c{} -- c{i} : doorway single", i - 1);
    }
    text
}

/// `n` rooms on the same square.
fn overlapping(n: usize) -> String {
    let mut text = String::new();
    for i in 0..n {
        let _ =
            writeln!(text, "room r{i} \"r\" {{\n  corners in m (0, 0) (0, 4) (4, 4) (4, 0)\n}}");
    }
    text.push_str("door exterior -- r0 : doorway single\n");
    text
}

/// A shape of input: the text before the items, one item (numbered), the text after them.
type Shape = (&'static str, &'static str, fn(usize) -> String, &'static str);

/// The shapes that repeat one thing until the file is as large as holoc reads: rooms on one
/// square, in a row along x, in a column along z; objects, windows or corners in one room;
/// doors between two rooms.
fn shapes() -> Vec<Shape> {
    const SQUARE: &str = "room a \"a\" {\n  corners in m (0, 0) (0, 4) (4, 4) (4, 0)\n";
    vec![
        (
            "overlapping rooms",
            "",
            |i| format!("room r{i} \"r\" {{\n  corners in m (0, 0) (0, 4) (4, 4) (4, 0)\n}}\n"),
            "door exterior -- r0 : doorway single\n",
        ),
        (
            "rooms in a row",
            "",
            |i| {
                let (a, b) = (4 * i, 4 * i + 4);
                format!("room r{i} \"r\" {{\n  corners in m ({a}, 0) ({a}, 4) ({b}, 4) ({b}, 0)\n}}\n")
            },
            "door exterior -- r0 : doorway single\n",
        ),
        (
            "rooms in a column",
            "",
            |i| {
                let (a, b) = (4 * i, 4 * i + 4);
                format!("room r{i} \"r\" {{\n  corners in m (0, {a}) (0, {b}) (4, {b}) (4, {a})\n}}\n")
            },
            "door exterior -- r0 : doorway single\n",
        ),
        (
            "objects in one room",
            SQUARE,
            |i| format!("  object o{i} \"chair\" {{\n    size 40 cm x 40 cm x 80 cm\n  }}\n"),
            "}\ndoor exterior -- a : doorway single\n",
        ),
        (
            "windows in one room",
            SQUARE,
            |_| "  window east fixed 10 cm x 10 cm, count 1, sill 50 cm\n".to_owned(),
            "}\ndoor exterior -- a : doorway single\n",
        ),
        (
            "doors between two rooms",
            "room a \"a\" {\n  corners in m (0, 0) (0, 4) (4, 4) (4, 0)\n}\nroom b \"b\" {\n  corners in m (4, 0) (4, 4) (8, 4) (8, 0)\n}\ndoor exterior -- a : doorway single\n",
            |_| "door a -- b : doorway single\n".to_owned(),
            "",
        ),
        ("corners of one room", "room a \"a\" {\n  corners in m ", |_| "(0, 0) ".to_owned(), "\n}\n"),
    ]
}

/// The shape's items, as many as fit in `bytes`.
fn fill(shape: &Shape, bytes: usize) -> String {
    let (_, head, item, tail) = shape;
    let mut text = String::from(*head);
    for i in 0.. {
        let next = item(i);
        if text.len() + next.len() + tail.len() > bytes {
            break;
        }
        text.push_str(&next);
    }
    text.push_str(tail);
    text
}

/// The shape's items, as many as holoc reads (at most `parse::MAX_TOKENS` tokens in all).
fn largest_read(shape: &Shape) -> String {
    let (_, head, item, tail) = shape;
    let budget = holoc::parse::MAX_TOKENS
        - holoc::parse::count_tokens(head)
        - holoc::parse::count_tokens(tail);
    let mut text = String::from(*head);
    let mut used = 0;
    for i in 0.. {
        let next = item(i);
        let tokens = holoc::parse::count_tokens(&next);
        if used + tokens > budget {
            break;
        }
        used += tokens;
        text.push_str(&next);
    }
    text.push_str(tail);
    text
}

/// Braces nested `n` deep inside a room.
fn nested(n: usize) -> String {
    format!(
        "room a \"a\" {{\n  corners in m (0, 0) (0, 4) (4, 4) (4, 0)\n  {}{}\n}}\n",
        "{".repeat(n),
        "}".repeat(n)
    )
}

/// A reference to an object whose name is `n` characters long.
fn long_name(n: usize) -> String {
    let name = "x".repeat(n);
    format!(
        "room a \"a\" {{\n  corners in m (0, 0) (0, 4) (4, 4) (4, 0)\n  object t \"table\" {{ near {name} }}\n}}\ndoor exterior -- a : doorway single\n"
    )
}

/// About `bytes` of comment lines after the classroom: the largest input holoc reads.
fn padded(bytes: usize) -> String {
    let mut text = classrooms(1);
    let line = "// a comment line that fills the file with bytes and nothing else\n";
    while text.len() + line.len() < bytes {
        text.push_str(line);
    }
    text
}

/// The house of the bedroom example with its bed copied `n` times on the same spot.
fn crowded_house(holoc: &Path, dir: &Path, n: usize) -> String {
    let out =
        Command::new(holoc).args(["build", "examples/bedroom.holo", "-q", "-o", "-"]).output();
    let out = out.expect("holoc builds");
    let mut house: serde_json::Value = serde_json::from_slice(&out.stdout).expect("json");
    let objects = house["objects"].as_array_mut().expect("objects");
    let bed = objects
        .iter()
        .find(|o| o["assetId"].as_str().is_some_and(|a| a.starts_with("Bed")))
        .cloned()
        .expect("a bed");
    for k in 0..n {
        let mut copy = bed.clone();
        copy["id"] = serde_json::json!(format!("copy-{k}"));
        copy["children"] = serde_json::json!([]);
        objects.push(copy);
    }
    let _ = dir;
    serde_json::to_string(&house).expect("prints")
}

/// Seconds, CPU seconds (user and system) and peak resident memory (MB) of one command, the
/// last two when `/usr/bin/time` is there.
fn measure(
    args: &[&std::ffi::OsStr],
    holoc: &Path,
) -> (f64, Option<f64>, Option<f64>, Option<i32>) {
    let time = Path::new("/usr/bin/time");
    let started = Instant::now();
    let out = if time.exists() {
        Command::new(time).args(["-f", "%U %S %M"]).arg(holoc).args(args).output()
    } else {
        Command::new(holoc).args(args).output()
    }
    .expect("runs");
    let seconds = started.elapsed().as_secs_f64();
    let err = String::from_utf8_lossy(&out.stderr);
    let figures: Vec<f64> = err
        .lines()
        .last()
        .map(|l| l.split_whitespace().filter_map(|w| w.parse().ok()).collect())
        .unwrap_or_default();
    let (cpu, peak) = match figures[..] {
        [user, system, kb] if time.exists() => (Some(user + system), Some(kb / 1024.0)),
        _ => (None, None),
    };
    (seconds, cpu, peak, out.status.code())
}

/// Seconds from opening `text` in `holoc lsp` to its first diagnostics, and the peak memory
/// of the server (from `/proc`, read just before it is told to exit).
fn lsp(holoc: &Path, text: &str) -> (f64, Option<f64>) {
    let mut child = Command::new(holoc)
        .arg("lsp")
        .stdin(Stdio::piped())
        .stdout(Stdio::piped())
        .stderr(Stdio::null())
        .spawn()
        .expect("starts");
    let mut input = child.stdin.take().expect("stdin");
    let mut output = std::io::BufReader::new(child.stdout.take().expect("stdout"));
    let mut send = |value: serde_json::Value| {
        let body = value.to_string();
        input.write_all(format!("Content-Length: {}\r\n\r\n{body}", body.len()).as_bytes())
    };
    let mut read = || -> serde_json::Value {
        let mut length = 0;
        loop {
            let mut line = String::new();
            if output.read_line(&mut line).unwrap_or(0) == 0 {
                return serde_json::Value::Null;
            }
            if line.trim_end().is_empty() {
                break;
            }
            if let Some(n) = line.trim_end().strip_prefix("Content-Length: ") {
                length = n.parse().unwrap_or(0);
            }
        }
        let mut body = vec![0; length];
        let _ = output.read_exact(&mut body);
        serde_json::from_slice(&body).unwrap_or_default()
    };
    let _ = send(
        serde_json::json!({"jsonrpc": "2.0", "id": 1, "method": "initialize", "params": {"capabilities": {}}}),
    );
    let _ = read();
    let _ = send(serde_json::json!({"jsonrpc": "2.0", "method": "initialized", "params": {}}));
    let started = Instant::now();
    let _ = send(
        serde_json::json!({"jsonrpc": "2.0", "method": "textDocument/didOpen", "params": {"textDocument": {"uri": "file:///bench/scene.holo", "languageId": "holo", "version": 1, "text": text}}}),
    );
    loop {
        let message = read();
        if message.is_null() || message["method"] == "textDocument/publishDiagnostics" {
            break;
        }
    }
    let seconds = started.elapsed().as_secs_f64();
    let peak = std::fs::read_to_string(format!("/proc/{}/status", child.id())).ok().and_then(|s| {
        s.lines()
            .find_map(|l| l.strip_prefix("VmHWM:"))
            .and_then(|v| v.trim().trim_end_matches("kB").trim().parse::<f64>().ok())
            .map(|kb| kb / 1024.0)
    });
    let _ = send(serde_json::json!({"jsonrpc": "2.0", "id": 2, "method": "shutdown"}));
    let _ = send(serde_json::json!({"jsonrpc": "2.0", "method": "exit"}));
    drop(input);
    let deadline = Instant::now() + Duration::from_secs(30);
    while Instant::now() < deadline {
        if child.try_wait().ok().flatten().is_some() {
            break;
        }
        std::thread::sleep(Duration::from_millis(20));
    }
    let _ = child.kill();
    let _ = child.wait();
    (seconds, peak)
}

/// The uid of synthetic asset `i` (32 hex digits).
fn synthetic_uid(i: usize) -> String {
    format!("{:032x}", (i as u128).wrapping_mul(0x9e37_79b9_7f4a_7c15_f39c_c060_5ced_c835))
}

/// One annotation entry, as objathor writes them (the shape of `fixture::write_synthetic`'s).
fn annotation_entry(i: usize) -> String {
    const NOUNS: [&str; 8] = ["sofa", "chair", "lamp", "table", "shelf", "plant", "rug", "desk"];
    let uid = synthetic_uid(i);
    let noun = NOUNS[i % NOUNS.len()];
    let kind = i % 4;
    serde_json::json!({
        "annotations": {
            "uid": uid, "category": noun,
            "description": format!("a wooden {noun} number {i}"),
            "onFloor": kind == 0, "onWall": kind == 1, "onObject": kind == 2, "onCeiling": kind == 3,
            "license_info": {"license": "by", "uri": format!("https://api.sketchfab.com/v3/models/user{}", i % 997),
                "creator_username": format!("user{}", i % 997), "creator_display_name": "USER",
                "creator_profile_url": "https://sketchfab.com/user"},
        },
        "thor_metadata": {"assetMetadata": {"boundingBox": {"x": 0.5 + (i % 7) as f64 * 0.1, "y": 0.8, "z": 0.4}}},
    })
    .to_string()
}

/// Writes `<dir>/annotations.json`: entries (as many as `bytes` holds) or only the first `n`.
/// Returns the entries written and the file's size.
fn write_annotations(dir: &Path, bytes: u64, n: Option<usize>) -> (usize, u64) {
    let file = std::fs::File::create(dir.join("annotations.json")).expect("annotations");
    let mut out = std::io::BufWriter::new(file);
    let mut written = 1u64;
    out.write_all(b"{").expect("write");
    let mut i = 0;
    loop {
        if n.is_some_and(|n| i >= n) {
            break;
        }
        let entry = format!(
            "{}\"{}\":{}",
            if i == 0 { "" } else { "," },
            synthetic_uid(i),
            annotation_entry(i)
        );
        if written + entry.len() as u64 + 2 > bytes {
            break;
        }
        out.write_all(entry.as_bytes()).expect("write");
        written += entry.len() as u64;
        i += 1;
    }
    out.write_all(b"}\n").expect("write");
    out.flush().expect("flush");
    (i, written + 2)
}

/// Writes `<dir>/features/clip_features.pkl`: a numpy pickle (protocol 5) of `uids` and
/// `img_features` of 3 views × 768 float16 per asset, with as many assets as `bytes` holds,
/// streamed to disk (the array is never in memory). Returns the assets and the file's size.
fn write_features(dir: &Path, bytes: u64) -> (usize, u64) {
    use holoc::resolve::objathor::pickle::{f32_to_f16, write, NumpyModules, Value};
    const ROW: u64 = 3 * 768 * 2;
    // The pickle with a 16-byte marker for the array's data: everything but the data is
    // written by holoc's own writer, the data's length patched in.
    let marker: Vec<u16> = vec![0x1234, 0x5678, 0x9abc, 0x0ef0, 0x1357, 0x2468, 0x0ace, 0x0bdf];
    let marker_bytes: Vec<u8> = marker.iter().flat_map(|b| b.to_le_bytes()).collect();
    let pickle = |n: usize| {
        let uids = (0..n).map(synthetic_uid).collect();
        write(
            &[
                ("uids", Value::Strings(uids)),
                ("img_features", Value::F16 { shape: vec![n, 3, 768], bits: marker.clone() }),
            ],
            5,
            NumpyModules::Core,
        )
    };
    // A uid costs its string in the pickle besides its row.
    let per_asset = ROW + pickle(1).len() as u64 - pickle(0).len() as u64;
    let mut n = (bytes / per_asset) as usize;
    let (head, tail) = loop {
        let out = pickle(n);
        let at = out.windows(16).position(|w| w == marker_bytes).expect("the marker");
        let total = out.len() as u64 - 16 + n as u64 * ROW;
        if total <= bytes {
            let mut head = out[..at].to_vec();
            let len_at = head.len() - 8;
            head[len_at..].copy_from_slice(&(n as u64 * ROW).to_le_bytes());
            break (head, out[at + 16..].to_vec());
        }
        n -= 1 + ((total - bytes) / ROW) as usize;
    };
    std::fs::create_dir_all(dir.join("features")).expect("features");
    let file = std::fs::File::create(dir.join("features").join("clip_features.pkl")).expect("pkl");
    let mut out = std::io::BufWriter::with_capacity(1 << 20, file);
    out.write_all(&head).expect("write");
    // 64 KiB of small float16 values, repeated.
    let chunk: Vec<u8> = (0..32_768u32)
        .flat_map(|k| {
            f32_to_f16((k.wrapping_mul(2_654_435_761) % 1201) as f32 / 10_000.0 - 0.06)
                .to_le_bytes()
        })
        .collect();
    let mut left = n as u64 * ROW;
    while left > 0 {
        let take = left.min(chunk.len() as u64) as usize;
        out.write_all(&chunk[..take]).expect("write");
        left -= take as u64;
    }
    out.write_all(&tail).expect("write");
    out.flush().expect("flush");
    let size =
        std::fs::metadata(dir.join("features").join("clip_features.pkl")).map_or(0, |m| m.len());
    (n, size)
}

/// The readers of the largest legal inputs of `--objathor` and `--catalog`: annotations of 512
/// MiB (the most a catalog holds, `resolve::catalog::MAX_CATALOG_BYTES`), as a folder's and as
/// a user catalog, and a feature file of 4 GiB
/// (`resolve::objathor::MAX_FEATURES_BYTES`), each read by `build` of the cat studio from the
/// folder's files (`--objathor-no-index`, features scoring). The folders are written under
/// `target/hostile-readers` and removed after (they take 4.5 GB of disk). Each runs with
/// `holoc`, or with every binary `HOLOC_BINS` names (comma-separated paths; to compare builds).
fn readers(holoc: &Path) {
    let bins: Vec<PathBuf> = match std::env::var("HOLOC_BINS") {
        Ok(list) => list.split(',').filter(|p| !p.is_empty()).map(PathBuf::from).collect(),
        Err(_) => vec![holoc.to_path_buf()],
    };
    let label = |bin: &Path| {
        if bins.len() > 1 {
            format!(" [{}]", bin.file_name().map(|f| f.to_string_lossy()).unwrap_or_default())
        } else {
            String::new()
        }
    };
    let base = std::env::current_dir().expect("a folder").join("target").join("hostile-readers");
    let _ = std::fs::remove_dir_all(&base);
    let row = |name: &str,
               bytes: u64,
               command: &str,
               s: f64,
               cpu: Option<f64>,
               peak: Option<f64>,
               code: Option<i32>| {
        let cpu = cpu.map_or("–".to_string(), |c| format!("{c:.2}"));
        let peak = peak.map_or("–".to_string(), |p| format!("{p:.0}"));
        let code = code.map_or("signal".to_string(), |c| c.to_string());
        println!("| {name} | {bytes} | {command} | {s:.2} | {cpu} | {peak} | {code} |");
    };
    let out = base.join("house.json");
    let build = |dir: &Path| -> Vec<std::ffi::OsString> {
        vec![
            "build".into(),
            "examples/cat_studio.holo".into(),
            "--objathor".into(),
            dir.into(),
            "--objathor-no-index".into(),
            "--objathor-scoring".into(),
            "features".into(),
            "-q".into(),
            "-o".into(),
            out.clone().into(),
        ]
    };
    // Annotations just under the bound, and just over it (refused: E0403).
    for (what, bytes) in [
        ("annotations, 512 MiB", 512 * 1024 * 1024 - 4096),
        ("annotations over 512 MiB", 512 * 1024 * 1024 + 4096),
    ] {
        let dir = base.join("annotations");
        std::fs::create_dir_all(&dir).expect("scratch");
        let (n, size) = write_annotations(&dir, bytes, None);
        let args = build(&dir);
        let args: Vec<&std::ffi::OsStr> = args.iter().map(std::ffi::OsString::as_os_str).collect();
        for bin in &bins {
            let (s, cpu, peak, code) = measure(&args, bin);
            let name = format!("{what} ({n} entries){}", label(bin));
            row(&name, size, "build --objathor", s, cpu, peak, code);
        }
        let _ = std::fs::remove_dir_all(&dir);
    }
    // The same annotations given as a user catalog (`--catalog`), just under the bound.
    {
        let dir = base.join("catalog");
        std::fs::create_dir_all(&dir).expect("scratch");
        let (n, size) = write_annotations(&dir, 512 * 1024 * 1024 - 4096, None);
        let file = dir.join("annotations.json");
        let args: Vec<&std::ffi::OsStr> = vec![
            "build".as_ref(),
            "examples/cat_studio.holo".as_ref(),
            "--catalog".as_ref(),
            file.as_os_str(),
            "-q".as_ref(),
            "-o".as_ref(),
            out.as_os_str(),
        ];
        for bin in &bins {
            let (s, cpu, peak, code) = measure(&args, bin);
            let name = format!("user catalog, 512 MiB ({n} entries){}", label(bin));
            row(&name, size, "build --catalog", s, cpu, peak, code);
        }
        let _ = std::fs::remove_dir_all(&dir);
    }
    // A feature file just under 4 GiB, with 1,000 annotations among its uids.
    let dir = base.join("features");
    std::fs::create_dir_all(&dir).expect("scratch");
    write_annotations(&dir, u64::MAX, Some(1000));
    let (n, size) = write_features(&dir, holoc::resolve::objathor::MAX_FEATURES_BYTES - 4096);
    let args = build(&dir);
    let args: Vec<&std::ffi::OsStr> = args.iter().map(std::ffi::OsString::as_os_str).collect();
    for bin in &bins {
        let (s, cpu, peak, code) = measure(&args, bin);
        let name = format!("clip features, 4 GiB ({n} assets){}", label(bin));
        row(&name, size, "build --objathor", s, cpu, peak, code);
    }
    // The same folder with its index: written (the rows copied into it), then read.
    let with_index: Vec<&std::ffi::OsStr> =
        args.iter().copied().filter(|a| *a != "--objathor-no-index").collect();
    for bin in &bins {
        let _ = std::fs::remove_dir_all(dir.join(".holoc-index"));
        for what in ["build --objathor (writes its index)", "build --objathor (reads its index)"] {
            let (s, cpu, peak, code) = measure(&with_index, bin);
            let name = format!("clip features, 4 GiB ({n} assets){}", label(bin));
            row(&name, size, what, s, cpu, peak, code);
        }
    }
    let _ = std::fs::remove_dir_all(&dir);
    // The largest house `validate`, `export` and `diff` read: just under 32 MiB (the input
    // bound) of beds on one spot.
    std::fs::create_dir_all(&base).expect("scratch");
    let house = base.join("largest.json");
    let mut n = 2000;
    let text = loop {
        let text = crowded_house(holoc, &base, n);
        if text.len() > 31 * 1024 * 1024 {
            break text;
        }
        n = n * 31 * 1024 * 1024 / text.len().max(1) + 100;
    };
    std::fs::write(&house, &text).expect("write");
    let glb = base.join("largest.glb");
    for bin in &bins {
        for (command, args) in [
            (
                "validate",
                vec!["validate".as_ref(), "--format".as_ref(), "short".as_ref(), house.as_os_str()],
            ),
            ("export", vec!["export".as_ref(), house.as_os_str(), "-o".as_ref(), glb.as_os_str()]),
            ("diff (against itself)", vec!["diff".as_ref(), house.as_os_str(), house.as_os_str()]),
        ] {
            let (s, cpu, peak, code) = measure(&args, bin);
            let name = format!("house with {n} beds on one spot{}", label(bin));
            row(&name, text.len() as u64, command, s, cpu, peak, code);
        }
    }
    let _ = std::fs::remove_dir_all(&base);
}

fn main() {
    // `cargo bench` passes `--bench`; a filter argument is not supported.
    let holoc = PathBuf::from(env!("CARGO_BIN_EXE_holoc"));
    // `HOLOC_HOSTILE_ROWS=readers` runs only the readers of the largest legal inputs.
    let only = std::env::var("HOLOC_HOSTILE_ROWS").ok();
    if only.as_deref() == Some("readers") {
        println!("| input | bytes | command | seconds | CPU seconds | peak MB | exit |");
        println!("|---|---:|---|---:|---:|---:|---:|");
        readers(&holoc);
        return;
    }
    let dir = std::env::temp_dir().join(format!("holoc-hostile-bench-{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).expect("scratch");
    let cases: Vec<(&str, String, bool)> = vec![
        ("classroom ×1", classrooms(1), true),
        ("classroom ×10", classrooms(10), true),
        ("classroom ×100", classrooms(100), true),
        ("nesting 4,000", nested(4000), false),
        ("nesting 1,000,000", nested(1_000_000), false),
        ("2,000 overlapping rooms", overlapping(2000), false),
        ("20,000 overlapping rooms", overlapping(20_000), false),
        ("16,000-character name", long_name(16_000), false),
        ("1,000,000-character name", long_name(1_000_000), false),
        ("32 MiB (classroom + comments)", padded(32 * 1024 * 1024 - 1024), true),
    ];
    println!("| input | bytes | command | seconds | CPU seconds | peak MB | exit |");
    println!("|---|---:|---|---:|---:|---:|---:|");
    let row = |name: &str,
               bytes: usize,
               command: &str,
               s: f64,
               cpu: Option<f64>,
               peak: Option<f64>,
               code: Option<i32>| {
        let cpu = cpu.map_or("–".to_string(), |c| format!("{c:.2}"));
        let peak = peak.map_or("–".to_string(), |p| format!("{p:.0}"));
        let code = code.map_or("signal".to_string(), |c| c.to_string());
        println!("| {name} | {bytes} | {command} | {s:.2} | {cpu} | {peak} | {code} |");
    };
    for (name, text, build) in &cases {
        let file = dir.join("scene.holo");
        std::fs::write(&file, text).expect("write");
        let (s, cpu, peak, code) = measure(
            &["check".as_ref(), "--format".as_ref(), "short".as_ref(), file.as_os_str()],
            &holoc,
        );
        let _ = code;
        row(name, text.len(), "check", s, cpu, peak, code);
        if *build {
            let house = dir.join("house.json");
            let args = [
                "build".as_ref(),
                "-q".as_ref(),
                "-o".as_ref(),
                house.as_os_str(),
                file.as_os_str(),
            ];
            let (s, cpu, peak, code) = measure(&args, &holoc);
            row(name, text.len(), "build", s, cpu, peak, code);
            if house.exists() {
                let bytes = std::fs::metadata(&house).map_or(0, |m| m.len() as usize);
                let (s, cpu, peak, code) = measure(
                    &[
                        "validate".as_ref(),
                        "--format".as_ref(),
                        "short".as_ref(),
                        house.as_os_str(),
                    ],
                    &holoc,
                );
                row(&format!("{name}: its house"), bytes, "validate", s, cpu, peak, code);
                let _ = std::fs::remove_file(&house);
            }
        }
        let (s, peak) = lsp(&holoc, text);
        row(name, text.len(), "lsp open → diagnostics", s, None, peak, Some(0));
    }
    // Every shape at 32 MiB (refused before it is parsed: more than a million tokens) and at the
    // most holoc reads, through every command that reads a scene.
    for shape in shapes() {
        for (size, text) in [
            ("32 MiB", fill(&shape, 32 * 1024 * 1024 - 1024)),
            ("the most read", largest_read(&shape)),
        ] {
            let file = dir.join("shape.holo");
            std::fs::write(&file, &text).expect("write");
            let house = dir.join("shape.json");
            for (command, args) in [
                ("check", vec!["check".as_ref(), "--format".as_ref(), "short".as_ref()]),
                ("build", vec!["build".as_ref(), "-q".as_ref(), "-o".as_ref(), house.as_os_str()]),
                ("repair", vec!["repair".as_ref()]),
                ("fmt --check", vec!["fmt".as_ref(), "--check".as_ref()]),
            ] {
                let mut args: Vec<&std::ffi::OsStr> = args;
                args.push(file.as_os_str());
                let (s, cpu, peak, code) = measure(&args, &holoc);
                row(&format!("{} ({size})", shape.0), text.len(), command, s, cpu, peak, code);
            }
            let _ = std::fs::remove_file(&house);
        }
    }
    for n in [200, 2000] {
        let house = dir.join("crowded.json");
        let text = crowded_house(&holoc, &dir, n);
        std::fs::write(&house, &text).expect("write");
        let (s, cpu, peak, code) = measure(
            &["validate".as_ref(), "--format".as_ref(), "short".as_ref(), house.as_os_str()],
            &holoc,
        );
        row(
            &format!("house with {n} beds on one spot"),
            text.len(),
            "validate",
            s,
            cpu,
            peak,
            code,
        );
    }
    // The readers of `diff` and `view` on the largest house they read (just under 32 MiB of
    // beds on one spot), and on that house against one bed fewer.
    let house = dir.join("largest.json");
    let mut n = 2000;
    let text = loop {
        let text = crowded_house(&holoc, &dir, n);
        if text.len() > 30 * 1024 * 1024 {
            break text;
        }
        n = n * 30 * 1024 * 1024 / text.len().max(1) + 100;
    };
    std::fs::write(&house, &text).expect("write");
    let other = dir.join("other.json");
    std::fs::write(&other, crowded_house(&holoc, &dir, n - 1)).expect("write");
    let name = format!("house with {n} beds on one spot");
    for (command, args) in [
        ("diff (against itself)", vec!["diff".as_ref(), house.as_os_str(), house.as_os_str()]),
        ("diff (one bed fewer)", vec!["diff".as_ref(), house.as_os_str(), other.as_os_str()]),
        (
            "validate",
            vec!["validate".as_ref(), "--format".as_ref(), "short".as_ref(), house.as_os_str()],
        ),
    ] {
        let (s, cpu, peak, code) = measure(&args, &holoc);
        row(&name, text.len(), command, s, cpu, peak, code);
    }
    readers(&holoc);
    let _ = std::fs::remove_dir_all(&dir);
}

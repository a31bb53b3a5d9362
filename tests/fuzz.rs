//! In-process fuzzing of every reader holoc has: `.holo` (parse, check, format, every
//! diagnostic format), each answer stage of the importer, original Holodeck scenes, holoc
//! transcripts, house validation, user catalogs (JSON and gzip), the LLM client's reading of
//! a chat completion, objathor's annotations and feature pickles, and what `diff`, `export` and
//! `view` do with a house.
//!
//! A stable harness (no nightly toolchain here): inputs are the seeds of each target (the test
//! corpora, the examples, the transcripts and, when present, `../shared/data`) mutated by a
//! deterministic generator (byte flips, inserts of bytes and of the formats' own tokens,
//! deletions, duplications, splices of two seeds, long runs of brackets). Each input runs with
//! panics caught; an input that panics or takes over a second fails the target, and is written
//! to `target/fuzz-findings/<target>/` to be added to `tests/corpus/fuzz/<target>/`, whose
//! files are replayed by `fuzz_findings_stay_fixed` on every run.
//!
//! Mutations are cut to 64 KB with bracket runs of at most 200, except for the uncapped
//! targets (`holo`, `objects`, `validate`) and `deep-and-long`, whose seeds are built deep and
//! long on purpose (nesting far past every limit, 16,000-character names, 100,000-word lines,
//! 500 rooms that all overlap, 2,000 objects in one room): up to 4 MiB and runs of 20,000.
//!
//! `cargo test --test fuzz` runs a short smoke of every target (`HOLOC_FUZZ_ITERS`, default 200
//! inputs each). The campaign: `HOLOC_FUZZ_ITERS=1000000 cargo test --release --test fuzz --
//! --ignored --nocapture fuzz_campaign` (every target, a table of inputs, failures, slowest
//! input and peak memory); `HOLOC_FUZZ_TARGETS=feature-pickle,house-readers` runs only those.

#![allow(clippy::print_stdout, reason = "the campaign prints its table")]

mod common;

use holoc::diag::Diagnostic;
use holoc::import::{self, ImportContext, ImportOptions, Stage};
use holoc::source::SourceMap;
use std::io::Write as _;
use std::panic::AssertUnwindSafe;
use std::path::{Path, PathBuf};
use std::time::{Duration, Instant};

/// The longest a single input may take.
const HANG: Duration = Duration::from_secs(1);
/// Mutated inputs are cut to this length (bytes).
const MAX_INPUT: usize = 64 * 1024;
/// The longest run of one bracket a mutation inserts.
const MAX_RUN: usize = 200;
/// The same bounds for the uncapped targets (`holo`, `objects`, `validate`, `deep-and-long`):
/// inputs as large as holoc reads in a second, runs deeper than any nesting limit.
const UNCAPPED_INPUT: usize = 4 * 1024 * 1024;
const UNCAPPED_RUN: usize = 20_000;

/// One fuzz target: its name, its seed inputs and what it runs on one input.
struct Target {
    name: &'static str,
    seeds: Vec<Vec<u8>>,
    dictionary: &'static [&'static str],
    run: fn(&[u8]),
    /// The longest input (bytes) and bracket run of its mutations.
    max_input: usize,
    max_run: usize,
}

/// Renders diagnostics in every format (the human renderer has panicked before).
fn render_all(sources: &SourceMap, diagnostics: &[Diagnostic]) {
    let _ = holoc::diag::format::render_json(sources, diagnostics);
    let _ = holoc::diag::lsp::render_lsp(sources, diagnostics);
    let _ = holoc::diag::format::render_human(
        sources,
        diagnostics,
        holoc::diag::format::HumanOptions::default(),
    );
}

fn text(bytes: &[u8]) -> String {
    String::from_utf8_lossy(bytes).into_owned()
}

fn run_holo(bytes: &[u8]) {
    let text = text(bytes);
    let parsed = holoc::parse::parse_str(&text);
    let checked = holoc::check::check(&parsed.value);
    let printed = holoc::fmt::print(&parsed.value);
    let _ = holoc::check::dump(&checked.value);
    let mut sources = SourceMap::new();
    let file = sources.add("fuzz.holo", text);
    let mut all = parsed.diagnostics;
    all.extend(checked.diagnostics);
    render_all(&sources, &all);
    // The whole front end as `holoc check` runs it (plan and resolve included).
    let out = holoc::compile::check_file(&sources, file);
    render_all(&sources, &out.diagnostics);
    // Formatting is idempotent on what parses cleanly.
    if !all.iter().any(Diagnostic::is_error) {
        let again = holoc::fmt::print(&holoc::parse::parse_str(&printed).value);
        assert_eq!(again, printed, "formatting twice differs");
    }
}

fn run_stage(stage: Stage, bytes: &[u8]) {
    let mut sources = SourceMap::new();
    let id = sources.add("answer", text(bytes));
    let out = import::import_answer(stage, &sources, id, &ImportContext::new());
    let _ = holoc::fmt::print(&out.value.fragment);
    render_all(&sources, &out.diagnostics);
}

macro_rules! stage_runner {
    ($name:ident, $stage:expr) => {
        fn $name(bytes: &[u8]) {
            run_stage($stage, bytes);
        }
    };
}
stage_runner!(run_floor_plan, Stage::FloorPlan);
stage_runner!(run_wall_height, Stage::WallHeight);
stage_runner!(run_doorways, Stage::Doorways);
stage_runner!(run_windows, Stage::Windows);
stage_runner!(run_objects, Stage::Objects);
stage_runner!(run_objects_pipe, Stage::ObjectsPipe);
stage_runner!(run_floor_constraints, Stage::FloorConstraints);
stage_runner!(run_wall_constraints, Stage::WallConstraints);
stage_runner!(run_small_objects, Stage::SmallObjects);
stage_runner!(run_ceiling, Stage::Ceiling);
stage_runner!(run_absolute_layout, Stage::AbsoluteLayout);

fn run_original_scene(bytes: &[u8]) {
    let Ok(value) = serde_json::from_slice::<serde_json::Value>(bytes) else { return };
    let mut sources = SourceMap::new();
    let out = import::import_holodeck_scene(&value, &mut sources, &ImportOptions::default());
    let _ = holoc::fmt::print(&out.value);
    render_all(&sources, &out.diagnostics);
}

fn run_transcript(bytes: &[u8]) {
    let Ok(transcript) = serde_json::from_slice::<import::Transcript>(bytes) else { return };
    let mut sources = SourceMap::new();
    let out = import::import_transcript(&transcript, &mut sources, &ImportOptions::default());
    let _ = holoc::fmt::print(&out.value);
    render_all(&sources, &out.diagnostics);
}

fn run_validate(bytes: &[u8]) {
    let mut sources = SourceMap::new();
    let file = sources.add("house.json", text(bytes));
    let out = holoc::lower::validate::validate(
        &sources,
        file,
        holoc::resolve::structure::StructureCatalog::builtin(),
        embedded_catalog(),
    );
    render_all(&sources, &out.diagnostics);
}

fn run_catalog(bytes: &[u8]) {
    let mut sources = SourceMap::new();
    let out = holoc::resolve::Catalog::read_user_catalog("fuzz.json", bytes, &mut sources);
    render_all(&sources, &out.diagnostics);
}

fn run_annotations(bytes: &[u8]) {
    let mut sources = SourceMap::new();
    let (_, diagnostics) = holoc::resolve::objathor::read_annotations(bytes, &mut sources);
    render_all(&sources, &diagnostics);
}

fn run_features(bytes: &[u8]) {
    let _ = holoc::resolve::objathor::read_feature_bytes(bytes.to_vec());
}

fn run_index(bytes: &[u8]) {
    let _ = holoc::resolve::objathor::stored::read_index_bytes(bytes.to_vec());
}

/// The indexes holoc writes for fixture folders (float16, float32, image rows only, and one
/// with unusable entries, whose index keeps the annotations' text).
fn index_seeds() -> Vec<Vec<u8>> {
    use holoc::resolve::objathor::fixture::{write_fixture, FixtureOptions};
    use holoc::resolve::objathor::ObjathorOptions;
    let mut out = Vec::new();
    let Ok(dir) = tempfile::tempdir() else { return out };
    for (i, options) in [
        FixtureOptions { assets: false, ..FixtureOptions::default() },
        FixtureOptions { assets: false, float32: true, ..FixtureOptions::default() },
        FixtureOptions { assets: false, text_rows: false, ..FixtureOptions::default() },
    ]
    .into_iter()
    .enumerate()
    {
        let Ok(root) = write_fixture(&dir.path().join(i.to_string()), options) else { continue };
        if i == 2 {
            // An entry that is not an object: the index keeps the text its warning points into.
            let _ =
                std::fs::write(root.join("annotations.json.gz"), gzip(b"{\"a\": 1, \"b\": {}}"));
        }
        let options = ObjathorOptions { dir: root.clone(), ..ObjathorOptions::default() };
        let _ = holoc::resolve::Catalog::load_with(
            &[] as &[PathBuf],
            Some(&options),
            &mut SourceMap::new(),
        );
        out.extend(std::fs::read(root.join(".holoc-index").join("objathor.idx")));
    }
    out
}

/// A house through what `diff`, `export` and `view` do with it: the diff's view (against
/// itself and against the first seed house, rendered both ways), and, for a house `validate`
/// accepts, the glTF export and the viewer page.
fn run_house_readers(bytes: &[u8]) {
    use holoc::diff::{diff, HouseView, Options};
    static OTHER: std::sync::OnceLock<Option<HouseView>> = std::sync::OnceLock::new();
    let other = OTHER.get_or_init(|| {
        let first = house_seeds().into_iter().next()?;
        let value = serde_json::from_slice::<serde_json::Value>(&first).ok()?;
        HouseView::read(&value).ok()
    });
    let text = text(bytes);
    if let Ok(value) = serde_json::from_str::<serde_json::Value>(&text) {
        if let Ok(view) = HouseView::read(&value) {
            for d in [
                Some(diff(&view, &view, &Options::default())),
                other.as_ref().map(|o| diff(o, &view, &Options::default())),
            ]
            .into_iter()
            .flatten()
            {
                let _ = d.render();
                let _ = d.summary();
                let _ = holoc::diff::to_json(&d);
            }
        }
    }
    let mut sources = SourceMap::new();
    let file = sources.add("house.json", text.clone());
    let checked = holoc::lower::validate::validate(
        &sources,
        file,
        holoc::resolve::structure::StructureCatalog::builtin(),
        embedded_catalog(),
    );
    if checked.diagnostics.iter().any(Diagnostic::is_error) {
        return;
    }
    let Ok(house) = serde_json::from_str::<holoc::lower::thor::House>(&text) else { return };
    let options = holoc::export::ExportOptions::default();
    if let Ok(exported) = holoc::export::export(&house, embedded_catalog(), &options) {
        let glb = exported.to_glb();
        let _ = holoc::export::viewer::page(&house, &glb, None, "fuzz");
    }
}

/// The houses of the lower snapshots (without insta's header), then `{}`.
fn house_seeds() -> Vec<Vec<u8>> {
    let mut seeds = Vec::new();
    for snap in read_all(&files(Path::new("snapshots/lower"), &[".snap"])) {
        let snap = text(&snap);
        if let Some((_, house)) = snap.split_once("\n---\n") {
            seeds.push(house.as_bytes().to_vec());
        }
    }
    seeds.push(b"{}".to_vec());
    seeds
}

/// The objathor fixture's annotations (gzip and plain) and feature pickles (every protocol),
/// and the real numpy pickles of `tests/objathor/pickles`.
fn objathor_seeds() -> (Vec<Vec<u8>>, Vec<Vec<u8>>) {
    use holoc::resolve::objathor::fixture::{write_fixture, FixtureOptions};
    use holoc::resolve::objathor::pickle::NumpyModules;
    let mut annotations = Vec::new();
    let mut pickles = read_all(&files(Path::new("tests/objathor/pickles"), &[".pkl"]));
    let Ok(dir) = tempfile::tempdir() else { return (annotations, pickles) };
    for (protocol, modules) in [
        (2, NumpyModules::Core),
        (3, NumpyModules::Core),
        (4, NumpyModules::UnderscoreCore),
        (5, NumpyModules::UnderscoreCore),
    ] {
        let base = dir.path().join(format!("p{protocol}"));
        let options =
            FixtureOptions { protocol, modules, assets: false, ..FixtureOptions::default() };
        let Ok(root) = write_fixture(&base, options) else { continue };
        for name in ["clip_features.pkl", "sbert_features.pkl"] {
            pickles.extend(std::fs::read(root.join("features").join(name)));
        }
        if protocol == 2 {
            let gz = std::fs::read(root.join("annotations.json.gz")).unwrap_or_default();
            let mut plain = Vec::new();
            let _ =
                std::io::Read::read_to_end(&mut flate2::read::GzDecoder::new(&gz[..]), &mut plain);
            annotations.push(plain);
            annotations.push(gz);
        }
    }
    (annotations, pickles)
}

/// Tokens of the objathor index: its magic, sizes as varints and little-endian words.
const INDEX_WORDS: &[&str] = &[
    "HOLOCOBJ",
    "\u{1}\u{0}\u{0}\u{0}",
    "\u{ff}\u{ff}\u{ff}\u{ff}\u{f}",
    "\u{80}\u{80}\u{80}\u{80}\u{1}",
    "\u{0}\u{0}\u{0}\u{0}\u{0}\u{0}\u{0}\u{0}",
    "\u{ff}\u{ff}\u{ff}\u{ff}\u{ff}\u{ff}\u{ff}\u{7f}",
    "\u{2}",
    "\u{4}",
    "img_features",
    "text_features",
];

/// Tokens of numpy's pickles: opcodes, module names, dtype names, sizes.
const PICKLE_WORDS: &[&str] = &[
    "\u{80}\u{4}",
    "\u{95}",
    "}",
    "]",
    ")",
    "(",
    "t",
    "R",
    "b",
    "u",
    "e",
    ".",
    "N",
    "K\u{0}",
    "K\u{ff}",
    "J\u{ff}\u{ff}\u{ff}\u{7f}",
    "\u{8a}\u{8}",
    "\u{8c}\u{3}f2",
    "\u{94}",
    "\u{93}",
    "h\u{0}",
    "C\u{2}",
    "B",
    "\u{8e}",
    "\u{96}",
    "numpy",
    "numpy.core.multiarray",
    "_reconstruct",
    "_frombuffer",
    "dtype",
    "uids",
    "img_features",
    "text_features",
    ">",
    "<",
    "latin1",
];

fn run_completion(bytes: &[u8]) {
    let _ = holoc::generate::client::parse_completion(&text(bytes));
}

fn embedded_catalog() -> &'static holoc::resolve::Catalog {
    static CATALOG: std::sync::OnceLock<holoc::resolve::Catalog> = std::sync::OnceLock::new();
    CATALOG.get_or_init(holoc::resolve::Catalog::embedded)
}

/// Every file under `dir` (recursively) whose name ends with one of `ends`.
fn files(dir: &Path, ends: &[&str]) -> Vec<PathBuf> {
    let mut out = Vec::new();
    let Ok(entries) = std::fs::read_dir(dir) else { return out };
    let mut entries: Vec<_> = entries.filter_map(Result::ok).map(|e| e.path()).collect();
    entries.sort();
    for path in entries {
        if path.is_dir() {
            out.extend(files(&path, ends));
        } else if ends.iter().any(|e| path.to_string_lossy().ends_with(e)) {
            out.push(path);
        }
    }
    out
}

fn read_all(paths: &[PathBuf]) -> Vec<Vec<u8>> {
    paths.iter().filter_map(|p| std::fs::read(p).ok()).collect()
}

fn gzip(bytes: &[u8]) -> Vec<u8> {
    let mut enc = flate2::write::GzEncoder::new(Vec::new(), flate2::Compression::fast());
    enc.write_all(bytes).expect("in memory");
    enc.finish().expect("in memory")
}

const HOLO_WORDS: &[&str] = &[
    "room",
    "scene",
    "door",
    "object",
    "instance",
    "corners",
    "in m",
    "(0, 0)",
    "window",
    "{",
    "}",
    ";",
    "near",
    "edge",
    "middle",
    "above",
    "around",
    "face to",
    "count 9999",
    "exterior",
    "--",
    ":",
    "doorway single",
    "\"",
    "m",
    "cm",
    "deg",
    "-1e308",
    "NaN",
    "\n",
    "//",
    "wall height 2.7 m",
    "on top",
    "describe",
    "asset",
    "size 1 m x 1 m x 1 m",
];
const PIPE_WORDS: &[&str] = &[
    "|",
    "-0",
    "(",
    ")",
    "[",
    "]",
    ",",
    "near",
    "edge",
    "above",
    "\r",
    "\n",
    "x 1000000",
    "\"",
    "{",
    "}",
    ":",
    "1e400",
    "-0",
    "living room",
    "doorway",
    "single",
    "sliding",
];
const JSON_WORDS: &[&str] = &[
    "{",
    "}",
    "[",
    "]",
    ":",
    ",",
    "\"",
    "null",
    "true",
    "1e999",
    "-1",
    "\"id\"",
    "\"rooms\"",
    "\"objects\"",
    "\"floorPolygon\"",
    "\"x\"",
    "\"z\"",
    "\"assetId\"",
    "\"children\"",
    "\\u0000",
];

/// A small scene in the original system's format (the fields its importer reads).
const ORIGINAL_SCENE: &str = r#"{"query": "a bedroom", "wall_height": 2.7,
 "raw_floor_plan": "bedroom | oak | white | [(0, 0), (0, 4), (4, 4), (4, 0)]",
 "raw_doorway_plan": "exterior | bedroom | doorway | single",
 "raw_window_plan": "bedroom | west | slidingWindow | (120, 100) | 1 | 90",
 "object_selection_plan": {"bedroom": {"bed": {"description": "a double bed", "location": "floor", "size": [160, 200, 50], "quantity": 1, "variance_type": "same", "objects_on_top": [{"object_name": "pillow", "quantity": 2, "variance_type": "same"}]}}},
 "rooms": [{"id": "bedroom", "floorPolygon": [{"x": 0, "y": 0, "z": 0}, {"x": 0, "y": 0, "z": 4}, {"x": 4, "y": 0, "z": 4}, {"x": 4, "y": 0, "z": 0}]}],
 "objects": [{"id": "bed-0 (bedroom)", "assetId": "Bed_1", "position": {"x": 2, "y": 0.3, "z": 3}, "rotation": {"x": 0, "y": 180, "z": 0}}]}"#;

/// Inputs deep and long on purpose: nesting far past every limit (braces, `instance` blocks,
/// JSON), very long lines and names, many rooms that all overlap, a room of many objects.
fn hostile_seeds() -> Vec<Vec<u8>> {
    use std::fmt::Write as _;
    let room = "room a \"a\" {\n  corners in m (0, 0) (0, 4) (4, 4) (4, 0)\n";
    let mut seeds = Vec::new();
    for depth in [65, 1000, 100_000] {
        seeds.push(format!("{room}  {}{}\n}}\n", "{".repeat(depth), "}".repeat(depth)));
        let mut nested = format!("{room}  object t \"table\" ");
        nested.push_str(&"{ instance t-0 ".repeat(depth));
        nested.push_str(&"}".repeat(depth));
        nested.push_str("\n}\n");
        seeds.push(nested);
        // JSON answers and houses.
        seeds.push(format!("{}{}", "{\"a\": ".repeat(depth), "}".repeat(depth)));
        seeds.push(format!("{}{}", "[".repeat(depth), "]".repeat(depth)));
    }
    let name = "x".repeat(16_000);
    seeds.push(format!("{room}  object t \"table\" {{ near {name} }}\n}}\n"));
    seeds.push(format!("{room}  object t \"{name}\" {{ edge }}\n}}\n"));
    seeds.push(format!("{room}  // {}\n}}\n", "long line ".repeat(100_000)));
    let mut rooms = String::new();
    for i in 0..500 {
        let _ = writeln!(rooms, "room r{i} \"r\" {{ corners in m (0, 0) (0, 4) (4, 4) (4, 0) }}");
    }
    seeds.push(rooms);
    let mut objects = String::from(room);
    for i in 0..2000usize {
        let _ = writeln!(objects, "  object o{i} \"box\" {{ near o{} }}", i.saturating_sub(1));
    }
    objects.push_str("}\n");
    seeds.push(objects);
    seeds.into_iter().map(String::into_bytes).collect()
}

/// A hostile input through every reader it may reach: the scene readers, the objects answer
/// and validate.
fn run_hostile(bytes: &[u8]) {
    run_holo(bytes);
    if bytes.first().is_some_and(|b| matches!(b, b'{' | b'[')) {
        run_objects(bytes);
        run_validate(bytes);
    }
}

/// The targets, with their seeds from the repository (and `../shared/data` when present).
fn targets() -> Vec<Target> {
    let holo = {
        let mut paths = files(Path::new("examples"), &[".holo"]);
        paths.extend(files(Path::new("tests/corpus/parse"), &[".holo"]));
        paths.extend(files(Path::new("tests/corpus/check"), &[".holo"]));
        paths.extend(files(Path::new("tests/corpus/plan"), &[".holo"]));
        paths.extend(files(Path::new("tests/corpus/repair"), &[".holo"]));
        read_all(&paths)
    };
    let stage_seeds = |folder: &str| {
        let mut seeds = read_all(&files(&Path::new("tests/corpus/import").join(folder), &[""]));
        seeds.push(Vec::new());
        seeds
    };
    let shared_scenes = read_all(&files(Path::new("../shared/data/real-scenes"), &[".json"]));
    if shared_scenes.is_empty() {
        common::skip(
            "fuzz seeds from ../shared/data/real-scenes",
            "absent; the original-scene and validate targets start from the repository's seeds",
        );
    }
    let houses = [shared_scenes.clone(), house_seeds()].concat();
    let (annotations, pickles) = objathor_seeds();
    let transcripts = read_all(&files(Path::new("examples/transcripts"), &[".json"]));
    let catalogs = {
        let mut seeds = read_all(&files(Path::new("tests/catalog"), &[".json"]));
        seeds.push(br#"{"id": {"assetId": "id", "objectType": "Chair", "boundingBox": {"x": 0.5, "y": 1, "z": 0.5}}}"#.to_vec());
        seeds
    };
    let gz_catalogs: Vec<Vec<u8>> = catalogs.iter().map(|c| gzip(c)).collect();
    let completions = vec![
        br#"{"choices":[{"message":{"role":"assistant","content":"living room | oak | white | [(0, 0), (0, 4), (4, 4), (4, 0)]"}}],"usage":{"prompt_tokens":10,"completion_tokens":20}}"#.to_vec(),
        br#"{"error":{"message":"rate limited"}}"#.to_vec(),
    ];
    let t = |name, seeds: Vec<Vec<u8>>, dictionary, run| Target {
        name,
        seeds,
        dictionary,
        run,
        max_input: MAX_INPUT,
        max_run: MAX_RUN,
    };
    let uncapped =
        |target: Target| Target { max_input: UNCAPPED_INPUT, max_run: UNCAPPED_RUN, ..target };
    vec![
        uncapped(t("holo", holo, HOLO_WORDS, run_holo as fn(&[u8]))),
        uncapped(t("deep-and-long", hostile_seeds(), HOLO_WORDS, run_hostile)),
        t("floor-plan", stage_seeds("floor-plan"), PIPE_WORDS, run_floor_plan),
        t("wall-height", stage_seeds("wall-height"), PIPE_WORDS, run_wall_height),
        t("doorways", stage_seeds("doorways"), PIPE_WORDS, run_doorways),
        t("windows", stage_seeds("windows"), PIPE_WORDS, run_windows),
        uncapped(t("objects", stage_seeds("objects"), JSON_WORDS, run_objects)),
        t("objects-pipe", stage_seeds("objects-pipe"), PIPE_WORDS, run_objects_pipe),
        t("floor-constraints", stage_seeds("floor-constraints"), PIPE_WORDS, run_floor_constraints),
        t("wall-constraints", stage_seeds("wall-constraints"), PIPE_WORDS, run_wall_constraints),
        t("small-objects", stage_seeds("small-objects"), PIPE_WORDS, run_small_objects),
        t("ceiling", stage_seeds("ceiling"), PIPE_WORDS, run_ceiling),
        t("absolute-layout", stage_seeds("absolute-layout"), PIPE_WORDS, run_absolute_layout),
        t(
            "original-scene",
            [shared_scenes, vec![ORIGINAL_SCENE.as_bytes().to_vec()]].concat(),
            JSON_WORDS,
            run_original_scene,
        ),
        t("transcript", transcripts, JSON_WORDS, run_transcript),
        uncapped(t("validate", houses, JSON_WORDS, run_validate)),
        t("catalog-json", catalogs, JSON_WORDS, run_catalog),
        t("catalog-gzip", gz_catalogs, JSON_WORDS, run_catalog),
        t("completion", completions, JSON_WORDS, run_completion),
        t("objathor-annotations", annotations, JSON_WORDS, run_annotations),
        t("feature-pickle", pickles, PICKLE_WORDS, run_features),
        t("objathor-index", index_seeds(), INDEX_WORDS, run_index),
        t("house-readers", house_seeds(), JSON_WORDS, run_house_readers),
    ]
}

/// splitmix64: a small deterministic generator.
struct Rng(u64);

impl Rng {
    fn next(&mut self) -> u64 {
        self.0 = self.0.wrapping_add(0x9e37_79b9_7f4a_7c15);
        let mut z = self.0;
        z = (z ^ (z >> 30)).wrapping_mul(0xbf58_476d_1ce4_e5b9);
        z = (z ^ (z >> 27)).wrapping_mul(0x94d0_49bb_1331_11eb);
        z ^ (z >> 31)
    }
    fn below(&mut self, n: usize) -> usize {
        if n == 0 {
            0
        } else {
            (self.next() % n as u64) as usize
        }
    }
}

/// One mutated input from the seeds.
fn mutate(rng: &mut Rng, target: &Target) -> Vec<u8> {
    let (seeds, dictionary) = (&target.seeds, target.dictionary);
    let mut data = seeds[rng.below(seeds.len())].clone();
    if data.len() > target.max_input {
        let start = rng.below(data.len() - target.max_input);
        data = data[start..start + target.max_input].to_vec();
    }
    let rounds = 1 + rng.below(8);
    for _ in 0..rounds {
        let at = rng.below(data.len() + 1);
        match rng.below(9) {
            0 if !data.is_empty() => {
                let i = rng.below(data.len());
                data[i] ^= 1 << rng.below(8);
            }
            1 => data.insert(at, (rng.next() & 0xff) as u8),
            2 | 3 => {
                let word = dictionary[rng.below(dictionary.len())].as_bytes();
                data.splice(at..at, word.iter().copied());
            }
            4 if !data.is_empty() => {
                let len = 1 + rng.below(64.min(data.len() - at.min(data.len() - 1)));
                let end = (at + len).min(data.len());
                data.drain(at.min(end)..end);
            }
            5 if !data.is_empty() => {
                let start = rng.below(data.len());
                let end = (start + 1 + rng.below(256)).min(data.len());
                let chunk = data[start..end].to_vec();
                data.splice(at..at, chunk);
            }
            6 => {
                let other = &seeds[rng.below(seeds.len())];
                if !other.is_empty() {
                    let start = rng.below(other.len());
                    let end = (start + 1 + rng.below(512)).min(other.len());
                    data.splice(at..at, other[start..end].iter().copied());
                }
            }
            7 => {
                let c =
                    *[b'{', b'}', b'[', b'(', b'"', b'|', b'\r'].get(rng.below(7)).unwrap_or(&b'{');
                let n = 1 + rng.below(target.max_run);
                data.splice(at..at, std::iter::repeat_n(c, n));
            }
            _ => data.truncate(at),
        }
    }
    data.truncate(target.max_input);
    data
}

/// What a run of one target found.
#[derive(Default)]
struct Findings {
    inputs: u64,
    panics: Vec<(Vec<u8>, String)>,
    hangs: Vec<(Vec<u8>, Duration)>,
    slowest: Duration,
}

fn run_one(target: &Target, input: &[u8], found: &mut Findings) {
    let start = Instant::now();
    let result = std::panic::catch_unwind(AssertUnwindSafe(|| (target.run)(input)));
    let took = start.elapsed();
    found.inputs += 1;
    found.slowest = found.slowest.max(took);
    if let Err(payload) = result {
        let message = payload
            .downcast_ref::<String>()
            .cloned()
            .or_else(|| payload.downcast_ref::<&str>().map(|s| (*s).to_string()))
            .unwrap_or_default();
        found.panics.push((input.to_vec(), message));
    } else if took > HANG {
        found.hangs.push((input.to_vec(), took));
    }
}

fn fuzz(target: &Target, iterations: u64, seed: u64) -> Findings {
    let mut found = Findings::default();
    let mut rng =
        Rng(seed ^ target.name.bytes().fold(0u64, |h, b| h.wrapping_mul(31) ^ u64::from(b)));
    // Every seed as it is, then mutations.
    for s in &target.seeds {
        run_one(target, s, &mut found);
    }
    if target.seeds.is_empty() {
        return found;
    }
    for _ in 0..iterations {
        let input = mutate(&mut rng, target);
        run_one(target, &input, &mut found);
    }
    found
}

/// Keeps what was found where a person can add it to the regression corpus.
fn keep_findings(target: &Target, found: &Findings) {
    let dir = Path::new(env!("CARGO_TARGET_TMPDIR")).join("fuzz-findings").join(target.name);
    for (i, (input, _)) in found.panics.iter().enumerate() {
        let _ = std::fs::create_dir_all(&dir);
        let _ = std::fs::write(dir.join(format!("panic-{i}")), input);
    }
    for (i, (input, _)) in found.hangs.iter().enumerate() {
        let _ = std::fs::create_dir_all(&dir);
        let _ = std::fs::write(dir.join(format!("slow-{i}")), input);
    }
}

fn iterations(default: u64) -> u64 {
    std::env::var("HOLOC_FUZZ_ITERS").ok().and_then(|v| v.parse().ok()).unwrap_or(default)
}

fn quiet_panics<T>(f: impl FnOnce() -> T) -> T {
    let hook = std::panic::take_hook();
    std::panic::set_hook(Box::new(|_| {}));
    let out = f();
    std::panic::set_hook(hook);
    out
}

fn report(target: &Target, found: &Findings) -> String {
    let first = found.panics.first().map(|(input, m)| {
        format!(
            "first panic: {m}\ninput: {:?}",
            String::from_utf8_lossy(&input[..input.len().min(400)])
        )
    });
    let hang = found.hangs.first().map(|(input, t)| {
        format!("slow input ({t:?}): {:?}", String::from_utf8_lossy(&input[..input.len().min(400)]))
    });
    format!(
        "{}: {} inputs, {} panics, {} over {HANG:?}; {}{}",
        target.name,
        found.inputs,
        found.panics.len(),
        found.hangs.len(),
        first.unwrap_or_default(),
        hang.unwrap_or_default()
    )
}

/// A short run of every target: no panics, no input over a second.
#[test]
fn fuzz_smoke() {
    let n = iterations(200);
    let failures: Vec<String> = quiet_panics(|| {
        targets()
            .iter()
            // The deep-and-long target's inputs take seconds each on a loaded machine; the
            // campaign runs it, and `tests/hostile.rs` runs its shapes through the binary.
            .filter(|target| target.name != "deep-and-long")
            .filter_map(|target| {
                assert!(
                    !target.seeds.is_empty() || target.name == "original-scene",
                    "{}",
                    target.name
                );
                let found = fuzz(target, n, 0x686f_6c6f);
                keep_findings(target, &found);
                (!found.panics.is_empty() || !found.hangs.is_empty())
                    .then(|| report(target, &found))
            })
            .collect()
    });
    assert!(failures.is_empty(), "{}", failures.join("\n"));
}

/// Everything once found stays fixed: the files of `tests/corpus/fuzz/<target>/` run through
/// their target.
#[test]
fn fuzz_findings_stay_fixed() {
    let targets = targets();
    let mut count = 0;
    let failures: Vec<String> = quiet_panics(|| {
        let mut failures = Vec::new();
        for target in &targets {
            for path in files(&Path::new("tests/corpus/fuzz").join(target.name), &[""]) {
                let input = std::fs::read(&path).expect("readable");
                let mut found = Findings::default();
                run_one(target, &input, &mut found);
                count += 1;
                if !found.panics.is_empty() || !found.hangs.is_empty() {
                    failures.push(format!("{}: {}", path.display(), report(target, &found)));
                }
            }
        }
        failures
    });
    assert!(count > 0, "the regression corpus is empty");
    assert!(failures.is_empty(), "{}", failures.join("\n"));
}

/// The campaign (run by hand, in release): `HOLOC_FUZZ_ITERS` inputs per target, with a table
/// of inputs, panics, slow inputs, the slowest input and the peak memory of the process.
#[test]
#[ignore = "a long campaign; run by hand with HOLOC_FUZZ_ITERS"]
fn fuzz_campaign() {
    let n = iterations(1_000_000);
    let seed = std::env::var("HOLOC_FUZZ_SEED").ok().and_then(|v| v.parse().ok()).unwrap_or(1);
    println!("| target | seeds | inputs | panics | over 1 s | slowest ms | seconds |");
    println!("|---|---|---|---|---|---|---|");
    let mut failures = Vec::new();
    quiet_panics(|| {
        // `HOLOC_FUZZ_TARGETS=a,b` runs only those targets.
        let only: Option<Vec<String>> = std::env::var("HOLOC_FUZZ_TARGETS")
            .ok()
            .map(|v| v.split(',').map(|t| t.trim().to_string()).collect());
        let chosen = |t: &Target| only.as_ref().is_none_or(|o| o.iter().any(|n| n == t.name));
        for target in targets().iter().filter(|t| chosen(t)) {
            let start = Instant::now();
            let found = fuzz(target, n, seed);
            keep_findings(target, &found);
            println!(
                "| {} | {} | {} | {} | {} | {:.1} | {:.0} |",
                target.name,
                target.seeds.len(),
                found.inputs,
                found.panics.len(),
                found.hangs.len(),
                found.slowest.as_secs_f64() * 1000.0,
                start.elapsed().as_secs_f64()
            );
            if !found.panics.is_empty() || !found.hangs.is_empty() {
                failures.push(report(target, &found));
            }
        }
    });
    let peak = std::fs::read_to_string("/proc/self/status")
        .ok()
        .and_then(|s| s.lines().find(|l| l.starts_with("VmHWM")).map(str::to_string))
        .unwrap_or_default();
    println!("peak memory: {peak}");
    assert!(failures.is_empty(), "{}", failures.join("\n"));
}

#[test]
fn the_harness_is_deterministic() {
    let targets = targets();
    let target = &targets[1];
    let mut a = Rng(7);
    let mut b = Rng(7);
    for _ in 0..100 {
        assert_eq!(mutate(&mut a, target), mutate(&mut b, target));
    }
}

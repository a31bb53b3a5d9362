//! Properties of the language front end over the whole corpus and the examples:
//! formatting round-trips and is idempotent; no input makes the parser or checker panic; the
//! parser that reuses unchanged top-level items gives exactly what parsing at once gives; the
//! language server's incremental analysis gives exactly what a whole analysis gives.

use proptest::prelude::*;
use std::fmt::Write as _;
use std::path::PathBuf;

#[path = "support/user_scene.rs"]
mod user_scene;

fn holo_files() -> Vec<PathBuf> {
    let mut out = Vec::new();
    let mut stack = vec![PathBuf::from("tests/corpus"), PathBuf::from("examples")];
    while let Some(dir) = stack.pop() {
        let Ok(entries) = std::fs::read_dir(&dir) else { continue };
        for entry in entries.flatten() {
            let path = entry.path();
            if path.is_dir() {
                stack.push(path);
            } else if path.extension().is_some_and(|e| e == "holo") {
                out.push(path);
            }
        }
    }
    out.sort();
    out
}

#[test]
fn fmt_round_trips_and_is_idempotent() {
    let files = holo_files();
    assert!(files.len() > 20, "the corpus should have many files, found {}", files.len());
    for path in files {
        let text = std::fs::read_to_string(&path).expect("readable");
        let first = holoc::parse::parse_str(&text);
        if first.has_errors() {
            continue;
        }
        let printed = holoc::fmt::print(&first.value);
        let second = holoc::parse::parse_str(&printed);
        assert!(
            !second.has_errors(),
            "{}: the printed form does not parse:\n{printed}",
            path.display()
        );
        assert_eq!(
            first.value.shape(),
            second.value.shape(),
            "{}: parse → print → parse changed the tree",
            path.display()
        );
        assert_eq!(
            holoc::fmt::print(&second.value),
            printed,
            "{}: printing twice differs",
            path.display()
        );
    }
}

#[test]
fn examples_are_canonical() {
    for path in holo_files().into_iter().filter(|p| p.starts_with("examples")) {
        let text = std::fs::read_to_string(&path).expect("readable");
        let parsed = holoc::parse::parse_str(&text);
        assert_eq!(
            holoc::fmt::print(&parsed.value),
            text,
            "{} is not in canonical form",
            path.display()
        );
    }
}

/// Runs the front end on a text; the property is that it returns.
fn front_end(text: &str) {
    let parsed = holoc::parse::parse_str(text);
    let checked = holoc::check::check(&parsed.value);
    let _ = holoc::fmt::print(&parsed.value);
    let _ = holoc::check::dump(&checked.value);
    let mut sources = holoc::source::SourceMap::new();
    sources.add("fuzz.holo", text);
    let mut all = parsed.diagnostics;
    all.extend(checked.diagnostics);
    let _ = holoc::diag::format::render_json(&sources, &all);
    let _ = holoc::diag::lsp::render_lsp(&sources, &all);
    let _ = holoc::diag::format::render_human(
        &sources,
        &all,
        holoc::diag::format::HumanOptions::default(),
    );
}

/// The embedded catalog, loaded once.
fn catalog() -> &'static holoc::resolve::Catalog {
    static CATALOG: std::sync::OnceLock<holoc::resolve::Catalog> = std::sync::OnceLock::new();
    CATALOG.get_or_init(holoc::resolve::Catalog::embedded)
}

/// Analyses each version in turn with one incremental memo (as the language server does for
/// one document) and holds every result to a whole analysis of the same text; returns how
/// often the plan and asset resolution were reused.
fn incremental_equals_whole(
    versions: &[String],
) -> Result<holoc::lsp::incremental::Counts, TestCaseError> {
    let mut memo = holoc::lsp::incremental::Memo::default();
    for text in versions {
        let mut sources = holoc::source::SourceMap::new();
        let file = sources.add("t.holo", text.as_str());
        let incremental = holoc::lsp::incremental::analyse(&sources, file, catalog(), &mut memo);
        let whole =
            holoc::compile::analyse(&sources, file, catalog(), holoc::compile::CheckStage::Resolve);
        prop_assert_eq!(format!("{incremental:?}"), format!("{whole:?}"), "version:\n{}", text);
        // As the language server does when the document changes: the analysis goes back.
        memo.give_back(incremental, text);
    }
    Ok(memo.counts)
}

/// Replaces `cut` bytes at `at` (moved back onto character boundaries) with `insert`.
fn mutate(text: &str, at: usize, cut: usize, insert: &str) -> String {
    let mut at = at.min(text.len());
    while !text.is_char_boundary(at) {
        at -= 1;
    }
    let mut end = (at + cut).min(text.len());
    while !text.is_char_boundary(end) {
        end -= 1;
    }
    format!("{}{}{}", &text[..at], insert, &text[end..])
}

/// The versions a user typing makes of `text`: each edit `(nth, class, cut, insert)` cuts up
/// to `cut` characters and inserts `insert` after the `nth` quote (class 0), digit (1) or line
/// start (2).
fn typed_versions(text: String, edits: &[(usize, usize, usize, String)]) -> Vec<String> {
    let mut current = text;
    let mut versions = vec![current.clone()];
    for (nth, class, cut, insert) in edits {
        let bytes: &[u8] = match class {
            0 => b"\"",
            1 => b"0123456789",
            _ => b"\n",
        };
        let at = after_nth(&current, bytes, *nth);
        current = mutate(&current, at, *cut, insert);
        versions.push(current.clone());
    }
    versions
}

/// The byte just after the `nth` (modulo their number) occurrence of one of `bytes`, or 0.
fn after_nth(text: &str, bytes: &[u8], nth: usize) -> usize {
    let all: Vec<usize> =
        text.bytes().enumerate().filter(|(_, b)| bytes.contains(b)).map(|(i, _)| i + 1).collect();
    if all.is_empty() {
        0
    } else {
        all[nth % all.len()]
    }
}

#[test]
fn typing_in_a_valid_scene_reuses_the_plan_and_gives_the_whole_analysis() {
    // Typing into every description of the apartment, then into a corner: the plan runs once
    // for the descriptions, again for the corner.
    let text = std::fs::read_to_string("examples/apartment_1b1b.holo").expect("readable");
    let mut versions = vec![text.clone()];
    let mut current = text;
    for nth in 0..6 {
        let at = current.match_indices("describe \"").nth(nth).expect("a description").0 + 10;
        current = mutate(&current, at, 0, "x");
        versions.push(current.clone());
    }
    current = current.replacen("(5, 7) (5, 0)", "(5, 7.5) (5, 0)", 1);
    versions.push(current);
    let counts = incremental_equals_whole(&versions).expect("the same analyses");
    assert_eq!((counts.planned, counts.plans_reused), (2, 6), "{counts:?}");
}

/// A row of `rooms` rooms of 4 m × 4 m that ask for the same things (so that each avoids the
/// assets of the rooms before it, and a choice changed in one room changes the rooms after it),
/// with doors between them; some objects carry things on top, some rooms a ceiling light.
fn competing_rooms(rooms: usize) -> String {
    let things = [
        ("sofa", "grey fabric sofa", "200 cm x 90 cm x 80 cm"),
        ("table", "round oak dining table", "120 cm x 120 cm x 75 cm"),
        ("chair", "wooden chair", "45 cm x 50 cm x 90 cm"),
        ("bookshelf", "tall bookshelf", "90 cm x 30 cm x 190 cm"),
        ("plant", "potted fern", "40 cm x 40 cm x 90 cm"),
    ];
    let mut text = String::from("scene \"rooms that compete for assets\" {\n  seed 3\n}\n");
    for r in 0..rooms {
        let x = r * 4;
        let _ = write!(
            text,
            "\nroom r{r} \"room {r}\" {{\n  corners in m ({x}, 0) ({x}, 4) ({}, 4) ({}, 0)\n",
            x + 4,
            x + 4
        );
        for (k, (category, description, size)) in things.iter().enumerate() {
            let _ = write!(
                text,
                "  object o{k} \"{category}\" {{\n    describe \"{description}\"\n    size {size}\n    edge\n"
            );
            if k == 1 {
                text.push_str("    on top \"book\" x2 varied\n");
            }
            text.push_str("  }\n");
        }
        if r % 2 == 0 {
            text.push_str("  ceiling \"round ceiling light\"\n");
        }
        text.push_str("}\n");
    }
    for r in 0..rooms {
        let from = if r == 0 { "exterior".to_string() } else { format!("r{}", r - 1) };
        let _ = writeln!(text, "door {from} -- r{r} : doorway single");
    }
    text
}

#[test]
fn typing_in_one_room_resolves_that_room_and_keeps_the_others() {
    // Typing into the last room's first description resolves that room alone; typing into the
    // first room's resolves it and those whose answers about used assets changed.
    let text = competing_rooms(4);
    let mut versions = vec![text.clone()];
    let last = text.rfind("describe \"").expect("a description") + 10;
    versions.push(mutate(&text, last, 0, "x"));
    let counts = incremental_equals_whole(&versions).expect("the same analyses");
    assert_eq!((counts.rooms_resolved, counts.rooms_reused), (4 + 1, 3), "{counts:?}");
    // The checker, too, checks again that room alone.
    assert_eq!((counts.rooms_checked, counts.rooms_check_reused), (4 + 1, 3), "{counts:?}");
    let first = text.find("describe \"").expect("a description") + 10;
    let edited = mutate(&text, first, 0, "velvet ");
    let counts = incremental_equals_whole(&[text, edited]).expect("the same analyses");
    assert!(counts.rooms_reused < 4, "{counts:?}");
}

#[test]
fn typing_twice_in_one_room_chooses_again_only_the_group_typed_in() {
    // The first edit resolves the room and records its groups' choices; at the second, every
    // group but the one typed in is taken again, and the doors are not checked again.
    let text = competing_rooms(3);
    let at = text.rfind("describe \"").expect("a description") + 10;
    let once = mutate(&text, at, 0, "x");
    let twice = mutate(&once, at, 0, "y");
    let counts = incremental_equals_whole(&[text, once, twice]).expect("the same analyses");
    // Five groups in the last room: four kept at the second edit.
    assert_eq!(counts.groups_kept, 4, "{counts:?}");
    assert_eq!(counts.doors_kept, 2, "{counts:?}");
}

/// Tokens that make up plausible and implausible `.holo` text.
fn token() -> impl Strategy<Value = String> {
    prop_oneof![
        Just("room".to_string()),
        Just("scene".to_string()),
        Just("door".to_string()),
        Just("object".to_string()),
        Just("wall".to_string()),
        Just("corners".to_string()),
        Just("window".to_string()),
        Just("instance".to_string()),
        Just("near".to_string()),
        Just("in front of".to_string()),
        Just("edge".to_string()),
        Just("{".to_string()),
        Just("}".to_string()),
        Just("(".to_string()),
        Just(")".to_string()),
        Just("--".to_string()),
        Just(":".to_string()),
        Just(",".to_string()),
        Just(";".to_string()),
        Just("\n".to_string()),
        Just("\"".to_string()),
        Just("//".to_string()),
        Just("/*".to_string()),
        Just("x".to_string()),
        Just("m".to_string()),
        Just("cm".to_string()),
        Just("deg".to_string()),
        "[a-z_][a-z0-9_-]{0,8}",
        "-?[0-9]{1,4}(\\.[0-9]{1,3})?",
        "\"[^\"\\n]{0,12}\"",
        "\\PC{1,3}",
    ]
}

proptest! {
    #![proptest_config(ProptestConfig { cases: 2000, rng_seed: proptest::test_runner::RngSeed::Fixed(0x686f_6c6f), ..ProptestConfig::default() })]

    #[test]
    fn random_token_streams_never_panic(tokens in proptest::collection::vec(token(), 0..60)) {
        front_end(&tokens.join(" "));
    }

    #[test]
    fn arbitrary_text_never_panics(text in "\\PC{0,200}") {
        front_end(&text);
    }

    #[test]
    fn mutated_examples_never_panic(index in 0usize..64, at in 0usize..4000, cut in 0usize..40, insert in "\\PC{0,6}") {
        let files = holo_files();
        let path = &files[index % files.len()];
        let text = std::fs::read_to_string(path).expect("readable");
        let mut at = at.min(text.len());
        while !text.is_char_boundary(at) { at -= 1; }
        let mut end = (at + cut).min(text.len());
        while !text.is_char_boundary(end) { end -= 1; }
        let mutated = format!("{}{}{}", &text[..at], insert, &text[end..]);
        front_end(&mutated);
    }

    #[test]
    fn piecewise_parsing_equals_parsing_at_once(index in 0usize..64, at in 0usize..4000, cut in 0usize..40, insert in proptest::collection::vec(token(), 0..4), second in 0usize..4000) {
        let files = holo_files();
        let path = &files[index % files.len()];
        let text = std::fs::read_to_string(path).expect("readable");
        let mutate = |text: &str, at: usize, cut: usize, insert: &str| {
            let mut at = at.min(text.len());
            while !text.is_char_boundary(at) { at -= 1; }
            let mut end = (at + cut).min(text.len());
            while !text.is_char_boundary(end) { end -= 1; }
            format!("{}{}{}", &text[..at], insert, &text[end..])
        };
        let once = mutate(&text, at, cut, &insert.join(" "));
        let twice = mutate(&once, second, 1, "x");
        // One cache across the original, the edit and a second edit, as an editor uses it.
        let mut cache = holoc::parse::ParseCache::default();
        for version in [text.as_str(), once.as_str(), twice.as_str()] {
            let mut sources = holoc::source::SourceMap::new();
            let file = sources.add("t.holo", version);
            let piecewise = holoc::parse::parse_cached(&sources, file, &mut cache);
            let whole = holoc::parse::parse_whole(&sources, file);
            prop_assert_eq!(format!("{:?}", piecewise.value), format!("{:?}", whole.value));
            prop_assert_eq!(format!("{:?}", piecewise.diagnostics), format!("{:?}", whole.diagnostics));
        }
        // The tree edited in place through the same versions and back to the first, as the
        // language server makes it (each tree handed back for the next).
        let mut cache = holoc::parse::ParseCache::default();
        for version in [text.as_str(), once.as_str(), twice.as_str(), once.as_str(), text.as_str()] {
            let mut sources = holoc::source::SourceMap::new();
            let file = sources.add("t.holo", version);
            let edited = holoc::parse::parse_edited(&sources, file, &mut cache);
            let whole = holoc::parse::parse_whole(&sources, file);
            prop_assert_eq!(format!("{:?}", edited.value), format!("{:?}", whole.value));
            prop_assert_eq!(format!("{:?}", edited.diagnostics), format!("{:?}", whole.diagnostics));
            cache.give_back(edited.value, version);
        }
    }

    #[test]
    fn incremental_analysis_equals_whole_analysis(index in 0usize..64, edits in proptest::collection::vec((0usize..64, 0usize..3, 0usize..3, "[a-z0-9 ]{0,3}"), 1..5)) {
        // Edits after a quote, a digit or a line start of an example or corpus file: inside
        // descriptions, numbers (corners, sizes) and statements, as a user types.
        let files = holo_files();
        let path = &files[index % files.len()];
        let versions = typed_versions(std::fs::read_to_string(path).expect("readable"), &edits);
        incremental_equals_whole(&versions)?;
    }

    #[test]
    fn incremental_analysis_of_competing_rooms_equals_whole_analysis(rooms in 2usize..6, edits in proptest::collection::vec((0usize..40, 0usize..3, 0usize..3, "[a-z ]{0,4}"), 1..6)) {
        // Edits inside the descriptions, sizes and names of rooms that avoid each other's
        // assets: a choice changed in one room changes what the rooms after it read.
        let versions = typed_versions(competing_rooms(rooms), &edits);
        incremental_equals_whole(&versions)?;
    }

    #[test]
    fn incremental_analysis_through_lines_added_and_removed_equals_whole_analysis(rooms in 2usize..5, edits in proptest::collection::vec((0usize..200, 0usize..12), 1..8)) {
        // Whole lines put in or taken out, as a user adds objects, counts, relations (some to
        // names of no room, or of another room), rooms, doors and scene settings: rooms change
        // how many objects they have, names resolve elsewhere, rooms come and go.
        let snippets = [
            "  object extra \"chair\" {\n    near o0-0\n    edge\n  }\n",
            "    count 3\n",
            "    near zz-0\n",
            "    near o1-0\n",
            "    near extra-0\n",
            "  ceiling \"round ceiling light\"\n",
            "door r0 -- r1 : open\n",
            "scene \"again\" {\n  wall height 3 m\n}\n",
            "room extra \"extra\" {\n  corners in m (0, 4) (0, 8) (4, 8) (4, 4)\n}\n",
            "// a comment\n\n",
        ];
        let mut current = competing_rooms(rooms);
        let mut versions = vec![current.clone()];
        for (nth, kind) in edits {
            let at = after_nth(&current, b"\n", nth);
            current = match snippets.get(kind) {
                Some(snippet) => mutate(&current, at, 0, snippet),
                // Take the line out.
                None => {
                    let end = current[at..].find('\n').map_or(current.len(), |n| at + n + 1);
                    mutate(&current, at, end - at, "")
                }
            };
            versions.push(current.clone());
        }
        incremental_equals_whole(&versions)?;
    }

    #[test]
    fn a_room_edited_again_and_again_inside_its_body_parses_as_a_whole_and_analyses_the_same(rooms in 1usize..3, edits in proptest::collection::vec((0usize..400, 0usize..9, "[a-z0-9 ]{0,3}"), 1..10)) {
        // Keystrokes and lines inside the rooms' bodies, one after the other: from a room's
        // second edit on its statements are edited in place (the groups it begins and ends with
        // kept, those between parsed again), blank lines and comments included.
        let snippets = [
            "",
            "\n",
            "\n\n",
            "  // a comment\n",
            "  object extra \"chair\" {\n    near o0-0\n  }\n",
            "    near o1-0\n",
            "  }\n",
            "{",
        ];
        let mut current = competing_rooms(rooms);
        let mut versions = vec![current.clone()];
        for (nth, kind, typed) in edits {
            let at = after_nth(&current, b"\n\" ", nth);
            current = match snippets.get(kind) {
                Some(&"") => mutate(&current, at, 0, &typed),
                Some(snippet) => mutate(&current, at, 0, snippet),
                // Take the line out.
                None => {
                    let end = current[at..].find('\n').map_or(current.len(), |n| at + n + 1);
                    mutate(&current, at, end - at, "")
                }
            };
            versions.push(current.clone());
        }
        let mut cache = holoc::parse::ParseCache::default();
        for version in &versions {
            let mut sources = holoc::source::SourceMap::new();
            let file = sources.add("t.holo", version.as_str());
            let edited = holoc::parse::parse_edited(&sources, file, &mut cache);
            let whole = holoc::parse::parse_whole(&sources, file);
            prop_assert_eq!(format!("{:?}", edited.value), format!("{:?}", whole.value), "version:\n{}", version);
            prop_assert_eq!(format!("{:?}", edited.diagnostics), format!("{:?}", whole.diagnostics));
            cache.give_back(edited.value, version);
        }
        incremental_equals_whole(&versions)?;
    }

    #[test]
    fn piecewise_parsing_equals_parsing_at_once_on_token_streams(tokens in proptest::collection::vec(token(), 0..80)) {
        // Tokens joined by newlines half of the time, so that many lines start at column 0.
        let text: String = tokens.iter().enumerate().map(|(i, t)| if i % 2 == 0 { format!("{t}\n") } else { format!("{t} ") }).collect();
        let mut sources = holoc::source::SourceMap::new();
        let file = sources.add("t.holo", text.as_str());
        let piecewise = holoc::parse::parse(&sources, file);
        let whole = holoc::parse::parse_whole(&sources, file);
        prop_assert_eq!(format!("{:?}", piecewise.value), format!("{:?}", whole.value));
        prop_assert_eq!(format!("{:?}", piecewise.diagnostics), format!("{:?}", whole.diagnostics));
    }
}

/// [`incremental_equals_whole`] for large scenes: the analysis from scratch of each version
/// shares the asset rankings of the one before (a ranking depends on its query, the catalog
/// and the seed alone: the result is the same without them), and each version's diagnostics,
/// sorted as the language server publishes them, are compared first.
fn keystrokes_equal_checks_from_scratch(
    versions: &[String],
) -> Result<holoc::lsp::incremental::Counts, TestCaseError> {
    let mut memo = holoc::lsp::incremental::Memo::default();
    let mut ranks = holoc::resolve::RankCache::default();
    for text in versions {
        let mut sources = holoc::source::SourceMap::new();
        let file = sources.add("t.holo", text.as_str());
        let incremental = holoc::lsp::incremental::analyse(&sources, file, catalog(), &mut memo);
        let mut scratch = holoc::compile::AnalysisCache {
            parse: holoc::parse::ParseCache::default(),
            ranks: std::mem::take(&mut ranks),
        };
        let whole = holoc::compile::analyse_cached(
            &sources,
            file,
            catalog(),
            holoc::compile::CheckStage::Resolve,
            &mut scratch,
        );
        ranks = scratch.ranks;
        let sorted = |d: &[holoc::diag::Diagnostic]| {
            let mut d = d.to_vec();
            holoc::diag::sort(&mut d);
            format!("{d:?}")
        };
        prop_assert_eq!(sorted(&incremental.diagnostics), sorted(&whole.diagnostics));
        prop_assert_eq!(format!("{incremental:?}"), format!("{whole:?}"));
        memo.give_back(incremental, text);
    }
    Ok(memo.counts)
}

/// `typed` typed one character at a time after the `nth` quote of `text` (into a description
/// or a name, as a user types), then the edits of [`typed_versions`].
fn keystrokes(
    text: String,
    nth: usize,
    typed: &str,
    edits: &[(usize, usize, usize, String)],
) -> Vec<String> {
    let at = after_nth(&text, b"\"", nth);
    let mut versions = vec![text.clone()];
    let mut current = text;
    for (k, c) in typed.char_indices() {
        current = mutate(&current, at + k, 0, &c.to_string());
        versions.push(current.clone());
    }
    let mut rest = typed_versions(current, edits);
    rest.remove(0);
    versions.extend(rest);
    versions
}

#[test]
fn keystrokes_in_one_group_of_a_large_room_check_and_resolve_that_group_alone() {
    // The large room of the users' shape: from the second keystroke in a description on, the
    // group typed in is checked and chosen again alone; the result is a check from scratch's.
    let text = user_scene::user_scene(0, true);
    let at = text.match_indices("describe \"").nth(400).expect("a description").0 + 10;
    let mut versions = vec![text.clone()];
    let mut current = text;
    for (k, c) in "oak".chars().enumerate() {
        current = mutate(&current, at + k, 0, &c.to_string());
        versions.push(current.clone());
    }
    let counts = keystrokes_equal_checks_from_scratch(&versions).expect("the same analyses");
    // The first keystroke checks the room, the next two the group alone.
    assert_eq!((counts.rooms_checked, counts.groups_checked), (1 + 1, 2), "{counts:?}");
    // And every other group's choice is kept (937 groups in the room).
    assert_eq!(counts.groups_kept, 2 * 937, "{counts:?}");
}

proptest! {
    #![proptest_config(ProptestConfig { cases: 24, rng_seed: proptest::test_runner::RngSeed::Fixed(0x0053), ..ProptestConfig::default() })]

    #[test]
    fn keystrokes_in_the_large_users_room_give_the_diagnostics_of_a_check_from_scratch(nth in 0usize..4000, typed in "[a-z \"{}0-9]{1,4}", edits in proptest::collection::vec((0usize..20000, 0usize..3, 0usize..3, "[a-z0-9 \"}]{0,2}"), 0..4)) {
        // Keystrokes in one place of the 6,200-line room (a description, a name, a category),
        // then edits anywhere: quotes and braces typed too, which break the groups around.
        let versions = keystrokes(user_scene::user_scene(0, true), nth, &typed, &edits);
        keystrokes_equal_checks_from_scratch(&versions)?;
    }

    #[test]
    fn keystrokes_in_the_examples_give_the_diagnostics_of_a_check_from_scratch(index in 0usize..64, nth in 0usize..200, typed in "[a-z \"{}0-9]{1,4}", edits in proptest::collection::vec((0usize..400, 0usize..3, 0usize..3, "[a-z0-9 \"}]{0,2}"), 0..4)) {
        let files = holo_files();
        let path = &files[index % files.len()];
        let text = std::fs::read_to_string(path).expect("readable");
        let versions = keystrokes(text, nth, &typed, &edits);
        keystrokes_equal_checks_from_scratch(&versions)?;
    }
}

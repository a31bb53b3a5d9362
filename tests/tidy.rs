//! Tidiness of the project: the diagnostics catalogue is complete and each page's example
//! produces its code; every grammar rule is documented; every `holo` snippet of the book checks.

use holoc::diag::Code;
use holoc::source::SourceMap;
use std::collections::BTreeSet;
use std::path::{Path, PathBuf};

fn markdown_files(dir: &Path) -> Vec<PathBuf> {
    let mut out = Vec::new();
    let mut stack = vec![dir.to_path_buf()];
    while let Some(d) = stack.pop() {
        for entry in std::fs::read_dir(&d).expect("book folder").flatten() {
            let p = entry.path();
            if p.is_dir() {
                stack.push(p);
            } else if p.extension().is_some_and(|e| e == "md") {
                out.push(p);
            }
        }
    }
    out.sort();
    out
}

/// The fenced code blocks of a Markdown text: (info string, body).
fn code_blocks(text: &str) -> Vec<(String, String)> {
    let mut out = Vec::new();
    let mut current: Option<(String, String)> = None;
    for line in text.lines() {
        if let Some(info) = line.trim_start().strip_prefix("```") {
            match current.take() {
                Some(block) => out.push(block),
                None => current = Some((info.trim().to_string(), String::new())),
            }
        } else if let Some((_, body)) = &mut current {
            body.push_str(line);
            body.push('\n');
        }
    }
    out
}

#[test]
fn every_code_has_exactly_its_page() {
    let pages: BTreeSet<String> = std::fs::read_dir("book/src/diagnostics")
        .expect("catalogue folder")
        .flatten()
        .filter_map(|e| e.path().file_stem().map(|s| s.to_string_lossy().to_string()))
        .filter(|s| s != "index")
        .collect();
    let codes: BTreeSet<String> = Code::ALL.iter().map(|c| c.as_str().to_string()).collect();
    assert_eq!(pages, codes, "pages in book/src/diagnostics and codes in src/diag/codes.rs differ");
    for code in Code::ALL {
        let page = code.page();
        assert!(
            page.starts_with(&format!("# {}: {}\n", code.as_str(), code.name())),
            "{}: the page must start with `# {}: {}`",
            code.as_str(),
            code.as_str(),
            code.name()
        );
        for heading in ["## What it means", "## Example", "## How to fix", "## Since"] {
            assert!(page.contains(heading), "{}: the page lacks `{heading}`", code.as_str());
        }
    }
}

#[test]
fn every_page_example_produces_its_code_and_no_other() {
    for code in Code::ALL {
        let blocks = code_blocks(code.page());
        let Some((_, example)) = blocks.iter().find(|(info, _)| info == "holo") else {
            // Codes about files and the command line have examples of a session: a `console`
            // transcript (run by tests/transcripts.rs) that shows the code, or a `text` one.
            assert!(
                blocks
                    .iter()
                    .any(|(info, body)| (info == "console" && body.contains(code.as_str()))
                        || info == "text"
                        || info == "json"),
                "{}: the page has no example",
                code.as_str()
            );
            continue;
        };
        let mut sources = SourceMap::new();
        let id = sources.add(format!("{}.holo", code.as_str()), example.clone());
        let codes: BTreeSet<&str> =
            holoc::compile::diagnose(&sources, id).iter().map(|d| d.code.as_str()).collect();
        assert_eq!(
            codes,
            BTreeSet::from([code.as_str()]),
            "{}: the page's example must produce this code and no other",
            code.as_str()
        );
    }
}

#[test]
fn every_grammar_rule_is_documented() {
    for grammar in ["grammar/holo.pest"] {
        let text = std::fs::read_to_string(grammar).expect("grammar file");
        let lines: Vec<&str> = text.lines().collect();
        for (i, line) in lines.iter().enumerate() {
            let is_rule = line.split_once(" = ").is_some_and(|(name, rest)| {
                !name.starts_with("//")
                    && name.chars().all(|c| c.is_ascii_alphanumeric() || c == '_')
                    && (rest.starts_with('{')
                        || rest.starts_with("_{")
                        || rest.starts_with("@{")
                        || rest.starts_with("${"))
            });
            if is_rule {
                assert!(
                    i > 0 && lines[i - 1].starts_with("///"),
                    "{grammar}:{}: rule `{}` has no `///` comment",
                    i + 1,
                    line.split(' ').next().unwrap_or_default()
                );
            }
        }
    }
}

#[test]
fn book_snippets_check_without_errors() {
    let mut checked = 0;
    for path in markdown_files(Path::new("book/src")) {
        if path.starts_with("book/src/diagnostics") {
            continue;
        }
        let text = std::fs::read_to_string(&path).expect("readable");
        for (info, body) in code_blocks(&text) {
            // `holo excerpt` marks a piece of a larger file (the tutorial's transcripts test
            // checks that it is one) and `holo broken` a file shown for its errors (its
            // transcript shows them); every other `holo` block is a whole, valid file.
            if info != "holo" {
                continue;
            }
            let mut sources = SourceMap::new();
            let id = sources.add(path.display().to_string(), body.clone());
            let errors: Vec<String> = holoc::compile::check_file(&sources, id)
                .diagnostics
                .iter()
                .filter(|d| d.is_error())
                .map(|d| format!("{}: {}", d.code.as_str(), d.message))
                .collect();
            assert!(
                errors.is_empty(),
                "{}: a holo snippet has errors: {errors:?}\n{body}",
                path.display()
            );
            checked += 1;
        }
    }
    assert!(checked >= 5, "the book should have holo snippets, found {checked}");
}

#[test]
fn every_corpus_snapshot_has_its_input() {
    let mut stack = vec![PathBuf::from("snapshots")];
    while let Some(dir) = stack.pop() {
        let Ok(entries) = std::fs::read_dir(&dir) else { continue };
        for entry in entries.flatten() {
            let path = entry.path();
            if path.is_dir() {
                stack.push(path);
                continue;
            }
            assert!(
                path.extension().is_none_or(|e| e != "new"),
                "{}: a pending snapshot was left behind; review it",
                path.display()
            );
            let text = std::fs::read_to_string(&path).expect("readable snapshot");
            if let Some(line) = text.lines().take(6).find(|l| l.starts_with("input_file: ")) {
                let input = line.trim_start_matches("input_file: ").trim();
                assert!(
                    Path::new(input).exists(),
                    "{}: its input `{input}` no longer exists; delete the snapshot",
                    path.display()
                );
            }
        }
    }
}

#[test]
fn the_book_summary_links_every_page_and_only_existing_ones() {
    let summary = std::fs::read_to_string("book/src/SUMMARY.md").expect("SUMMARY.md");
    let mut linked = BTreeSet::new();
    for part in summary.split("](").skip(1) {
        let target = part.split(')').next().unwrap_or_default();
        assert!(
            Path::new("book/src").join(target).exists(),
            "SUMMARY.md links the missing page `{target}`"
        );
        linked.insert(target.to_string());
    }
    for path in markdown_files(Path::new("book/src")) {
        let relative = path
            .strip_prefix("book/src")
            .expect("inside the book")
            .to_string_lossy()
            .replace('\\', "/");
        if relative != "SUMMARY.md" {
            assert!(
                linked.contains(&relative),
                "book/src/{relative} is not linked from SUMMARY.md"
            );
        }
    }
}

/// The book's table of stand-ins is the table the resolver uses.
#[test]
fn the_book_lists_every_stand_in() {
    let page = std::fs::read_to_string("book/src/design/catalog-matching.md").expect("page");
    for line in holoc::resolve::standins::STAND_INS {
        let types = if line.types.is_empty() { "—".to_owned() } else { line.types.join(", ") };
        let row = format!("| {} | {types} | {} |", line.key, line.reason);
        assert!(page.contains(&row), "the book lacks the stand-in row `{row}`");
    }
}

/// The crates a first install does without (README, "Install"): miette without its backtrace
/// printer (holoc prints no backtraces), `textwrap` 0.16.1 and `idna_adapter` 1.1 (which use
/// the small unicode-rs tables instead of ICU4X), `toml` without its editing parser. Each
/// saved 10–60 s of CPU on a first build; a lock file that brings one back fails here.
#[test]
fn the_lock_file_keeps_out_the_crates_a_first_build_does_without() {
    let lock = std::fs::read_to_string(concat!(env!("CARGO_MANIFEST_DIR"), "/Cargo.lock"))
        .expect("Cargo.lock is committed");
    let names: Vec<&str> =
        lock.lines().filter_map(|l| l.strip_prefix("name = \"")?.strip_suffix('"')).collect();
    for unwanted in
        ["backtrace", "gimli", "addr2line", "icu_segmenter", "icu_normalizer", "icu_properties"]
    {
        assert!(
            !names.contains(&unwanted),
            "Cargo.lock has `{unwanted}` again: see the README's Install section for why it is kept out"
        );
    }
}

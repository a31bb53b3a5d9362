//! The tree-sitter grammar of `.holo` (`editors/tree-sitter-holo`) against holoc's own parser
//! and server, through its Rust binding:
//!
//! - every example, every `.holo` file under `tests/` and every `holo` snippet of the book that
//!   holoc's parser reads without a syntax error parses with no ERROR or MISSING node, and every
//!   one the parser rejects with a syntax error (E0101, E0102, E0104, E0107) gets one;
//! - the highlight queries (`queries/highlights.scm`, and Helix's copy with Helix's capture
//!   names) give every byte of every token of the server's semantic tokens that token's class,
//!   and every class occurs;
//! - `tree-sitter generate` reproduces the committed `src/` (skipped with a message when the
//!   tree-sitter CLI is not installed; `.ci/run` builds it from the crate registry).

mod common;

use std::collections::BTreeSet;
use std::fmt::Write as _;
use std::path::{Path, PathBuf};
use std::process::Command;

use holoc::lsp::highlight::Class;
use tree_sitter_highlight::{HighlightConfiguration, HighlightEvent, Highlighter};

const GRAMMAR: &str = "editors/tree-sitter-holo";

/// Every scene to check: (where it is, its text), sorted by where.
fn scenes() -> Vec<(String, String)> {
    fn walk(dir: &Path, out: &mut Vec<PathBuf>) {
        let Ok(entries) = std::fs::read_dir(dir) else { return };
        for entry in entries.flatten() {
            let path = entry.path();
            if path.is_dir() {
                walk(&path, out);
            } else if path.extension().is_some_and(|e| e == "holo") {
                out.push(path);
            }
        }
    }
    let mut files = Vec::new();
    walk(Path::new("examples"), &mut files);
    walk(Path::new("tests"), &mut files);
    let mut books = Vec::new();
    walk_md(Path::new("book/src"), &mut books);
    files.sort();
    books.sort();
    let mut out: Vec<(String, String)> = files
        .iter()
        .map(|p| (p.display().to_string(), std::fs::read_to_string(p).expect("a scene")))
        .collect();
    // The book's snippets: every fenced block whose info string starts with `holo`.
    for page in books {
        let text = std::fs::read_to_string(&page).expect("a page");
        let mut block: Option<(usize, String)> = None;
        for (n, line) in text.lines().enumerate() {
            match &mut block {
                None => {
                    if let Some(info) = line.strip_prefix("```") {
                        if info.split_whitespace().next() == Some("holo") {
                            block = Some((n + 1, String::new()));
                        }
                    }
                }
                Some((start, body)) => {
                    if line.starts_with("```") {
                        out.push((format!("{}:{start}", page.display()), std::mem::take(body)));
                        block = None;
                    } else {
                        body.push_str(line);
                        body.push('\n');
                    }
                }
            }
        }
    }
    out
}

fn walk_all(dir: &Path, out: &mut Vec<PathBuf>) {
    let Ok(entries) = std::fs::read_dir(dir) else { return };
    for entry in entries.flatten() {
        let path = entry.path();
        if path.is_dir() {
            walk_all(&path, out);
        } else {
            out.push(path);
        }
    }
}

fn walk_md(dir: &Path, out: &mut Vec<PathBuf>) {
    let Ok(entries) = std::fs::read_dir(dir) else { return };
    for entry in entries.flatten() {
        let path = entry.path();
        if path.is_dir() {
            walk_md(&path, out);
        } else if path.extension().is_some_and(|e| e == "md") {
            out.push(path);
        }
    }
}

fn language() -> tree_sitter::Language {
    tree_sitter_holo::LANGUAGE.into()
}

/// The first ERROR or MISSING node of a tree, as `line:column kind`, if any.
fn first_error(tree: &tree_sitter::Tree) -> Option<String> {
    let mut cursor = tree.walk();
    loop {
        let node = cursor.node();
        if node.is_error() || node.is_missing() {
            let at = node.start_position();
            let what = if node.is_missing() { "MISSING" } else { "ERROR" };
            return Some(format!("{}:{} {what} {}", at.row + 1, at.column + 1, node.kind()));
        }
        if node.has_error() && cursor.goto_first_child() {
            continue;
        }
        loop {
            if cursor.goto_next_sibling() {
                break;
            }
            if !cursor.goto_parent() {
                return None;
            }
        }
    }
}

/// Whether holoc's parser finds a syntax error (not a number or unit it refuses).
fn syntax_error(text: &str) -> Option<String> {
    holoc::parse::parse_str(text)
        .diagnostics
        .iter()
        .find(|d| matches!(d.code.as_str(), "E0101" | "E0102" | "E0104" | "E0107"))
        .map(|d| format!("{} {}", d.code.as_str(), d.message))
}

#[test]
fn every_scene_the_parser_reads_parses_with_no_error_node_and_every_broken_one_has_one() {
    let mut parser = tree_sitter::Parser::new();
    parser.set_language(&language()).expect("the grammar loads");
    let mut problems = Vec::new();
    let (mut clean, mut broken) = (0, 0);
    for (name, text) in scenes() {
        let tree = parser.parse(&text, None).expect("a tree");
        let holoc = syntax_error(&text);
        match (holoc, first_error(&tree)) {
            (None, None) => clean += 1,
            (Some(_), Some(_)) => broken += 1,
            (None, Some(error)) => {
                problems.push(format!("{name}: holoc reads it, tree-sitter has {error}"));
            }
            (Some(said), None) => {
                problems.push(format!("{name}: holoc says {said}, tree-sitter has no error"));
            }
        }
    }
    assert!(problems.is_empty(), "{} disagreements:\n{}", problems.len(), problems.join("\n"));
    // The examples, the corpus and the book: well over a hundred clean scenes, and the parse
    // corpus's broken ones.
    assert!(clean > 100 && broken >= 10, "{clean} clean, {broken} broken");
}

/// The capture names a query file is written with, in [`Class::ALL`]'s order.
const STANDARD: [&str; 9] = [
    "keyword", "module", "variable", "type", "constant", "string", "number", "comment", "operator",
];
const HELIX: [&str; 9] = [
    "keyword",
    "namespace",
    "variable",
    "type",
    "constant",
    "string",
    "constant.numeric",
    "comment",
    "operator",
];

/// The class tree-sitter's highlighter gives each byte of `text` (`None` where it gives none).
fn classes(
    highlighter: &mut Highlighter,
    config: &HighlightConfiguration,
    text: &str,
) -> Vec<Option<Class>> {
    let mut out = vec![None; text.len()];
    let mut stack = Vec::new();
    let events =
        highlighter.highlight(config, text.as_bytes(), None, |_| None).expect("highlights");
    for event in events {
        match event.expect("an event") {
            HighlightEvent::HighlightStart(h) => stack.push(Class::ALL[h.0]),
            HighlightEvent::HighlightEnd => {
                stack.pop();
            }
            HighlightEvent::Source { start, end } => {
                for class in &mut out[start..end] {
                    *class = stack.last().copied();
                }
            }
        }
    }
    out
}

/// Checks `query`, written with the capture names `names`, against the server's tokens of every
/// scene.
fn check_query(query: &str, names: [&str; 9]) {
    let mut config =
        HighlightConfiguration::new(language(), "holo", query, "", "").expect("the query reads");
    config.configure(&names);
    // Every capture of the query is one of the classes' names or below one (`string.escape`).
    for capture in config.names() {
        let known = names.iter().any(|n| capture == n || capture.starts_with(&format!("{n}.")));
        assert!(
            known || capture.starts_with("punctuation"),
            "the capture @{capture} is not one of the server's classes"
        );
    }
    let mut highlighter = Highlighter::new();
    let mut seen = BTreeSet::new();
    let mut problems = Vec::new();
    for (name, text) in scenes() {
        if syntax_error(&text).is_some() {
            continue;
        }
        let given = classes(&mut highlighter, &config, &text);
        for token in holoc::lsp::highlight::tokens(&text) {
            let wrong = (token.start..token.end).find(|&b| given[b] != Some(token.class));
            if let Some(b) = wrong {
                let line = text[..token.start].matches('\n').count() + 1;
                problems.push(format!(
                    "{name}:{line}: `{}` is {} for the server, {:?} for tree-sitter",
                    &text[token.start..token.end],
                    token.class.as_str(),
                    given[b].map(Class::as_str),
                ));
            } else {
                seen.insert(token.class);
            }
        }
    }
    let shown: Vec<&String> = problems.iter().take(40).collect();
    assert!(problems.is_empty(), "{} tokens differ:\n{shown:#?}", problems.len());
    assert_eq!(seen, Class::ALL.into_iter().collect(), "every class occurs");
}

#[test]
fn the_highlight_queries_give_every_token_the_class_of_the_servers_tokens() {
    check_query(tree_sitter_holo::HIGHLIGHTS_QUERY, STANDARD);
}

#[test]
fn helixs_highlight_queries_are_the_grammars_with_helixs_names() {
    let helix = std::fs::read_to_string("editors/helix/runtime/queries/holo/highlights.scm")
        .expect("Helix's queries");
    check_query(&helix, HELIX);
    // The same patterns, captured with Helix's names.
    let renamed = tree_sitter_holo::HIGHLIGHTS_QUERY
        .replace("@module", "@namespace")
        .replace("@number", "@constant.numeric")
        .replace("@string.escape", "@constant.character.escape");
    let body = |q: &str| -> Vec<String> {
        q.lines().filter(|l| !l.starts_with(';')).map(str::to_owned).collect()
    };
    assert_eq!(body(&helix), body(&renamed), "Helix's queries follow queries/highlights.scm");
}

/// The version of the tree-sitter CLI that generated `src/` (`.ci/run` builds this one).
const CLI_VERSION: &str = "0.27.1";

/// The tree-sitter CLI of [`CLI_VERSION`]: where `.ci/run` installs it, or on the `PATH`.
fn tree_sitter_cli() -> Result<PathBuf, String> {
    let home = std::env::var_os("HOME").unwrap_or_default();
    let cached = Path::new(&home).join(".cache/holoc/cargo/bin/tree-sitter");
    let mut found = Vec::new();
    for cli in [cached, PathBuf::from("tree-sitter")] {
        let Ok(output) = Command::new(&cli).arg("--version").output() else { continue };
        let version = String::from_utf8_lossy(&output.stdout).trim().to_owned();
        if version.split_whitespace().nth(1) == Some(CLI_VERSION) {
            return Ok(cli);
        }
        found.push(format!("{} is {version}", cli.display()));
    }
    Err(if found.is_empty() {
        format!(
            "the tree-sitter CLI is not installed (`cargo install tree-sitter-cli --version \
             {CLI_VERSION} --locked`, or run .ci/run)"
        )
    } else {
        format!("the parser was generated by tree-sitter {CLI_VERSION}, and {}", found.join(", "))
    })
}

#[test]
fn tree_sitter_generate_reproduces_the_committed_parser() {
    let test = "tree_sitter_generate_reproduces_the_committed_parser";
    let cli = match tree_sitter_cli() {
        Ok(cli) => cli,
        Err(why) => {
            common::skip(test, &why);
            return;
        }
    };
    let dir = std::env::temp_dir().join(format!("holoc-tree-sitter-{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).expect("a scratch folder");
    for file in ["grammar.js", "tree-sitter.json"] {
        std::fs::copy(Path::new(GRAMMAR).join(file), dir.join(file)).expect("copy");
    }
    let output = Command::new(&cli)
        .args(["generate", "--abi", "14"])
        .current_dir(&dir)
        .output()
        .expect("the CLI runs");
    assert!(output.status.success(), "{}", String::from_utf8_lossy(&output.stderr));
    // Every file `generate` writes is committed as it was written, and nothing else is there.
    let listing = |root: &Path| -> Vec<String> {
        let mut files = Vec::new();
        walk_all(&root.join("src"), &mut files);
        let mut names: Vec<String> = files
            .iter()
            .map(|f| f.strip_prefix(root).expect("inside").display().to_string())
            .collect();
        names.sort();
        names
    };
    let made = listing(&dir);
    assert_eq!(made, listing(Path::new(GRAMMAR)), "the files of src/");
    for file in made {
        let fresh = std::fs::read(dir.join(&file)).expect("generated");
        let committed = std::fs::read(Path::new(GRAMMAR).join(&file)).expect("committed");
        assert!(
            fresh == committed,
            "editors/tree-sitter-holo/{file} is not what `tree-sitter generate --abi 14` makes \
             of grammar.js: run it in editors/tree-sitter-holo and commit src/"
        );
    }
    let _ = std::fs::remove_dir_all(&dir);
}

fn runs(program: &str) -> bool {
    Command::new(program).arg("--version").output().is_ok_and(|o| o.status.success())
}

#[test]
fn neovims_own_tree_sitter_loads_the_parser_and_queries_as_the_book_sets_them_up() {
    let test = "neovims_own_tree_sitter_loads_the_parser_and_queries_as_the_book_sets_them_up";
    if !runs("nvim") || !runs("cc") {
        common::skip(
            test,
            "neovim (`nvim`) or a C compiler (`cc`) is missing; `apt-get install neovim gcc` or run .ci/run",
        );
        return;
    }
    let dir = std::env::temp_dir().join(format!("holoc-tree-sitter-nvim-{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&dir);
    // The book's plugin-free setup: the parser compiled into `site/parser`, the queries copied
    // into `site/queries/holo`.
    let site = dir.join("site");
    std::fs::create_dir_all(site.join("parser")).expect("folders");
    std::fs::create_dir_all(site.join("queries/holo")).expect("folders");
    let status = Command::new("cc")
        .args(["-O1", "-shared", "-fPIC", "-I"])
        .arg(Path::new(GRAMMAR).join("src"))
        .arg(Path::new(GRAMMAR).join("src/parser.c"))
        .arg("-o")
        .arg(site.join("parser/holo.so"))
        .status()
        .expect("cc runs");
    assert!(status.success(), "the parser compiles");
    std::fs::copy(
        Path::new(GRAMMAR).join("queries/highlights.scm"),
        site.join("queries/holo/highlights.scm"),
    )
    .expect("copy the queries");
    // Every scene holoc's parser reads, as a file, with the server's tokens.
    let mut cases = String::new();
    for (n, (_, text)) in scenes().into_iter().enumerate() {
        // Vim reads a lone `\r` as a line break only in `fileformat=mac` (see tests/editor.rs).
        if syntax_error(&text).is_some() || text.replace("\r\n", "").contains('\r') {
            continue;
        }
        let file = dir.join(format!("scene{n}.holo"));
        std::fs::write(&file, &text).expect("write");
        let _ = writeln!(cases, "file {}", file.display());
        let mut starts = vec![0];
        starts.extend(text.match_indices('\n').map(|(i, _)| i + 1));
        for token in holoc::lsp::highlight::tokens(&text) {
            let line = starts.partition_point(|&s| s <= token.start);
            let column = token.start - starts[line - 1] + 1;
            let _ = writeln!(cases, "{line} {column} {}", token.class.as_str());
        }
    }
    let cases_path = dir.join("cases.txt");
    std::fs::write(&cases_path, cases).expect("write");
    let out = dir.join("out.txt");
    let script = std::path::absolute("tests/editor/treesitter.lua").expect("absolute");
    let output = Command::new("nvim")
        .args(["--headless", "--clean", "-n", "-c"])
        .arg(format!("luafile {}", script.display()))
        .env("HOLO_SITE", &site)
        .env("HOLO_CASES", &cases_path)
        .env("HOLO_OUT", &out)
        .env("XDG_STATE_HOME", &dir)
        .env("XDG_DATA_HOME", &dir)
        .env("XDG_CACHE_HOME", &dir)
        .stdin(std::process::Stdio::null())
        .output()
        .expect("nvim runs");
    let report = std::fs::read_to_string(&out).unwrap_or_default();
    assert!(output.status.success(), "nvim: {report}{}", String::from_utf8_lossy(&output.stderr));
    let mut every: Vec<&str> = Class::ALL.iter().map(|c| c.as_str()).collect();
    every.sort_unstable();
    assert_eq!(report, format!("seen {}\ndone\n", every.join(" ")));
    let _ = std::fs::remove_dir_all(&dir);
}

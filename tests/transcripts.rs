//! The README's and the book's command examples are tests: every ```console block (`$ holoc …`,
//! its output and, after `? CODE`, its exit status) runs against the freshly built binary, so
//! the documentation fails CI the moment it drifts from what holoc prints.
//!
//! Blocks run in the repository root unless the page has a `<page>.in/` folder beside it (then
//! in a scratch copy of that folder, when `<page>.out/` exists too). Outputs of README commands
//! go to `out/`, which git ignores. After an intended change of output:
//! `TRYCMD=overwrite cargo test --test transcripts`, then read the diff.

#[test]
fn readme_and_book_transcripts() {
    std::fs::create_dir_all("out").expect("the out/ folder can be made");
    trycmd::TestCases::new()
        .env("NO_COLOR", "1")
        .env("COLUMNS", "100")
        .case("README.md")
        .case("book/src/*.md")
        .case("book/src/*/*.md");
}

/// The tutorial shows the files its commands read: every `holo` block of the page (a whole file,
/// or a `holo excerpt`) is a piece of one of the files in `book/src/tutorial.in/`.
#[test]
fn tutorial_shows_the_files_it_runs() {
    let page = std::fs::read_to_string("book/src/tutorial.md").expect("the tutorial");
    let files: Vec<String> = std::fs::read_dir("book/src/tutorial.in")
        .expect("the tutorial's files")
        .flatten()
        .map(|e| std::fs::read_to_string(e.path()).expect("readable"))
        .collect();
    let mut blocks = 0;
    for block in page.split("```holo").skip(1) {
        let body = block.split_once('\n').map_or("", |(_, rest)| rest);
        let body = body.split("```").next().unwrap_or_default();
        blocks += 1;
        assert!(
            files.iter().any(|f| f.contains(body)),
            "this block of the tutorial is in none of its files:\n{body}"
        );
    }
    assert!(blocks >= 4, "the tutorial shows {blocks} holo blocks");
}

//! The tree-sitter grammar of `.holo`, holoc's scene language, for Rust.
//!
//! ```
//! let mut parser = tree_sitter::Parser::new();
//! parser.set_language(&tree_sitter_holo::LANGUAGE.into()).expect("the grammar loads");
//! let tree = parser.parse("room a \"a\" {\n  corners in m (0, 0) (0, 4) (4, 4)\n}\n", None);
//! assert!(!tree.expect("a tree").root_node().has_error());
//! ```

use tree_sitter_language::LanguageFn;

extern "C" {
    fn tree_sitter_holo() -> *const ();
}

/// The language, for `tree_sitter::Parser::set_language(&LANGUAGE.into())`.
// SAFETY: `tree_sitter_holo` is the generated parser's entry point, which returns a pointer to
// its static `TSLanguage`.
pub const LANGUAGE: LanguageFn = unsafe { LanguageFn::from_raw(tree_sitter_holo) };

/// The node types of the grammar, as `tree-sitter generate` writes them.
pub const NODE_TYPES: &str = include_str!("../../src/node-types.json");

/// The highlight queries, with the capture names of tree-sitter's CLI, Neovim and Zed
/// (`@keyword`, `@module`, `@variable`, `@type`, `@constant`, `@string`, `@number`, `@comment`,
/// `@operator`).
pub const HIGHLIGHTS_QUERY: &str = include_str!("../../queries/highlights.scm");

#[cfg(test)]
mod tests {
    #[test]
    fn the_grammar_loads() {
        let mut parser = tree_sitter::Parser::new();
        parser.set_language(&super::LANGUAGE.into()).expect("the grammar loads");
    }
}

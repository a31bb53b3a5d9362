//! holoc: a compiler from `.holo` scene descriptions (and the LLM answers they are imported
//! from) to AI2-THOR house JSON.
//!
//! Each stage is one module with one entry verb, its output noun and its diagnostics; see
//! `ARCHITECTURE.md` for the pipeline and the invariants of every module.

pub mod ast;
pub mod batch;
pub mod build_info;
pub mod cancel;
pub mod check;
pub mod cli;
pub mod compile;
pub mod diag;
pub mod diff;
pub mod export;
pub mod fmt;
pub mod generate;
pub mod geometry;
pub mod import;
pub mod lower;
pub mod lsp;
pub mod make;
pub mod parse;
pub mod plan;
pub mod render;
pub mod report;
pub mod resolve;
pub mod solve;
pub mod source;

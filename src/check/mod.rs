//! The checker: syntax tree → typed [`Scene`].

pub mod scene;

pub use scene::*;

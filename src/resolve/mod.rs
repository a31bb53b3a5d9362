//! The `resolve` stage (being written).

pub mod structure;

//! The `cli` stage (being written).

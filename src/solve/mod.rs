//! The `solve` stage (being written).

//! The `resolve` stage (being written).

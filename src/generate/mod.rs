//! The `generate` stage (being written).

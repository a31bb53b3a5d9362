//! The `lower` stage (being written).

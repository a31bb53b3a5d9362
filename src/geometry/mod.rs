//! The `geometry` stage (being written).

//! The `render` stage (being written).

//! The `plan` stage (being written).

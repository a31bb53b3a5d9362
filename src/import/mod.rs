//! The `import` stage (being written).

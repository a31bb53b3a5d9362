//! The `report` stage (being written).
